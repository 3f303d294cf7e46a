"""Exact rigid solver: values from docs/corrections.md, energy to round-off, grid independence, state."""

import numpy as np
import pytest

from pipeplug import build_model
from pipeplug.params import Params

Q0, T0 = 23000.0, 0.05
PULSE = [(0.0, T0, Q0)]
TAU_STAR = Q0 / Params().P1          # Pa


def _final(params, options=None, t_end=0.3):
    m = build_model(params, options or {})
    m.advance(Q0, T0)
    m.advance(0.0, t_end - T0)
    return m.outputs()


@pytest.mark.parametrize("tau1, tau2, U1, U2", [
    (2e4, 1e4, 13.4727, 5.5750),       # domain I
    (2e4, 2e4, 11.4254, None),         # domain II
    (7e4, 3.5e4, 0.8338, 0.9334),      # domain III
    (6.5e4, 6.5e4, 1.1272, None)])     # domain IV
def test_final_displacements_of_errata_a1(tau1, tau2, U1, U2):
    out = _final({"tau1": tau1, "tau2": tau2})
    assert out.v_pipe == 0.0 and out.v_plug == 0.0 and out.pipe_mode == 0
    assert out.u_pipe == pytest.approx(U1, abs=5e-5)
    if U2 is not None:
        assert out.u_plug == pytest.approx(U2, abs=5e-5)


def test_errata_a2_stop_times_of_domain_iii():
    m = build_model({"tau1": 7e4, "tau2": 3.5e4})
    m.advance(Q0, T0)
    m.advance(0.0, 0.065218 - 2e-6 - T0)
    assert m.outputs().v_pipe > 0
    m.advance(0.0, 4e-6)
    assert m.outputs().v_pipe == 0.0 and m.outputs().v_plug > 0
    m.advance(0.0, 0.073012 + 2e-6 - m.time)
    assert m.outputs().v_plug == 0.0


TAU_CAPPED = [0.0, 5e3, 14e3, 28e3, None, 65e3]
PEAK_CAPPED = [214.3, 196.2, 164.2, 116.0, 88.0, 59.0]   # docs/corrections.md C8, model II, min(U1, L1)


@pytest.mark.parametrize("tau, peak", list(zip(TAU_CAPPED, PEAK_CAPPED)))
def test_model_ii_peak_velocities_of_errata_c8(tau, peak):
    p = Params()
    gamma = p.P2 / p.P1 * (1 + p.M1 / p.M2)
    tau = TAU_STAR / (gamma + 1) if tau is None else tau
    m = build_model({"tau1": tau, "tau2": tau}, {"contact_growth": True})
    peaks = []
    for i in range(200):
        m.advance(Q0 if i < 100 else 0.0, T0 / 100)
        peaks.append(m.outputs().v_pipe)
    assert max(peaks) == pytest.approx(peak, abs=0.051)


