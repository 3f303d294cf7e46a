"""Harness tests run the ``pipeplug`` command in a subprocess, as a user or a CI job does."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def fmu_file(tmp_path_factory) -> Path:
    """A freshly built PipePlug.fmu (one per test worker)."""
    dest = tmp_path_factory.mktemp("fmu") / "PipePlug.fmu"
    subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--dest", str(dest)],
                   check=True, capture_output=True)
    return dest


@pytest.fixture
def pipeplug_cli(tmp_path):
    """``pipeplug_cli(*args)``: run ``python -m pipeplug_harness.cli ARGS`` in ``tmp_path``."""
    def _run(*args, check=True):
        proc = subprocess.run([sys.executable, "-m", "pipeplug_harness.cli", *map(str, args)],
                              cwd=tmp_path, capture_output=True, text=True, timeout=600)
        if check and proc.returncode != 0:
            raise AssertionError(f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}")
        return proc
    return _run
