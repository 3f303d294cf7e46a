"""The blow train of Hammer.fmu: its parameters, their ranges, and the force at a time.

A train of ``count`` rectangular blows (``count = 0``: no end) of force ``amplitude`` [N], each
lasting ``duration`` [s], blow k starting at ``start + k period`` (k = 0, 1, ...)::

    Q(t) = amplitude   if start + k period <= t < start + k period + duration
                       for some integer k with 0 <= k (and k < count when count > 0)
    Q(t) = 0           otherwise

Q is right-continuous: at an edge it takes the value after the edge, which is the force of a
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

__all__ = ["BlowParameter", "BlowTrain", "BlowTrainError", "PARAMETERS", "OUTPUT",
           "DESCRIPTION", "DEFAULT_EXPERIMENT", "EDGE_TOLERANCE", "check"]

#: Relative tolerance of a time on an edge (and of the FMU's time check); as PipePlug's.
EDGE_TOLERANCE = 1e-9

#: What the FMU is (modelDescription.xml and documentation).
DESCRIPTION = ("A train of rectangular blows: the force Q on the struck end of a pipe, for "
               "PipePlug's input Q")

#: The output: (name, unit, meaning).
OUTPUT = ("Q", "N", "force of the blow train for the communication step that starts at the "
                    "FMU's current time (right-continuous); positive drives the pipe into the "
                    "soil")

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
)
_BY_NAME = {p.name: p for p in PARAMETERS}


@dataclass(frozen=True)
class BlowTrain:
    """A checked blow train (build one with :func:`check`)."""

    amplitude: float
    duration: float
    period: float
    count: int
    start: float

    def force(self, t: float) -> float:
        """The force [N] at time ``t`` [s]: right-continuous, edges within the tolerance."""
        tol = EDGE_TOLERANCE * max(1.0, abs(t))
        since = t - self.start
        if since < -tol:
            return 0.0
        k = math.floor((since + tol) / self.period)     # the last blow started at or before t
        if self.count and k >= self.count:
            return 0.0
        return self.amplitude if since - k * self.period < self.duration - tol else 0.0

    def end(self) -> float:
        """When the last blow ends [s] (inf for a train without end)."""
        if not self.count:
            return math.inf
        return self.start + (self.count - 1) * self.period + self.duration


def check(values: Mapping[str, object]) -> BlowTrain:
    """The blow train of ``values`` (missing names take their defaults), every value checked.

    Raises
    ------
    BlowTrainError
        Naming the first refused variable in table order (``duration`` against ``period``
        last), its value and the allowed range; also for a name that is not a parameter.
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
    return BlowTrain(**{name: (int(v) if _BY_NAME[name].kind == "Integer" else float(v))
                        for name, v in merged.items()})


def _check_own_range(p: BlowParameter, value: object) -> None:
    """Refuse ``value`` for ``p`` unless it is of its type, finite and above its lower bound."""
    if p.kind == "Integer":
        ok = isinstance(value, numbers.Integral) and not isinstance(value, bool) and value >= p.lower
    else:
        ok = (isinstance(value, numbers.Real) and not isinstance(value, bool)
              and math.isfinite(value)
              and (p.lower is None or (value > p.lower if p.strict_lower else value >= p.lower)))
    if not ok:
        raise BlowTrainError(p.name, value, p.allowed)
