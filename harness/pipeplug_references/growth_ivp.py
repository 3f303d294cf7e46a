"""Reference solution of the rigid models with a plug that grows, by ODE integration.

The plug is the soil inside the pipe, its front face at the pipe's front end; its length L2
follows the relative displacement while it slides in the pipe (docs/physics.md, "A plug that
grows")::

    M1 U1'' = Q + f1 + e1 + f2,          f2 = -r k L2 while sliding (k = P2 tau2)
    P' = r k L2 + e3 - mu (V2 - V1)+ V2,  P = mu L2 V2 (mu = rho2 S2),  L2' = V1 - V2
    W_accretion' = mu |V1 - V2| V2^2 / 2,  G' = V2 - V1

The gap G = L1 - L2 between the plug and the head is a state of its own, carried from piece to
piece: the plug fills the pipe at G = 0, known to the precision of the gap, not to round-off of
L1 as L1 - L2 would be (a plug pulled 1e-8 m out and driven back, fuzz growth 4043:6960).

At L2 = L1 the pipe is plugged (the plug meets the head in a plastic impact and is carried
until it slides ahead); at L2 = 0 the plug is gone (the pipe alone, coring again as soon as
it advances). Every piece of constant modes ``(p, r, g)`` (signs of U1', U1' - U2', U2'; 0
stuck) is integrated by scipy's DOP853 (rtol 1e-13), the works and W_accretion as parts of the
state, with a terminal event for every mode change: a velocity's zero, the plug filling or
leaving the pipe, a held pipe's or plug's load leaving its window, model II's kinks. Modes are
decided at every event by :func:`pipeplug_references.face_ivp.face_modes` on a system of the
plug's current length; a plugged pipe that would core is decided as one body.

Independence: numpy, scipy and the other references only, nothing of the project's core.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from .face_ivp import FaceSystem, face_modes
from .rigid_ivp import MAX_STALLED, RTOL

__all__ = ["simulate_growth", "OUTPUT_NAMES"]

OUTPUT_NAMES = ("v_pipe", "v_plug", "u_pipe", "u_plug", "L2_now", "W_input", "W_friction_outer",
                "W_friction_inner", "W_face", "W_accretion", "W_removed", "E_kinetic")
_U1, _V1, _U2, _P, _L2, _WO, _WI, _WF, _WA, _GAP = range(10)
_EMPTY = 1e-10          #: of L1: a shorter plug is taken as gone at a decision


class _Growth:
    """The constants and the current plug length."""

    def __init__(self, params: dict, contact_growth: bool):
        self.params = dict(params)
        self.after = float(self.params.pop("L2_after_cleanout", 0.0))
        self.growth = contact_growth
        full = FaceSystem(dict(self.params, L2=self.params.get("L1", 1.0)), contact_growth)
        self.base = full
        self.L1, self.M1 = full.L1, full.M1
        p = {"R1": 0.035, "rho2": 1800.0, "tau2": 1.0e4, **self.params}
        self.mu = p["rho2"] * math.pi * p["R1"] ** 2
        self.k = 2.0 * math.pi * p["R1"] * p["tau2"]
        self.qp = float(self.params.get("q_plug_face", 0.0)) * math.pi * p["R1"] ** 2
        self.gripped = False        # a plug of length 0 carried by the pipe (_grips)

    def system(self, l2: float, merged: bool = False) -> FaceSystem:
        """face_ivp's system for a plug of length l2 (merged: one body with the pipe)."""
        s = FaceSystem(dict(self.params, L2=l2), self.growth)
        if merged:
            s.M1, s.qf, s.plug, s.M2, s.c2, s.qp = s.M1 + s.M2, s.qf + s.qp, False, 0.0, 0.0, 0.0
        return s


