"""Closed-form pieces of linear damped motion: ``M q' = g - C q`` for at most two velocities.

Between two events of the rigid model I with Smith damping every sliding body feels constant
forces ``g`` and linear dampers ``C`` (symmetric, positive semi-definite: the shaft's, the
end resistances' and, when pipe and plug slide on each other, the plug's, which couples them),
so the velocities ``q`` obey ``M q' = g - C q`` with a diagonal ``M``. With ``y = M^(1/2) q`` and
``S = M^(-1/2) C M^(-1/2) = R diag(mu) R^T`` (a Jacobi rotation; ``mu >= 0``) the modes
``z = R^T y`` decouple::

    z_i(t) = z_i(0) + d_i E(mu_i, t),     d_i = beta_i - mu_i z_i(0),   beta = R^T M^(-1/2) g
    E(mu, t) = (1 - exp(-mu t)) / mu = t phi1(mu t)         (t at mu = 0)

and every quantity is a closed form from the piece's origin: the displacements
``int z_i = z_i(0) t + d_i t^2 phi2(mu_i t)``, the dampers' dissipation
``int q^T C q = sum_i mu_i int z_i^2`` (``z^T diag(mu) z``: no cross terms) with
``int E^2 = t^3 psi(mu t)``. ``phi1``, ``phi2``, ``psi`` are evaluated without cancellation
(series below 1), so that ``mu -> 0`` (no damping) is the uniform motion to round-off.

Events are zeros of affine functions of the velocities (a velocity, a relative velocity, a
static force that reaches its limit; an acceleration is affine in them too):
``h(t) = A + sum_i B_i E(mu_i, t)``, a constant plus at most two exponentials. Its derivative
``sum_i B_i exp(-mu_i t)`` changes sign at most once, at a time in closed form, so ``h`` is
monotone on at most two parts: each is searched for a sign change and bisected to the first
float at which ``h`` has left its sign (:func:`first_zero`), a time that does not depend on
how far the search looked ahead.
"""
from __future__ import annotations

import math

__all__ = ["LinearPiece", "phi1", "phi2", "psi", "first_zero"]

_PHI2 = tuple((-1.0) ** n / math.factorial(n) for n in range(2, 24))
_PSI = tuple((-1.0) ** n * (2.0 - 2.0 ** (n - 1)) / math.factorial(n) for n in range(3, 30))


def _series(coefs, x):
    total = 0.0
    for c in reversed(coefs):
        total = total * x + c
    return total


def phi1(x: float) -> float:
    """(1 - exp(-x)) / x, 1 at x = 0 (x >= 0)."""
    return -math.expm1(-x) / x if x != 0.0 else 1.0


def phi2(x: float) -> float:
    """(x - 1 + exp(-x)) / x^2, 1/2 at x = 0 (x >= 0)."""
    if x < 0.5:
        return _series(_PHI2, x)
    return (x + math.expm1(-x)) / (x * x)


def psi(x: float) -> float:
    """(x - 3/2 + 2 exp(-x) - exp(-2 x)/2) / x^3, 1/3 at x = 0 (x >= 0): int_0^t E^2 / t^3."""
    if x < 1.0:
        return _series(_PSI, x)
    return (x - 1.5 + 2.0 * math.exp(-x) - 0.5 * math.exp(-2.0 * x)) / (x * x * x)


def _e(mu: float, t: float) -> float:
    """E(mu, t) = (1 - exp(-mu t)) / mu [s], never decreasing in t to the last bit (each step
    of ``-expm1(-mu t) / mu`` is; ``t phi1(mu t)`` wanders by an ulp where it is flat)."""
    return -math.expm1(-mu * t) / mu if mu > 0.0 else t


