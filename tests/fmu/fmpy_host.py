"""The commands of the plain C host (``fmi_host.c``) on FMPy's low-level API, in a Python host.

    python fmpy_host.py FMU_DIR < commands

Same protocol, same answers (see ``fmi_host.c``): ``@L`` lines for log messages (after FMPy's C
logger proxy has printf-formatted them, as C hosts do), ``@@ STATUS KIND VALUES`` answers.
Binaries are FMU folders here: ``open DIR`` (hex) loads another FMU. The FMU runs in this
process's interpreter, so :class:`~fmi_c_host.CHost` drives this host as it drives the C one.
"""
from __future__ import annotations

import sys
from ctypes import byref, c_char, c_char_p, c_double, c_int, c_size_t, c_uint

from fmpy import calloc, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2FMUstate,
)
from fmpy.logging import addLoggerProxy


def _hex(data: bytes | None) -> str:
    return "~" if data is None else data.hex() or "-"


def _unhex(word: str) -> bytes | None:
    return None if word == "~" else b"" if word == "-" else bytes.fromhex(word)


def _logger(env, instance, status, category, message):
    print("@L", _hex(instance or b""), status, "NULL" if category is None else _hex(category),
          _hex(message or b""), flush=True)


CALLBACKS = fmi2CallbackFunctions()
CALLBACKS.logger = fmi2CallbackLoggerTYPE(_logger)
CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(CALLBACKS))          # printf-formats messages in C, as real hosts do

_ARRAY = {"R": c_double, "I": c_int, "B": c_int, "S": c_char_p}


def _status(call, *args) -> int:
    """The FMI status of a low-level call (FMPy raises for statuses above fmi2Warning)."""
    try:
        call(*args)
    except FMICallException as exc:
        return int(exc.status)
    return 0


