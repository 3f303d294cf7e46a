"""Pieces of the exact solver with end resistance: the soil at the front ends.

The soil resists the pipe's front end (the steel annulus) up to ``Qf = q_face S1`` and the
plug's front face up to ``Qp = q_plug_face S2`` while they advance, nothing while they retreat
(:mod:`pipeplug.contact.face`). Both forces are constant while a body slides, so every piece
stays in closed form: a sliding body moves under a constant force plus model II's affine
friction, as without them. What changes:

* the modes are decided by :func:`~pipeplug.contact.face.face_contacts` (asymmetric window on
  the pipe, a third contact plug/soil with mode ``S3``), not
  :func:`~pipeplug.contact.coulomb.two_contacts`; while the plug slides in the pipe, each body
  apart with the round-off of its own forces (:func:`~pipeplug.contact.face.sliding_pair`);
* a sliding pipe advancing in the soil feels ``-Qf`` more (model II: from U = 0 on, a segment
  end), a plug advancing ``-Qp``; a plug may be held by its face while the pipe slides over it
  (``BOTH_SLIDE`` with ``S3 = 0``: coring), and a plug sliding in a sliding pipe comes to rest
  (``PLUG_STOP``, :func:`pipeplug.rigid.pieces.find_event`) where its face's force switches;
* a carried plug breaks away where the force it needs, its face's included, reaches the inner
  limit (:func:`pipeplug.rigid.pieces.find_event`).

The end forces of a piece, ``FACE1`` on the pipe and ``FACE3`` on the plug, are constant in it
(static reactions of a stuck contact too: the loads are constant); the work against them is
``-FACE1 d1 - FACE3 d2`` over the piece's displacements, >= 0. A model without end resistance
(``P_FACE = 0``) never runs this module: its pieces are those of
:func:`~pipeplug.rigid.pieces.make_piece`, bit for bit.
"""
from __future__ import annotations

from ..contact.coulomb import SLACK
from ..contact.face import face_contacts, one_sided, sign, sliding_force, sliding_pair
from ..contact.outer import face_on, limit, segment
from ..jit import jitable
from .motion import motion, travel
from .pieces import AT_REST, BOTH_SLIDE, PLUG_SLIDES, TOGETHER, law_of, pipe_of, plug_of
from .record import (
    A1,
    A2,
    END,
    FACE1,
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
    P_M1,
    P_M2,
    P_QF,
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
    W_FACE,
)

__all__ = ["face_modes", "make_face_piece", "face_work_at"]


@jitable
def face_modes(par, m1, q, u1, v1, v2, kick, kick1):
    """The contact modes ``(s1, s2, s3)`` at an origin and the soil's and the plug's forces on
    the pipe and the soil's on the plug ``(f1, f2, f3)`` [N] (sliding or static) under the force
    ``q`` [N] on a pipe of mass ``m1`` [kg] (with a riding ram, the ram's too).

    As :func:`~pipeplug.rigid.pieces.contact_modes`: sliding contacts keep their modes and
    forces; stuck ones are decided jointly under them. ``kick`` makes a stuck plug slide,
    ``kick1`` (-1, 0, 1) a stuck pipe (a ram's cushion pushing it past the soil's hold).
    """
    m2, f2_limit, qp = par[P_M2], par[P_F2], par[P_QP]
    coupled = par[P_COUPLED] != 0.0
    law = law_of(par)
    c1 = limit(law, u1)
    c1p = c1 + par[P_QF] * face_on(law, u1)
    s1 = sign(v1)
    if s1 == 0:
        s1 = kick1
    s2 = sign(v1 - v2) if coupled else 0
    s3 = sign(v2) if coupled else 0
    f1 = sliding_force(s1, c1p, c1) if s1 != 0 else 0.0
    f2 = -s2 * f2_limit
    f3 = sliding_force(s3, qp, 0.0) if s3 != 0 else 0.0
    w1 = (q + f1 + f2) / m1
    if coupled:
        w2 = (f3 - f2) / m2
        c1s, c1ms = (0.0, 0.0) if s1 != 0 else (c1p, c1)
        c3s = 0.0 if s3 != 0 else qp
        if s2 != 0:                   # the bodies apart, each with its own round-off
            x1, x2, g1, g2, g3, p1, p2, p3 = sliding_pair(m1, m2, w1, w2, c1s, c1ms, c3s)
        else:
            x1, x2, g1, g2, g3, p1, p2, p3 = face_contacts(m1, m2, w1, w2, c1s, c1ms,
                                                           f2_limit, c3s, 0.0)
    else:
        cp, cm = (0.0, 0.0) if s1 != 0 else (c1p, c1)
        x1, g1 = one_sided(m1, w1, cp, cm, SLACK * (abs(m1 * w1) + cp + cm))
        p1, p2, p3, g2, g3 = sign(x1), 0, 0, 0.0, 0.0
    if s1 == 0:
        s1 = p1
    if s2 == 0:
        s2 = kick if kick != 0 else p2
    if s3 == 0:
        s3 = p3 if s2 != 0 else s1        # a carried plug moves with the pipe
    if kick1 != 0 and v1 == 0.0 and s2 == 0 and coupled:
        # pushed past its hold, the pipe carries the plug: the face's sliding force (the joint
        # problem, at the threshold, may have left it a static share of the other sign)
        return s1, s2, s3, f1 + g1, f2 + g2, sliding_force(s3, qp, 0.0)
    return s1, s2, s3, f1 + g1, f2 + g2, f3 + g3


