"""Scenarios run against PipePlug.fmu, each in a fresh process (``fmu_helpers.run_scenario``).

    python fmu_scenarios.py SCENARIO FMU_DIR '{"json": "keyword arguments"}'

The last stdout line is ``RESULT <json>``: the scenario's result, the collected log and the
file the FMU's private copy of the core (``pipeplug_fmu_<tag>.pipeplug``) was loaded from. A process that
crashes prints no result, so the test fails.
"""
from __future__ import annotations

import json
import sys

from fmu_driver import LOG, Slave, pulse, run_grid


def runs(fmu_dir, q0, t0, runs):
    """One instance per named run ``{"params": {...}, "times": [t0, t1, ...]}``, each driven
    under the pulse: outputs after each step."""
    rows = {}
    for name, run in runs.items():
        slave = Slave(fmu_dir, name)
        if slave.start(run["params"]):
            raise RuntimeError(f"initialization of {name} refused")
        rows[name] = run_grid(slave, run["times"], q0, t0)
        slave.close()
    return {"rows": rows}


def interleaved(fmu_dir, cases, times, q0, t0):
    """Instances with different parameters, stepped in turn on one grid."""
    slaves = [Slave(fmu_dir, f"inst{k}") for k in range(len(cases))]
    for slave, params in zip(slaves, cases):
        slave.start(params)
    rows = [[] for _ in slaves]
    for a, b in zip(times[:-1], times[1:]):
        for slave, out in zip(slaves, rows):
            if slave.step(a, b - a, pulse(a, q0, t0)):
                raise RuntimeError("step refused")
            out.append(slave.outputs())
    return {"rows": rows}


def state(fmu_dir, params, q0, t0, times, save_index):
    """Save the state at times[save_index]; continue, restore twice, restore a serialized copy
    into a fresh default instance; the four continuations and the outputs right after restore."""
    a = Slave(fmu_dir, "a")
    a.start(params)
    run_grid(a, times[:save_index + 1], q0, t0)
    saved_outputs = a.outputs()
    snapshot = a.fmu.getFMUstate()
    rest = times[save_index:]
    runs = {"original": run_grid(a, rest, q0, t0)}
    after_restore = {}
    for name in ("restore1", "restore2"):
        a.fmu.setFMUstate(snapshot)
        after_restore[name] = a.outputs()
        runs[name] = run_grid(a, rest, q0, t0)
    blob = a.fmu.serializeFMUstate(snapshot)
    b = Slave(fmu_dir, "fresh")
    b.start()                               # default parameters: the state must bring its own
    b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
    after_restore["fresh"] = b.outputs()
    restored_params = {name: b.get(name) for name in params}
    runs["fresh"] = run_grid(b, rest, q0, t0)
    a.fmu.freeFMUstate(snapshot)
    return {"saved_outputs": saved_outputs, "after_restore": after_restore, "runs": runs,
            "restored_params": restored_params, "blob_size": len(blob)}


def bad_input(fmu_dir, kind, value=None):
    """One refused input of ``kind``; then every kind of call on that instance, and a second
    instance in the same process stepping normally."""
    bad = Slave(fmu_dir, "bad")
    statuses = {}
    if kind == "parameters":                     # value = {name: value}
        statuses["exit_init"] = bad.start(value)
    else:
        stop = 0.01 if kind == "past_stop" else None
        statuses["exit_init"] = bad.start(stop=stop)
        statuses["first_step"] = bad.step(0.0, 0.005, 23e3)
        if kind == "fixed_after_init":
            statuses["refused"] = bad.set(value[0], value[1])
        elif kind == "nan_q":
            statuses["refused"] = bad.step(0.005, 0.005, float("nan"))
        elif kind == "wrong_time":
            statuses["refused"] = bad.step(0.5, 0.005, 23e3)
        elif kind == "bad_state":
            statuses["refused"] = bad.call("deSerializeFMUstate", b"not a PipePlug state")
        elif kind == "unknown_get":
            statuses["refused"] = bad.call("getReal", [value])
        elif kind == "unknown_set":
            statuses["refused"] = bad.call("setReal", [value], [1.0])
        elif kind == "past_stop":
            statuses["to_stop"] = bad.step(0.005, 0.005, 23e3)
            statuses["refused"] = bad.step(0.01, 0.005, 23e3)
    lines_at_refusal = len(LOG)
    if kind != "past_stop":                      # past the stop time no step is valid
        statuses["later_step"] = bad.step(0.005, 0.005, 23e3)
    statuses["later_set"] = bad.set("Q", 1.0)
    if "refused" not in statuses or statuses["refused"] == 3:   # refused for good: quiet now
        statuses["later_set_parameter"] = bad.set("tau1", 1.0)
    statuses["later_get"] = bad.call("getReal", [0, 1, 2])
    statuses["later_terminate"] = bad.call("terminate")
    statuses["reset"] = bad.call("reset")               # and usable again
    statuses["after_reset"] = bad.start()
    after_reset_rows = run_grid(bad, [0.0, 0.01, 0.02], 23e3, 0.05)
    bad.fmu.freeInstance()
    good = Slave(fmu_dir, "good")
    good.start()
    good_rows = run_grid(good, [0.0, 0.01, 0.02], 23e3, 0.05)
    good.close()
    return {"statuses": statuses, "lines_at_refusal": lines_at_refusal, "good_rows": good_rows,
            "after_reset_rows": after_reset_rows}


