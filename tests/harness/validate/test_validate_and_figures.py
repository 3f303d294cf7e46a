"""The validate and figures subcommands on small inputs."""
import csv

import numpy as np
import pytest

from pipeplug_harness.load import Load
from pipeplug_references import closed_form as cf


def test_help_lists_the_subcommands(pipeplug_cli):
    out = pipeplug_cli("--help").stdout
    for name in ("validate", "figures", "cost"):
        assert name in out


def test_validate_passes_and_writes_table_and_cross_check_files(pipeplug_cli, fmu_file, tmp_path):
    proc = pipeplug_cli("validate", "--fmu", fmu_file, "--out", tmp_path / "v")
    assert "0 failed" in proc.stdout
    rows = list(csv.DictReader(open(tmp_path / "v" / "validate.csv")))
    assert {r["solver"] for r in rows} == {"exact", "fd"}
    assert {r["domain"] for r in rows} == {"I", "II", "III", "IV", "V"}
    exact = [float(r["worst"]) for r in rows if r["solver"] == "exact"]
    assert max(exact) <= 1e-9
    cross_check_as_a_third_party(fmu_file, tmp_path / "v")


def cross_check_as_a_third_party(fmu_file, folder):
    """The FMI cross-check rules: the FMU at its default start values, the ``_in.csv`` input,
    the ``.opt`` times, and fmpy's ``validate_result``: no sample may lie outside the band."""
    from fmpy import simulate_fmu
    from fmpy.util import read_csv, validate_result
    opt = dict(line.split(", ") for line in (folder / "PipePlug_ref.opt").read_text().split("\n")
               if line)
    start, stop, step = (float(opt[k]) for k in ("StartTime", "StopTime", "StepSize"))
    reference = read_csv(folder / "PipePlug_ref.csv")
    result = simulate_fmu(fmu_file, start_time=start, stop_time=stop, output_interval=step,
                          input=read_csv(folder / "PipePlug_in.csv"),
                          output=list(reference.dtype.names[1:]))
    assert result["time"][-1] == pytest.approx(stop, abs=1e-12)
    assert validate_result(result, reference) == 0.0
    # The reference itself, derived by hand: at the defaults there is no soil friction, so after
    # the blow the momentum of pipe and plug is the blow's impulse, M1 v_pipe + M2 v_plug = Q0 t0.
    case = cf.Case()
    after = reference["time"] >= 0.05
    momentum = case.M1 * reference["v_pipe"][after] + case.M2 * reference["v_plug"][after]
    np.testing.assert_allclose(momentum, 23e3 * 0.05, rtol=1e-13)


