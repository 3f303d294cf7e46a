"""The ``pipeplug`` console command: drive dist/PipePlug.fmu with fmpy and check it.

Each subcommand lives in its own module exposing ``HELP`` (one line), ``add_arguments(parser)``
and ``main(args) -> int`` (the exit code).
"""
from __future__ import annotations

import argparse
import importlib
import sys

#: subcommand -> module of this package
SUBCOMMANDS = {
    "validate": "validate",
    "figures": "figures",
    "cost": "cost",
    "stability": "stability",
    "scene": "scene",
}


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="pipeplug",
        description="Run the PipePlug FMU with rectangular pulses and check it against the "
                    "analytic solutions; reproduce the paper's figures; measure accuracy cost.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, module_name in SUBCOMMANDS.items():
        module = importlib.import_module(f"pipeplug_harness.{module_name}")
        cmd = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(cmd)
        cmd.set_defaults(run=module.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``pipeplug`` command."""
    args = _parser().parse_args(argv)
    return int(args.run(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
