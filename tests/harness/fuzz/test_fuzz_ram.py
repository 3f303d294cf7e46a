"""The fuzz of model I with a ram: its cases, a fixed-seed share of the campaign through the
core, the ODE reference with a ram and the FMU's strikes, and planted defects it must find."""
from __future__ import annotations

import json
import re

import numpy as np
from fuzz_helpers import count

from pipeplug import build_model
from pipeplug_harness.fuzz.cases import Plan
from pipeplug_harness.fuzz.engine import fuzz
from pipeplug_harness.fuzz.paths import CORE_PATHS
from pipeplug_harness.fuzz.ram_cases import generate_ram, ram_from_json, ram_to_json
from pipeplug_harness.fuzz.ram_run import COLUMN, sign_violations
from pipeplug_harness.fuzz.report import load_failure, save_failure
from pipeplug_harness.fuzz.run import CaseResult, Setup

PLAN = Plan(reference=3, fmu=0, fd=0, model="ram")


def test_a_case_depends_on_seed_and_index_only_round_trips_and_replays(tmp_path):
    a = generate_ram(7, 31, PLAN)
    assert generate_ram(7, 31, PLAN) == a
    assert generate_ram(8, 31, PLAN) != a and generate_ram(7, 32, PLAN) != a
    for i in range(10):
        case = generate_ram(3, i, PLAN)
        assert ram_from_json(json.loads(json.dumps(ram_to_json(case)))) == case
        assert not case.growth and case.params["ram_mass"] > 0.0 and case.strikes
        for grid in case.grids.values():           # every grid holds every strike
            assert {t for t, _ in case.strikes} <= set(grid)
    result = CaseResult(a.seed, a.index, a.model, a.checks)
    path = save_failure(result, a, tmp_path, ("compiled",))
    assert load_failure(path)[0] == a


def test_fuzz_finds_no_failure(pipeplug_cli, fmu_dir):
    cases = 60
    proc = pipeplug_cli("fuzz", "--model", "ram", "--seed", 301, "--cases", cases,
                        "--reference-every", 3, "--fmu-every", 10, "--fmu", fmu_dir,
                        "--out", "out", "--workers", 1, check=False)   # (the suite's
    # two workers already use both cores: a second Dask worker would only add its start-up)
    text = proc.stdout
    print(text)
    assert proc.returncode == 0, text + proc.stderr
    assert count(r"cases: (\d+)", text) == cases
    assert count(r"failing cases: (\d+)", text) == 0
    for check in ("ram ledger [compiled]", "ram energies [compiled]", "grid [compiled]",
                  "friction work [compiled]", "reference [python]", "paths [compiled]",
                  "fmu [fmu t+=h]", "fmu [fmu t=k*h]"):
        assert re.search(re.escape(check) + r"\s+\d+\s+0\s", text), check


class _SoftStrike:
    """A planted defect: every strike at 0.999 of its velocity."""

    def __init__(self, model):
        self._model = model

    def strike(self, velocity):
        self._model.strike(0.999 * velocity)

    def __getattr__(self, name):
        return getattr(self._model, name)


def test_the_fuzz_finds_a_strike_at_the_wrong_speed(monkeypatch):
    """Strikes 0.1 % slow: the reference finds every case it compares."""
    monkeypatch.setitem(CORE_PATHS, "python",
                        lambda params, options: _SoftStrike(build_model(params, options,
                                                                        compiled=False)))
    summary, _ = fuzz(5, range(6), Plan(reference=1, fmu=0, fd=0, model="ram"),
                      Setup(paths=("python",)), progress=None)
    assert summary.rows[("reference", "python")][1] >= 5


def test_the_fuzz_finds_a_ledger_that_does_not_close(monkeypatch):
    """The cushion's loss not booked: the ledger breaks wherever a cushion loses energy."""
    class _NoLoss:
        def __init__(self, model):
            self._model = model

        def outputs(self):
            return self._model.outputs()._replace(W_cushion=0.0)

        def __getattr__(self, name):
            return getattr(self._model, name)

    monkeypatch.setitem(CORE_PATHS, "python",
                        lambda params, options: _NoLoss(build_model(params, options,
                                                                    compiled=False)))
    summary, _ = fuzz(5, range(12), Plan(reference=0, fmu=0, fd=0, model="ram"),
                      Setup(paths=("python",)), progress=None)
    assert summary.rows[("ram ledger", "python")][1] >= 4


