"""Parameters and options: contract defaults, derived masses, validation messages."""
import math

import pytest

from pipeplug import OPTIONS, PARAMETERS, ParameterError, Params, build_model
from pipeplug.options import Options

# The FMU contract's defaults (SI), typed from the contract table.
CONTRACT_DEFAULTS = dict(L1=1.0, L2=1.0, R1=0.035, h1=0.003, rho1=7800, rho2=1800, E1=1.95e11,
                         E2=6.0e8, tau1=0, tau2=1.0e4, dt=2.0e-4, dx=0.01, courant=1.0,
                         x_monitor=0.5, ram_mass=0.0, cushion_stiffness=0.0,
                         cushion_restitution=1.0,
                         max_internal_steps=1e8)     # not in the contract: the project's own


def test_defaults_are_the_contracts():
    assert {p.name: p.default for p in PARAMETERS} == CONTRACT_DEFAULTS
    assert {k: v[1] for k, v in OPTIONS.items()} == dict(solver="exact", contact_growth=False,
                                                         elastic=False)


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