def _v2(g, mode, y, l2_0=0.0):
    """The plug's velocity in the state ``y`` whose length entry is ``L2 - l2_0`` [m]."""
    p, r, gg = mode
    if r == 0:
        return y[_V1]
    if gg == 0:
        return 0.0
    if r < 0:           # a shrinking plug carries its velocity in the state (_shrinks)
        return y[_P]
    l2 = l2_0 + y[_L2]
    return y[_P] / (g.mu * l2) if l2 > 0.0 else 0.0


def _shrinks(mode) -> bool:
    """Whether the state's entry ``_P`` holds the plug's velocity V2 instead of its momentum:
    while the plug leaves through the front end (r < 0) and moves. Its momentum and its
    length then vanish together where it leaves, and V2 = P/(mu L2) is 0/0 there (DOP853 ran
    out of step size on a plug 4e-15 m long); V2 itself is smooth: mu L2 V2' = -k L2 + e3,
    the soil that leaves taking its own momentum."""
    return mode[1] < 0 and mode[2] != 0


def _rhs(g, s, q, mode, u_start, l2_0):
    p, r, gg = mode
    slope, offset = s.branch(u_start, p) if p else (0.0, 0.0)
    face = -s.qf_at(u_start) if p > 0 else 0.0
    shrinks = _shrinks(mode)

    def rhs(_, y):
        v1 = y[_V1] if p else 0.0
        l2 = l2_0 + y[_L2]
        c1 = slope * y[_U1] + offset
        if r == 0:      # (merged: the plug's face is in the body's, s.qf, s.qp = 0)
            e3 = -s.qp if (p > 0 and l2 > 0.0) else 0.0
            a1 = (q - p * c1 + face + e3) / (g.M1 + g.mu * l2) if p else 0.0
            carried = v1 if (l2 > 0.0 or g.gripped) else 0.0
            return [v1, a1, carried, g.mu * l2 * a1, 0.0, p * c1 * v1, 0.0, -(face + e3) * v1,
                    0.0, 0.0]
        v2 = _v2(g, mode, y, l2_0)
        a1 = (q - p * c1 + face - r * g.k * l2) / g.M1 if p else 0.0
        e3 = (-g.qp if gg > 0 else 0.0) if gg else 0.0
        dp = 0.0
        if shrinks:
            dp = r * g.k / g.mu + (e3 / (g.mu * l2) if e3 else 0.0)
        elif gg:
            dp = r * g.k * l2 + e3
        # the slip r (V1 - V2) >= 0 in the piece, signed, not |V1 - V2|: past the piece's
        # end a kink at the stick would spoil DOP853's whole last step, dense output
        # included, which the stick is located on (fuzz 4091:3320: W_accretion 7e-3 J high,
        # 13 times the plug's last 5.9e-4 J, as it stopped leaving a held pipe)
        slip = r * (v1 - v2)
        return [v1, a1, v2, dp, v1 - v2, p * c1 * v1, g.k * l2 * slip, -face * v1 - e3 * v2,
                0.5 * g.mu * slip * v2 * v2, v2 - v1]
    return rhs


