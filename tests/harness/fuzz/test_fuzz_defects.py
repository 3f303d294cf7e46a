"""The fuzz finds planted defects, and a saved failing case replays them.

Each defect is a core path (or an fd path) of its own, registered for the test; the fuzz runs
a few dozen cases on it and must report the check that the defect breaks, and only the ones
it can break.
"""
from __future__ import annotations

import json
import math
import shlex

import pytest

from pipeplug import build_model
from pipeplug_harness.fuzz.cases import Plan, generate
from pipeplug_harness.fuzz.command import replay
from pipeplug_harness.fuzz.engine import fuzz
from pipeplug_harness.fuzz.paths import CORE_PATHS, FD_PATHS
from pipeplug_harness.fuzz.run import Setup, run_case

INVARIANTS = ("grid", "energy", "friction work", "stuck", "static limits", "at rest")


class Skewed:
    """A model whose outputs are altered by ``change(outputs, model)``."""

    def __init__(self, model, change):
        self.model, self.change, self.steps = model, change, 0

    def advance_to(self, q, t):
        self.steps += 1
        self.model.advance_to(q, t)

    def outputs(self):
        return self.change(self.model.outputs(), self)


def skewed(change):
    return lambda params, options: Skewed(build_model(params, options), change)


def _run(monkeypatch, builder, cases=40, plan=None, seed=4, failures=None):
    monkeypatch.setitem(CORE_PATHS, "defect", builder)
    summary, _ = fuzz(seed, range(cases), plan or Plan(1, 0, 0), Setup(("defect",)),
                      failures=failures, progress=None)
    return summary


def _failed(summary, check, subject="defect") -> int:
    return summary.rows.get((check, subject), [0, 0])[1]


def _wrong_model(params, options):
    """The inner limit 1e-6 too low: consistent with itself, and within the checks' limit."""
    return build_model({**params, "tau2": params["tau2"] * (1.0 - 1e-6)}, options)


def test_a_wrong_model_fails_the_reference_check_only(monkeypatch):
    summary = _run(monkeypatch, _wrong_model)
    assert _failed(summary, "reference") >= 5
    assert all(_failed(summary, check) == 0 for check in INVARIANTS)


@pytest.mark.parametrize("check, change", [
    ("grid", lambda out, m: out._replace(u_pipe=out.u_pipe + 1e-9 * m.steps)),
    ("energy", lambda out, m: out._replace(W_input=out.W_input * (1.0 + 1e-10))),
    ("stuck", lambda out, m: out._replace(v_pipe=out.v_pipe + 1e-300 * (out.pipe_mode == 0))),
    ("friction work", lambda out, m: out._replace(
        W_friction=out.W_friction * (1.0 - 1e-15 * (m.steps % 2)))),
    ("static limits", lambda out, m: out._replace(F_outer=out.F_outer * (1.0 + 1e-9))),
])
def test_each_invariant_catches_its_defect(monkeypatch, check, change):
    summary = _run(monkeypatch, skewed(change), plan=Plan(0, 0, 0))
    assert _failed(summary, check) >= 3


def test_a_nan_output_fails(monkeypatch):
    summary = _run(monkeypatch, skewed(lambda out, m: out._replace(W_input=math.nan)),
                   cases=5, plan=Plan(0, 0, 0))
    assert summary.failures == 5
    assert not math.isfinite(summary.rows[("energy", "defect")][2])


def test_a_nan_late_in_a_later_column_fails(monkeypatch):
    """A NaN that Python's ``max`` would drop (not the first value it compares) still fails:
    F_inner is neither the first column of the grid check nor the first limit checked."""
    summary = _run(monkeypatch, skewed(lambda out, m: out._replace(
        F_inner=math.nan if m.steps >= 3 else out.F_inner)), cases=5, plan=Plan(0, 0, 0))
    assert summary.failures == 5
    assert _failed(summary, "grid") == 5
    assert _failed(summary, "static limits") == 5


def test_a_claimed_rest_that_moves_is_caught(monkeypatch):
    summary = _run(monkeypatch, skewed(lambda out, m: out._replace(at_rest=out.v_pipe == 0.0)),
                   plan=Plan(0, 0, 0))
    assert _failed(summary, "at rest") >= 1


def test_an_exception_is_a_failure_with_its_message(monkeypatch):
    def fragile(params, options):
        if params["tau1"] > 0.0:
            raise ZeroDivisionError("planted")
        return build_model(params, options)
    monkeypatch.setitem(CORE_PATHS, "defect", fragile)
    result = run_case(generate(4, 1), Setup(("defect",)))
    assert result.failed == [("exception", "defect")]
    assert "planted" in result.errors[("exception", "defect")]


