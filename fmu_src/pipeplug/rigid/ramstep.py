"""The exact solver's event loop for a model with a ram: strikes, stepping, outputs.

The functions of :mod:`~pipeplug.rigid.stepping` with the ram's pieces and events
(:mod:`~pipeplug.rigid.ram`): a model with ``ram_mass > 0`` runs these, one without runs those
(unchanged). Before its first strike a model with a ram moves exactly as one without.

Outputs of a model with a ram: ``E_kinetic`` holds the ram's kinetic energy, ``E_strain`` the
cushion's recoverable energy, ``W_cushion`` its loss; ``W_input + W_ram = E_kinetic + E_strain +
W_friction + W_cushion``. ``F_head`` is Q plus the cushion's force (or the force of a ram riding
on the head); a direct impact is an impulse, whose force has no finite value: it moves the
velocities, not ``F_head``. ``E_transferred``, the work of ``F_head`` on the head, is by the
work-energy theorem of pipe and plug their kinetic energy and the work of the soil's and the
plug's friction and of the end resistance: terms that never go below 0, where the ram's side
(``W_input + W_ram`` less the ram's kinetic energy, the cushion's stored energy and its loss)
is a difference of energies far larger than what reaches a held pipe (1.3e-12 of ENTHRU between
two grids). ``stress_min`` and ``stress_max`` are the extremes over the
last communication step (the force of the cushion peaks inside a step): the axial force of the
rigid pipe (:mod:`~pipeplug.rigid.stress`) is affine in the cushion's compression at any time
of a piece, so its extremes lie at the ends of each piece's share of the step or where the
compression turns (closed form).
"""
from __future__ import annotations

import math

from ..contact.outer import contact_length
from ..jit import jitable
from .pieces import AT_REST, PIPE_REST, STICK, friction_work_of, law_of, slip_of
from .ram import (
    ACCUMULATE,
    CONTACT,
    FREE,
    LOAD_END,
    NONE,
    PIPE_GO_NEG,
    PIPE_GO_POS,
    RELOAD,
    RIDING,
    SEPARATE,
    ZENO,
    find_ram_event,
    impact,
    make_ram_piece,
    ram_forces,
    ram_state,
    travels,
)
from .record import (
    D0,
    DA,
    DB,
    DK,
    DMAX,
    DV,
    DW,
    EXT_T,
    FACE1,
    FACE3,
    HORIZON,
    KICK,
    KICK1,
    KIND,
    LABELS,
    N_HIGH,
    N_LOW,
    P_COUPLED,
    P_F2,
    P_FACE,
    P_K,
    P_KU,
    P_L2,
    P_LAW,
    P_M1,
    P_M2,
    P_QP,
    P_RAM_M,
    P_S1,
    RAM,
    RAM_ON,
    RHO,
    S1,
    S2,
    SEARCHED,
    STEPPING,
    T0,
    T_EVENT,
    T_SNAP,
    TIME,
    U1,
    U2,
    VR,
    VSCALE,
    W_CUSH,
    W_FACE,
    W_IN,
    W_INNER,
    W_OUTER,
    W_RAM,
    ZW,
    Q,
)
from .stepping import (
    LOAD_NOT_FINITE,
    LOG_FULL,
    MAX_EVENTS_PER_STEP,
    OK,
    TOO_MANY_EVENTS,
    log_full,
    log_mode,
    pipe_plug_events,
    record_event,
    settle,
)
from .stress import axial_extremes

__all__ = ["ram_step_to", "ram_start_piece", "ram_sample_into", "ram_outputs_at", "strike",
           "ram_at_rest", "values_at"]

@jitable
def values_at(st, par, t):
    """``(U1, V1, U2, V2, W_input, W_outer, W_inner)`` [m, m/s, J] at absolute time ``t`` [s]
    inside the current piece (:func:`pipeplug.rigid.stepping.values_at` with the ram)."""
    dt = t - st[T0]
    d1, v1, d2, v2 = travels(st, par, dt)
    # the pieces' own closed form of the slip holds while the ram does not bend the pipe's
    # motion (no cushion contact, no run of impacts)
    plain = st[RHO] == 0.0 and st[RAM] != ZENO
    slip = slip_of(st, dt, d1, d2) if plain else d1 - d2
    outer, inner = friction_work_of(st, par, d1, d2, slip)
    q = st[Q]
    w_in = st[W_IN] + (q * d1 if q == q else 0.0)
    return (st[U1] + d1, v1, st[U2] + d2, v2, w_in, st[W_OUTER] + outer,
            st[W_INNER] + inner)