def _events(g, s, q, mode, y0, merged, v_tol, l2_0):
    """The piece's terminal events on its state from ``y0``, whose length entry is
    ``L2 - l2_0`` [m]; ``v_tol`` [m/s]: the velocities' round-off (below)."""
    p, r, gg = mode
    evs = []

    def v2(y):
        return _v2(g, mode, y, l2_0)

    def add(fun, name, direction=-1):
        def event(t, y):
            return fun(y)
        event.terminal, event.direction, event.name = True, direction, name
        evs.append(event)

    if p:
        add(lambda y: p * y[_V1], "pipe stops")
    if r:
        # A slip that starts from relative rest (a plug breaking away, where the accelerations
        # are equal) sticks only once the relative velocity has come back by more than its
        # round-off: an event root located some ulps off left the relative acceleration
        # below round-off of the wrong sign, and the plug stuck again at once, without end
        # (fuzz 4043:7540 and 7910).
        rest = max(v_tol, 1e-15 * abs(y0[_V1])) if y0[_V1] == _v2(g, mode, y0) else 0.0
        add(lambda y: r * (y[_V1] - v2(y)) + rest, "plug sticks")
        if r > 0:
            add(lambda y: y[_GAP], "plug fills the pipe")
        else:
            # A plug held back by its face slows as qp/(mu L2) and would stop only some
            # 1e-17 m before its end (DOP853 ran out of step size there, 4043:4590): shorter
            # than round-off of L1 it is gone (as at a decision). Any other leaves at L2 = 0,
            # where its displacement is kept: at 1e-10 L1 that was off by V2 times the time
            # the rest takes to leave (2.2e-7 m, a plug leaving at 5e-3 m/s relative to its
            # pipe and at -8 m/s: fuzz 4092:2590).
            held_back = gg > 0 and g.qp > 0.0
            rest = _EMPTY * g.L1 if held_back else 0.0
            add(lambda y: (l2_0 - rest) + y[_L2], "plug leaves the pipe")
        if gg and g.qp > 0.0 and p:
            add(lambda y: gg * v2(y), "plug stops")
        if gg == 0:
            add(lambda y: g.qp - r * g.k * (l2_0 + y[_L2]), "held plug goes")
            add(lambda y: r * g.k * (l2_0 + y[_L2]) + 1e-300, "held plug goes")
        if p == 0:
            c1, qf = s.c1(y0[_U1]), s.qf_at(y0[_U1])
            add(lambda y: c1 + qf - (q - r * g.k * (l2_0 + y[_L2])), "held pipe goes")
            add(lambda y: c1 + (q - r * g.k * (l2_0 + y[_L2])), "held pipe goes")
    if p and r == 0 and y0[_L2] > 0.0 and s.dc1(y0[_U1], p) > 0.0:
        u_start = y0[_U1]
        m2 = g.mu * y0[_L2]
        c2 = g.k * y0[_L2]
        slope, offset = s.branch(u_start, p)
        face = -s.qf_at(u_start) if p > 0 else 0.0
        e3 = -g.qp if p > 0 and (not merged or s.qf_at(u_start) > 0.0) else 0.0
        # the body's end force: the merged body's face holds the plug's already (e3 counted
        # twice broke a plugged pipe's plug away too early: fuzz 4043:7540)
        ends = face if merged else face + e3

        def f2(y):
            a = (q - p * (slope * y[_U1] + offset) + ends) / (g.M1 + m2)
            return -(m2 * a - e3)
        add(lambda y: c2 - f2(y), "plug breaks away ahead")
        if not merged:
            add(lambda y: c2 + f2(y), "plug breaks away behind")
    if p and s.kinks():
        for kink in (0.0, s.L1):
            if (p > 0 and y0[_U1] < kink) or (p < 0 and y0[_U1] > kink):
                add(lambda y, kink=kink: y[_U1] - kink, "kink", p)
    return evs


def _grips(g, s, q, y) -> bool:
    """An advancing pipe with no plug whose front soil moves with it (from rest, already
    gripped, or a plug shorter than round-off that stuck to it): the soil grips the pipe when
    no face resistance holds it and the pipe's acceleration a1 <= k/mu, the limit of a plug of
    length eps -> 0 stuck to the pipe (it needs mu eps a1, it holds k eps). It then stays of
    length 0, carried, while the pipe advances with a1 <= k/mu. (From rest, a plug growing from
    nothing, V2 = k t/(3 mu), also solves the equations for a1 > k/(3 mu), but it is not that
    limit, and for k/(3 mu a1) > 5/7 it is unstable.)"""
    if not (g.gripped or y[_V1] == 0.0) or g.qp > 0.0:
        g.gripped = False
        return False
    u1 = float(y[_U1])
    a1 = (q - s.c1(u1) - s.qf_at(u1)) / g.M1
    g.gripped = g.k >= g.mu * a1
    return g.gripped


