"""Benchmark: the cost of a scene follows the effects it enables.

Run ``python -m benchmarks.effects``. On the Fig. 7 scene (one 23 kN blow of
50 ms, 0.08 s simulated, dx = 1 cm, Courant 1, communication step 0.1 ms) it times, in one
run and in the core (no FMU overhead), the model each variant builds:

* full: elastic pipe and plug, plug friction and outer friction (tau1 = 20 kPa, tau2 = 10 kPa);
* elastic pipe alone: tau2 = 0 (no plug degrees of freedom) and tau1 = 0 (no outer friction);
* rigid: the same full scene with the exact rigid solver.

It prints each variant's wall time (best of several runs, after a warm-up that absorbs
compilation) and the ratios to the full scene (targets: pipe alone <= 0.7, rigid <= 0.05).
"""
from __future__ import annotations

import argparse
import time

from pipeplug import build_model

Q0, T0, T_END, STEP = 23000.0, 0.05, 0.08, 1e-4
FULL = {"tau1": 2e4, "tau2": 1e4}
VARIANTS = {
    "full elastic (plug + outer friction)": (FULL, {"elastic": True}),
    "elastic pipe alone (tau1 = tau2 = 0)": ({"tau1": 0.0, "tau2": 0.0}, {"elastic": True}),
    "rigid exact (full friction)": (FULL, {"solver": "exact"}),
}


def run_scene(params: dict, options: dict) -> float:
    """Build the model and drive it through the scene; returns the final pipe velocity [m/s]."""
    model = build_model(params, options)
    n_load, n_all = round(T0 / STEP), round(T_END / STEP)
    for i in range(n_all):
        model.advance(Q0 if i < n_load else 0.0, STEP)
        out = model.outputs()
    return out.v_pipe


def best_time(params: dict, options: dict, repeats: int) -> float:
    """Best wall time [s] of :func:`run_scene` over ``repeats`` runs (after one warm-up)."""
    run_scene(params, options)
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        run_scene(params, options)
        best = min(best, time.perf_counter() - start)
    return best


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per variant")
    args = parser.parse_args(argv)
    times = {name: best_time(p, o, args.repeat) for name, (p, o) in VARIANTS.items()}
    full = times[next(iter(VARIANTS))]
    print("| variant | wall time [ms] | ratio to full | target |")
    print("|---|---|---|---|")
    targets = ["", "<= 0.7", "<= 0.05"]
    for (name, t), target in zip(times.items(), targets):
        print(f"| {name} | {t * 1e3:.2f} | {t / full:.3f} | {target} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
