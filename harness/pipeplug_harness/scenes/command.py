"""``pipeplug scene FILE.toml``: run one described scene through the FMU; write CSV and PNG."""
from __future__ import annotations

import argparse
import csv
from pathlib import Path

from pipeplug_harness.fmu_run import DEFAULT_FMU, Run, run_fmu

from .file import load_scene

_UNITS = {"v_pipe": "m/s", "v_plug": "m/s", "u_pipe": "m", "u_plug": "m", "F_outer": "N",
          "F_inner": "N", "W_input": "J", "W_friction": "J", "pipe_mode": "-", "plug_mode": "-"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", nargs="+", help="scene file(s) (.toml)")
    parser.add_argument("--fmu", default=str(DEFAULT_FMU), help="the FMU (default: %(default)s)")
    parser.add_argument("--out", default="out/scenes", help="output folder (%(default)s)")


def main(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for path in args.scene:
        scene = load_scene(path)
        print(f"{scene.name}: {scene.reason}", flush=True)
        run = Run(params=scene.start_values, pulses=scene.pulses, step=scene.step,
                  stop_time=scene.stop_time)
        result = run_fmu(run, args.fmu, outputs=scene.variables)
        csv_path = out / f"{scene.name}.csv"
        _write_csv(csv_path, result, scene.variables)
        png_path = _plot(out / f"{scene.name}.png", result, scene)
        peaks = ", ".join(f"max {v} = {result[v].max():.6g} {_UNITS[v]}" for v in scene.variables)
        print(f"  {peaks}\n  wrote {csv_path} and {png_path}", flush=True)
    return 0


def _write_csv(path: Path, result, variables) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["time"] + list(variables))
        for row in result:
            writer.writerow([repr(float(row["time"]))] + [repr(float(row[v])) for v in variables])


def _plot(path: Path, result, scene) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    units = sorted({_UNITS[v] for v in scene.variables})
    fig, axes = plt.subplots(len(units), 1, figsize=(8, 2.8 * len(units)), sharex=True,
                             squeeze=False)
    for ax, unit in zip(axes[:, 0], units):
        for v in scene.variables:
            if _UNITS[v] == unit:
                ax.plot(result["time"] * 1e3, result[v], label=v)
        ax.set_ylabel(f"[{unit}]")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t [ms]")
    axes[0, 0].set_title(f"{scene.name}: {scene.reason}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