def test_validate_fails_on_a_wrong_fmu(pipeplug_cli, fmu_file, tmp_path):
    # A copy whose core takes P2 as the outer perimeter (docs/corrections.md A6) must fail (exit 1).
    import shutil
    import zipfile
    bad = tmp_path / "Bad.fmu"
    with zipfile.ZipFile(fmu_file) as src, zipfile.ZipFile(bad, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename.endswith("pipeplug/params.py"):
                fixed = data.replace(b"return 2.0 * math.pi * p.R1\n",
                                     b"return 2.0 * math.pi * (p.R1 + p.h1)\n")
                assert fixed != data
                data = fixed
            dst.writestr(item, data)
    shutil.rmtree(tmp_path / "v", ignore_errors=True)
    proc = pipeplug_cli("validate", "--fmu", bad, "--out", tmp_path / "v", "--random", "0",
                        check=False)
    assert proc.returncode == 1 and "failed" in proc.stdout


def test_load_signal_puts_every_edge_on_a_duplicated_stamp():
    pulses = [(0.01, 0.0123, 5.0), (0.05, 0.01, -2.0)]
    sig = Load.from_pulses(pulses).signal(0.1)
    for edge in [e for s, d, _ in pulses for e in (s, s + d)]:
        assert np.count_nonzero(sig["time"] == edge) == 2
    assert sig["Q"][sig["time"] < 0.01].max() == 0.0
    load = Load.from_pulses(pulses)
    assert [load.at(t) for t in (0.0, 0.01, 0.015, 0.0223, 0.05, 0.06, 0.1)] == [
        0.0, 5.0, 5.0, 0.0, -2.0, -2.0, 0.0]


def test_an_unknown_figure_is_a_one_line_mistake(pipeplug_cli, fmu_file):
    """--only 8 ended in a traceback (KeyError)."""
    proc = pipeplug_cli("figures", "--fmu", fmu_file, "--only", "8", check=False)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1
    assert "invalid choice: '8'" in proc.stderr and "6a" in proc.stderr


def test_figures_draws_pngs(pipeplug_cli, fmu_file, tmp_path):
    pipeplug_cli("figures", "--fmu", fmu_file, "--out", tmp_path / "f", "--only", "4", "6b")
    for name in ("fig4.png", "fig6b.png"):
        data = (tmp_path / "f" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


def test_fmi3_cross_check_files_in_the_rules_layout_pass_as_a_third_party(fmi3_files, tmp_path):
    """validate --fmi 3 writes the cross-check files under fmus/3.0/cs/x86_64-linux/<tool>/
    <version>/PipePlug/; the FMI 3.0 FMU run on them as the rules run it passes."""
    from pipeplug import __version__
    from pipeplug_harness import io
    from pipeplug_harness.validate.command import write_cross_check
    with io.OutputFolder(tmp_path / "v", "validate") as out:
        folder = write_cross_check(out, 3)
    assert folder == tmp_path.joinpath("v", "fmus", "3.0", "cs", "x86_64-linux", "PipePlug",
                                       __version__, "PipePlug")
    cross_check_as_a_third_party(fmi3_files["PipePlug"], folder)


@pytest.mark.parametrize("command", ["validate", "figures"])
def test_an_fmu_of_another_fmi_version_is_a_one_line_mistake(pipeplug_cli, fmu_file, command,
                                                            tmp_path):
    proc = pipeplug_cli(command, "--fmi", "3", "--fmu", fmu_file, "--out", tmp_path / "x",
                        check=False)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1, proc.stderr
    assert "fmiVersion = '2.0'; allowed: an FMI 3.0 FMU (--fmi 3)" in proc.stderr


def test_stress_profile_figure_from_the_fmi3_fmu_follows_dalembert_without_friction(
        pipeplug_cli, fmi3_files, tmp_path):
    """figures --fmi 3 --only stress: without friction the FMU's stress_pipe_profile is, at
    every section more than one grid cell from a front, d'Alembert's free rod (derived here):
    the blow's wave of -Q/S1 between its front x = c t and tail x = c (t - T), and its
    reflection at the free end x = L with the opposite sign."""
    pipeplug_cli("figures", "--fmi", "3", "--only", "stress", "--fmu", fmi3_files["PipePlug"],
                 "--out", tmp_path / "f")
    data = (tmp_path / "f" / "stress_profile.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000
    rows = list(csv.DictReader(open(tmp_path / "f" / "stress_profile.csv")))
    c, L, T, dx = 5000.0, 1.0, 1e-4, 0.01          # sqrt(1.95e11 / 7800), defaults, the blow
    sigma = -23e3 / (np.pi * (0.038 ** 2 - 0.035 ** 2))
    checked = 0
    for row in rows:
        if row["scene"] != "frictionless":
            continue
        t, x, stress = float(row["t [s]"]), float(row["x [m]"]), float(row["stress [Pa]"])
        fronts = [c * t, c * (t - T), 2 * L - c * t, 2 * L - c * (t - T)]
        if min(abs(x - f) for f in fronts) <= 1.01 * dx:
            continue
        incident = sigma if c * (t - T) < x < c * t else 0.0
        reflected = -sigma if c * (t - T) < 2 * L - x < c * t else 0.0
        assert stress == pytest.approx(incident + reflected, abs=1e-6 * abs(sigma)), row
        checked += 1
    assert checked > 400
