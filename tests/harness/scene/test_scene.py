"""Scene files: the closed key table, units, required sections, plausibility, the blow-train
rules, the auto choice, and a run through the FMU."""
import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest

from pipeplug_harness.errors import UserError
from pipeplug_harness.limits import Limits
from pipeplug_harness.scene.file import load_scene
from pipeplug_harness.spec import AUTO_RATIO

SCENES = Path(__file__).resolve().parents[3] / "scenes"
#: the sections every scene needs (the paper's pipe, plug and soil)
BASE = "[pipe]\nL1 = 1.0\n[plug]\nL2 = 1.0\ntau2 = 1.0e4\n[soil]\ntau1 = 0.0\n"
BLOW = "[blows]\namplitude = 23000.0\nduration = 0.05\n"


def _write(tmp_path, text, name="s"):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, match", [
    ("[pipes]\nL1 = 1.0\n", "unknown section.*pipe, plug, soil"),
    (BASE + BLOW + "[pipe]\n", "not valid TOML"),
    ("[pipe]\nlength = 1.0\n", "unknown key 'length'.*L1, R1"),
    (BASE + BLOW + "[model]\nelastic = \"maybe\"\n", "true, false or \"auto\""),
    (BASE + BLOW.replace("duration", "count = 2.5\nduration"), "an integer"),
    (BASE + BLOW + "[output]\nvariables = [\"speed\"]\n", "allowed: v_pipe"),
])
def test_unknown_keys_and_values_name_the_allowed_ones(tmp_path, text, match):
    with pytest.raises(UserError, match=match):
        load_scene(_write(tmp_path, text))


@pytest.mark.parametrize("blows, match", [
    # each of these ran before and gave a result, silently wrong (exit 0)
    ("duration = -0.05", r"\[blows\] duration = -0.05; allowed: > 0 s"),
    ("duration = 0.05\nstart = -0.1", r"\[blows\] start = -0.1; allowed: >= 0 s"),
    ("duration = 0.05\ncount = 3\nperiod = -0.2", r"\[blows\] period = -0.2; allowed: > 0 s"),
    ("duration = 0.05\ncount = 3\nperiod = 200000.0", r"\[blows\] period = 200000.0 s is outside"),
    ("duration = 0.05\ncount = 3\nperiod = 0.02", r"duration = 0.05; allowed: .*<= period"),
    ("duration = 0.05\n[checks]\nallow = [\"start\"]\n[blows]\nstart = -0.1",
     "not valid TOML"),
])
def test_blow_trains_follow_the_hammers_rules(tmp_path, blows, match):
    text = BASE + "[blows]\namplitude = 23000.0\n" + blows + "\n"
    with pytest.raises(UserError, match=match):
        load_scene(_write(tmp_path, text))


def test_a_negative_start_allowed_by_name_is_still_refused(tmp_path):
    text = BASE + BLOW + "start = -0.1\n[checks]\nallow = [\"start\"]\n"
    with pytest.raises(UserError, match=r"\[blows\] start = -0.1; allowed: >= 0 s"):
        load_scene(_write(tmp_path, text))


def test_a_train_without_end_runs_to_the_stop_time(tmp_path):
    """count = 0 is the Hammer's train without end (it raised IndexError here before)."""
    with pytest.raises(UserError, match=r"stop_time is missing"):
        load_scene(_write(tmp_path, BASE + BLOW + "count = 0\nperiod = 0.2\n"))
    s = load_scene(_write(tmp_path, BASE + BLOW + "count = 0\nperiod = 0.2\n[output]\n"
                                                  "stop_time = 0.5\n"))
    assert s.load.times == (0.0, 0.05, 0.2, 0.25, 0.4, 0.45)
    assert s.load.forces == (23000.0, 0.0) * 3


def test_a_stop_time_that_is_not_a_number_is_refused(tmp_path):
    with pytest.raises(UserError, match=r"\[output\] stop_time = nan; allowed: a finite"):
        load_scene(_write(tmp_path, BASE + BLOW + "[output]\nstop_time = nan\n"))