@jitable
def make_face_piece(st, par, t0, u1, v1, u2, v2, q, kick):
    """:func:`~pipeplug.rigid.pieces.make_piece` with end resistance: decide the modes at the
    origin ``(u1, v1, u2, v2)`` [m, m/s] at ``t0`` [s] under ``q`` [N] and write the piece."""
    m1, m2, f2_limit = par[P_M1], par[P_M2], par[P_F2]
    coupled = par[P_COUPLED] != 0.0
    law = law_of(par)
    s1, s2, s3, f1, f2, f3 = face_modes(par, m1, q, u1, v1, v2, kick, 0)
    st[T0], st[U1], st[V1], st[U2], st[V2] = t0, u1, v1, u2, v2
    st[S1], st[S2], st[S3] = float(s1), float(s2), float(s3)
    st[A1] = st[K1] = st[W1] = st[A2] = st[K2] = st[W2] = 0.0     # at rest until set
    # The plug's face: sliding -Qp forward, 0 backward; held (s3 = 0) its static reaction.
    st[FACE3] = f3 if coupled else 0.0
    if s2 != 0 and s3 != 0:           # the plug slides in the pipe and in the soil: uniform
        st[A2] = (s2 * f2_limit + f3) / m2
    if s1 == 0:
        shaft = max(f1, -limit(law, u1))        # the shaft friction holds first
        st[FS1], st[FACE1] = shaft, f1 - shaft
        if s2 == 0:
            st[KIND], st[FS2] = AT_REST, f2
        else:
            st[KIND] = PLUG_SLIDES
        return
    force0, kappa, end = segment(law, u1, float(s1))
    st[FORCE0], st[KAPPA], st[END] = force0, kappa, end
    face1 = -par[P_QF] * face_on(law, u1) if s1 > 0 else 0.0
    st[FACE1] = face1
    if s2 == 0:                       # the pipe carries the plug, whose face advances with it
        st[KIND] = TOGETHER
        mass = m1 + m2
        a0 = (q + force0 - kappa * u1 + face1 + st[FACE3]) / mass
    else:
        st[KIND] = BOTH_SLIDE
        mass = m1
        a0 = (q + force0 - kappa * u1 + face1 - s2 * f2_limit) / m1
    _, _, st[A1], st[K1], st[W1] = motion(u1, v1, a0, kappa / mass)
    if s2 == 0 and coupled:
        st[A2], st[K2], st[W2] = st[A1], st[K1], st[W1]


@jitable
def face_work_at(st, dt):
    """The work done against the end resistance since t = 0 [J] at ``dt`` [s] after the
    piece's start (a float or an array): the work before it and the piece's, from the
    displacements themselves."""
    d1 = travel(pipe_of(st), dt)[0]
    d2 = travel(plug_of(st), dt)[0]
    return st[W_FACE] - st[FACE1] * d1 - st[FACE3] * d2
