"""Many runs and model kinds in one Python process, live instances side by side, two builds;
FMI 2.0 and FMI 3.0 FMUs of both builds together.

pythonfmu runs every FMU of a process in one interpreter and imports their modules by name;
fmpy's ``simulate_fmu`` unpacks the FMU into a new temporary folder per run and deletes it
afterwards. Each result here must be bit-identical to the same run alone in a fresh process.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from pipeplug_references import closed_form as cf

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
BLOW = dict(t_off=0.05, Q=23e3)

#: One run of each kind, with parameters that differ between runs.
RUNS = {
    "exact I": dict(start={"tau1": 2e4}, stop=0.2, step=1e-3, **BLOW),
    "exact II": dict(start={"tau1": 3e4, "tau2": 5e3, "contact_growth": True}, stop=0.2,
                     step=1e-3, **BLOW),
    "fd": dict(start={"tau1": 2.5e4, "solver": "fd", "dt": 2e-4}, stop=0.2, step=1e-3, **BLOW),
    "elastic": dict(start={"tau1": 2e4, "elastic": True, "dx": 0.05}, stop=0.004, step=1e-4,
                    t_off=0.002, Q=23e3),
}


def _scenario(name: str, fmu: Path, runs: list[dict]) -> list:
    proc = subprocess.run([sys.executable, str(HERE / "one_process_scenarios.py"), name,
                           json.dumps({"fmu": str(fmu), "runs": runs})], capture_output=True,
                          text=True, timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def alone(fmu_file) -> dict:
    """Every run alone in a fresh process, through simulate_fmu and through a live instance."""
    return {(kind, how): _scenario(how, fmu_file, [run])[0]
            for kind, run in RUNS.items() for how in ("sequence", "stepped")}


@pytest.mark.parametrize("order", [["exact I", "exact II", "fd", "elastic"],
                                   ["elastic", "fd", "exact II", "exact I", "elastic"]],
                         ids=["first-to-last", "last-to-first"])
def test_simulate_fmu_runs_of_every_kind_in_one_process(fmu_file, alone, order):
    results = _scenario("sequence", fmu_file, [RUNS[k] for k in order])
    for kind, result in zip(order, results):
        assert result == alone[kind, "sequence"], kind


def test_fmi3_runs_of_every_kind_in_one_process_equal_fmi2_runs_alone(fmi3_files, alone):
    """The FMI 3.0 PipePlug (same core, same FMI base) in one process, run after run: each the
    FMI 2.0 FMU's run alone in a fresh process, bit for bit."""
    order = ["exact I", "elastic", "exact II", "fd", "exact I"]
    results = _scenario("sequence", fmi3_files["PipePlug"], [RUNS[k] for k in order])
    for kind, result in zip(order, results):
        assert result == alone[kind, "sequence"], kind


def test_live_instances_of_every_kind_stepped_interleaved(fmu_file, alone):
    """Each instance from its own unpacked copy; the copies of earlier ones are deleted."""
    order = ["elastic", "exact II", "fd", "exact I"]
    results = _scenario("stepped", fmu_file, [RUNS[k] for k in order])
    for kind, result in zip(order, results):
        assert result == alone[kind, "stepped"], kind


def test_two_different_builds_run_their_own_code(fmu_file, tmp_path):
    """A rebuilt FMU with a changed core runs its own core beside the first build."""
    changed = _build_with_changed_core(tmp_path)
    run = RUNS["exact I"]
    fmi3 = [f.parent / "fmi3" / "PipePlug.fmu" for f in (fmu_file, changed)]
    # FMI 2.0 and 3.0 builds of both cores in one process: original, changed, original, ...
    results = _scenario_two_builds([fmu_file, changed, fmi3[0], fmi3[1], fmu_file, fmi3[1]],
                                   run)
    t = np.array([float.fromhex(r[0]) for r in results[0]])
    case = cf.Case(tau1=run["start"]["tau1"], Q0=run["Q"], t0=run["t_off"])
    v_exact = cf.solution(case, t)["V1"]
    peak = np.abs(v_exact).max()
    for k, result in enumerate(results):
        v = np.array([float.fromhex(r[1]) for r in result])
        factor = 2.0 if k % 2 else 1.0         # the changed core doubles v_pipe
        assert np.abs(v - factor * v_exact).max() <= 1e-12 * peak, k


def _build_with_changed_core(tmp_path: Path) -> Path:
    """Build PipePlug.fmu from a copy of the sources whose core reports twice v_pipe."""
    src = tmp_path / "src"
    shutil.copytree(ROOT / "fmu_src", src, ignore=shutil.ignore_patterns("__pycache__"))
    exact = src / "pipeplug" / "rigid" / "exact.py"
    text = exact.read_text()
    marker = "        out = self._outputs(self._st, self._par, self._st[TIME])\n"
    assert marker in text
    exact.write_text(text.replace(marker, marker + "        out = (2.0 * out[0], *out[1:])\n"))
    dest = tmp_path / "changed" / "PipePlug.fmu"
    env = {**os.environ, "PYTHONPATH": str(src)}        # the copy before the installed one
    subprocess.run([sys.executable, "-m", "pipeplug_fmu", "build", "--dest", str(dest)],
                   check=True, capture_output=True, env=env, cwd=str(tmp_path))
    assert zipfile.ZipFile(dest).read("resources/slavemodule.txt").startswith(b"pipeplug_slave_")
    return dest


def _scenario_two_builds(fmus: list[Path], run: dict) -> list:
    """simulate_fmu of each FMU in turn, in one process."""
    script = (f"import json, sys; sys.path.insert(0, {str(HERE)!r});"
              f"import one_process_scenarios as s; run = json.loads({json.dumps(run)!r});"
              f"print(json.dumps([s.sequence(f, [run])[0] for f in "
              f"{[str(f) for f in fmus]!r}]))")
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])
