"""The engine of campaigns (sweeps, fuzz runs): chunks of cases on a Dask cluster, collected as
they finish.

A campaign is any object with ``name``, ``n_chunks``, ``chunk_cases(c)`` (cases in chunk ``c``)
and ``run_chunk(c)``, a pure function of the chunk's number (cases generated where they run,
from the campaign and their indices: only the campaign, chunk numbers and results travel).
:func:`map_chunks` runs chunks and hands each result to a collector
in this process (a fuzz run's summary); :func:`run_campaign` collects into an output folder:
``run_chunk`` gives a ``pyarrow.Table``, the campaign has a ``digest``, and the engine submits
the chunks not yet in the folder (:class:`~.store.ChunkStore`: each file whole or not at all).
A worker that sees the folder writes its chunk's file itself (a LocalCluster's workers always
do) and its task returns an acknowledgement, which stays on the worker: the scheduler tells the
client a finished task's result type, so the client fetches nothing (a round trip to the worker
per chunk less); a worker that does not see it (a remote worker without the same file system)
returns the file's bytes, which the client fetches and writes. So:

* a rerun skips the finished chunks;
* a worker that dies loses nothing: Dask runs its unfinished chunks again on another worker;
  its half-written file has a temporary name, and a chunk run twice gives the same file under
  the same name;
* the output does not depend on the number of workers, on which of them see the folder, nor on
  the order chunks finish in.

A chunk that raises is reported and left out; a rerun tries it again.
"""
from __future__ import annotations

import time
import uuid
from dataclasses import dataclass, field
from functools import partial

from pipeplug_harness.io import parquet_bytes

from .store import ChunkFiles, ChunkStore, Written

__all__ = ["map_chunks", "run_campaign", "ChunkRun", "CampaignRun"]


@dataclass
class ChunkRun:
    """What a run of chunks did."""

    chunks: int                     #: chunks of the campaign
    skipped: int = 0                #: already done (not run)
    written: int = 0                #: chunks run and collected now
    by_workers: int = 0             #: of these, files the workers wrote themselves
    cases: int = 0                  #: cases run now
    failed: dict = field(default_factory=dict)    #: chunk -> error text
    seconds: float = 0.0            #: wall time (submission to the last result collected)

    @property
    def complete(self) -> bool:
        return self.skipped + self.written == self.chunks


#: the record of :func:`run_campaign`
CampaignRun = ChunkRun


def _run(campaign, c: int):
    return campaign.run_chunk(c)


def _run_stored(campaign, c: int, files: ChunkFiles | None) -> Written | bytes:
    """On a worker: run chunk ``c``; write its file if this process sees the folder (the
    :class:`Written` acknowledgement stays here: the client, told its type, does not fetch
    it), else return the file's bytes for the client to write."""
    table = campaign.run_chunk(c)
    if files is not None and files.visible():
        return files.write_table(c, table)
    return parquet_bytes(table)


def map_chunks(campaign, chunks, client, collect, *, progress: bool = True,
               on_chunk=None, skipped: int = 0, task=_run, fetch=None) -> ChunkRun:
    """Run ``campaign.run_chunk(c)`` for each of ``chunks`` on ``client``'s cluster and hand
    each result to ``collect(c, result)`` in this process, in the order they finish.

    Parameters
    ----------
    campaign : object
        ``name``, ``n_chunks``, ``chunk_cases(c)``, ``run_chunk(c)`` (see the module
        docstring); sent with every task, so it should be small (no case data).
    chunks : sequence of int
        The chunks to run.
    client : distributed.Client
    collect : callable
        ``collect(c, result)``: e.g. write the chunk, or add it to a summary.
    fetch : callable, optional
        ``fetch(c, kind)``, asked once chunk ``c``'s task has finished, ``kind`` the type of its
        result (None if unknown): whether the result must come to this process (default:
        always); when it says no, ``collect(c, None)``.
    progress : bool
        Show a progress bar (tqdm, on standard error) counting cases.
    on_chunk : callable, optional
        ``on_chunk(c, run)`` after chunk ``c`` is collected.
    skipped : int
        Chunks done before (counted in the bar and the record).
    task : callable
        ``task(campaign, c)``, what a worker runs for chunk ``c`` (default: ``run_chunk``).
    """
    from distributed import as_completed
    from tqdm import tqdm
    run = ChunkRun(campaign.n_chunks, skipped=skipped)
    todo = list(chunks)
    total = sum(campaign.chunk_cases(c) for c in range(campaign.n_chunks))
    bar = tqdm(total=total, initial=total - sum(campaign.chunk_cases(c) for c in todo),
               unit="case", desc=campaign.name, disable=not progress, mininterval=1.0)
    start = time.perf_counter()
    if todo:
        # Each task carries the campaign (a few kB) rather than sharing one scattered copy:
        # a task then needs nothing that a dead worker might have held.
        token = uuid.uuid4().hex[:8]
        futures = {client.submit(task, campaign, c, key=f"{campaign.name}-{token}-{c}",
                                 retries=0): c for c in todo}
        for future in as_completed(futures):
            c = futures.pop(future)
            if future.status == "error":
                run.failed[c] = repr(future.exception())
            else:
                wanted = fetch is None or fetch(c, future.type)
                collect(c, future.result() if wanted else None)
                run.written += 1
                run.cases += campaign.chunk_cases(c)
                bar.update(campaign.chunk_cases(c))
                if on_chunk is not None:
                    on_chunk(c, run)
            future.release()
    bar.close()
    run.seconds = time.perf_counter() - start
    return run


def run_campaign(campaign, out, client, *, fresh: bool = False, progress: bool = True,
                 on_chunk=None, about: dict | None = None,
                 workers_write: bool = True) -> ChunkRun:
    """Run the campaign's chunks missing from the folder ``out`` on ``client``'s cluster,
    writing each as it arrives.

    Parameters
    ----------
    campaign : object
        See the module docstring (also ``digest``: what the folder must hold).
    out : path
        The output folder (:class:`~.store.ChunkStore`).
    client : distributed.Client
    fresh : bool
        Start afresh: drop what the folder holds.
    progress, on_chunk
        As for :func:`map_chunks`.
    about : dict, optional
        Written into the folder's manifest (e.g. the campaign's file).
    workers_write : bool
        Let the workers that see the folder write their chunks' files (False: every chunk's
        bytes come to the client, as from workers that do not see it).
    """
    store = ChunkStore(out, campaign.digest, campaign.n_chunks, fresh=fresh, about=about)
    todo = [c for c in range(campaign.n_chunks) if not store.done(c)]
    # Whether a worker sees the folder is found out by each task, not assumed nor asked of the
    # user: it reads this run's token in the manifest (cheap, once per chunk), which a worker on
    # another machine with a same-named folder cannot; workers joining mid-run are covered, and
    # a worker that cannot see the folder only costs the client the writing, as before.
    by_workers = []

    def collect(c: int, result: Written | bytes | None) -> None:
        if result is None or isinstance(result, Written):   # the worker wrote the file
            by_workers.append(c)
        else:
            store.write(c, result)

    # Decided by what the task returned, not by looking for the file: a file that a stale or
    # concurrent writer left is overwritten with the bytes, and a file system that shows new
    # files late (NFS) does not matter.
    try:
        run = map_chunks(campaign, todo, client, collect, progress=progress,
                         on_chunk=on_chunk, skipped=campaign.n_chunks - len(todo),
                         task=partial(_run_stored,
                                      files=store.files if workers_write else None),
                         fetch=lambda c, kind: kind is not Written)
    finally:
        store.close()
    run.by_workers = len(by_workers)
    return run
