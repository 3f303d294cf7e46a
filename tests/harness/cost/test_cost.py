"""The ``cost`` study on its quick settings, and its pieces against hand-derived values."""
import argparse
import csv
import math
import statistics
from collections import defaultdict

import numpy as np
import pytest

import pipeplug
from pipeplug_harness.cost import command as cost
from pipeplug_harness.cost.cases import default_cases, quick_cases
from pipeplug_harness.cost.front import fastest_reaching, pareto_front, time_to_error
from pipeplug_harness.cost.regularised import TanhFriction
from pipeplug_references.closed_form import domain, stop_times

FILES = ("cost.csv", "cost_comm.csv", "cost_creep.csv", "cost.md", "cost_pareto.png",
         "cost_creep.png")
REGULARISED = ("LSODA", "odeint-LSODA", "Radau")


def _read(path):
    """The rows of a CSV file, the units left out of the column titles."""
    with open(path, newline="") as f:
        return [{k.split(" [")[0]: v for k, v in row.items()} for row in csv.DictReader(f)]


def _floats(row, *keys):
    return [float(row[k]) for k in keys]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("cost")
    parser = argparse.ArgumentParser()
    cost.add_arguments(parser)
    assert cost.main(parser.parse_args(["--quick", "--out", str(out)])) == 0
    return out


@pytest.fixture(scope="module")
def rows(study):
    return _read(study / "cost.csv")


def _elastic_builds():
    bench = quick_cases()[0]
    try:
        pipeplug.build_model(dict(bench.params, dx=cost.quick_config().elastic_dxs[0]),
                             {"elastic": True})
    except (ImportError, pipeplug.ParameterError):
        return False
    return True


