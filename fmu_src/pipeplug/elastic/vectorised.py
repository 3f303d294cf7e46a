"""The time loops of the elastic model as whole-array numpy operations (the path without numba).

The same scheme and the same variants as :mod:`pipeplug.elastic.kernels` (one per combination
of enabled effects, chosen once when a model is built; the same arguments), with each internal
step done for all cells at once: kick all cells, project all of them
(:mod:`pipeplug.contact.vectorised`), drift all faces. Each cell sees the operations of the
compiled loops in the same order, and every sum over cells is taken in the loops' order
(:func:`_total`), so the results are those of the compiled kernels bit for bit. numba is never
imported here.

A variant is a list of parts, each a group of cells with its own contacts (pipe cells alone,
pipe cells on the soil, coupled pipe and plug cells, ...); a part kicks and projects its cells,
keeping their impulses and friction works, and takes back shares of its projection when the
step's friction work would be negative. :func:`_loop` makes the kernel: the struck-end force,
the parts, the works and the drift of the rods, step after step.
"""
from __future__ import annotations

import numpy as np

from ..contact.vectorised import TwoContacts, one_contact, pair_contact
from .cells import accumulate, soil_start
from .kernels import (
    C1,
    C2,
    COMPENSATION,
    DX,
    F_IN,
    F_OUT,
    K1,
    K2,
    LIMITED,
    M1,
    M2,
    N_MAX,
    N_MIN,
    RAM_MASS,
    W_IN,
    W_INNER,
    W_OUTER,
    finish_ram,
    start_step,
)

__all__ = ["VECTORISED"]


class _Cells:
    """Cells ``lo..hi-1`` of a rod: their velocities (a view) and the faces around them."""

    def __init__(self, v, N, lo, hi, a):
        self.v, self.a = v[lo:hi], a                # a = dt/m [s/kg]
        self._ahead, self._behind = N[lo + 1:hi + 1], N[lo:hi]

    def kick(self):
        """Kick the velocities in place (no friction)."""
        self.v += self.a * (self._ahead - self._behind)

    def trial(self):
        """The kicked velocities, as a new array (the cells' own stay unchanged) [m/s]."""
        return self.v + self.a * (self._ahead - self._behind)


class _Rod:
    """One rod's drift: inner-face forces from the new velocities, tracked displacements."""

    def __init__(self, v, N, cells, u, b, dt):
        self._ahead, self._behind, self._inner = v[1:], v[:-1], N[1:-1]
        self._v, self._cells, self._u = v, cells, u
        self._b, self._dt = b, dt                   # b = E S dt/dx [N s/m]

    def drift(self):
        """Drift the inner-face forces and the tracked displacements by one step."""
        self._inner += self._b * (self._ahead - self._behind)
        self._u += self._dt * self._v[self._cells]


def _total(x):
    """Sum of ``x`` in index order, as a loop from 0.0 adds it (bit for bit).

    ``cumsum`` adds in index order (``sum`` pairs terms up); it starts from ``x[0]`` rather
    than 0.0, which changes nothing but the sign of a zero total: ``+ 0.0`` restores it.
    """
    return x.cumsum()[-1] + 0.0 if x.size else 0.0


def _share(f, r, w, x):
    """:func:`pipeplug.elastic.cells.share` cell by cell (the same operations)."""
    a = -f * (r + w)
    b = -f * (x - w)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = a / -b
    return np.where(a + b >= 0.0, 1.0, np.where(a <= 0.0, 0.0, ratio))


def _window(f, r, w, x):
    """:func:`pipeplug.elastic.cells.window` cell by cell (the same operations)."""
    a = -f * (r + w)
    b = -f * (x - w)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = a / -b
    grows = b >= 0.0
    whole = np.where(grows, a >= 0.0, a + b >= 0.0)
    lo = np.where(whole, 0.0, np.where(grows, np.where(a + b >= 0.0, ratio, 1.0),
                                       np.where(a > 0.0, 0.0, 1.0)))
    hi = np.where(whole, 1.0, np.where(grows, np.where(a + b >= 0.0, 1.0, 0.0),
                                       np.where(a > 0.0, ratio, 0.0)))
    return lo, hi


