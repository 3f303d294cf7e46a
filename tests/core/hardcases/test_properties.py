"""Property-based tests (hypothesis) over physical parameter ranges and load histories.

Parameters span both friction limits from 0 to 1.2 tau*, plugs from absent to as long as the
pipe, plug densities over six decades, model I and II; loads are random piecewise-constant
histories (pushes and pulls), then a coast. Examples are derandomized (reproducible in CI).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hardcase_helpers import BASE, Q0, T0, TAU_STAR, all_finite, kinetic_energy, model
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pipeplug import Params

SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])

_taus = st.one_of(st.just(0.0), st.floats(0.0, 1.2 * TAU_STAR))
PARAMS = st.fixed_dictionaries({
    "tau1": _taus, "tau2": _taus, "L2": st.sampled_from([0.0, 0.25, 0.5, 1.0]),
    "rho2": st.floats(-3.0, 3.0).map(lambda e: 1800.0 * 10.0 ** e)})
GROWTH = st.booleans()


def loads(min_q: float) -> st.SearchStrategy:
    """Piecewise-constant loads [(Q [N], h [s]), ...] followed by a coast of 0.2 s."""
    step = st.tuples(st.floats(min_q, 5e4), st.floats(1e-4, 3e-2))
    return st.lists(step, min_size=1, max_size=6).map(lambda s: s + [(0.0, 0.1)] * 2)


def _run(m, steps):
    """Advance through ``steps``; the outputs after each."""
    outs = []
    for q, h in steps:
        m.advance(q, h)
        outs.append(m.outputs())
    return outs


@settings(max_examples=80, **SETTINGS)
@given(PARAMS, GROWTH, loads(-5e4), st.sampled_from(["exact", "fd", "elastic"]))
def test_outputs_stay_finite_and_friction_work_never_decreases(params, growth, steps, solver):
    if solver == "elastic":
        params = dict(params, dx=0.05)
    outs = _run(model(solver, params, growth), steps)
    assert all(all_finite(o) for o in outs)
    w_fr = [o.W_friction for o in outs]
    assert w_fr[0] >= 0.0 and all(b >= a for a, b in zip(w_fr, w_fr[1:])), w_fr


@settings(max_examples=200, **SETTINGS)
@given(PARAMS, GROWTH, loads(-5e4))
def test_exact_solver_balances_energy_to_round_off(params, growth, steps):
    m = model("exact", params, growth)
    for o in _run(m, steps):
        ke = kinetic_energy(m, o)
        scale = abs(o.W_input) + o.W_friction + ke + 1e-300
        assert abs(o.W_input - ke - o.W_friction) <= 1e-11 * scale


@settings(max_examples=100, **SETTINGS)
@given(PARAMS, GROWTH, loads(-5e4), st.sampled_from([2e-4, 1e-3]))
def test_fd_energy_defect_is_nonnegative_and_bounded_by_its_step(params, growth, steps, dt):
    """W_input - W_friction - KE = sum M dv^2 / 2 over internal steps (the scheme's own
    dissipation), so 0 <= defect <= sum n tau^2 ((|Q| + F1 + F2)^2/(2 M1) + F2^2/(2 M2))
    with |dv1| <= tau (|Q| + F1 + F2)/M1 and |dv2| <= tau F2/M2 (hand derivation)."""
    p = Params().with_(**params)
    m = model("fd", dict(params, dt=dt), growth)
    f2 = p.F2 if p.has_plug else 0.0
    bound = 0.0
    for (q, h), o in zip(steps, _run(m, steps)):
        n = max(1, math.ceil(h / dt - 1e-9))
        tau = h / n
        bound += n * tau ** 2 * ((abs(q) + p.F1 + f2) ** 2 / (2 * p.M1)
                                 + (f2 ** 2 / (2 * p.M2) if p.has_plug else 0.0))
        defect = o.W_input - o.W_friction - kinetic_energy(m, o)
        scale = abs(o.W_input) + o.W_friction + 1e-300
        assert -1e-11 * scale <= defect <= bound * (1 + 1e-9) + 1e-11 * scale
        assert abs(o.W_numerical - defect) <= 1e-11 * scale      # the model books it


@settings(max_examples=150, **SETTINGS)
@given(PARAMS, GROWTH, loads(0.0), st.sampled_from(["exact", "fd"]))
def test_a_rigid_pipe_never_moves_backward_under_a_pushing_load(params, growth, steps, solver):
    outs = _run(model(solver, params, growth), steps)
    u = [o.u_pipe for o in outs]
    assert min(o.v_pipe for o in outs) >= 0.0
    assert all(b >= a for a, b in zip(u, u[1:]))


@settings(max_examples=150, **SETTINGS)
@given(PARAMS, GROWTH, loads(0.0), st.floats(0.0, 1.0))
def test_more_outer_friction_never_gives_more_penetration(params, growth, steps, share):
    """Same load, tau1 raised: the pipe's front ends no further in (exact solver)."""
    more = dict(params, tau1=params["tau1"] + share * (1.2 * TAU_STAR - params["tau1"]))
    u_less = _run(model("exact", params, growth), steps)[-1].u_pipe
    u_more = _run(model("exact", more, growth), steps)[-1].u_pipe
    assert u_more <= u_less + 1e-12 * abs(u_less)