@jitable
def face_work_at(st, par, t):
    """The work done against the end resistance since t = 0 [J] at absolute time ``t`` [s] in
    the current piece: the work before it and the piece's, from the displacements
    (:func:`pipeplug.rigid.face.face_work_at` with the ram's pieces)."""
    d1, _, d2, _ = travels(st, par, t - st[T0])
    return st[W_FACE] - st[FACE1] * d1 - st[FACE3] * d2


@jitable
def _book_face(st, par, t):
    """Book the end resistance's work up to ``t`` [s] before a new piece starts there."""
    if par[P_FACE] != 0.0:
        st[W_FACE] = face_work_at(st, par, t)


@jitable
def ram_start_piece(st, par, log, t0, u1, v1, u2, v2, w_in, w_outer, w_inner, q, kick, horizon):
    """:func:`pipeplug.rigid.stepping.start_piece` with the ram (its origin values in ``st``:
    D0, VR, DMAX, W_CUSH, KICK1, ZW)."""
    st[W_IN], st[W_OUTER], st[W_INNER] = w_in, w_outer, w_inner
    st[KICK] = kick
    make_ram_piece(st, par, t0, u1, v1, u2, v2, 0.0 if math.isnan(q) else q, kick)
    st[Q] = q
    log_mode(st, log)
    _search(st, par, horizon)


@jitable
def _search(st, par, horizon):
    """Look for the piece's next event up to ``horizon`` [s] after its origin."""
    dt, labels = find_ram_event(st, par, horizon)
    record_event(st, horizon, dt, labels)


@jitable
def _origin(st, delta, v_ram, delta_max, loss, kick1, closing):
    """Write the ram's origin values of the next piece."""
    st[D0], st[VR], st[DMAX], st[W_CUSH] = delta, v_ram, delta_max, loss
    st[KICK1], st[ZW] = kick1, closing


@jitable
def _now(st, par, t):
    """The pipe's, plug's and ram's values at ``t`` [s], velocities past a stop or a stick that
    round-off crossed set back (:func:`pipeplug.rigid.stepping.settle`)."""
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    delta, v_ram, delta_max, loss, fc = ram_state(st, par, t - st[T0], v1)
    riding = st[RAM] == RIDING
    v1, v2 = settle(st, par, _pipe_mass(par, riding), v1, v2)
    if riding:
        v_ram = v1
    return u1, v1, u2, v2, w_in, w_outer, w_inner, delta, v_ram, delta_max, loss, fc


@jitable
def _restart(st, par, log, q, t_end):
    """A new piece at the current time under a new force ``q`` [N]."""
    t = st[TIME]
    u1, v1, u2, v2, w_in, w_outer, w_inner, delta, v_ram, delta_max, loss, _ = _now(st, par, t)
    _book_face(st, par, t)
    _origin(st, delta, v_ram, delta_max, loss, 0.0, 0.0)
    ram_start_piece(st, par, log, t, u1, v1, u2, v2, w_in, w_outer, w_inner, q, 0, t_end - t)


@jitable
def strike(st, par, log, velocity):
    """Start a strike now: the ram at the head, touching an unloaded cushion, moving at
    ``velocity`` [m/s] (a direct strike faster than the head strikes it at once). The kinetic
    energy the ram had is replaced (W_RAM counts the difference) and what the cushion still
    held is lost. ``log`` must have room for one piece's modes."""
    t = st[TIME]
    u1, v1, u2, v2, w_in, w_outer, w_inner, _, v_ram, _, loss, fc = _now(st, par, t)
    _book_face(st, par, t)
    if par[P_K] > 0.0:
        loss += fc * fc / (2.0 * par[P_KU])
    mr = par[P_RAM_M]
    st[W_RAM] += 0.5 * mr * (velocity * velocity - v_ram * v_ram)
    st[RAM_ON], st[VSCALE] = 1.0, 0.0
    closing = 0.0
    if par[P_K] == 0.0 and velocity > v1:
        v1, velocity, lost, closing = impact(st, par, v1, velocity, t)
        loss += lost
    _origin(st, 0.0, velocity, 0.0, loss, 0.0, closing)
    if par[P_COUPLED] == 0.0:
        u2 = v2 = 0.0
    ram_start_piece(st, par, log, t, u1, v1, u2, v2, w_in, w_outer, w_inner, st[Q], 0,
                    max(st[T0] + st[HORIZON] - t, 0.0))


