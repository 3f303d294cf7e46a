"""Regressions of the rigid solvers, one per root cause found by differential fuzzing
(``pipeplug fuzz``; all model II but the load at the limit, which is any pipe without a plug).

Each case came from random load histories; the checks need no reference solution: the
results must not depend on the communication grid, energy must balance, a plug held by static
friction must never need more than its limit, a load at a friction limit must not move a
body, and the solver must finish. Every check runs on both paths of the exact solver: plain
Python and compiled (the same functions; both plain without numba).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug import OUTPUT_NAMES, Params, build_model, jit
from pipeplug.options import Options
from pipeplug.rigid import motion, pieces, record, stepping
from pipeplug.rigid.exact import RigidExact
from pipeplug.rigid.motion import state, time_to_rest
from pipeplug.rigid.pieces import pipe_of


@pytest.fixture(params=[False, True], ids=["python", "compiled"])
def compiled(request) -> bool:
    """The exact solver's path: plain Python, or compiled by numba (when it is enabled)."""
    return request.param


def _run(params, segments, grid, compiled):
    """Outputs after each step of ``grid`` under piecewise-constant ``segments`` (dur, Q)."""
    model = build_model(params, {"contact_growth": True}, compiled=compiled)
    edges = np.cumsum([0.0] + [d for d, _ in segments])
    rows = []
    for a, b in zip(grid[:-1], grid[1:]):
        k = int(np.searchsorted(edges, a, side="right")) - 1
        model.advance(segments[k][1] if k < len(segments) else 0.0, b - a)
        rows.append(model.outputs())
    return np.array(rows, dtype=float)


def _grids(segments, T, counts=(3, 11, 101, 200, 2001)):
    """Uniform grids of ``counts`` points and one irregular grid, all holding the load edges."""
    edges = np.cumsum([0.0] + [d for d, _ in segments])
    irregular = np.sort(np.random.default_rng(1).uniform(0.0, T, 300))
    return [np.union1d(grid, np.r_[0.0, T, edges[edges < T]])
            for grid in [np.linspace(0.0, T, n) for n in counts] + [irregular]]


def _check_grid_independent_and_balanced(params, segments, T, compiled):
    p = Params(**params)
    M2 = p.M2 if p.has_plug else 0.0
    finals = []
    for grid in _grids(segments, T):
        out = _run(params, segments, grid, compiled)
        finals.append(out[-1])
        kinetic = 0.5 * p.M1 * out[:, 0] ** 2 + 0.5 * M2 * out[:, 1] ** 2
        work = np.max(np.abs(out[:, 6]))
        assert np.max(np.abs(out[:, 6] - kinetic - out[:, 7])) <= 1e-12 * work
        assert np.all(np.diff(out[:, 7]) >= -1e-15 * work)          # friction work
        if p.has_plug:                                              # static plug force
            assert np.max(np.abs(out[:, 5])) <= p.F2 * (1.0 + 1e-12)
    finals = np.array(finals)
    scale = np.max(np.abs(finals), axis=0) + 1e-300
    assert np.max(np.abs(finals - finals[0]) / scale) <= 1e-12
    return finals[0]


ISSUE_CASE = dict(tau1=34556.19387290386, tau2=1400.460541181589, L2=0.5723765091554823)
ISSUE_BLOW = 0.015541713314679568                   # s, 23 kN


def test_root_search_returns_the_converged_root_not_the_far_bracket_end(compiled):
    """The pipe's harmonic piece after the issue's blow crosses L1 = 1 m at 8.74 ms; searched
    up to its stop (32 ms), Newton converged from the left, the bracket's right end never
    moved, and the stop time was returned as the crossing."""
    model = build_model(ISSUE_CASE, {"contact_growth": True}, compiled=compiled)
    model.advance(23e3, ISSUE_BLOW)
    model.advance(0.0, 1e-9)
    pipe = tuple(map(float, pipe_of(model._st)))     # the pipe's motion after the blow
    t_stop = time_to_rest(pipe, 1)
    search = jit.compiled(motion.time_to_position) if compiled else motion.time_to_position
    t_cross = search(pipe, 1.0, t_stop, 0.0)
    assert t_cross < 0.5 * t_stop
    assert abs(state(pipe, t_cross)[0] - 1.0) <= 4e-16
    assert state(pipe, t_cross * (1.0 - 1e-12))[0] < 1.0 < state(pipe, t_cross * (1 + 1e-12))[0]


