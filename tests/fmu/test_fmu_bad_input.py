"""Bad input per the contract's "Bad input" and "Stepping" sections: one log line naming the
variable, its value and the allowed range, with the category of its status; fmi2Error at
initialization, on a fixed parameter set after it, on an unknown value reference or for a step
past the stopTime, discard for a step that cannot be taken; after fmi2Error every other call is
refused with one short line until fmi2Reset (fmi2Terminate accepted); the host process survives
and another instance in it keeps working. (``test_fmu_probes.py`` drives many more such calls,
logging off too, in a C host as well.)"""
from __future__ import annotations

import subprocess
import sys

import pytest
from fmu_helpers import Q0, assert_matches_closed_form, closed_form, columns, run_scenario

ERROR, DISCARD = 3, 2
CATEGORY = {ERROR: "logStatusError", DISCARD: "logStatusDiscard"}

#: id -> (kind, value, call refused, status, texts the log line must contain)
CASES = {
    "NaN parameter": ("parameters", {"tau2": float("nan")}, "exit_init", ERROR,
                      ["tau2 = nan", "allowed", ">= 0"]),
    "L2 > L1": ("parameters", {"L2": 2.0}, "exit_init", ERROR, ["L2 = 2.0", "allowed", "L1"]),
    "negative dt with fd": ("parameters", {"solver": "fd", "dt": -1e-4}, "exit_init", ERROR,
                            ["dt = -0.0001", "allowed", "> 0"]),
    "unknown solver": ("parameters", {"solver": "rk4"}, "exit_init", ERROR,
                       ["solver = 'rk4'", "'exact'", "'fd'"]),
    "percent in a string": ("parameters", {"solver": "%s%s%n%d"}, "exit_init", ERROR,
                            ["solver = '%s%s%n%d' is not allowed", "'exact'"]),
    "fixed parameter after init": ("fixed_after_init", ["tau2", 2e4], "refused", ERROR,
                                   ["tau2 = 20000.0", "allowed", "after initialization"]),
    "fixed option after init": ("fixed_after_init", ["solver", "fd"], "refused", ERROR,
                                ["solver = 'fd'", "after initialization"]),
    "unknown value reference (get)": ("unknown_get", 123456, "refused", ERROR,
                                      ["valueReference = 123456", "allowed"]),
    "unknown value reference (set)": ("unknown_set", 2 ** 32 - 1, "refused", ERROR,
                                      ["valueReference = 4294967295", "allowed"]),
    "damaged FMU state": ("bad_state", None, "refused", ERROR, ["serializedState", "allowed",
                                                                "PipePlug"]),
    "NaN Q": ("nan_q", None, "refused", DISCARD, ["Q = nan", "allowed", "finite"]),
    "wrong communication point": ("wrong_time", None, "refused", DISCARD,
                                  ["currentCommunicationPoint = 0.5", "allowed", "0.005"]),
    "past stopTime": ("past_stop", None, "refused", ERROR, ["0.015", "allowed", "stopTime"]),
}


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_refusal_per_contract(fmu_dir, case):
    kind, value, call, status, texts = CASES[case]
    result = run_scenario("bad_input", fmu_dir, kind=kind, value=value)
    statuses = result["statuses"]
    assert statuses[call] == status, statuses
    refusal, later_lines = (result["log"][:result["lines_at_refusal"]],
                            result["log"][result["lines_at_refusal"]:])
    assert len(refusal) == 1, refusal                            # exactly one line, from "bad"
    line = refusal[0]
    assert (line["instance"], line["status"], line["category"]) == ("bad", status,
                                                                    CATEGORY[status])
    for text in texts:
        assert text in line["message"], (text, line["message"])
    later = {k: v for k, v in statuses.items() if k.startswith("later")}
    if status == ERROR:                  # every call refused with a short line; terminate is not
        assert later == {k: 0 if k == "later_terminate" else ERROR for k in later}, later
        calls = {"later_step": 2, "later_terminate": 0}      # a step: setReal Q, doStep
        assert len(later_lines) == sum(calls.get(k, 1) for k in later), later_lines
        for entry in later_lines:
            assert (entry["instance"], entry["status"], entry["category"]) == (
                "bad", ERROR, "logStatusError") and "not allowed after an error" in entry[
                "message"], entry
    else:                                                        # still usable
        assert set(later.values()) == {0} and later_lines == [], (later, later_lines)
    assert (statuses["reset"], statuses["after_reset"]) == (0, 0)   # reset: usable again
    assert_matches_closed_form(columns(result["after_reset_rows"]), [0.01, 0.02], {})
    assert_matches_closed_form(columns(result["good_rows"]), [0.01, 0.02], {})


