"""The blow trains of Hammer.fmu: its parameters, their ranges, and its outputs at a time.

Two trains, chosen by ``ram_mass`` (the table's one switch, as PipePlug's): 0 (the default)
gives rectangular blows of a force Q; > 0 gives strikes of a ram of that mass for PipePlug's
own ram (PipePlug's ``ram_mass`` should be the same), at ``blows_per_minute``, each at the
velocity ``v_strike = sqrt(2 efficiency rated_energy / ram_mass)``; Q is then 0.

Rectangular blows:

A train of ``count`` rectangular blows (``count = 0``: no end) of force ``amplitude`` [N], each
lasting ``duration`` [s], blow k starting at ``start + k period`` (k = 0, 1, ...)::

    Q(t) = amplitude   if start + k period <= t < start + k period + duration
                       for some integer k with 0 <= k (and k < count when count > 0)
    Q(t) = 0           otherwise

Ram strikes: strike k (k = 0, 1, ...; k < count when count > 0) starts at
``start + 60 k / blows_per_minute``; ``strikes(t)`` is the number started at or before t, so each
increase, seen by PipePlug at a communication point, starts one strike there.

Q (and ``strikes``) is right-continuous: at an edge it takes the value after the edge, which is the force of a
communication step that starts there. A time within :data:`EDGE_TOLERANCE` ``* max(1, |t|)`` of
an edge counts as on it, so a host whose communication points are computed as ``k h``,
accumulated as ``t += h`` or counted in integer nanoseconds (libcosim) still lands on the edges
its grid contains. Edges closer together than that tolerance are not resolved.

Pure Python (``math`` only): shipped inside Hammer.fmu beside its slave, read by the build
(modelDescription.xml, documentation) and by the harness, which checks a system's Hammer
parameters with :func:`check` before libcosim runs it.
"""
from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["BlowParameter", "BlowTrain", "RamTrain", "BlowTrainError", "PARAMETERS", "OUTPUTS",
           "DESCRIPTION", "DEFAULT_EXPERIMENT", "EDGE_TOLERANCE", "check"]

#: Relative tolerance of a time on an edge (and of the FMU's time check); as PipePlug's.
EDGE_TOLERANCE = 1e-9

#: What the FMU is (modelDescription.xml and documentation).
DESCRIPTION = ("A train of rectangular blows: the force Q on the struck end of a pipe, for "
               "PipePlug's input Q")

#: The outputs: (name, FMI type, unit, meaning), in registration order.
OUTPUTS = (
    ("Q", "Real", "N", "force of the blow train for the communication step that starts at the "
                       "FMU's current time (right-continuous); positive drives the pipe into "
                       "the soil; 0 with a ram"),
    ("strikes", "Integer", None, "strikes of the ram started at or before the FMU's current "
                                 "time (for PipePlug's input strikes); 0 without a ram"),
    ("v_strike", "Real", "m/s", "the ram's velocity at a strike, sqrt(2 efficiency "
                                "rated_energy / ram_mass) (for PipePlug's input v_strike); 0 "
                                "without a ram"),
)

#: The default experiment written into modelDescription.xml: (start [s], stop [s], step [s]).
#: The step contains every edge of the default train (0, 0.05 s).
DEFAULT_EXPERIMENT = (0.0, 0.2, 1e-3)


