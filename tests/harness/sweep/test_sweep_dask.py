"""Sweeps on a Dask LocalCluster: the same results for any number of workers and whoever writes
the files, resuming, a worker killed mid-run, the command line. One cluster of two worker
processes serves the module; its workers see the output folder, so they write the files."""
import os
import signal

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from pipeplug_harness.errors import UserError
from pipeplug_harness.sweep.cluster import dask_client
from pipeplug_harness.sweep.engine import run_campaign
from pipeplug_harness.sweep.file import load_sweep, sweep_spec
from pipeplug_harness.sweep.store import read_folder

# Short rigid drives (~3 ms each) over lognormal soil: some reach the target, some refuse.
DRIVES = """
[sweep]
kind = "drive"
seed = 11
samples = {samples}
chunk = {chunk}
report = "drivability"
[random]
tau1 = {{dist = "lognormal", median = 8.0e4, sigma = 0.2}}
tau2 = {{dist = "lognormal", median = 2.0e4, sigma = 0.5}}
[pipe]
L1 = 2.0
[plug]
L2 = 2.0
[blows]
amplitude = 23000.0
duration = 0.01
period = 0.2
[model]
elastic = false
[drive]
target = 1.0
step = 0.01
"""


@pytest.fixture(scope="module")
def client():
    with dask_client(workers=2) as c:
        yield c


def test_the_workers_run_with_dasks_self_watching_slowed(client):
    """The settings of this process reach the worker processes through their nannies: each
    worker's periodic callbacks (Dask's defaults: profiler every 10 ms, event-loop tick every
    20 ms, memory monitor every 100 ms, system monitor every 500 ms)."""
    def periods(dask_worker):
        return {k: pc.callback_time for k, pc in dask_worker.periodic_callbacks.items()}
    held = client.run(periods)
    assert len(held) == 2
    for every in held.values():
        assert "profile" not in every and "profile-cycle" not in every, every
        assert (every["tick"], every["memory_monitor"], every["monitor"]) == (1000, 1000, 2000)


def _sweep(tmp_path, samples=60, chunk=6, name="drives"):
    path = tmp_path / f"{name}.toml"
    path.write_text(DRIVES.format(samples=samples, chunk=chunk))
    return path, load_sweep(path)


def _reference(spec) -> pa.Table:
    """The sweep run chunk by chunk in this process."""
    return pa.concat_tables([spec.run_chunk(c) for c in range(spec.n_chunks)])


def test_same_results_in_process_on_two_workers_and_on_one(client, tmp_path, pipeplug_cli):
    path, spec = _sweep(tmp_path)
    expected = _reference(spec)
    outcomes = set(expected.column("outcome").to_pylist())
    assert {"target", "set"} <= outcomes and not any(expected.column("error").to_pylist())
    run = run_campaign(spec, tmp_path / "two", client, progress=False)
    assert run.complete and run.written == run.by_workers == spec.n_chunks and not run.failed
    assert read_folder(tmp_path / "two").equals(expected)
    proc = pipeplug_cli("sweep", path, "--workers", "1", "--out", tmp_path / "one",
                        "--figure", tmp_path / "one.png", "--no-progress")
    assert read_folder(tmp_path / "one").equals(expected)
    assert "1 worker(s)" in proc.stdout and "P(refusal) = " in proc.stdout
    assert f"{spec.n_chunks} files written by the workers, 0 here" in proc.stdout
    assert (tmp_path / "one.png").stat().st_size > 10_000


def test_a_batch_sweep_on_two_workers_is_the_sweep_run_here(client, tmp_path, monkeypatch):
    """Single blows on the core's batch API (one call per chunk) through the engine; the
    client fetches a chunk's result only when the worker sent the file's bytes."""
    from distributed import Future
    fetched = []
    result = Future.result
    monkeypatch.setattr(Future, "result", lambda f, *a, **k: fetched.append(f.key)
                        or result(f, *a, **k))
    spec = sweep_spec("blows", {
        "pipe": {"L1": 1.0}, "plug": {"L2": 1.0}, "blows": {"amplitude": 23e3, "duration": 0.05},
        "sweep": {"samples": 3000, "seed": 4, "chunk": 500}, "model": {"elastic": False},
        "random": {"tau1": {"dist": "uniform", "low": 1e3, "high": 1.2e5},
                   "tau2": {"dist": "uniform", "low": 0.0, "high": 8e4}}})
    assert spec.runner == "batch"
    run = run_campaign(spec, tmp_path / "out", client, progress=False)
    assert run.complete and run.written == run.by_workers == 6 and not run.failed
    assert read_folder(tmp_path / "out").equals(_reference(spec)) and not fetched
    sent = run_campaign(spec, tmp_path / "sent", client, progress=False, workers_write=False)
    assert sent.complete and sent.written == 6 and sent.by_workers == 0 and len(fetched) == 6
    for mine, theirs in zip(sorted((tmp_path / "sent").glob("part-*")),
                            sorted((tmp_path / "out").glob("part-*")), strict=True):
        assert mine.read_bytes() == theirs.read_bytes()         # the same files, byte for byte


