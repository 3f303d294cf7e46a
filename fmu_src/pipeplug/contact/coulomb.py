"""The two-contact Coulomb problem, solved jointly: the one pattern table every solver uses.

Two bodies: the pipe (mass ``m1``) touches the fixed soil (contact 1) and the plug (mass
``m2``, contact 2). Given "free" rates ``w1``, ``w2`` (accelerations or velocities the bodies
would have without the undecided friction forces), find the rates ``x1``, ``x2`` and the friction
forces ``f1`` (soil on pipe) and ``f2`` (plug on pipe), both signed along +x::

    m1 x1 = m1 w1 + f1 + f2
    m2 x2 = m2 w2 - f2
    f1 in -c1 Sign(x1),   f2 in -c2 Sign(x1 - x2)

with ``Sign(0) = [-1, 1]`` (static limit = sliding limit). ``(x1, x2)`` minimises the strictly
convex function ``m1 (x1-w1)^2/2 + m2 (x2-w2)^2/2 + c1 |x1| + c2 |x1-x2|``, so the solution
is unique. It is one of nine sign patterns (s1, s2) in {-1, 0, 1}^2 (:data:`PATTERNS`), found by
testing the patterns from the most stuck to the least: on a boundary the stuck pattern wins, so a
load exactly at the friction limit does not move a body (docs/corrections.md, B4 and A7).

Used at the acceleration level by the exact solver (``c`` are forces, ``w`` accelerations) and at
the velocity level by the explicit schemes (``c`` are impulses ``dt*F``, ``w`` trial velocities,
forces returned are impulses).

The functions use scalars and tuples only, so that the compiled kernels (elastic and exact) call
them (:func:`pipeplug.jit.jitable`); this module never imports numba itself. The vectorised
form for many nodes at once is :mod:`pipeplug.contact.vectorised`; both are tested against
:data:`PATTERNS`.
"""
from __future__ import annotations

from ..jit import jitable

__all__ = ["PATTERNS", "SLACK", "one_contact", "pair_contact", "two_contacts", "pattern"]

#: Relative slack of the consistency tests: a pattern within this of its inequality is accepted.
SLACK = 1e-13

#: The sign patterns (s1, s2), most stuck first: the order decides ties on a boundary.
PATTERNS = ((0, 0), (0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))
_S1 = tuple(s1 for s1, _ in PATTERNS)
_S2 = tuple(s2 for _, s2 in PATTERNS)


@jitable
def one_contact(m, w, c, slack):
    """Coulomb projection for one body on a fixed support.

    Parameters
    ----------
    m : float
        Mass [kg].
    w : float
        Free rate (acceleration [m/s^2] or trial velocity [m/s]).
    c : float
        Friction limit in the same units times mass (force [N] or impulse [N s]).
    slack : float
        Round-off allowance in the units of ``c``: a load within it of the limit sticks.

    Returns
    -------
    x, f : float
        The rate after friction and the friction (force or impulse) along +x.
    """
    p = m * w
    if abs(p) <= c + slack:
        return 0.0, _clip(-p, c)
    f = -c if p > 0.0 else c
    return w + f / m, f


@jitable
def pair_contact(m1, m2, w1, w2, c2):
    """Pipe and plug without a soil contact: ``(x1, x2, f2)``.

    The problem of :func:`two_contacts` without contact 1: stuck together at the momentum
    average when the static reaction is within ``c2``, else sliding with
    ``f2 = -c2 sign(w1 - w2)``; the momentum ``m1 w1 + m2 w2`` is kept. (:func:`two_contacts`
    with ``c1 = 0`` gives the same except within its slack: there it takes a pair whose momentum
    is round-off against ``m1 |w1| + m2 |w2|`` as stuck to the support.)
    """
    x = (m1 * w1 + m2 * w2) / (m1 + m2)
    f2 = -m2 * (x - w2)
    if abs(f2) - c2 <= SLACK * (abs(m1 * w1) + abs(m2 * w2) + c2):
        return x, x, _clip(f2, c2)
    s2 = 1 if w1 > w2 else -1
    f2 = -c2 * s2
    return w1 + f2 / m1, w2 - f2 / m2, f2


@jitable
def two_contacts(m1, m2, w1, w2, c1, c2, slack):
    """Solve the joint two-contact Coulomb problem (see the module docstring).

    Parameters
    ----------
    m1, m2 : float
        Pipe and plug masses [kg], positive.
    w1, w2 : float
        Free rates of pipe and plug.
    c1, c2 : float
        Friction limits of contact 1 (soil/pipe) and 2 (pipe/plug), >= 0.
    slack : float
        Round-off allowance in the units of ``c`` (at least a :data:`SLACK` share of the
        problem's own scale is always allowed).

    Returns
    -------
    x1, x2, f1, f2 : float
        Rates after friction and friction terms on the pipe (``-f2`` acts on the plug).
    s1, s2 : int
        The sign pattern: ``s1 = sign(x1)``, ``s2 = sign(x1 - x2)``; 0 means stuck.
    """
    scale = max(SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1 + c2), slack)
    best = 0
    best_violation = 0.0
    for k in range(9):
        x1, x2, f1, f2, violation = pattern(m1, m2, w1, w2, c1, c2, _S1[k], _S2[k])
        if violation <= scale:
            return x1, x2, _clip(f1, c1), _clip(f2, c2), _S1[k], _S2[k]
        if k == 0 or violation < best_violation:
            best, best_violation = k, violation
    # Unreachable in exact arithmetic (a solution always exists); never fail on round-off.
    x1, x2, f1, f2, violation = pattern(m1, m2, w1, w2, c1, c2, _S1[best], _S2[best])
    return x1, x2, _clip(f1, c1), _clip(f2, c2), _S1[best], _S2[best]


@jitable
def pattern(m1, m2, w1, w2, c1, c2, s1, s2):
    """Rates and forces of the sign pattern ``(s1, s2)``, and how far it violates its
    conditions (<= 0: consistent) [N or N s]."""
    # Static reactions are written 0.0 - m w - f: the same numbers as -m w - f, but +0.0
    # rather than -0.0 under no load, so that a body at rest stays bit for bit the same.
    if s1 == 0 and s2 == 0:
        f2 = m2 * w2
        f1 = 0.0 - m1 * w1 - f2
        return 0.0, 0.0, f1, f2, max(abs(f1) - c1, abs(f2) - c2)
    if s1 == 0:
        f2 = -c2 * s2
        x2 = w2 - f2 / m2
        f1 = 0.0 - m1 * w1 - f2
        return 0.0, x2, f1, f2, max(abs(f1) - c1, x2 * s2 * m2)
    if s2 == 0:
        f1 = -c1 * s1
        x = (m1 * w1 + m2 * w2 + f1) / (m1 + m2)
        f2 = -m2 * (x - w2)
        return x, x, f1, f2, max(-x * s1 * (m1 + m2), abs(f2) - c2)
    f1 = -c1 * s1
    f2 = -c2 * s2
    x1 = w1 + (f1 + f2) / m1
    x2 = w2 - f2 / m2
    return x1, x2, f1, f2, max(-x1 * s1 * m1, -(x1 - x2) * s2 * min(m1, m2))


@jitable
def _clip(f, c):
    """Clip a static reaction to its limit (it may exceed it by round-off only)."""
    if f > c:
        return c
    if f < -c:
        return -c
    return f
