"""Checks of the model I closed form against the paper's published values and against its own physics.

Published values: N. I. Aleksandrova, "Influence of Soil Plug on Pipe Ramming Process", section 3 and its
corrections (final displacements of the corrected displacement formulas, t6/t7, figure levels and domains,
peak pipe velocities of Fig. 6a). They are printed to the digits used as tolerances here.
"""

import ast
import inspect
import math
from dataclasses import replace

import numpy as np
import pytest

from pipeplug_references import closed_form as cf
from pipeplug_references.closed_form import (
    Case,
    domain,
    event_times,
    figure_cases,
    solution,
    stop_times,
)

MPA = 1.0e6
BASE = Case()
TAU_STAR, GAMMA = BASE.tau_star, BASE.gamma


def taus(tau1, tau2, **kw):
    """Base case with the two limit stresses (Pa) and optional other fields."""
    return replace(BASE, tau1=tau1, tau2=tau2, **kw)


def at(case, t):
    """Solution at one time, as floats."""
    return {k: float(v[0]) for k, v in solution(case, np.array([t])).items()}


def time_grid(case, n=4001, horizon=1.0):
    """Uniform grid on [0, T] merged with every finite switch time below T (phases then fill whole cells)."""
    finite = [x for x in stop_times(case) if math.isfinite(x)]
    end = 1.25 * max(finite + [case.t0]) if all(map(math.isfinite, stop_times(case))) else horizon
    events = [x for x in event_times(case).values() if x < end]
    return np.union1d(np.linspace(0.0, end, n), events)


# ---------------------------------------------------------------- published numbers
def test_base_case_derived_quantities():
    assert BASE.M1 == pytest.approx(5.3665, abs=5e-5)
    assert BASE.M2 == pytest.approx(6.9272, abs=5e-5)
    assert TAU_STAR == pytest.approx(96330.62, abs=5e-3)
    assert BASE.beta == pytest.approx(0.921053, abs=5e-7)
    assert GAMMA == pytest.approx(1.634586, abs=5e-7)
    assert TAU_STAR / (GAMMA + 1) == pytest.approx(36563.85, abs=5e-3)


@pytest.mark.parametrize(
    "tau1, tau2, dom, u1_end, u2_end",
    [
        (0.02, 0.01, "I", 13.4727, 5.5750),
        (0.02, 0.02, "II", 11.4254, None),
        (0.07, 0.035, "III", 0.8338, 0.9334),
        (0.065, 0.065, "IV", 1.1272, None),
    ],
)
def test_final_displacements_of_corrected_formulas(tau1, tau2, dom, u1_end, u2_end):
    case = taus(tau1 * MPA, tau2 * MPA)
    assert domain(case) == dom
    end = at(case, max(stop_times(case)) + 1.0)
    assert end["U1"] == pytest.approx(u1_end, abs=5e-5)
    if u2_end is not None:
        assert end["U2"] == pytest.approx(u2_end, abs=5e-5)


def test_domain_III_stop_times_t6_t7():
    case = taus(0.07 * MPA, 0.035 * MPA)
    ev = event_times(case)
    assert ev["t6"] == pytest.approx(0.065218, abs=5e-7)
    assert ev["t7"] == pytest.approx(0.073012, abs=5e-7)
    assert stop_times(case) == (ev["t6"], ev["t7"])


def test_figure_velocity_levels():
    figs = figure_cases()
    u_star = BASE.Q0 * BASE.t0 / BASE.M1
    assert u_star == pytest.approx(214.29, abs=5e-3)
    assert at(figs["6a"][0], 0.2)["V1"] == pytest.approx(214.29, abs=5e-3)
    for case in figs["5"]:  # tau1 = 0: the pair ends at Q0 t0 / (M1 + M2)
        assert at(case, 1.0)["V1"] == pytest.approx(93.54, abs=5e-3)
        assert at(case, 1.0)["V2"] == pytest.approx(93.54, abs=5e-3)
    # U** = Q0 t0 beta / (M2 (gamma + alpha)): the common velocity at t1 when tau1 = alpha tau2
    for _alpha, cases, level in ((2, figs["4"][1:3], 42.07), (1, figs["6a"][1:4], 58.04)):
        for case in cases:
            state = at(case, event_times(case)["t1"])
            assert state["V1"] == pytest.approx(level, abs=5e-3)
            assert state["V2"] == pytest.approx(level, abs=5e-3)


