"""The calls hosts really make, as probes of PipePlug.fmu: bad values, calls out of order, bad
pointers and strings, bad resource locations and FMU states, a Python that never answers.

A probe is a function of a :class:`Session` (one host process: the plain C host ``fmi_host.c``
or FMPy's low-level API in ``fmpy_host.py``, logging on or off); it makes its refused call last
and returns ``(answer, instance)``: the answer of that call and the instance it refused
(None when fmi2Instantiate returned NULL). :data:`PROBES` says what the contract expects of each.
:class:`HostSession` holds what the sessions of both FMI versions share (``probes3.py``).
"""
from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

from fmi_c_host import CHost, guid_of, hexed, host_env, resource_uri

HERE = Path(__file__).resolve().parent
ERROR, DISCARD = 3, 2


def null_or_hexed(x) -> str:
    """``x`` as a host word: "~" (NULL) for None, else hex."""
    return "~" if x is None else hexed(x)


class HostSession:
    """One host process (``host``, of kind ``kind``) with an FMU (and Hammer.fmu) loaded, instances made with the
    session's debug logging: the steps of the probes under FMI 2.0's method names. A version's
    session makes its instances (``new``), names the binary to open (``_binary_word``), enters
    initialization (``enter``) and says how a set call gives its value (``_set_words``)."""

    def __init__(self, kind: str, logging: bool, fmu_dir: Path, hammer_dir: Path,
                 host: CHost):
        self.fmu_dir, self.hammer_dir, self.logging, self.kind = fmu_dir, hammer_dir, logging, kind
        self.host = host
        from fmpy import read_model_description

        self.vars = {v.name: v for v in read_model_description(str(fmu_dir)).modelVariables}

    def __call__(self, *words) -> dict:
        return self.host(*words)

    def vr(self, name: str) -> int:
        return self.vars[name].valueReference

    def instance(self) -> str:
        """A new PipePlug instance (checked: made, no line)."""
        made = self.new(uri="usual")
        assert made["kind"] == "int" and made["log"] == [], made
        return made["words"][0]

    def hammer(self) -> str:
        """A new Hammer instance, in the same process (its own binary)."""
        opened = self.host("open", hexed(self._binary_word(self.hammer_dir, "Hammer")))
        made = self.new("hammer", "usual", fmu_dir=self.hammer_dir, lib=opened["words"][0])
        assert made["kind"] == "int", made
        return made["words"][0]

    def call(self, ident, method, *args) -> dict:
        return self("call", ident, method, *args)

    def ok(self, ident, method, *args) -> dict:
        """A call that must succeed without a line."""
        answer = self.call(ident, method, *args)
        assert answer["status"] == 0 and answer["log"] == [], (method, args, answer)
        return answer

    def set(self, ident, name, value) -> dict:
        """The set call of one variable's type (Strings: str, bytes, or None for NULL)."""
        v = self.vars[name]
        if v.type == "String":
            word = null_or_hexed(value)
        elif v.type in ("Boolean", "Integer", "Int32", "UInt64"):
            word = str(int(value))
        else:
            word = repr(float(value))
        return self.host("call", ident, "set" + v.type,
                         *self._set_words(v.valueReference, word))

    def start(self, ident, params=None, stop=None) -> dict:
        """Parameters set (checked), then exitInitializationMode: its answer."""
        self.enter(ident, stop)
        for name, value in (params or {}).items():
            answer = self.set(ident, name, value)
            assert answer["status"] == 0 and answer["log"] == [], (name, answer)
        return self.call(ident, "exitInitializationMode")

    def running(self, params=None, stop=None) -> str:
        """A new instance initialized with ``params`` (checked)."""
        ident = self.instance()
        answer = self.start(ident, params, stop)
        assert answer["status"] == 0 and answer["log"] == [], answer
        return ident

    def step(self, ident, t, h, q=23e3) -> dict:
        """Q set (checked), then doStep(t, h): its answer."""
        answer = self.set(ident, "Q", q)
        assert answer["status"] == 0 and answer["log"] == [], answer
        return self.call(ident, "doStep", repr(float(t)), repr(float(h)))

    def blob(self, ident) -> str:
        """A serialized state of a running instance, hex (checked)."""
        state = self("get_state", ident)
        assert state["status"] == 0, state
        blob = self("serialize", ident, state["words"][0])
        assert blob["status"] == 0 and blob["log"] == [], blob
        return blob["words"][0]

    def close(self) -> int:
        return self.host.close()


