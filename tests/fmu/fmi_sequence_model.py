"""What the contract says an FMU instance must do: the test's own model of PipePlug's FMI side.

Parameter ranges are copied from the contract (``Parameters`` table and its activation rule),
not from the code. Each instance keeps a mirror of the core model (:mod:`pipeplug`) driven
with the same inputs: the FMU must give the very same numbers, so instances are independent
and a restored state continues exactly as the original did.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
import threading
from dataclasses import dataclass, field
from pathlib import Path
from queue import Empty, Queue

from pipeplug import build_model

#: contract defaults of the parameters and options the test sets
DEFAULTS = {"L1": 1.0, "L2": 1.0, "R1": 0.035, "h1": 0.003, "rho1": 7800.0, "rho2": 1800.0,
            "E1": 1.95e11, "E2": 6.0e8, "tau1": 0.0, "tau2": 1.0e4, "dt": 2.0e-4, "dx": 0.01,
            "courant": 1.0, "x_monitor": 0.5, "contact_growth": False, "elastic": False,
            "solver": "exact"}
OPTIONS = ("solver", "contact_growth", "elastic")
NUMBERS = tuple(name for name in DEFAULTS if name not in OPTIONS)
REAL_OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction", "W_friction_outer", "W_friction_inner", "E_kinetic", "E_strain",
                "W_numerical", "F_head", "v_ram", "W_ram", "W_cushion", "E_transferred",
                "stress_head", "stress_min", "stress_max", "W_face", "W_damping", "L2_now",
                "W_accretion", "W_removed")
MODES = ("pipe_mode", "plug_mode")
FLAGS = ("at_rest",)
OK, DISCARD, ERROR = 0, 2, 3
#: modelDescription.xml's LogCategories: every log line carries one of them
LOG_CATEGORIES = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                  "logAll"}


def _positive(x) -> bool:
    return _finite(x) and x > 0.0


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _whole(length: float, dx: float) -> bool:
    ratio = length / dx
    return abs(ratio - round(ratio)) <= 1e-9 * max(1.0, ratio)


def invalid_names(given: dict) -> set[str]:
    """Names the contract refuses at exitInitializationMode for these set values."""
    v = {**DEFAULTS, **given}
    bad = {name for name in NUMBERS if not _finite(v[name])}   # active or not
    bad |= {name for name in ("L1", "R1", "h1", "rho1", "rho2") if not _positive(v[name])}
    bad |= {name for name in ("tau1", "tau2") if not (_finite(v[name]) and v[name] >= 0.0)}
    if not (_finite(v["L2"]) and 0.0 <= v["L2"] <= v["L1"]):
        bad.add("L2")
    if v["solver"] not in ("exact", "fd"):
        bad.add("solver")
    if v["elastic"]:
        bad |= {name for name in ("E1", "E2") if not _positive(v[name])}
        if not (_positive(v["dx"]) and v["dx"] <= v["L1"] / 2 and _whole(v["L1"], v["dx"])
                and (v["L2"] == 0.0 or v["tau2"] == 0.0 or _whole(v["L2"], v["dx"]))):
            bad.add("dx")
        if not (_positive(v["courant"]) and v["courant"] <= 1.0):
            bad.add("courant")
        if not (_finite(v["x_monitor"]) and 0.0 <= v["x_monitor"] <= v["L1"]):
            bad.add("x_monitor")
    elif v["solver"] == "fd" and not _positive(v["dt"]):
        bad.add("dt")
    return bad


def mirror_model(given: dict):
    """The core model the FMU must be running for these set values."""
    v = {**DEFAULTS, **given}
    return build_model({k: x for k, x in v.items() if k not in OPTIONS},
                       {k: v[k] for k in OPTIONS})


@dataclass
class Instance:
    """The expected state of one FMU instance.

    ``phase``: FMI 2.0's "instantiated", "init" (initialization mode: parameters settable, no
    model yet), "run" (stepping), "terminated", and "error" after a call returned fmi2Error
    (every call but fmi2SetFMUstate, fmi2Reset, fmi2Terminate, fmi2FreeInstance and
    fmi2FreeFMUstate refused with one line, until a state is set or the instance reset).
    """

    ident: int
    name: str
    phase: str = "instantiated"
    given: dict = field(default_factory=dict)
    q: float = 0.0
    time: float = 0.0
    stop: float | None = None
    mirror: object = None
    outputs: dict = field(default_factory=dict)
    states: set = field(default_factory=set)     # FMU states obtained through this instance

    def reset(self) -> None:
        self.phase, self.given, self.q, self.time = "instantiated", {}, 0.0, 0.0
        self.stop, self.mirror, self.outputs = None, None, {}

    def snapshot(self) -> dict:
        """What an FMU state taken now holds (never taken in "error": refused there)."""
        snap = {"kind": self.phase, "given": dict(self.given), "q": self.q, "time": self.time,
                "stop": self.stop, "outputs": dict(self.outputs)}
        if self.mirror is not None:
            snap["model"] = {k: (v.copy() if hasattr(v, "copy") else v)
                             for k, v in self.mirror.get_state().items()}
        return snap

    def restore(self, snap: dict) -> None:
        """Take over a snapshot: its phase, values, time and model."""
        self.given, self.q, self.time, self.stop = dict(snap["given"]), snap["q"], snap["time"], \
            snap["stop"]
        self.outputs, self.phase, self.mirror = dict(snap["outputs"]), snap["kind"], None
        if "model" in snap:
            self.mirror = mirror_model(self.given)
            self.mirror.set_state({k: (v.copy() if hasattr(v, "copy") else v)
                                   for k, v in snap["model"].items()})


def step_refusal(inst: Instance, t: float, h: float) -> tuple[int, str] | None:
    """How the contract refuses doStep(t, h) of a running instance: (status, the name its line
    gives), the first reason in this order; None: the step must be taken. A step that cannot be
    taken is discarded; a step past the stopTime is an error (FMI 2.0)."""
    if not abs(t - inst.time) <= 1e-9 * max(1.0, abs(inst.time)):
        return DISCARD, "currentCommunicationPoint"
    if not h > 0.0:
        return DISCARD, "communicationStepSize"
    if not t + h > inst.time:
        return DISCARD, "currentCommunicationPoint + communicationStepSize"
    if inst.stop is not None and t + h > inst.stop + 1e-9 * max(1.0, abs(inst.stop)):
        return ERROR, "stopTime"
    if not math.isfinite(inst.q):
        return DISCARD, "Q"
    return None


class WorkerDied(AssertionError):
    """The host process ended: a crash of the FMU or of FMPy."""


class Worker:
    """The host subprocess (``fmi_sequence_worker.py``) and its JSON-lines channel."""

    def __init__(self, fmu_dir: Path, log_file: Path):
        self._stderr = open(log_file, "w+")
        self.proc = subprocess.Popen(
            [sys.executable, str(Path(__file__).with_name("fmi_sequence_worker.py")),
             str(fmu_dir)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._stderr, text=True)
        self._answers: Queue = Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            if line.startswith("@@"):
                self._answers.put(json.loads(line[2:]))
        self._answers.put(None)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def __call__(self, op: str, **args) -> dict:
        try:
            self.proc.stdin.write(json.dumps({"op": op, **args}) + "\n")
            self.proc.stdin.flush()
            answer = self._answers.get(timeout=120)
        except (BrokenPipeError, Empty):
            answer = None
        if answer is None:
            try:
                code = self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                code = "none (hung)"
            self._stderr.seek(0)
            raise WorkerDied(f"the host process died during {op} {args}: exit code "
                             f"{code}\n{self._stderr.read()[-3000:]}")
        return answer

    def close(self) -> None:
        if self.alive():
            self.proc.stdin.write(json.dumps({"op": "quit"}) + "\n")
            self.proc.stdin.flush()
            self.proc.wait(timeout=60)
        self._stderr.close()
