"""The FMI 2.0 co-simulation base of the project's FMUs (PipePlug and Hammer) on pythonfmu 0.7.

One base, as the Reference-FMUs share one ``fmi2Functions.c``: it holds the variables' values,
the FMI 2.0 call sequence, every refusal and the FMU state. A slave subclasses it, registers
its variables with :meth:`FmiBase._add` and supplies four hooks:

* ``_build(values)``: the model of the parameter values (by name), at
  fmi2ExitInitializationMode and when a state is restored; raises :class:`Refuse`;
* ``_step(model, t, h)``: advance from t by h [s] and return the outputs in registration
  order; raises :class:`Discard` (the model unchanged) or :class:`Refuse`;
* ``_save(model)`` / ``_load(model, saved)``: the model's own state (copies), and its restore;
* optionally ``_refresh()``: outputs that depend on values set before initialization.

The call sequence is FMI 2.0's for co-simulation (``Phase``): fmi2SetupExperiment and
fmi2EnterInitializationMode in "instantiated", fmi2ExitInitializationMode in
"initialization mode", fmi2DoStep and fmi2Terminate in "stepping"; parameters may be set before
initialization, inputs also while stepping, nothing after fmi2Terminate; values may be read in
every phase. A call out of that sequence is refused and changes nothing.

Every refusal is one line naming the variable (or the call), its value and what is allowed:

* fmi2Error (the slave raises :class:`~pipeplug_fmu.pythonfmu07.Refusal`, which the loader gives
  the host as fmi2Error): invalid parameters or options, calls out of order, unknown value
  references, values of the wrong kind, a step past the stopTime, a corrupt FMU state, and a
  step whose outputs would not be finite (the instance is then in error: the host restores a
  state or resets it);
* fmi2Discard (``do_step`` logs the line and returns False): a step that cannot be taken (a
  communication point off the FMU's time, a step size that is not > 0, or what ``_step``
  refuses, such as a non-finite input); the instance is unchanged and goes on.

What happens after an fmi2Error (only fmi2SetFMUstate, fmi2Reset, fmi2Terminate and
fmi2FreeInstance accepted) is enforced by the linux64 loader, which sees every status it
returns; pythonfmu's win64 binary has no such gate.
"""
from __future__ import annotations

import enum
import json
import math
from dataclasses import dataclass

from pythonfmu import Boolean, Fmi2Slave, Integer, Real, String
from pythonfmu.enums import Fmi2Status

from .fmi import decorate_model_description, refusal
from .pythonfmu07 import (
    NOT_UTF8,
    Refusal,
    escape_percent,
    never_raising,
    outlive_the_exception,
    value_reference,
)

__all__ = ["FmiBase", "Phase", "Refuse", "Discard", "TIME_TOLERANCE", "conformity"]

#: Relative tolerance of a communication point against the FMU's time (contract "Stepping").
TIME_TOLERANCE = 1e-9

_TYPES = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}


class Phase(enum.Enum):
    """The FMI 2.0 co-simulation states an instance goes through (error is the loader's)."""

    INSTANTIATED = "instantiated"
    INITIALIZATION = "initialization mode"
    STEPPING = "stepping"
    TERMINATED = "terminated"


_RUNNING = (Phase.STEPPING, Phase.TERMINATED)        # a model exists
_STEPPING = Phase.STEPPING


class Refuse(Exception):
    """Raised by a hook: refuse the call with fmi2Error and this line (``%`` not escaped)."""

    def __init__(self, line: str):
        super().__init__(line)
        self.line = line

    @classmethod
    def of(cls, name: str, value: object, allowed: str) -> Refuse:
        """The refusal of variable ``name`` at ``value`` (see :func:`~pipeplug_fmu.fmi.refusal`)."""
        return cls(refusal(name, value, allowed))


class Discard(Refuse):
    """Raised by ``_step``: the step cannot be taken (fmi2Discard); nothing has changed."""


