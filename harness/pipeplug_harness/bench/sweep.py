"""Benchmark of the sweep engine: cases per second per worker, 2 workers against 1, a million
single blows, and the time projected for a cluster.

Usage::

    python -m pipeplug_harness.bench.sweep [--cases 40000] [--million 1000000] [--repeat 2]
                                           [--chunk 2000] [--big-chunk 10000]

The cases are single blows of model I (the paper's base case, 23 kN for 50 ms, run from rest
until all is at rest: exact solver through the core), (tau1, tau2) drawn uniformly over the
Fig. 2 plane (tau1 < 0.12 MPa, tau2 < 0.08 MPa). Measured, in one run:

1. ``c0``: the cost of a case in this process (chunks run directly, no Dask);
2. ``s``: the engine's cost per chunk: empty chunks through a one-worker LocalCluster (the
   scheduler's round trip, moving the result, the client writing its Parquet file);
3. the same sweep of ``--cases`` through the engine on 1 and on 2 workers, alternately
   ``--repeat`` times (the best of each counts: the machine is shared): cases per second,
   ``c`` (seconds per case per worker), the speed-up T1 / T2 and the parallel efficiency
   T1 / (2 T2) (target: speed-up >= 1.6);
4. ``--million`` cases on 2 workers in chunks of ``--big-chunk`` (0: skip);
5. the projection for W workers of a cluster::

       T(N, W) = t_start + (N c + n_chunks s) / W,   n_chunks = ceil(N / B)

   with ``c`` and ``s`` as measured here (a cluster's cores may be faster or slower). The
   scheduler and the client handle chunks one at a time, so beyond
   ``W_max = (N c / n_chunks) / s`` workers (a chunk's work over the serial cost per chunk)
   they, not the workers, set the pace: choose B so that B c >> W s.
"""
from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
from pathlib import Path

import pyarrow as pa

from pipeplug_harness.sweep.cluster import dask_client
from pipeplug_harness.sweep.engine import run_campaign
from pipeplug_harness.sweep.file import sweep_spec

_PLANE = {"tau1": {"dist": "uniform", "low": 0.0, "high": 1.2e5},
          "tau2": {"dist": "uniform", "low": 0.0, "high": 8.0e4}}


def blow_sweep(cases: int, chunk: int, seed: int = 1):
    """The benchmark's sweep: ``cases`` single blows over the Fig. 2 plane."""
    return sweep_spec(f"bench{seed}", {
        "sweep": {"kind": "blow", "seed": seed, "samples": cases, "chunk": chunk},
        "random": _PLANE, "soil": {"contact_growth": False},
        "model": {"elastic": False, "solver": "exact"},
        "blows": {"amplitude": 23e3, "duration": 0.05}})


class EmptyChunks:
    """A campaign of ``n`` chunks of no work: what the engine costs per chunk."""

    name = "empty"

    def __init__(self, n: int):
        self.n_chunks, self.digest = n, f"empty{n}{time.time_ns()}"

    def chunk_cases(self, c: int) -> int:
        return 0

    def run_chunk(self, c: int) -> pa.Table:
        return pa.table({"case": pa.array([c], pa.int64())})


def in_process(spec, chunks: int) -> float:
    """Seconds per case, chunks run here."""
    start = time.perf_counter()
    cases = sum(spec.run_chunk(c).num_rows for c in range(chunks))
    return (time.perf_counter() - start) / cases


