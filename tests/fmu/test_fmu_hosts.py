"""PipePlug.fmu under three hosts -- fmpy.simulate_fmu, the ``fmpy`` command line and libcosim --
against the closed form of model I for the paper's pulse (Q0 = 23 kN for t0 = 50 ms)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
from fmu_helpers import Q0, T0, assert_matches_closed_form, columns, run_scenario

STOP = 0.3
#: (tau1, tau2) [Pa] in each solution domain of model I, plus the defaults and no plug.
CASES = {"I": (2e4, 1e4), "II": (2e4, 2e4), "III": (7e4, 3.5e4), "IV": (6.5e4, 6.5e4),
         "V": (1e5, 1e4), "defaults": (0.0, 1e4), "no plug": (2e4, 0.0)}


def test_simulate_fmu_pulse_matches_closed_form(fmu_dir):
    params = [{"tau1": t1, "tau2": t2} for t1, t2 in CASES.values()]
    result = run_scenario("simulate_pulse", fmu_dir, cases=params, q0=Q0, t0=T0, stop=STOP,
                          interval=1e-3)
    for name, case, run in zip(CASES, params, result["runs"]):
        time = np.array(run["time"])
        assert time[-1] == STOP, f"{name}: the run stopped early at {time[-1]}"
        assert len(time) == 301, name
        assert_matches_closed_form(run, time, case)
    # the rigid models run as plain Python in the FMU: numba's import would cost more than it saves
    assert result["numba_loaded"] is False


def _fmpy_command() -> list:
    script = Path(sys.executable).with_name("fmpy")
    return [str(script)] if script.exists() else [sys.executable, "-m", "fmpy"]


def test_fmpy_command_line(fmu_file, tmp_path):
    (tmp_path / "pulse.csv").write_text(f"time,Q\n0,{Q0}\n{T0},{Q0}\n{T0},0\n{STOP},0\n")
    out = tmp_path / "out.csv"
    cmd = _fmpy_command() + [
        "simulate", str(fmu_file), "--stop-time", str(STOP), "--output-interval", "1e-3",
        "--input-file", str(tmp_path / "pulse.csv"), "--output-file", str(out),
        "--start-values", "tau1", "20000", "tau2", "10000"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=str(tmp_path), check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data["time"][-1] == STOP
    assert_matches_closed_form({n: data[n] for n in data.dtype.names}, data["time"],
                               {"tau1": 2e4, "tau2": 1e4})


def test_libcosim_pulse_matches_closed_form(fmu_file):
    checkpoints = [round(0.01 * k, 10) for k in range(1, 31)]
    assert T0 in checkpoints
    for name in ("I", "III"):
        tau1, tau2 = CASES[name]
        result = run_scenario("cosim_pulse", fmu_file, params={"tau1": tau1, "tau2": tau2},
                              q0=Q0, t0=T0, step=1e-4, checkpoints=checkpoints)
        assert_matches_closed_form(columns(result["rows"]), checkpoints,
                                   {"tau1": tau1, "tau2": tau2})
