"""``pipeplug fuzz``: differential fuzzing of the rigid models I and II.

Runs ``--cases`` random cases of the run ``--seed`` (see :mod:`.cases`) through every core
path: invariants on every case, the independent reference on every ``--reference-every``-th,
the FMU (one instance, hosts stepping t += h and t = k h) on every ``--fmu-every``-th, the
fd scheme on every ``--fd-every``-th. Prints the summary table (cases, failures by check,
worst values, time), writes it to ``--out``/summary.txt, saves each failing case as a JSON
file in ``--out``/failures (replay it with ``--replay FILE``) and exits 1 if any case failed. A
rerun into the same folder first removes the files the earlier run wrote there (its manifest's).
``--fit-fd-constant`` runs the fd check alone on ``--cases`` cases and prints the fit of the
constant of the fd bound.
"""
from __future__ import annotations

import argparse

import numpy as np

from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.fmus import find_fmu

from .cases import Plan
from .checks import CHECKS
from .elastic_run import ELASTIC_PATHS
from .engine import MODELS, fuzz, run_one
from .paths import CORE_PATHS
from .report import load_failure
from .run import Setup

__all__ = ["add_arguments", "main", "replay", "fit_fd_constant"]

def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--model", choices=tuple(MODELS), default="rigid",
                        help="rigid: models I and II (exact solver, reference, fd); elastic: "
                             "model III (with rams); ram: model I with a ram (exact solver, "
                             "reference with a ram, FMU strikes); growth: models I and II with "
                             "a plug that grows and clean-outs (exact solver, reference of the "
                             "growing plug) (default: %(default)s)")
    parser.add_argument("--cases", type=int, default=1000, help="number of cases (%(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the run (%(default)s)")
    parser.add_argument("--start", type=int, default=0,
                        help="index of the first case (%(default)s)")
    parser.add_argument("--scheduler", default=None,
                        help="address of a running Dask scheduler (e.g. tcp://10.0.0.5:8786); "
                             "default: a LocalCluster on this machine")
    parser.add_argument("--workers", type=int, default=None,
                        help="LocalCluster worker processes (default: one per core)")
    parser.add_argument("--reference-every", type=int, default=10,
                        help="compare every N-th case with the reference (%(default)s; 0: none)")
    parser.add_argument("--fmu-every", type=int, default=20,
                        help="run every N-th case through the FMU (%(default)s; 0: none)")
    parser.add_argument("--fd-every", type=int, default=100,
                        help="run every N-th case through the fd check (%(default)s; 0: none)")
    parser.add_argument("--paths", default=None,
                        help=f"core paths, comma-separated, among {', '.join(CORE_PATHS)} "
                             "(default: all; with --replay: those of the file)")
    parser.add_argument("--fmu", default=None,
                        help="the FMU (file or extracted folder; default: the build of this "
                             "installation, made once into the user's cache)")
    parser.add_argument("--no-fmu", action="store_true", help="run no case through the FMU")
    parser.add_argument("--out", default="out/fuzz", help="output folder (%(default)s)")
    parser.add_argument("--replay", default=None, metavar="FILE",
                        help="run the case saved in FILE and print every check")
    parser.add_argument("--fit-fd-constant", action="store_true",
                        help="fit the constant of the fd bound on --cases cases")


def main(args: argparse.Namespace) -> int:
    given = args.paths if args.paths is not None else ",".join(CORE_PATHS)
    paths = tuple(p for p in given.split(",") if p)          # --paths '' names none: refused
    unknown = [p for p in paths if p not in CORE_PATHS]
    if unknown or not paths:
        raise UserError(key="--paths", value=args.paths, allowed=", ".join(CORE_PATHS))
    for flag in ("cases", "reference_every", "fmu_every", "fd_every", "start", "workers", "seed"):
        value = getattr(args, flag)
        if value is not None and value < (1 if flag in ("cases", "workers") else 0):
            raise UserError(key=f"--{flag.replace('_', '-')}", value=value,
                            allowed=">= 1" if flag in ("cases", "workers") else ">= 0")
    args.limits.check("cases", args.cases, f"--cases {args.cases}")
    if args.no_fmu and args.fmu is not None:
        raise UserError(key="--fmu", value=args.fmu, allowed="none with --no-fmu (which runs no "
                                                          "case through an FMU)")
    if args.replay:
        return replay(args.replay, Setup(paths), paths_given=args.paths is not None,
                      fmu=lambda: _fmu(args))
    plan = Plan(args.reference_every, 0 if args.no_fmu else args.fmu_every, args.fd_every,
                args.model)
    # the FMU found (or refused) before the output folder is touched
    setup = Setup(paths, fmu=_fmu(args) if plan.fmu and not args.fit_fd_constant else None)
    with io.OutputFolder(args.out, "fuzz") as out:
        # A run's files are its summary and failing cases: an earlier run's failure files left
        # beside them would read as this run's, so they go before this run writes.
        out.remove_owned()
        if args.fit_fd_constant:
            return fit_fd_constant(args, Setup(paths), out)
        indices = range(args.start, args.start + args.cases)
        summary, seconds, workers = _on_dask(args, indices, plan, setup, out)
        shown = tuple(ELASTIC_PATHS) if args.model == "elastic" else paths
        title = (f"pipeplug fuzz --model {args.model} --seed {args.seed} --start {args.start} "
                 f"--cases {args.cases} (paths: {', '.join(shown)})")
        table = f"{title}\n{summary.table(seconds, workers)}"
        print(table)
        out.file("summary.txt").write_text(table + "\n")
        if summary.failures:
            print(f"\n{summary.failures} failing case(s) saved in {out.path / 'failures'}")
    return 1 if summary.failures else 0


