"""Hammer driving PipePlug as a co-simulated system: the built SSP and OSP files, ``pipeplug
system`` (libcosim) on both routes, and an FMPy-driven co-simulation of the two FMUs, against
the exact solutions for the same blow train (within 1e-9 of each quantity's peak)."""
from __future__ import annotations

import csv
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from system_helpers import CASES, REAL_OUTPUTS, assert_exact, train_force

from pipeplug_fmu.systems import System, write_systems

HERE = Path(__file__).resolve().parent
SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
OSPA = "{http://opensimulationplatform.com/SSP/OSPAnnotations}"
OSP = "{http://opensimulationplatform.com/MSMI/OSPSystemStructure}"
OSPMD = "{https://open-simulation-platform.com/OspModelDescription/1.0.0}"
#: The documented default system (README, pipeplug_fmu.systems): values that are not defaults.
DEFAULT_PIPEPLUG, DEFAULT_HAMMER = {"tau1": 4e4, "tau2": 1e4}, {"count": 3}
#: Hammer's outputs connected to PipePlug's inputs of the same names (the contract's).
CONNECTED = ("Q", "strikes", "v_strike")
#: The documented ram system: PipePlug's values that are not defaults, its ram, Hammer's ram.
RAM_PIPEPLUG = {"tau1": 4e4, "tau2": 1e4}
RAM = {"mass": 50.0, "k": 2e7, "e": 0.8}
RAM_HAMMER = {"ram_mass": 50.0, "rated_energy": 400.0, "efficiency": 0.8,
              "blows_per_minute": 300.0, "count": 3}


def _read_csv(path: Path) -> dict:
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return {name.split(" [")[0]: np.array([float(r[k]) for r in rows[1:]])
            for k, name in enumerate(rows[0])}


def _system_run(pipeplug_cli, route: str, path: Path, out: Path, *options) -> dict:
    proc = pipeplug_cli("system", f"--{route}", path, "--out", out, *options)
    csv_path = out / f"{path.stem}.csv"
    assert csv_path.exists(), proc.stdout
    result = _read_csv(csv_path)
    got = {name: result[f"PipePlug.{name}"] for name in REAL_OUTPUTS}
    return {"time": result["time"], "got": got, "hammer_q": result["Hammer.Q"],
            "pipeplug_q": result["PipePlug.Q"], "stdout": proc.stdout}


def _assert_no_delay(run: dict, hammer: dict, step: float) -> None:
    """Hammer's Q at t is the train at t; PipePlug's input during the step ending at t was the
    train at t - step: exactly, no one-step delay."""
    times = run["time"]
    assert list(run["hammer_q"]) == [train_force(hammer, t) for t in times]
    assert list(run["pipeplug_q"]) == [train_force(hammer, t - step) for t in times]


@pytest.fixture(scope="module")
def case_files(fmu_file, hammer_file, tmp_path_factory) -> dict:
    """Each case's SSP and OSP files (the FMUs of this test run)."""
    files = {}
    for name, (pipeplug, hammer, step, stop, _) in CASES.items():
        folder = tmp_path_factory.mktemp("case")
        write_systems(folder, fmu_file, hammer_file,
                      System(pipeplug=pipeplug, hammer=hammer, stop=stop, step=step))
        files[name] = folder
    return files


# The built files --------------------------------------------------------------------------------
def test_built_ssp_holds_both_fmus_values_and_step(fmu_file, hammer_file):
    ssp = zipfile.ZipFile(fmu_file.with_name("PipeRamming.ssp"))
    assert ssp.read("resources/PipePlug.fmu") == fmu_file.read_bytes()
    assert ssp.read("resources/Hammer.fmu") == hammer_file.read_bytes()
    root = ET.fromstring(ssp.read("SystemStructure.ssd"))
    assert root.get("version") == "1.0"
    components = {c.get("name"): c for c in root.find(f"{SSD}System/{SSD}Elements")}
    assert set(components) == {"Hammer", "PipePlug"}
    connections = root.find(f"{SSD}System/{SSD}Connections")
    assert [[c.get(k) for k in ("startElement", "startConnector", "endElement", "endConnector")]
            for c in connections] == [["Hammer", name, "PipePlug", name] for name in CONNECTED]
    values = {}
    for name, component in components.items():
        assert component.get("source") == f"resources/{name}.fmu"
        parameters = component.find(f"{SSD}ParameterBindings/{SSD}ParameterBinding/"
                                    f"{SSD}ParameterValues/{SSV}ParameterSet/{SSV}Parameters")
        values[name] = {p.get("name"): p[0].get("value") for p in parameters}
    assert float(values["PipePlug"]["tau1"]) == DEFAULT_PIPEPLUG["tau1"]
    assert values["PipePlug"]["contact_growth"] == "false"
    assert int(values["Hammer"]["count"]) == DEFAULT_HAMMER["count"]
    algorithm = root.find(f"{SSD}DefaultExperiment/{SSD}Annotations/*/{OSPA}Algorithm/"
                          f"{OSPA}FixedStepAlgorithm")
    assert float(algorithm.get("baseStepSize")) == 1e-3
    assert float(root.find(f"{SSD}DefaultExperiment").get("stopTime")) == 0.6


