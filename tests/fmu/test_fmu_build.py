"""The built PipePlug.fmu: validation, modelDescription.xml per the contract, contents, and a
run in a Python without this repository."""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest
from fmu_helpers import (
    CONTRACT_INPUTS,
    CONTRACT_OPTIONS,
    CONTRACT_OUTPUTS,
    CONTRACT_PARAMETERS,
    env_without_site_hooks,
    run_scenario,
)

#: SI base-unit exponents of the contract's units.
SI = {"m": {"m": 1}, "s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "kg/m3": {"kg": 1, "m": -3},
      "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
      "J": {"kg": 1, "m": 2, "s": -2}, "kg": {"kg": 1}, "N/m": {"kg": 1, "s": -2}, "1": {},
      "s/m": {"s": 1, "m": -1}}


@pytest.fixture(scope="module")
def md(fmu_file):
    """The parsed modelDescription.xml."""
    with zipfile.ZipFile(fmu_file) as zf:
        return ET.fromstring(zf.read("modelDescription.xml"))


@pytest.fixture(scope="module")
def variables(md):
    """name -> (ScalarVariable element, its type element)."""
    return {v.get("name"): (v, v[0]) for v in md.find("ModelVariables")}


def test_fmpy_validation_finds_no_problem(fmu_file):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu_file)) == []


def test_cosimulation_flags(md):
    cs = md.find("CoSimulation")
    assert cs.get("modelIdentifier") == "PipePlug"
    assert md.get("fmiVersion") == "2.0"
    for flag in ("canHandleVariableCommunicationStepSize", "canGetAndSetFMUstate",
                 "canSerializeFMUstate"):
        assert cs.get(flag) == "true", flag
    assert cs.get("canBeInstantiatedOnlyOncePerProcess") == "false"


def test_default_experiment(md):
    exp = md.find("DefaultExperiment")
    start, stop, step = (float(exp.get(k)) for k in ("startTime", "stopTime", "stepSize"))
    assert start == 0.0 and stop > start and 0.0 < step < stop - start


def test_exactly_the_contract_variables(variables):
    expected = set(CONTRACT_INPUTS) | set(CONTRACT_OUTPUTS) | set(CONTRACT_PARAMETERS) | set(CONTRACT_OPTIONS)
    assert set(variables) == expected


def test_every_variable_has_a_description(variables):
    for name, (var, _) in variables.items():
        assert len(var.get("description", "")) > 10, name


def test_units_are_si_and_defined(md, variables):
    defined = {u.get("name"): {k: int(v) for k, v in u.find("BaseUnit").attrib.items()}
               for u in md.find("UnitDefinitions")}
    for name, (_, typ) in variables.items():
        if typ.tag == "Real":
            unit = typ.get("unit")
            assert unit in defined, f"{name}: unit {unit} not defined"
            assert defined[unit] == SI[unit], unit
    assert variables["Q"][1].get("unit") == "N"


def test_input_and_outputs(variables):
    for name, (kind, unit, variability) in CONTRACT_INPUTS.items():
        var, typ = variables[name]
        assert (var.get("causality"), var.get("variability"), typ.tag) == (
            "input", variability, kind), name
        assert typ.get("unit") == unit and float(typ.get("start")) == 0.0, name
    for name, (kind, unit) in CONTRACT_OUTPUTS.items():
        var, typ = variables[name]
        assert (var.get("causality"), var.get("initial")) == ("output", "exact"), name
        assert typ.get("start") == ("false" if kind == "Boolean" else typ.get("start")), name
        assert kind == "Boolean" or float(typ.get("start")) == 0.0, name
        assert typ.tag == kind, name
        assert typ.get("unit") == unit, name
    for name in ("pipe_mode", "plug_mode"):
        assert (variables[name][1].get("min"), variables[name][1].get("max")) == ("-1", "1")


@pytest.mark.parametrize("name", sorted(CONTRACT_PARAMETERS))
def test_parameter_per_contract(variables, name):
    unit, default, lo, hi = CONTRACT_PARAMETERS[name]
    var, typ = variables[name]
    assert (var.get("causality"), var.get("variability")) == ("parameter", "fixed")
    assert typ.tag == "Real" and typ.get("unit") == unit
    assert float(typ.get("start")) == default
    assert float(typ.get("min")) == lo
    assert (typ.get("max") is None) if hi is None else (float(typ.get("max")) == hi)


@pytest.mark.parametrize("name", sorted(CONTRACT_OPTIONS))
def test_option_per_contract(variables, name):
    kind, default = CONTRACT_OPTIONS[name]
    var, typ = variables[name]
    assert (var.get("causality"), var.get("variability")) == ("parameter", "fixed")
    assert typ.tag == kind and typ.get("start") == default