def test_figure_domains():
    expected = {
        "3": ["I", "I", "IV"],
        "4": ["II", "I", "I", "III"],
        "5": ["II"] * 5,
        "6a": ["II", "II", "II", "II", "IV", "IV"],
    }
    assert {k: [domain(c) for c in v] for k, v in figure_cases().items()} == expected
    assert figure_cases()["6a"][4].tau1 == pytest.approx(0.036564 * MPA, abs=0.5)


def test_near_boundary_figure_curves():
    # Fig. 4 curve 3 sits just inside domain I, Fig. 5 curve 5 just inside domain II
    assert 2 * TAU_STAR / (2 + GAMMA) == pytest.approx(0.0530077 * MPA, abs=0.05)
    assert event_times(figure_cases()["4"][2])["t1"] - BASE.t0 == pytest.approx(7.3e-6, abs=5e-8)
    assert TAU_STAR / GAMMA == pytest.approx(0.0589327 * MPA, abs=0.05)
    assert event_times(figure_cases()["5"][4])["t1"] - BASE.t0 == pytest.approx(27.8e-6, abs=5e-8)


def test_fig3_slip_to_stick_boundary():
    tau1 = TAU_STAR / (GAMMA + 1)
    assert tau1 / GAMMA == pytest.approx(0.02237 * MPA, abs=5.0)
    assert [domain(taus(tau1, tau2 * MPA)) for tau2 in (0.02236, 0.02238, 0.03)] == [
        "I",
        "II",
        "II",
    ]
    assert domain(taus(tau1, tau1 / GAMMA)) == "II"


def test_peak_pipe_velocity_fig6a():
    peaks = [solution(c, np.linspace(0.0, 0.4, 8001))["V1"].max() for c in figure_cases()["6a"]]
    assert peaks == pytest.approx([214.3, 192.9, 154.5, 94.6, 58.0, 30.4], abs=0.05)


# ---------------------------------------------------------------- limits stated by hand
def test_no_plug_is_a_single_block():
    case = taus(0.03 * MPA, 0.02 * MPA, L2=0.0)
    f1, m1, impulse = case.F1, case.M1, case.Q0 * case.t0
    stop = impulse / f1
    assert domain(case) == "I" and stop_times(case) == (pytest.approx(stop, rel=1e-14), 0.0)
    t = time_grid(case)
    sol = solution(case, t)
    assert np.allclose(
        sol["V1"], np.maximum(case.Q0 * np.minimum(t, case.t0) - f1 * t, 0) / m1, atol=1e-12
    )
    assert sol["U1"][-1] == pytest.approx(impulse * (stop - case.t0) / (2 * m1), rel=1e-13)
    for key in ("V2", "U2", "F_inner"):
        assert not sol[key].any()
    free = solution(taus(0.0, 0.02 * MPA, L2=0.0), np.array([0.5]))
    assert free["V1"][0] == pytest.approx(impulse / m1, rel=1e-14)


def test_frictionless_pipe_leaves_plug_behind():
    case = taus(0.0, 0.0)
    assert domain(case) == "II" and event_times(case)["t1"] == math.inf
    assert stop_times(case) == (math.inf, 0.0)
    sol = solution(case, np.array([0.02, 0.5]))
    assert sol["V1"] == pytest.approx(
        [case.Q0 * 0.02 / case.M1, case.Q0 * case.t0 / case.M1], rel=1e-14
    )
    assert not sol["V2"].any() and not sol["W_friction"].any()


