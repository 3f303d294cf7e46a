"""Closed-form solution of model I under a single rectangular pulse.

Model I (N. I. Aleksandrova, "Influence of Soil Plug on Pipe Ramming Process", section 1): a rigid pipe
(mass M1) driven into immobile soil, with a rigid soil plug (mass M2) inside it, Coulomb dry friction with equal
static and sliding limits F1 = P1 L1 tau1 (soil on the pipe's outer face) and F2 = P2 L2 tau2 (plug on the inner
face), load Q(t) = Q0 for 0 <= t < t0 and 0 afterwards, rest at t = 0:

    M1 U1'' = Q - F1 k1 - F2 k2,    M2 U2'' = F2 k2,    k1 = sign U1',  k2 = sign(U1' - U2').

The (tau1, tau2) plane splits into five domains (paper's eqs. (7)-(10)):

- I   : slip until t1, then the plug overtakes; pipe stops at t3, plug at t4 = 2 t1;
- II  : slip until t1, then pipe and plug stick and coast to rest at t5 = tau* t0 / tau1;
- III : stuck together until t0, then the plug overtakes; pipe stops at t6, plug at t7;
- IV  : stuck together until t0 and after, at rest at t5;
- V   : tau1 >= tau*: nothing moves.

The printed paper has typos; this module uses the corrected forms: every later-phase displacement is the
integral from the switch time ts, (t - ts)(2 te - t - ts) instead of (t - ts)(2 te - t + ts); t6 =
t0 [1 + (tau* - tau1)(gamma - beta) / ((tau1 - beta tau2) gamma)]; P1 is the outer perimeter and P2 the inner one;
boundaries are non-strict as in the domain list of the paper, and a point within 1e-12 tau* of a boundary counts
as on it; coasting is written Q0 t0 - F1 t instead of F1 (t5 - t) so that tau1 = 0 (t5 = inf) is regular.
The plug is absent when L2 = 0 (beta = gamma = 0, plug outputs 0).

This module depends on numpy only, so it can serve as an independent reference for the solvers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

#: relative distance (in units of tau*) within which a point counts as lying on a domain boundary
BOUNDARY_RTOL = 1e-12


@dataclass(frozen=True)
class Case:
    """Model I parameters (SI). Defaults are the paper's section 3 values, tau1 = 0, tau2 = 0.01 MPa."""

    L1: float = 1.0  #: pipe length, m
    L2: float = 1.0  #: plug length, m (0 = no plug)
    R1: float = 0.035  #: pipe inner radius, m
    h1: float = 0.003  #: pipe wall thickness, m
    rho1: float = 7800.0  #: pipe density, kg/m3
    rho2: float = 1800.0  #: plug density, kg/m3
    tau1: float = 0.0  #: limit shear stress, pipe outer face / soil, Pa
    tau2: float = 1.0e4  #: limit shear stress, pipe inner face / plug, Pa
    Q0: float = 23000.0  #: pulse amplitude, N
    t0: float = 0.05  #: pulse duration, s

    P1 = property(lambda s: 2.0 * math.pi * (s.R1 + s.h1), doc="outer perimeter, m")
    P2 = property(lambda s: 2.0 * math.pi * s.R1, doc="inner perimeter, m")
    S1 = property(lambda s: math.pi * ((s.R1 + s.h1) ** 2 - s.R1**2), doc="pipe wall section, m2")
    S2 = property(lambda s: math.pi * s.R1**2, doc="plug section, m2")
    M1 = property(lambda s: s.rho1 * s.S1 * s.L1, doc="pipe mass, kg")
    M2 = property(lambda s: s.rho2 * s.S2 * s.L2, doc="plug mass, kg (0 without plug)")
    has_plug = property(lambda s: s.L2 > 0.0, doc="True when a plug is present")
    F1 = property(lambda s: s.P1 * s.L1 * s.tau1, doc="outer friction limit, N")
    F2 = property(lambda s: s.P2 * s.L2 * s.tau2, doc="inner friction limit, N (0 without plug)")
    tau_star = property(lambda s: s.Q0 / (s.P1 * s.L1), doc="tau* = Q0 / (P1 L1), Pa")
    beta = property(lambda s: s.P2 * s.L2 / (s.P1 * s.L1), doc="beta = P2 L2 / (P1 L1), 1")

    @property
    def gamma(self) -> float:
        """gamma = beta (1 + M1/M2), 1; 0 without plug (the plug term vanishes)."""
        return self.beta * (1.0 + self.M1 / self.M2) if self.has_plug else 0.0


def domain(case: Case) -> str:
    """Solution domain of `case` in the (tau1, tau2) plane: "I", "II", "III", "IV" or "V".

    Boundaries are non-strict as in the paper; a point within ``BOUNDARY_RTOL * tau*`` of a boundary
    counts as on it.
    """
    tol = BOUNDARY_RTOL * case.tau_star
    if case.tau1 >= case.tau_star - tol:
        return "V"
    slips_first = case.tau1 + case.gamma * case.tau2 < case.tau_star - tol
    sticks_later = case.gamma * case.tau2 >= case.tau1 - tol
    return {(True, False): "I", (True, True): "II", (False, False): "III", (False, True): "IV"}[
        (slips_first, sticks_later)
    ]


