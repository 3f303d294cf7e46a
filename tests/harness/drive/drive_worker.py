"""Run one drive in its own process and print the result as JSON (floats exact).

Usage: ``python drive_worker.py FILE.toml FMU``. The FMU is loaded only here, never into the test
process (pythonfmu FMUs share the interpreter of the process that loads them).
"""
from __future__ import annotations

import json
import sys
from dataclasses import asdict

from pipeplug_harness.drive.file import load_drive
from pipeplug_harness.drive.run import run_drive

if __name__ == "__main__":
    result = run_drive(load_drive(sys.argv[1]), sys.argv[2])
    print(json.dumps({"outcome": result.outcome, "steps": result.steps,
                      "blows": [asdict(b) for b in result.blows]}))
