"""The exact solver's two paths: the same source run compiled (numba) and as plain Python.

Random cases (both models, every domain, loads of both signs and at friction limits, random
communication grids) give the same outputs on both paths within 1e-15 of each output's scale
(its largest magnitude over the run), stepped and through dense output; states move between
the paths.
"""
from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from pipeplug import OUTPUT_NAMES, Params, build_model, jit

CASES = 40


def _random_case(rng):
    """Parameters, options, load segments [(duration s, Q N)] and a communication grid [s]."""
    p = Params()
    tau_star = 60e3 / (p.P1 * p.L1)
    params = {"tau1": float(rng.choice([0.0, rng.uniform(0.0, 1.3 * tau_star)])),
              "tau2": float(rng.choice([0.0, rng.uniform(0.0, 2e5)])),
              "L2": float(rng.choice([0.0, rng.uniform(0.0, 1.0), 1.0])),
              "rho2": float(10.0 ** rng.uniform(1.0, 5.0))}
    limits = Params(**params)
    segments = []
    for _ in range(int(rng.integers(1, 6))):
        duration = float(10.0 ** rng.uniform(-5.0, np.log10(0.2)))
        kind = rng.random()
        if kind < 0.15 and limits.F1 > 0.0:
            q = float(rng.choice([1.0, -1.0]) * limits.F1 * rng.choice([1.0, 0.5]))
        elif kind < 0.25:
            q = float(rng.choice([1.0, -1.0]) * (limits.F1 + limits.F2))
        else:
            q = float(rng.uniform(-60e3, 60e3))
        segments.append((duration, q))
    edges = np.cumsum([0.0] + [d for d, _ in segments])
    t_end = edges[-1] + float(rng.uniform(0.0, 0.3))
    grid = np.union1d(np.sort(rng.uniform(0.0, t_end, int(rng.integers(3, 300)))),
                      np.r_[0.0, t_end, edges])
    return params, {"contact_growth": bool(rng.random() < 0.6)}, segments, grid[grid <= t_end]


def _load(segments, t):
    edges = np.cumsum([0.0] + [d for d, _ in segments])
    k = int(np.searchsorted(edges, t, side="right")) - 1
    return segments[k][1] if k < len(segments) else 0.0


def _stepped(params, options, segments, grid, compiled):
    model = build_model(params, options, compiled=compiled)
    rows = []
    for a, b in zip(grid[:-1], grid[1:]):
        model.advance_to(_load(segments, a), b)
        rows.append(model.outputs())
    return np.array(rows, dtype=float), model


def _dense(params, options, segments, grid, compiled):
    """Dense output at the grid points, one sample call per load segment."""
    model = build_model(params, options, compiled=compiled)
    columns, start = [], 0
    while start < len(grid) - 1:
        q = _load(segments, grid[start])
        stop = start + 1
        while stop < len(grid) - 1 and _load(segments, grid[stop]) == q:
            stop += 1
        out = model.sample(q, grid[start + 1:stop + 1])
        columns.append(np.column_stack([out[name] for name in OUTPUT_NAMES]))
        start = stop
    return np.concatenate(columns)


def _assert_close(a, b):
    scale = np.maximum(np.max(np.abs(a), axis=0), np.max(np.abs(b), axis=0))
    assert np.all(np.abs(a - b) <= 1e-15 * scale), np.max(np.abs(a - b) / (scale + 1e-300))


def test_the_compiled_path_is_taken_when_numba_is_enabled():
    """With numba (the tests' 'fast' extra) the paths below differ; without it, or with
    PIPEPLUG_NO_JIT=1, both are plain Python."""
    assert build_model({}, {}).compiled == jit.enabled()
    assert not build_model({}, {}, compiled=False).compiled


@pytest.mark.parametrize("seed", range(CASES))
def test_compiled_and_python_paths_agree(seed):
    case = _random_case(np.random.default_rng(seed))
    runs = [_stepped(*case, compiled) for compiled in (False, True)]
    stepped = [rows for rows, _ in runs]
    _assert_close(*stepped)
    assert runs[0][1].modes() == runs[1][1].modes()
    dense = [_dense(*case, compiled) for compiled in (False, True)]
    _assert_close(*dense)
    _assert_close(dense[0], stepped[0])      # dense output is stepping, sampled


