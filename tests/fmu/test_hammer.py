"""Hammer.fmu on its own: modelDescription.xml per the contract, validation, the exact blow train
on grids containing its edges (as hosts compute their points), Q after initialization and after
each step, refusals like PipePlug's, state save/restore, and the loader in a plain C host."""
from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest
from fmi_c_host import LOG_CATEGORIES, CHost, guid_of, hexed, resource_uri
from fmu_helpers import run_scenario

#: The contract's Hammer parameters: name -> (type, unit, default). Copied from the contract.
CONTRACT = {"amplitude": ("Real", "N", 23000.0), "duration": ("Real", "s", 0.05),
            "period": ("Real", "s", 0.2), "count": ("Integer", None, 1),
            "start": ("Real", "s", 0.0),
            # the ram mode (names of the project's own; the contract names what they mean)
            "ram_mass": ("Real", "kg", 0.0), "rated_energy": ("Real", "J", 0.0),
            "efficiency": ("Real", "1", 1.0), "blows_per_minute": ("Real", "1/min", 60.0)}
#: Outputs: name -> (type, unit).
OUTPUTS = {"Q": ("Real", "N"), "strikes": ("Integer", None), "v_strike": ("Real", "m/s")}
ERROR, DISCARD = 3, 2
NS = 10 ** 9
#: A train whose numbers are not the defaults: a pull (negative force) starting late.
TRAIN = {"amplitude": -1234.5, "duration": 0.03, "period": 0.07, "count": 3, "start": 0.02}


def expected_q(t_ns: int, amplitude, duration, period, count, start) -> float:
    """The train at the integer time ``t_ns`` [ns], in integer arithmetic (times given in s
    must be whole nanoseconds): right-continuous, blow k on [start + k period, + duration)."""
    since = t_ns - round(start * NS)
    if since < 0:
        return 0.0
    k = since // round(period * NS)
    if count and k >= count:
        return 0.0
    return float(amplitude) if since - k * round(period * NS) < round(duration * NS) else 0.0


def _hammer_run(hammer_dir, params, times, **kwargs) -> dict:
    return run_scenario("sequence", hammer_dir, script="hammer_scenarios.py", params=params,
                        times=times, **kwargs)


# modelDescription.xml -----------------------------------------------------------------------
@pytest.fixture(scope="module")
def md(hammer_file):
    with zipfile.ZipFile(hammer_file) as zf:
        return ET.fromstring(zf.read("modelDescription.xml"))


def test_fmpy_validation_finds_no_problem(hammer_file):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(hammer_file)) == []


def test_model_description_per_contract(md):
    cs = md.find("CoSimulation")
    assert (md.get("fmiVersion"), md.get("modelName"), cs.get("modelIdentifier")) == (
        "2.0", "Hammer", "Hammer")
    for flag in ("canHandleVariableCommunicationStepSize", "canGetAndSetFMUstate",
                 "canSerializeFMUstate"):
        assert cs.get(flag) == "true", flag
    variables = {v.get("name"): v for v in md.find("ModelVariables")}
    assert set(variables) == {*OUTPUTS, *CONTRACT}
    # The first Hammer's value references stay: Q 0, amplitude 1, ..., start 5.
    refs = {name: int(v.get("valueReference")) for name, v in variables.items()}
    assert [refs[n] for n in ("Q", "amplitude", "duration", "period", "count", "start")] == [
        0, 1, 2, 3, 4, 5]
    units = {u.get("name"): {k: float(x) for k, x in u.find("BaseUnit").attrib.items()}
             for u in md.find("UnitDefinitions")}
    assert units == {"N": {"kg": 1, "m": 1, "s": -2}, "s": {"s": 1}, "kg": {"kg": 1},
                     "J": {"kg": 1, "m": 2, "s": -2}, "1": {}, "m/s": {"m": 1, "s": -1},
                     "1/min": {"s": -1, "factor": pytest.approx(1 / 60, rel=1e-15)}}
    for name, (kind, unit) in OUTPUTS.items():
        q = variables[name]
        assert (q.get("causality"), q[0].tag, q[0].get("unit")) == ("output", kind, unit)
        assert q.get("initial") == "calculated" and q[0].get("start") is None  # from parameters
    unknowns = [int(u.get("index")) - 1 for u in md.find("ModelStructure/InitialUnknowns")]
    assert sorted(unknowns) == sorted(refs[n] for n in OUTPUTS)
    for name, (kind, unit, default) in CONTRACT.items():
        var = variables[name]
        assert (var.get("causality"), var.get("variability"), var[0].tag) == (
            "parameter", "fixed", kind), name
        assert var[0].get("unit") == unit and float(var[0].get("start")) == default, name
        assert len(var.get("description", "")) > 10, name
    assert float(variables["efficiency"][0].get("max")) == 1.0
    exp = md.find("DefaultExperiment")
    start, stop, step = (float(exp.get(k)) for k in ("startTime", "stopTime", "stepSize"))
    assert start == 0.0 and stop > start and 0.0 < step < stop
    for edge in (0.0, 0.05):                    # the default train's edges are on its grid
        assert round(edge / step) * step == pytest.approx(edge, abs=1e-15)


