"""Energy and momentum balances of the elastic scheme (exact discrete identities)."""
from __future__ import annotations

import numpy as np
import pytest
from elastic_helpers import elastic, energy_residual

from pipeplug.elastic.kernels import M1, M2

# Every kernel variant: (parameter changes, contact growth, expected kernel).
VARIANTS = [
    (dict(tau1=0.0, tau2=0.0), False, "run_pipe"),
    (dict(tau1=2e4, tau2=0.0), False, "run_pipe_soil"),
    (dict(tau1=2e4, tau2=0.0), True, "run_pipe_soil_growth"),
    (dict(tau1=0.0, tau2=1e4, L2=0.6), False, "run_pipe_plug"),
    (dict(tau1=2e4, tau2=1e4, L2=0.6), False, "run_pipe_plug_soil"),
    (dict(tau1=7e4, tau2=3.5e4), True, "run_pipe_plug_soil_growth"),
]


def _blow_loads(h, t_end=0.06):
    """Blows of 5 ms every 20 ms, each followed by a 3 ms pull-back, on steps h [s]."""
    phase = (np.arange(round(t_end / h)) * h) % 0.02
    return np.where(phase < 0.005, 23000.0, np.where(phase < 0.008, -3000.0, 0.0))


def _blows(model, h):
    """Advance through the blows; yields the outputs after each step."""
    for q in _blow_loads(h):
        model.advance(float(q), h)
        yield model.outputs()


@pytest.mark.parametrize("changes, growth, kernel", VARIANTS)
def test_work_equals_kinetic_plus_elastic_plus_friction(changes, growth, kernel):
    """W_input = kinetic + elastic + W_friction + reversing, to round-off (equal steps).

    Reversing work (<= 0) is the friction work of steps that reverse a node's relative
    velocity; it is kept out of W_friction, which must never decrease.
    """
    model = elastic(changes, growth, dx=0.02)
    assert model.kernel_name == kernel
    previous = 0.0
    for out in _blows(model, 10 * model.grid.h_max):
        assert out.W_friction >= previous
        previous = out.W_friction
    _, _, reversing = model.energies()
    assert out.W_input > 0.0
    assert abs(energy_residual(model)) <= 1e-10 * out.W_input
    assert -1e-3 * out.W_input <= reversing <= 0.0


def test_momentum_of_pipe_and_plug_equals_impulse_of_q():
    """Without soil friction the plug forces are internal: sum m v = integral of Q, exactly."""
    model = elastic(dx=0.02, tau2=3e4, L2=0.5)
    h = 7 * model.grid.h_max
    for _ in _blows(model, h):
        pass
    c = model.grid.coef
    momentum = c[M1] * model.v1.sum() + c[M2] * model.v2.sum()  # cell masses
    np.testing.assert_allclose(momentum, h * _blow_loads(h).sum(), rtol=1e-11)
