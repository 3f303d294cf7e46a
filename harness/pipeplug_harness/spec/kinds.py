"""The kinds of file (scene, drive, sweep) as selections of the one table of sections.

A kind names the sections it takes (narrowed to the keys that make sense for it), which of them
it keeps nested (the rest are flattened into FMU start values) and which a file must have.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from .tables import SECTIONS, Key

__all__ = ["FileKind", "SCENE", "DRIVE", "DRIVE_BLOWS", "SWEEP_BLOW", "SWEEP_DRIVE",
           "SWEEP_KINDS"]


@dataclass(frozen=True)
class FileKind:
    """What one kind of file takes."""

    name: str
    sections: dict           #: section -> {key: Key}
    nested: tuple            #: sections kept as their own dict
    required: tuple          #: sections a file must have


def _only(section: str, *keys: str, **changed: Key) -> dict:
    """The keys ``keys`` of ``section`` (all when none named), some replaced."""
    table = {k: v for k, v in SECTIONS[section].items() if not keys or k in keys}
    return {**table, **changed}


_PHYSICS = {"pipe": _only("pipe"), "plug": _only("plug"), "soil": _only("soil")}
_REQUIRED = ("pipe", "plug", "soil", "blows")

SCENE = FileKind("scene", {
    **_PHYSICS, "blows": _only("blows"), "hammer": _only("hammer"), "model": _only("model"),
    "output": _only("output", "stop_time", "step", "variables"), "checks": _only("checks")},
    nested=("blows", "hammer", "output", "checks"), required=("pipe", "plug", "soil"))

#: a drive starts at the soil face (model II), blow k at k period, and monitors the front end
DRIVE = FileKind("drive", {
    **_PHYSICS,
    "soil": _only("soil", contact_growth=replace(SECTIONS["soil"]["contact_growth"],
                                                 default=True)),
    "blows": _only("blows", "amplitude", "duration", "period", "rate"),
    "hammer": {k: v for k, v in SECTIONS["hammer"].items() if k not in ("count", "start")},
    "model": {k: v for k, v in SECTIONS["model"].items() if k != "x_monitor"},
    "drive": _only("drive"), "checks": _only("checks")},
    nested=("blows", "hammer", "drive", "checks"), required=("pipe", "plug", "soil"))
#: the sections of a drive that say how the blows come: exactly one of them
DRIVE_BLOWS = ("blows", "hammer")

#: a sweep of single blows runs each case until all is at rest or stop_time
SWEEP_BLOW = FileKind("sweep", {
    **{k: v for k, v in SCENE.sections.items() if k not in ("output", "hammer")},
    "output": _only("output", "stop_time", "modes",
                    stop_time=replace(SECTIONS["output"]["stop_time"], default=100.0)),
    "sweep": _only("sweep")},
    nested=("blows", "output", "checks", "sweep"), required=_REQUIRED)

SWEEP_DRIVE = FileKind("sweep", {**DRIVE.sections, "sweep": _only("sweep")},
                       nested=("blows", "hammer", "drive", "checks", "sweep"),
                       required=DRIVE.required)

#: [sweep] kind -> its file kind
SWEEP_KINDS = {"blow": SWEEP_BLOW, "drive": SWEEP_DRIVE}
