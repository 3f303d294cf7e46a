"""Drive files: the closed key table, the drive's own rules, the core's check, shipped files."""
from pathlib import Path

import pytest
from drive_helpers import toml_text

from pipeplug_harness.drive.file import DEFAULT_REFUSAL, load_drive
from pipeplug_harness.errors import UserError

DRIVES = Path(__file__).resolve().parents[3] / "scenes" / "drives"


def _load(tmp_path, sections):
    path = tmp_path / "d.toml"
    path.write_text(toml_text(sections))
    return load_drive(path)


@pytest.mark.parametrize("sections, match", [
    ({"output": {"step": 1e-3}},
     r"unknown section \[output\].*pipe, plug, soil, blows, hammer, model, "
                                 r"drive"),
    ({"drive": {"goal": 1.0}}, "unknown key 'goal'.*target, refusal_set, refusal_count"),
    ({"blows": {"count": 3}}, "unknown key 'count'.*amplitude, duration, period"),
    ({"model": {"x_monitor": 0.5}}, "unknown key 'x_monitor'.*elastic, solver"),
    ({"drive": {"max_blows": 2.5}}, "an integer"),
    ({"soil": {"contact_growth": False}}, "contact_growth = false; allowed: true"),
    ({"drive": {"target": 1.5}}, r"target = 1.5 m; allowed: > 0 and <= L1 = 1.0"),
    ({"drive": {"refusal_set": 1e-3, "refusal_count": 10}}, "either refusal_set, or"),
    ({"drive": {"refusal_count": 10}}, "go together"),
    ({"drive": {"refusal_set": -1e-3}}, "allowed: >= 0"),
    ({"blows": {"duration": 0.2, "period": 0.1}}, r"period = 0.1 s; allowed: > duration"),
    # each of these ran before and gave a result, silently wrong (exit 0)
    ({"blows": {"amplitude": -2.0e4}}, r"amplitude = -20000.0 N; allowed: > 0"),
    ({"blows": {"amplitude": "nan N"}}, r"amplitude = 'nan N'; allowed: a finite quantity"),
    ({"soil": {"tau1": 2e8}}, r'tau1 = 200000000.0 Pa is outside .*allow = \["tau1"\]'),
    ({"blows": {"amplitude": float("nan")}}, r"amplitude = nan; allowed: a finite number"),
    ({"blows": {"duration": 0.0}, "drive": {"step": 1e-3}}, r"duration = 0.0; allowed: > 0 s"),
    ({"soil": {"q_tip": "1 MPa"}}, "unknown key 'q_tip'.*tau1, contact_growth, q_face, "
                                   "q_plug_face"),
    ({"soil": {"q_face": "3 m"}}, r"\[soil\] q_face = '3 m'; allowed: a quantity of the "
                                  r"dimension of Pa"),
    ({"soil": {"q_plug_face": "-1 kPa"}}, r"\[soil\] q_plug_face = -1000.0; allowed: >= 0 Pa"),
    ({"soil": {"q_face": "2 GPa"}}, r'q_face = 2000000000.0 Pa is outside .*allow = \["q_face"\]'),
])
def test_unknown_or_bad_values_name_the_allowed_ones(tmp_path, sections, match):
    with pytest.raises(UserError, match=match):
        _load(tmp_path, sections)


def test_the_core_checks_every_parameter(tmp_path):
    with pytest.raises(UserError, match="dx = 0.3"):          # does not divide L1 = 1 m
        _load(tmp_path, {"model": {"elastic": True, "dx": 0.3}})
    with pytest.raises(UserError, match="tau1 = -1.0"):
        _load(tmp_path, {"soil": {"tau1": -1.0}})
    with pytest.raises(UserError, match="solver = 'euler'"):
        _load(tmp_path, {"model": {"solver": "euler"}})


def test_a_missing_section_is_an_error(tmp_path):
    path = tmp_path / "d.toml"
    sections = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1e4},
                "blows": {"amplitude": 1e4, "duration": 0.01, "period": 0.1}}
    path.write_text(toml_text(sections, fill=False))
    with pytest.raises(UserError, match=r"d.toml: missing section \[soil\]"):
        load_drive(path)


def test_work_past_the_limits_is_refused_before_the_drive(tmp_path):
    """step = 1e-12 took 11.7 GB in 40 s before any check."""
    with pytest.raises(UserError, match=r"step = 1e-12 s over a blow of 0.05 s asks for "
                                        r"5e\+10 steps.*--limit steps="):
        _load(tmp_path, {"drive": {"step": 1e-12}, "checks": {"allow": ["step"]}})


def test_defaults_and_the_monitored_front_end(tmp_path):
    rigid = _load(tmp_path, {"blows": {"duration": 0.05, "period": 0.2}})
    assert not rigid.elastic and "x_monitor" not in rigid.start_values
    assert rigid.start_values["contact_growth"] is True
    assert (rigid.refusal_count, rigid.refusal_length) == DEFAULT_REFUSAL
    assert rigid.target == 1.0 and rigid.step == pytest.approx(0.005)
    elastic = _load(tmp_path, {"pipe": {"L1": 2.0}, "blows": {"duration": 1e-4},
                               "drive": {"refusal_set": 1e-4, "target": 1.5}})
    assert elastic.elastic and elastic.start_values["x_monitor"] == 2.0    # the front end
    assert (elastic.refusal_count, elastic.refusal_length, elastic.target) == (1, 1e-4, 1.5)


def test_the_soil_s_end_resistance_in_the_engineer_s_units(tmp_path):
    spec = _load(tmp_path, {"soil": {"q_face": "3.5 MPa", "q_plug_face": "150 kPa"}})
    assert spec.start_values["q_face"] == 3.5e6 and spec.start_values["q_plug_face"] == 1.5e5
    assert "q_face" not in _load(tmp_path, {}).start_values        # absent: the FMU's default


def test_every_shipped_drive_loads():
    files = sorted(DRIVES.glob("*.toml"))
    assert files
    for path in files:
        spec = load_drive(path)
        assert spec.target <= spec.params().L1