def _joint_share(f1, r1, w1, x1, f2, r2, w2, x2):
    """:func:`pipeplug.elastic.cells.joint_share` cell by cell."""
    lo1, hi1 = _window(f1, r1, w1, x1)
    lo2, hi2 = _window(f2, r2, w2, x2)
    hi = np.minimum(hi1, hi2)
    return np.where(np.maximum(lo1, lo2) <= hi, hi, 0.0)


def _applied(lam, w, x):
    """``cells._applied`` cell by cell: ``x`` where the whole impulse is applied."""
    return np.where(lam == 1.0, x, w + lam * (x - w))


class _Part:
    """A group of cells with the same contacts. :meth:`project` kicks and projects them and
    keeps what :meth:`limit` needs; ``f1``/``d1`` and ``f2``/``d2`` are the impulses [N s] and
    works [J] at the soil and the plug contact (None where the part has no such contact)."""

    f1 = d1 = f2 = d2 = None

    def project(self):
        """Kick and project the cells (the whole projection)."""

    def limit(self):
        """Take back the share of the projection of the cells whose work is negative
        (:func:`pipeplug.elastic.cells.limit`)."""


class _Free(_Part):
    """Cells touching nothing."""

    def __init__(self, cells):
        self.project = cells.kick


class _Soil(_Part):
    """Cells touching the soil alone, with impulse limits ``limit`` [N s] (an array is read at
    each step)."""

    def __init__(self, cells, m, limits):
        self.cells, self.m, self.limits = cells, m, limits

    def project(self):
        v = self.cells.v
        self.r, self.w = v.copy(), self.cells.trial()
        x, self.f1 = one_contact(self.m, self.w, self.limits, 0.0)
        self.d1 = -0.5 * self.f1 * (self.r + x)
        v[...] = x

    def limit(self):
        v, negative = self.cells.v, self.d1 < 0.0
        lam = np.where(negative, _share(self.f1, self.r, self.w, v), 1.0)
        v[...] = np.where(negative, _applied(lam, self.w, v), v)
        self.f1 = np.where(negative, lam * self.f1, self.f1)
        self.d1 = np.where(negative, -0.5 * self.f1 * (self.r + v), self.d1)


class _Coupled(_Part):
    """Coupled pipe and plug cells; on the soil with limits ``c1`` as in :class:`_Soil`, or
    without it (``c1`` None)."""

    def __init__(self, pipe, plug, m1, m2, c1, c2):
        self.pipe, self.plug, self.m1, self.m2, self.c1, self.c2 = pipe, plug, m1, m2, c1, c2
        self.solve = None if c1 is None else TwoContacts(m1, m2, c2, 0.0, plug.v.size)

    def project(self):
        p, q = self.pipe.v, self.plug.v
        self.r1, self.r2 = p.copy(), q.copy()
        w1, w2 = self.w1, self.w2 = self.pipe.trial(), self.plug.trial()
        if self.solve is None:
            x1, x2, f2 = pair_contact(self.m1, self.m2, w1, w2, self.c2)
        else:
            x1, x2, f1, f2 = self.solve(w1, w2, self.c1)
            if np.ndim(self.c1):
                # Cells outside the soil's contact (limit 0) are the pair problem, as in the
                # loops.
                free = self.c1 == 0.0
                if free.any():
                    x1, x2, f1, f2 = x1.copy(), x2.copy(), f1.copy(), f2.copy()
                    x1[free], x2[free], f2[free] = pair_contact(self.m1, self.m2, w1[free],
                                                                w2[free], self.c2)
                    f1[free] = 0.0
            self.f1, self.d1 = f1, -0.5 * f1 * (self.r1 + x1)
        self.f2, self.d2 = f2, -0.5 * f2 * (self.r1 - self.r2 + x1 - x2)
        p[...] = x1
        q[...] = x2

    def limit(self):
        p, q = self.pipe.v, self.plug.v
        negative = self.d2 < 0.0
        relative = (self.f2, self.r1 - self.r2, self.w1 - self.w2, p - q)
        if self.d1 is None:
            lam = _share(*relative)
        else:
            negative |= self.d1 < 0.0
            lam = _joint_share(self.f1, self.r1, self.w1, p, *relative)
        lam = np.where(negative, lam, 1.0)
        p[...] = np.where(negative, _applied(lam, self.w1, p), p)
        q[...] = np.where(negative, _applied(lam, self.w2, q), q)
        self.f2 = np.where(negative, lam * self.f2, self.f2)
        self.d2 = np.where(negative, -0.5 * self.f2 * (self.r1 - self.r2 + p - q), self.d2)
        if self.d1 is not None:
            self.f1 = np.where(negative, lam * self.f1, self.f1)
            self.d1 = np.where(negative, -0.5 * self.f1 * (self.r1 + p), self.d1)


