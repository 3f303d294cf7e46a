"""Read a system file as libcosim reads it: components, their FMUs, parameter values, times.

Two routes (libcosim's ``ssp_parser.cpp``/``ssp_loader.cpp`` and ``osp_config_parser.cpp``):

* SSP: a ``.ssp`` archive (``SystemStructure.ssd`` inside), a ``.ssd`` file, or a folder holding
  ``SystemStructure.ssd``. Each component's FMU is its ``source`` relative to the .ssd; its
  values are its *first* parameter set (``ssd:ParameterBinding`` with ``ssd:ParameterValues``
  inline or a ``source`` .ssv file), which is the set libcosim applies. The step size is the
  ``osp:FixedStepAlgorithm baseStepSize`` of the DefaultExperiment's OSP annotation (libcosim
  has no other), the start and stop the DefaultExperiment's ``startTime``/``stopTime``.
* OSP: ``OspSystemStructure.xml``: ``StartTime``, ``BaseStepSize`` (libcosim's default 0.1 s),
  and per Simulator its ``source`` (relative to the file) and ``InitialValues``. No stop time.

Each FMU's ``modelName`` (from its modelDescription.xml) says which component is a PipePlug or
a Hammer, whatever the component is called.
"""
from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from xml.etree import ElementTree as ET

from pipeplug_harness.errors import UserError

__all__ = ["Component", "SystemFile", "SystemFileError", "read_system", "ROUTES"]

ROUTES = ("ssp", "osp")
_SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
_SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
_SSC = "{http://ssp-standard.org/SSP1/SystemStructureCommon}"
_OSPA = "{http://opensimulationplatform.com/SSP/OSPAnnotations}"
_OSP = "{http://opensimulationplatform.com/MSMI/OSPSystemStructure}"
_OSP_DEFAULT_STEP = 0.1        # libcosim's base step when an OSP file gives none [s]


class SystemFileError(UserError):
    """A system file that cannot be run as it is (the message says why)."""


@dataclass
class Component:
    """One FMU instance of a system."""

    name: str
    model: str                    # modelName of its FMU
    values: dict = field(default_factory=dict)   # parameter -> value as libcosim sets it


@dataclass
class SystemFile:
    """A system file and what libcosim will read from it."""

    path: Path
    route: str                    # "ssp" or "osp"
    components: dict              # name -> Component
    start: float
    step: float | None            # None: libcosim would have no step size (SSP)
    stop: float | None            # None: the file gives none

    def of_model(self, model: str) -> list:
        """The components whose FMU is ``model``."""
        return [c for c in self.components.values() if c.model == model]


def read_system(path: Path | str, route: str) -> SystemFile:
    """Read the system file ``path`` of ``route`` ("ssp" or "osp")."""
    path = Path(path)
    if not path.exists():
        raise SystemFileError(f"{path}: no such file or folder")
    try:
        return _read_ssp(path) if route == "ssp" else _read_osp(path)
    except SystemFileError as exc:
        raise exc.in_file(path) from None
    except (ET.ParseError, KeyError, ValueError, TypeError, IndexError, OSError,
            zipfile.BadZipFile) as exc:
        raise SystemFileError(f"{path}: cannot be read as {route.upper()}: "
                              f"{type(exc).__name__}: {exc}") from None


# SSP -------------------------------------------------------------------------------------------
class _Files:
    """Files relative to the .ssd: inside the .ssp archive or on disk."""

    def __init__(self, path: Path):
        if path.is_dir():
            path = path / "SystemStructure.ssd"
        self.archive = zipfile.ZipFile(path) if path.suffix == ".ssp" else None
        self.base = PurePosixPath("SystemStructure.ssd") if self.archive else path

    def read(self, relative: str) -> bytes:
        target = self.base.parent / relative
        if self.archive is not None:
            return self.archive.read(_normalised(str(target)))
        return Path(target).read_bytes()


def _normalised(name: str) -> str:
    """``name`` inside the archive with ``.`` and ``..`` resolved; a name that leaves the
    archive is refused."""
    parts = []
    for part in PurePosixPath(name).parts:
        if part == "..":
            if not parts:
                raise SystemFileError(f"source {name!r} points outside the archive")
            parts.pop()
        elif part != ".":
            parts.append(part)
    return "/".join(parts)