def _decide(g, q, y, forced=(0, 0, 0)):
    """The modes at y (``y[-1]``: the plug's velocity), and whether the plugged pipe carries
    its plug as one body; ``forced``: signs fixed by the event (a held body that goes)."""
    l2 = y[_L2]
    ps = forced[0] or int(np.sign(y[_V1]))
    if l2 <= 0.0:
        s = g.system(0.0)
        (p, _, _), _ = face_modes(s, q, float(y[_U1]), ps, 0, 0)
        if p > 0 and not _grips(g, s, q, y):
            return (p, 1, 0 if g.qp > 0.0 else 1), False
        g.gripped = g.gripped and p > 0
        return (p, 0, 0), False
    s = g.system(l2)
    rs = forced[1] or int(np.sign(y[_V1] - y[-1]))
    gs = forced[2] or int(np.sign(y[-1]))
    mode, _ = face_modes(s, q, float(y[_U1]), ps, rs, gs)
    # A full plug that does not slide ahead is one body with the pipe, also at rest: its face
    # is the body's front (model II: in the soil from U1 = 0 on). Held as a plug of its own
    # it took Qp at U1 < 0 and kept a pushed pipe at rest there (fuzz 4043:6970).
    if y[_GAP] <= 0.0 and mode[1] >= 0:
        sm = g.system(l2, merged=True)
        (p, _, _), _ = face_modes(sm, q, float(y[_U1]), ps, 0, 0)
        return (p, 0, p), True
    return mode, False


def _self_similar(g, s, q, y, t, w_in):
    """A plug growing from nothing behind a pipe starting from rest: (P, L2) = (0, 0) is
    singular for V2 = P/(mu L2), so the piece starts after tau = 1e-8 sqrt(M1/k) from the
    leading-order solution V1 = a1 t, V2 = c a1 t (c = k/(3 mu a1)), L2 = (1 - c) a1 t^2/2,
    P = mu L2 V2 (next order (k/M1) tau^2 below round-off). Updates y; returns the new time,
    W_input and V2."""
    u1 = float(y[_U1])
    c1, qf = s.c1(u1), s.qf_at(u1)
    a1 = (q - c1 - qf) / g.M1
    c = g.k / (3.0 * g.mu * a1)
    tau = 1e-8 * math.sqrt(g.M1 / g.k)
    d1 = 0.5 * a1 * tau * tau
    v2, l2 = c * a1 * tau, (1.0 - c) * d1
    slip = (1.0 - c) * a1
    y[_U1] += d1
    y[_V1] = a1 * tau
    y[_U2] += c * d1
    y[_P], y[_L2], y[_GAP] = g.mu * l2 * v2, l2, g.L1 - l2
    y[_WO] += c1 * d1
    y[_WI] += g.k * (1.0 - c) * a1 * slip * tau ** 4 / 8.0
    y[_WF] += qf * d1
    y[_WA] += g.mu * slip * (c * a1) ** 2 * tau ** 4 / 8.0
    return t + tau, w_in + q * d1, v2


def _crossed_twice(evs, sol, t_hi) -> list:
    """Events that left the piece and came back within the last step before ``t_hi`` [s]
    (scipy looks for sign changes between a step's ends only): DOP853 takes a whole
    quadratic motion in one step, so the plug could fill the pipe and, the pipe's velocity
    turning past its stop, empty it again before the step's end (4043:1710: L2 1.9e-2 past
    L1 unseen). Their roots on the dense output, as ``(t, index)``."""
    from scipy.optimize import brentq

    t_lo = sol.t[-2] if len(sol.t) > 1 else sol.t[0]
    out = []
    for i, event in enumerate(evs):
        inside = -event.direction if event.direction else 1.0

        def value(t, event=event, inside=inside):
            return inside * event(t, sol.sol(t))
        if t_hi > t_lo and value(t_lo) > 0.0 and value(t_hi) < 0.0:
            out.append((brentq(value, t_lo, t_hi, xtol=1e-300, rtol=1e-15), i))
    return out