def test_pipe_reaching_L1_late_in_a_long_step(compiled):
    """The issue's reproduction: the L1 crossing was found at the search horizon (a step end),
    so the result depended on the grid (u_pipe 1.65, 1.31, 1.85, 1.59 m; energy off by up to
    1712 J of 11453 J)."""
    final = _check_grid_independent_and_balanced(ISSUE_CASE, [(ISSUE_BLOW, 23e3)],
                                                 0.173862112150763, compiled)
    assert final[0] == 0.0 and final[1] == 0.0                  # all at rest by then
    assert abs(final[6] - final[7]) <= 1e-12 * final[6]        # all input work dissipated


def test_segment_event_is_checked_not_hidden(compiled):
    """Snapping onto L1 must be round-off; a late event is raised, not teleported over."""
    model = RigidExact(Params(tau1=3e4), Options(contact_growth=True), compiled)
    model.advance(23e3, 1e-3)
    st = model._st
    stepping._search(st, model._par, 1.0)          # the piece's events up to 1 s: L1 first
    assert st[record.END] == 1.0 and st[record.LABELS] == pieces.SEGMENT
    st[record.U1] += 0.3           # the piece's origin moved: its event is now far off L1
    with pytest.raises(RuntimeError, match="segment event"):
        model.advance(23e3, 1.0)


def test_a_step_beyond_float_range_is_an_overflow_not_a_missed_event(compiled):
    """23 kN for 1e300 s takes the pipe past any float: an OverflowError (which the FMU refuses
    naming Q and the step), never a RuntimeError about a segment event."""
    model = RigidExact(Params(tau1=2e4, tau2=1e4), Options(), compiled)
    with pytest.raises(OverflowError, match="U1 = inf m"):
        model.advance(23e3, 1e300)


def test_breakaway_does_not_stick_again_at_once(compiled):
    """After a breakaway the relative velocity and acceleration are both zero; round-off in
    the relative acceleration made the next piece find a stick at once on some grids, and the
    plug was then held beyond its friction limit (grid dependence 1.3e-4 of scale)."""
    params = dict(tau1=158087.93191153646, tau2=169423.08420902485, L2=0.13494951527890708,
                  rho2=6223.031382415773)
    segments = [(0.06478816013262927, 14108.707425982284), (5.552727538914102e-05,
                21476.29482161411), (0.011509042108123193, -20882.509360811506),
                (0.09471089864152296, 55736.36843426553), (0.0006500066971955544,
                49920.33188276153)]
    _check_grid_independent_and_balanced(params, segments, 0.17750710266488676, compiled)


def test_breakaway_and_stick_do_not_alternate_forever(compiled):
    """A spurious stick after a breakaway, then a breakaway at once, and so on: more than
    100,000 events in one step. The plug must break away once and slide."""
    params = dict(tau1=312816.07075152657, tau2=131513.1861968109, L2=0.10843096181261502,
                  rho2=773.6240846443366)
    segments = [(4.7005432887188357e-05, 1719.3606060085003),
                (0.03364954476962969, -37344.14545231719), (0.04830736923188498,
                                                            37344.14545231719)]
    final = _check_grid_independent_and_balanced(params, segments, 0.308848100639877, compiled)
    assert math.isfinite(final[0])


def test_crossing_sooner_than_time_can_resolve_is_taken_at_once(compiled):
    """A load of 2.6e-254 N leaves the pipe 1e-262 m in; pulled back at -1 N it recrosses 0
    after about 1e-131 s, a nearly double root that Newton approaches only linearly. The search
    stops at the resolution of absolute time instead of returning an event 3e-14 s late (which
    the segment check rejected). Model II with tau1 = 1 Pa; derived: the pipe then moves as
    M1 U'' = -1 N, free of the soil (no contact behind its start)."""
    model = build_model({"tau1": 1.0, "tau2": 0.0, "L2": 0.0}, {"contact_growth": True},
                        compiled=compiled)
    model.advance(2.648521645394783e-254, 0.015625)
    model.advance(-1.0, 0.015625)
    out = model.outputs()
    m1 = Params().M1
    assert out.v_pipe == pytest.approx(-0.015625 / m1, rel=1e-12)
    assert out.u_pipe == pytest.approx(-0.5 * 0.015625 ** 2 / m1, rel=1e-12)


