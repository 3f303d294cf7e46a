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

(evaluated without dividing by w or k, see :meth:`Motion._basis`)
    k = 0:  S = t,            C = t^2/2,                  S' = 1
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
        """(S, C, S') at time ``t`` [s] (a float, or a numpy array for dense output).

        Written as ``S = t f(w t) / (w t)`` and ``C = t^2/2 (f(w t/2) / (w t/2))^2`` (f = sin,
        or sinh for k < 0), the same functions, with no division by a tiny ``w`` or ``k``: the
        squared sine of a tiny ``w t`` underflows (at tau1 = 1e-295 Pa, C was garbage).
        """
        k, w = self.k, self._w
        if k == 0.0:
            return t, 0.5 * t * t, 1.0
        fn = math if isinstance(t, float) else np
        f, df = (fn.sin, fn.cos) if k > 0.0 else (fn.sinh, fn.cosh)
        x = w * t
        half = _over_x(f, 0.5 * x)
        return t * _over_x(f, x), 0.5 * t * t * half * half, df(x)

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


def _over_x(f, x):
    """f(x) / x, 1 at x = 0 (``x`` a float or a numpy array)."""
    if isinstance(x, float):
        return f(x) / x if x != 0.0 else 1.0
    safe = np.where(x == 0.0, 1.0, x)
    return np.where(x == 0.0, 1.0, f(safe) / safe)


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
    resolution: a root sooner after ``a`` than time can resolve, approached only linearly by
    Newton, is no better known below it). Newton converges from one side on a convex or
    concave ``g``, so the far bracket end may never move: a converged Newton iterate is the
    answer, not that end.

    Returns the first float at which ``g`` has left the sign of ``g(a)`` (reached 0 or
    crossed), in (a, b]: the converged iterate is walked there ulp by ulp. Where the
    iteration stops depends on the bracket, and the bracket on how far the search looked
    ahead, that is on the host's step ends; that float does not, so a run's events, and
    with them its outputs, do not depend on the communication grid (an event time one ulp
    apart, times a pipe braking at 5000 m/s^2, moved a plug's velocity by 1.3e-12 of the
    velocity scale between two grids).
    """
    positive = g(a) > 0.0
    return _first_past(g, _newton(g, dg, a, b, xtol), a, b, positive)


def _newton(g, dg, a: float, b: float, xtol: float) -> float:
    """An iterate within a few ulps of the root (see :func:`refine_root`)."""
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


_WALK = 64          # ulps walked at most from the Newton iterate to the first float past


def _first_past(g, t: float, a: float, b: float, positive: bool) -> float:
    """The first float in (a, b] at which ``g`` is 0 or has the sign opposite to
    ``positive``, walking from ``t`` (which is within a few ulps of it)."""
    def past(x):
        gx = g(x)
        return gx == 0.0 or (gx > 0.0) != positive

    if past(t):
        for _ in range(_WALK):
            before = math.nextafter(t, -math.inf)
            if before <= a or not past(before):
                return t
            t = before
        return t
    for _ in range(_WALK):
        t = math.nextafter(t, math.inf)
        if t >= b or past(t):
            return min(t, b)
    return t
