"""``pipeplug sweep FILE.toml``: run a sweep on a Dask cluster; Parquet out; optional report."""
from __future__ import annotations

import argparse
import importlib
import os
import sys
from pathlib import Path

from pipeplug_harness import io
from pipeplug_harness.errors import RunFailed, UserError

from .file import load_sweep

#: report -> module with ``report(spec, table, figure) -> str`` (see .file.REPORTS)
_REPORT_MODULES = {"domains": "pipeplug_harness.sweep.domains",
                   "drivability": "pipeplug_harness.sweep.drivability"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("sweep", help="sweep file (.toml)")
    parser.add_argument("--out", help="output folder, a Parquet dataset (default: "
                                      "out/sweeps/NAME)")
    parser.add_argument("--figure", help="the report's PNG (default: _REPORT.png in the output "
                                         "folder, e.g. _drivability.png)")
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
    if args.workers is not None and args.workers < 1:    # a LocalCluster of 0 or -1 hangs
        raise UserError(key="--workers", value=args.workers, allowed=">= 1")
    spec = load_sweep(args.sweep, args.limits)
    try:
        checked = check_sweep(spec)
        if spec.report != "none":                  # before the run, not after it
            importlib.import_module(_REPORT_MODULES[spec.report]).check_applies(spec)
    except UserError as exc:
        raise exc.in_file(args.sweep) from None
    out = Path(args.out or Path("out/sweeps") / spec.name)
    figure = Path(args.figure) if args.figure else None
    if spec.report != "none":                      # before the run, not after it
        _check_figure(figure, out, _default_figure(spec))
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
        if figure is not None:
            print(module.report(spec, table, figure), flush=True)
        else:
            with _reopened(out, spec) as folder:
                print(module.report(spec, table, folder.file(_default_figure(spec))),
                      flush=True)
    if errors:
        raise RunFailed(f"{len(errors)} case(s) failed (the 'error' column)")
    return 0


def _default_figure(spec) -> str:
    """The report's figure in the output folder: a ``_`` name, which Parquet readers skip, so
    the folder stays one dataset."""
    return f"_{spec.report}.png"


_PNG = b"\x89PNG\r\n\x1a\n"               # a PNG file's first bytes


def _check_figure(figure: Path | None, out: Path, default: str) -> None:
    """Refuse up front a ``--figure`` path that cannot be written (a folder, a path under a
    file, a read-only folder) or must not be (not a .png, a file there that is not a PNG, or
    another output folder's file), or a default figure's name held by a file of someone
    else."""
    if figure is None:
        if io.foreign(out, default):
            raise UserError(key="--out", value=str(out),
                            allowed=f"a folder whose files pipeplug may write: {default} (the "
                                    f"report's figure) is there and is not one {io.MANIFEST} "
                                    f"names (move it, choose another folder, or give --figure)")
        return
    if figure.is_dir() or (figure.exists() and not figure.is_file()):
        raise UserError(key="--figure", value=str(figure), allowed="a PNG file's path")
    if figure.suffix.lower() != ".png":
        raise UserError(key="--figure", value=str(figure), allowed="a path ending in .png")
    if figure.exists():
        # a file there is overwritten only if it is a PNG and no other output's: a sweep's own
        # data, a scene's figure or a file of the user's is never written over
        with open(figure, "rb") as held:
            if held.read(8) != _PNG:
                raise UserError(key="--figure", value=str(figure),
                                allowed="a free path or a PNG's (the file there is not a PNG, "
                                        "and is not written over)")
        if io.listed(figure.parent, figure.name) and figure.parent.resolve() != out.resolve():
            raise UserError(key="--figure", value=str(figure),
                            allowed=f"a path that is not another output's file (the "
                                    f"{io.MANIFEST} beside it names it)")
    parent = next(p for p in figure.parents if p.exists())      # "." at least
    if not parent.is_dir():
        raise UserError(key="--figure", value=str(figure),
                        allowed=f"a PNG file's path in a folder ({parent} is a file)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UserError(key="--figure", value=str(figure),
                        allowed=f"a path this user can write ({parent} is read-only)")


def _reopened(out: Path, spec) -> io.OutputFolder:
    """The campaign's folder, held again (its lock, its manifest) to write the report's figure
    under the manifest; refused if another campaign took it over since."""
    def accept(held: dict) -> None:
        if held.get("campaign") != spec.digest:
            raise UserError(f"{out.resolve()} holds another campaign now (digest "
                            f"{held.get('campaign')}): the report's figure is not written there")
    return io.OutputFolder(out, "sweep", accept=accept)


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