def test_nearly_no_outer_friction_keeps_the_closed_form_accurate(compiled):
    """tau1 = 2.4e-295 Pa: the harmonic piece's C = 2 sin(w t/2)^2 / k underflowed into
    subnormal numbers (k ~ 1e-296 1/s^2) and the pipe crossed its start 1e-28 m off. The Taylor
    series in k t^2 is used there; derived: the pipe then moves as M1 U'' = Q, friction-free."""
    model = build_model({"tau1": 2.418727066052555e-295, "tau2": 0.0, "L2": 0.0},
                        {"contact_growth": True}, compiled=compiled)
    model.advance(2.648521645394783e-254, 0.015625)
    model.advance(-1.0, 0.015625)
    m1 = Params().M1
    assert model.outputs().u_pipe == pytest.approx(-0.5 * 0.015625 ** 2 / m1, rel=1e-12)


@pytest.mark.parametrize("solver", ["exact", "fd"])
def test_load_one_ulp_above_the_limit_holds_a_pipe_without_plug(solver, compiled):
    """A load at the outer limit to round-off (1 ulp above P1 L1 tau1 as the core computes
    it; the fuzz made it as tau1 = Q / (P1 L1)) held the pipe with a plug but, without one,
    the projection allowed no round-off: the pipe crept at 7e-13 m/s^2 for the whole blow."""
    tau1, q = 134470.15961602173, 32106.235383832303
    assert q > 2.0 * math.pi * (0.035 + 0.003) * 1.0 * tau1            # 1 ulp above
    for tau2 in (0.0, 1e4):                                          # no plug, plug
        model = build_model({"tau1": tau1, "tau2": tau2}, {"solver": solver},
                            compiled=compiled)
        for k in range(1, 21):
            model.advance_to(q, k * 1e-3)
            out = model.outputs()
            assert (out.v_pipe, out.u_pipe, out.pipe_mode, out.W_input) == (0.0, 0.0, 0, 0.0)
    model = build_model({"tau1": tau1, "tau2": 0.0}, {"solver": solver}, compiled=compiled)
    model.advance_to(q * (1.0 + 1e-9), 1e-2)          # a load truly above the limit slides
    assert model.outputs().pipe_mode == 1 and model.outputs().v_pipe > 0.0


def test_plug_at_its_limit_as_the_pipe_leaves_the_soil_stays_stuck_on_every_grid(compiled):
    """Pulled back by Q = -F2 (M1 + M2) / M2, the plug's required force reaches F2 exactly as
    the pipe leaves the soil (U1 = 0) and stays there (no outer friction beyond). When the
    breakaway and the segment end fell into one event (depending on the grid), the plug was
    kicked into sliding at zero relative acceleration: plug_mode -1 on some grids, 0 on
    others, for 16 ms."""
    params = dict(tau1=283964.2790735522, tau2=124.9535275947494, rho2=1003.3946708278456)
    segments = [(0.002696308685690301, 65.66674745827976),
                (0.02239678389501865, -65.66674745827976), (1.3451293843254578e-05,
                                                            -15078.1512914407)]
    T = 0.0251
    for grid in _grids(segments, T, counts=(3, 11, 101, 2001)):
        out = _run(params, segments, grid, compiled)
        leaving = (grid[1:] > 0.00906) & (grid[1:] < 0.025093)      # U1 < 0, same load
        assert np.all(out[leaving, 12] == 0)                                # plug_mode
        assert np.all(out[leaving, 0] == out[leaving, 1])                   # together
    _check_grid_independent_and_balanced(params, segments, T, compiled)


