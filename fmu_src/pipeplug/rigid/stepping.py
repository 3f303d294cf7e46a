"""The exact solver's event loop: stepping, dense output and outputs, on the records.

Every function here reads and writes the records of :mod:`~pipeplug.rigid.record` (``st``, the
state, and ``par``, the constants) and nothing else, so that one source runs as Python and,
compiled by numba (:func:`pipeplug.jit.compiled`), as machine code. Failures are returned as
codes (:data:`OK`, :data:`TOO_MANY_EVENTS`, :data:`SEGMENT_MISSED`, :data:`LOAD_NOT_FINITE`);
the model raises them.

The contact modes of every piece go to a mode log (:func:`log_mode`), a float array (a list in
Python) the caller passes with the records; an empty one logs nothing (the batch API). When it
is full a function returns :data:`LOG_FULL` before starting another piece: the caller takes the
codes logged (:func:`mode_of`) and calls again, which continues where it stopped.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.outer import contact_length
from ..jit import compiled_form, jitable
from .face import face_work_at, make_face_piece
from .motion import acceleration_at, travel, ulp
from .pieces import (
    AT_REST,
    BREAKAWAY_NEG,
    BREAKAWAY_POS,
    PIPE_REST,
    PLUG_REST,
    PLUG_STOP,
    SEGMENT,
    STICK,
    find_event,
    forces_of,
    friction_work_of,
    kinematics,
    law_of,
    make_piece,
    pipe_of,
    plug_of,
    slip_of,
)
from .record import (
    END,
    ERROR,
    FACE1,
    HORIZON,
    KICK,
    KIND,
    LABELS,
    LOGGED,
    MODE,
    P_COUPLED,
    P_FACE,
    P_L2,
    P_LAW,
    P_M1,
    P_M2,
    P_QP,
    P_S1,
    S1,
    S2,
    S3,
    SEARCHED,
    T0,
    T_EVENT,
    T_SNAP,
    TIME,
    U1,
    U2,
    V1,
    W_FACE,
    W_IN,
    W_INNER,
    W_OUTER,
    Q,
)
from .stress import axial_extremes

__all__ = ["OK", "TOO_MANY_EVENTS", "SEGMENT_MISSED", "LOAD_NOT_FINITE", "LOG_FULL",
           "MAX_EVENTS_PER_STEP", "step_to", "start_piece", "sample_into", "outputs_at",
           "at_rest", "log_mode", "mode_of", "mode_code", "log_full", "record_event", "settle",
           "pipe_plug_events", "common_velocity"]

#: return codes
OK, TOO_MANY_EVENTS, SEGMENT_MISSED, LOAD_NOT_FINITE, LOG_FULL = 0, 1, 2, 3, 4
MAX_EVENTS_PER_STEP = 100_000
_EVENT_SNAP = 1e-13          # relative: an event this close after a step end is taken in it
_SNAP_LIMIT = 1e-9           # relative: largest believable round-off of a segment crossing
_SNAP_FLOOR = 1e-12          # of the pipe length: round-off of positions near a segment end


@jitable
def step_to(st, par, log, q, t_end):
    """Advance to ``t_end`` [s] under a constant struck-end force ``q`` [N], logging the modes
    of every piece started into ``log``.

    Returns a code: :data:`OK`, :data:`LOG_FULL` (call again when the log is taken), or why the
    step failed.
    """
    if q == st[Q] and t_end < st[T_SNAP] and t_end <= st[SEARCHED]:
        st[TIME] = t_end             # the common case: no event inside the step
        return OK
    if q != st[Q]:
        if log_full(st, log):
            return LOG_FULL
        _restart(st, par, log, q, t_end)
    for _ in range(MAX_EVENTS_PER_STEP):
        if t_end > st[SEARCHED]:
            _search(st, par, max(t_end - st[T0], 2.0 * st[HORIZON]))
        if t_end < st[T_SNAP]:
            st[TIME] = t_end
            return OK
        if log_full(st, log):
            return LOG_FULL
        code = _take_event(st, par, log)
        if code != OK:
            return code
    return TOO_MANY_EVENTS


@jitable
def start_piece(st, par, log, t0, u1, v1, u2, v2, w_in, w_outer, w_inner, q, kick, horizon):
    """Start a piece at ``t0`` [s] from ``(u1, v1, u2, v2)`` [m, m/s] with the works done so far
    (input, outer and inner friction [J]) under ``q`` [N] (nan: no force yet), the plug kicked
    by ``kick``, log its modes into ``log`` (which has room) and look for its events up to
    ``horizon`` [s] after ``t0``."""
    st[W_IN], st[W_OUTER], st[W_INNER] = w_in, w_outer, w_inner
    st[KICK] = kick
    if par[P_FACE] != 0.0:            # end resistance (its work before the piece: W_FACE)
        make_face_piece(st, par, t0, u1, v1, u2, v2, 0.0 if math.isnan(q) else q, kick)
    else:
        make_piece(st, par, t0, u1, v1, u2, v2, 0.0 if math.isnan(q) else q, kick)
    st[Q] = q
    log_mode(st, log)
    _search(st, par, horizon)


@jitable
def mode_code(s1, s2):
    """The code 0..8 of the contact modes ``(s1, s2)`` (each -1, 0 or 1) in the mode log."""
    return 3.0 * (s1 + 1.0) + (s2 + 1.0)


def mode_of(code) -> tuple[int, int]:
    """The contact modes ``(pipe_mode, plug_mode)`` of a code of the mode log."""
    s1, s2 = divmod(int(code), 3)
    return s1 - 1, s2 - 1


@jitable
def log_mode(st, log):
    """Append the current piece's modes to ``log`` unless they repeat the last ones logged
    (nothing when ``log`` is empty: no log kept)."""
    if len(log) == 0:
        return
    code = mode_code(st[S1], st[S2])
    if code == st[MODE]:
        return
    n = int(st[LOGGED])
    log[n] = code
    st[LOGGED], st[MODE] = n + 1.0, code


@jitable
def log_full(st, log):
    """True when ``log`` is kept and has no room for another piece's modes."""
    return len(log) > 0 and st[LOGGED] >= len(log)


