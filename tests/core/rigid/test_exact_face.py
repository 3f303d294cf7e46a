"""End resistance in the rigid models (exact solver and fd) against closed forms derived here,
the independent ODE reference (pipeplug_references.face_ivp) and the ledger; without it the
face code is not run at all."""
import math

import numpy as np
import pytest
from rigid_helpers import drive

from pipeplug import Params, build_model
from pipeplug.interface import ledger_residual
from pipeplug_references.face_ivp import simulate_face

P = Params()
M1, M2, S1, S2, F2 = P.M1, P.M2, P.S1, P.S2, P.F2     # defaults: tau2 = 1e4, L2 = L1 = 1 m


def _free_pipe(q, duration, qf, t):
    """A free rigid pipe (no friction) with only the end resistance Qf under Q for
    ``duration``: (u, v, W_face) at time ``t`` (derived by hand, piecewise uniform)."""
    if q <= qf and q >= 0.0:           # held: the window [-Qf, 0] takes Q
        return 0.0, 0.0, 0.0
    if q < 0.0:                        # pulled back: nothing resists a retreat
        tp = min(t, duration)
        v = q / M1 * tp
        return 0.5 * q / M1 * tp ** 2 + v * (t - tp), v, 0.0
    a = (q - qf) / M1                  # pushed forward, then braked by Qf alone
    tp = min(t, duration)
    u, v = 0.5 * a * tp ** 2, a * tp
    if t > duration:
        b = qf / M1
        tb = min(t - duration, v / b)
        u, v = u + v * tb - 0.5 * b * tb ** 2, v - b * tb
    return u, v, qf * u


@pytest.mark.parametrize("q", [23e3, 2e3, -5e3])
@pytest.mark.parametrize("compiled", [False, True])
def test_free_pipe_with_end_resistance_is_the_closed_form(q, compiled):
    qf = 5e6 * S1                      # q_face = 5 MPa: Qf = 5.66 kN
    model = build_model({"tau2": 0.0, "q_face": 5e6}, {}, compiled=compiled)
    times = np.linspace(0.01, 0.2, 20)
    out = drive(model, [(0.0, 0.05, q)], times)
    u, v, w = np.array([_free_pipe(q, 0.05, qf, t) for t in times]).T
    scale = max(abs(u).max(), 1e-3)
    assert out["u_pipe"] == pytest.approx(u, abs=1e-13 * scale)
    assert out["v_pipe"] == pytest.approx(v, abs=1e-13 * max(abs(v).max(), 1e-3))
    assert out["W_face"] == pytest.approx(w, abs=1e-12 * max(w.max(), 1.0))
    assert abs(ledger_residual(model.outputs())) <= 1e-12 * max(abs(out["W_input"]).max(), 1.0)


def test_a_held_pipe_takes_the_load_on_its_annulus_first_on_its_shaft():
    # tau1 = 1e3: shaft 239 N; Qf = 5.66 kN; Q = 3 kN is held, the annulus taking the rest
    model = build_model({"tau1": 1e3, "tau2": 0.0, "q_face": 5e6}, {}, compiled=False)
    model.advance(3e3, 0.01)
    out = model.outputs()
    assert out.v_pipe == 0.0 and out.u_pipe == 0.0 and out.pipe_mode == 0
    assert out.F_outer == pytest.approx(-P.P1 * P.L1 * 1e3)
    assert out.stress_min * S1 == pytest.approx(-3e3)       # the head
    assert out.stress_max * S1 == pytest.approx(-(3e3 - P.P1 * P.L1 * 1e3))   # the front end


