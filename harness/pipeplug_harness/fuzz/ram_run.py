"""One case of model I with a ram in, one result out: :func:`run_ram_case`.

Every case runs on every core path of the setup, on each of its grids (a strike starts at its
grid point, before the step from there), with the checks that need no reference on every
point: the ledger ``W_input + W_ram = E_kinetic + E_strain + W_friction + W_cushion + W_face``
with the kinetic energy of pipe, plug and ram from the paper's masses, every term's sign, friction works
never decreasing, stuck contacts still, the static limits; the grids must agree at the common
sample times. Cases marked ``reference`` are compared with the ODE reference of model I with a
ram (:mod:`pipeplug_references.ram_ivp`, which never imports the core); cases marked ``fmu``
run through the FMU on two hosts' points (strikes by its inputs ``strikes`` and ``v_strike``)
against the core on the same points.
"""
from __future__ import annotations

import time

import numpy as np

from pipeplug import OUTPUT_NAMES
from pipeplug.interface import LEDGER_SOURCES, LEDGER_TERMS

from . import checks as ck
from .cases import calls_of, loads_on, strikes_on_calls
from .paths import CORE_PATHS
from .ram_cases import RAM_PARAMETERS, RamCase
from .run import HOST_STYLES, CaseResult, _guarded
from .runners import COLUMN, drop_fmu_host, fmu_host

__all__ = ["run_ram_case", "RAM_FAMILIES", "still_scale", "STILL_ULPS"]

#: outputs compared with the reference, each on the scale of its family
RAM_FAMILIES = (("v_pipe", "v_plug", "v_ram"), ("u_pipe", "u_plug"),
                ("W_input", "W_friction", "W_cushion", "E_kinetic", "W_ram", "E_strain",
                 "W_face"))
#: the ledger's sources and terms (the core's table: W_face with end resistance)
_LEDGER_IN, _LEDGER_OUT = LEDGER_SOURCES, LEDGER_TERMS


def run_ram_case(case: RamCase, setup) -> CaseResult:
    """Run every check the case is marked for (module docstring)."""
    start = time.perf_counter()
    result = CaseResult(case.seed, case.index, case.model, case.checks)
    body = ck.Body.of(case.params, False)
    runs = {path: _guarded(result, path, _grids, case, CORE_PATHS[path], path, body, result)
            for path in setup.paths}
    first = setup.paths[0] if setup.paths else None
    for path, rows in runs.items():
        if path != first and rows is not None and runs[first] is not None:
            result.put("paths", path, max(ck.same_outputs_error(a, b)
                                          for a, b in zip(rows, runs[first])))
    if "reference" in case.checks and first and runs[first] is not None:
        _guarded(result, first, _reference, case, runs[first], first, result)
    if "fmu" in case.checks and setup.fmu:
        for style in HOST_STYLES:
            _guarded(result, f"fmu {style}", _fmu, case, setup, style, result)
    result.seconds = time.perf_counter() - start
    return result


def _advance(builder, case: RamCase, starts, ends, strikes: dict) -> np.ndarray:
    """A fresh model from ``starts[0]`` through the steps ``starts[i] -> ends[i]`` [s], the
    strike ``strikes[i]`` [m/s] (if any) started at ``starts[i]``: the outputs after each."""
    model = builder(case.params, case.options)
    loads = loads_on(case.segments, starts)
    rows = np.empty((len(ends), len(OUTPUT_NAMES)))
    for i in range(len(ends)):
        if i in strikes:
            model.strike(strikes[i])
        model.advance_to(float(loads[i]), float(ends[i]), float(starts[i]))
        rows[i] = model.outputs()
    return rows


def _grids(case: RamCase, builder, path: str, body, result: CaseResult) -> list:
    """Every grid on one path: the invariants on every point, the grids at the samples."""
    at_samples, runs = [], []
    for grid in case.grids.values():
        grid = np.asarray(grid)
        at = {i: v for i, t in enumerate(grid[:-1]) for s, v in case.strikes if t == s}
        rows = _advance(builder, case, grid[:-1], grid[1:], at)
        runs.append(rows)
        result.put("ram ledger", path, ledger_error(rows, body, case.params["ram_mass"]))
        result.put("ram energies", path, sign_violations(rows))
        result.put("friction work", path, ck.friction_decrease(rows))
        result.put("stuck", path, ck.stuck_violations(rows, body))
        at_samples.append(rows[np.searchsorted(grid[1:], case.samples)])
    result.put("grid", path, ck.grid_error(at_samples))
    return runs


def ledger_error(rows, body: ck.Body, ram_mass: float) -> float:
    """Largest |W_input + W_ram - (E_kinetic + E_strain + W_friction + W_cushion +
    W_numerical)| and |E_kinetic - kinetic energy of pipe, plug and ram from the paper's
    masses|, over the largest work or energy of the run."""
    c = COLUMN
    balance = (sum(rows[:, c[n]] for n in _LEDGER_IN) - sum(rows[:, c[n]] for n in _LEDGER_OUT))
    v1, v2, vr = rows[:, c["v_pipe"]], rows[:, c["v_plug"]], rows[:, c["v_ram"]]
    kinetic = 0.5 * (body.M1 * v1 * v1 + body.M2 * v2 * v2 + ram_mass * vr * vr)
    scale = max(float(np.max(np.abs(rows[:, c[n]]), initial=0.0))
                for n in _LEDGER_IN + _LEDGER_OUT)
    return max(ck.relative_error(balance, 0.0, scale),
               ck.relative_error(rows[:, c["E_kinetic"]], kinetic, scale))


