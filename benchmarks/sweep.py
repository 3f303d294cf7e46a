"""Benchmark of the sweep engine: cases per second per worker, 2 workers against 1, a million
single blows, and the time projected for a cluster.

Usage::

    python -m benchmarks.sweep [--cases 4000000] [--million 1000000] [--chunk 100000]
                                           [--repeat 6] [--slow-cases 40000] [--slow-chunk 2000]

The cases are single blows of model I (the paper's base case, 23 kN for 50 ms, run from rest
until all is at rest), (tau1, tau2) drawn uniformly over the Fig. 2 plane (tau1 < 0.12 MPa,
tau2 < 0.08 MPa), in two mixes:

* ``batch``: the sweep as written, run by the core's batch API, one call per chunk (what every
  single-blow sweep wanting no mode sequence runs): a few microseconds per case, so a chunk
  must hold many cases (``--chunk``, by default what a sweep file without ``chunk`` gets,
  0.1-0.3 s of work) for the engine's cost per chunk not to matter;
* ``per-case``: the same blows with their mode sequences wanted (``[output] modes = true``, as
  for Fig. 2): one model per case, a few hundred microseconds each, chunks of
  ``--slow-chunk`` (by default, too, a sweep file's).

The workers of the LocalCluster see the output folder, so they write the chunk files; the batch
mix is also run as ``batch, client writes`` (each chunk's bytes sent to the client, which
writes them: what a cluster whose workers do not see the folder does), and as ``batch, plain
processes``: its chunks run, encoded and written by 1 and by 2 plain processes (a process pool,
no Dask), what this machine itself gives two processes against one at the time; the engine's
speed-up is printed as a fraction of it too (on this shared virtual machine two plain processes
gave 1.57 to 2.15 times one, from one minute to the next).

Measured, in one run:

1. per mix, ``c0``: a chunk's cost per case in this process, its table encoded as Parquet (what
   a worker does), and the cost per case of writing a chunk's file;
2. ``s``: the engine's cost per chunk: empty chunks through a one-worker LocalCluster (the
   scheduler's round trips, the worker writing the file, the client seeing it);
3. per mix, the sweep on 1 and on 2 workers, in ``--repeat`` pairs of runs side by side (a
   LocalCluster of each size up throughout): cases per second, ``c`` (seconds per case per
   worker, from the best 1-worker run), the speed-up T1 / T2 and the parallel efficiency
   T1 / (2 T2) (target: speed-up >= 1.6). The speed-up is the median over the pairs: the
   speed of this shared virtual machine's cores swings by up to a half from one run to the next (a
   plain process's time per case, with nothing else running here), more than the engine's
   overhead; the two runs of a pair see much the same machine, and the median leaves out the
   pair that one swing decided. The range of the pairs and the best run against the best run
   are printed beside it. The
   batch mix runs ``--cases`` blows, about 6 s on one worker here: a run of 1 s (10^6 blows)
   on two workers is decided as much by its start, its last chunk and any hiccup of the shared
   machine of a tenth of a second as by the rate of the workers. Beside each run: the cores
   that the rest of the machine took meanwhile (busy CPU time of the machine, less that of this
   process and its workers, plus the time the hypervisor gave elsewhere, over the run's wall
   time): a 2-worker run is only a fair measure when that is near 0. Also ``w``: the CPU time
   per case of this process (the client and the LocalCluster's scheduler: each chunk's
   completion, or its file to receive and write; its part per chunk is then counted in
   ``s`` too, the pessimistic side) in the 1-worker runs. Here it shares the 2 cores with the
   workers, which bounds the speed-up by ``2 c / (c + w)``. Part of ``w`` is Dask's
   housekeeping, paid per second, not per case (``h``: this process's CPU per second with both
   clusters and both pools up and idle, as during those runs);
4. ``--million`` single blows (batch mix) on 2 workers, ``--repeat`` times: the time of 10^6
   cases on this machine, and what the model below predicts for it;
5. the projection for W workers of a cluster (batch mix)::

       T(N, W) = t_start + max((N c + n s) / W, n s + N w),   n = ceil(N / B)

   with ``c``, ``s`` as measured here and ``w`` less the housekeeping, ``w - h c`` (a
   cluster's cores may be faster or slower; the client on a machine of its own): the workers
   share the cases and the chunks' costs; the scheduler and the client take the chunks one at
   a time (counting all of ``s`` there is the pessimistic side) and the client's work per case.
   Beyond ``W_max = (c + s / B) / (w + s / B)`` workers they, not the workers, set the pace: larger
   chunks raise it (the projection is printed for B and 10 B).
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import tempfile
import time
from contextlib import ExitStack, contextmanager
from functools import partial
from pathlib import Path
from typing import NamedTuple

import pyarrow as pa

from pipeplug_harness.io import parquet_bytes
from pipeplug_harness.sweep.cluster import dask_client
from pipeplug_harness.sweep.engine import run_campaign
from pipeplug_harness.sweep.file import sweep_spec
from pipeplug_harness.sweep.runners import BATCH_CHUNK
from pipeplug_harness.sweep.store import ChunkFiles

_PLANE = {"tau1": {"dist": "uniform", "low": 0.0, "high": 1.2e5},
          "tau2": {"dist": "uniform", "low": 0.0, "high": 8.0e4}}
#: mix -> what the output section adds to the sweep (the mode sequence takes the per-case path)
MIXES = {"batch": {"modes": False}, "per-case": {"modes": True}}
#: the batch mix with every chunk's bytes sent to the client (which writes them)
CLIENT_WRITES = "batch, client writes"
#: the batch mix's chunks run and written by plain processes, no Dask: the machine's own scaling
PLAIN = "batch, plain processes"


def blow_sweep(cases: int, chunk: int, seed: int = 1, mix: str = "batch"):
    """The benchmark's sweep: ``cases`` single blows over the Fig. 2 plane."""
    spec = sweep_spec(f"bench-{mix}-{seed}", {
        "sweep": {"kind": "blow", "seed": seed, "samples": cases, "chunk": chunk},
        "random": _PLANE, "pipe": {"L1": 1.0}, "plug": {"L2": 1.0},
        "soil": {"contact_growth": False},
        "model": {"elastic": False, "solver": "exact"},
        "blows": {"amplitude": 23e3, "duration": 0.05}, "output": MIXES[mix]})
    assert spec.runner == ("batch" if mix == "batch" else "case"), spec.runner
    return spec


