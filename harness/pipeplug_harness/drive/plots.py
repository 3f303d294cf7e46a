"""The drive's two figures: penetration against blow number, and the drivability curve."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pipeplug_harness import io

from .report import INTERVAL, blows_per_interval
from .run import OUTCOMES, DriveResult

__all__ = ["plot_penetration", "plot_drivability", "describe_blow"]


def describe_blow(spec) -> str:
    """The blow in the file's terms: the rectangle, or the ram that strikes."""
    hammer = spec.hammer
    if hammer is None:
        return f"{spec.amplitude:.4g} N x {spec.duration:.3g} s"
    return (f"ram {hammer.ram_mass:.4g} kg at {hammer.v_strike:.3g} m/s, "
            f"{hammer.efficiency:.3g} x {hammer.rated_energy:.4g} J")


def _title(result: DriveResult) -> str:
    spec = result.spec
    model = "elastic" if spec.elastic else "rigid"
    return (f"{spec.name} ({model}, {describe_blow(spec)}, {60.0 / spec.period:.4g} blows/min)\n"
            f"{OUTCOMES[result.outcome]} after {len(result.blows)} blows at "
            f"{result.penetration:.4g} m")


def plot_penetration(path: Path, result: DriveResult) -> Path:
    """Front-end penetration [m] after each blow."""
    fig, ax = io.subplots(figsize=(7.5, 4.2))
    blows = [b.blow for b in result.blows]
    ax.plot([0] + blows, [0.0] + [b.penetration for b in result.blows], lw=1.2)
    ax.axhline(result.spec.target, color="0.5", ls="--", lw=0.8, label="target")
    ax.set_xlabel("blow number")
    ax.set_ylabel("penetration of the front end [m]")
    ax.set_title(_title(result), fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return io.save_png(fig, path)


def plot_drivability(path: Path, result: DriveResult) -> Path:
    """Blows per 0.25 m of penetration against penetration (the last interval, where the drive
    stopped, drawn hatched over the part driven: its count is partial)."""
    starts, counts = blows_per_interval(result)
    fig, ax = io.subplots(figsize=(7.5, 4.2))
    if counts.size:
        full = np.arange(counts.size) < counts.size - 1     # the drive stopped in the last
        ax.bar(starts[full], counts[full], width=INTERVAL, align="edge", color="C0",
               edgecolor="C0", lw=0.3)
        covered = max(result.penetration - starts[-1], 0.02 * INTERVAL)
        ax.bar(starts[~full], counts[~full], width=covered, align="edge", color="none",
               edgecolor="C0", hatch="///", lw=0.6,
               label=f"last interval, partial ({covered:.3g} m driven)")
        ax.legend(fontsize=8)
    ax.set_xlabel("penetration of the front end [m]")
    ax.set_ylabel(f"blows per {INTERVAL:g} m")
    ax.set_xlim(0.0, max(result.spec.target, result.penetration))
    ax.set_title(_title(result), fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return io.save_png(fig, path)
