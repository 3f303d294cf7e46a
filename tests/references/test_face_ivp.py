"""The ODE reference with end resistance (pipeplug_references.face_ivp) against closed forms
derived here; it imports nothing of the project's core."""
import ast
import inspect
import math

import numpy as np
import pytest

import pipeplug_references.face_ivp as face_ivp
from pipeplug_references import rigid_ivp

R1, H1, RHO1, L1, TAU2 = 0.035, 0.003, 7800.0, 1.0, 1.0e4
S1 = math.pi * ((R1 + H1) ** 2 - R1 ** 2)
S2 = math.pi * R1 ** 2
M1 = RHO1 * S1 * L1
F2 = 2 * math.pi * R1 * L1 * TAU2


@pytest.mark.parametrize("q", [23e3, 3e3, -5e3])
def test_free_pipe_with_end_resistance(q):
    qf = 5e6 * S1
    times = np.linspace(0.01, 0.3, 30)
    out = face_ivp.simulate_face({"tau2": 0.0, "q_face": 5e6}, [(0.05, q)], times, False)
    for t, u, v, w in zip(times, out["u_pipe"], out["v_pipe"], out["W_face"]):
        if 0.0 <= q <= qf:
            eu, ev = 0.0, 0.0
        elif q < 0.0:                  # a retreat meets no end resistance
            tp = min(t, 0.05)
            ev = q / M1 * tp
            eu = 0.5 * q / M1 * tp ** 2 + ev * (t - tp)
        else:
            a, b = (q - qf) / M1, qf / M1
            tp = min(t, 0.05)
            eu, ev = 0.5 * a * tp ** 2, a * tp
            tb = min(max(t - 0.05, 0.0), ev / b)
            eu, ev = eu + ev * tb - 0.5 * b * tb ** 2, ev - b * tb
        assert u == pytest.approx(eu, abs=1e-13 * 10.0)
        assert v == pytest.approx(ev, abs=1e-13 * 300.0)
        assert w == pytest.approx(qf * max(eu, 0.0), abs=1e-12 * 1e5)


def test_coring_plug_held_by_its_face():
    qf, qp, q = 2e6 * S1, 1e6 * S2, 23e3          # Qp > F2: the plug stays
    out = face_ivp.simulate_face({"q_face": 2e6, "q_plug_face": 1e6}, [(0.05, q)],
                                 [0.05, 0.5], False)
    a, b = (q - qf - F2) / M1, (qf + F2) / M1
    v = a * 0.05
    assert np.all(out["u_plug"] == 0.0)
    assert out["u_pipe"][0] == pytest.approx(0.5 * a * 0.05 ** 2, rel=1e-13)
    assert out["u_pipe"][1] == pytest.approx(0.5 * a * 0.05 ** 2 + v * v / (2 * b), rel=1e-13)
    assert qp > F2 and out["W_face"][1] == pytest.approx(qf * out["u_pipe"][1], rel=1e-13)


def test_without_end_resistance_it_is_the_rigid_reference():
    params = {"tau1": 1e4, "tau2": 2e4, "L2": 0.5}
    times = np.linspace(0.0, 0.2, 41)
    for growth in (False, True):
        a = face_ivp.simulate_face(params, [(0.03, 3e4), (0.02, -2e4)], times, growth)
        b = rigid_ivp.simulate(params, [(0.03, 3e4), (0.02, -2e4)], times, growth)
        for name in rigid_ivp.OUTPUT_NAMES:
            assert np.abs(a[name] - b[name]).max() <= 1e-12 * max(np.abs(b[name]).max(), 1.0)
        assert np.all(a["W_face"] == 0.0)


def test_imports_nothing_of_the_project_but_the_rigid_reference():
    tree = ast.parse(inspect.getsource(face_ivp))
    roots = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import)
             for a in n.names}
    roots |= {n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert roots <= {"__future__", "numpy", "scipy", "rigid_ivp"}, roots