def test_a_plug_sliding_at_its_limit_books_friction_work_that_never_decreases():
    """Two campaign cases (seed:index 2028:191, 31:2235) whose plug slides on the pipe at a
    relative velocity and acceleration of round-off size: the slip's friction work decreased
    by 1e-17 of the largest work between samples while it was a difference of displacements.
    The invariant needs no reference: friction work never decreases."""
    from pipeplug_harness.fuzz.ram_run import run_ram_case

    for seed, index in ((2028, 191), (31, 2235)):
        case = generate_ram(seed, index, Plan(reference=0, fmu=0, fd=0, model="ram"))
        result = run_ram_case(case, Setup(("python",)))
        assert result.values[("friction work", "python")] == 0.0, (seed, index)
        assert result.failed == [], (seed, index, result.failed)


def test_a_displacement_the_reference_holds_at_zero_allows_round_off_drift_only(monkeypatch):
    """Where the reference holds pipe and plug at exactly 0 the displacements have no scale
    (fuzz 4051:6110 reported inf). The core may drift no farther than 16 ulps of the largest
    static force move the pipe over the run (derived here from the case's numbers: F1 = 2 pi
    (R1 + h1) L1 tau1 or the largest |Q|, a = 16 eps F / M1, a T^2 / 2); 1.1e-9 m, the slide
    that case's reference had missed, fails."""
    import math

    import numpy as np

    from pipeplug import OUTPUT_NAMES
    from pipeplug_harness.fuzz import ram_run
    from pipeplug_harness.fuzz.runners import COLUMN
    from pipeplug_references import ram_ivp

    case = generate_ram(4051, 6110)
    p = case.params
    M1 = p["rho1"] * math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2) * p["L1"]
    F = max(2.0 * math.pi * (p["R1"] + p["h1"]) * p["L1"] * p["tau1"],
            *(abs(q) for _, q in case.segments))
    drift = 0.5 * 16.0 * np.finfo(float).eps * F / M1 * case.stop ** 2
    n = len(case.grids["fine"]) - 1

    def held(params, ram, history, times):
        out = {name: np.zeros(n) for name in ram_ivp.OUTPUTS}
        out["v_ram"] = out["W_ram"] = np.ones(n)
        return out

    monkeypatch.setattr(ram_ivp, "simulate_ram", held)
    values = []
    for creep in (0.5 * drift, 2.0 * drift, 1.1e-9):
        rows = np.zeros((n, len(OUTPUT_NAMES)))
        rows[:, COLUMN["v_ram"]] = rows[:, COLUMN["W_ram"]] = 1.0
        rows[-1, COLUMN["u_pipe"]] = creep
        result = CaseResult(case.seed, case.index, case.model, case.checks)
        ram_run._reference(case, [rows] * len(case.grids), "python", result)
        values.append(result.values[("reference", "python")])
    assert values[0] <= 1e-9 < values[1] < values[2] < math.inf


def test_a_loss_that_falls_is_a_sign_violation():
    """W_cushion, W_face and the friction work are losses: one that falls by more than 1e-12 of
    the largest work is flagged though it stays >= 0 (a strike used to lower W_cushion)."""
    rows = np.zeros((3, len(COLUMN)))
    rows[:, COLUMN["W_input"]] = 10.0
    rows[:, COLUMN["E_kinetic"]] = [4.0, 4.0, 4.5]
    rows[:, COLUMN["W_cushion"]] = [1.0, 1.0, 0.5]        # falls at the third point
    assert sign_violations(rows) == 1.0
    rows[2, COLUMN["W_cushion"]] = 1.0 - 1e-13              # round-off: not flagged
    assert sign_violations(rows) == 0.0