def test_shipped_under_names_of_its_own(hammer_file):
    """Modules that cannot clash with PipePlug's in one interpreter; its own loader."""
    fmu = zipfile.ZipFile(hammer_file)
    names = fmu.namelist()
    module = fmu.read("resources/slavemodule.txt").decode().strip()
    tag = module.removeprefix("hammer_slave_")
    assert module != tag and len(tag) == 12
    for name in (f"resources/{module}.py", f"resources/hammer_fmu_{tag}/hammer.py",
                 f"resources/hammer_fmu_{tag}/blows.py", f"resources/hammer_fmu_{tag}/fmi.py"):
        assert name in names, name
    assert not [n for n in names if "pipeplug_fmu_" in n or "pipeplug_slave_" in n]
    assert not [n for n in names if "__pycache__" in n]
    assert {"binaries/linux64/Hammer.so", "binaries/linux64/Hammer_pythonfmu.so",
            "binaries/win64/Hammer.dll"} <= set(names)


def test_documentation_states_the_timing(hammer_file):
    html = zipfile.ZipFile(hammer_file).read("documentation/index.html").decode()
    for text in ("right-continuous", "after fmi2DoStep(t, h): Q = Q(t + h)",
                 "after fmi2ExitInitializationMode", "PIPEPLUG_PYTHON", "no one-step delay"):
        assert text in html, text
    for name in ("Q", *CONTRACT):
        assert f"<td>{name}</td>" in html, name


# The train --------------------------------------------------------------------------------------
def _grids(h_ns: int, n: int) -> dict:
    """The same grid as three kinds of host compute it."""
    h = h_ns / NS
    accumulated, t = [0.0], 0.0
    for _ in range(n):
        t += h
        accumulated.append(t)
    return {"k*h": [k * h for k in range(n + 1)], "t += h": accumulated,
            "integer ns": [k * h_ns / NS for k in range(n + 1)]}


@pytest.mark.parametrize("host", ["k*h", "t += h", "integer ns"])
def test_output_is_the_exact_train_on_a_grid_with_its_edges(hammer_dir, host):
    h_ns = 10_000_000                                   # 10 ms: every edge of TRAIN is on it
    times = _grids(h_ns, 30)[host]
    result = _hammer_run(hammer_dir, TRAIN, times)
    assert result["status"] == 0
    want = [expected_q(k * h_ns, **TRAIN) for k in range(31)]
    # q[0]: right after initialization (t = 0); q[k]: after the step ending at t_k
    assert result["q"] == want
    assert result["in_init"] == want[0]
    assert -1234.5 in want and want.count(-1234.5) == 9     # three blows of 3 steps each


def test_endless_train_over_many_accumulated_steps(hammer_dir):
    """count = 0: no end; 2000 steps of 1 ms accumulated as t += h still hit every edge."""
    params = {"amplitude": 5e3, "duration": 0.012, "period": 0.05, "count": 0, "start": 0.0}
    times = _grids(1_000_000, 2000)["t += h"]
    result = _hammer_run(hammer_dir, params, times)
    want = [expected_q(k * 1_000_000, **params) for k in range(2001)]
    assert result["q"] == want
    assert sum(q > 0 for q in want) == 40 * 12 + 1      # 40 blows, the 41st starts at 2 s


