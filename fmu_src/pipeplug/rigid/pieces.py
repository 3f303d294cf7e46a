"""Pieces of rigid motion between two events, and the events that end them.

A piece starts from an origin state with fixed contact modes and a constant force Q. Its
motion is known in closed form (:mod:`~pipeplug.rigid.motion`), so every quantity at a time
``dt`` after the origin is evaluated from the origin (never accumulated step by step): the
outputs do not depend on how a host slices time.

Kinds of piece (s1 = pipe/soil mode, s2 = pipe/plug mode, 0 = stuck):

* :data:`AT_REST`     s1 = 0, s2 = 0: nothing moves; friction forces are static reactions.
* :data:`PLUG_SLIDES` s1 = 0, s2 != 0: the pipe is held by the soil, the plug slides in it.
* :data:`TOGETHER`    s1 != 0, s2 = 0: pipe and plug move as one body (or the pipe alone when
  there is no plug); ends when it stops, changes contact segment, or the plug breaks away.
* :data:`BOTH_SLIDE`  s1 != 0, s2 != 0: ends when the pipe stops, changes contact segment, or
  the relative velocity vanishes.

A piece is two closed-form motions, the pipe's and the plug's (a body at rest has a motion of
zeros, a carried plug the pipe's), its friction forces (static reactions of stuck contacts) and
its outer contact segment. It lives in the state record (:mod:`~pipeplug.rigid.record`):
:func:`make_piece` decides the modes and writes it there, the other functions read it. Events are bits of a label set:
:data:`PIPE_REST`, :data:`PLUG_REST`, :data:`STICK`, :data:`SEGMENT`, :data:`BREAKAWAY_POS`,
:data:`BREAKAWAY_NEG` (the plug starts sliding with s2 = +1/-1). Evaluations take a time or an
array of times (dense output).
"""
from __future__ import annotations

import math

from ..contact.coulomb import SLACK, one_contact, two_contacts
from ..contact.face import sign
from ..contact.outer import limit, segment, work
from ..jit import jitable
from .motion import (
    RELATIVE_VELOCITY,
    acceleration_at,
    motion,
    refine_root,
    time_to_position,
    time_to_rest,
    travel,
    ulp,
)
from .record import (
    A1,
    A2,
    END,
    FACE3,
    FORCE0,
    FS1,
    FS2,
    K1,
    K2,
    KAPPA,
    KIND,
    P_COUPLED,
    P_F2,
    P_LAW,
    P_M1,
    P_M2,
    P_QP,
    S1,
    S2,
    S3,
    T0,
    U1,
    U2,
    V1,
    V2,
    W1,
    W2,
)

__all__ = ["AT_REST", "PLUG_SLIDES", "TOGETHER", "BOTH_SLIDE", "PIPE_REST", "PLUG_REST", "STICK",
           "SEGMENT", "BREAKAWAY_POS", "BREAKAWAY_NEG", "PLUG_STOP", "make_piece", "contact_modes", "kinematics",
           "forces_of",
           "friction_work_of", "slip_of", "find_event", "pipe_of", "plug_of", "law_of"]

_INF = math.inf

#: kinds of piece
AT_REST, PLUG_SLIDES, TOGETHER, BOTH_SLIDE = 0.0, 1.0, 2.0, 3.0
#: event labels (bits); PLUG_STOP: a plug sliding in a sliding pipe comes to rest in the soil,
#: where its face's end resistance switches (:mod:`pipeplug.rigid.face`)
PIPE_REST, PLUG_REST, STICK, SEGMENT, BREAKAWAY_POS, BREAKAWAY_NEG, PLUG_STOP = (
    1, 2, 4, 8, 16, 32, 64)


@jitable
def law_of(par):
    """The outer friction law of the constants ``par``."""
    return par[P_LAW], par[P_LAW + 1], par[P_LAW + 2], par[P_LAW + 3]


@jitable(inline=True)
def pipe_of(st):
    """The pipe's motion in the current piece (:func:`~pipeplug.rigid.motion.motion`)."""
    return st[U1], st[V1], st[A1], st[K1], st[W1]


@jitable(inline=True)
def plug_of(st):
    """The plug's motion in the current piece (the pipe's when it carries the plug)."""
    return st[U2], st[V2], st[A2], st[K2], st[W2]


