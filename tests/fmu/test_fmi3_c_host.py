"""The FMI 3.0 PipePlug.fmu in a plain C host (``fmi3_host.c``): no Python in the process,
nothing preloaded, the FMU's binary opened with dlopen as C importers do.

Checked, in one host process: the reference case agrees with the closed form and, bit for bit,
with the FMI 2.0 FMU in the FMI 2.0 C host; the host's logger gets the instanceEnvironment of
the instance a line is about (FMI 3.0 loggers get no instance name); the start and stop times of
fmi3EnterInitializationMode reach the slave; ``profile_points`` set from C sizes the profile
arrays, each element the scalar output at its section, and a host asking for more values than
the variables hold gets fmi3Error with one line; the exit guard is armed and the host exits
cleanly.
"""
from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from fmi_c_host import CHost, guid_of, hexed, host_env, resource_uri
from fmu_helpers import Q0, T0, assert_matches_closed_form

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input", "W_friction")
REFERENCE = {"tau1": 2e4, "tau2": 1e4}        # model I, domain I of the closed form
STEPS = 100


def token_of(fmu_dir: Path) -> str:
    return ET.parse(Path(fmu_dir) / "modelDescription.xml").getroot().get("instantiationToken")


def resource_path(fmu_dir: Path) -> str:
    """FMI 3.0's spelling: the absolute path of the resources folder, with a trailing slash."""
    return str(Path(fmu_dir) / "resources") + "/"


class Host3:
    """The FMI 3.0 C host with PipePlug's binary, its variables by name."""

    def __init__(self, c3_host, fmu_dir, env):
        from fmpy import read_model_description

        self.fmu_dir = Path(fmu_dir)
        self.host = CHost(c3_host, self.fmu_dir / "binaries" / "x86_64-linux" / "PipePlug.so",
                          env)
        self.vr = {v.name: v.valueReference
                   for v in read_model_description(str(fmu_dir)).modelVariables}

    def __call__(self, *words) -> dict:
        return self.host(*words)

    def new(self, name="c", logging=1, path=None, event_mode=0) -> dict:
        return self("instantiate", hexed(name), hexed(token_of(self.fmu_dir)),
                    hexed(path or resource_path(self.fmu_dir)), logging, event_mode)

    def ok(self, ident, *words) -> dict:
        answer = self("call", ident, *words)
        assert answer["status"] == 0 and answer["log"] == [], (words, answer)
        return answer

    def running(self, params=None, start=0.0, stop=None, points=None) -> str:
        made = self.new()
        assert made["kind"] == "int" and made["log"] == [], made
        ident = made["words"][0]
        if points is not None:
            self.ok(ident, "setUInt64", 1, self.vr["profile_points"], 1, points)
        for name, value in (params or {}).items():
            self.ok(ident, "setFloat64", 1, self.vr[name], 1, repr(float(value)))
        self.ok(ident, "enterInitializationMode", repr(start), "none" if stop is None
                else repr(stop))
        self.ok(ident, "exitInitializationMode")
        return ident

    def pulse(self, ident, names, steps, n_values=None, h=1e-3) -> np.ndarray:
        """``steps`` steps under the paper's pulse; the values of ``names`` per step."""
        n_values = n_values or len(names)
        answer = self("pulse", ident, self.vr["Q"], Q0, T0, h, steps, n_values, len(names),
                      *[self.vr[n] for n in names])
        assert answer["status"] == 0 and answer["log"] == [], answer
        return np.array(answer["words"][2:], dtype=float).reshape(steps, n_values)


def _env() -> dict:
    """PIPEPLUG_PYTHON naming this Python; no PYTHON* variable, nothing preloaded."""
    env = host_env(PIPEPLUG_PYTHON=sys.executable)
    assert "LD_PRELOAD" not in env
    return env


@pytest.fixture(scope="module")
def fmi2_reference(fmu_dir, c_host) -> np.ndarray:
    """The reference case through the FMI 2.0 FMU in the FMI 2.0 C host."""
    from fmpy import read_model_description

    vr = {v.name: v.valueReference for v in read_model_description(str(fmu_dir)).modelVariables}
    host = CHost(c_host, Path(fmu_dir) / "binaries" / "linux64" / "PipePlug.so", _env())
    ident = host("instantiate", hexed("c2"), hexed(guid_of(fmu_dir)),
                 hexed(resource_uri(fmu_dir)), 1)["words"][0]
    for words in (("setupExperiment", "none", "0.0", "none"), ("enterInitializationMode",),
                  ("setReal", 2, vr["tau1"], vr["tau2"], "20000.0", "10000.0"),
                  ("exitInitializationMode",)):
        assert host("call", ident, *words)["status"] == 0
    answer = host("pulse", ident, vr["Q"], Q0, T0, 1e-3, STEPS, len(OUTPUTS),
                  *[vr[n] for n in OUTPUTS])
    assert answer["status"] == 0, answer
    assert host.close() == 0
    return np.array(answer["words"][2:], dtype=float).reshape(STEPS, len(OUTPUTS))


