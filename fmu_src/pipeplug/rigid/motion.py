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

(evaluated without dividing by w or k, see :func:`_basis`).

A motion is the tuple ``(U0 [m], V0 [m/s], a0 [m/s^2], k [1/s^2], w [1/s])`` made by
:func:`motion` (``w = sqrt(|k|)``), times are measured from its start. The functions take
floats and tuples only, so that numba compiles them (:func:`pipeplug.jit.jitable`) and Python
runs the same source; :func:`travel` and :func:`state` also take an array of times (dense
output).
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import jitable

__all__ = ["motion", "travel", "state", "acceleration_at", "time_to_rest", "time_to_position",
           "refine_root", "ulp", "line_and_sine", "lag", "POSITION", "RELATIVE_VELOCITY",
           "LINE_AND_SINE"]

_INF = math.inf

#: what :func:`refine_root` zeroes: the position minus a target, the velocity minus that of
#: a uniformly accelerated second body, or a line plus a sinusoid (:func:`line_and_sine`)
POSITION, RELATIVE_VELOCITY, LINE_AND_SINE = 0, 1, 2


@jitable
def motion(U0, V0, a0, k=0.0):
    """The motion starting at ``U0`` [m] with ``V0`` [m/s] and acceleration ``a0`` [m/s^2],
    stiffness per unit mass ``k`` [1/s^2]: ``(U0, V0, a0, k, w)``."""
    return U0, V0, a0, k, math.sqrt(abs(k))


@jitable
def ulp(x):
    """The unit in the last place of ``x`` (``math.ulp``, in a form numba compiles)."""
    x = abs(x)
    if not x < _INF:
        return x                             # inf or nan
    if x == 0.0:
        return 5e-324
    _, e = math.frexp(x)                     # x = m 2^e, 0.5 <= m < 1
    return max(math.ldexp(1.0, e - 53), 5e-324)


# Trigonometry of a float (math) or of an array of times (numpy): numba resolves the branch when
# it compiles, Python when it runs.
@jitable
def _cos(x):
    if isinstance(x, float):
        return math.cos(x)
    return np.cos(x)


@jitable
def _sin(x):
    if isinstance(x, float):
        return math.sin(x)
    return np.sin(x)


@jitable
def _cosh(x):
    if isinstance(x, float):
        return math.cosh(x)
    return np.cosh(x)


@jitable
def _sin_over_x(x):
    """sin(x)/x, 1 at x = 0 (``x`` a float or an array)."""
    if isinstance(x, float):
        return math.sin(x) / x if x != 0.0 else 1.0
    safe = np.where(x == 0.0, 1.0, x)
    return np.where(x == 0.0, 1.0, np.sin(safe) / safe)


@jitable
def _over(sine, x):
    """sin(x)/x from ``sine`` = sin(x), 1 at x = 0 (``x`` a float or an array)."""
    if isinstance(x, float):
        return sine / x if x != 0.0 else 1.0
    return np.where(x == 0.0, 1.0, sine / np.where(x == 0.0, 1.0, x))


@jitable
def _sinh_over_x(x):
    """sinh(x)/x, 1 at x = 0 (``x`` a float or an array)."""
    if isinstance(x, float):
        return math.sinh(x) / x if x != 0.0 else 1.0
    safe = np.where(x == 0.0, 1.0, x)
    return np.where(x == 0.0, 1.0, np.sinh(safe) / safe)


@jitable
def _basis(k, w, t):
    """(S, C, S') of a motion with ``k != 0`` at time(s) ``t`` [s].

    Written as ``S = t f(w t) / (w t)`` and ``C = t^2/2 (f(w t/2) / (w t/2))^2`` (f = sin, or
    sinh for k < 0), the same functions, with no division by a tiny ``w`` or ``k``: the squared
    sine of a tiny ``w t`` underflows (at tau1 = 1e-295 Pa, C was garbage). The harmonic one
    from the half angle alone, sin(w t) = 2 sin(h) cos(h) and cos(w t) = 1 - 2 sin(h)^2 (h =
    w t/2): a sine and a cosine of one argument, which compiled code takes in one call, where
    three sines and cosines of two arguments cost twice as long in dense output.
    """
    x = w * t
    if k > 0.0:
        h = 0.5 * x
        sine = _sin(h)
        half = _over(sine, h)
        return t * half * _cos(h), 0.5 * t * t * half * half, 1.0 - 2.0 * sine * sine
    half = _sinh_over_x(0.5 * x)
    return t * _sinh_over_x(x), 0.5 * t * t * half * half, _cosh(x)


@jitable(inline=True)
def travel(m, t):
    """Displacement since the start [m] and velocity [m/s] at time(s) ``t`` [s].

    Works are computed from the displacement itself, never as a difference of two positions,
    which would lose the digits the positions share.
    """
    _, V0, a0, k, w = m
    if k == 0.0:                 # uniform acceleration, the common case: fewer operations
        return t * (V0 + 0.5 * a0 * t), V0 + a0 * t
    return _travel_curved(V0, a0, k, w, t)


