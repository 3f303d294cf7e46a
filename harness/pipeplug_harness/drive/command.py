"""``pipeplug drive FILE.toml``: a whole drive through the FMU; per-blow CSV, two PNGs, summary.

Progress (blow, penetration, blows per second, the time left at the recent set per blow) goes
to stderr while the drive runs. A blow that breaks the energy ledger or a physical bound
(:mod:`.checks`) stops the drive: one line on stderr, exit code 1, no result written.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pipeplug_harness.fmu_run import DEFAULT_FMU

from .checks import DriveInvalid
from .file import load_drive
from .plots import plot_drivability, plot_penetration
from .progress import DriveProgress
from .report import summary, write_csv
from .run import run_drive


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("drive", nargs="+", help="drive file(s) (.toml)")
    parser.add_argument("--fmu", default=str(DEFAULT_FMU), help="the FMU (default: %(default)s)")
    parser.add_argument("--out", default="out/drives", help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for path in args.drive:
        try:
            spec = load_drive(path)
        except ValueError as exc:          # SceneError, or the core's ParameterError
            print(f"pipeplug drive: {path}: {exc}", file=sys.stderr)
            return 2
        print(f"{spec.name}: {spec.reason}", flush=True)
        if spec.grid:
            print(f"{spec.name}: {spec.grid}", flush=True)
        try:
            with DriveProgress(spec) as progress:
                result = run_drive(spec, args.fmu, progress)
        except DriveInvalid as exc:
            print(f"pipeplug drive: {path}: {exc}; the drive is not valid, no result written",
                  file=sys.stderr)
            return 1
        csv_path = out / f"{spec.name}.csv"
        write_csv(csv_path, result)
        pngs = (plot_penetration(out / f"{spec.name}_penetration.png", result),
                plot_drivability(out / f"{spec.name}_drivability.png", result))
        print(summary(result), flush=True)
        print(f"  wrote {csv_path}, {pngs[0]} and {pngs[1]}", flush=True)
    return 0
