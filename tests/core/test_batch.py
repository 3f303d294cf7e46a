"""The batch API: single blows over arrays of parameters, against the closed form of model I,
the energy balance, one model stepped to rest, and its refusals."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug import ParameterError, build_model
from pipeplug.batch import RESULTS, blows
from pipeplug_references import closed_form as cf

BASE = cf.Case()
#: (tau1, tau2) over domains I-V of model I, in units of tau*
TAUS = [(0.3, 0.1), (0.6, 0.05), (0.4, 0.3), (0.9, 0.4), (0.7, 0.7), (1.1, 0.2), (0.2, 0.0),
        (0.5, 1e-3), (0.05, 0.9)]


def _closed_form_at_rest(tau1: float, tau2: float) -> dict:
    """Displacements [m] and works [J] of model I once all is at rest, and the rest time [s]."""
    case = cf.Case(tau1=tau1, tau2=tau2)
    t_rest = max(cf.stop_times(case) + (case.t0,))
    sol = cf.solution(case, np.array([t_rest + 0.01]))
    return {"u_pipe": sol["U1"][0], "u_plug": sol["U2"][0], "W_input": sol["W_input"][0],
            "t_rest": t_rest}


@pytest.mark.parametrize("compiled", [False, True])
def test_model_I_blows_match_the_closed_form(compiled):
    taus = np.array(TAUS) * BASE.tau_star
    out = blows({"tau1": taus[:, 0], "tau2": taus[:, 1]}, BASE.Q0, BASE.t0, compiled=compiled)
    for i, (tau1, tau2) in enumerate(taus):
        ref = _closed_form_at_rest(tau1, tau2)
        for name in ("u_pipe", "u_plug", "W_input"):
            assert out[name][i] == pytest.approx(ref[name], rel=1e-12, abs=1e-12), (i, name)
        if ref["u_pipe"] > 0.0:              # domain V: held during the blow, at rest after it
            assert out["t_rest"][i] == pytest.approx(ref["t_rest"], rel=1e-12), i
        else:
            assert out["t_rest"][i] == BASE.t0
        # the steps end at t0, 2 t0, 4 t0, ...: t_end is the first end past the rest (after the
        # blow's own step: under load nothing is at rest)
        k = max(1, math.ceil(math.log2(ref["t_rest"] / BASE.t0)))
        assert abs(ref["t_rest"] / (BASE.t0 * 2.0 ** k) - 1.0) > 1e-9     # not at a step end
        assert out["t_end"][i] == BASE.t0 * 2.0 ** k, i


def test_the_last_step_is_cut_at_t_max():
    """tau1 = 0.2 tau*, no plug: at rest at 0.25 s (closed form), between the step ends 0.2
    and 0.4 s. With t_max = 0.3 s the last step ends there, at rest; with 0.24 s the case is
    still moving at t_max."""
    tau1 = 0.2 * BASE.tau_star
    ref = _closed_form_at_rest(tau1, 0.0)
    assert ref["t_rest"] == pytest.approx(0.25, rel=1e-12)
    done = blows({"tau1": [tau1], "tau2": [0.0]}, BASE.Q0, BASE.t0, t_max=0.3)
    assert done["t_end"][0] == 0.3 and done["t_rest"][0] == pytest.approx(0.25, rel=1e-12)
    assert done["u_pipe"][0] == pytest.approx(ref["u_pipe"], rel=1e-12)
    moving = blows({"tau1": [tau1], "tau2": [0.0]}, BASE.Q0, BASE.t0, t_max=0.24)
    assert moving["t_end"][0] == 0.24 and moving["t_rest"][0] == math.inf


def _random(n: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    return {"tau1": rng.uniform(1e3, 1.2 * BASE.tau_star, n),
            "tau2": rng.choice([0.0, 1.0], n) * rng.uniform(0.0, 1.2 * BASE.tau_star, n),
            "L2": rng.uniform(0.0, 1.0, n), "rho2": rng.uniform(500.0, 5000.0, n)}


@pytest.mark.parametrize("growth", [False, True])
def test_each_case_is_one_model_stepped_to_rest(growth):
    """The same results as build_model advanced through the blow and on until at rest, and all
    of the input work dissipated, on both paths."""
    params = _random(30, seed=int(growth))
    amplitude = np.linspace(5e3, 40e3, 30)
    out = {c: blows(params, amplitude, 0.03, growth, compiled=c) for c in (False, True)}
    for name in RESULTS:
        a, b = out[False][name], out[True][name]
        assert np.all(np.abs(a - b) <= 1e-15 * np.max(np.abs(a))), name
    res = out[True]
    works = res["W_friction_outer"] + res["W_friction_inner"]
    assert np.all(np.abs(res["W_input"] - works) <= 1e-12 * res["W_input"])
    for i in range(0, 30, 3):
        model = build_model({k: v[i] for k, v in params.items()}, {"contact_growth": growth})
        model.advance(amplitude[i], 0.03)
        while not model.at_rest():
            model.advance(0.0, 0.01)
        o = model.outputs()
        got = (o.u_pipe, o.u_plug, o.W_input, o.W_friction_outer, o.W_friction_inner)
        for name, value in zip(RESULTS, got):
            assert res[name][i] == pytest.approx(value, rel=1e-12, abs=1e-15), (i, name)


def test_end_resistance_cases_are_one_model_stepped_to_rest():
    """With q_face and q_plug_face the batch gives what one model gives, W_face included, and
    the input work goes into friction and the face's work."""
    rng = np.random.default_rng(5)
    params = {**_random(12, seed=7), "q_face": rng.uniform(0.0, 2e7, 12),
              "q_plug_face": rng.uniform(0.0, 2e5, 12)}
    res = blows(params, 23e3, 0.05)
    works = res["W_friction_outer"] + res["W_friction_inner"] + res["W_face"]
    assert np.all(np.abs(res["W_input"] - works) <= 1e-12 * res["W_input"])
    assert np.all(res["W_face"][res["u_pipe"] > 0.0] > 0.0) and np.any(res["u_pipe"] > 0.0)
    for i in range(0, 12, 4):
        model = build_model({k: v[i] for k, v in params.items()})
        model.advance(23e3, 0.05)
        while not model.at_rest():
            model.advance(0.0, 0.01)
        o = model.outputs()
        for name in ("u_pipe", "u_plug", "W_input", "W_face"):
            assert res[name][i] == pytest.approx(getattr(o, name), rel=1e-12, abs=1e-15), \
                (i, name)


def test_a_case_that_never_stops_is_marked():
    """tau1 = 0: nothing stops the pipe (it and the plug glide on together)."""
    out = blows({"tau1": [0.0, 2e4]}, 23e3, 0.05, t_max=10.0)
    assert out["t_rest"][0] == math.inf and all(math.isnan(out[n][0]) for n in RESULTS[:6])
    assert math.isfinite(out["t_rest"][1]) and out["u_pipe"][1] > 0.0


def test_refusals_name_the_offending_value():
    with pytest.raises(ParameterError, match="tau1 = -1.0"):
        blows({"tau1": [2e4, -1.0]})
    with pytest.raises(ParameterError, match="L2 = 2.0"):
        blows({"L2": [0.5, 2.0]})
    with pytest.raises(ParameterError, match="duration = 0.0"):
        blows({"tau1": [2e4]}, 23e3, [0.0])
    with pytest.raises(ParameterError, match="amplitude = nan"):
        blows({"tau1": [2e4, 3e4]}, [1.0, math.nan], 0.05)
    with pytest.raises(ParameterError, match="tau3"):
        blows({"tau3": [1.0]})
