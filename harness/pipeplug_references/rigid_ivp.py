"""Reference solution of the rigid models I and II under piecewise-constant loads, by ODE integration.

Model (N. I. Aleksandrova, pipe ramming with a soil plug; rigid pipe of mass M1, rigid plug of mass M2)::

    M1 U1'' = Q(t) + f1 + f2,      M2 U2'' = -f2
    f1 in -c1(U1) Sign(U1'),       c1 = P1 Lc tau1,   Lc = L1 (model I) or min(max(U1, 0), L1) (model II)
    f2 in -c2 Sign(U1' - U2'),     c2 = P2 L2 tau2    (no plug when L2 = 0 or tau2 = 0: plug outputs 0)

with Sign(0) = [-1, 1] (static limit = sliding limit) and rest at t = 0.

Method
------
The motion is split into pieces of constant contact mode (pipe: sliding +1 / -1 or stuck 0; plug: sliding
relative to the pipe +1 / -1 or stuck to it 0). In each piece the mode's ODE for (U1, U1', U2, U2') is
integrated by scipy's ``solve_ivp`` (DOP853, rtol 1e-13, atol = 1e-3 rtol times the velocity scale
V = total impulse / M1 and the displacement scale V * duration), with terminal events for

- a sliding contact's velocity reaching zero (pipe U1', relative U1' - U2'),
- the plug's required static force reaching its limit +-c2 while it moves with the pipe (model II: the
  required force -M2 (Q - p c1(U1)) / (M1 + M2) changes with U1),
- the contact-length kinks of model II (U1 reaching 0 or L1). A piece keeps the c1 formula of the branch
  it starts on, continued past the kink, so no step's right-hand side has a kink in it,

and every load-segment boundary ends a piece too. When the pipe is stuck its required static force
Q + f2 is constant over a piece (U1, Q and the sliding plug's c2 are fixed), as is everything when
nothing moves, so those are decided once at the piece start (a stuck pipe breaks away only at a load
change, which is a piece boundary). Event functions are compared at step ends only; two safeguards
make that reliable: an event function that is exactly 0 at the piece start (a contact that starts
sliding from zero relative velocity) reads as a tiny value on its starting side there, and a crossing
hidden inside a step that reaches past the piece's end is caught by comparing the piece's start and end
states and integrating the piece again up to its end (see :func:`_piece`).

At the end of every piece the contact whose event fired has its relative velocity set to exactly 0 (a
kink event puts U1 exactly on the kink; a plug sticking to a moving pipe takes, with it, their
momentum-conserving common velocity); another contact whose velocity is within 1e-12 of the velocity
scale and heading to zero is taken as stopping at the same instant (simultaneous events; the snap moves
the state by no more than the claimed accuracy: at 1e-10 a pipe stopping 1.1e-11 s after its plug stuck
was merged, off by 1.4e-9 of the displacement scale by the end). The new modes
then come from this module's own solution of the joint two-contact Coulomb problem
(:func:`coulomb_modes`): candidates are tried stuck-first, a stuck candidate is accepted when its static
force is within a relative slack of 1e-12 of the limit (a load exactly at a limit does not move a body),
a sliding candidate when its acceleration has the sliding sign. One second-order rule completes this:
with the plug moving together with the pipe in model II, the required plug force only grows
(d f2/dt = M2 P1 tau1 |U1'| / (M1 + M2) inside the penetrated region), so a plug at the +c2 limit there
slips at once (plug overtakes, zero initial relative acceleration) instead of sticking for a zero-length
piece. Grazing (velocity and acceleration vanishing together) therefore does not chatter; more than
``MAX_STALLED`` consecutive pieces without time progress, or more than ``max_events`` pieces, raise
``RuntimeError``. Modes are re-decided at every event and every load change.

Works are not integrated as extra ODE states: within a piece Q and the sliding friction laws are fixed
functions of the displacements, so W_input += Q dU1, W_friction_outer += p (G(U1) - G(U1_start)) with
G(U) = integral_0^U c1, W_friction_inner += r c2 d(U1 - U2), exactly. This keeps the ODE at 4 states (the
step-size control only sees the motion) and makes the energy balance W_input = kinetic energy + W_friction
a genuine check of the integrated motion rather than an identity of the integrator.

Independence
------------
Written from the equations above only; it imports numpy and scipy, nothing of the project. The project's
exact solver advances closed-form motion pieces; here each piece is a numerical integration with
numerically located events, and the Coulomb problem is solved by candidate enumeration.

Accuracy (default tolerances; errors relative to the peak of each quantity over the run)
--------
Measured by tests/references/test_rigid_ivp.py:

- model I vs the closed form (harness/closed_form.py), domains I-V and limit cases, 23 kN pulse of 0.05 s
  pushing and pulling: states and works <= 5e-15 (model I motion is piecewise polynomial, which DOP853
  integrates exactly), stop times <= 3e-15 relative, forces identical except at samples within 1e-9 s
  of a switch instant (the located switch may fall on the other side of such a sample);
- model II vs hand-derived solutions (harmonic push, L1 crossing, pulse ending mid-motion, pull-out past
  the start, plug breakaway from the moving pipe): displacement and velocity <= 3e-13, event times
  <= 2.4e-13 relative;
- energy balance <= 3e-13 of the largest work over 50 random runs (6e-13 over 80 random model II runs);
- default vs the tightest DOP853 tolerances (rtol 2.3e-14, atol 100x smaller): <= 1.1e-13 in the test's
  runs, <= 8e-13 over 80 random model II runs. Claimed accuracy: 2e-12 of scale (model II), 1e-14
  (model I).

Speed: ~3 ms (model I) and ~5.5 ms (model II) per case of 1-6 load segments over 0.2 s with 200 samples,
at most ~16 ms; the time goes to scipy's DOP853 stepping, its dense output at the samples and the
per-piece set-up of ``solve_ivp`` (~7 pieces and ~25 steps per case).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["simulate", "coulomb_modes", "DEFAULTS", "OUTPUT_NAMES"]

#: parameter defaults (SI)
DEFAULTS = {
    "L1": 1.0,
    "L2": 1.0,
    "R1": 0.035,
    "h1": 0.003,
    "rho1": 7800.0,
    "rho2": 1800.0,
    "tau1": 0.0,
    "tau2": 1.0e4,
}
#: array outputs of :func:`simulate` (plus ``events``)
OUTPUT_NAMES = (
    "v_pipe",
    "v_plug",
    "u_pipe",
    "u_plug",
    "F_outer",
    "F_inner",
    "W_input",
    "W_friction",
    "W_friction_outer",
    "W_friction_inner",
    "pipe_mode",
    "plug_mode",
)

RTOL = 1e-13  #: default relative tolerance of DOP853
FORCE_SLACK = 1e-12  #: relative slack of a static force at its limit (stuck wins)
SNAP_VTOL = 1e-12  #: relative velocity (of the velocity scale) taken as a simultaneous stop
MAX_EVENTS = 100_000  #: default cap on the number of pieces of one run
MAX_STALLED = 50  #: consecutive pieces without time progress before giving up
ATOL_FACTOR = 1e-3  #: default atol = atol_factor * rtol * (displacement, velocity scales)


class System:
    """Parameters, derived quantities and friction limits of one model."""

    def __init__(self, params: dict | None, contact_growth: bool):
        params = dict(params or {})
        unknown = set(params) - set(DEFAULTS)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)}; known: {sorted(DEFAULTS)}")
        p = {**DEFAULTS, **{k: float(v) for k, v in params.items()}}
        for name, value in p.items():
            if not math.isfinite(value) or value < 0.0:
                raise ValueError(f"parameter {name} = {value} must be finite and >= 0")
        for name in ("L1", "R1", "h1", "rho1"):
            if p[name] <= 0.0:
                raise ValueError(f"parameter {name} = {p[name]} must be > 0")
        self.L1, self.tau1 = p["L1"], p["tau1"]
        self.P1 = 2.0 * math.pi * (p["R1"] + p["h1"])
        self.P2 = 2.0 * math.pi * p["R1"]
        self.S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
        self.S2 = math.pi * p["R1"] ** 2
        self.M1 = p["rho1"] * self.S1 * p["L1"]
        self.plug = p["L2"] > 0.0 and p["tau2"] > 0.0
        if self.plug and p["rho2"] <= 0.0:
            raise ValueError("a plug with friction (L2 > 0, tau2 > 0) needs rho2 > 0")
        self.M2 = p["rho2"] * self.S2 * p["L2"] if self.plug else 0.0
        self.c2 = self.P2 * p["L2"] * p["tau2"] if self.plug else 0.0
        self.growth = bool(contact_growth)
        self.k = self.P1 * self.tau1  # model II: c1 = k * clip(U1, 0, L1)
        self.c1_full = self.P1 * self.L1 * self.tau1
        self.varying = self.growth and self.tau1 > 0.0  # c1 depends on U1

    def c1(self, u1):
        """Outer friction limit at pipe displacement u1 (scalar or array), N."""
        if not self.growth:
            return self.c1_full + 0.0 * np.asarray(u1) if np.ndim(u1) else self.c1_full
        return (
            self.k * np.clip(u1, 0.0, self.L1)
            if np.ndim(u1)
            else self.k * min(max(u1, 0.0), self.L1)
        )

    def dc1(self, u1: float, direction: int) -> float:
        """One-sided derivative of c1 along the direction of motion at u1, N/m."""
        if not self.varying:
            return 0.0
        inside = (0.0 <= u1 < self.L1) if direction > 0 else (0.0 < u1 <= self.L1)
        return self.k if inside else 0.0

    def branch(self, u1: float, direction: int):
        """(slope, offset): c1 = slope * U1 + offset on the branch of c1 that motion along `direction`
        enters from u1. A piece keeps its branch's formula (continued past the kink it ends at), so no
        integration step straddles a kink of the right-hand side."""
        if not self.growth:
            return 0.0, self.c1_full
        if self.dc1(u1, direction) > 0.0:
            return self.k, 0.0
        beyond = u1 >= self.L1 if direction > 0 else u1 > self.L1
        return (0.0, self.c1_full) if beyond else (0.0, 0.0)

    def outer_work(self, u1):
        """G(u1) = integral of c1 from 0 to u1, J (so outer friction work on a forward slide is dG)."""
        if not self.growth:
            return self.c1_full * np.asarray(u1, dtype=float)
        u = np.asarray(u1, dtype=float)
        inside = np.clip(u, 0.0, self.L1)
        return self.k * (0.5 * inside * inside + self.L1 * np.maximum(u - self.L1, 0.0))


def coulomb_modes(system: System, q: float, u1: float, pipe_sign: int, rel_sign: int):
    """Joint two-contact Coulomb problem: the contact modes that start at this instant.

    Parameters
    ----------
    system : System
    q : float
        Load, N.
    u1 : float
        Pipe displacement (sets c1 in model II), m.
    pipe_sign, rel_sign : int
        Sign of U1' and of U1' - U2' (0: that contact has zero relative velocity and its mode is free).
        A nonzero sign fixes that contact as sliding.

    Returns
    -------
    (p, r, f1, f2)
        Pipe mode, plug mode (0 = stuck), friction forces on the pipe along +x, N.
    """
    s = system
    c1, c2, m1, m2 = s.c1(u1), s.c2, s.M1, s.M2
    slack1 = FORCE_SLACK * (abs(q) + c1 + c2)
    slack2 = FORCE_SLACK * (c2 + m2 / (m1 + m2) * (abs(q) + c1)) if s.plug else 0.0
    ps = (0, 1, -1) if pipe_sign == 0 else (pipe_sign,)
    rs = ((0, 1, -1) if rel_sign == 0 else (rel_sign,)) if s.plug else (0,)
    candidates = sorted(
        ((p, r) for p in ps for r in rs), key=lambda pr: (pr[0] != 0) + (pr[1] != 0)
    )
    forced = set()  # pipe modes for which the plug must slip (drift rule)
    for p, r in candidates:
        if p == 0 and r == 0:  # nothing moves
            f1, f2 = -q, 0.0
            ok = abs(f1) <= c1 + slack1
        elif p == 0:  # pipe stuck, plug slides
            f2 = -r * c2
            f1 = -(q + f2)
            rel_acc = -r * c2 / m2  # a1 - a2 with a1 = 0
            ok = abs(f1) <= c1 + slack1 and (rel_sign != 0 or r * rel_acc > 0.0)
        elif r == 0:  # pipe slides, plug moves with it (or no plug)
            f1 = -p * c1
            a = (q + f1) / (m1 + m2)
            f2 = -m2 * a if s.plug else 0.0
            ok = pipe_sign != 0 or p * a > 0.0
            if ok and s.plug:
                ok = abs(f2) <= c2 + slack2
                # At +c2 and the required force grows: slip now. Only inside the penetrated
                # region: at a kink it stops growing (a breakaway found exactly there, as a
                # load at the limit without outer friction makes it, leaves the plug stuck,
                # whichever of the two simultaneous events the integrator reports first).
                if ok and f2 >= c2 - slack2 and s.dc1(u1, p) > 0.0:
                    ok = False
                    forced.add(p)
        else:  # both slide
            f1, f2 = -p * c1, -r * c2
            a1 = (q + f1 + f2) / m1
            a2 = r * c2 / m2
            ok = (pipe_sign != 0 or p * a1 > 0.0) and (
                rel_sign != 0 or r * (a1 - a2) > 0.0 or (r == -1 and p in forced)
            )
        if ok:
            return p, r, float(f1) + 0.0, float(f2) + 0.0
    raise RuntimeError(
        f"no consistent contact mode at Q={q!r}, U1={u1!r}, signs ({pipe_sign}, {rel_sign})"
    )


def _accelerations(s: System, q: float, p: int, r: int, u1: float):
    """(a1, a2) in mode (p, r) at pipe displacement u1."""
    if p == 0:
        return 0.0, (r * s.c2 / s.M2 if r else 0.0)
    c1 = s.c1(u1)
    if r == 0:
        a = (q - p * c1) / (s.M1 + s.M2)
        return a, (a if s.plug else 0.0)
    return (q - p * c1 - r * s.c2) / s.M1, r * s.c2 / s.M2


def _rhs(s: System, q: float, p: int, r: int, u1: float):
    """Right-hand side of the mode (p, r) ODE for y = (U1, V1, U2, V2), piece starting at U1 = u1."""
    m1, m2, c2 = s.M1, s.M2, s.c2
    if p == 0:
        a2 = r * c2 / m2

        def rhs(t, y):
            return (0.0, 0.0, y[3], a2)

        return rhs
    slope, offset = s.branch(u1, p)
    if r == 0:
        m = m1 + m2
        both = 1.0 if s.plug else 0.0
        if slope:

            def rhs(t, y):
                a = (q - p * (slope * y[0] + offset)) / m
                return (y[1], a, y[3], both * a)
        else:
            a = (q - p * offset) / m

            def rhs(t, y):
                return (y[1], a, y[3], both * a)

        return rhs
    a2 = r * c2 / m2
    if slope:

        def rhs(t, y):
            return (y[1], (q - p * (slope * y[0] + offset) - r * c2) / m1, y[3], a2)
    else:
        a1 = (q - p * offset - r * c2) / m1

        def rhs(t, y):
            return (y[1], a1, y[3], a2)

    return rhs


def _events(s: System, q: float, p: int, r: int, t0: float, y0):
    """Terminal events of the mode (p, r) piece starting at (t0, y0).

    An event function that is exactly 0 at t0 (a contact that starts sliding from zero relative velocity)
    reads as a tiny value on the side it starts from there: otherwise the root search of a first step
    that contains the real crossing would return t0 itself.
    """
    evs, add = event_list(t0)
    add_stops(add, p, r)
    if p != 0 and r == 0 and s.plug and s.dc1(y0[0], p) > 0.0:
        m, m2, c2 = s.M1 + s.M2, s.M2, s.c2
        slope, offset = s.branch(y0[0], p)

        def required(y):  # static plug force on the pipe moving together
            return -m2 * (q - p * (slope * y[0] + offset)) / m

        add(lambda y: c2 - required(y), -1, "plug breaks away forward")
        add(lambda y: c2 + required(y), -1, "plug breaks away backward")
    if p != 0 and s.varying:
        add_kinks(add, p, y0[0], s.L1)
    return evs


def event_list(t0: float):
    """An empty list of terminal events of a piece starting at ``t0`` [s], and the function
    ``add(fun, direction, name)`` that appends the event ``fun(y)`` to it (see :func:`_events`
    for the value it reads at ``t0``)."""
    evs = []

    def add(fun, direction, name):
        def event(t, y):
            g = fun(y)
            return -direction * 1e-300 if g == 0.0 and t == t0 else g

        event.terminal, event.direction, event.name = True, direction, name
        evs.append(event)

    return evs, add


def add_stops(add, p: int, r: int) -> None:
    """The events of a sliding pipe stopping (``p`` != 0) and of a slipping plug sticking
    (``r`` != 0): the state is (U1, U1', U2, U2', ...)."""
    if p != 0:
        add(lambda y: y[1], -p, "pipe stops")
    if r != 0:
        add(lambda y: y[1] - y[3], -r, "plug sticks")


def add_kinks(add, p: int, u: float, L1: float) -> None:
    """Model II's kinks ahead of a pipe at ``u`` [m] moving the way of ``p``: the contact
    length min(max(U1, 0), L1) changes law at U1 = 0 and U1 = L1 [m]."""
    for kink, name in ((0.0, "U1 reaches 0"), (L1, "U1 reaches L1")):
        if (p > 0 and u < kink) or (p < 0 and u > kink):
            add(lambda y, kink=kink: y[0] - kink, p, name)


def _piece(s: System, q: float, p: int, r: int, t: float, tb: float, y0, samples, rtol, atol):
    """Integrate mode (p, r) from (t, y0) until its first event or tb.

    Returns (t_end, y_end, fired event name or None, solve_ivp result holding the samples before t_end).

    Event functions are only compared at step ends, so a step reaching past the piece's end can hide
    a crossing that comes back within the step (e.g. U1 crossing 0 and returning after the pipe stops,
    which ends the piece). Within a piece the kink and breakaway functions are monotone (the pipe moves
    one way), so such a crossing shows as a sign change between the piece's start and end states; then
    the piece is integrated again with its end as bound, where every step end lies inside the piece.
    """
    return integrate_piece(_rhs(s, q, p, r, y0[0]), _events(s, q, p, r, t, y0), t, tb, y0,
                           samples, rtol, atol)


def integrate_piece(rhs, evs, t: float, tb: float, y0, samples, rtol, atol):
    """Integrate ``rhs`` from (t, y0) until the first of the terminal events ``evs`` or tb,
    with DOP853, sampled at ``samples`` [s]; the second pass of :func:`_piece` when a crossing
    hides inside a step past the piece's end."""
    bound = tb
    for attempt in range(2):
        t_eval = np.append(samples[samples < bound], bound)
        sol = solve_ivp(
            rhs,
            (t, bound),
            y0,
            method="DOP853",
            t_eval=t_eval,
            events=evs or None,
            rtol=rtol,
            atol=atol,
        )
        if sol.status < 0:
            raise RuntimeError(f"integration failed at t = {t!r}: {sol.message}")
        if sol.status == 1:
            i = next(i for i, te in enumerate(sol.t_events) if len(te))
            t_end, y_end, fired = (
                float(sol.t_events[i][-1]),
                sol.y_events[i][-1].copy(),
                evs[i].name,
            )
        elif attempt == 0:
            t_end, y_end, fired = tb, sol.y[:, -1].copy(), None
        else:  # the hidden crossing is at the bound itself: keep the first end
            t_end, y_end = bound, sol.y[:, -1].copy()
        if attempt or t_end == t:
            break
        hidden = [
            e.name
            for e in evs
            if e.name != fired
            and e.direction * e(t, y0) < 0.0
            and e.direction * e(t_end, y_end) >= 0.0
        ]
        if not hidden:
            break
        bound = t_end
    return t_end, y_end, fired, sol