def test_built_osp_files_declare_the_groups_and_the_connection(fmu_file):
    folder = fmu_file.parent
    root = ET.parse(folder / "OspSystemStructure.xml").getroot()
    sources = {s.get("name"): s.get("source") for s in root.iter(f"{OSP}Simulator")}
    assert sources == {"Hammer": "Hammer.fmu", "PipePlug": "PipePlug.fmu"}
    assert [[(v.get("simulator"), v.get("name")) for v in connection]
            for connection in root.iter(f"{OSP}VariableConnection")] == [
        [("Hammer", name), ("PipePlug", name)] for name in CONNECTED]
    port = ET.parse(folder / "PipePlug_OspModelDescription.xml").getroot().find(
        f"{OSPMD}VariableGroups/{OSPMD}LinearMechanicalPort")
    assert [(g.tag.split("}")[1], g[0].get("ref"), g[0].get("unit")) for g in port] == [
        ("Force", "Q", "N"), ("LinearVelocity", "v_pipe", "m/s")]
    force = ET.parse(folder / "Hammer_OspModelDescription.xml").getroot().find(
        f"{OSPMD}VariableGroups/{OSPMD}Force")
    assert [(v.get("ref"), v.get("unit")) for v in force] == [("Q", "N")]


@pytest.mark.parametrize("route", ["ssp", "osp"])
def test_built_system_runs_exactly_in_libcosim(fmu_file, pipeplug_cli, tmp_path, route):
    """The files as built (default system: three blows, 1 ms steps), through ``pipeplug
    system``: the exact train reaches PipePlug, whose outputs are the ODE reference's."""
    path = fmu_file.with_name("PipeRamming.ssp" if route == "ssp" else "OspSystemStructure.xml")
    run = _system_run(pipeplug_cli, route, path, tmp_path / "out")
    assert run["time"].size == 600 and run["time"][-1] == 0.6
    hammer = {"count": 3}
    _assert_no_delay(run, hammer, 1e-3)
    errors = assert_exact(run["got"], DEFAULT_PIPEPLUG, hammer, run["time"], "ode")
    print(f"built {route}: worst error {max(errors.values()):.2e} of scale")
    png = (tmp_path / "out" / f"{path.stem}.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) > 20_000


@pytest.mark.parametrize("route", ["ssp", "osp"])
def test_built_ram_system_runs_exactly_in_libcosim(fmu_file, pipeplug_cli, tmp_path, route):
    """The ram system as built (three strikes of a 50 kg ram through a cushion, 1 ms steps),
    through ``pipeplug system``: Hammer's strikes reach PipePlug at their instants with
    v_strike = sqrt(2 eta E / m), and PipePlug's outputs are those of the ODE reference of
    model I with a ram (``pipeplug_references.ram_ivp``) within 1e-9 of each family's scale."""
    from pipeplug_references.ram_ivp import simulate_ram

    folder = fmu_file.parent / "ram"
    path = folder / ("PipeRamming.ssp" if route == "ssp" else "OspSystemStructure.xml")
    out = tmp_path / "out"
    proc = pipeplug_cli("system", f"--{route}", path, "--out", out)
    result = _read_csv(out / f"{path.stem}.csv")
    times = result["time"]
    assert times.size == 600 and times[-1] == 0.6, proc.stdout
    period = 60.0 / RAM_HAMMER["blows_per_minute"]
    speed = (2 * RAM_HAMMER["efficiency"] * RAM_HAMMER["rated_energy"]
             / RAM_HAMMER["ram_mass"]) ** 0.5
    # Hammer's strikes at t count those started at or before t (0, 0.2 and 0.4 s).
    assert list(result["Hammer.strikes"]) == [min(3, int(np.floor(t / period + 1e-9)) + 1)
                                              for t in times]
    assert np.all(result["Hammer.v_strike"] == speed) and np.all(result["Hammer.Q"] == 0.0)
    history = [(k * period, "strike", speed) for k in range(3)]
    # The outputs at a strike's instant are those before it (it starts the next step); the
    # reference samples there after it: ask it for the float just before.
    before = np.array([np.nextafter(t, 0.0) if any(t == h[0] for h in history) else t
                       for t in times])
    ref = simulate_ram(dict(_defaults(), **RAM_PIPEPLUG), RAM, history, before)
    worst = 0.0
    for family in (("v_pipe", "v_plug", "v_ram"), ("u_pipe", "u_plug"),
                   ("W_friction", "W_cushion", "E_kinetic", "W_ram")):
        scale = max(np.abs(ref[n]).max() for n in family)
        for name in family:
            error = np.abs(result[f"PipePlug.{name}"] - ref[name]).max()
            worst = max(worst, error / scale)
            assert error <= 1e-9 * scale, (name, error / scale)
    print(f"ram system ({route}): worst error {worst:.2e} of scale")
    assert result["PipePlug.u_pipe"][-1] > 0.05        # three strikes drove the pipe
    png = (out / f"{path.stem}.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) > 20_000


def _defaults() -> dict:
    """The contract's defaults of the rigid parameters the reference takes (SI)."""
    return {"L1": 1.0, "L2": 1.0, "R1": 0.035, "h1": 0.003, "rho1": 7800.0, "rho2": 1800.0,
            "tau1": 0.0, "tau2": 1e4}


# Each case, three hosts ---------------------------------------------------------------------------
@pytest.mark.parametrize("route", ["ssp", "osp"])
@pytest.mark.parametrize("case", list(CASES))
def test_libcosim_system_equals_the_exact_solution(case_files, pipeplug_cli, tmp_path, case,
                                                   route):
    pipeplug, hammer, step, stop, kind = CASES[case]
    name = "PipeRamming.ssp" if route == "ssp" else "OspSystemStructure.xml"
    stop_option = () if route == "ssp" else ("--stop", stop)       # OSP files have no stop time
    run = _system_run(pipeplug_cli, route, case_files[case] / name, tmp_path / "out",
                      *stop_option)
    assert run["time"].size == round(stop / step)
    _assert_no_delay(run, hammer, step)
    errors = assert_exact(run["got"], pipeplug, hammer, run["time"], kind)
    print(f"{case} ({route}): worst error {max(errors.values()):.2e} of scale")


@pytest.mark.parametrize("case", list(CASES))
def test_fmpy_driven_system_equals_the_exact_solution(fmu_file, hammer_file, case):
    pipeplug, hammer, step, stop, kind = CASES[case]
    spec = {"pipeplug": pipeplug, "hammer": hammer, "step": step, "stop": stop}
    proc = subprocess.run([sys.executable, str(HERE / "two_fmus.py"), str(fmu_file),
                           str(hammer_file), json.dumps(spec)], capture_output=True, text=True,
                          timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    rows = json.loads(proc.stdout.strip().splitlines()[-1].removeprefix("RESULT "))
    times = np.array(rows["time"])
    assert rows["Q_applied"] == [train_force(hammer, t - step) for t in times]
    errors = assert_exact({n: np.array(rows[n]) for n in REAL_OUTPUTS}, pipeplug, hammer, times,
                          kind)
    print(f"{case} (fmpy): worst error {max(errors.values()):.2e} of scale")


def test_ssd_folder_with_a_parameter_file(case_files, pipeplug_cli, tmp_path):
    """An unpacked SSP whose PipePlug values live in an .ssv file (ParameterBinding source):
    read as libcosim reads it, and run exactly."""
    pipeplug, hammer, step, stop, kind = CASES["train, model I"]
    folder = tmp_path / "unpacked"
    zipfile.ZipFile(case_files["train, model I"] / "PipeRamming.ssp").extractall(folder)
    ssd = (folder / "SystemStructure.ssd").read_text()
    start = ssd.index("<ssv:ParameterSet", ssd.index('name="PipePlug"'))
    end = ssd.index("</ssv:ParameterSet>", start) + len("</ssv:ParameterSet>")
    (folder / "pipeplug.ssv").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n' + ssd[start:end].replace(
            "<ssv:ParameterSet", '<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/'
                                 'SystemStructureParameterValues"', 1))
    binding_start = ssd.rindex("<ssd:ParameterBinding>", 0, start)
    binding_end = ssd.index("</ssd:ParameterBinding>", end) + len("</ssd:ParameterBinding>")
    (folder / "SystemStructure.ssd").write_text(
        ssd[:binding_start] + '<ssd:ParameterBinding source="pipeplug.ssv"/>'
        + ssd[binding_end:])
    proc = pipeplug_cli("system", "--ssp", folder, "--out", tmp_path / "out")
    result = _read_csv(tmp_path / "out" / "unpacked.csv")
    assert_exact({n: result[f"PipePlug.{n}"] for n in REAL_OUTPUTS}, pipeplug, hammer,
                 result["time"], kind)
    assert "refused" not in proc.stdout


# Refusals before libcosim ---------------------------------------------------------------------------
def _edited(source: Path, dest: Path, old: str, new: str) -> Path:
    """A copy of the system file ``source`` (SSP archive or OSP file) with ``old`` -> ``new``
    in its XML."""
    if source.suffix == ".ssp":
        with zipfile.ZipFile(source) as src, zipfile.ZipFile(dest, "w") as dst:
            for info in src.infolist():
                data = src.read(info)
                if info.filename == "SystemStructure.ssd":
                    assert old.encode() in data
                    data = data.replace(old.encode(), new.encode())
                dst.writestr(info, data)
    else:
        text = source.read_text()
        assert old in text
        dest.write_text(text.replace(old, new))
    return dest


#: id -> (file, old text, new text, words of the refusal)
REFUSED = {
    "negative tau1 (SSP)": ("PipeRamming.ssp", '<ssv:Real value="20000.0" />',
                            '<ssv:Real value="-1.0" />',
                            ["component PipePlug (PipePlug)", "tau1 = -1.0 is not allowed"]),
    "unknown PipePlug parameter (SSP)": ("PipeRamming.ssp", 'name="tau1"', 'name="tau3"',
                                         ["tau3", "a parameter or option of PipePlug"]),
    "blows longer than the period (OSP)": ("OspSystemStructure.xml",
                                           '<InitialValue variable="duration">\n'
                                           '          <Real value="0.05" />',
                                           '<InitialValue variable="duration">\n'
                                           '          <Real value="0.5" />',
                                           ["component Hammer (Hammer)", "duration = 0.5",
                                            "<= period"]),
    "no step size (SSP)": ("PipeRamming.ssp", '<osp:FixedStepAlgorithm baseStepSize="0.01" />',
                           "", ["no step size", "libcosim cannot run it"]),
    # each of these ended in a traceback or ran for ever before
    "stop time not a number (SSP)": ("PipeRamming.ssp", 'stopTime="0.7"', 'stopTime="nan"',
                                     ["stopTime = nan", "a finite time"]),
    "a source outside the archive (SSP)": ("PipeRamming.ssp", 'source="resources/Hammer.fmu"',
                                           'source="../../x"',
                                           ["source '../../x' points outside the archive"]),
    "a stop time of 1e9 s (SSP)": ("PipeRamming.ssp", 'stopTime="0.7"', 'stopTime="1e9"',
                                   ["asks for 1e+11 steps", "--limit steps="]),
}


@pytest.mark.parametrize("case", list(REFUSED), ids=list(REFUSED))
def test_refused_before_libcosim_sees_it(case_files, pipeplug_cli, tmp_path, case):
    name, old, new, words = REFUSED[case]
    path = _edited(case_files["train, model I"] / name, tmp_path / name, old, new)
    route = "ssp" if name.endswith(".ssp") else "osp"
    proc = pipeplug_cli("system", f"--{route}", path, "--out", tmp_path / "out", check=False)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and proc.stderr.startswith("pipeplug system: ")
    assert proc.stderr.count(str(path)) == 1, proc.stderr              # the file, named once
    for word in words:
        assert word in proc.stderr, (word, proc.stderr)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("source", ["../../x", "resources/none.fmu"])
def test_a_component_source_that_is_no_file_is_named(case_files, pipeplug_cli, tmp_path, source):
    """An unpacked SSP whose component points at no file: the component, its source and why,
    in one line (it was the reader's FileNotFoundError with the joined path)."""
    folder = tmp_path / "unpacked"
    zipfile.ZipFile(case_files["train, model I"] / "PipeRamming.ssp").extractall(folder)
    ssd = folder / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text().replace('source="resources/Hammer.fmu"', f'source="{source}"'))
    proc = pipeplug_cli("system", "--ssp", folder, "--out", tmp_path / "out", check=False)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1, proc.stderr
    for word in (str(folder), f"component Hammer: source = {source!r}", "no such file"):
        assert word in proc.stderr, (word, proc.stderr)
    assert "Error" not in proc.stderr and not (tmp_path / "out").exists()


def test_a_grid_missing_an_edge_is_named(case_files, pipeplug_cli, tmp_path):
    source = case_files["train, model I"] / "OspSystemStructure.xml"
    path = _edited(source, tmp_path / "o.xml", "0.01<", "0.04<")          # BaseStepSize
    path.write_text(path.read_text().replace('stepSize="0.01"', 'stepSize="0.04"'))
    proc = pipeplug_cli("system", "--osp", path, "--stop", "0.08", "--out", tmp_path / "out")
    assert "misses the blow edges [0.01, 0.06]" in proc.stdout, proc.stdout
