"""Run one hard case on one solver and measure it: error, finiteness, energy, long-run drift.

The core is driven directly (``pipeplug.build_model``): a communication step per comm point of
the case, the load held constant over it. The long run continues after ``t_end`` under the
case's ``hold`` force for a given number of steps: communication steps of 1 ms for the exact
solver, internal steps for fd and elastic (whose communication steps then hold 1000 each).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from pipeplug import Params, build_model

from .refs import closed_form_sequence, monitored_free_rod, single_body_train

__all__ = ["build_for", "run_case", "reference_for", "errors", "energy_residual",
           "long_run", "measure", "tolerance", "TOLERANCES", "COMPARED"]

COMPARED = ("v_pipe", "v_plug", "u_pipe", "u_plug")
#: (reference, solver) -> largest allowed error relative to the reference's peaks
TOLERANCES = {("closed form", "exact"): 1e-9, ("hand", "exact"): 1e-9,
              ("closed form", "fd"): 1e-2, ("hand", "fd"): 1e-2, ("exact solver", "fd"): 1e-2,
              ("closed form", "elastic"): 3e-2, ("hand", "elastic"): 3e-2,
              ("exact solver", "elastic"): 3e-2, ("d'Alembert", "elastic"): 1e-12}
_INNER_PER_STEP = 1000     # internal steps per communication step in the fd/elastic long run
#: The energy balance of every solver holds to round-off (fd books its own dissipation as
#: W_numerical), relative to W_input.
ENERGY_TOLERANCE = 1e-9


def build_for(case, solver: str):
    """A fresh core model of ``case`` for ``solver`` ("exact", "fd" or "elastic")."""
    params = dict(case.params)
    if solver == "fd":
        params["dt"] = case.fd_dt
    if solver == "elastic":
        params.update(case.elastic)
    options = {"contact_growth": case.growth, "elastic": solver == "elastic",
               "solver": "fd" if solver == "fd" else "exact"}
    return build_model(params, options)


def run_case(case, model, times=None) -> dict:
    """Advance ``model`` through ``times`` [s] (default: the case's communication points);
    the outputs there as arrays, and ``time``."""
    times = case.comm_points() if times is None else np.asarray(times, dtype=float)
    out = model.sample(case.load_history.on_steps(np.concatenate([[model.time], times[:-1]])),
                       times)
    out["time"] = times
    return out


def reference_for(case, times, exact_run=None) -> dict | None:
    """The case's reference outputs at ``times`` (None when it has none)."""
    kind = case.reference
    if kind == "closed form":
        return closed_form_sequence(case, times)
    if kind == "closed form, tau1 = 0":
        return closed_form_sequence(replace(case, params={**case.params, "tau1": 0.0}), times)
    if kind == "hand":
        return single_body_train(case, times)
    if kind == "d'Alembert":
        p = Params().with_(**{**case.params, **case.elastic})
        return monitored_free_rod(case, times, p.dx, p.c1, p.rho1 * p.c1 * p.S1)
    if kind == "exact solver":
        if exact_run is not None:
            return exact_run
        return run_case(case, build_for(case, "exact"), times)
    return None


def errors(out: dict, ref: dict, case) -> tuple[float, float]:
    """Largest velocity and displacement errors relative to the reference's peaks.

    Where the reference is at rest throughout (nothing may move), the scales are those of the
    blows instead: V = largest |impulse| / (M1 + M2) [m/s] and V times the longest blow [m].
    """
    c = case.rigid_case()
    v_blow = max(abs(a * d) for _, d, a in case.pulses) / (c.M1 + c.M2)
    scales = {"v_": v_blow, "u_": v_blow * max(d for _, d, _ in case.pulses)}
    result = []
    for prefix in ("v_", "u_"):
        names = [n for n in COMPARED if n.startswith(prefix)]
        peak = max(np.abs(ref[n]).max() for n in names) or scales[prefix]
        result.append(max(float(np.abs(out[n] - ref[n]).max()) for n in names) / peak)
    return result[0], result[1]


def energy_residual(model, out: dict) -> float:
    """Energy balance at the end, relative to W_input (0 when nothing was put in).

    W_input - (E_kinetic + E_strain + W_friction + W_numerical): round-off for every solver (fd
    books its own dissipation as W_numerical).
    """
    o = model.outputs()
    w_in = abs(o.W_input)
    rest = o.E_kinetic + o.E_strain + o.W_numerical + o.W_friction
    return (o.W_input - rest) / w_in if w_in > 0.0 else 0.0


def long_run(case, model, solver: str, n_steps: int) -> dict:
    """Hold ``case.hold`` for ``n_steps`` more steps; finiteness, largest speed and creep.

    The exact solver records all ``n_steps`` 1-ms points through its dense output; fd and
    elastic take ``n_steps`` internal steps, recorded every 1000.
    """
    start = model.outputs()
    if solver == "exact":
        rec = model.sample(case.hold, model.time + 1e-3 * np.arange(1, n_steps + 1))
    else:
        inner = case.fd_dt if solver == "fd" else model.grid.h_max
        rows = []
        for _ in range(max(1, n_steps // _INNER_PER_STEP)):
            model.advance(case.hold, _INNER_PER_STEP * inner)
            rows.append(model.outputs())
        rec = {name: np.array([getattr(r, name) for r in rows]) for name in rows[0]._fields}
    finite = all(bool(np.all(np.isfinite(np.asarray(v, dtype=float)))) for v in rec.values())
    drift_v = max(float(np.abs(rec[n]).max()) for n in ("v_pipe", "v_plug"))
    drift_u = max(float(np.abs(rec[n] - getattr(start, n)).max()) for n in ("u_pipe", "u_plug"))
    return {"finite": finite, "drift_v": drift_v, "drift_u": drift_u}


def measure(case, solver: str, long_steps: int, exact_run=None) -> dict:
    """One row of the stability table for ``case`` on ``solver``.

    Returns
    -------
    dict
        case, solver, reference, err_v, err_u (relative to the reference's peaks; nan without
        one), tol_v, tol_u, finite, energy (see :func:`energy_residual`), long_steps, drift_v
        [m/s], drift_u [m] (nan when the motion does not stop), ok.
    """
    model = build_for(case, solver)
    out = run_case(case, model)
    ref = reference_for(case, out["time"], exact_run)
    err_v, err_u = errors(out, ref, case) if ref is not None else (math.nan, math.nan)
    tol_v, tol_u = tolerance(case, solver)
    finite = all(bool(np.all(np.isfinite(out[n]))) for n in out)
    energy = energy_residual(model, out)
    late = long_run(case, model, solver, long_steps)
    drift_v, drift_u = (late["drift_v"], late["drift_u"]) if case.stops else (math.nan,) * 2
    ok = (finite and late["finite"] and not (err_v > tol_v or err_u > tol_u)
          and not (drift_v > 0.0 or drift_u > 0.0) and abs(energy) <= ENERGY_TOLERANCE)
    return {"case": case.name, "solver": solver, "reference": case.reference,
            "err_v": err_v, "err_u": err_u, "tol_v": tol_v, "tol_u": tol_u,
            "finite": finite and late["finite"],
            "energy": energy, "long_steps": long_steps, "drift_v": drift_v, "drift_u": drift_u,
            "ok": bool(ok)}


def tolerance(case, solver: str) -> tuple[float, float]:
    """(velocity, displacement) tolerances of ``case`` on ``solver`` (nan: no reference)."""
    if case.reference == "none":
        return math.nan, math.nan
    if case.tolerance is not None:
        return case.tolerance
    kind = "closed form" if case.reference.startswith("closed form") else case.reference
    tol = TOLERANCES[(kind, solver)]
    return tol, tol

