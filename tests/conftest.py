"""Fixtures shared by the whole suite: the FMUs and system files, built once per test process by
the project's own build command (``build_fmu.py``, in a subprocess, as a user runs it)."""
from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def fmu_file(tmp_path_factory) -> Path:
    """PipePlug.fmu of ``build_fmu.py`` run once, into a temporary directory (the build's other
    files beside it)."""
    dest = tmp_path_factory.mktemp("fmu") / "PipePlug.fmu"
    subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--dest", str(dest)],
                   check=True, capture_output=True, cwd=str(dest.parent))
    return dest


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
