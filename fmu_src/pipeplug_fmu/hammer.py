"""Hammer: the FMI 2.0 co-simulation slave of a train of rectangular blows (pythonfmu).

The train and its parameter table are :mod:`~pipeplug_fmu.blows`; this adapter registers them,
checks them at ``exitInitializationMode`` and sets its one output from the train at each
communication point.

Output timing: Q at the FMU's current time t is the force for the step that starts at t, so a
host that steps Hammer and PipePlug on a grid containing the blow edges hands PipePlug the exact
train with no one-step delay:

* in initialization mode and right after ``exitInitializationMode``: Q = force(t_start), the
  start time of ``fmi2SetupExperiment`` (from the parameter values set so far; 0 while they are
  invalid);
* after ``doStep(t, h)``: Q = force(t + h), the force on [t + h, next point).

Refusals follow PipePlug's conventions (see :mod:`pipeplug_fmu.slave`): invalid parameters, a
fixed parameter set after initialization, a get or set of an unknown value reference raise the
instance's single exception, a :class:`HammerRefusal` (the loader gives the host its line with
fmi2Error); a doStep before initialization, off the FMU's time, of a non-positive length or past
the stopTime is one log line and fmi2Discard. Like PipePlug it keeps its own time and adopts the
host's within ``1e-9 max(1, |t|)``.

Runs only inside a built Hammer.fmu (see :mod:`pipeplug_fmu.build`), in a package whose name
carries the build's content digest.
"""
from __future__ import annotations

import json
import math
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import (
    DefaultExperiment,
    Fmi2Causality,
    Fmi2Initial,
    Fmi2Slave,
    Fmi2Variability,
    Integer,
    Real,
)
from pythonfmu.enums import Fmi2Status

from .blows import (
    DEFAULT_EXPERIMENT,
    DESCRIPTION,
    EDGE_TOLERANCE,
    OUTPUT,
    PARAMETERS,
    BlowTrainError,
    check,
)
from .fmi import Refusal, decorate_model_description, escape_percent, outlive_the_exception, refusal

_Q_VR = 0                                         # the output, registered first
_PARAMETER_VRS = {p.name: vr for vr, p in enumerate(PARAMETERS, start=1)}
_VR_RANGE = 2 ** 32     # pythonfmu passes fmi2ValueReference (unsigned) as a C int: shown mod this
_STATE_MARK = "Hammer state of " + __name__       # of this build, not of another FMU


class HammerRefusal(Refusal):
    """Hammer's refusal (its ``repr`` starts with ``HammerRefusal: ``, which the loader reads)."""