def _random_cases(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        tau1, tau2 = rng.uniform(0, 1.2 * TAU_STAR, 2) * (rng.random(2) > 0.15)
        q = rng.normal(0, Q0, 6)
        h = rng.uniform(1e-3, 3e-2, 6)
        yield dict(tau1=tau1, tau2=tau2, L2=rng.choice([0.0, 0.5, 1.0])), bool(rng.random() < 0.5), q, h


@pytest.mark.parametrize("case", list(_random_cases(40, 11)))
def test_energy_balance_to_round_off_and_friction_work_grows(case):
    params, growth, q, h = case
    m = build_model(params, {"contact_growth": growth})
    p = Params().with_(**params)
    last_wf, scale = 0.0, 1.0
    for qi, hi in zip(q, h):
        m.advance(float(qi), float(hi))
        o = m.outputs()
        ke = 0.5 * p.M1 * o.v_pipe ** 2 + (0.5 * p.M2 * o.v_plug ** 2 if p.has_plug else 0.0)
        scale = max(scale, abs(o.W_input), o.W_friction)
        assert abs(o.W_input - ke - o.W_friction) <= 1e-12 * scale
        assert o.W_friction >= last_wf - 1e-13 * scale
        last_wf = o.W_friction
        assert abs(o.F_outer) <= p.P1 * p.L1 * p.tau1 * (1 + 1e-12)
        assert abs(o.F_inner) <= p.F2 * (1 + 1e-12)


def _sample(params, options, grid, t_load_edges):
    """Outputs at 0.01 s marks, advancing with communication points ``grid``."""
    m = build_model(params, options)
    marks = np.round(np.arange(1, 21) * 0.01, 12)
    points = np.unique(np.concatenate([grid, marks, t_load_edges]))
    points = points[points <= marks[-1]]
    wanted = set(marks.tolist())
    out = []
    for t in points:
        m.advance(Q0 if 0.5 * (m.time + t) < T0 else -0.3 * Q0 if t > 0.15 else 0.0, t - m.time)
        if t in wanted:
            out.append(m.outputs()[:8])
    return np.array(out)


@pytest.mark.parametrize("options", [{}, {"contact_growth": True}])
def test_outputs_do_not_depend_on_the_communication_grid(options):
    params = {"tau1": 3e4, "tau2": 1.5e4}
    edges = [T0, 0.15]
    coarse = _sample(params, options, np.array([0.2]), edges)
    fine = _sample(params, options, np.arange(1, 2001) * 1e-4, edges)
    rng = np.random.default_rng(5)
    irregular = _sample(params, options, np.sort(rng.uniform(0, 0.2, 333)), edges)
    scale = np.abs(fine).max(axis=0) + 1e-300
    assert np.all(np.abs(coarse - fine) <= 1e-12 * scale)
    assert np.all(np.abs(irregular - fine) <= 1e-12 * scale)


def test_pipe_pulled_back_slides_backward_then_sticks():
    # Pipe alone (tau2 = 0): independent derivation with constant accelerations.
    p = Params(tau1=2e4, tau2=0.0)
    F1, M1 = p.F1, p.M1
    m = build_model({"tau1": 2e4, "tau2": 0.0})
    m.advance(-2.0 * F1, 0.01)                   # |Q| > F1: backward, a = -(2F1 - F1)/M1
    o = m.outputs()
    assert o.pipe_mode == -1 and o.v_pipe == pytest.approx(-F1 / M1 * 0.01, rel=1e-14)
    assert o.F_outer == F1
    m.advance(0.0, 0.02)                          # friction alone stops it after 0.01 s
    o = m.outputs()
    assert o.v_pipe == 0.0 and o.pipe_mode == 0
    assert o.u_pipe == pytest.approx(-F1 / M1 * 0.01 ** 2, rel=1e-13)   # two triangles
    m.advance(-0.999 * F1, 1.0)                    # below the limit: stays exactly stuck
    assert m.outputs().v_pipe == 0.0 and m.outputs().F_outer == pytest.approx(0.999 * F1)


def test_state_restore_twice_continues_bit_identically():
    m = build_model({"tau1": 3e4, "tau2": 1.5e4}, {"contact_growth": True})
    m.advance(Q0, 0.0301)
    saved = m.get_state()
    runs = []
    for _ in range(2):
        m.set_state(saved)
        for q, h in [(Q0, 0.0199), (0.0, 0.07), (-Q0, 0.013)]:
            m.advance(q, h)
        runs.append(tuple(m.outputs()))
    assert runs[0] == runs[1]
    fresh = build_model({"tau1": 3e4, "tau2": 1.5e4}, {"contact_growth": True})
    fresh.set_state(saved)
    for q, h in [(Q0, 0.0199), (0.0, 0.07), (-Q0, 0.013)]:
        fresh.advance(q, h)
    assert tuple(fresh.outputs()) == runs[0]


def test_no_plug_means_plug_outputs_are_zero():
    for params in ({"tau2": 0.0}, {"L2": 0.0}):
        o = _final(params)
        assert (o.v_plug, o.u_plug, o.F_inner, o.plug_mode) == (0.0, 0.0, 0.0, 0)
        assert o.v_pipe == pytest.approx(Q0 * T0 / Params().M1, rel=1e-14)   # tau1 = 0: free


def test_pulse_train_next_blow_arrives_while_moving():
    # tau1 = 0, tau2 = 0: each blow adds Q0 t0 / M1 to the velocity exactly.
    m = build_model({"tau2": 0.0})
    for _ in range(3):
        m.advance(Q0, 0.01)
        m.advance(0.0, 0.005)
    assert m.outputs().v_pipe == pytest.approx(3 * Q0 * 0.01 / Params().M1, rel=1e-14)


def _run_velocities(tau1, tau2, t_end=0.4, n=400):
    m = build_model({"tau1": tau1, "tau2": tau2})
    first = m.sample(Q0, np.linspace(T0 / 50, T0, 50))
    rest = m.sample(0.0, np.linspace(T0 + (t_end - T0) / n, t_end, n))
    return (np.concatenate([first["v_pipe"], rest["v_pipe"]]),
            np.concatenate([first["v_plug"], rest["v_plug"]]))


@pytest.mark.parametrize("tau2", [0.01e6, 0.02e6, 0.03e6, 0.05e6, 0.0589e6])
def test_fig5_all_curves_reach_the_common_level_u_star(tau2):
    # docs/corrections.md C4: with tau1 = 0 pipe and plug end at Q0 t0 / (M1 + M2) = 93.54 m/s.
    v1, v2 = _run_velocities(0.0, tau2)
    assert v1[-1] == pytest.approx(93.54, abs=0.005) and v2[-1] == pytest.approx(v1[-1])


@pytest.mark.parametrize("ratio, level, taus", [(2.0, 42.07, [0.02e6, 0.053e6]),
                                                (1.0, 58.04, [0.005e6, 0.014e6, 0.028e6])])
def test_fig4_and_fig6a_velocities_level_at_u_double_star(ratio, level, taus):
    # docs/corrections.md C4: when the relative velocity first vanishes (t1 = tau* t0 / (tau1 + gamma
    # tau2), section 1), both bodies move at U** whatever tau1 = alpha tau2 is.
    p = Params()
    gamma = p.P2 / p.P1 * (1 + p.M1 / p.M2)
    for tau1 in taus:
        tau2 = tau1 / ratio
        t1 = TAU_STAR * T0 / (tau1 + gamma * tau2)
        m = build_model({"tau1": tau1, "tau2": tau2})
        m.advance(Q0, T0)
        m.advance(0.0, t1 - T0)
        o = m.outputs()
        assert o.v_pipe == pytest.approx(level, abs=0.005)
        assert o.v_plug == pytest.approx(o.v_pipe, abs=1e-9 * level)


@pytest.mark.parametrize("tau1, tau2, domain, expected", [
    (2e4, 1e4, "I", ((1, 1), (1, -1), (0, -1), (0, 0))),
    (2e4, 2e4, "II", ((1, 1), (1, 0), (0, 0))),
    (7e4, 3.5e4, "III", ((1, 0), (1, -1), (0, -1), (0, 0))),
    (6.5e4, 6.5e4, "IV", ((1, 0), (0, 0))),
    (1e5, 1e4, "V", ((0, 0),)),
])
@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_modes_are_the_paper_s_domain_sequences(tau1, tau2, domain, expected, compiled):
    """The paper's section 1, rectangular pulse 23 kN for 50 ms: I both slide, the plug overtakes
    after t1, the pipe stops, then the plug; II both slide, stick, stop together; III move
    together, the plug overtakes after t0, the pipe stops, then the plug; IV together to the
    stop; V nothing moves. (pipe_mode, plug_mode) = (sign U1', sign(U1' - U2'))."""
    m = build_model({"tau1": tau1, "tau2": tau2}, compiled=compiled)
    m.advance(23e3, 0.05)
    m.advance(0.0, 1.0)
    assert m.modes() == expected, domain
    restored = build_model({"tau1": tau1, "tau2": tau2}, compiled=compiled)
    restored.set_state(m.get_state())
    assert restored.modes() == expected


@pytest.mark.parametrize("params, options", [
    ({}, {}), ({}, {"contact_growth": True}), ({}, {"plug_growth": True}),
    ({"ram_mass": 10.0, "cushion_stiffness": 1e8}, {}), ({"J_shaft": 0.1}, {}),
    ({}, {"solver": "fd"}), ({}, {"elastic": True})])
def test_a_fresh_model_of_every_kind_is_at_rest_and_a_step_under_no_load_keeps_it(params,
                                                                                    options):
    """build_model gives a model at rest at t = 0 (every kind alike): at_rest is true before
    any step, and a step under Q = 0 changes no output."""
    m = build_model(dict(params, tau1=2e4), options)
    before = m.outputs()
    assert m.at_rest() and before.at_rest
    m.advance(0.0, 1e-3)
    assert m.at_rest() and m.outputs() == before
