"""Parameters and options: contract defaults, derived masses, validation messages."""
import math

import pytest

from pipeplug import OPTIONS, PARAMETERS, ParameterError, Params, build_model
from pipeplug.options import Options

# The FMU contract's defaults (SI), typed from the contract table.
CONTRACT_DEFAULTS = dict(L1=1.0, L2=1.0, R1=0.035, h1=0.003, rho1=7800, rho2=1800, E1=1.95e11,
                         E2=6.0e8, tau1=0, tau2=1.0e4, dt=2.0e-4, dx=0.01, courant=1.0,
                         x_monitor=0.5, ram_mass=0.0, cushion_stiffness=0.0,
                         cushion_restitution=1.0, q_face=0.0, q_plug_face=0.0,
                         J_shaft=0.0, J_face=0.0, L2_after_cleanout=0.0,
                         max_internal_steps=1e8)     # not in the contract: the project's own


def test_defaults_are_the_contracts():
    assert {p.name: p.default for p in PARAMETERS} == CONTRACT_DEFAULTS
    assert {k: v[1] for k, v in OPTIONS.items()} == dict(solver="exact", contact_growth=False,
                                                         elastic=False, plug_growth=False)


def test_derived_quantities_match_the_paper():
    p = Params()
    assert p.M1 == pytest.approx(5.3665, abs=1e-4)       # paper: 5.37 kg, docs/corrections.md A6: 5.3665
    assert p.M2 == pytest.approx(6.9272, abs=1e-4)       # paper: 6.93 kg, docs/corrections.md A6: 6.9272
    assert 23000 / (p.P1 * p.L1) == pytest.approx(96330.62, abs=0.01)   # tau*
    assert p.P2 > p.P1 * 0.9 and p.P1 == pytest.approx(2 * math.pi * 0.038)


@pytest.mark.parametrize("name, value, allowed", [
    ("L1", 0.0, "> 0"), ("L2", 1.5, "<= L1"), ("tau1", -1.0, ">= 0"), ("R1", math.nan, "finite"),
    ("tau2", math.inf, "finite")])
def test_out_of_range_names_variable_value_and_range(name, value, allowed):
    with pytest.raises(ParameterError) as err:
        build_model({name: value})
    assert err.value.name == name and allowed in err.value.allowed
    assert name in str(err.value) and repr(value) in str(err.value)


def test_conditional_parameters_checked_only_when_active():
    build_model({"dt": -1.0})                      # exact solver: dt unused
    with pytest.raises(ParameterError, match="dt"):
        build_model({"dt": -1.0}, {"solver": "fd"})


@pytest.mark.parametrize("options, match", [({"solver": "rk4"}, "'exact', 'fd'"),
                                            ({"elastik": True}, "elastic"),
                                            ({"contact_growth": 1}, "False, True")])
def test_unknown_options_name_the_allowed_ones(options, match):
    with pytest.raises(ParameterError, match=match):
        Options.from_mapping(options)


def test_unknown_parameter_is_refused():
    with pytest.raises(ParameterError, match="L1"):
        build_model({"length": 2.0})


@pytest.mark.parametrize("changes, options, name, words", [
    ({"h1": 1e-18}, {}, "h1", "S1 = pi((R1+h1)^2 - R1^2) within [1e-100"),     # cancels to 0
    ({"R1": 1e-300}, {"elastic": True}, "R1", "S2 = pi*R1^2"),                  # underflows
    ({"rho1": 1e-300}, {}, "rho1", "M1 = rho1*S1*L1"),
    ({"R1": 1e300}, {}, "R1", "a magnitude <= 1e+100"),                         # R1^2 overflows
    ({"tau2": 1e99, "L1": 1e3, "L2": 1e3}, {}, "tau2", "F2 = P2*L2*tau2"),      # works overflow
    ({"E1": 1e100, "rho1": 1e-200, "R1": 1e25, "h1": 1e25, "L1": 1e50, "L2": 0.0,
      "dx": 5e49}, {"elastic": True}, "E1", "c1 = sqrt(E1/rho1)"),              # 1e150 m/s
    ({"dx": 1e-7}, {"elastic": True}, "dx", "cells = L1/dx within [1, 1e+06]"),
])
def test_values_the_models_cannot_compute_with_are_refused_by_name(changes, options, name,
                                                                   words):
    with pytest.raises(ParameterError) as err:
        build_model(changes, options)
    assert err.value.name == name and err.value.value == changes[name]
    assert words in err.value.allowed, err.value.allowed