def test_every_needed_section_is_required(tmp_path):
    """No [soil] was "no friction" before; now it is an error, as is no tau1 in [soil]."""
    with pytest.raises(UserError, match=r"missing section \[soil\]"):
        load_scene(_write(tmp_path, BASE.replace("[soil]\ntau1 = 0.0\n", "") + BLOW))
    with pytest.raises(UserError, match=r"\[soil\] tau1 is missing"):
        load_scene(_write(tmp_path, BASE.replace("tau1 = 0.0\n", "") + BLOW))
    with pytest.raises(UserError, match=r"\[blows\] duration is missing"):
        load_scene(_write(tmp_path, BASE + "[blows]\namplitude = 1.0\n"))


def test_values_with_units_are_converted_and_wrong_dimensions_refused(tmp_path):
    text = ("[pipe]\nL1 = \"100 cm\"\nR1 = \"35 mm\"\n[plug]\nL2 = \"1 m\"\ntau2 = \"10 kPa\"\n"
            "[soil]\ntau1 = \"0.02 MPa\"\n[blows]\namplitude = \"23 kN\"\nduration = \"50 ms\"\n"
            "rate = \"200 /min\"\ncount = 2\n")
    s = load_scene(_write(tmp_path, text))
    assert (s.start_values["L1"], s.start_values["R1"]) == (1.0, 0.035)
    assert (s.start_values["tau2"], s.start_values["tau1"]) == (1e4, 2e4)
    assert s.load.times == (0.0, 0.05, 0.3, 0.35) and s.load.forces[0] == 23000.0
    with pytest.raises(UserError, match=r"\[pipe\] R1 = '35 kg'.*dimension of m"):
        load_scene(_write(tmp_path, text.replace("35 mm", "35 kg")))
    with pytest.raises(UserError, match=r"period = 0.3 s and rate = .* give one of them"):
        load_scene(_write(tmp_path, text + "period = 0.3\n"))


def test_implausible_values_need_to_be_allowed_by_name(tmp_path):
    """R1 = 292.3 (mm typed as m) ran before; now it needs [checks] allow = ["R1"]."""
    text = BASE.replace("L1 = 1.0", "L1 = 1.0\nR1 = 292.3") + BLOW
    with pytest.raises(UserError, match=r'R1 = 292.3 m is outside.*allow = \["R1"\]'):
        load_scene(_write(tmp_path, text))
    allowed = load_scene(_write(tmp_path, text + "[checks]\nallow = [\"R1\"]\n"))
    assert allowed.start_values["R1"] == 292.3
    with pytest.raises(UserError, match=r"\[checks\] allow names \['R9'\]"):
        load_scene(_write(tmp_path, text + "[checks]\nallow = [\"R9\"]\n"))


def test_work_past_the_limits_is_refused_before_any_allocation(tmp_path):
    many = BASE + BLOW + "count = 100000000000\nperiod = 0.05\n[checks]\nallow = [\"count\"]\n"
    with pytest.raises(UserError, match=r"asks for 1e\+11 blows.*--limit blows="):
        load_scene(_write(tmp_path, many))
    fine = BASE + BLOW + "[output]\nstep = 1e-12\n[checks]\nallow = [\"step\"]\n"
    with pytest.raises(UserError, match=r"step = 1e-12 s.*steps.*--limit steps="):
        load_scene(_write(tmp_path, fine))
    raised = load_scene(_write(tmp_path, BASE + BLOW + "[output]\nstep = 1e-6\n"),
                        Limits({"steps": 1e7}))
    assert raised.steps == 300_000


def test_auto_needs_a_positive_modulus(tmp_path):
    text = BASE.replace("L1 = 1.0", "L1 = 1.0\nE1 = -1.0") + BLOW + "[checks]\nallow = [\"E1\"]\n"
    with pytest.raises(UserError, match=r"\[pipe\] E1 = -1.0; allowed: > 0"):
        load_scene(_write(tmp_path, text))


def test_auto_picks_rigid_for_long_blows_and_elastic_for_short_ones(tmp_path):
    c1 = math.sqrt(1.95e11 / 7800)                       # 5000 m/s, docs/corrections.md D1
    round_trip = 2 * 1.0 / c1

    def blow(duration, model=""):
        return BASE + f"[blows]\namplitude = 23000.0\nduration = {duration}\n" + model

    long = load_scene(_write(tmp_path, blow(AUTO_RATIO * round_trip * 1.01)))
    short = load_scene(_write(tmp_path, blow(AUTO_RATIO * round_trip * 0.99)))
    assert long.start_values["elastic"] is False and "rigid" in long.reason
    assert short.start_values["elastic"] is True and "elastic" in short.reason
    given = load_scene(_write(tmp_path, blow(1e-4, "[model]\nelastic = false\n")))
    assert given.start_values["elastic"] is False and "given" in given.reason


