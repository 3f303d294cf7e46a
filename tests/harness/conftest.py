"""Harness tests run the ``pipeplug`` command in a subprocess, as a user or a CI job does."""
from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.fixture
def pipeplug_cli(tmp_path):
    """``pipeplug_cli(*args)``: run ``python -m pipeplug_harness.cli ARGS`` in ``tmp_path``."""
    def _run(*args, check=True):
        proc = subprocess.run([sys.executable, "-m", "pipeplug_harness.cli", *map(str, args)],
                              cwd=tmp_path, capture_output=True, text=True, timeout=600, check=False)
        if check and proc.returncode != 0:
            raise AssertionError(f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}")
        return proc
    return _run
