"""The ``pipeplug`` console command: drive the PipePlug FMU and the core, and check them.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and
``main(args) -> int`` (the exit code). A module is imported only when its subcommand runs, so
``pipeplug --help`` works on any install, and a subcommand whose extra is missing says which
one to install.

The contract of every subcommand: it works from any folder (it finds the FMUs it needs, see
:mod:`pipeplug_harness.fmus`, or takes ``--fmu``); a user mistake is one line on stderr naming the
file, the key, the value and what is allowed, exit code 2; a run that fails is one line, exit
code 1; ``--limit NAME=VALUE`` raises a limit of :mod:`pipeplug_harness.limits`. No traceback
is shown unless ``PIPEPLUG_DEBUG=1``.
"""
from __future__ import annotations

import argparse
import importlib
import os
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
    "stability": ("pipeplug_harness.stability.command", "harness",
                  "run the catalogue of hard cases on every solver: errors, finiteness, "
                  "energy, drift"),
    "scene": ("pipeplug_harness.scene.command", "harness",
              "run a scene file (TOML: pipe, plug, soil, blows, model, output) through the FMU"),
    "drive": ("pipeplug_harness.drive.command", "harness",
              "drive a pipe blow by blow from the soil face to a target or refusal (TOML: pipe, "
              "plug, soil, blows, model, drive); per-blow CSV, drivability PNG"),
    "system": ("pipeplug_harness.system.command", "cosim",
               "run a co-simulated system (SSP or OSP file: Hammer driving PipePlug) with "
               "libcosim, every parameter checked first; CSV and PNG"),
    "fuzz": ("pipeplug_harness.fuzz.command", "dask",
             "differential fuzzing of the models: random cases through the core, the "
             "reference, the FMU and the fd scheme on Dask; invariants, summary, replayable "
             "failures"),
    "sweep": ("pipeplug_harness.sweep.command", "dask",
              "run a sweep (TOML: a grid or random sample of single blows or whole drives) "
              "through the core on a Dask cluster (this machine by default); Parquet out, "
              "resumable; reports: the paper's Fig. 2 domains, probabilistic drivability"),
}


class _Parser(argparse.ArgumentParser):
    """argparse, with a usage mistake as one line on stderr (exit code 2)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: {message} (see {self.prog} --help)\n")


def _version() -> str:
    try:
        from pipeplug import __version__
    except ImportError:                       # pragma: no cover - broken install
        return "unknown"
    return __version__


def _overview() -> argparse.ArgumentParser:
    """The top-level parser: lists the subcommands without importing them."""
    parser = _Parser(
        prog="pipeplug",
        description="Run the PipePlug FMU and check it against the analytic solutions; "
                    "reproduce the paper's figures; measure what accuracy costs.",
        epilog="Subcommands need the extra shown in brackets: pip install 'pipeplug[EXTRA]'. "
               "'pipeplug COMMAND --help' shows a subcommand's options.")
    parser.add_argument("--version", action="version", version=f"pipeplug {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (_, extra, text) in SUBCOMMANDS.items():
        sub.add_parser(name, help=f"{text} [{extra}]", add_help=False)
    return parser


def _common(parser: argparse.ArgumentParser) -> None:
    """The flags every subcommand takes."""
    parser.add_argument("--limit", action="append", default=[], metavar="NAME=VALUE",
                        help="raise a limit on the work of a run (memory, steps, work, blows, "
                             "cases, tasks), e.g. --limit steps=1e9")


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``pipeplug`` command."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] not in SUBCOMMANDS:
        _overview().parse_args(argv)          # prints the help or version, or names the mistake
        return 2
    name, rest = argv[0], argv[1:]
    module_name, extra, text = SUBCOMMANDS[name]
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        print(f"pipeplug {name}: needs the '{extra}' extra (pip install 'pipeplug[{extra}]'): "
              f"{exc}", file=sys.stderr)
        return 2
    parser = _Parser(prog=f"pipeplug {name}", description=text)
    module.add_arguments(parser)
    _common(parser)
    args = parser.parse_args(rest)
    return _run(name, module, args)


def _run(name: str, module, args) -> int:
    """Run a subcommand; its mistakes and failures as one line with their exit codes."""
    from pipeplug_harness.errors import RUN_FAILED, USER_ERROR, RunFailed, UserError
    from pipeplug_harness.limits import parse_limits
    try:
        args.limits = parse_limits(args.limit)
        return int(module.main(args) or 0)
    except UserError as exc:
        return _say(name, exc, USER_ERROR)
    except RunFailed as exc:
        return _say(name, exc, RUN_FAILED)
    except KeyboardInterrupt:
        return _say(name, "interrupted", 130)
    except Exception as exc:                  # a defect: still one line, and how to see more
        if os.environ.get("PIPEPLUG_DEBUG") == "1":
            raise
        return _say(name, f"internal error: {type(exc).__name__}: {exc} (PIPEPLUG_DEBUG=1 shows "
                          f"the traceback)", RUN_FAILED)


def _say(name: str, what, code: int) -> int:
    text = " ".join(str(what).split())       # one line, whatever the message holds
    print(f"pipeplug {name}: {text}", file=sys.stderr, flush=True)
    return code


if __name__ == "__main__":
    sys.exit(main())
