"""What a drive writes: the per-blow CSV, the drivability counts and the summary line."""
from __future__ import annotations

import math
from dataclasses import fields
from pathlib import Path

import numpy as np

from pipeplug_harness import io

from .run import IFR_TOL, OUTCOMES, WORKS, Blow, DriveResult, no_plug

__all__ = ["write_csv", "blows_per_interval", "summary", "stresses", "pace", "plug", "INTERVAL", "COLUMNS"]

#: A stress at most this fraction of the drive's largest one is round-off: the summary gives 0.
ROUND_OFF = 1e-9
#: Penetration interval of the drivability curve [m].
INTERVAL = 0.25

#: CSV column -> unit
COLUMNS = {"blow": "-", "t_start": "s", "set": "m", "penetration": "m", "v_pipe_peak": "m/s",
           "v_plug_peak": "m/s", "W_input": "J", "W_friction_outer": "J",
           "W_friction_inner": "J", "v_pipe_end": "m/s", "v_plug_end": "m/s", "settled": "-",
           "motion": "s", "steps": "-", "ringing_friction": "J", "stress_head_min": "Pa",
           "stress_head_max": "Pa", "stress_min": "Pa", "stress_max": "Pa", "enthru": "J",
           "enthru_share": "1", "cleanout": "-", "L2": "m", "ifr": "1", "plr": "1",
           "plugging": "-", "metres_per_hour": "m/h", **{name: "J" for name in WORKS}}
assert tuple(COLUMNS) == tuple(f.name for f in fields(Blow) if f.name != "works") + WORKS


def _row(blow: Blow) -> list:
    """The blow's values in the order of :data:`COLUMNS` (``None``: not defined, an empty
    field)."""
    return [getattr(blow, f.name) for f in fields(Blow) if f.name != "works"] \
        + [blow.works[name] for name in WORKS]


def write_csv(path: Path, result: DriveResult) -> Path:
    """One row per blow, units in the header; works are the blow's own (its window's
    increments); a ratio that is not defined is an empty field."""
    return io.write_csv(path, list(COLUMNS), (_row(blow) for blow in result.blows), COLUMNS)


def blows_per_interval(result: DriveResult, width: float = INTERVAL):
    """Blows per penetration interval: the blow counts whose final penetration falls in
    [j w, (j+1) w).

    Returns
    -------
    starts : ndarray
        Interval starts [m].
    counts : ndarray of int
        Blows ending in each interval; the last interval is partial when the drive stopped
        inside it.
    """
    depth = np.array([b.penetration for b in result.blows])
    if depth.size == 0:
        return np.zeros(0), np.zeros(0, dtype=int)
    index = np.floor(np.maximum(depth, 0.0) / width).astype(int)
    counts = np.bincount(index)
    return np.arange(counts.size) * width, counts


def summary(result: DriveResult) -> str:
    """The one-line summary: blows, drive time at the blow rate, refusal or not, and where."""
    spec = result.spec
    n = len(result.blows)
    rate = 60.0 / spec.period
    line = (f"{spec.name}: {n} blows, drive time {_duration(result.drive_time)} at "
            f"{rate:.4g} blows/min; {OUTCOMES[result.outcome]}")
    if result.outcome == "set":
        line += f" ({spec.refusal_text()})"
    elif spec.refusal_length == 0.0 and result.outcome != "target":
        line += " (no set refusal: refusal_set = 0)"
    return (line + f" at penetration {result.penetration:.6g} m (target {spec.target:.6g} m)"
            + _end(result) + pace(result) + plug(result) + stresses(result))


def _end(result: DriveResult) -> str:
    """How the pipe is at the drive's end, where the penetration alone would mislead: still
    moving after the last blow's window (:func:`_still_moving`), or past L1 (the pipe went on
    after its last blow stopped acting, and the soil stopped it: any other pipe past L1 stops
    the drive, see :mod:`.checks`)."""
    if not result.blows:
        return ""
    last, L1 = result.blows[-1], result.spec.params().L1
    text = ""
    if last.penetration > L1:
        text += (f", {last.penetration - L1:.3g} m past L1 = {L1:.6g} m (the pipe went on "
                 f"after the last blow, its head below the soil face)")
    if last.settled == "moving":
        text += _still_moving(last.v_pipe_end, last.v_plug_end)
    return text


