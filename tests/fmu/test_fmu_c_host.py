"""PipePlug.fmu in a plain C host (``fmi_host.c``): no Python in the process, nothing preloaded,
the FMU's binary opened with dlopen as C importers do.

Checked: the reference case agrees with the closed form; the FMU finds a Python in the
documented order (one in the process, then PIPEPLUG_PYTHON, then python3 on PATH with numpy);
without a usable one fmi2Instantiate returns NULL after one line saying what to set, and the host
lives on; refusals are fmi2Error with a category, later calls are refused until the instance is
reset; every valid spelling of the resource URI works.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmi_c_host import LOG_CATEGORIES, CHost, guid_of, hexed, host_env, resource_uri
from fmu_helpers import Q0, T0, assert_matches_closed_form, run_scenario

REAL_OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction")
REFERENCE = {"tau1": 2e4, "tau2": 1e4}       # model I, domain I of the closed form


@pytest.fixture(scope="module")
def vr(fmu_dir) -> dict:
    from fmpy import read_model_description

    return {v.name: v.valueReference for v in read_model_description(str(fmu_dir)).modelVariables}


@pytest.fixture(scope="module")
def python_without_numpy(tmp_path_factory) -> Path:
    """A virtual environment of the base Python with nothing installed (no numpy)."""
    env_dir = tmp_path_factory.mktemp("no_numpy") / "venv"
    base = getattr(sys, "_base_executable", sys.executable)
    subprocess.run([base, "-m", "venv", "--without-pip", str(env_dir)], check=True)
    python = env_dir / "bin" / "python3"
    probe = subprocess.run([str(python), "-c", "import numpy"], capture_output=True, check=False)
    assert probe.returncode != 0                                    # really without numpy
    return python


def _host(c_host, fmu_dir, env) -> CHost:
    return CHost(c_host, Path(fmu_dir) / "binaries" / "linux64" / "PipePlug.so", env)


def _instantiate(host, fmu_dir, name="c", uri=None) -> dict:
    return host("instantiate", hexed(name), hexed(guid_of(fmu_dir)),
                hexed(uri or resource_uri(fmu_dir)), 1)


def _start(host, ident, vr, params) -> int:
    """setupExperiment, enter, Real ``params``, exit: the status of exitInitializationMode."""
    for command in (("setupExperiment", "none", "0.0", "none"), ("enterInitializationMode",)):
        assert host("call", ident, *command)["status"] == 0
    if params:
        names = list(params)
        answer = host("call", ident, "setReal", len(names), *[vr[n] for n in names],
                      *[repr(float(params[n])) for n in names])
        assert answer["status"] == 0 and answer["log"] == [], answer
    return host("call", ident, "exitInitializationMode")


def _pulse(host, ident, vr, steps, h=1e-3) -> tuple[float, dict]:
    """``steps`` steps of ``h`` under the paper's pulse: us per step, outputs by name."""
    answer = host("pulse", ident, vr["Q"], Q0, T0, h, steps, len(REAL_OUTPUTS),
                  *[vr[n] for n in REAL_OUTPUTS])
    assert answer["status"] == 0 and answer["log"] == [], answer
    values = np.array(answer["words"][2:], dtype=float).reshape(steps, len(REAL_OUTPUTS))
    return float(answer["words"][0]), {n: values[:, k] for k, n in enumerate(REAL_OUTPUTS)}


def _runs_reference(host, fmu_dir, vr, steps=20, **instantiate) -> None:
    """A fresh instance runs the reference case for ``steps`` ms, as the closed form says."""
    made = _instantiate(host, fmu_dir, **instantiate)
    assert made["kind"] == "int" and made["log"] == [], made
    ident = made["words"][0]
    assert _start(host, ident, vr, REFERENCE)["status"] == 0
    _, outputs = _pulse(host, ident, vr, steps)
    assert_matches_closed_form(outputs, np.arange(1, steps + 1) * 1e-3, REFERENCE, rtol=1e-12)
    assert host("free", ident)["status"] == 0


def _only_line(answer: dict) -> list:
    """The one log line of ``answer``, checked to carry a category of LogCategories."""
    assert len(answer["log"]) == 1, answer
    line = answer["log"][0]
    assert line[3] in LOG_CATEGORIES, line
    return line


