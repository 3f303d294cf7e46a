"""Where a campaign runs: a Dask LocalCluster on this machine (default) or an existing cluster.

The local cluster has one worker process per core (or ``workers``), one thread each: the core
is Python code holding the GIL, so processes, not threads, run cases in parallel. The workers
of an existing cluster need the project installed (``pip install 'pipeplug[dask]'``) in the same
version as the client.

Dask's defaults suit interactive work with a dashboard: every process wakes many times a
second to watch itself (:data:`QUIET` lists what). A campaign's tasks are long compute-bound
chunks and no dashboard is started, so the local cluster and the client run with those watches
slowed or off: on a 2-core virtual machine they took 0.17 of a core with the cluster idle, a
twelfth of the machine, against 0.02 with :data:`QUIET`.
"""
from __future__ import annotations

import logging
import os
import tempfile
import time
from contextlib import contextmanager

__all__ = ["dask_client", "QUIET"]

#: Dask settings of the processes a campaign starts (the client's, and a LocalCluster's
#: scheduler, nannies and workers: nannies pass their settings on to their workers)
QUIET = {
    # the event loop's latency probe (20 ms by default) only feeds warnings and the dashboard
    "distributed.admin.tick.interval": "1s",
    # the worker's statistical profiler samples every task's stack every 10 ms for the
    # dashboard; it takes the GIL from the worker's event loop and a core from the other workers
    "distributed.worker.profile.enabled": False,
    # memory limits are still enforced, checked every second instead of every 100 ms: a
    # chunk's table holds some 13 MB (100,000 blows)
    "distributed.worker.memory.monitor-interval": "1s",
    # CPU, memory and network counters for the dashboard (500 ms by default)
    "distributed.admin.system-monitor.interval": "2s",
    # GIL contention, polled every 1 ms when the package gilknocker is installed
    "distributed.admin.system-monitor.gil.enabled": False,
}


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None):
    """A ``distributed.Client``: of the scheduler at ``scheduler`` (e.g.
    ``tcp://10.0.0.5:8786``) or of a new LocalCluster of ``workers`` processes (default: one
    per core), closed on exit; both with the settings :data:`QUIET` in this process."""
    import dask
    from distributed import Client, LocalCluster
    with dask.config.set(QUIET):
        if scheduler:
            with Client(scheduler) as client:
                yield client
            return
        n = workers or os.cpu_count() or 1
        # The workers' scratch space (and Dask's lock files beside it) in a folder of this run,
        # removed with the cluster: nothing is left in the temporary directory.
        with tempfile.TemporaryDirectory(prefix="pipeplug-dask-") as scratch, \
                dask.config.set({"temporary-directory": scratch}):
            # No dashboard; the scheduler's HTTP routes (health, metrics) still listen, on a
            # free port of the loopback rather than on 8787, which a user's own cluster may hold.
            # The cluster's own log lines stay off the user's terminal: on a loaded machine (two
            # campaigns at once) a late heartbeat logged an ERROR and tracebacks of a retry that
            # then succeeded; a task that fails reaches the campaign through its result.
            with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                              dashboard_address=None, silence_logs=logging.CRITICAL,
                              local_directory=scratch,
                              scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cluster, \
                    Client(cluster) as client:
                yield client
                _close_workers(cluster, client)


def _close_workers(cluster, client, timeout: float = 30.0) -> None:
    """Close the workers while the scheduler still runs. Closing the cluster closes the
    scheduler while workers may still send it a heartbeat, which they log as an ERROR with a
    traceback after a campaign that went well (distributed's race at close: one campaign in
    six here)."""
    cluster.scale(0)
    deadline = time.monotonic() + timeout
    while client.scheduler_info(n_workers=-1)["workers"] and time.monotonic() < deadline:
        time.sleep(0.05)
