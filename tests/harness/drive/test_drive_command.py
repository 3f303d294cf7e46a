"""``pipeplug drive`` end to end: an elastic drive from the soil face to its target, its CSV, PNGs
and summary, and the counts of the drivability curve."""
import csv
import re

import pytest
from drive_helpers import toml_text

from pipeplug_harness.drive.report import blows_per_interval

# A 1 m pipe struck by 0.4 ms blows (one wave round trip): "auto" picks the elastic model.
ELASTIC = {"pipe": {"L1": 1.0}, "plug": {"L2": 0.5, "tau2": 3.0e4}, "soil": {"tau1": 2.0e5},
           "blows": {"amplitude": 2.0e5, "duration": 4e-4, "period": 0.02},
           "model": {"elastic": "auto", "dx": 0.05},
           "drive": {"target": 0.5, "refusal_set": 1e-6, "step": 4e-5}}


def test_an_elastic_drive_reaches_its_target(pipeplug_cli, fmu_file, tmp_path):
    (tmp_path / "el.toml").write_text(toml_text(ELASTIC))
    proc = pipeplug_cli("drive", "el.toml", "--fmu", fmu_file, "--out", "o")
    assert "elastic model" in proc.stdout
    found = re.search(r"el: (\d+) blows, drive time .* at 3000 blows/min; target reached at "
                      r"penetration ([0-9.]+) m", proc.stdout)
    assert found, proc.stdout
    rows = list(csv.DictReader(open(tmp_path / "o" / "el.csv")))
    assert list(rows[0])[:4] == ["blow", "t_start [s]", "set [m]", "penetration [m]"]
    assert len(rows) == int(found.group(1)) > 1
    sets = [float(r["set [m]"]) for r in rows]
    penetration = [float(r["penetration [m]"]) for r in rows]
    assert penetration[-1] >= 0.5 > penetration[-2]
    assert sum(sets) == pytest.approx(penetration[-1], rel=1e-12)
    assert all(float(r["W_input [J]"]) > 0.0 for r in rows)
    assert all(r["settled"] in ("rest", "front", "moving") for r in rows)
    for r in rows:      # the friction work after the front end stopped is part of the window's
        window = float(r["W_friction_outer [J]"]) + float(r["W_friction_inner [J]"])
        assert 0.0 <= float(r["ringing_friction [J]"]) <= window * (1.0 + 1e-12)
    for name in ("el_penetration.png", "el_drivability.png"):
        assert (tmp_path / "o" / name).stat().st_size > 10_000


def test_a_solver_option_is_set_as_the_fmu_takes_it(pipeplug_cli, fmu_file, tmp_path):
    """[model] solver = "exact" ended in a traceback (AttributeError from setString)."""
    (tmp_path / "s.toml").write_text(toml_text({
        "soil": {"tau1": 2.0e5}, "blows": {"amplitude": 1.5e4, "duration": 0.01,
                                           "period": 0.015},
        "model": {"elastic": False, "solver": "exact"}, "drive": {"max_blows": 2}}))
    proc = pipeplug_cli("drive", "s.toml", "--fmu", fmu_file, "--out", "o")
    assert "s: 2 blows" in proc.stdout or "s: 1 blows" in proc.stdout, proc.stdout


def test_a_bad_file_is_refused_with_the_reason(pipeplug_cli, fmu_file, tmp_path):
    (tmp_path / "bad.toml").write_text(toml_text({"drive": {"target": 2.0}}))
    proc = pipeplug_cli("drive", "bad.toml", "--fmu", fmu_file, check=False)
    assert proc.returncode == 2 and "target = 2.0 m; allowed: > 0 and <= L1 = 1.0" in proc.stderr
    assert proc.stderr.startswith("pipeplug drive: bad.toml: [drive] target")
    assert len(proc.stderr.splitlines()) == 1 and not proc.stdout


class _Blow:
    def __init__(self, penetration):
        self.penetration = penetration


class _Result:
    def __init__(self, depths):
        self.blows = [_Blow(d) for d in depths]


def test_blows_per_interval_counts_blows_by_final_penetration():
    starts, counts = blows_per_interval(_Result([0.1, 0.2, 0.3, 0.6, 0.61, 0.62, 0.8]), 0.25)
    assert list(starts) == [0.0, 0.25, 0.5, 0.75]
    assert list(counts) == [2, 1, 3, 1]
