"""Reference solution of the rigid models I and II with end resistance and Smith damping (ODE).

The model of :mod:`pipeplug_references.face_ivp` with every sliding resistance ``R`` grown to
``R (1 + J v)`` by its sliding speed ``v`` (docs/physics.md, "Smith damping")::

    M1 U1'' = Q(t) + f1 + e1 + f2,      M2 U2'' = -f2 + e3
    f1 = -p c1(U1) (1 + J_shaft |U1'|),          e1 = -Qf (1 + J_face U1')    (p > 0 only)
    f2 = -r c2 (1 + J_shaft |U1' - U2'|),        e3 = -Qp (1 + J_face U2')    (g > 0 only)

while the contacts slide in directions ``(p, r, g)``; stuck contacts are set-valued with their
static limits. Each piece of constant modes is integrated by scipy's DOP853 (rtol 1e-13) with
the state ``(U1, U1', U2, U2')``, the works as quadratures of their powers (W_input,
W_friction_outer, W_friction_inner, W_face from the static parts, W_damping from the dampers:
an integral of ``J R v^2``, nothing in closed form) and the sliding speed ``w = U1' - U2'``
integrated in its own right. Two things the dampers bring to an explicit integrator:

* **The sliding speed as a state.** A plug that starts to slide in a moving pipe can slide for
  a moment only (the pipe's damper changes its deceleration) and stick again within one step.
  As a difference of two velocities near 6 m/s, ``w`` would be round-off for its first 1e-14 s,
  and the root finder of the event "plug sticks" took that round-off for the stick: pieces of
  4e-16 s without end. Integrated itself from its exact 0, ``w`` has its full relative
  precision, and the stick is found where it is.
* **Steps within the stiffness.** A damper makes a piece stiff (rates ``J R / M`` up to 1e4/s
  and more); DOP853 then steps at its stability limit, where the step's ends are accurate but
  its dense output is not (1e-7 of scale between the ends, measured). Each piece's step is
  capped at ``MAX_STEP_RATE`` over the largest rate of its modes (the trace of ``M^-1 C``, a
  bound of the largest eigenvalue), where the dense output is as accurate as the ends.

Terminal events: a sliding contact's velocity reaching zero, and every static force reaching
its limit (the damping forces vary, so a held pipe under a sliding plug, a carried plug and a
plug held by its face can break loose inside a piece), model II's kinks. Modes are decided at
every event by enumerating candidates, stuck first, each accepted when its static forces lie
in their windows and its starting accelerations have the sliding signs; the damping forces at
the decision are those of the current velocities (a contact starting to slide has none). The
contact that reached its limit is made to slide at the event.

Independence: numpy and scipy only, nothing of the project's core.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from .face_ivp import FaceSystem, candidate_modes
from .rigid_ivp import ATOL_FACTOR, FORCE_SLACK, MAX_EVENTS, MAX_STALLED, RTOL, _validate

__all__ = ["simulate_damped", "OUTPUT_NAMES", "MAX_STEP_RATE"]

#: largest step times the piece's largest damping rate (dense output accurate to 1e-14 of
#: scale at 2; 1e-7 at DOP853's stability limit, near 5)
MAX_STEP_RATE = 2.0
#: the state: U1, U1', U2, U2', W_input, the four dissipated works, w = U1' - U2'
_W = 9

OUTPUT_NAMES = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction", "W_friction_outer", "W_friction_inner", "W_face", "W_damping",
                "pipe_mode", "plug_mode")


class _System(FaceSystem):
    def __init__(self, params, contact_growth):
        params = dict(params or {})
        self.js = float(params.pop("J_shaft", 0.0))
        self.jf = float(params.pop("J_face", 0.0))
        if not (self.js >= 0.0 and self.jf >= 0.0):
            raise ValueError("J_shaft and J_face must be >= 0")
        super().__init__(params, contact_growth)


def _forces(s, mode, y, u_start, q):
    """Forces of the sliding contacts and their powers: ``(f1 shaft, e1 annulus, f2 inner,
    e3 plug face)`` [N] with the dampers, and ``(coulomb_outer, coulomb_inner, face, damping)``
    dissipated powers [W] (0 for a stuck contact)."""
    p, r, g = mode
    _, v1, _, v2 = y[:4]
    f1 = e1 = f2 = e3 = 0.0
    pw = [0.0, 0.0, 0.0, 0.0]
    if p != 0:
        slope, offset = s.branch(u_start, p)
        c1 = slope * y[0] + offset
        qf = s.qf_at(u_start) if p > 0 else 0.0
        f1 = -p * c1 - s.js * c1 * v1
        e1 = -qf - s.jf * qf * v1
        pw[0] += p * c1 * v1
        pw[2] += qf * v1
        pw[3] += (s.js * c1 + s.jf * qf) * v1 * v1
    if r != 0:
        dv = y[_W]
        f2 = -r * s.c2 - s.js * s.c2 * dv
        pw[1] += r * s.c2 * dv
        pw[3] += s.js * s.c2 * dv * dv
    if g > 0:
        e3 = -s.qp - s.jf * s.qp * v2
        pw[2] += s.qp * v2
        pw[3] += s.jf * s.qp * v2 * v2
    return (f1, e1, f2, e3), pw


def _accelerations(s, mode, y, u_start, q):
    """(a1, a2) and the static forces (soil on pipe, plug on pipe, soil on plug) in ``mode``."""
    p, r, g = mode
    (f1, e1, f2, e3), _ = _forces(s, mode, y, u_start, q)
    if p == 0 and r == 0:
        return 0.0, 0.0, None
    if p == 0:                         # the plug slides in a held pipe
        a2 = (-f2 + e3) / s.M2
        return 0.0, a2, (-(q + f2), f2, 0.0)
    if r == 0:                         # together
        if not s.plug:
            return (q + f1 + e1) / s.M1, 0.0, (f1 + e1, 0.0, 0.0)
        e3 = _plug_face_together(s, p, y)
        a = (q + f1 + e1 + e3) / (s.M1 + s.M2)
        return a, a, (f1 + e1, -(s.M2 * a - e3), e3)
    a1 = (q + f1 + e1 + f2) / s.M1
    if g == 0:                         # the plug held by its face
        return a1, 0.0, (f1 + e1, f2, f2)
    return a1, (-f2 + e3) / s.M2, (f1 + e1, f2, e3)


def _plug_face_together(s, p, y):
    return -(s.qp + s.jf * s.qp * y[1]) if p > 0 else 0.0


def _decide(s, q, y, forced):
    """The modes starting now: candidates stuck first, with ``forced`` (p, r, g) signs fixed
    (0: free); the damping forces are those of the current velocities."""
    u1, v1, _, v2 = y[:4]
    signs = [int(np.sign(v1)), int(np.sign(y[_W])) if s.plug else 0,
             int(np.sign(v2)) if s.plug else 0]
    signs = [a or b for a, b in zip(signs, forced)]
    ps, rs, gs = signs
    c1, qf, c2, qp = s.c1(u1), s.qf_at(u1), s.c2, s.qp
    # damping forces of the contacts sliding now (0 for one starting from rest)
    d1 = -(s.js * c1 + (s.jf * qf if v1 > 0.0 else 0.0)) * v1
    d2 = -s.js * c2 * y[_W]
    d3 = -s.jf * qp * max(v2, 0.0)
    slack = FORCE_SLACK * (abs(q) + c1 + qf + c2 + qp + abs(d1) + abs(d2) + abs(d3))
    cands = candidate_modes(s.plug, ps, rs, gs)
    for p, r, g in cands:
        fp = -(c1 + qf) if p > 0 else (c1 if p < 0 else 0.0)     # sliding Coulomb parts
        fr = -r * c2
        fg = -qp if g > 0 else 0.0
        if p == 0 and r == 0:
            qq = q + d1 + d2
            if not s.plug:
                ok = -(c1 + qf) - slack <= -qq <= c1 + slack
            else:   # f2 in [-c2, c2]; face f2 + d2... plug: 0 = -f2 - d2 + e3 + d3
                lo = max(-c2, -qq - c1, -qp - d2 - d3)
                hi = min(c2, -qq + c1 + qf, -d2 - d3)
                ok = lo <= hi + slack
        elif p == 0:
            f2 = fr + d2
            f1 = -(q + d1 + f2)
            a2 = (-f2 + fg + d3) / s.M2
            ok = -(c1 + qf) - slack <= f1 <= c1 + slack and (rs != 0 or -r * a2 > 0.0)
        elif r == 0:
            e3 = (-qp if p > 0 else 0.0) + d3 if s.plug else 0.0
            a = (q + fp + d1 + e3) / (s.M1 + s.M2)
            ok = ps != 0 or p * a > 0.0
            if ok and s.plug:
                f2 = -(s.M2 * a - e3)
                ok = abs(f2) <= c2 + slack
        else:
            a1 = (q + fp + d1 + fr + d2) / s.M1
            ok = ps != 0 or p * a1 > 0.0
            if g == 0:
                e3 = fr + d2
                ok = ok and -qp - slack <= e3 <= slack and (rs != 0 or r * a1 > 0.0)
            else:
                a2 = (-(fr + d2) + fg + d3) / s.M2
                ok = ok and (rs != 0 or r * (a1 - a2) > 0.0) and (gs != 0 or g * a2 > 0.0)
        if ok:
            return (p, r, g)
    raise RuntimeError(f"no consistent mode at Q={q!r}, y={y!r}, signs {signs}")


def _rate(s, mode):
    """The largest damping rate [1/s] of ``mode``: the trace of ``M^-1 C`` (C the dampers of
    the sliding contacts, the shaft's at its largest friction), >= its largest eigenvalue."""
    p, r, g = mode
    pipe = (s.js * s.c1(s.L1) + (s.jf * s.qf if p > 0 else 0.0)) if p != 0 else 0.0
    plug = s.jf * s.qp if g > 0 else 0.0
    if p == 0 and r == 0:
        return 0.0
    if r == 0:                         # together
        return (pipe + plug) / (s.M1 + s.M2)
    slide = s.js * s.c2
    if p == 0:
        return (slide + plug) / s.M2
    return (pipe + slide) / s.M1 + ((slide + plug) / s.M2 if g != 0 else 0.0)


def _events(s, q, mode, t0, y0):
    p, r, g = mode
    u_start = float(y0[0])
    evs = []
    slack = FORCE_SLACK * (abs(q) + s.c1(u_start) + s.qf + s.c2 + s.qp)

    def add(fun, name):
        def event(t, y):
            v = fun(y)
            return 1e-300 if t == t0 and v <= 0.0 else v

        event.terminal, event.direction, event.name = True, -1, name
        evs.append(event)

    def static(y):
        return _accelerations(s, mode, y, u_start, q)[2]

    if p != 0:
        add(lambda y: p * y[1], "pipe stops")
    if r != 0 and p != 0:
        add(lambda y: r * y[_W], "plug sticks")
    if p == 0 and r != 0:
        add(lambda y: -r * y[3], "plug sticks")
        c1, qf = s.c1(u_start), s.qf_at(u_start)
        add(lambda y: c1 - static(y)[0] + slack, "pipe breaks backward")
        add(lambda y: static(y)[0] + c1 + qf + slack, "pipe breaks forward")
    if p != 0 and r != 0 and g != 0 and s.qp > 0.0:
        add(lambda y: g * y[3], "plug stops")
    if p != 0 and r == 0 and s.plug:
        add(lambda y: s.c2 + static(y)[1] + slack, "plug breaks away forward")
        add(lambda y: s.c2 - static(y)[1] + slack, "plug breaks away backward")
    if p != 0 and r != 0 and g == 0:
        add(lambda y: static(y)[2] + s.qp + slack, "plug face breaks forward")
        add(lambda y: -static(y)[2] + slack, "plug face breaks backward")
    if p != 0 and s.kinks():
        for kink, name in ((0.0, "U1 reaches 0"), (s.L1, "U1 reaches L1")):
            if (p > 0 and u_start < kink) or (p < 0 and u_start > kink):
                add(lambda y, kink=kink: p * (kink - y[0]), name)
    return evs


_FORCED = {"pipe breaks backward": (-1, 0, 0), "pipe breaks forward": (1, 0, 0),
           "plug breaks away forward": (0, 1, 0), "plug breaks away backward": (0, -1, 0),
           "plug face breaks forward": (0, 0, 1), "plug face breaks backward": (0, 0, -1)}


def simulate_damped(params: dict, segments: list, times, contact_growth: bool, *,
                    rtol: float = RTOL, atol_factor: float = ATOL_FACTOR,
                    max_events: int = MAX_EVENTS) -> dict:
    """Model I or II with end resistance and Smith damping (``J_shaft``, ``J_face`` [s/m] in
    ``params``) under a piecewise-constant load: the arguments and results of
    :func:`pipeplug_references.face_ivp.simulate_face`, with ``W_damping`` [J]."""
    s = _System(params, contact_growth)
    segs, times = _validate(segments, times)
    n = times.size
    out = {name: np.zeros(n) for name in OUTPUT_NAMES}
    events: list = []
    t_final = float(times[-1]) if n else 0.0
    intervals, ta = [], 0.0
    for duration, q in segs:
        if duration > 0.0 and ta < t_final:
            intervals.append((ta, min(ta + duration, t_final), q))
        ta += duration
    if ta < t_final:
        intervals.append((ta, t_final, 0.0))
    impulse = sum(abs(q) * d for d, q in segs)
    vscale = impulse / s.M1 if impulse > 0.0 else 1.0
    tscale = max(t_final, 1e-300)
    wscale = max(impulse * vscale, 1e-300)
    atol = atol_factor * rtol * np.array([vscale * tscale, vscale, vscale * tscale, vscale]
                                         + [wscale] * 5 + [vscale])
    y = np.zeros(10)
    mode = (0, 0, 0)
    k = pieces = stalled = 0

    def record(idx, ys, q, mode, u_start):
        for j, col in zip(idx, ys.T):
            (f1, e1, f2, e3), _ = _forces(s, mode, col, u_start, q)
            if mode[0] == 0:           # held pipe: the soil's static force, the shaft first
                statics = _accelerations(s, mode, col, u_start, q)[2]
                soil, f2 = statics[:2] if statics else (static_rest[0], static_rest[1])
                f1 = max(soil, -s.c1(col[0]))
            elif mode[1] == 0 and s.plug:
                f2 = _accelerations(s, mode, col, u_start, q)[2][1]
            values = (col[1], col[3], col[0], col[2], f1, f2, col[4], col[5] + col[6], col[5],
                      col[6], col[7], col[8], mode[0], mode[1])
            for name, v in zip(OUTPUT_NAMES, values):
                out[name][j] = v

    static_rest = (0.0, 0.0)

    def rest_statics(q):
        """The static forces of everything stuck (the shaft first, the plug's force near 0)."""
        c1, qf = s.c1(y[0]), s.qf_at(y[0])
        if not s.plug:
            return -q, 0.0
        lo, hi = max(-s.c2, -q - c1, -s.qp), min(s.c2, -q + c1 + qf, 0.0)
        f2 = min(max(0.0, lo), hi)
        return -q - f2, f2

    t = 0.0
    for ta, tb, q in intervals:
        t = ta
        y[_W] = y[1] - y[3]
        mode = _decide(s, q, y, (0, 0, 0))
        events.append((t, f"load {q:.17g} N: {mode}"))
        while t < tb:
            pieces += 1
            if pieces > max_events:
                raise RuntimeError(f"more than {max_events} pieces by t = {t!r} s")
            u_start = float(y[0])
            j_end = int(np.searchsorted(times, tb, side="right"))
            if mode[0] == 0 and mode[1] == 0:
                static_rest = rest_statics(q)
                idx = np.arange(k, j_end)
                record(idx, np.repeat(y[:, None], len(idx), axis=1), q, mode, u_start)
                k, t = j_end, tb
                break
            frozen = mode

            def rhs(_, yy, frozen=frozen, u_start=u_start, q=q):
                a1, a2, _st = _accelerations(s, frozen, yy, u_start, q)
                _, pw = _forces(s, frozen, yy, u_start, q)
                return (yy[1], a1, yy[3], a2, q * yy[1], *pw, a1 - a2)

            evs = _events(s, q, mode, t, y)
            rate = _rate(s, mode)
            sol = solve_ivp(rhs, (t, tb), y, method="DOP853", events=evs or None, rtol=rtol,
                            atol=atol, dense_output=True,
                            max_step=MAX_STEP_RATE / rate if rate > 0.0 else np.inf)
            if sol.status < 0:
                raise RuntimeError(f"integration failed at t = {t!r}: {sol.message}")
            fired = None
            t_end, y_end = tb, sol.y[:, -1].copy()
            if sol.status == 1:
                i = next(i for i, te in enumerate(sol.t_events) if len(te))
                t_end, y_end, fired = (float(sol.t_events[i][-1]), sol.y_events[i][-1].copy(),
                                       evs[i].name)
            j_in = int(np.searchsorted(times, t_end, side="left" if fired else "right"))
            if j_in > k:
                idx = np.arange(k, j_in)
                record(idx, sol.sol(times[idx]).reshape(y.size, -1), q, mode, u_start)
                k = j_in
            stalled = stalled + 1 if t_end <= t + 4e-16 * max(abs(t), tscale) else 0
            if stalled > MAX_STALLED:
                raise RuntimeError(f"{stalled} events without progress at t = {t!r}: {fired}")
            y[:] = y_end
            t = t_end
            if fired is None:
                continue
            p, r, g = mode
            if fired == "pipe stops":
                y[1] = 0.0
                if r == 0 and s.plug:
                    y[3] = 0.0
            elif fired == "plug sticks":
                y[1] = y[3] = (s.M1 * y[1] + s.M2 * y[3]) / (s.M1 + s.M2) if p else 0.0
            elif fired == "plug stops":
                y[3] = 0.0
            elif fired == "U1 reaches 0":
                y[0] = 0.0
            elif fired == "U1 reaches L1":
                y[0] = s.L1
            if mode[0] == 0:
                y[1] = 0.0
            if s.plug and (mode[1] == 0 and fired != "plug breaks away forward"
                           and fired != "plug breaks away backward"):
                y[3] = y[1]
            if s.plug and mode[2] == 0 and mode[1] != 0:
                y[3] = 0.0
            # at an event the sliding speed follows the velocities just set (inside a piece it
            # is integrated from there in its own right)
            y[_W] = y[1] - y[3]
            mode = _decide(s, q, y, _FORCED.get(fired, (0, 0, 0)))
            events.append((t, f"{fired}: {mode}"))
    if k < n:
        static_rest = rest_statics(0.0)
        idx = np.arange(k, n)
        record(idx, np.repeat(y[:, None], len(idx), axis=1), 0.0, mode, float(y[0]))
    for name in ("pipe_mode", "plug_mode"):
        out[name] = out[name].astype(int)
    out["events"] = events
    return out
