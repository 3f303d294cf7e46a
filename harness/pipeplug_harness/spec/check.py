"""Checking parsed sections against the closed tables: known sections and keys, types, units,
required keys, plausibility.

Every refusal is a :class:`~pipeplug_harness.errors.UserError` naming ``[section] key``, the value
and what is allowed.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import replace

from pipeplug_harness.errors import UserError

from .tables import KINDS_OF_VALUE, Key
from .units import to_si

__all__ = ["check_sections", "value_of", "plausibility", "allowed_names"]


def check_sections(raw: dict, sections: dict, nested=(), required=(), varied=()) -> dict:
    """Check every section and key of ``raw`` against ``sections`` and fill in the defaults.

    Parameters
    ----------
    raw : dict
        The parsed file (sections as tables).
    sections : dict
        section -> {key: :class:`~.tables.Key`}: what this kind of file takes.
    nested : sequence of str
        Sections kept as their own dict; the keys of the others are flattened into one dict
        (they are FMU start values).
    required : sequence of str
        Sections the file must have.
    varied : sequence of str
        Keys a sweep varies: they count as given (their base value may be absent).

    Returns
    -------
    dict
        The values in SI (``None``: the FMU's default).
    """
    for section, given in raw.items():
        if section not in sections:
            raise UserError(f"unknown section [{section}]; allowed: {', '.join(sections)}")
        if not isinstance(given, dict):
            raise UserError(key=f"[{section}]", value=given, allowed="a section of keys")
        for key in given:
            if key not in sections[section]:
                raise UserError(f"unknown key {key!r} in [{section}]; allowed: "
                                f"{', '.join(sections[section])}")
    for section in required:
        if section not in raw and not any(k in varied for k in sections[section]):
            raise UserError(f"missing section [{section}]: this file needs it (keys: "
                            f"{', '.join(sections[section])})")
    out = {}
    for section, keys in sections.items():
        given = raw.get(section, {})
        target = out.setdefault(section, {}) if section in nested else out
        for key, spec in keys.items():
            if key in given:
                target[key] = value_of(f"[{section}] {key}", given[key], spec)
            elif spec.required and key not in varied and section in raw:
                raise UserError(f"[{section}] {key} is missing: give it ({spec.meaning}, "
                                f"{spec.unit or KINDS_OF_VALUE[spec.kind]})")
            else:
                target[key] = spec.default
    return out


def value_of(where: str, value, spec: Key):
    """``value`` of the key ``spec`` at ``where``, checked and in SI (a list kind: each item,
    and the list strictly ascending)."""
    if spec.kind in _LISTS:
        return _ascending(where, value, replace(spec, kind=_LISTS[spec.kind]))
    value = _typed(where, value, spec)
    low = spec.lower
    if low is not None and not (value > low if spec.strict else value >= low):
        unit = f" {spec.unit}" if spec.unit not in ("", "1") else ""
        raise UserError(key=where, value=value,
                        allowed=f"{'>' if spec.strict else '>='} {low:g}{unit}")
    return value


#: list kind -> the kind of its items
_LISTS = {"numbers": "number", "integers": "integer"}


def _ascending(where: str, value, item: Key) -> tuple:
    """A non-empty list of ``item`` values, each checked, strictly ascending."""
    if not isinstance(value, list) or not value:
        raise UserError(key=where, value=value,
                        allowed=f"a non-empty list of {item.kind}s"
                                + (f" in {item.unit} or quantities with their unit"
                                   if item.kind == "number" else ""))
    items = tuple(value_of(f"{where}[{i}]", v, item) for i, v in enumerate(value))
    if any(b <= a for a, b in zip(items, items[1:])):
        raise UserError(key=where, value=value, allowed="values in strictly ascending order")
    return items


def _typed(where: str, value, spec: Key):
    """``value`` as the key's kind (numbers in SI)."""
    kind = spec.kind
    if kind == "number":
        if isinstance(value, str):
            return to_si(where, value, spec.unit)
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise UserError(key=where, value=value,
                            allowed=f"a number in {spec.unit} or a quantity with its unit")
        if not math.isfinite(value):
            raise UserError(key=where, value=value, allowed="a finite number")
        return float(value)
    if kind == "integer":
        if isinstance(value, float) and value.is_integer() and abs(value) < 2 ** 63:
            value = int(value)                  # 1e3 is an integer written as a float
        if isinstance(value, bool) or not isinstance(value, int):
            raise UserError(key=where, value=value, allowed="an integer")
        return value
    if kind == "bool":
        if not isinstance(value, bool):
            raise UserError(key=where, value=value, allowed="true or false")
        return value
    if kind == "auto":
        if not (isinstance(value, bool) or value == "auto"):
            raise UserError(key=where, value=value, allowed='true, false or "auto"')
        return value
    if kind == "choice":
        if value not in spec.choices or not isinstance(value, str):
            raise UserError(key=where, value=value, allowed=", ".join(spec.choices))
        return value
    if kind == "names":
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise UserError(key=where, value=value, allowed="a list of names (strings)")
        unknown = [v for v in value if spec.choices and v not in spec.choices]
        if unknown:
            raise UserError(f"{where}: unknown names {unknown}; allowed: "
                            f"{', '.join(spec.choices)}")
        if spec.choices and (not value or len(set(value)) < len(value)):
            # a choice of outputs: a run recording nothing, or a column twice, is a slip
            raise UserError(key=where, value=value, allowed="one or more names, each once, of "
                                                            + ", ".join(spec.choices))
        return tuple(value)
    raise UserError(key=where, value=value, allowed=KINDS_OF_VALUE.get(kind, kind))


def plausibility(where: str, key: str, value: float, spec: Key, allowed: set) -> None:
    """Refuse ``value`` outside the key's plausible range unless the file allows ``key``."""
    if spec.plausible is None or value is None or key in allowed:
        return
    if isinstance(value, tuple):                   # a list kind: each item
        for i, item in enumerate(value):
            plausibility(f"{where}[{i}]", key, item, spec, allowed)
        return
    low, high = spec.plausible
    if low <= value <= high:
        return
    unit = f" {spec.unit}" if spec.unit not in ("", "1") else ""
    raise UserError(f"{where} = {value!r}{unit} is outside the plausible range "
                    f"{low:g}-{high:g}{unit} (a unit slip?); if it is meant, allow it by name: "
                    f"[checks] allow = [\"{key}\"]")


def allowed_names(values: dict, sections: dict) -> set:
    """The names ``[checks] allow`` lists, each checked to be a key of the file's sections."""
    names = set(values.get("checks", {}).get("allow", ()) or ())
    known = {k for s, keys in sections.items() if s != "checks" for k in keys}
    unknown = sorted(names - known)
    if unknown:
        raise UserError(f"[checks] allow names {unknown}, which are no keys of this file; "
                        f"allowed: {', '.join(sorted(known))}")
    return names
