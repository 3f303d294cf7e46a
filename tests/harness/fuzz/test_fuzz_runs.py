"""``pipeplug fuzz`` with fixed seeds: 3,600 cases on the invariants, every tenth against the
reference (but the damped cases too stiff for it), 180 through the FMU (both host styles),
every 400th through the fd check (but the damped ones); no failure.

Split over three runs (three seeds) so that the suite's workers share them.
"""
from __future__ import annotations

import re

import pytest
from fuzz_helpers import count

from pipeplug_harness.fuzz.cases import Plan, generate

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
    planned = [generate(seed, i, Plan(10, 20, 400)).checks for i in range(cases)]
    assert count(r"against the reference: (\d+)", text) == sum("reference" in c for c in planned)
    assert count(r"through the FMU: (\d+)", text) == cases // 20
    assert count(r"fd: (\d+)", text) == sum("fd" in c for c in planned)
    assert count(r"failing cases: (\d+)", text) == 0
    assert count(r"model I damped (\d+)", text) == sum(
        generate(seed, i).model == "I damped" for i in range(cases))
    for check in ("reference [python]", "grid [python]", "energy [python]", "reference [compiled]",
                  "grid [compiled]", "energy [compiled]",
                  "fmu [fmu t+=h]", "fmu [fmu t=k*h]", "reference [fmu t=k*h]", "fd bound [fd]"):
        assert re.search(re.escape(check) + r"\s+\d+\s+0\s", text), check


def test_the_runs_reach_the_promised_counts():
    assert sum(cases for _, cases in RUNS) >= 3000
    checks = [generate(seed, i, Plan(10, 20, 400)).checks for seed, cases in RUNS
              for i in range(cases)]
    assert sum("reference" in c for c in checks) >= 300


def test_a_rerun_leaves_none_of_the_earlier_runs_failures(pipeplug_cli, tmp_path):
    """A run into a folder where an earlier run had saved failures/case-0-0.json reported 0
    failures, yet the old file stayed and the new manifest named it as its own."""
    import json

    from pipeplug_harness.io import MANIFEST, OutputFolder
    with OutputFolder(tmp_path / "fx", "fuzz") as earlier:          # as an earlier run left it
        (tmp_path / "fx" / "failures").mkdir()
        earlier.file("failures/case-0-0.json").write_text("{}")
        earlier.file("summary.txt").write_text("1 failing case\n")
    (tmp_path / "fx" / "failures" / "mine.txt").write_text("the user's")   # never removed
    proc = pipeplug_cli("fuzz", "--cases", 20, "--no-fmu", "--fd-every", 0, "--out", "fx",
                        "--workers", 1)
    assert count(r"failing cases: (\d+)", proc.stdout) == 0
    assert not (tmp_path / "fx" / "failures" / "case-0-0.json").exists()
    assert (tmp_path / "fx" / "failures" / "mine.txt").read_text() == "the user's"
    assert json.loads((tmp_path / "fx" / MANIFEST).read_text())["files"] == ["summary.txt"]
    assert "--cases 20" in (tmp_path / "fx" / "summary.txt").read_text()
