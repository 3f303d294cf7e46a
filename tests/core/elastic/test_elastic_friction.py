"""Nodal Coulomb friction of the elastic model: sticking, no reversal, exact deceleration.

The projection itself is tested in tests/core/contact/test_coulomb.py."""
from __future__ import annotations

import numpy as np
from elastic_helpers import elastic


def _sliding_model(**changes):
    """A model whose cells all start with velocity v0 (set through set_state)."""
    model = elastic(dx=0.05, **changes)
    state = model.get_state()
    state["v1"][:] = 2.0
    model.set_state(state)
    return model


def test_sliding_pipe_decelerates_uniformly_and_stays_stopped():
    """Uniform velocity v0 with soil friction only: every cell follows v0 - a t, a =
    P1 tau1 / (rho1 S1), until it stops at t = v0/a; then it stays exactly at rest."""
    model = _sliding_model(tau1=2e4, tau2=0.0)
    p = model.params
    a = p.P1 * p.tau1 / (p.rho1 * p.S1)
    h = 50 * model.grid.h_max
    for _ in range(round(1.5 * 2.0 / a / h)):
        model.advance(0.0, h)
        expected = max(2.0 - a * model.time, 0.0)
        np.testing.assert_allclose(model.v1, expected, rtol=0, atol=1e-9)
        assert (model.v1 >= 0.0).all() and np.abs(model.N1).max() <= 1e-6
    assert (model.v1 == 0.0).all()
    out = model.outputs()
    assert out.pipe_mode == 0 and out.F_outer == 0.0


def test_sliding_plug_drags_pipe_to_the_momentum_average():
    """Plug at v0, pipe at rest, no soil: the relative velocity decreases without reversing
    and both end at M2 v0 / (M1 + M2), exactly stuck."""
    model = elastic(dx=0.05, tau1=0.0, tau2=3e4)
    state = model.get_state()
    state["v2"][:] = 2.0
    model.set_state(state)
    p = model.params
    h = 50 * model.grid.h_max
    for _ in range(400):
        model.advance(0.0, h)
        assert (model.v2 - model.v1 >= 0.0).all()
    common = p.M2 * 2.0 / (p.M1 + p.M2)
    np.testing.assert_allclose(model.v1, common, rtol=1e-12)
    assert (model.v1 == model.v2).all() and model.outputs().plug_mode == 0


def test_load_within_one_cells_limit_moves_nothing():
    model = elastic(dx=0.01, tau1=2e4, tau2=0.0)
    q = 0.9 * model.params.P1 * model.params.tau1 * model.params.dx
    for _ in range(50):
        model.advance(q, 7 * model.grid.h_max)
    assert (model.v1 == 0.0).all() and (model.N1[1:] == 0.0).all() and (model.u1 == 0.0).all()
    out = model.outputs()
    assert out.F_outer == -q and out.pipe_mode == 0 and out.W_input == 0.0


def test_load_below_the_pipe_limit_stays_local_and_comes_to_rest():
    """A step load Q < F1/2: the front's velocity Q/Z - P1 tau1 t/(2 rho1 S1) (characteristics)
    dies at x = 2 Q/(P1 tau1); beyond it nothing ever moves. Later the pipe is at rest and the
    soil holds Q statically."""
    model = elastic(dx=0.01, tau1=2e4, tau2=0.0, x_monitor=1.0)
    p = model.params
    q = 0.3 * p.P1 * p.tau1 * p.L1
    reach = 2.0 * q / (p.P1 * p.tau1)
    far = (np.arange(model.grid.n1) * p.dx) >= reach + p.dx  # cells starting beyond the reach
    moved = np.zeros(model.grid.n1, bool)
    for _ in range(2000):
        model.advance(q, 5 * model.grid.h_max)
        moved |= model.v1 != 0.0
    assert moved.any() and not moved[far].any()
    assert (model.v1 == 0.0).all()
    out = model.outputs()
    np.testing.assert_allclose(out.F_outer, -q, rtol=1e-12)
    assert out.u_pipe == 0.0 and out.pipe_mode == 0