def test_after_initialization_q_is_the_force_of_the_first_step(hammer_dir):
    """A start time on a rising edge: Q is already the blow (right-continuous); on a falling
    edge it is 0; the stop time given is honoured up to its end."""
    on_edge = _hammer_run(hammer_dir, TRAIN, [0.02, 0.03, 0.05, 0.06], stop=0.06)
    assert on_edge["q"] == [-1234.5, -1234.5, 0.0, 0.0]
    assert on_edge["in_init"] == -1234.5
    off_edge = _hammer_run(hammer_dir, TRAIN, [0.05, 0.09, 0.1])
    assert off_edge["q"] == [0.0, -1234.5, -1234.5]


def test_defaults_are_one_blow_of_the_contract(hammer_dir):
    times = [k * 1e-3 for k in range(201)]
    q = _hammer_run(hammer_dir, {}, times)["q"]
    assert q == [23000.0] * 50 + [0.0] * 151


def test_ram_mode_counts_strikes_at_their_instants(hammer_dir):
    """ram_mass > 0: Q = 0, strikes counts the strikes started at or before t (one every
    60 / blows_per_minute s from start, count of them), v_strike = sqrt(2 eta E / m)."""
    params = {"ram_mass": 3000.0, "rated_energy": 30000.0, "efficiency": 0.6,
              "blows_per_minute": 240.0, "count": 3, "start": 0.05}
    times = _grids(50_000_000, 20)["t += h"]            # 50 ms steps: every strike on the grid
    result = run_scenario("ram_sequence", hammer_dir, script="hammer_scenarios.py",
                          params=params, times=times)
    assert result["status"] == 0
    speed = (2 * 0.6 * 30000.0 / 3000.0) ** 0.5          # 3.4641 m/s
    # strikes at 0.05, 0.30, 0.55 s: steps 1, 6 and 11 of 50 ms
    want = [min(3, (k - 1) // 5 + 1) if k >= 1 else 0 for k in range(21)]
    assert [row[1] for row in result["rows"]] == want
    assert {row[0] for row in result["rows"]} == {0.0}
    assert {row[2] for row in result["rows"]} == {speed}


# Refusals ---------------------------------------------------------------------------------------
#: id -> (kind, value, status, texts of the one log line)
REFUSALS = {
    "NaN amplitude": ("parameters", {"amplitude": float("nan")}, ERROR,
                      ["amplitude = nan is not allowed", "finite"]),
    "duration > period": ("parameters", {"duration": 0.3}, ERROR,
                          ["duration = 0.3 is not allowed", "<= period", "0.2"]),
    "zero duration": ("parameters", {"duration": 0.0}, ERROR, ["duration = 0.0", "> 0"]),
    "negative period": ("parameters", {"period": -0.2}, ERROR, ["period = -0.2", "> 0"]),
    "negative count": ("parameters", {"count": -1}, ERROR, ["count = -1", ">= 0"]),
    "infinite start": ("parameters", {"start": float("inf")}, ERROR, ["start = inf"]),
    "fixed parameter after init": ("fixed_after_init", ["period", 0.3], ERROR,
                                   ["period = 0.3", "after initialization"]),
    "output set": ("set_output", None, ERROR, ["Q = 1.0", "settable"]),
    "unknown value reference (get)": ("unknown_get", 99, ERROR, ["valueReference = 99"]),
    "unknown value reference (set)": ("unknown_set", 2 ** 32 - 1, ERROR,
                                      ["valueReference = 4294967295"]),
    "Integer read as Real": ("wrong_type", None, ERROR, ["valueReference = 4", "Real"]),
    "damaged FMU state": ("bad_state", None, ERROR, ["serializedState", "allowed", "Hammer"]),
    "step before initialization": ("before_init", None, ERROR,
                                   ["fmi2DoStep is not allowed in instantiated", "stepping"]),
    "wrong communication point": ("wrong_time", None, DISCARD,
                                  ["currentCommunicationPoint = 0.5", "0.01"]),
    "zero step": ("zero_step", None, DISCARD, ["communicationStepSize = 0.0", "> 0"]),
    "past stopTime": ("past_stop", None, ERROR, ["0.03", "stopTime"]),
    "efficiency above 1": ("parameters", {"efficiency": 1.5}, ERROR,
                           ["efficiency = 1.5 is not allowed", "<= 1"]),
    "a ram without energy": ("parameters", {"ram_mass": 100.0}, ERROR,
                             ["rated_energy = 0.0 is not allowed", "> 0 with a ram",
                              "ram_mass = 100.0"]),
    "no blow rate": ("parameters", {"blows_per_minute": 0.0}, ERROR,
                     ["blows_per_minute = 0.0", "> 0"]),
}


@pytest.mark.parametrize("case", list(REFUSALS), ids=list(REFUSALS))
def test_refusal_like_pipeplugs(hammer_dir, case):
    kind, value, status, texts = REFUSALS[case]
    result = run_scenario("refusals", hammer_dir, script="hammer_scenarios.py", kind=kind,
                          value=value)
    statuses = result["statuses"]
    assert statuses["refused"] == status, statuses
    assert len(result["log_at_refusal"]) == 1, result["log_at_refusal"]
    line = result["log_at_refusal"][0]
    category = {ERROR: "logStatusError", DISCARD: "logStatusDiscard"}[status]
    assert (line["instance"], line["status"], line["category"]) == ("bad", status, category)
    for text in texts:
        assert text in line["message"], (text, line["message"])
    later = result["log"][len(result["log_at_refusal"]):]   # "good" is quiet throughout
    if status == ERROR:        # a short line for each refused call until reset; terminate is not
        assert (statuses["later_get"], statuses["later_terminate"]) == (ERROR, 0)
        assert [(e["instance"], e["status"], e["category"]) for e in later] == [
            ("bad", ERROR, "logStatusError")], later
        assert "fmi2GetReal is not allowed after an error" in later[0]["message"], later
    else:
        assert (statuses["later_get"], statuses["later_terminate"]) == (0, 0)
        assert later == [], later
    assert (statuses["reset"], statuses["after_reset"]) == (0, 0)
    assert result["after_reset"] == [23000.0, 23000.0, 0.0]       # usable again, defaults
    assert result["good_q"] == [0.0, 23000.0, 0.0]


# State ------------------------------------------------------------------------------------------
def test_state_save_restore_and_serialize(hammer_dir):
    times = [k * 0.01 for k in range(31)]
    result = run_scenario("state", hammer_dir, script="hammer_scenarios.py", params=TRAIN,
                          times=times, save_index=4)
    want = [expected_q(k * 10_000_000, **TRAIN) for k in range(5, 31)]
    for name, run in result["runs"].items():
        assert run == want, name
    assert set(result["right_after"].values()) == {expected_q(40_000_000, **TRAIN)}
    assert result["restored"] == TRAIN
    assert result["refused_change"] == ERROR


# The loader in a C host -------------------------------------------------------------------------
def test_loader_in_a_plain_c_host(hammer_dir, c_host, c_host_env):
    """No Python in the process: the loader starts PIPEPLUG_PYTHON's; a refusal is fmi2Error
    with a category; after fmi2Reset the instance runs the train; the exit guard is armed."""
    from fmpy import read_model_description

    vr = {v.name: v.valueReference for v in read_model_description(str(hammer_dir)).modelVariables}
    host = CHost(c_host, Path(hammer_dir) / "binaries" / "linux64" / "Hammer.so", c_host_env)
    made = host("instantiate", hexed("c"), hexed(guid_of(hammer_dir)),
                hexed(resource_uri(hammer_dir)), 1)
    assert made["kind"] == "int", made
    ident = made["words"][0]

    def start(duration):
        for command in (("setupExperiment", "none", "0.0", "none"), ("enterInitializationMode",)):
            assert host("call", ident, *command)["status"] == 0
        assert host("call", ident, "setReal", 1, vr["duration"], repr(duration))["status"] == 0
        return host("call", ident, "exitInitializationMode")

    refused = start(0.5)
    assert refused["status"] == ERROR
    (line,) = refused["log"]
    assert line[1] == ERROR and line[3] in LOG_CATEGORIES and "duration = 0.5" in line[2]
    assert host("call", ident, "reset")["status"] == 0
    assert start(0.03)["status"] == 0
    q = []
    for k in range(5):
        assert host("call", ident, "doStep", repr(k * 0.01), "0.01")["status"] == 0
        q.append(float(host("call", ident, "getReal", 1, vr["Q"])["words"][1]))
    assert q == [23000.0, 23000.0, 0.0, 0.0, 0.0]
    assert int(host("guard")["words"][0]) != 0
    assert host.close() == 0