@pytest.mark.parametrize("seed", range(0, CASES, 4))
def test_a_state_moves_between_the_paths(seed):
    """A state saved on one path and restored on the other continues bit for bit."""
    params, options, segments, grid = _random_case(np.random.default_rng(seed))
    half = len(grid) // 2
    _, python = _stepped(params, options, segments, grid[:half + 1], False)
    _, compiled = _stepped(params, options, segments, grid[:half + 1], True)
    state, other = python.get_state(), compiled.get_state()
    assert np.array_equal(state.pop("modes"), other.pop("modes")) and state == other
    state = python.get_state()
    compiled.set_state(state)
    python.set_state(state)
    for a, b in zip(grid[half:-1], grid[half + 1:]):
        q = _load(segments, a)
        python.advance_to(q, b)
        compiled.advance_to(q, b)
        assert python.outputs() == compiled.outputs()
    assert python.modes() == compiled.modes()


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_modes_of_many_blows_are_logged_completely(compiled):
    """Twenty blows of the paper's domain I (23 kN for 50 ms from rest, tau1 = 20 kPa,
    tau2 = 10 kPa) each go through its four modes: 80 pieces of modes, more than the solver
    logs between two takings, stepped and through dense output alike."""
    expected = ((1, 1), (1, -1), (0, -1), (0, 0)) * 20
    period, edges = 0.5, np.arange(20) * 0.5
    grid = np.union1d(np.linspace(0.0, 20 * period, 4001)[1:], np.r_[edges, edges + 0.05][1:])
    loads = np.where((grid - 1e-12) % period < 0.05, 23e3, 0.0)     # over the step ending there
    stepped = build_model({"tau1": 2e4, "tau2": 1e4}, compiled=compiled)
    for q, t in zip(loads, grid):
        stepped.advance_to(q, t)
    dense = build_model({"tau1": 2e4, "tau2": 1e4}, compiled=compiled)
    out = dense.sample(loads, grid)
    assert stepped.modes() == expected and dense.modes() == expected
    assert out["u_pipe"][-1] == stepped.outputs().u_pipe


_PLAIN_RUNS = """
import sys
import pipeplug, pipeplug.batch
for options in ({}, {"contact_growth": True}, {"solver": "fd"}):
    model = pipeplug.build_model({"tau1": 2e4}, options, compiled=False)
    model.advance(23e3, 0.05)
    model.sample(0.0, [0.1, 0.2])
pipeplug.batch.blows({"tau1": [2e4, 3e4]}, compiled=False)
print("numba" in sys.modules)
pipeplug.build_model({}, {})
print("numba" in sys.modules)
"""


def test_plain_python_runs_never_import_numba():
    """Rigid models and batches on the plain path leave numba unimported (a fresh process); the
    compiled path imports it when the model is built."""
    env = {k: v for k, v in os.environ.items() if k != jit.NO_JIT_ENV}
    proc = subprocess.run([sys.executable, "-c", _PLAIN_RUNS], capture_output=True, text=True,
                          timeout=120, check=True, env=env)
    assert proc.stdout.split() == ["False", "True"]


def _run_ends_by_definition(loads):
    """The ends of the runs of equal loads, one load at a time (the definition)."""
    ends, lo = [], 0
    while lo < len(loads):
        hi = lo + 1
        while hi < len(loads) and loads[hi] == loads[lo]:
            hi += 1
        ends.append(hi)
        lo = hi
    return ends


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_runs_of_equal_loads_end_where_a_load_differs(compiled):
    """The dense output splits the loads into runs of equal values, comparing blocks of them
    at once: runs of every length about the block's (128), loads equal with other bits (-0.0 and
    0.0) and a nan end where the definition ends them."""
    from pipeplug.rigid import stepping
    run_end = jit.compiled(stepping._run_end_loop) if compiled else stepping._run_end
    rng = np.random.default_rng(7)
    for _ in range(200):
        values = rng.choice([0.0, -0.0, 23e3, -23e3, np.nan, 1.0], size=int(rng.integers(1, 8)))
        loads = np.repeat(values, rng.integers(1, 400, size=values.size))
        ends, lo = [], 0
        while lo < len(loads):
            lo = int(run_end(loads, lo, float(loads[lo])))
            ends.append(lo)
        assert ends == _run_ends_by_definition(loads)


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_dense_output_takes_any_array_of_times_and_loads_or_refuses_it(compiled):
    """The compiled path calls its kernel for one set of argument types, without numba's
    dispatch: times and loads of other kinds (a list, ints, a strided or read-only view,
    float32) give the values of the plain float64 arrays, and times of two dimensions are
    refused, never read as one."""
    times = np.linspace(1e-3, 0.1, 100)
    loads = np.where(times < 0.05, 23e3, 0.0)
    params = {"tau1": 2e4, "tau2": 1e4}
    expected = build_model(params, compiled=compiled).sample(loads, times)

    wide = np.zeros((2, 200))
    wide[0, ::2] = times
    frozen = times.copy()
    frozen.flags.writeable = False
    variants = [(list(loads), list(times)), (loads.astype(int), times),
                (loads, wide[0, ::2]), (loads, frozen), (loads.astype(np.float32), times)]
    for q, t in variants:
        out = build_model(params, compiled=compiled).sample(q, t)
        for name in OUTPUT_NAMES:
            np.testing.assert_array_equal(out[name], expected[name])
    with pytest.raises(ValueError, match="1-D"):
        build_model(params, compiled=compiled).sample(loads, times.reshape(2, 50))