class LinearPiece:
    """The motion ``M q' = g - C q`` from ``q(0) = q0`` (one or two velocities).

    Parameters
    ----------
    m : sequence of float
        The diagonal of M [kg], positive.
    c : sequence of sequence of float
        C [N s/m], symmetric, positive semi-definite.
    g : sequence of float
        The constant forces [N].
    q0 : sequence of float
        The velocities at the start [m/s].
    """

    def __init__(self, m, c, g, q0):
        self.n = n = len(m)
        self.r = [1.0 / math.sqrt(mi) for mi in m]          # M^(-1/2)
        self.m, self.c, self.g = list(m), [list(row) for row in c], list(g)
        if n == 1:
            self.mu = [max(c[0][0] * self.r[0] ** 2, 0.0)]
            self.rot = [[1.0]]
        else:
            s00 = c[0][0] * self.r[0] ** 2
            s11 = c[1][1] * self.r[1] ** 2
            s01 = c[0][1] * self.r[0] * self.r[1]
            theta = 0.5 * math.atan2(2.0 * s01, s00 - s11) if s01 != 0.0 else 0.0
            co, si = math.cos(theta), math.sin(theta)
            self.mu = [max(s00 * co * co + 2.0 * s01 * si * co + s11 * si * si, 0.0),
                       max(s00 * si * si - 2.0 * s01 * si * co + s11 * co * co, 0.0)]
            self.rot = [[co, -si], [si, co]]                 # columns: the eigenvectors
        y0 = [math.sqrt(mi) * qi for mi, qi in zip(m, q0)]
        b = [ri * gi for ri, gi in zip(self.r, g)]
        self.z0 = [sum(self.rot[k][i] * y0[k] for k in range(n)) for i in range(n)]
        beta = [sum(self.rot[k][i] * b[k] for k in range(n)) for i in range(n)]
        self.d = [beta[i] - self.mu[i] * self.z0[i] for i in range(n)]
        self.q0 = list(q0)

    def _back(self, z):
        """Velocities (or displacements) of the modes ``z``: M^(-1/2) R z."""
        return [self.r[k] * sum(self.rot[k][i] * z[i] for i in range(self.n))
                for k in range(self.n)]

    def velocity(self, t: float) -> list:
        """q(t) [m/s]."""
        return self._back([self.z0[i] + self.d[i] * _e(self.mu[i], t) for i in range(self.n)])

    def _settling(self, i: int):
        """The steady value ``z_inf = beta_i / mu_i`` of a mode that settles towards it from
        the same side of 0 (``|z_inf| <= |z0|``, no sign change), else None."""
        mu, z0 = self.mu[i], self.z0[i]
        if mu <= 0.0:
            return None
        z_inf = z0 + self.d[i] / mu
        if abs(z_inf) <= 1e-15 * abs(z0):
            return 0.0                    # a load at the friction limit, to round-off
        return z_inf if z0 * z_inf >= 0.0 and abs(z_inf) <= abs(z0) else None

    def displacement(self, t: float) -> list:
        """int_0^t q [m], from the modes (never a difference of positions).

        A mode that settles (:meth:`_settling`) is ``z_inf t + (z0 - z_inf) E(mu, t)``: two
        terms that grow the same way, so the displacement is monotone to the last bit where
        the velocity has decayed to round-off (``z0 t + d t^2 phi2`` there cancels two large
        terms and wanders, and a friction work would decrease by round-off)."""
        modes = []
        for i in range(self.n):
            z_inf = self._settling(i)
            if z_inf is None:
                modes.append(self.z0[i] * t + self.d[i] * t * t * phi2(self.mu[i] * t))
            else:
                modes.append(z_inf * t + (self.z0[i] - z_inf) * _e(self.mu[i], t))
        return self._back(modes)

    def dissipation(self, t: float) -> float:
        """int_0^t q^T C q [J], >= 0 (a settling mode as a sum of terms that never decrease,
        as in :meth:`displacement`)."""
        total = 0.0
        for i, (mu, z0, d) in enumerate(zip(self.mu, self.z0, self.d)):
            if mu > 0.0:
                z_inf = self._settling(i)
                if z_inf is None:
                    x = mu * t
                    total += mu * t * (z0 * z0 + 2.0 * z0 * d * t * phi2(x)
                                       + d * d * t * t * psi(x))
                else:
                    r = z0 - z_inf
                    total += mu * (z_inf * z_inf * t + 2.0 * z_inf * r * _e(mu, t)
                                   + r * r * _e(2.0 * mu, t))
        return max(total, 0.0)

    def affine(self, h0: float, k) -> tuple:
        """``h(t) = h0 + k . q(t)`` as ``(A, B)``: ``h(t) = A + sum_i B_i E(mu_i, t)``."""
        kappa = [sum(self.rot[j][i] * self.r[j] * k[j] for j in range(self.n))
                 for i in range(self.n)]
        # h(0) from the start's velocities themselves (a contact starting from rest gives an
        # exact 0, which the modes' sum would give only to round-off)
        a = h0 + sum(k[j] * self.q0[j] for j in range(self.n))
        return a, [kappa[i] * self.d[i] for i in range(self.n)]

    def acceleration_affine(self, k) -> tuple:
        """``(c0, kq)`` with ``k . q'(t) = c0 + kq . q(t)``: q' = M^(-1) (g - C q)."""
        w = [k[i] / self.m[i] for i in range(self.n)]
        c0 = sum(w[i] * self.g[i] for i in range(self.n))
        kq = [-sum(w[i] * self.c[i][j] for i in range(self.n)) for j in range(self.n)]
        return c0, kq

    def first_zero(self, a: float, b, horizon: float, limit: bool = False) -> float:
        """:func:`first_zero` of ``A + sum B_i E(mu_i, t)`` in this piece."""
        return first_zero(a, b, self.mu, horizon, limit)


