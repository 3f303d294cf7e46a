"""``pipeplug drive FILE.toml ...``: whole drives through the FMU; per-blow CSV, two PNGs,
summary.

Progress (blow, penetration, blows per second, the time left at the recent set per blow) goes
to stderr while the drive runs. A blow that breaks the energy ledger or a physical bound
(:mod:`.checks`) stops the drive: one line on stderr, exit code 1, no result written.
"""
from __future__ import annotations

import argparse

from pipeplug_harness import io
from pipeplug_harness.errors import RunFailed, UserError
from pipeplug_harness.fmus import find_fmu
from pipeplug_harness.scene.command import _distinct
from pipeplug_harness.session import fmu_inputs

from .checks import DriveInvalid
from .file import load_drive
from .plots import plot_drivability, plot_penetration, plot_plug
from .progress import DriveProgress
from .report import summary, write_csv
from .run import check_inputs, run_drive


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("drive", nargs="+", help="drive file(s) (.toml)")
    parser.add_argument("--fmu", help="the FMU (default: the build of this installation, made "
                                      "once into the user's cache)")
    parser.add_argument("--out", default="out/drives", help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    specs = [load_drive(path, args.limits) for path in args.drive]     # every file checked first
    _distinct([s.name for s in specs], args.drive)
    fmu = find_fmu(args.fmu)
    inputs = fmu_inputs(fmu)
    for path, spec in zip(args.drive, specs):          # before any output is written
        try:
            check_inputs(spec, inputs)
        except UserError as exc:
            raise exc.in_file(path) from None
    with io.OutputFolder(args.out, "drive") as out:
        for path, spec in zip(args.drive, specs):
            print(f"{spec.name}: {spec.reason}", flush=True)
            if spec.grid:
                print(f"{spec.name}: {spec.grid}", flush=True)
            try:
                with DriveProgress(spec) as progress:
                    result = run_drive(spec, fmu, progress)
            except DriveInvalid as exc:
                raise RunFailed(f"{path}: {exc}; the drive is not valid, no result written") \
                    from None
            csv_path = write_csv(out.file(f"{spec.name}.csv"), result)
            pngs = (plot_penetration(out.file(f"{spec.name}_penetration.png"), result),
                    plot_drivability(out.file(f"{spec.name}_drivability.png"), result),
                    plot_plug(out.file(f"{spec.name}_plug.png"), result))
            print(summary(result), flush=True)
            print(f"  wrote {csv_path}, {', '.join(map(str, pngs))}", flush=True)
    return 0
