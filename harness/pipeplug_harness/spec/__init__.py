"""The file format of scene, drive and sweep files: TOML read against one closed table of
sections (:mod:`.tables`), selected per kind of file (:mod:`.kinds`).

A value is SI as a number, or a string with its unit (``"610 mm"``, ``"10 kPa"``); keys outside
their plausible range are refused unless ``[checks] allow`` names them; a file must have the
sections its run needs. Every refusal is one :class:`~pipeplug_harness.errors.UserError` naming
the file, ``[section] key``, the value and what is allowed.
"""
from __future__ import annotations

from pipeplug_harness.errors import UserError

from .blows import blow_train, period_of, ram_train
from .check import allowed_names, check_sections, plausibility, value_of
from .kinds import DRIVE, SCENE, SWEEP_BLOW, SWEEP_DRIVE, SWEEP_KINDS, FileKind
from .model import AUTO_RATIO, elastic_choice, unused_model_keys
from .tables import SECTIONS, Key
from .toml import read_toml

__all__ = ["AUTO_RATIO", "elastic_choice", "unused_model_keys", "read_toml", "checked", "read_file", "blow_train",
           "period_of", "ram_train", "value_of",
           "FileKind", "Key", "SECTIONS", "SCENE", "DRIVE", "SWEEP_BLOW", "SWEEP_DRIVE",
           "SWEEP_KINDS", "check_plausible", "plausibility"]


def checked(raw: dict, kind: FileKind, varied=()) -> dict:
    """The sections of a parsed file checked as ``kind`` (types, units, required sections and
    keys, plausibility), in SI; see :func:`.check.check_sections` for the shape."""
    values = check_sections(raw, kind.sections, kind.nested, kind.required, varied)
    check_plausible(values, kind, allowed_names(values, kind.sections))
    return values


def check_plausible(values: dict, kind: FileKind, allowed: set) -> None:
    """Every value of ``values`` (as :func:`checked` gives them) within its plausible range,
    unless ``allowed`` names its key."""
    for section, keys in kind.sections.items():
        here = values.get(section, {}) if section in kind.nested else values
        for key, spec in keys.items():
            if spec.kind in ("number", "integer", "numbers", "integers"):
                plausibility(f"[{section}] {key}", key, here.get(key), spec, allowed)


def read_file(path, kind: FileKind) -> dict:
    """Read and check the file ``path`` as ``kind``; errors name the file."""
    raw = read_toml(path)
    try:
        return checked(raw, kind)
    except UserError as exc:
        raise exc.in_file(path) from None