def test_plug_without_inner_friction_stays_put():
    case = taus(0.02 * MPA, 0.0)
    ev = event_times(case)
    assert domain(case) == "I" and ev["t3"] == ev["t1"] == pytest.approx(
        TAU_STAR * case.t0 / case.tau1
    )
    assert stop_times(case) == (ev["t1"], 0.0)
    sol = solution(case, time_grid(case))
    assert not sol["V2"].any() and not sol["U2"].any()


def test_domain_V_holds_still_and_right_limits():
    case = taus(TAU_STAR, 0.01 * MPA)
    assert domain(case) == "V" and stop_times(case) == (0.0, 0.0)
    sol = solution(case, np.array([0.0, 0.01, case.t0, 0.1]))
    assert sol["F_outer"] == pytest.approx([-case.Q0, -case.Q0, 0.0, 0.0])
    for key in ("V1", "V2", "U1", "U2", "F_inner", "W_input", "W_friction"):
        assert not sol[key].any()
    domain3 = taus(0.07 * MPA, 0.035 * MPA)
    ev = event_times(domain3)
    assert at(domain3, domain3.t0)["F_inner"] == pytest.approx(
        domain3.F2
    )  # plug overtakes from t0 on
    assert at(domain3, ev["t6"])["F_outer"] == pytest.approx(
        -domain3.F2
    )  # pipe held by static friction


def test_stop_time_convention():
    for case in [
        taus(0.02 * MPA, 0.01 * MPA),
        taus(0.02 * MPA, 0.02 * MPA),
        taus(0.07 * MPA, 0.035 * MPA),
    ]:
        for key, stop in zip(("V1", "V2"), stop_times(case)):
            sol = solution(case, np.array([stop * (1 - 1e-6), stop, stop * 1.5]))
            assert sol[key][0] > 0 and sol[key][1] == 0 and sol[key][2] == 0


