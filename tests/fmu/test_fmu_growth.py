"""The growing plug and clean-outs through PipePlug.fmu by the contract's names (``plug_growth``,
``L2_after_cleanout``, input ``cleanouts``, outputs ``L2_now``, ``W_accretion``,
``W_removed``), against the independent reference (pipeplug_references.growth_ivp)."""
from __future__ import annotations

import numpy as np
import pytest
from fmu_helpers import run_scenario

from pipeplug_references.growth_ivp import simulate_growth

PARAMS = {"plug_growth": True, "L1": 3.0, "L2": 0.0, "tau1": 1e4, "L2_after_cleanout": 0.02}
Q, T0 = 23e3, 0.01
TIMES = [k * 1e-3 for k in range(61)]
#: cleanouts rises at 12 ms, falls at 15 ms (nothing removed), rises again at 20 ms
SCHEDULE = {0.012: 1, 0.015: 0, 0.02: 1}


def test_growth_and_cleanouts_through_the_fmu(fmu_dir):
    result = run_scenario("cleanouts", fmu_dir, params=PARAMS, times=TIMES, q0=Q, t0=T0,
                          schedule=SCHEDULE, save_index=24)
    rows = result["rows"]
    assert all(r["status"] == 0 for r in rows)
    ref = simulate_growth({k: v for k, v in PARAMS.items() if k != "plug_growth"},
                          [(T0, Q)], np.array(TIMES[1:]), cleanouts=(0.012, 0.02))
    w = ref["W_input"].max()
    for name, scale in (("L2_now", 3.0), ("u_pipe", 3.0), ("v_pipe", 50.0), ("v_plug", 50.0),
                        ("W_accretion", w), ("W_removed", w), ("W_input", w)):
        got = np.array([r[name] for r in rows])
        assert np.abs(got - ref[name]).max() <= 1e-9 * scale, name
    # rows[k]: after the step from TIMES[k]; the clean-outs act at the start of rows[12], [20]
    l2 = [r["L2_now"] for r in rows]
    relative = [r["u_pipe"] - r["u_plug"] for r in rows]
    for k in (12, 20):
        assert l2[k - 1] > 0.02
        assert l2[k] == pytest.approx(0.02 + relative[k] - relative[k - 1], abs=1e-12)
    removed = [r["W_removed"] for r in rows]
    assert removed[11] == 0.0 < removed[12] == removed[19] < removed[20]
    ledger = [r["W_input"] - r["E_kinetic"] - r["W_friction"] - r["W_face"] - r["W_accretion"]
              - r["W_removed"] for r in rows]
    assert np.abs(ledger).max() <= 1e-12 * w
    assert result["again"] == rows[25:]           # a restored state runs the same


def test_cleanouts_without_plug_growth_are_discarded(fmu_dir):
    result = run_scenario("cleanout_without_growth", fmu_dir, params={}, h=1e-3)
    assert result["refused"] == 2
    line = result["log_at_refusal"][-1]["message"]
    assert "cleanouts" in line and "plug_growth" in line


def test_a_cleanout_length_beyond_the_pipe_is_refused(fmu_dir):
    result = run_scenario("bad_input", fmu_dir, kind="parameters",
                          value={"L2_after_cleanout": 2.0})
    assert result["statuses"]["exit_init"] == 3
    (line,) = result["log"][:result["lines_at_refusal"]]
    assert "L2_after_cleanout = 2.0" in line["message"] and "L1" in line["message"]
