"""The checks of the fuzz and their tolerances (one table), as functions of run outputs.

Every check reduces the runs of one case to one number, its *value*; the case fails the
check when the value exceeds the tolerance of :data:`CHECKS`. The scale of a quantity is its
largest magnitude over the run (over every run of the case that is compared) of it and its
kin (:data:`FAMILIES`: both velocities, both displacements, both forces, all works). Masses and
limits are computed here from the parameters (the paper's formulas), not taken from the core.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pipeplug.interface import PER_STEP

from .runners import COLUMN

__all__ = ["Check", "CHECKS", "CONTINUOUS", "FAMILIES", "Body", "relative_error", "reference_errors",
           "grid_error", "energy_error", "friction_decrease", "stuck_violations",
           "limit_excess", "same_outputs_error"]


class Check(NamedTuple):
    tolerance: float
    meaning: str


#: The constant C of the fd bound, fitted once: ``pipeplug fuzz --fit-fd-constant`` on
#: 3,000 cases each of seeds 22, 23 and 24 (all resolved) gave K = E / dt up to 0.340,
#: median 0.018; C = 1.5 x 0.340 = 0.51, rounded up. (Seed 24: observed order of the works'
#: error 0.977-1.004 for 98 % of the 2,372 cases measured, none outside 0.9-1.1.)
FD_C = 0.6

#: check -> (tolerance, what its value is). A case fails when value > tolerance.
CHECKS: dict[str, Check] = {
    "exception": Check(0.0, "runs that raised an exception"),
    "reference": Check(1e-9, "exact vs the DOP853 reference: largest |error| / scale of "
                             "velocities, displacements and works, at every grid point"),
    "reference forces": Check(1e-9, "the same for F_outer, F_inner at points farther than "
                                    "1e-9 T from every switch instant of the reference (their "
                                    "scale at least the largest |Q|)"),
    "reference modes": Check(0.0, "points farther than 1e-9 T from every switch instant "
                                  "where a contact mode differs from the reference's (not "
                                  "where the contact's speeds differ and are both within 16 "
                                  "ulps of the velocity scale: a round-off motion's label)"),
    "grid": Check(1e-12, "coarse vs fine vs irregular grid at the common sample times: "
                         "largest |difference| / scale over all outputs (modes: exact)"),
    "energy": Check(1e-12, "|W_input - kinetic energy - W_friction - W_face - W_damping| / "
                           "largest work"),
    "friction work": Check(0.0, "largest decrease of W_friction, W_friction_outer, "
                                "W_friction_inner, W_face or W_damping between two points / "
                                "largest work"),
    "stuck": Check(0.0, "points where a stuck contact's relative velocity is not exactly 0 "
                        "(pipe_mode 0: v_pipe; plug_mode 0: v_pipe - v_plug), or, without a "
                        "plug, a plug output is not exactly 0"),
    "static limits": Check(1e-12, "largest (|F_inner| - F2 D2) / F2 and (|F_outer| - "
                                  "P1 tau1 Lc(u) D1) / (that limit + |Q| + F2), with Smith "
                                  "damping's D1 = 1 + J_shaft |v_pipe|, D2 = 1 + J_shaft "
                                  "|v_pipe - v_plug| (1 without)"),
    "at rest": Check(0.0, "points where at_rest holds but a velocity is not 0 or a step "
                          "under Q = 0 changes an output"),
    "ram ledger": Check(1e-12, "model I with a ram: |W_input + W_ram - E_kinetic - E_strain - "
                               "W_friction - W_cushion - W_numerical| and |E_kinetic - the "
                               "kinetic energy of pipe, plug and ram from their masses| / "
                               "largest work or energy"),
    "ram energies": Check(0.0, "model I with a ram: points with a negative E_kinetic or "
                               "E_strain, W_cushion below -1e-12 of the largest work, "
                               "W_numerical != 0, W_friction > W_input + W_ram, or a "
                               "non-finite output"),
    "growth ledger": Check(1e-10, "a growing plug: |W_input - E_kinetic - W_friction - W_face "
                                  "- W_accretion - W_removed| and |E_kinetic - the kinetic "
                                  "energy of the pipe and the plug of length L2_now| / largest "
                                  "work or energy (the integrated pieces keep 1e-13 of scales "
                                  "of the whole pipe and the largest forces per step, not of "
                                  "the run's own work: 6e-12 seen where a blow moves the pipe "
                                  "by 1e-4 of its length)"),
    "growth energies": Check(0.0, "a growing plug: points with a non-finite output, a loss "
                                  "that decreased (beyond 1e-12 of W_input), L2_now outside "
                                  "[0, L1], a stuck pipe moving, or a stuck plug moving in "
                                  "the pipe"),
    "ledger": Check(1.0, "model III: |W_input + W_ram - E_kinetic - E_strain - W_friction - "
                         "W_numerical - W_cushion - W_face| / ((1e-12 + 2.2e-16 n) x largest "
                         "work or energy of the run), n the internal steps so far"),
    "energies": Check(0.0, "model III: points with a negative E_kinetic or E_strain, W_numerical "
                           "!= 0, W_friction > W_input, a non-finite output, or at_rest while "
                           "moving"),
    "bound": Check(1.3, "model III: largest |v_pipe| / (impulse of |Q| so far / M1 + 2 (sum of "
                        "|Q| over the load's pieces so far + F1 + F2) / Z1); below Courant 1 "
                        "the scheme overshoots a front by up to 27 % (dispersion)"),
    "rod reference": Check(1e-12, "model III, free rod at Courant 1: v_pipe and u_pipe vs the "
                                  "exact d'Alembert cell averages / their largest value / (1 + "
                                  "2.2e-4 n), n the internal steps so far"),
    "paths": Check(1e-15, "every core path vs the first on every grid (the compiled and the "
                          "plain exact solver are one source; model III: the numpy steps vs "
                          "the compiled kernels): largest |difference| / scale over all "
                          "outputs"),
    "fmu": Check(1e-12, "FMU vs the core on the host's own points: largest |difference| / "
                        "scale over all outputs"),
    "fd bound": Check(FD_C, "fd vs exact: largest |error| / (dt x R x G) over dt, dt/2, "
                            "dt/4 (R: scale of what drives the output, G: growth factor; see "
                            "fdcheck)"),
    "fd order": Check(0.1, "|observed order - 1| of the works' error, fd vs exact over dt, "
                           "dt/2, dt/4, on resolved cases without grazing and with G <= 10"),
}

#: outputs compared with the reference at every point
CONTINUOUS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "W_input", "W_friction",
              "W_friction_outer", "W_friction_inner", "W_face", "W_damping")
_WORKS = ("W_input", "W_friction", "W_friction_outer", "W_friction_inner", "W_face",
          "W_damping")
#: Outputs measured on one scale, the largest magnitude over the run of any of them. The
#: plug's velocity is set to the pipe's at each stick, so it is known to the pipe's absolute
#: accuracy (an event time one ulp off times the pipe's deceleration), not to a share of its
#: own peak, which can be 1e4 times smaller; likewise for the displacements. A static force
#: balances the other force and the load; a work is a difference of energies. The discrete
#: outputs (at_rest, modes) form one family each.
FAMILIES = (("v_pipe", "v_plug"), ("u_pipe", "u_plug"), ("F_outer", "F_inner"), _WORKS)
_PER_STEP_COLUMNS = frozenset(COLUMN[name] for name in PER_STEP)
_FORCES = ("F_outer", "F_inner")
_FRICTION_WORKS = ("W_friction", "W_friction_outer", "W_friction_inner", "W_face", "W_damping")


class Body(NamedTuple):
    """Masses [kg] and friction data of a case, from the paper's formulas."""

    M1: float
    M2: float          #: 0 without a plug
    F2: float          #: 0 without a plug
    k1: float          #: P1 tau1 [N/m]
    L1: float
    growth: bool
    Qf: float = 0.0    #: the annulus' end resistance q_face S1 [N]
    Qp: float = 0.0    #: the plug face's q_plug_face S2 [N] (0 without a plug)
    J_shaft: float = 0.0   #: Smith damping of shaft and plug friction [s/m]

    @classmethod
    def of(cls, params: dict, growth: bool) -> Body:
        R1, h1, L1 = params["R1"], params["h1"], params["L1"]
        S1 = math.pi * ((R1 + h1) ** 2 - R1 ** 2)
        M1 = params["rho1"] * S1 * L1
        plug = params["L2"] > 0.0 and params["tau2"] > 0.0
        M2 = params["rho2"] * math.pi * R1 ** 2 * params["L2"] if plug else 0.0
        F2 = 2.0 * math.pi * R1 * params["L2"] * params["tau2"] if plug else 0.0
        qp = params.get("q_plug_face", 0.0) * math.pi * R1 ** 2 if plug else 0.0
        return cls(M1, M2, F2, 2.0 * math.pi * (R1 + h1) * params["tau1"], L1, growth,
                   params.get("q_face", 0.0) * S1, qp, params.get("J_shaft", 0.0))

    @property
    def plug(self) -> bool:
        return self.M2 > 0.0

    def outer_limit(self, u1):
        """Outer friction limit [N] at pipe displacement(s) ``u1`` [m]."""
        length = np.clip(u1, 0.0, self.L1) if self.growth else self.L1 + 0.0 * u1
        return self.k1 * length


