"""``pipeplug cost``: what accuracy costs in time.

Every method runs on the same cases, a rectangular pulse from rest (the paper's model I figure
cases of domains I-IV and one model II case), sampled every 0.2 ms:

- ``exact``: the core's event-driven solver, dense output at the sample times;
- ``fd``: the paper's explicit scheme at several internal steps dt, driven at the sample times;
- ``LSODA``, ``BDF``, ``Radau``: tanh(v/eps) friction integrated with
  :func:`scipy.integrate.solve_ivp` at several eps and tolerances; ``odeint-LSODA``: the same
  LSODA through :func:`scipy.integrate.odeint`, whose stepping loop is compiled;
- ``elastic``: model III at several grid spacings, a different model, so compared with the rigid
  closed form only as a model difference and reported apart.

The error of a run is the largest velocity error of either body over the samples, relative to
the peak pipe velocity (model I: against the closed form; model II: against the exact solver);
its time is the best of several repeats of build + run (imports excluded), in this process,
without the FMU. Case by case, the exact solver is compared with the fastest regularised setting
of any family that reaches a relative error of 1e-6 there. The batch API's throughput (single
blows through the core, :mod:`pipeplug_harness.bench.batch`) is measured in the same run.
Output (``--out``): ``cost.csv``, ``cost_comm.csv``, ``cost_creep.csv``, ``cost_pareto.png``,
``cost_creep.png`` and ``cost.md`` (also printed); progress goes to stderr.
"""
from __future__ import annotations

import contextlib
import os
import platform
import sys
import warnings
from pathlib import Path

import numpy as np
import scipy

from pipeplug_harness import io

from . import report
from .batch import TARGET as BATCH_TARGET
from .batch import throughput
from .cases import creep_cases, default_cases, quick_cases
from .core import MIN_TIME, TIME_BUDGET
from .creep import creep_sweep
from .front import TARGET
from .plots import creep_plot, pareto_plot
from .regularised import MAX_CALLS
from .sweep import (
    COMPILED,
    REGULARISED,
    RIGID_FAMILIES,
    Config,
    comm_step_sweep,
    elastic_sweep,
    prepare_compiled,
    progress,
    sweep,
)

ROW_COLUMNS = ("method", "setting", "case", "max_rel_error", "max_rel_disp_error", "wall_s",
               "success")
#: column -> unit of the CSV files
UNITS = {"wall_s": "s", "step_s": "s", "eps": "m/s", "pipe_creep_m": "m", "plug_creep_m": "m",
         "pipe_residual_v": "m/s", "plug_residual_v": "m/s", "creep_speed_theory": "m/s"}
CREEP_COLUMNS = ("method", "eps", "case", "pipe_creep_m", "pipe_residual_v", "plug_creep_m",
                 "plug_residual_v", "creep_speed_theory", "wall_s", "success")


def default_config() -> Config:
    """The full study (about ten minutes on two cores)."""
    return Config(cases=default_cases(),
                  fd_dts=(2e-4, 1e-4, 4e-5, 2e-5, 1e-5, 4e-6, 2e-6, 1e-6),
                  methods=("odeint-LSODA", "LSODA", "BDF", "Radau"),
                  eps=(1e-4, 1e-5, 1e-6, 1e-7, 1e-8), rtols=(1e-6, 1e-8, 1e-10, 1e-12),
                  atol_scale=1e-3, elastic_dxs=(0.05, 0.02, 0.01),
                  comm_rates=(1000, 2000, 5000, 10000, 50000),
                  creep_eps=(1e-2, 1e-3, 1e-4, 1e-5, 1e-6), creep_rtol=1e-8, repeats=25,
                  batch_cases=20_000, compiled=COMPILED)


