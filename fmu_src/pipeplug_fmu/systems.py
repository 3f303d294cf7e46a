"""The pipe-ramming system: Hammer.fmu driving PipePlug.fmu, written as SSP and as OSP files.

Two components, ``Hammer`` and ``PipePlug``, with Hammer's outputs ``Q``, ``strikes`` and
``v_strike`` connected to PipePlug's inputs of the same names (:data:`CONNECTED`), a fixed
communication step and every parameter's value:

* ``PipeRamming.ssp`` (SSP 1.0): ``SystemStructure.ssd`` with both FMUs inside the archive under
  ``resources/``. libcosim (``ssp_parser.cpp``, ``ssp_loader.cpp``) reads the step size only from
  the OSP annotation of the DefaultExperiment (``ssc:Annotation type="com.opensimulationplatform"``
  holding ``osp:Algorithm/osp:FixedStepAlgorithm baseStepSize``; without it an execution made
  with ``CosimExecution.from_ssp_file`` has no algorithm), and it applies each component's first
  parameter set (``ssd:ParameterBindings/ssd:ParameterBinding/ssd:ParameterValues/
  ssv:ParameterSet``). It matches XML prefixes literally (``ssd:``, ``ssv:``, ``ssc:``, ``osp:``),
  not namespaces, so these files use exactly those prefixes. A parameter name that the FMU does
  not have is only a warning there: the harness checks the names before a run.
* ``OspSystemStructure.xml`` (libcosim's OSP configuration): the FMUs beside it, the base step
  and each simulator's step, the parameter values as InitialValues, and one VariableConnection.
  ``PipePlug_OspModelDescription.xml`` and ``Hammer_OspModelDescription.xml`` (OSP-IS 1.0, found
  by libcosim beside the FMUs under ``<modelName>_OspModelDescription.xml``) declare the variable
  groups: PipePlug's struck end as a LinearMechanicalPort of the force Q and the velocity v_pipe
  (the struck end's velocity in the rigid models; in the elastic model v_pipe is taken at
  ``x_monitor``, the struck end when x_monitor = 0), Hammer's Q as a Force. Hammer is a force
  source with no velocity input, so there is no port of Hammer's to bond to PipePlug's, and OSP-IS
  allows a VariableGroupConnection only between groups of one type: the connection is the
  variable connection Hammer.Q -> PipePlug.Q (and strikes, v_strike). (libcosim refuses a group connection of Hammer's
  Force to PipePlug's whole port, "different size [0] than ... [2]"; it accepts one to the port's
  nested Force group, which makes the same scalar connection.)

The default system (:func:`default_system`) is PipePlug with the contract's defaults except
tau1 = 4e4 Pa under three of Hammer's default blows (23 kN for 50 ms every 0.2 s), stepped at
1 ms from 0 to 0.6 s. The step contains every blow edge, so PipePlug sees the exact train. Each
blow drives pipe and plug (model I, domain I: both slide, the plug overtakes) and both come to
rest (the pipe 0.105 s, the plug 0.171 s after the blow starts) before the next blow: three
equal sets. (With tau1 = 2e4 Pa a blow's motion would last 0.265 s and the blows would pile up.)

The ram system (:func:`ram_system`, written into ``ram/`` beside the FMUs) is the same pipe
struck by a 50 kg ram through a cushion of 2e7 N/m (restitution 0.8): Hammer in ram mode with
a rated energy of 400 J at an efficiency of 0.8 (v_strike = sqrt(2 * 0.8 * 400 / 50) =
3.578 m/s), 300 blows per minute (one every 0.2 s), three strikes, stepped at 1 ms (every
strike instant is a grid point) from 0 to 0.6 s.
"""
from __future__ import annotations

import math
import os
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from xml.etree.ElementTree import Element, SubElement, indent, tostring

from . import blows

__all__ = ["System", "default_system", "write_systems", "ssd_xml", "write_ssp", "osp_xml",
           "osp_model_description_xml", "SSP_NAME", "OSP_NAME", "COMPONENTS", "GROUPS", "Group",
           "grid_misses", "ram_system", "CONNECTED", "RAM_FOLDER"]

