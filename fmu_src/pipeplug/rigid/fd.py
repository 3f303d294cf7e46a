"""The paper's explicit finite-difference scheme for the rigid models (section 2), corrected.

Scheme (docs/corrections.md B1: ``U^{n-1}`` on the right-hand side), step ``tau``::

    U1^{n+1} - 2 U1^n + U1^{n-1} = tau^2 (Q^n + f1 + f2) / M1
    U2^{n+1} - 2 U2^n + U2^{n-1} = -tau^2 f2 / M2

written with the step velocities ``v^{n+1/2} = (U^{n+1} - U^n) / tau``. The friction terms come
from the paper's "fictitious velocity" test, generalised (docs/corrections.md B4) to solving both contacts
jointly at the impulse level (:func:`pipeplug.contact.coulomb.two_contacts`): the frictionless
trial velocities are projected with impulse limits ``tau P1 Lc(U1^n) tau1`` and
``tau P2 L2 tau2``; a contact whose trial relative velocity cannot overcome its limit sticks
(zero relative velocity, passive friction). Model II evaluates the contact length at ``U1^n``.

First order in ``tau`` where the friction switches; exact between switches for model I.
Energy: ``W_input - W_friction - KE = sum M dv^2 / 2 >= 0``, the scheme's numerical dissipation
(O(tau)), output as ``W_numerical``: the input and friction powers are taken at the step's end
velocity, so every change of velocity costs the kinetic energy of its jump.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.coulomb import SLACK, one_contact, two_contacts
from ..contact.face import face_contacts, one_sided
from ..contact.outer import contact_length, face_on, limit, outer_contact_for
from ..interface import ModelBase, Outputs
from ..params import ParameterError
from .damped_fd import damping_of, step_damped_alone, step_damped_pair
from .stress import axial_extremes

__all__ = ["RigidFd", "internal_steps"]

_STATE_KEYS = ("time", "U1", "V1", "U2", "V2", "W_in", "W_outer", "W_inner", "W_num", "f1", "f2",
               "s1", "s2", "p_max", "q", "W_face", "face1", "W_damp")
# Velocities carry round-off of the largest momentum the run has seen: a trial momentum within
# this share of it from a friction limit sticks (else a body whose load equals its limit
# slides on forever at 1e-13 m/s after a grazing stop).
_ROUND_OFF = 1e-12


def internal_steps(h: float, h_max: float) -> int:
    """The contract's number of equal internal steps: ``ceil(h / h_max - 1e-9)``, at least 1."""
    return max(1, math.ceil(h / h_max - 1e-9))