def test_stick_conserves_momentum_so_energy_balances_with_a_heavy_plug(compiled):
    """A plug of 127 pipe masses sticks to a pipe braking at 2e4 m/s^2. The stick time is a
    root to a few ulps, where the relative velocity is ~1e-13 m/s; setting the plug to the
    pipe's velocity there changed the kinetic energy by M2 V d: 3.9e-12 of the work. The
    momentum-conserving common velocity changes it by M1 M2 d^2 / (2 (M1 + M2)) only."""
    params = dict(tau1=187204.3634534553, tau2=274273.1251634091, rho2=177290.89476976704)
    segments = [(0.0006100347674109973, -18953.937308155582),
                (0.0007023491811414517, -4363.383990987881), (0.042770182046069034, 0.0),
                (1.3339018164587106e-05, -105012.91928017858),
                (3.6256806706069485e-05, 56051.802526441345)]
    _check_grid_independent_and_balanced(params, segments, 0.16067348642753898, compiled)


def test_friction_work_never_decreases_after_a_breakaway_cut_short(compiled):
    """A plug broke away (zero relative velocity and acceleration) 1.4e-10 s before the pipe
    stopped; the relative displacement of that piece, a difference of two displacements of
    1e-18 m, came out as -1e-34 m: W_friction_inner = -1.03e-33 J ever after."""
    params = dict(L1=0.6832118171949602, L2=0.015985771564293844, rho2=3464.2334867902814,
                  tau1=352142.93494809733, tau2=3038.715656773539)
    segments = [(0.02609634245246205, 194.45847785253008),
                (0.018547268220555264, -57432.4102403413)]
    for grid in _grids(segments, 0.03):
        out = _run(params, segments, grid, compiled)
        for col in (7, 8, 9):                 # W_friction, its outer and inner parts
            assert np.all(np.diff(np.r_[0.0, out[:, col]]) >= 0.0)


def test_event_times_do_not_depend_on_the_grid(compiled):
    """The plug sticks to a pipe braking at 5000 m/s^2, then slides on alone. The stick time
    came from a root search bracketed by how far ahead the step asked, so it was one ulp
    apart on some grids, and the plug's velocity with it (1.6e-12 of its value here). The
    root is the first float past the crossing: every grid gives the same outputs, bit for
    bit."""
    params = dict(tau1=137145.47348779085, tau2=47.11339360210337, rho2=793.8562601222261)
    segments = [(0.0001314688401900647, 32755.356887043476),
                (0.0002531184871952582, -22318.914628429426),
                (0.008676288609590525, 32744.996110657652),
                (0.027392148234137534, -32755.356887043476),
                (0.05414672411470262, 16372.498055328826),
                (0.00011639023613625012, 2682.411687114385)]
    finals = np.array([_run(params, segments, grid, compiled)[-1]
                       for grid in _grids(segments, 0.17)])
    plug_mode = OUTPUT_NAMES.index("plug_mode")
    assert finals[0][1] != 0.0 and finals[0][plug_mode] != 0          # the plug slides
    assert np.all(finals == finals[0])


def test_harmonic_motion_of_a_vanishing_friction_limit_is_uniform(compiled):
    """At tau1 = 2.4e-295 Pa the harmonic basis divided a squared sine that had underflowed
    by k: the pipe's position was garbage near a piece start, and a segment event was placed
    8.6e-29 m past U1 = 0 (raised). Found with the root walk to the first float past."""
    travel = jit.compiled(motion.travel) if compiled else motion.travel
    for k in (1e-296, -1e-296):
        body = motion.motion(1e-256, 7.7e-257, -0.186, k)
        for t in (1e-130, 2.1e-14, 1e-3):
            d, v = travel(body, t)
            assert d == pytest.approx(7.7e-257 * t - 0.093 * t * t, rel=1e-15)
            assert v == pytest.approx(7.7e-257 - 0.186 * t, rel=1e-15)
        dense = travel(body, np.array([1e-130, 2.1e-14, 1e-3, 0.0]))[0]
        assert np.all(np.isfinite(dense)) and dense[-1] == 0.0
    model = build_model({"tau1": 2.418727066052555e-295, "tau2": 0.0, "L2": 0.0},
                        {"contact_growth": True}, compiled=compiled)
    model.advance(2.648521645394783e-254, 0.015625)
    model.advance(-1.0, 0.015625)                       # pulled out past U1 = 0
    assert model.outputs().u_pipe == pytest.approx(-0.5 / model.M1 * 0.015625 ** 2, rel=1e-12)
