"""The engine of campaigns (sweeps, fuzz runs): chunks of cases on a Dask cluster, written as
they finish.

A campaign is any object with ``name``, ``digest``, ``n_chunks``, ``chunk_cases(c)`` (cases in
chunk ``c``) and ``run_chunk(c) -> pyarrow.Table``, a pure function of the chunk's number. The
engine submits the chunks not yet in the output folder, and the client writes each chunk's
table as it arrives (:class:`~.store.ChunkStore`: whole or not at all), so:

* a rerun skips the finished chunks;
* a worker that dies loses nothing: Dask runs its unfinished chunks again on another worker,
  and a chunk is written once, when its result reaches the client (the workers need no shared
  file system);
* the output does not depend on the number of workers nor on the order chunks finish in.

A chunk that raises is reported and left out; a rerun tries it again.
"""
from __future__ import annotations

import time
import uuid
from dataclasses import dataclass, field

from .store import ChunkStore

__all__ = ["run_campaign", "CampaignRun"]


@dataclass
class CampaignRun:
    """What a run did."""

    chunks: int                     #: chunks of the campaign
    skipped: int = 0                #: already in the folder
    written: int = 0
    cases: int = 0                  #: cases run now
    failed: dict = field(default_factory=dict)    #: chunk -> error text
    seconds: float = 0.0            #: wall time of the run (submission to last write)

    @property
    def complete(self) -> bool:
        return self.skipped + self.written == self.chunks


def _run(campaign, c: int):
    return campaign.run_chunk(c)


def run_campaign(campaign, out, client, *, fresh: bool = False, progress: bool = True,
                 on_chunk=None, about: dict | None = None) -> CampaignRun:
    """Run the campaign's missing chunks on ``client``'s cluster into the folder ``out``.

    Parameters
    ----------
    campaign : object
        See the module docstring.
    out : path
        The output folder (:class:`~.store.ChunkStore`).
    client : distributed.Client
    fresh : bool
        Start afresh: drop what the folder holds.
    progress : bool
        Show a progress bar (tqdm, on standard error) counting cases.
    on_chunk : callable, optional
        ``on_chunk(c, run)`` after chunk ``c`` is written.
    about : dict, optional
        Written into the folder's manifest (e.g. the campaign's file).
    """
    from distributed import as_completed
    from tqdm import tqdm
    store = ChunkStore(out, campaign.digest, campaign.n_chunks, fresh=fresh, about=about)
    todo = [c for c in range(campaign.n_chunks) if not store.done(c)]
    run = CampaignRun(campaign.n_chunks, skipped=campaign.n_chunks - len(todo))
    total = sum(campaign.chunk_cases(c) for c in range(campaign.n_chunks))
    bar = tqdm(total=total, initial=total - sum(campaign.chunk_cases(c) for c in todo),
               unit="case", desc=campaign.name, disable=not progress, smoothing=0.1)
    start = time.perf_counter()
    if todo:
        shared = client.scatter(campaign, broadcast=True, hash=False)
        token = uuid.uuid4().hex[:8]
        futures = {client.submit(_run, shared, c, key=f"{campaign.name}-{token}-{c}",
                                 retries=0): c for c in todo}
        for future in as_completed(futures):
            c = futures.pop(future)
            if future.status == "error":
                run.failed[c] = repr(future.exception())
            else:
                store.write(c, future.result())
                run.written += 1
                run.cases += campaign.chunk_cases(c)
                bar.update(campaign.chunk_cases(c))
                if on_chunk is not None:
                    on_chunk(c, run)
            future.release()
    bar.close()
    run.seconds = time.perf_counter() - start
    return run
