"""``pipeplug validate``: the FMU against the closed form of model I, case by case.

Runs the paper's figure cases (Figs. 3, 4, 5, 6a) and random single pulses (amplitude,
duration off the communication grid, friction levels across all five domains) through the
FMU with fmpy, for each rigid solver, and compares every output with the independent closed
form. Prints a table of maximum errors, writes it as CSV, writes the FMI cross-check files
``PipePlug_in.csv``, ``PipePlug_ref.csv``, ``PipePlug_ref.opt``, and exits non-zero if any
case fails its tolerance (usable in a CI pipeline). ``--fmi 3`` does the same with the FMI 3.0
FMU, and writes its cross-check files in the folders of the cross-check rules' layout,
``fmus/3.0/cs/x86_64-linux/PipePlug/<version>/PipePlug/`` (FMI 3.0's platform name; the tool
is this project at its version), the FMU beside them.
"""
from __future__ import annotations

import argparse
import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np

from pipeplug import PARAMETERS
from pipeplug_fmu.fmi import DEFAULT_EXPERIMENT
from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.fmus import add_fmi_argument, find_fmu
from pipeplug_harness.load import Load
from pipeplug_harness.paper import (
    PARAMETER_UNITS,
    Q0,
    RIGID_PARAMETERS,
    SYMBOLS,
    T0,
    rigid_values,
)
from pipeplug_harness.session import fmi_version, simulate
from pipeplug_references import closed_form as cf

#: solver -> (FMU start values, tolerance on errors relative to the peaks)
SOLVERS = {"exact": ({"solver": "exact"}, 1e-9), "fd": ({"solver": "fd", "dt": 2e-4}, 1e-2)}
COMPARED = SYMBOLS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fmu", help="the FMU (default: the build of this installation, made "
                                      "once into the user's cache)")
    parser.add_argument("--out", default="out/validate", help="output folder (%(default)s)")
    parser.add_argument("--random", type=int, default=12, help="random pulses (%(default)s)")
    parser.add_argument("--seed", type=int, default=2024, help="random seed (%(default)s)")
    parser.add_argument("--step", type=float, default=1e-3,
                        help="communication step [s] (%(default)s)")
    add_fmi_argument(parser)


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


def _run(fmu, case: cf.Case, solver_values: dict, step: float) -> np.ndarray:
    """The FMU's run of a closed-form case (one pulse from rest)."""
    return simulate(fmu, {**rigid_values(case), **solver_values},
                    Load.from_pulses([(0.0, case.t0, case.Q0)]), step, _stop_time(case))


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
    if args.random < 0:
        raise UserError(key="--random", value=args.random, allowed=">= 0")
    if not (args.step > 0.0 and math.isfinite(args.step)):
        raise UserError(key="--step", value=args.step, allowed="> 0 s")
    args.limits.check("steps", 1.0 / args.step, f"--step {args.step!r} s over a case of up to 1 s")
    args.limits.check("cases", args.random, f"--random {args.random}")
    args.limits.memory(2 * args.random * 20, f"--random {args.random} cases' rows")
    fmu = find_fmu(args.fmu, fmi=args.fmi)
    fmi_version(fmu, args.fmi)
    with io.OutputFolder(args.out, "validate") as out:
        rows, failures = [], 0
        for name, case in cases(args.random, args.seed):
            for solver, (values, tol) in SOLVERS.items():
                err = compare(case, _run(fmu, case, values, args.step))
                worst = max(err.values())
                ok = worst <= tol
                failures += not ok
                rows.append(dict(case=name, domain=cf.domain(case), solver=solver,
                                 tau1=case.tau1, tau2=case.tau2, Q0=case.Q0, t0=case.t0,
                                 **{f"err_{k}": v for k, v in err.items()}, worst=worst,
                                 tolerance=tol, passed=ok))
        io.write_records(out.file("validate.csv"), rows,
                         units={"tau1": PARAMETER_UNITS["tau1"], "tau2": PARAMETER_UNITS["tau2"],
                                "Q0": "N", "t0": "s"})
        write_cross_check(out, args.fmi)
        if args.fmi == 3 and Path(fmu).is_file():        # the rules' layout holds the FMU
            shutil.copyfile(fmu, _cross_check_file(out, 3, "PipePlug.fmu"))
    print(_table(rows))
    print(f"\n{len(rows) - failures} passed, {failures} failed")
    return 1 if failures else 0


