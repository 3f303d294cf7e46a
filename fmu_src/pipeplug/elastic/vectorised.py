"""The time loops of the elastic model as whole-array numpy operations (the path without numba).

The same scheme and the same variants as :mod:`pipeplug.elastic.kernels` (one per combination
of enabled effects, chosen once when a model is built; the same arguments), with each internal
step done for all cells at once: kick all cells, project all of them
(:mod:`pipeplug.contact.vectorised`), drift all faces. Each cell sees the operations of the
compiled loops in the same order, and every sum over cells is taken in the loops' order
(:func:`_total`), so the results are those of the compiled kernels bit for bit. numba is never
imported here.

A variant is a list of parts, each a group of cells with its own contacts (pipe cells alone,
pipe cells on the soil, coupled pipe and plug cells, ...); a part kicks and projects its cells
and returns the impulses of the soil and of the plug on them. :func:`_loop` makes the kernel:
the struck-end force, the parts, the input work and the drift of the rods, step after step.
"""
from __future__ import annotations

import numpy as np

from ..contact.vectorised import TwoContacts, one_contact, pair_contact
from .cells import soil_start
from .kernels import C1, C2, DX, F_IN, F_OUT, K1, K2, M1, M2, W_IN, W_INNER, W_NEG, W_OUTER

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


def _book(acc, contact, works):
    """Add friction works ``works`` [J] to ``acc``: the dissipated ones at ``contact``
    (W_OUTER or W_INNER), the negative ones of reversing steps at W_NEG."""
    acc[contact] += _total(np.maximum(works, 0.0))
    acc[W_NEG] += _total(np.minimum(works, 0.0))


def _free_part(cells):
    """Cells touching nothing."""
    def part():
        cells.kick()
        return None, None
    return part


def _soil_part(cells, m, limit, acc):
    """Cells touching the soil alone, with impulse limits ``limit`` [N s] (an array is read at
    each step)."""
    def part():
        v = cells.v
        x, f = one_contact(m, cells.trial(), limit, 0.0)
        _book(acc, W_OUTER, -0.5 * f * (v + x))
        v[...] = x
        return f, None
    return part


def _plug_part(pipe, plug, m1, m2, c2, acc):
    """Coupled pipe and plug cells, no soil."""
    def part():
        p, q = pipe.v, plug.v
        x1, x2, f2 = pair_contact(m1, m2, pipe.trial(), plug.trial(), c2)
        _book(acc, W_INNER, -0.5 * f2 * (p - q + x1 - x2))
        p[...] = x1
        q[...] = x2
        return None, f2
    return part


def _plug_soil_part(pipe, plug, m1, m2, c1, c2, acc):
    """Coupled pipe and plug cells with the pipe on the soil (limits ``c1`` as in
    :func:`_soil_part`)."""
    solve = TwoContacts(m1, m2, c2, 0.0, plug.v.size)
    # The loops add both contacts' reversing works node by node: keep them interleaved.
    works = np.empty(2 * plug.v.size)
    outer_works, inner_works = works[0::2], works[1::2]

    def part():
        p, q = pipe.v, plug.v
        w1, w2 = pipe.trial(), plug.trial()
        x1, x2, f1, f2 = solve(w1, w2, c1)
        if np.ndim(c1):
            # Cells outside the soil's contact (limit 0) are the pair problem, as in the loops.
            free = c1 == 0.0
            if free.any():
                x1, x2, f1, f2 = x1.copy(), x2.copy(), f1.copy(), f2.copy()
                x1[free], x2[free], f2[free] = pair_contact(m1, m2, w1[free], w2[free], c2)
                f1[free] = 0.0
        np.multiply(-0.5 * f1, p + x1, out=outer_works)
        np.multiply(-0.5 * f2, p - q + x1 - x2, out=inner_works)
        p[...] = x1
        q[...] = x2
        acc[W_OUTER] += _total(np.maximum(outer_works, 0.0))
        acc[W_INNER] += _total(np.maximum(inner_works, 0.0))
        acc[W_NEG] += _total(np.minimum(works, 0.0))
        return f1, f2
    return part


def _growth_part(u1, limits, c1, dx):
    """No cells: sets the soil limits [N s] of the pipe's cells to the penetrated share of
    each cell (contact growth) times the full-cell limit ``c1``; ``u1[0]`` is the displacement
    of the pipe's front cell [m]."""
    ends = np.arange(1.0, limits.size + 1.0)        # cell ends, in cells from the struck end

    def part():
        start = soil_start(u1[0], limits.size, dx)
        np.multiply(c1, np.minimum(np.maximum(ends - start, 0.0), 1.0), out=limits)
        return None, None
    return part


