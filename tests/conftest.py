"""Fixtures shared by the whole suite: the FMUs and system files, built once per test process by
the project's own build command (``build_fmu.py``, in a subprocess, as a user runs it)."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: the build made once for a run on several workers (:func:`pytest_sessionstart`)
SHARED_BUILD = "PIPEPLUG_TESTS_BUILD"


def _build(dest: Path) -> Path:
    subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--dest", str(dest)],
                   check=True, capture_output=True, cwd=str(dest.parent))
    return dest


@pytest.fixture(scope="session")
def fmu_file(tmp_path_factory) -> Path:
    """PipePlug.fmu of ``build_fmu.py`` run once, into a temporary directory (the build's other
    files beside it): the run's shared build when there is one, else this process's own."""
    shared = os.environ.get(SHARED_BUILD)
    if shared:
        return Path(shared)
    return _build(tmp_path_factory.mktemp("fmu") / "PipePlug.fmu")


@pytest.fixture(scope="session")
def fmu_dir(fmu_file, tmp_path_factory) -> Path:
    """The FMU extracted once (FMPy accepts the directory)."""
    target = tmp_path_factory.mktemp("fmu_extracted")
    with zipfile.ZipFile(fmu_file) as zf:
        zf.extractall(target)
    return target


@pytest.fixture(scope="session")
def hammer_file(fmu_file) -> Path:
    """Hammer.fmu of the same build."""
    return fmu_file.with_name("Hammer.fmu")


@pytest.fixture(scope="session")
def hammer_dir(hammer_file, tmp_path_factory) -> Path:
    """Hammer.fmu extracted once."""
    target = tmp_path_factory.mktemp("hammer_extracted")
    with zipfile.ZipFile(hammer_file) as zf:
        zf.extractall(target)
    return target


@pytest.fixture(scope="session")
def fmi3_files(fmu_file) -> dict:
    """The FMI 3.0 PipePlug.fmu and Hammer.fmu of the same build (``fmi3/`` beside it)."""
    return {name: fmu_file.parent / "fmi3" / f"{name}.fmu" for name in ("PipePlug", "Hammer")}


@pytest.fixture(scope="session")
def fmi3_dirs(fmi3_files, tmp_path_factory) -> dict:
    """The FMI 3.0 FMUs extracted once."""
    dirs = {}
    for name, path in fmi3_files.items():
        dirs[name] = tmp_path_factory.mktemp(f"fmi3_{name}")
        with zipfile.ZipFile(path) as zf:
            zf.extractall(dirs[name])
    return dirs


# The order of the suite --------------------------------------------------------------------------
#: Tests that take long, by node id or its start (a test function: each of its cases): CPU seconds
#: per test (the test process and its children), measured on a 2-core machine. Only the order
#: matters; refresh when tests are added or become slower (``python dev.py test --durations=60``
#: shows the longest).
EXPENSIVE = {
    "tests/harness/fuzz/test_fuzz_runs.py::test_fuzz_finds_no_failure": 50,
    "tests/harness/fuzz/test_fuzz_elastic.py::test_fuzz_finds_no_failure": 40,
    "tests/fmu/test_wheel.py": 38,
    "tests/fmu/test_fmi_sequences.py::test_random_fmi_call_sequences": 29,
    "tests/fmu/test_fmi_sequences.py::test_random_fmi_call_sequences_in_a_c_host": 8,
    "tests/harness/fuzz/test_fuzz_elastic.py::test_the_fuzz_finds": 11,
    "tests/harness/fuzz/test_fuzz_ram.py::test_fuzz_finds_no_failure": 12,
    "tests/fmu/test_fmu_exit_guard.py": 12,
    "tests/core/hardcases/test_properties.py::test_outputs_stay_finite": 10,
    "tests/harness/stability/test_stability_cmd.py": 10,
    "tests/fmu/test_fmu_ram.py::test_a_direct_strike_on_a_long_elastic_rod": 9,
    "tests/harness/validate/test_validate_and_figures.py::test_figures_draws_pngs": 8,
    "tests/core/elastic/test_jit_cache.py": 7,
    "tests/harness/sweep/test_sweep_dask.py": 4,
    "tests/fmu/test_one_process.py": 4,
    "tests/fmu/test_fmi3.py": 5,
    "tests/harness/system/test_system.py": 1,
    "tests/fmu/test_fmu_probes.py": 0.15,
}


def _cost(item) -> float:
    """The seconds :data:`EXPENSIVE` gives ``item`` (the longest matching start), else 0."""
    starts = [start for start in EXPENSIVE if item.nodeid.startswith(start)]
    return EXPENSIVE[max(starts, key=len)] if starts else 0.0


def _shares_module_fixtures(item) -> bool:
    """Whether ``item`` uses a fixture set up once per module (or class)."""
    info = getattr(item, "_fixtureinfo", None)
    return info is not None and any(
        defs and defs[-1].scope in ("module", "class")
        for defs in info.name2fixturedefs.values())


@pytest.hookimpl(tryfirst=True)      # before pytest-xdist reads the xdist_group marks
def pytest_collection_modifyitems(config, items):
    """The longest work first, so that with ``--dist loadgroup`` (pyproject.toml) no long test
    starts late on one worker while the other one is idle.

    A module whose tests share a module-scoped fixture is one unit of work (an ``xdist_group``:
    one worker sets the fixture up once); any other test is a unit of its own. Units run in
    decreasing order of their :data:`EXPENSIVE` seconds; units of equal cost (all the cheap ones)
    keep their order, and so do the tests within a unit.
    """
    units: dict[str, list] = {}
    for item in items:
        module = item.nodeid.split("::")[0]
        if _shares_module_fixtures(item):
            item.add_marker(pytest.mark.xdist_group(module))
            units.setdefault(module, []).append(item)
        else:
            units.setdefault(item.nodeid, []).append(item)
    ordered = sorted(units.values(), key=lambda unit: -sum(map(_cost, unit)))
    items[:] = [item for unit in ordered for item in unit]


# One build and compiled kernels for all workers -------------------------------------------------
def pytest_sessionstart(session):
    """On several workers (``-n``): build the FMUs once for all of them, and compile the kernels
    of the core (from the start, while the FMUs build) and of the FMU's copy of it into the
    on-disk cache (``warm_kernels.py``, one process each) before the workers start, so that no
    two processes compile the same kernel. Only
    a speed-up: if it fails, each worker builds and compiles as it would alone."""
    config = session.config
    if (hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None)
            or config.option.collectonly):
        return
    script = str(Path(__file__).with_name("warm_kernels.py"))

    def warm(*copy):
        return subprocess.Popen([sys.executable, script, *copy], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)

    warming = [warm("pipeplug")]          # the core's kernels compile while the FMUs build
    try:
        folder = Path(tempfile.mkdtemp(prefix="pipeplug-tests-"))
        config.add_cleanup(lambda: shutil.rmtree(folder, ignore_errors=True))
        (folder / "build").mkdir()
        fmu = _build(folder / "build" / "PipePlug.fmu")
        unpacked = folder / "unpacked"
        with zipfile.ZipFile(fmu) as zf:
            zf.extractall(unpacked)
        os.environ[SHARED_BUILD] = str(fmu)        # the workers inherit it
        warming += [warm(f"{core.parent.name}.pipeplug", str(core.parent.parent))
                    for core in (unpacked / "resources").glob("*/pipeplug")]
    except (OSError, subprocess.CalledProcessError, zipfile.BadZipFile):
        pass
    finally:
        for process in warming:
            process.wait()