class BlowTrainError(ValueError):
    """A parameter of the blow train outside its allowed set (same wording as PipePlug's)."""

    def __init__(self, name: str, value: object, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {value!r} is not allowed; allowed: {allowed}")


@dataclass(frozen=True)
class BlowParameter:
    """One row of the parameter table; ``lower`` is exclusive when ``strict_lower`` is set.

    ``lower`` also goes into modelDescription.xml as ``min`` (FMI bounds are inclusive).
    """

    name: str
    kind: str                      # "Real" or "Integer"
    unit: str | None
    default: float | int
    description: str
    allowed: str
    lower: float | int | None = None
    strict_lower: bool = False
    upper: float | None = None     #: inclusive


PARAMETERS: tuple[BlowParameter, ...] = (
    BlowParameter("amplitude", "Real", "N", 23000.0,
                  "force of every blow; positive drives the pipe into the soil", "finite"),
    BlowParameter("duration", "Real", "s", 0.05, "length of one blow",
                  "finite, > 0 and <= period", 0.0, True),
    BlowParameter("period", "Real", "s", 0.2, "time from the start of one blow to the next",
                  "finite, > 0", 0.0, True),
    BlowParameter("count", "Integer", None, 1, "number of blows; 0 = no end",
                  "an Integer >= 0", 0),
    BlowParameter("start", "Real", "s", 0.0, "time at which the first blow starts", "finite"),
    BlowParameter("ram_mass", "Real", "kg", 0.0, "mass of the ram; 0: rectangular blows of Q, "
                  "> 0: strikes of this ram (amplitude, duration and period then unused)",
                  "finite, >= 0", 0.0),
    BlowParameter("rated_energy", "Real", "J", 0.0, "rated energy of one blow (with a ram)",
                  "finite, >= 0 (> 0 with a ram)", 0.0),
    BlowParameter("efficiency", "Real", "1", 1.0, "share of the rated energy the ram has at "
                  "the strike", "finite, > 0 and <= 1", 0.0, True, 1.0),
    BlowParameter("blows_per_minute", "Real", "1/min", 60.0, "strikes per minute (with a ram)",
                  "finite, > 0", 0.0, True),
)
_BY_NAME = {p.name: p for p in PARAMETERS}


@dataclass(frozen=True)
class BlowTrain:
    """A checked train of rectangular blows (build one with :func:`check`)."""

    amplitude: float
    duration: float
    period: float
    count: int
    start: float
    v_strike = 0.0          #: no ram [m/s]

    def force(self, t: float) -> float:
        """The force [N] at time ``t`` [s]: right-continuous, edges within the tolerance."""
        k = _started(self.start, self.period, self.count, t) - 1   # the last blow started
        if k < 0:
            return 0.0
        since = t - self.start - k * self.period
        return self.amplitude if since < self.duration - EDGE_TOLERANCE * max(1.0, abs(t)) \
            else 0.0

    def strikes(self, t: float) -> int:
        """No ram: no strikes."""
        return 0

    def edges(self, k: int) -> tuple[float, ...]:
        """Blow ``k``'s start and end [s]."""
        on = self.start + k * self.period
        return on, on + self.duration

    def end(self) -> float:
        """When the last blow ends [s] (inf for a train without end)."""
        if not self.count:
            return math.inf
        return self.start + (self.count - 1) * self.period + self.duration


@dataclass(frozen=True)
class RamTrain:
    """A checked train of ram strikes (build one with :func:`check`)."""

    ram_mass: float
    v_strike: float           #: [m/s]
    period: float             #: 60 / blows_per_minute [s]
    count: int
    start: float

    def force(self, t: float) -> float:
        """The ram's blows put no force Q in [N]."""
        return 0.0

    def strikes(self, t: float) -> int:
        """Strikes started at or before ``t`` [s] (edges within the tolerance)."""
        return _started(self.start, self.period, self.count, t)

    def edges(self, k: int) -> tuple[float, ...]:
        """Strike ``k``'s instant [s]."""
        return (self.start + k * self.period,)

    def end(self) -> float:
        """When the last strike starts [s] (inf for a train without end)."""
        return math.inf if not self.count else self.start + (self.count - 1) * self.period


def _started(start: float, period: float, count: int, t: float) -> int:
    """Blows (or strikes) started at or before ``t`` [s], one every ``period`` [s] from
    ``start`` [s], at most ``count`` (0: no end); a time within the tolerance of a start is
    on it."""
    since = t - start
    if since < -EDGE_TOLERANCE * max(1.0, abs(t)):
        return 0
    started = math.floor((since + EDGE_TOLERANCE * max(1.0, abs(t))) / period) + 1
    return min(started, count) if count else started


def check(values: Mapping[str, object]) -> BlowTrain | RamTrain:
    """The blow train of ``values`` (missing names take their defaults), every value checked:
    a :class:`RamTrain` when ``ram_mass > 0``, else a :class:`BlowTrain`.

    Raises
    ------
    BlowTrainError
        Naming the first refused variable in table order (``duration`` against ``period``
        and ``rated_energy`` against ``ram_mass`` last), its value and the allowed range;
        also for a name that is not a parameter.
    """
    for name, value in values.items():
        if name not in _BY_NAME:
            raise BlowTrainError(name, value, "a parameter of Hammer: " + ", ".join(_BY_NAME))
    merged = {p.name: values.get(p.name, p.default) for p in PARAMETERS}
    for p in PARAMETERS:
        _check_own_range(p, merged[p.name])
    if not merged["duration"] <= merged["period"]:
        raise BlowTrainError("duration", merged["duration"], _BY_NAME["duration"].allowed
                             + f" (period = {merged['period']!r})")
    v = {name: (int(x) if _BY_NAME[name].kind == "Integer" else float(x))
         for name, x in merged.items()}
    if v["ram_mass"] == 0.0:
        return BlowTrain(v["amplitude"], v["duration"], v["period"], v["count"], v["start"])
    if not v["rated_energy"] > 0.0:
        raise BlowTrainError("rated_energy", merged["rated_energy"],
                             f"> 0 with a ram (ram_mass = {merged['ram_mass']!r})")
    speed = math.sqrt(2.0 * v["efficiency"] * v["rated_energy"] / v["ram_mass"])
    if not math.isfinite(speed):
        raise BlowTrainError("rated_energy", merged["rated_energy"],
                             "a finite strike velocity sqrt(2 efficiency rated_energy / "
                             "ram_mass)")
    return RamTrain(v["ram_mass"], speed, 60.0 / v["blows_per_minute"], v["count"], v["start"])


def _check_own_range(p: BlowParameter, value: object) -> None:
    """Refuse ``value`` for ``p`` unless it is of its type, finite and above its lower bound."""
    if p.kind == "Integer":
        ok = isinstance(value, numbers.Integral) and not isinstance(value, bool) and value >= p.lower
    else:
        ok = (isinstance(value, numbers.Real) and not isinstance(value, bool)
              and math.isfinite(value)
              and (p.lower is None or (value > p.lower if p.strict_lower else value >= p.lower))
              and (p.upper is None or value <= p.upper))
    if not ok:
        raise BlowTrainError(p.name, value, p.allowed)
