"""``pipeplug fuzz`` with fixed seeds: 3,600 cases on the invariants, 360 of them against the
reference, 180 through the FMU (both host styles), 9 through the fd check; no failure.

Split over three runs (three seeds) so that the suite's workers share them.
"""
from __future__ import annotations

import re

import pytest
from fuzz_helpers import count

RUNS = [(101, 1200), (102, 1200), (103, 1200)]        # (seed, cases)


@pytest.mark.parametrize("seed, cases", RUNS)
def test_fuzz_finds_no_failure(pipeplug_cli, fmu_dir, seed, cases):
    proc = pipeplug_cli("fuzz", "--seed", seed, "--cases", cases, "--reference-every", 10,
                        "--fmu-every", 20, "--fd-every", 400, "--fmu", fmu_dir, "--out", "out",
                        "--workers", 1,
                        check=False)
    text = proc.stdout
    print(text)                                             # the counts, in the test log
    assert proc.returncode == 0, text + proc.stderr
    assert count(r"cases: (\d+)", text) == cases
    assert count(r"against the reference: (\d+)", text) == cases // 10
    assert count(r"through the FMU: (\d+)", text) == cases // 20
    assert count(r"fd: (\d+)", text) == cases // 400
    assert count(r"failing cases: (\d+)", text) == 0
    for check in ("reference [python]", "grid [python]", "energy [python]", "reference [compiled]",
                  "grid [compiled]", "energy [compiled]",
                  "fmu [fmu t+=h]", "fmu [fmu t=k*h]", "reference [fmu t=k*h]", "fd bound [fd]"):
        assert re.search(re.escape(check) + r"\s+\d+\s+0\s", text), check


def test_the_runs_reach_the_promised_counts():
    assert sum(cases for _, cases in RUNS) >= 3000
    assert sum(cases // 10 for _, cases in RUNS) >= 300
