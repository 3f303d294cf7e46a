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

    [pipe] [plug] [soil] [blows] [model]        # the base case: as in a scene or drive file
    [output]                # kind = "blow": stop_time [s] (default 100): the run goes on under
                            # Q = 0 after the blows until all is at rest or this time;
                            # modes = true: a column of the contact modes each run went
                            # through (default false; the "domains" report always has it)
    [drive]                 # kind = "drive": as in a drive file

Any number key of the base sections can vary (parameters, blow settings, [drive] settings).
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

from pipeplug_harness.drive.file import DRIVE_SECTIONS
from pipeplug_harness.scenes.file import SECTIONS, SceneError, checked_sections, read_toml

from .runners import BATCH_CHUNK, RUNNERS, runner_of
from .sample import DISTRIBUTIONS, GRID_KEYS, GRID_SCALES, Dimension

__all__ = ["SweepSpec", "KINDS", "REPORTS", "load_sweep", "sweep_spec", "variables"]

#: kind -> (base sections, the nested ones, default cases per task)
KINDS = {
    "blow": ({**{k: v for k, v in SECTIONS.items() if k != "output"},
              "output": {"stop_time": (float, 100.0), "modes": (bool, False)}},
             ("blows", "output"), 2000),
    "drive": (DRIVE_SECTIONS, ("blows", "drive"), 100),
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

_SWEEP = {"kind": (str, "blow"), "seed": (int, 0), "samples": (int, None),
          "chunk": (int, None), "report": (str, "none")}
_SAMPLINGS = ("grid", "random")


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
        runner."""
        return RUNNERS[self.runner](self, c)

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
    sections = KINDS[kind][0]
    return {key: section for section, keys in sections.items()
            for key, (typ, _) in keys.items() if typ is float}


def load_sweep(path: str | Path) -> SweepSpec:
    """Read and validate a sweep file (see the module docstring)."""
    path = Path(path)
    return sweep_spec(path.stem, read_toml(path))


def sweep_spec(name: str, raw: dict) -> SweepSpec:
    """A :class:`SweepSpec` from a parsed sweep file."""
    raw = copy.deepcopy(raw)
    head = checked_sections({"sweep": raw.pop("sweep", {})}, {"sweep": _SWEEP},
                            nested=("sweep",))["sweep"]
    kind = _choice("kind", head["kind"], KINDS)
    report = _choice("report", head["report"], REPORTS)
    sections, nested, default_chunk = KINDS[kind]
    given = [s for s in _SAMPLINGS if s in raw]
    if len(given) != 1:
        raise SceneError(f"a sweep needs exactly one of [grid] or [random] (got "
                         f"{', '.join(given) or 'none'})")
    sampling = given[0]
    allowed = variables(kind)
    table = {sampling: {k: ((list, dict) if sampling == "grid" else dict, None) for k in allowed}}
    given = raw.pop(sampling)
    varied = checked_sections({sampling: given}, table, nested=(sampling,))[sampling]
    dims = tuple(_dimension(sampling, k, varied[k]) for k in given)    # file order
    if not dims:
        raise SceneError(f"[{sampling}] varies nothing; allowed: {', '.join(allowed)}")
    base = checked_sections(raw, sections, nested=nested)
    if sampling == "grid":
        n_cases = math.prod(len(d.values) for d in dims)
        if head["samples"] is not None:
            raise SceneError("[sweep] samples is for a random sample; a grid has "
                             f"{n_cases} cases")
    else:
        n_cases = head["samples"]
        if n_cases is None or n_cases < 1:
            raise SceneError(f"[sweep] samples = {n_cases!r}; allowed: an integer >= 1 "
                             f"(a random sample needs it)")
    chunk = head["chunk"]
    if chunk is not None and chunk < 1:
        raise SceneError(f"[sweep] chunk = {chunk!r}; allowed: >= 1")
    spec = SweepSpec(name, kind, base, sampling, dims, head["seed"], n_cases,
                     chunk or default_chunk, report, digest="")
    runner = runner_of(spec)                    # decided by the cases, not by their chunking
    if chunk is None:
        chunk = BATCH_CHUNK if runner == "batch" else default_chunk
    digest = _digest(kind, base, sampling, dims, head["seed"], n_cases, chunk, report)
    return dataclasses.replace(spec, chunk=chunk, digest=digest, runner=runner)


def _choice(key: str, value: str, table: dict) -> str:
    if value not in table:
        raise SceneError(f"[sweep] {key} = {value!r}; allowed: {', '.join(table)}")
    return value


def _dimension(sampling: str, name: str, value) -> Dimension:
    """One varied name checked against the grid forms or the distributions table."""
    if sampling == "grid":
        return Dimension(name, values=_grid_values(name, value))
    dist = value.get("dist")
    if dist not in DISTRIBUTIONS:
        raise SceneError(f"[random] {name}: dist = {dist!r}; allowed: {', '.join(DISTRIBUTIONS)}")
    keys = DISTRIBUTIONS[dist].keys
    unknown = sorted(set(value) - {"dist", *keys})
    missing = [k for k in keys if k not in value]
    if unknown or missing:
        raise SceneError(f"[random] {name}: {dist} takes {', '.join(keys)} "
                         f"(unknown: {unknown}, missing: {missing})")
    numbers = tuple(_number(f"[random] {name}", k, value[k]) for k in keys)
    problem = DISTRIBUTIONS[dist].check(*numbers)
    if problem:
        raise SceneError(f"[random] {name}: {dist} {problem}")
    return Dimension(name, dist=dist, args=numbers)


def _grid_values(name: str, value) -> np.ndarray:
    where = f"[grid] {name}"
    if isinstance(value, list):
        if not value:
            raise SceneError(f"{where} = []; allowed: a non-empty list of numbers")
        return np.array([_number(where, str(i), v) for i, v in enumerate(value)])
    unknown = sorted(set(value) - set(GRID_KEYS))
    if unknown or not {"start", "stop", "num"} <= set(value):
        raise SceneError(f"{where}: a table takes {', '.join(GRID_KEYS)} (start, stop, num "
                         f"required; unknown: {unknown})")
    start, stop = (_number(where, k, value[k]) for k in ("start", "stop"))
    num, scale = value["num"], value.get("scale", "linear")
    if not (isinstance(num, int) and not isinstance(num, bool) and num >= 1):
        raise SceneError(f"{where}: num = {num!r}; allowed: an integer >= 1")
    if scale not in GRID_SCALES:
        raise SceneError(f"{where}: scale = {scale!r}; allowed: {', '.join(GRID_SCALES)}")
    return GRID_SCALES[scale](start, stop, num, where)


def _number(where: str, key: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SceneError(f"{where}: {key} = {value!r}; allowed: a finite number")
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
