"""The FMI co-simulation base of the project's FMUs (PipePlug and Hammer), FMI 2.0 and 3.0.

One base, as the Reference-FMUs share one ``fmi2Functions.c``: it holds the variables' values,
the FMI 2.0 call sequence (:mod:`~pipeplug_fmu.sequence`), every refusal and the FMU state
(:mod:`~pipeplug_fmu.fmu_state`). A slave subclasses it, registers its variables with
:meth:`FmiBase._add` and supplies four hooks:

* ``_build(values)``: the model of the parameter values (by name), at
  fmi2ExitInitializationMode and when a state is restored; raises :class:`Refuse`;
* ``_step(model, t, h)``: advance from t by h [s] and return the outputs in registration
  order; raises :class:`Discard` (the model unchanged) or :class:`Refuse`;
* ``_save(model)`` / ``_load(model, saved)``: the model's own state (copies), and its restore;
* optionally ``_refresh()``: outputs that depend on values set before initialization.

What differs between FMI versions is a binding mixed in after the slave: :mod:`pipeplug_fmu.fmi2`
(pythonfmu 0.7) and :mod:`pipeplug_fmu.fmi3` (pythonfmu3). It declares each variable to its
library (:meth:`FmiBase._declare`), maps the getters and setters of its FMI types onto
:meth:`FmiBase._get` and :meth:`FmiBase._set`, and names the calls in refusals (``fmi2DoStep``,
``fmi3DoStep``). This module imports neither library.

The call sequence is FMI 2.0's for co-simulation (``Phase``; FMI 3.0's co-simulation without
event mode maps onto it, its start and stop time coming with fmi3EnterInitializationMode and
structural parameters settable with the parameters): fmi2SetupExperiment and
fmi2EnterInitializationMode in "instantiated", fmi2ExitInitializationMode in
"initialization mode", fmi2DoStep and fmi2Terminate in "stepping"; parameters may be set before
initialization, inputs also while stepping, nothing after fmi2Terminate; values may be read
from initialization mode on (FMI 3.0: also before it, as its state machine allows; the binding
checks). A call out of that sequence is refused and changes nothing.

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

import math
from dataclasses import dataclass

from .fmi import refusal
from .fmu_state import StateHandling, conformity
from .pythonfmu07 import NOT_UTF8, Refusal, outlive_the_exception, value_reference
from .sequence import TIME_TOLERANCE, Discard, Phase, Refuse, all_finite, stop_limit

__all__ = ["FmiBase", "Phase", "Refuse", "Discard", "TIME_TOLERANCE", "conformity", "Variable"]

#: The project's value kinds (FMI 2.0 names; UInt64 only in FMI 3.0).
KINDS = ("Real", "Integer", "Boolean", "String", "UInt64")
_STEPPING = Phase.STEPPING


@dataclass(frozen=True)
class Variable:
    """One registered variable; ``allowed`` says in words which values it takes."""

    vr: int
    name: str
    kind: str                     # one of KINDS
    causality: str                # "input", "output", "parameter" or "structuralParameter"
    unit: str | None
    bounds: tuple                 # (min, max) for modelDescription.xml, None where absent
    allowed: str
    size_of: int | None = None    # an array sized by this structural parameter's value


class FmiBase(StateHandling):
    """The FMI side of a slave (see the module docstring); subclasses set
    :attr:`model_identifier`, register variables in ``_register`` and supply the hooks; a
    binding supplies what belongs to its FMI version."""

    #: The FMU's modelIdentifier (its slave class's name).
    model_identifier = ""
    # The binding (after this class in the FMU class's bases, so nothing here may shadow it)
    # supplies: FMI (its calls' prefix, "fmi2"), SEQUENCE (its call sequence in words), DISCARD
    # (its status of a discarded step), STATE ("FMUstate" or "FMUState", as in its calls),
    # DESERIALIZE (its deserializing call without the prefix), ARRAYS
    # (whether array variables exist),
    # TYPE_NAMES (its type name by kind, for call names), _escape(line) (a line as its library
    # hands it to the host), _experiment (its DefaultExperiment),
    # _declare(var, meaning, getter, variability, initial) (register a variable with it) and
    # _register_binding() (register the variables its version requires, after the slave's).

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._tables = {kind: {} for kind in KINDS}       # kind -> {value reference: value}
        self._variables: list[Variable] = []                 # by value reference
        self._phase = Phase.INSTANTIATED      # changed by _enter() only
        self._time = 0.0                  # the FMU's own time [s]
        self._stop_time = None            # stopTime of fmi2SetupExperiment [s], None: none
        self._stop_limit = math.inf       # the last end of a step accepted [s]
        self._model = None                # built at fmi2ExitInitializationMode
        self._register()
        self._register_binding()
        self._index()
        self._refresh()

    # Registration ---------------------------------------------------------------------------
    def _register(self) -> None:
        """Register every variable with :meth:`_add` (subclass)."""
        raise NotImplementedError

    def _add(self, kind, name, start, unit, meaning, causality, variability, initial=None,
             bounds=(None, None), allowed="", size_of=None) -> int:
        """Register one variable of kind ``kind`` (:data:`KINDS`; causality, variability and
        initial by their FMI names; ``size_of``: the value reference of the structural
        parameter giving an array's length); its value reference."""
        vr = len(self.vars)
        table = self._tables[kind]
        table[vr] = start
        var = Variable(vr, name, kind, causality, unit, bounds, allowed, size_of)
        self._variables.append(var)
        self._declare(var, meaning, lambda: table[vr], variability, initial)
        return vr

    def _call(self, name: str) -> str:
        """The FMI function ``name`` of this version (``DoStep`` -> ``fmi2DoStep``)."""
        return self.FMI + name

    def _index(self) -> None:
        """Which value references each phase lets be set, and where the outputs go."""
        inputs = [v for v in self._variables if v.causality == "input"]
        early = inputs + [v for v in self._variables
                          if v.causality in ("parameter", "structuralParameter")]
        self._settable = {
            phase: {kind: frozenset(v.vr for v in group if v.kind == kind) for kind in KINDS}
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
            raise Refuse.of(self.STATE, sorted(saved), "no model state")

    def _refresh(self) -> None:
        """Update outputs that depend on values set before initialization (default: none)."""

    # FMI calls: the sequence ------------------------------------------------------------------
    def _setup(self, call, start_time, stop_time=None):
        """The experiment's start and stop time [s] (FMI 2.0: fmi2SetupExperiment)."""
        try:
            self._expect(call, Phase.INSTANTIATED)
            if not math.isfinite(start_time):
                raise Refuse.of("startTime", start_time, "finite [s]")
            if stop_time is not None and not (math.isfinite(stop_time)
                                              and stop_time >= start_time):
                raise Refuse.of("stopTime", stop_time,
                                f"finite, >= startTime = {start_time!r} [s]")
            self._time, self._stop_time = float(start_time), stop_time
            self._stop_limit = stop_limit(stop_time)
            self._refresh()
        except Exception as exc:
            self._fail(call, exc)

    def enter_initialization_mode(self):
        call = self._call("EnterInitializationMode")
        try:
            self._expect(call, Phase.INSTANTIATED)
            self._enter(Phase.INITIALIZATION)
        except Exception as exc:
            self._fail(call, exc)

    def exit_initialization_mode(self):
        call = self._call("ExitInitializationMode")
        try:
            self._expect(call, Phase.INITIALIZATION)
            self._model = self._build(self._named_values())
            self._enter(Phase.STEPPING)
            self._refresh()
        except Exception as exc:
            self._fail(call, exc)

    def terminate(self):
        call = self._call("Terminate")
        try:
            self._expect(call, Phase.STEPPING)
            self._enter(Phase.TERMINATED)
        except Exception as exc:
            self._fail(call, exc)

    def do_step(self, current_time, step_size):
        try:
            if self._phase is not _STEPPING:
                self._expect(self._call("DoStep"), _STEPPING)
            t, end = self._time, current_time + step_size
            # Written so that NaN fails every test: ``not (x <= bound)`` rather than ``x > bound``.
            if not (abs(current_time - t) <= TIME_TOLERANCE * max(1.0, abs(t))
                    and 0.0 < step_size < _INF and end > t and end <= self._stop_limit):
                return self._refuse_step(current_time, step_size)
            out = self._step(self._model, current_time, step_size)
            try:                                   # _all_finite(out), inline: every step
                finite = (total := _fsum(out)) - total == 0.0
            except OverflowError:                  # finite terms whose sum overflows
                finite = True
            except ValueError:                     # inf - inf
                finite = False
            except TypeError:                      # array outputs (FMI 3.0)
                finite = all_finite(_flat(out))
            if not finite:
                raise Refuse(self._not_finite(out, current_time, step_size))
        except Discard as exc:
            self.log(self._escape(exc.line), self.DISCARD)
            return False
        except Exception as exc:
            self._fail(self._call("DoStep"), exc)
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
        if not 0.0 < step_size < _INF:
            raise Discard.of("communicationStepSize", step_size, "> 0, finite [s]")
        if not current_time + step_size > t:
            raise Discard.of("currentCommunicationPoint + communicationStepSize",
                             current_time + step_size, f"> the FMU time {t!r} s")
        raise Refuse.of("currentCommunicationPoint + communicationStepSize",
                        current_time + step_size,
                        f"<= stopTime = {self._stop_time!r} s (+1e-9*max(1, |stopTime|))")

    def _not_finite(self, out, t, h) -> str:
        """The refusal of a step whose outputs are not all finite (the first one named)."""
        outputs = [v for v in self._variables if v.causality == "output"]
        name, value = next((v.name, x) for v, x in zip(outputs, out)
                           if not all_finite(_flat((x,))))
        return refusal(name, value, f"finite; the step from t = {t!r} s by {h!r} s exceeded "
                                    f"what the model computes (set a saved FMU state or reset)")

    # Getters and setters (the binding's getters and setters of its FMI types call these) -----
    def _get(self, kind, vrs):
        """The values of ``vrs`` of ``kind``, array elements in order."""
        table = self._tables[kind]
        try:
            values = [table[vr] for vr in vrs]
        except Exception:
            self._refuse_get(vrs, kind)
        if any(type(x) is list for x in values):
            return list(_flat(values))
        return values

    def _refuse_get(self, vrs, kind):
        table = self._tables[kind]
        bad = next((vr for vr in vrs if vr not in table), None)
        self._fail(self._call(f"Get{self.TYPE_NAMES[kind]}"), Refuse.of(
            "valueReference", value_reference(bad) if bad is not None else bad,
            f"a {self.TYPE_NAMES[kind]} variable of {self.model_identifier}"))

    def _set_input(self, kind, vrs, values) -> None:
        """Set ``values``: one input of ``kind`` while stepping (every step: first), else all."""
        if len(vrs) == 1 and vrs[0] in self._real_inputs:
            self._reals[vrs[0]] = values[0]
            if self._phase is not _STEPPING:
                self._refresh()
            return
        self._set(kind, vrs, values)

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
                self._check_value(self._variables[vr], value)
            table = self._tables[kind]
            for vr, value in zip(vrs, values):
                table[vr] = value
            if self._phase is not _STEPPING:
                self._refresh()
        except Exception as exc:
            self._fail(self._call(f"Set{self.TYPE_NAMES[kind]}"), exc)

    def _check_value(self, var: Variable, value) -> None:
        """Refuse a value that can never be set (default: none; ranges are checked at
        initialization)."""

    def _unsettable(self, kind, vr, value) -> Refuse:
        """Why ``vr`` cannot be set to ``value`` with its setter now."""
        var = self._variables[vr] if 0 <= vr < len(self._variables) else None
        if var is None or var.kind != kind:
            return Refuse.of("valueReference", value_reference(vr),
                             f"a settable {self.TYPE_NAMES[kind]} variable of "
                             f"{self.model_identifier}")
        if var.causality == "output":
            return Refuse.of(var.name, value, f"a settable variable ({var.name} is an output)")
        if self._phase is Phase.TERMINATED:
            return Refuse.of(var.name, value, f"no change after {self._call('Terminate')}")
        return Refuse.of(var.name, value, f"no change after initialization (fixed parameter; "
                                          f"it stays {self._tables[kind][vr]!r})")

    # Refusals ---------------------------------------------------------------------------------
    def _expect(self, call: str, phase: Phase) -> None:
        """Refuse ``call`` unless the instance is in ``phase``."""
        if self._phase is not phase:
            raise Refuse(f"{call} is not allowed in {self._phase.value}; allowed: in "
                         f"{phase.value} only ({self.SEQUENCE})")

    def _fail(self, call: str, exc: Exception):
        """Refuse ``call`` with fmi2Error: the line of a :class:`Refuse`, or what went wrong."""
        if isinstance(exc, Refusal):
            raise exc
        line = exc.line if isinstance(exc, Refuse) else (
            f"{call} failed: {type(exc).__name__}: {exc}")
        outlive_the_exception(self)                        # P2
        raise Refusal(self.model_identifier, self._escape(line)) from None

    def _named_values(self) -> dict:
        """Every variable's value by name."""
        return {v.name: self._tables[v.kind][v.vr] for v in self._variables}


_fsum = math.fsum
_INF = math.inf


def _flat(values):
    """The numbers of ``values``, array elements in order."""
    for x in values:
        if type(x) is list:
            yield from x
        else:
            yield x


def _shown(value) -> object:
    """A String value as a refusal shows it: the bytes behind the loader's mark (P7)."""
    if isinstance(value, str) and value.startswith(NOT_UTF8):
        hexed = value[len(NOT_UTF8):]
        try:
            return bytes.fromhex(hexed[:400]) + (b"..." if len(hexed) > 400 else b"")
        except ValueError:
            return value
    return value


