"""How the cases of a sweep run: the closed table of runners and the one rule choosing one.

* ``"batch"``: a chunk of single blows in one call of the core's batch API
  (:func:`pipeplug.batch.blows`, :mod:`.batch`): compiled, model build included;
* ``"case"``: one model per case (:mod:`.cases`): any kind, model, solver, blows, columns.

The choice is made once per sweep, from the sweep alone (:func:`runner_of`): a blow sweep
takes the batch API when every rule of :data:`BATCH_RULES` holds, i.e. when the batch API
computes the very values the per-case path would (the same functions, the same steps) and the
sweep wants nothing it does not give. Both give the same columns.
"""
from __future__ import annotations

from . import batch, cases

__all__ = ["RUNNERS", "BATCH_RULES", "BATCH_CHUNK", "runner_of", "batch_misses", "described"]

#: runner -> run_chunk(spec, c) -> pyarrow.Table
RUNNERS = {"batch": batch.run_chunk, "case": cases.run_chunk}

#: cases per task of a sweep the batch API runs when its file sets no ``chunk``: a few
#: microseconds a blow make a task of 0.1-0.3 s; the per-case default (2000) would make tasks of
#: a few milliseconds, less than Dask spends on a task (about 8 ms of CPU on a 2-core VM)
BATCH_CHUNK = 100_000

#: what a sweep needs for the batch API -> its test on the sweep (:class:`~.file.SweepSpec`)
BATCH_RULES = {
    "single blows ([sweep] kind = \"blow\")": lambda s: s.kind == "blow",
    # it keeps no mode log
    "no mode sequence ([output] modes = false, a report needing none)": lambda s: not s.modes,
    "rigid ([model] elastic = false)": lambda s: s.base.get("elastic") is False,
    "the exact solver ([model] solver unset or \"exact\")":
        lambda s: s.base.get("solver") in (None, "exact"),
    "one blow from rest at t = 0 ([blows] count = 1, start = 0, not varied)":
        lambda s: s.base.get("blows", {}).get("count") == 1
        and s.base["blows"]["start"] == 0.0 and not _varies(s, "start"),
    "one stop time ([output] stop_time not varied)": lambda s: not _varies(s, "stop_time"),
}


def _varies(spec, name: str) -> bool:
    return any(d.name == name for d in spec.dims)


def batch_misses(spec) -> list[str]:
    """The rules of :data:`BATCH_RULES` the sweep breaks (none: it takes the batch API)."""
    return [rule for rule, holds in BATCH_RULES.items() if not holds(spec)]


def runner_of(spec) -> str:
    """The sweep's runner: ``"batch"`` when every rule of :data:`BATCH_RULES` holds."""
    return "case" if batch_misses(spec) else "batch"


def described(spec) -> str:
    """How the sweep's cases run, in words (for a blow sweep off the batch API: why)."""
    if spec.runner == "batch":
        return "cases run by the core's batch API, one call per chunk"
    misses = batch_misses(spec) if spec.kind == "blow" else []
    return "one model per case" + (f"; the batch API needs {misses[0]}" if misses else "")
