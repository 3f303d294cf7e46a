"""The contact problem with Smith damping: Coulomb windows plus linear dampers, solved jointly.

Smith damping (docs/physics.md, "Smith damping") makes a sliding resistance ``R`` resist with
``R (1 + J v)``, ``v`` the sliding speed: a constant part, the Coulomb limit, and a linear
damper ``J R v`` that acts only while the contact slides (at ``v = 0`` it is 0, and the
sticking limits stay the static ones). At the level of one implicit step (rates ``x`` after
it; the fd scheme's velocities, with windows and dampers of impulses ``tau R`` and ``tau J R``)
the problem of :mod:`pipeplug.contact.face` becomes::

    m1 x1 = m1 w1 + f1 + g1 + f2 + g2,      m2 x2 = m2 w2 - f2 - g2 + f3 + g3
    f1 in [-c1p, c1m] (Coulomb, as there),  g1 = -(a1p if x1 > 0 else a1m) x1
    f2 in -c2 Sign(x1 - x2),                g2 = -d2 (x1 - x2)
    f3 in [-c3p, 0],                        g3 = -a3p max(x2, 0)

``(x1, x2)`` minimises the strictly convex ``m1 (x1-w1)^2/2 + m2 (x2-w2)^2/2 + phi1(x1) +
c2 |x1 - x2| + c3p max(x2, 0) + a1p max(x1, 0)^2/2 + a1m min(x1, 0)^2/2 + d2 (x1 - x2)^2/2 +
a3p max(x2, 0)^2/2``: the rates are unique, and every force, each the (sub)gradient of a convex
potential that is least at rate 0, does work ``<= 0`` at them (the dampers' ``-a x^2``). The
rates are one of the 13 sign patterns of :data:`pipeplug.contact.face.PATTERNS`, each a linear
problem of at most two unknowns, tested from the most stuck to the least (a stuck pattern has
no damping force, so the all-stuck one is :func:`~pipeplug.contact.face.face_pattern`'s).
Without end resistance ``c1p = c1m``, ``c3p = a3p = 0``.

A model without damping never calls this: the effect switched off is absent. Scalars only,
so that compiled kernels call them too (:func:`pipeplug.jit.jitable`: the elastic model's
damped cells, :mod:`pipeplug.elastic.damped`).
"""
from __future__ import annotations

from ..jit import jitable
from .coulomb import SLACK
from .face import PATTERNS, face_pattern, sliding_force

_S1 = tuple(p[0] for p in PATTERNS)
_S2 = tuple(p[1] for p in PATTERNS)
_S3 = tuple(p[2] for p in PATTERNS)

__all__ = ["damped_contacts", "damped_pattern", "damped_one"]


@jitable
def damped_one(m, w, cp, cm, ap, am, slack):
    """One body on a fixed support with the window ``[-cp, cm]`` and the dampers ``ap``
    (advancing) and ``am`` (retreating), in the units of ``m w``.

    Returns
    -------
    x, f, g : float
        The rate after the projection, the support's Coulomb force and its damping force.
    """
    p = m * w
    if -cm - slack <= p <= cp + slack:
        return 0.0, min(max(0.0 - p, -cp), cm), 0.0
    if p > 0.0:
        x = (p - cp) / (m + ap)
        return x, -cp, -ap * x
    x = (p + cm) / (m + am)
    return x, cm, -am * x


