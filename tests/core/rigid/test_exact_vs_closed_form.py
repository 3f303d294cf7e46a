"""The exact solver against the independent closed form of model I (domains I-V, docs/corrections.md A)."""
import math

import numpy as np
import pytest
from rigid_helpers import drive

from pipeplug import build_model
from pipeplug_references import closed_form as cf

BASE = cf.Case()
TAU_STAR, GAMMA = BASE.tau_star, BASE.gamma
KEYS = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2",
        "F_outer": "F_outer", "F_inner": "F_inner", "W_input": "W_input",
        "W_friction": "W_friction"}


def _grid_points():
    """A dense (tau1, tau2) grid over all five domains, plus every boundary and the limits."""
    pts = [(a, b) for a in np.linspace(0, 1.1, 12) for b in np.linspace(0, 1.0, 12)]
    for b in np.linspace(0, 1.0 / GAMMA, 7):
        pts.append((GAMMA * b, b))                   # I/II, and III/IV above the I/III line
        if b <= 1.0 / GAMMA:
            pts.append((1.0 - GAMMA * b, b))         # I/III and II/IV
    pts += [(1.0, b) for b in (0.0, 0.3, 1.0)]       # V boundary
    pts += [(0.5, 0.5 / GAMMA), (0.0, 0.0), (0.3, 0.0), (0.0, 0.3), (1.0 / (GAMMA + 1),) * 2]
    return [(a * TAU_STAR, b * TAU_STAR) for a, b in pts]


def _compare(tau1, tau2, t_end=None, extra=(), jumps=()):
    """Compare on a grid plus ``extra`` times; forces are not compared exactly at ``jumps``
    (there the contract reports the force under the step's own Q, i.e. the left limit)."""
    case = cf.Case(tau1=tau1, tau2=tau2)
    stops = [s for s in cf.stop_times(case) if s is not None and math.isfinite(s)]
    t_end = t_end or min(1.2 * max(stops + [BASE.t0]), 2.0)
    times = np.union1d(np.linspace(t_end / 397, t_end, 397), [t for t in extra if t < t_end])
    got = drive(build_model({"tau1": tau1, "tau2": tau2}), [(0.0, case.t0, case.Q0)], times)
    ref = cf.solution(case, times)
    cond = 1.0 / (1.0 - tau1 / TAU_STAR) if tau1 < TAU_STAR else 1.0
    smooth = ~np.isin(times, jumps)
    for ours, theirs in KEYS.items():
        scale = max(np.abs(ref[theirs]).max(), 1e-300)
        keep = smooth if ours.startswith("F_") else slice(None)
        err = np.abs(got[ours] - ref[theirs])[keep].max() / scale
        assert err <= 1e-10 * cond, (ours, err, cf.domain(case))
    return cf.domain(case)


def test_dense_grid_covers_all_domains_and_agrees():
    domains = {_compare(a, b) for a, b in _grid_points()}
    assert domains == {"I", "II", "III", "IV", "V"}


@pytest.mark.parametrize("name", ["3", "4", "5", "6a"])
def test_figure_cases_agree_including_event_times(name):
    for case in cf.figure_cases()[name]:
        events = [t for t in cf.event_times(case).values() if t is not None and math.isfinite(t)]
        near = [t + d for t in events for d in (-1e-7, 0.0, 1e-7)]
        _compare(case.tau1, case.tau2, extra=near, jumps=events)


def test_load_edge_on_no_grid():
    # t0 off every sampling point: the step is split at the edge, the result stays exact.
    case = cf.Case(tau1=2e4, tau2=1e4, t0=0.0503217)
    times = np.linspace(0.0013, 0.3, 101)
    got = drive(build_model({"tau1": 2e4, "tau2": 1e4}), [(0.0, case.t0, case.Q0)], times)
    ref = cf.solution(case, times)
    assert np.abs(got["v_pipe"] - ref["V1"]).max() <= 1e-10 * np.abs(ref["V1"]).max()