@jitable
def _travel_curved(V0, a0, k, w, t):
    """:func:`travel` of a harmonic or hyperbolic motion (apart, so that compiled code inlines
    the short uniform case into its loops)."""
    S, C, dS = _basis(k, w, t)
    return V0 * S + a0 * C, V0 * dS + a0 * S


#: 1/(2n+3)! and 1/(2n+4)!, n = 0..9: the series of (x - sin x)/x^3 and (x^2/2 - 1 + cos x)/x^4,
#: to below an ulp for |x| < 1 (1/21! = 2e-20)
_LAG_S = tuple((-1.0) ** n / math.factorial(2 * n + 3) for n in range(10))
_LAG_C = tuple((-1.0) ** n / math.factorial(2 * n + 4) for n in range(10))


@jitable
def _series(coef, y):
    total = coef[9]
    for n in range(8, -1, -1):
        total = total * y + coef[n]
    return total


@jitable
def lag(k, w, t):
    """``(t - S, t^2/2 - C)`` of a harmonic motion (``k > 0``) at time(s) ``t`` [s]: what a
    motion's displacement lags behind its uniform part, ``(x - sin x)/w`` and
    ``(x^2/2 - 1 + cos x)/w^2`` (x = w t), in [s] and [s^2].

    Apart, so that a displacement that is a small difference of a uniform and a harmonic
    motion (a pipe creeping while the cushion loads) keeps its digits: written as ``t - S``
    both terms are ~ t and cancel to ~ t x^2/6. Below |x| = 1 a series in x^2, above it the
    direct form (x - sin x >= x/6 there: a few ulps).
    """
    x = w * t
    y = x * x
    if isinstance(t, float):
        if abs(x) < 1.0:
            return t * y * _series(_LAG_S, y), t * t * y * _series(_LAG_C, y)
        return t - math.sin(x) / w, t * t * (0.5 - (1.0 - math.cos(x)) / y)
    small = np.abs(x) < 1.0
    safe = np.where(small, 1.0, y)
    ws = np.where(small, 1.0, w)
    far_s = t - np.sin(x) / ws
    far_c = t * t * (0.5 - (1.0 - np.cos(x)) / safe)
    ss, sc = _series(_LAG_S, y), _series(_LAG_C, y)
    return np.where(small, t * y * ss, far_s), np.where(small, t * t * y * sc, far_c)


@jitable
def state(m, t):
    """Position [m] and velocity [m/s] at time(s) ``t`` [s] after the start."""
    d, V = travel(m, t)
    return m[0] + d, V


@jitable
def acceleration_at(m, U):
    """Acceleration [m/s^2] when the body is at position ``U`` [m]."""
    return m[2] - m[3] * (U - m[0])


@jitable
def time_to_rest(m, sgn):
    """First time t > 0 [s] at which the velocity, of sign ``sgn`` at the start, reaches zero.

    Closed form (atan2 for harmonic, atanh for hyperbolic, division for uniform motion).
    Returns ``inf`` if it never does. ``sgn * V0 >= 0``; if ``V0 == 0`` the body starts from
    rest and ``sgn * a0`` should be positive.
    """
    _, V0, a0, k, w = m
    v, a = sgn * V0, sgn * a0
    if v <= 0.0 and a <= 0.0:
        return 0.0
    if k == 0.0:
        return v / -a if a < 0.0 else _INF
    if k > 0.0:
        return math.atan2(v, -a / w) / w
    if a < 0.0 and v * w < -a:
        return math.atanh(v * w / -a) / w
    return _INF


@jitable
def time_to_position(m, target, t_max, xtol=0.0):
    """First time in (0, t_max] [s] at which U(t) = ``target`` [m], or ``inf``.

    The caller guarantees the motion is monotone on [0, t_max] (the velocity does not change
    sign inside a piece: its zero is itself an event). ``xtol`` [s]: the resolution of time.
    """
    g0 = m[0] - target
    g1 = state(m, t_max)[0] - target
    if g0 == 0.0 or g0 * g1 > 0.0:
        return _INF
    if m[3] == 0.0:
        return _first_quadratic_root(0.5 * m[2], m[1], g0, t_max)
    return refine_root(POSITION, m, target, 0.0, 0.0, 0.0, t_max, xtol)


@jitable
def _first_quadratic_root(a, b, c, t_max):
    """Smallest root in (0, t_max] of a t^2 + b t + c (a sign change is known to exist)."""
    if a == 0.0:
        return -c / b
    disc = max(b * b - 4.0 * a * c, 0.0)
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    r1 = (q / a) if q != 0.0 else _INF
    r2 = (c / q) if q != 0.0 else _INF
    best = t_max                      # no positive root: the bracket's end
    if 0.0 < r1:
        best = r1
        if 0.0 < r2 and r2 < best:
            best = r2
    elif 0.0 < r2:
        best = r2
    return min(best, t_max)