def _table(rows: list[dict]) -> str:
    """A short markdown table: the worst error per solver and domain."""
    lines = []
    for solver, dom in sorted({(r["solver"], r["domain"]) for r in rows}):
        sel = [r for r in rows if r["solver"] == solver and r["domain"] == dom]
        ev = max(max(r["err_v_pipe"], r["err_v_plug"]) for r in sel)
        eu = max(max(r["err_u_pipe"], r["err_u_plug"]) for r in sel)
        lines.append([solver, dom, len(sel), f"{ev:.2e}", f"{eu:.2e}",
                      f"{sel[0]['tolerance']:.0e}", sum(not r["passed"] for r in sel)])
    return io.markdown_table(["solver", "domain", "cases", "max error (velocities)",
                              "max error (displacements)", "tolerance", "failed"], lines)


#: The cross-check case: the FMU's own defaults (a third party simulates with them), under the
#: paper's blow, on the FMU's DefaultExperiment. Reference columns: every output the closed form
#: gives that is continuous in time (forces jump at friction events).
CROSS_CHECK_BLOW = (0.0, T0, Q0)
CROSS_CHECK_COLUMNS = {**SYMBOLS, "W_input": "W_input", "W_friction": "W_friction"}


#: Where the FMI 3.0 cross-check files go in the output folder: the cross-check rules' layout
#: ``fmus/<FMI version>/<type>/<platform>/<tool>/<tool version>/<model>`` with FMI 3.0's name
#: of the platform the loader runs on.
CROSS_CHECK_3 = ("fmus", "3.0", "cs", "x86_64-linux")


def _cross_check_prefix(fmi: int) -> str:
    """Where the cross-check files go in the output folder: at its top (FMI 2.0), or in the
    rules' layout (FMI 3.0), the tool being this project at its version."""
    if fmi == 2:
        return ""
    from pipeplug import __version__
    return "/".join((*CROSS_CHECK_3, "PipePlug", __version__, "PipePlug")) + "/"


def _cross_check_file(out, fmi: int, name: str) -> Path:
    path = out.file(_cross_check_prefix(fmi) + name)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def write_cross_check(out, fmi: int = 2) -> Path:
    """FMI cross-check files ``PipePlug_in.csv``, ``PipePlug_ref.csv``, ``PipePlug_ref.opt``
    into the output folder ``out`` (FMI 2.0), or into its cross-check layout's folder (FMI
    3.0: :data:`CROSS_CHECK_3`); returns their folder.

    The case is the FMU at its default start values (the cross-check rules simulate the FMU
    with its defaults and the ``_in.csv`` input), the reference the closed form of that case at
    the ``.opt`` file's output points; no FMU run is involved. The rules fix the headers: plain
    variable names, no units.
    """
    defaults = {p.name: p.default for p in PARAMETERS}
    case = cf.Case(**{k: defaults[k] for k in RIGID_PARAMETERS},
                   Q0=CROSS_CHECK_BLOW[2], t0=CROSS_CHECK_BLOW[1])
    start, stop, step = DEFAULT_EXPERIMENT
    signal = Load.from_pulses([CROSS_CHECK_BLOW]).signal(stop)
    io.write_csv(_cross_check_file(out, fmi, "PipePlug_in.csv"), ["time", "Q"], signal[["time", "Q"]].tolist(),
                 titles=["time", "Q"])
    t = np.linspace(start, stop, round((stop - start) / step) + 1)
    ref = cf.solution(case, t)
    names = ["time", *CROSS_CHECK_COLUMNS]
    io.write_csv(_cross_check_file(out, fmi, "PipePlug_ref.csv"), names,
                 ([ti] + [ref[k][i] for k in CROSS_CHECK_COLUMNS.values()]
                  for i, ti in enumerate(t)), titles=names)
    opt = _cross_check_file(out, fmi, "PipePlug_ref.opt")
    opt.write_text(
        f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\nRelTol, 1e-09\n")
    return opt.parent
