"""Throughput of the core's batch API, measured by the cost study: single blows, cases per
second on one core (``benchmarks/batch.py`` runs it alone).

A case is a parameter set plus one rectangular blow from rest (23 kN for 50 ms), advanced until
all is at rest, returning the final displacements and works: :func:`pipeplug.batch.blows`,
model build included, no dense output. Parameters are drawn at random (fixed seed) over the
paper's range: tau1 and tau2 up to 1.2 tau* (tau* = Q0/(P1 L1), the blow's own limit), a plug
length up to L1 (a tenth of the cases without a plug), plug densities from 500 to 5000 kg/m3;
half of the cases are model II. The process runs one thread, so the rate is per core; the best
of ``repeat`` runs is reported (the least disturbed by the rest of the machine), beside the same
cases through ``build_model`` and ``advance`` one by one (plain Python) on a sample.
"""
from __future__ import annotations

import time

import numpy as np

import pipeplug
from pipeplug import jit
from pipeplug.batch import blows
from pipeplug_harness.paper import Q0, T0

#: target rate, cases per second per core
TARGET = 20_000


def random_cases(n: int, seed: int = 1) -> dict:
    """``n`` parameter sets over the paper's range (see the module docstring)."""
    rng = np.random.default_rng(seed)
    base = pipeplug.Params()
    tau_star = Q0 / (base.P1 * base.L1)
    L2 = rng.uniform(0.0, 1.0, n) * base.L1
    L2[rng.random(n) < 0.1] = 0.0
    return {"tau1": rng.uniform(0.0, 1.2 * tau_star, n),
            "tau2": rng.uniform(0.0, 1.2 * tau_star, n), "L2": L2,
            "rho2": rng.uniform(500.0, 5000.0, n)}


def run_batch(params: dict, growth: np.ndarray) -> dict:
    """Both models' cases through the batch API (two calls, one per model)."""
    parts = [blows({k: v[mask] for k, v in params.items()}, Q0, T0, bool(g))
             for g, mask in ((False, ~growth), (True, growth))]
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def one_by_one(params: dict, growth: np.ndarray, count: int) -> float:
    """Seconds per case through build_model + advance (plain Python), first ``count`` cases."""
    start = time.perf_counter()
    for i in range(count):
        model = pipeplug.build_model({k: v[i] for k, v in params.items()},
                                     {"contact_growth": bool(growth[i])}, compiled=False)
        model.advance(Q0, T0)
        while not model.at_rest():
            model.advance(0.0, T0)
    return (time.perf_counter() - start) / count


def throughput(n: int = 20_000, repeat: int = 5, seed: int = 1) -> dict:
    """Best cases per second of the batch API over ``repeat`` runs of ``n`` cases.

    Returns
    -------
    dict
        ``cases``, ``rate`` [1/s], ``compiled`` (numba used), ``rate_python`` [1/s] (the batch
        API as plain Python), ``rate_one_by_one`` [1/s] (build_model + advance, plain Python),
        ``at_rest`` (share of cases that came to rest).
    """
    params = random_cases(n, seed)
    growth = np.arange(n) % 2 == 1
    run_batch({k: v[:10] for k, v in params.items()}, growth[:10])     # compile or load
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        out = run_batch(params, growth)
        best = min(best, time.perf_counter() - start)
    sample = min(n, 500)
    start = time.perf_counter()
    for g in (False, True):
        blows({k: v[:sample][growth[:sample] == g] for k, v in params.items()}, Q0, T0, g,
              compiled=False)
    python = (time.perf_counter() - start) / sample
    return {"cases": n, "rate": n / best, "compiled": jit.enabled(),
            "rate_python": 1.0 / python, "rate_one_by_one": 1.0 / one_by_one(params, growth, 200),
            "at_rest": float(np.mean(np.isfinite(out["t_rest"])))}
