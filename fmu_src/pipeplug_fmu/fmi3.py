"""The FMI 3.0 binding of the FMI base (:mod:`pipeplug_fmu.base`) on pythonfmu3.

Mixed in after a slave, as :mod:`pipeplug_fmu.fmi2` is for FMI 2.0: it declares the variables to
pythonfmu3 (Real as Float64, Integer as Int32, Boolean, String, UInt64; arrays with a
``<Dimension>`` naming their structural parameter), maps fmi3Get/Set of those types onto the
base and writes units and ranges into ``modelDescription.xml``.

FMI 3.0 co-simulation without event mode maps onto the base's FMI 2.0 call sequence: structural
parameters are set with the parameters, before initialization. pythonfmu3 0.3.4 passes neither
the start nor the stop time of fmi3EnterInitializationMode to the slave (its binary drops them);
the linux64 loader (``native/loader3.c``) passes them first, as an fmi3SetFloat64 of
:data:`EXPERIMENT_MARK`, and puts :data:`COUNT_MARK`, nValues and nValueReferences before the
value references of every get and set, so that an nValues that is not the number of values of
those variables is refused (pythonfmu3 gives getters no nValues and reads past their list).
Without the loader (win64) the FMU's time starts at 0, it has no stopTime, and only setters
check nValues. pythonfmu3's behaviours with exceptions are
pythonfmu 0.7's (pythonfmu07 P1, P2, P5, P6, P9, P10: a Python exception is fmi3Fatal, its
references to the instance are released once), so the same workarounds apply; FMI 3.0 loggers
take the message as it is (no printf), so lines are not escaped.
"""
from __future__ import annotations

import ctypes

from pythonfmu3 import (
    Boolean,
    DefaultExperiment,
    Dimension,
    Float64,
    Fmi3Causality,
    Fmi3Initial,
    Fmi3Slave,
    Fmi3Variability,
    Int32,
    String,
    UInt64,
)
from pythonfmu3.enums import Fmi3Status

from .fmi import decorate_model_description
from .sequence import Refuse

__all__ = ["Fmi3Binding", "COUNT_MARK", "EXPERIMENT_MARK"]

#: The loader's marks (``native/fmi3.h``), as pythonfmu3 gives value references: C ints.
COUNT_MARK, EXPERIMENT_MARK = -1, -2
_HEADER = 3                      # COUNT_MARK, nValues, nValueReferences

_TYPES = {"Real": Float64, "Integer": Int32, "Boolean": Boolean, "String": String,
          "UInt64": UInt64}


class Fmi3Binding(Fmi3Slave):
    """FMI 3.0 co-simulation through pythonfmu3 (see the module docstring)."""

    FMI = "fmi3"
    SEQUENCE = "the FMI 3.0 call sequence of co-simulation without event mode"
    DISCARD = Fmi3Status.discard
    STATE = "FMUState"          # as in fmi3GetFMUState
    DESERIALIZE = "DeserializeFMUState"
    TYPE_NAMES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean",
                  "String": "String", "UInt64": "UInt64"}
    _experiment = staticmethod(DefaultExperiment)
    ARRAYS = True                # array variables exist

    def _declare(self, var, meaning, getter, variability, initial) -> None:
        extra = {} if initial is None else {"initial": Fmi3Initial[initial]}
        if var.size_of is not None:
            extra["dimensions"] = [Dimension(valueReference=str(var.size_of))]
        self.register_variable(_TYPES[var.kind](
            var.name, description=meaning, getter=getter, causality=Fmi3Causality[var.causality],
            variability=Fmi3Variability[variability], **extra))

    @staticmethod
    def _escape(line: str) -> str:
        return line

    def _register_binding(self) -> None:
        # FMI 3.0 requires the independent variable; it comes after every variable of the
        # slave, so that theirs keep the value references of the FMI 2.0 FMU.
        self._time_vr = self._add("Real", "time", 0.0, "s", "simulation time", "independent",
                                  "continuous")

    # Getters and setters --------------------------------------------------------------------
    def get_float64(self, vrs):
        self._reals[self._time_vr] = self._time
        return self._counted_get("Real", vrs)

    def get_int32(self, vrs):
        return self._counted_get("Integer", vrs)

    def get_boolean(self, vrs):
        return self._counted_get("Boolean", vrs)

    def get_string(self, vrs):
        return self._counted_get("String", vrs)

    def get_uint64(self, vrs):
        # pythonfmu3 reads each element's ``value``
        return [ctypes.c_uint64(x) for x in self._counted_get("UInt64", vrs)]

    def set_float64(self, vrs, values):
        if vrs[:1] == [EXPERIMENT_MARK]:
            start, stop_defined, stop = values
            self._setup("fmi3EnterInitializationMode", start, stop if stop_defined else None)
            return
        vrs, _ = self._unmarked(vrs)
        if len(values) != len(vrs):      # every settable variable is a scalar
            self._refuse_count("Real", vrs, len(values), "Set")
        self._set_input("Real", vrs, values)

    def set_int32(self, vrs, values):
        self._counted_set("Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self._counted_set("Boolean", vrs, values)

    def set_string(self, vrs, values):
        self._counted_set("String", vrs, values)

    def set_uint64(self, vrs, values):
        self._counted_set("UInt64", vrs, values)

    # nValues (see the module docstring) ------------------------------------------------------
    @staticmethod
    def _unmarked(vrs):
        """The host's value references and its nValues (None without the loader's header)."""
        if vrs[:1] == [COUNT_MARK] and len(vrs) >= _HEADER:
            return vrs[_HEADER:_HEADER + vrs[2]], vrs[1]
        return vrs, None

    def _counted_get(self, kind, vrs):
        vrs, n = self._unmarked(vrs)
        values = self._get(kind, vrs)
        if n is not None and n != len(values):
            self._refuse_count(kind, vrs, n, "Get")
        return values

    def _counted_set(self, kind, vrs, values):
        marked = vrs[:1] == [COUNT_MARK]
        vrs, n = self._unmarked(vrs)
        if marked and kind == "String":  # the loader's three header Strings, then the host's
            values = values[_HEADER:_HEADER + n]
        if len(values) != len(vrs):      # every settable variable is a scalar
            self._refuse_count(kind, vrs, len(values), "Set")
        self._set(kind, vrs, values)

    def _refuse_count(self, kind, vrs, n, action):
        """Refuse ``n`` values for ``vrs`` (an unknown value reference counts one)."""
        table = self._tables[kind]
        count = sum(len(x) if type(x) is list else 1 for x in (table.get(vr) for vr in vrs))
        call = self._call(f"{action}{self.TYPE_NAMES[kind]}")
        self._fail(call, Refuse(f"nValues = {n} is not allowed in {call}; allowed: {count} (the "
                                f"number of values of the {len(vrs)} value references given)"))

    # modelDescription.xml (build time only) ------------------------------------------------
    def to_xml(self, model_options=None):
        root = super().to_xml(model_options or {})
        decorate_model_description(root, [(v.name, v.unit, v.bounds) for v in self._variables],
                                   fmi3=True)
        return root
