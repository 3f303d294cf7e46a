"""The system file generator (pipeplug_fmu.systems) on its own: the documented default system,
grids that miss a blow edge are refused, and the values written are the ones given."""
from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from pipeplug_fmu.systems import (
    System,
    default_system,
    grid_misses,
    osp_xml,
    ram_system,
    ssd_xml,
)

SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"


def test_default_system_is_the_documented_one():
    system = default_system()
    assert (system.start, system.stop, system.step) == (0.0, 0.6, 1e-3)
    assert system.pipeplug["tau1"] == 4e4 and system.pipeplug["tau2"] == 1e4
    assert system.pipeplug["contact_growth"] is False and system.pipeplug["solver"] == "exact"
    assert system.hammer == {"amplitude": 23000.0, "duration": 0.05, "period": 0.2, "count": 3,
                             "start": 0.0, "ram_mass": 0.0, "rated_energy": 0.0,
                             "efficiency": 1.0, "blows_per_minute": 60.0}


def test_ram_system_is_the_documented_one():
    """A 50 kg ram through a 2e7 N/m cushion (e = 0.8) in PipePlug; Hammer's ram of the same
    mass at 400 J, 80 %, 300 blows per minute, three strikes; its strike instants (0, 0.2 and
    0.4 s) on the 1 ms grid."""
    system = ram_system()
    assert (system.start, system.stop, system.step) == (0.0, 0.6, 1e-3)
    assert {k: system.pipeplug[k] for k in ("tau1", "ram_mass", "cushion_stiffness",
                                            "cushion_restitution")} == {
        "tau1": 4e4, "ram_mass": 50.0, "cushion_stiffness": 2e7, "cushion_restitution": 0.8}
    assert {k: system.hammer[k] for k in ("ram_mass", "rated_energy", "efficiency",
                                          "blows_per_minute", "count")} == {
        "ram_mass": 50.0, "rated_energy": 400.0, "efficiency": 0.8, "blows_per_minute": 300.0,
        "count": 3}
    assert grid_misses(system) == []
    assert grid_misses(System(hammer=system.hammer, stop=0.6, step=0.03)) == pytest.approx(
        [0.2, 0.4])


@pytest.mark.parametrize(("step", "misses"), [(1e-3, []), (0.05, []), (0.03, [0.05, 0.2, 0.25]),
                                               (0.04, [0.05, 0.25])])
def test_grid_misses_the_edges_it_does_not_contain(step, misses):
    system = System(hammer={"count": 2}, stop=0.3, step=step)
    assert grid_misses(system) == pytest.approx(misses)


def test_a_grid_missing_an_edge_is_refused():
    with pytest.raises(ValueError, match=r"misses the blow edges \[0.05, 0.2, 0.25\]"):
        ssd_xml(System(hammer={"count": 2}, stop=0.3, step=0.03))


def test_values_are_written_with_their_fmi_types():
    system = System(pipeplug={"tau1": 1.5e4, "contact_growth": True, "solver": "fd"},
                    hammer={"count": 2, "amplitude": 1e4})
    ssd = ET.fromstring(ssd_xml(system))
    written = {p.get("name"): (p[0].tag.split("}")[1], p[0].get("value"))
               for p in ssd.iter(f"{SSV}Parameter")}
    assert written == {"tau1": ("Real", "15000.0"), "contact_growth": ("Boolean", "true"),
                       "solver": ("String", "fd"), "count": ("Integer", "2"),
                       "amplitude": ("Real", "10000.0")}
    osp = osp_xml(system, {"PipePlug": "p.fmu", "Hammer": "h.fmu"})
    for text in ('<Boolean value="true" />', '<String value="fd" />', '<Integer value="2" />'):
        assert text in osp
