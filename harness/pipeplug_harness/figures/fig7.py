"""The paper's Fig. 7 scene (model III against model I) and its convergence under dx refinement.

Scene (paper section 4, docs/corrections.md D1): default geometry, E1 = 195e9 Pa, E2 = 0.6e9 Pa, tau1 = 0,
tau2 = 1e4 Pa, one rectangular pulse Q0 = 23000 N for t0 = 0.05 s, observed to 0.08 s at the
pipe section x = L1/2. These are the package defaults with ``elastic = True``.

Model I for this scene is domain II with tau1 = 0 (docs/corrections.md A8): the pipe slides on the plug
during the whole pulse, so its velocity peaks at t0 with V1 = (Q0 - F2) t0 / M1, F2 = P2 L2 tau2.
"""
from __future__ import annotations

import math

import numpy as np

from pipeplug import Params, build_model
from pipeplug_harness.paper import Q0, T0
from pipeplug_harness.paper import T_FIG7 as T_END

__all__ = ["Q0", "T0", "T_END", "rigid_peak", "history", "convergence"]


def rigid_peak(params: Params | None = None) -> float:
    """Peak pipe velocity of model I in the Fig. 7 scene [m/s] (closed form, domain II)."""
    p = params or Params()
    return (Q0 - p.P2 * p.L2 * p.tau2) * T0 / p.M1


def history(dx: float, h: float, **changes) -> np.ndarray:
    """Pipe velocity at x_monitor = L1/2 [m/s] at t = h, 2h, ... T_END (model III).

    ``h`` [s] should be a whole multiple of the internal step dx/c1 and divide T0.
    """
    model = build_model(dict({"dx": dx, "x_monitor": 0.5}, **changes), {"elastic": True})
    count, pulse = round(T_END / h), round(T0 / h)
    loads = np.where(np.arange(count) < pulse, Q0, 0.0)
    return model.sample(loads, h * np.arange(1, count + 1), ("v_pipe",))["v_pipe"]


def convergence(dxs=(0.04, 0.02, 0.01, 0.005, 0.0025), h: float = 8e-6) -> list[dict]:
    """Peak and history of each grid against the finest one (the last of ``dxs``).

    Returns one row per dx: ``dx``, ``peak`` [m/s], ``peak_rel`` (relative difference to the
    finest grid's peak), ``rms_rel`` (RMS difference of the histories over the finest peak),
    ``rigid_rel`` (peak relative to model I's).
    """
    runs = {dx: history(dx, h) for dx in dxs}
    fine = runs[dxs[-1]]
    peak_fine, v_rigid = fine.max(), rigid_peak()
    return [{"dx": dx, "peak": v.max(), "peak_rel": v.max() / peak_fine - 1.0,
             "rms_rel": math.sqrt(np.mean((v - fine) ** 2)) / peak_fine,
             "rigid_rel": v_rigid / v.max() - 1.0} for dx, v in runs.items()]