SSP_NAME = "PipeRamming.ssp"
OSP_NAME = "OspSystemStructure.xml"
#: Component name -> modelName of its FMU (OSP model descriptions are named after it).
COMPONENTS = {"Hammer": "Hammer", "PipePlug": "PipePlug"}
#: The default system's values that differ from the FMUs' defaults.
DEFAULT_OVERRIDES = {"PipePlug": {"tau1": 4.0e4}, "Hammer": {"count": 3}}
DEFAULT_STEP = 1e-3      # [s]; contains every edge of the default train
DEFAULT_STOP = 0.6       # [s]; three blows and the rest after the last
#: The ram system's values that differ from the FMUs' defaults (see the module docstring).
RAM_OVERRIDES = {"PipePlug": {"tau1": 4.0e4, "ram_mass": 50.0, "cushion_stiffness": 2.0e7,
                              "cushion_restitution": 0.8},
                 "Hammer": {"count": 3, "ram_mass": 50.0, "rated_energy": 400.0,
                            "efficiency": 0.8, "blows_per_minute": 300.0}}
RAM_FOLDER = "ram"       # the ram system's files, beside the FMUs

_SSD_NAMESPACES = {
    "xmlns:ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "xmlns:ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "xmlns:ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "xmlns:osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
}
_OSP_NAMESPACE = "http://opensimulationplatform.com/MSMI/OSPSystemStructure"
_OSP_MD_NAMESPACE = "https://open-simulation-platform.com/OspModelDescription/1.0.0"
_UNITS = {"N": {"kg": 1, "m": 1, "s": -2}, "m/s": {"m": 1, "s": -1}}   # SI base exponents
#: Hammer's outputs connected to PipePlug's inputs of the same name: (name, FMI type, unit).
CONNECTED = (("Q", "Real", "N"), ("strikes", "Integer", None), ("v_strike", "Real", "m/s"))
_KIND = {"Hammer": "output", "PipePlug": "input"}


@dataclass(frozen=True)
class System:
    """One Hammer-PipePlug system: parameter values by component, start, stop and step [s]."""

    pipeplug: dict = field(default_factory=dict)     # PipePlug parameter/option -> value
    hammer: dict = field(default_factory=dict)       # Hammer parameter -> value
    start: float = 0.0
    stop: float = DEFAULT_STOP
    step: float = DEFAULT_STEP
    name: str = "PipeRamming"

    def values(self, component: str) -> dict:
        return {"PipePlug": self.pipeplug, "Hammer": self.hammer}[component]


def default_system() -> System:
    """The documented default system (see the module docstring), every value explicit."""
    return _system(DEFAULT_OVERRIDES, "PipeRamming")


def ram_system() -> System:
    """The documented ram system (see the module docstring), every value explicit."""
    return _system(RAM_OVERRIDES, "PipeRammingRam")


def _system(overrides: dict, name: str) -> System:
    from pipeplug import OPTIONS, PARAMETERS

    pipeplug = {p.name: float(p.default) for p in PARAMETERS}
    pipeplug.update({name: default for name, (_, default, _) in OPTIONS.items()})
    pipeplug.update(overrides["PipePlug"])
    hammer = {p.name: p.default for p in blows.PARAMETERS}
    hammer.update(overrides["Hammer"])
    return System(pipeplug=pipeplug, hammer=hammer, start=0.0, stop=DEFAULT_STOP,
                  step=DEFAULT_STEP, name=name)


def grid_misses(system: System) -> list[float]:
    """The blow edges in [start, stop] that the step grid start + k step misses (by more than
    1e-9 of a step)."""
    train = blows.check(system.hammer)
    misses, k = [], 0
    while True:
        edges = train.edges(k)
        if edges[0] > system.stop or (train.count and k >= train.count):
            return misses
        for edge in edges:
            steps = (edge - system.start) / system.step
            if system.start <= edge <= system.stop and abs(steps - round(steps)) > 1e-9:
                misses.append(edge)
        k += 1


