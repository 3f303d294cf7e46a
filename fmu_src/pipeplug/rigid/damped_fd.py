"""The paper's explicit scheme (:mod:`pipeplug.rigid.fd`) with Smith damping.

Each step projects the trial velocities with the Coulomb windows and the dampers of impulses
(:func:`pipeplug.contact.damping.damped_contacts`): the damper of a resistance ``R`` (the
shaft's ``P1 Lc(U1^n) tau1``, the plug's ``P2 L2 tau2``, the end resistances ``Qf``, ``Qp``)
is ``tau J R``, implicit (at the step's end velocity), so a damper never reverses a motion and
its work ``tau J R v^2`` is >= 0 at any step: the scheme stays unconditionally dissipative.
Model II's damping follows the contact length at ``U1^n`` as its friction does. First order,
as the scheme without damping.

Ledger: the damping work is booked as ``W_damping`` at the step's end velocity like every other
force's work, so ``W_input = E_kinetic + W_friction + W_face + W_damping + W_numerical`` holds
to round-off with ``W_numerical = sum M dv^2 / 2 >= 0`` as before. ``F_outer`` and ``F_inner``
are the whole resistances of shaft and plug, their dampers' parts included.
"""
from __future__ import annotations

from ..contact.coulomb import SLACK
from ..contact.damping import damped_contacts, damped_one
from ..contact.outer import face_on, limit

__all__ = ["damping_of", "step_damped_pair", "step_damped_alone"]

# as in pipeplug.rigid.fd: a trial momentum within this share of the largest from a limit sticks
_ROUND_OFF = 1e-12


def damping_of(params) -> tuple[float, float]:
    """``(J_shaft, J_face)`` [s/m] of validated ``params``."""
    return params.J_shaft, params.J_face


def _dampers(model, s: dict, tau: float) -> tuple:
    """The step's windows and dampers of impulses: ``(c1p, c1m, a1p, a1m, a_shaft)`` [N s,
    N s^2/m]; the annulus meets the soil as its Coulomb part does (model II: from U1 >= 0)."""
    j_shaft, j_face = model._damping
    c1 = tau * limit(model.outer, s["U1"])
    face = tau * model.Qf * face_on(model.outer, s["U1"])
    a_shaft = j_shaft * c1
    return c1 + face, c1, a_shaft + j_face * face, a_shaft, a_shaft


def step_damped_pair(model, s: dict, q: float, tau: float) -> None:
    """One step of pipe and plug with Smith damping."""
    j_shaft, j_face = model._damping
    c1p, c1m, a1p, a1m, a_shaft = _dampers(model, s, tau)
    c2, c3p = tau * model.F2, tau * model.Qp
    x1, x2, f1, f2, f3, g1, g2, g3, s1, s2, _ = damped_contacts(
        model.M1, model.M2, s["V1"] + tau * q / model.M1, s["V2"], c1p, c1m, c2, c3p, a1p, a1m,
        j_shaft * c2, j_face * c3p, _ROUND_OFF * s["p_max"])
    _commit(model, s, q, tau, x1, x2, f1, f2, f3, g1, g2, g3, s1, s2, c1m, a_shaft)


def step_damped_alone(model, s: dict, q: float, tau: float) -> None:
    """One step of the pipe without a plug, with Smith damping."""
    c1p, c1m, a1p, a1m, a_shaft = _dampers(model, s, tau)
    trial = s["V1"] + tau * q / model.M1
    x1, f1, g1 = damped_one(model.M1, trial, c1p, c1m, a1p, a1m,
                            max(SLACK * (abs(model.M1 * trial) + c1p + c1m),
                                _ROUND_OFF * s["p_max"]))
    _commit(model, s, q, tau, x1, 0.0, f1, 0.0, 0.0, g1, 0.0, 0.0, (x1 > 0.0) - (x1 < 0.0), 0,
            c1m, a_shaft)


def _commit(model, s, q, tau, v1, v2, f1, f2, f3, g1, g2, g3, s1, s2, c1, a_shaft) -> None:
    """Book the dampers' work and commit the Coulomb impulses as the scheme with end
    resistance does; the outputs' forces then gain the shaft's and the plug's dampers."""
    s["W_damp"] += max(-(g1 * v1 + g2 * (v1 - v2) + g3 * v2), 0.0)
    model._commit_face(s, q, tau, v1, v2, f1, f2, f3, s1, s2, c1)
    s["f1"] -= a_shaft * v1 / tau
    s["f2"] += g2 / tau
