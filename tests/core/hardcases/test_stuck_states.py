"""Long runs: 10^6 steps after the motion has stopped.

A stuck body must stay at exactly zero velocity with its displacement bit-for-bit unchanged
(no creep, no drift, no NaN): the exact solver by 10^6 communication steps, fd and elastic by
10^6 internal steps (communication steps holding 1000 each). The stuck states come with a
load held on them: none, a push below the friction limit, and a pull.
"""
from __future__ import annotations

import numpy as np
import pytest
from hardcase_helpers import BASE, Q0, T0, model

N_STEPS = 1_000_000
STUCK = [  # (params, blow [N], held load after the motion [N], growth)
    ({"tau1": 2e4, "tau2": 1e4}, Q0, 0.0, False),                       # domain I, no load
    ({"tau1": 7e4, "tau2": 3.5e4}, -Q0, 0.9 * BASE.P1 * 7e4, False),    # pulled, then pushed
    ({"tau1": 2e4, "tau2": 1e4}, Q0, -0.99 * BASE.P1 * 2e4, True),      # model II, pulled
]
IDS = ["domain I, no load", "pulled back, pushed below the limit", "model II, pulled"]


def _stop(m, blow: float) -> None:
    """The blow, then coast until both bodies are at rest (checked)."""
    m.advance(blow, T0)
    for _ in range(100):
        m.advance(0.0, 0.05)
        o = m.outputs()
        if o.v_pipe == 0.0 and o.v_plug == 0.0:
            return
    raise AssertionError("the motion did not stop within 5 s")


@pytest.mark.parametrize("params, blow, hold, growth", STUCK, ids=IDS)
def test_exact_solver_stays_stuck_for_a_million_steps(params, blow, hold, growth):
    m = model("exact", params, growth)
    _stop(m, blow)
    rest, t_host = m.outputs(), m.time
    for k in range(N_STEPS):
        m.advance(hold, 1e-3)
        t_host += 1e-3              # the host's clock, summed the same way
        if k % 1000 == 999:
            o = m.outputs()
            assert (o.v_pipe, o.v_plug, o.u_pipe, o.u_plug, o.pipe_mode, o.plug_mode) == (
                0.0, 0.0, rest.u_pipe, rest.u_plug, 0, 0), (k, o)
    assert m.time == t_host
    assert np.isfinite(m.outputs()).all()


@pytest.mark.parametrize("params, blow, hold, growth", STUCK[:2], ids=IDS[:2])
def test_fd_stays_stuck_for_a_million_internal_steps(params, blow, hold, growth):
    m = model("fd", dict(params, dt=2e-4), growth)
    _stop(m, blow)
    rest = m.outputs()
    for _ in range(N_STEPS // 1000):
        m.advance(hold, 1000 * 2e-4)
        o = m.outputs()
        assert (o.v_pipe, o.v_plug, o.u_pipe, o.u_plug) == (0.0, 0.0, rest.u_pipe, rest.u_plug)
    assert np.isfinite(m.outputs()).all()


def test_elastic_rods_stay_stuck_for_a_million_internal_steps():
    """Every cell at rest, the locked-in axial forces unchanged, bit for bit."""
    m = model("elastic", {"tau1": 2e4, "tau2": 1e4, "dx": 0.1})
    _stop(m, Q0)
    rest = m.get_state()
    assert not rest["v1"].any() and not rest["v2"].any()
    h = 1000 * m.grid.h_max
    for _ in range(N_STEPS // 1000):
        m.advance(0.0, h)
    late = m.get_state()
    for name in ("v1", "v2", "N1", "N2", "u1", "u2"):
        np.testing.assert_array_equal(late[name], rest[name], err_msg=name)
    assert np.isfinite(m.outputs()).all()
