"""PipePlug.fmu under the calls hosts really make (``probes.py``), in the plain C host
(``fmi_host.c``, no Python until the FMU brings one) and through FMPy's low-level API
(``fmpy_host.py``), with debug logging on and off.

The probes of one host and logging share a host process (:class:`~probes.Hosts`: starting a
host and the FMU's Python costs more than a probe). A crash is a failure all the same: the
probe running fails, and the next one gets a fresh process, as does the next probe after any
failure. Each shared process must exit cleanly at the end of the module. A probe of
fmi2Instantiate (the first instantiation of a process is where the C host's FMU finds its
Python) and a probe with an environment of its own run in a process of their own, which must
exit cleanly after it.

Checked for every probe: the refused call's status (fmi2Error, fmi2Discard, or NULL from
fmi2Instantiate); exactly one log line, with the category of its status, naming the variable
(or call), its value and what is allowed; then what the contract says follows: after fmi2Error
every other call is refused with one short line until fmi2Reset, which makes the instance
usable again; after fmi2Discard the instance steps on; after NULL the next fmi2Instantiate
works. Another instance in the same process runs the reference case, and the host exits
cleanly.
"""
from __future__ import annotations

import stat
import subprocess
import sys
from pathlib import Path

import pytest
from fmi_c_host import hexed
from probes import DISCARD, ERROR, PROBES, Hosts, Session

HERE = Path(__file__).resolve().parent
CATEGORY = {ERROR: "logStatusError", DISCARD: "logStatusDiscard"}
CASES = [(name, host, logging) for name, (_, expected) in PROBES.items()
         for host in expected.hosts for logging in (True, False)]


def _environment(variables: dict, folder) -> dict:
    """The probe's environment: a value starting with "#!" becomes an executable script."""
    env = {}
    for name, value in variables.items():
        if value.startswith("#!"):
            script = folder / f"{name.lower()}.sh"
            script.write_text(value)
            script.chmod(script.stat().st_mode | stat.S_IEXEC)
            value = str(script)
        env[name] = value
    return env


@pytest.fixture(scope="module")
def hosts(fmu_dir, hammer_dir, c_host):
    """The shared host processes of this module; each must exit cleanly at its end."""
    shared = Hosts(fmu_dir, hammer_dir, c_host)
    yield shared
    for (host, logging), (code, stderr) in shared.close().items():
        assert code == 0, f"the shared {host} host (logging {logging}) exited {code}\n{stderr}"


@pytest.mark.parametrize("name, host, logging", CASES,
                         ids=[f"{n}/{h}/logging-{'on' if g else 'off'}" for n, h, g in CASES])
def test_probe_is_refused_with_one_line_and_the_host_goes_on(name, host, logging, fmu_dir,
                                                            hammer_dir, c_host, hosts, tmp_path):
    probe, expected = PROBES[name]
    if not expected.enabled:
        pytest.skip("runs once the core refuses a step of too many internal steps "
                    "(max_internal_steps)")
    if expected.env or expected.status == "null":          # a process of its own
        session = Session(host, logging, fmu_dir, hammer_dir, c_host,
                          _environment(expected.env, tmp_path))
        _check(session, probe, expected)
        assert session.close() == 0
        return
    try:
        _check(hosts.session(host, logging), probe, expected)
    except BaseException:
        hosts.drop(host, logging)                           # the next probe gets a fresh one
        raise


def _check(session: Session, probe, expected) -> None:
    """Run the probe in ``session``; check its answer, what follows, another instance."""
    _refused_then(session, probe, expected)
    _another_instance_runs(session)


def _refused_then(session: Session, probe, expected) -> None:
    """Run the probe in ``session`` (of either FMI version); check its answer and what the
    contract says follows it."""
    answer, ident = probe(session)
    refused_with = ERROR if expected.status == "null" else expected.status
    if expected.status == "null":
        assert answer["kind"] == "null", answer
    else:
        assert answer["status"] == expected.status, answer
    assert len(answer["log"]) == 1, answer
    _, status, message, category = answer["log"][0]
    assert (status, category) == (refused_with, CATEGORY[refused_with]), answer
    for text in expected.texts:
        assert text in message, (text, message)
    if expected.status == ERROR:
        _refuses_until_reset(session, ident)
    elif expected.status == DISCARD:
        _steps_on(session, ident, expected.then_q, expected.then_set)
    else:
        _instantiates_again(session)


def _refuses_until_reset(s: Session, ident) -> None:
    """After fmi2Error: one short line per refused call; fmi2Terminate and fmi2Reset accepted;
    after the reset the instance runs."""
    for words in (("call", ident, "getReal", 1, s.vr("v_pipe")),
                  ("call", ident, "doStep", "0.0", "0.001"),
                  ("call", ident, "setReal", 1, s.vr("Q"), "1.0"),
                  ("call", ident, "exitInitializationMode"), ("get_state", ident)):
        answer = s(*words)
        assert answer["status"] == ERROR and len(answer["log"]) == 1, (words, answer)
        assert "is not allowed after an error" in answer["log"][0][2], answer
    s.ok(ident, "terminate")
    s.ok(ident, "reset")
    assert s.start(ident)["status"] == 0
    assert s.step(ident, 0.0, 0.001) == {"status": 0, "kind": "none", "words": [], "log": []}


