"""The probes of ``probes.py`` for the FMI 3.0 PipePlug.fmu, where they map, and FMI 3.0's own.

:class:`Session3` speaks FMI 3.0 (``fmi3_host.c``, in a plain C process or inside a Python one,
``python_host3.py``) under the method names of the FMI 2.0 :class:`~probes.Session`, so that the
FMI 2.0 probe functions run unchanged: it translates the FMI 2.0 calls they make (getReal ->
getFloat64 with its nValues, fmi2's enterInitializationMode after setupExperiment ->
fmi3EnterInitializationMode with the start and stop time, ...). :data:`PROBES3` names each
probe, what its one line must say and, for probes of FMI 2.0, which one it repeats.
"""
from __future__ import annotations

import sys
from pathlib import Path

from fmi_c_host import CHost, hexed, host_env
from probes import (
    DISCARD,
    ERROR,
    LIMITED,
    PROBES,
    WRONG_TOKEN,
    Expected,
    HostSession,
    instantiate,
    null_or_hexed,
    out_of_order,
    parameters,
    raw,
)

HERE = Path(__file__).resolve().parent
_TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
_STATE_CALLS = {"getFMUstate": "getFMUState", "deSerializeFMUstate": "deserializeFMUState",
                "serializedFMUstateSize": "serializedFMUStateSize"}


def token_of(fmu_dir: Path) -> str:
    import xml.etree.ElementTree as ET

    return ET.parse(Path(fmu_dir) / "modelDescription.xml").getroot().get("instantiationToken")


def resource_path(fmu_dir: Path) -> str:
    return str(Path(fmu_dir) / "resources") + "/"


class Session3(HostSession):
    """One host process with the FMI 3.0 PipePlug.fmu (and Hammer.fmu) loaded; ``host`` "c"
    (no Python in the process until the FMU brings one) or "python" (the FMU uses the host's
    interpreter)."""

    def __init__(self, host: str, logging: bool, fmu_dir: Path, hammer_dir: Path,
                 c3_host: Path, c3_library: Path, env: dict | None = None):
        binary = fmu_dir / "binaries" / "x86_64-linux" / "PipePlug.so"
        if host == "c":
            env = host_env(**{"PIPEPLUG_PYTHON": sys.executable, **(env or {})})
            process = CHost(c3_host, binary, env)
        else:
            process = CHost([sys.executable, str(HERE / "python_host3.py"), str(c3_library)],
                            binary, None)
        super().__init__(host, logging, fmu_dir, hammer_dir, process)

    # The FMI 2.0 words of probes.py, in FMI 3.0 ------------------------------------------------
    def __call__(self, *words) -> dict:
        words = [str(w) for w in words]
        if words[0] == "call":
            words = words[:2] + _translated(words[2], words[3:])
        elif words[0] == "null":
            words[2] = _null_method(words[2])
        return self.host(*words)

    def new(self, name="probe", uri=None, kind=1, event_mode=0, fmu_dir=None,
            lib=None, token=None) -> dict:
        """fmi3InstantiateCoSimulation of PipePlug, or of the FMU in ``fmu_dir`` from the host's
        binary ``lib`` (``name`` or ``uri`` None: NULL; ``uri`` "usual": the FMU's resources;
        ``kind`` 0, FMI 2.0's model exchange: eventModeUsed true; ``token``: the
        instantiationToken given, by default the FMU's)."""
        fmu_dir = fmu_dir or self.fmu_dir
        path = resource_path(fmu_dir) if uri == "usual" else uri
        return self.host("instantiate", null_or_hexed(name), hexed(token or token_of(fmu_dir)),
                         null_or_hexed(path), int(self.logging), int(event_mode or kind == 0),
                         *([] if lib is None else [lib]))

    @staticmethod
    def _binary_word(fmu_dir: Path, identifier: str) -> str:
        """What the host opens for an FMU: its x86_64-linux binary."""
        return str(fmu_dir / "binaries" / "x86_64-linux" / f"{identifier}.so")

    @staticmethod
    def _set_words(vr: int, word: str) -> list:
        """fmi3Set<type>'s words: nValueReferences, the value reference, nValues, the value."""
        return [1, vr, 1, word]

    def enter(self, ident, stop=None, start=0.0) -> None:
        """fmi3EnterInitializationMode with the start and stop time (checked)."""
        self.ok(ident, "enterInitializationMode", repr(start),
                "none" if stop is None else repr(stop))

    def step(self, ident, t, h, q=23e3) -> dict:
        """FMI 2.0's answer to a step: fmi3DoStep's flags left out."""
        answer = super().step(ident, t, h, q)
        return {**answer, "kind": "none", "words": []} if answer["kind"] == "step" else answer


