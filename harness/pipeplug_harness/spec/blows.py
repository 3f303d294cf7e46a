"""The one rule set of blow trains: the Hammer FMU's (:mod:`pipeplug_fmu.blows`), read from a
file's ``[blows]`` section.

A train is ``count`` rectangular blows (0: no end) of ``amplitude`` [N] lasting ``duration`` [s],
blow k starting at ``start + k period`` [s]; ``duration <= period``, so blows never overlap; the
defaults are the Hammer's. A file may give ``rate`` (blows per time, e.g. ``"200 /min"``)
instead of ``period``. A run starts at t = 0, so ``start >= 0``.
"""
from __future__ import annotations

from pipeplug_fmu.blows import BlowTrain, BlowTrainError, check
from pipeplug_harness.errors import UserError

from .tables import blow_default

__all__ = ["blow_train", "period_of"]


def period_of(blows: dict) -> float:
    """The period [s] of a ``[blows]`` section: ``period``, or ``1 / rate``."""
    rate, period = blows.get("rate"), blows.get("period")
    if rate is None:
        return blow_default("period") if period is None else period
    if period is not None:
        raise UserError(f"[blows] period = {period!r} s and rate = {rate!r} /s: give one of them")
    if not rate > 0.0:
        raise UserError(key="[blows] rate", value=rate, allowed="> 0 blows per second")
    return 1.0 / rate


def blow_train(blows: dict) -> BlowTrain:
    """The checked train of a ``[blows]`` section (values in SI).

    Raises
    ------
    UserError
        Naming ``[blows] key``, its value and the allowed range (the Hammer's wording).
    """
    values = {k: blows[k] for k in ("amplitude", "duration", "count", "start")
              if blows.get(k) is not None}
    values["period"] = period_of(blows)
    if blows.get("period") is None and blows.get("rate") is None and values.get("count", 1) == 1:
        # one blow has no period: the default must not refuse a blow longer than it
        values["period"] = max(values["period"], values.get("duration", 0.0))
    try:
        train = check(values)
    except BlowTrainError as exc:
        raise UserError(key=f"[blows] {exc.name}", value=exc.value, allowed=exc.allowed) \
            from None
    if not train.start >= 0.0:
        raise UserError(key="[blows] start", value=train.start,
                        allowed=">= 0 s (a run starts at t = 0)")
    return train
