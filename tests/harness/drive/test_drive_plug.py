"""The drive's plug and pace per blow (plug length, IFR, L2/s, coring or plugged, metres per
hour) and its clean-outs: the file's rules, the refusal by an FMU without the input, and the
blows they fall on."""
import csv
import math
from pathlib import Path

import numpy as np
import pytest
from drive_helpers import toml_text

from pipeplug_harness.drive.file import load_drive
from pipeplug_harness.drive.report import summary, write_csv
from pipeplug_harness.drive.run import drive_with, run_drive_on_core
from pipeplug_harness.errors import UserError
from pipeplug_harness.session import CoreSession
from pipeplug_references.rigid_ivp import simulate

# test_drive_rigid's MOVING case: blows end moving, then a blow that does not move the pipe
MOVING = dict(tau1=2.0e5, tau2=3.0e4, amplitude=1.5e4, duration=0.01, period=0.015)
RIGID = {"plug": {"L2": 0.6, "tau2": MOVING["tau2"]}, "soil": {"tau1": MOVING["tau1"]},
         "blows": {"amplitude": MOVING["amplitude"], "duration": MOVING["duration"],
                   "period": MOVING["period"]},
         "model": {"elastic": False}, "drive": {"refusal_set": 0.0, "max_blows": 6}}


def _load(tmp_path, sections):
    path = tmp_path / "d.toml"
    path.write_text(toml_text(sections))
    return load_drive(path)


def test_a_fixed_plug_is_plugged_and_the_pace_is_the_reference_s(tmp_path):
    """Model II reference (independent of the core): each blow's set at 4000 blows/min gives
    its metres per hour; the fixed plug's IFR is 0 (plugged), L2/s the file's L2 over the
    reference's penetration; the last blow, which does not move the pipe, has no IFR."""
    result = run_drive_on_core(_load(tmp_path, RIGID))
    assert result.outcome == "static"
    n = len(result.blows)
    segments = [(MOVING["duration"], MOVING["amplitude"]),
                (MOVING["period"] - MOVING["duration"], 0.0)] * n
    ref = simulate({"L1": 1.0, "L2": 0.6, "tau1": MOVING["tau1"], "tau2": MOVING["tau2"]},
                   segments, np.arange(n + 1) * MOVING["period"], contact_growth=True)
    depth = ref["u_pipe"][1:]
    sets = np.diff(ref["u_pipe"])
    per_hour = 60.0 / MOVING["period"] * 60.0
    for blow, s, d in zip(result.blows, sets, depth):
        assert blow.metres_per_hour == pytest.approx(s * per_hour, rel=1e-8, abs=1e-9)
        assert blow.L2 == 0.6 and blow.plr == pytest.approx(0.6 / d, rel=1e-8)
    assert all(b.ifr == 0.0 and b.plugging == "plugged" for b in result.blows[:-1])
    last = result.blows[-1]
    assert last.set == 0.0 and last.ifr is None and last.plugging == ""
    assert result.metres_per_hour == pytest.approx(depth[-1] * 3600.0 / (n * MOVING["period"]),
                                                   rel=1e-8)
    rows = list(csv.DictReader(open(write_csv(tmp_path / "d.csv", result))))
    assert rows[-1]["ifr"] == "" and rows[-1]["plugging"] == ""      # not defined
    assert float(rows[0]["ifr"]) == 0.0 and rows[0]["metres_per_hour [m/h]"]
    assert "W_face [J]" in rows[0] and "L2 [m]" in rows[0]
    text = summary(result)
    assert "m/h overall at the blow rate" in text and "last IFR not defined" in text


def test_without_penetration_the_plug_length_ratio_is_not_defined(tmp_path):
    """A first blow that cannot move the pipe (the soil's end resistance holds it: q_face S1 =
    2e7 x 6.88e-4 m^2 = 13.8 kN > 8 kN): s = 0, so L2/s and IFR are not defined."""
    sections = {**RIGID, "soil": {"tau1": 0.0, "q_face": "20 MPa"},
                "blows": {"amplitude": 8e3, "duration": 0.01, "period": 0.015}}
    result = run_drive_on_core(_load(tmp_path, sections))
    (blow,) = result.blows
    assert (blow.penetration, blow.plr, blow.ifr, blow.plugging) == (0.0, None, None, "")
    assert "L2/s not defined" in summary(result)


def test_end_resistance_work_is_reported_per_blow(tmp_path):
    """Each blow's input work goes into friction and the face's work (W_face per blow)."""
    sections = {**RIGID, "soil": {"tau1": MOVING["tau1"], "q_face": "5 MPa",
                                  "q_plug_face": "50 kPa"}}
    result = run_drive_on_core(_load(tmp_path, sections))
    face = sum(b.works["W_face"] for b in result.blows)
    spent = sum(b.W_friction_outer + b.W_friction_inner + b.works["W_face"]
                for b in result.blows)
    assert face > 0.0 and spent == pytest.approx(sum(b.W_input for b in result.blows),
                                                 rel=1e-12)


