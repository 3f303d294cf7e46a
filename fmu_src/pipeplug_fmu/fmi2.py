"""The FMI 2.0 binding of the FMI base (:mod:`pipeplug_fmu.base`) on pythonfmu 0.7.

Mixed in after a slave (``class PipePlug(PipePlugSlave, Fmi2Binding)``): it declares the
variables to pythonfmu, maps fmi2Get/Set of Real, Integer, Boolean and String onto the base,
takes the experiment from fmi2SetupExperiment and writes what pythonfmu 0.7 leaves out of
``modelDescription.xml`` (units, ranges, InitialUnknowns). Lines are escaped for the host's
printf (pythonfmu07 P4).
"""
from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

from pythonfmu import (
    Boolean,
    DefaultExperiment,
    Fmi2Causality,
    Fmi2Initial,
    Fmi2Slave,
    Fmi2Variability,
    Integer,
    Real,
    String,
)
from pythonfmu.enums import Fmi2Status

from .fmi import decorate_model_description
from .pythonfmu07 import escape_percent
from .sequence import Phase, Refuse

__all__ = ["Fmi2Binding"]

_INSTANTIATED = Phase.INSTANTIATED
_TYPES = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}


class Fmi2Binding(Fmi2Slave):
    """FMI 2.0 co-simulation through pythonfmu 0.7 (see the module docstring)."""

    FMI = "fmi2"
    SEQUENCE = "the FMI 2.0 call sequence"
    DISCARD = Fmi2Status.discard
    STATE = "FMUstate"          # as in fmi2GetFMUstate
    DESERIALIZE = "DeSerializeFMUstate"
    TYPE_NAMES = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean", "String": "String"}
    _experiment = staticmethod(DefaultExperiment)
    ARRAYS = False                # array variables exist

    def _declare(self, var, meaning, getter, variability, initial) -> None:
        extra = {} if initial is None else {"initial": Fmi2Initial[initial]}
        self.register_variable(_TYPES[var.kind](
            var.name, description=meaning, getter=getter, causality=Fmi2Causality[var.causality],
            variability=Fmi2Variability[variability], **extra))
        if initial == "calculated" and var.causality == "output":
            self._calculated = (*getattr(self, "_calculated", ()), var.vr)

    _escape = staticmethod(escape_percent)

    def _register_binding(self) -> None:
        """Variables of the binding's own (none in FMI 2.0)."""

    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._setup("fmi2SetupExperiment", start_time, stop_time)

    # Getters and setters: the hot ones inline ------------------------------------------------
    # FMI 2.0 reads values from fmi2EnterInitializationMode on: a getter before it is out of
    # the call sequence (the standard's state machine; FMI 3.0 allows it, see fmi3.py).
    def get_real(self, vrs):
        if self._phase is _INSTANTIATED:
            self._refuse_early_get("Real")
        try:
            return list(map(self._reals.__getitem__, vrs))
        except Exception:
            self._refuse_get(vrs, "Real")

    def get_integer(self, vrs):
        return self._read("Integer", vrs)

    def get_boolean(self, vrs):
        return self._read("Boolean", vrs)

    def get_string(self, vrs):
        return self._read("String", vrs)

    def _read(self, kind: str, vrs) -> list:
        """The values of ``vrs`` of ``kind``, from initialization mode on."""
        if self._phase is _INSTANTIATED:
            self._refuse_early_get(kind)
        return self._get(kind, vrs)

    def _refuse_early_get(self, kind: str) -> None:
        call = f"fmi2Get{kind}"
        self._fail(call, Refuse(f"{call} is not allowed in {_INSTANTIATED.value}; allowed: "
                                f"from fmi2EnterInitializationMode on ({self.SEQUENCE})"))

    def set_real(self, vrs, values):
        self._set_input("Real", vrs, values)

    def set_integer(self, vrs, values):
        self._set("Integer", vrs, values)

    def set_boolean(self, vrs, values):
        self._set("Boolean", vrs, values)

    def set_string(self, vrs, values):
        self._set("String", vrs, values)

    # modelDescription.xml (build time only) ------------------------------------------------
    def to_xml(self, model_options=None):
        # pythonfmu reads the start values with the getters, which FMI 2.0 allows from
        # initialization mode on: this instance, made to be described, is put there first.
        self._enter(Phase.INITIALIZATION)
        root = super().to_xml(model_options or {})
        decorate_model_description(root, [(v.name, v.unit, v.bounds) for v in self._variables])
        calculated = getattr(self, "_calculated", ())
        if calculated:
            unknowns = SubElement(root.find("ModelStructure"), "InitialUnknowns")
            for vr in calculated:
                unknowns.append(Element("Unknown", index=str(vr + 1)))
        return root
