"""The one rule set of blow trains: the Hammer FMU's (:mod:`pipeplug_fmu.blows`), read from a
file's ``[blows]`` section.

A train is ``count`` rectangular blows (0: no end) of ``amplitude`` [N] lasting ``duration`` [s],
blow k starting at ``start + k period`` [s]; ``duration <= period``, so blows never overlap; the
defaults are the Hammer's. A file may give ``rate`` (blows per time, e.g. ``"200 /min"``)
instead of ``period``. A run starts at t = 0, so ``start >= 0``.

A ``[hammer]`` section gives the strikes of a ram instead, by the Hammer's ram mode: strike k at
``start + k / rate`` (``count`` of them in a scene; a drive strikes once a blow), the ram at
``v = sqrt(2 efficiency rated_energy / ram_mass)``.
"""
from __future__ import annotations

from pipeplug_fmu.blows import BlowTrain, BlowTrainError, RamTrain, check
from pipeplug_harness.errors import UserError

from .tables import blow_default

__all__ = ["blow_train", "period_of", "ram_train"]


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


def ram_train(hammer: dict, count: int = 0, start: float = 0.0) -> RamTrain:
    """The checked strikes of a ``[hammer]`` section (values in SI; ``count`` strikes, 0: no
    end, from ``start`` [s]) by the Hammer's own rules, and its cushion's restitution.

    Raises
    ------
    UserError
        Naming ``[hammer] key``, its value and the allowed range.
    """
    if not 0.0 < hammer["cushion_restitution"] <= 1.0:
        raise UserError(key="[hammer] cushion_restitution", value=hammer["cushion_restitution"],
                        allowed="> 0 and <= 1")
    values = {"ram_mass": hammer["ram_mass"], "rated_energy": hammer["rated_energy"],
              "efficiency": hammer["efficiency"], "blows_per_minute": 60.0 * hammer["rate"],
              "count": count, "start": start}
    try:
        train = check(values)
    except BlowTrainError as exc:
        name = "rate" if exc.name == "blows_per_minute" else exc.name
        raise UserError(key=f"[hammer] {name}", value=hammer.get(name, exc.value),
                        allowed=exc.allowed) from None
    if not train.start >= 0.0:
        raise UserError(key="[hammer] start", value=train.start,
                        allowed=">= 0 s (a run starts at t = 0)")
    return train