def test_percent_through_fmpy_default_logger(fmu_dir):
    """FMPy's default logger printf-formats the message in C: '%s' must arrive escaped."""
    result = run_scenario("default_logger", fmu_dir, script="fmu_default_logger.py",
                          params={"solver": "%s%s%s%n"})
    assert result["status"] == ERROR
    assert "[ERROR]" in result["stdout"]
    assert "solver = '%s%s%s%n' is not allowed" in result["stdout"]


def test_refused_step_under_libcosim(fmu_file):
    """A NaN Q under libcosim: the step is discarded, libcosim stops the run, the process and
    the FMU's last values survive. (A refusal at exitInitializationMode cannot be shown under
    libcosim: its fixed-step algorithm does not catch a failing fmi2ExitInitializationMode of
    any FMU and aborts the process.)"""
    result = run_scenario("cosim_refused_step", fmu_file, params={"tau2": 1e4}, q0=Q0,
                          step=1e-4, t_nan=0.01)
    assert result["ok_before"] is True and result["ok_after"] is False
    want = closed_form({}, [0.01])["v_pipe"][0]
    assert abs(result["v_pipe"] - want) <= 1e-9 * want


@pytest.mark.parametrize("attempt", range(3))
def test_elastic_is_built_or_refused_cleanly(fmu_dir, attempt):
    """elastic=true goes through the same model factory: it runs, or it is one clean refusal;
    either way the host process ends normally (repeated: a crash at exit may be intermittent)."""
    result = run_scenario("initialize_only", fmu_dir, params={"elastic": True})
    if result["status"] == 0:
        assert result["log"] == [] and len(result["rows"]) == 2
        assert 0.0 < result["rows"][-1]["W_input"]
    else:
        assert result["status"] == ERROR and len(result["log"]) == 1
        assert "elastic = True is not allowed" in result["log"][0]["message"]


def test_refused_parameters_never_reach_libcosim(fmu_file):
    """libcosim terminates the process on a failed exitInitializationMode: the harness's check
    refuses the execution first, with the FMU's wording, and the process goes on."""
    result = run_scenario("cosim_refused_parameters", fmu_file, params={"tau1": -1.0})
    assert result["refused"] == "tau1 = -1.0 is not allowed; allowed: finite, >= 0"


OVERFLOW = """
import sys
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi1 import FMICallException
md = read_model_description(sys.argv[1])
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(sys.argv[1]), modelIdentifier="PipePlug")
fmu.instantiate(loggingOn=False)
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.setBoolean([vr["elastic"]], [True])
fmu.exitInitializationMode()
fmu.setReal([vr["Q"]], [1e300])
try:
    fmu.doStep(0.0, 1e-3)
except FMICallException as exc:
    print("STATUS", int(exc.status), flush=True)
"""


def test_an_overflow_inside_a_step_is_refused_by_its_line_alone(fmu_file):
    """The elastic model under Q = 1e300: fmi2Error with the line naming the output that is not
    finite, and nothing of numpy's on the host's stderr (its overflow warnings are the FMU's
    business, said by that line)."""
    proc = subprocess.run([sys.executable, "-c", OVERFLOW, str(fmu_file)], capture_output=True,
                          text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "STATUS 3" in proc.stdout, proc.stdout
    assert "is not allowed" in proc.stdout + proc.stderr        # fmpy prints the error line
    assert "Warning" not in proc.stderr, proc.stderr
