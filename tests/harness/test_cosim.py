"""check_parameters refuses what the FMU contract refuses at initialization (libcosim would
terminate the process), with the FMU's wording, and accepts the rest."""
import math

import pytest

from pipeplug import ParameterError
from pipeplug_harness.cosim import check_parameters

#: start values -> (refused name, text of the message); from the contract's parameter table
REFUSED = [
    ({"tau1": -1.0}, "tau1", "tau1 = -1.0 is not allowed; allowed: "),
    ({"tau2": math.nan}, "tau2", "tau2 = nan is not allowed"),
    ({"L2": 2.0}, "L2", "L2 = 2.0 is not allowed"),
    ({"solver": "rk4"}, "solver", "solver = 'rk4' is not allowed"),
    ({"solver": "fd", "dt": 0.0}, "dt", "dt = 0.0 is not allowed"),
    ({"elastic": True, "courant": 1.5}, "courant", "courant = 1.5 is not allowed"),
    ({"tau3": 1.0}, "tau3", "tau3 = 1.0 is not allowed; allowed: a parameter or option"),
    ({"tau1": "much"}, "tau1", "tau1 = 'much' is not allowed; allowed: a Real number"),
]
ACCEPTED = [{}, {"tau1": 2e4, "tau2": 1e4}, {"tau1": 20000}, {"dt": -1.0},   # dt: only with fd
            {"elastic": True, "dx": 0.05}, {"solver": "fd", "contact_growth": True}]


@pytest.mark.parametrize(("values", "name", "text"), REFUSED)
def test_refused_with_the_fmu_wording(values, name, text):
    with pytest.raises(ParameterError) as refused:
        check_parameters(values)
    assert refused.value.name == name
    assert text in str(refused.value)


@pytest.mark.parametrize("values", ACCEPTED)
def test_accepted(values):
    assert check_parameters(values) is None


#: Hammer start values -> (refused name, text); from the contract's Hammer section
HAMMER_REFUSED = [
    ({"period": 0.0}, "period", "period = 0.0 is not allowed; allowed: finite, > 0"),
    ({"duration": 0.25}, "duration", "duration = 0.25 is not allowed; allowed: finite, > 0 and "
                                     "<= period"),
    ({"amplitude": math.inf}, "amplitude", "amplitude = inf is not allowed"),
    ({"count": -2}, "count", "count = -2 is not allowed"),
    ({"count": 2.5}, "count", "count = 2.5 is not allowed; allowed: an Integer >= 0"),
    ({"start": math.nan}, "start", "start = nan is not allowed"),
    ({"force": 1.0}, "force", "force = 1.0 is not allowed; allowed: a parameter of Hammer"),
]
HAMMER_ACCEPTED = [{}, {"count": 0}, {"duration": 0.2, "period": 0.2},
                   {"amplitude": -5e3, "start": -0.1}, {"duration": 0.5, "period": 1.0}]


@pytest.mark.parametrize(("values", "name", "text"), HAMMER_REFUSED)
def test_hammer_refused_with_the_fmu_wording(values, name, text):
    from pipeplug_harness.cosim import check_hammer_parameters

    with pytest.raises(ParameterError) as refused:
        check_hammer_parameters(values)
    assert refused.value.name == name
    assert text in str(refused.value)


@pytest.mark.parametrize("values", HAMMER_ACCEPTED)
def test_hammer_accepted(values):
    from pipeplug_harness.cosim import check_hammer_parameters

    assert check_hammer_parameters(values) is None