def reset(fmu_dir, params, times, q0, t0):
    """Runs after fmi2Reset (of a used instance and of a refused one) and on a fresh instance."""
    used = Slave(fmu_dir, "used")
    used.start(params)
    run_grid(used, times, q0, t0)
    used.call("reset")
    used.call("setupExperiment", None, 0.0, None)
    used.call("enterInitializationMode")              # FMI 2.0 reads values from here on
    after_reset = {name: used.get(name) for name in params}
    after_reset_outputs = used.outputs()
    used.call("reset")
    refused = Slave(fmu_dir, "refused")
    refused_status = refused.start({"tau2": float("nan")})
    refused.call("reset")
    runs = {}
    for name, slave in (("used", used), ("refused", refused), ("fresh", Slave(fmu_dir, "new"))):
        slave.start()
        runs[name] = run_grid(slave, times, q0, t0)
        slave.close()
    return {"after_reset": after_reset, "after_reset_outputs": after_reset_outputs,
            "refused_status": refused_status, "runs": runs}


def simulate_pulse(fmu_dir, cases, q0, t0, stop, interval):
    """fmpy.simulate_fmu with a rectangular-pulse input signal, once per parameter case."""
    import numpy as np
    from fmpy import simulate_fmu

    signal = np.array([(0.0, q0), (t0, q0), (t0, 0.0), (stop, 0.0)],
                      dtype=[("time", float), ("Q", float)])
    runs = []
    for params in cases:
        res = simulate_fmu(fmu_dir, start_time=0.0, stop_time=stop, output_interval=interval,
                           input=signal, start_values=params, fmi_type="CoSimulation")
        runs.append({name: res[name].tolist() for name in res.dtype.names})
    import sys
    return {"runs": runs, "numba_loaded": "numba" in sys.modules}


def host_clock(fmu_dir, params, q0, t0, h, n_steps, clock):
    """A host keeping its own clock, as C hosts and OMSimulator do: doStep(t, h) with a
    constant h and t = k h (``clock = "k*h"``) or t += h (``"+=h"``); it switches Q off at its
    first point t >= t0. Returns the points, the outputs and that switch time."""
    slave = Slave(fmu_dir, clock)
    if slave.start(params):
        raise RuntimeError("initialization refused")
    times, rows, t, switch = [0.0], [], 0.0, None
    for k in range(1, n_steps + 1):
        t_next = k * h if clock == "k*h" else t + h
        if switch is None and t >= t0:
            switch = t
        if slave.step(t, h, q0 if switch is None else 0.0):
            raise RuntimeError(f"doStep({t!r}, {h!r}) refused")
        rows.append(slave.outputs())
        times.append(t_next)
        t = t_next
    slave.close()
    return {"times": times, "rows": rows, "switch": switch}


def host_core_first(fmu_dir):
    """The host imports this repository's ``pipeplug`` before the FMU; v_pipe after 1 ms."""
    import pipeplug

    slave = Slave(fmu_dir, "after_host")
    slave.start()
    rows = run_grid(slave, [0.0, 1e-3], 23e3, 0.05)
    slave.close()
    return {"host_core_file": pipeplug.__file__, "v_pipe": rows[-1]["v_pipe"]}


def initialize_only(fmu_dir, params):
    """exitInitializationMode with ``params``; a few steps if it is accepted."""
    slave = Slave(fmu_dir, "only")
    status = slave.start(params)
    rows = [] if status else run_grid(slave, [0.0, 1e-4, 2e-4], 23e3, 0.05)
    slave.close()
    return {"status": status, "rows": rows}


def process_pythons(fmu_dir):
    """:func:`initialize_only` with default parameters, and the libpython files mapped then."""
    result = initialize_only(fmu_dir, {})
    with open("/proc/self/maps") as maps:
        result["libpythons"] = sorted({line.split()[-1] for line in maps
                                       if "/libpython" in line})
    return result


def standalone(fmu_dir):
    """Whether ``pipeplug`` is importable before the FMU loads; v_pipe after 1 ms of Q0."""
    import importlib.util

    visible = importlib.util.find_spec("pipeplug") is not None
    slave = Slave(fmu_dir, "standalone")
    slave.start()
    rows = run_grid(slave, [0.0, 1e-3], 23e3, 0.05)
    slave.close()
    return {"core_visible_before": visible, "v_pipe": rows[-1]["v_pipe"]}


