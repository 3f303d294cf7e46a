"""Runs of the core's own solvers for the ``cost`` study, and the timer.

The core is driven without the FMU: the exact solver through its dense output
(``model.sample``), the fd solver and the elastic model through ``advance``/``outputs`` at the
sample times (the sample step is their communication step).
"""
from __future__ import annotations

import time

import numpy as np

import pipeplug

from .cases import BenchCase, from_outputs

#: a timing stops repeating once it has spent this long, s (one run always happens)
TIME_BUDGET = 0.3
#: a timing repeats for at least this long, s (a run of microseconds is repeated over a window
#: long enough that a moment's load on the machine does not decide its best time)
MIN_TIME = 0.05


def best_time(run, repeats: int = 5, budget: float = TIME_BUDGET, min_time: float = MIN_TIME):
    """Best wall time of ``run()`` over at least `repeats` calls and `min_time` s of calls,
    stopping after `budget` s in total.

    Returns
    -------
    (object, float)
        The last call's result and the best time, s.
    """
    best, spent, count, result = float("inf"), 0.0, 0, None
    while count < max(1, repeats) or spent < min_time:
        start = time.perf_counter()
        result = run()
        elapsed = time.perf_counter() - start
        best, spent, count = min(best, elapsed), spent + elapsed, count + 1
        if spent > budget:
            break
    return result, best


#: the outputs the exact solver samples: the states an ODE solver returns
EXACT_OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug")


def exact_call(bench: BenchCase):
    """The exact solver's single-case API on `bench` as one call, timed as it is:
    ``build_model`` then ``sample`` at the sample times (the load of each sample interval given,
    Q0 up to t0), returning the core's columns (:data:`EXACT_OUTPUTS`).

    Its arguments are made here, before any call: the study times the API alone, not the
    making of a parameter mapping or the renaming of its outputs (a few microseconds, a third
    of the API's own time)."""
    params, options = bench.params, dict(bench.options, solver="exact")
    loads, times = bench.loads, bench.times

    def call() -> dict:
        return pipeplug.build_model(params, options).sample(loads, times, EXACT_OUTPUTS)

    return call


def run_exact(bench: BenchCase) -> dict:
    """Exact event-driven solver, dense output at the sample times, under the study's keys."""
    return from_outputs(exact_call(bench)())


def drive(model, bench: BenchCase, times: np.ndarray) -> dict:
    """Advance `model` through `times` (s) under the pulse, recording the outputs at each."""
    q0, t0 = bench.case.Q0, bench.case.t0
    v1, v2, u1, u2 = (np.empty(len(times)) for _ in range(4))
    previous = 0.0
    for i, t in enumerate(times.tolist()):
        model.advance(q0 if t <= t0 else 0.0, t - previous)   # the step ending at t0 is loaded
        previous = t
        out = model.outputs()
        v1[i], v2[i], u1[i], u2[i] = out.v_pipe, out.v_plug, out.u_pipe, out.u_plug
    return {"V1": v1, "V2": v2, "U1": u1, "U2": u2}


def run_fd(bench: BenchCase, dt: float) -> dict:
    """The paper's explicit scheme with internal steps <= `dt` (s), driven at the sample times."""
    model = pipeplug.build_model(dict(bench.params, dt=dt), dict(bench.options, solver="fd"))
    return drive(model, bench, bench.times)


def run_stepped(bench: BenchCase, solver: str, rate: int) -> dict:
    """A rigid solver driven at `rate` communication steps per second (fd: internal step = step)."""
    params = dict(bench.params, dt=1.0 / rate) if solver == "fd" else bench.params
    model = pipeplug.build_model(params, dict(bench.options, solver=solver))
    times = np.arange(1, round(bench.t_end * rate) + 1) / rate
    return drive(model, bench, times)


def run_elastic(bench: BenchCase, dx: float) -> dict:
    """Elastic model III on a grid of spacing `dx` (m), outputs at ``x_monitor``."""
    model = pipeplug.build_model(dict(bench.params, dx=dx), {"elastic": True})
    return drive(model, bench, bench.times)


def elastic_available(bench: BenchCase, dx: float) -> str:
    """Empty string when the elastic model builds for `bench`, else why not."""
    try:
        pipeplug.build_model(dict(bench.params, dx=dx), {"elastic": True})
    except (ImportError, pipeplug.ParameterError) as err:
        return f"{type(err).__name__}: {err}"
    return ""
