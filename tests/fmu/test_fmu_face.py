"""The end resistance through PipePlug.fmu by the contract's names (``q_face``,
``q_plug_face``, output ``W_face``): closed forms derived here, for the exact solver, fd and
the elastic model."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest
from fmu_helpers import run_scenario

R1, H1, RHO1, L1 = 0.035, 0.003, 7800.0, 1.0
S1, S2 = math.pi * ((R1 + H1) ** 2 - R1 ** 2), math.pi * R1 ** 2
M1 = RHO1 * S1 * L1
F2 = 2 * math.pi * R1 * L1 * 1e4                 # the default tau2, L2 = L1
Q, T0 = 23e3, 0.05


def _cored_pipe(t):
    """q_face = 2 MPa, q_plug_face = 1 MPa: Qp = 3.85 kN > F2 = 2.2 kN holds the plug while the
    pipe slides over it; the pipe moves under Q - Qf - F2, then brakes under Qf + F2 (stops at
    0.32 s). (u_pipe, W_face)."""
    qf = 2e6 * S1
    a, b = (Q - qf - F2) / M1, (qf + F2) / M1
    tp = min(t, T0)
    u, v = 0.5 * a * tp ** 2, a * tp
    tb = min(max(t - T0, 0.0), v / b)
    u += v * tb - 0.5 * b * tb ** 2
    return u, qf * u


FACE = {"q_face": 2e6, "q_plug_face": 1e6}


def _runs(fmu_dir, cases, stop, env=None):
    result = run_scenario("simulate_pulse", fmu_dir, env=env, cases=cases, q0=Q, t0=T0,
                          stop=stop, interval=0.01)
    return [{k: np.array(v) for k, v in run.items()} for run in result["runs"]]


def test_exact_solver_and_fd_through_the_fmu_are_the_closed_form(fmu_dir):
    exact, fd = _runs(fmu_dir, [FACE, dict(FACE, solver="fd", dt=1e-5)], 0.4)
    u, w = np.array([_cored_pipe(t) for t in exact["time"]]).T
    assert exact["u_pipe"] == pytest.approx(u, rel=1e-13, abs=1e-15)
    assert exact["W_face"] == pytest.approx(w, rel=1e-13, abs=1e-12)
    assert np.all(exact["u_plug"] == 0.0)
    balance = exact["W_input"] - exact["E_kinetic"] - exact["W_friction"] - exact["W_face"]
    assert np.abs(balance).max() <= 1e-12 * exact["W_input"].max()
    assert fd["u_pipe"][-1] == pytest.approx(u[-1], rel=1e-3)
    assert fd["W_face"][-1] == pytest.approx(w[-1], rel=1e-3)


def test_the_elastic_model_through_the_fmu(fmu_dir):
    """A 1 m steel pipe is nearly rigid over these times; its own ledger closes. (Plain
    Python kernels: their compilation is not this test's to pay.)"""
    env = dict(os.environ, PIPEPLUG_NO_JIT="1")
    (el,) = _runs(fmu_dir, [dict(FACE, elastic=True, dx=0.1, x_monitor=1.0)], 0.06, env)
    u, w = np.array([_cored_pipe(t) for t in el["time"]]).T
    assert el["W_face"][-1] == pytest.approx(w[-1], rel=0.02)
    assert np.all(np.diff(el["W_face"]) >= 0.0)
    balance = (el["W_input"] - el["E_kinetic"] - el["E_strain"] - el["W_friction"]
               - el["W_face"])
    assert np.abs(balance).max() <= 1e-12 * el["W_input"].max()