class EmptyChunks:
    """A campaign of ``n`` chunks of no work: what the engine costs per chunk."""

    name = "empty"

    def __init__(self, n: int):
        self.n_chunks, self.digest = n, f"empty{n}{time.time_ns()}"

    def chunk_cases(self, c: int) -> int:
        return 0

    def run_chunk(self, c: int) -> pa.Table:
        return pa.table({"case": pa.array([c], pa.int64())})


def in_process(spec, chunks: int, folder: Path) -> tuple[float, float]:
    """Seconds per case of running and encoding chunks here, and of writing their files."""
    work = write = 0.0
    cases = 0
    for c in range(chunks):
        start = time.perf_counter()
        table = spec.run_chunk(c)
        data = parquet_bytes(table)
        middle = time.perf_counter()
        (folder / f"{c}.parquet").write_bytes(data)
        work, write = work + middle - start, write + time.perf_counter() - middle
        cases += table.num_rows
    return work / cases, write / cases


def engine_seconds(spec, client, folder: Path, workers_write: bool = True) -> float:
    run = run_campaign(spec, folder, client, fresh=True, progress=False,
                       workers_write=workers_write)
    assert run.complete and not run.failed
    assert run.by_workers == (run.written if workers_write else 0), run
    return run.seconds


def _warm(client, folder: Path) -> None:
    """Each worker loads what both mixes run (compiled code from the disk cache)."""
    for mix in MIXES:
        engine_seconds(blow_sweep(400, 100, seed=9, mix=mix), client, folder / f"warm-{mix}")


def _cpu_seconds() -> tuple[float, float]:
    """Busy CPU seconds of the machine (with the hypervisor's steal) and of this process with
    its children (the workers)."""
    import psutil
    m = psutil.cpu_times()
    me = psutil.Process()
    ours = 0.0
    for proc in [me, *me.children(recursive=True)]:
        try:
            t = proc.cpu_times()
            ours += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return m.user + m.nice + m.system + m.irq + m.softirq + m.steal, ours