def simulate_growth(params: dict, segments: list, times, contact_growth: bool = False, *,
                    cleanouts=(), rtol: float = RTOL, max_pieces: int = 100_000) -> dict:
    """The rigid model with a growing plug under a piecewise-constant load.

    Parameters
    ----------
    params : dict
        Contract names (SI): the pipe, the plug (``L2`` may be 0), ``tau1``, ``tau2 > 0``,
        ``q_face``, ``q_plug_face``, ``L2_after_cleanout``.
    segments : list of (duration [s], Q [N])
        The load; 0 after the last segment.
    times : array
        Increasing sample times [s].
    contact_growth : bool
        Model II.
    cleanouts : sequence of float
        Times [s] of clean-outs (each cuts the plug to ``L2_after_cleanout``).

    Returns
    -------
    dict of arrays, :data:`OUTPUT_NAMES` at ``times``, and ``events`` (time, text).

    The absolute tolerances are 1e-3 rtol of the run's scales: first estimated from the load's
    impulse over the pipe's mass, then, where that was more than ten times too large (a plug
    of 300 pipe masses moving with it: works of 5 J against an estimate of 2e6 J, and
    W_accretion 1.6e-3 off its own value, 9e-9 of the works), measured on that run and run again.
    """
    out = _simulate(params, segments, times, contact_growth, cleanouts, rtol, max_pieces, None)
    estimated = out.pop("scales")
    measured = (max(float(np.max(np.abs(out[n]), initial=0.0)) for n in names)
                for names in (("u_pipe", "u_plug"), ("v_pipe", "v_plug"), _WORK_NAMES))
    measured = tuple(max(m, 1e-300) for m in measured)
    if any(e > 10.0 * m for e, m in zip(estimated, measured)):
        out = _simulate(params, segments, times, contact_growth, cleanouts, rtol, max_pieces,
                        tuple(min(e, m) for e, m in zip(estimated, measured)))
        out.pop("scales")
    return out


_WORK_NAMES = ("W_input", "W_friction_outer", "W_friction_inner", "W_face", "W_accretion",
               "W_removed", "E_kinetic")