class Session(HostSession):
    """One host process with PipePlug.fmu (and Hammer.fmu) loaded: the C host (``host`` "c")
    or FMPy's (any other ``host``)."""

    def __init__(self, host: str, logging: bool, fmu_dir: Path, hammer_dir: Path,
                 c_host: Path, env: dict | None = None):
        if host == "c":
            env = host_env(**{"PIPEPLUG_PYTHON": sys.executable, **(env or {})})
            process = CHost(c_host, fmu_dir / "binaries" / "linux64" / "PipePlug.so", env)
        else:
            process = CHost([sys.executable, str(HERE / "fmpy_host.py")], fmu_dir, None)
        super().__init__(host, logging, fmu_dir, hammer_dir, process)

    def new(self, name="probe", uri=None, kind=1, fmu_dir=None, lib=None, token=None) -> dict:
        """fmi2Instantiate of PipePlug, or of the FMU in ``fmu_dir`` from the host's binary
        ``lib`` (``name`` or ``uri`` None: NULL; bytes: as they are; ``uri`` "usual": the
        FMU's resources; ``token``: the fmuGUID given, by default the FMU's)."""
        fmu_dir = fmu_dir or self.fmu_dir
        uri = resource_uri(fmu_dir) if uri == "usual" else uri
        return self("instantiate", null_or_hexed(name), hexed(token or guid_of(fmu_dir)),
                    null_or_hexed(uri), int(self.logging), kind, *([] if lib is None else [lib]))

    def _binary_word(self, fmu_dir: Path, identifier: str) -> str:
        """What the host opens for an FMU: its linux64 binary (FMPy's host: its folder)."""
        binary = fmu_dir / "binaries" / "linux64" / f"{identifier}.so"
        return str(binary if self.kind == "c" else fmu_dir)

    @staticmethod
    def _set_words(vr: int, word: str) -> list:
        """fmi2Set<type>'s words: N, the value reference, the value."""
        return [1, vr, word]

    def enter(self, ident, stop=None, start=0.0) -> None:
        """fmi2SetupExperiment and fmi2EnterInitializationMode (checked)."""
        self.ok(ident, "setupExperiment", "none", repr(start),
                "none" if stop is None else repr(stop))
        self.ok(ident, "enterInitializationMode")


class Hosts:
    """Host processes shared by probes: one :class:`Session` per (host, logging), made when
    first asked for and again after it was dropped (a probe that failed, or a host that died,
    takes its process with it: the next probe gets a fresh one).
    """

    def __init__(self, fmu_dir: Path, hammer_dir: Path, c_host: Path):
        self._args = fmu_dir, hammer_dir, c_host
        self._open: dict[tuple, Session] = {}

    def session(self, host: str, logging: bool) -> Session:
        key = (host, logging)
        if key not in self._open or not self._open[key].host.alive():
            self.drop(host, logging)
            self._open[key] = Session(host, logging, *self._args)
        return self._open[key]

    def drop(self, host: str, logging: bool) -> None:
        """End the shared process of (host, logging), if any, without asking it to quit."""
        session = self._open.pop((host, logging), None)
        if session is not None:
            session.host.kill()

    def close(self) -> dict:
        """Quit every shared process: (host, logging) -> (exit code, the end of its stderr)."""
        codes = {}
        while self._open:
            key, session = self._open.popitem()
            code = session.close()
            codes[key] = (code, session.host.stderr_tail)
        return codes


@dataclass(frozen=True)
class Expected:
    """What the contract says of a probe: the status of its call ("null": fmi2Instantiate
    returned NULL), texts its one line must hold, the hosts it applies to, the C host's
    environment."""

    status: int | str
    texts: tuple
    hosts: tuple = ("c", "fmpy")
    env: dict = field(default_factory=dict)
    enabled: bool = True          # False: waits for the core's limit of internal steps
    then_q: float = 23e3          # Q of the step taken after a discard [N]
    then_set: tuple = ()          # (name, value) the host sets before that step


# Probes ------------------------------------------------------------------------------------------
def parameters(params):
    def probe(s: Session):
        ident = s.instance()
        return s.start(ident, params), ident
    return probe


def set_in_init(name, value):
    def probe(s: Session):
        ident = s.instance()
        s.enter(ident)
        return s.set(ident, name, value), ident
    return probe


