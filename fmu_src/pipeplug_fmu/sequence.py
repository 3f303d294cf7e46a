"""The FMI 2.0 co-simulation call sequence of the FMI base (:mod:`pipeplug_fmu.base`): its
phases, the two refusals a hook raises, and the FMU's time rules (contract "Stepping").

Plain Python: no pythonfmu, no numpy.
"""
from __future__ import annotations

import enum
import math

from .fmi import refusal

__all__ = ["Phase", "RUNNING", "Refuse", "Discard", "TIME_TOLERANCE", "stop_limit",
           "all_finite"]

#: Relative tolerance of a communication point against the FMU's time (contract "Stepping").
TIME_TOLERANCE = 1e-9


class Phase(enum.Enum):
    """The FMI 2.0 co-simulation states an instance goes through (error is the loader's)."""

    INSTANTIATED = "instantiated"
    INITIALIZATION = "initialization mode"
    STEPPING = "stepping"
    TERMINATED = "terminated"


RUNNING = (Phase.STEPPING, Phase.TERMINATED)          # a model exists


class Refuse(Exception):
    """Raised by a hook: refuse the call with fmi2Error and this line (``%`` not escaped)."""

    def __init__(self, line: str):
        super().__init__(line)
        self.line = line

    @classmethod
    def of(cls, name: str, value: object, allowed: str) -> Refuse:
        """The refusal of variable ``name`` at ``value`` (see :func:`~pipeplug_fmu.fmi.refusal`)."""
        return cls(refusal(name, value, allowed))


class Discard(Refuse):
    """Raised by ``_step``: the step cannot be taken (fmi2Discard); nothing has changed."""


def stop_limit(stop_time) -> float:
    """The last end of a step allowed by ``stop_time`` [s] (inf without one)."""
    if stop_time is None:
        return math.inf
    return stop_time + TIME_TOLERANCE * max(1.0, abs(stop_time))


def all_finite(values) -> bool:
    """True when every number of ``values`` is finite (bools and ints count as finite)."""
    try:
        total = math.fsum(values)
    except OverflowError:           # finite terms whose sum overflows
        return True
    except ValueError:              # inf - inf
        return False
    return total - total == 0.0
