"""Hard cases checked event by event: simultaneous events, near-boundary switches, loads at
the friction limit, absent contacts, grazing, comm steps below the fd step, Courant 1.

Expected values come from the paper's formulas as corrected in docs/corrections.md (t1, t3 = t4 = t5
= 2 t1 on the I/II boundary, the 7.3 us and 27.8 us of docs/corrections.md C1/C2) or from hand
derivation (stated in each test).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hardcase_helpers import BASE, GAMMA, Q0, T0, TAU_STAR, model, record

from pipeplug_references import closed_form as cf

RIGID = ("exact", "fd")


def _t1(tau1: float, tau2: float) -> float:
    """End of the first slip phase, t1 = tau* t0 / (tau1 + gamma tau2) [s] (paper, eq. (7))."""
    return TAU_STAR * T0 / (tau1 + GAMMA * tau2)


def _modes_at(params: dict, times: list[float], solver: str = "exact"):
    """(pipe_mode, plug_mode, v_pipe, v_plug) at each of ``times`` under the paper's blow."""
    m = model(solver, params)
    found = []
    for t in times:
        if m.time < T0 < t:
            m.advance(Q0, T0 - m.time)
        m.advance(Q0 if t <= T0 else 0.0, t - m.time)
        o = m.outputs()
        found.append((o.pipe_mode, o.plug_mode, o.v_pipe, o.v_plug))
    return found


def test_pipe_stops_as_the_plug_sticks_on_the_I_II_boundary():
    """docs/corrections.md A7: on tau1 = gamma tau2, t3 = t4 = t5 = 2 t1: both contacts stick at once."""
    tau2 = 1e4
    tau1 = GAMMA * tau2
    t_stop = 2.0 * _t1(tau1, tau2)
    (before, after) = _modes_at({"tau1": tau1, "tau2": tau2},
                                [t_stop * (1 - 1e-6), t_stop * (1 + 1e-12)])
    assert before[0] == 1 and before[2] > 0.0 and before[3] > 0.0
    assert after == (0, 0, 0.0, 0.0)


@pytest.mark.parametrize("tau1, tau2, slip, after_t1, errata_gap", [
    (0.053e6, 0.0265e6, 1, -1, 7.3e-6),    # Fig. 4 curve 3, domain I: the plug overtakes
    (0.0, 0.0589e6, 1, 0, 27.8e-6),        # Fig. 5 curve 5, domain II: pipe and plug stick
])
def test_near_boundary_curves_switch_at_the_errata_times(tau1, tau2, slip, after_t1,
                                                         errata_gap):
    """docs/corrections.md C1/C2: the plug slips past t0 by 7.3 us (Fig. 4/3) or 27.8 us (Fig. 5/5)."""
    gap = _t1(tau1, tau2) - T0
    assert gap == pytest.approx(errata_gap, abs=0.05e-6)
    (early, late) = _modes_at({"tau1": tau1, "tau2": tau2},
                              [T0 + 0.5 * gap, T0 + 1.5 * gap])
    assert early[1] == slip and early[0] == 1
    assert late[1] == after_t1 and late[0] == 1


@pytest.mark.parametrize("solver", RIGID)
@pytest.mark.parametrize("tau1", [1e3, 2e4, TAU_STAR, 3e5])
def test_a_load_exactly_at_the_friction_limit_moves_nothing(solver, tau1):
    """Static limit = sliding limit: Q = F1 = P1 L1 tau1 exactly holds the pipe and plug."""
    f1 = BASE.P1 * BASE.L1 * tau1
    m = model(solver, {"tau1": tau1, "tau2": 1e4})
    out = record(m, [(f1, 1e-3)] * 200)
    assert not np.any(out["v_pipe"]) and not np.any(out["u_pipe"])
    assert not np.any(out["v_plug"]) and not np.any(out["pipe_mode"])
    np.testing.assert_allclose(out["F_outer"], -f1, rtol=1e-15)   # the static reaction


@pytest.mark.parametrize("solver", ("exact", "fd", "elastic"))
def test_tau1_far_above_tau_star_holds_everything(solver):
    """tau1 = 1000 tau*: the soil takes the whole blow; nothing else is nonzero."""
    out = record(model(solver, {"tau1": 1e3 * TAU_STAR}), [(Q0, 1e-3)] * 50 + [(0.0, 1e-3)] * 50)
    for name in ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_inner", "W_input", "W_friction",
                 "pipe_mode", "plug_mode"):
        assert not np.any(out[name]), name
    np.testing.assert_allclose(out["F_outer"], [-Q0] * 50 + [0.0] * 50, rtol=1e-15)


@pytest.mark.parametrize("solver", ("exact", "fd", "elastic"))
@pytest.mark.parametrize("params", [{"tau2": 0.0, "tau1": 2e4}, {"L2": 0.0, "tau1": 2e4},
                                    {"tau2": 0.0, "tau1": 0.0}])
