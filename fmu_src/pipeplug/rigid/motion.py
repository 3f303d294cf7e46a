"""Closed-form motion of one rigid body under a force linear in its position.

Between two events of the rigid models every moving body obeys::

    M U'' = F - kappa U        i.e.   U'' = a0 - k (U - U0),   k = kappa / M

with constant ``F`` and ``kappa``: ``kappa = 0`` (model I: uniform acceleration), ``kappa > 0``
(model II sliding forward: harmonic, omega = sqrt(k)) or ``kappa < 0`` (model II sliding
backward: hyperbolic, lambda = sqrt(-k)). The solution is written in a form that stays
accurate as k -> 0 (no large equilibrium offset that cancels)::

    U(t) = U0 + V0 S(t) + a0 C(t),      V(t) = V0 S'(t) + a0 S(t)

    k > 0:  S = sin(w t)/w,   C = 2 sin(w t/2)^2 / k,     S' = cos(w t)
    k < 0:  S = sinh(l t)/l,  C = 2 sinh(l t/2)^2 / (-k), S' = cosh(l t)
    k = 0:  S = t,            C = t^2/2,                  S' = 1

Where |k| t^2 is small the three are one Taylor series in x = k t^2 (the same for both signs
of k), used below |x| = 1e-3 (truncation below 1e-17 relative): the closed forms would divide
quantities that underflow when k is tiny (a friction of 1e-295 Pa), and the series is also the
more accurate of the two there.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["Motion", "refine_root"]

_INF = math.inf


class Motion:
    """One body's motion over one piece (times measured from the piece start).

    Parameters
    ----------
    U0 : float
        Position at the piece start [m].
    V0 : float
        Velocity at the piece start [m/s].
    a0 : float
        Acceleration at the piece start [m/s^2].
    k : float
        Stiffness per unit mass kappa/M [1/s^2]; the acceleration is ``a0 - k (U - U0)``.
    """

    __slots__ = ("U0", "V0", "a0", "k", "_w")

    def __init__(self, U0: float, V0: float, a0: float, k: float = 0.0):
        self.U0, self.V0, self.a0, self.k = U0, V0, a0, k
        self._w = math.sqrt(abs(k))

    def _basis(self, t):
        """(S, C, S') at time ``t`` [s] (a float, or a numpy array for dense output)."""
        k = self.k
        if k == 0.0:
            return t, 0.5 * t * t, 1.0
        x = k * t * t
        if isinstance(t, float):
            return _series(t, x) if abs(x) < _SERIES_BELOW else self._closed(t, math)
        closed, series = self._closed(t, np), _series(t, x)
        near = np.abs(x) < _SERIES_BELOW
        return tuple(np.where(near, a, b) for a, b in zip(series, closed))

    def _closed(self, t, fn):
        """(S, C, S') in closed form; ``fn`` is math (floats) or numpy (arrays)."""
        k, w = self.k, self._w
        if k > 0.0:
            half = fn.sin(0.5 * w * t)
            return fn.sin(w * t) / w, 2.0 * half * half / k, fn.cos(w * t)
        half = fn.sinh(0.5 * w * t)
        return fn.sinh(w * t) / w, -2.0 * half * half / k, fn.cosh(w * t)

    def state(self, t):
        """Position [m] and velocity [m/s] at time ``t`` [s] after the piece start.

        ``t`` may be a float or a numpy array (then both results are arrays).
        """
        d, V = self.travel(t)
        return self.U0 + d, V

    def travel(self, t):
        """Displacement since the piece start [m] and velocity [m/s] at time ``t`` [s].

        Works are computed from the displacement itself, never as a difference of two
        positions, which would lose the digits the positions share.
        """
        if self.k == 0.0:                 # uniform acceleration, the common case: fewer ops
            V0, a0 = self.V0, self.a0
            return t * (V0 + 0.5 * a0 * t), V0 + a0 * t
        S, C, dS = self._basis(t)
        return self.V0 * S + self.a0 * C, self.V0 * dS + self.a0 * S

    def acceleration_at(self, U: float) -> float:
        """Acceleration [m/s^2] when the body is at position ``U`` [m]."""
        return self.a0 - self.k * (U - self.U0)

    def time_to_rest(self, sgn: int) -> float:
        """First time t > 0 at which the velocity, of sign ``sgn`` at the start, reaches zero.

        Closed form (atan2 for harmonic, atanh for hyperbolic, division for uniform pieces).
        Returns ``inf`` if it never does. ``sgn * V0 >= 0``; if ``V0 == 0`` the body starts
        from rest and ``sgn * a0`` should be positive.
        """
        v, a = sgn * self.V0, sgn * self.a0
        if v <= 0.0 and a <= 0.0:
            return 0.0
        k, w = self.k, self._w
        if k == 0.0:
            return v / -a if a < 0.0 else _INF
        if k > 0.0:
            return math.atan2(v, -a / w) / w
        if a < 0.0 and v * w < -a:
            return math.atanh(v * w / -a) / w
        return _INF

    def time_to_position(self, target: float, t_max: float, xtol: float = 0.0) -> float:
        """First time in (0, t_max] at which U(t) = ``target``, or ``inf``.

        The caller guarantees the motion is monotone on [0, t_max] (the velocity does not
        change sign inside a piece: its zero is itself an event).
        """
        g0 = self.U0 - target
        g1 = self.state(t_max)[0] - target
        if g0 == 0.0 or g0 * g1 > 0.0:
            return _INF
        if self.k == 0.0:
            return _first_quadratic_root(0.5 * self.a0, self.V0, g0, t_max)
        return refine_root(lambda t: self.state(t)[0] - target,
                           lambda t: self.state(t)[1], 0.0, t_max, xtol)


_SERIES_BELOW = 1e-3     # |k t^2| below which the Taylor series is used


def _series(t, x):
    """(S, C, S') as Taylor series in x = k t^2, four terms each (float or array)."""
    S = t * (1.0 - x / 6.0 * (1.0 - x / 20.0 * (1.0 - x / 42.0)))
    C = 0.5 * t * t * (1.0 - x / 12.0 * (1.0 - x / 30.0 * (1.0 - x / 56.0)))
    dS = 1.0 - 0.5 * x * (1.0 - x / 12.0 * (1.0 - x / 30.0))
    return S, C, dS


def _first_quadratic_root(a: float, b: float, c: float, t_max: float) -> float:
    """Smallest root in (0, t_max] of a t^2 + b t + c (a sign change is known to exist)."""
    if a == 0.0:
        return -c / b
    disc = max(b * b - 4.0 * a * c, 0.0)
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    roots = [r for r in ((q / a) if q != 0.0 else _INF, (c / q) if q != 0.0 else _INF)
             if 0.0 < r]
    best = min(roots) if roots else t_max
    return min(best, t_max)


def refine_root(g, dg, a: float, b: float, xtol: float = 0.0) -> float:
    """The root of ``g`` in a bracket [a, b] where ``g(a)`` and ``g(b)`` differ in sign.

    Safeguarded Newton: a Newton step from the latest iterate when it stays inside the
    bracket, bisection otherwise; the bracket shrinks with every evaluation. Stops when the
    update or the bracket is a few ulps wide, or narrower than ``xtol`` (the caller's time
    resolution: below it a root is no better known). Returns a time in (a, b].

    Newton converges from one side on a convex or concave ``g``, so the far bracket end may
    never move: a converged Newton iterate is the answer, not that end.
    """
    ga, gb = g(a), g(b)
    if gb == 0.0:
        return b
    t, gt = (b, gb) if abs(gb) < abs(ga) else (a, ga)
    for _ in range(200):
        d = dg(t)
        new = t - gt / d if d != 0.0 else 0.5 * (a + b)
        if not a < new < b:
            new = 0.5 * (a + b)
        g_new = g(new)
        if g_new == 0.0:
            return new
        if (g_new > 0.0) == (ga > 0.0):
            a, ga = new, g_new
        else:
            b, gb = new, g_new
        if abs(new - t) <= 4.0 * math.ulp(new):
            return new
        if b - a <= max(4.0 * math.ulp(b), xtol):
            return b
        t, gt = new, g_new
    return b