def test_reference_case_matches_closed_form(fmu_dir, c_host, c_host_env, vr):
    """tau1 = 2e4, tau2 = 1e4, Q = 23 kN for 50 ms, 1 ms steps for 0.3 s, no LD_PRELOAD."""
    assert "LD_PRELOAD" not in c_host_env
    host = _host(c_host, fmu_dir, c_host_env)
    made = _instantiate(host, fmu_dir)
    assert made["kind"] == "int" and made["log"] == [], made
    ident = made["words"][0]
    assert _start(host, ident, vr, REFERENCE) == {"status": 0, "kind": "none", "words": [],
                                                  "log": []}
    us_per_step, outputs = _pulse(host, ident, vr, 300)
    times = np.arange(1, 301) * 1e-3
    assert_matches_closed_form(outputs, times, REFERENCE, rtol=1e-12)
    print(f"C host: {us_per_step:.1f} us per step (setReal, doStep, getReal of 8 outputs)")
    assert host("call", ident, "terminate")["status"] == 0
    assert host("free", ident)["status"] == 0
    assert host.close() == 0


def test_python3_on_path_is_used_without_the_variable(fmu_dir, c_host, vr):
    """No PIPEPLUG_PYTHON: python3 on PATH (this virtual environment's, with numpy)."""
    env = host_env(PATH=str(Path(sys.executable).parent))
    host = _host(c_host, fmu_dir, env)
    _runs_reference(host, fmu_dir, vr)
    assert host.close() == 0


def test_the_python_of_the_process_comes_first(fmu_dir):
    """In a Python host its interpreter is used: PIPEPLUG_PYTHON and PATH are not even looked
    at (both unusable here), and no second libpython is loaded."""
    env = host_env(PIPEPLUG_PYTHON="/nonexistent/python3", PATH="/nonexistent")
    result = run_scenario("process_pythons", fmu_dir, env=env)
    assert result["status"] == 0 and result["log"] == [] and len(result["rows"]) == 2
    assert len(result["libpythons"]) == 1, result["libpythons"]


def _venv_bin() -> str:
    return str(Path(sys.executable).parent)


#: id -> (environment variables given (tmp_path, a python without numpy), texts of the line)
MISSING_PYTHON = {
    "variable names a file that is no program": (
        lambda tmp, _: {"PIPEPLUG_PYTHON": str(tmp / "not_a_python"), "PATH": _venv_bin()},
        ["PIPEPLUG_PYTHON=", "not_a_python: it is not an executable file"]),
    "variable names a program that is no python": (
        lambda tmp, _: {"PIPEPLUG_PYTHON": shutil.which("true"), "PATH": _venv_bin()},
        ["PIPEPLUG_PYTHON=", "did not answer as a Python"]),
    "variable names a python without numpy": (
        lambda tmp, no_numpy: {"PIPEPLUG_PYTHON": str(no_numpy), "PATH": _venv_bin()},
        ["PIPEPLUG_PYTHON=", "has no numpy"]),
    "python3 on PATH without numpy": (
        lambda tmp, no_numpy: {"PATH": str(no_numpy.parent)},
        ["PIPEPLUG_PYTHON is not set", "python3 on PATH", "has no numpy",
         "Set PIPEPLUG_PYTHON"]),
    "no python3 on PATH": (
        lambda tmp, _: {"PATH": str(tmp)},
        ["PIPEPLUG_PYTHON is not set", "no python3 on PATH", "Set PIPEPLUG_PYTHON"]),
}


@pytest.mark.parametrize("case", list(MISSING_PYTHON))
def test_without_a_usable_python_instantiate_fails_and_the_host_lives_on(
        fmu_dir, c_host, vr, python_without_numpy, tmp_path, case):
    variables, texts = MISSING_PYTHON[case]
    (tmp_path / "not_a_python").write_text("not a program\n")
    host = _host(c_host, fmu_dir, host_env(**variables(tmp_path, python_without_numpy)))
    refused = _instantiate(host, fmu_dir)
    assert refused["kind"] == "null", refused
    instance, status, message, category = _only_line(refused)
    assert (instance, status, category) == ("c", 3, "logStatusError")
    for text in texts:
        assert text in message, (text, message)
    # The host lives on: told where a Python is, the next instantiation works.
    assert host("setenv", hexed("PIPEPLUG_PYTHON"), hexed(sys.executable))["status"] == 0
    _runs_reference(host, fmu_dir, vr)
    assert host.close() == 0