def test_files_are_written(study):
    for name in FILES:
        assert (study / name).stat().st_size > 0, name
    for name in ("cost_pareto.png", "cost_creep.png"):
        assert (study / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = (study / "cost.md").read_text()
    assert "exact vs best LSODA" in text and "exact vs best Radau" in text
    assert "Exact against the fastest regularised setting" in text and "median ratio" in text
    assert "cases/s** on one core" in text


def test_the_report_states_the_exact_solvers_time_per_case_against_its_goal(study, rows):
    times = sorted(float(r["wall_s"]) for r in rows if r["method"] == "exact")
    median = statistics.median(times)
    text = (study / "cost.md").read_text()
    assert (f"median **{1e6 * median:.1f} µs**, slowest **{1e6 * times[-1]:.1f} µs** (goal on "
            "the compiled path: at most 10 µs per case)") in text


def test_every_method_family_is_in_the_csv(rows):
    methods = {r["method"] for r in rows}
    assert {"exact", "fd", *REGULARISED} <= methods
    assert ("elastic" in methods) == _elastic_builds()
    assert {r["case"] for r in rows} == {b.name for b in quick_cases()}


def test_exact_solver_is_exact(rows):
    exact = [r for r in rows if r["method"] == "exact"]
    assert exact
    for r in exact:
        assert max(_floats(r, "max_rel_error", "max_rel_disp_error")) <= 1e-10


def test_regularised_errors_exceed_the_exact_ones(rows):
    exact = {r["case"]: float(r["max_rel_error"]) for r in rows if r["method"] == "exact"}
    regularised = [r for r in rows if r["method"] in REGULARISED and r["success"] == "1"]
    assert regularised
    for r in regularised:
        assert float(r["max_rel_error"]) > max(exact[r["case"]], 1e-10), r


def test_fd_displacement_error_is_first_order_in_dt(rows):
    # The fd velocities are exact at the grid points between friction events of model I with
    # piecewise-constant forces; its displacements carry the scheme's O(dt) error.
    by_case = defaultdict(list)
    for r in rows:
        if r["method"] == "fd":
            by_case[r["case"]].append((float(r["setting"][3:]), float(r["max_rel_disp_error"])))
    assert by_case
    for case, runs in by_case.items():
        runs.sort(reverse=True)
        for (dt_a, err_a), (dt_b, err_b) in zip(runs, runs[1:]):
            assert err_b < err_a, case
            assert err_a / err_b == pytest.approx(dt_a / dt_b, rel=0.3), case


def test_exact_solver_never_creeps_and_regularised_one_does(study):
    creep = _read(study / "cost_creep.csv")
    keys = ("pipe_creep_m", "pipe_residual_v", "plug_creep_m", "plug_residual_v")
    exact = [r for r in creep if r["method"] == "exact"]
    assert exact and all(v == 0.0 for r in exact for v in _floats(r, *keys))
    pushed = [r for r in creep if r["method"] == "LSODA" and r["case"] == "III"]
    assert pushed
    for r in pushed:
        drift, speed, eps = _floats(r, "pipe_creep_m", "pipe_residual_v", "eps")
        assert drift > 0.0
        bench = next(b for b in quick_cases() if b.name == "III")
        # tanh friction holds the pipe against the plug's drag F2 < F1 only while it creeps
        assert speed == pytest.approx(eps * math.atanh(bench.case.F2 / bench.case.F1), rel=1e-3)


def test_communication_step_leaves_the_exact_solver_exact(study):
    comm = _read(study / "cost_comm.csv")
    assert {r["method"] for r in comm} == {"exact", "fd"}
    for r in comm:
        if r["method"] == "exact":
            assert float(r["max_rel_error"]) <= 1e-10


def test_cases_lie_in_their_named_domains_and_sample_t0():
    for bench in default_cases():
        if not bench.growth:
            assert domain(bench.case) == bench.name.split("-")[0]
        assert np.any(bench.times == bench.case.t0)


def test_cases_share_2000_sample_times_past_every_stop():
    cases = default_cases()
    for bench in cases:
        assert np.array_equal(bench.times, cases[0].times) and len(bench.times) == 2000
        if not bench.growth:
            assert max(stop_times(bench.case)) < bench.times[-1] or bench.case.tau1 == 0.0


def test_fastest_setting_reaching_the_target_is_taken_per_case():
    rows = [{"method": "LSODA", "setting": "a", "case": "I", "max_rel_error": 1e-7, "wall_s": 2.0},
            {"method": "Radau", "setting": "b", "case": "I", "max_rel_error": 5e-7, "wall_s": 1.0},
            {"method": "LSODA", "setting": "c", "case": "I", "max_rel_error": 2e-6, "wall_s": 0.1},
            {"method": "fd", "setting": "d", "case": "I", "max_rel_error": 1e-9, "wall_s": 0.01},
            {"method": "LSODA", "setting": "a", "case": "II", "max_rel_error": math.nan,
             "wall_s": 0.5}]
    best = fastest_reaching(rows, ("LSODA", "Radau"))
    assert best["I"]["setting"] == "b" and "II" not in best


def test_time_to_error_interpolates_log_log_on_the_front():
    points = [{"setting": "a", "wall_s": 1.0, "max_rel_error": 1e-4},
              {"setting": "slow", "wall_s": 5.0, "max_rel_error": 1e-3},
              {"setting": "b", "wall_s": 10.0, "max_rel_error": 1e-8}]
    front = pareto_front(points)
    assert [p["setting"] for p in front] == ["a", "b"]
    seconds, setting = time_to_error(front, 1e-6)
    assert seconds == pytest.approx(math.sqrt(10.0)) and setting == "b"
    assert math.isnan(time_to_error(front, 1e-9)[0])
    assert time_to_error(front, 1e-3) == (1.0, "a")


def test_regularised_jacobian_matches_finite_differences():
    bench = next(b for b in default_cases() if b.growth)
    model = TanhFriction(bench, eps=0.3)
    model.q = bench.case.Q0
    y = np.array([0.4, 0.2, 0.1, 0.05])
    h = 1e-7
    numeric = np.column_stack([(np.array(model.rhs(0.0, y + h * e)) -
                                np.array(model.rhs(0.0, y - h * e))) / (2 * h)
                               for e in np.eye(4)])
    assert np.allclose(model.jac(0.0, y), numeric, rtol=1e-6, atol=1e-6)


def test_the_report_has_the_compiled_section(study):
    text = (study / "cost.md").read_text()
    assert "## Exact against the compiled competitors" in text
    assert "No compiled competitor ran." in text          # the quick study asks for none


def test_a_competitor_that_cannot_import_is_named_with_why(monkeypatch):
    from pipeplug_harness.cost import compiled
    monkeypatch.setitem(compiled.FAMILIES, "absent", ("numpy", "no_such_module_here"))
    monkeypatch.setitem(compiled.INSTALL, "absent", "pip install it")
    why = compiled.available(["absent"])
    assert list(why) == ["absent"]
    assert "no_such_module_here" in why["absent"] and "pip install it" in why["absent"]
