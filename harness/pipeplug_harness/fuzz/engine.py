"""Running many cases: generate from ``(seed, index)``, run, aggregate, save failures.

The map step is :func:`run_indices` (cases generated where they run, so only indices and
results travel); it runs in this process or on a Dask cluster (``client``: the one parallel
back end of the harness, the sweep engine's :func:`pipeplug_harness.sweep.engine.map_chunks`,
with :class:`FuzzCampaign`); aggregation (:class:`~.report.Summary`) does not care about the
order results arrive in.
"""
from __future__ import annotations

import sys
import time
from dataclasses import dataclass

from .cases import Plan, generate
from .elastic_cases import generate_elastic
from .elastic_run import run_elastic_case
from .growth_cases import generate_growth
from .growth_run import run_growth_case
from .ram_cases import generate_ram
from .ram_run import run_ram_case
from .report import Summary, save_failure
from .run import CaseResult, Setup, run_case

__all__ = ["fuzz", "run_indices", "make_case", "run_one", "FuzzCampaign", "MODELS"]

#: the fuzz's model families: --model name -> case generator and runner
MODELS = {"rigid": (generate, run_case), "elastic": (generate_elastic, run_elastic_case),
          "ram": (generate_ram, run_ram_case), "growth": (generate_growth, run_growth_case)}


def make_case(seed: int, index: int, plan: Plan):
    """Case ``index`` of the fuzz run ``seed`` of the plan's model family."""
    return MODELS[plan.model][0](seed, index, plan)


def run_one(case, setup: Setup) -> CaseResult:
    """Run a case of either family with its own runner."""
    return MODELS[getattr(case, "kind", "rigid")][1](case, setup)

#: cases per task on a cluster: a task costs the engine ~10 ms (scheduler round trip), a case
#: a few ms, so a chunk of 100 keeps that under a few per cent
DASK_CHUNK = 100


def run_indices(seed: int, indices, plan: Plan, setup: Setup) -> list[CaseResult]:
    """Generate and run cases ``indices`` of the fuzz run ``seed``."""
    return [run_one(make_case(seed, i, plan), setup) for i in indices]


@dataclass(frozen=True)
class FuzzCampaign:
    """The cases ``indices`` of the fuzz run ``seed`` as a campaign of the sweep engine: chunk
    ``c`` is :func:`run_indices` of its ``chunk`` indices (a ``range`` travels as three
    numbers)."""

    seed: int
    indices: range | tuple
    plan: Plan
    setup: Setup
    chunk: int = DASK_CHUNK
    name: str = "fuzz"

    @property
    def n_chunks(self) -> int:
        return -(-len(self.indices) // self.chunk)

    def _part(self, c: int):
        return self.indices[c * self.chunk:(c + 1) * self.chunk]

    def chunk_cases(self, c: int) -> int:
        return len(self._part(c))

    def run_chunk(self, c: int) -> list[CaseResult]:
        return run_indices(self.seed, self._part(c), self.plan, self.setup)


def fuzz(seed: int, indices, plan: Plan, setup: Setup, failures=None, progress=sys.stderr,
         client=None) -> tuple[Summary, float]:
    """Run the cases ``indices``; return the summary and the wall time [s].

    Failing cases are written into ``failures`` (if given: a folder or an output folder) as
    replayable files. With a ``distributed.Client`` the cases run on its cluster, else in this
    process.
    """
    if client is not None:
        return _fuzz_on_dask(seed, indices, plan, setup, client, failures, progress)
    indices = list(indices)
    chunks = [indices[i:i + DASK_CHUNK] for i in range(0, len(indices), DASK_CHUNK)]
    summary, start = Summary(), time.perf_counter()
    every = max(1, len(chunks) // 20)
    _collect((run_indices(seed, chunk, plan, setup) for chunk in chunks), summary, seed, plan,
             setup, failures, progress, every, start, len(indices))
    return summary, time.perf_counter() - start


def _collect(batches, summary, seed, plan, setup, failures, progress, every, start, total):
    for k, batch in enumerate(batches, 1):
        for result in batch:
            summary.add(result)
            if result.failed and failures is not None:
                save_failure(result, make_case(seed, result.index, plan), failures, setup.paths)
        if progress is not None and k % every == 0:
            print(f"  {summary.cases}/{total} cases, {summary.failures} failing, "
                  f"{time.perf_counter() - start:.0f} s", file=progress, flush=True)


def _fuzz_on_dask(seed, indices, plan, setup, client, failures, progress):
    from pipeplug_harness.sweep.engine import map_chunks
    indices = indices if isinstance(indices, range) else tuple(indices)
    campaign = FuzzCampaign(seed, indices, plan, setup)
    summary = Summary()

    def collect(c, batch):
        _collect([batch], summary, seed, plan, setup, failures, None, 1, 0.0, len(indices))

    run = map_chunks(campaign, range(campaign.n_chunks), client, collect,
                     progress=progress is not None)
    if run.failed:
        raise RuntimeError(f"{len(run.failed)} chunk(s) of the fuzz run failed on the cluster: "
                           + "; ".join(f"chunk {c}: {t}" for c, t in sorted(run.failed.items())))
    return summary, run.seconds
