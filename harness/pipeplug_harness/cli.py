"""The ``pipeplug`` console command: drive the PipePlug FMU with fmpy and check it.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and
``main(args) -> int`` (the exit code). A module is imported only when its subcommand runs, so
``pipeplug --help`` works on any install, and a subcommand whose extra is missing says which
one to install.
"""
from __future__ import annotations

import argparse
import importlib
import sys

#: subcommand -> (module, extra it needs, one-line help)
SUBCOMMANDS = {
    "validate": ("pipeplug_harness.validate.command", "harness",
                 "check the FMU against the closed-form solutions (figure cases and random "
                 "pulses); write FMI cross-check files"),
    "figures": ("pipeplug_harness.figures.command", "harness",
                "redraw the paper's Figs. 3-7 as PNG from FMU runs, references overlaid"),
    "cost": ("pipeplug_harness.cost.command", "harness",
             "measure what accuracy costs in time: exact, fd, regularised friction (scipy), "
             "elastic"),
    "stability": ("pipeplug_harness.hardcases.command", "harness",
                  "run the catalogue of hard cases on every solver: errors, finiteness, "
                  "energy, drift"),
    "scene": ("pipeplug_harness.scenes.command", "harness",
              "run a scene file (TOML: pipe, plug, soil, blows, model, output) through the FMU"),
    "drive": ("pipeplug_harness.drive.command", "harness",
              "drive a pipe blow by blow from the soil face to a target or refusal (TOML: pipe, "
              "plug, soil, blows, model, drive); per-blow CSV, drivability PNG"),
    "system": ("pipeplug_harness.system.command", "cosim",
               "run a co-simulated system (SSP or OSP file, e.g. dist/PipeRamming.ssp: Hammer "
               "driving PipePlug) with libcosim, every parameter checked first; CSV and PNG"),
    "fuzz": ("pipeplug_harness.fuzz.command", "harness",
             "differential fuzzing of the rigid models: random cases through the core, the "
             "reference, the FMU and the fd scheme; invariants, summary, replayable failures"),
    "sweep": ("pipeplug_harness.sweep.command", "dask",
              "run a sweep (TOML: a grid or random sample of single blows or whole drives) "
              "through the core on a Dask cluster (this machine by default); Parquet out, "
              "resumable; reports: the paper's Fig. 2 domains, probabilistic drivability"),
}


def _overview() -> argparse.ArgumentParser:
    """The top-level parser: lists the subcommands without importing them."""
    parser = argparse.ArgumentParser(
        prog="pipeplug",
        description="Run the PipePlug FMU and check it against the analytic solutions; "
                    "reproduce the paper's figures; measure what accuracy costs.",
        epilog="Subcommands need the extra shown in brackets: pip install 'pipeplug[EXTRA]'. "
               "'pipeplug COMMAND --help' shows a subcommand's options.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (_, extra, text) in SUBCOMMANDS.items():
        sub.add_parser(name, help=f"{text} [{extra}]", add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``pipeplug`` command."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] not in SUBCOMMANDS:
        _overview().parse_args(argv)          # prints the help, or names the bad command
        return 2
    name, rest = argv[0], argv[1:]
    module_name, extra, text = SUBCOMMANDS[name]
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        print(f"pipeplug {name}: needs the '{extra}' extra (pip install 'pipeplug[{extra}]'): "
              f"{exc}", file=sys.stderr)
        return 2
    parser = argparse.ArgumentParser(prog=f"pipeplug {name}", description=text)
    module.add_arguments(parser)
    return int(module.main(parser.parse_args(rest)) or 0)


if __name__ == "__main__":
    sys.exit(main())
