"""The contact problem with end resistance: asymmetric Coulomb windows, solved jointly.

The soil resists a front end that advances into it (docs/physics.md, "End resistance"): on the
pipe's steel annulus up to ``Qf = q_face S1`` and on the plug's front face up to
``Qp = q_plug_face S2``, set-valued like Coulomb friction, one-sided (nothing while the end
retreats). With the shaft friction ``T1`` the soil's force on the pipe lies in an asymmetric
window, and the plug gets a third contact, with the soil::

    m1 x1 = m1 w1 + f1 + f2,      m2 x2 = m2 w2 - f2 + f3
    f1 in [-c1p, c1m]: -c1p if x1 > 0, c1m if x1 < 0     (c1p = T1 + Qf, c1m = T1)
    f2 in -c2 Sign(x1 - x2)
    f3 in [-c3p, 0]:   -c3p if x2 > 0, 0 if x2 < 0        (c3p = Qp)

``(x1, x2)`` minimises the strictly convex ``m1 (x1-w1)^2/2 + m2 (x2-w2)^2/2 + phi1(x1) +
c2 |x1 - x2| + c3p max(x2, 0)`` with ``phi1(x) = c1p max(x, 0) + c1m max(-x, 0)``: the rates are
unique. They are one of 13 sign patterns ``(s1, s2, s3)`` (``s3 = sign(x2)``; three rates have
only two degrees of freedom, :data:`PATTERNS`), tested from the most stuck to the least, as
:mod:`pipeplug.contact.coulomb` does for its nine: on a boundary the stuck pattern wins. Where
every contact is stuck the forces are not unique (the plug's face and the inner friction can
share a load); the plug's friction is then the one :mod:`~pipeplug.contact.coulomb` takes
(``f2 = m2 w2``, no face force) moved into the window the others allow.

A model without end resistance never calls this (:mod:`~pipeplug.contact.coulomb` alone): the
effect switched off is absent, so its results stay those of before, bit for bit. The functions
take scalars only (compiled kernels call them, :func:`pipeplug.jit.jitable`).
"""
from __future__ import annotations

from ..jit import jitable
from .coulomb import SLACK

__all__ = ["PATTERNS", "sign", "face_contacts", "face_pattern", "one_sided", "sliding_force",
           "sliding_pair"]

#: sign patterns (s1, s2, s3), most stuck first
PATTERNS = ((0, 0, 0), (0, 1, -1), (0, -1, 1), (1, 0, 1), (-1, 0, -1), (1, 1, 0), (-1, -1, 0),
            (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, -1), (-1, -1, 1), (-1, -1, -1))
_S1 = tuple(p[0] for p in PATTERNS)
_S2 = tuple(p[1] for p in PATTERNS)
_S3 = tuple(p[2] for p in PATTERNS)


@jitable
def sliding_force(s, cp, cm):
    """The force of a window ``[-cp, cm]`` on a body sliding in direction ``s`` (+1, -1)."""
    return -cp if s > 0 else cm


@jitable
def one_sided(m, w, cp, cm, slack):
    """The projection of one body on a fixed support with the window ``[-cp, cm]``.

    Parameters
    ----------
    m : float
        Mass [kg].
    w : float
        Free rate (acceleration [m/s^2] or trial velocity [m/s]).
    cp, cm : float
        The limits against forward and backward motion, in the units of ``m w``.
    slack : float
        Round-off allowance in those units: a load within it of a limit sticks.

    Returns
    -------
    x, f : float
        The rate after the projection and the support's force along +x.
    """
    p = m * w
    if -cm - slack <= p <= cp + slack:
        return 0.0, _clip(0.0 - p, cp, cm)
    f = -cp if p > 0.0 else cm
    return w + f / m, f


@jitable
def face_contacts(m1, m2, w1, w2, c1p, c1m, c2, c3p, slack):
    """Solve the joint problem of the module docstring.

    Parameters
    ----------
    m1, m2 : float
        Pipe and plug masses [kg], positive.
    w1, w2 : float
        Free rates of pipe and plug.
    c1p, c1m : float
        The window of the soil on the pipe: its limits against forward and backward motion.
    c2 : float
        The pipe/plug friction limit.
    c3p : float
        The plug face's limit against forward motion (none against backward).
    slack : float
        Round-off allowance (at least a :data:`~pipeplug.contact.coulomb.SLACK` share of the
        problem's own scale is always allowed).

    Returns
    -------
    x1, x2, f1, f2, f3 : float
        Rates and forces: ``f1`` soil on pipe, ``f2`` plug on pipe, ``f3`` soil on plug.
    s1, s2, s3 : int
        The sign pattern: ``sign(x1)``, ``sign(x1 - x2)``, ``sign(x2)``; 0 means stuck.
    """
    scale = max(SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1p + c1m + c2 + c3p), slack)
    best = 0
    best_violation = 0.0
    for k in range(13):
        x1, x2, f1, f2, f3, violation = face_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p,
                                                     _S1[k], _S2[k], _S3[k])
        if violation <= scale:
            best = k
            break
        if k == 0 or violation < best_violation:
            best, best_violation = k, violation
    x1, x2, f1, f2, f3, violation = face_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p,
                                                 _S1[best], _S2[best], _S3[best])
    return (x1, x2, _clip(f1, c1p, c1m), _clip(f2, c2, c2), _clip(f3, c3p, 0.0), _S1[best],
            _S2[best], _S3[best])