def test_shipped_under_names_of_this_build_without_caches(fmu_file):
    """The slave script, the adapter and the core, all under the build's content digest."""
    fmu = zipfile.ZipFile(fmu_file)
    names = fmu.namelist()
    module = fmu.read("resources/slavemodule.txt").decode().strip()
    tag = module.removeprefix("pipeplug_slave_")
    assert module != tag and len(tag) == 12 and int(tag, 16) >= 0
    package = f"resources/pipeplug_fmu_{tag}/"
    for name in (f"resources/{module}.py", package + "slave.py", package + "fmi.py",
                 package + "pipeplug/__init__.py",
                 package + "pipeplug/rigid/exact.py", package + "pipeplug/elastic/kernels.py"):
        assert name in names, name
    assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")]
    assert not [n for n in names if n.startswith("resources/pipeplug/")]    # no shared names
    assert {"binaries/linux64/PipePlug.so", "binaries/linux64/PipePlug_pythonfmu.so",
            "binaries/win64/PipePlug.dll"} <= set(names)


def test_documentation_states_equations_and_variables(fmu_file, variables):
    html = zipfile.ZipFile(fmu_file).read("documentation/index.html").decode()
    for heading in ("Model I", "Model II", "Model III"):
        assert heading in html
    for equation in ("M1 U1'' = Q(t) + F_outer + F_inner", "Lc = min(max(U1, 0), L1)",
                     "E1 S1 d2u1/dx2"):
        assert equation in html
    for name in variables:
        assert f"<td>{name}</td>" in html, name
    for name, (unit, default, _, _) in CONTRACT_PARAMETERS.items():
        assert f"<td>{name}</td><td>{unit}</td><td>{default:g}</td>" in html, name


def test_runs_in_a_python_without_this_repository(fmu_dir):
    """``python -S``: no .pth files, so neither the editable install nor the harness exists."""
    result = run_scenario("standalone", fmu_dir, python_args=("-S",),
                          env=env_without_site_hooks())
    assert result["core_visible_before"] is False
    assert result["core_file"].startswith(str(fmu_dir))
    # defaults, 1 ms under Q0: both contacts slide forward, M1 v = (Q0 - P2 L2 tau2) t
    m1 = 7800.0 * math.pi * (0.038 ** 2 - 0.035 ** 2)
    f2 = 2.0 * math.pi * 0.035 * 1.0 * 1.0e4
    assert math.isclose(result["v_pipe"], (23e3 - f2) * 1e-3 / m1, rel_tol=1e-12)


def test_a_core_imported_by_the_host_does_not_replace_the_shipped_one(fmu_dir):
    result = run_scenario("host_core_first", fmu_dir)
    assert not result["host_core_file"].startswith(str(fmu_dir))
    assert result["core_file"].startswith(str(fmu_dir))


def test_documentation_states_how_a_python_is_found_and_the_statuses(fmu_file):
    html = zipfile.ZipFile(fmu_file).read("documentation/index.html").decode()
    for text in ("PIPEPLUG_PYTHON", "<code>python3</code> on <code>PATH</code>",
                 "already running in the host process", "fmi2Instantiate returns NULL",
                 "refused with fmi2Error", "until fmi2Reset", "LogCategories",
                 "is not run-tested by this project"):
        assert text in html, text


#: Every function of the FMI 2.0 co-simulation API (fmi2Functions.h).
FMI2_FUNCTIONS = (
    "GetTypesPlatform GetVersion SetDebugLogging Instantiate FreeInstance SetupExperiment "
    "EnterInitializationMode ExitInitializationMode Terminate Reset GetReal GetInteger "
    "GetBoolean GetString SetReal SetInteger SetBoolean SetString GetFMUstate SetFMUstate "
    "FreeFMUstate SerializedFMUstateSize SerializeFMUstate DeSerializeFMUstate "
    "GetDirectionalDerivative SetRealInputDerivatives GetRealOutputDerivatives DoStep "
    "CancelStep GetStatus GetRealStatus GetIntegerStatus GetBooleanStatus GetStringStatus")


def test_linux_binary_is_the_loader_and_exports_every_fmi2_function(fmu_dir):
    """The loader needs no libpython to load (dlopen in this process only maps it: it starts
    nothing before fmi2Instantiate) and answers the two calls it serves itself."""
    import ctypes

    loader = ctypes.CDLL(str(fmu_dir / "binaries" / "linux64" / "PipePlug.so"))
    for name in FMI2_FUNCTIONS.split():
        assert hasattr(loader, "fmi2" + name), name
    loader.fmi2GetVersion.restype = loader.fmi2GetTypesPlatform.restype = ctypes.c_char_p
    assert (loader.fmi2GetVersion(), loader.fmi2GetTypesPlatform()) == (b"2.0", b"default")


def test_pythonfmu_binaries_are_shipped_unchanged(fmu_file):
    import pythonfmu

    shipped = Path(pythonfmu.__file__).parent / "resources" / "binaries"
    fmu = zipfile.ZipFile(fmu_file)
    assert fmu.read("binaries/linux64/PipePlug_pythonfmu.so") == (
        shipped / "linux64" / "libpythonfmu-export.so").read_bytes()
    assert fmu.read("binaries/win64/PipePlug.dll") == (
        shipped / "win64" / "pythonfmu-export.dll").read_bytes()