@jitable
def contact_modes(par, m1, q, u1, v1, v2, kick, kick1):
    """The contact modes ``(s1, s2)`` at an origin and the static and sliding friction forces
    ``(f1s, f2s, f1_sliding, f2_sliding)`` [N] under the force ``q`` [N] on a pipe of mass
    ``m1`` [kg] (with a riding ram, the ram's too).

    The modes of sliding contacts are kept; stuck ones are decided by solving both contacts
    jointly (:func:`~pipeplug.contact.coulomb.two_contacts`) under the sliding forces.
    ``kick1`` (-1, 0, 1) makes a stuck pipe slide in that direction, ``kick`` a stuck plug.
    """
    m2, f2_limit = par[P_M2], par[P_F2]
    coupled = par[P_COUPLED] != 0.0
    law = law_of(par)
    s1 = sign(v1)
    if s1 == 0:
        s1 = kick1
    s2 = sign(v1 - v2) if coupled else 0
    c1 = limit(law, u1)
    f1_sliding = -s1 * c1 if s1 != 0 else 0.0
    f2_sliding = -s2 * f2_limit
    w1 = (q + f1_sliding + f2_sliding) / m1
    w2 = -f2_sliding / m2 if coupled else 0.0
    c1_static = 0.0 if s1 != 0 else c1
    c2_static = 0.0 if s2 != 0 else f2_limit
    if coupled:
        _, _, f1s, f2s, p1, p2 = two_contacts(m1, m2, w1, w2, c1_static, c2_static, 0.0)
    else:
        # The round-off share two_contacts always allows: a load at the limit to round-off
        # (1 ulp above it, as Q = F1 computed in another order) holds the pipe, plug or not.
        x1, f1s = one_contact(m1, w1, c1_static, SLACK * (abs(m1 * w1) + c1_static))
        p1, p2, f2s = sign(x1), 0, 0.0
    if s1 == 0:
        s1 = p1
    if s2 == 0:
        s2 = kick if kick != 0 else p2
    return s1, s2, f1s, f2s, f1_sliding, f2_sliding


@jitable
def make_piece(st, par, t0, u1, v1, u2, v2, q, kick):
    """Decide the contact modes at the origin ``(u1, v1, u2, v2)`` [m, m/s] at time ``t0`` [s]
    under the force ``q`` [N] (:func:`contact_modes`; ``kick`` (-1, 0, 1) makes a stuck plug
    break away in that direction) and write the piece into ``st``."""
    m1, m2, f2_limit = par[P_M1], par[P_M2], par[P_F2]
    coupled = par[P_COUPLED] != 0.0
    law = law_of(par)
    s1, s2, f1s, f2s, f1_sliding, f2_sliding = contact_modes(par, m1, q, u1, v1, v2, kick, 0)
    st[T0], st[U1], st[V1], st[U2], st[V2] = t0, u1, v1, u2, v2
    st[S1], st[S2] = float(s1), float(s2)
    st[A1] = st[K1] = st[W1] = st[A2] = st[K2] = st[W2] = 0.0     # at rest until set
    if s2 != 0:                       # the plug slides in the pipe: uniform deceleration
        st[A2] = s2 * f2_limit / m2
    if s1 == 0:
        st[FS1] = f1_sliding + f1s
        if s2 == 0:
            st[KIND], st[FS2] = AT_REST, f2_sliding + f2s
        else:
            st[KIND] = PLUG_SLIDES
        return
    force0, kappa, end = segment(law, u1, float(s1))
    st[FORCE0], st[KAPPA], st[END] = force0, kappa, end
    if s2 == 0:                       # the pipe carries the plug
        st[KIND] = TOGETHER
        mass = m1 + m2
        a0 = (q + force0 - kappa * u1) / mass
    else:
        st[KIND] = BOTH_SLIDE
        mass = m1
        a0 = (q + force0 - kappa * u1 - s2 * f2_limit) / m1
    _, _, st[A1], st[K1], st[W1] = motion(u1, v1, a0, kappa / mass)
    if s2 == 0 and coupled:
        st[A2], st[K2], st[W2] = st[A1], st[K1], st[W1]