def _loop(variant):
    """The kernel of ``variant``.

    ``variant(v1, N1, v2, N2, u1, coef, dt, acc)`` returns the parts of one step, in order; a
    part is a function of no arguments returning the impulses of the soil and of the plug on
    its cells [N s] (arrays, or None).
    """
    def kernel(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
        N1[0] = -q
        rods = [_Rod(v1, N1, cells1, u1, coef[K1] * dt, dt)]
        if v2.size:
            rods.append(_Rod(v2, N2, cells2, u2, coef[K2] * dt, dt))
        drifts = [rod.drift for rod in rods]
        parts = variant(v1, N1, v2, N2, u1, coef, dt, acc)
        half_impulse = 0.5 * q * dt
        w_in = acc[W_IN]
        impulses = []
        for _ in range(n):
            v_first = v1[0]
            impulses = [part() for part in parts]
            w_in += half_impulse * (v_first + v1[0])
            for drift in drifts:
                drift()
        acc[W_IN] = w_in
        acc[F_OUT] = _sum_of_totals(outer for outer, _ in impulses) / dt
        acc[F_IN] = _sum_of_totals(inner for _, inner in impulses) / dt
    kernel.__name__ = kernel.__qualname__ = variant.__name__
    kernel.__doc__ = variant.__doc__
    return kernel


def _sum_of_totals(arrays):
    """The loops' sum of the parts' impulses: each part's in order, then the parts'."""
    total = 0.0
    for array in arrays:
        if array is not None:
            total += _total(array)
    return total


def _pipe_cells(v1, N1, lo, hi, coef, dt):
    return _Cells(v1, N1, lo, hi, dt / coef[M1])


def _plug_cells(v1, N1, v2, N2, coef, dt):
    """The pipe's coupled cells and the plug's."""
    j0 = v1.size - v2.size
    return _pipe_cells(v1, N1, j0, v1.size, coef, dt), _Cells(v2, N2, 0, v2.size, dt / coef[M2])


@_loop
def run_pipe(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe alone, no friction."""
    return [_free_part(_pipe_cells(v1, N1, 0, v1.size, coef, dt))]


@_loop
def run_pipe_soil(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe on the soil over its whole length."""
    cells = _pipe_cells(v1, N1, 0, v1.size, coef, dt)
    return [_soil_part(cells, coef[M1], dt * coef[C1], acc)]


@_loop
def run_pipe_soil_growth(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe on the soil over the penetrated length."""
    limits = np.empty(v1.size)
    cells = _pipe_cells(v1, N1, 0, v1.size, coef, dt)
    return [_growth_part(u1, limits, dt * coef[C1], coef[DX]),
            _soil_part(cells, coef[M1], limits, acc)]


@_loop
def run_pipe_plug(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe and plug, no soil friction."""
    j0 = v1.size - v2.size
    coupled = _plug_part(*_plug_cells(v1, N1, v2, N2, coef, dt), coef[M1], coef[M2],
                         dt * coef[C2], acc)
    return ([_free_part(_pipe_cells(v1, N1, 0, j0, coef, dt))] if j0 else []) + [coupled]


@_loop
def run_pipe_plug_soil(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe, plug and soil over the whole pipe length."""
    return _soil_and_plug(v1, N1, v2, N2, coef, dt, acc, dt * coef[C1])


@_loop
def run_pipe_plug_soil_growth(v1, N1, v2, N2, u1, coef, dt, acc):
    """Pipe, plug and soil over the penetrated length."""
    limits = np.empty(v1.size)
    return ([_growth_part(u1, limits, dt * coef[C1], coef[DX])]
            + _soil_and_plug(v1, N1, v2, N2, coef, dt, acc, limits))


def _soil_and_plug(v1, N1, v2, N2, coef, dt, acc, limits):
    """Parts of pipe cells on the soil alone (if any) and of the coupled cells; ``limits`` [N s]
    a float or an array over the pipe's cells."""
    j0 = v1.size - v2.size
    m1, m2, c2 = coef[M1], coef[M2], dt * coef[C2]
    outer, coupled = (limits[:j0], limits[j0:]) if np.ndim(limits) else (limits, limits)
    parts = [_plug_soil_part(*_plug_cells(v1, N1, v2, N2, coef, dt), m1, m2, coupled, c2, acc)]
    if j0:
        cells = _pipe_cells(v1, N1, 0, j0, coef, dt)
        parts.insert(0, _soil_part(cells, m1, outer, acc))
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
