"""Profiles along the rods (``build_model(profile_points=n)``, ``model.profiles()``).

Element k of a profile is defined as the scalar output of the same quantity with x_monitor at
section k (issue: "Profiles as arrays"), so the expected values are runs of models monitoring
those sections; the rigid stress is checked against the equilibrium of the whole pipe.
"""
from __future__ import annotations

import numpy as np
import pytest

from pipeplug import ParameterError, build_model
from pipeplug.interface import PROFILES, profile_sections

N = 5
TIMES = np.arange(1, 13) * 1e-3
CASES = [
    ({"elastic": True}, {"tau1": 2e4, "L2": 0.5, "dx": 0.05}),
    ({"elastic": True, "contact_growth": True}, {"tau1": 3e5, "dx": 0.05}),
    ({}, {"tau1": 2e4}),
    ({"solver": "fd", "contact_growth": True}, {"tau1": 2e4}),
]


def _run(params, options, **kwargs):
    model = build_model(params, options, **kwargs)
    for t in TIMES:
        model.advance_to(23e3 if t <= 0.006 else 0.0, t)
    return model


@pytest.mark.parametrize("options, params", CASES)
def test_profiles_are_the_scalar_outputs_at_their_sections(options, params):
    v, u, stress, v_plug = _run(params, options, profile_points=N).profiles()
    pipe, plug = profile_sections(1.0, params.get("L2", 1.0), N)
    assert pipe[0] == 0.0 and pipe[-1] == 1.0 and all(a.shape == (N,) for a in (v, u, stress))
    for k in range(N):
        at = _run(dict(params, x_monitor=float(pipe[k])), options).outputs()
        assert (v[k], u[k]) == (at.v_pipe, at.u_pipe)
        assert v_plug[k] == _run(dict(params, x_monitor=float(plug[k])), options).outputs().v_plug
    assert stress[0] == pytest.approx(_run(params, options).outputs().stress_head, abs=0.0)


def test_rigid_stress_is_the_equilibrium_of_the_pipe():
    # Stuck in the soil (tau1 large), no plug: F_outer = -Q spread evenly over the whole
    # pipe, no inertia, so N(x) = -Q (1 - x / L1): linear from -Q at the head to 0.
    q, p = 1e3, {"tau1": 1e6, "L2": 0.0}
    model = build_model(p, {}, profile_points=N)
    model.advance(q, 1e-3)
    stress = model.profiles()[2]
    S1 = np.pi * ((0.035 + 0.003) ** 2 - 0.035 ** 2)
    expected = -q * (1.0 - np.linspace(0.0, 1.0, N)) / S1
    np.testing.assert_allclose(stress, expected, rtol=1e-12, atol=1e-9)


def test_profile_points_out_of_range_are_refused_and_default_models_have_none():
    with pytest.raises(ParameterError, match="profile_points"):
        build_model({}, {}, profile_points=1)
    with pytest.raises(ValueError, match="profile_points"):
        build_model({}, {}).profiles()
    assert [p.name for p in PROFILES] == ["v_pipe_profile", "u_pipe_profile",
                                          "stress_pipe_profile", "v_plug_profile"]