def sign_violations(rows) -> float:
    """Points where E_kinetic, E_strain, W_cushion or W_face is negative (beyond 1e-12 of the
    largest work: W_cushion and W_face are differences), a loss (W_friction, W_cushion, W_face)
    falls by more than that, W_numerical is not 0, W_friction and W_face exceed the work put
    in, or an output is not finite."""
    c = COLUMN
    scale = max(float(np.max(np.abs(rows[:, c[n]]), initial=0.0)) for n in _LEDGER_IN)
    bad = ~np.all(np.isfinite(rows), axis=1)
    bad |= (rows[:, c["E_kinetic"]] < 0.0) | (rows[:, c["E_strain"]] < 0.0)
    bad |= rows[:, c["W_cushion"]] < -1e-12 * scale
    bad |= rows[:, c["W_face"]] < -1e-12 * scale
    for loss in ("W_friction", "W_cushion", "W_face"):      # dissipated: never given back
        bad |= np.diff(rows[:, c[loss]], prepend=0.0) < -1e-12 * scale
    bad |= rows[:, c["W_numerical"]] != 0.0
    bad |= (rows[:, c["W_friction"]] + rows[:, c["W_face"]] > rows[:, c["W_input"]]
            + rows[:, c["W_ram"]] + 1e-12 * scale)
    return float(np.count_nonzero(bad))


def _reference(case: RamCase, rows, path: str, result: CaseResult) -> None:
    """The first core path's run on the fine grid against the ODE reference."""
    from pipeplug_references.ram_ivp import simulate_ram

    grid = np.asarray(case.grids["fine"])
    times = grid[1:].copy()
    struck = np.isin(times, [t for t, _ in case.strikes])
    # Outputs at a strike's time are those before it; the reference samples there after it.
    times[struck] = np.nextafter(times[struck], -np.inf)
    t, history = 0.0, []
    for duration, q in case.segments:
        history.append((t, "q", q))
        t += duration
    history.append((t, "q", 0.0))
    history += [(s, "strike", v) for s, v in case.strikes]
    history.sort(key=lambda h: (h[0], h[1] == "strike"))
    params = {k: v for k, v in case.params.items() if k not in RAM_PARAMETERS}
    ram = {"mass": case.params["ram_mass"], "k": case.params["cushion_stiffness"],
           "e": case.params["cushion_restitution"]}
    ref = simulate_ram(params, ram, [h for h in history if h[0] <= case.stop], times)
    fine = rows[list(case.grids).index("fine")]
    body = ck.Body.of(case.params, False)
    tolerance = ck.CHECKS["reference"].tolerance
    for family in RAM_FAMILIES:
        scale = max(float(np.max(np.abs(ref[n]), initial=0.0)) for n in family)
        for name in family:
            own = scale if scale > 0.0 else still_scale(case, body, name) / tolerance
            result.put("reference", path,    # (put keeps the worst value, NaN included)
                       ck.relative_error(fine[:, COLUMN[name]], ref[name], own))


#: ulps of the case's largest static force whose drift a family held at exactly 0 allows
STILL_ULPS = 16.0


def still_scale(case: RamCase, body: ck.Body, name: str) -> float:
    """What round-off moves output ``name`` where the reference holds its whole family at
    exactly 0.

    A relative error has no scale there (any difference would be infinite), yet the core may
    decide a load at its limit to the last digit the other way and let a body drift under
    :data:`STILL_ULPS` ulps of the largest static force it feels for the run's time T [s]:
    the pipe (mass M1) under F = the largest of |Q|, F1, F2, Qf, Qp [N], the plug (M2) under
    F2 or Qp or as the pipe carrying it. With ``a = STILL_ULPS eps F / M`` a velocity
    reaches ``a T`` [m/s], a displacement ``a T^2 / 2`` [m], a work ``F a T^2 / 2`` [J] (the
    ram feels no static force: 0). The caller divides this by the tolerance, so that a
    difference up to it passes and anything more fails.
    """
    loads = max((abs(q) for _, q in case.segments), default=0.0)
    force = max(loads, body.outer_limit(0.0), body.F2, body.Qf, body.Qp)
    drift = STILL_ULPS * np.finfo(float).eps * force / body.M1
    if name in ("v_plug", "u_plug") and body.plug:
        drift = max(drift, STILL_ULPS * np.finfo(float).eps * max(body.F2, body.Qp) / body.M2)
    t = case.stop
    if name == "v_ram":
        return 0.0
    if name.startswith("v_"):
        return drift * t
    if name.startswith("u_"):
        return 0.5 * drift * t * t
    return 0.5 * force * drift * t * t


def _fmu(case: RamCase, setup, style: str, result: CaseResult) -> None:
    """The FMU on one host's points, against the first core path on the same points."""
    calls = calls_of(case.edges, case.stop, case.host_h, style)
    loads = loads_on(case.segments, [t for t, _ in calls])
    try:
        rows = fmu_host(setup.fmu).run_with(case.params, case.options, loads, calls,
                                            case.strikes)
    except Exception:
        drop_fmu_host(setup.fmu)        # the next case gets a fresh instance
        raise
    starts = np.array([t for t, _ in calls])
    core = _advance(CORE_PATHS[setup.paths[0]], case, starts, starts + [h for _, h in calls],
                    strikes_on_calls(calls, case.strikes))
    result.put("fmu", f"fmu {style}", ck.same_outputs_error(rows, core))
