"""The file format: one closed table of keys per section, shared by scene, drive and sweep files.

Each key (:class:`Key`) has a kind, an SI unit (numbers may be written with any unit of the same
dimension), a default, whether a file must give it, and a plausibility range: a value outside it
(a pipe radius of 292 m, a train of 1e11 blows) is refused unless the file allows that key by
name (``[checks] allow = ["R1"]``). The hard ranges are the core's and the Hammer's own checks,
applied after these. Adding a section or a key is one entry here; a file kind
(:mod:`.kinds`) then says which sections it takes. A key that is a core parameter or option is
one line ``name: _core(name, plausible)``: its unit, kind, meaning and hard bounds come from the
core's tables (:data:`pipeplug.PARAMETERS`, :data:`pipeplug.options.OPTIONS`).

A default of ``None`` means "the FMU's default" (the key is not passed on).
"""
from __future__ import annotations

from dataclasses import dataclass

from pipeplug import OUTPUT_NAMES, PARAMETERS
from pipeplug.options import OPTIONS
from pipeplug_fmu.blows import PARAMETERS as BLOW_PARAMETERS

__all__ = ["Key", "SECTIONS", "KINDS_OF_VALUE", "blow_default"]

#: kind -> what a value of it is, in words (for messages)
KINDS_OF_VALUE = {"number": "a number", "integer": "an integer", "bool": "true or false",
                  "string": "a string", "auto": 'true, false or "auto"', "names": "a list of names",
                  "choice": "one of the names listed",
                  "numbers": "a list of numbers, ascending", "integers": "a list of integers, "
                                                                         "ascending"}

_CORE = {p.name: p for p in PARAMETERS}


@dataclass(frozen=True)
class Key:
    """One key of a section.

    ``unit`` is its SI unit (numbers); ``plausible`` the inclusive range (SI) outside which a
    value needs ``[checks] allow``; ``choices`` the allowed values of a choice or the allowed
    names of a list; ``required`` a file must give it (or, in a sweep, vary it). A key of kind
    ``"numbers"`` or ``"integers"`` is a list of them, strictly ascending, each within the
    bounds and the plausible range.
    """

    kind: str
    unit: str = ""
    default: object = None
    required: bool = False
    plausible: tuple | None = None
    choices: tuple = ()
    meaning: str = ""
    lower: float | None = None       #: hard lower bound (no file can allow past it)
    strict: bool = False             #: the lower bound is excluded


def _core(name: str, plausible: tuple | None = None, required: bool = False) -> Key:
    """A key that is a core parameter or option: its kind, unit, meaning and hard bounds from
    the core's tables (a parameter: a number in its SI unit, ``plausible`` its plausible
    range; an option: true or false, or one of its names). Default ``None``: the FMU's."""
    if name in OPTIONS:
        allowed, _, meaning = OPTIONS[name]
        if set(allowed) == {False, True}:
            return Key("bool", required=required, meaning=meaning)
        return Key("choice", required=required, choices=allowed, meaning=meaning)
    p = _CORE[name]
    return Key("number", p.unit, None, required, plausible, meaning=p.description,
               lower=p.lower, strict=p.strict_lower)


def _positive(unit: str, plausible: tuple, meaning: str, default=None, strict=True,
              kind="number") -> Key:
    """A key whose values are > 0 (``strict``) or >= 0."""
    return Key(kind, unit, default, False, plausible, meaning=meaning, lower=0.0,
               strict=strict)


def blow_default(name: str):
    """The Hammer FMU's default of a blow-train parameter (the one rule set of blow trains)."""
    return next(p.default for p in BLOW_PARAMETERS if p.name == name)


