"""The ram of the exact rigid solver: pieces and events in closed form while a ram strikes.

A ram of mass ``m`` [kg] moves along the pipe's axis behind its head. Between ram and head is a
cushion that pushes but never pulls, loaded along ``k`` [N/m] and unloaded along ``k / e^2``
(Smith's convention; ``e`` the coefficient of restitution), reloaded along the unloading line up
to the largest compression reached::

    F(delta) = max(0, min(k delta, k delta_max - (k / e^2) (delta_max - delta)))

``delta`` [m] is the cushion's compression: the ram's displacement less the head's since the
strike (a strike puts the ram at the head, touching an unloaded cushion). On each branch the
force is ``F = k_b (delta - delta_b)``: ``k_b = k, delta_b = 0`` loading, ``k_b = k / e^2,
delta_b = (1 - e^2) delta_max`` unloading. A direct strike (``k = 0``, steel on steel) is an
impulse with restitution ``e`` between ram and pipe alone (the plug and the soil take no impulse:
their friction is finite).

Exact pieces (model I: the soil's friction is constant while the pipe slides; also tau1 = 0):

* the ram on the cushion, the pipe sliding: ram and pipe (with a carried plug) are two bodies on
  a linear spring. Their centre of mass accelerates uniformly under the load and the sliding
  friction; the compression is harmonic, ``omega^2 = k_b (1/m + 1/M)``. The pipe's velocity,
  the relative velocity of a sliding plug and the acceleration a carried plug needs are a line
  plus a sinusoid (:func:`~pipeplug.rigid.motion.line_and_sine`); their zeros and level
  crossings are found by splitting the search at the function's critical points (closed form)
  into monotone parts and refining the bracketed root (:func:`first_crossing`);
* the ram on the cushion, the pipe held by the soil: the ram alone oscillates on the cushion
  (``omega^2 = k_b / m``); the pipe breaks away when the load, the cushion's force and the
  plug's force pass the soil's hold (a level of the compression);
* the ram flying (no force): uniform; it reaches the cushion again (or the head) when its
  motion meets the pipe's, a quadratic's root;
* a direct impact that leaves the ram behind a decelerating pipe is followed by more impacts,
  each a factor ``e`` slower: a Zeno sequence. When the pipe's and the plug's contact modes stay
  the same through all of them (the velocities at impacts form affine sequences in ``e^n``,
  monotone, so four values decide it) the sequence is one piece (:data:`ZENO`), summed in
  closed form to its accumulation point; after it the ram rides on the pipe (:data:`RIDING`)
  while the contact stays compressive, and leaves when it would pull. An impact slower than
  :data:`PLASTIC` of the fastest since the strike, or than time can resolve (:func:`impact`),
  is taken as perfectly plastic (the rest of a sequence of hops of a pipe stopping between
  impacts moves the bodies by less than round-off).

With the soil's end resistance (:mod:`~pipeplug.rigid.face`; model I: the front end is always in
the soil) the pieces keep their forms: the soil's end forces are constant while a body slides
(``FACE1 = -Qf`` on a pipe advancing, ``FACE3 = -Qp`` on a plug advancing, 0 retreating), so they
join the load of what moves; the modes are decided by the three-contact problem
(:func:`~pipeplug.rigid.face.face_modes`); a held pipe breaks away forward where the cushion's
force passes the shaft's hold, Qf and what the plug adds (carried, Qp; cored, F2); a plug sliding
in the soil stops there (``PLUG_STOP``); a carried plug breaks away where the force it needs, its
face's included, reaches F2.

Model II (the soil's friction growing with the penetration) with a ram gives two coupled
frequencies and is refused when the model is built, as is the paper's explicit scheme.

Energy: the cushion's recoverable energy ``F^2 / (2 k / e^2)`` is its strain energy; its loss
``W_cushion`` is ``(1 - e^2)`` of the work done on the loading line and
``(1 - e^2) mu w^2 / 2`` per direct impact (``mu = m M1 / (m + M1)``, ``w`` the closing
velocity), never negative. The functions read and write the records of
:mod:`~pipeplug.rigid.record` only, so that numba compiles them.
"""
from __future__ import annotations

import math

