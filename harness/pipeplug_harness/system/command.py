"""``pipeplug system [--ssp FILE | --osp FILE]``: run a co-simulated system with libcosim.

Reads the file as libcosim does (:mod:`.files`), checks every PipePlug and Hammer parameter with
the FMUs' own checks and the times (:mod:`.checks`); only then runs it (:mod:`.run`). Writes
``<out>/<file stem>.csv`` (time and every input and output of every component, full
precision) and
``<out>/<file stem>.png`` (the force and PipePlug's motion), and prints a summary.
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from pipeplug_fmu.fmi import INPUTS
from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.paper import OUTPUT_UNITS

from .checks import check_system
from .files import read_system

#: units of the variables of the system's FMUs: PipePlug's outputs and inputs (Q, strikes,
#: v_strike), which are also the names of Hammer's outputs connected to them
UNITS = {**OUTPUT_UNITS, **{name: unit or "1" for name, _, unit, _, _ in INPUTS}}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    files = parser.add_mutually_exclusive_group()
    files.add_argument("--ssp", type=Path, help="an SSP system: .ssp archive, .ssd file or "
                                                "a folder with SystemStructure.ssd (default: "
                                                "PipeRamming.ssp of this installation's build)")
    files.add_argument("--osp", type=Path, help="an OSP system: OspSystemStructure.xml or its "
                                                "folder")
    parser.add_argument("--stop", type=float, help="stop time [s] (default: the file's; for an "
                                                   "OSP file, one period after a Hammer's last "
                                                   "blow starts)")
    parser.add_argument("--out", type=Path, default=Path("out/system"),
                        help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    if args.osp:
        route, path = "osp", args.osp
    elif args.ssp:
        route, path = "ssp", args.ssp
    else:
        from pipeplug_harness.fmus import find_fmu
        route, path = "ssp", find_fmu(None, "PipeRamming.ssp")
    if args.stop is not None and not math.isfinite(args.stop):
        raise UserError(key="--stop", value=args.stop, allowed="a finite time [s]")
    system = read_system(path, route)
    try:
        plan = check_system(system, args.stop, args.limits)
    except UserError as exc:
        raise exc.in_file(path) from None
    for warning in plan.warnings:
        print(f"warning: {warning}")
    names = ", ".join(f"{c.name} ({c.model})" for c in system.components.values())
    print(f"{path} ({route.upper()}): {names}; {plan.steps} steps of {plan.step!r} s from "
          f"{plan.start!r} s", flush=True)
    from .run import run_system

    with io.OutputFolder(args.out, "system") as out:
        began = time.perf_counter()
        try:
            result = run_system(system, plan)
        except AssertionError as exc:          # libcosimpy's way of saying libcosim refused it
            raise UserError(f"libcosim refused {path}: {exc}") from None
        elapsed = time.perf_counter() - began
        stem = Path(path).stem if Path(path).is_file() else Path(path).name
        names = list(result)
        units = {n: UNITS.get(n.rpartition(".")[2], "") for n in names}
        units["time"] = "s"
        csv_path = io.write_csv(out.file(f"{stem}.csv"), names,
                                zip(*(result[n] for n in names)), units)
        png_path = _plot(out.file(f"{stem}.png"), result, system, path)
    print(f"libcosim: {plan.steps} steps to t = {float(result['time'][-1])!r} s in {elapsed:.2f} s "
          f"({1e6 * elapsed / plan.steps:.0f} us per step)")
    for pipeplug in system.of_model("PipePlug"):
        u, v = result[f"{pipeplug.name}.u_pipe"], result[f"{pipeplug.name}.v_pipe"]
        print(f"{pipeplug.name}: u_pipe at the end {u[-1]:.6g} m, max v_pipe {v.max():.6g} m/s")
    print(f"wrote {csv_path} and {png_path}")
    return 0


#: What each panel draws; a ram's head force and velocity only where the system has a ram.
_PANELS = (("force [kN]", ("Q", "F_head"), 1e-3), ("velocity [m/s]", ("v_pipe", "v_plug", "v_ram"),
                                                     1.0),
           ("displacement [m]", ("u_pipe", "u_plug"), 1.0))
_RAM_ONLY = {"F_head", "v_ram"}
#: How a piecewise-constant force is drawn from its values after each step: Hammer's Q at t is
#: the force on [t, next point), PipePlug's input Q at t the force that acted up to t.
_HELD = {"Hammer": dict(drawstyle="steps-post"), "PipePlug": dict(drawstyle="steps-pre",
                                                                  linestyle="--")}


def _plot(path: Path, result: dict, system, source) -> Path:
    fig, axes = io.subplots(len(_PANELS), 1, figsize=(8, 8), sharex=True)
    t_ms = result["time"] * 1e3
    for ax, (label, variables, scale) in zip(axes, _PANELS):
        for component in system.components.values():
            for variable in variables:
                column = f"{component.name}.{variable}"
                ram = float(component.values.get("ram_mass", 0.0) or 0.0) > 0.0
                if column in result and (ram or variable not in _RAM_ONLY):
                    style = _HELD.get(component.model, {}) if variable == "Q" else {}
                    ax.plot(t_ms, result[column] * scale, label=column, **style)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("t [ms]")
    axes[0].set_title(f"{Path(source).name}: libcosim, step {system.step * 1e3:g} ms",
                      fontsize=9)
    fig.tight_layout()
    return io.save_png(fig, path)
