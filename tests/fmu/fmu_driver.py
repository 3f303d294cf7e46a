"""Drive PipePlug.fmu (or Hammer.fmu) through FMPy's raw FMI 2.0 API (used by
``fmu_scenarios.py`` and ``hammer_scenarios.py``).

Loaded only inside the scenario processes. It never imports the ``pipeplug`` core: the FMU must
bring its own copy. Log messages of every instance are collected in :data:`LOG`, after FMPy's C
proxy has printf-formatted them, as a C host would.
"""
from __future__ import annotations

from ctypes import byref

from fmpy import calloc, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.logging import addLoggerProxy

REAL_OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction")
MODES = ("pipe_mode", "plug_mode")
LOG: list[dict] = []            # every log message of every instance, in order


def _log_message(env, instance, status, category, message):
    LOG.append({"instance": instance.decode(), "status": status,
                "category": category.decode() if category else None,
                "message": message.decode("utf-8", "replace")})


_CALLBACKS = fmi2CallbackFunctions()
_CALLBACKS.logger = fmi2CallbackLoggerTYPE(_log_message)
_CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
_CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(_CALLBACKS))   # printf-formats messages in C, as real hosts do


class Slave:
    """One instance of the FMU, with status-returning calls instead of exceptions."""

    def __init__(self, fmu_dir: str, name: str):
        md = read_model_description(fmu_dir)
        self.vars = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmu_dir,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=_CALLBACKS, loggingOn=True)

    def call(self, method: str, *args) -> int:
        """Call an FMU2Slave method; return the FMI status (0 ok, 2 discard, 3 error, 4 fatal)."""
        try:
            getattr(self.fmu, method)(*args)
        except FMICallException as exc:
            return exc.status
        return 0

    def set(self, name: str, value) -> int:
        """Set one variable by name, with the setter of its type."""
        v = self.vars[name]
        return self.call("set" + v.type, [v.valueReference], [value])

    def start(self, params: dict | None = None, start: float = 0.0, stop=None) -> int:
        """setupExperiment, parameters, initialization; the status of exitInitializationMode."""
        self.call("setupExperiment", None, start, stop)
        self.call("enterInitializationMode")
        for name, value in (params or {}).items():
            self.set(name, value)
        return self.call("exitInitializationMode")

    def step(self, t: float, h: float, q: float) -> int:
        """setReal(Q), doStep(t, h); the status of doStep."""
        self.set("Q", q)
        return self.call("doStep", t, h)

    def outputs(self) -> dict:
        """All outputs (Real and Integer) by name."""
        reals = self.fmu.getReal([self.vars[n].valueReference for n in REAL_OUTPUTS])
        modes = self.fmu.getInteger([self.vars[n].valueReference for n in MODES])
        return dict(zip(REAL_OUTPUTS + MODES, list(reals) + list(modes)))

    def get(self, name: str):
        """Get one variable by name (Strings decoded)."""
        v = self.vars[name]
        value = getattr(self.fmu, "get" + v.type)([v.valueReference])[0]
        return value.decode() if isinstance(value, bytes) else value

    def close(self) -> None:
        self.call("terminate")
        self.fmu.freeInstance()


def pulse(t: float, q0: float, t0: float) -> float:
    """Rectangular pulse [N]: ``q0`` for 0 <= t < t0, then 0."""
    return q0 if t < t0 else 0.0


def run_grid(slave: Slave, times: list, q0: float, t0: float) -> list:
    """Step through ``times`` (times[0] = start) under the pulse; outputs after each step."""
    rows = []
    for a, b in zip(times[:-1], times[1:]):
        status = slave.step(a, b - a, pulse(a, q0, t0))
        if status:
            raise RuntimeError(f"doStep({a}, {b - a}) returned status {status}")
        rows.append(slave.outputs())
    return rows
