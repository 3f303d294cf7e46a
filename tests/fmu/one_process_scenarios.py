"""Scenarios that run several PipePlug FMUs in ONE Python process, as users' scripts do.

Run as ``python one_process_scenarios.py SCENARIO ARGS_JSON``; prints one JSON line: for each
run, every output at every communication point, as hex floats (so that results compare bit for
bit across processes).

* ``sequence``: ``simulate_fmu`` runs one after another (fmpy unpacks the FMU into a new
  temporary folder for each run and deletes it afterwards);
* ``stepped``: live ``FMU2Slave`` instances, each from its own unpacked copy (the copies of
  earlier instances are deleted once the next instance exists), stepped interleaved.
"""
from __future__ import annotations

import json
import shutil
import sys
import tempfile

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "W_input", "W_friction")


def _signal(run: dict) -> np.ndarray:
    """Q on [0, t_off), 0 after: the edge on a duplicated time stamp."""
    t_off, q, stop = run["t_off"], run["Q"], run["stop"]
    return np.array([(0.0, q), (t_off, q), (t_off, 0.0), (stop, 0.0)],
                    dtype=[("time", float), ("Q", float)])


def _hex(rows) -> list[list[str]]:
    return [[float(v).hex() for v in row] for row in rows]


def sequence(fmu: str, runs: list[dict]) -> list:
    """``simulate_fmu`` for each run, in order, in this process."""
    results = []
    for run in runs:
        res = simulate_fmu(fmu, stop_time=run["stop"], output_interval=run["step"],
                           start_values=run["start"], input=_signal(run), output=list(OUTPUTS))
        assert res["time"][-1] == run["stop"], (run, res["time"][-1])
        results.append(_hex(zip(res["time"], *(res[n] for n in OUTPUTS))))
    return results


def stepped(fmu: str, runs: list[dict]) -> list:
    """One live instance per run, each from its own unpacked copy, stepped interleaved.

    Communication points are t = k h (h the run's step) plus the load edge; Q is set before
    each step to its value on that step.
    """
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    live, folders = [], []
    for k, run in enumerate(runs):
        folder = extract(fmu, unzipdir=tempfile.mkdtemp(prefix="pipeplug_live_"))
        slave = FMU2Slave(guid=md.guid, unzipDirectory=folder,
                          modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"i{k}")
        slave.instantiate()
        for name, value in run["start"].items():
            _set(slave, vr[name], value)
        slave.setupExperiment(startTime=0.0, stopTime=run["stop"])
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        times = np.union1d(np.arange(round(run["stop"] / run["step"]) + 1) * run["step"],
                           [run["t_off"]])
        live.append((slave, run, times, []))
        for old in folders:                   # later instances never need earlier files
            shutil.rmtree(old)
        folders = [folder]
    for k in range(max(len(t) for _, _, t, _ in live) - 1):
        for slave, run, times, rows in live:
            if k + 1 < len(times):
                t, t_next = times[k], times[k + 1]
                slave.setReal([vr["Q"]], [run["Q"] if t < run["t_off"] else 0.0])
                slave.doStep(t, t_next - t)         # raises on any status but OK
                rows.append([t_next, *slave.getReal([vr[n] for n in OUTPUTS])])
    for slave, *_ in live:
        slave.terminate()
        slave.freeInstance()
    for folder in folders:
        shutil.rmtree(folder)
    return [_hex(rows) for *_, rows in live]


def _set(slave, vr, value) -> None:
    if isinstance(value, bool):
        slave.setBoolean([vr], [value])
    elif isinstance(value, str):
        slave.setString([vr], [value])
    else:
        slave.setReal([vr], [float(value)])


if __name__ == "__main__":
    scenario, args = sys.argv[1], json.loads(sys.argv[2])
    print(json.dumps({"sequence": sequence, "stepped": stepped}[scenario](**args)))