def test_rejects_bad_times_and_never_imports_core():
    with pytest.raises(ValueError):
        solution(BASE, np.array([-1.0]))
    tree = ast.parse(inspect.getsource(cf))
    roots = {
        a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names
    }
    roots |= {n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert roots <= {"__future__", "math", "dataclasses", "numpy"}


# ---------------------------------------------------------------- self-consistency
SAMPLE_CASES = {
    "I": taus(0.02 * MPA, 0.01 * MPA),
    "II": taus(0.02 * MPA, 0.02 * MPA),
    "III": taus(0.07 * MPA, 0.035 * MPA),
    "IV": taus(0.065 * MPA, 0.065 * MPA),
    "IV tau1=0": taus(0.0, 0.07 * MPA),
    "II tau1=0": taus(0.0, 0.01 * MPA),
    "I tau2=0": taus(0.03 * MPA, 0.0),
    "II no friction": taus(0.0, 0.0),
    "I no plug": taus(0.03 * MPA, 0.01 * MPA, L2=0.0),
    "II no plug": taus(0.0, 0.0, L2=0.0),
    "I short plug": taus(0.03 * MPA, 0.02 * MPA, L2=0.3),
    "I/II": taus(GAMMA * 0.01 * MPA, 0.01 * MPA),
    "III/IV": taus(0.06 * MPA, 0.06 * MPA / GAMMA),
    "I/III": taus(0.07 * MPA, (TAU_STAR - 0.07 * MPA) / GAMMA),
    "II/IV": taus(0.0, TAU_STAR / GAMMA),
    "corner": taus(TAU_STAR / 2, TAU_STAR / (2 * GAMMA)),
    "V": taus(1.2 * TAU_STAR, 0.01 * MPA),
}


@pytest.fixture(scope="module", params=sorted(SAMPLE_CASES))
def sampled(request):
    case = SAMPLE_CASES[request.param]
    t = time_grid(case)
    return case, t, solution(case, t)


def test_displacement_integrates_velocity(sampled):
    case, t, sol = sampled
    for v, u in (("V1", "U1"), ("V2", "U2")):
        trapezoid = np.concatenate(
            [[0.0], np.cumsum(0.5 * (sol[v][1:] + sol[v][:-1]) * np.diff(t))]
        )
        assert np.allclose(sol[u], trapezoid, rtol=1e-9, atol=1e-12), v  # V linear on every cell


def test_velocities_continuous_at_switches(sampled):
    case, _, _ = sampled
    eps, acc = (
        1e-9,
        (case.Q0 + case.F1 + case.F2) / case.M1 + (case.F2 / case.M2 if case.has_plug else 0),
    )
    for te in [x for x in event_times(case).values() if math.isfinite(x)]:
        sol = solution(case, np.array([max(te - eps, 0.0), te, te + eps]))
        for key in ("V1", "V2", "U1", "U2"):
            assert np.ptp(sol[key]) <= 2 * eps * acc * (1 + 300 * (key[0] == "U")) + 1e-12, (
                key,
                te,
            )


def test_force_balance_of_each_cell(sampled):
    case, t, sol = sampled
    dt = np.diff(t)
    keep = dt > 1e-3 * dt.max()  # cells cut tiny by a switch time lose digits
    pulse = np.where(t < case.t0, case.Q0, 0.0)[:-1]
    pipe = case.M1 * np.diff(sol["V1"]) / dt - (pulse + sol["F_outer"][:-1] + sol["F_inner"][:-1])
    plug = case.M2 * np.diff(sol["V2"]) / dt + sol["F_inner"][:-1]
    assert np.abs(pipe[keep]).max() <= 1e-6 * case.Q0
    assert np.abs(plug[keep]).max() <= 1e-6 * case.Q0


def test_coulomb_law(sampled):
    case, _, sol = sampled
    assert np.all(np.abs(sol["F_outer"]) <= case.F1 * (1 + 1e-12))
    assert np.all(np.abs(sol["F_inner"]) <= case.F2 * (1 + 1e-12))
    sliding = sol["V1"] > 1e-9
    assert np.allclose(sol["F_outer"][sliding], -case.F1, rtol=1e-12)
    rel = sol["V1"] - sol["V2"]
    slipping = np.abs(rel) > 1e-9
    assert np.allclose(sol["F_inner"][slipping], -case.F2 * np.sign(rel[slipping]), rtol=1e-12)
    assert np.all(sol["V1"] >= 0.0)


def test_energy_balance(sampled):
    case, _, sol = sampled
    kinetic = 0.5 * case.M1 * sol["V1"] ** 2 + 0.5 * case.M2 * sol["V2"] ** 2
    scale = max(sol["W_input"].max(), 1.0)
    assert np.allclose(sol["W_input"], kinetic + sol["W_friction"], rtol=0, atol=1e-11 * scale)
    assert np.all(np.diff(sol["W_friction"]) >= -1e-11 * scale)


# ---------------------------------------------------------------- the (tau1, tau2) plane
def test_dense_plane_covers_all_domains_without_nan():
    grid_t = np.linspace(0.0, 2.0, 201)
    seen = set()
    for tau1 in np.linspace(0.0, 1.1 * TAU_STAR, 23):
        for tau2 in np.linspace(0.0, 1.2 * TAU_STAR / GAMMA, 23):
            case = taus(tau1, tau2)
            seen.add(domain(case))
            sol = solution(case, grid_t)
            assert all(np.all(np.isfinite(v)) for v in sol.values()), (tau1, tau2)
            assert not any(math.isnan(x) for x in [*event_times(case).values(), *stop_times(case)])
            assert sol["V1"].min() >= 0.0
    assert seen == {"I", "II", "III", "IV", "V"}


def on_boundaries():
    """(name, tau1, tau2) on every domain boundary, at the two triple points and on the axes."""
    s = TAU_STAR
    pts = [("I/II", GAMMA * x * s / (2 * GAMMA), x * s / (2 * GAMMA)) for x in (0.1, 0.5, 0.9)]
    pts += [("III/IV", GAMMA * x * s / GAMMA, x * s / GAMMA) for x in (0.6, 0.8, 0.95)]
    pts += [("I/III", x * s, (1 - x) * s / GAMMA) for x in (0.6, 0.8, 0.99)]
    pts += [("II/IV", x * s, (1 - x) * s / GAMMA) for x in (0.0, 0.2, 0.45)]
    pts += [("V", s, x * s / GAMMA) for x in (0.0, 0.3, 2.0)]
    pts += [("I/II/III/IV", s / 2, s / (2 * GAMMA)), ("I/III/V", s, 0.0)]
    pts += [("tau1=0", 0.0, x * s / GAMMA) for x in (0.0, 0.3, 1.5)]
    pts += [("tau2=0", x * s, 0.0) for x in (0.3, 0.7)]
    return pts


@pytest.mark.parametrize(
    "name, tau1, tau2", on_boundaries(), ids=lambda v: v if isinstance(v, str) else ""
)
def test_continuity_across_boundaries(name, tau1, tau2):
    t = np.linspace(0.0, 1.5, 601)
    scale = {"V": BASE.Q0 * BASE.t0 / BASE.M1, "U": BASE.Q0 * BASE.t0 / BASE.M1 * 1.5}
    scale["W"] = BASE.Q0 * scale["U"]
    ref = solution(taus(tau1, tau2), t)
    for delta in (1e-5, 1e-8):
        for d1, d2 in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)):
            near = taus(tau1 + d1 * delta * TAU_STAR, tau2 + d2 * delta * TAU_STAR)
            if near.tau1 < 0 or near.tau2 < 0:
                continue
            sol = solution(near, t)
            for key in ("V1", "V2", "U1", "U2", "W_input", "W_friction"):
                gap = np.abs(sol[key] - ref[key]).max() / scale[key[0]]
                # friction limits move by <= 2 delta Q0, acting <= 1.5 s on a mass >= M1: gap <~ 60 delta
                assert gap <= 200 * delta, (name, domain(near), delta, key, gap)


