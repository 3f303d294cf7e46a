"""The FMI 3.0 FMUs (``dist/fmi3/``): fmpy's validation, the same variables as the FMI 2.0 FMUs,
the same results bit for bit, FMU states, and the profile arrays.

Everything runs in one fresh process (pythonfmu FMUs share the host's interpreter), which also
checks FMI 2.0 and 3.0 PipePlug together in one process.
"""
from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

WORKER = textwrap.dedent('''
    import json, sys
    import numpy as np
    from fmpy import read_model_description, simulate_fmu, extract
    from fmpy.fmi3 import FMU3Slave
    from fmpy.validation import validate_fmu

    fmi2, fmi3, hammer2, hammer3 = sys.argv[1:5]
    out = {"problems": {f: validate_fmu(f) for f in (fmi3, hammer3)}}

    def variables(path):
        md = read_model_description(path)
        return {v.name: (v.causality, v.variability, v.start, v.unit, v.min, v.max)
                for v in md.modelVariables}
    out["variables"] = [variables(fmi2), variables(fmi3), variables(hammer2), variables(hammer3)]

    sig = np.array([(0.0, 23e3), (0.004, 23e3), (0.004, 0.0), (0.012, 0.0)],
                   dtype=[("time", float), ("Q", float)])
    cases = [{"tau1": 2e4}, {"tau1": 2e4, "contact_growth": True, "solver": "fd"},
             {"tau1": 2e4, "L2": 0.5, "elastic": True, "dx": 0.05}]
    out["same"] = []
    for sv in cases:
        r2 = simulate_fmu(fmi2, stop_time=0.012, output_interval=1e-3, input=sig, start_values=sv)
        r3 = simulate_fmu(fmi3, stop_time=0.012, output_interval=1e-3, input=sig, start_values=sv)
        out["same"].append([n for n in r2.dtype.names if not np.array_equal(r2[n], r3[n])])
    h2 = simulate_fmu(hammer2, stop_time=0.5, output_interval=1e-2, start_values={"count": 2})
    h3 = simulate_fmu(hammer3, stop_time=0.5, output_interval=1e-2, start_values={"count": 2})
    out["hammer_same"] = bool(np.array_equal(h2["Q"], h3["Q"]))

    # Low level: profile_points = 5, state saved, serialized and restored, scalars at x_k.
    md = read_model_description(fmi3)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    where = extract(fmi3)
    def run(params, n_steps, points=None, state_at=None):
        fmu = FMU3Slave(guid=md.guid, unzipDirectory=where,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="p")
        fmu.instantiate()
        if points is not None:
            fmu.setUInt64([vr["profile_points"]], [points])
        for name, value in params.items():
            if isinstance(value, bool):
                fmu.setBoolean([vr[name]], [value])
            else:
                fmu.setFloat64([vr[name]], [value])
        fmu.enterInitializationMode(); fmu.exitInitializationMode()
        saved, t, h = None, 0.0, 1e-3
        for k in range(n_steps):
            if k == state_at:
                saved = fmu.serializeFMUState(fmu.getFMUState())
            fmu.setFloat64([vr["Q"]], [23e3 if k < 4 else 0.0])
            fmu.doStep(t, h); t += h
        result = {"v": fmu.getFloat64([vr["v_pipe"]])[0], "vp": fmu.getFloat64([vr["v_plug"]])[0],
                  "u": fmu.getFloat64([vr["u_pipe"]])[0]}
        if points is not None:
            n = fmu.getUInt64([vr["profile_points"]])[0]
            result["profiles"] = [fmu.getFloat64([vr[p]], nValues=n) for p in
                                  ("v_pipe_profile", "u_pipe_profile", "stress_pipe_profile",
                                   "v_plug_profile")]
            result["stress_head"] = fmu.getFloat64([vr["stress_head"]])[0]
        if saved is not None:    # back to step state_at, then the same steps again
            fmu.setFMUState(fmu.deserializeFMUState(saved)); t = state_at * h
            for k in range(state_at, n_steps):
                fmu.setFloat64([vr["Q"]], [23e3 if k < 4 else 0.0])
                fmu.doStep(t, h); t += h
            result["again"] = fmu.getFloat64([vr["v_pipe"]])[0]
        fmu.terminate(); fmu.freeInstance()
        return result
    elastic = {"tau1": 2e4, "L2": 0.5, "elastic": True, "dx": 0.05}
    main = run(elastic, 10, points=5, state_at=6)
    out["main"] = main
    out["at"] = [run(dict(elastic, x_monitor=k * 1.0 / 4), 10) for k in range(5)]
    out["plug_at"] = [run(dict(elastic, x_monitor=0.5 + k * 0.5 / 4), 10) for k in range(5)]
    sys.stdout.write(json.dumps(out) + "\\n")
    sys.stdout.flush()
''')


