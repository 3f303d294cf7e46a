"""Running many cases: generate from ``(seed, index)``, run, aggregate, save failures.

The map step is :func:`run_indices` (cases generated where they run, so only indices and
results travel); it runs in this process or in a pool of ``jobs`` processes. Any other map
(a cluster's) can call it the same way; aggregation (:class:`~.report.Summary`) does not care
about the order results arrive in.
"""
from __future__ import annotations

import multiprocessing
import sys
import time
from pathlib import Path

from .cases import Plan, generate
from .report import Summary, save_failure
from .run import CaseResult, Setup, run_case

__all__ = ["fuzz", "run_indices"]

_CHUNK = 20          # cases per task of a pool


def run_indices(seed: int, indices, plan: Plan, setup: Setup) -> list[CaseResult]:
    """Generate and run cases ``indices`` of the fuzz run ``seed``."""
    return [run_case(generate(seed, i, plan), setup) for i in indices]


def _task(args) -> list[CaseResult]:
    return run_indices(*args)


def fuzz(seed: int, indices, plan: Plan, setup: Setup, jobs: int = 1,
         failures: Path | None = None, progress=sys.stderr) -> tuple[Summary, float]:
    """Run the cases ``indices``; return the summary and the wall time [s].

    Failing cases are written into ``failures`` (if given) as replayable files.
    """
    indices = list(indices)
    chunks = [indices[i:i + _CHUNK] for i in range(0, len(indices), _CHUNK)]
    tasks = [(seed, chunk, plan, setup) for chunk in chunks]
    summary, start = Summary(), time.perf_counter()
    every = max(1, len(chunks) // 20)
    if jobs > 1:
        with multiprocessing.get_context("spawn").Pool(jobs) as pool:
            _collect(pool.imap_unordered(_task, tasks), summary, seed, plan, setup, failures,
                     progress, every, start, len(indices))
    else:
        _collect(map(_task, tasks), summary, seed, plan, setup, failures, progress, every,
                 start, len(indices))
    return summary, time.perf_counter() - start


def _collect(batches, summary, seed, plan, setup, failures, progress, every, start, total):
    for k, batch in enumerate(batches, 1):
        for result in batch:
            summary.add(result)
            if result.failed and failures is not None:
                save_failure(result, generate(seed, result.index, plan), failures, setup.paths)
        if progress is not None and k % every == 0:
            print(f"  {summary.cases}/{total} cases, {summary.failures} failing, "
                  f"{time.perf_counter() - start:.0f} s", file=progress, flush=True)
