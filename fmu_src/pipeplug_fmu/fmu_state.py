"""FMU states of the FMI base (:mod:`pipeplug_fmu.base`): taken, set and serialized.

A state is a dict of plain values: a mark of the FMU and build, the phase, the FMU's time and
stopTime, every variable's value by name and, once initialized, the model's own state (the
slave's ``_save``). Setting one checks it whole before anything changes (the mark, the phase,
finite times, every variable of its FMI type, outputs finite, structural parameters (FMI 3.0)
the instance's own, the model's state like one of a model of its parameters: :func:`conformity`)
and refuses it with one line otherwise.
Serialized, it is its JSON without the model, a newline and the model's bytes (the slave's
``_model_to_bytes``); the classmethods pythonfmu calls never raise (pythonfmu07 P10).
"""
from __future__ import annotations

import json
import math

from .pythonfmu07 import never_raising
from .sequence import RUNNING, Phase, Refuse, all_finite, stop_limit

__all__ = ["StateHandling", "conformity"]


class StateHandling:
    """The FMU-state methods pythonfmu calls, for :class:`~pipeplug_fmu.base.FmiBase` (which
    holds the values, phase and time they read and write)."""

    def _state_mark(self) -> str:
        """What a state of this FMU and build is marked with (the module name has the build's
        tag)."""
        return f"{self.model_identifier} state of {type(self).__module__}"

    def _get_fmu_state(self):
        try:
            model = self._save(self._model) if self._phase in RUNNING else None
            values = {v.name: _plain(v.kind, self._tables[v.kind][v.vr])
                      for v in self._variables}            # plain Python: JSON-ready
            return {"mark": self._state_mark(), "phase": self._phase.value, "time": self._time,
                    "stop": self._stop_time, "values": values, "model": model}
        except Exception as exc:
            self._fail(self._call(f"Get{self.STATE}"), exc)

    def _set_fmu_state(self, state):
        try:
            phase, time, stop, values = self._checked_state(state)
            model = None
            if phase in RUNNING:
                model = self._build({n: values[n] for n, v in self._by_name.items()
                                     if v.causality in ("parameter", "structuralParameter")})
                self._load(model, state["model"])
        except Exception as exc:
            self._fail(self._call(f"Set{self.STATE}"), exc)
        for name, value in values.items():              # all checked: now change everything
            var = self._by_name[name]
            self._tables[var.kind][var.vr] = value
        self._time, self._stop_time = time, stop
        self._enter(phase)
        self._stop_limit, self._model = stop_limit(stop), model

    def _checked_state(self, state) -> tuple:
        """Phase, time, stop time and values of a state; raises :class:`Refuse` with what is
        wrong with it."""
        allowed = (f"a state of this {self.model_identifier} build from "
                   f"{self._call('Get' + self.STATE)} or "
                   f"{self._call(self.DESERIALIZE)}")
        if not isinstance(state, dict) or state.get("mark") != self._state_mark():
            reason = state.get("invalid") if isinstance(state, dict) else None
            raise Refuse.of(self.STATE, reason or _mark_of(state), allowed)
        try:
            phase = Phase(state["phase"])
            time, stop, values = state["time"], state["stop"], dict(state["values"])
        except Exception as exc:
            raise Refuse.of(self.STATE, f"{type(exc).__name__}: {exc}", allowed) from None
        if type(time) is not float or not math.isfinite(time):
            raise Refuse.of(f"{self.STATE} time", time, "finite [s]")
        if stop is not None and not (type(stop) is float and math.isfinite(stop)):
            raise Refuse.of(f"{self.STATE} stopTime", stop, "None or finite [s]")
        if set(values) != set(self._by_name):
            raise Refuse.of(f"{self.STATE} variables", sorted(set(values) ^ set(self._by_name)),
                            f"exactly the variables of {self.model_identifier}")
        for name, value in values.items():
            var = self._by_name[name]
            shape_ok = (type(value) is list) == (var.size_of is not None)
            items = value if type(value) is list else (value,)
            if not shape_ok or not all(_of_kind(x, var.kind) for x in items) or (
                    var.causality == "output" and not all_finite(items)):
                raise Refuse.of(f"{self.STATE} {name}", value, f"a {var.kind}" + (
                    ", finite" if var.causality == "output" else ""))
            if var.causality == "structuralParameter" and value != self._tables[var.kind][var.vr]:
                # the host sized its arrays by the instance's value: a state never changes it
                raise Refuse.of(f"{self.STATE} {name}", value,
                                f"{self._tables[var.kind][var.vr]!r}, this instance's "
                                f"(a structural parameter: a state of another is refused)")
        if (phase in RUNNING) != isinstance(state.get("model"), dict):
            raise Refuse.of(f"{self.STATE} model", type(state.get("model")).__name__,
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


_NUMBER_KINDS = {"Real": "f", "Integer": "i", "Boolean": "b", "UInt64": "i"}
_PLAIN = {"Real": float, "Integer": int, "Boolean": bool, "String": str, "UInt64": int}


def _plain(kind: str, value):
    """``value`` (a number, or a list of them) as plain Python of its kind."""
    if type(value) is list:
        return [_PLAIN[kind](x) for x in value]
    return _PLAIN[kind](value)


def _of_kind(value, kind: str) -> bool:
    """Whether ``value`` is a value of FMI type ``kind`` (a bool is no Integer, nor a Real)."""
    if kind == "String":
        return type(value) is str
    return _number_kind(value) == _NUMBER_KINDS[kind]


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
            if value.dtype.kind == "f" and all_finite(ref.ravel()) and not all_finite(
                    value.ravel()):
                return f"field {name!r} holds a value that is not finite"
        elif _number_kind(value) != _number_kind(ref) or (
                all_finite((ref,)) and not all_finite((value,))):
            return f"field {name!r} = {value!r} is not a number like {ref!r}"
    return None


def _number_kind(x) -> str | None:
    """"b", "i" or "f" for a bool, integer or real number (Python's or numpy's), else None."""
    kind = getattr(x, "dtype", None)
    if kind is not None:
        return kind.kind if x.ndim == 0 else None
    return {bool: "b", int: "i", float: "f"}.get(type(x))