def _steps_on(s: Session, ident, q: float, settings=()) -> None:
    """After fmi2Discard: nothing changed, the next step from the FMU's time is taken (once the
    host has set ``settings``, (name, value) pairs)."""
    for name, value in settings:
        answer = s.set(ident, name, value)
        assert answer["status"] == 0 and answer["log"] == [], answer
    assert s.step(ident, 0.005, 0.005, q) == {"status": 0, "kind": "none", "words": [],
                                               "log": []}


def _instantiates_again(s: Session) -> None:
    """After NULL from fmi2Instantiate: with the usual arguments (and a Python) it works."""
    if s.kind == "c":
        s("setenv", hexed("PIPEPLUG_PYTHON"), hexed(sys.executable))
        # the usual time allowed too: a probe's 2 s is too short for a loaded machine
        s("setenv", hexed("PIPEPLUG_PYTHON_TIMEOUT"), hexed("60"))
    s.running()


def freed_instance_refuses(s) -> None:
    """A host that frees an instance twice, or calls it in its clean-up after freeing it: the
    second free does nothing, a call is refused with the error status and no line (the logger
    belonged to the freed instance); the process goes on (FMI leaves such calls undefined)."""
    ident = s.running()
    assert s("free", ident, "keep") == {"status": 0, "kind": "none", "words": [], "log": []}
    assert s("free", ident, "keep") == {"status": 0, "kind": "none", "words": [], "log": []}
    for words in (("call", ident, "getReal", 1, s.vr("v_pipe")),
                  ("call", ident, "doStep", "0.0", "0.001"), ("get_state", ident),
                  ("call", ident, "reset"), ("call", ident, "terminate")):
        answer = s(*words)
        assert answer["status"] == ERROR and answer["log"] == [], (words, answer)
    _another_instance_runs(s)


@pytest.mark.parametrize("host", ["c", "fmpy"])
def test_a_freed_instance_is_refused_not_a_crash(host, hosts):
    try:
        freed_instance_refuses(hosts.session(host, True))
    except BaseException:
        hosts.drop(host, True)
        raise


def _another_instance_runs(s: Session) -> None:
    ident = s.running({"tau1": 2e4})
    for k in range(3):
        assert s.step(ident, k * 1e-3, 1e-3)["status"] == 0
    values = s.call(ident, "getReal", 1, s.vr("v_pipe"))
    assert values["status"] == 0 and float(values["words"][1]) > 0.0, values


SIMULATE = """
import sys
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
try:
    simulate_fmu(sys.argv[1], start_values={"L2": 3.0})      # FMPy's defaults: logging off
except FMICallException as exc:
    print("STATUS", int(exc.status), flush=True)
"""


def test_simulate_fmu_with_fmpys_defaults_prints_the_line_and_fails_with_error(fmu_file):
    proc = subprocess.run([sys.executable, "-c", SIMULATE, str(fmu_file)], capture_output=True,
                          text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = proc.stdout + proc.stderr
    assert ("L2 = 3.0 is not allowed; allowed: finite, >= 0 and <= L1 (L1 = 1.0)" in out), out
    assert "STATUS 3" in proc.stdout, out


LIBCOSIM = """
import shutil, sys, tempfile
from pathlib import Path
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
sys.path.insert(0, sys.argv[2])
from fmu_cosim import _OSP, _initial_value
log_output_level(CosimLogLevel.WARNING)
folder = Path(tempfile.mkdtemp())
shutil.copy(sys.argv[1], folder / "PipePlug.fmu")
osp = folder / "OspSystemStructure.xml"
osp.write_text(_OSP.format(step="0.001", initial=_initial_value("L2", 3.0)))
execution = CosimExecution.from_osp_config_file(str(osp))    # values not checked first
print("BUILT", flush=True)
execution.simulate_until(10 ** 7)
print("NOT ENDED", flush=True)
"""


def test_libcosim_gets_the_line_before_it_ends_its_process(fmu_file):
    """libcosim ends its own process when exitInitializationMode fails (``pipeplug system``
    checks the values first, ``test_fmu_bad_input.py``); the line is logged before."""
    proc = subprocess.run([sys.executable, "-c", LIBCOSIM, str(fmu_file), str(HERE)],
                          capture_output=True, text=True, timeout=300, check=False)
    out = proc.stdout + proc.stderr
    assert "BUILT" in proc.stdout and "NOT ENDED" not in proc.stdout, out
    assert proc.returncode != 0, out                   # libcosim's std::terminate
    logged = out.index("category=logStatusError] L2 = 3.0 is not allowed")
    assert logged < out.index("terminate called"), out