@pytest.mark.parametrize("solver", ["exact", "fd", "elastic"])
def test_more_plug_friction_can_give_more_penetration(solver):
    """Counterexample to monotonicity in tau2, tau1 = 0.07 MPa, the paper's blow:
    tau2 = 0.035 MPa (domain III): U1(inf) = 0.8338 m (docs/corrections.md A1);
    tau2 = 0.065 MPa (domain IV, stuck together throughout; hand: the pair gains the
    impulse (Q0 - F1) t0 and coasts against F1): U1(inf) = Q0 (Q0 - F1) t0^2 / (2 (M1+M2) F1)
    = 0.8797 m. More plug friction keeps the plug's momentum with the pipe, so it goes further."""
    f1 = BASE.P1 * BASE.L1 * 7e4
    hand = Q0 * (Q0 - f1) * T0 ** 2 / (2 * (BASE.M1 + BASE.M2) * f1)
    final = {}
    for tau2 in (3.5e4, 6.5e4):
        m = model(solver, {"tau1": 7e4, "tau2": tau2})
        m.advance(Q0, T0)
        m.advance(0.0, 0.1)
        final[tau2] = m.outputs().u_pipe
    if solver == "exact":
        assert final[3.5e4] == pytest.approx(0.8338, abs=1e-4)
        assert final[6.5e4] == pytest.approx(hand, rel=1e-12)
    assert final[6.5e4] > final[3.5e4] + 0.03


@settings(max_examples=50, **SETTINGS)
@given(PARAMS, GROWTH, loads(-5e4))
def test_fd_tends_to_the_exact_solver_as_dt_shrinks(params, growth, steps):
    """Sixteen times smaller dt: at least half the error (first order would give 1/16)."""
    exact = _run(model("exact", params, growth), steps)
    errs = []
    for dt in (2e-4, 2e-4 / 16):
        fd = _run(model("fd", dict(params, dt=dt), growth), steps)
        errs.append(max(max(abs(a.u_pipe - b.u_pipe), abs(a.u_plug - b.u_plug),
                            abs(a.v_pipe - b.v_pipe) * 1e-3, abs(a.v_plug - b.v_plug) * 1e-3)
                        for a, b in zip(fd, exact)))
    scale = max(max(abs(o.u_pipe), abs(o.u_plug), 1e-3 * abs(o.v_pipe)) for o in exact)
    assert errs[1] <= 0.5 * errs[0] + 1e-12 * scale, errs
    assert np.isfinite(errs).all()
