"""One case with a growing plug in, one result out: :func:`run_growth_case`.

Every case runs on the first core path of the setup (the growing plug's model is one Python
source: the compiled exact solver is not used) on each of its grids, a clean-out at its grid
point before the step from there, with the checks that need no reference on every point: the
ledger ``W_input = E_kinetic + W_friction + W_face + W_accretion + W_removed`` with the kinetic
energy of the pipe and of the plug of its current length, the losses never decreasing, L2 within
[0, L1], stuck contacts still; the grids must agree at the common sample times. Cases marked
``reference`` are compared with the ODE reference of the growing plug
(:mod:`pipeplug_references.growth_ivp`, which never imports the core). The FMU and the fd scheme
are not run (the fd scheme refuses a growing plug; the FMU's clean-outs are tested in
``tests/fmu/test_fmu_growth.py``).
"""
from __future__ import annotations

import math
import time

import numpy as np

from pipeplug import OUTPUT_NAMES

from . import checks as ck
from .cases import loads_on
from .growth_cases import GrowthCase
from .paths import CORE_PATHS
from .run import CaseResult, _guarded
from .runners import COLUMN

__all__ = ["run_growth_case", "GROWTH_FAMILIES"]

#: outputs compared with the reference, each on the scale of its family
GROWTH_FAMILIES = (("v_pipe", "v_plug"), ("u_pipe", "u_plug", "L2_now"),
                   ("W_input", "W_friction_outer", "W_friction_inner", "W_face", "W_accretion",
                    "W_removed", "E_kinetic"))
#: the grids' families: the rigid ones (:data:`~.checks.FAMILIES`) with the plug's length among
#: the displacements and the growing plug's losses among the works: the integrated pieces hold
#: them to 1e-13 of the pipe's scales (a W_accretion of 8e-3 J in a run of 2.5e5 J differed by
#: 2.3e-14 J between grids, 2.7e-12 of its own peak: fuzz 4043:789)
GRID_FAMILIES = tuple(family + {"u_pipe": ("L2_now",), "W_input": ("W_accretion", "W_removed")}
                      .get(family[0], ()) for family in ck.FAMILIES)
_LOSSES = ("W_friction", "W_friction_outer", "W_friction_inner", "W_face", "W_accretion",
           "W_removed")
_TERMS = ("E_kinetic", "W_friction", "W_face", "W_accretion", "W_removed")


def run_growth_case(case: GrowthCase, setup) -> CaseResult:
    """Run every check the case is marked for (module docstring)."""
    start = time.perf_counter()
    result = CaseResult(case.seed, case.index, case.model, case.checks)
    path = setup.paths[0] if setup.paths else "python"
    rows = _guarded(result, path, _grids, case, CORE_PATHS[path], path, result)
    if "reference" in case.checks and rows is not None:
        _guarded(result, path, _reference, case, rows, path, result)
    result.seconds = time.perf_counter() - start
    return result


def _advance(builder, case: GrowthCase, grid) -> np.ndarray:
    """A fresh model through the steps of ``grid`` [s] (a clean-out at a grid point before the
    step from there): the outputs after each step."""
    model = builder(case.params, case.options)
    starts, ends = grid[:-1], grid[1:]
    loads = loads_on(case.segments, starts)
    cleanouts = set(case.cleanouts)
    rows = np.empty((len(ends), len(OUTPUT_NAMES)))
    for i in range(len(ends)):
        if float(starts[i]) in cleanouts:
            model.clean_out()
        model.advance_to(float(loads[i]), float(ends[i]), float(starts[i]))
        rows[i] = model.outputs()
    return rows


def _grids(case: GrowthCase, builder, path: str, result: CaseResult) -> list:
    """Every grid: the invariants on every point, the grids at the samples."""
    at_samples, runs = [], []
    for grid in case.grids.values():
        grid = np.asarray(grid)
        rows = _advance(builder, case, grid)
        runs.append(rows)
        result.put("growth ledger", path, ledger_error(rows, case.params))
        result.put("growth energies", path, violations(rows, case.params))
        at_samples.append(rows[np.searchsorted(grid[1:], case.samples)])
    result.put("grid", path, ck.grid_error(at_samples, GRID_FAMILIES))
    return runs


def ledger_error(rows, params: dict) -> float:
    """Largest |W_input - (E_kinetic + W_friction + W_face + W_accretion + W_removed)| and
    |E_kinetic - the kinetic energy of the pipe and of the plug of length L2_now|, over the
    largest work or energy of the run."""
    c = COLUMN
    balance = rows[:, c["W_input"]] - sum(rows[:, c[n]] for n in _TERMS)
    r1, h1 = params["R1"], params["h1"]
    m1 = params["rho1"] * math.pi * ((r1 + h1) ** 2 - r1 ** 2) * params["L1"]
    mu = params["rho2"] * math.pi * r1 ** 2
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    kinetic = 0.5 * (m1 * v1 * v1 + mu * rows[:, c["L2_now"]] * v2 * v2)
    scale = max(float(np.max(np.abs(rows[:, c[n]]), initial=0.0))
                for n in ("W_input",) + _TERMS)
    return max(ck.relative_error(balance, 0.0, scale),
               ck.relative_error(rows[:, c["E_kinetic"]], kinetic, scale))


def violations(rows, params: dict) -> float:
    """Points with a non-finite output, a loss that decreased (beyond 1e-12 of the largest
    work), L2_now outside [0, L1], a stuck pipe moving, or a stuck plug (of length > 0) moving
    relative to the pipe."""
    c = COLUMN
    scale = max(float(np.max(np.abs(rows[:, c["W_input"]]), initial=0.0)), 1e-300)
    bad = ~np.all(np.isfinite(rows), axis=1)
    for name in _LOSSES:
        steps = np.diff(np.concatenate([[0.0], rows[:, c[name]]]))
        bad |= steps < -1e-12 * scale
    l2 = rows[:, c["L2_now"]]
    bad |= (l2 < 0.0) | (l2 > params["L1"])
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    bad |= (rows[:, c["pipe_mode"]] == 0) & (v1 != 0.0)
    bad |= (rows[:, c["plug_mode"]] == 0) & (l2 > 0.0) & (v1 != v2)
    return float(np.count_nonzero(bad))


def _reference(case: GrowthCase, runs, path: str, result: CaseResult) -> None:
    """The run on the fine grid against the ODE reference."""
    from pipeplug_references.growth_ivp import simulate_growth

    grid = np.asarray(case.grids["fine"])
    ref = simulate_growth(case.params, list(case.segments), grid[1:], case.base.growth,
                          cleanouts=case.cleanouts)
    fine = runs[list(case.grids).index("fine")]
    for family in GROWTH_FAMILIES:
        scale = max(float(np.max(np.abs(ref[n]), initial=0.0)) for n in family)
        if family[1] == "u_plug":
            scale = max(scale, case.params["L1"])
        for name in family:
            result.put("reference", path,    # (put keeps the worst value, NaN included)
                       ck.relative_error(fine[:, COLUMN[name]], ref[name], scale))