from ..contact.outer import face_on, limit, segment
from ..jit import jitable
from .face import face_modes, make_face_piece
from .motion import (
    LINE_AND_SINE,
    lag,
    line_and_sine,
    motion,
    refine_root,
    time_to_rest,
    travel,
    ulp,
)
from .pieces import (
    AT_REST,
    BOTH_SLIDE,
    PIPE_REST,
    PLUG_SLIDES,
    PLUG_STOP,
    STICK,
    TOGETHER,
    contact_modes,
    find_event,
    forces_of,
    law_of,
    make_piece,
    pipe_of,
    plug_of,
)
from .record import (
    A1,
    A2,
    D0,
    DA,
    DB,
    DK,
    DMAX,
    DV,
    DW,
    END,
    FACE1,
    FACE3,
    FC0,
    FORCE0,
    FS1,
    FS2,
    K1,
    K2,
    KAPPA,
    KB,
    KICK1,
    KIND,
    P_COUPLED,
    P_E,
    P_E2,
    P_F2,
    P_FACE,
    P_K,
    P_KU,
    P_M1,
    P_M2,
    P_QF,
    P_QP,
    P_RAM_M,
    RAM,
    RAM_ON,
    RHO,
    S1,
    S2,
    S3,
    T0,
    U1,
    U2,
    V1,
    V2,
    VR,
    VSCALE,
    W1,
    W2,
    W_CUSH,
    ZT,
    ZW,
    Q,
)

__all__ = ["NONE", "FREE", "LOADING", "UNLOADING", "RIDING", "ZENO", "LOAD_END", "SEPARATE",
           "RELOAD", "CONTACT", "PIPE_GO_POS", "PIPE_GO_NEG", "ACCUMULATE", "PLASTIC",
           "cushion_force", "make_ram_piece", "find_ram_event", "travels", "ram_state",
           "ram_forces", "impact", "first_crossing", "first_rise", "rel_of"]

_INF = math.inf
_TWO_PI = 2.0 * math.pi

#: kinds of the ram's piece: not struck yet, flying, on the cushion's loading or unloading
#: line, riding on the pipe (direct contact, no relative motion), a Zeno sequence of impacts
NONE, FREE, LOADING, UNLOADING, RIDING, ZENO = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0
#: event labels (bits, after those of :mod:`~pipeplug.rigid.pieces`): largest compression,
#: the cushion's force reaching 0, the compression reaching its largest again, the ram reaching
#: the cushion (or the head), the pipe starting to slide forward or backward under the
#: cushion's force, the accumulation point of a Zeno sequence
LOAD_END, SEPARATE, RELOAD, CONTACT, PIPE_GO_POS, PIPE_GO_NEG, ACCUMULATE = (
    PLUG_STOP << 1, PLUG_STOP << 2, PLUG_STOP << 3, PLUG_STOP << 4, PLUG_STOP << 5,
    PLUG_STOP << 6, PLUG_STOP << 7)
#: a direct impact closing at most this share of the fastest since the strike is plastic
PLASTIC = 2.0 ** -40
#: a direct impact closing slower than the pipe's deceleration times this many ulps of the
#: time, over 1 - e, is plastic (:func:`impact`)
_FLIGHT_ULPS = 16.0


@jitable
def cushion_force(delta, delta_max, k, k_unload):
    """The cushion's force [N] at compression ``delta`` [m] after the largest ``delta_max``."""
    return max(0.0, min(k * delta, k * delta_max - k_unload * (delta_max - delta)))


@jitable(inline=True)
def rel_of(st):
    """The compression's motion in the current piece (:mod:`~pipeplug.rigid.motion`)."""
    return st[D0], st[DV], st[DA], st[DK], st[DW]


@jitable
def _sliding_load(par, q, u1, s1, s2, m1, face1, face3):
    """``(G [N], M [kg])``: the load with the sliding friction and the mass of what moves with
    the pipe sliding in direction ``s1`` (the plug carried when ``s2 = 0``), pipe of mass
    ``m1`` [kg] (with a riding ram); the soil's friction is constant (model I), its end forces
    ``face1`` on the pipe and ``face3`` on the plug [N] too (0 without end resistance)."""
    force0 = segment(law_of(par), u1, float(s1))[0]
    ends = face1 + face3 if s2 == 0 else face1
    g = q + force0
    if ends != 0.0:                   # (no addition of 0: a zero keeps its sign)
        g += ends
    if s2 == 0:
        return g, m1 + par[P_M2]
    return g - s2 * par[P_F2], m1