class Host:
    """The binaries (FMU folders), instances and FMU states of this process."""

    def __init__(self, fmu_dir: str):
        self.fmus = [self._load(fmu_dir)]
        self.instances: dict[int, tuple] = {}            # id -> (FMU2Slave, component)
        self.states: dict[int, fmi2FMUstate] = {}
        self.n_instances = self.n_states = 0

    @staticmethod
    def _load(fmu_dir: str) -> FMU2Slave:
        md = read_model_description(fmu_dir)
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmu_dir,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="host")
        return fmu

    def run(self, words: list[str]) -> str:
        op = words[0]
        if op in ("setenv", "guard", "pulse"):
            return "@@ 4 unsupported"
        return getattr(self, "op_" + op)(*words[1:])

    def _of(self, ident: str) -> tuple:
        return self.instances.get(int(ident), (self.fmus[0], None))

    # Instances --------------------------------------------------------------------------------
    def op_open(self, folder: str) -> str:
        self.fmus.append(self._load(_unhex(folder).decode()))
        return f"@@ 0 int {len(self.fmus) - 1}"

    def op_instantiate(self, name, guid, uri, logging, kind="1", which="0") -> str:
        fmu = self.fmus[int(which)]
        component = fmu.fmi2Instantiate(_unhex(name), int(kind), _unhex(guid), _unhex(uri),
                                        byref(CALLBACKS), 0, int(logging))
        if not component:
            return "@@ 0 null"
        self.n_instances += 1
        self.instances[self.n_instances] = (fmu, component)
        return f"@@ 0 int {self.n_instances}"

    def op_free(self, ident, keep=None) -> str:
        # "keep": the slot keeps the freed instance (a host's late calls through it)
        fmu, c = self.instances[int(ident)] if keep == "keep" else self.instances.pop(int(ident))
        fmu.fmi2FreeInstance(c)
        return "@@ 0 none"

    # Calls -------------------------------------------------------------------------------------
    def op_call(self, ident, method, *args) -> str:
        fmu, c = self._of(ident)
        if method == "setupExperiment":
            tol, start, stop = args
            return self._answer(_status(fmu.fmi2SetupExperiment, c, tol != "none",
                                        0.0 if tol == "none" else float(tol), float(start),
                                        stop != "none", 0.0 if stop == "none" else float(stop)))
        if method == "doStep":
            return self._answer(_status(fmu.fmi2DoStep, c, float(args[0]), float(args[1]), 1))
        if method.startswith(("get", "set")):
            return self._values(fmu, c, method, args)
        name = "fmi2" + method[0].upper() + method[1:]
        return self._answer(_status(getattr(fmu, name), c))

    def _values(self, fmu, c, method, args) -> str:
        kind, n = method[3], int(args[0])
        vrs = (c_uint * max(n, 1))(*map(int, args[1:1 + n]))
        values = (_ARRAY[kind] * max(n, 1))()
        if method.startswith("set"):
            for i, word in enumerate(args[1 + n:1 + 2 * n]):
                values[i] = (float(word) if kind == "R" else _unhex(word) if kind == "S"
                             else int(word))
        status = _status(getattr(fmu, "fmi2" + method[0].upper() + method[1:]), c, vrs, n,
                         values)
        if method.startswith("set") or status > 1:
            return self._answer(status)
        shown = {"R": lambda v: repr(float(v)), "I": str, "B": lambda v: str(int(v)),
                 "S": _hex}[kind]
        name = {"R": "reals", "I": "ints", "B": "bools", "S": "strs"}[kind]
        return f"@@ {status} {name} {n} " + " ".join(shown(values[i]) for i in range(n))

    def op_null(self, ident, method, n) -> str:
        fmu, c = self._of(ident)
        name, n = "fmi2" + method[0].upper() + method[1:], int(n)
        call = getattr(fmu, name)
        if "Status" in method:
            return self._answer(_status(call, c, 2, None))
        if method in ("getFMUstate", "freeFMUstate"):
            return self._answer(_status(call, c, None))
        if method == "serializedFMUstateSize":
            return self._answer(_status(call, c, None, None))
        if method == "deSerializeFMUstate":
            return self._answer(_status(call, c, None, n, None))
        if method == "setDebugLogging":
            return self._answer(_status(call, c, 1, n, None))
        return self._answer(_status(call, c, None, n, None))

    def op_debug(self, ident, on, n, *categories) -> str:
        fmu, c = self._of(ident)
        array = (c_char_p * max(int(n), 1))(*[_unhex(w) for w in categories])
        return self._answer(_status(fmu.fmi2SetDebugLogging, c, int(on), int(n), array))

    # FMU states ---------------------------------------------------------------------------------
    def _new_state(self, state) -> int:
        self.n_states += 1
        self.states[self.n_states] = state
        return self.n_states

    def op_get_state(self, ident) -> str:
        fmu, c = self._of(ident)
        state = fmi2FMUstate()
        status = _status(fmu.fmi2GetFMUstate, c, byref(state))
        return f"@@ {status} int {self._new_state(state)}"

    def op_set_state(self, ident, s) -> str:
        fmu, c = self._of(ident)
        return self._answer(_status(fmu.fmi2SetFMUstate, c, self.states.get(int(s),
                                                                            fmi2FMUstate())))

    def op_free_state(self, ident, s, keep=None) -> str:
        fmu, c = self._of(ident)
        state = self.states.get(int(s), fmi2FMUstate())
        kept = fmi2FMUstate(state.value)
        status = _status(fmu.fmi2FreeFMUstate, c, byref(state))
        self.states[int(s)] = kept if keep == "keep" else fmi2FMUstate()
        return self._answer(status)

    def op_serialize(self, ident, s, size=None) -> str:
        fmu, c = self._of(ident)
        state, real = self.states.get(int(s), fmi2FMUstate()), c_size_t()
        status = _status(fmu.fmi2SerializedFMUstateSize, c, state, byref(real))
        n = real.value if size is None else int(size)
        buffer = (c_char * (max(n, real.value) + 1))()
        if status == 0:
            status = _status(fmu.fmi2SerializeFMUstate, c, state, buffer, n)
        return f"@@ {status} hex {_hex(bytes(buffer)[:n])}"

    def op_deserialize(self, ident, data) -> str:
        fmu, c = self._of(ident)
        raw = _unhex(data) or b""
        state = fmi2FMUstate()
        buffer = (c_char * max(len(raw), 1)).from_buffer_copy(raw or b"\0")
        status = _status(fmu.fmi2DeSerializeFMUstate, c, buffer, len(raw), byref(state))
        return f"@@ {status} int {self._new_state(state)}"

    @staticmethod
    def _answer(status: int) -> str:
        return f"@@ {status} none"


def main() -> None:
    host = Host(sys.argv[1])
    for line in sys.stdin:
        words = line.split()
        if not words:
            continue
        if words[0] == "quit":
            break
        print(host.run(words), flush=True)


if __name__ == "__main__":
    main()