def _validate(segments, times):
    times = np.asarray(times, dtype=float)
    if (
        times.ndim != 1
        or not np.all(np.isfinite(times))
        or np.any(times < 0.0)
        or np.any(np.diff(times) < 0)
    ):
        raise ValueError("times must be a 1-D non-decreasing array of finite values >= 0")
    segs = []
    for duration, q in segments:
        duration, q = float(duration), float(q)
        if not (math.isfinite(duration) and duration >= 0.0 and math.isfinite(q)):
            raise ValueError(
                f"bad segment ({duration}, {q}): duration must be finite >= 0, Q finite"
            )
        segs.append((duration, q))
    return segs, times


def simulate(
    params: dict,
    segments: list,
    times,
    contact_growth: bool,
    *,
    rtol: float = RTOL,
    atol_factor: float = ATOL_FACTOR,
    max_events: int = MAX_EVENTS,
) -> dict:
    """Rigid model I (``contact_growth=False``) or II under a piecewise-constant load.

    Parameters
    ----------
    params : dict
        Parameters by name (L1, L2, R1, h1, rho1, rho2, tau1, tau2; SI); missing ones take `DEFAULTS`.
    segments : list of (duration [s], Q [N])
        Applied one after another from t = 0; Q = 0 after the last one.
    times : array_like
        Non-decreasing sample times >= 0, s.
    contact_growth : bool
        Model II (outer friction over the penetrated length) instead of model I.
    rtol, atol_factor : float
        Tolerances of DOP853: rtol, and atol = atol_factor * rtol * (total impulse / M1) * (1, duration)
        for the velocities and displacements.
    max_events : int
        Cap on the number of pieces; more raise ``RuntimeError``.

    Returns
    -------
    dict
        Arrays at `times` for every name in `OUTPUT_NAMES` (states continuous; forces and modes are
        right limits, under the load of the segment that starts at a load edge), and ``events``: list of
        (time, description) of every mode decision.
    """
    s = System(params, contact_growth)
    segs, times_asked = _validate(segments, times)
    times, repeat = np.unique(times_asked, return_inverse=True)  # solve_ivp wants distinct times
    n = times.size
    out = {name: np.zeros(n) for name in OUTPUT_NAMES}
    events: list = []
    out["events"] = events
    if n == 0:
        out.update(pipe_mode=np.zeros(0, int), plug_mode=np.zeros(0, int))
        return out
    t_final = float(times[-1])

    # load intervals [ta, tb) covering [0, t_final), then the final instant t_final
    intervals, ta = [], 0.0
    for duration, q in segs:
        tb = ta + duration
        if tb > ta and ta < t_final:
            intervals.append((ta, min(tb, t_final), q))
        ta = tb
    if ta < t_final:
        intervals.append((ta, t_final, 0.0))
    q_final = 0.0
    ta = 0.0
    for duration, q in segs:
        if ta <= t_final < ta + duration:
            q_final = q
            break
        ta += duration

    impulse = sum(abs(q) * d for d, q in segs)
    vscale = impulse / s.M1 if impulse > 0.0 else 1.0
    tscale = max(t_final, sum(d for d, _ in segs), 1e-300)
    v2scale = min(vscale, s.c2 * tscale / s.M2) if s.plug else vscale
    v2scale = v2scale if v2scale > 0.0 else vscale
    atol = atol_factor * rtol * np.array([vscale * tscale, vscale, v2scale * tscale, v2scale])
    vtol = SNAP_VTOL * vscale

    y = np.zeros(4)  # U1, V1, U2, V2
    work = np.zeros(3)  # W_input, W_friction_outer, W_friction_inner
    p = r = 0
    k = 0  # next sample index
    n_pieces = stalled = 0

    def fill(idx, ys, q, p, r, y_start, w_start):
        """Store samples idx (array of indices) with states ys (4 x m) of a piece in mode (p, r)."""
        u1, v1, u2, v2 = ys
        c1 = s.c1(u1)
        if p != 0:
            f1 = -p * c1
            f2 = (
                (-r * s.c2 + 0.0 * u1)
                if r
                else (-s.M2 * (q - p * c1) / (s.M1 + s.M2) if s.plug else 0.0 * u1)
            )
        else:
            f2 = -r * s.c2 + 0.0 * u1
            f1 = -(q + f2)
        w_in = w_start[0] + q * (u1 - y_start[0])
        w_fo = w_start[1] + (p * (s.outer_work(u1) - s.outer_work(y_start[0])) if p else 0.0 * u1)
        w_fi = w_start[2] + (r * s.c2 * ((u1 - u2) - (y_start[0] - y_start[2])) if r else 0.0 * u1)
        for name, val in (
            ("u_pipe", u1),
            ("v_pipe", v1),
            ("u_plug", u2),
            ("v_plug", v2),
            ("F_outer", f1 + 0.0),
            ("F_inner", f2 + 0.0),
            ("W_input", w_in),
            ("W_friction_outer", w_fo),
            ("W_friction_inner", w_fi),
            ("W_friction", w_fo + w_fi),
            ("pipe_mode", p + 0.0 * u1),
            ("plug_mode", r + 0.0 * u1),
        ):
            out[name][idx] = val

    def decide(t, q, prev_q, fired, cause):
        """Snap, then choose the modes starting at t under load q. Updates y, p, r."""
        nonlocal p, r

        def stick():
            """Plug and pipe take one velocity: the momentum-conserving one while the pipe moves
            (the plug's friction is internal, so it is right to second order in the event time,
            which scipy locates to ~1e-15 s absolute; the braking pipe's own velocity would be
            off by that times the relative acceleration: 6.5e-10 of it for a plug of 63 pipe
            masses), the pipe's when the pipe is at rest."""
            moving = p != 0 and y[1] != 0.0
            y[1] = y[3] = (s.M1 * y[1] + s.M2 * y[3]) / (s.M1 + s.M2) if moving else y[1]

        if fired == "pipe stops":
            y[1] = 0.0
        elif fired == "plug sticks":
            stick()
        elif fired == "U1 reaches 0":
            y[0] = 0.0
        elif fired == "U1 reaches L1":
            y[0] = s.L1
        if p != 0 or r != 0:  # another contact stopping at the same instant
            a1, a2 = _accelerations(s, prev_q, p, r, y[0])
            if p != 0 and y[1] != 0.0 and abs(y[1]) <= vtol and p * a1 < 0.0:
                y[1] = 0.0
                if r == 0 and s.plug:
                    y[3] = 0.0
            if r != 0 and y[1] != y[3] and abs(y[1] - y[3]) <= vtol and r * (a1 - a2) < 0.0:
                stick()
        if p == 0:
            y[1] = 0.0
        if r == 0:
            y[3] = y[1] if s.plug else 0.0
        pipe_sign = int(np.sign(y[1]))
        rel_sign = int(np.sign(y[1] - y[3])) if s.plug else 0
        p, r, _, _ = coulomb_modes(s, q, float(y[0]), pipe_sign, rel_sign)
        events.append((t, f"{cause}: pipe {p:+d}, plug {r:+d}"))

    prev_q = 0.0
    for ta, tb, q in intervals:
        t = ta
        decide(t, q, prev_q, None, f"load {q:.17g} N")
        prev_q = q
        while t < tb:
            n_pieces += 1
            if n_pieces > max_events:
                raise RuntimeError(
                    f"more than {max_events} pieces by t = {t!r} s (chattering contact mode?)"
                )
            y0, w0 = y.copy(), work.copy()
            j_end = int(np.searchsorted(times, tb, side="left"))  # samples in [t, tb)
            at_start = k + int(np.searchsorted(times[k:j_end], t, side="right"))
            if at_start > k:
                fill(np.arange(k, at_start), y0[:, None], q, p, r, y0, w0)
                k = at_start
            if p == 0 and r == 0:  # at rest: nothing to integrate
                fill(
                    np.arange(k, j_end), np.repeat(y0[:, None], j_end - k, axis=1), q, p, r, y0, w0
                )
                k, t = j_end, tb
                break
            t_end, y_end, fired, sol = _piece(s, q, p, r, t, tb, y0, times[k:j_end], rtol, atol)
            m = int(np.searchsorted(sol.t, t_end, side="left"))  # returned samples before t_end
            m = min(m, j_end - k)
            if m:
                fill(np.arange(k, k + m), sol.y[:, :m], q, p, r, y0, w0)
                k += m
            # works over the whole piece
            work[0] += q * (y_end[0] - y0[0])
            if p:
                work[1] += p * (float(s.outer_work(y_end[0])) - float(s.outer_work(y0[0])))
            if r:
                work[2] += r * s.c2 * ((y_end[0] - y_end[2]) - (y0[0] - y0[2]))
            stalled = (
                stalled + 1 if t_end <= t + 4.0 * np.finfo(float).eps * max(abs(t), tscale) else 0
            )
            if stalled > MAX_STALLED:
                raise RuntimeError(
                    f"{stalled} consecutive events without time progress at t = {t!r} s "
                    f"(grazing contact?), last: {fired}"
                )
            y[:] = y_end
            t = t_end
            if fired is not None:
                decide(t, q, q, fired, fired)
    # final instant: forces and modes under the load that holds at t_final
    decide(t_final, q_final, prev_q, None, f"end, load {q_final:.17g} N")
    if k < n:
        fill(
            np.arange(k, n),
            np.repeat(y[:, None], n - k, axis=1),
            q_final,
            p,
            r,
            y.copy(),
            work.copy(),
        )
    for name in OUTPUT_NAMES:
        out[name] = out[name][repeat]
    for name in ("pipe_mode", "plug_mode"):
        out[name] = out[name].astype(int)
    return out