@jitable
def _modes(par, m1, q, u1, v1, v2, kick, kick1):
    """The contact modes and forces at an origin under ``q`` [N] on a pipe of mass ``m1`` [kg]:
    ``(s1, s2, s3, f1, f2, face1, face3)``, the held contacts' forces ``f1`` (the shaft's),
    ``f2`` [N] and the soil's end forces on pipe and plug [N] (sliding or static; ``s3``,
    ``face1``, ``face3`` 0 without end resistance: :func:`~pipeplug.rigid.pieces.
    contact_modes` alone decides then)."""
    if par[P_FACE] == 0.0:
        s1, s2, f1s, f2s, f1_sliding, f2_sliding = contact_modes(par, m1, q, u1, v1, v2, kick,
                                                                 kick1)
        return s1, s2, 0, f1_sliding + f1s, f2_sliding + f2s, 0.0, 0.0
    s1, s2, s3, f1, f2, f3 = face_modes(par, m1, q, u1, v1, v2, kick, kick1)
    law = law_of(par)
    if s1 == 0:
        shaft = max(f1, -limit(law, u1))            # the shaft friction holds first
        face1 = f1 - shaft
        f1 = shaft
    else:
        face1 = -par[P_QF] * face_on(law, u1) if s1 > 0 else 0.0
    return s1, s2, s3, f1, f2, face1, f3 if par[P_COUPLED] != 0.0 else 0.0


@jitable
def make_ram_piece(st, par, t0, u1, v1, u2, v2, q, kick):
    """:func:`~pipeplug.rigid.pieces.make_piece` with the ram: decide the contact modes and the
    ram's kind at the origin (the ram's origin values are in ``st``: D0, VR, DMAX, KICK1, ZW)
    and write the piece's closed-form motions."""
    if st[RAM_ON] == 0.0:             # not struck yet: the pipe alone, as without a ram
        if par[P_FACE] != 0.0:
            make_face_piece(st, par, t0, u1, v1, u2, v2, q, kick)
        else:
            make_piece(st, par, t0, u1, v1, u2, v2, q, kick)
        _no_coupling(st)
        st[RAM] = NONE
        return
    m1, m2, mr = par[P_M1], par[P_M2], par[P_RAM_M]
    k, ku = par[P_K], par[P_KU]
    delta, vr, dmax = st[D0], st[VR], st[DMAX]
    kick1 = int(st[KICK1])
    cushion = k > 0.0
    touch = dmax - par[P_E2] * dmax           # where the unloading line's force is 0
    fc = 0.0
    if cushion:
        # the branch's own form, so that a compression set onto ``touch`` has no force at all
        fc = k * delta if delta >= dmax else max(0.0, ku * (delta - touch))
    riding = False
    if not cushion and delta == 0.0 and vr == v1:
        # Touching without closing: the ram rides when the pipe alone would slow down (it
        # presses on the ram), else the pipe leaves it.
        s1, s2, _, _, _, face1, face3 = _modes(par, m1, q, u1, v1, v2, kick, kick1)
        if s1 != 0:
            g, mass = _sliding_load(par, q, u1, s1, s2, m1, face1, face3)
            riding = g / mass < 0.0
    m_pipe = m1 + mr if riding else m1
    s1, s2, s3, f1, f2, face1, face3 = _modes(par, m_pipe, q + fc, u1, v1, v2, kick, kick1)
    st[T0], st[U1], st[V1], st[U2], st[V2] = t0, u1, v1, u2, v2
    st[S1], st[S2] = float(s1), float(s2)
    st[A1] = st[K1] = st[W1] = st[A2] = st[K2] = st[W2] = 0.0
    _no_coupling(st)
    st[FC0] = fc
    if par[P_FACE] != 0.0:
        st[S3], st[FACE1], st[FACE3] = float(s3), face1, face3
        if s2 != 0 and s3 != 0:       # the plug slides in the pipe and in the soil: uniform
            st[A2] = (s2 * par[P_F2] + face3) / m2
    elif s2 != 0:
        st[A2] = s2 * par[P_F2] / m2
    g, mass, a1 = 0.0, m_pipe, 0.0
    if s1 == 0:
        st[FS1] = f1
        if s2 == 0:
            st[KIND], st[FS2] = AT_REST, f2
        else:
            st[KIND] = PLUG_SLIDES
    else:
        force0, kappa, end = segment(law_of(par), u1, float(s1))
        st[FORCE0], st[KAPPA], st[END] = force0, kappa, end
        st[KIND] = TOGETHER if s2 == 0 else BOTH_SLIDE
        g, mass = _sliding_load(par, q, u1, s1, s2, m_pipe, face1, face3)
        a1 = (g + fc) / mass
    closing = vr - v1
    if riding:
        st[RAM], st[D0], st[VR] = RIDING, 0.0, v1
        _pipe_motion(st, par, u1, v1, a1)
        return
    if cushion:
        pressing = fc > 0.0 or (delta >= touch and (closing > 0.0 or (closing == 0.0
                                                                       and a1 < 0.0)))
        if pressing:
            loading = delta >= dmax and (closing > 0.0 or (fc == 0.0 and dmax == 0.0))
            st[RAM] = LOADING if loading else UNLOADING
            st[KB] = k if loading else ku
            st[DB] = 0.0 if loading else touch
            _contact_motion(st, par, u1, v1, closing, fc, g, mass, s1)
            return
        st[DB] = touch
    st[RAM] = FREE
    _pipe_motion(st, par, u1, v1, a1)
    st[DV], st[DA] = closing, -st[A1]
    if st[ZW] > 0.0 and not _zeno_fits(st, par):
        st[ZW] = 0.0
    if st[ZW] > 0.0:
        st[RAM] = ZENO


