"""Values with units: a number is SI; a string is a quantity with its unit (``"610 mm"``,
``"10 kPa"``, ``"200 /min"``), converted by pint.

The registry is made on the first string only (it takes about a second), so files written in
plain SI numbers never pay for it.
"""
from __future__ import annotations

import math
from functools import cache

from pipeplug_harness.errors import UserError

__all__ = ["to_si", "PINT_UNITS"]

#: the tables' unit names that pint spells otherwise
PINT_UNITS = {"kg/m3": "kg/m**3", "1": "dimensionless", "-": "dimensionless"}


@cache
def _registry():
    import pint
    return pint.UnitRegistry()


def _pint_unit(unit: str) -> str:
    return PINT_UNITS.get(unit, unit)


def to_si(where: str, value: str, unit: str) -> float:
    """The quantity ``value`` (a string such as ``"610 mm"``) in the SI unit ``unit``.

    Raises
    ------
    UserError
        Naming ``where`` (``[section] key``), the value and the unit expected: an unknown unit,
        a unit of another dimension, a string that is no quantity, a value that is not finite.
    """
    registry = _registry()
    try:
        quantity = registry.Quantity(value)
        target = registry.Unit(_pint_unit(unit))
    except Exception as exc:                 # pint raises several kinds: all mean "not a quantity"
        raise UserError(key=where, value=value,
                        allowed=f"a number in {unit}, or a quantity with its unit, e.g. "
                                f"'{_example(unit)}' ({type(exc).__name__}: {exc})") from None
    if quantity.dimensionality != target.dimensionality:
        raise UserError(key=where, value=value,
                        allowed=f"a quantity of the dimension of {unit} "
                                f"({target.dimensionality}), not {quantity.dimensionality}")
    si = float(quantity.to(target).magnitude)
    if not math.isfinite(si):
        raise UserError(key=where, value=value, allowed=f"a finite quantity in {unit}")
    return si


def _example(unit: str) -> str:
    return {"m": "610 mm", "Pa": "10 kPa", "s": "1 ms", "N": "2.2 MN", "1/s": "200 /min",
            "kg/m3": "7.85 g/cm**3"}.get(unit, f"1 {unit}")
