"""Scene files: the closed key table, the auto choice, and a run through the FMU."""
import csv
import math
from pathlib import Path

import pytest

from pipeplug_harness.scenes.file import AUTO_RATIO, SceneError, load_scene

SCENES = Path(__file__).resolve().parents[3] / "scenes"


def _write(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, match", [
    ("[pipes]\nL1 = 1.0\n", "unknown section.*pipe, plug, soil"),
    ("[pipe]\nlength = 1.0\n", "unknown key 'length'.*L1, R1"),
    ("[model]\nelastic = \"maybe\"\n", "true, false or \"auto\""),
    ("[blows]\ncount = 2.5\n", "an integer"),
    ("[output]\nvariables = [\"speed\"]\n", "allowed: v_pipe"),
])
def test_unknown_keys_and_values_name_the_allowed_ones(tmp_path, text, match):
    with pytest.raises(SceneError, match=match):
        load_scene(_write(tmp_path, text))


def test_auto_picks_rigid_for_long_blows_and_elastic_for_short_ones(tmp_path):
    c1 = math.sqrt(1.95e11 / 7800)                       # 5000 m/s, docs/corrections.md D1
    round_trip = 2 * 1.0 / c1
    long = load_scene(_write(tmp_path, f"[blows]\nduration = {AUTO_RATIO * round_trip * 1.01}\n"))
    short = load_scene(_write(tmp_path, f"[blows]\nduration = {AUTO_RATIO * round_trip * 0.99}\n"))
    assert long.start_values["elastic"] is False and "rigid" in long.reason
    assert short.start_values["elastic"] is True and "elastic" in short.reason
    given = load_scene(_write(tmp_path, "[model]\nelastic = false\n[blows]\nduration = 1e-4\n"))
    assert given.start_values["elastic"] is False and "given" in given.reason


def test_blows_become_a_pulse_train(tmp_path):
    s = load_scene(_write(tmp_path, "[blows]\namplitude = 5.0\nduration = 0.01\ncount = 3\n"
                                    "period = 0.04\nstart = 0.005\n"))
    assert [(p.start, p.duration, p.amplitude) for p in s.pulses] == [
        (0.005, 0.01, 5.0), (0.045, 0.01, 5.0), (0.085, 0.01, 5.0)]


def test_scene_runs_through_the_fmu(pipeplug_cli, fmu_file, tmp_path):
    proc = pipeplug_cli("scene", SCENES / "paper_fig5_curve1.toml", "--fmu", fmu_file,
                        "--out", tmp_path / "o")
    assert "rigid model" in proc.stdout
    rows = list(csv.DictReader(open(tmp_path / "o" / "paper_fig5_curve1.csv")))
    # Fig. 5 curve 1 ends with pipe and plug together at Q0 t0/(M1 + M2) = 93.54 m/s (docs/corrections.md C4)
    assert float(rows[-1]["v_pipe"]) == pytest.approx(93.54, abs=0.005)
    assert float(rows[-1]["time"]) == pytest.approx(0.35)
    assert (tmp_path / "o" / "paper_fig5_curve1.png").stat().st_size > 10_000


def test_every_shipped_scene_loads():
    for path in SCENES.glob("*.toml"):
        assert load_scene(path).pulses