@jitable
def _no_coupling(st):
    """A piece whose pipe does not feel the ram's relative motion (written before the rest)."""
    st[RHO] = st[DV] = st[DA] = st[DK] = st[DW] = 0.0
    st[DB] = st[KB] = st[FC0] = st[ZT] = 0.0


@jitable
def _pipe_motion(st, par, u1, v1, a1):
    """The pipe's uniform motion from ``(u1, v1)`` with ``a1`` [m/s^2] (0 when stuck); a
    carried plug moves with it."""
    if st[S1] == 0.0:
        return
    _, _, st[A1], st[K1], st[W1] = motion(u1, v1, a1, 0.0)
    if st[S2] == 0.0 and par[P_COUPLED] != 0.0:
        st[A2], st[K2], st[W2] = st[A1], st[K1], st[W1]


@jitable
def _contact_motion(st, par, u1, v1, closing, fc, g, mass, s1):
    """The motions while the ram presses the cushion (branch KB, DB set): the ram alone
    against a held pipe, or two bodies on a spring (centre of mass uniformly accelerated,
    compression harmonic; the pipe's motion holds the centre's acceleration and RHO its share
    of the compression)."""
    mr, kb = par[P_RAM_M], st[KB]
    if s1 == 0:
        _, st[DV], st[DA], st[DK], st[DW] = motion(st[D0], closing, -fc / mr, kb / mr)
        return
    total = mr + mass
    st[RHO] = mr / total
    _pipe_motion(st, par, u1, v1, g / total)
    _, st[DV], st[DA], st[DK], st[DW] = motion(st[D0], closing, -fc / mr - (g + fc) / mass,
                                               kb * (1.0 / mr + 1.0 / mass))


@jitable
def _zeno_fits(st, par):
    """True when the impacts that follow the direct impact the piece starts with (closing
    velocity ZW) form a Zeno sequence through which the contact modes hold; sets ZT, its
    length [s].

    Between impacts the ram flies and the pipe decelerates uniformly (``a < 0``): each flight
    is ``e`` times the last, so the impacts accumulate at ``T = 2 e w / ((1 - e) (-a))``.
    The pipe's velocity just after the n-th impact, just before it, and the plug's relative
    velocity there, are affine in ``e^n`` (monotone in n) and linear between impacts: they
    keep their signs through the sequence when they do just after the impact at the origin,
    just before and after the next one, and at the limit.
    """
    e, s1, s2 = par[P_E], st[S1], st[S2]
    a = st[A1]
    if not (e < 1.0 and s1 != 0.0 and a < 0.0):
        return False
    if st[KIND] == TOGETHER and par[P_COUPLED] != 0.0:
        return False                  # each impact would set the carried plug sliding
    w = st[ZW]
    period = 2.0 * e * w / (-a)       # the first flight
    length = period / (1.0 - e)
    if not (length < _INF):
        return False
    st[ZT] = length
    v1_after = _after_impacts(st, par, 1)[1]
    v1_before = st[V1] + a * period
    v1_limit = _zeno_at(st, par, length)[1]
    if not (s1 * st[V1] > 0.0 and s1 * v1_before > 0.0 and s1 * v1_after > 0.0
            and s1 * v1_limit >= 0.0):
        return False
    if st[KIND] == BOTH_SLIDE:
        v2_first = st[V2] + st[A2] * period
        v2_limit = st[V2] + st[A2] * length
        if not (s2 * (st[V1] - st[V2]) > 0.0 and s2 * (v1_before - v2_first) > 0.0
                and s2 * (v1_after - v2_first) > 0.0 and s2 * (v1_limit - v2_limit) >= 0.0):
            return False
        if st[S3] != 0.0 and not st[S3] * v2_limit > 0.0:
            return False              # the plug would stop in the soil (its face) on the way
    return True


@jitable
def _impacts_by(e, length, dt):
    """The number of impacts of a Zeno piece of ``length`` [s] after its origin's, at or
    before ``dt`` [s] < ``length``: the largest j with ``length (1 - e^j) <= dt``."""
    x = 1.0 - dt / length
    j = int(math.log(x) / math.log(e)) if x > 0.0 else 0
    j = max(j, 0)
    while j > 0 and length * (1.0 - math.pow(e, float(j))) > dt:
        j -= 1
    while length * (1.0 - math.pow(e, float(j + 1))) <= dt:
        j += 1
    return j


