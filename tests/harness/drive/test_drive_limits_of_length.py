"""A drive's results that were not results: a pipe run in beyond its length (printed as
"target reached at penetration 4.18 m" of a 2 m pipe), a drive without a plug reported as
plugged, round-off printed as a tensile stress, ENTHRU's share written as nan without a hammer,
and refusal_length = 0 silently turning the set refusal off.

Expected values are Newton's law for a rigid pipe with no resistance (the pipe's mass from the
default dimensions: M1 = rho1 pi ((R1 + h1)^2 - R1^2) L1), the model II reference
(``pipeplug_references.rigid_ivp``) and the rigid pipe's equilibrium."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from drive_helpers import toml_text

from pipeplug import PARAMETERS
from pipeplug_harness.drive.checks import DriveInvalid
from pipeplug_harness.drive.file import load_drive
from pipeplug_harness.drive.report import _still_moving, summary, write_csv
from pipeplug_harness.drive.run import NO_PLUG, run_drive_on_core
from pipeplug_harness.errors import UserError
from pipeplug_references.rigid_ivp import simulate

DEFAULT = {p.name: p.default for p in PARAMETERS}
Q = 23000.0


def _mass(L1: float) -> float:
    R1, h1 = DEFAULT["R1"], DEFAULT["h1"]
    return DEFAULT["rho1"] * math.pi * ((R1 + h1) ** 2 - R1 ** 2) * L1


def _load(tmp_path, sections):
    path = tmp_path / "d.toml"
    path.write_text(toml_text(sections))
    return load_drive(path)


def _free(L1=1.0, duration=0.005, period=0.1, target=None, plug=None):
    """A rigid drive without friction, end resistance or plug (tau2 = 0)."""
    drive = {"refusal_set": 0.0, "max_blows": 5}
    if target is not None:
        drive["target"] = target
    return {"pipe": {"L1": L1}, "plug": plug or {"L2": L1, "tau2": 0.0}, "soil": {"tau1": 0.0},
            "blows": {"amplitude": Q, "duration": duration, "period": period},
            "model": {"elastic": False}, "drive": drive}


def test_a_pipe_nothing_holds_that_runs_in_beyond_its_length_is_no_result(tmp_path):
    """Blow 1 pushes the free pipe to Q td^2 / (2 M1) = 0.054 m and leaves it at Q td / M1 =
    21.4 m/s: at the next blow's start it is Q td (T - td / 2) / M1 = 2.09 m in, past L1 = 1 m
    and still moving. Before, this printed "target reached at penetration 2.09 m"."""
    M1, td, T = _mass(1.0), 0.005, 0.1
    assert Q * td ** 2 / (2.0 * M1) < 1.0                     # in the soil while pushed
    depth, v = Q * td * (T - td / 2.0) / M1, Q * td / M1
    with pytest.raises(DriveInvalid) as caught:
        run_drive_on_core(_load(tmp_path, _free()))
    text = str(caught.value)
    assert text.startswith("blow 1: the pipe ran in beyond its length")
    assert f"penetration {depth:.6g} m > L1 = 1 m" in text
    assert f"still moving at {v:.4g} m/s" in text
    assert "nothing in the soil holds it" in text and "\n" not in text


def test_a_blow_that_drives_the_head_below_the_soil_face_is_no_result(tmp_path):
    """A blow of td = 0.05 s pushes the free pipe Q td^2 / (2 M1) = 5.36 m while it acts: past
    L1 = 1 m with the hammer still on it."""
    pushed = Q * 0.05 ** 2 / (2.0 * _mass(1.0))
    with pytest.raises(DriveInvalid, match=rf"blow 1: .*beyond its length while the blow drove "
                                           rf"it: penetration {pushed:.6g} m when the blow "
                                           rf"stopped acting, past L1 = 1 m"):
        run_drive_on_core(_load(tmp_path, _free(duration=0.05)))


def test_the_command_stops_with_one_line_and_writes_no_result(pipeplug_cli, fmu_file,
                                                              tmp_path):
    (tmp_path / "zero.toml").write_text(toml_text(_free()))
    proc = pipeplug_cli("drive", "zero.toml", "--fmu", fmu_file, "--out", "o", check=False)
    assert proc.returncode == 1
    (line,) = proc.stderr.strip().splitlines()
    assert "blow 1: the pipe ran in beyond its length" in line and "Traceback" not in line
    assert "no result written" in line and "target reached" not in proc.stdout
    assert not (tmp_path / "o" / "zero.csv").exists()


def test_a_target_reached_while_the_pipe_still_moves_says_so(tmp_path):
    """A 100 m free pipe: blow 1 leaves it at Q td (T - td / 2) / M1 = 0.0209 m, moving at
    Q td / M1 = 0.214 m/s, past a target of 0.02 m: the target is reached, and the summary
    says the penetration is not where the pipe comes to rest."""
    M1, td, T = _mass(100.0), 0.005, 0.1
    depth, v = Q * td * (T - td / 2.0) / M1, Q * td / M1
    result = run_drive_on_core(_load(tmp_path, _free(L1=100.0, target=0.02,
                                                     plug={"L2": 1.0, "tau2": 0.0})))
    assert result.outcome == "target" and len(result.blows) == 1
    assert result.penetration == pytest.approx(depth, rel=1e-12)
    text = summary(result)
    assert f"target reached at penetration {depth:.6g} m" in text
    assert f"still moving at {v:.4g} m/s when the drive stopped" in text


def test_a_pipe_that_coasts_past_its_length_and_stops_is_reported_as_past_it(tmp_path):
    """100 kN for 10 ms on the 1 m pipe (tau1 = 100 kPa, a 0.6 m plug at 30 kPa): the model II
    reference puts the front end at the blow's end short of L1 and at rest past it: a result,
    and the summary says by how much the head went below the soil face."""
    sections = {"plug": {"L2": 0.6, "tau2": 3.0e4}, "soil": {"tau1": 1.0e5},
                "blows": {"amplitude": 1.0e5, "duration": 0.01, "period": 0.2},
                "model": {"elastic": False}, "drive": {"refusal_set": 0.0}}
    ref = simulate({"L1": 1.0, "L2": 0.6, "tau1": 1.0e5, "tau2": 3.0e4},
                   [(0.01, 1.0e5), (0.19, 0.0)], np.array([0.0, 0.01, 0.2]),
                   contact_growth=True)
    pushed, depth = ref["u_pipe"][1], ref["u_pipe"][2]
    assert pushed < 1.0 < depth and ref["v_pipe"][2] == 0.0
    result = run_drive_on_core(_load(tmp_path, sections))
    assert result.outcome == "target" and result.blows[-1].settled == "rest"
    assert result.penetration == pytest.approx(depth, rel=1e-9)
    assert f", {depth - 1.0:.3g} m past L1 = 1 m (the pipe went on after the last blow, its " \
           f"head below the soil face)" in summary(result)


@pytest.mark.parametrize("plug, why", [({"L2": 0.0, "tau2": 2.0e4}, "L2 = 0"),
                                       ({"L2": 1.0, "tau2": 0.0}, "tau2 = 0")])
def test_a_drive_without_a_plug_reports_no_plug(tmp_path, plug, why):
    """docs/files.md: "tau2 = 0 or L2 = 0: no plug". Before, the summary read "plug 0 m ...
    (plugged)" or "plug 1 m, L2/s ... (plugged)"; now every plug measure is empty and the
    summary says "no plug". The pipe alone under its head force and friction is in
    compression everywhere (N(x) <= 0, 0 at its free front end), so no tensile stress: the
    round-off at the front end (2.6e-9 Pa) is not printed as one."""
    sections = {"pipe": {"L1": 2.0}, "plug": plug, "soil": {"tau1": 7.0e4},
                "blows": {"amplitude": Q, "duration": 0.01, "period": 0.2},
                "model": {"elastic": False}, "drive": {"target": 1.0}}
    result = run_drive_on_core(_load(tmp_path, sections))
    assert result.outcome == "target"
    assert all((b.L2, b.ifr, b.plr, b.plugging) == (None, None, None, NO_PLUG)
               for b in result.blows)
    rows = list(csv.DictReader(open(write_csv(tmp_path / "d.csv", result))))
    assert all((r["L2 [m]"], r["ifr"], r["plr"], r["plugging"]) == ("", "", "", "no plug")
               for r in rows)
    text = summary(result)
    assert f"; no plug ({why});" in text
    assert "plugged" not in text and "coring" not in text and "L2/s" not in text
    assert "MPa compressive, 0 MPa tensile" in text


def test_a_growing_plug_without_plug_friction_is_no_plug(tmp_path):
    """The elastic model lets a plug grow with tau2 = 0 (soil enters, coupled to nothing);
    that is no plug too: before, "14 of 14 blows coring"."""
    sections = {"plug": {"L2": 0.0, "tau2": 0.0, "plug_growth": True},
                "soil": {"tau1": 2.0e5},
                "blows": {"amplitude": 2.0e5, "duration": 4e-4, "period": 0.02},
                "model": {"elastic": True, "dx": 0.05},
                "drive": {"target": 0.2, "refusal_set": 1e-6, "step": 4e-5, "max_blows": 3}}
    result = run_drive_on_core(_load(tmp_path, sections))
    assert result.blows
    assert all((b.L2, b.ifr, b.plr, b.plugging) == (None, None, None, NO_PLUG)
               for b in result.blows)
    assert "; no plug (tau2 = 0)" in summary(result)


def test_a_growing_plug_that_starts_empty_is_a_plug(tmp_path):
    """L2 = 0 with plug_growth and tau2 > 0 is a plug that grows from an empty pipe (the
    casing's growing-plug drive): its measures stay defined."""
    sections = {"plug": {"L2": 0.0, "tau2": 3.0e4, "plug_growth": True},
                "soil": {"tau1": 2.0e5},
                "blows": {"amplitude": 1.5e4, "duration": 0.01, "period": 0.015},
                "model": {"elastic": False}, "drive": {"refusal_set": 0.0, "max_blows": 2}}
    result = run_drive_on_core(_load(tmp_path, sections))
    first = result.blows[0]
    assert first.L2 > 0.0 and first.plugging in ("coring", "plugged")
    assert "no plug" not in summary(result)


def test_enthru_share_without_a_hammer_is_an_empty_field(tmp_path):
    """drive.md: a ratio that is not defined is never written as a number; a force-driven
    drive has no rated energy to share ENTHRU with (before: "nan" on every row)."""
    sections = {"plug": {"L2": 0.6, "tau2": 3.0e4}, "soil": {"tau1": 2.0e5},
                "blows": {"amplitude": 1.5e4, "duration": 0.01, "period": 0.015},
                "model": {"elastic": False}, "drive": {"refusal_set": 0.0, "max_blows": 3}}
    result = run_drive_on_core(_load(tmp_path, sections))
    assert all(b.enthru_share is None for b in result.blows)
    rows = list(csv.DictReader(open(write_csv(tmp_path / "d.csv", result))))
    assert [r["enthru_share"] for r in rows] == [""] * len(rows)
    assert "nan" not in (tmp_path / "d.csv").read_text().lower()


@pytest.mark.parametrize("length", [0.0, -0.025])
def test_a_refusal_length_of_zero_or_less_is_refused(tmp_path, length):
    """10 blows advancing "less than 0 m" never refuse: the set refusal was silently off (571
    blows to a static refusal where 25 mm refuses after 47)."""
    with pytest.raises(UserError, match=rf"\[drive\] refusal_length = {length!r}; allowed: "
                                        rf"> 0 m"):
        _load(tmp_path, {"drive": {"refusal_count": 10, "refusal_length": length}})


def test_no_set_refusal_is_refusal_set_zero_and_the_summary_says_so(tmp_path):
    sections = {"plug": {"L2": 0.6, "tau2": 3.0e4}, "soil": {"tau1": 2.0e5},
                "blows": {"amplitude": 1.5e4, "duration": 0.01, "period": 0.015},
                "model": {"elastic": False}, "drive": {"refusal_set": 0.0, "max_blows": 20}}
    result = run_drive_on_core(_load(tmp_path, sections))
    assert result.outcome == "static"
    assert "(no set refusal: refusal_set = 0)" in summary(result)


@pytest.mark.parametrize("v_pipe, v_plug, says", [
    (0.25, 0.25, "still moving at 0.25 m/s when the drive stopped (it comes to rest further in)"),
    (-0.5, 0.0, "still moving at -0.5 m/s when the drive stopped (back, out of the soil)"),
    (0.0, 0.125, "the plug still moving at 0.125 m/s in the pipe when the drive stopped"),
    (0.0, 0.0, "at rest at the monitor when the drive stopped, but not yet for a wave's round "
               "trip in the pipe"),
])
def test_a_last_blow_not_settled_says_what_still_moves(v_pipe, v_plug, says):
    """The summary's end, by what the last blow left moving: never "still moving at 0 m/s"."""
    text = _still_moving(v_pipe, v_plug)
    assert says in text
    assert "0 m/s" not in text