@jitable
def _search(st, par, horizon):
    """Look for the piece's next event up to ``horizon`` [s] after its origin."""
    dt, labels = find_event(st, par, horizon)
    record_event(st, horizon, dt, labels)


@jitable
def record_event(st, horizon, dt, labels):
    """Record the piece's next event, ``dt`` [s] after its origin (``inf``: none), with its
    ``labels``, found by a search up to ``horizon`` [s] after the origin."""
    st[HORIZON] = horizon
    t_event = st[T0] + dt
    st[T_EVENT], st[LABELS] = t_event, labels
    # A step ending within round-off of an event takes it: otherwise a grazing stop (velocity
    # and acceleration vanishing together) would leave a velocity of 1e-14 m/s that a load at
    # the friction limit never removes.
    st[T_SNAP] = t_event - _EVENT_SNAP * t_event if dt < math.inf else math.inf
    st[SEARCHED] = st[T0] + horizon if dt > horizon else math.inf


@jitable
def _restart(st, par, log, q, t_end):
    """Start a new piece at the current time under a new force ``q`` [N], looking for its
    events up to ``t_end`` [s]."""
    t = st[TIME]
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    if par[P_FACE] != 0.0:
        st[W_FACE] = face_work_at(st, t - st[T0])
    v1, v2 = settle(st, par, par[P_M1], v1, v2)
    start_piece(st, par, log, t, u1, v1, u2, v2, w_in, w_outer, w_inner, q, 0, t_end - t)


@jitable
def _take_event(st, par, log):
    """Move the origin to the next event, set the exact post-event values, re-decide modes."""
    t = st[T_EVENT]
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    if par[P_FACE] != 0.0:
        st[W_FACE] = face_work_at(st, t - st[T0])
    labels = int(st[LABELS])
    v1, v2, kick = pipe_plug_events(st, par, labels, par[P_M1], v1, v2)
    if labels & SEGMENT:
        end = st[END]
        if not abs(u1 - end) <= _snap_allowance(st, par, t, u1):
            st[ERROR] = u1
            return SEGMENT_MISSED
        if st[S2] == 0:               # the plug moves with the pipe: same shift
            u2 += end - u1
        u1 = end
        # The plug reaching its limit just as the pipe changes contact segment: whether it
        # slips depends on the new segment (its required force may stop growing there); the
        # new piece decides, breaking away at once if the force still grows.
        kick = 0
    if par[P_COUPLED] == 0.0:
        u2 = v2 = 0.0
    searched_to = st[T0] + st[HORIZON]
    start_piece(st, par, log, t, u1, v1, u2, v2, w_in, w_outer, w_inner, st[Q], kick,
                max(searched_to - t, 0.0))
    return OK