def test_without_plug_coupling_the_plug_outputs_are_zero(solver, params):
    """Contract: with tau2 = 0 or L2 = 0 the plug is not simulated and its outputs are 0."""
    out = record(model(solver, params), [(Q0, 5e-3)] * 10 + [(0.0, 5e-3)] * 10)
    assert np.all(out["v_pipe"][:10] > 0.0)
    for name in ("v_plug", "u_plug", "F_inner", "plug_mode"):
        assert not np.any(out[name]), name


# Grazing: the pipe comes to rest at tb exactly as Q rises to F1, so velocity and
# acceleration reach zero together. Hand: from rest, Q0 during ta then 0, the pipe stops at
# tb = Q0 ta / F1 (one body; with a plug in domain II the pair stops at tau* t0 / tau1 =
# Q0 ta / F1 too). Static limit = sliding limit, so Q = F1 from tb on must keep it at rest.
GRAZING = [({"tau1": 2e4, "tau2": 0.0}, 0.01), ({"tau1": 2e4, "tau2": 2e4}, T0)]


@pytest.mark.parametrize("solver", RIGID)
@pytest.mark.parametrize("params, ta", GRAZING, ids=["pipe alone", "pipe and plug"])
@pytest.mark.parametrize("ulps", [-2, 0, 2])
def test_grazing_stop_under_a_load_at_the_limit_stays_at_rest(solver, params, ta, ulps):
    """An edge within 2 ulps of the stop is the stop: afterwards v = 0 exactly, no creep."""
    f1 = BASE.P1 * BASE.L1 * params["tau1"]
    tb = Q0 * ta / f1
    for _ in range(abs(ulps)):
        tb = math.nextafter(tb, math.copysign(math.inf, ulps))
    m = model(solver, params)
    m.advance(Q0, ta)
    m.advance(0.0, tb - ta)
    at_stop = m.outputs()
    late = record(m, [(f1, 1e-2)] * 1000)
    moving = np.flatnonzero(late["v_pipe"] != 0.0)
    assert moving.size == 0 and not np.any(late["pipe_mode"]), (
        f"still sliding after the grazing stop at tb = {tb!r} s: v_pipe = "
        f"{late['v_pipe'][-1]!r} m/s, pipe_mode = {late['pipe_mode'][-1]}, creep "
        f"{late['u_pipe'][-1] - at_stop.u_pipe!r} m in 10 s")
    assert late["u_pipe"][-1] == at_stop.u_pipe


def test_fd_communication_steps_shorter_than_dt_refine_the_scheme():
    """Contract: a step h < dt is one internal step of length h, so the error falls with h
    (first order). Reference: the closed form of model I (domain III)."""
    params = {"tau1": 7e4, "tau2": 3.5e4, "dt": 2e-4}
    case = cf.Case(tau1=7e4, tau2=3.5e4, Q0=Q0, t0=T0)
    errs = []
    for h in (1e-3, 1e-5):
        n = round(0.08 / h)
        fd = record(model("fd", params), [(Q0 if k < round(T0 / h) else 0.0, h) for k in range(n)])
        times = np.arange(1, n + 1) * h
        ref = cf.solution(case, times)
        errs.append(max(np.abs(fd["u_pipe"] - ref["U1"]).max(),
                        np.abs(fd["u_plug"] - ref["U2"]).max()))
    assert errs[1] < errs[0] / 10


def test_elastic_at_courant_1_has_no_odd_even_decoupling():
    """docs/corrections.md D6: the node-centred cross scheme at Courant 1 alternates 72.1 / 5.5 m/s at
    10 ms (tau2 = 0.01 MPa). Rigid model I (domain II, tau1 = 0): V1 = (Q0 - F2) t / M1."""
    m = model("elastic", {"dx": 0.01})
    h = m.grid.h_max
    m.advance(Q0, 0.01 - 20 * h)
    v = record(m, [(Q0, h)] * 20)["v_pipe"]
    rigid = (Q0 - BASE.F2) * 0.01 / BASE.M1
    assert np.abs(np.diff(v)).max() < 1e-3 * rigid
    assert np.abs(v - rigid).max() < 0.02 * rigid


@pytest.mark.parametrize("courant", [1.0, 0.5, 0.05])
def test_elastic_momentum_equals_the_impulse_at_any_courant_number(courant):
    """No friction: sum of cell momenta = integral of Q (the scheme's forces telescope), with
    the impulse the model holds for its next internal step when a step ends between two."""
    m = model("elastic", {"tau2": 0.0, "dx": 0.01, "courant": courant})
    cell_mass = BASE.rho1 * BASE.S1 * 0.01
    impulse = 0.0
    for q, h in [(Q0, 1.3e-5), (0.0, 7.1e-5), (-0.5 * Q0, 2e-5), (0.0, 4e-4)]:
        m.advance(q, h)
        impulse += q * h
        momentum = cell_mass * m.get_state()["v1"].sum() + m.clock.pending
        assert momentum == pytest.approx(impulse, rel=1e-12, abs=1e-12 * Q0 * 1e-5)