@pytest.fixture(scope="module")
def session(fmi3_dirs, c3_host) -> dict:
    """Everything the tests look at, from one FMI 3.0 C host process."""
    host = Host3(c3_host, fmi3_dirs["PipePlug"], _env())
    vr, out = host.vr, {}
    ident = host.running(REFERENCE)
    out["reference"] = host.pulse(ident, OUTPUTS, STEPS)
    # Two instances: a line of each carries its own environment.
    other = host.running()
    out["lines"] = [host("call", i, "doStep", "0.0", "0.0")["log"] for i in (ident, other)]
    out["idents"] = [ident, other]
    # Start and stop times reach the slave.
    late = host.running(REFERENCE, start=0.5, stop=0.502)
    out["late_step"] = host("call", late, "doStep", "0.5", "0.001")
    out["late_time"] = host("call", late, "getFloat64", 1, 1, vr["time"])
    out["past_stop"] = host("call", late, "doStep", "0.501", "0.002")
    # profile_points from C; elastic, the scalars at the sections of the profile.
    elastic = {"tau1": 2e4, "L2": 0.5, "dx": 0.05}
    profiled = host.new()["words"][0]
    host.ok(profiled, "setUInt64", 1, vr["profile_points"], 1, 5)
    host.ok(profiled, "setBoolean", 1, vr["elastic"], 1, 1)
    for name, value in elastic.items():
        host.ok(profiled, "setFloat64", 1, vr[name], 1, repr(value))
    host.ok(profiled, "enterInitializationMode", "0.0", "none")
    host.ok(profiled, "exitInitializationMode")
    out["points"] = host("call", profiled, "getUInt64", 1, 1, vr["profile_points"])
    out["profile"] = host.pulse(profiled, ("v_pipe_profile",), 10, n_values=5)[-1]
    out["at"] = []
    for k in range(5):
        single = host.new()["words"][0]
        host.ok(single, "setBoolean", 1, vr["elastic"], 1, 1)
        for name, value in dict(elastic, x_monitor=k / 4).items():
            host.ok(single, "setFloat64", 1, vr[name], 1, repr(value))
        host.ok(single, "enterInitializationMode", "0.0", "none")
        host.ok(single, "exitInitializationMode")
        out["at"].append(host.pulse(single, ("v_pipe",), 10)[-1, 0])
        host("free", single)
    out["too_many"] = host("call", profiled, "getFloat64", 6, 1, vr["v_pipe_profile"])
    out["after"] = host("call", profiled, "getFloat64", 1, 1, vr["v_pipe"])
    out["guard"] = list(map(int, host("guard")["words"]))
    out["exit"] = host.host.close()
    return out


def test_reference_case_matches_closed_form_and_fmi2_bit_for_bit(session, fmi2_reference):
    values = session["reference"]
    outputs = {n: values[:, k] for k, n in enumerate(OUTPUTS)}
    assert_matches_closed_form(outputs, np.arange(1, STEPS + 1) * 1e-3, REFERENCE, rtol=1e-12)
    assert np.array_equal(values, fmi2_reference)


def test_the_logger_gets_the_instance_environment_of_each_line(session):
    for ident, lines in zip(session["idents"], session["lines"]):
        assert len(lines) == 1, lines
        env, status, message, category = lines[0]
        assert (env, status, category) == (ident, 2, "logStatusDiscard"), lines
        assert " = 0.0 is not allowed; allowed: " in message


def test_start_and_stop_time_reach_the_slave(session):
    step = session["late_step"]
    assert step["status"] == 0 and step["log"] == [], step
    assert step["words"] == ["0", "0", "0", "0.501"]           # flags false, lastSuccessfulTime
    assert session["late_time"]["words"] == ["1", "0.501"]
    past = session["past_stop"]
    assert past["status"] == 3 and len(past["log"]) == 1, past
    assert "<= stopTime = 0.502 s" in past["log"][0][2]


def test_profile_points_set_from_c_and_each_element_the_scalar_at_its_section(session):
    assert session["points"]["words"] == ["1", "5"]
    assert list(session["profile"]) == session["at"]


def test_more_values_than_the_variables_hold_is_an_error_with_one_line(session):
    refused = session["too_many"]
    assert refused["status"] == 3 and len(refused["log"]) == 1, refused
    assert refused["log"][0][3] == "logStatusError"
    assert "nValues = 6 is not allowed in fmi3GetFloat64; allowed: 5" in refused["log"][0][2]
    after = session["after"]
    assert after["status"] == 3 and "is not allowed after an error" in after["log"][0][2]


def test_exit_guard_is_armed_and_the_host_exits_cleanly(session):
    address, *words = session["guard"]
    assert address != 0 and address % 8 == 0
    assert all(w and w % 8 == 0 for w in words), words
    assert session["exit"] == 0
