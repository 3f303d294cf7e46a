"""Drives by a hammer: the [hammer] section in an engineer's terms, its refusals, and a drive of
strikes whose records (set, stresses, ENTHRU) hold what the physics allows."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest
from drive_helpers import toml_text

from pipeplug_harness.drive.file import load_drive
from pipeplug_harness.drive.plots import describe_blow
from pipeplug_harness.drive.report import summary
from pipeplug_harness.drive.run import run_drive_on_core
from pipeplug_harness.errors import UserError

HAMMER = {"rated_energy": "40.5 kJ", "efficiency": 0.5, "ram_mass": "2000 kg",
          "rate": "200 /min", "cushion_stiffness": "2e9 N/m", "cushion_restitution": 0.8}
PIPE = {"pipe": {"L1": 6.0, "R1": "295 mm", "h1": "9.5 mm", "E1": 2e11, "rho1": 7850.0},
        "plug": {"L2": 6.0, "tau2": "10 kPa", "rho2": 2000.0}, "soil": {"tau1": "10 kPa"},
        "model": {"elastic": True, "dx": 0.25}}


def _load(tmp_path, sections):
    path = tmp_path / "d.toml"
    path.write_text(toml_text(sections))
    return load_drive(path)


def test_the_hammer_in_an_engineers_terms(tmp_path):
    spec = _load(tmp_path, {**PIPE, "hammer": HAMMER, "drive": {"yield_stress": "241 MPa"}})
    v = math.sqrt(2 * 0.5 * 40500.0 / 2000.0)             # sqrt(2 eta E / m) = 4.50 m/s
    assert spec.hammer.v_strike == pytest.approx(v, rel=1e-15)
    assert spec.amplitude == 0.0 and spec.period == pytest.approx(0.3, rel=1e-15)
    assert {k: spec.start_values[k] for k in ("ram_mass", "cushion_stiffness",
                                              "cushion_restitution")} == {
        "ram_mass": 2000.0, "cushion_stiffness": 2e9, "cushion_restitution": 0.8}
    assert spec.yield_stress == 2.41e8
    # the contact's length: the cushion's half period on a fixed head, pi sqrt(m / k)
    assert spec.duration == pytest.approx(math.pi * math.sqrt(2000.0 / 2e9), rel=1e-12)
    # the figures name the ram, not a rectangle of 0 N
    assert describe_blow(spec) == "ram 2000 kg at 4.5 m/s, 0.5 x 4.05e+04 J"


@pytest.mark.parametrize("sections, match", [
    ({"hammer": HAMMER, "blows": {"amplitude": 1e4, "duration": 0.01, "period": 0.1}},
     r"\[blows\] and \[hammer\] both given"),
    ({"hammer": dict(HAMMER, efficiency=1.2)}, r"\[hammer\] efficiency = 1.2.*<= 1"),
    ({"hammer": dict(HAMMER, cushion_restitution=0.0)}, r"cushion_restitution = 0.0.*> 0"),
    ({"hammer": dict(HAMMER, rated_energy="40 kg")}, r"\[hammer\] rated_energy"),
    ({"hammer": {k: v for k, v in HAMMER.items() if k != "ram_mass"}},
     r"\[hammer\] ram_mass is missing"),
    ({"hammer": HAMMER, "model": {"elastic": False}},
     r"ram_mass = 2000.0 is not allowed.*model II"),
])
def test_hammer_mistakes_are_one_line(tmp_path, sections, match):
    with pytest.raises(UserError, match=match):
        _load(tmp_path, {**PIPE, **sections})


def test_neither_blows_nor_hammer_is_an_error(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text(toml_text({k: v for k, v in PIPE.items()}, fill=False))
    with pytest.raises(UserError, match=r"missing section \[blows\] or \[hammer\]"):
        load_drive(path)


def test_a_drive_of_strikes_reports_stresses_and_enthru(tmp_path):
    """Each blow: the energy through the head (ENTHRU) within what the ram brought, eta E
    (the ram starts each strike with eta E, and may still move), the head's stress within the
    stresses along the pipe, and the first strike's peak head stress near what the cushion's
    half sine on the pipe's impedance allows; the summary states the largest stress against
    the yield stress and the mean ENTHRU."""
    spec = _load(tmp_path, {**PIPE, "hammer": HAMMER,
                            "drive": {"yield_stress": "241 MPa", "max_blows": 4}})
    result = run_drive_on_core(spec)
    assert len(result.blows) == 4 and result.outcome == "max_blows"
    for blow in result.blows:
        assert 0.0 < blow.enthru <= 0.5 * 40500.0 * (1 + 1e-12)
        assert blow.enthru_share == pytest.approx(blow.enthru / 40500.0, rel=1e-15)
        assert blow.stress_min <= blow.stress_head_min < 0.0 < blow.stress_max
        assert blow.set > 0.0
    # A cushion k on a fixed head (an infinitely stiff pipe) pushes with m v w at most
    # (w = sqrt(k / m)); the elastic pipe gives way, so its head sees less.
    v, m, k = spec.hammer.v_strike, 2000.0, 2e9
    S1 = math.pi * ((0.295 + 0.0095) ** 2 - 0.295 ** 2)
    assert -result.blows[0].stress_head_min < m * v * math.sqrt(k / m) / S1
    line = summary(result)
    assert "% of the yield stress 241 MPa" in line and "ENTHRU" in line
    assert "EXCEEDED" not in line


CASING_RAM = (Path(__file__).resolve().parents[3] / "scenes" / "drives"
              / "casing_24in_17m_ram.toml")


def test_the_shipped_ram_casing_drive_holds_its_stated_derivations():
    """The file's ram: the time constant m / Z1 is the 1 ms it states, the strike velocity is
    sqrt(2 eta E / m), and the first strike's largest compressive stress is the closed form of a
    rigid ram on a long rod, Z1 v0 / S1 (the wave's round trip, 6.7 ms, is far longer than the
    ram's 1 ms, and the direct strike has one cell's stiffness, hence 1e-5)."""
    spec = load_drive(CASING_RAM)
    p = spec.params()
    S1 = math.pi * ((p.R1 + p.h1) ** 2 - p.R1 ** 2)
    Z1 = S1 * math.sqrt(p.E1 * p.rho1)
    assert spec.hammer.ram_mass / Z1 == pytest.approx(1e-3, rel=1e-4)
    v0 = math.sqrt(2 * 0.17 * 40500.0 / 711.5)
    assert spec.hammer.v_strike == pytest.approx(v0, rel=1e-15)
    first = run_drive_on_core(dataclasses.replace(spec, max_blows=1)).blows[0]
    assert -first.stress_min == pytest.approx(Z1 * v0 / S1, rel=1e-5)


def test_a_blow_whose_pipe_stopped_is_settled_and_the_summary_does_not_call_it_moving(tmp_path):
    """A 3 m casing struck by a 711.5 kg ram: blows 3 and 4 stop the pipe well before the next
    blow. The drive's steps grow after each blow, and the step to the next blow jumped over the
    settling window (a wave's round trip): such blows ended "moving" with v = 0 and the summary
    said "still moving at 0 m/s ... it comes to rest further in". A pipe still at a point a
    window before the next blow and at that blow has settled."""
    sections = {"pipe": {"L1": 3.0, "R1": 0.295275, "h1": 0.009525, "rho1": 7850.0,
                         "E1": 2.0e11},
                "plug": {"L2": 3.0, "rho2": 2000.0, "E2": 4.0e7, "tau2": 10184.0},
                "soil": {"tau1": 10184.0, "contact_growth": True},
                "hammer": {"rated_energy": "40.5 kJ", "efficiency": 0.17,
                           "ram_mass": "711.5 kg", "rate": "200 /min"},
                "model": {"elastic": True, "dx": 0.25},
                "drive": {"target": 1.0, "refusal_set": 8.33e-5, "max_blows": 200}}
    result = run_drive_on_core(_load(tmp_path, sections))
    assert result.outcome == "target" and len(result.blows) == 4
    for blow in result.blows:
        still = blow.v_pipe_end == 0.0 and blow.v_plug_end == 0.0
        assert (blow.settled != "moving") == still, blow
    assert result.blows[-1].settled == "front"
    assert "still moving" not in summary(result)
