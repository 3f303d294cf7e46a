"""Scenarios run against Hammer.fmu, each in a fresh process (``fmu_helpers.run_scenario(...,
script="hammer_scenarios.py")``).

    python hammer_scenarios.py SCENARIO FMU_DIR '{"json": "keyword arguments"}'

The last stdout line is ``RESULT <json>``: the scenario's result and the collected log.
"""
from __future__ import annotations

import json
import sys

from fmu_driver import LOG, Slave


def _walk(slave: Slave, times: list) -> list:
    """Q after each doStep along ``times`` (times[0] is where the instance stands)."""
    out = []
    for a, b in zip(times[:-1], times[1:]):
        status = slave.call("doStep", a, b - a)
        if status:
            raise RuntimeError(f"doStep({a!r}, {b - a!r}) returned status {status}")
        out.append(slave.get("Q"))
    return out


def sequence(fmu_dir, params, times, stop=None):
    """Q in initialization mode (after the parameters are set), right after
    exitInitializationMode, and after each doStep along ``times`` (times[0]: the start time)."""
    slave = Slave(fmu_dir, "hammer")
    slave.call("setupExperiment", None, times[0], stop)
    slave.call("enterInitializationMode")
    for name, value in params.items():
        slave.set(name, value)
    in_init = slave.get("Q")
    status = slave.call("exitInitializationMode")
    q = [slave.get("Q")] + _walk(slave, times)
    slave.close()
    return {"status": status, "in_init": in_init, "q": q}


def ram_sequence(fmu_dir, params, times):
    """(Q, strikes, v_strike) right after exitInitializationMode and after each doStep along
    ``times`` (times[0]: the start time)."""
    slave = Slave(fmu_dir, "hammer")
    slave.call("setupExperiment", None, times[0], None)
    slave.call("enterInitializationMode")
    for name, value in params.items():
        slave.set(name, value)
    status = slave.call("exitInitializationMode")
    rows = [[slave.get(n) for n in ("Q", "strikes", "v_strike")]]
    for a, b in zip(times[:-1], times[1:]):
        if slave.call("doStep", a, b - a):
            raise RuntimeError(f"doStep({a!r}, {b - a!r}) refused")
        rows.append([slave.get(n) for n in ("Q", "strikes", "v_strike")])
    slave.close()
    return {"status": status, "rows": rows, "log": LOG}


def refusals(fmu_dir, kind, value=None):
    """One refused call of ``kind``: its status and log; then the instance's later calls, a
    reset, and a second instance stepping normally in the same process."""
    bad = Slave(fmu_dir, "bad")
    statuses = {}
    if kind == "parameters":                       # value = {name: value}
        statuses["refused"] = bad.start(value)
    elif kind == "before_init":
        statuses["refused"] = bad.call("doStep", 0.0, 0.01)
    else:
        statuses["exit_init"] = bad.start(stop=0.02 if kind == "past_stop" else None)
        statuses["first_step"] = bad.call("doStep", 0.0, 0.01)
        if kind == "fixed_after_init":
            statuses["refused"] = bad.set(value[0], value[1])
        elif kind == "set_output":
            statuses["refused"] = bad.set("Q", 1.0)
        elif kind == "wrong_time":
            statuses["refused"] = bad.call("doStep", 0.5, 0.01)
        elif kind == "zero_step":
            statuses["refused"] = bad.call("doStep", 0.01, 0.0)
        elif kind == "past_stop":
            statuses["to_stop"] = bad.call("doStep", 0.01, 0.01)
            statuses["refused"] = bad.call("doStep", 0.02, 0.01)
        elif kind == "unknown_get":
            statuses["refused"] = bad.call("getReal", [value])
        elif kind == "unknown_set":
            statuses["refused"] = bad.call("setReal", [value], [1.0])
        elif kind == "wrong_type":
            statuses["refused"] = bad.call("getReal", [bad.vars["count"].valueReference])
        elif kind == "bad_state":
            statuses["refused"] = bad.call("deSerializeFMUstate", b"not a Hammer state")
    log_at_refusal = list(LOG)
    statuses["later_get"] = bad.call("getReal", [0])
    statuses["later_terminate"] = bad.call("terminate")
    statuses["reset"] = bad.call("reset")              # and usable again
    statuses["after_reset"] = bad.start()
    after_reset = _walk(bad, [0.0, 0.01, 0.04, 0.05])
    bad.fmu.freeInstance()
    good = Slave(fmu_dir, "good")
    good.start({"count": 2})
    good_q = _walk(good, [0.0, 0.05, 0.2, 0.25])
    good.close()
    return {"statuses": statuses, "log_at_refusal": log_at_refusal, "after_reset": after_reset,
            "good_q": good_q}


def state(fmu_dir, params, times, save_index):
    """Save the state at times[save_index]; continue; restore twice; restore a serialized copy
    into a fresh default instance: the continuations, Q right after each restore, and the
    parameters the fresh instance has then."""
    a = Slave(fmu_dir, "a")
    a.start(params)
    _walk(a, times[:save_index + 1])
    snapshot = a.fmu.getFMUstate()
    rest = times[save_index:]
    runs = {"original": _walk(a, rest)}
    right_after = {}
    for name in ("restore1", "restore2"):
        a.fmu.setFMUstate(snapshot)
        right_after[name] = a.get("Q")
        runs[name] = _walk(a, rest)
    blob = a.fmu.serializeFMUstate(snapshot)
    b = Slave(fmu_dir, "fresh")
    b.start()
    b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
    right_after["fresh"] = b.get("Q")
    restored = {name: b.get(name) for name in params}
    runs["fresh"] = _walk(b, rest)
    refused_change = b.set("amplitude", 1.0)        # restored as initialized: fixed now
    a.fmu.freeFMUstate(snapshot)
    return {"runs": runs, "right_after": right_after, "restored": restored,
            "refused_change": refused_change}


if __name__ == "__main__":
    name, fmu_dir, kwargs = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
    result = globals()[name](fmu_dir, **kwargs)
    result["log"] = LOG
    sys.stdout.write("\nRESULT " + json.dumps(result) + "\n")
