"""Where a campaign runs: a Dask LocalCluster on this machine (default) or an existing cluster.

The local cluster has one worker process per core (or ``workers``), one thread each: the core
is Python code holding the GIL, so processes, not threads, run cases in parallel. The workers
of an existing cluster need the project installed (``pip install 'pipeplug[dask]'``) in the same
version as the client.
"""
from __future__ import annotations

import logging
import os
from contextlib import contextmanager

__all__ = ["dask_client"]


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None):
    """A ``distributed.Client``: of the scheduler at ``scheduler`` (e.g.
    ``tcp://10.0.0.5:8786``) or of a new LocalCluster of ``workers`` processes (default: one
    per core), closed on exit."""
    from distributed import Client, LocalCluster
    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                      dashboard_address=None, silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        yield client
