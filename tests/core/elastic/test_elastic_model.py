"""The elastic model's interface: built effects, grid checks, stepping, sections, state."""
from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from elastic_helpers import elastic

from pipeplug import ParameterError, jit, state_from_bytes, state_to_bytes


@pytest.mark.parametrize("changes, plug_cells, kernel", [
    (dict(tau2=0.0), 0, "run_pipe"),
    (dict(L2=0.0, tau1=1e4), 0, "run_pipe_soil"),
    (dict(L2=0.3), 30, "run_pipe_plug"),
    (dict(tau1=1e4), 100, "run_pipe_plug_soil"),
])
def test_only_the_called_for_effects_are_built(changes, plug_cells, kernel):
    model = elastic(changes, dx=0.01)
    assert model.kernel_name == kernel
    assert model.v2.size == plug_cells and model.v1.size == 100
    if not plug_cells:
        model.advance(23000.0, 1e-3)
        out = model.outputs()
        assert out.v_plug == out.u_plug == out.F_inner == 0.0 and out.plug_mode == 0


def test_contact_growth_is_a_variant_only_with_soil_friction():
    assert elastic(dict(tau1=1e4), growth=True).kernel_name == "run_pipe_plug_soil_growth"
    assert elastic(dict(tau1=0.0), growth=True).kernel_name == "run_pipe_plug"


@pytest.mark.parametrize("changes", [dict(dx=0.03), dict(dx=0.01, L2=0.305),
                                     dict(dx=0.01, L1=1.005, L2=0.5)])
def test_lengths_must_be_whole_multiples_of_dx(changes):
    with pytest.raises(ParameterError) as info:
        elastic(changes)
    assert info.value.name == "dx" and "multiples of dx" in str(info.value)


def test_plug_length_is_free_when_the_plug_is_not_simulated():
    assert elastic(dx=0.01, L2=0.305, tau2=0.0).v2.size == 0
    assert elastic(dx=0.1, L1=0.3, L2=0.3, x_monitor=0.1).v1.size == 3  # 0.3/0.1 = 2.9999999999999996


def test_internal_steps_are_the_points_of_one_grid_of_times():
    """Every internal step is h_max long; a communication step takes the grid points it
    passes (within 1e-6 h_max of its end counts) and holds the load's impulse beyond them."""
    model = elastic(dx=0.01, tau2=0.0)
    h_max = 0.01 / model.params.c1
    assert model.grid.h_max == pytest.approx(h_max, rel=1e-15)
    h = model.clock.h
    for step, n in ((3 * h, 3), (3 * h * (1 + 1e-12), 3), (3 * h * (1 - 1e-9), 3),
                    (3.5 * h, 3), (1e-9, 0)):
        assert model.steps_for(step) == n
    model.advance(1000.0, 2.5 * h)
    assert model.clock.k == 2 and model.clock.pending == pytest.approx(500.0 * h, rel=1e-12)
    at_point = model.outputs()
    model.advance(-3000.0, 0.25 * h)                     # still before grid point 3
    assert model.outputs() == at_point                   # the outputs of grid point 2
    assert model.clock.pending == pytest.approx(-250.0 * h, rel=1e-12)
    model.advance(0.0, 0.25 * h)                         # reaches grid point 3
    assert model.clock.k == 3 and model.clock.pending == 0.0
    p = model.params
    momentum = p.rho1 * p.S1 * p.dx * model.v1.sum()
    assert momentum == pytest.approx(1750.0 * h, rel=1e-12)   # 1000 * 2.5 h - 3000 * 0.25 h
    slow_plug = elastic(dx=0.01, E2=1e12)  # the plug is now the faster rod
    assert slow_plug.grid.h_max == pytest.approx(0.01 / slow_plug.params.c2, rel=1e-15)


def test_a_step_of_too_many_internal_steps_is_refused_unless_at_rest():
    model = elastic(dx=0.01, max_internal_steps=1000.0)
    h = model.clock.h
    model.advance(0.0, 5000 * h)                          # at rest: no internal steps
    model.advance(23000.0, 1000 * h)
    with pytest.raises(ParameterError) as info:
        model.advance(0.0, 1001 * h)
    assert info.value.name == "communicationStepSize" and "max_internal_steps" in str(info.value)


