"""Smith damping through PipePlug.fmu by the contract's names (``J_shaft``, ``J_face``, output
``W_damping``): a sliding pipe against its closed form, derived here; the elastic model
near it."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest
from fmu_helpers import run_scenario

R1, H1, RHO1, L1 = 0.035, 0.003, 7800.0, 1.0
P1, S1 = 2 * math.pi * (R1 + H1), math.pi * ((R1 + H1) ** 2 - R1 ** 2)
M1 = RHO1 * S1 * L1
Q, T0 = 23e3, 0.05
PARAMS = {"tau1": 2e4, "tau2": 0.0, "q_face": 2e6, "J_shaft": 0.5, "J_face": 0.2}


def _sliding_pipe(t):
    """No plug; shaft friction T1 = P1 L1 tau1 and the annulus' Qf = q_face S1, damped by
    c = J_shaft T1 + J_face Qf while the pipe advances: M v' = F - c v (F = Q - T1 - Qf for
    T0, then -(T1 + Qf)), v = F/c + (v0 - F/c) exp(-c t / M), until it stops. Returns
    (v, u, W_damping = int c v^2)."""
    t1, qf = P1 * L1 * PARAMS["tau1"], PARAMS["q_face"] * S1
    c = PARAMS["J_shaft"] * t1 + PARAMS["J_face"] * qf
    lam = c / M1

    def piece(v0, f, s):
        vinf, e = f / c, math.exp(-lam * s)
        sq = (vinf ** 2 * s + 2 * vinf * (v0 - vinf) * (1 - e) / lam
              + (v0 - vinf) ** 2 * (1 - e * e) / (2 * lam))
        return vinf + (v0 - vinf) * e, vinf * s + (v0 - vinf) * (1 - e) / lam, c * sq

    v, u, w = piece(0.0, Q - t1 - qf, min(t, T0))
    if t <= T0:
        return v, u, w
    stop = math.log(1 + c * v / (t1 + qf)) / lam
    v2, u2, w2 = piece(v, -(t1 + qf), min(t - T0, stop))
    return (v2 if t - T0 < stop else 0.0), u + u2, w + w2


def test_a_damped_sliding_pipe_through_the_fmu_is_the_closed_form(fmu_dir):
    result = run_scenario("simulate_pulse", fmu_dir, cases=[PARAMS], q0=Q, t0=T0, stop=0.1,
                          interval=0.0025)
    run = {k: np.array(v) for k, v in result["runs"][0].items()}
    v, u, w = np.array([_sliding_pipe(t) for t in run["time"]]).T
    assert np.max(np.abs(run["v_pipe"] - v)) <= 1e-13 * np.max(v)
    assert run["u_pipe"] == pytest.approx(u, rel=1e-13, abs=1e-16)
    assert run["W_damping"] == pytest.approx(w, rel=1e-12, abs=1e-12 * w[-1])
    assert w[-1] > 0.1 * run["W_input"][-1]            # damping takes a good share
    qf = PARAMS["q_face"] * S1
    assert run["W_face"] == pytest.approx(qf * u, rel=1e-13, abs=1e-12)
    balance = (run["W_input"] - run["E_kinetic"] - run["W_friction"] - run["W_face"]
               - run["W_damping"])
    assert np.abs(balance).max() <= 1e-12 * run["W_input"].max()


def test_the_elastic_model_with_damping_runs_through_the_fmu_near_the_rigid_closed_form(fmu_dir):
    # A steel pipe of 1 m rings for 0.4 ms per round trip: over a blow of 50 ms it moves as
    # the rigid pipe to within the scheme's first-order error (1e-3 at dx = 0.1 m). The FMU's
    # plain-Python path (its compiled one gives the same bits; its compilation is the elastic
    # fuzz's to pay, not a test's).
    params = dict(PARAMS, elastic=True, dx=0.1, x_monitor=0.0)
    env = dict(os.environ, PIPEPLUG_NO_JIT="1")
    result = run_scenario("simulate_pulse", fmu_dir, env=env, cases=[params], q0=Q, t0=T0,
                          stop=0.06, interval=0.0025)              # it stops at 53 ms
    run = {k: np.array(v) for k, v in result["runs"][0].items()}
    assert run["time"][-1] == pytest.approx(0.06)     # no step refused
    _, u, w = np.array([_sliding_pipe(t) for t in run["time"]]).T
    assert np.max(np.abs(run["u_pipe"] - u)) <= 1e-2 * np.max(u)
    assert np.max(np.abs(run["W_damping"] - w)) <= 1e-2 * np.max(w)
    assert np.all(np.diff(run["W_damping"]) >= 0.0)
    balance = (run["W_input"] - run["E_kinetic"] - run["E_strain"] - run["W_friction"]
               - run["W_face"] - run["W_damping"])
    assert np.abs(balance).max() <= 1e-12 * run["W_input"].max()