@jitable
def _after_impacts(st, par, j):
    """``(t_j [s], v1 [m/s], v_ram [m/s], e^j)`` just after the j-th impact of a Zeno piece
    after its origin's (:func:`_zeno_at`)."""
    m1, mr, e = par[P_M1], par[P_RAM_M], par[P_E]
    ej = math.pow(e, float(j))
    tj = st[ZT] * (1.0 - ej)
    moved = (1.0 + e) * st[ZW] * (e * (1.0 - ej) / (1.0 - e)) / (m1 + mr)
    return tj, st[V1] + st[A1] * tj + mr * moved, st[VR] - m1 * moved, ej


@jitable
def _zeno_at(st, par, dt):
    """``(d1, v1, delta, v_ram, loss)`` at ``dt`` [s] into a Zeno piece: the pipe's
    displacement [m] and velocity [m/s], the compression [m] (<= 0: the ram behind the head),
    the ram's velocity [m/s] and the impacts' loss since the origin [J].

    After the j-th impact (at ``t_j = T (1 - e^j)``) the closing velocity was ``e^j w``; the
    impulses moved ``(1 + e) m M1 / (m + M1) w (e + ... + e^j)`` of momentum from ram to pipe;
    the momentum of both grew by ``M1 a t`` (the pipe's load), and at each impact both are at
    one place, so the pipe's displacement there is the centre of mass's.
    """
    m1, mr, e = par[P_M1], par[P_RAM_M], par[P_E]
    w, length, a = st[ZW], st[ZT], st[A1]
    total = m1 + mr
    p0 = mr * st[VR] + m1 * st[V1]
    mu = m1 * mr / total
    if dt >= length:                  # the accumulation point
        v = (p0 + m1 * a * length) / total
        d = (p0 * length + 0.5 * m1 * a * length * length) / total
        return d, v, 0.0, v, 0.5 * mu * w * w * e * e
    tj, v1_j, v_ram, ej = _after_impacts(st, par, _impacts_by(e, length, dt))
    s = dt - tj
    d1 = (p0 * tj + 0.5 * m1 * a * tj * tj) / total + v1_j * s + 0.5 * a * s * s
    delta = -e * ej * w * s - 0.5 * a * s * s
    return d1, v1_j + a * s, delta, v_ram, 0.5 * mu * w * w * e * e * (1.0 - ej * ej)


@jitable
def travels(st, par, dt):
    """``(d1, v1, d2, v2)``: the displacements [m] since the origin and the velocities [m/s] of
    pipe and plug at ``dt`` [s] into the current piece."""
    if st[RAM] == ZENO:
        d1, v1, _, _, _ = _zeno_at(st, par, dt)
        d2, v2 = travel(plug_of(st), dt)
        return d1, v1, d2, v2
    d1, v1 = travel(pipe_of(st), dt)
    rho = st[RHO]
    if rho != 0.0:
        # U = (centre of mass) - rho delta. The displacement as the pipe's own uniform part
        # (its velocity and acceleration at the origin) plus rho times the compression's lag
        # behind its own uniform part, each term without cancellation: as the centre's
        # travel less rho times the compression's change, two ~1e-9 m terms left a pipe
        # creeping at 1e-16 m/s a displacement of either sign (friction work falling)
        dv = travel(rel_of(st), dt)[1]
        lag_s, lag_c = lag(st[DK], st[DW], dt)
        own = st[A1] - rho * st[DA]
        d1 = dt * (st[V1] + 0.5 * own * dt) + rho * (st[DV] * lag_s + st[DA] * lag_c)
        v1 = v1 + rho * (st[DV] - dv)
    if st[KIND] == TOGETHER and par[P_COUPLED] != 0.0:
        return d1, v1, d1, v1
    d2, v2 = travel(plug_of(st), dt)
    return d1, v1, d2, v2


