#!/usr/bin/env python3
"""Set up the project and run its two jobs; needs only Python >= 3.10 and the package registries.

    python dev.py          the main job: set up .venv, build dist/ (the FMUs and system files),
                           validate PipePlug.fmu against the analytic solutions, print the table
    python dev.py test     the linters (ruff, the import contracts), then the whole test suite

The virtual environment is made in ``.venv`` beside this file and (re)installed whenever
``pyproject.toml`` changes. Extra arguments after ``test`` go to pytest.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PYTHON = BIN / ("python.exe" if os.name == "nt" else "python")
STAMP = VENV / ".pipeplug-installed"


def _run(*cmd: object) -> None:
    """Run a command in the project root; stop with its exit code if it fails."""
    print("+", " ".join(map(str, cmd)), flush=True)
    code = subprocess.call([str(c) for c in cmd], cwd=ROOT)
    if code:
        sys.exit(code)


def ensure_environment() -> None:
    """Create ``.venv`` and install the project with its test extras when needed."""
    digest = hashlib.sha256((ROOT / "pyproject.toml").read_bytes()).hexdigest()
    if STAMP.exists() and STAMP.read_text() == digest and PYTHON.exists():
        return
    if not PYTHON.exists():
        print(f"creating {VENV}", flush=True)
        venv.EnvBuilder(with_pip=True).create(VENV)
    _run(PYTHON, "-m", "pip", "install", "--quiet", "--upgrade", "pip")
    _run(PYTHON, "-m", "pip", "install", "--quiet", "-e", ".[test]")
    STAMP.write_text(digest)


def main(argv: list[str]) -> None:
    """Dispatch ``python dev.py [test [pytest args...]]``."""
    ensure_environment()
    if argv[:1] == ["test"]:
        _run(PYTHON, "-m", "ruff", "check", ".")
        _run(BIN / "lint-imports")
        _run(PYTHON, "-m", "pytest", "-n", "2", "-q", *argv[1:])
    elif not argv:
        _run(PYTHON, "build_fmu.py")
        _run(BIN / "pipeplug", "validate", "--fmu", "dist/PipePlug.fmu")
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