@dataclass(frozen=True)
class Variable:
    """One registered variable; ``allowed`` says in words which values it takes."""

    vr: int
    name: str
    kind: str                     # "Real", "Integer", "Boolean" or "String"
    causality: str                # "input", "output" or "parameter"
    unit: str | None
    bounds: tuple                 # (min, max) for modelDescription.xml, None where absent
    allowed: str


class FmiBase(Fmi2Slave):
    """The FMI side of a slave (see the module docstring); subclasses set
    :attr:`model_identifier`, register variables in ``_register`` and supply the hooks."""

    #: The FMU's modelIdentifier (its slave class's name).
    model_identifier = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._tables = {kind: {} for kind in _TYPES}       # kind -> {value reference: value}
        self._variables: list[Variable] = []                 # by value reference
        self._phase = Phase.INSTANTIATED      # changed by _enter() only
        self._time = 0.0                  # the FMU's own time [s]
        self._stop_time = None            # stopTime of fmi2SetupExperiment [s], None: none
        self._stop_limit = math.inf       # the last end of a step accepted [s]
        self._model = None                # built at fmi2ExitInitializationMode
        self._register()
        self._index()
        self._refresh()

    # Registration ---------------------------------------------------------------------------
    def _register(self) -> None:
        """Register every variable with :meth:`_add` (subclass)."""
        raise NotImplementedError

    def _add(self, kind, name, start, unit, meaning, causality, variability, initial=None,
             bounds=(None, None), allowed="") -> int:
        """Register one variable of FMI type ``kind``; its value reference."""
        vr = len(self.vars)
        table = self._tables[kind]
        table[vr] = start
        self._variables.append(Variable(vr, name, kind, causality.name, unit, bounds, allowed))
        extra = {} if initial is None else {"initial": initial}
        self.register_variable(_TYPES[kind](name, description=meaning, getter=lambda: table[vr],
                                            causality=causality, variability=variability,
                                            **extra))
        return vr

    def _index(self) -> None:
        """Which value references each phase lets be set, and where the outputs go."""
        inputs = [v for v in self._variables if v.causality == "input"]
        early = inputs + [v for v in self._variables if v.causality == "parameter"]
        self._settable = {
            phase: {kind: frozenset(v.vr for v in group if v.kind == kind) for kind in _TYPES}
            for phase, group in ((Phase.INSTANTIATED, early), (Phase.INITIALIZATION, early),
                                 (Phase.STEPPING, inputs), (Phase.TERMINATED, []))}
        self._output_slots = tuple((self._tables[v.kind], v.vr) for v in self._variables
                                   if v.causality == "output")
        self._by_name = {v.name: v for v in self._variables}
        self._reals = self._tables["Real"]
        self._enter(self._phase)

    def _enter(self, phase: Phase) -> None:
        """Go to ``phase``; keep what the per-step calls look at at hand."""
        self._phase = phase
        self._real_inputs = self._settable[phase]["Real"]     # settable Reals now

    # Hooks of the subclass --------------------------------------------------------------------
    def _build(self, values: dict):
        """The model of ``values`` (name -> value); raises :class:`Refuse`."""
        raise NotImplementedError

    def _step(self, model, t: float, h: float) -> tuple:
        """Advance ``model`` from ``t`` by ``h`` [s]; the outputs in registration order."""
        raise NotImplementedError

    def _save(self, model) -> dict:
        """The model's own state, as copies (default: none)."""
        return {}

    def _load(self, model, saved: dict) -> None:
        """Restore the model's own state from :meth:`_save`; raises :class:`Refuse`."""
        if saved:
            raise Refuse.of("FMUstate", sorted(saved), "no model state")

    def _refresh(self) -> None:
        """Update outputs that depend on values set before initialization (default: none)."""

    # FMI calls: the sequence ------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        try:
            self._expect("fmi2SetupExperiment", Phase.INSTANTIATED)
            if not math.isfinite(start_time):
                raise Refuse.of("startTime", start_time, "finite [s]")
            if stop_time is not None and not (math.isfinite(stop_time)
                                              and stop_time >= start_time):
                raise Refuse.of("stopTime", stop_time,
                                f"finite, >= startTime = {start_time!r} [s]")
            self._time, self._stop_time = float(start_time), stop_time
            self._stop_limit = _stop_limit(stop_time)
            self._refresh()
        except Exception as exc:
            self._fail("fmi2SetupExperiment", exc)

    def enter_initialization_mode(self):
        try:
            self._expect("fmi2EnterInitializationMode", Phase.INSTANTIATED)
            self._enter(Phase.INITIALIZATION)
        except Exception as exc:
            self._fail("fmi2EnterInitializationMode", exc)

    def exit_initialization_mode(self):
        try:
            self._expect("fmi2ExitInitializationMode", Phase.INITIALIZATION)
            self._model = self._build(self._named_values())
            self._enter(Phase.STEPPING)
            self._refresh()
        except Exception as exc:
            self._fail("fmi2ExitInitializationMode", exc)

    def terminate(self):
        try:
            self._expect("fmi2Terminate", Phase.STEPPING)
            self._enter(Phase.TERMINATED)
        except Exception as exc:
            self._fail("fmi2Terminate", exc)

    def do_step(self, current_time, step_size):
        try:
            if self._phase is not _STEPPING:
                self._expect("fmi2DoStep", _STEPPING)
            t, end = self._time, current_time + step_size
            # Written so that NaN fails every test: ``not (x <= bound)`` rather than ``x > bound``.
            if not (abs(current_time - t) <= TIME_TOLERANCE * max(1.0, abs(t))
                    and step_size > 0.0 and end > t and end <= self._stop_limit):
                return self._refuse_step(current_time, step_size)
            out = self._step(self._model, current_time, step_size)
            try:                                   # _all_finite(out), inline: every step
                finite = (total := _fsum(out)) - total == 0.0
            except OverflowError:                  # finite terms whose sum overflows
                finite = True
            except ValueError:                     # inf - inf
                finite = False
            if not finite:
                raise Refuse(self._not_finite(out, current_time, step_size))
        except Discard as exc:
            self.log(escape_percent(exc.line), Fmi2Status.discard)
            return False
        except Exception as exc:
            self._fail("fmi2DoStep", exc)
        for (table, vr), value in zip(self._output_slots, out):
            table[vr] = value
        self._time = end                # the host's point: the contract's rule
        return True

    def _refuse_step(self, current_time, step_size) -> bool:
        """The one reason a step is refused: discard, or error for a step past the stopTime."""
        t = self._time
        if not abs(current_time - t) <= TIME_TOLERANCE * max(1.0, abs(t)):
            raise Discard.of("currentCommunicationPoint", current_time,
                             f"the FMU time {t!r} s within 1e-9*max(1, |t|)")
        if not step_size > 0.0:
            raise Discard.of("communicationStepSize", step_size, "> 0 [s]")
        if not current_time + step_size > t:
            raise Discard.of("currentCommunicationPoint + communicationStepSize",
                             current_time + step_size, f"> the FMU time {t!r} s")
        raise Refuse.of("currentCommunicationPoint + communicationStepSize",
                        current_time + step_size,
                        f"<= stopTime = {self._stop_time!r} s (+1e-9*max(1, |stopTime|))")

    def _not_finite(self, out, t, h) -> str:
        """The refusal of a step whose outputs are not all finite (the first one named)."""
        outputs = [v for v in self._variables if v.causality == "output"]
        name, value = next((v.name, x) for v, x in zip(outputs, out) if not _all_finite((x,)))
        return refusal(name, value, f"finite; the step from t = {t!r} s by {h!r} s exceeded "
                                    f"what the model computes (set a saved FMU state or reset)")

    # Getters and setters ------------------------------------------------------------------
    def get_real(self, vrs):
        try:
            return list(map(self._reals.__getitem__, vrs))
        except Exception:
            self._refuse_get(vrs, "Real")

    def get_integer(self, vrs):
        try:
            return list(map(self._tables["Integer"].__getitem__, vrs))
        except Exception:
            self._refuse_get(vrs, "Integer")

    def get_boolean(self, vrs):
        try:
            return list(map(self._tables["Boolean"].__getitem__, vrs))
        except Exception:
            self._refuse_get(vrs, "Boolean")

    def get_string(self, vrs):
        try:
            return list(map(self._tables["String"].__getitem__, vrs))
        except Exception:
            self._refuse_get(vrs, "String")

    def _refuse_get(self, vrs, kind):
        table = self._tables[kind]
        bad = next((vr for vr in vrs if vr not in table), None)
        self._fail(f"fmi2Get{kind}", Refuse.of(
            "valueReference", value_reference(bad) if bad is not None else bad,
            f"a {kind} variable of {self.model_identifier}"))

    def set_real(self, vrs, values):
        if len(vrs) == 1 and vrs[0] in self._real_inputs:
            self._reals[vrs[0]] = values[0]               # the input, every step: first
            if self._phase is not _STEPPING:
                self._refresh()
            return
        self._set("Real", vrs, values)

    def set_integer(self, vrs, values):
        self._set("Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self._set("Boolean", vrs, values)

    def set_string(self, vrs, values):
        self._set("String", vrs, values)

    def _set(self, kind, vrs, values):
        """Set all of ``values`` or, refusing the first one that cannot be set, none."""
        try:
            settable = self._settable[self._phase][kind]
            for vr, value in zip(vrs, values):
                if vr not in settable:
                    raise self._unsettable(kind, vr, value)
                if kind == "String" and (not isinstance(value, str)
                                         or value.startswith(NOT_UTF8)):         # P7
                    raise Refuse.of(self._variables[vr].name, _shown(value),
                                    f"UTF-8 text ({self._variables[vr].allowed})")
            table = self._tables[kind]
            for vr, value in zip(vrs, values):
                table[vr] = value
            if self._phase is not _STEPPING:
                self._refresh()
        except Exception as exc:
            self._fail(f"fmi2Set{kind}", exc)

    def _unsettable(self, kind, vr, value) -> Refuse:
        """Why ``vr`` cannot be set to ``value`` with fmi2Set<kind> now."""
        var = self._variables[vr] if 0 <= vr < len(self._variables) else None
        if var is None or var.kind != kind:
            return Refuse.of("valueReference", value_reference(vr),
                             f"a settable {kind} variable of {self.model_identifier}")
        if var.causality == "output":
            return Refuse.of(var.name, value, f"a settable variable ({var.name} is an output)")
        if self._phase is Phase.TERMINATED:
            return Refuse.of(var.name, value, "no change after fmi2Terminate")
        return Refuse.of(var.name, value, f"no change after initialization (fixed parameter; "
                                          f"it stays {self._tables[kind][vr]!r})")

    # FMU state -------------------------------------------------------------------------------
    def _state_mark(self) -> str:
        """What a state of this FMU and build is marked with (the module name has the build's
        tag)."""
        return f"{self.model_identifier} state of {type(self).__module__}"

    def _get_fmu_state(self):
        try:
            model = self._save(self._model) if self._phase in _RUNNING else None
            values = {v.name: _PLAIN[v.kind](self._tables[v.kind][v.vr])
                      for v in self._variables}            # plain Python: JSON-ready
            return {"mark": self._state_mark(), "phase": self._phase.value, "time": self._time,
                    "stop": self._stop_time, "values": values, "model": model}
        except Exception as exc:
            self._fail("fmi2GetFMUstate", exc)

    def _set_fmu_state(self, state):
        try:
            phase, time, stop, values = self._checked_state(state)
            model = None
            if phase in _RUNNING:
                model = self._build({n: values[n] for n, v in self._by_name.items()
                                     if v.causality == "parameter"})
                self._load(model, state["model"])
        except Exception as exc:
            self._fail("fmi2SetFMUstate", exc)
        for name, value in values.items():              # all checked: now change everything
            var = self._by_name[name]
            self._tables[var.kind][var.vr] = value
        self._time, self._stop_time = time, stop
        self._enter(phase)
        self._stop_limit, self._model = _stop_limit(stop), model

    def _checked_state(self, state) -> tuple:
        """Phase, time, stop time and values of a state; raises :class:`Refuse` with what is
        wrong with it."""
        allowed = (f"a state of this {self.model_identifier} build from fmi2GetFMUstate or "
                   f"fmi2DeSerializeFMUstate")
        if not isinstance(state, dict) or state.get("mark") != self._state_mark():
            reason = state.get("invalid") if isinstance(state, dict) else None
            raise Refuse.of("FMUstate", reason or _mark_of(state), allowed)
        try:
            phase = Phase(state["phase"])
            time, stop, values = state["time"], state["stop"], dict(state["values"])
        except Exception as exc:
            raise Refuse.of("FMUstate", f"{type(exc).__name__}: {exc}", allowed) from None
        if type(time) is not float or not math.isfinite(time):
            raise Refuse.of("FMUstate time", time, "finite [s]")
        if stop is not None and not (type(stop) is float and math.isfinite(stop)):
            raise Refuse.of("FMUstate stopTime", stop, "None or finite [s]")
        if set(values) != set(self._by_name):
            raise Refuse.of("FMUstate variables", sorted(set(values) ^ set(self._by_name)),
                            f"exactly the variables of {self.model_identifier}")
        for name, value in values.items():
            var = self._by_name[name]
            if not _of_kind(value, var.kind) or (var.causality == "output"
                                                 and not _all_finite((value,))):
                raise Refuse.of(f"FMUstate {name}", value, f"a {var.kind}" + (
                    ", finite" if var.causality == "output" else ""))
        if (phase in _RUNNING) != isinstance(state.get("model"), dict):
            raise Refuse.of("FMUstate model", type(state.get("model")).__name__,
                            "the model's state once initialized, none before")
        return phase, time, stop, values

    @classmethod
    def _model_to_bytes(cls, saved: dict) -> bytes:
        """The model's own state as bytes (default: JSON)."""
        return json.dumps(saved).encode()

    @classmethod
    def _model_from_bytes(cls, data: bytes) -> dict:
        """Inverse of :meth:`_model_to_bytes`."""
        return json.loads(data.decode())

    @classmethod
    @never_raising(lambda exc: json.dumps({"invalid": f"{type(exc).__name__}: {exc}"}).encode())
    def _fmu_state_to_bytes(cls, state):
        """A state as bytes: its JSON without the model, a newline, the model's bytes."""
        head = dict(state)
        model = head.pop("model", None)
        head["model"] = model is not None
        return (json.dumps(head).encode() + b"\n"
                + (cls._model_to_bytes(model) if model is not None else b""))

    @classmethod
    @never_raising(lambda exc: {"invalid": f"{type(exc).__name__}: {exc}"})
    def _fmu_state_from_bytes(cls, data):
        head, _, blob = bytes(data).partition(b"\n")
        state = json.loads(head.decode())
        if not isinstance(state, dict):
            raise ValueError("not a state")
        state["model"] = cls._model_from_bytes(blob) if state.get("model") is True else None
        return state

    # Refusals ---------------------------------------------------------------------------------
    def _expect(self, call: str, phase: Phase) -> None:
        """Refuse ``call`` unless the instance is in ``phase``."""
        if self._phase is not phase:
            raise Refuse(f"{call} is not allowed in {self._phase.value}; allowed: in "
                         f"{phase.value} only (the FMI 2.0 call sequence)")

    def _fail(self, call: str, exc: Exception):
        """Refuse ``call`` with fmi2Error: the line of a :class:`Refuse`, or what went wrong."""
        if isinstance(exc, Refusal):
            raise exc
        line = exc.line if isinstance(exc, Refuse) else (
            f"{call} failed: {type(exc).__name__}: {exc}")
        outlive_the_exception(self)                        # P2
        raise Refusal(self.model_identifier, escape_percent(line)) from None

    def _named_values(self) -> dict:
        """Every variable's value by name."""
        return {v.name: self._tables[v.kind][v.vr] for v in self._variables}

    # modelDescription.xml (build time only) ------------------------------------------------
    def to_xml(self, model_options=None):
        root = super().to_xml(model_options or {})
        decorate_model_description(root, [(v.name, v.unit, v.bounds) for v in self._variables])
        return root


def _stop_limit(stop_time) -> float:
    """The last end of a step allowed by ``stop_time`` [s] (inf without one)."""
    if stop_time is None:
        return math.inf
    return stop_time + TIME_TOLERANCE * max(1.0, abs(stop_time))


_fsum = math.fsum


def _all_finite(values) -> bool:
    """True when every number of ``values`` is finite (bools and ints count as finite)."""
    try:
        total = math.fsum(values)
    except OverflowError:           # finite terms whose sum overflows
        return True
    except ValueError:              # inf - inf
        return False
    return total - total == 0.0


_NUMBER_KINDS = {"Real": "f", "Integer": "i", "Boolean": "b"}
_PLAIN = {"Real": float, "Integer": int, "Boolean": bool, "String": str}


def _of_kind(value, kind: str) -> bool:
    """Whether ``value`` is a value of FMI type ``kind`` (a bool is no Integer, nor a Real)."""
    if kind == "String":
        return type(value) is str
    return _number_kind(value) == _NUMBER_KINDS[kind]


def _shown(value) -> object:
    """A String value as a refusal shows it: the bytes behind the loader's mark (P7)."""
    if isinstance(value, str) and value.startswith(NOT_UTF8):
        hexed = value[len(NOT_UTF8):]
        try:
            return bytes.fromhex(hexed[:400]) + (b"..." if len(hexed) > 400 else b"")
        except ValueError:
            return value
    return value


def _mark_of(state) -> str:
    """What a refused state is, in a few words."""
    if isinstance(state, dict):
        return repr(state.get("mark", "a state without a mark"))
    return type(state).__name__


def conformity(reference: dict, given) -> str | None:
    """What makes ``given`` unlike ``reference`` (a model state: names to numbers and arrays),
    None when it conforms: the same names, numbers of the same type, arrays of the same kind,
    dimensions and trailing shape; finite wherever ``reference`` is (a model may mark a field
    unset with NaN, as the exact solver's load before its first step)."""
    if not isinstance(given, dict) or set(given) != set(reference):
        names = sorted(set(given) ^ set(reference)) if isinstance(given, dict) else given
        return f"fields {names!r} differ"
    for name, ref in reference.items():
        value = given[name]
        if hasattr(ref, "dtype"):
            if not (hasattr(value, "dtype") and value.dtype.kind == ref.dtype.kind
                    and value.ndim == ref.ndim and value.shape[1:] == ref.shape[1:]
                    and (value.ndim == 0 or value.shape[0] == ref.shape[0]
                         or ref.dtype.kind == "i")):
                return f"field {name!r} is not an array like {ref.dtype}{list(ref.shape)}"
            if value.dtype.kind == "f" and _all_finite(ref.ravel()) and not _all_finite(
                    value.ravel()):
                return f"field {name!r} holds a value that is not finite"
        elif _number_kind(value) != _number_kind(ref) or (
                _all_finite((ref,)) and not _all_finite((value,))):
            return f"field {name!r} = {value!r} is not a number like {ref!r}"
    return None


def _number_kind(x) -> str | None:
    """"b", "i" or "f" for a bool, integer or real number (Python's or numpy's), else None."""
    kind = getattr(x, "dtype", None)
    if kind is not None:
        return kind.kind if x.ndim == 0 else None
    return {bool: "b", int: "i", float: "f"}.get(type(x))
