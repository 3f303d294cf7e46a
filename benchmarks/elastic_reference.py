"""Independent codings of the elastic scheme, for the benchmarks only (never imported by the core).

Used by :mod:`benchmarks.elastic` to time the package's kernels against

(a) the same scheme as numpy operations on whole arrays, one time step at a time:
    :func:`run_numpy` for pipe and plug (the Fig. 7 scene), :func:`run_numpy_full` for pipe,
    plug and soil friction over the penetrated length (every effect on);
(b) a C loop for pipe and plug, compiled at run time with the system compiler (``cc -O3``) and
    called through ctypes.

All follow the scheme of :mod:`pipeplug.elastic.cells` step by step: kick, Coulomb projection of
each cell, friction works (a step whose summed work at a contact would be negative takes back the
share of each cell whose own work is negative), drift of the inner-face forces, tracked
displacements, works (plain sums: the core's compensated sums differ by their rounding error). The joint projection of
pipe, plug and soil in :func:`run_numpy_full` is solved here in closed form (the plug's friction
as a function of the pipe's velocity, then the pipe's), not with the core's pattern table, so the
two agree to round-off, not bit for bit.

Arrays and constants are those of :class:`pipeplug.elastic.model.ElasticModel` (``v1, N1, v2,
N2, u1, u2, acc`` and ``grid.coef``, ``grid.cells1``, ``grid.cells2``), changed in place.
"""
from __future__ import annotations

import ctypes
import subprocess
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["run_numpy", "run_numpy_full", "build_c", "run_c", "C_SOURCE"]

_SLACK = 1e-13
# coefficient and accumulator indices of pipeplug.elastic.kernels (M1, K1, M2, K2, C1, C2, DX;
# W_IN, W_OUTER, W_INNER, F_OUT, F_IN, 3 rounding errors, LIMITED), repeated here: the core is not
# imported
_M1, _K1, _M2, _K2, _C1, _C2, _DX = range(7)
_W_IN, _W_OUTER, _W_INNER, _F_OUT, _F_IN = range(5)
_LIMITED = 8


def _share(f, r, w, x):
    """The share of a projected impulse ``f`` whose friction work is not negative (relative
    velocities before the step ``r``, after the kick ``w``, after the projection ``x``)."""
    a, b = -f * (r + w), -f * (x - w)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a + b >= 0.0, 1.0, np.where(a <= 0.0, 0.0, a / -b))