def test_blows_become_a_load(tmp_path):
    s = load_scene(_write(tmp_path, BASE + "[blows]\namplitude = 5.0\nduration = 0.01\n"
                                           "count = 3\nperiod = 0.04\nstart = 0.005\n"))
    assert s.load.times == (0.005, 0.015, 0.045, 0.055, 0.085, 0.095)
    assert s.load.forces == (5.0, 0.0, 5.0, 0.0, 5.0, 0.0)


def test_scene_runs_through_the_fmu(pipeplug_cli, fmu_file, tmp_path):
    proc = pipeplug_cli("scene", SCENES / "paper_fig5_curve1.toml", "--fmu", fmu_file,
                        "--out", tmp_path / "o")
    assert "rigid model" in proc.stdout
    # the input signal gives every input of the FMU (fmpy warned of the ram's, left out)
    assert "missing input" not in proc.stdout + proc.stderr
    rows = list(csv.DictReader(open(tmp_path / "o" / "paper_fig5_curve1.csv")))
    # Fig. 5 curve 1 ends with pipe and plug together at Q0 t0/(M1 + M2) = 93.54 m/s (docs/corrections.md C4)
    assert float(rows[-1]["v_pipe [m/s]"]) == pytest.approx(93.54, abs=0.005)
    assert float(rows[-1]["time [s]"]) == pytest.approx(0.35)
    assert (tmp_path / "o" / "paper_fig5_curve1.png").stat().st_size > 10_000


def test_every_output_can_be_recorded(pipeplug_cli, fmu_file, tmp_path):
    """variables = ["at_rest"] passed the file check and then raised KeyError."""
    _write(tmp_path, BASE + BLOW + "[output]\nstop_time = 0.1\nvariables = [\"at_rest\", "
                                   "\"E_strain\", \"pipe_mode\"]\n", name="flags")
    pipeplug_cli("scene", "flags.toml", "--fmu", fmu_file, "--out", "o")
    rows = list(csv.DictReader(open(tmp_path / "o" / "flags.csv")))
    assert list(rows[0]) == ["time [s]", "at_rest", "E_strain [J]", "pipe_mode"]
    assert rows[-1]["at_rest"] in ("0", "1")


def test_two_scenes_of_one_name_are_refused(pipeplug_cli, fmu_file, tmp_path):
    """a/s.toml and b/s.toml wrote one s.csv, the second over the first."""
    for sub in ("a", "b"):
        (tmp_path / sub).mkdir()
        _write(tmp_path / sub, BASE + BLOW)
    proc = pipeplug_cli("scene", "a/s.toml", "b/s.toml", "--fmu", fmu_file, check=False)
    assert proc.returncode == 2 and "would both write s.csv" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_every_shipped_scene_loads():
    files = sorted(SCENES.glob("*.toml"))
    assert files
    for path in files:
        assert load_scene(path).load.times


RAM_SCENE = """
[pipe]
L1 = 1.0
[plug]
L2 = 1.0
tau2 = "10 kPa"
[soil]
tau1 = "40 kPa"
[hammer]
rated_energy = "400 J"
efficiency = 0.8
ram_mass = "50 kg"
rate = "300 /min"
cushion_stiffness = "2e7 N/m"
cushion_restitution = 0.8
count = 3
[model]
elastic = false
[output]
stop_time = 0.6
variables = ["u_pipe", "v_ram", "W_ram"]
"""