def test_boundary_event_identities():
    t1 = lambda c: event_times(c)["t1"]  # noqa: E731
    on_12 = taus(GAMMA * 0.01 * MPA, 0.01 * MPA)
    assert domain(on_12) == "II" and event_times(on_12)["t5"] == pytest.approx(
        2 * t1(on_12), rel=1e-12
    )
    just_i = taus(on_12.tau1 * (1 + 1e-9), on_12.tau2)
    assert domain(just_i) == "I"
    assert event_times(just_i)["t3"] == pytest.approx(2 * t1(just_i), rel=1e-7)
    on_34 = taus(0.06 * MPA, 0.06 * MPA / GAMMA)
    just_iii = taus(on_34.tau1 * (1 + 1e-9), on_34.tau2)
    assert domain(on_34) == "IV" and domain(just_iii) == "III"
    ev = event_times(just_iii)
    assert ev["t6"] == pytest.approx(event_times(on_34)["t5"], rel=1e-7)
    assert ev["t7"] == pytest.approx(event_times(on_34)["t5"], rel=1e-7)
    for tau1 in (0.02 * MPA, 0.07 * MPA):  # just inside I / II near tau1 + gamma tau2 = tau*
        near = taus(tau1, (TAU_STAR - tau1) / GAMMA * (1 - 1e-9))
        assert domain(near) in ("I", "II") and t1(near) == pytest.approx(BASE.t0, rel=1e-8)
    within_tol = taus(GAMMA * 0.01 * MPA + 0.5e-12 * TAU_STAR, 0.01 * MPA)
    assert domain(within_tol) == "II"