@jitable
def _pipe_mass(par, riding):
    """The mass [kg] of the pipe with a ``riding`` ram."""
    return par[P_M1] + par[P_RAM_M] if riding else par[P_M1]


@jitable
def _turn(st, par, v1, v2, v_ram, stopped, stick):
    """``(v1, v2, v_ram)`` [m/s] of pipe, plug and ram where the cushion's compression turns.

    The turn's time is a root to round-off, and as an absolute time it is rounded again (to
    an ulp of t), so the relative velocity left there is the relative deceleration times that
    (2e-12 m/s at 7e4 m/s^2 and t = 0.3 s), not 0. Setting the ram to the pipe's velocity
    would change the kinetic energy by m v_ram times that, a first-order error that repeats at
    every turn (4e-10 J each of a ram of 51 kg at 4.9 m/s, 2e-12 of the work after six). As
    at a stick (:func:`~pipeplug.rigid.stepping.common_velocity`), ram and what moves with
    the pipe take their momentum's velocity, which changes it only by mu d^2 / 2. A pipe held
    by the soil (or stopping now) keeps its velocity 0: the ram takes it, an error m v_ram d
    with v_ram itself ~ d.
    """
    if st[S1] == 0.0 or stopped:
        return v1, v2, v1
    carried = par[P_COUPLED] != 0.0 and (st[S2] == 0.0 or stick)
    mass = par[P_M1] + (par[P_M2] if carried else 0.0)
    mr = par[P_RAM_M]
    v = (mr * v_ram + mass * v1) / (mr + mass)
    return v, (v if carried else v2), v


@jitable
def _take_event(st, par, log):
    """Move the origin to the next event, set the exact post-event values, re-decide modes."""
    t = st[T_EVENT]
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    delta, v_ram, delta_max, loss, _ = ram_state(st, par, t - st[T0], v1)
    _book_face(st, par, t)
    labels = int(st[LABELS])
    riding = st[RAM] == RIDING
    v1, v2, kick = pipe_plug_events(st, par, labels, _pipe_mass(par, riding), v1, v2)
    stick = (labels & STICK) != 0
    kick1 = 0.0
    if labels & PIPE_GO_POS:
        kick1 = 1.0
        if par[P_FACE] != 0.0 and st[KIND] == AT_REST and par[P_QP] > par[P_F2] \
                and par[P_COUPLED] != 0.0:
            kick = 1                  # released at F1 + Qf + F2: the pipe slides over the plug
    if labels & PIPE_GO_NEG:
        kick1 = -1.0
    if riding:
        v_ram = v1
    closing = 0.0
    if labels & LOAD_END:                     # the compression turns: no relative velocity
        delta_max = delta
        v1, v2, v_ram = _turn(st, par, v1, v2, v_ram, (labels & PIPE_REST) != 0, stick)
    if labels & SEPARATE:
        delta = st[DB]
    if labels & RELOAD:
        delta = delta_max
    if labels & ACCUMULATE:
        delta, v_ram = 0.0, v1
    if labels & CONTACT:
        delta = st[DB]
        if par[P_K] == 0.0 and v_ram > v1:
            v1, v_ram, lost, closing = impact(st, par, v1, v_ram, t)
            loss += lost
    if par[P_COUPLED] == 0.0:
        u2 = v2 = 0.0
    _origin(st, delta, v_ram, delta_max, loss, kick1, closing)
    searched_to = st[T0] + st[HORIZON]
    ram_start_piece(st, par, log, t, u1, v1, u2, v2, w_in, w_outer, w_inner, st[Q], kick,
                    max(searched_to - t, 0.0))
    return OK


@jitable
def _axial(st, par, t):
    """The smallest and largest axial force along the pipe [N] at ``t`` [s] in the piece."""
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    dt = t - st[T0]
    fc = ram_state(st, par, dt, v1)[4]
    f1, f2, face = ram_forces(st, par, u1, fc, dt)
    q = st[Q] if st[Q] == st[Q] else 0.0
    return axial_extremes(q + fc, f1, f2, par[P_LAW + 3], contact_length(law_of(par), u1),
                          par[P_L2], face)