@jitable(inline=True)
def kinematics(pipe, plug, dt):
    """``(V1, V2, U1, U2)`` [m/s, m] of the motions ``pipe`` and ``plug`` at ``dt`` [s] after
    their start (floats, or arrays for an array ``dt``).

    Every kind of piece is two motions (a body at rest has a motion of zeros, a carried plug
    the pipe's), so this has no branch: compiled dense output runs it in a tight loop.
    """
    d1, v1 = travel(pipe, dt)
    d2, v2 = travel(plug, dt)
    return v1, v2, pipe[0] + d1, plug[0] + d2


@jitable
def forces_of(st, par, u1):
    """Friction forces on the pipe ``(f1, f2)`` [N] when the pipe is at ``u1`` [m]."""
    kind = st[KIND]
    zero = 0.0 * u1
    if kind == AT_REST:
        return st[FS1] + zero, st[FS2] + zero
    if kind == PLUG_SLIDES:
        return st[FS1] + zero, -st[S2] * par[P_F2] + zero
    f1 = st[FORCE0] - st[KAPPA] * u1
    if kind == TOGETHER:
        if par[P_COUPLED] == 0.0:
            return f1, zero
        # the plug's own face force FACE3 (0 without end resistance) is part of its balance
        return f1, -(par[P_M2] * acceleration_at(pipe_of(st), u1) - st[FACE3])
    return f1, -st[S2] * par[P_F2] + zero


@jitable
def slip_of(st, dt, d1, d2):
    """The pipe's displacement relative to the plug [m] at ``dt`` [s] into the current piece,
    ``d1``, ``d2`` [m] being the two displacements there.

    When both move uniformly it is the relative motion's own closed form, not the difference
    of the two: a plug sliding at its limit with a relative velocity and acceleration of
    round-off size (a breakaway whose forces balance to the last digit) has a difference of
    two displacements that wanders by their round-off, of either sign, from sample to sample,
    and its friction work would decrease; ``dt (dV0 + dA dt / 2)`` is monotone there.
    """
    if st[K1] == 0.0 and st[K2] == 0.0:
        return dt * ((st[V1] - st[V2]) + 0.5 * (st[A1] - st[A2]) * dt)
    return d1 - d2


@jitable
def friction_work_of(st, par, d1, d2, slip):
    """Friction work [J] since the origin, outer and inner, after displacements ``d1``, ``d2``
    [m] of pipe and plug and the pipe's displacement ``slip`` [m] relative to the plug
    (:func:`slip_of`)."""
    kind = st[KIND]
    if kind == AT_REST:
        zero = 0.0 * d1
        return zero, zero
    if kind == PLUG_SLIDES:
        return 0.0 * d1, -par[P_F2] * st[S2] * d2
    outer = work(law_of(par), st[U1], d1, st[S1])
    if kind == TOGETHER:
        return outer, 0.0 * d1
    # The plug's work is >= 0 (its force opposes the relative motion), but a relative
    # displacement of round-off size (a piece that starts at zero relative velocity and
    # acceleration, a breakaway, cut short by another event) can have either sign (-1e-33 J
    # once). Dissipation is never negative.
    inner = par[P_F2] * st[S2] * slip
    return outer, inner * (inner > 0.0)


@jitable
def find_event(st, par, horizon):
    """Time [s] after the piece start of its first event within ``horizon`` [s], and its
    labels (``inf, 0`` when there is none)."""
    kind = st[KIND]
    if kind == AT_REST:
        return _INF, 0
    if kind == PLUG_SLIDES:           # the plug moves with sign -s2 (the pipe is at rest)
        return time_to_rest(plug_of(st), -st[S2]), PLUG_REST
    pipe = pipe_of(st)
    t_rest = time_to_rest(pipe, st[S1])
    t_lim = min(t_rest, horizon)
    xtol = _resolution(st[T0], t_lim)
    t_segment = time_to_position(pipe, st[END], t_lim, xtol)
    if kind == BOTH_SLIDE:
        t_stick = _time_to_stick(st, t_lim)
        t_stop = _INF
        if st[S3] != 0.0 and par[P_QP] > 0.0:
            t_stop = time_to_rest(plug_of(st), st[S3])
        return _earliest(t_rest, PIPE_REST, t_segment, SEGMENT, t_stick, STICK, t_stop,
                         PLUG_STOP)
    t_pos = t_neg = _INF
    if par[P_COUPLED] != 0.0 and pipe[3] != 0.0:
        t_pos, t_neg = _breakaways(st, par, t_lim, xtol)
    return _earliest(t_rest, PIPE_REST, t_segment, SEGMENT, t_pos, BREAKAWAY_POS, t_neg,
                     BREAKAWAY_NEG)