@pytest.mark.parametrize("x", [0.0, 0.004, 0.25, 0.5, 0.6049, 0.8, 0.995, 1.0])
def test_sections_follow_the_contract(x):
    """Linear interpolation between the nodes x = j dx (the head's cell at x = 0, the mean of
    the two cells at each face, the last cell at the far end), the nearest section beyond them;
    the plug's section coupled to x, or its nearest one; modes at the cell containing x."""
    model = elastic(dx=0.01, L2=0.4, tau1=1e4, x_monitor=x)
    model.advance(23000.0, 0.002)
    model.advance(-9000.0, 0.0003)
    p, out = model.params, model.outputs()

    def nodes(v):
        return np.concatenate((v[:1], 0.5 * (v[:-1] + v[1:]), v[-1:]))

    pipe_nodes = np.arange(101) * p.dx
    plug_nodes = p.L1 - p.L2 + np.arange(41) * p.dx
    np.testing.assert_allclose(out.v_pipe, np.interp(x, pipe_nodes, nodes(model.v1)),
                               rtol=1e-12)
    np.testing.assert_allclose(out.v_plug, np.interp(x, plug_nodes, nodes(model.v2)),
                               rtol=1e-12)
    cell = min(int(x / p.dx + 1e-9), 99)
    assert out.pipe_mode == np.sign(model.v1[cell])
    k = min(max(cell - 60, 0), 39)
    assert out.plug_mode == np.sign(model.v1[60 + k] - model.v2[k])


def _run(model, loads, h):
    for q in loads:
        model.advance(q, h)
    return model.outputs(), {k: v.copy() for k, v in model.get_state().items()
                             if isinstance(v, np.ndarray)}


def test_restoring_a_state_twice_continues_bit_identically():
    model = elastic(dx=0.02, tau1=3e4, tau2=2e4, L2=0.6, x_monitor=0.7, growth=True)
    h = 13 * model.grid.h_max
    _run(model, [23000.0] * 40, h)
    saved = state_from_bytes(state_to_bytes(model.get_state()))
    first = _run(model, [23000.0] * 10 + [-4000.0] * 30, h)
    model.set_state(saved)
    model.set_state(saved)  # restoring twice, and the saved copy must stay untouched
    second = _run(model, [23000.0] * 10 + [-4000.0] * 30, h)
    assert first[0] == second[0]
    for name, array in first[1].items():
        assert np.array_equal(array, second[1][name])
    with pytest.raises(ValueError):
        elastic(dx=0.05).set_state(saved)


def test_a_state_inside_a_mixed_impulse_holds_finite_numbers_and_continues():
    """A load switched between grid points leaves an impulse of two forces pending: its state
    (which an FMU refuses when it holds a non-finite number) is finite, and a model restored
    to it continues as the original does."""
    model = elastic(dx=0.05, tau1=3e4)
    h = model.grid.h_max
    model.advance_to(23000.0, 10.4 * h, 0.0)
    model.advance_to(-5000.0, 10.7 * h)          # the pending impulse: two forces
    saved = state_from_bytes(state_to_bytes(model.get_state()))
    assert all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in saved.values())
    model.advance_to(0.0, 30 * h)
    after = model.outputs()
    other = elastic(dx=0.05, tau1=3e4)
    other.set_state(saved)
    other.advance_to(0.0, 30 * h)
    assert other.outputs() == after


_PURE_PROBE = r"""
import json, sys
from pipeplug import build_model, jit
model = build_model(json.loads(sys.argv[1]), {"elastic": True, "contact_growth": True})
h = 3 * model.grid.h_max
for i in range(300):
    model.advance(23000.0 if i % 50 < 20 else -2000.0, h)
state = model.get_state()
print(json.dumps({"jit": jit.enabled(), "vectorised": model.vectorised,
                  "numba_imported": "numba" in sys.modules,
                  **{k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in state.items()}}))
"""


def test_path_without_numba_gives_the_compiled_results():
    """Without numba (PIPEPLUG_NO_JIT=1, in a fresh process, which then never imports numba)
    the model steps with whole-array numpy operations and gives the numbers of this process's
    path (compiled when numba is installed), bit for bit."""
    params = dict(tau1=3e4, tau2=2e4, L2=0.6, dx=0.05, x_monitor=0.3)
    env = dict(os.environ, PIPEPLUG_NO_JIT="1")
    done = subprocess.run([sys.executable, "-c", _PURE_PROBE, json.dumps(params)], env=env,
                          check=True, capture_output=True, text=True)
    other = json.loads(done.stdout)
    assert other.pop("jit") is False and other.pop("vectorised") is True
    assert other.pop("numba_imported") is False
    assert jit.enabled() == (importlib.util.find_spec("numba") is not None)
    model = elastic(params, growth=True)
    h = 3 * model.grid.h_max
    for i in range(300):
        model.advance(23000.0 if i % 50 < 20 else -2000.0, h)
    for name, value in model.get_state().items():
        assert np.array_equal(np.asarray(other[name]), np.asarray(value)), name