def _still_moving(v_pipe: float, v_plug: float) -> str:
    """What a last blow whose motion had not died out left moving: pipe (forward or back),
    plug, or neither at the monitor while the elastic pipe had not been still for a wave's
    round trip (the settling window)."""
    if v_pipe > 0.0:
        return (f", still moving at {v_pipe:.4g} m/s when the drive stopped (it comes to rest "
                f"further in)")
    if v_pipe < 0.0:
        return (f", still moving at {v_pipe:.4g} m/s when the drive stopped (back, out of the "
                f"soil)")
    if v_plug != 0.0:
        return f", the plug still moving at {v_plug:.4g} m/s in the pipe when the drive stopped"
    return (", at rest at the monitor when the drive stopped, but not yet for a wave's round "
            "trip in the pipe (its waves may still move it)")


def pace(result: DriveResult) -> str:
    """The drive's progress at the blow rate: overall, and the range of the blows' own."""
    if not result.blows:
        return ""
    each = [b.metres_per_hour for b in result.blows]
    return (f"; {result.metres_per_hour:.4g} m/h overall at the blow rate (blows "
            f"{min(each):.3g} to {max(each):.3g} m/h)")


def plug(result: DriveResult) -> str:
    """The plug at the end: its length, L2/s, the last blow's IFR and label, clean-outs."""
    if not result.blows:
        return ""
    last = result.blows[-1]
    why = no_plug(result.spec)
    if why:
        return f"; no plug ({why})"
    coring = sum(b.plugging == "coring" for b in result.blows)
    text = (f"; plug {last.L2:.4g} m, L2/s {_ratio(last.plr)}, last IFR {_ratio(last.ifr)}"
            f"{f' ({last.plugging})' if last.plugging else ''}, {coring} of "
            f"{len(result.blows)} blows coring (IFR > {IFR_TOL:g})")
    if result.spec.cleanouts is not None:
        text += f", {result.cleanouts} clean-out{'s' if result.cleanouts != 1 else ''}"
    return text


def _ratio(value: float | None) -> str:
    return "not defined" if value is None else f"{value:.4g}"


def stresses(result: DriveResult) -> str:
    """The largest stresses of the drive (and against the yield stress), the mean ENTHRU."""
    if not result.blows:
        return ""
    spec = result.spec
    # magnitudes; no compression or tension: 0, not -0
    low = max([0.0] + [-b.stress_min for b in result.blows])
    high = max([0.0] + [b.stress_max for b in result.blows])
    # a stress that is round-off of the drive's largest one (a rigid pipe's free front end
    # reads a few ulps of the head's force) is none
    scale = ROUND_OFF * max(low, high)
    low, high = (0.0 if low <= scale else low), (0.0 if high <= scale else high)
    text = (f"; largest stress {low / 1e6:.4g} MPa compressive, {high / 1e6:.4g} MPa "
            f"tensile")
    if spec.yield_stress:
        worst = max(low, high) / spec.yield_stress
        text += (f" ({100 * worst:.3g} % of the yield stress {spec.yield_stress / 1e6:.4g} "
                 f"MPa{', EXCEEDED' if worst > 1.0 else ''})")
    if spec.hammer is not None:
        share = float(np.mean([b.enthru_share for b in result.blows]))
        text += (f"; ENTHRU {100 * share:.3g} % of the rated energy "
                 f"{spec.hammer.rated_energy:.4g} J on average")
    return text


def _duration(seconds: float) -> str:
    """``1 h 02 min 03 s`` style."""
    if seconds < 60.0:
        return f"{seconds:.3g} s"
    minutes, s = divmod(int(math.floor(seconds + 0.5)), 60)
    h, m = divmod(minutes, 60)
    return f"{h} h {m:02d} min {s:02d} s" if h else f"{m} min {s:02d} s"