@jitable
def settle(st, par, m1, v1, v2):
    """``(v1, v2)`` [m/s] of pipe (of mass ``m1`` [kg], with a riding ram the ram's too) and
    plug where a piece is cut by a new load: a velocity that round-off carried past a stop or
    a stick the search had not reached is set back onto it."""
    s1, s2 = st[S1], st[S2]
    if s1 != 0 and v1 * s1 < 0.0:
        v1 = 0.0
    if s2 != 0 and (v1 - v2) * s2 < 0.0:
        if s1 != 0:
            v1 = common_velocity(par, m1, v1, v2)
        v2 = v1
    if par[P_QP] > 0.0 and st[S3] != 0 and v2 * st[S3] < 0.0:   # a plug face's stop
        v2 = 0.0
    return v1, v2


@jitable
def pipe_plug_events(st, par, labels, m1, v1, v2):
    """``(v1, v2, kick)``: the velocities [m/s] of pipe (of mass ``m1`` [kg]) and plug set by
    the pipe's and the plug's events among ``labels`` (a stop, a stick), and the kick (-1, 0,
    1) of a plug breaking away."""
    kick = 0
    if labels & PIPE_REST:
        v1 = 0.0
        if st[S2] == 0:
            v2 = 0.0
    stick = (labels & STICK) != 0
    if (labels & PLUG_REST) != 0 or (stick and (labels & PIPE_REST) != 0):
        v2 = v1
    elif stick:
        v1 = v2 = common_velocity(par, m1, v1, v2)
    if labels & PLUG_STOP and not stick:
        v2 = 0.0
    if labels & BREAKAWAY_POS:
        kick = 1
    if labels & BREAKAWAY_NEG:
        kick = -1
    return v1, v2, kick


@jitable
def common_velocity(par, m1, v1, v2):
    """The velocity [m/s] of pipe (of mass ``m1`` [kg]) and plug sticking together while the
    pipe slides.

    The stick time is a root to round-off, where the relative velocity is a round-off ``d``
    (the pipe's deceleration times a few ulps of time). Momentum is conserved: the plug's
    friction is internal, so this is the together-motion's velocity at that time to second
    order, and the kinetic energy changes by only M1 M2 d^2 / (2 (M1 + M2)). Setting the plug to
    the pipe's velocity instead would change it by M2 V2 d, which a heavy plug and a
    hard-braking pipe make visible in the energy balance (4e-12 of the work at M2 = 127 M1).
    """
    m2 = par[P_M2]
    return (m1 * v1 + m2 * v2) / (m1 + m2)


@jitable
def _snap_allowance(st, par, t, u1):
    """How far [m] the pipe at ``u1`` [m] may be from the segment end it reached at ``t`` [s].

    The event time is a root to round-off, so the move onto the end is round-off; a larger one
    means the event was found at the wrong time, which is reported rather than hidden. Allowed:
    round-off of the position, and the way covered in a few ulps of the event time (a crossing
    sooner after the piece start than time can resolve is taken at its start), at the
    resolution of the search's own time (near its horizon), and a floor for the round-off of
    positions near a segment end at tiny scales (segments are model II's: L1 sets the scale).
    """
    end = st[END]
    dt = 4.0 * ulp(max(t, st[T0] + st[HORIZON]))
    a = abs(acceleration_at(pipe_of(st), u1))
    return (_SNAP_LIMIT * (abs(end - st[U1]) + abs(end)) + dt * (abs(st[V1]) + a * dt)
            + _SNAP_FLOOR * par[P_LAW + 3])


@jitable
def values_at(st, par, t):
    """``(U1, V1, U2, V2, W_input, W_outer, W_inner)`` [m, m/s, J] at absolute time(s) ``t``
    [s] inside the current piece."""
    dt = t - st[T0]
    d1, v1 = travel(pipe_of(st), dt)
    d2, v2 = travel(plug_of(st), dt)
    outer, inner = friction_work_of(st, par, d1, d2, slip_of(st, dt, d1, d2))
    q = st[Q]
    w_in = st[W_IN] + (q * d1 if q == q else 0.0 * d1)       # q is nan before the first step
    return (st[U1] + d1, v1, st[U2] + d2, v2, w_in, st[W_OUTER] + outer,
            st[W_INNER] + inner)