@jitable
def ram_state(st, par, dt, v1):
    """``(delta [m], v_ram [m/s], delta_max [m], W_cushion [J], F [N])`` at ``dt`` [s] into the
    current piece, the pipe's velocity being ``v1`` [m/s] there."""
    rk = st[RAM]
    if rk == NONE:
        return 0.0, 0.0, 0.0, st[W_CUSH], 0.0
    if rk == ZENO:
        _, _, delta, v_ram, loss = _zeno_at(st, par, dt)
        return delta, v_ram, st[DMAX], st[W_CUSH] + loss, 0.0
    if rk == RIDING:
        return 0.0, v1, st[DMAX], st[W_CUSH], max(0.0, -par[P_RAM_M] * st[A1])
    dd, dv = travel(rel_of(st), dt)
    delta = st[D0] + dd
    if rk == FREE:
        return delta, st[VR], st[DMAX], st[W_CUSH], 0.0
    if rk == LOADING:
        # (1 - e^2) of the work k (delta^2 - D0^2) / 2 on the loading line is lost
        work = 0.5 * par[P_K] * dd * (2.0 * st[D0] + dd)
        loss = st[W_CUSH] + max(0.0, (1.0 - par[P_E2]) * work)
        return delta, v1 + dv, max(st[DMAX], delta), loss, max(0.0, par[P_K] * delta)
    return delta, v1 + dv, st[DMAX], st[W_CUSH], max(0.0, st[KB] * (delta - st[DB]))


@jitable
def ram_forces(st, par, u1, fc, dt):
    """Friction forces on the pipe ``(f1, f2)`` [N] and the soil's end force on its front end
    [N] at ``dt`` [s] into the piece, the pipe at ``u1`` [m] and the cushion pushing with
    ``fc`` [N]."""
    f1, f2 = forces_of(st, par, u1)
    face = st[FACE1]
    if st[KIND] == AT_REST or st[KIND] == PLUG_SLIDES:
        f1 = f1 - (fc - st[FC0])                # the soil holds what the cushion adds
        if par[P_FACE] != 0.0:                  # the shaft first, the front end the rest
            total = f1 + face
            f1 = max(total, -limit(law_of(par), u1))
            face = total - f1
        return f1, f2, face
    rho = st[RHO]
    if rho != 0.0 and st[KIND] == TOGETHER and par[P_COUPLED] != 0.0:
        dd = travel(rel_of(st), dt)[0]
        a1 = st[A1] - rho * (st[DA] - st[DK] * dd)   # the carried plug needs M2 a1
        return f1, -(par[P_M2] * a1 - st[FACE3]), face
    return f1, f2, face


@jitable
def impact(st, par, v1, vr, t):
    """A direct impact of the ram at ``vr`` on the pipe at ``v1`` [m/s], closing, at ``t``
    [s] at the end of the current piece: the new ``(v1, vr)`` [m/s], the loss [J] and the
    closing velocity that may start a Zeno sequence (0 for a plastic impact). Updates VSCALE.

    Plastic besides :data:`PLASTIC`: an impact closing slower than time can resolve. When
    the sequence is not one Zeno piece (an impact sets a carried plug sliding), each flight
    back, ``2 e w / a`` under the pipe's deceleration ``a``, ends at an absolute time rounded
    up to its ulp, where the ram has gained up to ``a`` ulp(t) of closing velocity: the
    closing velocities stop decreasing near ``a ulp(t) / (1 - e)`` (1.5e-12 m/s at 1.3e4
    m/s^2, t = 0.13 s, e = 0.92), above PLASTIC of the fastest, and the impacts would repeat
    without end. :data:`_FLIGHT_ULPS` times that is plastic: what the rest of the sequence
    would move is ~ w^2 / a, below 1e-20 m.
    """
    m1, mr, e = par[P_M1], par[P_RAM_M], par[P_E]
    w = vr - v1
    st[VSCALE] = max(st[VSCALE], w)
    total = m1 + mr
    mu = m1 * mr / total
    unresolved = _FLIGHT_ULPS * ulp(t) * abs(st[A1]) / (1.0 - e) if e < 1.0 else 0.0
    if w <= PLASTIC * st[VSCALE] or w <= unresolved:
        v = (mr * vr + m1 * v1) / total
        return v, v, 0.5 * mu * w * w, 0.0
    j = (1.0 + e) * mu * w
    return v1 + j / m1, vr - j / mr, 0.5 * (1.0 - e) * (1.0 + e) * mu * w * w, w


# ---------------------------------------------------------------- events