class Run(NamedTuple):
    seconds: float        #: wall time
    others: float         #: cores the rest of the machine took meanwhile
    client: float         #: CPU seconds of this process (client and scheduler)


def one_against_two(specs: dict, repeat: int, folder: Path) -> tuple[dict, float]:
    """mix -> {workers: [:class:`Run` of each run]}: ``repeat`` pairs of runs, one on 1 worker
    and one on 2 next to each other (which goes first alternating, so an even ``repeat``
    balances what one run leaves to the next, e.g. files still being flushed), each mix in turn
    and then the batch mix in plain processes (:data:`PLAIN`). Both LocalClusters and both
    pools stay up throughout (warmed first; an idle cluster takes about 0.01 of a core), so no
    run waits for a cluster to start and the two runs of a pair are seconds apart. Also ``h``,
    this process's CPU per second with all of them up and idle (its housekeeping)."""
    times = {mix: {1: [], 2: []} for mix in [*specs, PLAIN]}
    with ExitStack() as stack:
        clients = {w: stack.enter_context(dask_client(workers=w)) for w in (1, 2)}
        pools = {w: stack.enter_context(plain_pool(w)) for w in (1, 2)}
        for client in clients.values():
            _warm(client, folder)
        h = _idle_cpu(3.0)
        for i in range(repeat):
            order = (1, 2) if i % 2 == 0 else (2, 1)
            for mix, spec in specs.items():
                for w in order:
                    times[mix][w].append(_timed(partial(
                        engine_seconds, spec, clients[w], folder / mix.replace(" ", "_"),
                        workers_write=mix != CLIENT_WRITES)))
            for w in order:
                times[PLAIN][w].append(_timed(partial(plain_seconds, pools[w], specs["batch"],
                                                      folder / "plain")))
    return times, h


def _timed(run) -> Run:
    """``run()`` (it returns its wall time) with the cores the rest of the machine took."""
    (busy, ours), mine = _cpu_seconds(), _own_cpu()
    seconds = run()
    (busy2, ours2), mine2 = _cpu_seconds(), _own_cpu()
    others = max(0.0, (busy2 - busy) - (ours2 - ours)) / seconds
    return Run(seconds, others, mine2 - mine)


@contextmanager
def plain_pool(processes: int):
    """A pool of ``processes`` plain processes, each started and warm (no Dask)."""
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context
    with ProcessPoolExecutor(processes, mp_context=get_context("spawn")) as pool:
        list(pool.map(_warm_plain, [blow_sweep(400, 100, seed=9)] * processes))
        yield pool


def _warm_plain(spec) -> None:
    spec.run_chunk(0)
    time.sleep(0.5)                 # hold this process so that the pool starts the others


def plain_seconds(pool, spec, folder: Path) -> float:
    """Wall time [s] of ``spec``'s chunks run and written by ``pool``'s processes, each
    doing with a chunk what a worker does: what the machine itself gives."""
    folder.mkdir(exist_ok=True)
    start = time.perf_counter()
    done = list(pool.map(_run_and_write, [spec] * spec.n_chunks, range(spec.n_chunks),
                         [folder] * spec.n_chunks))
    seconds = time.perf_counter() - start
    assert done == list(range(spec.n_chunks))
    return seconds


def _run_and_write(spec, c: int, folder: Path) -> int:
    """In a plain process: run chunk ``c``, encode it, write its file."""
    ChunkFiles(folder, 6, "plain").write_table(c, spec.run_chunk(c))
    return c


def on_two_workers(spec, repeat: int, folder: Path) -> list:
    """Wall times [s] of ``repeat`` runs of ``spec`` on a 2-worker LocalCluster (warmed)."""
    with dask_client(workers=2) as client:
        _warm(client, folder)
        return [engine_seconds(spec, client, folder / f"run{i}") for i in range(repeat)]


def _idle_cpu(seconds: float) -> float:
    """This process's CPU seconds per second over ``seconds`` of doing nothing."""
    start, wall = _own_cpu(), time.perf_counter()
    time.sleep(seconds)
    return (_own_cpu() - start) / (time.perf_counter() - wall)


