"""Sweep files: many cases described in TOML, read by the scene and drive files' machinery.

A sweep names a base case (the sections of a scene file for single blows, of a drive file for
whole drives, same keys and defaults), what varies, and how the run is cut into tasks::

    [sweep]
    kind = "blow"           # "blow": one case = one model run through [blows] from rest;
                            # "drive": one case = a whole drive ([drive] section, see
                            # pipeplug_harness.drive.file)
    seed = 0                # random sample: the same seed gives the same cases (any workers)
    samples = 10000         # random sample: how many cases
    chunk = 1000            # cases per task (default: 2000 blows, 100,000 blows on the batch
                            # API, 100 drives)
    report = "none"         # after the run: "none", "domains" (the paper's Fig. 2) or
                            # "drivability" (blows to drive and refusal, with standard errors)

    [grid]                  # either a grid: every combination, the first name varying slowest
    tau1 = [0.0, 1e4, 2e4]                              # the values, or
    tau2 = {start = 0.0, stop = 1e5, num = 101}         # num values from start to stop
    L1 = {start = 1.0, stop = 100.0, num = 3, scale = "log"}

    [random]                # or a random sample: each name from a distribution
    tau1 = {dist = "lognormal", median = 7e4, sigma = 0.2}
    tau2 = {dist = "normal", mean = 2e4, sd = 2e3}
    L2 = {dist = "uniform", low = 0.5, high = 1.0}
    # also {dist = "truncnormal", mean, sd, low, high}: a normal cut to [low, high]
    # every value (but lognormal's sigma) SI, or a string with its unit: low = "10 kPa"

    [pipe] [plug] [soil] [blows] [model]        # the base case: as in a scene or drive file
    [output]                # kind = "blow": stop_time [s] (default 100): the run goes on under
                            # Q = 0 after the blows until all is at rest or this time;
                            # modes = true: a column of the contact modes each run went
                            # through (default false; the "domains" report always has it)
    [drive]                 # kind = "drive": as in a drive file

Any number key of the base sections can vary (parameters, blow settings, [drive] settings); a
varied key is not also given in its base section (an error naming both places).
Unknown sections, keys or values are errors naming the allowed ones.

How the cases run is chosen once per sweep (:attr:`SweepSpec.runner`): single rigid exact
blows from rest with no mode sequence wanted run a chunk in one call of the core's batch API
(:mod:`.batch`; the rules: :data:`.runners.BATCH_RULES`); anything else builds one model per
case.
"""
from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pipeplug_harness import io
from pipeplug_harness import spec as files
from pipeplug_harness.errors import UserError
from pipeplug_harness.io.files import UNITLESS
from pipeplug_harness.limits import Limits
from pipeplug_harness.spec.units import to_si

from .cases import RESULT_UNITS
from .runners import BATCH_CHUNK, RUNNERS, runner_of
from .sample import DISTRIBUTIONS, GRID_KEYS, GRID_SCALES, Dimension

__all__ = ["SweepSpec", "KINDS", "REPORTS", "load_sweep", "sweep_spec", "variables"]

#: kind -> (its file kind, the nested sections, default cases per task)
KINDS = {
    "blow": (files.SWEEP_BLOW, files.SWEEP_BLOW.nested, 2000),
    "drive": (files.SWEEP_DRIVE, files.SWEEP_DRIVE.nested, 100),
}

#: report -> (what it gives, the result columns it needs beyond the default ones); the modules
#: are named in pipeplug_harness.sweep.command
REPORTS = {
    "none": ("the Parquet output only", ()),
    "domains": ("the paper's Fig. 2: each (tau1, tau2) point classified by its mode sequence, "
                "against the analytic domains", ("modes",)),
    "drivability": ("distribution of blows to drive, probability of refusal, standard errors",
                    ()),
}

