"""The paper's names (:mod:`pipeplug_harness.paper`) against the core's table and the closed form."""
from __future__ import annotations

from dataclasses import fields

from pipeplug import PARAMETERS
from pipeplug_harness.paper import RAM_PARAMETERS, RIGID_PARAMETERS, rigid_values
from pipeplug_references import closed_form as cf


def test_the_rigid_parameters_are_those_of_the_closed_form():
    """The paper's models I and II take the closed form's parameters, no more (the blow aside):
    a parameter the core adds (the ram's) stays out of what validate, cost, the sweeps' domains
    and the fuzz pass to the closed form."""
    model = [f.name for f in fields(cf.Case) if f.name not in ("Q0", "t0")]
    assert list(RIGID_PARAMETERS) == model
    case = cf.Case(tau1=2e4)
    assert rigid_values(case) == {name: getattr(case, name) for name in model}


def test_the_ram_parameters_are_in_the_core_table_and_not_the_papers():
    assert set(RAM_PARAMETERS) <= {p.name for p in PARAMETERS}
    assert not set(RAM_PARAMETERS) & set(RIGID_PARAMETERS)