@jitable
def first_crossing(c, s, t_max, immediate):
    """First time in [0, t_max] [s] at which ``s f(t) <= 0``, ``f`` the
    :func:`~pipeplug.rigid.motion.line_and_sine` of ``c`` (``inf``: none).

    ``f`` can vanish only where its line ``c0 + c2 + c1 t`` is within the oscillation's
    amplitude of 0; that window is split at the critical points of ``f`` (closed form), and the
    first monotone part whose end has left the sign ``s`` holds the root, refined by
    :func:`~pipeplug.rigid.motion.refine_root` (the first float past it, whatever the part's
    ends, so that the events do not depend on how far ahead the search looked; the iteration
    runs to a few ulps of the time since the piece's start, not to the absolute time's coarser
    resolution, from which that walk could not reach the same float on every grid). A piece may
    start with ``s f(0) <= 0``: ``immediate`` (a force at a friction limit) returns 0 when the
    first part goes on past the limit; otherwise (a velocity or a compression starting at its
    event's value, as the piece's modes chose) a first part going the other way is round-off.
    Which way the first part goes is read at its own end (the first critical point, or the end
    of the window where ``f`` can vanish), never at ``t_max``: a search cut short (``t_max``
    0 when a strike starts where the last search ended) decides as a longer one.
    """
    c0, c1, c2, c3, w = c
    if not t_max >= 0.0:
        return _INF
    amp = (math.hypot(c2, c3 / w) + ulp(abs(c0) + abs(c2))) * (1.0 + 1e-9)
    mid = c0 + c2
    lo, hi, window = 0.0, t_max, _INF
    if c1 == 0.0:
        if abs(mid) > amp:
            return _INF
    else:
        ta, tb = (-amp - mid) / c1, (amp - mid) / c1
        window = max(ta, tb)
        lo, hi = max(lo, min(ta, tb)), min(hi, window)
        if lo > hi:
            return _INF
    a = lo
    fa = s * line_and_sine(c, a)[0]
    first = a == 0.0
    slope = math.hypot(c2 * w, c3)
    monotone = not slope > abs(c1)
    base = spread = 0.0
    if not monotone:
        base = math.atan2(c2 * w, c3)
        spread = math.acos(-c1 / slope)
    # the critical points base -+ spread + 2 pi n, in increasing order: index i = 2 n (-), 2 n + 1
    i = 2 * int(math.floor((w * lo - base - spread) / _TWO_PI))
    while True:
        b = hi
        end = window                  # the end of the monotone part from a
        if not monotone:
            while True:
                x = base + (spread if i % 2 else -spread) + _TWO_PI * (i // 2)
                i += 1
                if x / w > a:
                    break
            end = min(end, x / w)
            if x / w < hi:
                b = x / w
        fb = s * line_and_sine(c, b)[0]
        if fb <= 0.0:
            if fa > 0.0:
                if fb == 0.0:
                    return b
                return refine_root(LINE_AND_SINE, c, 0.0, 0.0, 0.0, a, b, 0.0)
            if not first:
                return a
            if immediate and (b == end or end == _INF
                              or s * line_and_sine(c, end)[0] <= 0.0):
                return 0.0
        first = False
        if b >= hi:
            return _INF
        a, fa = b, fb


@jitable
def first_rise(c, b, a, t_max):
    """First time in [0, t_max] [s] at which ``c + b t + a t^2`` reaches 0 from below
    (``c <= 0``), in closed form (``inf``: none). Starting at 0, it must first go below."""
    if c > 0.0:
        return 0.0
    if c == 0.0:
        if b > 0.0 or (b == 0.0 and a > 0.0):
            return 0.0
        t = -b / a if a > 0.0 else _INF          # where it comes back
        return t if t <= t_max else _INF
    if a == 0.0:
        t = -c / b if b > 0.0 else _INF
        return t if t <= t_max else _INF
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return _INF
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    best = _INF
    for r in (q / a, c / q if q != 0.0 else _INF):
        if 0.0 < r < best:
            best = r
    return best if best <= t_max else _INF


@jitable
def _velocity_line(st, v0, a0):
    """The coefficients of a velocity ``v0 + a0 t`` less the pipe's share of the compression's
    change, as :func:`~pipeplug.rigid.motion.line_and_sine` takes them."""
    rho = st[RHO]
    return v0, a0, rho * st[DV], -rho * st[DA], st[DW]


@jitable
def _coupled_events(st, par, horizon):
    """The pipe's events while it slides coupled to the ram by the cushion: it stops, the plug
    sticks, or the carried plug breaks away."""
    s1 = st[S1]
    t_rest = first_crossing(_velocity_line(st, st[V1], st[A1]), s1, horizon, False)
    t_lim = min(t_rest, horizon)
    t_b, label = _INF, 0
    if st[KIND] == BOTH_SLIDE:
        line = _velocity_line(st, st[V1] - st[V2], st[A1] - st[A2])
        t_b, label = first_crossing(line, st[S2], t_lim, False), STICK
        if st[S3] != 0.0 and par[P_QP] > 0.0:
            # the plug, sliding uniformly in the soil, stops where its face's force switches
            t_b, label = _merge(t_b, label, time_to_rest(plug_of(st), st[S3]), PLUG_STOP)
    elif par[P_COUPLED] != 0.0:
        # the carried plug needs M2 a1(t) - f3 (f3 its face's force, FACE3)
        c0, c1, c2, c3, w = _velocity_line(st, st[V1], st[A1])
        for s in (1, -1):
            plug_limit = (par[P_F2] + s * st[FACE3]) / par[P_M2]
            line = (plug_limit - s * (c1 + c3), 0.0, s * c3, -s * c2 * w * w, w)
            t = first_crossing(line, 1.0, t_lim, True)
            if t < t_b:
                t_b, label = t, (16 if s == 1 else 32)      # BREAKAWAY_POS / _NEG
    return _merge(t_rest, PIPE_REST, t_b, label)


@jitable
def _level(st, target, sign):
    """The coefficients of ``sign (delta(t) - target)`` (the compression harmonic)."""
    k = st[DK]
    return sign * (st[D0] - target), 0.0, sign * st[DA] / k, sign * st[DV], st[DW]


@jitable
def _cushion_events(st, par, t_lim):
    """The cushion's and the held pipe's events while the ram presses the cushion."""
    t_ev, labels = _INF, 0
    if st[RAM] == LOADING:
        t_ev, labels = time_to_rest(rel_of(st), 1.0), LOAD_END
    else:
        t_ev, labels = _merge(first_crossing(_level(st, st[DB], 1.0), 1.0, t_lim, False),
                              SEPARATE,
                              first_crossing(_level(st, st[DMAX], -1.0), 1.0, t_lim, False),
                              RELOAD)
    if st[S1] == 0.0:
        # the soil holds the pipe while |Q + F + f2| <= its limit: two levels of delta
        f2 = st[FS2] if st[KIND] == AT_REST else -st[S2] * par[P_F2]
        hold = limit(law_of(par), st[U1])
        q = st[Q] if st[Q] == st[Q] else 0.0
        kb = st[KB]
        ahead = hold
        if par[P_FACE] != 0.0:
            ahead, f2 = _held_ahead(st, par, hold)
        for s in (1, -1):
            reach = st[DB] + ((ahead if s == 1 else -hold) - q - f2) / kb
            if s == -1 and not reach > st[DB]:
                continue               # the cushion pulls never: its force cannot hold less
            t = first_crossing(_level(st, reach, -s), 1.0, min(t_lim, t_ev), True)
            t_ev, labels = _merge(t_ev, labels, t, PIPE_GO_POS if s == 1 else PIPE_GO_NEG)
    return t_ev, labels


@jitable
def _held_ahead(st, par, hold):
    """``(limit [N], f2 [N])`` with end resistance: the force on a held pipe at which it
    advances, and the plug's force on it to count beside the load. The soil holds the shaft's
    ``hold`` and Qf; a plug stuck to the pipe adds the lesser of its face's Qp (carried along)
    and its friction F2 (the pipe sliding over it); a plug sliding in the pipe its friction's
    sliding force. Retreating, neither face resists (the plug goes back with the pipe)."""
    if st[KIND] == AT_REST:
        extra = min(par[P_QP], par[P_F2]) if par[P_COUPLED] != 0.0 else 0.0
        return hold + par[P_QF] + extra, 0.0
    return hold + par[P_QF], -st[S2] * par[P_F2]


@jitable
def find_ram_event(st, par, horizon):
    """Time [s] after the piece start of its first event within ``horizon`` [s], and its
    labels (:func:`~pipeplug.rigid.pieces.find_event` with the ram's)."""
    rk = st[RAM]
    if rk == NONE:
        return find_event(st, par, horizon)
    if rk == ZENO:
        return st[ZT], ACCUMULATE
    if st[RHO] == 0.0:
        t_pipe, l_pipe = find_event(st, par, horizon)
    else:
        t_pipe, l_pipe = _coupled_events(st, par, horizon)
    t_lim = min(horizon, t_pipe)
    if rk == FREE:
        t = first_rise(st[D0] - st[DB], st[DV], 0.5 * st[DA], t_lim)
        return _merge(t_pipe, l_pipe, t, CONTACT)
    if rk == RIDING:
        return t_pipe, l_pipe
    t, labels = _cushion_events(st, par, t_lim)
    return _merge(t_pipe, l_pipe, t, labels)


@jitable
def _merge(ta, la, tb, lb):
    """The earlier of two events and the labels of both when within round-off of each other."""
    t_min = min(ta, tb)
    if t_min == _INF:
        return _INF, 0
    tol = 8.0 * ulp(max(t_min, 1e-300)) + 1e-15 * t_min
    labels = 0
    if ta <= t_min + tol:
        labels |= la
    if tb <= t_min + tol:
        labels |= lb
    return t_min, labels

