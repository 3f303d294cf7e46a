"""pythonfmu 0.7's own behaviours (``pipeplug_fmu.pythonfmu07``, P1-P12), each in a process of
its own, driven through FMPy on an FMU folder whose linux64 binary is pythonfmu's (no loader).

    python pythonfmu07_scenarios.py SCENARIO RAW_FMU_DIR

The slave runs in this process's interpreter, so a scenario can look at it (``gc``) and replace
its methods to see what pythonfmu hands it. The last stdout line is ``RESULT <json>``; some
scenarios crash the process, which is the behaviour they show.
"""
from __future__ import annotations

import gc
import json
import os
import sys
from ctypes import byref, c_char, c_char_p, c_uint

from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2FMUstate
from fmu_driver import _CALLBACKS, LOG


def _instance(folder, logging=True, name="raw"):
    md = read_model_description(folder)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier="PipePlug",
                    instanceName=name)
    fmu.instantiate(callbacks=_CALLBACKS, loggingOn=logging)
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def _slave():
    """The Python slave object of the last instance made."""
    return [o for o in gc.get_objects() if type(o).__name__ == "PipePlug"][-1]


def _status(call, *args) -> int:
    try:
        call(*args)
    except FMICallException as exc:
        return int(exc.status)
    return 0


def _refused_init(fmu, vrs, params=None) -> int:
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for name, value in (params or {"tau1": -1.0}).items():
        if isinstance(value, str):
            fmu.setString([vrs[name]], [value])
        else:
            fmu.setReal([vrs[name]], [value])
    return _status(fmu.exitInitializationMode)


def exception_is_fatal(folder):
    """P1: a refusal raised by the slave: status and line as pythonfmu gives them."""
    fmu, vrs = _instance(folder)
    return {"status": _refused_init(fmu, vrs), "log": list(LOG)}


def references_released(folder):
    """P2: reference counts of the instance, its log queue and its class across a refusal
    (the slave adds one to each before raising)."""
    fmu, vrs = _instance(folder)
    slave = _slave()
    objects = (slave, slave.log_queue, type(slave))
    gc.collect()
    before = [sys.getrefcount(o) for o in objects]
    status = _refused_init(fmu, vrs)
    gc.collect()
    after = [sys.getrefcount(o) for o in objects]         # counted the same way as before
    return {"status": status, "change": [a - b for a, b in zip(after, before)]}


def logging_off(folder):
    """P3: a refusal with loggingOn = fmi2False, and with logging on but one category."""
    fmu, vrs = _instance(folder, logging=False)
    off = {"status": _refused_init(fmu, vrs), "log": list(LOG)}
    del LOG[:]
    fmu2, vrs = _instance(folder, name="categories")
    fmu2.setDebugLogging(True, ["logStatusWarning"])
    return {"off": off, "categories": {"status": _refused_init(fmu2, vrs), "log": list(LOG)}}


def message_is_a_format(folder):
    """P4: a refusal whose text holds "%" (escaped by the slave as "%%")."""
    fmu, vrs = _instance(folder)
    status = _refused_init(fmu, vrs, {"solver": "100%"})
    return {"status": status, "log": list(LOG)}


def queued_while_raising(folder):
    """P5: a line queued by the slave in a call that then raises (a refusal, so that the
    instance outlives it, P2): whether and when pythonfmu gives it to the host."""
    fmu, _ = _instance(folder)
    slave = _slave()
    workarounds = sys.modules[type(slave).__module__.rsplit(".", 1)[0] + ".pythonfmu07"]

    def log_then_raise():
        slave.log("queued line")
        workarounds.outlive_the_exception(slave)
        raise workarounds.Refusal("PipePlug", "refused")
    slave.exit_initialization_mode = log_then_raise
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    return {"status": _status(fmu.exitInitializationMode), "log": list(LOG)}


def value_references_as_int(folder):
    """P6: the value references the slave receives for 2**32 - 1 and 2**31."""
    fmu, _ = _instance(folder)
    slave, seen = _slave(), []
    slave.get_real = lambda vrs: seen.extend(vrs) or [0.0] * len(vrs)
    fmu.getReal([2 ** 32 - 1, 2 ** 31])
    return {"seen": seen}


