"""The measurements of the ``cost`` study: every method on every case, the elastic model, and
the communication step (the creep study is :mod:`pipeplug_harness.cost.creep`).

Each measurement is a row (a dict) with the method family, its setting, the case, the maximum
relative errors against the exact solution and the best wall time (model build included).
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np

from . import compiled, core
from .cases import BenchCase, closed_form_reference, from_outputs, relative_errors
from .regularised import run_regularised

#: regularised families with a compiled right-hand side (:mod:`pipeplug_harness.cost.compiled`)
COMPILED = tuple(compiled.FAMILIES)
#: families whose settings form a Pareto front (elastic is another model: kept apart)
RIGID_FAMILIES = ("exact", "fd", "LSODA", "odeint-LSODA", "Radau", "BDF", *COMPILED)
#: study name of each regularised method (solve_ivp's or odeint)
REGULARISED = {"LSODA": "LSODA", "Radau": "Radau", "BDF": "BDF", "odeint-LSODA": "odeint"}


@dataclass(frozen=True)
class Config:
    """What the study runs.

    Attributes
    ----------
    cases : list of BenchCase
    fd_dts : tuple of float
        Largest internal steps of the fd solver, s (divisors of the sample step).
    methods : tuple of str
        Regularised families, keys of :data:`REGULARISED`.
    eps : tuple of float
        Regularisation velocities, m/s.
    rtols : tuple of float
        Relative tolerances; the absolute tolerance is ``rtol * atol_scale``.
    atol_scale : float
        m and m/s per unit of rtol.
    elastic_dxs : tuple of float
        Elastic grid spacings, m.
    comm_rates : tuple of int
        Communication steps per second of the communication-step study.
    creep_eps : tuple of float
        Regularisation velocities of the creep study, m/s.
    creep_rtol : float
        Relative tolerance of the creep study's LSODA runs.
    repeats : int
        Most repeats of a timing (best taken).
    batch_cases : int
        Cases of the batch throughput measurement.
    compiled : tuple of str
        Compiled competitors to run (keys of :data:`COMPILED`), on the grid of `eps` and
        `rtols`; those that cannot run here are named in the report.
    """

    cases: list
    fd_dts: tuple
    methods: tuple
    eps: tuple
    rtols: tuple
    atol_scale: float
    elastic_dxs: tuple
    comm_rates: tuple
    creep_eps: tuple
    creep_rtol: float
    repeats: int
    batch_cases: int
    compiled: tuple = ()


def progress(message: str) -> None:
    """A progress line on stderr (stdout carries the report)."""
    print(message, file=sys.stderr, flush=True)


def reference(bench: BenchCase) -> dict:
    """Closed form for model I; the exact solver for model II (no closed form)."""
    return core.run_exact(bench) if bench.growth else closed_form_reference(bench)


def measure(family, setting, bench, run, ref, repeats, columns: bool = False) -> dict:
    """Time ``run()`` and compare its result with `ref`: one row. With `columns`, ``run()``
    returns the core's output columns, put under the study's keys after the timing."""
    result, seconds = core.best_time(run, repeats)
    if columns:
        result = from_outputs(result)
    ok = bool(result.get("success", True))
    v_err, u_err = relative_errors(result, ref) if ok else (math.nan, math.nan)
    row = {"method": family, "setting": setting, "case": bench.name, "max_rel_error": v_err,
           "max_rel_disp_error": u_err, "wall_s": seconds, "success": ok}
    progress(f"  {family:13s} {setting:26s} {bench.name:10s} error {v_err:9.3g}  "
             f"time {1e3 * seconds:9.3f} ms")
    return row


def _runs(bench: BenchCase, config: Config, families):
    """(family, setting, run) of every rigid method on `bench` but the exact solver (of the
    compiled competitors, `families`)."""
    for dt in config.fd_dts:
        yield "fd", f"dt={dt:g}", lambda dt=dt: core.run_fd(bench, dt)
    for family in config.methods:
        for eps in config.eps:
            for rtol in config.rtols:
                atol = rtol * config.atol_scale
                yield (family, f"eps={eps:g} rtol={rtol:g}",
                       lambda e=eps, r=rtol, a=atol, m=REGULARISED[family]:
                       run_regularised(bench, m, e, r, a))
    for family in (f for f in families if f in compiled.STEPPED):
        for dt in config.fd_dts:
            yield family, f"dt={dt:g}", lambda dt=dt: compiled.run_fd_compiled(bench, dt)
    for family in (f for f in families if f not in compiled.STEPPED):
        for eps in config.eps:
            for rtol in config.rtols:
                yield (family, f"eps={eps:g} rtol={rtol:g}",
                       lambda e=eps, r=rtol, a=rtol * config.atol_scale, f=family:
                       compiled.RUNS[f](bench, e, r, a))


def warm_up(config: Config) -> None:
    """Run each method once, untimed, so that first-call costs (lazy imports, loading or
    compiling the exact solver's kernels: dense output and stepping) are not timed."""
    bench = min(config.cases, key=lambda b: b.t_end)
    core.run_exact(bench)
    core.run_stepped(bench, "exact", min(config.comm_rates))
    core.run_fd(bench, max(config.fd_dts))
    for family in config.methods:
        run_regularised(bench, REGULARISED[family], 1e-3, 1e-4, 1e-7)


def prepare_compiled(config: Config) -> tuple[dict, dict]:
    """Compile each compiled competitor that can run here, untimed in the study.

    Returns
    -------
    (dict, dict)
        {family: first call's wall time [s]: compiling and jit included} and {family: why it
        cannot run}.
    """
    missing = compiled.available(config.compiled)
    bench = min(config.cases, key=lambda b: b.t_end)
    prepared = {}
    for family in config.compiled:
        if family in missing:
            progress(f"  {family}: not run: {missing[family]}")
            continue
        progress(f"  compiling {family}")
        prepared[family] = compiled.prepare(family, bench)
    return prepared, missing


def sweep(config: Config, families=()) -> list[dict]:
    """Every rigid method at every setting on every case (of the compiled competitors,
    `families`, prepared by :func:`prepare_compiled`)."""
    warm_up(config)
    rows = []
    for bench in config.cases:
        progress(f"case {bench.name} (t_end = {bench.t_end:g} s, {len(bench.times)} samples)")
        ref = reference(bench)
        rows.append(measure("exact", "dense output", bench, core.exact_call(bench), ref,
                            config.repeats, columns=True))
        rows += [measure(family, setting, bench, run, ref, config.repeats)
                 for family, setting, run in _runs(bench, config, families)]
    return rows


def elastic_sweep(config: Config) -> tuple[list[dict], str]:
    """Model III at every grid spacing on the model I cases, against the rigid closed form.

    Returns
    -------
    (list of dict, str)
        The rows, and why the elastic model was skipped (empty if it ran).
    """
    model1 = [b for b in config.cases if not b.growth]
    if not config.elastic_dxs or not model1:
        return [], "no elastic runs requested"
    why = core.elastic_available(model1[0], config.elastic_dxs[0])
    if why:
        progress(f"elastic model skipped: {why}")
        return [], why
    for bench in model1:               # compiles (or loads) the kernel each case calls for
        core.run_elastic(bench, config.elastic_dxs[0])
    rows = []
    for bench in model1:
        ref = closed_form_reference(bench)
        rows += [measure("elastic", f"dx={dx:g}", bench,
                         lambda dx=dx, b=bench: core.run_elastic(b, dx), ref, config.repeats)
                 for dx in config.elastic_dxs]
    return rows, ""


def comm_step_sweep(config: Config) -> list[dict]:
    """Exact and fd solvers driven through ``advance`` at several communication steps h.

    The fd solver's internal step is h itself; errors are taken at the communication points.
    """
    rows = []
    for bench in (b for b in config.cases if not b.growth):
        for rate in config.comm_rates:
            ref = closed_form_reference(bench, np.arange(1, round(bench.t_end * rate) + 1) / rate)
            for solver in ("exact", "fd"):
                row = measure(solver, f"h={1.0 / rate:g}", bench,
                              lambda s=solver, r=rate, b=bench: core.run_stepped(b, s, r), ref,
                              config.repeats)
                rows.append(dict(row, step_s=1.0 / rate))
    return rows