def test_limits_of_the_plug_apply_only_where_it_is_simulated():
    build_model({"R1": 1e-60, "h1": 1.0, "tau2": 0.0})      # S2 = 3e-120 m2, no plug: fine
    with pytest.raises(ParameterError, match="R1"):
        build_model({"R1": 1e-60, "h1": 1.0})


@pytest.mark.parametrize("name", ["E1", "E2", "dt", "dx", "courant", "x_monitor"])
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_every_non_finite_parameter_is_refused_active_or_not(name, value):
    with pytest.raises(ParameterError) as err:
        build_model({name: value})                         # rigid exact: all six unused
    assert err.value.name == name and "finite" in err.value.allowed


def test_the_batch_api_refuses_the_same_cases():
    import numpy as np

    from pipeplug.params import ParamArrays

    with pytest.raises(ParameterError) as err:
        ParamArrays({"h1": np.array([0.003, 1e-18]), "dt": 1e-4}).validate()
    assert (err.value.name, err.value.value) == ("h1", 1e-18)
    with pytest.raises(ParameterError, match="dt = nan"):
        ParamArrays({"dt": np.array([1e-4, math.nan])}).validate()


def test_the_limits_quantities_are_the_tables_in_its_order():
    """The compiled check reads the limits' quantities by position (params.limit_values)."""
    from pipeplug.params import LIMITS, limit_values

    p = Params(tau1=2e4, q_face=3e5, q_plug_face=1e5, J_shaft=0.2, J_face=0.1)
    assert limit_values(p) == tuple(getattr(p, limit.quantity) for limit in LIMITS)


def _edge_values(rng, count):
    """Mappings of a few parameters each, at and around the edges of their ranges."""
    edges = [0.0, -0.0, -1.0, 1e-300, 1e-120, 1e-60, 1e-18, 0.5, 1.0, 2.0, 1e3, 1e99, 1e100,
             1.0000000000000002e100, 1e300, math.inf, -math.inf, math.nan]
    for _ in range(count):
        names = rng.choice([p.name for p in PARAMETERS], size=int(rng.integers(1, 4)),
                           replace=False)
        yield {str(n): float(rng.choice(edges)) * float(rng.choice([1.0, 1.0, 0.3]))
               for n in names}


@pytest.mark.parametrize("options", [{}, {"contact_growth": True}])
def test_the_compiled_check_refuses_what_the_table_refuses(options):
    """build_model's compiled check and build (the common case) against the general path
    (compiled=False: Params.validate): the same refusals with the same messages, the same
    constants where both build."""
    import numpy as np

    from pipeplug import jit

    rng = np.random.default_rng(29)
    built = refused = 0
    for values in _edge_values(rng, 400):
        outcomes = []
        for compiled in (True, False):
            try:
                model = build_model(values, options, compiled=compiled)
            except ParameterError as err:
                outcomes.append(str(err))
            else:
                outcomes.append(list(np.asarray(model._par, dtype=float))
                                if hasattr(model, "_par") else type(model))
        assert outcomes[0] == outcomes[1], values
        built += not isinstance(outcomes[0], str)
        refused += isinstance(outcomes[0], str)
    assert built > 40 and refused > 200            # both kinds were exercised
    if jit.enabled():
        from pipeplug.rigid.exact import compiled_model

        assert compiled_model({"tau1": 2e4}, False) is not None
        assert compiled_model({"tau1": -1.0}, False) is None      # refused
        assert compiled_model({"ram_mass": 1.0}, False) is None   # another variant