def _read_ssp(path: Path) -> SystemFile:
    files = _Files(path)
    root = ET.fromstring(files.read(files.base.name))
    components = {}
    for node in root.find(f"{_SSD}System/{_SSD}Elements"):
        name = node.get("name")
        model = _model_name(_source(files.read, node, f"component {name}"), f"component {name}")
        components[name] = Component(name, model, _first_parameter_set(node, files))
    experiment = root.find(f"{_SSD}DefaultExperiment")
    start, stop, step = 0.0, None, None
    if experiment is not None:
        start = float(experiment.get("startTime", 0.0))
        stop = float(experiment.get("stopTime")) if experiment.get("stopTime") else None
        for annotation in experiment.iterfind(f"{_SSD}Annotations/*"):
            if annotation.get("type") == "com.opensimulationplatform":
                algorithm = annotation.find(f"{_OSPA}Algorithm/{_OSPA}FixedStepAlgorithm")
                if algorithm is not None:
                    step = float(algorithm.get("baseStepSize"))
    return SystemFile(path, "ssp", components, start, step, stop)


def _first_parameter_set(component: ET.Element, files: _Files) -> dict:
    for binding in component.iterfind(f"{_SSD}ParameterBindings/{_SSD}ParameterBinding"):
        if binding.get("source"):
            return _parameters(ET.fromstring(files.read(binding.get("source"))))
        inline = binding.find(f"{_SSD}ParameterValues/{_SSV}ParameterSet")
        if inline is not None:
            return _parameters(inline)
    return {}


def _parameters(parameter_set: ET.Element) -> dict:
    values = {}
    for parameter in parameter_set.iterfind(f"{_SSV}Parameters/{_SSV}Parameter"):
        typed = parameter[0]
        values[parameter.get("name")] = _typed(typed.tag.rsplit("}", 1)[-1], typed.get("value"))
    return values


# OSP -------------------------------------------------------------------------------------------
def _read_osp(path: Path) -> SystemFile:
    if path.is_dir():
        path = path / "OspSystemStructure.xml"
    root = ET.parse(path).getroot()
    start = float(root.findtext(f"{_OSP}StartTime", "0.0"))
    step = float(root.findtext(f"{_OSP}BaseStepSize", repr(_OSP_DEFAULT_STEP)))
    components = {}
    for node in root.iterfind(f"{_OSP}Simulators/{_OSP}Simulator"):
        name = node.get("name")
        model = _model_name(_source(lambda s: (path.parent / s).read_bytes(), node,
                                    f"simulator {name}"), f"simulator {name}")
        values = {v.get("variable"): _typed(v[0].tag.rsplit("}", 1)[-1], v[0].get("value"))
                  for v in node.iterfind(f"{_OSP}InitialValues/{_OSP}InitialValue")}
        components[name] = Component(name, model, values)
    return SystemFile(path, "osp", components, start, step, None)


# Both ------------------------------------------------------------------------------------------
def _source(read, node: ET.Element, what: str) -> bytes:
    """The bytes of the FMU a component's ``source`` names (``read(source)``), or an error
    naming the component and its source."""
    source = node.get("source")
    if not source:
        raise SystemFileError(f"{what}: no source (the FMU it runs)")
    try:
        return read(source)
    except (OSError, KeyError):
        raise SystemFileError(key=f"{what}: source", value=source,
                              allowed="the path of its FMU, relative to the system file "
                                      "(no such file)") from None


def _model_name(fmu: bytes, what: str) -> str:
    """modelName of the FMU whose zip is ``fmu``."""
    try:
        with zipfile.ZipFile(io.BytesIO(fmu)) as zf:
            return ET.fromstring(zf.read("modelDescription.xml")).get("modelName")
    except (zipfile.BadZipFile, KeyError, ET.ParseError) as exc:
        raise SystemFileError(f"{what}: its source is not an FMU ({exc})") from None


def _typed(kind: str, text: str):
    """A value as libcosim converts it from XML text."""
    if kind == "Real":
        return float(text)
    if kind in ("Integer", "Enumeration"):
        return int(text)
    if kind == "Boolean":
        if text.strip().lower() not in ("true", "false", "1", "0"):
            raise SystemFileError(f"{text!r} is not a Boolean value")
        return text.strip().lower() in ("true", "1")
    return text
