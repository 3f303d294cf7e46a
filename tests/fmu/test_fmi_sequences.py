"""Random sequences of FMI calls on the built FMU (hypothesis stateful testing).

The calls run in a long-lived host subprocess: FMPy's raw FMU2Slave API in a Python process
(``fmi_sequence_worker.py``), or the plain C host (``fmi_host.c``, no Python in it until the
FMU brings one). This process generates the sequences, keeps the contract's model of every
instance (:mod:`fmi_sequence_model`) and checks each answer (:mod:`fmi_sequence_rules`):
valid and invalid call orders, random and non-finite values, unknown value references, FMU
states taken, restored (into any instance), serialized and freed at any point (never used
after being freed), several instances at once.

Checked: the host never dies; every refusal has the contract's status (fmi2Error at
initialization, for a set after it, for an unknown reference, for a call out of the FMI 2.0
call sequence and for a step past the stopTime; discard for a step that cannot be taken) and
exactly one log line naming the variable or call, with its status's category (every line has a
category of LogCategories); after an fmi2Error every call but fmi2SetFMUstate, fmi2Reset,
fmi2Terminate, fmi2FreeInstance (and fmi2FreeFMUstate) is refused with one short line until a
state is set or the instance reset; outputs equal those of the core model driven the same way
(instances independent, restored states continue exactly); states round-trip exactly through
serialization.
"""
from __future__ import annotations

from fmi_c_host import CWorker
from fmi_sequence_model import OK, Worker
from fmi_sequence_rules import INSTANCES, Q_VALUES, STATES, WORKER, FmiRules
from hypothesis import HealthCheck, event, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    consumes,
    invariant,
    multiple,
    precondition,
    rule,
    run_state_machine_as_test,
)


