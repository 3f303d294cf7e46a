"""``pipeplug stability --quick``: the table of hard cases, printed, as CSV and as markdown."""
from __future__ import annotations

import csv


def test_stability_quick_writes_the_table(pipeplug_cli, fmu_file, tmp_path):
    proc = pipeplug_cli("stability", "--quick", "--fmu", fmu_file, "--out", "stab", check=False)
    rows = list(csv.DictReader(open(tmp_path / "stab" / "stability.csv")))
    table = (tmp_path / "stab" / "stability.md").read_text()
    cases = {r["case"] for r in rows}
    assert {"boundary I/II", "pulled back", "grazing", "elastic Courant 1"} <= cases
    solvers = {(r["case"], r["solver"]) for r in rows}
    for solver in ("exact", "fd", "elastic", "FMU exact", "FMU fd"):
        assert ("boundary I/II", solver) in solvers
    by_key = {(r["case"], r["solver"]): r for r in rows}
    exact = by_key[("boundary I/II", "exact")]
    assert float(exact["err_v"]) < 1e-12 and float(exact["err_u"]) < 1e-12   # closed form
    assert float(by_key[("boundary I/II", "FMU exact")]["err_u"]) < 1e-12
    assert float(exact["drift_v [m/s]"]) == 0.0 and exact["finite"] == "1"
    assert float(by_key[("elastic Courant 1", "elastic")]["err_v"]) < 1e-12  # d'Alembert
    assert all(r["finite"] == "1" for r in rows)
    failed = [r for r in rows if r["ok"] != "1"]
    assert proc.returncode == (1 if failed else 0), proc.stdout + proc.stderr
    for r in failed:                      # the exit code and the printed table tell the same
        assert f"FAILED: {r['case']} / {r['solver']}" in proc.stdout
    assert table.splitlines()[0].startswith("| case | solver |")
    assert len(table.splitlines()) == 2 + len(rows) and "| case |" in proc.stdout
