"""pythonfmu 0.7's behaviours that ``pipeplug_fmu/pythonfmu07.py`` works around (P1-P12), shown
on pythonfmu's own binary, without the loader (``pythonfmu07_scenarios.py``, a process each).

Each test fails when a pythonfmu upgrade changes the behaviour, so that its workaround is
reviewed (and removed when no longer needed). Some behaviours end the process: that is what
they show.
"""
from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="module")
def raw_dir(fmu_dir, tmp_path_factory) -> Path:
    """The extracted FMU with pythonfmu's linux64 binary in the loader's place."""
    target = tmp_path_factory.mktemp("raw") / "fmu"
    shutil.copytree(fmu_dir, target)
    binaries = target / "binaries" / "linux64"
    shutil.copy(binaries / "PipePlug_pythonfmu.so", binaries / "PipePlug.so")
    return target


def _run(name: str, folder: Path) -> tuple[int, dict | None, str]:
    """Exit code, result (None if the process ended without one) and output of a scenario."""
    proc = subprocess.run([sys.executable, str(HERE / "pythonfmu07_scenarios.py"), name,
                           str(folder)], capture_output=True, text=True, timeout=300,
                          check=False, cwd=str(HERE))
    lines = [x for x in proc.stdout.splitlines() if x.startswith("RESULT ")]
    result = json.loads(lines[-1][len("RESULT "):]) if lines else None
    return proc.returncode, result, proc.stdout + proc.stderr


def _result(name, folder) -> dict:
    code, result, out = _run(name, folder)
    assert code == 0 and result is not None, out[-3000:]
    return result


def test_p1_an_exception_is_fatal_with_a_null_category(raw_dir):
    result = _result("exception_is_fatal", raw_dir)
    assert result["status"] == 4
    line, = result["log"]
    assert (line["status"], line["category"]) == (4, None)
    assert "PipePlugRefusal: tau1 = -1.0 is not allowed" in line["message"]


def test_p2_references_are_released_once_per_exception(raw_dir):
    """The slave adds one reference each before it raises: no net change means pythonfmu
    released one each."""
    result = _result("references_released", raw_dir)
    assert result == {"status": 4, "change": [0, 0, 0]}


def test_p2_p10_an_exception_of_the_class_releases_the_instance(raw_dir):
    result = _result("class_method_raising", raw_dir)
    assert (result["status"], result["change"]) == (4, -1)


def test_p3_logging_off_or_other_categories_drop_every_line(raw_dir):
    result = _result("logging_off", raw_dir)
    assert result == {"off": {"status": 4, "log": []}, "categories": {"status": 4, "log": []}}


def test_p4_a_message_is_the_hosts_printf_format(raw_dir):
    """The slave wrote "100%%"; the host's printf made it "100%"."""
    message = _result("message_is_a_format", raw_dir)["log"][0]["message"]
    assert "solver = '100%'" in message and "100%%" not in message, message


def test_p5_a_line_queued_in_a_raising_call_is_given_while_the_exception_is_pending(raw_dir):
    """The queued line reaches the host's (Python) logger first, and the exception is lost
    on the way: pythonfmu reports "unknown error" instead of the refusal."""
    result = _result("queued_while_raising", raw_dir)
    assert result["status"] == 4
    assert [line["message"] for line in result["log"]][0] == "queued line"
    assert "unknown error" in result["log"][1]["message"], result["log"]


def test_p6_value_references_arrive_as_c_ints(raw_dir):
    assert _result("value_references_as_int", raw_dir) == {"seen": [-1, -2 ** 31]}


def test_p7_null_strings_arrive_as_none_and_bytes_not_utf8_crash(raw_dir):
    code, result, out = _run("strings", raw_dir)
    assert "NULL [null]" in out, out
    assert result is None and code == -signal.SIGSEGV, (code, out[-3000:])


def test_p8_a_folder_without_the_slave_crashes_instantiation(raw_dir):
    code, result, out = _run("resources_elsewhere", raw_dir)
    assert "INSTANTIATING" in out and result is None and code == -signal.SIGSEGV, (code, out)


def test_p8_a_null_instance_name_aborts_the_host(raw_dir):
    code, result, out = _run("null_name", raw_dir)
    assert result is None and code == -signal.SIGABRT and "std::logic_error" in out, (code, out)


def test_p9_states_are_the_slaves_objects_and_serialization_copies_the_given_size(raw_dir):
    result = _result("states", raw_dir)
    assert result["same_object"] is True                   # handed back as is: copy on set
    assert result["small_status"] == 0                     # 10 bytes of a longer state: "OK"
    assert result["small"] == result["full_start"]
    assert result["null_status"] == 4                      # a NULL state is used as one


def test_p11_instantiation_releases_the_scripts_namespace_once(raw_dir):
    """The script takes the reference back: the count stays put over instantiations."""
    counts = _result("script_namespace", raw_dir)["counts"]
    assert len(set(counts)) == 1, counts


def test_p12_no_call_order_is_enforced(raw_dir):
    result = _result("no_call_order", raw_dir)
    assert result == {"status": 0, "seen": [[5.0, None, None]]}
