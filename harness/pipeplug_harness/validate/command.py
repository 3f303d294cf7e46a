"""``pipeplug validate``: the FMU against the closed form of model I, case by case.

Runs the paper's figure cases (Figs. 3, 4, 5, 6a) and random single pulses (amplitude,
duration off the communication grid, friction levels across all five domains) through the
FMU with fmpy, for each rigid solver, and compares every output with the independent closed
form. Prints a table of maximum errors, writes it as CSV, writes the FMI cross-check files
``PipePlug_in.csv``, ``PipePlug_ref.csv``, ``PipePlug_ref.opt``, and exits non-zero if any
case fails its tolerance (usable in a CI pipeline).
"""
from __future__ import annotations

import argparse
import csv
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from pipeplug import PARAMETERS
from pipeplug_fmu.fmi import DEFAULT_EXPERIMENT
from pipeplug_harness.fmu_run import DEFAULT_FMU, Pulse, Run, load_signal, run_fmu
from pipeplug_references import closed_form as cf

#: solver -> (FMU start values, tolerance on errors relative to the peaks)
SOLVERS = {"exact": ({"solver": "exact"}, 1e-9), "fd": ({"solver": "fd", "dt": 2e-4}, 1e-2)}
COMPARED = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fmu", default=str(DEFAULT_FMU), help="the FMU (default: %(default)s)")
    parser.add_argument("--out", default="out/validate", help="output folder (%(default)s)")
    parser.add_argument("--random", type=int, default=12, help="random pulses (%(default)s)")
    parser.add_argument("--seed", type=int, default=2024, help="random seed (%(default)s)")
    parser.add_argument("--step", type=float, default=1e-3,
                        help="communication step [s] (%(default)s)")


def cases(n_random: int, seed: int) -> list[tuple[str, cf.Case]]:
    """Named closed-form cases: the figure curves, then random single pulses."""
    named = [(f"fig{fig}-{i + 1}", c) for fig, group in cf.figure_cases().items()
             for i, c in enumerate(group)]
    rng = np.random.default_rng(seed)
    base = cf.Case()
    for i in range(n_random):
        tau1, tau2 = rng.uniform(0.0, 1.1, 2) * base.tau_star * (rng.random(2) > 0.1)
        case = replace(base, tau1=float(tau1), tau2=float(tau2),
                       Q0=float(rng.uniform(5e3, 5e4)), t0=float(rng.uniform(0.005, 0.08)))
        named.append((f"random-{i + 1}", case))
    return named


def _stop_time(case: cf.Case) -> float:
    finite = [t for t in cf.stop_times(case) if t is not None and math.isfinite(t)]
    return float(np.clip(1.15 * max(finite + [case.t0]), 0.1, 1.0))


def _run_for(case: cf.Case, solver_values: dict, step: float) -> Run:
    params = {k: getattr(case, k) for k in ("L1", "L2", "R1", "h1", "rho1", "rho2", "tau1",
                                             "tau2")}
    return Run(params={**params, **solver_values}, pulses=[Pulse(0.0, case.t0, case.Q0)],
               step=step, stop_time=_stop_time(case))


def compare(case: cf.Case, result: np.ndarray) -> dict:
    """Maximum errors of an FMU result against the closed form, relative to the peaks."""
    ref = cf.solution(case, result["time"])
    v_peak = max(np.abs(ref["V1"]).max(), np.abs(ref["V2"]).max(), 1e-300)
    u_peak = max(np.abs(ref["U1"]).max(), np.abs(ref["U2"]).max(), 1e-300)
    err = {}
    for ours, theirs in COMPARED.items():
        peak = v_peak if ours.startswith("v") else u_peak
        err[ours] = float(np.abs(result[ours] - ref[theirs]).max() / peak)
    return err


def main(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows, failures = [], 0
    for name, case in cases(args.random, args.seed):
        for solver, (values, tol) in SOLVERS.items():
            result = run_fmu(_run_for(case, values, args.step), args.fmu)
            err = compare(case, result)
            worst = max(err.values())
            ok = worst <= tol
            failures += not ok
            rows.append(dict(case=name, domain=cf.domain(case), solver=solver,
                             tau1=case.tau1, tau2=case.tau2, Q0=case.Q0, t0=case.t0,
                             **{f"err_{k}": v for k, v in err.items()}, worst=worst,
                             tolerance=tol, passed=ok))
    _write_csv(out / "validate.csv", rows)
    write_cross_check(out)
    print(_table(rows))
    print(f"\n{len(rows) - failures} passed, {failures} failed")
    return 1 if failures else 0


def _write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _table(rows: list[dict]) -> str:
    """A short markdown table: the worst error per solver and domain."""
    lines = ["| solver | domain | cases | max error (velocities) | max error (displacements) "
             "| tolerance | failed |", "|---|---|---|---|---|---|---|"]
    keys = sorted({(r["solver"], r["domain"]) for r in rows})
    for solver, dom in keys:
        sel = [r for r in rows if r["solver"] == solver and r["domain"] == dom]
        ev = max(max(r["err_v_pipe"], r["err_v_plug"]) for r in sel)
        eu = max(max(r["err_u_pipe"], r["err_u_plug"]) for r in sel)
        lines.append(f"| {solver} | {dom} | {len(sel)} | {ev:.2e} | {eu:.2e} | "
                     f"{sel[0]['tolerance']:.0e} | {sum(not r['passed'] for r in sel)} |")
    return "\n".join(lines)


#: The cross-check case: the FMU's own defaults (a third party simulates with them), under the
#: paper's blow, on the FMU's DefaultExperiment. Reference columns: every output the closed form
#: gives that is continuous in time (forces jump at friction events).
CROSS_CHECK_BLOW = Pulse(0.0, 0.05, 23e3)
CROSS_CHECK_COLUMNS = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2",
                       "W_input": "W_input", "W_friction": "W_friction"}


def write_cross_check(out: Path) -> None:
    """FMI cross-check files ``PipePlug_in.csv``, ``PipePlug_ref.csv``, ``PipePlug_ref.opt``.

    The case is the FMU at its default start values (the cross-check rules simulate the FMU
    with its defaults and the ``_in.csv`` input), the reference the closed form of that case at
    the ``.opt`` file's output points; no FMU run is involved.
    """
    defaults = {p.name: p.default for p in PARAMETERS}
    case = cf.Case(**{k: defaults[k] for k in ("L1", "L2", "R1", "h1", "rho1", "rho2", "tau1",
                                               "tau2")},
                   Q0=CROSS_CHECK_BLOW.amplitude, t0=CROSS_CHECK_BLOW.duration)
    start, stop, step = DEFAULT_EXPERIMENT
    signal = load_signal(Run(pulses=[CROSS_CHECK_BLOW], stop_time=stop))
    with open(out / "PipePlug_in.csv", "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["time", "Q"])
        writer.writerows((repr(float(t)), repr(float(q))) for t, q in signal)
    t = np.linspace(start, stop, round((stop - start) / step) + 1)
    ref = cf.solution(case, t)
    with open(out / "PipePlug_ref.csv", "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["time", *CROSS_CHECK_COLUMNS])
        for i, ti in enumerate(t):
            writer.writerow([repr(float(ti))]
                            + [repr(float(ref[k][i])) for k in CROSS_CHECK_COLUMNS.values()])
    (out / "PipePlug_ref.opt").write_text(
        f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\nRelTol, 1e-09\n")
