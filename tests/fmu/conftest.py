"""Fixtures of the FMU tests: the plain C host, compiled once per test process."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest
from fmi_c_host import compile_host, host_env


@pytest.fixture(scope="session")
def c_host(tmp_path_factory) -> Path:
    """``fmi_host.c`` compiled (plain C: no libpython in it)."""
    return compile_host(tmp_path_factory.mktemp("c_host") / "fmi_host")


@pytest.fixture(scope="session")
def c3_host(tmp_path_factory) -> Path:
    """``fmi3_host.c`` compiled (plain C FMI 3.0 host: no libpython in it)."""
    return compile_host(tmp_path_factory.mktemp("c3_host") / "fmi3_host", "fmi3_host.c")


@pytest.fixture
def c_host_env() -> dict:
    """An environment naming this test run's Python (which has numpy) in PIPEPLUG_PYTHON, with
    no PYTHON* variable (nothing preloaded, no PYTHONPATH)."""
    return host_env(PIPEPLUG_PYTHON=sys.executable)
