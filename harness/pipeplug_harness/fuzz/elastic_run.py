"""One model III case in, one result out: :func:`run_elastic_case`.

Every case runs on the compiled kernels over each of its grids, with the checks that need no
reference on every point (:mod:`.elastic_checks`); its grids must agree at the common sample
times to round-off. Cases marked ``reference`` also run on the path without numba (the same
bits), and, where the rods have no friction and step at Courant 1, against the exact cell
averages of the free rod (:mod:`pipeplug_references.rods`); cases marked ``fmu`` run through
the FMU on two hosts' points, against the core on the same points.
"""
from __future__ import annotations

import time

import numpy as np

from pipeplug import OUTPUT_NAMES, Options, Params
from pipeplug.elastic.growth import GrowthModel
from pipeplug.elastic.model import ElasticModel

from . import checks as ck
from . import elastic_checks as ek
from .cases import calls_of, strikes_on_calls
from .elastic_cases import GRIDS, ElasticCase, internal_step, plug_simulated
from .run import HOST_STYLES, CaseResult, _guarded
from .runners import drop_fmu_host, fmu_host

__all__ = ["run_elastic_case", "ELASTIC_PATHS"]


def _model(case: ElasticCase, vectorised: bool) -> ElasticModel:
    options = Options(elastic=True, contact_growth=case.growth, plug_growth=case.plug_growth)
    params = Params.from_mapping(case.params).validate(options.active_groups())
    model = GrowthModel if case.plug_growth else ElasticModel
    return model(params, options, vectorised=vectorised)


#: name -> builder of a model III path: the compiled kernels (every case) and the numpy steps
#: (the cases marked "reference")
ELASTIC_PATHS = {"compiled": lambda case: _model(case, False),
                 "numpy": lambda case: _model(case, True)}


def run_elastic_case(case: ElasticCase, setup) -> CaseResult:
    """Run every check the case is marked for (module docstring)."""
    start = time.perf_counter()
    result = CaseResult(case.seed, case.index, case.model, case.checks)
    body = ek.RodBody.of(case.params, case.plug_growth)
    runs = _guarded(result, "compiled", _grids, case, "compiled", body, result)
    if "reference" in case.checks and runs is not None:
        numpy = _guarded(result, "numpy", _run, case, "numpy", case.grids["multiples"])
        if numpy is not None:
            result.put("paths", "numpy", ck.same_outputs_error(numpy, runs[0]))
        if _free_rod(case.params) and not case.plug_growth:
            result.put("rod reference", "compiled",
                       ek.free_rod_error(case, case.grids["multiples"], runs[0]))
    if "fmu" in case.checks and setup.fmu:
        for style in HOST_STYLES:
            _guarded(result, f"fmu {style}", _fmu, case, setup, style, result)
    result.seconds = time.perf_counter() - start
    return result


def _free_rod(params: dict) -> bool:
    """No friction at all, no end resistance, no ram and Courant 1: the scheme transports the
    free rod's waves exactly."""
    return (params["tau1"] == 0.0 and not plug_simulated(params) and params["courant"] == 1.0
            and params.get("ram_mass", 0.0) == 0.0 and params.get("q_face", 0.0) == 0.0)


def _run(case: ElasticCase, path: str, grid) -> np.ndarray:
    """A fresh model of ``path`` through the points ``grid`` [s]: the outputs at each (a
    strike starts at its point, before the step from there)."""
    model = ELASTIC_PATHS[path](case)
    grid = np.asarray(grid, dtype=float)
    loads = case.load_at(grid[:-1])
    strikes = dict(case.strikes)
    cleanouts = set(case.cleanouts)
    rows = np.empty((len(grid) - 1, len(OUTPUT_NAMES)))
    for i, (t, t_next) in enumerate(zip(grid[:-1], grid[1:])):
        if float(t) in cleanouts:
            model.clean_out()
        if float(t) in strikes:
            model.strike(strikes[float(t)])
        model.advance_to(float(loads[i]), float(t_next), float(t))
        rows[i] = model.outputs()
    return rows


def _grids(case: ElasticCase, path: str, body, result: CaseResult) -> list:
    """Every grid on one path: the invariants on every point, the grids at the samples."""
    at_samples, runs = [], []
    h = internal_step(case.params, case.plug_growth)
    for name in GRIDS:
        grid = np.asarray(case.grids[name])
        rows = _run(case, path, grid)
        runs.append(rows)
        loads = case.load_at(grid[:-1])
        result.put("ledger", path, ek.ledger_error(rows, grid[1:], h))
        result.put("energies", path, ek.energy_violations(
            rows, body.m_ram, grid[1:], h))
        result.put("friction work", path, ck.friction_decrease(rows))
        result.put("bound", path, ek.bound_ratio(rows, loads, np.diff(grid), body, h,
                                                 case.strikes, grid[:-1]))
        at_samples.append(rows[np.searchsorted(grid[1:], case.samples)])
    result.put("grid", path, ck.grid_error(at_samples))
    return runs


def _fmu(case: ElasticCase, setup, style: str, result: CaseResult) -> None:
    """The FMU on one host's points, against the compiled core on the same points."""
    calls = calls_of(case.edges, case.stop, case.host_h, style)
    loads = case.load_at([t for t, _ in calls])
    try:
        rows = fmu_host(setup.fmu).run_with(case.params, case.options, loads, calls,
                                            case.strikes)
    except Exception:
        drop_fmu_host(setup.fmu)        # the next case gets a fresh instance
        raise
    model = ELASTIC_PATHS["compiled"](case)
    strikes = strikes_on_calls(calls, case.strikes)
    core = np.empty_like(rows)
    for i, (t, h) in enumerate(calls):
        if i in strikes:
            model.strike(strikes[i])
        model.advance_to(float(loads[i]), t + h, t)
        core[i] = model.outputs()
    result.put("fmu", f"fmu {style}", ck.same_outputs_error(rows, core))
