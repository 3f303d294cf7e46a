"""Smith damping in the rigid models: the exact solver against closed forms derived here and
the independent ODE reference, its ledger and grid independence, fd's first order, defaults
and refusals."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug import build_model
from pipeplug.params import ParameterError
from pipeplug.rigid.damped import RigidDamped
from pipeplug.rigid.exact import RigidExact
from pipeplug_references.damping_ivp import simulate_damped

R1, H1, RHO1, L1 = 0.035, 0.003, 7800.0, 1.0
P1, S1 = 2 * math.pi * (R1 + H1), math.pi * ((R1 + H1) ** 2 - R1 ** 2)
M1 = RHO1 * S1 * L1
Q, T0 = 23e3, 0.05


def _sliding_pipe(t, tau1, j):
    """A pipe alone (tau2 = 0) with shaft friction T1 = P1 L1 tau1 damped by c = J T1, pushed
    from rest by Q for T0, then free: M v' = F - c v (F = Q - T1, then -T1) has
    v = F/c + (v0 - F/c) exp(-c t / M). Returns (v, u, W_damping = int c v^2, stop time)."""
    t1, c = P1 * L1 * tau1, j * P1 * L1 * tau1
    lam = c / M1

    def piece(v0, f, s):              # velocity, displacement and int v^2 after s
        vinf = f / c
        e = math.exp(-lam * s)
        v = vinf + (v0 - vinf) * e
        u = vinf * s + (v0 - vinf) * (1 - e) / lam
        sq = (vinf ** 2 * s + 2 * vinf * (v0 - vinf) * (1 - e) / lam
              + (v0 - vinf) ** 2 * (1 - e * e) / (2 * lam))
        return v, u, sq

    v1, u1, sq1 = piece(0.0, Q - t1, min(t, T0))
    stop = T0 + math.log(1 + c * v1 / t1) / lam
    if t <= T0:
        return v1, u1, c * sq1, stop
    v2, u2, sq2 = piece(v1, -t1, min(t, stop) - T0)
    return (v2 if t < stop else 0.0), u1 + u2, c * (sq1 + sq2), stop


def _run(params, times, solver="exact"):
    model = build_model(params, {"solver": solver})
    return model, model.sample(np.where(times <= T0, Q, 0.0), times)


@pytest.mark.parametrize("j", [0.05, 0.7, 30.0])
def test_a_sliding_pipe_with_damped_shaft_friction_is_the_closed_form(j):
    tau1 = 2e4
    params = {"tau1": tau1, "tau2": 0.0, "J_shaft": j}
    stop = _sliding_pipe(T0, tau1, j)[3]
    times = np.sort(np.concatenate([np.linspace(0.001, 2 * stop, 97), [T0, stop]]))
    model, out = _run(params, times)
    assert isinstance(model, RigidDamped)
    v, u, w, _ = np.array([_sliding_pipe(t, tau1, j) for t in times]).T
    scale = np.max(np.abs(v))
    assert np.max(np.abs(out["v_pipe"] - v)) <= 1e-13 * scale
    assert out["u_pipe"] == pytest.approx(u, rel=1e-13, abs=1e-16)
    assert out["W_damping"] == pytest.approx(w, rel=1e-12, abs=1e-12 * w[-1])
    assert np.all(out["v_pipe"][times > stop * (1 + 1e-12)] == 0.0)   # stuck exactly after it


CASES = [      # coupled pipe and plug, model I: every kind of piece and event
    dict(tau1=2e4, tau2=1e4, q_face=1e6, q_plug_face=5e5, J_shaft=0.5, J_face=0.5),
    dict(tau1=2e4, tau2=1e4, J_shaft=0.3),
    dict(tau1=0.0, tau2=1e4, J_shaft=2.0, q_face=2e6, q_plug_face=1e6, J_face=0.2),
]


@pytest.mark.parametrize("params", CASES)
def test_coupled_cases_agree_with_the_reference_ode(params):
    times = np.linspace(0.0, 0.2, 201)[1:]
    _, out = _run(params, times)
    ref = simulate_damped(params, [(T0, Q)], times, False)
    for name in ("v_pipe", "v_plug", "u_pipe", "u_plug", "W_damping", "W_face", "W_friction",
                 "F_outer", "F_inner"):
        scale = max(np.max(np.abs(ref[name])), 1e-30)
        assert np.max(np.abs(out[name] - ref[name])) <= 1e-10 * scale, name
    assert np.max(out["W_damping"]) > 0.0


@pytest.mark.parametrize("params", CASES)
def test_ledger_closes_and_the_damping_work_never_decreases(params):
    times = np.linspace(0.0, 0.2, 401)[1:]
    _, out = _run(params, times)
    residual = (out["W_input"] - out["E_kinetic"] - out["W_friction"] - out["W_face"]
                - out["W_damping"])
    assert np.max(np.abs(residual)) <= 1e-13 * np.max(out["W_input"])
    assert np.all(np.diff(out["W_damping"]) >= 0.0)


def test_outputs_do_not_depend_on_the_host_grid():
    params = CASES[0]
    coarse = build_model(params)
    coarse.advance_to(Q, T0)
    coarse.advance_to(0.0, 0.2)
    fine = build_model(params)
    for t in np.linspace(0.0, T0, 38)[1:]:
        fine.advance_to(Q, t)
    for t in np.linspace(T0, 0.2, 71)[1:]:
        fine.advance_to(0.0, t)
    a, b = coarse.outputs(), fine.outputs()
    for name in ("u_pipe", "u_plug", "W_damping", "W_friction", "W_face"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-15), name


def test_fd_converges_at_first_order_to_the_reference():
    params = CASES[0]
    times = np.array([T0, 0.2])
    ref = simulate_damped(params, [(T0, Q)], times, False)
    errors = []
    for dt in (4e-5, 1e-5):
        _, out = _run(dict(params, dt=dt), times, "fd")
        errors.append(abs(out["u_pipe"][-1] - ref["u_pipe"][-1]))
        residual = (out["W_input"] - out["E_kinetic"] - out["W_friction"] - out["W_face"]
                    - out["W_damping"] - out["W_numerical"])
        assert np.max(np.abs(residual)) <= 1e-10 * np.max(out["W_input"])
    order = math.log(errors[0] / errors[1]) / math.log(4.0)
    assert 0.7 < order < 1.3


def test_model_ii_fd_agrees_with_the_reference():
    params = dict(tau1=2e4, tau2=1e4, J_shaft=0.5, q_face=1e6, J_face=0.3)
    times = np.array([0.05, 0.3])
    model = build_model(dict(params, dt=5e-6), {"solver": "fd", "contact_growth": True})
    out = model.sample(np.array([Q, 0.0]), times)
    ref = simulate_damped(params, [(T0, Q)], times, True)
    assert out["u_pipe"] == pytest.approx(ref["u_pipe"], rel=1e-3)
    assert out["W_damping"][-1] == pytest.approx(ref["W_damping"][-1], rel=1e-3)


def test_without_damping_the_models_are_those_of_before():
    assert type(build_model({"tau1": 2e4})) is RigidExact
    assert type(build_model({"tau1": 2e4, "J_shaft": 0.0, "J_face": 0.0})) is RigidExact
    # a damping with nothing to damp is absent: no shaft friction, no plug, no end resistance
    assert type(build_model({"tau1": 0.0, "tau2": 0.0, "J_shaft": 1.0, "J_face": 1.0})) \
        is RigidExact
    fd = build_model({"tau1": 2e4}, {"solver": "fd"})
    assert not hasattr(fd, "_damping")


@pytest.mark.parametrize("params, options, words", [
    ({"tau1": 2e4, "J_shaft": 0.5}, {"contact_growth": True}, "contact_growth"),
    ({"tau1": 2e4, "J_shaft": 0.5, "ram_mass": 100.0}, {}, "ram"),
    ({"tau1": 2e4, "J_shaft": 0.5, "L2": 0.5}, {"plug_growth": True}, "plug_growth"),
    ({"tau1": 2e4, "J_shaft": 2e3}, {}, "<= 1000"),
])
def test_refusals_name_the_parameter_and_the_combination(params, options, words):
    with pytest.raises(ParameterError) as refusal:
        build_model(dict(params, L1=1.0, dx=0.01), options)
    assert refusal.value.name in ("J_shaft", "J_face")
    assert words in str(refusal.value)


def test_the_elastic_model_carries_damping_with_a_growing_plug():
    model = build_model({"tau1": 2e4, "J_shaft": 0.5, "L2": 0.5, "L1": 1.0, "dx": 0.05},
                        {"elastic": True, "plug_growth": True})
    assert model.kernel_name == "run_damped_growth"


def test_a_pipe_held_exactly_at_its_limit_under_a_sliding_plug_stays_held():
    # No shaft friction: the annulus' end resistance Qf holds the pipe forward, nothing holds
    # it backward. Pipe and plug driven back, then the load Qf + F2 (exactly the limit of a
    # held pipe under a plug sliding back in it): the pipe stops and stays held (stuck first)
    # while the plug slides to a stick; its margin to the limit is a constant 0 (no damper
    # acts on it), no breakaway. Modes and events from the reference.
    tau2, L2, q_face = 3.3e4, 0.9, 3.3e7
    F2, Qf = 2 * math.pi * R1 * L2 * tau2, q_face * S1
    params = dict(tau1=0.0, tau2=tau2, L2=L2, q_face=q_face, J_face=0.02)
    segments = [(0.05, -27000.0), (0.15, Qf + F2)]
    times = np.linspace(0.0, 0.2, 201)[1:]
    ref = simulate_damped(params, segments, times, False)
    stops = [t for t, what in ref["events"] if what.startswith("pipe stops: (0, 1")]
    sticks = [t for t, what in ref["events"] if what.startswith("plug sticks") and t > stops[0]]
    model = build_model(params)
    out = model.sample(np.where(times <= 0.05, -27000.0, Qf + F2), times)
    assert model.modes() == ((-1, -1), (-1, 1), (0, 1), (1, 0))
    held = (times > stops[0]) & (times < sticks[0])
    assert np.count_nonzero(held) > 40
    assert np.all(out["v_pipe"][held] == 0.0) and np.all(out["pipe_mode"][held] == 0)
    scale = np.max(np.abs(ref["v_plug"]))
    assert np.max(np.abs(out["v_plug"] - ref["v_plug"])) <= 1e-12 * scale


def test_a_velocity_decaying_to_zero_is_the_same_on_every_grid_and_its_works_never_fall():
    # Pushed, then held at exactly its friction limit (Q = T1): M v' = -c v, v0 exp(-c t / M),
    # zero only in the limit. Where it has decayed to round-off, whether it has stopped is
    # round-off too, but the same on every host's grid, and no work decreases.
    tau1, j = 2e4, 0.5
    t1 = P1 * L1 * tau1
    params = {"tau1": tau1, "tau2": 0.0, "J_shaft": j}
    end = T0 + 200 * M1 / (j * t1)                 # 200 time constants: v0 exp(-200)
    coarse = np.array([T0, end])
    fine = np.concatenate([np.linspace(0.001, T0, 50), np.linspace(T0, end, 2001)[1:]])
    outs = []
    for times in (coarse, fine):
        model = build_model(params)
        outs.append(model.sample(np.where(times <= T0, Q, t1), times))
    for name in outs[0]:
        assert outs[0][name][-1] == outs[1][name][-1], name
    v0 = _sliding_pipe(T0, tau1, j)[0]
    after = fine > T0
    decay = v0 * np.exp(-j * t1 / M1 * (fine[after] - T0))
    assert np.max(np.abs(outs[1]["v_pipe"][after] - decay)) <= 1e-13 * v0
    for name in ("W_friction", "W_damping"):
        assert np.all(np.diff(outs[1][name]) >= 0.0), name


def test_a_stick_closed_by_round_off_conserves_momentum():
    # A plug 600 times the pipe's mass, stiffly coupled (J_shaft 81 s/m): a load reverses the
    # pipe, whose sliding speed on the plug closes within 2.3 us; round-off carries it past
    # zero, and the plug set to the pipe's velocity took 2.7e-12 J (6e-13 of the works) out
    # of the ledger W_input = E_kinetic + W_friction + W_face + W_damping.
    params = {"L2": 0.038004522214962026, "rho2": 22134688.431499217,
              "tau1": 25625.05653975771, "tau2": 998275.0654159638,
              "q_face": 84411259.63400412, "J_shaft": 81.36734041634145,
              "J_face": 0.3323013315254771}
    segments = [(0.09037887259787439, 8343.214578901428),
                (0.0009244359562810896, -64193.95389142974),
                (0.00553966465959264, 48561.50767870751)]
    model = build_model(params)
    t, worst, largest = 0.0, 0.0, 0.0
    for duration, q in segments:
        for s in np.linspace(t, t + duration, 40)[1:]:
            model.advance_to(q, s)
            out = model.outputs()
            worst = max(worst, abs(out.W_input - out.E_kinetic - out.W_friction - out.W_face
                                   - out.W_damping))
            largest = max(largest, out.W_input)
        t += duration
    assert worst <= 1e-14 * largest


def test_a_decayed_piece_never_gives_back_work():
    # M v' = -c v: W_damping = c int v^2 = M v0^2 (1 - exp(-2 c t / M)) / 2 grows (to the last
    # bit) also where it has flattened out; so does the displacement (fuzz 2026:2078).
    from pipeplug.rigid.linear import LinearPiece

    m = 5.36646857086209
    c, v0 = 3013.4449519802 * m, -1.2165327109940056 / math.sqrt(m)
    piece = LinearPiece([m], [[c]], [0.0], [v0])
    t = np.linspace(0.005, 0.01, 2001)                # c t / m from 15 to 30: flat
    work = np.array([piece.dissipation(s) for s in t])
    travel = np.array([piece.displacement(s)[0] for s in t])
    assert np.all(np.diff(work) >= 0.0) and np.all(np.diff(travel) <= 0.0)
    exact = 0.5 * m * v0 ** 2 * -np.expm1(-2 * c / m * t)
    assert np.max(np.abs(work - exact)) <= 1e-15 * exact[-1]


def test_a_load_exactly_at_the_pipes_window_stops_pipe_and_plug_for_good():
    # fuzz 2071:4481: a full plug held by its face (Qp > F2), pipe and plug driven back, then
    # Q = T1 + F2 (the whole window of a pipe sliding forward over a held plug, to the last
    # bit): they decelerate together, stop, and stay at rest. At the stop the plug's need
    # reaches F2 (a breakaway ahead), but the pipe, its load at its window's edge, is held,
    # and the plug by its face: neither moves, so their contact cannot slide. It was set
    # sliding anyway, then the pair moved on together, and back, without end (more than
    # 100,000 events at one instant). Modes and the motion from the reference.
    r1, l1, tau1, tau2 = 0.035, 0.3497187137786887, 457022.5779824606, 1073779.5421750222
    T1, F2 = 2 * math.pi * (r1 + 0.003) * l1 * tau1, 2 * math.pi * r1 * l1 * tau2
    params = dict(L1=l1, L2=l1, R1=r1, rho2=6293.189231105356, tau1=tau1, tau2=tau2,
                  q_plug_face=28427600.33598276, J_shaft=4.373523469178697)
    segments = [(6.0e-3, -42799.88), (1.2e-3, T1 + F2)]
    times = np.linspace(0.0, 7.2e-3, 361)[1:]
    ref = simulate_damped(params, segments, times, False)
    model = build_model(params)
    out = model.sample(np.where(times <= 6.0e-3, -42799.88, T1 + F2), times)
    rest = times > max(t for t, _ in ref["events"])
    assert np.count_nonzero(rest) > 10 and model.modes()[-1] == (0, 0)
    for name in ("v_pipe", "v_plug"):
        assert np.all(out[name][rest] == 0.0) and np.all(ref[name][rest] == 0.0)
    assert np.all(out["u_pipe"][rest] == out["u_pipe"][-1])
    scale = np.max(np.abs(ref["v_pipe"]))
    assert np.max(np.abs(out["v_pipe"] - ref["v_pipe"])) <= 1e-9 * scale
