"""Stepping behaviour of PipePlug.fmu: grid independence of the exact solver, the fd solver and
model II, several instances, fmi2Reset, and FMU state save/restore/serialization."""
from __future__ import annotations

import json
import math
import random

import numpy as np
import pytest
from fmu_helpers import Q0, T0, assert_matches_closed_form, closed_form, columns, run_scenario

STOP = 0.3
COARSE = [k / 100 for k in range(31)]                       # h = 10 ms
FINE = [k / 10000 for k in range(3001)]                     # h = 0.1 ms; FINE[100 j] == COARSE[j]


def _irregular(seed: int = 7) -> list:
    """The coarse points plus 400 random ones: steps from ~1 us to ~10 ms."""
    rng = random.Random(seed)
    return sorted(set(COARSE) | {rng.uniform(0.0, STOP) for _ in range(400)})


def _at(times: list, rows: list, wanted: list) -> dict:
    """Columns of ``rows`` (outputs after each step of ``times``) at the ``wanted`` times."""
    index = {t: k for k, t in enumerate(times[1:])}
    return columns([rows[index[t]] for t in wanted])


@pytest.mark.parametrize("params", [{"tau1": 2e4, "tau2": 1e4},
                                    {"tau1": 2e4, "tau2": 1e4, "contact_growth": True}],
                         ids=["model I", "model II"])
def test_exact_solver_is_grid_independent(fmu_dir, params):
    grids = {"coarse": COARSE, "fine": FINE, "irregular": _irregular()}
    result = run_scenario("runs", fmu_dir, q0=Q0, t0=T0,
                          runs={k: {"params": params, "times": v} for k, v in grids.items()})
    rows = result["rows"]
    fine_all = columns(rows["fine"])
    ref = _at(FINE, rows["fine"], COARSE[1:])
    for name in ("coarse", "irregular"):
        got = _at(grids[name], rows[name], COARSE[1:])
        for out, want in ref.items():
            if out.endswith("_mode"):
                assert np.array_equal(got[out], want), (name, out)
                continue
            scale = np.max(np.abs(fine_all[out]))
            err = np.max(np.abs(got[out] - want))
            assert err <= 1e-12 * scale, f"{name} {out}: {err:.3e} > 1e-12 * {scale:.6g}"


def test_model_ii_matches_harmonic_solution(fmu_dir):
    """tau2 = 0 and P1 tau1 U > Q0 before U = L1: the pipe swings harmonically, M1 U'' =
    Q0 - k U (k = P1 tau1), stops at pi/omega at U = 2 Q0/k and stays stuck (k 2Q0/k > Q0)."""
    tau1 = 2e5
    m1 = 7800.0 * math.pi * (0.038 ** 2 - 0.035 ** 2)
    k = 2.0 * math.pi * 0.038 * tau1
    omega = math.sqrt(k / m1)
    times = [j / 2000 for j in range(201)]                  # 0.5 ms steps to 0.1 s
    runs = {name: {"params": {"tau1": tau1, "tau2": 0.0, "contact_growth": growth},
                   "times": times} for name, growth in (("II", True), ("I", False))}
    rows = run_scenario("runs", fmu_dir, q0=Q0, t0=T0, runs=runs)["rows"]
    got = columns(rows["II"])
    t = np.array(times[1:])
    phase = np.minimum(omega * t, math.pi)
    u_want = Q0 / k * (1.0 - np.cos(phase))
    v_want = Q0 / (m1 * omega) * np.sin(phase)
    assert 2.0 * Q0 / k < 1.0                               # U stays on the growing segment
    assert np.max(np.abs(got["u_pipe"] - u_want)) <= 1e-9 * np.max(u_want)
    assert np.max(np.abs(got["v_pipe"] - v_want)) <= 1e-9 * np.max(v_want)
    assert np.all(columns(rows["I"])["u_pipe"] == 0.0)      # model I: tau1 > tau*, no motion