def test_a_scene_of_strikes_runs_through_the_fmus_inputs(pipeplug_cli, fmu_file, tmp_path):
    """[hammer] instead of [blows]: three strikes at 0, 0.2 and 0.4 s at v = sqrt(2 eta E / m)
    reach PipePlug through its inputs strikes and v_strike; the pipe is model I, whose ODE
    reference with a ram (independent of the core) gives the same motion within 1e-9."""
    from pipeplug_references.ram_ivp import simulate_ram

    (tmp_path / "ram.toml").write_text(RAM_SCENE)
    proc = pipeplug_cli("scene", tmp_path / "ram.toml", "--fmu", fmu_file, "--out",
                        tmp_path / "o")
    assert "missing input" not in proc.stdout + proc.stderr
    rows = list(csv.DictReader(open(tmp_path / "o" / "ram.csv")))
    t = np.array([float(r["time [s]"]) for r in rows])[1:]
    v = math.sqrt(2 * 0.8 * 400.0 / 50.0)
    before = np.where(np.isin(t, [0.2, 0.4]), np.nextafter(t, 0.0), t)   # outputs before a strike
    ref = simulate_ram({"L1": 1.0, "L2": 1.0, "R1": 0.035, "h1": 0.003, "rho1": 7800.0,
                        "rho2": 1800.0, "tau1": 4e4, "tau2": 1e4},
                       {"mass": 50.0, "k": 2e7, "e": 0.8},
                       [(k * 0.2, "strike", v) for k in range(3)], before)
    for name, unit in (("u_pipe", "m"), ("v_ram", "m/s"), ("W_ram", "J")):
        got = np.array([float(r[f"{name} [{unit}]"]) for r in rows])[1:]
        assert np.abs(got - ref[name]).max() <= 1e-9 * np.abs(ref[name]).max(), name


@pytest.mark.parametrize("change, words", [
    ("[blows]\namplitude = 1e4\nduration = 0.01\n", r"\[blows\] and \[hammer\] both given"),
    ("", None),
])
def test_a_scene_takes_blows_or_a_hammer(tmp_path, change, words):
    path = tmp_path / "s.toml"
    path.write_text(RAM_SCENE + change)
    if words:
        with pytest.raises(UserError, match=words):
            load_scene(path)
    else:
        scene = load_scene(path)
        assert [t for t, _ in scene.strikes] == [0.0, 0.2, 0.4]
        assert scene.start_values["ram_mass"] == 50.0 and not scene.load.forces
    path.write_text(RAM_SCENE.replace("efficiency = 0.8", "efficiency = 1.5"))
    with pytest.raises(UserError, match=r"\[hammer\] efficiency = 1.5"):
        load_scene(path)


def test_core_keys_take_their_facts_from_the_core_s_tables():
    """A key that is a core parameter or option is one line of the file format's table: its
    unit, bounds, meaning and allowed values are the core's."""
    from pipeplug import PARAMETERS
    from pipeplug.options import OPTIONS
    from pipeplug_harness.spec import SECTIONS
    core = {p.name: p for p in PARAMETERS}
    keys = {k: key for section in SECTIONS.values() for k, key in section.items()}
    for name in ("q_face", "q_plug_face", "tau1", "L1", "dx"):
        p, key = core[name], keys[name]
        assert (key.kind, key.unit, key.lower, key.meaning) == ("number", p.unit, p.lower,
                                                                p.description), name
    assert keys["solver"].choices == OPTIONS["solver"][0]


def test_end_resistance_keys_in_units(tmp_path):
    text = BASE.replace("tau1 = 0.0", 'tau1 = 0.0\nq_face = "12 MPa"\nq_plug_face = "0.3 MPa"')
    scene = load_scene(_write(tmp_path, text + BLOW))
    assert scene.start_values["q_face"] == 1.2e7 and scene.start_values["q_plug_face"] == 3e5
    with pytest.raises(UserError, match=r"\[soil\] q_face = '12 MN'; allowed: a quantity of "
                                        r"the dimension of Pa"):
        load_scene(_write(tmp_path, text.replace("12 MPa", "12 MN") + BLOW))


@pytest.mark.parametrize("text, match", [
    # each of these made the output folder and then failed in the FMU with "internal error"
    (BASE.replace("L1 = 1.0", 'L1 = "1 ft"') + BLOW, r"L2 = 1.0 is not allowed.*L1 = 0.3047"),
    (BASE + BLOW + "[output]\nvariables = []\n", r"\[output\] variables = \[\]; allowed: one or"),
    (BASE + BLOW + '[output]\nvariables = ["v_pipe", "v_pipe"]\n', r"each once"),
])
def test_values_the_core_refuses_are_mistakes_of_the_file(tmp_path, text, match):
    with pytest.raises(UserError, match=match):
        load_scene(_write(tmp_path, text))