@jitable
def damped_contacts(m1, m2, w1, w2, c1p, c1m, c2, c3p, a1p, a1m, d2, a3p, slack):
    """Solve the joint problem of the module docstring.

    Parameters
    ----------
    m1, m2 : float
        Pipe and plug masses [kg], positive.
    w1, w2 : float
        Free rates of pipe and plug.
    c1p, c1m, c2, c3p : float
        The Coulomb windows (as :func:`pipeplug.contact.face.face_contacts`).
    a1p, a1m : float
        The pipe's dampers advancing and retreating (shaft, plus the annulus' advancing).
    d2 : float
        The pipe/plug damper.
    a3p : float
        The plug face's damper (advancing only).
    slack : float
        Round-off allowance (at least a :data:`~pipeplug.contact.coulomb.SLACK` share of the
        problem's own scale).

    Returns
    -------
    x1, x2, f1, f2, f3, g1, g2, g3 : float
        Rates, Coulomb forces (soil on pipe, plug on pipe, soil on plug) and damping forces
        (the same three contacts).
    s1, s2, s3 : int
        The sign pattern; 0 means stuck.
    """
    scale = max(SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1p + c1m + c2 + c3p), slack)
    best = 0
    best_violation = 0.0
    for k in range(13):
        violation = damped_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p, a1p, a1m, d2, a3p,
                                   _S1[k], _S2[k], _S3[k])[8]
        if violation <= scale:
            best = k
            break
        if k == 0 or violation < best_violation:
            best, best_violation = k, violation
    s1, s2, s3 = _S1[best], _S2[best], _S3[best]
    x1, x2, f1, f2, f3, g1, g2, g3, _ = damped_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p, a1p,
                                                       a1m, d2, a3p, s1, s2, s3)
    return (x1, x2, min(max(f1, -c1p), c1m), min(max(f2, -c2), c2), min(max(f3, -c3p), 0.0),
            g1, g2, g3, s1, s2, s3)


@jitable
def damped_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p, a1p, a1m, d2, a3p, s1, s2, s3):
    """Rates and forces of the pattern ``(s1, s2, s3)`` and how far it violates its conditions
    (<= 0: consistent): ``(x1, x2, f1, f2, f3, g1, g2, g3, violation)``."""
    if s1 == 0 and s2 == 0:           # nothing slides: no damping force
        x1, x2, f1, f2, f3, violation = face_pattern(m1, m2, w1, w2, c1p, c1m, c2, c3p, 0, 0,
                                                     0)
        return x1, x2, f1, f2, f3, 0.0, 0.0, 0.0, violation
    a1 = a1p if s1 > 0 else a1m
    a3 = a3p if s3 > 0 else 0.0
    f3 = sliding_force(s3, c3p, 0.0) if s3 != 0 else 0.0
    if s1 == 0:                       # the plug slides in a held pipe (s3 = -s2)
        f2 = -c2 * s2
        x2 = (m2 * w2 - f2 + f3) / (m2 + d2 + a3)
        g2, g3 = d2 * x2, -a3 * x2
        f1 = 0.0 - m1 * w1 - f2 - g2
        return (0.0, x2, f1, f2, f3, 0.0, g2, g3,
                max(f1 - c1m, -f1 - c1p, -x2 * s3 * m2))
    f1 = sliding_force(s1, c1p, c1m)
    if s2 == 0:                       # pipe and plug move together (s3 = s1)
        x = (m1 * w1 + m2 * w2 + f1 + f3) / (m1 + m2 + a1 + a3)
        g1, g3 = -a1 * x, -a3 * x
        f2 = m2 * w2 + f3 + g3 - m2 * x
        return x, x, f1, f2, f3, g1, 0.0, g3, max(-x * s1 * (m1 + m2), abs(f2) - c2)
    f2 = -c2 * s2
    if s3 == 0:                       # the plug held by its face, the pipe sliding over it
        x1 = (m1 * w1 + f1 + f2) / (m1 + a1 + d2)
        g1, g2 = -a1 * x1, -d2 * x1
        f3 = f2 + g2 - m2 * w2
        return (x1, 0.0, f1, f2, f3, g1, g2, 0.0,
                max(-x1 * s1 * m1, -x1 * s2 * min(m1, m2), f3, -f3 - c3p))
    # both slide: (m1 + a1 + d2) x1 - d2 x2 = b1,  -d2 x1 + (m2 + d2 + a3) x2 = b2
    b1 = m1 * w1 + f1 + f2
    b2 = m2 * w2 - f2 + f3
    p11, p22 = m1 + a1 + d2, m2 + d2 + a3
    det = p11 * p22 - d2 * d2         # > m1 m2 > 0
    x1 = (b1 * p22 + d2 * b2) / det
    x2 = (p11 * b2 + d2 * b1) / det
    g1, g2, g3 = -a1 * x1, -d2 * (x1 - x2), -a3 * x2
    return (x1, x2, f1, f2, f3, g1, g2, g3,
            max(-x1 * s1 * m1, -(x1 - x2) * s2 * min(m1, m2), -x2 * s3 * m2))
