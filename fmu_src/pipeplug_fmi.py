"""Tables and helpers of the PipePlug FMU's interface, shipped beside the slave ``PipePlug.py``.

The input and output tables (names, units, meanings), the unit definitions, the default
experiment, the wording of refusals and the decoration of ``modelDescription.xml`` that
pythonfmu 0.7 cannot write itself (``<UnitDefinitions>``, ``unit``, ``min``, ``max``). Parameter
and option rows come from :data:`pipeplug.PARAMETERS` and :data:`pipeplug.OPTIONS`. Neither
pythonfmu nor the core is imported: ``build_fmu.py`` also reads these tables to write the FMU's
documentation.
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

#: Real outputs, in the order of :class:`pipeplug.Outputs`: (name, unit, meaning).
REAL_OUTPUTS = (
    ("v_pipe", "m/s", "pipe velocity (elastic model: at section x_monitor)"),
    ("v_plug", "m/s", "plug velocity (elastic model: at the plug section coupled to x_monitor)"),
    ("u_pipe", "m", "pipe displacement (elastic model: at section x_monitor)"),
    ("u_plug", "m", "plug displacement (elastic model: at the plug section coupled to x_monitor)"),
    ("F_outer", "N", "total friction force of the soil on the pipe, along +x (a stuck contact "
                     "gives its static reaction)"),
    ("F_inner", "N", "total friction force of the plug on the pipe, along +x (same rule)"),
    ("W_input", "J", "work done by Q since t = 0"),
    ("W_friction", "J", "friction work dissipated since t = 0 (never decreases)"),
)

#: Integer outputs, after the Real ones in :class:`pipeplug.Outputs`: (name, meaning).
MODE_OUTPUTS = (
    ("pipe_mode", "pipe/soil contact: -1 sliding backward, 0 stuck to the soil, 1 sliding "
                  "forward (elastic: at x_monitor)"),
    ("plug_mode", "pipe/plug contact: sign(v_pipe - v_plug); 0 = stuck together or no plug "
                  "(elastic: at x_monitor)"),
)

#: SI base-unit exponents of every unit used (for <UnitDefinitions>).
UNITS = {"m": {"m": 1}, "s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "kg/m3": {"kg": 1, "m": -3},
         "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
         "J": {"kg": 1, "m": 2, "s": -2}, "1": {}}

#: The default experiment written into modelDescription.xml: (start [s], stop [s], step [s]).
DEFAULT_EXPERIMENT = (0.0, 0.1, 1e-4)

class PipePlugRefusal(RuntimeError):
    """The single exception an instance raises (pythonfmu reports it as fmi2Fatal)."""


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


def decorate_model_description(root: Element, variables, output_names) -> None:
    """Add ``<UnitDefinitions>`` and each Real's ``unit``, ``min`` and ``max`` (build time).

    Parameters
    ----------
    root : Element
        ``fmiModelDescription`` as pythonfmu writes it.
    variables : iterable of (name, unit or None, Parameter or None)
        One entry per ScalarVariable, in value-reference order.
    output_names : sequence of str
        The core's output order (:data:`pipeplug.OUTPUT_NAMES`), which the slave relies on.
    """
    names = [n for n, *_ in REAL_OUTPUTS] + [n for n, _ in MODE_OUTPUTS]
    if names != list(output_names):      # the slave copies the outputs by position
        raise RuntimeError(f"output tables {names} differ from {list(output_names)}")
    units = Element("UnitDefinitions")
    for unit, exponents in UNITS.items():
        SubElement(SubElement(units, "Unit", name=unit), "BaseUnit",
                   {k: str(v) for k, v in exponents.items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
    for node, (name, unit, parameter) in zip(root.find("ModelVariables"), variables):
        _decorate(node[0], unit, parameter, name)


def _decorate(type_node: Element, unit, parameter, name: str) -> None:
    """Add ``unit``, ``min`` and ``max`` to a variable's type element."""
    if unit is not None:
        type_node.set("unit", unit)
    if parameter is not None and parameter.lower is not None:
        type_node.set("min", f"{parameter.lower:.17g}")
    if parameter is not None and parameter.upper is not None:
        type_node.set("max", f"{parameter.upper:.17g}")
    if name in dict(MODE_OUTPUTS):
        type_node.set("min", "-1")
        type_node.set("max", "1")
