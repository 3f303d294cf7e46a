"""A long-lived host process for the FMI stateful test: drives PipePlug through FMPy's raw
FMI 2.0 API on commands read from stdin, one JSON object a line; answers on stdout.

pythonfmu runs every instance in this process's interpreter, so the test process never loads
the FMU itself: a host crash ends this process, and the test sees its pipe close.

Commands (``op``): ``instantiate`` (name) -> id; ``call`` (id, method, args) -> status and
value; ``get_state`` (id) -> state; ``set_state``/``free_state`` (id, state);
``serialize`` (id, state) -> hex; ``deserialize`` (id, hex) -> state; ``free`` (id);
``quit``. Every answer carries ``status`` (FMI status, 0 = OK) and ``log``: the messages the
FMU logged during the command, after FMPy's C proxy has printf-formatted them (as C hosts do).
Answers are lines prefixed with ``@@`` (anything else on stdout is not ours).
"""
from __future__ import annotations

import json
import sys
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

LOG: list = []


def _logger(env, instance, status, category, message):
    LOG.append([instance.decode() if instance else None, status,
                message.decode("utf-8", "replace") if message else "",
                category.decode() if category else None])


CALLBACKS = fmi2CallbackFunctions()
CALLBACKS.logger = fmi2CallbackLoggerTYPE(_logger)
CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(CALLBACKS))

ALLOWED = {"setupExperiment", "enterInitializationMode", "exitInitializationMode", "terminate",
           "reset", "doStep", "getReal", "getInteger", "getBoolean", "getString", "setReal",
           "setInteger", "setBoolean", "setString"}


class Host:
    """The instances and FMU states of this process, by integer id."""

    def __init__(self, fmu_dir: str):
        self.fmu_dir = fmu_dir
        self.md = read_model_description(fmu_dir)
        self.instances, self.states, self.next_id = {}, {}, 1

    def _new_id(self) -> int:
        self.next_id += 1
        return self.next_id

    def instantiate(self, name):
        fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.fmu_dir,
                        modelIdentifier="PipePlug", instanceName=name)
        fmu.instantiate(callbacks=CALLBACKS, loggingOn=True)
        ident = self._new_id()
        self.instances[ident] = fmu
        return ident

    def call(self, id, method, args):
        if method not in ALLOWED:
            raise ValueError(method)
        value = getattr(self.instances[id], method)(*args)
        if isinstance(value, (list, tuple)):
            value = [v.decode() if isinstance(v, bytes) else v for v in value]
            value = [bool(v) if method == "getBoolean" else v for v in value]
        return value if method.startswith("get") else None

    def get_state(self, id):
        ident = self._new_id()
        self.states[ident] = self.instances[id].getFMUstate()
        return ident

    def set_state(self, id, state):
        self.instances[id].setFMUstate(self.states[state])

    def free_state(self, id, state):
        self.instances[id].freeFMUstate(self.states.pop(state))

    def serialize(self, id, state):
        return self.instances[id].serializeFMUstate(self.states[state]).hex()

    def deserialize(self, id, hex):
        ident = self._new_id()
        self.states[ident] = self.instances[id].deSerializeFMUstate(bytes.fromhex(hex))
        return ident

    def free(self, id):
        self.instances.pop(id).freeInstance()


def main() -> None:
    host = Host(sys.argv[1])
    for line in sys.stdin:
        command = json.loads(line)
        op = command.pop("op")
        if op == "quit":
            break
        del LOG[:]
        answer = {"status": 0, "value": None}
        try:
            answer["value"] = getattr(host, op)(**command)
        except FMICallException as exc:
            answer["status"] = int(exc.status)
        answer["log"] = list(LOG)
        sys.stdout.write("@@" + json.dumps(answer) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