class FmiCalls(FmiRules):
    """The rules of :class:`FmiRules`, and those of FMU states, out-of-order calls, survival."""

    instances, states = INSTANCES, STATES

    # Refusals with fmi2Error ---------------------------------------------------------------------
    @rule(ident=instances, data=st.data())
    def refuse_with_error(self, ident, data):
        """An unknown value reference read, or something set that cannot be set (rarely)."""
        inst = self.live[ident]
        if data.draw(st.integers(0, 3)):
            return
        target = data.draw(st.sampled_from(["get", "v_pipe", "W_friction", "pipe_mode", "set"]))
        unknown = data.draw(st.sampled_from([10_000, 123_456_789, 2 ** 32 - 1]))
        if target == "get":
            kind = data.draw(st.sampled_from(["getReal", "getInteger", "getBoolean",
                                              "getString"]))
            answer, name = self.call(inst, kind, [unknown]), "valueReference"
            if inst.phase == "instantiated":      # refused before its value reference is read
                name = "fmi2G" + kind[1:]
        elif target == "pipe_mode":
            answer, name = self.call(inst, "setInteger", [self.vr[target]], [1]), target
        elif target == "set":
            answer, name = self.call(inst, "setReal", [unknown], [1.0]), "valueReference"
        else:
            answer = self.call(inst, "setReal", [self.vr[target]], [data.draw(Q_VALUES)])
            name = target
        self.refused_with_error(inst, answer, [name])

    # FMU states ----------------------------------------------------------------------------
    @rule(target=states, ident=instances)
    def get_state(self, ident):
        inst = self.live[ident]
        answer = self.worker("get_state", id=ident)
        if inst.phase == "error":
            self.refused_with_error(inst, answer, [])
            return multiple()
        assert answer["status"] == OK and answer["log"] == [], answer
        state = answer["value"]
        self.owner[state], self.snaps[state] = ident, inst.snapshot()
        inst.states.add(state)
        return state

    @rule(ident=instances, state=states)
    def set_state(self, ident, state):
        if state not in self.snaps:
            return                                        # freed: never used again
        inst, snap = self.live[ident], self.snaps[state]
        answer = self.worker("set_state", id=ident, state=state)   # also in error: it ends it
        self.expect(answer, inst, OK)
        inst.restore(snap)
        if inst.phase != "instantiated":                 # (read from initialization on)
            self.check_outputs(inst, inst.outputs)       # the saved outputs, exactly
        event(f"state restored: {snap['kind']}")

    @rule(target=states, ident=instances, state=states)
    def serialize_and_back(self, ident, state):
        """Serialize through the state's owner, deserialize through any instance."""
        if state not in self.snaps:
            return state                                  # freed: never used again
        owner, inst = self.live[self.owner[state]], self.live[ident]
        blob = self.worker("serialize", id=owner.ident, state=state)
        if owner.phase == "error":
            self.refused_with_error(owner, blob, [])
            return multiple()
        assert blob["status"] == OK and blob["log"] == [], blob
        answer = self.worker("deserialize", id=ident, hex=blob["value"])
        if inst.phase == "error":
            self.refused_with_error(inst, answer, [])
            return multiple()
        assert answer["status"] == OK and answer["log"] == [], answer
        new = answer["value"]
        self.owner[new], self.snaps[new] = ident, self.snaps[state]
        self.live[ident].states.add(new)
        again = self.worker("serialize", id=ident, state=new)
        assert again["value"] == blob["value"]            # the bytes round-trip exactly
        return new

    @precondition(lambda self: self.running())
    @rule(data=st.data(), steps=st.lists(st.tuples(st.floats(-5e4, 5e4), st.floats(1e-6, 0.02),
                                                  st.just(0.0)), min_size=1, max_size=4))
    def rewind_and_replay(self, data, steps):
        """Save, step, restore a serialized copy (here or into another live instance), replay:
        the replay repeats the first run bit for bit."""
        ident = data.draw(st.sampled_from(self.running()))
        target = data.draw(st.sampled_from(sorted(self.live)))
        saved = self.get_state(ident)
        first = []
        for q, h, offset in steps:
            self.step(ident, q, h, offset)
            first.append(dict(self.live[ident].outputs))
        if "error" in (self.live[ident].phase, self.live[target].phase):
            target, copy = ident, saved             # no serialization in error: set it as it is
        else:
            copy = self.serialize_and_back(target, saved)
        self.set_state(target, copy)
        inst = self.live[target]
        for (q, h, offset), want in zip(steps, first):
            self.step(target, q, h, offset)
            assert inst.outputs == want             # and equal to the mirror (checked)
        for state in {saved, copy}:
            self._free_state(state)

    @rule(state=consumes(states))
    def free_state(self, state):
        self._free_state(state)

    # Calls in orders FMI forbids ----------------------------------------------------------------
    @rule(ident=instances, method=st.sampled_from(
        ["exitInitializationMode", "enterInitializationMode", "setupExperiment", "terminate"]),
        now=st.integers(0, 2))
    def call_out_of_order(self, ident, method, now):
        """A call the FMI 2.0 call sequence does not allow now: fmi2Error naming it, nothing
        changed (fmi2Terminate after an error is accepted)."""
        inst = self.live[ident]
        if now:
            return                                          # rarely
        legal = {"instantiated": {"setupExperiment", "enterInitializationMode"},
                 "init": {"exitInitializationMode"}, "run": {"terminate"},
                 "error": {"terminate"}}.get(inst.phase, set())
        if method in legal:
            return
        args = [None, 0.0, None] if method == "setupExperiment" else []
        self.refused_with_error(inst, self.call(inst, method, *args), ["fmi2" + method[0].upper()
                                                                       + method[1:]])

    @invariant()
    def host_alive(self):
        assert self.worker.alive()

    def teardown(self):
        for ident in list(self.live):
            inst = self.live.pop(ident)
            for state in sorted(inst.states):
                if state in self.owner:
                    self.owner.pop(state)
                    self.worker("free_state", id=ident, state=state)
            self.worker("call", id=ident, method="terminate", args=[])
            self.worker("free", id=ident)



def _run_sequences(fmu_dir, worker, examples: int) -> None:
    from fmpy import read_model_description

    md = read_model_description(str(fmu_dir))
    WORKER["vr"] = {v.name: v.valueReference for v in md.modelVariables}
    WORKER["worker"] = worker
    try:
        run_state_machine_as_test(FmiCalls, settings=settings(
            max_examples=examples, stateful_step_count=50, deadline=None, derandomize=True,
            database=None, suppress_health_check=list(HealthCheck)))
    finally:
        WORKER.pop("worker").close()


def test_random_fmi_call_sequences(fmu_dir, tmp_path):
    _run_sequences(fmu_dir, Worker(fmu_dir, tmp_path / "host_stderr.txt"), 150)


def test_random_fmi_call_sequences_in_a_c_host(fmu_dir, c_host, c_host_env):
    _run_sequences(fmu_dir, CWorker(c_host, fmu_dir, c_host_env), 60)