def _translated(method: str, args: list) -> list:
    """An FMI 2.0 call of probes.py as the FMI 3.0 host's words."""
    kind = method[3:]
    if method[:3] in ("get", "set") and kind in _TYPES:
        n = int(args[0])
        vrs, values = args[1:1 + n], args[1 + n:]
        if method.startswith("get"):
            return [f"get{_TYPES[kind]}", n, n, *vrs]
        return [f"set{_TYPES[kind]}", n, *vrs, len(values), *values]
    if method == "enterInitializationMode" and not args:
        return [method, "0.0", "none"]
    return [method, *args]


def _null_method(method: str) -> str:
    kind = method[3:]
    if method[:3] in ("get", "set") and kind in _TYPES:
        return method[:3] + _TYPES[kind]
    return _STATE_CALLS.get(method, method)


def _fmi3(texts: tuple) -> tuple:
    """FMI 2.0's words in a probe's expected texts, as FMI 3.0 says them."""
    return tuple(t.replace("fmi2", "fmi3").replace("FMUstate", "FMUState")
                 .replace("DeSerialize", "Deserialize").replace("Integer", "Int32")
                 for t in texts)


#: FMI 2.0 probes that do not map: their FMI 3.0 counterparts are below.
NOT_MAPPED = {"setupExperiment after init", "setupExperiment in init", "NaN startTime",
              "stopTime before startTime", "terminate before init", "model exchange",
              "resources: temp folder", "resources: no folder", "resources: malformed escape",
              "resources: too long", "resources: another host", "NULL arrays get",
              "NULL arrays set", "NULL arrays strings", "NULL status value",
              "python never exits", "python prints without end", "percent in a string",
              "getReal before init", "GUID of another FMU"}


def _from_fmi2() -> dict:
    out = {}
    for name, (probe, expected) in PROBES.items():
        if name in NOT_MAPPED:
            continue
        out[name] = (probe, Expected(expected.status, _fmi3(expected.texts), ("c", "python"),
                                     expected.env, expected.enabled, expected.then_q,
                                     expected.then_set))
    return out


def _enter_again(s, ident):
    s.enter(ident)


def _configuring(s, ident):
    s.ok(ident, "enterConfigurationMode")


def _run(s, ident):
    assert s.start(ident)["status"] == 0


def _running_then(method, *args):
    return out_of_order(_run, method, *args)


def _nvalues(method, n_values, names):
    """A get or set of the variables ``names`` with ``n_values`` values."""
    def probe(s: Session3):
        ident = s.running()
        vrs = [s.vr(n) for n in names]
        if method.startswith("get"):
            return s.host("call", ident, method, n_values, len(vrs), *vrs), ident
        return s.host("call", ident, method, len(vrs), *vrs, n_values,
                      *(["1.0"] * n_values)), ident
    return probe


def _state_of_other_points(s: Session3):
    """fmi3SetFMUState of a state of 11 profile points into an instance configured for 50: the
    host sized its arrays by 50, so the state is refused (it would change them)."""
    saved = s("get_state", s.running())["words"][0]
    ident = s.instance()
    s.ok(ident, "enterConfigurationMode")
    answer = s.set(ident, "profile_points", 50)
    assert answer["status"] == 0 and answer["log"] == [], answer
    s.ok(ident, "exitConfigurationMode")
    assert s.start(ident)["status"] == 0
    return s("set_state", ident, saved), ident


