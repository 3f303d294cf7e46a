"""``pipeplug scene FILE.toml ...``: run described scenes through the FMU; write CSV and PNG."""
from __future__ import annotations

import argparse
from pathlib import Path

from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.fmus import find_fmu
from pipeplug_harness.paper import OUTPUT_UNITS
from pipeplug_harness.session import simulate

from .file import load_scene


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", nargs="+", help="scene file(s) (.toml)")
    parser.add_argument("--fmu", help="the FMU (default: the build of this installation, made "
                                      "once into the user's cache)")
    parser.add_argument("--out", default="out/scenes", help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    scenes = [load_scene(path, args.limits) for path in args.scene]   # every file checked first
    _distinct([s.name for s in scenes], args.scene)
    fmu = find_fmu(args.fmu)
    with io.OutputFolder(args.out, "scene") as out:
        for scene in scenes:
            print(f"{scene.name}: {scene.reason}", flush=True)
            result = simulate(fmu, scene.start_values, scene.load, scene.step, scene.stop_time,
                              outputs=scene.variables, strikes=scene.strikes)
            names = ["time", *scene.variables]
            units = {"time": "s", **{v: OUTPUT_UNITS[v] for v in scene.variables}}
            csv_path = io.write_csv(out.file(f"{scene.name}.csv"), names,
                                    ([row[n] for n in names] for row in result), units)
            png_path = _plot(out.file(f"{scene.name}.png"), result, scene)
            # the range, not the max: forces and stresses are signed (a pull, a compression)
            ranges = ", ".join(f"{v} from {result[v].min():.6g} to {result[v].max():.6g}"
                               f"{_unit(v)}" for v in scene.variables)
            print(f"  {ranges}\n  wrote {csv_path} and {png_path}", flush=True)
    return 0


def _unit(name: str) -> str:
    unit = OUTPUT_UNITS[name]
    return "" if unit == "1" else f" {unit}"


def _distinct(names: list, paths: list) -> None:
    """Refuse two files whose outputs would have one name."""
    for i, name in enumerate(names):
        if name in names[:i]:
            first = paths[names.index(name)]
            raise UserError(f"{first} and {paths[i]} would both write {name}.csv: give them "
                            f"different names or run them into different --out folders")


def _plot(path: Path, result, scene) -> Path:
    units = sorted({OUTPUT_UNITS[v] for v in scene.variables})
    fig, axes = io.subplots(len(units), 1, figsize=(8, 2.8 * len(units)), sharex=True,
                            squeeze=False)
    for ax, unit in zip(axes[:, 0], units):
        for v in scene.variables:
            if OUTPUT_UNITS[v] == unit:
                ax.plot(result["time"] * 1e3, result[v], label=v)
        ax.set_ylabel(f"[{unit}]")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t [ms]")
    axes[0, 0].set_title(f"{scene.name}: {scene.reason}", fontsize=8)
    fig.tight_layout()
    return io.save_png(fig, path)