def _h(a, b, mu, t):
    return a + sum(bi * _e(mi, t) for bi, mi in zip(b, mu))


#: the unbounded last part is searched at t = lo + 2^k _FIRST up to _LAST [s]
_FIRST, _LAST = 2.0 ** -40, 2.0 ** 40


def _end_of_part(a, b, mu, lo: float) -> float:
    """A finite end for the part ``[lo, inf)``: ``_LAST`` where ``h`` cannot reach 0 (it grows,
    or falls towards a limit clearly above 0), else the first ``lo + 2^k _FIRST`` at which
    ``h <= 0``. The points do not depend on any horizon, so neither does the zero found."""
    slowest = min(mu) if b else 0.0
    slope = sum(bi for bi, mi in zip(b, mu) if mi == slowest)
    if slope >= 0.0 and _h(a, b, mu, lo) > 0.0:
        return _LAST
    if all(mi > 0.0 for mi in mu):
        limit = a + sum(bi / mi for bi, mi in zip(b, mu))
        if limit > 1e-12 * (abs(a) + sum(abs(bi / mi) for bi, mi in zip(b, mu))):
            return _LAST
    step = _FIRST
    while lo + step < _LAST:
        if _h(a, b, mu, lo + step) <= 0.0:
            return lo + step
        step *= 2.0
    return _LAST


def first_zero(a: float, b, mu, horizon: float, limit: bool = False) -> float:
    """The first time in [0, horizon] [s] at which ``h(t) = a + sum_i b_i E(mu_i, t)`` (positive
    where the piece is consistent) is <= 0, or ``inf``.

    ``h' = sum_i b_i exp(-mu_i t)`` changes sign at most once, at ``t*`` (closed form), so
    ``h`` is monotone on [0, t*] and [t*, horizon]; a part that ends <= 0 while it starts > 0
    is bisected to the first float at which ``h <= 0``. With ``horizon = inf`` the result
    depends on the piece alone (:func:`_end_of_part`): where ``h`` only falls towards 0 (a
    velocity decaying to exactly 0) its sign is round-off, and a search that looked as far as
    the host's next point would find that round-off where another host's would not. A start at ``h(0) <= 0`` with ``h``
    falling is an event at once (a limit reached exactly at the piece's start), and so is a
    constant ``h <= 0`` of a velocity (a body at rest with nothing to move it). A ``limit``
    (``h`` the margin of a static force to its limit) that is constant is no event: the modes
    were just decided with that force held (stuck first, within round-off of the limit), and
    a force that stays where it is does not break loose (a load exactly at a limit does not
    move a body).
    """
    cuts = [0.0]
    if len(b) == 2 and b[0] * b[1] < 0.0 and mu[0] != mu[1]:
        ratio = -b[1] / b[0]
        t_star = math.log(ratio) / (mu[1] - mu[0])
        if 0.0 < t_star < horizon:
            cuts.append(t_star)
    cuts.append(horizon)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        if hi == math.inf:
            hi = _end_of_part(a, b, mu, lo)
        h_lo, h_hi = _h(a, b, mu, lo), _h(a, b, mu, hi)
        if h_lo <= 0.0:
            # the part's direction, from inside it (at its start h' may be 0 to round-off)
            mid = 0.5 * (lo + hi)
            slope = sum(bi * math.exp(-mi * mid) for bi, mi in zip(b, mu))
            if lo == 0.0 and h_lo == 0.0 and len(cuts) > 2 and slope <= 0.0:
                # A contact starting from rest (a breakaway, its h' = 0 at the start) whose
                # first part goes the other way: round-off of the start, not an event (the
                # modes made it slide this way); the next part grows.
                continue
            if slope < 0.0 or (slope == 0.0 and h_hi <= 0.0 and not limit):
                return lo
            continue                      # growing from <= 0: consistent (a start from rest)
        if h_hi > 0.0:
            continue
        for _ in range(2200):             # bisection to adjacent floats
            mid = lo + 0.5 * (hi - lo)
            if not lo < mid < hi:
                break
            if _h(a, b, mu, mid) > 0.0:
                lo = mid
            else:
                hi = mid
        return hi
    return math.inf