def _own_cpu() -> float:
    t = os.times()
    return t.user + t.system


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=4_000_000,
                        help="cases of the batch mix's 1-vs-2 runs")
    parser.add_argument("--million", type=int, default=1_000_000,
                        help="cases of the timed run on 2 workers (batch mix)")
    parser.add_argument("--chunk", type=int, default=BATCH_CHUNK,
                        help="cases per chunk (batch; default: a batch sweep's)")
    parser.add_argument("--slow-cases", type=int, default=40_000,
                        help="cases of the per-case mix")
    parser.add_argument("--slow-chunk", type=int, default=2000,
                        help="cases per chunk (per-case)")
    parser.add_argument("--repeat", type=int, default=6,
                        help="pairs of 1- and 2-worker runs (even: each goes first as often)")
    parser.add_argument("--empty", type=int, default=200, help="empty chunks timed for s")
    args = parser.parse_args(argv)
    print(f"sweep benchmark, {time.strftime('%Y-%m-%d %H:%M:%S')}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f} (the machine is shared: ratios from one run)",
          flush=True)
    specs = {"batch": blow_sweep(args.cases, args.chunk),
             "per-case": blow_sweep(args.slow_cases, args.slow_chunk, mix="per-case")}
    runs = {**specs, CLIENT_WRITES: specs["batch"]}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        here = {}
        for mix, spec in specs.items():
            spec.run_chunk(spec.n_chunks - 1)                         # warm-up: imports, JIT
            (tmp / f"here-{mix}").mkdir()
            here[mix] = in_process(spec, min(spec.n_chunks, 4), tmp / f"here-{mix}")
            print(f"{mix}: in this process {here[mix][0] * 1e6:.2f} us per case run and "
                  f"encoded ({1 / here[mix][0]:,.0f} cases/s); writing its file "
                  f"{here[mix][1] * 1e6:.3f} us per case", flush=True)
        start = time.perf_counter()
        with dask_client(workers=1) as client:
            t_start = time.perf_counter() - start
            _warm(client, tmp)
            s = engine_seconds(EmptyChunks(args.empty), client, tmp / "empty") / args.empty
        print(f"LocalCluster start {t_start:.2f} s; engine cost per chunk s = {s * 1e3:.2f} ms "
              f"({args.empty} empty chunks, 1 worker)", flush=True)
        times, h = one_against_two(runs, args.repeat, tmp)
        print(f"housekeeping h = {h:.3f} cores (this process, both clusters up and idle)",
              flush=True)
        big = blow_sweep(args.million, args.chunk)
        t_big = min(on_two_workers(big, args.repeat, tmp / "million"))
    print(f"load average after the runs {os.getloadavg()[0]:.2f}")
    costs = {mix: _report(mix, runs[mix], times[mix], s) for mix in runs}
    _print_runs(PLAIN, specs["batch"], times[PLAIN])
    print(f"the machine's own scaling (plain processes, same chunks, no Dask): "
          f"{_speedups(times[PLAIN])}; "
          f"the engine's speed-up against it, the median over the repeats of the ratio of a "
          f"repeat's two: {_relative(times['batch'], times[PLAIN]):.0%} (batch), "
          f"{_relative(times[CLIENT_WRITES], times[PLAIN]):.0%} (client writes)", flush=True)
    c, w = costs["batch"]
    net = max(0.0, w - h * c)                  # the client's work per case, on a core of its own
    print(f"{big.n_cases:,} single blows (batch API) on 2 workers, chunks of {big.chunk:,}: "
          f"{t_big:.2f} s ({big.n_cases / t_big:,.0f} cases/s); the model below predicts "
          f"{_projected(big.n_cases, 2, big.chunk, c, s, net, 0.0):.2f} s with its client on "
          f"cores of its own, {(big.n_cases * (c + w) + big.n_chunks * s) / 2:.2f} s sharing "
          f"these 2", flush=True)
    _projection(c, s, net, t_start, big.chunk)
    return 0