def test_refusals_are_errors_with_a_category_and_reset_recovers(fmu_dir, c_host, c_host_env,
                                                                 vr):
    host = _host(c_host, fmu_dir, c_host_env)
    ident = _instantiate(host, fmu_dir)["words"][0]
    refused = _start(host, ident, vr, {"tau1": -1.0})
    assert refused["status"] == 3
    assert _only_line(refused) == ["c", 3, "tau1 = -1.0 is not allowed; allowed: finite, >= 0",
                                   "logStatusError"]
    after = host("call", ident, "doStep", "0.0", "0.001")          # refused until reset
    assert after["status"] == 3 and _only_line(after) == [
        "c", 3, "fmi2DoStep is not allowed after an error; allowed: fmi2SetFMUstate, "
        "fmi2Reset, fmi2Terminate, fmi2FreeInstance", "logStatusError"]
    assert host("call", ident, "reset")["status"] == 0
    assert _start(host, ident, vr, REFERENCE)["status"] == 0
    _pulse(host, ident, vr, 5)
    after = host("call", ident, "setReal", 1, vr["tau2"], "2.0")   # fixed, after initialization
    assert after["status"] == 3 and "tau2 = 2.0 is not allowed" in _only_line(after)[2]
    assert host("call", ident, "reset")["status"] == 0
    assert _start(host, ident, vr, {})["status"] == 0
    unknown = host("call", ident, "getInteger", 1, 777)
    assert unknown["status"] == 3 and "valueReference = 777" in _only_line(unknown)[2]
    percent = host("call", ident, "reset"), host("call", ident, "enterInitializationMode"), \
        host("call", ident, "setString", 1, vr["solver"], hexed("%s%n%d")), \
        host("call", ident, "exitInitializationMode")
    assert [a["status"] for a in percent] == [0, 0, 0, 3]          # printf in C: no crash
    assert "solver = '%s%n%d' is not allowed" in _only_line(percent[-1])[2]
    assert host("free", ident)["status"] == 0
    assert host.close() == 0


@pytest.fixture(scope="module")
def odd_fmu_dir(fmu_dir, tmp_path_factory) -> Path:
    """The extracted FMU under a path with a space, a literal "%20", "%" and a non-ASCII
    letter."""
    target = tmp_path_factory.mktemp("uri") / "odd dir%20 100% é"
    shutil.copytree(fmu_dir, target)
    return target


def _spellings(folder: Path) -> dict:
    encoded = (folder / "resources").as_uri()[len("file://"):]          # /tmp/.../odd%20dir...
    return {"file:///p": "file://" + encoded, "file:/p": "file:" + encoded,
            "file://localhost/p": "file://localhost" + encoded,
            "FILE://LOCALHOST/p/": "FILE://LOCALHOST" + encoded + "/"}


@pytest.mark.parametrize("spelling", ["file:///p", "file:/p", "file://localhost/p",
                                      "FILE://LOCALHOST/p/"])
def test_every_file_uri_spelling_works(odd_fmu_dir, fmu_dir, c_host, c_host_env, vr, spelling):
    """Each spelling in a host of its own (pythonfmu imports the slave once per process), on a
    folder whose name needs percent-encoding, and on the plain folder."""
    for folder in (odd_fmu_dir, fmu_dir):
        host = _host(c_host, folder, c_host_env)
        _runs_reference(host, folder, vr, steps=5, uri=_spellings(Path(folder))[spelling])
        assert host.close() == 0


def test_exit_guard_is_armed_in_a_c_host(fmu_dir, c_host, c_host_env, vr):
    """The loader empties pythonfmu's interpreter pointer at exit: it has found it (a live
    shared_ptr: two non-null, aligned heap addresses), and the host exits cleanly."""
    host = _host(c_host, fmu_dir, c_host_env)
    _runs_reference(host, fmu_dir, vr, steps=2)
    address, *words = map(int, host("guard")["words"])
    assert address != 0 and address % 8 == 0
    assert all(w and w % 8 == 0 for w in words), words
    assert host.close() == 0
