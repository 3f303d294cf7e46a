"""PipePlug.fmu's ram inputs: ``strikes`` (each increase seen at a communication point starts
one strike there) and ``v_strike``; checked against the ODE reference of model I with a ram
(``pipeplug_references.ram_ivp``, independent of the core), against the elastic core stepped
on its own, and under the calls hosts make (no ram, a rise by more than one, a saved state)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from fmu_helpers import run_scenario

from pipeplug_references.ram_ivp import simulate_ram

STEP = 1e-3
TIMES = [round(k * STEP, 12) for k in range(401)]
#: The contract's defaults of the parameters the reference takes (SI).
DEFAULTS = {"L1": 1.0, "L2": 1.0, "R1": 0.035, "h1": 0.003, "rho1": 7800.0, "rho2": 1800.0,
            "tau1": 0.0, "tau2": 1e4}
SOIL = {"tau1": 4e4}
RAM = {"ram_mass": 50.0, "cushion_stiffness": 2e7, "cushion_restitution": 0.8}
V1, V2 = 3.5, 2.0           # [m/s]


def _strikes(fmu_dir, params, schedule, times=TIMES, **kwargs) -> dict:
    return run_scenario("strikes", fmu_dir, params=params, times=times, schedule=schedule,
                        **kwargs)


def _columns(rows) -> dict:
    return {name: np.array([row[name] for row in rows]) for name in rows[0]}


def test_strikes_reach_model_one_as_the_reference_has_them(fmu_dir):
    """Strikes at 0 and 0.2 s (the second a rise from 1 to 3: one strike), 1 ms steps: every
    output within 1e-9 of its family's scale of the reference, every step fmi2OK."""
    got = _columns(_strikes(fmu_dir, dict(SOIL, **RAM),
                            {"0.0": [1, V1], "0.2": [3, V2]})["rows"])
    assert set(got["status"]) == {0}
    history = [(0.0, "strike", V1), (0.2, "strike", V2)]
    # The outputs at a strike's instant are those before it (it starts the next step); the
    # reference samples there after it: ask it for the float just before.
    times = np.array(TIMES[1:])
    times[times == 0.2] = np.nextafter(0.2, 0.0)
    ref = simulate_ram(dict(DEFAULTS, **SOIL), {"mass": 50.0, "k": 2e7, "e": 0.8}, history,
                       times)
    for family in (("v_pipe", "v_plug", "v_ram"), ("u_pipe", "u_plug"),
                   ("W_friction", "W_cushion", "E_kinetic", "W_ram")):
        scale = max(np.abs(ref[n]).max() for n in family)
        for name in family:
            assert np.abs(got[name] - ref[name]).max() <= 1e-9 * scale, name
    # Two strikes, not three: the ram brought 1/2 m (V1^2 + V2^2) less what it still had.
    assert got["W_ram"][-1] <= 0.5 * 50.0 * (V1 ** 2 + V2 ** 2)
    assert got["W_ram"][-1] > 0.5 * 50.0 * (V1 ** 2 + V2 ** 2) - 0.5 * 50.0 * V1 ** 2


def test_a_cushion_on_a_free_rigid_pipe_gives_the_half_sine(fmu_dir):
    """Model I, no friction, no plug: a ram of m through a cushion k on the pipe of mass M
    pushes it with F = v0 sqrt(k mu) sin(omega t) for t <= pi / omega (mu = m M / (m + M),
    omega = sqrt(k / mu)), then parts from it; M from the contract's section
    S1 = pi ((R1 + h1)^2 - R1^2) and the defaults."""
    m, k, v0 = 100.0, 1e6, 4.0
    M = 7800.0 * math.pi * ((0.035 + 0.003) ** 2 - 0.035 ** 2) * 1.0
    mu = m * M / (m + M)
    omega = math.sqrt(k / mu)
    times = [j * 1e-4 for j in range(301)]
    got = _columns(_strikes(fmu_dir, {"tau2": 0.0, "ram_mass": m, "cushion_stiffness": k},
                            {"0.0": [1, v0]}, times=times)["rows"])
    t = np.array(times[1:])
    exact = np.where(t <= math.pi / omega, v0 * math.sqrt(k * mu) * np.sin(omega * t), 0.0)
    assert math.pi / omega < 0.02                        # the pulse ends inside the run
    error = np.abs(got["F_head"] - exact).max() / (v0 * math.sqrt(k * mu))
    print(f"half sine through the FMU: max |F_head - exact| / peak = {error:.1e}")
    assert error <= 1e-9
    # after parting, each body keeps its velocity of the elastic collision
    assert got["v_pipe"][-1] == pytest.approx(2 * m * v0 / (m + M), rel=1e-12)
    assert got["v_ram"][-1] == pytest.approx((m - M) * v0 / (m + M), rel=1e-12)


