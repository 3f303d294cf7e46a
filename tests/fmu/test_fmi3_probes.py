"""The FMI 3.0 PipePlug.fmu under the calls hosts really make (``probes3.py``: the FMI 2.0
probes where they map, and FMI 3.0's own), in the plain C host (``fmi3_host.c``: no Python until
the FMU brings one) and inside a Python process (``python_host3.py``), with debug logging on and
off (the C host with logging off, the Python one with logging on: each session costs seconds,
and together they cover both hosts and both ways of logging; any of the four runs as they do).

What ``test_fmu_probes.py`` checks for each FMI 2.0 probe is checked for each of these: the
refused call's status (fmi3Error, fmi3Discard, or NULL from fmi3InstantiateCoSimulation); exactly
one log line, with the category of its status, naming the variable (or call), its value and
what is allowed; after fmi3Error every other call refused with one short line until fmi3Reset,
which makes the instance usable again; after fmi3Discard the instance steps on; after NULL the
next instantiation works; another instance in the same process runs, and the host exits
cleanly. To stay cheap, the probes of one host and logging share one host process (each on
instances of its own); the probes that need a process without Python get one each.
"""
from __future__ import annotations

import pytest
from probes3 import PROBES3, Session3
from test_fmu_probes import (
    _another_instance_runs,
    _environment,
    _refused_then,
    freed_instance_refuses,
)

SHARED = [name for name, (_, expected) in PROBES3.items() if not expected.env]
OWN_PROCESS = [name for name, (_, expected) in PROBES3.items() if expected.env]


@pytest.fixture(scope="module")
def c3_library(tmp_path_factory):
    from fmi_c_host import compile_host

    return compile_host(tmp_path_factory.mktemp("c3_library") / "fmi3_host.so", "fmi3_host.c",
                        library=True)


def _probe(session: Session3, name: str) -> None:
    """Run probe ``name`` in ``session`` and what follows it (see the module docstring)."""
    probe, expected = PROBES3[name]
    if expected.enabled:
        _refused_then(session, probe, expected)


@pytest.mark.parametrize("host, logging", [("c", False), ("python", True)],
                         ids=["c/logging-off", "python/logging-on"])
def test_every_probe_is_refused_with_one_line_and_the_host_goes_on(host, logging, fmi3_dirs,
                                                                   c3_host, c3_library):
    session = Session3(host, logging, fmi3_dirs["PipePlug"], fmi3_dirs["Hammer"], c3_host,
                       c3_library)
    failed, ran = {}, 0
    for name in SHARED:
        if host not in PROBES3[name][1].hosts:
            continue
        try:
            _probe(session, name)
            ran += 1
        except AssertionError as exc:
            failed[name] = str(exc)[:400]
            if not session.host.alive():
                break
    assert failed == {}
    _another_instance_runs(session)
    assert session.close() == 0
    print(f"{ran} probes in one {host} host process")


@pytest.mark.parametrize("name", OWN_PROCESS)
def test_a_python_that_does_not_answer_is_refused_in_a_c_host(name, fmi3_dirs, c3_host,
                                                              c3_library, tmp_path):
    session = Session3("c", False, fmi3_dirs["PipePlug"], fmi3_dirs["Hammer"], c3_host,
                       c3_library, _environment(PROBES3[name][1].env, tmp_path))
    _probe(session, name)
    _another_instance_runs(session)
    assert session.close() == 0


def test_a_freed_instance_is_refused_not_a_crash(fmi3_dirs, c3_host, c3_library):
    session = Session3("c", True, fmi3_dirs["PipePlug"], fmi3_dirs["Hammer"], c3_host,
                       c3_library)
    freed_instance_refuses(session)
    assert session.close() == 0
