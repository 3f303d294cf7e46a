"""Tables and helpers of the FMUs' interfaces, shipped beside each slave.

PipePlug's input, default experiment and description; for both FMUs (PipePlug and Hammer) the
unit definitions, the wording of refusals, the refusal exception the loader recognises and the
decoration of ``modelDescription.xml`` that pythonfmu 0.7 cannot write itself
(``<UnitDefinitions>``, ``unit``, ``min``, ``max``). PipePlug's output, parameter and option
rows come from the core's tables (:data:`pipeplug.OUTPUTS`, :data:`pipeplug.PARAMETERS`,
:data:`pipeplug.OPTIONS`), passed in by the caller: neither pythonfmu nor the core is imported
here, so the build also reads these tables to write the FMUs' documentation.
"""
from __future__ import annotations

import ctypes
from xml.etree.ElementTree import Element, SubElement

#: What the FMU is (modelDescription.xml and documentation).
DESCRIPTION = ("Percussive pipe ramming with a soil plug and Coulomb dry friction: rigid models "
               "I and II (exact or explicit solver) and elastic model III")

#: The input: (name, unit, meaning).
INPUT = ("Q", "N", "axial force on the struck end of the pipe (x = 0); positive drives the "
                   "pipe into the soil; held constant over a communication step")

#: SI base-unit exponents of every unit used (for <UnitDefinitions>).
UNITS = {"m": {"m": 1}, "s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "kg/m3": {"kg": 1, "m": -3},
         "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
         "J": {"kg": 1, "m": 2, "s": -2}, "kg": {"kg": 1}, "N/m": {"kg": 1, "s": -2}, "1": {}}

#: The default experiment written into modelDescription.xml: (start [s], stop [s], step [s]).
DEFAULT_EXPERIMENT = (0.0, 0.1, 1e-4)



def refusal_mark(model_identifier: str) -> str:
    """How a refusal of FMU ``model_identifier`` starts in pythonfmu's fatal log line.

    The FMU's linux64 binary (the loader, ``native/loader.c``: ``MODEL "Refusal: "``) turns such
    a line into the refusal's own fmi2Error line.
    """
    return f"{model_identifier}Refusal: "


class Refusal(RuntimeError):
    """The single exception an instance raises; one subclass per FMU, named
    ``<modelIdentifier>Refusal``.

    pythonfmu reports it as fmi2Fatal, in a line holding its ``repr``: the refusal mark of its
    FMU and the refusal's text, so that the loader can find the text without parsing a Python
    literal.
    """

    def __repr__(self) -> str:
        return type(self).__name__ + ": " + str(self)


class PipePlugRefusal(Refusal):
    """PipePlug's refusal."""


#: How a refusal of PipePlug starts in pythonfmu's fatal log line.
REFUSAL_MARK = refusal_mark("PipePlug")


def escape_percent(text: str) -> str:
    """Escape ``%`` so a host's printf-style logger prints ``text`` literally."""
    return text.replace("%", "%%")


def refusal(name: str, value: object, allowed: str) -> str:
    """The one log line of a refusal: variable, value and allowed range."""
    return f"{name} = {value!r} is not allowed; allowed: {allowed}"


def outlive_the_exception(instance) -> None:
    """Keep ``instance`` valid after pythonfmu has handled its exception.

    pythonfmu's C++ side releases its references to the instance, its log queue and its class
    when a call raises, and releases them once more at fmi2Reset/fmi2FreeInstance. One extra
    reference each balances that, so later calls reach a live object and the host survives.
    """
    incref = ctypes.pythonapi.Py_IncRef
    incref.argtypes, incref.restype = [ctypes.py_object], None
    for obj in (instance, instance.log_queue, type(instance)):
        incref(obj)


def decorate_model_description(root: Element, variables) -> None:
    """Add ``<UnitDefinitions>`` (the units of :data:`UNITS` that ``variables`` use) and each
    Real's ``unit``, ``min`` and ``max`` (build time).

    Parameters
    ----------
    root : Element
        ``fmiModelDescription`` as pythonfmu writes it.
    variables : iterable of (name, unit or None, bounds)
        One entry per ScalarVariable, in value-reference order; ``bounds`` is ``(min, max)``
        with None for an absent bound.
    """
    variables = list(variables)
    used = {unit for _, unit, _ in variables}
    units = Element("UnitDefinitions")
    for unit, exponents in UNITS.items():
        if unit in used:
            SubElement(SubElement(units, "Unit", name=unit), "BaseUnit",
                       {k: str(v) for k, v in exponents.items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
    for node, (_, unit, (lower, upper)) in zip(root.find("ModelVariables"), variables):
        type_node = node[0]
        if unit is not None and type_node.tag == "Real":
            type_node.set("unit", unit)
        if lower is not None:
            type_node.set("min", _xml_number(lower))
        if upper is not None:
            type_node.set("max", _xml_number(upper))


def _xml_number(value) -> str:
    """A bound as written in modelDescription.xml (integers plain, reals round-tripping)."""
    return str(value) if isinstance(value, int) else f"{value:.17g}"
