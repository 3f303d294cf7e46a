"""``pipeplug sweep FILE.toml``: run a sweep on a Dask cluster; Parquet out; optional report."""
from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from pipeplug_harness.errors import RunFailed, UserError

from .file import load_sweep

#: report -> module with ``report(spec, table, figure) -> str`` (see .file.REPORTS)
_REPORT_MODULES = {"domains": "pipeplug_harness.sweep.domains",
                   "drivability": "pipeplug_harness.sweep.drivability"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("sweep", help="sweep file (.toml)")
    parser.add_argument("--out", help="output folder, a Parquet dataset (default: "
                                      "out/sweeps/NAME)")
    parser.add_argument("--figure", help="the report's PNG (default: out/sweeps/NAME.png)")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (e.g. "
                                            "tcp://10.0.0.5:8786); default: a LocalCluster "
                                            "on this machine")
    parser.add_argument("--workers", type=int, help="LocalCluster worker processes (default: "
                                                    "one per core)")
    parser.add_argument("--fresh", action="store_true",
                        help="start afresh (default: resume, skipping finished chunks)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def main(args: argparse.Namespace) -> int:
    from .check import check_sweep
    from .cluster import dask_client
    from .engine import run_campaign
    from .runners import described
    from .store import read_folder
    spec = load_sweep(args.sweep, args.limits)
    try:
        checked = check_sweep(spec)
    except UserError as exc:
        raise exc.in_file(args.sweep) from None
    out = Path(args.out or Path("out/sweeps") / spec.name)
    figure = Path(args.figure or Path("out/sweeps") / f"{spec.name}.png")
    if spec.report != "none" and (figure.is_dir() or (figure.exists() and not figure.is_file())):
        raise UserError(key="--figure", value=str(figure), allowed="a PNG file's path")
    print(f"{spec.name}: {spec.n_cases} {spec.kind} cases ({spec.sampling} over "
          f"{', '.join(d.name for d in spec.dims)}) in {spec.n_chunks} chunks of "
          f"{spec.chunk}; {checked}; {described(spec)}", flush=True)
    with dask_client(args.scheduler, args.workers) as client:
        workers = len(client.scheduler_info()["workers"])
        run = run_campaign(spec, out, client, fresh=args.fresh, progress=not args.no_progress,
                           about={"file": str(Path(args.sweep).resolve())})
    print(_summary(run, workers, out), flush=True)
    if run.failed:
        for c, text in sorted(run.failed.items()):
            print(f"  chunk {c} failed: {text}", file=sys.stderr)
        raise RunFailed(f"{len(run.failed)} chunk(s) failed: rerun to retry them")
    table = read_folder(out)
    errors = [r for r in table.select(["case", "error"]).to_pylist() if r["error"]]
    for row in errors[:10]:
        print(f"  case {row['case']}: {row['error']}", file=sys.stderr)
    if spec.report != "none":
        module = importlib.import_module(_REPORT_MODULES[spec.report])
        print(module.report(spec, table, figure), flush=True)
    if errors:
        raise RunFailed(f"{len(errors)} case(s) failed (the 'error' column)")
    return 0


def _summary(run, workers: int, out: Path) -> str:
    text = (f"  {run.written} chunks run now ({run.cases} cases; {run.by_workers} files "
            f"written by the workers, {run.written - run.by_workers} here), {run.skipped} "
            f"already done, {len(run.failed)} failed; {workers} worker(s); results in {out}")
    if run.cases:
        per_case = run.seconds * workers / run.cases
        text += (f"\n  wall time {run.seconds:.1f} s: {_rate(run.cases / run.seconds)} cases/s, "
                 f"{per_case * 1e3:.3g} ms per case per worker")
    return text


def _rate(per_second: float) -> str:
    """A rate with 3 significant digits (0.145, 12.3), whole and grouped from 100 on
    (543,210)."""
    return f"{per_second:,.0f}" if per_second >= 99.95 else f"{per_second:.3g}"
