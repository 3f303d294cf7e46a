"""Drive tests: drives run in a worker process each; the results come back as JSON."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from drive_helpers import toml_text

WORKER = Path(__file__).with_name("drive_worker.py")


@pytest.fixture
def run_drive(fmu_file, tmp_path):
    """``run_drive(sections)``: write the drive file, run it in a worker, return the result."""
    def _run(sections: dict) -> dict:
        path = tmp_path / "d.toml"
        path.write_text(toml_text(sections))
        proc = subprocess.run([sys.executable, str(WORKER), str(path), str(fmu_file)],
                              capture_output=True, text=True, timeout=600, check=False)
        if proc.returncode:
            raise AssertionError(f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}")
        return json.loads(proc.stdout.strip().splitlines()[-1])
    return _run
