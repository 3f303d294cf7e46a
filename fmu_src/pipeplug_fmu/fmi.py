"""Tables and helpers of the FMUs' interfaces, shipped beside each slave.

PipePlug's inputs, default experiment and description; for both FMUs (PipePlug and Hammer) the
unit definitions, the wording of refusals and the decoration of ``modelDescription.xml`` that
pythonfmu 0.7 cannot write itself (``<UnitDefinitions>``, ``unit``, ``min``, ``max``). PipePlug's
output, parameter and option rows come from the core's tables (:data:`pipeplug.OUTPUTS`,
:data:`pipeplug.PARAMETERS`, :data:`pipeplug.OPTIONS`), passed in by the caller: neither
pythonfmu nor the core is imported here, so the build also reads these tables to write the
FMUs' documentation.
"""
from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

#: What the FMU is (modelDescription.xml and documentation).
DESCRIPTION = ("Percussive pipe ramming with a soil plug and Coulomb dry friction: rigid models "
               "I and II (exact or explicit solver) and elastic model III")

#: The inputs: (name, FMI type, unit, start, meaning).
INPUTS = (
    ("Q", "Real", "N", 0.0, "axial force on the struck end of the pipe (x = 0); positive drives "
                            "the pipe into the soil; held constant over a communication step"),
    ("strikes", "Integer", None, 0,
     "strikes of the ram so far: each increase (from 0 at the start) seen at a communication "
     "point starts one strike there, at v_strike (with ram_mass > 0; else the step is "
     "discarded); a decrease starts none"),
    ("v_strike", "Real", "m/s", 0.0, "the ram's velocity when a strike starts (positive "
                                     "towards the soil)"),
    ("cleanouts", "Integer", None, 0,
     "clean-outs so far: each increase (from 0 at the start) seen at a communication point "
     "removes the plug down to L2_after_cleanout there (with plug_growth = true; else the step "
     "is discarded); a decrease removes nothing"),
)

#: SI base-unit exponents (and factor) of every unit used (for <UnitDefinitions>).
UNITS = {"m": {"m": 1}, "s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "kg/m3": {"kg": 1, "m": -3},
         "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
         "J": {"kg": 1, "m": 2, "s": -2}, "kg": {"kg": 1}, "N/m": {"kg": 1, "s": -2},
         "s/m": {"s": 1, "m": -1}, "1": {},
         "1/min": {"s": -1, "factor": 1.0 / 60.0}}

#: The default experiment written into modelDescription.xml: (start [s], stop [s], step [s]).
DEFAULT_EXPERIMENT = (0.0, 0.1, 1e-4)


def refusal(name: str, value: object, allowed: str) -> str:
    """The one log line of a refusal: variable, value and allowed range."""
    return f"{name} = {value!r} is not allowed; allowed: {allowed}"


def decorate_model_description(root: Element, variables, fmi3: bool = False) -> None:
    """Add ``<UnitDefinitions>`` (the units of :data:`UNITS` that ``variables`` use) and each
    Real's ``unit``, ``min`` and ``max`` (build time).

    Parameters
    ----------
    root : Element
        ``fmiModelDescription`` as pythonfmu writes it.
    variables : iterable of (name, unit or None, bounds)
        One entry per variable, in value-reference order; ``bounds`` is ``(min, max)``
        with None for an absent bound.
    fmi3 : bool, optional
        FMI 3.0: the variable's element is typed itself (``<Float64 .../>``), not its child.
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
        type_node = node if fmi3 else node[0]
        if unit is not None and type_node.tag in ("Real", "Float64"):
            type_node.set("unit", unit)
        if lower is not None:
            type_node.set("min", _xml_number(lower))
        if upper is not None:
            type_node.set("max", _xml_number(upper))


def _xml_number(value) -> str:
    """A bound as written in modelDescription.xml (integers plain, reals round-tripping)."""
    return str(value) if isinstance(value, int) else f"{value:.17g}"


def fmi3_section(model_identifier: str) -> str:
    """The section of an FMI 3.0 FMU's ``documentation/index.html`` that says how it differs
    from the FMI 2.0 one the rest of the page describes (HTML)."""
    return f"""
<h2>FMI 3.0</h2>
<p>This is the FMI 3.0 co-simulation FMU: the same variables, value references and results as
the FMI 2.0 {model_identifier}.fmu this page describes (Real as Float64, Integer as Int32), with
FMI 3.0's names of the calls (fmi3GetFMUState, fmi3DeserializeFMUState, ...). What differs:</p>
<ul>
<li>The start and stop time come with fmi3EnterInitializationMode (FMI 2.0: fmi2SetupExperiment);
there is no event mode, early return or intermediate update; fmi3EnterConfigurationMode is
allowed before initialization only; calls of what the FMU does not have (event mode, model
exchange, clocks, derivatives, types without variables) are refused with fmi3Error and one
line.</li>
<li>nValues must be the number of values of the value references given; any other is refused
with fmi3Error naming the right count.</li>
<li>On linux64 the binary is <code>binaries/x86_64-linux/{model_identifier}.so</code> (the same
loader, in front of pythonfmu3's binary <code>{model_identifier}_pythonfmu.so</code>); the
host's logger gets the host's instanceEnvironment; log lines are not escaped for printf
(FMI 3.0 loggers take the message as it is). On win64 pythonfmu3's binary runs unchanged:
refusals are fmi3Fatal and the FMU's time starts at 0.</li>
</ul>
"""