@pytest.mark.parametrize("drive, match", [
    ({"cleanout_at": ["1 m"], "cleanout_at_blows": [3]}, "both given; allowed: one of them"),
    ({"cleanout_at": ["0.5 m", "0.2 m"]}, r"cleanout_at = \['0.5 m', '0.2 m'\]; allowed: "
                                          r"values in strictly ascending order"),
    ({"cleanout_at_blows": [3, 3]}, "strictly ascending"),
    ({"cleanout_at_blows": [0, 3]}, r"cleanout_at_blows\[0\] = 0; allowed: >= 1"),
    ({"cleanout_at": ["2 kg"]}, r"cleanout_at\[0\] = '2 kg'; allowed: a quantity of the "
                                r"dimension of m"),
    ({"cleanout_at": []}, "a non-empty list of numbers"),
    ({"cleanout_at": 0.5}, "a non-empty list of numbers"),
    ({"cleanout_at_blows": [2.5]}, "an integer"),
])
def test_clean_out_lists_follow_the_format_s_rules(tmp_path, drive, match):
    with pytest.raises(UserError, match=match):
        _load(tmp_path, {**RIGID, "drive": {**RIGID["drive"], **drive}})


class _Cleaning(CoreSession):
    """A stand-in of an instance with the input ``cleanouts``: the core model, and a record of
    the steps at whose start the input rose (the plug itself is not cleaned: this checks where
    the drive puts the clean-outs, not what they do)."""

    def __init__(self, start_values):
        super().__init__(start_values)
        self.inputs = self.inputs | {"cleanouts"}
        self.cleaned_at = []

    def cleanout(self):
        self.cleaned_at.append(self.steps)

    def step(self, t, h, q):
        if self.cleaned_at and self.cleaned_at[-1] == self.steps:
            self.cleaned_at[-1] = t                 # the time of the step it rose before
        return super().step(t, h, q)


@pytest.mark.parametrize("by", ["blows", "penetration"])
def test_clean_outs_rise_at_the_start_of_their_blows(tmp_path, by):
    """By number: before blows 2 and 4. By penetration: before the first blow starting at or
    past each value; two values passed in one blow are one clean-out (two thresholds between
    the penetrations after blows 1 and 2: before blow 3; one equal to the penetration after
    blow 3: before blow 4)."""
    growing = {**RIGID, "plug": {**RIGID["plug"], "plug_growth": True}}
    free = run_drive_on_core(_load(tmp_path, growing))
    depth = [b.penetration for b in free.blows]
    if by == "blows":
        drive, expected = {"cleanout_at_blows": [2, 4]}, [2, 4]
    else:
        between = [0.6 * depth[0] + 0.4 * depth[1], 0.5 * (depth[0] + depth[1]),
                   depth[2]]
        drive, expected = {"cleanout_at": [f"{x!r} m" for x in between]}, [3, 4]
    spec = _load(tmp_path, {**growing, "drive": {**RIGID["drive"], **drive}})
    session = _Cleaning(spec.start_values)
    result = drive_with(spec, session)
    assert [b.blow for b in result.blows if b.cleanout] == expected
    assert session.cleaned_at == [(n - 1) * MOVING["period"] for n in expected]
    assert result.cleanouts == len(expected)
    assert [b.penetration for b in result.blows] == depth      # the stand-in cleans nothing


class _NoCleaning(CoreSession):
    """A stand-in of an FMU without the input ``cleanouts`` (an older PipePlug.fmu)."""

    def __init__(self, start_values):
        super().__init__(start_values)
        self.inputs = frozenset({"Q", "strikes", "v_strike"})


def test_clean_outs_need_a_growing_plug_and_an_fmu_with_the_input(pipeplug_cli, fmu_file,
                                                                  tmp_path):
    """Without [plug] plug_growth = true the file is refused before any run (exit 2, no
    output folder); with it, an instance without the input ``cleanouts`` refuses the drive."""
    sections = {**RIGID, "drive": {**RIGID["drive"], "cleanout_at": ["0.2 m", "0.4 m"]}}
    (tmp_path / "c.toml").write_text(toml_text(sections))
    proc = pipeplug_cli("drive", "c.toml", "--fmu", fmu_file, "--out", "o", check=False)
    assert proc.returncode == 2 and not (tmp_path / "o").exists()
    assert proc.stderr.strip() == (
        "pipeplug drive: c.toml: [drive] cleanout_at = [0.2, 0.4]; allowed: none without "
        "[plug] plug_growth = true (only a plug that grows is cleaned out)")
    growing = {**sections, "plug": {**RIGID["plug"], "plug_growth": True}}
    (tmp_path / "g.toml").write_text(toml_text(growing))
    spec = load_drive(tmp_path / "g.toml")
    with pytest.raises(UserError, match="no input 'cleanouts'"):
        drive_with(spec, _NoCleaning(spec.start_values))