def test_fd_solver_is_selectable_and_steps_internally(fmu_dir):
    """solver="fd": a 1 ms step is 5 internal steps of dt = 0.2 ms (same result as 0.2 ms
    communication steps); first order: error vs the exact solution shrinks with dt."""
    base = {"tau1": 2e4, "tau2": 1e4, "solver": "fd"}
    every_ms = [k / 1000 for k in range(301)]
    runs = {"h1ms": {"params": base, "times": every_ms},
            "h02ms": {"params": base, "times": [k / 5000 for k in range(1501)]},
            "dt_fine": {"params": dict(base, dt=2.5e-5), "times": every_ms}}
    rows = run_scenario("runs", fmu_dir, q0=Q0, t0=T0, runs=runs)["rows"]
    coarse = columns(rows["h1ms"])
    same = _at(runs["h02ms"]["times"], rows["h02ms"], every_ms[1:])
    for out in ("v_pipe", "u_pipe", "v_plug", "u_plug"):
        scale = np.max(np.abs(coarse[out]))
        assert np.max(np.abs(coarse[out] - same[out])) <= 1e-9 * scale, out
    from fmu_helpers import closed_form
    exact = closed_form(base, every_ms[1:])
    err = {name: np.max(np.abs(columns(rows[name])["v_pipe"] - exact["v_pipe"]))
           for name in ("h1ms", "dt_fine")}
    peak = np.max(exact["v_pipe"])
    assert 1e-6 * peak < err["h1ms"] < 2e-2 * peak           # fd, not the exact solver
    assert err["dt_fine"] < err["h1ms"] / 3.0                # dt / 8 -> clearly smaller error


def test_interleaved_instances_are_independent(fmu_dir):
    cases = [{"tau1": 2e4, "tau2": 1e4}, {"tau1": 7e4, "tau2": 3.5e4}, {}]
    times = [k / 1000 for k in range(301)]
    result = run_scenario("interleaved", fmu_dir, cases=cases, times=times, q0=Q0, t0=T0)
    for params, rows in zip(cases, result["rows"]):
        assert_matches_closed_form(columns(rows), times[1:], params)


def test_reset_returns_to_state_after_instantiation(fmu_dir):
    times = [k / 1000 for k in range(61)]
    result = run_scenario("reset", fmu_dir, params={"tau1": 2e4, "solver": "fd"}, times=times,
                          q0=Q0, t0=T0)
    assert result["after_reset"] == {"tau1": 0.0, "solver": "exact"}      # contract defaults
    assert set(result["after_reset_outputs"].values()) == {0}
    assert result["refused_status"] == 3                  # fmi2Error: the instance can be reset
    runs = result["runs"]
    assert json.dumps(runs["used"]) == json.dumps(runs["fresh"])
    assert json.dumps(runs["refused"]) == json.dumps(runs["fresh"])


@pytest.mark.parametrize("params", [{"tau1": 2e4, "tau2": 1e4},
                                    {"tau1": 2e4, "tau2": 1e4, "contact_growth": True},
                                    {"tau1": 7e4, "tau2": 3.5e4, "solver": "fd"}],
                         ids=["exact model I", "exact model II", "fd"])
def test_state_restore_and_serialization_are_bit_identical(fmu_dir, params):
    """Saved at 40 ms (inside the pulse); the continuation crosses the pulse edge and stops."""
    times = [k / 1000 for k in range(151)]
    result = run_scenario("state", fmu_dir, params=params, q0=Q0, t0=T0, times=times,
                          save_index=40)
    runs = result["runs"]
    original = json.dumps(runs["original"])            # repr of floats: bit-exact comparison
    for name in ("restore1", "restore2", "fresh"):
        assert json.dumps(runs[name]) == original, name
        assert json.dumps(result["after_restore"][name]) == json.dumps(result["saved_outputs"])
    assert result["restored_params"] == params
    assert result["log"] == []


@pytest.mark.parametrize("clock", ["k*h", "+=h"])
def test_hosts_keeping_their_own_clock_get_their_own_points(fmu_dir, clock):
    """At h = 1e-5 the outputs equal the closed form at the host's points, for a pulse that
    ends where the host switched Q, within 1e-14 of the peak (the FMU takes the host's time)."""
    params = {"tau1": 2e4, "tau2": 1e4}
    result = run_scenario("host_clock", fmu_dir, params=params, q0=Q0, t0=T0, h=1e-5,
                          n_steps=6000, clock=clock)
    times, switch = np.array(result["times"][1:]), result["switch"]
    assert abs(switch - T0) < 1e-5
    got = columns(result["rows"])
    want = closed_form(dict(params, t0=switch), times)
    for name in ("v_pipe", "v_plug", "u_pipe", "u_plug", "W_input", "W_friction"):
        peak = np.max(np.abs(want[name]))
        assert np.max(np.abs(np.asarray(got[name]) - want[name])) <= 1e-14 * peak, name