@pytest.fixture(scope="module")
def report(fmu_file, hammer_file, fmi3_files) -> dict:
    proc = subprocess.run([sys.executable, "-c", WORKER, str(fmu_file), str(fmi3_files["PipePlug"]),
                           str(hammer_file), str(fmi3_files["Hammer"])],
                          capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_fmpy_validates_both_fmi3_fmus(report):
    assert report["problems"] == {k: [] for k in report["problems"]}


def test_every_fmi2_variable_is_in_fmi3_with_the_same_unit_default_and_range(report):
    pipe2, pipe3, hammer2, hammer3 = report["variables"]
    for fmi2, fmi3 in ((pipe2, pipe3), (hammer2, hammer3)):
        for name, (causality, variability, start, unit, low, high) in fmi2.items():
            assert fmi3[name][:2] == [causality, variability], name
            assert fmi3[name][3:] == [unit, low, high], name
            if start is not None:
                assert fmi3[name][2] == start or {fmi3[name][2], start} <= {"0", "0.0"}, name
    assert pipe3["profile_points"][:3] == ["structuralParameter", "fixed", "11"]


def test_fmi2_and_fmi3_runs_agree_bit_for_bit(report):
    assert report["same"] == [[], [], []]
    assert report["hammer_same"]


def test_profile_points_set_and_each_element_is_the_scalar_output_at_its_section(report):
    v, u, stress, v_plug = report["main"]["profiles"]
    assert len(v) == 5
    assert v == [run["v"] for run in report["at"]]
    assert u == [run["u"] for run in report["at"]]
    assert v_plug == [run["vp"] for run in report["plug_at"]]
    assert stress[0] == report["main"]["stress_head"]


def test_a_serialized_state_restores_the_run_bit_for_bit(report):
    assert report["main"]["again"] == report["main"]["v"]


@pytest.mark.parametrize("name", ["PipePlug", "Hammer"])
def test_documentation_names_every_variable_and_what_fmi3_changes(fmi3_files, name):
    import zipfile

    from fmpy import read_model_description

    html = zipfile.ZipFile(fmi3_files[name]).read("documentation/index.html").decode()
    assert "FMI 3.0 co-simulation" in html and "<h2>FMI 3.0</h2>" in html
    assert "fmi3EnterInitializationMode" in html and f"binaries/x86_64-linux/{name}.so" in html
    for v in read_model_description(str(fmi3_files[name])).modelVariables:
        if v.name != "time" and v.name != "profile_points":
            assert f"<td>{v.name}</td>" in html, v.name
    if name == "PipePlug":
        assert "profile_points elements each" in html


def test_the_readme_gives_the_value_references_of_the_model_description(fmi3_dirs):
    """The README's FMI 3.0 host example hard-codes value references (a C host has no names):
    they are those of the FMU the build writes."""
    import re
    import xml.etree.ElementTree as ET
    from pathlib import Path

    root = ET.parse(fmi3_dirs["PipePlug"] / "modelDescription.xml").getroot()
    refs = {v.get("name"): int(v.get("valueReference")) for v in root.iter()
            if v.get("valueReference") is not None}
    text = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    names = ("Q", "elastic", "profile_points", "stress_pipe_profile")
    prose = re.search(r"Q (\d+), elastic (\d+),\s+profile_points (\d+), stress_pipe_profile (\d+)",
                      text)
    code = re.search(r"fmi3ValueReference q = (\d+), elastic = (\d+), points = (\d+), "
                     r"stress = (\d+);", text)
    fmpy = re.search(r"getFloat64\(\[(\d+)\], nValues=n\)", text)
    expected = [refs[name] for name in names]
    assert [int(g) for g in prose.groups()] == expected
    assert [int(g) for g in code.groups()] == expected
    assert int(fmpy.group(1)) == refs["stress_pipe_profile"]