def _simulate(params, segments, times, contact_growth, cleanouts, rtol, max_pieces, scales):
    """:func:`simulate_growth` with the scales ``(length [m], velocity [m/s], work [J])`` of
    its tolerances (None: estimated); the outputs and the scales used (``"scales"``)."""
    g = _Growth(params, contact_growth)
    times = np.asarray(times, dtype=float)
    out = {name: np.zeros(times.size) for name in OUTPUT_NAMES}
    edges, ta = [], 0.0
    for duration, q in segments:
        edges.append((ta, q))
        ta += duration
    edges.append((ta, 0.0))
    cuts = sorted({*(t for t, _ in edges), *map(float, cleanouts), float(times[-1])})
    cleaned = {float(c) for c in cleanouts}

    def load_at(t):
        q = 0.0
        for start, value in edges:
            if start <= t:
                q = value
        return q

    impulse = sum(abs(q) * d for d, q in segments) or 1.0
    vscale = impulse / g.M1
    lscale = max(g.L1, vscale * max(times[-1], 1e-300))
    wscale = impulse * vscale
    if scales is not None:
        lscale, vscale, wscale = max(scales[0], g.L1), scales[1], scales[2]
    out["scales"] = (lscale, vscale, wscale)
    atol = 1e-3 * rtol * np.array([lscale, vscale, lscale, g.mu * g.L1 * vscale, g.L1,
                                   wscale, wscale, wscale, wscale, g.L1])
    y = np.zeros(10)
    y[_L2] = float(params.get("L2", 1.0))
    y[_GAP] = g.L1 - y[_L2]
    w_in = w_removed = 0.0
    events = []
    k = 0
    mode, merged = (0, 0, 0), False
    v2_now = 0.0
    pieces = stalled = 0

    def state_v2(yy, md):
        return _v2(g, md, yy)

    def record(idx, ys, md, w0, u0, q):
        for j, col in zip(idx, ys.T):
            v2 = state_v2(col, md)
            v1 = col[_V1] if md[0] else 0.0
            out["v_pipe"][j] = v1
            out["v_plug"][j] = v2 if (col[_L2] > 0.0 or (g.gripped and md[1] == 0)) else 0.0
            out["u_pipe"][j], out["u_plug"][j], out["L2_now"][j] = col[_U1], col[_U2], col[_L2]
            out["W_input"][j] = w0 + q * (col[_U1] - u0)
            out["W_friction_outer"][j], out["W_friction_inner"][j] = col[_WO], col[_WI]
            out["W_face"][j], out["W_accretion"][j] = col[_WF], col[_WA]
            out["W_removed"][j] = w_removed
            out["E_kinetic"][j] = 0.5 * (g.M1 * v1 * v1 + g.mu * col[_L2] * v2 * v2)

    def decide(q, forced=(0, 0, 0)):
        nonlocal mode, merged, v2_now
        if 0.0 < y[_L2] <= _EMPTY * g.L1:
            # A plug of a length below round-off of the pipe's is gone: its velocity (P over a
            # vanishing mass) no longer tells a mode; moving with the pipe, it may grip it.
            g.gripped = g.gripped or v2_now == y[_V1]
            y[_L2], y[_GAP], v2_now = 0.0, g.L1, 0.0
        yy = np.append(y, v2_now)
        mode, merged = _decide(g, q, yy, forced)
        if mode[1] == 0:
            y[_P] = g.mu * y[_L2] * y[_V1]
        elif _shrinks(mode):
            y[_P] = v2_now
        else:
            y[_P] = g.mu * y[_L2] * (v2_now if mode[2] else 0.0)

    for ta, tb in zip(cuts[:-1], cuts[1:]):
        q = load_at(ta)
        if ta in cleaned and y[_L2] > g.after:
            w_removed += 0.5 * g.mu * (y[_L2] - g.after) * v2_now ** 2
            y[_L2], y[_GAP] = g.after, g.L1 - g.after
            if g.after == 0.0:
                v2_now = 0.0
        decide(q)
        events.append((ta, f"load {q!r}: {mode}"))
        t = ta
        while t < tb:
            pieces += 1
            if pieces > max_pieces:
                raise RuntimeError(f"more than {max_pieces} pieces")
            if (mode[0] > 0 and mode[1] > 0 and mode[2] != 0 and y[_L2] == 0.0
                    and y[_V1] == 0.0):
                t, w_in, v2_now = _self_similar(g, g.system(0.0), q, y, t, w_in)
            y0, w0 = y.copy(), w_in
            if mode[0] == 0 and mode[1] == 0:
                idx = np.nonzero((times >= t) & (times <= tb))[0]
                record(idx[idx >= k], np.repeat(y0[:, None], len(idx[idx >= k]), 1), mode,
                       w0, y0[_U1], q)
                k = max(k, idx[-1] + 1 if len(idx) else k)
                t = tb
                break
            s = g.system(0.0 if y0[_L2] <= 0.0 else y0[_L2], merged)
            tight = atol.copy()
            if mode[1] > 0:         # a growing plug to a share of itself (from nothing: tiny)
                # (it holds the change: below); from nothing, 1e-30 L1 (scipy's first step
                # divides the rates by it: 1e-300 overflowed there)
                tight[_L2] = rtol * max(y0[_L2], 1e-30 * g.L1)
                tight[_P] = 1e-3 * rtol * g.mu * max(y0[_L2], 1e-30 * g.L1) * vscale
            elif _shrinks(mode):
                tight[_P] = atol[_V1]
            # A growing plug's length is integrated as its change since the piece's start (the
            # fill is the gap's zero, above). A shrinking one's is its length itself, precise
            # where it leaves the pipe (there its face's force goes as 1/L2).
            l2_0 = y0[_L2] if mode[1] > 0 else 0.0
            start = y0.copy()
            start[_L2] -= l2_0
            evs = _events(g, s, q, mode, y0, merged, atol[_V1], l2_0)
            sol = solve_ivp(_rhs(g, s, q, mode, y0[_U1], l2_0), (t, tb), start, method="DOP853",
                            events=evs or None, rtol=rtol, atol=tight, dense_output=True)
            if sol.status < 0:
                raise RuntimeError(sol.message)

            def state(at, sol=sol, l2_0=l2_0):
                ys = sol.sol(at)
                ys[_L2] += l2_0
                return ys
            fired = None
            t_end, y_end = tb, sol.y[:, -1].copy()
            y_end[_L2] += l2_0
            hits = [(te[0], i) for i, te in enumerate(sol.t_events or ()) if len(te)]
            hits += _crossed_twice(evs, sol, min(hits)[0] if hits else tb)
            if hits:
                t_end, i = min(hits)
                if len(sol.t_events[i]) and sol.t_events[i][0] == t_end:
                    y_end = sol.y_events[i][0].copy()
                    y_end[_L2] += l2_0
                else:
                    y_end = state(t_end)
                fired = {evs[j].name for te, j in hits if te - t_end <= 1e-14 * max(t_end, 1.0)}
            idx = np.nonzero((times >= t) & (times <= t_end))[0]
            idx = idx[idx >= k]
            if len(idx):
                record(idx, state(times[idx]), mode, w0, y0[_U1], q)
                k = idx[-1] + 1
            w_in = w0 + q * (y_end[_U1] - y0[_U1])
            stalled = stalled + 1 if t_end <= t else 0
            if stalled > MAX_STALLED:
                raise RuntimeError(f"stalled at t = {t!r}: {fired}")
            v2_now = state_v2(y_end, mode)
            y[:] = y_end
            if mode[0] == 0:
                y[_V1] = 0.0
            t = t_end
            if fired is None:
                continue
            forced = [0, 0, 0]
            p, r, gg = mode
            if "pipe stops" in fired:
                y[_V1] = 0.0
                if r == 0:
                    v2_now = 0.0
            if "plug stops" in fired:
                v2_now = 0.0
            if "plug sticks" in fired:
                m2 = g.mu * y[_L2]
                v2_now = y[_V1] = (g.M1 * y[_V1] + m2 * v2_now) / (g.M1 + m2) if p else 0.0
            if "plug fills the pipe" in fired:
                y[_L2], y[_GAP] = g.L1, 0.0
                m2 = g.mu * g.L1
                v = (g.M1 * y[_V1] + m2 * v2_now) / (g.M1 + m2)
                y[_WA] += 0.5 * (g.M1 * y[_V1] ** 2 + m2 * v2_now ** 2 - (g.M1 + m2) * v * v)
                y[_V1] = v2_now = v
            if "plug leaves the pipe" in fired:       # its rest comes to rest ahead
                y[_WA] += 0.5 * g.mu * y[_L2] * v2_now ** 2
                y[_L2], y[_GAP], v2_now = 0.0, g.L1, 0.0
            if "held pipe goes" in fired:
                forced[0] = 1 if q - r * g.k * y[_L2] > 0.0 else -1
                forced[1], forced[2] = r, gg
            if "held plug goes" in fired:
                forced[2] = 1 if r * g.k * y[_L2] > 0.0 else -1
                forced[0], forced[1] = p, r
            if "plug breaks away ahead" in fired:
                forced[1] = -1
            if "plug breaks away behind" in fired:
                forced[1] = 1
            if "kink" in fired:
                y[_U1] = round(y[_U1] / g.L1) * g.L1 if g.L1 else 0.0
            if r == 0 and y[_L2] > 0.0 and "plug sticks" not in fired:
                v2_now = y[_V1]
            decide(q, tuple(forced))
            events.append((t, f"{sorted(fired)}: {mode}"))
    out["events"] = events
    return out
