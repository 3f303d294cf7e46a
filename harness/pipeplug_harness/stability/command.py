"""``pipeplug stability``: the hard cases of dry-friction integrators, case by solver.

Runs every case of :data:`pipeplug_harness.stability.cases.CATALOGUE` on each solver it
applies to (the core's exact, fd and elastic models), compares the outputs with the case's
exact reference, checks that they stay finite and that the energy balances, and continues
each run for a long time after the motion has stopped to measure any creep. With ``--fmu``
the rigid cases are also run through the FMU with fmpy. Prints the table, writes it as
``stability.csv`` and ``stability.md`` into ``--out``, and exits non-zero if any row fails.

Columns: ``err v``/``err u`` -- largest velocity/displacement error relative to the
reference's peaks; ``energy`` -- (W_input - E_kinetic - E_strain - W_friction - W_numerical) /
W_input at the end (round-off: fd books its dissipation as W_numerical); ``drift v`` [m/s] / ``drift u`` [m] --
largest speed and displacement change over the long run after the motion stopped ("-" where
the motion never stops).
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pipeplug_harness import io
from pipeplug_harness.errors import UserError

from .cases import CATALOGUE, QUICK
from .runs import build_for, errors, measure, reference_for, run_case, tolerance

_COLUMNS = ("case", "solver", "reference", "err_v", "err_u", "tol_v", "tol_u", "finite",
            "energy", "long_steps", "drift_v", "drift_u", "ok")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", default="out/stability", help="output folder (%(default)s)")
    parser.add_argument("--quick", action="store_true",
                        help=f"only the cases {', '.join(QUICK)}, with short long runs")
    parser.add_argument("--long-steps", type=int, default=None,
                        help="steps of the long run after the motion stopped "
                             "(default 1000000; 1000 with --quick)")
    parser.add_argument("--fmu", default=None,
                        help="also run the rigid cases through this FMU with fmpy (\"cached\": "
                             "the build of this installation)")


def main(args: argparse.Namespace) -> int:
    long_steps = args.long_steps or (1000 if args.quick else 1_000_000)
    if long_steps < 1:
        raise UserError(key="--long-steps", value=args.long_steps, allowed=">= 1")
    args.limits.check("steps", long_steps, f"--long-steps {long_steps}")
    args.limits.memory(long_steps * 16, f"--long-steps {long_steps} of every output")
    fmu = None
    if args.fmu:
        from pipeplug_harness.fmus import find_fmu
        fmu = find_fmu(None if args.fmu == "cached" else args.fmu)
    with io.OutputFolder(args.out, "stability") as out:
        return _run(args, out, long_steps, fmu)


def _run(args, out, long_steps: int, fmu) -> int:
    cases = [c for c in CATALOGUE if not args.quick or c.name in QUICK]
    rows, start = [], time.perf_counter()
    for case in cases:
        exact_run = None
        if case.reference == "exact solver":
            exact_run = run_case(case, build_for(case, "exact"))
        for solver in case.solvers:
            rows.append(measure(case, solver, long_steps, exact_run))
        if fmu is not None:
            rows += _fmu_rows(case, fmu)
    table = markdown(rows)
    io.write_records(out.file("stability.csv"), rows, _COLUMNS,
                     {"drift_v": "m/s", "drift_u": "m"})
    out.file("stability.md").write_text(table + "\n")
    failed = [r for r in rows if not r["ok"]]
    print(table)
    print(f"\n{len(rows) - len(failed)} passed, {len(failed)} failed "
          f"({time.perf_counter() - start:.1f} s; long runs of {long_steps} steps)")
    for r in failed:
        print(f"FAILED: {r['case']} / {r['solver']}")
    return 1 if failed else 0


def _fmu_rows(case, fmu: str) -> list[dict]:
    """The rigid solvers of ``case`` through the FMU with fmpy (no long run)."""
    from pipeplug_harness.load import Load
    from pipeplug_harness.session import simulate

    rows = []
    for solver in ("exact", "fd"):
        if solver not in case.solvers or case.growth:
            continue
        values = {**case.params, "solver": solver, "dt": case.fd_dt}
        result = simulate(fmu, values, Load.from_pulses(case.pulses), case.step,
                          case.t_end)[1:]         # the first row is t = 0
        out = {name: np.asarray(result[name], dtype=float) for name in result.dtype.names}
        ref = reference_for(case, out["time"], None)
        err_v, err_u = errors(out, ref, case) if ref is not None else (math.nan, math.nan)
        tol_v, tol_u = tolerance(case, solver)
        finite = all(bool(np.all(np.isfinite(v))) for v in out.values())
        rows.append({"case": case.name, "solver": f"FMU {solver}", "reference": case.reference,
                     "err_v": err_v, "err_u": err_u, "tol_v": tol_v, "tol_u": tol_u,
                     "finite": finite, "energy": math.nan, "long_steps": 0,
                     "drift_v": math.nan, "drift_u": math.nan,
                     "ok": finite and not (err_v > tol_v or err_u > tol_u)})
    return rows


def markdown(rows: list[dict]) -> str:
    """The table in markdown."""
    lines = []
    for r in rows:
        tol = (_num(r["tol_v"]) if r["tol_v"] == r["tol_u"] or math.isnan(r["tol_u"])
               else f"{_num(r['tol_v'])} / {_num(r['tol_u'])}")
        lines.append([r["case"], r["solver"], r["reference"], _num(r["err_v"]), _num(r["err_u"]),
                      tol, "yes" if r["finite"] else "NO", _num(r["energy"]),
                      _num(r["drift_v"]), _num(r["drift_u"]), "yes" if r["ok"] else "NO"])
    return io.markdown_table(["case", "solver", "reference", "err v", "err u", "tolerance",
                              "finite", "energy", "drift v (m/s)", "drift u (m)", "ok"], lines)


def _num(x: float) -> str:
    """A short number: "-" for nan, "0" for zero, else 1.2e-03."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return "0" if x == 0 else f"{x:.1e}"