def test_clean_outs_through_the_fmu(run_drive):
    """The FMU's input cleanouts, output L2_now, parameters plug_growth, L2_after_cleanout
    from a drive file. A clean-out leaves at most
    L2_after_cleanout plus what the blow itself adds, at most its set (soil enters the pipe no
    faster than the pipe advances)."""
    sections = {**RIGID, "plug": {**RIGID["plug"], "plug_growth": True,
                                  "L2_after_cleanout": 0.1},
                "drive": {**RIGID["drive"], "cleanout_at_blows": [3]}}
    got = run_drive(sections)
    blows = got["blows"]
    assert [b["blow"] for b in blows if b["cleanout"]] == [3]
    third = blows[2]
    assert third["L2"] <= 0.1 + third["set"] * (1.0 + 1e-9) < blows[1]["L2"]
    assert third["works"]["W_removed"] > 0.0
    assert all(math.isfinite(b["ifr"]) for b in blows if b["set"] != 0.0)


DRIVES = Path(__file__).resolve().parents[3] / "scenes" / "drives"
SOIL_KEYS = ("L2", "plug_growth", "q_face", "q_plug_face")     # what the plug's drives add


def test_the_casing_drives_with_a_growing_plug_load_as_their_comments_derive_them():
    """The two files load (the core builds their model: ram, end resistance and a growing plug
    together), start empty, take the unit end bearing Nq p'o of the API method for medium dense
    sand (Nq = 20) at the overburden stress of the casing's axis (rho2 g z, z = 5.5 ft below the
    tie plus half the 24-in diameter) on both faces, keep every other value of the ram drive, and
    the second differs from the first by its one clean-out at mid-length only."""
    ram = load_drive(DRIVES / "casing_24in_17m_ram.toml")
    plug = load_drive(DRIVES / "casing_24in_17m_ram_plug.toml")
    clean = load_drive(DRIVES / "casing_24in_17m_ram_plug_cleanout.toml")
    z = 5.5 * 0.3048 + 24 * 0.0254 / 2
    q = 20.0 * 2000.0 * 9.81 * z
    start = plug.start_values
    assert start["q_face"] == start["q_plug_face"] == pytest.approx(q, rel=1e-5)
    assert start["L2"] == 0.0 and start["plug_growth"] is True
    assert plug.cleanouts is None
    assert {k: v for k, v in start.items() if k not in SOIL_KEYS} == {
        k: v for k, v in ram.start_values.items() if k not in SOIL_KEYS}
    assert (plug.hammer, plug.target, plug.refusal_length, plug.yield_stress) == (
        ram.hammer, ram.target, ram.refusal_length, ram.yield_stress)
    assert clean.cleanouts.by == "penetration" and clean.cleanouts.at == (plug.target / 2,)
    assert clean.start_values == {**start, "L2_after_cleanout": 0.0}
    assert clean.hammer == plug.hammer and clean.target == plug.target


def test_the_damped_casing_drive_is_the_growing_plug_drive_with_smiths_sand_values():
    """Smith (1960), sand: J = 0.15 s/ft at the point, J' = 0.05 s/ft on the side, in s/m;
    every other value that of casing_24in_17m_ram_plug.toml."""
    plug = load_drive(DRIVES / "casing_24in_17m_ram_plug.toml")
    damped = load_drive(DRIVES / "casing_24in_17m_ram_plug_damped.toml")
    assert damped.start_values == {**plug.start_values,
                                   "J_shaft": pytest.approx(0.05 / 0.3048, abs=5e-4),
                                   "J_face": pytest.approx(0.15 / 0.3048, abs=5e-4)}
    assert (damped.hammer, damped.target, damped.refusal_length, damped.yield_stress,
            damped.cleanouts) == (plug.hammer, plug.target, plug.refusal_length,
                                  plug.yield_stress, None)


def test_the_plug_ratio_axis_is_logarithmic_only_over_more_than_a_decade():
    """A fixed plug's L2/s falls from 17 m / 0.3 m to 1 (log10 56.7 = 1.75 decades: a log
    axis); a growing plug's stays near 1 (0.98-1.003: a linear one); gaps do not count."""
    from pipeplug_harness.drive.plots import _decades
    assert _decades(np.array([17.0 / 0.3, np.nan, 1.0])) == pytest.approx(math.log10(17 / 0.3))
    assert _decades(np.array([0.98, 1.003, np.nan])) < 1.0
    assert _decades(np.array([np.nan, 2.0])) == 0.0