def relative_error(a, b, scale) -> float:
    """Largest |a - b| / scale; a zero scale allows no difference at all."""
    d = float(np.max(np.abs(np.asarray(a) - np.asarray(b)), initial=0.0))
    if d == 0.0:
        return 0.0
    return d / scale if scale > 0.0 else math.inf


def _scale(*arrays) -> float:
    return max(float(np.max(np.abs(a), initial=0.0)) for a in arrays)


def worst_of(values) -> float:
    """The largest of ``values``; NaN if any is NaN (Python's ``max`` keeps a NaN only when it
    comes first, so a NaN later in a list would pass unseen)."""
    return float(np.max(np.asarray(values, dtype=float), initial=0.0))


def _column_errors(differences, scales) -> float:
    """:func:`relative_error` of many columns at once: the largest ``differences[c] /
    scales[c]`` (a difference of 0 is 0, a zero scale allows none), NaN if any is NaN."""
    d, s = np.asarray(differences, dtype=float), np.asarray(scales, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.where(d == 0.0, 0.0, np.where(s > 0.0, d / s, np.inf))
    return worst_of(ratios)


def reference_errors(rows, ref: dict, times, events, stop: float,
                     load: float = 0.0) -> dict[str, float]:
    """Values of the three reference checks for one run.

    ``rows`` are a run's outputs at ``times``; ``ref`` the reference's outputs at the same
    times, ``events`` its ``(time, description)`` list. Scales: the reference's peaks per
    family (:data:`FAMILIES`); the forces' at least ``load`` [N], the largest |Q| of the
    case: a static force is what balances the load against the other forces, known to the
    round-off of the load (a pipe held at rest by a window that the load meets to the last
    digit: F_inner is 1 ulp of Q or exactly 0, the forces' peak 0).
    """
    times = np.asarray(times)
    scale = {n: _scale(*(ref[m] for m in family)) for family in FAMILIES for n in family}
    for name in _FORCES:
        scale[name] = max(scale[name], abs(load))
    err = worst_of([relative_error(rows[:, COLUMN[n]], ref[n], scale[n]) for n in CONTINUOUS])
    switch = np.array(sorted(t for t, _ in events))
    window = 1e-9 * stop
    if switch.size:
        k = np.clip(np.searchsorted(switch, times), 1, switch.size)
        near = np.minimum(np.abs(times - switch[k - 1]),
                          np.abs(times - switch[np.minimum(k, switch.size - 1)]))
        away = near > window
    else:
        away = np.ones(times.size, bool)
    forces = worst_of([relative_error(rows[away, COLUMN[n]], ref[n][away], scale[n])
                     for n in _FORCES])
    modes = sum(int(np.count_nonzero(differs[away]))
                for differs in _mode_differences(rows, ref, scale["v_pipe"]))
    return {"reference": err, "reference forces": forces, "reference modes": float(modes)}


#: a velocity within this share of the run's velocity scale is round-off (16 ulps)
_ROUND_OFF_SPEED = 16.0 * np.finfo(float).eps


def _mode_differences(rows, ref: dict, v_scale: float):
    """Per contact (pipe, pipe/plug), where its mode differs from the reference's, except where
    the label is round-off's: the contact's speed differs between the runs, and is within 16
    ulps of ``v_scale`` [m/s] in both. (A load at a damped body's friction limit to the last
    bit: the body slows to a terminal speed that is the limit's round-off, -1.2e-17 m/s
    sliding on in one run, 0 after a stop in the other, fuzz 2072:6080; which one depends on
    the last bit of the limit.) A label that differs where both speeds are exactly equal, or
    either is above round-off, counts."""
    tiny = _ROUND_OFF_SPEED * v_scale
    out = []
    for name, speed, speed_ref in zip(("pipe_mode", "plug_mode"),
                                      _contact_speeds(lambda n: rows[:, COLUMN[n]]),
                                      _contact_speeds(ref.__getitem__)):
        round_off = ((np.abs(speed) <= tiny) & (np.abs(speed_ref) <= tiny)
                     & (speed != speed_ref))
        out.append((rows[:, COLUMN[name]] != ref[name]) & ~round_off)
    return out


def _contact_speeds(column):
    """The pipe's velocity and the pipe's relative to the plug [m/s], from ``column(name)``."""
    return column("v_pipe"), column("v_pipe") - column("v_plug")


def grid_error(runs: list, families=FAMILIES) -> float:
    """Largest difference between runs at common times, per output, relative to the scale
    of its family (``families``, :data:`FAMILIES` by default; an output in none is a family
    of its own) over all of them. ``runs``: outputs at the same times. The outputs that
    describe a communication step as a whole (:data:`pipeplug.interface.PER_STEP`) depend on
    the grid by definition and are left out."""
    stack = np.stack(runs)
    scales = _family_scales(stack, families)
    columns = [col for col in range(stack.shape[2]) if col not in _PER_STEP_COLUMNS]
    differences = np.max(np.abs(stack[1:, :, columns] - stack[0][:, columns]), axis=(0, 1),
                         initial=0.0)
    return _column_errors(differences, [scales[col] for col in columns])


def _family_scales(stack, families=FAMILIES) -> list[float]:
    """Scale of each output column: the peak over ``stack[..., columns of its family]``."""
    stack = np.asarray(stack)
    peaks = np.max(np.abs(stack.reshape(-1, stack.shape[-1])), axis=0, initial=0.0)
    family_of = {name: family for family in families for name in family}
    return [max(float(peaks[COLUMN[m]]) for m in family_of.get(name, (name,)))
            for name in COLUMN]


def energy_error(rows, body: Body) -> float:
    """Largest |W_input - kinetic energy - W_friction - W_face - W_damping| over the largest
    work."""
    v1, v2 = rows[:, COLUMN["v_pipe"]], rows[:, COLUMN["v_plug"]]
    kinetic = 0.5 * body.M1 * v1 * v1 + 0.5 * body.M2 * v2 * v2
    balance = (rows[:, COLUMN["W_input"]] - kinetic - rows[:, COLUMN["W_friction"]]
               - rows[:, COLUMN["W_face"]] - rows[:, COLUMN["W_damping"]])
    return relative_error(balance, 0.0, _scale(*(rows[:, COLUMN[n]] for n in _WORKS)))


def friction_decrease(rows) -> float:
    """Largest decrease of a friction work between consecutive points (from 0 at t = 0),
    over the largest work."""
    works = rows[:, [COLUMN[name] for name in _FRICTION_WORKS]]
    steps = np.diff(works, axis=0, prepend=0.0)
    worst = worst_of(-np.min(steps, axis=0, initial=0.0))
    return relative_error(worst, 0.0, _scale(*(rows[:, COLUMN[n]] for n in _WORKS)))


def stuck_violations(rows, body: Body) -> float:
    """Points where a stuck contact moves, or a missing plug has a nonzero output."""
    c = COLUMN
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    bad = (rows[:, c["pipe_mode"]] == 0) & (v1 != 0.0)
    if body.plug:
        bad |= (rows[:, c["plug_mode"]] == 0) & (v1 != v2)
    else:
        bad |= np.any(rows[:, [c[n] for n in ("v_plug", "u_plug", "F_inner",
                                              "W_friction_inner", "plug_mode")]] != 0.0, axis=1)
    return float(np.count_nonzero(bad))


def limit_excess(rows, loads, body: Body) -> float:
    """How far a friction force exceeds its limit (relative; see :data:`CHECKS`)."""
    c = COLUMN
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    outer = body.outer_limit(rows[:, c["u_pipe"]]) * (1.0 + body.J_shaft * np.abs(v1))
    f_outer = np.abs(rows[:, c["F_outer"]])
    scale = outer + np.abs(loads) + body.F2
    with np.errstate(divide="ignore", invalid="ignore"):
        excess = np.where(scale > 0.0, (f_outer - outer) / scale, np.where(f_outer > 0, np.inf, 0))
    worst = float(np.max(excess, initial=0.0))
    f_inner = np.abs(rows[:, c["F_inner"]])
    if body.plug:
        inner = body.F2 * (1.0 + body.J_shaft * np.abs(v1 - v2))
        worst = worst_of([worst, float(np.max((f_inner - inner) / body.F2, initial=0.0))])
    return worst


def same_outputs_error(a, b) -> float:
    """Largest |a - b| / scale over all outputs (scales: the family peaks of ``b``)."""
    differences = np.max(np.abs(np.asarray(a) - np.asarray(b)), axis=0, initial=0.0)
    return _column_errors(differences, _family_scales(b))
