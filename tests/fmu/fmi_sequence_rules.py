"""The FMI calls of the stateful test as hypothesis rules: instances, initialization, stepping,
refusals with fmi2Error. Every answer is checked against the contract's model
(:mod:`fmi_sequence_model`); the FMU states' rules are in ``test_fmi_sequences.py``.
"""
from __future__ import annotations

import math

from fmi_sequence_model import (
    DISCARD,
    ERROR,
    FLAGS,
    LOG_CATEGORIES,
    MODES,
    OK,
    REAL_OUTPUTS,
    Instance,
    invalid_names,
    mirror_model,
    step_refusal,
)
from hypothesis import event
from hypothesis import strategies as st
from hypothesis.stateful import (
    Bundle,
    RuleBasedStateMachine,
    consumes,
    initialize,
    precondition,
    rule,
)

NAN, INF = float("nan"), float("inf")
PARAM_VALUES = {
    "tau1": st.one_of(st.floats(0.0, 1.2e5), st.sampled_from([0.0, -1.0, NAN, INF])),
    "tau2": st.one_of(st.floats(0.0, 1.2e5), st.sampled_from([0.0, -1.0, NAN])),
    "L2": st.sampled_from([0.0, 0.5, 1.0, 2.0, NAN]),
    "rho2": st.sampled_from([180.0, 1800.0, 1.8e5, 0.0]),
    "dt": st.sampled_from([1e-4, 2e-4, 1e-3, 0.0, -1.0, NAN]),
    "dx": st.sampled_from([0.1, 0.25, 0.3, 0.6, NAN]),
    "courant": st.sampled_from([1.0, 0.5, 0.0, 1.5]),
    "x_monitor": st.sampled_from([0.5, 0.0, 1.0, 2.0]),
    "solver": st.sampled_from(["exact", "fd", "rk4", "%s%n%d", ""]),
    "contact_growth": st.booleans(),
    "elastic": st.booleans(),
}
VALID_START = st.fixed_dictionaries({
    "solver": st.sampled_from(["exact", "fd"]), "elastic": st.sampled_from([False, False, True]),
    "contact_growth": st.booleans(), "tau1": st.floats(0.0, 1.2e5), "tau2": st.floats(0.0, 1.2e5),
    "L2": st.sampled_from([0.0, 0.5, 1.0]), "rho2": st.sampled_from([180.0, 1800.0, 1.8e5]),
    "dt": st.sampled_from([1e-4, 2e-4]), "dx": st.sampled_from([0.1, 0.25])})
Q_VALUES = st.one_of(st.floats(-5e4, 5e4), st.sampled_from([NAN, INF, -INF]))
STEPS = st.one_of(st.floats(1e-6, 0.02), st.sampled_from([1e-3, 0.0, -1e-3, NAN]))
OFFSETS = st.sampled_from([0.0, 0.0, 0.0, 1e-12, 1e-6, -1e-3])   # host time - FMU time [s]
WORKER: dict = {}


def _same(a, b) -> bool:
    return a == b or (isinstance(a, float) and math.isnan(a) and math.isnan(b))


INSTANCES, STATES = Bundle("instances"), Bundle("states")
_CATEGORY = {DISCARD: "logStatusDiscard", ERROR: "logStatusError"}


