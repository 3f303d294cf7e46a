"""Nodal Coulomb projections at the impulse level, in a form numba compiles.

These are the rules of :mod:`pipeplug.friction` (same arithmetic, same order of the sign
patterns, same slack) written with scalars and tuples only, so that the elastic kernels can
inline them. Given trial velocities ``w`` [m/s] after the elastic and load update, masses ``m``
[kg] and friction impulse limits ``c = dt * (limit force)`` [N s], they return the velocities
after friction and the friction impulses on the pipe along +x [N s]. A zero relative velocity is
static friction: a node whose trial momentum is within its limit stops exactly.
"""
from __future__ import annotations

from .jit import jit

__all__ = ["one_contact", "pair_contact", "two_contacts"]

_SLACK = 1e-13  # as pipeplug.friction: a pattern this close to its inequality is accepted
_S1 = (0, 0, 0, 1, -1, 1, 1, -1, -1)  # sign patterns, most stuck first (pipeplug.friction)
_S2 = (0, 1, -1, 0, 0, 1, -1, 1, -1)


@jit
def one_contact(m, w, c):
    """One node on a fixed support: ``(velocity, impulse)`` (= friction.solve_one_contact)."""
    p = m * w
    if abs(p) <= c:
        return 0.0, -p
    f = -c if p > 0.0 else c
    return w + f / m, f


@jit
def pair_contact(m1, m2, w1, w2, c2):
    """Pipe node and plug node, no soil contact: ``(x1, x2, impulse of the plug on the pipe)``.

    Equals ``friction.solve_two_contacts(m1, m2, w1, w2, 0, c2)``: stuck together at the
    momentum average when the static reaction is within ``c2`` (with the same slack), else
    sliding with impulse ``-c2 sign(w1 - w2)``.
    """
    x = (m1 * w1 + m2 * w2) / (m1 + m2)
    f2 = -m2 * (x - w2)
    if abs(f2) - c2 <= _SLACK * (abs(m1 * w1) + abs(m2 * w2) + c2):
        return x, x, _clip(f2, c2)
    s2 = 1 if w1 > w2 else -1
    f2 = -c2 * s2
    return w1 + f2 / m1, w2 - f2 / m2, f2


@jit
def two_contacts(m1, m2, w1, w2, c1, c2):
    """Pipe node on the soil and against a plug node: ``(x1, x2, f1, f2)``.

    Same result as ``friction.solve_two_contacts`` (``f1`` soil on pipe, ``f2`` plug on pipe).
    """
    scale = _SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1 + c2)
    best = 0
    best_violation = 0.0
    for p in range(9):
        x1, x2, f1, f2, violation = _pattern(m1, m2, w1, w2, c1, c2, _S1[p], _S2[p])
        if violation <= scale:
            return x1, x2, _clip(f1, c1), _clip(f2, c2)
        if p == 0 or violation < best_violation:
            best, best_violation = p, violation
    # Unreachable in exact arithmetic (a solution always exists); never fail on round-off.
    x1, x2, f1, f2, violation = _pattern(m1, m2, w1, w2, c1, c2, _S1[best], _S2[best])
    return x1, x2, _clip(f1, c1), _clip(f2, c2)


@jit
def _pattern(m1, m2, w1, w2, c1, c2, s1, s2):
    """Velocities and impulses of one sign pattern, and how far it violates its conditions."""
    if s1 == 0 and s2 == 0:
        f2 = m2 * w2
        f1 = -m1 * w1 - f2
        return 0.0, 0.0, f1, f2, max(abs(f1) - c1, abs(f2) - c2)
    if s1 == 0:
        f2 = -c2 * s2
        x2 = w2 - f2 / m2
        f1 = -m1 * w1 - f2
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


@jit
def _clip(f, c):
    """Clip a static reaction to its limit (it may exceed it by round-off only)."""
    if f > c:
        return c
    if f < -c:
        return -c
    return f
