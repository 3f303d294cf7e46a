"""The drive's three figures: penetration against blow number, the drivability curve, and the
plug and the pace against penetration."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pipeplug_harness import io

from .report import INTERVAL, blows_per_interval
from .run import IFR_TOL, OUTCOMES, DriveResult, no_plug

__all__ = ["plot_penetration", "plot_drivability", "plot_plug", "describe_blow"]


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


def _defined(values) -> np.ndarray:
    """Values with those not defined (None) as gaps (NaN) in a line."""
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _decades(values: np.ndarray) -> float:
    """How many decades the positive, defined values span (0 with fewer than two)."""
    positive = values[np.isfinite(values) & (values > 0.0)]
    if positive.size < 2:
        return 0.0
    return float(np.log10(positive.max() / positive.min()))


def plot_plug(path: Path, result: DriveResult) -> Path:
    """Against penetration: the plug's length and L2/s; each blow's IFR, coring or plugged;
    each blow's metres per hour at the blow rate and the drive's overall. Ratios that are not
    defined (no set, s <= 0) are gaps, and so is every plug measure of a drive without a plug;
    clean-outs are vertical lines."""
    blows = result.blows
    depth = np.array([b.penetration for b in blows])
    fig, (top, mid, low) = io.subplots(3, 1, figsize=(7.5, 7.6), sharex=True)
    length = _defined(b.L2 for b in blows)
    why = no_plug(result.spec)
    top.plot(depth, length, color="C1", lw=1.2,
             label=f"no plug ({why})" if why else "plug length L2")
    top.set_ylabel("plug length L2 [m]")
    top.set_ylim(0.0, 1.15 * max([b.L2 for b in blows if b.L2 is not None] + [1e-3]))
    ratio = top.twinx()
    plr = _defined(b.plr for b in blows)
    ratio.plot(depth, plr, color="C2", lw=1.0, ls="--", label="L2/s")
    ratio.set_ylabel("plug length ratio L2/s [1]")
    if _decades(plr) > 1.0:           # a fixed plug's L2/s falls from L2/(first set) to L2/s
        ratio.set_yscale("log")
    top.legend(handles=top.get_lines() + ratio.get_lines(), fontsize=8, loc="center right")
    ifr = _defined(b.ifr for b in blows)
    for label, color in (("coring", "C3"), ("plugged", "C0")):
        mine = np.array([b.plugging == label for b in blows])
        mid.plot(depth[mine], ifr[mine], ".", ms=3, color=color,
                 label=f"{label} ({mine.sum()} blows)")
    undefined = sum(b.ifr is None for b in blows)
    mid.axhline(IFR_TOL, color="0.5", lw=0.6, ls=":",
                label=f"IFR = {IFR_TOL:g}: coring above" + (f"; {undefined} blows without "
                                                             f"set: not defined"
                                                             if undefined else ""))
    mid.set_ylabel("IFR = dL2/ds per blow [1]")
    mid.legend(fontsize=8, loc="upper right")
    low.plot(depth, [b.metres_per_hour for b in blows], lw=0.8, color="C0", label="per blow")
    if result.metres_per_hour is not None:
        low.axhline(result.metres_per_hour, color="k", ls="--", lw=0.8,
                    label=f"overall {result.metres_per_hour:.3g} m/h")
    low.set_ylabel("m/h at the blow rate")
    low.set_xlabel("penetration of the front end [m]")
    low.set_ylim(bottom=0.0)
    low.legend(fontsize=8, loc="upper right")
    for ax in (top, mid, low):
        for b in blows:
            if b.cleanout:
                ax.axvline(b.penetration - b.set, color="C4", lw=0.6, alpha=0.7)
        ax.grid(alpha=0.3)
    plural = "s" if result.cleanouts != 1 else ""
    top.set_title(_title(result) + (f", {result.cleanouts} clean-out{plural} (violet)"
                                    if result.cleanouts else ""), fontsize=8)
    fig.tight_layout()
    return io.save_png(fig, path)
