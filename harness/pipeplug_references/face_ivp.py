"""Reference solution of the rigid models I and II with end resistance, by ODE integration.

The model of :mod:`pipeplug_references.rigid_ivp` with the soil's resistance at the front ends::

    M1 U1'' = Q(t) + f1 + e1 + f2,      M2 U2'' = -f2 + e3
    e1 in -Qf Sign+(U1'),   Qf = q_face S1   (model II: only while U1 >= 0, the front in the soil)
    e3 in -Qp Sign+(U2'),   Qp = q_plug_face S2
    Sign+(v) = 1 (v > 0), 0 (v < 0), [0, 1] (v = 0)

The soil's force on the pipe, f1 + e1, lies in [-(c1 + Qf), c1]; the plug gets a third contact,
with the soil. The motion is split into pieces of constant modes ``(p, r, g)``: the signs of
U1', U1' - U2' and U2' (0: stuck). Each piece's ODE is integrated by scipy's DOP853 (rtol
1e-13) with terminal events for a sliding contact's velocity reaching zero (the pipe's, the
relative one, and the plug's own where its face's force switches), the carried plug's required
force reaching its limit (model II), and the kinks of model II (U1 = 0: the contact and the
face begin; U1 = L1). Modes are decided at every event by enumerating candidates, stuck
first, each accepted when its static forces lie in their windows (relative slack 1e-12) and its
sliding accelerations have the sliding signs (:func:`face_modes`). Where everything is stuck the
forces are not unique; this takes the plug's inner force as close to 0 as the windows allow and
the shaft friction before the end resistance (the convention docs/physics.md states).

Works: W_face += -e1 dU1 - e3 dU2 over each piece (the end forces are constant in it), like the
other works of :mod:`~pipeplug_references.rigid_ivp`, from the displacements. The energy balance
W_input = kinetic energy + W_friction + W_face checks the integrated motion.

Independence: numpy and scipy only, nothing of the project's core.
"""
from __future__ import annotations

import numpy as np

from .rigid_ivp import (
    ATOL_FACTOR,
    FORCE_SLACK,
    MAX_EVENTS,
    MAX_STALLED,
    RTOL,
    SNAP_VTOL,
    System,
    _validate,
    add_kinks,
    add_stops,
    event_list,
    integrate_piece,
)

__all__ = ["simulate_face", "face_modes", "FaceSystem", "OUTPUT_NAMES"]

OUTPUT_NAMES = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction", "W_friction_outer", "W_friction_inner", "W_face", "pipe_mode",
                "plug_mode")


class FaceSystem(System):
    """:class:`~pipeplug_references.rigid_ivp.System` with the end resistances Qf, Qp [N]."""

    def __init__(self, params: dict | None, contact_growth: bool):
        params = dict(params or {})
        q_face = float(params.pop("q_face", 0.0))
        q_plug = float(params.pop("q_plug_face", 0.0))
        if not (q_face >= 0.0 and q_plug >= 0.0):
            raise ValueError("q_face and q_plug_face must be >= 0")
        super().__init__(params, contact_growth)
        self.qf = q_face * self.S1
        self.qp = q_plug * self.S2 if self.plug else 0.0

    def qf_at(self, u1: float) -> float:
        """The pipe's end resistance limit with the front end at u1 (moving forward from it)."""
        return 0.0 if (self.growth and u1 < 0.0) else self.qf

    def kinks(self) -> bool:
        """Whether U1 = 0 and L1 end pieces (model II with friction or an end resistance)."""
        return self.varying or (self.growth and self.qf > 0.0)


def _plug_face(s: FaceSystem, g: int) -> float:
    return -s.qp if g > 0 else 0.0


def _pipe_face(s: FaceSystem, p: int, u1: float) -> float:
    return -s.qf_at(u1) if p > 0 else 0.0


def candidate_modes(plug: bool, ps: int, rs: int, gs: int) -> list[tuple[int, int, int]]:
    """The modes ``(p, r, g)`` (signs of U1', U1' - U2', U2'; 0: stuck) that agree with the
    fixed signs ``ps, rs, gs`` (0: free), stuck contacts first.

    The plug's own sign follows from the other two where they fix it: carried (r = 0) it moves
    with the pipe, under a stuck pipe it moves against the slip, with the pipe and the slip of
    opposite signs it moves with the pipe; only a plug slower than a pipe moving the same way
    may move either way or rest.
    """
    cands = []
    for p in ((0, 1, -1) if ps == 0 else (ps,)):
        for r in (((0, 1, -1) if rs == 0 else (rs,)) if plug else (0,)):
            if not plug:
                g_ok = (0,)
            elif r == 0:
                g_ok = (p,)
            elif p == 0:
                g_ok = (-r,)
            elif p != r:
                g_ok = (p,)
            else:
                g_ok = (0, 1, -1)
            cands += [(p, r, g) for g in g_ok if not (plug and gs != 0 and g != gs)]
    cands.sort(key=lambda c: (c[0] != 0) + (c[1] != 0) + 0.5 * (c[2] != 0))
    return cands