def _report(mix: str, spec, times: dict, s: float) -> tuple[float, float]:
    """Print a mix's rates, speed-up and efficiency; return ``c``, seconds per case per worker,
    and ``w``, this process's CPU seconds per case (both from the best 1-worker run)."""
    n = spec.n_cases
    _print_runs(mix, spec, times)
    one = min(times[1], key=lambda r: r.seconds)
    c, w, speedup = one.seconds / n, one.client / n, _speedup(times)
    print(f"{mix}: c = {c * 1e6:.2f} us per case per worker, client and scheduler w = "
          f"{w * 1e6:.2f} us CPU per case (1 worker); a chunk's work {spec.chunk * c * 1e3:.0f} "
          f"ms against s = {s * 1e3:.2f} ms; 2 workers against 1: speed-up {_speedups(times)} "
          f"(target >= 1.6: {'met' if speedup >= 1.6 else 'NOT met'}), parallel efficiency "
          f"{100 * speedup / 2:.0f} %; the client sharing the 2 cores bounds it at "
          f"{2 * c / (c + w):.2f}", flush=True)
    return c, w


def _print_runs(mix: str, spec, times: dict) -> None:
    n = spec.n_cases
    for workers, runs in times.items():
        best = min(r.seconds for r in runs)
        print(f"{mix}, {workers} worker(s): {n:,} cases in {spec.n_chunks} chunks of "
              f"{spec.chunk:,}: " + ", ".join(f"{r.seconds:.2f} s ({r.others:.2f})" for r in runs)
              + f" (in brackets: cores taken by the rest of the machine); best "
              f"{n / best:,.0f} cases/s, {n / best / workers:,.0f} cases/s per worker",
              flush=True)


def _speedup(times: dict) -> float:
    """The median over pairs of (1-worker time / 2-worker time), each pair run side by side."""
    return statistics.median(_ratios(times))


def _ratios(times: dict) -> list:
    return [one.seconds / two.seconds for one, two in zip(times[1], times[2], strict=True)]


def _relative(engine: dict, plain: dict) -> float:
    """The median over the repeats of the engine's pair ratio over the plain processes' pair
    ratio of the same repeat (a minute apart at most)."""
    return statistics.median(e / p for e, p in zip(_ratios(engine), _ratios(plain),
                                                    strict=True))


def _speedups(times: dict) -> str:
    """The speed-up in words: the median of the pairs, their range, best against best."""
    ratios = _ratios(times)
    best = min(r.seconds for r in times[1]) / min(r.seconds for r in times[2])
    return (f"{_speedup(times):.2f} (median of {len(ratios)} pairs run side by side; pairs "
            f"{min(ratios):.2f}-{max(ratios):.2f}; best run against best run {best:.2f})")


def _projected(n: int, w: int, b: int, c: float, s: float, write: float,
               t_start: float) -> float:
    chunks = math.ceil(n / b)
    return t_start + max((n * c + chunks * s) / w, chunks * s + n * write)


def _projection(c: float, s: float, write: float, t_start: float, b: int) -> None:
    print(f"projection (batch API): T(N, W) = t_start + max((N c + n s) / W, n s + N w), "
          f"n = ceil(N/B), with c = {c * 1e6:.2f} us, s = {s * 1e3:.2f} ms, w - h c = "
          f"{write * 1e6:.3f} us, t_start = {t_start:.1f} s (this machine's):")
    for chunk in (b, 10 * b):
        print(f"  B = {chunk:,}: the scheduler and the client set the pace beyond W_max = "
              f"{w_max(c, s, write, chunk):,.0f} workers")
        for n in (10 ** 6, 10 ** 8, 10 ** 10):
            cells = ", ".join(f"W={w}: {_human(_projected(n, w, chunk, c, s, write, t_start))}"
                              for w in (2, 16, 64, 256, 1024))
            print(f"    N = {n:.0e}: {cells}")


def w_max(c: float, s: float, write: float, b: int) -> float:
    """The workers beyond which the serial part (chunks through the scheduler and client,
    cases written) outlasts the workers' share."""
    return (c + s / b) / (write + s / b)


def _human(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else (f"{seconds / 60:.1f} min" if seconds < 7200
                                                     else f"{seconds / 3600:.1f} h")


if __name__ == "__main__":
    raise SystemExit(main())