@jitable
def sliding_pair(m1, m2, w1, w2, c1p, c1m, c3p):
    """:func:`face_contacts` while the pipe/plug contact slides (its force known, in ``w1``
    and ``w2``): two one-body problems, each body against its own forces.

    With that contact's limit 0 the bodies do not act on each other, so in exact arithmetic
    the joint problem is the pipe on its window and the plug on its face's. A round-off
    allowance taken from all the forces would let the pipe's forces hide a wrong pattern of a
    plug whose own forces are below their round-off (fuzz growth 4071:4781: a plug of 3e-14 kg
    held by its face against 6e-9 N of friction, a pipe under 6e4 N; the pattern "plug carried
    backward" was within 6e-9 N, the plug's piece ended at once and started again without
    end). The plug's allowance is the round-off of the forces on it, the pipe's that of the
    joint problem (its decision unchanged: the plug's friction on it is in ``w1``).

    Parameters
    ----------
    m1, m2, w1, w2, c1p, c1m, c3p : float
        As :func:`face_contacts` (``c2 = 0``).

    Returns
    -------
    x1, x2, f1, f2, f3, s1, s2, s3
        As :func:`face_contacts` (``f2 = 0``: the sliding force is in the free rates).
    """
    joint = SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1p + c1m + c3p)
    x1, f1 = one_sided(m1, w1, c1p, c1m, joint)
    x2, f3 = one_sided(m2, w2, c3p, 0.0, SLACK * (abs(m2 * w2) + c3p))
    return x1, x2, f1, 0.0, f3, sign(x1), sign(x1 - x2), sign(x2)


@jitable
def sign(x):
    """-1, 0 or 1: the direction of ``x`` (a velocity or a force)."""
    if x > 0.0:
        return 1
    if x < 0.0:
        return -1
    return 0


@jitable
def face_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p, s1, s2, s3):
    """Rates and forces of the pattern ``(s1, s2, s3)`` and how far it violates its conditions
    (<= 0: consistent): ``(x1, x2, f1, f2, f3, violation)``."""
    if s1 == 0 and s2 == 0:
        # f1 = A - f2 and f3 = f2 - B must lie in their windows, |f2| <= c2.
        a = 0.0 - m1 * w1
        b = m2 * w2
        lo = max(-c2, a - c1m, b - c3p)
        hi = min(c2, a + c1p, b)
        f2 = min(max(b, lo), hi)
        return 0.0, 0.0, a - f2, f2, f2 - b, lo - hi
    if s1 == 0:
        f2 = -c2 * s2
        f3 = sliding_force(s3, c3p, 0.0)
        x2 = w2 + (f3 - f2) / m2
        f1 = 0.0 - m1 * w1 - f2
        return 0.0, x2, f1, f2, f3, max(f1 - c1m, -f1 - c1p, -x2 * s3 * m2)
    f1 = sliding_force(s1, c1p, c1m)
    if s2 == 0:
        f3 = sliding_force(s1, c3p, 0.0)
        x = (m1 * w1 + m2 * w2 + f1 + f3) / (m1 + m2)
        f2 = m2 * w2 + f3 - m2 * x
        return x, x, f1, f2, f3, max(-x * s1 * (m1 + m2), abs(f2) - c2)
    f2 = -c2 * s2
    x1 = w1 + (f1 + f2) / m1
    if s3 == 0:
        f3 = f2 - m2 * w2
        return x1, 0.0, f1, f2, f3, max(-x1 * s1 * m1, f3, -f3 - c3p)
    f3 = sliding_force(s3, c3p, 0.0)
    x2 = w2 + (f3 - f2) / m2
    return x1, x2, f1, f2, f3, max(-x1 * s1 * m1, -(x1 - x2) * s2 * min(m1, m2),
                                   -x2 * s3 * m2)


@jitable
def _clip(f, cp, cm):
    """Clip a static reaction to its window ``[-cp, cm]`` (it may leave it by round-off)."""
    if f > cm:
        return cm
    if f < -cp:
        return -cp
    return f