def face_modes(s: FaceSystem, q: float, u1: float, ps: int, rs: int, gs: int):
    """The modes ``(p, r, g)`` starting now, and the static forces of a stuck pipe
    ``(f1 soil on pipe, f2 plug on pipe, e3 soil on plug)`` [N] (0 where sliding).

    ``ps, rs, gs``: the signs of U1', U1' - U2', U2' (0: free); a nonzero one fixes that contact
    as sliding.
    """
    c1, c2, m1, m2, qp = s.c1(u1), s.c2, s.M1, s.M2, s.qp
    qf = s.qf_at(u1)
    slack = FORCE_SLACK * (abs(q) + c1 + qf + c2 + qp)
    cands = candidate_modes(s.plug, ps, rs, gs)
    forced = set()
    for p, r, g in cands:
        f1 = f2 = e3 = 0.0
        if p == 0 and r == 0 and not s.plug:
            f1 = -q
            ok = -(c1 + qf) - slack <= f1 <= c1 + slack
        elif p == 0 and r == 0:
            # f2 in [-c2, c2], e3 = f2 in [-qp, 0], f1 = -q - f2 in [-(c1 + qf), c1]
            lo = max(-c2, -q - c1, -qp)
            hi = min(c2, -q + c1 + qf, 0.0)
            ok = lo <= hi + slack
            f2 = min(max(0.0, lo), hi)
            f1, e3 = -q - f2, f2
        elif p == 0:
            f2 = -r * c2
            f1 = -(q + f2)
            a2 = (r * c2 + _plug_face(s, g)) / m2
            ok = -(c1 + qf) - slack <= f1 <= c1 + slack and (rs != 0 or -r * a2 > 0.0)
        elif r == 0:
            e3 = _plug_face(s, p) if s.plug else 0.0
            a = (q - p * c1 + _pipe_face(s, p, u1) + e3) / (m1 + m2)
            f2 = -(m2 * a - e3) if s.plug else 0.0
            ok = ps != 0 or p * a > 0.0
            if ok and s.plug:
                slack2 = FORCE_SLACK * (c2 + m2 / (m1 + m2) * (abs(q) + c1 + qf + qp))
                ok = abs(f2) <= c2 + slack2
                if ok and f2 >= c2 - slack2 and s.dc1(u1, p) > 0.0:
                    ok = False          # at +c2 with a growing need: the plug slips now
                    forced.add(p)
        else:
            a1 = (q - p * c1 + _pipe_face(s, p, u1) - r * c2) / m1
            ok = ps != 0 or p * a1 > 0.0
            if g == 0:
                e3 = -r * c2                # the plug held by its face: e3 = f2
                ok = ok and -qp - slack <= e3 <= slack and (rs != 0 or r * a1 > 0.0)
            else:
                a2 = (r * c2 + _plug_face(s, g)) / m2
                ok = ok and (rs != 0 or r * (a1 - a2) > 0.0 or (r == -1 and p in forced))
                ok = ok and (gs != 0 or g * a2 > 0.0)
        if ok:
            return (p, r, g), (float(f1), float(f2), float(e3))
    raise RuntimeError(f"no consistent mode at Q={q!r}, U1={u1!r}, signs {(ps, rs, gs)}")


def _accelerations(s, q, mode, u1, u_start):
    """(a1, a2) in ``mode`` at u1, on the branch of a piece that started at u_start."""
    p, r, g = mode
    if p == 0:
        return 0.0, ((r * s.c2 + _plug_face(s, g)) / s.M2 if r else 0.0)
    slope, offset = s.branch(u_start, p)
    c1 = slope * u1 + offset
    face = _pipe_face(s, p, u_start)
    if r == 0:
        e3 = _plug_face(s, p) if s.plug else 0.0
        a = (q - p * c1 + face + e3) / (s.M1 + s.M2)
        return a, (a if s.plug else 0.0)
    a2 = (r * s.c2 + _plug_face(s, g)) / s.M2 if g else 0.0
    return (q - p * c1 + face - r * s.c2) / s.M1, a2