def strings(folder):
    """P7: what the slave receives for a NULL string; then bytes that are not UTF-8 (the
    status, if the process lives)."""
    fmu, vrs = _instance(folder)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    slave, seen = _slave(), []
    original = slave.set_string
    slave.set_string = lambda refs, values: seen.extend(values)
    fmu.fmi2SetString(fmu.component, (c_uint * 1)(vrs["solver"]), 1, (c_char_p * 1)(None))
    slave.set_string = original
    print("NULL", json.dumps(seen), flush=True)
    status = _status(fmu.fmi2SetString, fmu.component, (c_uint * 1)(vrs["solver"]), 1,
                     (c_char_p * 1)(b"\xff\xfe"))
    print("STATUS", status, flush=True)
    return {"null": seen, "status": status}


def resources_elsewhere(folder):
    """P8: fmi2Instantiate with the URI of a folder that holds no slave (the process dies)."""
    md = read_model_description(folder)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier="PipePlug",
                    instanceName="elsewhere")
    print("INSTANTIATING", flush=True)
    fmu.fmi2Instantiate(b"elsewhere", 1, md.guid.encode(), b"file:///tmp", byref(_CALLBACKS),
                        0, 1)
    return {"instantiated": True}


def null_name(folder):
    """P8: fmi2Instantiate with a NULL instance name (the process dies)."""
    md = read_model_description(folder)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier="PipePlug",
                    instanceName="null")
    uri = (os.path.abspath(folder) + "/resources").encode()
    print("INSTANTIATING", flush=True)
    fmu.fmi2Instantiate(None, 1, md.guid.encode(), b"file://" + uri, byref(_CALLBACKS), 0, 1)
    return {"instantiated": True}


def states(folder):
    """P9: the object the slave gets back when its state is set; fmi2SetFMUstate(NULL);
    fmi2SerializeFMUstate into 10 bytes."""
    fmu, vrs = _instance(folder)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    slave, given = _slave(), []
    original = slave._set_fmu_state
    state = fmu.getFMUstate()
    slave._set_fmu_state = given.append
    fmu.setFMUstate(state)
    slave._set_fmu_state = original
    same = len(given) == 1 and id(given[0]) == state.value     # the very object (CPython)
    full = fmu.serializeFMUstate(state)
    small = (c_char * 10)()
    status = _status(fmu.fmi2SerializeFMUstate, fmu.component, state, small, 10)
    null = _status(fmu.fmi2SetFMUstate, fmu.component, fmi2FMUstate())
    return {"same_object": same, "small_status": status, "small": bytes(small).hex(),
            "full_start": bytes(full[:10]).hex(), "null_status": null}


def class_method_raising(folder):
    """P10: the instance's reference count when the class's deserialization raises."""
    fmu, _ = _instance(folder)
    slave = _slave()
    gc.collect()
    before = sys.getrefcount(slave)

    def broken(cls, data):
        raise ValueError("broken")
    type(slave)._fmu_state_from_bytes = classmethod(broken)
    state = fmi2FMUstate()
    status = _status(fmu.fmi2DeSerializeFMUstate, fmu.component, (c_char * 4)(), 4,
                     byref(state))
    gc.collect()
    change = sys.getrefcount(slave) - before
    print("\nRESULT " + json.dumps({"status": status, "change": change, "log": list(LOG)}),
          flush=True)
    os._exit(0)                # the instance was released: nothing more may touch it


def script_namespace(folder):
    """P11: the reference count of the slave script's namespace over instantiations."""
    fmu, _ = _instance(folder)
    tag = type(_slave()).__module__.split(".")[0].removeprefix("pipeplug_fmu_")
    module = sys.modules[f"pipeplug_slave_{tag}"]
    counts = []
    for k in range(4):
        other, _ = _instance(folder, name=f"again{k}")
        other.freeInstance()
        gc.collect()
        counts.append(sys.getrefcount(module.__dict__))
    return {"counts": counts}


def no_call_order(folder):
    """P12: fmi2SetupExperiment after initialization reaches the slave."""
    fmu, _ = _instance(folder)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    slave, seen = _slave(), []
    slave.setup_experiment = lambda *args: seen.append(list(args))
    status = _status(fmu.setupExperiment, None, 5.0)
    return {"status": status, "seen": seen}


def main() -> None:
    name, folder = sys.argv[1], sys.argv[2]
    result = globals()[name](folder)
    sys.stdout.write("\nRESULT " + json.dumps(result) + "\n")
    sys.stdout.flush()
    os._exit(0)                # pythonfmu's binary alone double-frees at exit (the exit guard)


if __name__ == "__main__":
    main()
