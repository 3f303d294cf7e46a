"""``pipeplug system [--ssp FILE | --osp FILE]``: run a co-simulated system with libcosim.

Reads the file as libcosim does (:mod:`.files`), checks every PipePlug and Hammer parameter with
the FMUs' own checks and the times (:mod:`.checks`); only then runs it (:mod:`.run`). Writes
``<out>/<file stem>.csv`` (time and every input and output of every component, full
precision) and
``<out>/<file stem>.png`` (the force and PipePlug's motion), and prints a summary.
"""
from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

from .checks import check_system
from .files import SystemFileError, read_system

DEFAULT_SSP = Path("dist") / "PipeRamming.ssp"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    files = parser.add_mutually_exclusive_group()
    files.add_argument("--ssp", type=Path, help=f"an SSP system: .ssp archive, .ssd file or "
                                                f"a folder with SystemStructure.ssd (default: "
                                                f"{DEFAULT_SSP})")
    files.add_argument("--osp", type=Path, help="an OSP system: OspSystemStructure.xml or its "
                                                "folder")
    parser.add_argument("--stop", type=float, help="stop time [s] (default: the file's; for an "
                                                   "OSP file, one period after a Hammer's last "
                                                   "blow starts)")
    parser.add_argument("--out", type=Path, default=Path("out/system"),
                        help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    route, path = ("osp", args.osp) if args.osp else ("ssp", args.ssp or DEFAULT_SSP)
    try:
        system = read_system(path, route)
        plan = check_system(system, args.stop)
    except SystemFileError as exc:
        print(f"pipeplug system: refused: {exc}")
        return 2
    for warning in plan.warnings:
        print(f"warning: {warning}")
    names = ", ".join(f"{c.name} ({c.model})" for c in system.components.values())
    print(f"{path} ({route.upper()}): {names}; {plan.steps} steps of {plan.step!r} s from "
          f"{plan.start!r} s", flush=True)
    from .run import run_system

    began = time.perf_counter()
    try:
        result = run_system(system, plan)
    except AssertionError as exc:          # libcosimpy's way of saying libcosim refused it
        print(f"pipeplug system: libcosim refused {path}: {exc}")
        return 2
    elapsed = time.perf_counter() - began
    args.out.mkdir(parents=True, exist_ok=True)
    stem = Path(path).stem if Path(path).is_file() else Path(path).name
    csv_path = _write_csv(args.out / f"{stem}.csv", result)
    png_path = _plot(args.out / f"{stem}.png", result, system, path)
    print(f"libcosim: {plan.steps} steps to t = {float(result['time'][-1])!r} s in {elapsed:.2f} s "
          f"({1e6 * elapsed / plan.steps:.0f} us per step)")
    for pipeplug in system.of_model("PipePlug"):
        u, v = result[f"{pipeplug.name}.u_pipe"], result[f"{pipeplug.name}.v_pipe"]
        print(f"{pipeplug.name}: u_pipe at the end {u[-1]:.6g} m, max v_pipe {v.max():.6g} m/s")
    print(f"wrote {csv_path} and {png_path}")
    return 0


def _write_csv(path: Path, result: dict) -> Path:
    names = list(result)
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(names)
        for k in range(len(result["time"])):
            writer.writerow([_text(result[name][k]) for name in names])
    return path


def _text(value) -> str:
    """A value at full precision (Reals round-trip; Booleans as 0/1)."""
    if isinstance(value, (bool, int)) or getattr(value, "dtype", None) is not None and \
            value.dtype.kind in "biu":
        return str(int(value))
    return repr(float(value))


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
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(_PANELS), 1, figsize=(8, 8), sharex=True)
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
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
