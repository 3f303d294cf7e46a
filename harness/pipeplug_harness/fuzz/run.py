"""One case in, one result out: :func:`run_case` (a pure function of the case and the setup).

Every case runs on every core path of the setup, on each of its grids; the invariants are
checked on each path. Cases marked for it are also compared with the reference, run through
the FMU (both host styles) and through the fd scheme. A run that raises counts as a failure
of the ``exception`` check with its message kept.
"""
from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field

import numpy as np

from . import checks as ck
from .cases import GRIDS, Case, host_calls, loads_on
from .fdcheck import fd_measure
from .paths import CORE_PATHS, FD_PATHS
from .runners import drop_fmu_host, fmu_host, run_calls, run_grid, run_reference

__all__ = ["Setup", "CaseResult", "run_case", "HOST_STYLES"]

HOST_STYLES = ("t+=h", "t=k*h")


@dataclass(frozen=True)
class Setup:
    """What to run every case on: core paths (names in :data:`CORE_PATHS`), the fd path
    (in :data:`FD_PATHS`) and the FMU (a file or extracted folder; None: no FMU)."""

    paths: tuple = tuple(CORE_PATHS)
    fd_path: str = "fd"
    fmu: str | None = None


@dataclass
class CaseResult:
    """The values of every check run on one case, keyed ``(check, subject)``; the subject
    is a core path, ``"fmu t+=h"``/``"fmu t=k*h"`` or ``"fd"``."""

    seed: int
    index: int
    model: str
    families: tuple
    values: dict = field(default_factory=dict)
    errors: dict = field(default_factory=dict)      #: (check, subject) -> message
    fd: tuple | None = None                        #: FdResult as a tuple
    seconds: float = 0.0

    def put(self, check: str, subject: str, value: float) -> None:
        """Record a value; the worst one stays (NaN is the worst of all)."""
        key, value = (check, subject), float(value)
        old = self.values.get(key)
        if old is None or (old == old and not value <= old):
            self.values[key] = value

    @property
    def failed(self) -> list[tuple[str, str]]:
        """The ``(check, subject)`` pairs whose value exceeds the check's tolerance (a NaN
        value fails too)."""
        return [key for key, value in self.values.items()
                if not value <= ck.CHECKS[key[0]].tolerance]


def run_case(case: Case, setup: Setup = Setup()) -> CaseResult:
    """Run every check the case is marked for; see the module docstring."""
    start = time.perf_counter()
    result = CaseResult(case.seed, case.index, case.model, case.checks)
    body = ck.Body.of(case.params, case.growth)
    ref = None
    if "reference" in case.checks or "fd" in case.checks:
        ref = _guarded(result, "reference", _reference, case, setup)
    runs = {path: _guarded(result, path, _core, case, CORE_PATHS[path], path, body, ref, result)
            for path in setup.paths}
    first = setup.paths[0] if setup.paths else None
    for path, rows in runs.items():
        if path != first and rows is not None and runs[first] is not None:
            result.put("paths", path, max(ck.same_outputs_error(a, b)
                                          for a, b in zip(rows, runs[first])))
    if "fmu" in case.checks and setup.fmu:
        for style in HOST_STYLES:
            _guarded(result, f"fmu {style}", _fmu, case, setup, style, ref, result)
    if "fd" in case.checks and ref is not None:
        _guarded(result, "fd", _fd, case, setup, ref, result)
    result.seconds = time.perf_counter() - start
    return result


def _guarded(result: CaseResult, subject: str, job, *args):
    """``job(*args)``; an exception becomes a failure of the ``exception`` check."""
    try:
        value = job(*args)
        result.put("exception", subject, 0.0)
        return value
    except Exception as exc:            # any exception of any run is a finding
        result.put("exception", subject, 1.0)
        result.errors[("exception", subject)] = "".join(
            traceback.format_exception_only(type(exc), exc)).strip()
        return None


def _reference(case: Case, setup: Setup) -> tuple[np.ndarray, dict]:
    """The reference at every point any run of the case is compared at."""
    times = [np.asarray(case.grids[g][1:]) for g in GRIDS]
    if "fmu" in case.checks and setup.fmu:
        times += [np.array([t + h for t, h in host_calls(case, s)]) for s in HOST_STYLES]
    times = np.unique(np.concatenate(times))
    return times, run_reference(case, times)


def _core(case: Case, builder, path: str, body, ref, result: CaseResult) -> list:
    """All grids of the case on one core path: invariants, grid independence, reference.
    Returns the outputs on each grid (rows of :data:`pipeplug.OUTPUT_NAMES`)."""
    at_samples, runs = [], []
    for name in GRIDS:
        grid = np.asarray(case.grids[name])
        rows, rest = run_grid(builder, case, grid, probe_rest=(name == "coarse"))
        runs.append(rows)
        loads = loads_on(case.segments, grid[:-1])
        result.put("energy", path, ck.energy_error(rows, body))
        result.put("friction work", path, ck.friction_decrease(rows))
        result.put("stuck", path, ck.stuck_violations(rows, body))
        result.put("static limits", path, ck.limit_excess(rows, loads, body))
        result.put("at rest", path, rest)
        at_samples.append(rows[np.searchsorted(grid[1:], case.samples)])
        if ref is not None:
            _compare(result, path, rows, grid[1:], ref, case)
    result.put("grid", path, ck.grid_error(at_samples))
    return runs


def _compare(result: CaseResult, subject: str, rows, times, ref, case: Case) -> None:
    """The reference checks of one run at ``times``."""
    all_times, values = ref
    idx = np.searchsorted(all_times, times)
    at = {name: np.asarray(v)[idx] for name, v in values.items() if name != "events"}
    load = max((abs(q) for _, q in case.segments), default=0.0)
    for check, value in ck.reference_errors(rows, at, times, values["events"], case.stop,
                                            load).items():
        result.put(check, subject, value)


def _fmu(case: Case, setup: Setup, style: str, ref, result: CaseResult) -> None:
    """The FMU on one host style, against the first core path on the same points."""
    calls = host_calls(case, style)
    try:
        rows = fmu_host(setup.fmu).run(case, calls)
    except Exception:
        drop_fmu_host(setup.fmu)        # the next case gets a fresh instance
        raise
    core = run_calls(CORE_PATHS[setup.paths[0]], case, calls)
    subject = f"fmu {style}"
    result.put("fmu", subject, ck.same_outputs_error(rows, core))
    if ref is not None:
        _compare(result, subject, rows, np.array([t + h for t, h in calls]), ref, case)


def _fd(case: Case, setup: Setup, ref, result: CaseResult) -> None:
    """The fd check against the first core path."""
    fd = fd_measure(case, CORE_PATHS[setup.paths[0]], FD_PATHS[setup.fd_path],
                    ref[1]["events"])
    result.fd = tuple(fd)
    if fd.resolved:
        result.put("fd bound", "fd", fd.K)
    if fd.order == fd.order:                    # measured
        result.put("fd order", "fd", abs(fd.order - 1.0))