_SAMPLINGS = ("grid", "random")
#: bytes a grid value takes while a sweep is prepared: its float64, and its text in the
#: campaign's digest (a Python float in a list, then JSON)
_GRID_VALUE_BYTES = 64
#: bytes every submitted task carries besides the grid's values (the campaign, the future)
_TASK_BYTES = 4096


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep: the base case, what varies, the task size; the same on every worker."""

    name: str
    kind: str                 #: "blow" or "drive"
    base: dict                #: checked base sections (nested ones as dicts, the rest flat)
    sampling: str             #: "grid" or "random"
    dims: tuple               #: :class:`~.sample.Dimension` of each varied name, file order
    seed: int
    n_cases: int
    chunk: int                #: cases per task
    report: str
    digest: str               #: identifies the cases and their results (resuming checks it)
    runner: str = "case"      #: how the cases run (:data:`.runners.RUNNERS`), chosen once
                              #: by :func:`.runners.runner_of`

    @property
    def modes(self) -> bool:
        """True when the output has the ``modes`` column (blows: asked for, or the report
        needs it)."""
        return self.kind == "blow" and (self.base["output"]["modes"]
                                        or "modes" in REPORTS[self.report][1])

    @property
    def n_chunks(self) -> int:
        return -(-self.n_cases // self.chunk)

    def chunk_range(self, c: int) -> tuple[int, int]:
        """The cases ``[start, stop)`` of task ``c``."""
        return c * self.chunk, min(self.n_cases, (c + 1) * self.chunk)

    def chunk_cases(self, c: int) -> int:
        start, stop = self.chunk_range(c)
        return stop - start

    def run_chunk(self, c: int):
        """The results of chunk ``c`` (a pyarrow Table, see :mod:`.cases`), by the sweep's
        runner, each column's unit in its field's metadata (:attr:`units`)."""
        return io.with_units(RUNNERS[self.runner](self, c), self.units)

    @property
    def units(self) -> dict:
        """column -> SI unit of the output's columns: the varied keys' and the results'
        (none for counts, flags, modes, text and dimensionless values, as in a CSV header)."""
        sections, where = KINDS[self.kind][0].sections, variables(self.kind)
        units = {d.name: sections[where[d.name]][d.name].unit for d in self.dims}
        units.update(RESULT_UNITS[self.kind])
        return {name: unit for name, unit in units.items() if unit not in UNITLESS}

    def case_values(self, varied: dict, i: int) -> dict:
        """The base sections with case ``i`` of ``varied`` (name -> array) put in (a copy)."""
        values = copy.deepcopy(self.base)
        nested = KINDS[self.kind][1]
        for name, section in variables(self.kind).items():
            if name in varied:
                target = values[section] if section in nested else values
                target[name] = float(varied[name][i])
        return values


def variables(kind: str) -> dict:
    """name -> section of every number key a sweep of ``kind`` may vary."""
    sections = KINDS[kind][0].sections
    return {key: section for section, keys in sections.items()
            if section not in ("sweep", "checks")
            for key, spec in keys.items() if spec.kind == "number"}


def load_sweep(path, limits: Limits | None = None) -> SweepSpec:
    """Read, validate and bound a sweep file (see the module docstring; errors name the
    file)."""
    path = Path(path)
    try:
        return sweep_spec(path.stem, files.read_toml(path), limits)
    except UserError as exc:
        raise exc.in_file(path) from None


def sweep_spec(name: str, raw: dict, limits: Limits | None = None) -> SweepSpec:
    """A :class:`SweepSpec` from a parsed sweep file."""
    limits = limits or Limits()
    raw = copy.deepcopy(raw)
    head = raw.get("sweep", {})
    kind = files.value_of("[sweep] kind", head.get("kind", "blow"),
                          files.SECTIONS["sweep"]["kind"])
    given = [s for s in _SAMPLINGS if s in raw]
    if len(given) != 1:
        raise UserError(f"a sweep needs exactly one of [grid] or [random] (got "
                        f"{', '.join(given) or 'none'})")
    sampling = given[0]
    allowed = variables(kind)
    varied = raw.pop(sampling)
    if not isinstance(varied, dict):
        raise UserError(key=f"[{sampling}]", value=varied, allowed="a section of varied keys")
    if not varied:
        raise UserError(f"[{sampling}] varies nothing; allowed: {', '.join(allowed)}")
    for key, value in varied.items():
        if key not in allowed:
            raise UserError(f"unknown key {key!r} in [{sampling}]; allowed: "
                            f"{', '.join(allowed)}")
        if not isinstance(value, (list, dict) if sampling == "grid" else dict):
            raise UserError(key=f"[{sampling}] {key}", value=value,
                            allowed="a list or a table" if sampling == "grid" else "a table")
    file_kind, nested, default_chunk = KINDS[kind]
    _fixed_and_varied(raw, file_kind.sections, sampling, varied)
    base = files.checked(raw, file_kind, varied=tuple(varied))
    choice = base.get("elastic")
    if isinstance(choice, bool):        # the file chose the model: the other's keys are slips
        files.unused_model_keys(choice, dict(base, **varied), choice)
    head = base.pop("sweep")
    report = head["report"]
    units = {k: file_kind.sections[allowed[k]][k].unit for k in varied}
    dims = tuple(_dimension(sampling, k, varied[k], units[k], limits)
                 for k in varied)                                               # file order
    if sampling == "grid":
        n_cases = math.prod(len(d.values) for d in dims)
        if head["samples"] is not None:
            raise UserError("[sweep] samples is for a random sample; a grid has "
                            f"{n_cases} cases")
    else:
        n_cases = head["samples"]
        if n_cases is None:
            raise UserError("[sweep] samples is missing: a random sample needs it (an integer "
                            ">= 1)")
    limits.check("cases", n_cases, f"the sweep's {n_cases:.3g} cases")
    chunk = head["chunk"]
    spec = SweepSpec(name, kind, base, sampling, dims, head["seed"], n_cases,
                     chunk or default_chunk, report, digest="")
    runner = runner_of(spec)                    # decided by the cases, not by their chunking
    if chunk is None:
        chunk = BATCH_CHUNK if runner == "batch" else default_chunk
    tasks = -(-n_cases // chunk)
    limits.check("tasks", tasks, f"{n_cases:.3g} cases in chunks of {chunk}")
    values = sum(len(d.values) for d in dims if d.values is not None)
    limits.check("memory", tasks * (_TASK_BYTES + 8 * values),
                 f"{tasks:.3g} tasks, each carrying the campaign and its {values} grid values,")
    digest = _digest(kind, base, sampling, dims, head["seed"], n_cases, chunk, report)
    return dataclasses.replace(spec, chunk=chunk, digest=digest, runner=runner)


def _fixed_and_varied(raw: dict, sections: dict, sampling: str, varied: dict) -> None:
    """Refuse a key given in a base section and varied too: the varied values would replace
    the fixed one without a word."""
    for key in varied:
        for section, keys in sections.items():
            given = raw.get(section)
            if key in keys and isinstance(given, dict) and key in given:
                raise UserError(f"{key} is both fixed in [{section}] ({key} = {given[key]!r}) "
                                f"and varied in [{sampling}]; allowed: one of the two (remove "
                                f"it from [{section}] or from [{sampling}])",
                                key=f"[{section}] {key}", value=given[key],
                                allowed=f"not also in [{sampling}]")


def _dimension(sampling: str, name: str, value, unit: str, limits: Limits) -> Dimension:
    """One varied name checked against the grid forms or the distributions table (its values
    SI numbers, or strings with their unit, of the dimension of ``unit``)."""
    if sampling == "grid":
        return Dimension(name, values=_grid_values(name, value, unit, limits))
    dist = value.get("dist")
    if dist not in DISTRIBUTIONS:
        raise UserError(f"[random] {name}: dist = {dist!r}; allowed: {', '.join(DISTRIBUTIONS)}")
    keys = DISTRIBUTIONS[dist].keys
    unknown = sorted(set(value) - {"dist", *keys})
    missing = [k for k in keys if k not in value]
    if unknown or missing:
        raise UserError(f"[random] {name}: {dist} takes {', '.join(keys)} "
                         f"(unknown: {unknown}, missing: {missing})")
    numbers = tuple(_number(f"[random] {name}", k, value[k],
                            "1" if k in DISTRIBUTIONS[dist].unitless else unit) for k in keys)
    problem = DISTRIBUTIONS[dist].check(*numbers)
    if problem:
        raise UserError(f"[random] {name}: {dist} {problem}")
    return Dimension(name, dist=dist, args=numbers)


def _grid_values(name: str, value, unit: str, limits: Limits) -> np.ndarray:
    where = f"[grid] {name}"
    if isinstance(value, list):
        if not value:
            raise UserError(f"{where} = []; allowed: a non-empty list of numbers")
        return np.array([_number(where, str(i), v, unit) for i, v in enumerate(value)])
    unknown = sorted(set(value) - set(GRID_KEYS))
    if unknown or not {"start", "stop", "num"} <= set(value):
        raise UserError(f"{where}: a table takes {', '.join(GRID_KEYS)} (start, stop, num "
                         f"required; unknown: {unknown})")
    start, stop = (_number(where, k, value[k], unit) for k in ("start", "stop"))
    num, scale = value["num"], value.get("scale", "linear")
    if not (isinstance(num, int) and not isinstance(num, bool) and num >= 1):
        raise UserError(f"{where}: num = {num!r}; allowed: an integer >= 1")
    limits.check("cases", num, f"{where}: num = {num}")
    limits.check("memory", num * _GRID_VALUE_BYTES, f"{where}: num = {num} values")
    if scale not in GRID_SCALES:
        raise UserError(f"{where}: scale = {scale!r}; allowed: {', '.join(GRID_SCALES)}")
    return GRID_SCALES[scale](start, stop, num, where)


def _number(where: str, key: str, value, unit: str) -> float:
    """``value`` in SI: a finite number, or a string with its unit of the dimension of ``unit``
    (converted by the scene and drive files' parser)."""
    if isinstance(value, str):
        return to_si(f"{where}: {key}", value, unit)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        shown = f" in {unit} or a quantity with its unit" if unit not in ("", "1") else ""
        raise UserError(f"{where}: {key} = {value!r}; allowed: a finite number{shown}")
    return float(value)


def _digest(kind, base, sampling, dims, seed, n_cases, chunk, report) -> str:
    """A digest of everything that decides the cases, their chunks, their columns (the report
    may add some) and the code's version."""
    from pipeplug import __version__
    text = json.dumps([__version__, kind, base, sampling,
                       [(d.name, d.dist, d.args, None if d.values is None else d.values.tolist())
                        for d in dims], seed, n_cases, chunk, report], sort_keys=True,
                      default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]