@jitable
def at_rest(st):
    """Both bodies stuck with no load (none yet, NaN, in a fresh model): a step under Q = 0
    changes nothing but the time."""
    return st[KIND] == AT_REST and (st[Q] == 0.0 or st[Q] != st[Q])


@jitable
def outputs_at(st, par, t):
    """The 25 outputs of :data:`pipeplug.interface.OUTPUTS` at absolute time(s) ``t`` [s]
    inside the current piece (floats; at_rest and the modes as 0.0/1.0 and -1.0/0.0/1.0).
    The soil's end force on the pipe (FACE1) bears on its front end: the axial force there.
    Rigid bodies store no strain energy, the exact solution dissipates nothing but friction
    work, and no ram strikes (a model with a ram runs :mod:`~pipeplug.rigid.ramstep`): the head
    force is Q, its work the input work, and the axial
    stresses are those of the rigid pipe's equilibrium (:mod:`pipeplug.rigid.stress`)."""
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    f1, f2 = forces_of(st, par, u1)
    zero = 0.0 * u1                                   # (arrays for dense output)
    rest = (1.0 if at_rest(st) else 0.0) + zero
    kinetic = 0.5 * (par[P_M1] * v1 * v1 + par[P_M2] * v2 * v2)
    q = (st[Q] if st[Q] == st[Q] else 0.0) + zero      # nan before the first step
    low, high = axial_extremes(q, f1, f2, par[P_LAW + 3], contact_length(law_of(par), u1),
                               par[P_L2], st[FACE1])
    area = par[P_S1]
    w_face = face_work_at(st, t - st[T0]) if par[P_FACE] != 0.0 else zero
    return (v1, v2, u1, u2, f1, f2, w_in, w_outer + w_inner, w_outer, w_inner, kinetic, zero,
            zero, q, zero, zero, zero, w_in, -q / area, low / area, high / area, rest,
            st[S1] + zero, st[S2] + zero, w_face)


@jitable(inline=True)
def _kinematics_at(st, par, t):
    """``(V1, V2, U1, U2)`` [m/s, m] at absolute time(s) ``t`` [s] inside the current piece."""
    return kinematics(pipe_of(st), plug_of(st), t - st[T0])


@jitable
def sample_into(st, par, log, loads, times, table, first):
    """Dense output: advance through ``times[first:]`` [s] under the struck-end force
    ``loads[j]`` [N] over the interval ending at ``times[j]``, writing the outputs at
    ``times[j]`` into ``table[:, j]``: all of :data:`pipeplug.interface.OUTPUTS` (25 rows) or
    the kinematics alone (their first four); modes logged as by :func:`step_to`.

    Each piece is evaluated for all the sample times it covers at once, so a long record costs
    little more than its events. Same values as stepping to each time and taking the outputs
    there. Returns ``(code, j)``: a code like :func:`step_to`'s and the first sample not
    written (after :data:`LOG_FULL`, call again from there).
    """
    n = times.shape[0]
    lo = first
    while lo < n:                     # one run of samples per constant load
        q = float(loads[lo])
        if not q - q == 0.0:
            return LOAD_NOT_FINITE, lo
        code, lo = _sample_run(st, par, log, q, times, lo, _run_end(loads, lo, q), table)
        if code != OK:
            return code, lo
    return OK, n


@jitable
def _run_end_loop(loads, lo, q):
    """:func:`_run_end` as compiled code runs it.

    Blocks of 128 loads are compared with ``q`` by their bits, or-ed without a branch, which
    the compiler turns into vector instructions (a load-by-load loop took about a nanosecond
    per sample, as long as the dense output itself); the first block with a difference, and
    a load equal to ``q`` with other bits (-0.0 and 0.0), go through the load-by-load loop.
    A load that changes at every sample costs one comparison, as in that loop.
    """
    n = loads.shape[0]
    hi = lo + 1
    if hi == n or loads[hi] != q or q != q:
        return hi                       # (nan equals no load, though it has its own bits)
    bits = loads.view(np.int64)
    q_bits = bits[lo]                   # a load equal to q: other bits only go load by load
    while hi + _BLOCK <= n:
        block = bits[hi:hi + _BLOCK]          # indexed from 0: no wraparound test
        differ = 0
        for k in range(_BLOCK):
            differ |= block[k] ^ q_bits
        if differ != 0:
            break
        hi += _BLOCK
    while hi < n and loads[hi] == q:
        hi += 1
    return hi


