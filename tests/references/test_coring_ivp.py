"""The coring reference (pipeplug_references.coring_ivp) against its own conservation laws."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug_references.coring_ivp import simulate_coring

PIPE = dict(L1=2.0, L2=0.0, R1=0.1, h1=0.01, rho1=7800.0, rho2=1800.0, tau2=5e3)


@pytest.mark.parametrize("j_shaft", [0.0, 0.5])
def test_momentum_is_the_impulse_and_the_energy_balances(j_shaft):
    force, duration = 2e5, 4e-3
    times = np.linspace(0.0005, 0.3, 60)
    out = simulate_coring(dict(PIPE, J_shaft=j_shaft), force, duration, times)
    S1 = math.pi * (0.11 ** 2 - 0.1 ** 2)
    M1, rho_s = 7800.0 * S1 * 2.0, 1800.0 * math.pi * 0.1 ** 2
    momentum = M1 * out["v_pipe"] + rho_s * out["L2_now"] * out["v_plug"]
    np.testing.assert_allclose(momentum, force * np.minimum(times, duration), rtol=1e-8)
    kinetic = 0.5 * M1 * out["v_pipe"] ** 2 + 0.5 * rho_s * out["L2_now"] * out["v_plug"] ** 2
    balance = (out["W_input"] - kinetic - out["W_friction_inner"] - out["W_accretion"]
               - out["W_damping"])
    assert np.max(np.abs(balance)) <= 1e-7 * np.max(out["W_input"])
    # coring, then stuck together: the length grows by the relative advance, then stays
    assert out["L2_now"][-1] == out["L2_now"][-2] > 0.1
    assert out["v_pipe"][-1] == out["v_plug"][-1]
    assert np.all(np.diff(out["W_accretion"]) >= 0.0) and out["W_accretion"][-1] > 0.0
    assert np.all(np.diff(out["W_damping"]) >= 0.0)
    assert (out["W_damping"][-1] > 0.05 * out["W_input"][-1]) == (j_shaft > 0.0)