def after_init(name, value):
    def probe(s: Session):
        ident = s.running()
        return s.set(ident, name, value), ident
    return probe


def stepped(t, h, q=23e3, params=None, stop=None, first_q=23e3):
    """A step from ``t`` by ``h`` under ``q`` after one from 0 to 5 ms under ``first_q``."""
    def probe(s: Session):
        ident = s.running(params, stop)
        assert s.step(ident, 0.0, 0.005, first_q)["status"] == 0
        return s.step(ident, t, h, q), ident
    return probe


def struck(v_strike, params=None):
    """A strike (strikes 0 -> 1 at v_strike) for the step from 5 ms, after one at rest."""
    def probe(s: Session):
        ident = s.running(params)
        assert s.step(ident, 0.0, 0.005, 0.0)["status"] == 0
        for name, value in (("v_strike", v_strike), ("strikes", 1)):
            answer = s.set(ident, name, value)
            assert answer["status"] == 0 and answer["log"] == [], answer
        return s.call(ident, "doStep", "0.005", "0.005"), ident
    return probe


def _core_limits_internal_steps() -> bool:
    """Whether the core refuses a step of too many internal steps (its own parameter)."""
    from pipeplug import PARAMETERS

    return any(p.name == "max_internal_steps" for p in PARAMETERS)


LIMITED = _core_limits_internal_steps()


def raw(*words, running=True):
    """A call given as host words, "{I}" standing for the instance."""
    def probe(s: Session):
        ident = s.running() if running else s.instance()
        return s(*[ident if w == "{I}" else w for w in words]), ident
    return probe


def out_of_order(prepare, method, *args):
    def probe(s: Session):
        ident = s.instance()
        prepare(s, ident)
        return s.call(ident, method, *args), ident
    return probe


def _init(s, ident):
    s.enter(ident)


def _run(s, ident):
    assert s.start(ident)["status"] == 0


def _terminated(s, ident):
    _run(s, ident)
    s.ok(ident, "terminate")


def instantiate(**arguments):
    def probe(s: Session):
        return s.new(**arguments), None
    return probe


def state(kind):
    """fmi2SetFMUstate or fmi2DeSerializeFMUstate of a state that is not one of this FMU."""
    def probe(s: Session):
        ident = s.running()
        if kind == "null":
            return s("set_state", ident, 0), ident
        if kind == "freed":
            saved = s("get_state", ident)["words"][0]
            assert s("free_state", ident, saved, "keep")["status"] == 0
            return s("set_state", ident, saved), ident
        if kind == "hammer":
            other = s.hammer()
            saved = s("get_state", other)["words"][0]
            return s("set_state", ident, saved), ident
        blob = s.blob(ident)
        if kind == "short":
            return s("deserialize", ident, blob[:-2]), ident
        if kind == "long":
            return s("deserialize", ident, blob + "00"), ident
        if kind == "corrupt":
            at = len(blob) - 20                               # a byte of the payload
            return s("deserialize", ident, blob[:at] + f"{int(blob[at:at + 2], 16) ^ 1:02x}"
                     + blob[at + 2:]), ident
        if kind == "garbage":
            return s("deserialize", ident, hexed(b"not a PipePlug state")), ident
        if kind in ("NaN time", "NaN model field"):
            copy = s("deserialize", ident, _with_nan(blob, kind))
            assert copy["status"] == 0 and copy["log"] == [], copy     # framed as written
            return s("set_state", ident, copy["words"][0]), ident
        saved = s("get_state", ident)["words"][0]               # kind "small buffer"
        return s("serialize", ident, saved, 16), ident
    return probe


def _with_nan(blob: str, kind: str) -> str:
    """A serialized state (hex) with a NaN put in, framed again as the loader frames states
    (``states.c``: "FMI2STAT", identity, payload length and FNV-1a hash, 8 bytes each)."""
    import io

    import numpy as np

    data = bytes.fromhex(blob)
    head, _, model = data[32:].partition(b"\n")
    if kind == "NaN time":
        head = head.replace(b'"time": 0.0,', b'"time": NaN,')
    else:
        fields = dict(np.load(io.BytesIO(model)))
        fields["V1"] = np.array(np.nan)
        out = io.BytesIO()
        np.savez(out, **fields)
        model = out.getvalue()
    payload = head + b"\n" + model
    digest = 0xcbf29ce484222325
    for byte in payload:
        digest = ((digest ^ byte) * 0x100000001b3) % 2 ** 64
    return (data[:16] + len(payload).to_bytes(8, "little") + digest.to_bytes(8, "little")
            + payload).hex()