def engine_seconds(spec, client, folder: Path) -> float:
    run = run_campaign(spec, folder, client, fresh=True, progress=False)
    assert run.complete and not run.failed
    return run.seconds


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=40_000, help="cases of the 1-vs-2 run")
    parser.add_argument("--chunk", type=int, default=2000, help="cases per chunk (1-vs-2)")
    parser.add_argument("--repeat", type=int, default=2, help="alternate 1- and 2-worker runs")
    parser.add_argument("--million", type=int, default=1_000_000,
                        help="cases of the big run on 2 workers (0: skip)")
    parser.add_argument("--big-chunk", type=int, default=10_000, help="cases per chunk (big)")
    parser.add_argument("--empty", type=int, default=200, help="empty chunks timed for s")
    args = parser.parse_args(argv)
    print(f"sweep benchmark, {time.strftime('%Y-%m-%d %H:%M:%S')}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f} (the machine is shared: ratios from one run)",
          flush=True)
    spec = blow_sweep(args.cases, args.chunk)
    spec.run_chunk(0)                                                   # warm-up: imports
    c0 = in_process(spec, max(1, min(spec.n_chunks, 4000 // args.chunk + 1)))
    print(f"in this process: {c0 * 1e6:.1f} us per case ({1 / c0:,.0f} cases/s)", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        times = {1: [], 2: []}
        start = time.perf_counter()
        with dask_client(workers=1) as client:
            t_start = time.perf_counter() - start
            engine_seconds(blow_sweep(400, 200, seed=9), client, tmp / "warm")
            s = engine_seconds(EmptyChunks(args.empty), client, tmp / "empty") / args.empty
            print(f"LocalCluster start {t_start:.2f} s; engine cost per chunk s = "
                  f"{s * 1e3:.2f} ms ({args.empty} empty chunks, 1 worker)", flush=True)
            times[1].append(engine_seconds(spec, client, tmp / "w1"))
        for k in range(args.repeat):
            with dask_client(workers=2) as client:
                engine_seconds(blow_sweep(400, 200, seed=9), client, tmp / "warm")
                times[2].append(engine_seconds(spec, client, tmp / "w2"))
                if k == args.repeat - 1 and args.million:
                    big = blow_sweep(args.million, args.big_chunk, seed=2)
                    t_big = engine_seconds(big, client, tmp / "big")
            if k < args.repeat - 1:
                with dask_client(workers=1) as client:
                    engine_seconds(blow_sweep(400, 200, seed=9), client, tmp / "warm")
                    times[1].append(engine_seconds(spec, client, tmp / "w1"))
        t1, t2 = min(times[1]), min(times[2])
        for w, ts in times.items():
            print(f"{w} worker(s): {args.cases} cases in chunks of {args.chunk}: "
                  + ", ".join(f"{t:.2f} s" for t in ts)
                  + f"; best {args.cases / min(ts):,.0f} cases/s, "
                  f"{args.cases / min(ts) / w:,.0f} cases/s per worker", flush=True)
        c = t1 / args.cases
        speedup = t1 / t2
        print(f"c = {c * 1e6:.1f} us per case per worker (1 worker; in-process {c0 * 1e6:.1f} "
              f"us: engine overhead {100 * (c / c0 - 1):+.1f} %)")
        print(f"2 workers against 1: speed-up {speedup:.2f} (target >= 1.6: "
              f"{'met' if speedup >= 1.6 else 'NOT met'}), parallel efficiency "
              f"{100 * speedup / 2:.0f} %", flush=True)
        if args.million:
            print(f"{args.million:,} single blows on 2 workers, chunks of {args.big_chunk}: "
                  f"{t_big:.1f} s ({args.million / t_big:,.0f} cases/s, "
                  f"{2 * t_big / args.million * 1e6:.1f} us per case per worker); model "
                  f"predicts {_projected(args.million, 2, args.big_chunk, c, s, 0.0):.1f} s",
                  flush=True)
        _projection(c, s, t_start, args.big_chunk)
    return 0


def _projected(n: int, w: int, b: int, c: float, s: float, t_start: float) -> float:
    return t_start + (n * c + math.ceil(n / b) * s) / w


def _projection(c: float, s: float, t_start: float, b: int) -> None:
    print(f"projection T(N, W) = t_start + (N c + ceil(N/B) s) / W with c = {c * 1e6:.1f} us, "
          f"s = {s * 1e3:.2f} ms, t_start = {t_start:.1f} s (this machine's), B = {b}; "
          f"scheduler-bound beyond W_max = B c / s = {b * c / s:,.0f} workers:")
    for n in (10 ** 6, 10 ** 8):
        cells = ", ".join(f"W={w}: {_human(_projected(n, w, b, c, s, t_start))}"
                          for w in (2, 16, 64, 256, 1024) if w <= b * c / s)
        print(f"  N = {n:.0e}: {cells}")


def _human(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else (f"{seconds / 60:.1f} min" if seconds < 7200
                                                     else f"{seconds / 3600:.1f} h")


if __name__ == "__main__":
    raise SystemExit(main())