#: name -> (probe, expected): FMI 2.0's that map, then FMI 3.0's own.
PROBES3 = {
    **_from_fmi2(),
    "percent in a string": (parameters({"solver": "%s%n%d"}),
                            Expected(ERROR, ("solver = '%s%n%d' is not allowed",),
                                     ("c", "python"))),
    # fmi3EnterInitializationMode carries the experiment (FMI 2.0: fmi2SetupExperiment).
    "enterInit twice with times": (out_of_order(_enter_again, "enterInitializationMode", "-5.0",
                                                "none"),
                                   Expected(ERROR, ("fmi3EnterInitializationMode",
                                                    "initialization mode"), ("c", "python"))),
    "NaN startTime": (out_of_order(lambda s, i: None, "enterInitializationMode", "nan", "none"),
                      Expected(ERROR, ("startTime = nan",), ("c", "python"))),
    "stopTime before startTime": (out_of_order(lambda s, i: None, "enterInitializationMode",
                                               "2.0", "1.0"),
                                  Expected(ERROR, ("stopTime = 1.0", "startTime = 2.0"),
                                           ("c", "python"))),
    "terminate before init": (out_of_order(lambda s, i: None, "terminate"),
                              Expected(ERROR, ("fmi3Terminate", "instantiated"),
                                       ("c", "python"))),
    "token of another FMU": (instantiate(uri="usual", token=WRONG_TOKEN),
                             Expected("null", (f"instantiationToken = '{WRONG_TOKEN}'",
                                               "instantiationToken of this"), ("c", "python"))),
    # The FMI 3.0 state machine beyond the slave's call sequence.
    "enterConfigurationMode after init": (_running_then("enterConfigurationMode"),
                                          Expected(ERROR, ("fmi3EnterConfigurationMode",
                                                           "instantiated only"),
                                                   ("c", "python"))),
    "exitConfigurationMode unentered": (out_of_order(lambda s, i: None, "exitConfigurationMode"),
                                        Expected(ERROR, ("fmi3ExitConfigurationMode",
                                                         "configuration mode only"),
                                                 ("c", "python"))),
    "enterInit in configuration mode": (out_of_order(_configuring, "enterInitializationMode",
                                                     "0.0", "none"),
                                        Expected(ERROR, ("fmi3EnterInitializationMode",
                                                         "configuration mode"),
                                                 ("c", "python"))),
    "enterEventMode": (_running_then("enterEventMode"),
                       Expected(ERROR, ("fmi3EnterEventMode", "without event mode"),
                                ("c", "python"))),
    "enterStepMode": (_running_then("enterStepMode"),
                      Expected(ERROR, ("fmi3EnterStepMode",), ("c", "python"))),
    "state of other profile points": (_state_of_other_points,
                                      Expected(ERROR, ("FMUState profile_points = 11", "50",
                                                       "structural"), ("c", "python"))),
    # Counts of values, types without variables.
    "more values than the variables hold": (_nvalues("getFloat64", 20, ["v_pipe_profile"]),
                                            Expected(ERROR, ("nValues = 20", "allowed: 11"),
                                                     ("c", "python"))),
    "fewer values than the variables hold": (_nvalues("getFloat64", 2, ["v_pipe", "Q", "u_pipe"]),
                                             Expected(ERROR, ("nValues = 2", "allowed: 3"),
                                                      ("c", "python"))),
    "more values set": (_nvalues("setFloat64", 2, ["Q"]),
                        Expected(ERROR, ("nValues = 2", "fmi3SetFloat64", "allowed: 1"),
                                 ("c", "python"))),
    "Float32 of a Float64": (raw("call", "{I}", "getFloat32", 1, 1, 0),
                             Expected(ERROR, ("valueReference = 0", "Float32"),
                                      ("c", "python"))),
    "Int64 set": (raw("call", "{I}", "setInt64", 1, 0, 1, 5),
                  Expected(ERROR, ("valueReference = 0", "Int64"), ("c", "python"))),
    # fmi3InstantiateCoSimulation: NULL after one line.
    "NULL instance name": (instantiate(name=None, uri="usual"),
                           Expected("null", ("instanceName = NULL",), ("c", "python"))),
    "instance name not UTF-8": (instantiate(name=b"\xff\xfe", uri="usual"),
                                Expected("null", ("instanceName = '\\xff\\xfe'", "UTF-8"),
                                         ("c", "python"))),
    "event mode used": (instantiate(uri="usual", kind=0),
                        Expected("null", ("eventModeUsed = true", "no event mode"),
                                 ("c", "python"))),
    "resources: temp folder": (instantiate(uri="/tmp/"),
                               Expected("null", ("resourcePath = '/tmp/'", "resources"),
                                        ("c", "python"))),
    "resources: no folder": (instantiate(uri="/nonexistent/dir/"),
                             Expected("null", ("/nonexistent/dir/",), ("c", "python"))),
    "resources: too long": (instantiate(uri="/" + "a" * 5000),
                            Expected("null", ("(5001 bytes)", "4096"), ("c", "python"))),
    "resources: another host": (instantiate(uri="file://elsewhere/tmp"),
                                Expected("null", ("this machine",), ("c", "python"))),
    # NULL arrays and pointers.
    "NULL arrays get": (raw("null", "{I}", "getFloat64", 3),
                        Expected(ERROR, ("valueReferences = NULL", "3 elements"),
                                 ("c", "python"))),
    "NULL arrays set": (raw("null", "{I}", "setFloat64", 2),
                        Expected(ERROR, ("valueReferences = NULL",), ("c", "python"))),
    "NULL arrays strings": (raw("null", "{I}", "getString", 1),
                            Expected(ERROR, ("NULL",), ("c", "python"))),
    "NULL doStep results": (raw("null", "{I}", "doStep", 0),
                            Expected(ERROR, ("eventHandlingNeeded = NULL",), ("c", "python"))),
    # A Python that never answers (the C host; a Python host brings its own).
    "python never exits": (PROBES["python never exits"][0], Expected(
        "null", ("did not answer within 2 s",), ("c",),
        {"PIPEPLUG_PYTHON": "#!/bin/sh\nexec sleep 1000\n", "PIPEPLUG_PYTHON_TIMEOUT": "2"})),
    "python prints without end": (PROBES["python prints without end"][0], Expected(
        "null", ("printed more than",), ("c",), {"PIPEPLUG_PYTHON": "#!/bin/sh\nexec yes\n"})),
}

__all__ = ["PROBES3", "Session3", "DISCARD", "ERROR", "LIMITED"]