def python_answering(s: Session):
    """fmi2Instantiate in a host without Python, PIPEPLUG_PYTHON naming a program that does not
    answer as a python does (the expectation's environment)."""
    return s.new(uri="usual"), None


LIVE = "a live state of this PipePlug"
WRONG_TOKEN = "{00000000-dead-beef-0000-000000000000}"
AFTER = ("after an error",)

#: name -> (probe, expected)
PROBES = {
    # Parameters and options: fmi2Error at fmi2ExitInitializationMode.
    "L2 > L1": (parameters({"L2": 3.0}), Expected(ERROR, ("L2 = 3.0", "allowed", "<= L1",
                                                         "L1 = 1.0"))),
    "NaN tau2": (parameters({"tau2": float("nan")}), Expected(ERROR, ("tau2 = nan", ">= 0"))),
    "NaN inactive E1": (parameters({"E1": float("nan")}), Expected(ERROR, ("E1 = nan",
                                                                          "finite"))),
    "infinite inactive dt": (parameters({"dt": float("inf")}), Expected(ERROR, ("dt = inf",))),
    "h1 cancelling": (parameters({"h1": 1e-18}), Expected(ERROR, ("h1 = 1e-18", "S1"))),
    "R1 underflowing": (parameters({"R1": 1e-300, "elastic": True}),
                        Expected(ERROR, ("R1 = 1e-300", "S2"))),
    "R1 overflowing": (parameters({"R1": 1e300}), Expected(ERROR, ("R1 = 1e+300",
                                                                  "magnitude"))),
    "unknown solver": (parameters({"solver": "rk4"}), Expected(ERROR, ("solver = 'rk4'",
                                                                      "'exact', 'fd'"))),
    "percent in a string": (parameters({"solver": "%s%n%d"}),
                            Expected(ERROR, ("solver = '%s%n%d' is not allowed",))),
    # Values refused when set.
    "solver not UTF-8": (set_in_init("solver", b"\xff\xfeexact"),
                         Expected(ERROR, ("solver = b'\\xff\\xfeexact'", "UTF-8"))),
    "solver NULL": (set_in_init("solver", None), Expected(ERROR, ("solver = None",))),
    "fixed parameter after init": (after_init("tau2", 2e4),
                                   Expected(ERROR, ("tau2 = 20000.0", "after initialization"))),
    "option after init": (after_init("solver", "fd"), Expected(ERROR, ("solver = 'fd'",))),
    "output set": (after_init("v_pipe", 1.0), Expected(ERROR, ("v_pipe = 1.0", "output"))),
    "unknown value reference get": (raw("call", "{I}", "getReal", 1, 123456),
                                    Expected(ERROR, ("valueReference = 123456",))),
    "unknown value reference set": (raw("call", "{I}", "setReal", 1, 2 ** 32 - 1, "1.0"),
                                    Expected(ERROR, ("valueReference = 4294967295",))),
    "Real read as Integer": (raw("call", "{I}", "getInteger", 1, 0),
                             Expected(ERROR, ("valueReference = 0", "Integer"))),
    # Steps: fmi2Discard, or fmi2Error past the stopTime.
    "NaN Q": (stepped(0.005, 0.005, float("nan")), Expected(DISCARD, ("Q = nan", "finite"))),
    "infinite Q": (stepped(0.005, 0.005, float("inf")), Expected(DISCARD, ("Q = inf",))),
    "wrong communication point": (stepped(0.5, 0.005),
                                  Expected(DISCARD, ("currentCommunicationPoint = 0.5",
                                                     "0.005"))),
    "zero step": (stepped(0.005, 0.0), Expected(DISCARD, ("communicationStepSize = 0.0",))),
    "NaN step": (stepped(0.005, float("nan")), Expected(DISCARD, ("communicationStepSize",))),
    "past stopTime": (stepped(0.005, 0.01, stop=0.01), Expected(ERROR, ("0.015", "stopTime"))),
    "strike without a ram": (struck(3.0), Expected(DISCARD, ("strikes = 'an increase'",
                                                             "ram_mass > 0"),
                                                   then_set=(("strikes", 0),))),
    "NaN v_strike": (struck(float("nan"), {"ram_mass": 50.0}),
                     Expected(DISCARD, ("v_strike = nan", "finite"),
                              then_set=(("v_strike", 3.0),))),
    "infinite v_strike, elastic": (struck(float("inf"), {"ram_mass": 50.0, "elastic": True}),
                                   Expected(DISCARD, ("v_strike = inf", "finite"),
                                            then_set=(("v_strike", 3.0),))),
    # a finite velocity whose kinetic energy m v^2 / 2 overflows: every output after it would
    # be inf or nan (it was fmi2Error naming E_kinetic); the input is what is refused
    "huge v_strike": (struck(1e300, {"ram_mass": 50.0}),
                      Expected(DISCARD, ("v_strike = 1e+300", "kinetic energy"),
                               then_set=(("v_strike", 3.0),))),
    "huge v_strike, elastic": (struck(1e300, {"ram_mass": 50.0, "elastic": True}),
                               Expected(DISCARD, ("v_strike = 1e+300", "kinetic energy"),
                                        then_set=(("v_strike", 3.0),))),
    "huge Q": (stepped(0.005, 0.005, 1e200), Expected(ERROR, ("W_input = inf", "finite"))),
    "infinite step": (stepped(0.005, float("inf")),
                      Expected(DISCARD, ("communicationStepSize = inf", "finite"))),
    # values beyond float range inside a step: fmi2Error naming Q, the step and the overflow
    "fd huge Q": (stepped(0.005, 0.005, 1e300, params={"solver": "fd"}),
                  Expected(ERROR, ("Q = 1e+300", "by 0.005 s", "overflowed"))),
    "huge step": (stepped(0.005, 1e300), Expected(ERROR, ("Q = 23000.0", "by 1e+300 s",
                                                          "overflowed"))),
    # (the first step at rest costs nothing; after the discard the run goes on at rest)
    "fd dt = 1e-300": (stepped(0.005, 0.005, params={"solver": "fd", "dt": 1e-300},
                               first_q=0.0),
                       Expected(DISCARD, ("communicationStepSize = 0.005", "internal steps"),
                                enabled=LIMITED, then_q=0.0)),
    "elastic h = 1e300": (stepped(0.005, 1e300, params={"elastic": True}, first_q=0.0),
                          Expected(DISCARD, ("communicationStepSize = 1e+300", "internal steps"),
                                   enabled=LIMITED, then_q=0.0)),
    # Calls out of the FMI 2.0 call sequence: fmi2Error, nothing changed.
    "setupExperiment after init": (out_of_order(_run, "setupExperiment", "none", "-5.0",
                                                "none"),
                                   Expected(ERROR, ("fmi2SetupExperiment", "stepping"))),
    "setupExperiment in init": (out_of_order(_init, "setupExperiment", "none", "0.0", "none"),
                                Expected(ERROR, ("fmi2SetupExperiment",
                                                 "initialization mode"))),
    "doStep before init": (out_of_order(_init, "doStep", "0.0", "0.001"),
                           Expected(ERROR, ("fmi2DoStep", "initialization mode"))),
    "doStep after terminate": (out_of_order(_terminated, "doStep", "0.0", "0.001"),
                               Expected(ERROR, ("fmi2DoStep", "terminated"))),
    "set after terminate": (out_of_order(_terminated, "setReal", 1, 0, "1.0"),
                            Expected(ERROR, ("Q = 1.0", "fmi2Terminate"))),
    "exitInit twice": (out_of_order(_run, "exitInitializationMode"),
                       Expected(ERROR, ("fmi2ExitInitializationMode",))),
    "enterInit twice": (out_of_order(_init, "enterInitializationMode"),
                        Expected(ERROR, ("fmi2EnterInitializationMode",))),
    "terminate before init": (out_of_order(lambda s, i: None, "terminate"),
                              Expected(ERROR, ("fmi2Terminate", "instantiated"))),
    "getReal before init": (out_of_order(lambda s, i: None, "getReal", 1, 0),
                            Expected(ERROR, ("fmi2GetReal", "instantiated",
                                             "fmi2EnterInitializationMode"))),
    "NaN startTime": (out_of_order(lambda s, i: None, "setupExperiment", "none", "nan", "none"),
                      Expected(ERROR, ("startTime = nan",))),
    "stopTime before startTime": (out_of_order(lambda s, i: None, "setupExperiment", "none",
                                               "2.0", "1.0"),
                                  Expected(ERROR, ("stopTime = 1.0", "startTime = 2.0"))),
    # fmi2Instantiate: NULL after one line.
    "NULL instance name": (instantiate(name=None, uri="usual"),
                           Expected("null", ("instanceName = NULL",))),
    "instance name not UTF-8": (instantiate(name=b"\xff\xfe", uri="usual"),
                                Expected("null", ("instanceName = '\\xff\\xfe'", "UTF-8"))),
    "model exchange": (instantiate(uri="usual", kind=0), Expected("null", ("fmuType = 0",))),
    "GUID of another FMU": (instantiate(uri="usual", token=WRONG_TOKEN),
                            Expected("null", (f"fmuGUID = '{WRONG_TOKEN}'", "guid"))),
    "resources: temp folder": (instantiate(uri="file:///tmp"),
                               Expected("null", ("fmuResourceLocation = 'file:///tmp'",
                                                 "resources"))),
    "resources: no folder": (instantiate(uri="file:///nonexistent/dir"),
                             Expected("null", ("file:///nonexistent/dir",))),
    "resources: malformed escape": (instantiate(uri="file:///tmp/%zz"),
                                    Expected("null", ("%-escapes",))),
    "resources: too long": (instantiate(uri="file:///" + "a" * 5000),
                            Expected("null", ("(5008 bytes)", "4096"))),
    "resources: another host": (instantiate(uri="file://elsewhere/tmp"),
                                Expected("null", ("this machine",))),
    # NULL arrays and pointers: fmi2Error.
    "NULL arrays get": (raw("null", "{I}", "getReal", 3), Expected(ERROR, ("vr = NULL",
                                                                           "n = 3"))),
    "NULL arrays set": (raw("null", "{I}", "setReal", 2), Expected(ERROR, ("vr = NULL",))),
    "NULL arrays strings": (raw("null", "{I}", "getString", 1), Expected(ERROR, ("NULL",))),
    "NULL state pointer": (raw("null", "{I}", "getFMUstate", 0),
                           Expected(ERROR, ("FMUstate = NULL",))),
    "NULL serialized bytes": (raw("null", "{I}", "deSerializeFMUstate", 40),
                              Expected(ERROR, ("NULL",))),
    "NULL status value": (raw("null", "{I}", "getRealStatus", 0), Expected(ERROR, ("NULL",))),
    "NULL log categories": (raw("null", "{I}", "setDebugLogging", 2),
                            Expected(ERROR, ("categories = NULL",))),
    "unknown log category": (raw("debug", "{I}", 1, 1, hexed("logEverything")),
                             Expected(ERROR, ("categories[0] = 'logEverything'",))),
    # FMU states: fmi2Error.
    "NULL state": (state("null"), Expected(ERROR, ("FMUstate = NULL", LIVE))),
    "freed state": (state("freed"), Expected(ERROR, ("FMUstate = 0x", LIVE))),
    "Hammer state": (state("hammer"), Expected(ERROR, ("FMUstate = 0x", LIVE))),
    "serialized state too short": (state("short"), Expected(ERROR, ("serializedState",
                                                                    "length"))),
    "serialized state too long": (state("long"), Expected(ERROR, ("serializedState",
                                                                  "length"))),
    "serialized state corrupt": (state("corrupt"), Expected(ERROR, ("checksum",))),
    "serialized state of nothing": (state("garbage"), Expected(ERROR, ("serializedState",))),
    "state with a NaN time": (state("NaN time"), Expected(ERROR, ("FMUstate time = nan",
                                                                  "finite"))),
    "state with a NaN model field": (state("NaN model field"),
                                     Expected(ERROR, ("FMUstate", "'V1' = nan"))),
    "serialize into a small buffer": (state("small buffer"), Expected(ERROR, ("size = 16",))),
    # A Python that never answers (the C host; a Python host brings its own).
    "python never exits": (python_answering, Expected(
        "null", ("did not answer within 2 s",), ("c",),
        {"PIPEPLUG_PYTHON": "#!/bin/sh\nexec sleep 1000\n", "PIPEPLUG_PYTHON_TIMEOUT": "2"})),
    "python prints without end": (python_answering, Expected(
        "null", ("printed more than",), ("c",), {"PIPEPLUG_PYTHON": "#!/bin/sh\nexec yes\n"})),
}
