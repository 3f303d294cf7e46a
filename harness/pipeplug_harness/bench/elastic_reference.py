"""Two independent codings of the elastic scheme for pipe and plug (no soil friction).

Used only by the benchmark (:mod:`pipeplug_harness.bench.elastic`) to time the package's kernel
against (a) the same scheme as numpy vector operations per time step and (b) a C loop compiled
at run time with the system compiler (``cc -O3``) and called through ctypes. Both follow
:mod:`pipeplug.elastic_cells` step by step: kick, pair Coulomb projection of each coupled
pipe/plug cell, drift of the inner-face forces, tracked displacements, works.

Arrays and constants are those of :class:`pipeplug.elastic.ElasticModel` (``v1, N1, v2, N2, u1,
u2, acc`` and ``grid.coef``, ``grid.cells1``, ``grid.cells2``), changed in place.
"""
from __future__ import annotations

import ctypes
import subprocess
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["run_numpy", "build_c", "run_c", "C_SOURCE"]

_SLACK = 1e-13
# coefficient and accumulator indices of pipeplug.elastic_kernel (M1, K1, M2, K2, C1, C2, DX)
_M1, _K1, _M2, _K2, _C2 = 0, 1, 2, 3, 5
_W_IN, _W_FR, _W_NEG, _F_IN = 0, 1, 2, 4


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
        w1, w2 = v1[j0:], v2 + a2 * np.diff(N2)
        x = (m1 * w1 + m2 * w2) / (m1 + m2)
        f_stuck = -m2 * (x - w2)
        stuck = np.abs(f_stuck) - c2 <= _SLACK * (np.abs(m1 * w1) + np.abs(m2 * w2) + c2)
        f2 = np.where(stuck, np.clip(f_stuck, -c2, c2), np.where(w1 > w2, -c2, c2))
        v1[j0:] = np.where(stuck, x, w1 + f2 / m1)
        v2[:] = np.where(stuck, x, w2 - f2 / m2)
        d = -0.5 * f2 * (p_old - q_old + v1[j0:] - v2)
        acc[_W_FR] += d[d >= 0.0].sum()
        acc[_W_NEG] += d[d < 0.0].sum()
        impulse = f2.sum()
        acc[_W_IN] += 0.5 * q * dt * (v_first + v1[0])
        N1[1:-1] += b1 * np.diff(v1)
        N2[1:-1] += b2 * np.diff(v2)
        u1 += dt * v1[cells1]
        u2 += dt * v2[cells2]
    acc[_F_IN] = impulse / dt


C_SOURCE = r"""
#include <math.h>
#include <stdint.h>
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

void run_pipe_plug(int64_t n, double dt, double q, const double *coef, double *v1, double *N1,
                   int64_t n1, double *v2, double *N2, int64_t n2, const int64_t *cells1, double *u1,
                   int64_t t1, const int64_t *cells2, double *u2, int64_t t2, double *acc) {
    double m1 = coef[0], m2 = coef[2], a1 = dt / m1, a2 = dt / m2, c2 = dt * coef[5];
    double b1 = coef[1] * dt, b2 = coef[3] * dt, inner = 0.0;
    int64_t j0 = n1 - n2;
    N1[0] = -q;
    for (int64_t s = 0; s < n; ++s) {
        double v_first = v1[0], work = 0.0, neg = 0.0;
        for (int64_t j = 0; j < j0; ++j) v1[j] += a1 * (N1[j + 1] - N1[j]);
        inner = 0.0;
        for (int64_t k = 0; k < n2; ++k) {
            int64_t j = j0 + k;
            double p_old = v1[j], q_old = v2[k], x1, x2, f2;
            pair(m1, m2, p_old + a1 * (N1[j + 1] - N1[j]), q_old + a2 * (N2[k + 1] - N2[k]),
                 c2, &x1, &x2, &f2);
            v1[j] = x1; v2[k] = x2; inner += f2;
            double d = -0.5 * f2 * (p_old - q_old + x1 - x2);
            if (d >= 0.0) work += d; else neg += d;
        }
        acc[1] += work; acc[2] += neg;
        acc[0] += 0.5 * q * dt * (v_first + v1[0]);
        for (int64_t f = 1; f < n1; ++f) N1[f] += b1 * (v1[f] - v1[f - 1]);
        for (int64_t f = 1; f < n2; ++f) N2[f] += b2 * (v2[f] - v2[f - 1]);
        for (int64_t i = 0; i < t1; ++i) u1[i] += dt * v1[cells1[i]];
        for (int64_t i = 0; i < t2; ++i) u2[i] += dt * v2[cells2[i]];
    }
    acc[4] = inner / dt;
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
