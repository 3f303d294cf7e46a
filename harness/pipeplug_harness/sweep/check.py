"""Every case of a sweep checked by the core before any work is submitted.

The core's ranges are bounds on single parameters and linear relations between them (``L2 <=
L1``, ``x_monitor <= L1``, the drive's ``target <= L1``, ``period > duration``): such a rule
holds over a box of values exactly when it holds at the box's corners. So the corners of the
box spanned by the sweep's values (grid: its ends; random: the smallest and largest values
drawn) are checked, by the same function that prepares a case on a worker. The elastic model
has a rule that is not linear (L1 and L2 whole multiples of dx): when a corner is elastic, or
the sweep is small, every case is checked.
"""
from __future__ import annotations

import itertools

from pipeplug_harness.errors import UserError

from .cases import chunk_values, prepare, value_bounds

__all__ = ["check_sweep", "CHECK_ALL_BELOW"]

#: sweeps of at most this many cases have every case checked
CHECK_ALL_BELOW = 1000


def check_sweep(spec) -> str:
    """Check the sweep's cases with the core; say what was checked.

    Raises
    ------
    UserError
        Naming the case's varied values, the offending value and what is allowed.
    """
    bounds = value_bounds(spec)
    elastic = False
    for corner in itertools.product(*(sorted(set(b)) for b in bounds.values())):
        case = dict(zip(bounds, corner))
        elastic |= _is_elastic(_checked(spec, case))
    _plausible(spec, bounds)              # after the core's hard ranges, which say more
    if not (elastic or spec.n_cases <= CHECK_ALL_BELOW):
        return f"checked by the core: the {2 ** len(bounds)} corners of the values' box"
    for c in range(spec.n_chunks):
        values = chunk_values(spec, c)
        for j in range(len(next(iter(values.values())))):
            _checked(spec, {name: float(v[j]) for name, v in values.items()})
    return f"checked by the core: all {spec.n_cases} cases"


def _plausible(spec, bounds: dict) -> None:
    """The varied values within their keys' plausible ranges (or allowed by name)."""
    from pipeplug_harness.spec import plausibility
    from pipeplug_harness.spec.check import allowed_names

    from .file import KINDS, variables
    sections = KINDS[spec.kind][0].sections
    allowed = allowed_names(spec.base, sections)
    for name, section in variables(spec.kind).items():
        if name in bounds:
            for value in bounds[name]:
                plausibility(f"[{section}] {name}", name, value, sections[section][name], allowed)


def _checked(spec, case: dict):
    try:
        return prepare(spec.kind, spec.case_values({k: [v] for k, v in case.items()}, 0))
    except ValueError as exc:               # UserError or the core's ParameterError
        where = ", ".join(f"{k} = {v!r}" for k, v in case.items())
        raise UserError(f"the case with {where}: {exc}") from None


def _is_elastic(prepared) -> bool:
    return bool(prepared.elastic)
