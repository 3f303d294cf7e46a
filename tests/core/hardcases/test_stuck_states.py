"""Stuck states are fixed points: one step maps the whole state to itself, bit for bit.

A step is a deterministic map of (state, Q, step length): a state that one step leaves
unchanged stays unchanged for any number of further steps of that kind, so a stuck body can
never creep, drift or become NaN. The stuck states come with a load held on them: none, a push
below the friction limit, and a pull. (This replaces running 10^6 steps and watching.)
"""
from __future__ import annotations

import numpy as np
import pytest
from hardcase_helpers import BASE, Q0, T0, model

STUCK = [  # (params, blow [N], held load after the motion [N], growth)
    ({"tau1": 2e4, "tau2": 1e4}, Q0, 0.0, False),                       # domain I, no load
    ({"tau1": 7e4, "tau2": 3.5e4}, -Q0, 0.9 * BASE.P1 * 7e4, False),    # pulled, then pushed
    ({"tau1": 2e4, "tau2": 1e4}, Q0, -0.99 * BASE.P1 * 2e4, True),      # model II, pulled
]
IDS = ["domain I, no load", "pulled back, pushed below the limit", "model II, pulled"]
#: state entries that only keep time or the event search's book (no physics)
BOOKKEEPING = {"time", "t0", "horizon"}


def _stop(m, blow: float) -> None:
    """The blow, then coast until both bodies are at rest (checked)."""
    m.advance(blow, T0)
    for _ in range(100):
        m.advance(0.0, 0.05)
        o = m.outputs()
        if o.v_pipe == 0.0 and o.v_plug == 0.0:
            return
    raise AssertionError("the motion did not stop within 5 s")


def _bits(state: dict) -> dict:
    return {k: np.asarray(v).tobytes() for k, v in state.items() if k not in BOOKKEEPING}


def _real_step(m, q: float, h: float) -> None:
    """One step of length ``h`` under ``q`` that never takes the at-rest shortcut (whose
    premise is what is tested here)."""
    if hasattr(m, "_kernel"):                                   # elastic: the kernel itself
        g, n = m.grid, m.steps_for(h)
        m._kernel(n, h / n, q, g.coef, m.v1, m.N1, m.v2, m.N2, g.cells1, m.u1, g.cells2, m.u2,
                  m.acc)
    elif hasattr(m, "_s"):                                      # fd: its internal steps
        n = max(1, round(h / m.dt_max))
        for _ in range(n):
            m._step(m._s, q, h / n)
    else:                                                       # exact: has no shortcut
        m.advance(q, h)


def _assert_fixed_point(m, hold: float, h: float) -> None:
    _real_step(m, hold, h)                  # the held load's static reactions settle in
    before = _bits(m.get_state())
    _real_step(m, hold, h)
    assert _bits(m.get_state()) == before
    o = m.outputs()
    assert (o.v_pipe, o.v_plug, o.pipe_mode, o.plug_mode) == (0.0, 0.0, 0, 0)
    assert np.isfinite(np.array(o, dtype=float)).all()


@pytest.mark.parametrize("params, blow, hold, growth", STUCK, ids=IDS)
@pytest.mark.parametrize("h", [1e-3, 0.25])
def test_exact_solver_stuck_state_is_a_fixed_point(params, blow, hold, growth, h):
    m = model("exact", params, growth)
    _stop(m, blow)
    _assert_fixed_point(m, hold, h)


@pytest.mark.parametrize("params, blow, hold, growth", STUCK, ids=IDS)
def test_fd_stuck_state_is_a_fixed_point_of_its_internal_steps(params, blow, hold, growth):
    m = model("fd", dict(params, dt=2e-4), growth)
    _stop(m, blow)
    _assert_fixed_point(m, hold, 1000 * 2e-4)


def test_elastic_rods_at_rest_are_a_fixed_point():
    """Every cell at rest, the locked-in axial forces held by friction: unchanged, bit for bit,
    and the model says so (at_rest), which lets later steps under Q = 0 cost nothing."""
    m = model("elastic", {"tau1": 2e4, "tau2": 1e4, "dx": 0.1})
    _stop(m, Q0)
    assert np.abs(m.get_state()["N1"]).max() > 0.0        # stresses are locked in
    _assert_fixed_point(m, 0.0, m.clock.h)
    m._rest = None                          # the fields were stepped behind the model's back
    assert m.at_rest() and m.outputs().at_rest