def _events(s, q, mode, t0, y0):
    p, r, g = mode
    evs, add = event_list(t0)
    add_stops(add, p, r)
    if p != 0 and r != 0 and g != 0 and s.qp > 0.0:
        add(lambda y: y[3], -g, "plug stops")
    if p != 0 and r == 0 and s.plug and s.dc1(y0[0], p) > 0.0:
        u_start = y0[0]

        def required(y):
            a = _accelerations(s, q, mode, y[0], u_start)[0]
            return -(s.M2 * a - (_plug_face(s, p)))

        add(lambda y: s.c2 - required(y), -1, "plug breaks away forward")
        add(lambda y: s.c2 + required(y), -1, "plug breaks away backward")
    if p != 0 and s.kinks():
        add_kinks(add, p, y0[0], s.L1)
    return evs


def _piece(s, q, mode, t, tb, y0, samples, rtol, atol):
    """Integrate ``mode`` from (t, y0) to its first event or tb (as rigid_ivp's, with its
    second pass when a crossing hides inside a step past the piece's end)."""
    evs = _events(s, q, mode, t, y0)
    u_start = float(y0[0])

    def rhs(_, y):
        a1, a2 = _accelerations(s, q, mode, y[0], u_start)
        return (y[1], a1, y[3], a2)

    return integrate_piece(rhs, evs, t, tb, y0, samples, rtol, atol)