def write_systems(folder: Path, pipeplug_fmu: Path, hammer_fmu: Path,
                  system: System | None = None) -> list[Path]:
    """Write the SSP archive, the OSP configuration and both OSP model descriptions into
    ``folder``; return their paths.

    The SSP archive holds copies of the FMUs; the OSP configuration names them by their paths
    relative to ``folder`` (libcosim finds the model descriptions beside the FMUs or, failing
    that, beside the configuration).
    """
    system = system or default_system()
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    ssp = write_ssp(folder / SSP_NAME, pipeplug_fmu, hammer_fmu, system)
    osp = folder / OSP_NAME
    osp.write_text(osp_xml(system, {"PipePlug": _relative(pipeplug_fmu, folder),
                                    "Hammer": _relative(hammer_fmu, folder)}), encoding="utf-8")
    paths = [ssp, osp]
    for component, model in COMPONENTS.items():
        path = folder / f"{model}_OspModelDescription.xml"
        path.write_text(osp_model_description_xml(component), encoding="utf-8")
        paths.append(path)
    return paths


def _relative(path: Path, folder: Path) -> str:
    """``path`` relative to ``folder`` (``..`` allowed), as a URI reference."""
    return Path(os.path.relpath(Path(path).resolve(), Path(folder).resolve())).as_posix()


def write_ssp(dest: Path, pipeplug_fmu: Path, hammer_fmu: Path, system: System) -> Path:
    """The SSP archive ``dest``: SystemStructure.ssd, resources/PipePlug.fmu, resources/Hammer.fmu."""
    dest = Path(dest)
    with zipfile.ZipFile(dest, "w") as zf:
        zf.writestr("SystemStructure.ssd", ssd_xml(system), compress_type=zipfile.ZIP_DEFLATED)
        for component, fmu in (("PipePlug", pipeplug_fmu), ("Hammer", hammer_fmu)):
            zf.write(fmu, f"resources/{component}.fmu")      # already compressed: stored
    return dest


def ssd_xml(system: System) -> str:
    """SystemStructure.ssd of ``system`` (FMUs at resources/<component>.fmu)."""
    _check_grid(system)
    root = Element("ssd:SystemStructureDescription",
                   {**_SSD_NAMESPACES, "version": "1.0", "name": system.name})
    sys_node = SubElement(root, "ssd:System", name=system.name,
                          description="Hammer.fmu drives PipePlug.fmu: Hammer.Q -> PipePlug.Q, "
                                      "strikes and v_strike likewise")
    elements = SubElement(sys_node, "ssd:Elements")
    for component in COMPONENTS:
        node = SubElement(elements, "ssd:Component", name=component,
                          type="application/x-fmu-sharedlibrary",
                          source=f"resources/{component}.fmu")
        connectors = SubElement(node, "ssd:Connectors")
        for name, fmi_type, unit in CONNECTED:
            connector = SubElement(connectors, "ssd:Connector", name=name,
                                   kind=_KIND[component])
            SubElement(connector, f"ssc:{fmi_type}", **({} if unit is None else {"unit": unit}))
        binding = SubElement(SubElement(node, "ssd:ParameterBindings"), "ssd:ParameterBinding")
        parameter_set = SubElement(SubElement(binding, "ssd:ParameterValues"), "ssv:ParameterSet",
                                   version="1.0", name=f"{component}_parameters")
        parameters = SubElement(parameter_set, "ssv:Parameters")
        for pname, value in system.values(component).items():
            kind_of, text = _typed(value)
            SubElement(SubElement(parameters, "ssv:Parameter", name=pname), f"ssv:{kind_of}",
                       value=text)
    connections = SubElement(sys_node, "ssd:Connections")
    for name, _, _ in CONNECTED:
        SubElement(connections, "ssd:Connection", startElement="Hammer", startConnector=name,
                   endElement="PipePlug", endConnector=name)
    units = SubElement(root, "ssd:Units")
    for name in sorted({unit for _, _, unit in CONNECTED if unit is not None}):
        unit = SubElement(units, "ssc:Unit", name=name)
        SubElement(unit, "ssc:BaseUnit", {k: str(v) for k, v in _UNITS[name].items()})
    experiment = SubElement(root, "ssd:DefaultExperiment", startTime=_real(system.start),
                            stopTime=_real(system.stop))
    annotation = SubElement(SubElement(experiment, "ssd:Annotations"), "ssc:Annotation",
                            type="com.opensimulationplatform")
    SubElement(SubElement(annotation, "osp:Algorithm"), "osp:FixedStepAlgorithm",
               baseStepSize=_real(system.step))
    return _document(root)


