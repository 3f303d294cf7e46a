"""The energy checks of the model III fuzz on hand-made ledgers: what the ledger itself allows
passes, what it forbids is found."""
from __future__ import annotations

import numpy as np
import pytest

from pipeplug_harness.fuzz.elastic_checks import (
    LEDGER_BASE,
    LEDGER_PER_STEP,
    energy_violations,
    ledger_error,
)
from pipeplug_harness.fuzz.runners import COLUMN

H = 1e-5          # internal step [s]
TIMES = np.array([100 * H, 200 * H])    # the two points: 100 and 200 steps


def _rows(first: dict, second: dict) -> np.ndarray:
    rows = np.zeros((2, len(COLUMN)))
    for i, values in enumerate((first, second)):
        for name, value in values.items():
            rows[i, COLUMN[name]] = value
    return rows


def _push_then_pull(w_input: float, w_friction: float) -> np.ndarray:
    """A pipe pushed to 2 J of kinetic energy, then pulled back to rest: the push and the
    pull leave ``w_input`` [J], friction took ``w_friction`` [J]."""
    return _rows({"W_input": 2.0, "E_kinetic": 2.0},
                 {"W_input": w_input, "W_friction": w_friction, "W_friction_outer": w_friction,
                  "at_rest": 1.0})


def test_input_work_a_few_ulps_below_zero_after_push_and_pull_is_round_off():
    """Pushes and pulls that cancel may leave W_input ulps below 0 with no friction work: the
    ledger's own allowance at the point, (1e-12 + 2.2e-16 x 200) x 2 J, covers it."""
    rows = _push_then_pull(-2.3e-14, 0.0)
    assert ledger_error(rows, TIMES, H) < 1.0
    assert energy_violations(rows, times=TIMES, h=H) == 0.0


@pytest.mark.parametrize("share, flagged", [(0.5, 0.0), (2.0, 1.0)])
def test_friction_work_beyond_the_input_by_more_than_the_ledger_allows_is_found(share, flagged):
    """W_friction may exceed W_input by what the ledger's residual may hide, no more: the
    allowance at 200 steps of a run whose largest work is 2 J."""
    allowance = (LEDGER_BASE + LEDGER_PER_STEP * 200) * 2.0
    w_friction = 1e-3
    rows = _push_then_pull(w_friction - share * allowance, w_friction)
    assert energy_violations(rows, times=TIMES, h=H) == flagged


def test_without_times_no_round_off_is_allowed():
    assert energy_violations(_push_then_pull(-2.3e-14, 0.0)) == 1.0


def test_a_cushion_loss_that_falls_is_found_even_above_zero():
    """A strike in the cushion's pull step lowered W_cushion by up to 0.16 of the run's work
    while it stayed >= 0; the check took any W_cushion above -m_cell (2 v)^2 per strike. A loss
    falls by round-off at most now."""
    rows = _rows({"W_input": 2.0, "W_cushion": 1.0, "E_kinetic": 1.0},
                 {"W_input": 2.0, "W_cushion": 0.5, "E_kinetic": 1.5})
    assert energy_violations(rows, times=TIMES, h=H) > 0.0
    steady = _rows({"W_input": 2.0, "W_cushion": 1.0, "E_kinetic": 1.0},
                   {"W_input": 2.0, "W_cushion": 1.0, "E_kinetic": 1.0})
    assert energy_violations(steady, times=TIMES, h=H) == 0.0
