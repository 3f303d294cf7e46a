"""Scene files: one job described in TOML, read against a closed table of keys.

A scene names the pipe, the plug, the soil, the blows, the model choices and the outputs::

    [pipe]                      # any of: L1 R1 h1 rho1 E1
    L1 = 1.0
    [plug]                      # any of: L2 rho2 E2 tau2   (tau2 = 0 or L2 = 0: no plug)
    tau2 = 1.0e4
    [soil]                      # any of: tau1 contact_growth
    tau1 = 2.0e4
    [blows]                     # amplitude [N], duration [s], count, period [s], start [s]
    amplitude = 23000.0
    duration = 0.05
    [model]                     # elastic = true | false | "auto"; solver; dt dx courant x_monitor
    elastic = "auto"
    [output]                    # stop_time [s], step [s], variables
    stop_time = 0.3

Unknown sections, keys or values are errors that name the allowed ones. Values not given take
the FMU's defaults. ``elastic = "auto"`` applies the paper's criterion (section 4): the rigid
model is used when the blow lasts at least ``AUTO_RATIO`` wave round trips 2 L1 / c1.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:                                   # pragma: no cover - Python 3.10
    import tomli as tomllib

from pipeplug_harness.fmu_run import OUTPUTS, Pulse

__all__ = ["Scene", "SceneError", "load_scene", "read_sections", "read_toml", "checked_sections",
           "elastic_choice", "AUTO_RATIO", "SECTIONS"]

#: Blow duration / wave round trip at and above which "auto" picks the rigid model. The paper's
#: Fig. 7 case (ratio 125) differs from the elastic model by well under 1 % in peak velocity.
AUTO_RATIO = 20.0

#: section -> {key: (python type(s), default or None = the FMU's default)}
SECTIONS = {
    "pipe": {"L1": (float, None), "R1": (float, None), "h1": (float, None),
             "rho1": (float, None), "E1": (float, None)},
    "plug": {"L2": (float, None), "rho2": (float, None), "E2": (float, None),
             "tau2": (float, None)},
    "soil": {"tau1": (float, None), "contact_growth": (bool, None)},
    "blows": {"amplitude": (float, 23000.0), "duration": (float, 0.05), "count": (int, 1),
              "period": (float, 0.1), "start": (float, 0.0)},
    "model": {"elastic": ((bool, str), "auto"), "solver": (str, None), "dt": (float, None),
              "dx": (float, None), "courant": (float, None), "x_monitor": (float, None)},
    "output": {"stop_time": (float, None), "step": (float, 1e-3),
               "variables": (list, list(OUTPUTS[:4]))},
}


class SceneError(ValueError):
    """A scene file names an unknown section, key or value."""


@dataclass
class Scene:
    """A validated scene: FMU start values, blows, output settings and why it is (not) elastic."""

    name: str
    start_values: dict
    pulses: list
    stop_time: float
    step: float
    variables: list
    reason: str = ""


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file (TOML)."""
    path = Path(path)
    values = read_sections(path, SECTIONS, nested=("blows", "output"))
    blows = values.pop("blows")
    output = values.pop("output")
    pulses = [Pulse(blows["start"] + i * blows["period"], blows["duration"], blows["amplitude"])
              for i in range(blows["count"])]
    elastic, reason = elastic_choice(values.pop("elastic"), values, blows["duration"])
    start_values = {k: v for k, v in values.items() if v is not None}
    start_values["elastic"] = elastic
    stop = output["stop_time"] or pulses[-1].end + 0.25
    return Scene(path.stem, start_values, pulses, stop, output["step"],
                 list(output["variables"]), reason)


def read_sections(path: str | Path, sections: dict, nested=()) -> dict:
    """Read a TOML file and check it against a table of sections (see :func:`checked_sections`)."""
    return checked_sections(read_toml(path), sections, nested)


def read_toml(path: str | Path) -> dict:
    """The parsed TOML file, unchecked."""
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def checked_sections(raw: dict, sections: dict, nested=()) -> dict:
    """Check every section and key of ``raw`` against ``sections`` and fill in the defaults.

    Parameters
    ----------
    raw : dict
        The parsed TOML.
    sections : dict
        section -> {key: (python type(s), default)}, like :data:`SECTIONS`.
    nested : sequence of str
        Sections kept as their own dict; the keys of the others are flattened into one dict
        (they are FMU start values).

    Raises
    ------
    SceneError
        Naming the unknown section, key or value and the allowed ones.
    """
    for section in raw:
        if section not in sections:
            raise SceneError(f"unknown section [{section}]; allowed: {', '.join(sections)}")
    flat = {}
    for section, keys in sections.items():
        given = raw.get(section, {})
        for key in given:
            if key not in keys:
                raise SceneError(f"unknown key {key!r} in [{section}]; allowed: "
                                 f"{', '.join(keys)}")
        out = flat.setdefault(section, {}) if section in nested else flat
        for key, (kind, default) in keys.items():
            out[key] = _typed(section, key, given.get(key, default), kind)
    return flat


_ACCEPTS = {
    float: lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    int: lambda v: isinstance(v, int) and not isinstance(v, bool),
    bool: lambda v: isinstance(v, bool),
    str: lambda v: isinstance(v, str),
    list: lambda v: isinstance(v, list),
    dict: lambda v: isinstance(v, dict),
    (bool, str): lambda v: isinstance(v, bool) or v == "auto",
    (list, dict): lambda v: isinstance(v, (list, dict)),
}
_TYPE_NAMES = {float: "a number", int: "an integer", bool: "true or false", str: "a string",
               list: "a list", dict: "a table", (bool, str): 'true, false or "auto"',
               (list, dict): "a list or a table"}


def _typed(section: str, key: str, value, kind):
    """``value`` converted to ``kind``, or SceneError naming what is allowed."""
    if value is None:
        return None
    if not _ACCEPTS[kind](value):
        raise SceneError(f"[{section}] {key} = {value!r}; allowed: {_TYPE_NAMES[kind]}")
    if key == "variables":
        unknown = [v for v in value if v not in OUTPUTS]
        if unknown:
            raise SceneError(f"[output] unknown variables {unknown}; allowed: "
                             f"{', '.join(OUTPUTS)}")
    return float(value) if kind is float else value


def elastic_choice(choice, values: dict, duration: float) -> tuple[bool, str]:
    """Resolve ``elastic = "auto"`` by the paper's criterion and say why."""
    if isinstance(choice, bool):
        return choice, f"elastic = {str(choice).lower()} (given)"
    from pipeplug.params import Params
    given = {k: values[k] for k in ("L1", "rho1", "E1") if values.get(k) is not None}
    p = Params().with_(**given)
    round_trip = 2.0 * p.L1 / math.sqrt(p.E1 / p.rho1)
    ratio = duration / round_trip
    rigid = ratio >= AUTO_RATIO
    verdict = "rigid" if rigid else "elastic"
    return (not rigid, f"auto: blow {duration:g} s = {ratio:.3g} x the wave round trip "
                       f"2 L1/c1 = {round_trip:.3g} s ({'>=' if rigid else '<'} {AUTO_RATIO:g}) "
                       f"-> {verdict} model")
