"""Drive files: a whole drive described in TOML, read by the scene files' machinery.

A drive file has the scene sections ``[pipe]``, ``[plug]``, ``[soil]``, ``[blows]`` and ``[model]``
(same keys and defaults, see :mod:`pipeplug_harness.scenes.file`) with these differences, and a
``[drive]`` section::

    [soil]          tau1; contact_growth may only be true (the pipe starts at the soil face:
                    model II, penetration 0, no outer contact)
    [blows]         amplitude [N], duration [s], period [s] (no count, no start: blow k starts
                    at k * period)
    [model]         elastic = true | false | "auto"; solver dt dx courant (no x_monitor: the
                    drive monitors the pipe's front end, whose displacement is the penetration);
                    without dx, the elastic model takes the coarsest grid of at least
                    GRID_CELLS cells along the pipe and GRID_CELLS along the blow's wave c1 td
                    whose cells fit L1 and L2 a whole number of times (:func:`grid_for`)
    [drive]
    target = 30.0           # [m] stop when the front end has gone in this far (default and
                            #     at most L1)
    refusal_set = 1e-4      # [m] refusal: a blow whose set is below this, or
    refusal_count = 10      #     refusal_count blows that together advance the pipe less
    refusal_length = 0.025  #     than refusal_length [m] (default: 10 blows per 25 mm)
    max_blows = 100000      # stop after this many blows
    step = 1e-4             # [s] communication step while the blow acts and just after it
                            #     (default: duration / 10; elastic: rounded down to whole
                            #     internal steps, see pipeplug_harness.drive.run)

A set threshold of 0 leaves only the other refusal: a blow that does not move the front end at
all (static friction holds it). Unknown sections, keys or values are errors naming the allowed
ones; every parameter is then checked by the core itself (:func:`check_with_core`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from pipeplug_harness.scenes.file import SECTIONS, SceneError, elastic_choice, read_sections

__all__ = ["DriveSpec", "DRIVE_SECTIONS", "DEFAULT_REFUSAL", "GRID_CELLS", "load_drive",
           "drive_spec", "check_with_core", "grid_for"]

_OPTION_NAMES = ("elastic", "contact_growth", "solver")

#: The default refusal of pile-driving practice: 10 blows per 25 mm.
DEFAULT_REFUSAL = (10, 0.025)
#: Without dx: at least this many cells along the pipe and along the blow's wave c1 td.
GRID_CELLS = 20
_GRID_TRIES = 10_000             # cell counts tried for one that fits L2 too

#: section -> {key: (python type, default)}: the scene tables, narrowed, and [drive].
DRIVE_SECTIONS = {
    "pipe": SECTIONS["pipe"],
    "plug": SECTIONS["plug"],
    "soil": {"tau1": SECTIONS["soil"]["tau1"], "contact_growth": (bool, True)},
    "blows": {k: SECTIONS["blows"][k] for k in ("amplitude", "duration", "period")},
    "model": {k: v for k, v in SECTIONS["model"].items() if k != "x_monitor"},
    "drive": {"target": (float, None), "refusal_set": (float, None),
              "refusal_count": (int, None), "refusal_length": (float, None),
              "max_blows": (int, 100_000), "step": (float, None)},
}


@dataclass(frozen=True)
class DriveSpec:
    """A validated drive: FMU start values, the blow train and the stopping rules.

    ``refusal_count`` blows advancing the pipe less than ``refusal_length`` [m] in all is a
    refusal (a set per blow threshold is ``refusal_count = 1``).
    """

    name: str
    start_values: dict       #: FMU start values (parameters and options), contract names, SI
    amplitude: float         #: [N]
    duration: float          #: [s]
    period: float            #: [s]
    target: float            #: [m]
    refusal_count: int
    refusal_length: float    #: [m]
    max_blows: int
    step: float              #: [s]
    reason: str              #: why the model is (not) elastic
    grid: str = ""           #: the elastic model's grid and where dx came from

    @property
    def elastic(self) -> bool:
        return bool(self.start_values["elastic"])

    def params(self):
        """The core's :class:`~pipeplug.params.Params` of this drive."""
        return _params(self.start_values)

    def refusal_text(self) -> str:
        if self.refusal_count == 1:
            return f"set < {self.refusal_length:g} m per blow"
        return f"{self.refusal_count} blows advance < {self.refusal_length:g} m"


def load_drive(path: str | Path) -> DriveSpec:
    """Read, validate and check a drive file (see the module docstring)."""
    path = Path(path)
    values = read_sections(path, DRIVE_SECTIONS, nested=("blows", "drive"))
    return drive_spec(path.stem, values)