class _Growth(_Part):
    """No cells: sets the soil limits [N s] of the pipe's cells to the penetrated share of
    each cell (contact growth) times the full-cell limit ``c1``; ``u1[0]`` is the displacement
    of the pipe's front cell [m]."""

    def __init__(self, u1, limits, c1, dx):
        self.u1, self.limits, self.c1, self.dx = u1, limits, c1, dx
        self.ends = np.arange(1.0, limits.size + 1.0)   # cell ends, in cells from the struck end

    def project(self):
        start = soil_start(self.u1[0], self.limits.size, self.dx)
        np.multiply(self.c1, np.minimum(np.maximum(self.ends - start, 0.0), 1.0),
                    out=self.limits)


def _loop(variant):
    """The kernel of ``variant``.

    ``variant(v1, N1, v2, N2, u1, coef, dt)`` returns the parts (:class:`_Part`) of one step,
    in order, and whether the rods have soil friction and a plug.
    """
    def kernel(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
        start_step(q, N1, coef, acc)
        rods = [_Rod(v1, N1, cells1, u1, coef[K1] * dt, dt)]
        if v2.size:
            rods.append(_Rod(v2, N2, cells2, u2, coef[K2] * dt, dt))
        parts, friction = variant(v1, N1, v2, N2, u1, coef, dt)
        half_impulse = 0.5 * q * dt
        ram = coef[RAM_MASS] > 0.0
        for _ in range(n):
            v_first = v1[0]
            for part in parts:
                part.project()
            if friction:
                _friction_works(parts, acc)
            accumulate(acc, W_IN, W_IN + COMPENSATION, half_impulse * (v_first + v1[0]))
            for rod in rods:
                rod.drift()
            if ram:
                finish_ram(q, dt, v_first, v1[0], N1, coef, acc)
            # the node-centred forces (cells.node_forces) of the head and of every cell (the
            # loops take those that changed: the extremes are the same)
            means = 0.5 * (N1[:-1] + N1[1:])
            acc[N_MIN] = min(acc[N_MIN], N1[0], means.min())
            acc[N_MAX] = max(acc[N_MAX], N1[0], means.max())
        if friction:
            acc[F_OUT] = _sum_of_totals(part.f1 for part in parts) / dt
            acc[F_IN] = _sum_of_totals(part.f2 for part in parts) / dt
        else:
            acc[F_OUT] = acc[F_IN] = 0.0
    kernel.__name__ = kernel.__qualname__ = variant.__name__
    kernel.__doc__ = variant.__doc__
    return kernel


def _friction_works(parts, acc):
    """Book a step's friction works [J] at the soil and the plug, as the loops do: summed over
    the cells; if one is negative, the parts take back their shares and they are summed again."""
    outer, inner = _works(parts)
    if outer < 0.0 or inner < 0.0:
        for part in parts:
            part.limit()
        outer, inner = _works(parts)
        acc[LIMITED] += 1.0
    accumulate(acc, W_OUTER, W_OUTER + COMPENSATION, max(outer, 0.0))
    accumulate(acc, W_INNER, W_INNER + COMPENSATION, max(inner, 0.0))


def _works(parts):
    """The step's friction works at the soil and at the plug [J]: each part's sum over its
    cells in order, the parts' in order (the loops' sums)."""
    outer = [_total(part.d1) for part in parts if part.d1 is not None]
    inner = [_total(part.d2) for part in parts if part.d2 is not None]
    return (outer[0] + outer[1] if len(outer) == 2 else (outer[0] if outer else 0.0),
            inner[0] if inner else 0.0)


def _sum_of_totals(arrays):
    """The loops' sum of the parts' impulses: each part's in order, then the parts'."""
    totals = [_total(array) for array in arrays if array is not None]
    return totals[0] + totals[1] if len(totals) == 2 else (totals[0] if totals else 0.0)


def _pipe_cells(v1, N1, lo, hi, coef, dt):
    return _Cells(v1, N1, lo, hi, dt / coef[M1])


def _plug_cells(v1, N1, v2, N2, coef, dt):
    """The pipe's coupled cells and the plug's."""
    j0 = v1.size - v2.size
    return _pipe_cells(v1, N1, j0, v1.size, coef, dt), _Cells(v2, N2, 0, v2.size, dt / coef[M2])


@_loop
def run_pipe(v1, N1, v2, N2, u1, coef, dt):
    """Pipe alone, no friction."""
    return [_Free(_pipe_cells(v1, N1, 0, v1.size, coef, dt))], False


@_loop
def run_pipe_soil(v1, N1, v2, N2, u1, coef, dt):
    """Pipe on the soil over its whole length."""
    cells = _pipe_cells(v1, N1, 0, v1.size, coef, dt)
    return [_Soil(cells, coef[M1], dt * coef[C1])], True


@_loop
def run_pipe_soil_growth(v1, N1, v2, N2, u1, coef, dt):
    """Pipe on the soil over the penetrated length."""
    limits = np.empty(v1.size)
    cells = _pipe_cells(v1, N1, 0, v1.size, coef, dt)
    return [_Growth(u1, limits, dt * coef[C1], coef[DX]), _Soil(cells, coef[M1], limits)], True


@_loop
def run_pipe_plug(v1, N1, v2, N2, u1, coef, dt):
    """Pipe and plug, no soil friction."""
    j0 = v1.size - v2.size
    coupled = _Coupled(*_plug_cells(v1, N1, v2, N2, coef, dt), coef[M1], coef[M2], None,
                       dt * coef[C2])
    return ([_Free(_pipe_cells(v1, N1, 0, j0, coef, dt))] if j0 else []) + [coupled], True


@_loop
def run_pipe_plug_soil(v1, N1, v2, N2, u1, coef, dt):
    """Pipe, plug and soil over the whole pipe length."""
    return _soil_and_plug(v1, N1, v2, N2, coef, dt, dt * coef[C1]), True


@_loop
def run_pipe_plug_soil_growth(v1, N1, v2, N2, u1, coef, dt):
    """Pipe, plug and soil over the penetrated length."""
    limits = np.empty(v1.size)
    return ([_Growth(u1, limits, dt * coef[C1], coef[DX])]
            + _soil_and_plug(v1, N1, v2, N2, coef, dt, limits)), True


def _soil_and_plug(v1, N1, v2, N2, coef, dt, limits):
    """Parts of pipe cells on the soil alone (if any) and of the coupled cells; ``limits`` [N s]
    a float or an array over the pipe's cells."""
    j0 = v1.size - v2.size
    m1, m2, c2 = coef[M1], coef[M2], dt * coef[C2]
    outer, coupled = (limits[:j0], limits[j0:]) if np.ndim(limits) else (limits, limits)
    parts = [_Coupled(*_plug_cells(v1, N1, v2, N2, coef, dt), m1, m2, coupled, c2)]
    if j0:
        parts.insert(0, _Soil(_pipe_cells(v1, N1, 0, j0, coef, dt), m1, outer))
    return parts


#: (plug, soil, growth) -> kernel, as :data:`pipeplug.elastic.kernels.KERNELS`
VECTORISED = {
    (False, False, False): run_pipe,
    (False, False, True): run_pipe,
    (False, True, False): run_pipe_soil,
    (False, True, True): run_pipe_soil_growth,
    (True, False, False): run_pipe_plug,
    (True, False, True): run_pipe_plug,
    (True, True, False): run_pipe_plug_soil,
    (True, True, True): run_pipe_plug_soil_growth,
}