@jitable
def _resolution(t0, t_lim):
    """The resolution of absolute time near ``t0 + t_lim`` [s]: an event time after ``t0`` is
    not better known than this, so root searches stop there."""
    return 2.0 * ulp(t0 + t_lim)


@jitable
def _breakaways(st, par, t_lim, xtol):
    """Times [s] at which the carried plug's static force reaches its limit forward and
    backward (``inf``: not within ``t_lim``).

    The plug needs -f2 = M2 a(U) - f3, a(U) = a0 - k (U - U0), f3 its face's end force
    (FACE3, 0 without end resistance); it breaks away where s a(U) reaches (F2 + s f3)/M2
    (s = +1: breakaway+, s = -1: breakaway-). The piece may start with s a0 at the limit
    to round-off (it was chosen by the projection's slack): then the plug breaks away at once if
    s a grows as the body moves, else never on this side.
    """
    pipe = pipe_of(st)
    a0, k = pipe[2], pipe[3]
    moving = st[S1] * k               # s a(U) grows as the body moves iff -s moving > 0
    t_pos = t_neg = _INF
    for s in (1, -1):
        plug_limit = (par[P_F2] + s * st[FACE3]) / par[P_M2]
        if s * a0 >= plug_limit:
            t = 0.0 if -s * moving > 0.0 else _INF
        else:
            t = time_to_position(pipe, st[U1] + (a0 - s * plug_limit) / k, t_lim, xtol)
        if s == 1:
            t_pos = t
        else:
            t_neg = t
    return t_pos, t_neg


@jitable
def _time_to_stick(st, t_lim):
    """First zero in (0, t_lim] [s] of g(t) = V1(t) - V2(t), of sign s2 at the start.

    g'' = -k V1 keeps one sign inside the piece (V1 does not change sign), so g' is monotone:
    split at the zero of g' (a position crossing, U1 = U1_0 + (a0 - a2)/k) and search each
    monotone part for a sign change.
    """
    pipe = pipe_of(st)
    v2, a2, s2 = st[V2], st[A2], st[S2]
    da = pipe[2] - a2
    k = pipe[3]
    if k == 0.0:   # g is linear
        g0 = s2 * (st[V1] - v2)
        return g0 / (-s2 * da) if s2 * da < 0.0 else _INF
    if not math.isfinite(t_lim):
        return _INF
    xtol = _resolution(st[T0], t_lim)
    t_mid = min(time_to_position(pipe, st[U1] + da / k, t_lim, xtol), t_lim)
    a = 0.0
    for b in (t_mid, t_lim):
        if b <= a:
            continue
        gb = s2 * _relative_velocity(pipe, v2, a2, b)
        if gb <= 0.0:
            if s2 * _relative_velocity(pipe, v2, a2, a) > 0.0:
                if gb == 0.0:
                    return b
                return refine_root(RELATIVE_VELOCITY, pipe, 0.0, v2, a2, a, b, xtol)
            if a > 0.0 or st[V1] != v2:
                return a
            # Started at zero relative velocity (a breakaway): there the relative
            # acceleration is zero too, and the plug's mode says which way the relative
            # velocity goes. A first part going the other way is round-off, not a stick.
        a = b
    return _INF


@jitable
def _relative_velocity(pipe, v2, a2, t):
    """V1(t) - V2(t) [m/s] for the plug's uniform motion from ``v2`` with ``a2``."""
    return travel(pipe, t)[1] - (v2 + a2 * t)


@jitable
def _earliest(ta, la, tb, lb, tc, lc, td, ld):
    """The earliest of four event times [s] and the labels of every one within round-off of it."""
    t_min = min(ta, tb, tc, td)
    if t_min == _INF:
        return _INF, 0
    tol = 8.0 * ulp(max(t_min, 1e-300)) + 1e-15 * t_min
    labels = 0
    if ta <= t_min + tol:
        labels |= la
    if tb <= t_min + tol:
        labels |= lb
    if tc <= t_min + tol:
        labels |= lc
    if td <= t_min + tol:
        labels |= ld
    return t_min, labels