def test_a_wrong_fd_scheme_fails_bound_and_order(monkeypatch):
    """fd with an outer limit 5 % off converges to another solution: no first order. Case 6
    of seed 2: model I, the pipe slides on the soil (order 1.000 with the right scheme)."""
    def wrong(params, options):
        return build_model({**params, "tau1": params["tau1"] * 1.05}, options)
    case = generate(2, 6, Plan(1, 0, 1))
    assert run_case(case, Setup()).failed == []
    monkeypatch.setitem(FD_PATHS, "fd", wrong)
    failed = run_case(case, Setup()).failed
    assert ("fd bound", "fd") in failed and ("fd order", "fd") in failed


def test_a_saved_failure_replays(monkeypatch, tmp_path, capsys):
    summary = _run(monkeypatch, _wrong_model, cases=20, failures=tmp_path)
    files = sorted(tmp_path.glob("case-4-*.json"))
    assert summary.failures == len(files) >= 1
    data = json.loads(files[0].read_text())
    assert data["paths"] == ["defect"] and data["failed"][0]["check"] == "reference"
    # the stored command names the file by its whole path (its name alone failed elsewhere)
    assert shlex.split(data["replay"]) == ["pipeplug", "fuzz", "--replay",
                                           str(files[0].resolve())]
    assert replay(str(files[0])) == 1                       # on the file's (defective) path
    assert "FAILED" in capsys.readouterr().out
    assert replay(str(files[0]), Setup(("python",)), paths_given=True) == 0   # the core's


def test_a_path_that_differs_from_the_first_by_rounding_fails_the_paths_check(monkeypatch):
    """A second path off by a few ulps (far below every other check's tolerance) is caught."""
    nudged = skewed(lambda out, m: out._replace(u_pipe=out.u_pipe * (1.0 + 4e-15)))
    monkeypatch.setitem(CORE_PATHS, "defect", nudged)
    summary, _ = fuzz(4, range(20), Plan(0, 0, 0), Setup(("python", "defect")), progress=None)
    assert _failed(summary, "paths") >= 3
    assert _failed(summary, "paths", "python") == 0
    assert all(_failed(summary, check) == 0 for check in INVARIANTS)


def _weak_face(params, options):
    """The end resistances 1e-6 too weak: consistent with itself (ledger, invariants)."""
    return build_model({**params, "q_face": params.get("q_face", 0.0) * (1.0 - 1e-6),
                        "q_plug_face": params.get("q_plug_face", 0.0) * (1.0 - 1e-6)}, options)


def test_a_wrong_end_resistance_fails_the_reference_check_only(monkeypatch):
    summary = _run(monkeypatch, _weak_face, cases=20)
    assert _failed(summary, "reference") >= 3
    assert all(_failed(summary, check) == 0 for check in INVARIANTS)


def test_end_resistance_work_that_is_not_booked_fails_the_energy_check(monkeypatch):
    summary = _run(monkeypatch, skewed(lambda out, m: out._replace(W_face=0.0)), cases=20,
                   plan=Plan(0, 0, 0))
    assert _failed(summary, "energy") >= 3


def _weak_damping(params, options):
    """Smith damping 1e-4 too weak: consistent with itself (ledger, invariants)."""
    weak = {k: params[k] * (1.0 - 1e-4) for k in ("J_shaft", "J_face") if k in params}
    return build_model({**params, **weak}, options)


def _run_damped(monkeypatch, builder, plan):
    """Three cases of seed 2 with damping that acts (and the reference affordable)."""
    monkeypatch.setitem(CORE_PATHS, "defect", builder)
    return fuzz(2, (49, 52, 56), plan, Setup(("defect",)), progress=None)[0]


def test_a_wrong_damping_fails_the_reference_check_only(monkeypatch):
    summary = _run_damped(monkeypatch, _weak_damping, Plan(1, 0, 0))
    assert _failed(summary, "reference") == 3
    assert all(_failed(summary, check) == 0 for check in INVARIANTS)


def test_damping_work_that_is_not_booked_fails_the_energy_check(monkeypatch):
    summary = _run_damped(monkeypatch, skewed(lambda out, m: out._replace(W_damping=0.0)),
                          Plan(0, 0, 0))
    assert _failed(summary, "energy") == 3