def test_coring_the_plug_held_by_its_face_while_the_pipe_slides():
    # Qp = 1e6 S2 = 3.85 kN > F2 = 2.2 kN: the plug stays, the pipe slides over it
    qf, q = 2e6 * S1, 23e3
    model = build_model({"q_face": 2e6, "q_plug_face": 1e6}, {}, compiled=False)
    times = np.array([0.02, 0.05, 0.1, 0.4])          # it stops at 0.32 s
    out = drive(model, [(0.0, 0.05, q)], times)
    a, b = (q - qf - F2) / M1, (qf + F2) / M1      # the pipe alone under Qf and F2
    v_top = a * 0.05
    u_end = 0.5 * a * 0.05 ** 2 + v_top ** 2 / (2 * b)
    assert np.all(out["u_plug"] == 0.0) and np.all(out["v_plug"] == 0.0)
    assert out["u_pipe"][0] == pytest.approx(0.5 * a * 0.02 ** 2, rel=1e-13)
    assert out["u_pipe"][-1] == pytest.approx(u_end, rel=1e-13)
    assert out["W_face"][-1] == pytest.approx(qf * u_end, rel=1e-13)
    assert out["W_friction_inner"][-1] == pytest.approx(F2 * u_end, rel=1e-13)


def test_a_carried_plug_adds_its_face():
    # tau2 = 1e5 Pa: F2 = 22 kN holds the plug, which needs M2 a + Qp = 9.9 kN; Qp = 385 N
    qf, qp, q = 2e6 * S1, 1e5 * S2, 23e3
    model = build_model({"q_face": 2e6, "q_plug_face": 1e5, "tau2": 1e5}, {}, compiled=False)
    model.advance(q, 0.05)
    a = (q - qf - qp) / (M1 + M2)
    out = model.outputs()
    assert out.u_plug == out.u_pipe == pytest.approx(0.5 * a * 0.05 ** 2, rel=1e-13)
    assert out.F_inner == pytest.approx(-(M2 * a + qp), rel=1e-13)
    assert out.W_face == pytest.approx((qf + qp) * out.u_pipe, rel=1e-13)


CASES = [  # (params, options, pulses): every kind of piece, both models
    ({"tau1": 1e4, "q_face": 3e6, "q_plug_face": 2e6, "L2": 0.4}, {}, [(0, 0.03, 3e4)]),
    ({"tau1": 5e3, "q_face": 1e6, "q_plug_face": 5e5, "tau2": 2e4},
     {"contact_growth": True}, [(0, 0.02, 4e4), (0.02, 0.03, -2.5e4)]),
    ({"q_plug_face": 3e6, "tau2": 3e4, "L2": 0.5, "rho2": 3000.0}, {},
     [(0, 0.01, 5e4), (0.01, 0.04, -3e4)]),
    ({"tau1": 2e4, "q_face": 4e6, "tau2": 5e3}, {"contact_growth": True},
     [(0, 0.01, -2e4), (0.01, 0.05, 4e4)]),
]


@pytest.mark.parametrize("params, options, pulses", CASES)
def test_exact_solver_against_the_ode_reference(params, options, pulses):
    times = np.linspace(0.002, 0.15, 75)
    model = build_model(params, {"solver": "exact", **options}, compiled=False)
    out = drive(model, pulses, times)
    segments, t = [], 0.0
    for start, duration, amplitude in pulses:
        if start > t:
            segments.append((start - t, 0.0))
        segments.append((duration, amplitude))
        t = start + duration
    ref = simulate_face(params, segments, times, options.get("contact_growth", False))
    assert np.any(ref["v_plug"] != ref["v_pipe"]) or "q_face" in params
    for names in (("u_pipe", "u_plug"), ("v_pipe", "v_plug"),
                  ("W_input", "W_friction_outer", "W_friction_inner", "W_face")):
        scale = max(*(abs(ref[n]).max() for n in names), 1e-9)
        for n in names:
            assert np.abs(out[n] - ref[n]).max() <= 1e-10 * scale, n
    assert np.all(np.diff(out["W_face"]) >= 0.0)
    residual = ledger_residual({n: out[n] for n in out})
    assert np.abs(residual).max() <= 1e-12 * np.abs(out["W_input"]).max()