class Hammer(Fmi2Slave):
    author = "PipePlug contributors"
    license = "MIT"
    description = DESCRIPTION

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.default_experiment = DefaultExperiment(*DEFAULT_EXPERIMENT)
        self._values = {vr: p.default for vr, p in zip(_PARAMETER_VRS.values(), PARAMETERS)}
        self._train = None          # the checked train, from exitInitializationMode on
        self._q = 0.0               # Q once initialized
        self._time = 0.0            # the FMU's own time [s]
        self._stop_limit = math.inf
        self._dead = False          # True after the instance's one exception
        name, unit, meaning = OUTPUT
        self.register_variable(Real(name, description=meaning, getter=self._output,
                                    causality=Fmi2Causality.output,
                                    variability=Fmi2Variability.discrete,
                                    initial=Fmi2Initial.calculated))
        for p, vr in zip(PARAMETERS, _PARAMETER_VRS.values()):
            kind = Real if p.kind == "Real" else Integer
            self.register_variable(kind(p.name, description=f"{p.description} [allowed: "
                                        f"{p.allowed}]", getter=lambda vr=vr: self._values[vr],
                                        causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.fixed))

    # FMI calls ------------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if self._dead:
            return
        self._time = float(start_time)
        self._stop_limit = math.inf if stop_time is None else (
            stop_time + EDGE_TOLERANCE * max(1.0, abs(stop_time)))

    def exit_initialization_mode(self):
        if self._dead or self._train is not None:
            return
        try:
            self._train = check(self._named_values())
        except BlowTrainError as exc:
            self._refuse(refusal(exc.name, exc.value, exc.allowed))
            return
        self._q = self._train.force(self._time)

    def do_step(self, current_time, step_size):
        t = self._time
        # Written so that NaN fails every test: ``not (x <= bound)`` rather than ``x > bound``.
        if (self._train is None or not abs(current_time - t) <= EDGE_TOLERANCE * max(1.0, abs(t))
                or not step_size > 0.0 or not current_time + step_size <= self._stop_limit
                or not current_time + step_size > t):
            return self._refuse_step(current_time, step_size)
        self._time = current_time + step_size          # the host's point (see the docstring)
        self._q = self._train.force(self._time)
        return True

    def _refuse_step(self, current_time, step_size) -> bool:
        """Log why a doStep is refused (quietly once dead) and return False (discard)."""
        if self._dead:
            return False
        t = self._time
        if self._train is None:
            line = "doStep is not allowed before exitInitializationMode"
        elif not abs(current_time - t) <= EDGE_TOLERANCE * max(1.0, abs(t)):
            line = refusal("currentCommunicationPoint", current_time,
                           f"the FMU time {t!r} s within 1e-9*max(1, |t|)")
        elif not step_size > 0.0:
            line = refusal("communicationStepSize", step_size, "> 0 s")
        elif not current_time + step_size > t:
            line = refusal("currentCommunicationPoint + communicationStepSize",
                           current_time + step_size, f"> the FMU time {t!r} s")
        else:
            line = refusal("currentCommunicationPoint + communicationStepSize",
                           current_time + step_size, f"<= stopTime (+1e-9*max(1, |stopTime|)), "
                                                     f"here <= {self._stop_limit!r} s")
        self.log(escape_percent(line), Fmi2Status.discard)
        return False

    def _output(self) -> float:
        """Q: the step's force once initialized; before, the force the current values give."""
        if self._train is not None or self._dead:
            return self._q
        try:
            return check(self._named_values()).force(self._time)
        except BlowTrainError:
            return 0.0                # refused at exitInitializationMode

    def _named_values(self) -> dict:
        return {p.name: self._values[vr] for p, vr in zip(PARAMETERS, _PARAMETER_VRS.values())}

    # Getters and setters --------------------------------------------------------------------
    def get_real(self, vrs):
        return [self._get(vr, "Real") for vr in vrs]

    def get_integer(self, vrs):
        return [self._get(vr, "Integer") for vr in vrs]

    def get_boolean(self, vrs):
        return [self._get(vr, "Boolean") for vr in vrs]

    def get_string(self, vrs):
        return [self._get(vr, "String") for vr in vrs]

    def _get(self, vr, kind):
        if self._kind(vr) != kind:
            self._refuse(refusal("valueReference", vr % _VR_RANGE, f"a {kind} variable of Hammer"))
            return _EMPTY[kind]
        return self._output() if vr == _Q_VR else self._values[vr]

    def set_real(self, vrs, values):
        self._set(vrs, values, "Real")

    def set_integer(self, vrs, values):
        self._set(vrs, values, "Integer")

    def set_boolean(self, vrs, values):
        self._set(vrs, values, "Boolean")

    def set_string(self, vrs, values):
        self._set(vrs, values, "String")

    def _set(self, vrs, values, kind):
        for vr, value in zip(vrs, values):
            if self._dead:
                return
            if vr == _Q_VR or self._kind(vr) != kind:
                known = self._kind(vr) == kind
                self._refuse(refusal("Q" if known else "valueReference",
                                    value if known else vr % _VR_RANGE,
                                    f"a settable {kind} variable (a parameter)"))
            elif self._train is not None:
                self._refuse(refusal(PARAMETERS[vr - 1].name, value,
                                    f"no change after initialization (fixed parameter; it "
                                    f"stays {self._values[vr]!r})"))
            else:
                self._values[vr] = value

    @staticmethod
    def _kind(vr) -> str | None:
        """The FMI type of value reference ``vr`` (None: no such variable)."""
        if vr == _Q_VR:
            return "Real"
        return PARAMETERS[vr - 1].kind if 1 <= vr <= len(PARAMETERS) else None

    # The single exception -------------------------------------------------------------------
    def _refuse(self, line: str) -> None:
        """Raise the instance's one exception, carrying ``line``; quiet once that is done
        (see :meth:`pipeplug_fmu.slave.PipePlug._refuse` for why it is not also queued)."""
        if self._dead:
            return
        self._dead, self._train = True, None
        outlive_the_exception(self)
        raise HammerRefusal(escape_percent(line))

    # State ----------------------------------------------------------------------------------
    def _get_fmu_state(self):
        """The whole state (a new dict of immutable values): time, stop limit, parameters,
        whether initialized, Q."""
        if self._dead:
            return {}
        return {"mark": _STATE_MARK, "time": self._time, "stop_limit": self._stop_limit,
                "initialized": self._train is not None, "q": self._q,
                "values": [self._values[vr] for vr in _PARAMETER_VRS.values()]}

    def _set_fmu_state(self, state):
        if self._dead:
            return
        try:
            if state.get("mark") != _STATE_MARK:
                raise ValueError("not a state of this Hammer build")
            values = dict(zip(_PARAMETER_VRS.values(), state["values"], strict=True))
            train = check({p.name: values[vr] for p, vr in zip(PARAMETERS, values)}) if (
                state["initialized"]) else None
            time, stop_limit, q = float(state["time"]), float(state["stop_limit"]), state["q"]
        except Exception as exc:
            self._refuse(refusal("FMUstate", f"{type(exc).__name__}: {exc}", "a state saved by "
                                "fmi2GetFMUstate or fmi2DeSerializeFMUstate of Hammer"))
            return
        self._values, self._train = values, train
        self._time, self._stop_limit, self._q = time, stop_limit, float(q)

    @staticmethod
    def _fmu_state_to_bytes(state):
        return json.dumps(state).encode()            # floats round-trip; inf as Infinity

    @staticmethod
    def _fmu_state_from_bytes(data):
        try:
            state = json.loads(bytes(data).decode())
            return state if isinstance(state, dict) else {}
        except Exception:
            return {}                 # refused when it is loaded

    # modelDescription.xml (build time only) ----------------------------------------------
    def to_xml(self, model_options=None):
        import pipeplug  # the build's core: the project's version (not shipped)

        root = super().to_xml(model_options or {})
        root.set("version", pipeplug.__version__)
        name, unit, _ = OUTPUT
        decorate_model_description(root, [(name, unit, (None, None))] + [
            (p.name, p.unit, (p.lower, None)) for p in PARAMETERS])
        # Q is initial="calculated" (it depends on the parameters): an InitialUnknown, on all
        # knowns (no dependencies attribute).
        SubElement(root.find("ModelStructure"), "InitialUnknowns").append(
            Element("Unknown", index=str(_Q_VR + 1)))
        return root


_EMPTY = {"Real": 0.0, "Integer": 0, "Boolean": False, "String": ""}
