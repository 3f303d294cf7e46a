"""The adapter and its build ship in the wheel: a fresh virtual environment with only
``pipeplug[fmu]`` installed from the wheel builds the FMU, which validates and runs there."""
from __future__ import annotations

import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import sys
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu
problems = validate_fmu(sys.argv[1])
assert problems == [], problems
r = simulate_fmu(sys.argv[1], stop_time=0.01, output_interval=1e-3, start_values={"tau1": 2e4},
                 output=["v_pipe"])
print("OK", r["time"][-1], r["v_pipe"][-1])
"""


@pytest.mark.slow
def test_fmu_builds_from_an_installed_wheel_in_a_fresh_environment(tmp_path):
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w",
                    str(tmp_path / "wheels"), str(ROOT)], check=True, capture_output=True)
    wheel, = (tmp_path / "wheels").glob("pipeplug-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    for module in ("pipeplug_fmu/build.py", "pipeplug_fmu/slave.py", "pipeplug_fmu/__main__.py",
                   "pipeplug/rigid/exact.py", "pipeplug_harness/cli.py",
                   "pipeplug_references/closed_form.py"):
        assert module in names, module
    env_dir = tmp_path / "env"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "-q", f"{wheel}[fmu]"], check=True,
                   capture_output=True, cwd=tmp_path)
    fmu = tmp_path / "out" / "PipePlug.fmu"
    subprocess.run([str(python), "-m", "pipeplug_fmu", "build", "--dest", str(fmu)],
                   check=True, capture_output=True, cwd=tmp_path)   # not from the repository
    probe = subprocess.run([str(python), "-c", PROBE, str(fmu)], capture_output=True,
                           text=True, cwd=tmp_path, check=False)
    assert probe.returncode == 0, probe.stderr[-3000:]
    assert probe.stdout.startswith("OK 0.01")
    # The command line works without the harness extra, and names the extra a subcommand needs.
    pipeplug = env_dir / "bin" / "pipeplug"
    overview = subprocess.run([str(pipeplug), "--help"], capture_output=True, text=True,
                              check=False)
    assert overview.returncode == 0 and "validate" in overview.stdout, overview.stderr
    cost = subprocess.run([str(pipeplug), "cost"], capture_output=True, text=True, check=False)
    assert cost.returncode == 2 and "pip install 'pipeplug[harness]'" in cost.stderr, cost.stderr