def osp_xml(system: System, sources: dict) -> str:
    """OspSystemStructure.xml of ``system``; ``sources`` maps component -> FMU path (relative to
    the file)."""
    _check_grid(system)
    root = Element("OspSystemStructure", xmlns=_OSP_NAMESPACE, version="0.1")
    SubElement(root, "StartTime").text = _real(system.start)
    SubElement(root, "BaseStepSize").text = _real(system.step)
    SubElement(root, "Algorithm").text = "fixedStep"
    simulators = SubElement(root, "Simulators")
    for component in COMPONENTS:
        node = SubElement(simulators, "Simulator", name=component, source=sources[component],
                          stepSize=_real(system.step))
        initial = SubElement(node, "InitialValues")
        for name, value in system.values(component).items():
            kind, text = _typed(value)
            SubElement(SubElement(initial, "InitialValue", variable=name), kind, value=text)
    connections = SubElement(root, "Connections")
    for name, _, _ in CONNECTED:
        connection = SubElement(connections, "VariableConnection")
        SubElement(connection, "Variable", simulator="Hammer", name=name)
        SubElement(connection, "Variable", simulator="PipePlug", name=name)
    return _document(root)


@dataclass(frozen=True)
class Group:
    """An OSP-IS variable group: its type, name, variables ``(ref, unit)`` and nested groups."""

    kind: str
    name: str
    variables: tuple = ()
    groups: tuple = ()

    def units(self) -> set:
        return {unit for _, unit in self.variables}.union(*(g.units() for g in self.groups))


#: OSP-IS variable groups per component.
GROUPS = {
    "PipePlug": Group("LinearMechanicalPort", "struck_end", groups=(
        Group("Force", "struck_end_force", (("Q", "N"),)),
        Group("LinearVelocity", "struck_end_velocity", (("v_pipe", "m/s"),)))),
    "Hammer": Group("Force", "blow_force", (("Q", "N"),)),
}


def osp_model_description_xml(component: str) -> str:
    """``<modelName>_OspModelDescription.xml`` of ``component`` (OSP-IS 1.0)."""
    root = Element("OspModelDescription", xmlns=_OSP_MD_NAMESPACE, version="1.0")
    group = GROUPS[component]
    units = SubElement(root, "UnitDefinitions")
    for unit in sorted(group.units()):
        SubElement(SubElement(units, "Unit", name=unit), "BaseUnit",
                   {k: str(v) for k, v in _UNITS[unit].items()})
    _add_group(SubElement(root, "VariableGroups"), group)
    return _document(root)


def _add_group(parent: Element, group: Group) -> None:
    node = SubElement(parent, group.kind, name=group.name)
    for ref, unit in group.variables:
        SubElement(node, "Variable", ref=ref, unit=unit)
    for nested in group.groups:
        _add_group(node, nested)


def _check_grid(system: System) -> None:
    """Refuse a system whose grid misses a blow edge or whose times are not finite."""
    if not (math.isfinite(system.start) and math.isfinite(system.stop) and system.step > 0
            and system.stop > system.start):
        raise ValueError(f"start {system.start!r}, stop {system.stop!r} and step "
                         f"{system.step!r} s: need finite start < stop and step > 0")
    misses = grid_misses(system)
    if misses:
        shown = ", ".join(f"{edge:.12g}" for edge in misses)
        raise ValueError(f"the step {system.step!r} s misses the blow edges [{shown}] s: "
                         f"choose a step that divides every edge's time from the start")


def _typed(value) -> tuple[str, str]:
    """(FMI type, text) of a parameter value as SSV and OSP write it."""
    if isinstance(value, bool):
        return "Boolean", "true" if value else "false"
    if isinstance(value, int):
        return "Integer", str(value)
    if isinstance(value, str):
        return "String", value
    return "Real", _real(value)


def _real(value: float) -> str:
    return repr(float(value))      # round-trips


def _document(root: Element) -> str:
    indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + tostring(root, encoding="unicode") + "\n"