def test_a_direct_strike_on_a_long_elastic_rod_converges_to_the_exponential(fmu_dir):
    """Model III, a rigid ram of m striking a long free rod directly at v0: F_head =
    Z1 v0 exp(-Z1 t / m) until the wave returns at 2 L1 / c1 (Z1 = S1 sqrt(E1 rho1)); the
    FMU's error shrinks about in proportion to dx."""
    m, v0, L1 = 2000.0, 5.0, 20.0
    S1 = math.pi * ((0.035 + 0.003) ** 2 - 0.035 ** 2)
    Z1, c1 = S1 * math.sqrt(1.95e11 * 7800.0), math.sqrt(1.95e11 / 7800.0)
    times = [j * 1e-4 for j in range(int(0.9 * 2 * L1 / c1 / 1e-4) + 1)]
    t = np.array(times[1:])
    exact = Z1 * v0 * np.exp(-Z1 * t / m)
    errors = []
    for dx in (0.1, 0.05, 0.025):
        params = {"elastic": True, "L1": L1, "L2": 0.0, "tau2": 0.0, "dx": dx,
                  "ram_mass": m, "x_monitor": 0.0}
        got = _columns(_strikes(fmu_dir, params, {"0.0": [1, v0]}, times=times)["rows"])
        errors.append(np.abs(got["F_head"] - exact).max() / (Z1 * v0))
    print("direct strike through the FMU, max |F_head - exact| / (Z1 v0) at dx = 0.1, 0.05, "
          "0.025 m: " + ", ".join(f"{e:.2e}" for e in errors))
    assert errors[0] < 2e-2
    assert errors[1] < 0.6 * errors[0] and errors[2] < 0.6 * errors[1], errors


def test_strikes_reach_the_elastic_model_as_the_core_takes_them(fmu_dir):
    """The elastic model with a ram: the FMU's outputs are the core's, stepped on the same
    points with the same strikes, bit for bit."""
    import pipeplug

    params = dict(SOIL, **RAM, L1=1.0, L2=0.5, dx=0.05)
    got = _columns(_strikes(fmu_dir, dict(params, elastic=True),
                            {"0.0": [1, V1], "0.15": [2, V2]})["rows"])
    model = pipeplug.build_model(params, {"elastic": True})
    want = []
    for a, b in zip(TIMES[:-1], TIMES[1:]):
        if a in (0.0, 0.15):
            model.strike(V1 if a == 0.0 else V2)
        model.advance_to(0.0, b, a)
        want.append(model.outputs())
    for name in ("v_pipe", "u_pipe", "v_ram", "W_ram", "W_friction", "W_cushion"):
        assert list(got[name]) == [getattr(row, name) for row in want], name
    assert got["W_ram"][-1] > 0.0


def test_a_strike_without_a_ram_is_discarded_with_its_line(fmu_dir):
    """No ram: the step that sees strikes rise is fmi2Discard with one line naming strikes, and
    nothing moves; with the counter put back the same step is taken."""
    result = run_scenario("strike_without_ram", fmu_dir, params=SOIL, h=1e-3)
    assert (result["refused"], result["u_after"]) == (2, 0.0)
    (line,) = result["log_at_refusal"]
    assert line["status"] == 2 and line["message"] == (
        "strikes = 'an increase' is not allowed; allowed: none without a ram (ram_mass > 0)")
    assert result["again"] == 0 and result["u_again"] > 0.0


def test_a_restored_state_knows_which_strikes_were_taken(fmu_dir):
    """Saved after the first strike and before the second: the rest run again from the saved
    state with the same inputs gives the same bits (the second strike once, the first not
    again)."""
    result = _strikes(fmu_dir, dict(SOIL, **RAM), {"0.0": [1, V1], "0.2": [2, V2]},
                      save_index=99)
    rest = _columns(result["rows"][100:])
    again = _columns(result["again"])
    for name in rest:
        assert list(again[name]) == list(rest[name]), name
    assert rest["W_ram"][-1] > rest["W_ram"][0]         # the second strike is in the rest