@jitable
def _extremes(st, par, t_end):
    """Take the extremes of the axial force over [EXT_T, t_end] [s] of the current piece into
    the step's: at both ends and where the compression turns in between."""
    a = st[EXT_T]
    low, high = _axial(st, par, t_end)
    lo_a, hi_a = _axial(st, par, a)
    low, high = min(low, lo_a), max(high, hi_a)
    if st[DK] > 0.0 and st[RAM] != FREE:
        # delta' = 0 where w t = phase + n pi (the compression a sinusoid about its balance)
        w = st[DW]
        phase = math.atan2(st[DV] * w, -st[DA])
        n = math.floor((w * (a - st[T0]) - phase) / math.pi) + 1.0
        for _ in range(2):
            t = st[T0] + (phase + n * math.pi) / w
            if not t < t_end:
                break
            if t > a:
                lo_t, hi_t = _axial(st, par, t)
                low, high = min(low, lo_t), max(high, hi_t)
            n += 1.0
    st[N_LOW], st[N_HIGH] = min(st[N_LOW], low), max(st[N_HIGH], high)
    st[EXT_T] = t_end


@jitable
def ram_step_to(st, par, log, q, t_end):
    """:func:`pipeplug.rigid.stepping.step_to` with the ram, keeping the axial force's extremes
    over the step."""
    if st[STEPPING] == 0.0:
        st[STEPPING] = 1.0
        st[N_LOW], st[N_HIGH], st[EXT_T] = math.inf, -math.inf, st[TIME]
    if q != st[Q]:
        if log_full(st, log):
            return LOG_FULL
        _restart(st, par, log, q, t_end)
    for _ in range(MAX_EVENTS_PER_STEP):
        if t_end > st[SEARCHED]:
            _search(st, par, max(t_end - st[T0], 2.0 * st[HORIZON]))
        if t_end < st[T_SNAP]:
            _extremes(st, par, t_end)
            st[TIME] = t_end
            st[STEPPING] = 0.0
            return OK
        if log_full(st, log):
            return LOG_FULL
        _extremes(st, par, st[T_EVENT])
        code = _take_event(st, par, log)
        if code != OK:
            return code
    return TOO_MANY_EVENTS


@jitable
def ram_at_rest(st):
    """Nothing moves, no load, and the ram is off the head and not coming back (no force,
    not moving forward: a ram that left and recedes does not keep the pipe from rest)."""
    if not (st[KIND] == AT_REST and (st[Q] == 0.0 or st[Q] != st[Q])):   # NaN: none yet
        return False
    return st[RAM] == NONE or (st[RAM] == FREE and st[VR] <= 0.0)


@jitable
def ram_outputs_at(st, par, t):
    """The 25 outputs at absolute time ``t`` [s] (a float) inside the current piece, as
    :func:`pipeplug.rigid.stepping.outputs_at` with the ram (module docstring)."""
    u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
    dt = t - st[T0]
    _, v_ram, _, loss, fc = ram_state(st, par, dt, v1)
    f1, f2, _ = ram_forces(st, par, u1, fc, dt)
    mr = par[P_RAM_M]
    kinetic_ram = 0.5 * mr * v_ram * v_ram
    held = fc * fc / (2.0 * par[P_KU]) if par[P_K] > 0.0 else 0.0
    kinetic_pipe = 0.5 * (par[P_M1] * v1 * v1 + par[P_M2] * v2 * v2)
    kinetic = kinetic_pipe + kinetic_ram
    q = st[Q] if st[Q] == st[Q] else 0.0
    head = q + fc
    area = par[P_S1]
    rest = 1.0 if ram_at_rest(st) else 0.0
    w_face = face_work_at(st, par, t) if par[P_FACE] != 0.0 else 0.0
    transferred = kinetic_pipe + w_outer + w_inner + w_face
    return (v1, v2, u1, u2, f1, f2, w_in, w_outer + w_inner, w_outer, w_inner, kinetic, held,
            0.0, head, v_ram, st[W_RAM], loss, transferred, -head / area, st[N_LOW] / area,
            st[N_HIGH] / area, rest, st[S1], st[S2], w_face)


@jitable
def ram_sample_into(st, par, log, loads, times, table, first):
    """:func:`pipeplug.rigid.stepping.sample_into` with the ram: stepping to each sample time
    (the stresses are extremes over each interval), the outputs written into ``table``."""
    n = times.shape[0]
    for j in range(first, n):
        q = float(loads[j])
        if not q - q == 0.0:
            return LOAD_NOT_FINITE, j
        code = ram_step_to(st, par, log, q, times[j])
        if code != OK:
            return code, j
        out = ram_outputs_at(st, par, times[j])
        for i in range(len(out)):     # W_damping, after them, stays 0 (no ram is damped)
            table[i, j] = out[i]
    return OK, n