def run_numpy(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """The pipe-and-plug scheme with numpy operations on whole arrays, one time step at a time."""
    m1, m2 = coef[_M1], coef[_M2]
    a1, a2, c2 = dt / m1, dt / m2, dt * coef[_C2]
    b1, b2 = coef[_K1] * dt, coef[_K2] * dt
    j0 = v1.size - v2.size
    N1[0] = -q
    impulse = 0.0
    for _ in range(n):
        v_first = v1[0]
        p_old, q_old = v1[j0:].copy(), v2.copy()
        v1 += a1 * np.diff(N1)
        w1, w2 = v1[j0:].copy(), v2 + a2 * np.diff(N2)
        x = (m1 * w1 + m2 * w2) / (m1 + m2)
        f_stuck = -m2 * (x - w2)
        stuck = np.abs(f_stuck) - c2 <= _SLACK * (np.abs(m1 * w1) + np.abs(m2 * w2) + c2)
        f2 = np.where(stuck, np.clip(f_stuck, -c2, c2), np.where(w1 > w2, -c2, c2))
        x1, x2 = np.where(stuck, x, w1 + f2 / m1), np.where(stuck, x, w2 - f2 / m2)
        d = -0.5 * f2 * (p_old - q_old + x1 - x2)
        if d.sum() < 0.0:
            lam = np.where(d < 0.0, _share(f2, p_old - q_old, w1 - w2, x1 - x2), 1.0)
            x1, x2, f2 = w1 + lam * (x1 - w1), w2 + lam * (x2 - w2), lam * f2
            d = -0.5 * f2 * (p_old - q_old + x1 - x2)
            acc[_LIMITED] += 1.0
        v1[j0:], v2[:] = x1, x2
        acc[_W_INNER] += max(d.sum(), 0.0)
        impulse = f2.sum()
        acc[_W_IN] += 0.5 * q * dt * (v_first + v1[0])
        N1[1:-1] += b1 * np.diff(v1)
        N2[1:-1] += b2 * np.diff(v2)
        u1 += dt * v1[cells1]
        u2 += dt * v2[cells2]
    acc[_F_OUT] = 0.0
    acc[_F_IN] = impulse / dt


def run_numpy_full(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe, plug and soil friction over the penetrated length (contact growth), with numpy
    operations on whole arrays, one time step at a time."""
    m1, m2 = coef[_M1], coef[_M2]
    a1, a2, c1, c2 = dt / m1, dt / m2, dt * coef[_C1], dt * coef[_C2]
    b1, b2 = coef[_K1] * dt, coef[_K2] * dt
    n1, j0 = v1.size, v1.size - v2.size
    cell_ends = np.arange(1.0, n1 + 1.0)    # in cells from the struck end
    N1[0] = -q
    outer = inner = 0.0
    for _ in range(n):
        v_first = v1[0]
        # the soil touches reference x >= L1 - min(max(u_front, 0), L1): a share of each cell
        front = n1 - np.clip(u1[0] / coef[_DX], 0.0, n1)
        limit = c1 * np.clip(cell_ends - front, 0.0, 1.0)
        p_old, q_old = v1.copy(), v2.copy()
        w1, w2 = v1 + a1 * np.diff(N1), v2 + a2 * np.diff(N2)
        # pipe cells outside the plug: the soil contact alone
        mw, lim = m1 * w1[:j0], limit[:j0]
        f_soil = np.clip(-mw, -lim, lim)
        v1[:j0] = np.where(np.abs(mw) <= lim, 0.0, w1[:j0] + f_soil / m1)
        # cells with the plug: both contacts
        x1, x2, f1, f2 = _pipe_plug_soil(m1, m2, w1[j0:], w2, limit[j0:], c2)
        v1[j0:], v2[:] = x1, x2
        d_outer = -0.5 * np.concatenate((f_soil, f1)) * (p_old + v1)
        d_inner = -0.5 * f2 * (p_old[j0:] - q_old + x1 - x2)
        if d_outer.sum() < 0.0 or d_inner.sum() < 0.0:
            f_soil, f1, f2 = _limit(v1, v2, j0, p_old, q_old, w1, w2, f_soil, f1, f2,
                                    d_outer, d_inner)
            x1, x2 = v1[j0:], v2
            d_outer = -0.5 * np.concatenate((f_soil, f1)) * (p_old + v1)
            d_inner = -0.5 * f2 * (p_old[j0:] - q_old + x1 - x2)
            acc[_LIMITED] += 1.0
        acc[_W_OUTER] += max(d_outer.sum(), 0.0)
        acc[_W_INNER] += max(d_inner.sum(), 0.0)
        outer, inner = f_soil.sum() + f1.sum(), f2.sum()
        acc[_W_IN] += 0.5 * q * dt * (v_first + v1[0])
        N1[1:-1] += b1 * np.diff(v1)
        N2[1:-1] += b2 * np.diff(v2)
        u1 += dt * v1[cells1]
        u2 += dt * v2[cells2]
    acc[_F_OUT] = outer / dt
    acc[_F_IN] = inner / dt


def _limit(v1, v2, j0, p_old, q_old, w1, w2, f_soil, f1, f2, d_outer, d_inner):
    """Take back the share of the projection of every cell whose work at either contact is
    negative (in place on ``v1``, ``v2``); returns the impulses."""
    alone = d_outer[:j0] < 0.0
    lam = np.where(alone, _share(f_soil, p_old[:j0], w1[:j0], v1[:j0]), 1.0)
    v1[:j0] = np.where(alone, w1[:j0] + lam * (v1[:j0] - w1[:j0]), v1[:j0])
    f_soil = lam * f_soil
    both = (d_outer[j0:] < 0.0) | (d_inner < 0.0)
    p, x1, x2 = p_old[j0:], v1[j0:], v2
    lam = np.minimum(_share(f1, p, w1[j0:], x1), _share(f2, p - q_old, w1[j0:] - w2, x1 - x2))
    lam = np.where(both, lam, 1.0)
    v1[j0:], v2[:] = w1[j0:] + lam * (x1 - w1[j0:]), w2 + lam * (x2 - w2)
    return f_soil, lam * f1, lam * f2


def _pipe_plug_soil(m1, m2, w1, w2, c1, c2):
    """Pipe cells on the soil (impulse limits ``c1``) coupled to plug cells (limit ``c2``).

    For a pipe velocity ``x`` the plug either moves with the pipe or slides at its limit, so
    the plug's friction on the pipe is ``F(x) = clip(m2 (w2 - x), -c2, c2)``, decreasing in x.
    The pipe stays at rest when the reaction ``-m1 w1 - F(0)`` is within ``c1``; otherwise it
    moves against ``f1 = -+c1`` and ``m1 (x - w1) = f1 + F(x)`` has one root: the plug moving
    with it if that root keeps ``|F| <= c2``, else sliding. Returns ``x1, x2, f1, f2``.
    """
    mw1, mw2 = m1 * w1, m2 * w2
    reaction = -mw1 - np.clip(mw2, -c2, c2)
    at_rest = np.abs(reaction) <= c1
    f1 = np.clip(reaction, -c1, c1)
    x = (mw1 + mw2 + f1) / (m1 + m2)
    f_with = m2 * (w2 - x)
    with_pipe = np.where(at_rest, np.abs(mw2) <= c2, np.abs(f_with) <= c2)
    f2 = np.clip(np.where(at_rest, mw2, f_with), -c2, c2)
    x1 = np.where(at_rest, 0.0, np.where(with_pipe, x, w1 + (f1 + f2) / m1))
    x2 = np.where(with_pipe, x1, w2 - f2 / m2)
    return x1, x2, f1, f2


C_SOURCE = r"""
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#define SLACK 1e-13

static void pair(double m1, double m2, double w1, double w2, double c2,
                 double *x1, double *x2, double *f2) {
    double x = (m1 * w1 + m2 * w2) / (m1 + m2);
    double f = -m2 * (x - w2);
    if (fabs(f) - c2 <= SLACK * (fabs(m1 * w1) + fabs(m2 * w2) + c2)) {
        *x1 = x; *x2 = x; *f2 = f > c2 ? c2 : (f < -c2 ? -c2 : f);
        return;
    }
    f = w1 > w2 ? -c2 : c2;
    *x1 = w1 + f / m1; *x2 = w2 - f / m2; *f2 = f;
}

static double share(double f, double r, double w, double x) {
    double a = -f * (r + w), b = -f * (x - w);
    return a + b >= 0.0 ? 1.0 : (a <= 0.0 ? 0.0 : a / -b);
}

void run_pipe_plug(int64_t n, double dt, double q, const double *coef, double *v1, double *N1,
                   int64_t n1, double *v2, double *N2, int64_t n2, const int64_t *cells1, double *u1,
                   int64_t t1, const int64_t *cells2, double *u2, int64_t t2, double *acc) {
    double m1 = coef[0], m2 = coef[2], a1 = dt / m1, a2 = dt / m2, c2 = dt * coef[5];
    double b1 = coef[1] * dt, b2 = coef[3] * dt, inner = 0.0;
    int64_t j0 = n1 - n2;
    double *r = malloc(4 * (n2 > 0 ? n2 : 1) * sizeof(double)), *w = r + n2, *f = w + n2,
           *d = f + n2;
    N1[0] = -q;
    for (int64_t s = 0; s < n; ++s) {
        double v_first = v1[0], work = 0.0;
        for (int64_t j = 0; j < j0; ++j) v1[j] += a1 * (N1[j + 1] - N1[j]);
        for (int64_t k = 0; k < n2; ++k) {
            int64_t j = j0 + k;
            double p_old = v1[j], q_old = v2[k], x1, x2, f2;
            double w1 = p_old + a1 * (N1[j + 1] - N1[j]), w2 = q_old + a2 * (N2[k + 1] - N2[k]);
            pair(m1, m2, w1, w2, c2, &x1, &x2, &f2);
            v1[j] = x1; v2[k] = x2;
            r[k] = p_old - q_old; w[k] = w1 - w2; f[k] = f2;
            d[k] = -0.5 * f2 * (r[k] + x1 - x2);
            work += d[k];
        }
        if (work < 0.0) {               /* take back the shares of the negative cells */
            work = 0.0;
            for (int64_t k = 0; k < n2; ++k) {
                int64_t j = j0 + k;
                if (d[k] < 0.0) {
                    double lam = share(f[k], r[k], w[k], v1[j] - v2[k]);
                    double w1 = v1[j] - f[k] / m1, w2 = v2[k] + f[k] / m2;
                    v1[j] = w1 + lam * (v1[j] - w1); v2[k] = w2 + lam * (v2[k] - w2);
                    f[k] *= lam; d[k] = -0.5 * f[k] * (r[k] + v1[j] - v2[k]);
                }
                work += d[k];
            }
            acc[8] += 1.0;
        }
        inner = 0.0;
        for (int64_t k = 0; k < n2; ++k) inner += f[k];
        acc[2] += work > 0.0 ? work : 0.0;
        acc[0] += 0.5 * q * dt * (v_first + v1[0]);
        for (int64_t g = 1; g < n1; ++g) N1[g] += b1 * (v1[g] - v1[g - 1]);
        for (int64_t g = 1; g < n2; ++g) N2[g] += b2 * (v2[g] - v2[g - 1]);
        for (int64_t i = 0; i < t1; ++i) u1[i] += dt * v1[cells1[i]];
        for (int64_t i = 0; i < t2; ++i) u2[i] += dt * v2[cells2[i]];
    }
    free(r);
    acc[3] = 0.0; acc[4] = inner / dt;
}
"""


def build_c(folder: str | None = None, compiler: str = "cc"):
    """Compile :data:`C_SOURCE` with ``compiler -O3`` into ``folder`` (a new temporary folder
    by default) and return the loaded ctypes function."""
    folder = Path(folder or tempfile.mkdtemp(prefix="pipeplug_bench_"))
    source, library = folder / "elastic_ref.c", folder / "elastic_ref.so"
    source.write_text(C_SOURCE)
    subprocess.run([compiler, "-O3", "-shared", "-fPIC", "-o", str(library), str(source), "-lm"],
                   check=True, capture_output=True)
    function = ctypes.CDLL(str(library)).run_pipe_plug
    pd, lg = ctypes.POINTER(ctypes.c_double), ctypes.c_int64
    pl = ctypes.POINTER(ctypes.c_int64)
    function.argtypes = [lg, ctypes.c_double, ctypes.c_double, pd, pd, pd, lg, pd, pd, lg,
                         pl, pd, lg, pl, pd, lg, pd]
    function.restype = None
    return function


def run_c(function, n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Call the compiled C loop on the model's arrays (changed in place)."""
    def d(a):
        return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))

    def i(a):
        return a.ctypes.data_as(ctypes.POINTER(ctypes.c_int64))
    cells1 = np.ascontiguousarray(cells1, dtype=np.int64)
    cells2 = np.ascontiguousarray(cells2, dtype=np.int64)
    function(n, dt, q, d(coef), d(v1), d(N1), v1.size, d(v2), d(N2), v2.size,
             i(cells1), d(u1), cells1.size, i(cells2), d(u2), cells2.size, d(acc))
