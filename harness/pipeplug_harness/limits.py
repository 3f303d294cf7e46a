"""Bounded work: every command estimates what a run will take before it allocates or starts, and
refuses past the limits stated here.

A limit is raised for one run with ``--limit NAME=VALUE`` (any command; repeatable), e.g.
``--limit steps=1e9``. The defaults keep a run within a few GB of memory and hours of work on
a small machine.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from pipeplug_harness.errors import UserError

__all__ = ["Limit", "LIMITS", "Limits", "parse_limits", "ROW_BYTES"]

#: bytes a run keeps per recorded value (float64)
ROW_BYTES = 8


@dataclass(frozen=True)
class Limit:
    default: float
    unit: str
    meaning: str


#: name -> the default limit, its unit and what it bounds
LIMITS = {
    "memory": Limit(2e9, "bytes", "memory a run's results and load history take, or a "
                                 "sweep's grid values and tasks"),
    "steps": Limit(1e7, "steps", "communication steps of one run (a scene, a drive, a system, "
                                 "a blow of a drive)"),
    "work": Limit(1e12, "cell-steps", "elastic work of one run: cells x internal steps"),
    "blows": Limit(1e6, "blows", "blows of one load history or drive"),
    "cases": Limit(1e8, "cases", "cases of a sweep or a fuzz run"),
    "tasks": Limit(1e5, "tasks", "tasks (chunks) of a campaign"),
}


class Limits:
    """The limits in force for one command (defaults, some raised by ``--limit``)."""

    def __init__(self, raised: dict | None = None):
        self.values = {name: limit.default for name, limit in LIMITS.items()}
        self.values.update(raised or {})

    def check(self, name: str, amount: float, what: str) -> None:
        """Refuse ``amount`` of ``name`` (e.g. steps) past the limit; ``what`` says what asked
        for it (e.g. ``"[output] step = 1e-12 s"``)."""
        limit = self.values[name]
        if not amount <= limit:              # NaN is past every limit
            unit = LIMITS[name].unit
            raise UserError(f"{what} asks for {amount:.3g} {unit}, past the limit of "
                            f"{limit:.3g} {unit} ({LIMITS[name].meaning}); to allow it, run "
                            f"with --limit {name}={_ask(amount)}")

    def memory(self, values: float, what: str) -> None:
        """Refuse keeping ``values`` float64 values past the memory limit."""
        self.check("memory", values * ROW_BYTES, what)


def _ask(amount: float) -> str:
    if not math.isfinite(amount):
        return "N"
    return f"{float(f'{amount * 1.01:.2g}'):g}"


def parse_limits(items) -> Limits:
    """``--limit NAME=VALUE`` arguments as :class:`Limits`.

    Raises
    ------
    UserError
        An unknown name, or a value that is not a positive number.
    """
    raised = {}
    for item in items or ():
        name, _, text = item.partition("=")
        if name not in LIMITS:
            raise UserError(key="--limit", value=item,
                            allowed=f"NAME=VALUE with NAME among {', '.join(LIMITS)}")
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not (value > 0.0 and math.isfinite(value)):
            raise UserError(key="--limit", value=item, allowed=f"{name}=a positive number")
        raised[name] = value
    return Limits(raised)