def test_a_rerun_resumes_and_runs_only_the_missing_chunks(client, tmp_path):
    _, spec = _sweep(tmp_path, samples=24, chunk=4)
    out = tmp_path / "out"
    first = run_campaign(spec, out, client, progress=False)
    assert first.written == 6
    parts = sorted(out.glob("part-*.parquet"))
    parts[1].unlink()
    parts[4].unlink()
    again = run_campaign(spec, out, client, progress=False)
    assert (again.skipped, again.written, again.cases) == (4, 2, 8)
    assert read_folder(out).equals(_reference(spec))
    _, other = _sweep(tmp_path, samples=25, chunk=4, name="other")
    with pytest.raises(UserError, match="another campaign"):
        run_campaign(other, out, client, progress=False)
    assert run_campaign(other, out, client, progress=False, fresh=True).written == 7


@pytest.mark.parametrize("workers_write", [True, False])
def test_a_killed_worker_loses_nothing(client, tmp_path, workers_write):
    """After the first chunk is collected, the worker busy with a chunk is killed (SIGKILL);
    Dask runs its chunks again elsewhere: every case is in the output exactly once, with the
    same values as a run without the kill, whether the workers write the files or the client
    does."""
    _, spec = _sweep(tmp_path, samples=400, chunk=10)
    pids = client.run(os.getpid)
    killed = {}

    def kill_one(c, run):
        if killed:
            return
        busy = [w for w, keys in client.processing().items() if keys]
        assert busy, "no chunk in flight to lose"
        killed.update(worker=busy[0], pid=pids[busy[0]], written=run.written)
        os.kill(pids[busy[0]], signal.SIGKILL)

    run = run_campaign(spec, tmp_path / "out", client, progress=False, on_chunk=kill_one,
                       workers_write=workers_write)
    assert killed and killed["written"] < spec.n_chunks
    assert run.complete and not run.failed
    assert run.by_workers == (spec.n_chunks if workers_write else 0)
    table = pq.read_table(tmp_path / "out")                 # the raw files, as any reader sees them
    cases = sorted(table.column("case").to_pylist())
    assert cases == list(range(spec.n_cases))               # each case exactly once
    assert read_folder(tmp_path / "out").equals(_reference(spec))
    assert killed["pid"] not in client.run(os.getpid).values()


def test_a_bad_file_is_refused_before_any_work(tmp_path, pipeplug_cli):
    path = tmp_path / "bad.toml"
    path.write_text(DRIVES.format(samples=10, chunk=5).replace("= 2.0\n", "= 0.5\n"))
    proc = pipeplug_cli("sweep", path, check=False)
    assert proc.returncode == 2
    assert "target = 1.0" in proc.stderr and "<= L1" in proc.stderr


def test_fuzz_runs_on_the_engine(client, tmp_path):
    """``pipeplug fuzz`` on the cluster: the same summary as in this process (every check's
    cases, failures and worst value; which case was worst first may differ on ties)."""
    from pipeplug_harness.fuzz.cases import Plan
    from pipeplug_harness.fuzz.engine import fuzz
    from pipeplug_harness.fuzz.run import Setup
    plan, setup = Plan(reference=10, fmu=0, fd=0), Setup(("python",))
    here, _ = fuzz(5, range(40, 160), plan, setup, progress=None)
    there, _ = fuzz(5, range(40, 160), plan, setup, progress=None, client=client)
    assert there.cases == here.cases == 120 and there.failures == here.failures == 0
    assert {k: v[:3] for k, v in there.rows.items()} == {k: v[:3] for k, v in here.rows.items()}
    assert there.families == here.families and there.models == here.models


def test_the_local_cluster_closes_its_workers_while_its_scheduler_runs():
    """At the end of a campaign the workers go first: a worker whose heartbeat reaches a
    scheduler already closed logs an ERROR with a traceback after a run that went well."""
    from distributed import Client, LocalCluster

    from pipeplug_harness.sweep.cluster import _close_workers
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        assert len(c.scheduler_info(n_workers=-1)["workers"]) == 1
        _close_workers(cluster, c)
        assert c.scheduler_info(n_workers=-1)["workers"] == {}
        assert cluster.scheduler.status.name == "running"
