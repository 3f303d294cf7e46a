"""The fd check where model II's pipe enters the soil against its end resistance: the errors
its position error there explains."""
from __future__ import annotations

import numpy as np

from pipeplug import build_model
from pipeplug_harness.fuzz.cases import generate
from pipeplug_harness.fuzz.checks import Body
from pipeplug_harness.fuzz.fdcheck import FdResult, _entries, _explained
from pipeplug_harness.fuzz.run import FD_PATHS, Setup, run_case
from pipeplug_harness.fuzz.runners import COLUMN

BODY = Body(M1=5.0, M2=0.0, F2=0.0, k1=1e5, L1=1.0, growth=True, Qf=7e4)


def _rows(u, v):
    rows = np.zeros((len(u), len(COLUMN)))
    rows[:, COLUMN["u_pipe"]], rows[:, COLUMN["v_pipe"]] = u, v
    return rows


def test_entries_are_where_the_pipe_crosses_zero_forward_at_the_interpolated_speed():
    # u from -0.02 to 0.06 over a step, v from 5 to 3 m/s: a quarter of the step before the
    # entry, v = 5 - 0.25 * 2 = 4.5 m/s there; the second, u -0.01 to 0.01: v = 1.5 m/s
    rows = _rows([-0.02, 0.06, 0.1, -0.01, 0.01], [5.0, 3.0, -1.0, 2.0, 1.0])
    assert _entries(rows, BODY) == [(0, 4.5), (3, 1.5)]


def test_no_entry_no_end_resistance_or_model_I_explain_nothing():
    leaving = _rows([0.1, 0.01, -0.01], [-1.0, -2.0, -3.0])          # backward, out of the soil
    assert _entries(leaving, BODY) == []
    entering = _rows([-0.02, 0.06], [5.0, 3.0])
    assert _entries(entering, BODY._replace(Qf=0.0)) == []
    assert _entries(entering, BODY._replace(growth=False)) == []


def test_the_explained_errors_follow_the_position_error_at_the_entry():
    """The exact run enters between its points 1 and 2 at 4 m/s; the fd run, 1 mm ahead, one
    point earlier. From point 1 on (the earlier entry), the velocity error explained is
    Qf du / (M1 v) + k1 du t / M1 = 7e4 * 1e-3 / (5 * 4) + 1e5 * 1e-3 / 5 * t = 3.5 + 20 t
    m/s, and the displacement error its integral 3.5 t + 10 t^2 m, t from point 0."""
    times = np.array([0.0, 0.1, 0.2, 0.3])
    exact = _rows([-0.3, -0.0005, 0.3, 0.5], [4.0, 4.0, 4.0, 4.0])
    fd = _rows([-0.299, 0.0005, 0.301, 0.501], [4.0, 4.0, 4.0, 4.0])
    assert _entries(exact, BODY)[0][0] == 1 and _entries(fd, BODY)[0][0] == 0
    dv, du = _explained(fd, exact, times, BODY)
    t = times[1:] - times[0]
    np.testing.assert_allclose(dv, [0.0, 3.5 + 20 * t[0], 3.5 + 20 * t[1], 3.5 + 20 * t[2]])
    np.testing.assert_allclose(du, [0.0, *(3.5 * t + 10 * t * t)])


def test_a_pipe_flying_back_into_the_soil_passes_the_fd_check_at_first_order():
    """Case 9177:1600 (model II, q_face = 1e8 Pa): pulled out of the soil, the pipe flies 0.6 m
    and back in at 61 m/s; the position error of the flight moves its entry, and the face's
    69 kN over that time make the velocity error (K was 0.97 against the bound of 0.6)."""
    case = generate(9177, 1600)
    assert case.growth and case.params["q_face"] > 0.0 and "fd" in case.checks
    result = run_case(case, Setup())
    assert result.failed == []
    fd = FdResult(*result.fd)
    assert fd.resolved and not fd.grazing and abs(fd.order - 1.0) <= 0.1


def test_a_wrong_face_force_is_still_caught_on_that_case(monkeypatch):
    """What the entry explains is the position error's consequence, not the scheme's: an fd
    scheme with a face force 5 % off converges to another solution there, and fails."""
    def wrong(params, options):
        return build_model({**params, "q_face": params["q_face"] * 1.05}, options)
    monkeypatch.setitem(FD_PATHS, "fd", wrong)
    failed = run_case(generate(9177, 1600), Setup()).failed
    assert ("fd bound", "fd") in failed and ("fd order", "fd") in failed