def _ratio(num: float, den: float) -> float:
    """num / den with den == 0 read as a time that is never reached (inf)."""
    return num / den if den > 0.0 else math.inf


def event_times(case: Case) -> dict:
    """Switch times of the domain of `case`, s (paper's t0, t1, t3..t7; inf where never reached).

    Returns
    -------
    dict
        I: t0, t1, t3, t4; II: t0, t1, t5; III: t0, t6, t7; IV: t0, t5; V: t0.
        The paper's formulas are reported as they are (t4 = 2 t1 also when the plug never moves);
        `stop_times` gives when each body actually comes to rest.
    """
    c, dom = case, domain(case)
    tau1, tau2, ts, b, g = c.tau1, c.tau2, c.tau_star, c.beta, c.gamma
    times = {"t0": c.t0}
    if dom in ("I", "II"):
        times["t1"] = _ratio(ts * c.t0, tau1 + g * tau2)
    if dom == "I":
        times["t3"] = times["t1"] * (tau1 + (g - 2.0 * b) * tau2) / (tau1 - b * tau2)
        times["t4"] = 2.0 * times["t1"]
    if dom in ("II", "IV"):
        times["t5"] = _ratio(ts * c.t0, tau1)
    if dom == "III":
        times["t6"] = c.t0 * (1.0 + (ts - tau1) * (g - b) / ((tau1 - b * tau2) * g))
        times["t7"] = c.t0 * (g * tau2 - tau1 + ts) / (g * tau2)
    return times


def stop_times(case: Case) -> tuple:
    """(pipe_stop, plug_stop), s: time after which each body stays at rest; 0 if it never moves, inf if never stops."""
    dom, ev = domain(case), event_times(case)
    ends = {"I": ("t3", "t4"), "II": ("t5", "t5"), "III": ("t6", "t7"), "IV": ("t5", "t5")}
    if dom == "V":
        return 0.0, 0.0
    if dom == "II" and case.F1 == 0.0:
        pipe = math.inf  # t1 may be inf too (no friction at all): the pipe flies on
    else:
        pipe = ev[ends[dom][0]]
    plug = ev[ends[dom][1]] if case.F2 > 0.0 else 0.0
    return pipe, plug


def _plug_decel(c: Case) -> float:
    """Plug deceleration under sliding inner friction, F2/M2, m/s2 (0 without plug)."""
    return c.F2 / c.M2 if c.has_plug else 0.0


def _slip_start(c: Case, t):
    """Both contacts sliding forward from rest (k1 = k2 = 1), t <= t1: (V1, V2, U1, U2)."""
    impulse = c.Q0 * np.minimum(t, c.t0)  # I(t), N s
    impulse_int = c.Q0 * np.where(
        t < c.t0, 0.5 * t * t, c.t0 * (t - 0.5 * c.t0)
    )  # integral of I, N s2
    drag, a2 = c.F1 + c.F2, _plug_decel(c)
    return (
        (impulse - drag * t) / c.M1,
        a2 * t,
        (impulse_int - 0.5 * drag * t * t) / c.M1,
        0.5 * a2 * t * t,
    )


def _pushed_together(c: Case, t):
    """Pipe and plug stuck together under the pulse, t <= t0: (V1, V2, U1, U2)."""
    acc = (c.Q0 - c.F1) / (c.M1 + c.M2)
    v, u = acc * t, 0.5 * acc * t * t
    plug = 1.0 if c.has_plug else 0.0
    return v, plug * v, u, plug * u


def _ramp_down(t, ts: float, te: float, decel: float):
    """Velocity and displacement gained since ts of a body decelerating at `decel` to rest at te (t >= ts)."""
    s = np.clip(t, ts, te)
    return decel * (te - s), 0.5 * decel * (s - ts) * (2.0 * te - s - ts)


def _joint_coast(c: Case, t, ts: float, t5: float):
    """Stuck pair coasting from ts >= t0 against F1 until t5: velocity and displacement gained since ts."""
    s = np.clip(t, ts, t5)
    mass, impulse = c.M1 + c.M2, c.Q0 * c.t0
    v = (
        np.maximum(impulse - c.F1 * s, 0.0) / mass
    )  # rounding must not make a stopped pair move back
    return v, (s - ts) * (impulse - 0.5 * c.F1 * (s + ts)) / mass


def _switch_time(case: Case, dom: str, ev: dict) -> float:
    """End of the first phase: t1 (I, II), t0 (III, IV)."""
    return ev["t1"] if dom in ("I", "II") else case.t0


