"""Helpers of the FMU tests: the contract's tables and running scenarios in fresh processes.

pythonfmu FMUs share one interpreter and ``sys.modules`` per process, and a host crash must
show up as a failed process rather than take the test run down, so every FMU interaction runs
in a subprocess (``fmu_scenarios.py``).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: The FMU contract's parameter table: name -> (unit, default, min, max). Copied from the
#: contract, not from the code, so the tests check the code against it.
CONTRACT_PARAMETERS = {
    "L1": ("m", 1.0, 0.0, None), "L2": ("m", 1.0, 0.0, None), "R1": ("m", 0.035, 0.0, None),
    "h1": ("m", 0.003, 0.0, None), "rho1": ("kg/m3", 7800.0, 0.0, None),
    "rho2": ("kg/m3", 1800.0, 0.0, None), "E1": ("Pa", 1.95e11, 0.0, None),
    "E2": ("Pa", 6.0e8, 0.0, None), "tau1": ("Pa", 0.0, 0.0, None),
    "tau2": ("Pa", 1.0e4, 0.0, None), "dt": ("s", 2.0e-4, 0.0, None),
    "dx": ("m", 0.01, 0.0, None), "courant": ("1", 1.0, 0.0, 1.0),
    "x_monitor": ("m", 0.5, 0.0, None),
    "max_internal_steps": ("1", 1e8, 1.0, None),      # not in the contract: the project's own
    "ram_mass": ("kg", 0.0, 0.0, None), "cushion_stiffness": ("N/m", 0.0, 0.0, None),
    "cushion_restitution": ("1", 1.0, 0.0, 1.0),
    "q_face": ("Pa", 0.0, 0.0, None), "q_plug_face": ("Pa", 0.0, 0.0, None),
    "J_shaft": ("s/m", 0.0, 0.0, 1e3), "J_face": ("s/m", 0.0, 0.0, 1e3),
    "L2_after_cleanout": ("m", 0.0, 0.0, None),
}
#: The contract's inputs: name -> (type, unit, variability).
CONTRACT_INPUTS = {"Q": ("Real", "N", "continuous"), "strikes": ("Integer", None, "discrete"),
                   "v_strike": ("Real", "m/s", "continuous"),
                   "cleanouts": ("Integer", None, "discrete")}
CONTRACT_OPTIONS = {"contact_growth": ("Boolean", "false"), "elastic": ("Boolean", "false"),
                    "solver": ("String", "exact"), "plug_growth": ("Boolean", "false")}
#: Output name -> (type, unit), from the contract's table.
CONTRACT_OUTPUTS = {"v_pipe": ("Real", "m/s"), "v_plug": ("Real", "m/s"), "u_pipe": ("Real", "m"),
                    "u_plug": ("Real", "m"), "F_outer": ("Real", "N"), "F_inner": ("Real", "N"),
                    "W_input": ("Real", "J"), "W_friction": ("Real", "J"),
                    "W_friction_outer": ("Real", "J"), "W_friction_inner": ("Real", "J"),
                    "E_kinetic": ("Real", "J"), "E_strain": ("Real", "J"),
                    "W_numerical": ("Real", "J"),      # not in the contract: the project's own
                    "F_head": ("Real", "N"), "v_ram": ("Real", "m/s"), "W_ram": ("Real", "J"),
                    "W_cushion": ("Real", "J"),        # not in the contract: the project's own
                    "E_transferred": ("Real", "J"), "stress_head": ("Real", "Pa"),
                    "stress_min": ("Real", "Pa"), "stress_max": ("Real", "Pa"),
                    "at_rest": ("Boolean", None), "pipe_mode": ("Integer", None),
                    "plug_mode": ("Integer", None), "W_face": ("Real", "J"),
                    "W_damping": ("Real", "J"),
                    "L2_now": ("Real", "m"), "W_accretion": ("Real", "J"),
                    "W_removed": ("Real", "J")}
#: Output name -> name in pipeplug_references.closed_form.solution
CLOSED_FORM_NAMES = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2",
                     "F_outer": "F_outer", "F_inner": "F_inner", "W_input": "W_input",
                     "W_friction": "W_friction"}
Q0, T0 = 23000.0, 0.05          # the paper's pulse: amplitude [N], duration [s]


def run_scenario(name: str, fmu: Path, python_args=(), env=None,
                 script: str = "fmu_scenarios.py", **kwargs) -> dict:
    """Run scenario ``name`` of ``script`` in a fresh process; its result.

    Fails the test if the process does not exit normally (a crash of the host).
    """
    cmd = [sys.executable, *python_args, str(HERE / script), name, str(fmu), json.dumps(kwargs)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env, check=False,
                          cwd=str(HERE))
    assert proc.returncode == 0, (
        f"scenario {name} ended with {proc.returncode}\n{proc.stdout[-3000:]}\n"
        f"{proc.stderr[-3000:]}")
    line = proc.stdout.strip().splitlines()[-1]
    assert line.startswith("RESULT "), proc.stdout[-3000:]
    result = json.loads(line[len("RESULT "):])
    result["stdout"] = proc.stdout
    return result


def env_without_site_hooks() -> dict:
    """An environment for ``python -S`` that still finds numpy and FMPy but not this project.

    With ``-S`` no ``.pth`` file runs, so the editable install of ``pipeplug`` is invisible;
    the site-packages directory is given through PYTHONPATH.
    """
    import fmpy

    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(fmpy.__file__).resolve().parent.parent)
    return env


def closed_form(params: dict, times) -> dict:
    """Model I closed form for the paper's pulse (or one ending at ``params["t0"]``), by FMU
    output name."""
    import numpy as np

    from pipeplug_references.closed_form import Case, solution

    case = Case(tau1=params.get("tau1", CONTRACT_PARAMETERS["tau1"][1]),
                tau2=params.get("tau2", CONTRACT_PARAMETERS["tau2"][1]), Q0=Q0,
                t0=params.get("t0", T0))
    sol = solution(case, np.asarray(times, dtype=float))
    return {name: sol[key] for name, key in CLOSED_FORM_NAMES.items()}


def columns(rows: list) -> dict:
    """Rows of outputs (dicts) as arrays by output name."""
    import numpy as np

    return {name: np.array([row[name] for row in rows]) for name in rows[0]}


def assert_matches_closed_form(got: dict, times, params: dict, rtol: float = 1e-9) -> None:
    """Every Real output within ``rtol`` times its peak of the closed form.

    Forces are not compared at the pulse edges 0 and T0: the FMU reports the force under the
    step's Q that ends there (at t = 0: the start value 0), the closed form the right limit.
    """
    import numpy as np

    times = np.asarray(times, dtype=float)
    expected = closed_form(params, times)
    at_edge = (np.abs(times - T0) <= 1e-12) | (times == 0.0)
    for name, want in expected.items():
        keep = ~at_edge if name.startswith("F_") else np.ones_like(at_edge)
        peak = max(np.max(np.abs(want)), 1e-300)
        err = np.max(np.abs(np.asarray(got[name])[keep] - want[keep]))
        assert err <= rtol * peak, f"{name}: max error {err:.3e} > {rtol:g} * peak {peak:.6g}"