def drive_spec(name: str, values: dict) -> DriveSpec:
    """A :class:`DriveSpec` from checked sections (``values`` as :func:`read_sections` gives
    them: the ``blows`` and ``drive`` sections nested, the rest flat)."""
    blows, drive = values.pop("blows"), values.pop("drive")
    if values["contact_growth"] is not True:
        raise SceneError("[soil] contact_growth = false; allowed: true (a drive starts at the "
                         "soil face: model II, outer friction over the penetrated length)")
    if not blows["period"] > blows["duration"]:
        raise SceneError(f"[blows] period = {blows['period']!r} s; allowed: > duration "
                         f"({blows['duration']!r} s)")
    if not (blows["amplitude"] > 0.0 and math.isfinite(blows["amplitude"])):
        raise SceneError(f"[blows] amplitude = {blows['amplitude']!r} N; allowed: > 0 (a blow "
                         f"drives the pipe into the soil)")
    elastic, reason = elastic_choice(values.pop("elastic"), values, blows["duration"])
    start = {k: v for k, v in values.items() if v is not None}
    start["elastic"] = elastic
    grid = ""
    if elastic:                                      # monitor the front end: penetration
        start["x_monitor"] = _params(start).L1
        if "dx" not in start:
            start["dx"], grid = grid_for(_params(start), blows["duration"])
        else:
            grid = "dx given"
    params = check_with_core(start)
    L1 = params.L1
    if elastic:
        grid = _grid_text(params, grid)
    target = L1 if drive["target"] is None else drive["target"]
    if not 0.0 < target <= L1:
        raise SceneError(f"[drive] target = {target!r} m; allowed: > 0 and <= L1 = {L1!r} m")
    count, length = _refusal(drive)
    step = blows["duration"] / 10.0 if drive["step"] is None else drive["step"]
    for key, value, ok, allowed in (("max_blows", drive["max_blows"], drive["max_blows"] >= 1,
                                     ">= 1"),
                                    ("step", step, step > 0.0 and math.isfinite(step), "> 0")):
        if not ok:
            raise SceneError(f"[drive] {key} = {value!r}; allowed: {allowed}")
    return DriveSpec(name, start, blows["amplitude"], blows["duration"], blows["period"],
                     target, count, length, drive["max_blows"], step, reason, grid)


def grid_for(params, duration: float) -> tuple[float, str]:
    """The drive's default dx [m] and how it was chosen: the fewest cells ``n >= GRID_CELLS``
    and ``>= GRID_CELLS L1 / (c1 td)`` (the blow's wave, ``td = duration`` [s], at least
    GRID_CELLS cells long) for which ``L2 n / L1`` is whole when the plug is simulated.

    Raises
    ------
    SceneError
        When no such count is found among the next few thousand (L2 / L1 not a ratio of small
        integers): the file must give dx.
    """
    p = params
    wave = p.c1 * duration
    least = max(GRID_CELLS, math.ceil(GRID_CELLS * p.L1 / wave - 1e-9))
    for n in range(least, least + _GRID_TRIES):
        plug_cells = p.L2 * n / p.L1
        if not p.has_plug or abs(plug_cells - round(plug_cells)) <= 1e-9 * max(1.0, plug_cells):
            return p.L1 / n, (f"dx chosen: the fewest cells >= {GRID_CELLS} along the pipe and "
                              f">= {GRID_CELLS} along the blow's wave c1 td = {wave:.4g} m that "
                              f"fit L1 and L2")
    raise SceneError(f"[model] no dx given, and no grid of {least} to {least + _GRID_TRIES - 1} "
                     f"cells fits both L1 = {p.L1!r} m and L2 = {p.L2!r} m; give dx (a length "
                     f"that divides both)")


def _grid_text(params, how: str) -> str:
    """The elastic grid in words: cells, dx, internal step."""
    from pipeplug.elastic.grid import build_grid
    g = build_grid(params)
    plug = f" and {g.n2} plug cells" if g.n2 else ""
    return (f"model III grid: {g.n1} pipe cells{plug} of dx = {params.dx:.6g} m ({how}), "
            f"internal step {g.h_max:.4g} s")


def _refusal(drive: dict) -> tuple[int, float]:
    """(count, length) of the set refusal from either form in [drive]."""
    per_blow = drive["refusal_set"]
    count, length = drive["refusal_count"], drive["refusal_length"]
    if per_blow is not None and (count is not None or length is not None):
        raise SceneError("[drive] give either refusal_set, or refusal_count and refusal_length "
                         "(blows per length), not both")
    if per_blow is not None:
        count, length = 1, per_blow
    elif count is None and length is None:
        count, length = DEFAULT_REFUSAL
    elif count is None or length is None:
        raise SceneError("[drive] refusal_count and refusal_length go together (blows per "
                         "length)")
    if count < 1:
        raise SceneError(f"[drive] refusal_count = {count!r}; allowed: >= 1")
    if not (length >= 0.0 and math.isfinite(length)):
        raise SceneError(f"[drive] refusal length = {length!r} m; allowed: >= 0 "
                         f"(0: only a blow that does not move the pipe is a refusal)")
    return count, length


def check_with_core(start_values: dict):
    """Build the core model from the start values, as the FMU does at initialization, so that
    every parameter and option is checked by the core's own rules before a run.

    Returns
    -------
    Params
        The validated parameters.

    Raises
    ------
    pipeplug.ParameterError
        Naming the offending parameter or option, its value and the allowed range.
    """
    from pipeplug import build_model
    from pipeplug.options import Options
    options = Options.from_mapping({k: start_values[k] for k in _OPTION_NAMES
                                    if k in start_values})
    params = _params(start_values)
    build_model(params, options)
    return params


def _params(start_values: dict):
    """The core's Params from start values (options left out), not yet validated."""
    from pipeplug.params import Params
    return Params.from_mapping({k: v for k, v in start_values.items()
                                if k not in _OPTION_NAMES})