def simulate_face(params: dict, segments: list, times, contact_growth: bool, *,
                  rtol: float = RTOL, atol_factor: float = ATOL_FACTOR,
                  max_events: int = MAX_EVENTS) -> dict:
    """Model I or II with end resistance under a piecewise-constant load: the arguments and
    results of :func:`pipeplug_references.rigid_ivp.simulate`, with ``W_face`` [J]."""
    s = FaceSystem(params, contact_growth)
    segs, times_asked = _validate(segments, times)
    times, repeat = np.unique(times_asked, return_inverse=True)
    n = times.size
    out = {name: np.zeros(n) for name in OUTPUT_NAMES}
    events: list = []
    if n == 0:
        out["events"] = events
        return out
    t_final = float(times[-1])
    intervals, ta = [], 0.0
    for duration, q in segs:
        tb = ta + duration
        if tb > ta and ta < t_final:
            intervals.append((ta, min(tb, t_final), q))
        ta = tb
    if ta < t_final:
        intervals.append((ta, t_final, 0.0))
    q_final, ta = 0.0, 0.0
    for duration, q in segs:
        if ta <= t_final < ta + duration:
            q_final = q
            break
        ta += duration
    impulse = sum(abs(q) * d for d, q in segs)
    vscale = impulse / s.M1 if impulse > 0.0 else 1.0
    tscale = max(t_final, sum(d for d, _ in segs), 1e-300)
    atol = atol_factor * rtol * np.array([vscale * tscale, vscale, vscale * tscale, vscale])
    vtol = SNAP_VTOL * vscale

    y = np.zeros(4)
    work = np.zeros(4)              # W_input, W_friction_outer, W_friction_inner, W_face
    mode = (0, 0, 0)
    statics = (0.0, 0.0, 0.0)
    k = n_pieces = stalled = 0

    def face_work(mode, u_start, d1, d2):
        p, _, g = mode
        return -_pipe_face(s, p, u_start) * d1 - (_plug_face(s, g) if s.plug else 0.0) * d2

    def fill(idx, ys, q, mode, y_start, w_start):
        p, r, g = mode
        u1, v1, u2, v2 = ys
        c1 = s.c1(u1)
        if p != 0:
            f1 = -p * c1
            if r:
                f2 = -r * s.c2 + 0.0 * u1
            elif s.plug:
                a = _accelerations(s, q, mode, u1, y_start[0])[0]
                f2 = -(s.M2 * a - _plug_face(s, p))
            else:
                f2 = 0.0 * u1
        elif r:
            f2 = -r * s.c2 + 0.0 * u1
            f1 = np.maximum(-(q + f2), -c1)
        else:
            f1 = np.maximum(statics[0] + 0.0 * u1, -c1)
            f2 = statics[1] + 0.0 * u1
        w = [w_start[0] + q * (u1 - y_start[0]),
             w_start[1] + (p * (s.outer_work(u1) - s.outer_work(y_start[0])) if p else 0.0 * u1),
             w_start[2] + (r * s.c2 * ((u1 - u2) - (y_start[0] - y_start[2])) if r
                           else 0.0 * u1),
             w_start[3] + face_work(mode, y_start[0], u1 - y_start[0], u2 - y_start[2])]
        for name, val in (("u_pipe", u1), ("v_pipe", v1), ("u_plug", u2), ("v_plug", v2),
                          ("F_outer", f1 + 0.0), ("F_inner", f2 + 0.0), ("W_input", w[0]),
                          ("W_friction_outer", w[1]), ("W_friction_inner", w[2]),
                          ("W_friction", w[1] + w[2]), ("W_face", w[3]),
                          ("pipe_mode", p + 0.0 * u1), ("plug_mode", r + 0.0 * u1)):
            out[name][idx] = val

    def decide(t, q, prev_q, fired, cause):
        nonlocal mode, statics
        p, r, g = mode

        def stick():
            moving = p != 0 and y[1] != 0.0
            y[1] = y[3] = (s.M1 * y[1] + s.M2 * y[3]) / (s.M1 + s.M2) if moving else y[1]

        if fired == "pipe stops":
            y[1] = 0.0
        elif fired == "plug sticks":
            stick()
        elif fired == "plug stops":
            y[3] = 0.0
        elif fired == "U1 reaches 0":
            y[0] = 0.0
        elif fired == "U1 reaches L1":
            y[0] = s.L1
        if p != 0 or r != 0:
            a1, a2 = _accelerations(s, prev_q, mode, y[0], y[0])
            if p != 0 and y[1] != 0.0 and abs(y[1]) <= vtol and p * a1 < 0.0:
                y[1] = 0.0
                if r == 0 and s.plug:
                    y[3] = 0.0
            if r != 0 and y[1] != y[3] and abs(y[1] - y[3]) <= vtol and r * (a1 - a2) < 0.0:
                stick()
            if g != 0 and r != 0 and y[3] != 0.0 and abs(y[3]) <= vtol and g * a2 < 0.0:
                y[3] = 0.0
        if p == 0:
            y[1] = 0.0
        if r == 0:
            y[3] = y[1] if s.plug else 0.0
        if s.plug and g == 0 and r != 0:
            y[3] = 0.0
        signs = (int(np.sign(y[1])), int(np.sign(y[1] - y[3])) if s.plug else 0,
                 int(np.sign(y[3])) if s.plug else 0)
        mode, statics = face_modes(s, q, float(y[0]), *signs)
        p, r, g = mode
        events.append((t, f"{cause}: pipe {p:+d}, plug {r:+d}, face {g:+d}"))

    prev_q = 0.0
    for ta, tb, q in intervals:
        t = ta
        decide(t, q, prev_q, None, f"load {q:.17g} N")
        prev_q = q
        while t < tb:
            n_pieces += 1
            if n_pieces > max_events:
                raise RuntimeError(f"more than {max_events} pieces by t = {t!r} s")
            y0, w0 = y.copy(), work.copy()
            j_end = int(np.searchsorted(times, tb, side="left"))
            at_start = k + int(np.searchsorted(times[k:j_end], t, side="right"))
            if at_start > k:
                fill(np.arange(k, at_start), y0[:, None], q, mode, y0, w0)
                k = at_start
            if mode[0] == 0 and mode[1] == 0:
                fill(np.arange(k, j_end), np.repeat(y0[:, None], j_end - k, axis=1), q, mode,
                     y0, w0)
                k, t = j_end, tb
                break
            t_end, y_end, fired, sol = _piece(s, q, mode, t, tb, y0, times[k:j_end], rtol, atol)
            m = min(int(np.searchsorted(sol.t, t_end, side="left")), j_end - k)
            if m:
                fill(np.arange(k, k + m), sol.y[:, :m], q, mode, y0, w0)
                k += m
            p, r, g = mode
            work[0] += q * (y_end[0] - y0[0])
            if p:
                work[1] += p * (float(s.outer_work(y_end[0])) - float(s.outer_work(y0[0])))
            if r:
                work[2] += r * s.c2 * ((y_end[0] - y_end[2]) - (y0[0] - y0[2]))
            work[3] += face_work(mode, y0[0], y_end[0] - y0[0], y_end[2] - y0[2])
            stalled = (stalled + 1 if t_end <= t + 4.0 * np.finfo(float).eps
                       * max(abs(t), tscale) else 0)
            if stalled > MAX_STALLED:
                raise RuntimeError(f"{stalled} events without time progress at t = {t!r} s, "
                                   f"last: {fired}")
            y[:] = y_end
            t = t_end
            if fired is not None:
                decide(t, q, q, fired, fired)
    decide(t_final, q_final, prev_q, None, f"end, load {q_final:.17g} N")
    if k < n:
        fill(np.arange(k, n), np.repeat(y[:, None], n - k, axis=1), q_final, mode, y.copy(),
             work.copy())
    for name in OUTPUT_NAMES:
        out[name] = out[name][repeat]
    for name in ("pipe_mode", "plug_mode"):
        out[name] = out[name].astype(int)
    out["events"] = events
    return out