_BLOCK = 128                            # loads compared at once by _run_end_loop


@compiled_form(_run_end_loop)
def _run_end(loads, lo, q):
    """The end of the run of ``loads`` equal to ``q`` [N] from ``lo`` (``loads[lo] == q``):
    the first index after ``lo`` whose load differs, or the length of ``loads``. Python
    compares the next load alone (a load that changes at every sample costs no array
    operation), then blocks of loads as arrays, each twice as long as the one before."""
    n = loads.shape[0]
    hi = lo + 1
    if hi == n or loads[hi] != q:
        return hi
    block = _BLOCK
    while hi < n:
        differ = np.flatnonzero(loads[hi:hi + block] != q)
        if differ.size:
            return hi + int(differ[0])
        hi += block
        block *= 2
    return n


@jitable
def _sample_run(st, par, log, q, times, lo, hi, table):
    """:func:`sample_into` for the samples ``lo..hi-1``, all under the force ``q`` [N]; returns
    the code and the first sample not written."""
    t_last = float(times[hi - 1])
    if q != st[Q]:
        if log_full(st, log):
            return LOG_FULL, lo
        _restart(st, par, log, q, t_last)
    done = lo
    for _ in range(MAX_EVENTS_PER_STEP * (hi - lo)):
        if t_last > st[SEARCHED]:
            _search(st, par, max(t_last - st[T0], 2.0 * st[HORIZON]))
        upto = _first_not_before(times, done, hi, st[T_SNAP])
        if upto > done:
            _fill(st, par, times, done, upto, table)
            done = upto
        if done == hi:
            st[TIME] = t_last
            return OK, hi
        if log_full(st, log):
            return LOG_FULL, done
        code = _take_event(st, par, log)
        if code != OK:
            return code, done
    return TOO_MANY_EVENTS, done


@jitable
def _first_not_before(times, lo, hi, t):
    """The first index in ``lo..hi-1`` of increasing ``times`` [s] whose time is not before
    ``t`` [s] (``hi`` if none is): a bisection."""
    while lo < hi:
        mid = (lo + hi) // 2
        if times[mid] < t:
            lo = mid + 1
        else:
            hi = mid
    return lo


@jitable
def _fill_loop(st, par, times, lo, hi, table):
    """:func:`_fill` as compiled code runs it: a loop over the samples (no temporaries)."""
    if table.shape[0] == 4:           # the piece's motions read once, out of the loop
        pipe, plug, t0 = pipe_of(st), plug_of(st), st[T0]
        # Views indexed from 0: an index known >= 0 needs no wraparound test per access.
        t, v1, v2 = times[lo:hi], table[0, lo:hi], table[1, lo:hi]
        u1, u2 = table[2, lo:hi], table[3, lo:hi]
        for j in range(t.shape[0]):
            v1[j], v2[j], u1[j], u2[j] = kinematics(pipe, plug, t[j] - t0)
        return
    t, rows = times[lo:hi], table[:, lo:hi]
    for j in range(t.shape[0]):
        (rows[0, j], rows[1, j], rows[2, j], rows[3, j], rows[4, j], rows[5, j], rows[6, j],
         rows[7, j], rows[8, j], rows[9, j], rows[10, j], rows[11, j], rows[12, j], rows[13, j],
         rows[14, j], rows[15, j], rows[16, j], rows[17, j], rows[18, j], rows[19, j],
         rows[20, j], rows[21, j], rows[22, j], rows[23, j], rows[24, j]) = outputs_at(st, par,
                                                                                     t[j])


@compiled_form(_fill_loop)
def _fill(st, par, times, lo, hi, table):
    """Write the outputs at ``times[lo:hi]`` [s] (inside the current piece) into
    ``table[:, lo:hi]`` (the kinematics alone when ``table`` has four rows): one array
    operation per output and piece."""
    t = times[lo:hi]
    values = _kinematics_at(st, par, t) if table.shape[0] == 4 else outputs_at(st, par, t)
    for i, value in enumerate(values):
        table[i, lo:hi] = value
