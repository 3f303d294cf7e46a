"""The single-case API on the cost study's paper cases: ``build_model``, then ``sample`` at
2,000 times.

Usage (from the repository root)::

    python -m benchmarks.single_case [--rounds 200] [--batch 20]

For each case of ``pipeplug cost`` (model I domains I-IV, tau1 = 0, one model II case; 2,000
samples every 0.2 ms), in one run:

- ``api``: ``build_model(params, options)`` then ``model.sample(loads, times, names)`` (the
  four kinematic outputs), compiled (numba);
- ``sample``: ``model.sample`` alone on a model built beforehand (the kernel and the call
  around it, the build left out);
- ``plain``: the ``api`` run as plain Python (``compiled=False``).

A time is the best over ``--rounds`` rounds of the mean of ``--batch`` calls (a round that the
busy machine interrupts is not the best one). Prints the times per case, the ratios api/goal
(the compiled path's goal: at most 10 us per case), api/sample (what the build adds) and
plain/api, and the median over the cases.
"""
from __future__ import annotations

import argparse
import statistics
import time

import pipeplug
from pipeplug_harness.cost.cases import default_cases
from pipeplug_harness.cost.report import API_GOAL

#: the outputs sampled (those an ODE solver returns: the study's)
NAMES = ("v_pipe", "v_plug", "u_pipe", "u_plug")
#: the single-case API's goal on the compiled path, s per case (the cost study's)
TARGET = API_GOAL


def best_mean(run, rounds: int, batch: int) -> float:
    """Best over ``rounds`` of the mean time of ``batch`` calls of ``run(i)``, i = 0..batch-1
    [s]."""
    best = float("inf")
    for _ in range(rounds):
        start = time.perf_counter()
        for i in range(batch):
            run(i)
        best = min(best, (time.perf_counter() - start) / batch)
    return best


def measure(bench, rounds: int, batch: int) -> dict:
    """The three times of one case [s]."""
    params, options = bench.params, dict(bench.options, solver="exact")
    loads, times = bench.loads, bench.times

    def api(_, compiled=True):
        model = pipeplug.build_model(params, options, compiled=compiled)
        return model.sample(loads, times, NAMES)

    def sample(i):
        return built[i].sample(loads, times, NAMES)

    api(0)
    api(0, compiled=False)
    out = {"api": best_mean(api, rounds, batch)}
    best = float("inf")
    for _ in range(rounds):               # a fresh model per call: the builds are not timed
        built = [pipeplug.build_model(params, options) for _ in range(batch)]
        best = min(best, best_mean(sample, 1, batch))
    out["sample"] = best
    out["plain"] = best_mean(lambda i: api(i, compiled=False), max(rounds // 10, 1), batch)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=200, help="rounds per time (best kept)")
    parser.add_argument("--batch", type=int, default=20, help="calls per round (mean taken)")
    args = parser.parse_args(argv)
    rows = {b.name: measure(b, args.rounds, args.batch) for b in default_cases()}
    compiled = pipeplug.build_model({}).compiled
    print(f"single-case API, build_model + sample at 2,000 times, "
          f"{'compiled (numba)' if compiled else 'plain Python (numba not available)'}; "
          f"best of {args.rounds} rounds of {args.batch} calls")
    print(f"{'case':10s} {'api [us]':>9s} {'api/goal':>9s} {'sample [us]':>12s} "
          f"{'api/sample':>11s} {'plain [us]':>11s} {'plain/api':>10s}")
    rows["median"] = {k: statistics.median(r[k] for r in rows.values()) for k in ("api",
                                                                                "sample",
                                                                                "plain")}
    for name, r in rows.items():
        print(f"{name:10s} {1e6 * r['api']:9.1f} {r['api'] / TARGET:9.2f} "
              f"{1e6 * r['sample']:12.1f} {r['api'] / r['sample']:11.2f} "
              f"{1e6 * r['plain']:11.1f} {r['plain'] / r['api']:10.1f}")
    worst = max(r["api"] for name, r in rows.items() if name != "median")
    print(f"slowest case through the API: {1e6 * worst:.1f} us, {worst / TARGET:.2f} times the "
          f"goal of {1e6 * TARGET:g} us")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