def strikes(fmu_dir, params, times, schedule, save_index=None):
    """Step through ``times`` under Q = 0 with the inputs ``strikes`` and ``v_strike`` set
    before the step starting at ``schedule``'s times ({"t": [strikes, v_strike]}): the status
    and outputs (with the ram's) after each step. With ``save_index``, the state after that
    step is saved, the run finished, the state restored and the rest run again with the same
    inputs ("again")."""
    slave = Slave(fmu_dir, "strikes")
    if slave.start(params):
        raise RuntimeError("initialization refused")
    plan = {float(t): value for t, value in schedule.items()}

    def run(pairs):
        rows = []
        for a, b in pairs:
            if a in plan:
                slave.set("strikes", int(plan[a][0]))
                slave.set("v_strike", float(plan[a][1]))
            status = slave.call("doStep", a, b - a)
            row = dict(slave.outputs(), status=status, **{
                name: slave.get(name) for name in ("v_ram", "W_ram", "W_cushion", "E_kinetic",
                                                   "F_head")})
            rows.append(row)
        return rows

    pairs = list(zip(times[:-1], times[1:]))
    if save_index is None:
        return {"rows": run(pairs)}
    first = run(pairs[:save_index + 1])
    snapshot = slave.fmu.getFMUstate()
    rest = run(pairs[save_index + 1:])
    slave.fmu.setFMUstate(snapshot)
    again = run(pairs[save_index + 1:])      # the same inputs again: the same strikes
    return {"rows": first + rest, "again": again}


def strike_without_ram(fmu_dir, params, h):
    """A rise of strikes without a ram: the status and log of that doStep(0, h), u_pipe after
    it, then the status of the same step again once the counter is put back, and its time."""
    slave = Slave(fmu_dir, "noram")
    slave.start(params)
    slave.set("Q", 1e4)
    slave.set("strikes", 1)
    refused = slave.call("doStep", 0.0, h)
    at_refusal = list(LOG)
    u_after = slave.get("u_pipe")
    slave.set("strikes", 0)
    again = slave.call("doStep", 0.0, h)
    return {"refused": refused, "log_at_refusal": at_refusal, "u_after": u_after,
            "again": again, "u_again": slave.get("u_pipe")}


def cleanouts(fmu_dir, params, times, q0, t0, schedule, save_index):
    """Step through ``times`` under a rectangular pulse with the input ``cleanouts`` set before
    the step starting at ``schedule``'s times ({"t": count}); the status and the growing plug's
    outputs after each step. The state after step ``save_index`` is saved, the run finished,
    the state restored and the rest run again ("again")."""
    slave = Slave(fmu_dir, "cleanouts")
    if slave.start(params):
        raise RuntimeError("initialization refused")
    plan = {float(t): int(n) for t, n in schedule.items()}
    names = ("v_pipe", "v_plug", "u_pipe", "u_plug", "L2_now", "W_accretion", "W_removed",
             "W_input", "W_friction", "W_face", "E_kinetic")

    def run(pairs):
        rows = []
        for a, b in pairs:
            if a in plan:
                slave.set("cleanouts", plan[a])
            status = slave.step(a, b - a, pulse(a, q0, t0))
            rows.append(dict(status=status, **{n: slave.get(n) for n in names}))
        return rows

    pairs = list(zip(times[:-1], times[1:]))
    first = run(pairs[:save_index + 1])
    snapshot = slave.fmu.getFMUstate()
    rest = run(pairs[save_index + 1:])
    slave.fmu.setFMUstate(snapshot)
    again = run(pairs[save_index + 1:])
    return {"rows": first + rest, "again": again}


def cleanout_without_growth(fmu_dir, params, h):
    """A rise of cleanouts without plug_growth: the status and log of that doStep(0, h)."""
    slave = Slave(fmu_dir, "nogrowth")
    slave.start(params)
    slave.set("cleanouts", 1)
    refused = slave.call("doStep", 0.0, h)
    return {"refused": refused, "log_at_refusal": list(LOG)}


def main() -> None:
    name, fmu_dir, kwargs = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
    if name.startswith("cosim"):
        import fmu_cosim
        result = getattr(fmu_cosim, name)(fmu_dir, **kwargs)
    else:
        result = globals()[name](fmu_dir, **kwargs)
    cores = [m for name, m in sys.modules.items()        # the FMU's private copy of the core
             if name.startswith("pipeplug_fmu_") and name.endswith(".pipeplug")]
    core = cores[0] if len(cores) == 1 else None
    result.update(log=LOG, core_file=getattr(core, "__file__", None))
    sys.stdout.write("\nRESULT " + json.dumps(result) + "\n")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