class FmiRules(RuleBasedStateMachine):
    """The contract's model of up to four instances, checked call by call."""

    instances = INSTANCES
    states = STATES

    def __init__(self):
        super().__init__()
        self.worker, self.vr = WORKER["worker"], WORKER["vr"]
        self.live: dict[int, Instance] = {}
        self.owner: dict[int, int] = {}       # FMU state -> instance it was obtained through
        self.snaps: dict[int, dict] = {}
        self.serial = 0

    # Helpers -------------------------------------------------------------------------------
    def call(self, inst: Instance, method: str, *args) -> dict:
        return self.worker("call", id=inst.ident, method=method, args=list(args))

    def expect(self, answer: dict, inst: Instance, status: int, names=()) -> None:
        """Status as the contract says. A refusal: exactly one log line, with the status's
        category, saying what is not allowed and naming one of ``names``; otherwise no log
        line. Every line has a category of LogCategories."""
        assert all(entry[3] in LOG_CATEGORIES for entry in answer["log"]), answer
        assert answer["status"] == status, (status, answer)
        assert all(entry[0] == inst.name for entry in answer["log"]), answer  # others quiet
        lines = [entry[2] for entry in answer["log"]]
        if not names:
            assert lines == [], answer
            return
        assert len(lines) == 1 and "not allowed" in lines[0], answer
        assert any(f"{n} = " in lines[0] or n in lines[0] for n in names), (names, answer)
        assert answer["log"][0][1:4:2] == [status, _CATEGORY[status]], answer

    def refused_with_error(self, inst: Instance, answer: dict, names) -> None:
        """A call refused with fmi2Error naming one of ``names`` (the instance is then in error;
        it changes nothing else); in error already, the short refusal of every call."""
        if inst.phase == "error":
            self.expect(answer, inst, ERROR, ["after an error"])
            return
        self.expect(answer, inst, ERROR, names)
        inst.phase = "error"
        event(f"error: {names[0]}")

    def check_outputs(self, inst: Instance, want: dict) -> None:
        reals = self.call(inst, "getReal", [self.vr[n] for n in REAL_OUTPUTS])
        modes = self.call(inst, "getInteger", [self.vr[n] for n in MODES])
        flags = self.call(inst, "getBoolean", [self.vr[n] for n in FLAGS])
        self.expect(reals, inst, OK)
        got = dict(zip(REAL_OUTPUTS + MODES + FLAGS,
                       reals["value"] + modes["value"] + flags["value"]))
        assert all(_same(got[k], want[k]) for k in want), (inst.name, got, want)

    def _free_state(self, state):
        if state not in self.owner:
            return                                        # freed with its instance already
        owner = self.owner.pop(state)
        self.live[owner].states.discard(state)
        del self.snaps[state]
        assert self.worker("free_state", id=owner, state=state)["status"] == OK


    # Instances -----------------------------------------------------------------------------
    @initialize(target=instances, given=VALID_START, stop=st.sampled_from([None, None, 0.1]))
    def first(self, given, stop):
        """Every sequence starts with one running instance."""
        ident = self._new()
        self.start_running(ident, given, stop)
        return ident

    @precondition(lambda self: len(self.live) < 4)
    @rule(target=instances)
    def another(self):
        return self._new()

    def _new(self):
        self.serial += 1
        name = f"i{self.serial}"
        answer = self.worker("instantiate", name=name)
        assert answer["status"] == OK and answer["log"] == []
        inst = Instance(answer["value"], name)
        self.live[inst.ident] = inst
        inst.outputs = {n: 0.0 for n in REAL_OUTPUTS} | {n: 0 for n in MODES} | {n: False for n in FLAGS}
        return inst.ident

    @rule(ident=consumes(instances))
    def free_instance(self, ident):
        inst = self.live[ident]
        for state in sorted(inst.states):
            self._free_state(state)
        self.terminate(ident)
        assert self.worker("free", id=ident)["status"] == OK
        del self.live[ident]

    def terminate(self, ident):
        """fmi2Terminate: taken while stepping, accepted after an error, else out of order."""
        inst = self.live[ident]
        answer = self.call(inst, "terminate")
        if inst.phase in ("run", "error"):
            self.expect(answer, inst, OK)
            inst.phase = "terminated" if inst.phase == "run" else "error"
        else:
            self.refused_with_error(inst, answer, ["fmi2Terminate"])

    @rule(ident=instances)
    def reset(self, ident):
        inst = self.live[ident]
        answer = self.call(inst, "reset")
        self.expect(answer, inst, OK)
        inst.reset()
        inst.outputs = {n: 0.0 for n in REAL_OUTPUTS} | {n: 0 for n in MODES} | {n: False for n in FLAGS}

    # Initialization ------------------------------------------------------------------------
    @rule(ident=instances, start=st.sampled_from([0.0, 2.5]),
          length=st.sampled_from([None, 0.05, 1.0]))
    def setup(self, ident, start, length):
        inst = self.live[ident]
        if inst.phase != "instantiated":
            return
        stop = None if length is None else start + length
        self.expect(self.call(inst, "setupExperiment", None, start, stop), inst, OK)
        inst.time, inst.stop = start, stop

    @rule(ident=instances)
    def enter_initialization(self, ident):
        inst = self.live[ident]
        if inst.phase == "instantiated":
            self.expect(self.call(inst, "enterInitializationMode"), inst, OK)
            inst.phase = "init"

    @rule(ident=instances, data=st.data())
    def set_parameter(self, ident, data):
        inst = self.live[ident]
        name = data.draw(st.sampled_from(sorted(PARAM_VALUES)))
        value = data.draw(PARAM_VALUES[name])
        kind = {"solver": "String", "contact_growth": "Boolean", "elastic": "Boolean"}.get(
            name, "Real")
        if inst.phase == "run" and data.draw(st.integers(0, 3)):
            return                              # rarely: a fixed parameter after initialization
        answer = self.call(inst, "set" + kind, [self.vr[name]], [value])
        if inst.phase in ("instantiated", "init"):
            self.expect(answer, inst, OK)
            inst.given[name] = value
        else:   # a fixed parameter after initialization, or in error
            self.refused_with_error(inst, answer, [name])

    @rule(ident=instances)
    def exit_initialization(self, ident):
        inst = self.live[ident]
        if inst.phase != "init":
            return
        answer = self.call(inst, "exitInitializationMode")
        bad = invalid_names(inst.given)
        if bad:
            self.refused_with_error(inst, answer, sorted(bad))
            solver = inst.given.get("solver", "")
            if "solver" in bad and "%" in solver:                    # printf-safe logging
                assert any(f"solver = {solver!r}" in e[2] for e in answer["log"]), answer
        else:
            self.expect(answer, inst, OK)
            inst.phase, inst.mirror = "run", mirror_model(inst.given)
            inst.outputs = inst.mirror.outputs()._asdict()   # the model's own from now on

    @rule(ident=instances, given=VALID_START, stop=st.sampled_from([None, None, 0.1]))
    def start_running(self, ident, given, stop):
        """setupExperiment, enter, valid parameters, exit: the usual way to a running FMU. Values
        set earlier stay, so the whole set may still be refused (exit_initialization knows)."""
        inst = self.live[ident]
        if inst.phase != "instantiated":
            return
        self.setup(ident, 0.0, stop)
        self.enter_initialization(ident)
        for name, value in given.items():
            kind = {"solver": "String", "contact_growth": "Boolean", "elastic": "Boolean"}.get(
                name, "Real")
            self.expect(self.call(inst, "set" + kind, [self.vr[name]], [value]), inst, OK)
            inst.given[name] = value
        self.exit_initialization(ident)

    # Stepping ------------------------------------------------------------------------------
    def running(self) -> list[int]:
        return sorted(i for i, inst in self.live.items() if inst.phase == "run")

    @precondition(lambda self: self.running())
    @rule(data=st.data(), steps=st.lists(st.tuples(
        st.floats(-5e4, 5e4), st.floats(1e-6, 0.02), st.sampled_from([0.0, 1e-12])),
        min_size=1, max_size=5))
    def step_valid(self, data, steps):
        """A few steps the contract must take, on a running instance."""
        ident = data.draw(st.sampled_from(self.running()))
        for q, h, offset in steps:
            self.step(ident, q, h, offset)

    @rule(ident=instances, q=Q_VALUES, h=STEPS, offset=OFFSETS)
    def step(self, ident, q, h, offset):
        inst = self.live[ident]
        answer = self.call(inst, "setReal", [self.vr["Q"]], [q])
        if inst.phase in ("instantiated", "init", "run"):
            self.expect(answer, inst, OK)
            inst.q = q
        else:                                          # after fmi2Terminate, or in error
            self.refused_with_error(inst, answer, ["Q"])
        t = inst.time + offset * max(1.0, abs(inst.time))
        answer = self.call(inst, "doStep", t, h)
        refusal = step_refusal(inst, t, h) if inst.phase == "run" else (ERROR, "fmi2DoStep")
        if refusal is not None and refusal[0] == ERROR:
            self.refused_with_error(inst, answer, [refusal[1]])
        elif refusal is not None:
            self.expect(answer, inst, DISCARD, [refusal[1]])
            event(f"discarded step: {refusal[1][:30]}")
        else:
            self.expect(answer, inst, OK)
            inst.time = t + h
            inst.mirror.advance_to(inst.q, t + h, t)    # the FMU steps from the host's t to t + h
            inst.outputs = inst.mirror.outputs()._asdict()
            self.check_outputs(inst, inst.outputs)
            event(f"step taken: {inst.given.get('solver', 'exact')}"
                  f"{', elastic' if inst.given.get('elastic') else ''}")

    @rule(ident=instances)
    def get_outputs(self, ident):
        inst = self.live[ident]
        if inst.phase == "instantiated":          # FMI 2.0 reads from initialization on
            self.refused_with_error(inst, self.call(inst, "getReal", [self.vr["v_pipe"]]),
                                    ["fmi2GetReal"])
        elif inst.phase != "error":
            self.check_outputs(inst, inst.outputs)
        else:
            self.refused_with_error(inst, self.call(inst, "getReal", [self.vr["v_pipe"]]), [])