def _on_dask(args, indices, plan, setup, failures):
    """The run on a Dask cluster (the one parallel back end): summary, seconds, workers. The
    FMU's path is made absolute: every worker must be able to read it there."""
    from dataclasses import replace
    from pathlib import Path

    from pipeplug_harness.sweep.cluster import dask_client
    if setup.fmu:
        setup = replace(setup, fmu=str(Path(setup.fmu).resolve()))
    with dask_client(args.scheduler, args.workers) as client:
        workers = len(client.scheduler_info()["workers"])
        summary, seconds = fuzz(args.seed, indices, plan, setup, failures=failures,
                                client=client)
    return summary, seconds, workers


def _fmu(args) -> str | None:
    """The FMU to use: --fmu, or the build of this installation."""
    if args.no_fmu:
        return None
    return str(find_fmu(args.fmu))


def replay(file: str, setup: Setup | None = None, paths_given: bool = False, fmu=None) -> int:
    """Run the case saved in ``file`` on the paths it names (unless ``paths_given``: those
    of ``setup``) and print every check's value; 1 if any fails. ``fmu()`` gives the FMU
    when the case runs through it."""
    case, data = load_failure(file)
    setup = setup or Setup()
    paths = setup.paths if paths_given or not data.get("paths") else tuple(data["paths"])
    unknown = [p for p in paths if p not in CORE_PATHS]
    if unknown:
        raise UserError(f"names core path(s) {unknown} not in this build; allowed: "
                        f"{', '.join(CORE_PATHS)} (choose with --paths)", file=file)
    needs_fmu = "fmu" in case.checks and fmu is not None
    setup = Setup(paths, setup.fd_path, fmu() if needs_fmu else setup.fmu)
    result = run_one(case, setup)
    print(f"case {case.seed}:{case.index}, model {case.model}, checks {', '.join(case.checks)}")
    load = (f"segments {list(case.segments)}" if hasattr(case, "segments")
            else f"edges {list(case.edges)}\nloads {list(case.loads)}")
    print(f"params {case.params}\n{load}\nstop {case.stop!r} s")
    failed = set(result.failed)
    for (check, subject), value in sorted(result.values.items()):
        mark = "FAILED" if (check, subject) in failed else "ok"
        print(f"  {check} [{subject}]: {value:.3e} (tolerance {CHECKS[check].tolerance:.0e})"
              f"  {mark}")
    for (check, subject), message in result.errors.items():
        print(f"  {check} [{subject}]: {message}")
    return 1 if failed else 0


def fit_fd_constant(args, setup: Setup, out) -> int:
    """Run the fd check (and the reference) on every case and print the fit of the fd
    bound's constant: ``C = 1.5 max K`` over the resolved cases (K = E / dt at the three
    levels, see :mod:`.fdcheck`; the order fit E ~ K dt^p gives p ~ 1, so K is the constant
    of the fit). Failing cases are saved in the output folder and listed."""
    seed, start, cases = args.seed, args.start, args.cases
    plan = Plan(reference=1, fmu=0, fd=1)
    summary, seconds, _ = _on_dask(args, range(start, start + cases), plan, setup, out)
    fd = np.array([r for r in summary.fd_results], dtype=float)
    resolved = fd[fd[:, 0] == 1]
    K = resolved[:, 2]
    order = resolved[~np.isnan(resolved[:, 3]), 3]
    print(f"fd fit, seed {seed}, cases {start}..{start + cases - 1} ({seconds:.0f} s): "
          f"resolved {len(resolved)}, grazing {int(np.sum(resolved[:, 1]))}, "
          f"order measured {len(order)}, refined {int(np.sum(resolved[:, 6] > 3))}")
    print(f"K = E/dt: median {np.median(K):.3f}, 99 % {np.quantile(K, 0.99):.3f}, "
          f"max {np.max(K):.3f}")
    print(f"order: median {np.median(order):.4f}, 1 % {np.quantile(order, 0.01):.4f}, "
          f"99 % {np.quantile(order, 0.99):.4f}, outside 0.9-1.1: "
          f"{int(np.sum(np.abs(order - 1.0) > 0.1))}")
    print(f"C = 1.5 max K = {1.5 * np.max(K):.3f} (in use: {CHECKS['fd bound'].tolerance})")
    if summary.failures:
        print(f"{summary.failures} failing case(s): "
              + ", ".join(f"{s}:{i}" for s, i in summary.failed_cases))
    return 1 if summary.failures else 0

