"""Cases of a sweep run through the core: the paper's Fig. 2 domains from the mode sequences
against the closed form (an independent reference), boundary points, failing cases."""
import math

import pytest

from pipeplug_harness.sweep.domains import classify, on_boundary
from pipeplug_harness.sweep.file import sweep_spec
from pipeplug_references import closed_form as cf

BASE = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1.0e4},
        "soil": {"tau1": 0.0, "contact_growth": False}, "model": {"elastic": False},
        "blows": {"amplitude": 23e3, "duration": 0.05}, "output": {"modes": True}}
CASE = cf.Case()
TAU_STAR, GAMMA = CASE.tau_star, CASE.gamma


def _rows(grid, chunk=1000):
    base = {name: {k: v for k, v in keys.items() if k not in grid} if isinstance(keys, dict)
            else keys for name, keys in BASE.items()}        # a varied key is not fixed too
    spec = sweep_spec("t", {**base, "grid": grid, "sweep": {"chunk": chunk}})
    table = spec.run_chunk(0)
    assert table.num_rows == spec.n_cases
    return spec, table


def test_mode_sequences_give_the_analytic_domains_off_the_boundaries():
    """A coarse grid over all five domains (cell centres, none on a boundary)."""
    spec, table = _rows({"tau1": {"start": 2.5e3, "stop": 117.5e3, "num": 24},
                         "tau2": {"start": 2.5e3, "stop": 77.5e3, "num": 16}})
    rows = classify(spec, table)
    assert not any(r["boundary"] for r in rows)
    assert [r for r in rows if r["seen"] != r["expected"]] == []
    assert {r["seen"] for r in rows} == {"I", "II", "III", "IV", "V"}


def test_points_on_the_boundaries_are_recognised():
    """Points exactly on tau1 = tau* and on tau1 = gamma tau2 (to round-off) count as on a
    boundary; one a hair inside a domain does not. Their runs end at rest with some sequence."""
    t2 = 2.0e4
    spec, table = _rows({"tau1": [TAU_STAR, GAMMA * t2, GAMMA * t2 * (1 - 1e-9)], "tau2": [t2]})
    rows = classify(spec, table)
    assert [r["boundary"] for r in rows] == [True, True, False]
    assert rows[2]["seen"] == rows[2]["expected"] == "II"      # gamma tau2 > tau1: they stick
    assert rows[0]["modes"] == "(0,0)"                     # tau1 = tau*: nothing moves (A7)
    assert all(r["error"] == "" for r in rows)
    assert on_boundary(cf.Case(tau1=TAU_STAR - GAMMA * t2, tau2=t2))
    assert not on_boundary(cf.Case(tau1=TAU_STAR * (1 - 1e-6) - GAMMA * t2, tau2=t2))


def test_final_displacements_of_a_blow_case_are_the_closed_form_s():
    """Domain I of errata A1 (tau1 = 0.02, tau2 = 0.01 MPa): U1 and U2 at rest."""
    _, table = _rows({"tau1": [2e4], "tau2": [1e4]})
    row = table.to_pylist()[0]
    exact = cf.solution(cf.Case(tau1=2e4, tau2=1e4), [row["t_end"]])
    u1, u2 = exact["U1"][0], exact["U2"][0]
    assert row["at_rest"] and row["modes"] == "(1,1),(1,-1),(0,-1),(0,0)"
    assert row["u_pipe"] == pytest.approx(u1, rel=1e-12)
    assert row["u_plug"] == pytest.approx(u2, rel=1e-12)


def test_a_failing_case_is_a_row_with_its_error_and_the_others_go_on():
    """dx = 0.3 m does not divide L1 = 1 m: the elastic model refuses that case only."""
    spec = sweep_spec("t", {**BASE, "grid": {"dx": [0.25, 0.3]}, "model": {"elastic": True},
                            "output": {"stop_time": 0.06}})
    rows = spec.run_chunk(0).to_pylist()
    assert rows[0]["error"] == "" and math.isfinite(rows[0]["u_pipe"])
    assert "dx" in rows[1]["error"] and rows[1]["u_pipe"] is None


def test_a_sweep_of_hammer_drives_varies_the_hammer():
    """Drives by a hammer in a sweep: a more efficient hammer (more of its rated energy in the
    ram) needs no more blows, and each case is the drive run on its own."""
    from pipeplug_harness.drive.file import drive_spec
    from pipeplug_harness.drive.run import run_drive_on_core
    from pipeplug_harness.spec import DRIVE, checked

    base = {"pipe": {"L1": 4.0, "R1": "295 mm", "h1": "9.5 mm"},
            "plug": {"L2": 4.0, "tau2": "10 kPa"}, "soil": {"tau1": "10 kPa"},
            "hammer": {"rated_energy": "40.5 kJ", "ram_mass": "2000 kg", "rate": "200 /min",
                       "cushion_stiffness": "2e9 N/m", "cushion_restitution": 0.8},
            "model": {"elastic": True, "dx": 0.25}, "drive": {"target": 2.0}}
    spec = sweep_spec("t", {**base, "grid": {"efficiency": [0.3, 0.6]},
                            "sweep": {"kind": "drive"}})
    rows = spec.run_chunk(0).to_pylist()
    assert [r["error"] for r in rows] == ["", ""]
    assert [r["outcome"] for r in rows] == ["target", "target"]
    assert rows[1]["blows"] <= rows[0]["blows"]
    alone = run_drive_on_core(drive_spec("x", checked(
        {**base, "hammer": {**base["hammer"], "efficiency": 0.3}}, DRIVE)))
    assert (len(alone.blows), alone.penetration) == (rows[0]["blows"], rows[0]["penetration"])