def _kinematics(case: Case, dom: str, ev: dict, t):
    """(V1, V2, U1, U2) in m/s and m at the times t (array, s)."""
    c = case
    if dom == "V":
        zero = np.zeros_like(t)
        return zero, zero, zero, zero
    ts = _switch_time(c, dom, ev)
    first = _slip_start if dom in ("I", "II") else _pushed_together
    v1, v2, u1, u2 = first(c, np.minimum(t, ts))
    if math.isinf(ts):
        return v1, v2, u1, u2
    _, _, u1s, u2s = first(c, ts)
    if dom in ("I", "III"):
        te1, te2 = (ev["t3"], ev["t4"]) if dom == "I" else (ev["t6"], ev["t7"])
        w1, d1 = _ramp_down(t, ts, te1, (c.F1 - c.F2) / c.M1)
        w2, d2 = _ramp_down(t, ts, te2, _plug_decel(c))
    else:
        w1, d1 = _joint_coast(c, t, ts, ev["t5"])
        plug = 1.0 if c.has_plug else 0.0
        w2, d2 = plug * w1, plug * d1
    late = t >= ts
    return (
        np.where(late, w1, v1),
        np.where(late, w2, v2),
        np.where(late, u1s + d1, u1),
        np.where(late, u2s + d2, u2),
    )


def _forces(case: Case, dom: str, ev: dict, t):
    """(F_outer, F_inner): friction of soil and of plug on the pipe, N, signed along +x, right limits."""
    c = case
    if dom == "V":
        return np.where(t < c.t0, -c.Q0, 0.0), np.zeros_like(t)
    share = c.M2 / (c.M1 + c.M2)  # plug's share of a common acceleration
    ts = _switch_time(c, dom, ev)
    first_inner = -c.F2 if dom in ("I", "II") else -(c.Q0 - c.F1) * share
    if dom in ("I", "III"):
        te1, te2 = (ev["t3"], ev["t4"]) if dom == "I" else (ev["t6"], ev["t7"])
        # after te1 the pipe is held by static soil friction against the plug's drag
        outer = np.select([t < te1, t < te2], [-c.F1, -c.F2], 0.0)
        inner = np.select([t < ts, t < te2], [first_inner, c.F2], 0.0)
    else:
        moving = t < ev["t5"]
        outer = np.where(moving, -c.F1, 0.0)
        inner = np.select([t < ts, moving], [first_inner, c.F1 * share], 0.0)
    return outer + 0.0, inner + 0.0  # + 0.0 turns -0.0 (zero limits) into 0.0


def solution(case: Case, t) -> dict:
    """Exact model I response to the rectangular pulse.

    Parameters
    ----------
    case : Case
    t : array_like
        Times, s, finite and >= 0.

    Returns
    -------
    dict of ndarray
        V1, V2 (m/s), U1, U2 (m): pipe and plug velocity and displacement; F_outer, F_inner (N): friction of
        the soil and of the plug on the pipe along +x (static reaction when stuck; right limit at a switch);
        W_input (J): work of Q; W_friction (J): work dissipated by friction, W_input = kinetic energy + W_friction.
    """
    t = np.asarray(t, dtype=float)
    if not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("times must be finite and >= 0")
    dom, ev = domain(case), event_times(case)
    v1, v2, u1, u2 = _kinematics(case, dom, ev, t)
    f_outer, f_inner = _forces(case, dom, ev, t)
    u1_pulse = _kinematics(case, dom, ev, np.minimum(t, case.t0))[2]
    return {
        "V1": v1,
        "V2": v2,
        "U1": u1,
        "U2": u2,
        "F_outer": f_outer,
        "F_inner": f_inner,
        "W_input": case.Q0 * u1_pulse,
        "W_friction": case.F1 * u1 + case.F2 * _relative_slip(case, dom, ev, t, u1 - u2),
    }


def _relative_slip(case: Case, dom: str, ev: dict, t, rel):
    """Sliding distance of the plug in the pipe, m: total variation of U1 - U2.

    The relative velocity keeps one sign before the first switch time and one sign after it.
    """
    if dom == "V":
        return np.zeros_like(t)
    ts = _switch_time(case, dom, ev)
    _, _, u1, u2 = _kinematics(case, dom, ev, np.minimum(t, ts))
    rel_s = u1 - u2
    return np.abs(rel_s) + np.abs(rel - rel_s)


def figure_cases() -> dict:
    """Model I cases of the paper's Figs. 3, 4, 5 and 6a (section 3), curves in caption order.

    Returns
    -------
    dict
        {"3": [...], "4": [...], "5": [...], "6a": [...]}, lists of `Case`. The captions' 0.036564 MPa is
        tau*/(gamma + 1) exactly.
    """
    base, mpa = Case(), 1.0e6
    tau_c = base.tau_star / (base.gamma + 1.0)
    with_taus = lambda tau1, tau2: replace(base, tau1=tau1, tau2=tau2)  # noqa: E731
    return {
        "3": [with_taus(tau_c, tau2) for tau2 in (0.0, 0.01 * mpa, tau_c)],
        "4": [with_taus(tau1, 0.5 * tau1) for tau1 in (0.0, 0.02 * mpa, 0.053 * mpa, 0.07 * mpa)],
        "5": [with_taus(0.0, tau2 * mpa) for tau2 in (0.01, 0.02, 0.03, 0.05, 0.0589)],
        "6a": [
            with_taus(tau, tau)
            for tau in (0.0, 0.005 * mpa, 0.014 * mpa, 0.028 * mpa, tau_c, 0.065 * mpa)
        ],
    }