@jitable
def line_and_sine(c, t):
    """``f(t) = c0 + c1 t + c2 (1 - cos(w t)) + c3 sin(w t) / w`` and its time derivative at
    ``t`` [s], for ``c = (c0, c1, c2, c3, w)``, ``w > 0`` [1/s] (the rigid models' quantities
    while a ram presses a cushion: a uniform acceleration plus an oscillation)."""
    c0, c1, c2, c3, w = c
    x = w * t
    half = math.sin(0.5 * x)
    f = c0 + c1 * t + c2 * (2.0 * half * half) + c3 * t * _sin_over_x(x)
    return f, c1 + c2 * w * math.sin(x) + c3 * math.cos(x)


@jitable
def _g(kind, m, target, V2, a2, t):
    """The function whose root :func:`refine_root` finds, at ``t`` [s]: U(t) - target [m]
    (``kind`` POSITION), V(t) - (V2 + a2 t) [m/s] (RELATIVE_VELOCITY), or
    :func:`line_and_sine` of the coefficients ``m`` (LINE_AND_SINE)."""
    if kind == POSITION:
        return state(m, t)[0] - target
    if kind == LINE_AND_SINE:
        return line_and_sine(m, t)[0]
    return travel(m, t)[1] - (V2 + a2 * t)


@jitable
def _dg(kind, m, target, V2, a2, t):
    """Time derivative of :func:`_g`."""
    if kind == POSITION:
        return state(m, t)[1]
    if kind == LINE_AND_SINE:
        return line_and_sine(m, t)[1]
    return acceleration_at(m, state(m, t)[0]) - a2


@jitable
def refine_root(kind, m, target, V2, a2, a, b, xtol=0.0):
    """The root in a bracket [a, b] [s] of the function ``kind`` of motion ``m`` (see
    :func:`_g`: ``target`` [m] for POSITION; ``V2`` [m/s] and ``a2`` [m/s^2] of the second body
    for RELATIVE_VELOCITY), whose values at ``a`` and ``b`` differ in sign.

    Safeguarded Newton: a Newton step from the latest iterate when it stays inside the
    bracket, bisection otherwise; the bracket shrinks with every evaluation. Stops when the
    update or the bracket is a few ulps wide, or narrower than ``xtol`` [s] (the caller's time
    resolution: a root sooner after ``a`` than time can resolve, approached only linearly by
    Newton, is no better known below it). Newton converges from one side on a convex or
    concave function, so the far bracket end may never move: a converged Newton iterate is the
    answer, not that end.

    Returns the first float at which the function has left the sign it has at ``a`` (reached 0
    or crossed), in (a, b]: the converged iterate is walked there ulp by ulp. Where the
    iteration stops depends on the bracket, and the bracket on how far the search looked
    ahead, that is on the host's step ends; that float does not, so a run's events, and with
    them its outputs, do not depend on the communication grid (an event time one ulp apart,
    times a pipe braking at 5000 m/s^2, moved a plug's velocity by 1.3e-12 of the velocity
    scale between two grids).
    """
    positive = _g(kind, m, target, V2, a2, a) > 0.0
    t = _newton(kind, m, target, V2, a2, a, b, xtol)
    return _first_past(kind, m, target, V2, a2, t, a, b, positive)


@jitable
def _newton(kind, m, target, V2, a2, a, b, xtol):
    """An iterate within a few ulps of the root (see :func:`refine_root`)."""
    ga = _g(kind, m, target, V2, a2, a)
    gb = _g(kind, m, target, V2, a2, b)
    if gb == 0.0:
        return b
    if abs(gb) < abs(ga):
        t, gt = b, gb
    else:
        t, gt = a, ga
    for _ in range(200):
        d = _dg(kind, m, target, V2, a2, t)
        new = t - gt / d if d != 0.0 else 0.5 * (a + b)
        if not a < new < b:
            new = 0.5 * (a + b)
        g_new = _g(kind, m, target, V2, a2, new)
        if g_new == 0.0:
            return new
        if (g_new > 0.0) == (ga > 0.0):
            a, ga = new, g_new
        else:
            b, gb = new, g_new
        if abs(new - t) <= 4.0 * ulp(new):
            return new
        if b - a <= max(4.0 * ulp(b), xtol):
            return b
        t, gt = new, g_new
    return b


_WALK = 64          # ulps walked at most from the Newton iterate to the first float past


@jitable
def _past(kind, m, target, V2, a2, t, positive):
    """True when the function ``kind`` (see :func:`_g`) is 0 at ``t`` [s] or has the sign
    opposite to ``positive``."""
    g = _g(kind, m, target, V2, a2, t)
    return g == 0.0 or (g > 0.0) != positive


@jitable
def _first_past(kind, m, target, V2, a2, t, a, b, positive):
    """The first float in (a, b] [s] at which the function ``kind`` is 0 or has the sign
    opposite to ``positive``, walking from ``t`` [s] (which is within a few ulps of it)."""
    if _past(kind, m, target, V2, a2, t, positive):
        for _ in range(_WALK):
            before = math.nextafter(t, -_INF)
            if before <= a or not _past(kind, m, target, V2, a2, before, positive):
                return t
            t = before
        return t
    for _ in range(_WALK):
        t = math.nextafter(t, _INF)
        if t >= b or _past(kind, m, target, V2, a2, t, positive):
            return min(t, b)
    return t
