"""Regularised friction as a typical user would write it: tanh(v/eps) and scipy's stiff solvers.

The set-valued Sign of the rigid models is replaced by tanh(v/eps) for both contacts (outer on
the pipe velocity, inner on the relative velocity); the 4-state ODE, y = (U1, V1, U2, V2)::

    M1 V1' = Q - F1(U1) tanh(V1/eps) - F2 tanh((V1 - V2)/eps),    M2 V2' = F2 tanh((V1 - V2)/eps)

with F1 = P1 L1 tau1 (model I) or P1 tau1 min(max(U1, 0), L1) (model II), is integrated with
:func:`scipy.integrate.solve_ivp` (LSODA, Radau, BDF) and with :func:`scipy.integrate.odeint`
(the same LSODA, stepped by ODEPACK's own compiled driver instead of a Python loop). To give it
its best shot, the load discontinuity is handled
by integrating in two segments split at t0, outputs are requested at the sample times
(``t_eval``), and every method gets the analytic Jacobian. The right-hand side works on
floats with :mod:`math` and returns lists (each call is one state; numpy's per-call overhead
would dominate).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import odeint, solve_ivp

from .cases import BenchCase

#: right-hand-side evaluations after which a run is abandoned as failed: some settings (tiny eps
#: with a loose tolerance) make LSODA retry for minutes before giving up
MAX_CALLS = 20_000


class BudgetExceeded(RuntimeError):
    """The integrator used more than :data:`MAX_CALLS` right-hand-side evaluations."""


class TanhFriction:
    """Right-hand side and Jacobian of the regularised model for one case.

    Parameters
    ----------
    bench : BenchCase
        Masses, friction limits and model (I or II).
    eps : float
        Regularisation velocity, m/s.
    """

    def __init__(self, bench: BenchCase, eps: float):
        c = bench.case
        self.M1, self.M2, self.F2, self.eps = c.M1, c.M2, c.F2, eps
        self.growth, self.L1 = bench.growth, c.L1
        self.k1 = c.P1 * c.tau1                      # outer limit per unit contact length, N/m
        self.q = 0.0
        self.calls = 0

    def outer_limit(self, u1: float) -> tuple[float, float]:
        """Outer friction limit F1, N, and its slope dF1/dU1, N/m, at pipe displacement `u1`."""
        if not self.growth:
            return self.k1 * self.L1, 0.0
        inside = 0.0 < u1 < self.L1
        return self.k1 * min(max(u1, 0.0), self.L1), (self.k1 if inside else 0.0)

    def rhs(self, t, y):
        """dy/dt at state y = (U1, V1, U2, V2) under the current load ``self.q``, N."""
        self.calls += 1
        if self.calls > MAX_CALLS:
            raise BudgetExceeded(f"more than {MAX_CALLS} evaluations")
        u1, v1, _, v2 = y.tolist()
        f1 = self.outer_limit(u1)[0] * math.tanh(v1 / self.eps)
        f2 = self.F2 * math.tanh((v1 - v2) / self.eps)
        return [v1, (self.q - f1 - f2) / self.M1, v2, f2 / self.M2]

    def jac(self, t, y):
        """Jacobian d(dy/dt)/dy at state y (4 x 4)."""
        u1, v1, _, v2 = y.tolist()
        limit, slope = self.outer_limit(u1)
        th1, th2 = math.tanh(v1 / self.eps), math.tanh((v1 - v2) / self.eps)
        g1 = limit * (1.0 - th1 * th1) / self.eps     # d f1 / d V1, N s/m
        g2 = self.F2 * (1.0 - th2 * th2) / self.eps   # d f2 / d (V1 - V2), N s/m
        m1, m2 = self.M1, self.M2
        return [[0.0, 1.0, 0.0, 0.0],
                [-slope * th1 / m1, -(g1 + g2) / m1, 0.0, g2 / m1],
                [0.0, 0.0, 0.0, 1.0],
                [0.0, g2 / m2, 0.0, -g2 / m2]]


def _segment_ivp(model, method, y0, start, stop, times, rtol, atol):
    """One load segment with solve_ivp: states at `times` (4 x n), or None on failure."""
    sol = solve_ivp(model.rhs, (start, stop), y0, method=method, t_eval=times, rtol=rtol,
                    atol=atol, jac=model.jac)
    return sol.y if sol.success and sol.y.shape[1] == len(times) else None


def _segment_odeint(model, y0, start, times, rtol, atol):
    """One load segment with odeint (ODEPACK's LSODA, no Python work per step)."""
    out, info = odeint(model.rhs, y0, np.concatenate([[start], times]), Dfun=model.jac,
                       tfirst=True, rtol=rtol, atol=atol, mxstep=MAX_CALLS, full_output=True)
    return out[1:].T if info["message"] == "Integration successful." else None


def run_regularised(bench: BenchCase, method: str, eps: float, rtol: float, atol: float) -> dict:
    """Integrate the regularised model over the pulse and after it; values at the sample times.

    Parameters
    ----------
    bench : BenchCase
    method : str
        A solve_ivp method ("LSODA", "Radau", "BDF") or "odeint" (LSODA through ODEPACK's own
        driver, which steps in compiled code and interpolates to the sample times itself).
    eps : float
        Regularisation velocity, m/s.
    rtol, atol : float
        Relative and absolute (m, m/s) tolerances.

    Returns
    -------
    dict
        V1, V2, U1, U2 at the sample times (NaN after a failure), and ``success`` (bool).
    """
    model = TanhFriction(bench, eps)
    times, t0 = bench.times, bench.case.t0
    y, columns = np.zeros(4), []
    for start, q, mask in ((0.0, bench.case.Q0, times <= t0), (t0, 0.0, times > t0)):
        model.q = q
        try:
            if method == "odeint":
                values = _segment_odeint(model, y, start, times[mask], rtol, atol)
            else:
                values = _segment_ivp(model, method, y, start, times[mask][-1], times[mask],
                                      rtol, atol)
        except BudgetExceeded:
            values = None
        if values is None:
            break
        columns.append(values)
        y = values[:, -1]                  # the first segment ends on t0, a sample time
    success = len(columns) == 2
    values = np.concatenate(columns, axis=1) if success else np.full((4, len(times)), np.nan)
    return {"U1": values[0], "V1": values[1], "U2": values[2], "V2": values[3],
            "success": success}