class RigidFd(ModelBase):
    """Rigid pipe (and plug) by the paper's explicit scheme with internal steps <= ``dt``.

    Parameters
    ----------
    params : Params
        Validated parameters (``dt`` is the largest internal step [s]).
    options : Options
        ``contact_growth`` selects model II.
    """

    def __init__(self, params, options):
        self.M1, self.M2, self.F2 = params.M1, params.M2, params.F2
        self.L1, self.S1 = params.L1, params.S1
        self.L2 = params.L2 if params.has_plug else 0.0
        self._l2_now = float(params.L2)              # the output L2_now: the plug never changes
        self.dt_max = params.dt
        self._max_steps = params.max_internal_steps
        self.outer = outer_contact_for(params.P1, params.L1, params.tau1, options.contact_growth,
                                       params.q_face)
        self.Qf, self.Qp = params.F_face, params.F_plug_face
        if params.has_damping:        # Smith damping: the joint problem with its dampers
            self._damping = damping_of(params)
            self._step = self._step_damped_pair if params.has_plug else self._step_damped_alone
        elif params.has_face:         # end resistance: the joint problem with its windows
            self._step = self._step_face_pair if params.has_plug else self._step_face_alone
        else:
            self._step = self._step_pair if params.has_plug else self._step_alone
        self.time = 0.0
        self._s = dict.fromkeys(_STATE_KEYS, 0.0)
        self._s["s1"] = self._s["s2"] = 0
        self._modes: list[tuple[int, int]] = []      # every step's (s1, s2), repeats merged

    def _step_to(self, q: float, h: float, t_end: float) -> None:
        """Advance by ``h`` [s] in equal internal steps <= ``dt`` under ``q`` [N], ending at
        ``t_end`` [s]; at rest under no load the steps change nothing and are skipped."""
        s = self._s
        if not (q == 0.0 and self.at_rest()):
            n = internal_steps(h, self.dt_max)
            if n > self._max_steps:
                raise ParameterError(
                    "communicationStepSize", h,
                    f"at most max_internal_steps = {self._max_steps:g} internal steps of at "
                    f"most dt = {self.dt_max!r} s while the bodies move (raise "
                    f"max_internal_steps or dt to allow longer steps)")
            tau = h / n
            for _ in range(n):
                self._step(s, q, tau)
        self.time = t_end
        s["time"] = t_end

    def at_rest(self) -> bool:
        """Both bodies at rest and no friction force: a step under Q = 0 changes nothing."""
        s = self._s
        return (s["V1"] == 0.0 and s["V2"] == 0.0 and s["f1"] == 0.0 and s["f2"] == 0.0
                and s["face1"] == 0.0)

    def _step_pair(self, s: dict, q: float, tau: float) -> None:
        """One step of pipe and plug."""
        c1 = tau * limit(self.outer, s["U1"])
        v1, v2, p1, p2, s1, s2 = two_contacts(
            self.M1, self.M2, s["V1"] + tau * q / self.M1, s["V2"], c1, tau * self.F2,
            _ROUND_OFF * s["p_max"])
        self._commit(s, q, tau, v1, v2, p1, p2, s1, s2)

    def _step_alone(self, s: dict, q: float, tau: float) -> None:
        """One step of the pipe without a plug."""
        c1 = tau * limit(self.outer, s["U1"])
        trial = s["V1"] + tau * q / self.M1
        # At least the share two_contacts allows: a load 1 ulp above the limit holds the pipe
        # from rest, as it does with a plug.
        v1, p1 = one_contact(self.M1, trial, c1,
                             max(SLACK * (abs(self.M1 * trial) + c1), _ROUND_OFF * s["p_max"]))
        self._commit(s, q, tau, v1, 0.0, p1, 0.0, (v1 > 0.0) - (v1 < 0.0), 0)

    def _face_windows(self, s: dict, tau: float) -> tuple[float, float]:
        """The impulse window of the soil on the pipe, against advance and retreat [N s]."""
        c1 = tau * limit(self.outer, s["U1"])
        return c1 + tau * self.Qf * face_on(self.outer, s["U1"]), c1

    def _step_face_pair(self, s: dict, q: float, tau: float) -> None:
        """One step of pipe and plug with end resistance (:mod:`pipeplug.contact.face`)."""
        c1p, c1m = self._face_windows(s, tau)
        v1, v2, p1, p2, p3, s1, s2, _ = face_contacts(
            self.M1, self.M2, s["V1"] + tau * q / self.M1, s["V2"], c1p, c1m, tau * self.F2,
            tau * self.Qp, _ROUND_OFF * s["p_max"])
        self._commit_face(s, q, tau, v1, v2, p1, p2, p3, s1, s2, c1m)

    def _step_face_alone(self, s: dict, q: float, tau: float) -> None:
        """One step of the pipe alone with end resistance."""
        c1p, c1m = self._face_windows(s, tau)
        trial = s["V1"] + tau * q / self.M1
        v1, p1 = one_sided(self.M1, trial, c1p, c1m,
                           max(SLACK * (abs(self.M1 * trial) + c1p + c1m),
                               _ROUND_OFF * s["p_max"]))
        self._commit_face(s, q, tau, v1, 0.0, p1, 0.0, 0.0, (v1 > 0.0) - (v1 < 0.0), 0, c1m)

    def _step_damped_pair(self, s: dict, q: float, tau: float) -> None:
        """One step of pipe and plug with Smith damping (:mod:`pipeplug.rigid.damped_fd`)."""
        step_damped_pair(self, s, q, tau)

    def _step_damped_alone(self, s: dict, q: float, tau: float) -> None:
        """One step of the pipe alone with Smith damping."""
        step_damped_alone(self, s, q, tau)

    def _commit_face(self, s, q, tau, v1, v2, p1, p2, p3, s1, s2, c1) -> None:
        """:meth:`_commit` with the end impulses: the soil's ``p1`` on the pipe splits into the
        shaft's (up to its limit ``c1``, first) and the annulus'; ``p3`` on the plug's face.
        Their work at the step's end velocity is >= 0 (each acts only against advance)."""
        shaft = max(p1, -c1)
        face = p1 - shaft
        s["W_face"] -= face * v1 + p3 * v2
        s["face1"] = face / tau
        self._commit(s, q, tau, v1, v2, shaft, p2, s1, s2)

    def _commit(self, s, q, tau, v1, v2, p1, p2, s1, s2) -> None:
        """Store the new step velocities, displacements, works and friction forces."""
        s["p_max"] = max(s["p_max"], self.M1 * abs(v1) + self.M2 * abs(v2))
        s["U1"] += tau * v1
        s["U2"] += tau * v2
        s["W_num"] += 0.5 * (self.M1 * (v1 - s["V1"]) ** 2 + self.M2 * (v2 - s["V2"]) ** 2)
        s["V1"], s["V2"] = v1, v2
        s["W_in"] += q * tau * v1
        s["W_outer"] -= p1 * v1
        s["W_inner"] -= p2 * (v1 - v2)
        s["f1"], s["f2"], s["s1"], s["s2"], s["q"] = p1 / tau, p2 / tau, s1, s2, q
        if not self._modes or self._modes[-1] != (s1, s2):
            self._modes.append((s1, s2))

    def outputs(self) -> Outputs:
        """The contract's outputs (velocities: the last step's (U^{n+1} - U^n)/tau)."""
        s = self._s
        kinetic = 0.5 * (self.M1 * s["V1"] ** 2 + self.M2 * s["V2"] ** 2)
        q = s["q"]
        low, high = axial_extremes(q, s["f1"], s["f2"], self.L1,
                                   contact_length(self.outer, s["U1"]), self.L2, s["face1"])
        return Outputs(s["V1"], s["V2"], s["U1"], s["U2"], s["f1"], s["f2"], s["W_in"],
                       s["W_outer"] + s["W_inner"], s["W_outer"], s["W_inner"], kinetic, 0.0,
                       s["W_num"], q, 0.0, 0.0, 0.0, s["W_in"], -q / self.S1,
                       float(low) / self.S1, float(high) / self.S1, self.at_rest(),
                       int(s["s1"]), int(s["s2"]), s["W_face"], s["W_damp"], self._l2_now, 0.0,
                       0.0)

    def modes(self) -> tuple[tuple[int, int], ...]:
        """Every internal step's contact modes (pipe_mode, plug_mode), repeats merged."""
        return tuple(self._modes)

    def get_state(self) -> dict:
        """A copy of the whole state, and the modes gone through."""
        return {**self._s, "modes": np.array(self._modes, dtype=np.int64).reshape(-1, 2)}

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state`."""
        self._s = {k: state[k] for k in _STATE_KEYS}
        self._modes = [tuple(map(int, row)) for row in np.asarray(state["modes"]).reshape(-1, 2)]
        self._s["s1"], self._s["s2"] = int(state["s1"]), int(state["s2"])
        self.time = float(state["time"])