def quick_config() -> Config:
    """A tiny study for the tests: two short cases, few settings, three repeats."""
    return Config(cases=quick_cases(), fd_dts=(2e-4, 4e-5, 1e-5),
                  methods=("LSODA", "odeint-LSODA", "Radau"),
                  eps=(1e-3, 1e-5), rtols=(1e-6,), atol_scale=1e-3, elastic_dxs=(0.1,),
                  comm_rates=(1000, 5000), creep_eps=(1e-3, 1e-5), creep_rtol=1e-8, repeats=3,
                  batch_cases=200)


def add_arguments(parser) -> None:
    """Options of ``pipeplug cost``."""
    parser.add_argument("--out", type=Path, default=Path("out/cost"),
                        help="output folder (default: out/cost)")
    parser.add_argument("--quick", action="store_true",
                        help="a tiny run (two cases, few settings) for tests")


@contextlib.contextmanager
def _quiet_solvers():
    """Silence scipy's warnings and ODEPACK's Fortran messages (written straight to fd 1)."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as null, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            os.dup2(null.fileno(), 1)
            yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def run_study(config: Config) -> dict:
    """All measurements of the study: {"rows", "elastic", "elastic_note", "comm", "creep"}."""
    with _quiet_solvers():
        progress("compiled competitors")
        prepared, missing = prepare_compiled(config)
        rows = sweep(config, tuple(prepared))
        progress("elastic model")
        elastic, note = elastic_sweep(config)
        progress("communication step")
        comm = comm_step_sweep(config)
        progress("creep")
        creep = creep_sweep(config, creep_cases(config.cases))
    progress("batch throughput")
    batch = throughput(config.batch_cases, repeat=3)
    return {"rows": rows, "elastic": elastic, "elastic_note": note, "comm": comm, "creep": creep,
            "batch": batch, "prepared": prepared,
            "missing": missing}


def _setup(config: Config, study: dict) -> list[str]:
    cases = ", ".join(f"{b.name} ({'model II' if b.growth else 'model I'}, to {b.t_end:g} s)"
                      for b in config.cases)
    return [f"- cases: {cases}; samples every {1e3 / config.cases[0].rate:g} ms, t0 among them.",
            "- error: max over the samples of |V - V_exact| of pipe and plug / max |V1_exact|; "
            "model II measured against the exact solver (so its own error there is 0).",
            f"- time: best of at least {config.repeats} repeats and {MIN_TIME:g} s of repeats "
            f"(stopping after {TIME_BUDGET:g} s) of build + run, in this process, without the "
            "FMU.",
            f"- regularised: tanh(v/eps), eps in {list(config.eps)} m/s, rtol in "
            f"{list(config.rtols)}, atol = {config.atol_scale:g} rtol; two segments split at t0; "
            "analytic Jacobian; right-hand side in Python; a run stops as failed after "
            f"{MAX_CALLS:,} right-hand-side evaluations.",
            "- compiled competitors: the same regularised model and grid, right-hand side and "
            "Jacobian compiled (numba; jax for diffrax), and the fd scheme compiled (numba) at "
            "the fd steps; compile and jit times apart, below.",
            f"- exact solver: {'compiled (numba)' if study['batch']['compiled'] else 'plain Python'}"
            ", dense output at the sample times; its time is the single-case API's call, "
            "`build_model` then `sample`, on a parameter mapping and arrays made beforehand.",
            f"- machine: {platform.machine()}, {os.cpu_count()} cores, Python "
            f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}."]


def markdown(config: Config, study: dict) -> str:
    """The report: headline ratios, per-case times, fronts, elastic, communication step, creep."""
    families = [f for f in RIGID_FAMILIES if any(r["method"] == f for r in study["rows"])]
    n = len(config.cases)
    versus, _ = report.versus_regularised(study["rows"], [f for f in families if f in REGULARISED])
    parts = ["# What accuracy costs in time", "", *_setup(config, study), "",
             f"## Exact against the fastest regularised setting that reaches {TARGET:g}", "",
             "Case by case, measured times (no interpolation): every regularised family and "
             "setting is a candidate.", "", *versus, "",
             *_compiled_section(study, families), "",
             f"## Time to reach a relative error of {TARGET:g} (all {n} cases together)", "",
             "Each setting is one point: its largest error over the cases and its total time; "
             "the time to the target is interpolated (log-log) on each method's Pareto front.",
             "", *report.headline(study["rows"], families), "",
             "The fd scheme's step velocities are exact at its grid points while the forces are "
             "constant (model I between events), so its velocity error comes from the steps "
             "that contain an event and need not shrink on nested grids; its displacement error "
             "is O(dt).", "",
             f"## Time to reach {TARGET:g}, case by case [ms]", "",
             *report.per_case(study["rows"], families), "",
             "## Pareto fronts (all cases together)", "", *report.fronts(study["rows"], families),
             "", "## Elastic model III (a different model: difference from the rigid closed form)",
             ""]
    if study["elastic"]:
        parts += ["Velocities and displacements at x_monitor = 0.5 m.", "",
                  *report.elastic_table(study["elastic"])]
    else:
        parts.append(f"Not run: {study['elastic_note']}")
    batch = study["batch"]
    parts += ["", "## Batch throughput (single blows through the core)", "",
              f"`pipeplug.batch.blows`, {batch['cases']:,} random cases (parameters over the "
              "paper's range, models I and II), each a blow of 23 kN for 50 ms from rest until "
              "all is at rest, model build included: "
              f"**{batch['rate']:,.0f} cases/s** on one core (target >= {BATCH_TARGET:,}); "
              f"the same API as plain Python: {batch['rate_python']:,.0f} cases/s; "
              f"build_model + advance one by one: {batch['rate_one_by_one']:,.0f} cases/s.",
              "", "## Communication step (core driven through advance, model I cases)", "",
              "Errors at the communication points (largest over the cases), total times.", "",
              *report.comm_table(study["comm"]), "",
              "## Creep while a body should be stuck", "",
              "After each body's closed-form stop time (+1 ms) until the end of the run; the "
              f"regularised runs use LSODA with rtol = {config.creep_rtol:g}.", "",
              *report.creep_table(study["creep"]), ""]
    return "\n".join(parts)


def _compiled_section(study: dict, families) -> list[str]:
    """Exact against the compiled competitors, their one-time costs, and those not run."""
    ran = [f for f in families if f in COMPILED]
    parts = ["## Exact against the compiled competitors", ""]
    if ran:
        versus, _ = report.versus_compiled(study["rows"], ran)
        parts += ["Case by case, measured times: every compiled family and setting is a "
                  "candidate.", "", *versus, "", "One-time costs (first call: numba compiling, "
                  "jax tracing and compiling; not in any time above):", ""]
        parts += [f"- {f}: {s:.1f} s" for f, s in study["prepared"].items()]
        parts += ["", report.same_as_fd(study["rows"])] if "fd-compiled" in ran else []
    else:
        parts.append("No compiled competitor ran.")
    if study["missing"]:
        parts += ["", "Not run:", ""] + [f"- {f}: {why}" for f, why in study["missing"].items()]
    return parts


def main(args) -> int:
    """Run the study, write the files into ``args.out``, print the report."""
    config = quick_config() if args.quick else default_config()
    with io.OutputFolder(args.out, "cost") as out:
        study = run_study(config)
        io.write_records(out.file("cost.csv"), study["rows"] + study["elastic"], ROW_COLUMNS,
                         UNITS)
        io.write_records(out.file("cost_comm.csv"), study["comm"], ROW_COLUMNS + ("step_s",),
                         UNITS)
        io.write_records(out.file("cost_creep.csv"), study["creep"], CREEP_COLUMNS, UNITS)
        families = [f for f in RIGID_FAMILIES if any(r["method"] == f for r in study["rows"])]
        pareto_plot(study["rows"], families, len(config.cases), out.file("cost_pareto.png"))
        creep_plot(study["creep"], out.file("cost_creep.png"))
        text = markdown(config, study)
        out.file("cost.md").write_text(text)
    print(text)
    return 0