def test_without_end_resistance_the_face_code_is_not_run(monkeypatch):
    import pipeplug.rigid.stepping as stepping

    def refuse(*_):
        raise AssertionError("the face pieces ran")

    monkeypatch.setattr(stepping, "make_face_piece", refuse)
    monkeypatch.setattr(stepping, "face_work_at", refuse)
    model = build_model({"tau1": 1e4}, {"contact_growth": True}, compiled=False)
    model.advance(3e4, 0.02)
    model.advance(0.0, 0.2)
    assert model.outputs().W_face == 0.0
    with pytest.raises(AssertionError, match="face pieces"):
        build_model({"q_face": 1.0}, {}, compiled=False).advance(3e4, 0.02)


def test_state_round_trip_keeps_the_face_work():
    params = {"tau1": 1e4, "q_face": 3e6, "q_plug_face": 2e6, "L2": 0.4}
    a = build_model(params, {}, compiled=False)
    a.advance(3e4, 0.01)
    state = a.get_state()
    b = build_model(params, {}, compiled=False)
    b.set_state(state)
    for m in (a, b):
        m.advance(3e4, 0.01)
        m.advance(0.0, 0.1)
    assert a.outputs() == b.outputs() and a.outputs().W_face > 0.0


def test_fd_converges_to_the_closed_form_at_first_order():
    qf, q = 5e6 * S1, 23e3
    u_exact = _free_pipe(q, 0.05, qf, 0.2)[0]
    errors = []
    for dt in (1e-4, 5e-5, 2.5e-5):
        model = build_model({"tau2": 0.0, "q_face": 5e6, "dt": dt}, {"solver": "fd"})
        model.advance(q, 0.05)
        model.advance(0.0, 0.15)
        out = model.outputs()
        errors.append(abs(out.u_pipe - u_exact) / u_exact)
        assert abs(ledger_residual(out)) <= 1e-9 * out.W_input
        assert out.W_face == pytest.approx(qf * out.u_pipe, rel=1e-12)
    assert errors[0] < 1e-3
    assert 1.6 < errors[0] / errors[1] < 2.4 and 1.6 < errors[1] / errors[2] < 2.4


def test_a_ram_with_end_resistance_is_refused_by_the_rigid_model_II():
    from pipeplug import ParameterError
    with pytest.raises(ParameterError, match="q_face.*contact_growth"):
        build_model({"q_face": 1e6, "ram_mass": 10.0}, {"contact_growth": True})
    assert math.isfinite(build_model({"q_face": 1e6, "ram_mass": 10.0}, {}).time)
    assert math.isfinite(build_model({"q_face": 1e6, "ram_mass": 10.0, "dx": 0.05},
                                     {"elastic": True}).time)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_direct_strike_against_the_face_alone(compiled):
    """A ram of m = 3 kg strikes a free pipe (no friction, no plug) at v0 = 5 m/s with e = 1:
    the pipe leaves at 2 m v0 / (m + M1), the ram at (m - M1) v0 / (m + M1), and the face's
    Qf = q_face S1 stops the pipe after M1 v^2 / (2 Qf), all its kinetic energy done against
    it (closed form)."""
    S1 = math.pi * (0.038 ** 2 - 0.035 ** 2)
    M1, Qf, m, v0 = 7800.0 * S1, 2e6 * S1, 3.0, 5.0
    model = build_model({"tau1": 0.0, "tau2": 0.0, "q_face": 2e6, "ram_mass": m}, {},
                        compiled=compiled)
    model.strike(v0)
    model.advance(0.0, 1.0)
    out = model.outputs()
    v = 2.0 * m * v0 / (m + M1)
    assert out.u_pipe == pytest.approx(M1 * v * v / (2.0 * Qf), rel=1e-13)
    assert out.W_face == pytest.approx(0.5 * M1 * v * v, rel=1e-13)
    assert out.v_ram == pytest.approx((m - M1) * v0 / (m + M1), rel=1e-13)
    assert out.v_pipe == 0.0 and out.at_rest
    assert abs(ledger_residual(out)) <= 1e-14 * out.W_ram
