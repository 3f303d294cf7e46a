"""Whole FMU runs with the exact solver as plain Python (the FMU's choice) and compiled.

Usage::

    python -m benchmarks.fmu_path [--repeat 5]

Builds ``PipePlug.fmu`` twice from the installed sources: as shipped (the slave builds its rigid
models with ``compiled=False``) and with that switch turned to ``compiled=True`` (numba, cached on
disk). Each round runs the Fig. 3 case in a fresh Python process per FMU, as ``pipeplug
figures`` does: defaults, tau1 = tau*/(gamma + 1), the three tau2 of the figure, a 23 kN blow of
50 ms, communication step 0.5 ms to 0.3 s, through fmpy's ``simulate_fmu``. The cache is warmed by
one untimed run of each FMU first. Prints, per FMU, the best and median over the rounds of the
three runs' time (loading the FMU, numba's import and cache included) and of the process's whole
wall time.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SWITCH = "core.build_model(params, options, compiled=False)"

_RUN = """
import json, sys, time
start = time.perf_counter()
from pipeplug_harness.load import Load
from pipeplug_harness.session import simulate
from pipeplug_references.closed_form import figure_cases
imported = time.perf_counter()
for case in figure_cases()["3"]:
    simulate(sys.argv[1], {"tau1": case.tau1, "tau2": case.tau2},
             Load.from_pulses([(0.0, case.t0, case.Q0)]), 5e-4, 0.3)
print(json.dumps({"runs": time.perf_counter() - imported}))
"""


def build_both(folder: Path) -> dict:
    """Build the shipped FMU and its compiled variant into ``folder``: {label: path}."""
    import pipeplug
    import pipeplug_fmu

    src = folder / "src"
    for package in (pipeplug, pipeplug_fmu):
        origin = Path(package.__file__).resolve().parent
        shutil.copytree(origin, src / origin.name, ignore=shutil.ignore_patterns("__pycache__"))
    slave = src / "pipeplug_fmu" / "slave.py"
    text = slave.read_text()
    if SWITCH not in text:
        raise RuntimeError(f"the slave no longer builds its model with {SWITCH!r}")
    fmus = {}
    for label, code in (("plain Python (shipped)", text),
                        ("compiled (numba)", text.replace(SWITCH, SWITCH.replace("False", "True")))):
        slave.write_text(code)
        dest = folder / label.split()[0] / "PipePlug.fmu"
        env = dict(os.environ, PYTHONPATH=str(src))
        subprocess.run([sys.executable, "-m", "pipeplug_fmu", "build", "--dest", str(dest)],
                       check=True, capture_output=True, env=env, cwd=str(folder))
        fmus[label] = dest
    return fmus


def run_once(fmu: Path) -> tuple[float, float]:
    """(seconds of the three runs, seconds of the whole process) in a fresh process."""
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", _RUN, str(fmu)], capture_output=True, text=True,
                          check=True)
    wall = time.perf_counter() - start
    return json.loads(proc.stdout.strip().splitlines()[-1])["runs"], wall


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="fresh processes per FMU")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="pipeplug_fmu_path_") as tmp:
        fmus = build_both(Path(tmp))
        for fmu in fmus.values():
            run_once(fmu)                                    # warm the caches
        times = {label: [] for label in fmus}
        for _ in range(args.repeat):                         # interleaved
            for label, fmu in fmus.items():
                times[label].append(run_once(fmu))
    print(f"Fig. 3 case (three FMU runs of 600 steps), fresh process, warm cache, "
          f"{args.repeat} rounds:")
    for label, rows in times.items():
        runs, walls = [r for r, _ in rows], [w for _, w in rows]
        print(f"  {label:24s} runs {min(runs):6.3f} s (median {statistics.median(runs):6.3f}); "
              f"whole process {min(walls):6.3f} s (median {statistics.median(walls):6.3f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