#: section -> {key: Key}. The plausible ranges cover pipes rammed or jacked in practice (a few
#: centimetres to 4 m across, up to a few hundred metres long), soils from none to rock-like
#: friction, and hammers from hand tools to the largest rammers.
SECTIONS: dict[str, dict[str, Key]] = {
    "pipe": {
        "L1": _core("L1", (0.05, 500.0), required=True),
        "R1": _core("R1", (0.005, 2.0)),
        "h1": _core("h1", (2e-4, 0.2)),
        "rho1": _core("rho1", (500.0, 25000.0)),
        "E1": _core("E1", (1e6, 1e12)),
    },
    "plug": {
        "L2": _core("L2", (0.0, 500.0), required=True),
        "rho2": _core("rho2", (100.0, 5000.0)),
        "E2": _core("E2", (1e3, 1e12)),
        "tau2": _core("tau2", (0.0, 1e7), required=True),
        "plug_growth": _core("plug_growth"),
        "L2_after_cleanout": _core("L2_after_cleanout", (0.0, 500.0)),
    },
    "soil": {
        "tau1": _core("tau1", (0.0, 1e7), required=True),
        "contact_growth": Key("bool", default=False,
                              meaning="model II: outer friction over the penetrated length"),
        # end bearing from none to rock (cone resistances of dense sand reach 20-40 MPa)
        "q_face": _core("q_face", (0.0, 1e8)),
        "q_plug_face": _core("q_plug_face", (0.0, 1e8)),
        # Smith's damping factors: shaft 0.16 s/m (sand) to 0.66 s/m (clay), toe 0.49 s/m
        "J_shaft": _core("J_shaft", (0.0, 10.0)),
        "J_face": _core("J_face", (0.0, 10.0)),
    },
    "blows": {
        "amplitude": Key("number", "N", None, True, (-1e9, 1e9), meaning="force of every blow"),
        "duration": Key("number", "s", None, True, (1e-7, 100.0), meaning="length of one blow",
                         lower=0.0, strict=True),
        "period": _positive("s", (1e-4, 1e5), "from one blow's start to the next's (or give "
                                              "rate; default: the Hammer's)"),
        "rate": _positive("1/s", (1e-5, 1e4), "blows per second, e.g. \"200 /min\" (instead "
                                              "of period)"),
        "count": _positive("1", (0, 1e6), "number of blows; 0 = no end (to the stop time)",
                           blow_default("count"), strict=False, kind="integer"),
        "start": _positive("s", (0.0, 1e5), "when the first blow starts (a run starts at 0)",
                           blow_default("start"), strict=False),
    },
    "model": {
        "elastic": Key("auto", default="auto", meaning='model III; "auto": the paper\'s rule'),
        "solver": _core("solver"),
        "dt": _core("dt", (1e-9, 1.0)),
        "dx": _core("dx", (1e-4, 100.0)),
        "courant": _core("courant", (0.01, 1.0)),
        "x_monitor": _core("x_monitor", (0.0, 500.0)),
    },
    "output": {
        "stop_time": _positive("s", (1e-6, 1e5), "end of the run"),
        "step": _positive("s", (1e-8, 1e3), "communication step", 1e-3),
        "variables": Key("names", default=OUTPUT_NAMES[:4], choices=OUTPUT_NAMES,
                         meaning="outputs recorded"),
        "modes": Key("bool", default=False, meaning="sweeps: a column of the contact modes"),
    },
    "hammer": {
        "rated_energy": Key("number", "J", None, True, (10.0, 1e7),
                            meaning="the hammer's rated energy per blow, e.g. \"40.5 kJ\"",
                            lower=0.0, strict=True),
        "efficiency": Key("number", "1", 1.0, False, None, lower=0.0, strict=True,
                          meaning="share of the rated energy the ram has when it strikes "
                                  "(<= 1)"),
        "ram_mass": Key("number", "kg", None, True, (1.0, 1e5), lower=0.0, strict=True,
                        meaning="mass of the ram, e.g. \"300 kg\""),
        "rate": Key("number", "1/s", None, True, (1e-3, 50.0), lower=0.0, strict=True,
                    meaning="blows per second, e.g. \"200 /min\""),
        "cushion_stiffness": Key("number", "N/m", 0.0, False, (0.0, 1e12), lower=0.0,
                                 meaning="the cushion's stiffness; 0: the ram strikes the "
                                         "head directly"),
        "cushion_restitution": Key("number", "1", 1.0, False, None, lower=0.0,
                                   strict=True, meaning="the cushion's coefficient of "
                                                        "restitution (<= 1)"),
        "count": _positive("1", (0, 1e6), "scenes: number of strikes; 0 = no end (to the stop "
                                          "time)", 1, strict=False, kind="integer"),
        "start": _positive("s", (0.0, 1e5), "scenes: when the first strike starts", 0.0,
                           strict=False),
    },
    "drive": {
        "target": _positive("m", (1e-4, 500.0), "depth to reach"),
        "refusal_set": _positive("m", (0.0, 1.0), "refusal: a set per blow below this",
                                 strict=False),
        "refusal_count": Key("integer", "1", None, False, (1, 1e4), lower=1,
                             meaning="refusal: this many blows advance less than ..."),
        "refusal_length": _positive("m", (0.0, 10.0), "... this length in all (> 0; for no "
                                                      "set refusal, refusal_set = 0)"),
        "max_blows": Key("integer", "1", 100_000, False, (1, 1e7), lower=1, meaning="stop after"),
        "step": _positive("s", (1e-8, 10.0), "communication step while a blow acts"),
        "yield_stress": _positive("Pa", (1e6, 5e9), "the pipe's yield stress: the drive "
                                                    "reports its largest stress against it"),
        "cleanout_at": _positive("m", (1e-3, 500.0), "clean-outs: before the first blow at or "
                                                     "past each of these penetrations",
                                 kind="numbers"),
        "cleanout_at_blows": Key("integers", "1", None, False, (1, 1e7), lower=1,
                                 meaning="clean-outs: before each of these blows (instead of "
                                         "cleanout_at)"),
    },
    "sweep": {
        "kind": Key("choice", default="blow", choices=("blow", "drive"),
                    meaning="a case is a single blow or a whole drive"),
        "seed": Key("integer", "1", 0, False, None, meaning="random sample's seed", lower=0),
        "samples": Key("integer", "1", None, False, (1, 1e9), lower=1,
                       meaning="random sample's size"),
        "chunk": Key("integer", "1", None, False, (1, 1e7), lower=1, meaning="cases per task"),
        "report": Key("choice", default="none", choices=("none", "domains", "drivability"),
                      meaning="what is reported after the run"),
    },
    "checks": {
        "allow": Key("names", default=(), meaning="keys allowed outside their plausible range"),
    },
}