def test_a_value_the_core_refuses_is_one_line_before_any_output(pipeplug_cli, fmu_file,
                                                                 tmp_path):
    _write(tmp_path, BASE.replace("L2 = 1.0", "L2 = 2.0") + BLOW)
    proc = pipeplug_cli("scene", "s.toml", "--fmu", fmu_file, "--out", "o", check=False)
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    assert re.fullmatch(r"pipeplug scene: s.toml: L2 = 2.0 is not allowed; allowed: .*<= L1 "
                        r"\(L1 = 1.0\)\n", proc.stderr)
    assert not (tmp_path / "o").exists()


def test_a_direct_strike_is_elastic_by_the_contact_not_a_zero_blow(tmp_path):
    """A ram on the head without a cushion: "auto" said "blow 0 s = 0 x the wave round trip"."""
    text = BASE + ('[hammer]\nrated_energy = "1 kJ"\nram_mass = "100 kg"\nrate = "60 /min"\n'
                   "count = 1\n[output]\nstop_time = 0.05\n")
    scene = load_scene(_write(tmp_path, text))
    assert scene.start_values["elastic"] is True
    assert "direct strike" in scene.reason and "0 x" not in scene.reason


def test_the_run_starts_from_the_model_s_own_outputs(pipeplug_cli, fmu_file, tmp_path):
    """The row at t = 0 is the model's state after initialization: the plug's length, at rest
    (it held the FMU's registered zeros: L2_now = 0 and at_rest = 0); the summary gives each
    output's range, a signed force's minimum included."""
    _write(tmp_path, BASE.replace("tau1 = 0.0", "tau1 = 2.0e4").replace("L2 = 1.0", "L2 = 0.5")
           + BLOW + '[output]\nstop_time = 0.1\nvariables = ["L2_now", "at_rest", "F_outer"]\n')
    proc = pipeplug_cli("scene", "s.toml", "--fmu", fmu_file, "--out", "o")
    rows = list(csv.DictReader(open(tmp_path / "o" / "s.csv")))
    assert rows[0]["time [s]"] == "0.0" and rows[0]["L2_now [m]"] == "0.5"
    assert rows[0]["at_rest"] == "1" and rows[1]["at_rest"] == "0"
    lowest = min(float(r["F_outer [N]"]) for r in rows)
    assert lowest < 0.0 and f"F_outer from {lowest:.6g} to" in proc.stdout


@pytest.mark.parametrize("model, key", [
    ('elastic = false\ndx = 0.3', r"\[model\] dx = 0.3; allowed: none with elastic = false"),
    ('elastic = false\ndt = 1e-4', r"\[model\] dt = 0.0001; allowed: none with elastic = false"),
    ('elastic = true\nsolver = "fd"', r"\[model\] solver = 'fd'; allowed: none with elastic = t"),
    ('elastic = true\ndt = 1e-4', r"\[model\] dt = 0.0001; allowed: none with elastic = true"),
])
def test_a_key_the_chosen_model_does_not_read_is_a_slip(tmp_path, model, key):
    """dt on an elastic run, dx on a rigid one, solver = "fd" with elastic = true: each ran and
    gave the results of the file without it."""
    with pytest.raises(UserError, match=key):
        load_scene(_write(tmp_path, BASE + BLOW + "[model]\n" + model + "\n"))


def test_under_auto_the_keys_of_the_model_not_chosen_are_named_not_refused(tmp_path):
    scene = load_scene(_write(tmp_path, BASE + BLOW + '[model]\nelastic = "auto"\ndx = 0.1\n'
                                                      'solver = "fd"\ndt = 1e-4\n'))
    assert scene.start_values["elastic"] is False             # a 50 ms blow on a 1 m pipe
    assert scene.reason.endswith("[model] dx unused by the rigid model's fd scheme")
    fd_ok = load_scene(_write(tmp_path, BASE + BLOW + '[model]\nelastic = false\nsolver = "fd"'
                                                      '\ndt = 1e-4\n'))
    assert "unused" not in fd_ok.reason
