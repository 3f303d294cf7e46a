"""Drive files: the closed key table, the drive's own rules, the core's check, shipped files."""
from pathlib import Path

import pytest
from drive_helpers import toml_text

from pipeplug.params import ParameterError
from pipeplug_harness.drive.file import DEFAULT_REFUSAL, load_drive
from pipeplug_harness.scenes.file import SceneError

DRIVES = Path(__file__).resolve().parents[3] / "scenes" / "drives"


def _load(tmp_path, sections):
    path = tmp_path / "d.toml"
    path.write_text(toml_text(sections))
    return load_drive(path)


@pytest.mark.parametrize("sections, match", [
    ({"output": {"step": 1e-3}}, r"unknown section \[output\].*pipe, plug, soil, blows, model, drive"),
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
])
def test_unknown_or_bad_values_name_the_allowed_ones(tmp_path, sections, match):
    with pytest.raises(SceneError, match=match):
        _load(tmp_path, sections)


def test_the_core_checks_every_parameter(tmp_path):
    with pytest.raises(ParameterError, match="dx = 0.3"):          # does not divide L1 = 1 m
        _load(tmp_path, {"model": {"elastic": True, "dx": 0.3}})
    with pytest.raises(ParameterError, match="tau1 = -1.0"):
        _load(tmp_path, {"soil": {"tau1": -1.0}})
    with pytest.raises(ParameterError, match="solver = 'euler'"):
        _load(tmp_path, {"model": {"solver": "euler"}})


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


def test_every_shipped_drive_loads():
    files = sorted(DRIVES.glob("*.toml"))
    assert files
    for path in files:
        spec = load_drive(path)
        assert spec.target <= spec.params().L1
