"""The FMI 3.0 binding of the FMI base (:mod:`pipeplug_fmu.base`) on pythonfmu3.

Mixed in after a slave, as :mod:`pipeplug_fmu.fmi2` is for FMI 2.0: it declares the variables to
pythonfmu3 (Real as Float64, Integer as Int32, Boolean, String, UInt64; arrays with a
``<Dimension>`` naming their structural parameter), maps fmi3Get/Set of those types onto the
base and writes units and ranges into ``modelDescription.xml``.

FMI 3.0 co-simulation without event mode maps onto the base's FMI 2.0 call sequence: structural
parameters are set with the parameters, before initialization. pythonfmu3 0.3.4 passes neither
the start nor the stop time of fmi3EnterInitializationMode to the slave (its binary drops them):
the FMU's time starts at 0 and it has no stopTime. pythonfmu3's behaviours with exceptions are
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

__all__ = ["Fmi3Binding"]

_TYPES = {"Real": Float64, "Integer": Int32, "Boolean": Boolean, "String": String,
          "UInt64": UInt64}


class Fmi3Binding(Fmi3Slave):
    """FMI 3.0 co-simulation through pythonfmu3 (see the module docstring)."""

    FMI = "fmi3"
    SEQUENCE = "the FMI 3.0 call sequence of co-simulation without event mode"
    DISCARD = Fmi3Status.discard
    STATE = "FMUState"          # as in fmi3GetFMUState
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
        return self._get("Real", vrs)

    def get_int32(self, vrs):
        return self._get("Integer", vrs)

    def get_boolean(self, vrs):
        return self._get("Boolean", vrs)

    def get_string(self, vrs):
        return self._get("String", vrs)

    def get_uint64(self, vrs):
        # pythonfmu3 reads each element's ``value``
        return [ctypes.c_uint64(x) for x in self._get("UInt64", vrs)]

    def set_float64(self, vrs, values):
        self._set_input("Real", vrs, values)

    def set_int32(self, vrs, values):
        self._set("Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self._set("Boolean", vrs, values)

    def set_string(self, vrs, values):
        self._set("String", vrs, values)

    def set_uint64(self, vrs, values):
        self._set("UInt64", vrs, values)

    # modelDescription.xml (build time only) ------------------------------------------------
    def to_xml(self, model_options=None):
        root = super().to_xml(model_options or {})
        decorate_model_description(root, [(v.name, v.unit, v.bounds) for v in self._variables],
                                   fmi3=True)
        return root
