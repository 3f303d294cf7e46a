"""Single-blow sweeps on the core's batch API: which sweeps take it, the same columns as the
per-case path (a cross-path identity), its rows against the closed form of model I (an
independent reference), and the cases and chunks it hands to the per-case path."""
import dataclasses
import math

import numpy as np
import pytest

from pipeplug_harness.sweep.file import load_sweep, sweep_spec
from pipeplug_harness.sweep.runners import batch_misses
from pipeplug_references import closed_form as cf

RIGID = {"model": {"elastic": False}, "blows": {"amplitude": 23e3, "duration": 0.05}}
#: what every sweep file must give (the values they had as the files' defaults)
REQUIRED = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1.0e4}, "soil": {"tau1": 0.0},
            "blows": {"amplitude": 23e3, "duration": 0.05}}
CASE = cf.Case()


def _spec(**raw):
    """A sweep of ``raw``'s sections over REQUIRED's (without its values of the varied keys)."""
    sections = {**REQUIRED, **RIGID, **raw}          # a section given replaces RIGID's
    varied = {**raw.get("grid", {}), **raw.get("random", {})}
    sections = {name: {**REQUIRED.get(name, {}), **keys} for name, keys in sections.items()}
    return sweep_spec("t", {name: {k: v for k, v in keys.items()
                                   if k not in varied or k in raw.get(name, {})}
                            for name, keys in sections.items()})


def _per_case(spec):
    return dataclasses.replace(spec, runner="case")


@pytest.mark.parametrize("raw, miss", [
    ({"grid": {"tau1": [1.0]}}, None),
    ({"grid": {"tau1": [1.0], "amplitude": [1e4, 2e4], "duration": [0.01, 0.1],
               "period": [1.0], "E1": [1e9], "rho1": [7800.0]},   # (dx: refused, rigid)
      "soil": {"contact_growth": True},
      "model": {"elastic": False, "solver": "exact"}, "output": {"stop_time": 5.0}}, None),
    ({"grid": {"tau1": [1.0]}, "output": {"modes": True}}, "mode sequence"),
    ({"grid": {"tau1": [1.0]}, "sweep": {"report": "domains"}}, "mode sequence"),
    ({"grid": {"tau1": [1.0]}, "model": {}}, "rigid"),              # elastic = "auto"
    ({"grid": {"tau1": [1.0]}, "model": {"elastic": False, "solver": "fd"}}, "exact solver"),
    ({"grid": {"tau1": [1.0]}, "blows": {"count": 2}}, "one blow"),
    ({"grid": {"tau1": [1.0]}, "blows": {"start": 0.1}}, "one blow"),
    ({"grid": {"start": [0.0, 0.1]}}, "one blow"),
    ({"grid": {"stop_time": [1.0, 2.0]}}, "one stop time"),
    ({"grid": {"tau1": [1.0]}, "sweep": {"kind": "drive"}, "blows": {}}, "single blows"),
])
def test_which_sweeps_take_the_batch_api(raw, miss):
    spec = _spec(**raw)
    misses = batch_misses(spec)
    assert spec.runner == ("case" if miss else "batch")
    assert (miss is None and misses == []) or any(miss in m for m in misses)


def test_the_paper_s_sweeps_take_their_paths():
    """Fig. 2 needs the mode sequences: one model per case; the drives are drives; the
    million single blows take the batch API."""
    assert load_sweep("scenes/sweeps/fig2_domains.toml").runner == "case"
    assert load_sweep("scenes/sweeps/drivability_mc.toml").runner == "case"
    assert load_sweep("scenes/sweeps/single_blows_mc.toml").runner == "batch"


#: the soil's end resistance drawn too (W_face a column of both paths)
FACE = {"q_face": {"dist": "uniform", "low": 0.0, "high": 2e7},
        "q_plug_face": {"dist": "uniform", "low": 0.0, "high": 3e5}}


@pytest.mark.parametrize("growth, face", [(False, {}), (True, {}), (True, FACE)])
def test_the_batch_path_gives_the_per_case_path_s_columns(growth, face):
    """A random sweep over parameters and the blow; stop_time short enough that some cases
    (tau1 near 0) are still moving there (handed to the per-case path) and that some come to
    rest within the last, cut step. Every column within 1e-15 of its scale."""
    spec = _spec(sweep={"samples": 300, "seed": 5, "chunk": 120},
                 random={"tau1": {"dist": "uniform", "low": 0.0, "high": 1.2e5},
                         "tau2": {"dist": "uniform", "low": 0.0, "high": 1.0e5},
                         "L2": {"dist": "uniform", "low": 0.0, "high": 1.0},
                         "rho2": {"dist": "uniform", "low": 500.0, "high": 5000.0},
                         "amplitude": {"dist": "uniform", "low": 5e3, "high": 4e4},
                         "duration": {"dist": "lognormal", "median": 0.02, "sigma": 0.5},
                         **face},
                 soil={"contact_growth": growth}, output={"stop_time": 1.0})
    assert spec.runner == "batch" and spec.n_chunks == 3
    for c in range(spec.n_chunks):
        fast, slow = spec.run_chunk(c), _per_case(spec).run_chunk(c)
        assert fast.schema == slow.schema and "modes" not in fast.column_names
        assert fast.column("case").to_pylist() == slow.column("case").to_pylist()
        for name in fast.column_names:
            a, b = fast.column(name).to_numpy(), slow.column(name).to_numpy()
            if b.dtype.kind == "f":
                scale = np.max(np.abs(b))
                assert np.all(np.abs(a - b) <= 1e-15 * scale), (c, name)
            else:
                assert np.array_equal(a, b), (c, name)
    rows = _per_case(spec).run_chunk(0).to_pylist() + _per_case(spec).run_chunk(1).to_pylist()
    if face:          # an end resistance stops every pipe early: the work against it
        assert all(r["W_face"] > 0.0 for r in rows if r["u_pipe"] > 0.0)
        return
    assert any(not r["at_rest"] for r in rows)                     # the hand-over is exercised
    assert any(r["at_rest"] and r["t_end"] == 1.0 for r in rows)   # the cut step too


def test_batch_rows_are_model_I_s_closed_form():
    """Model I, the paper's blow, over all five domains: displacements and input work at rest,
    and t_end, the end of the first step (the blow, then steps doubling from its duration)
    after the closed form's rest time."""
    taus = np.array([(0.3, 0.1), (0.6, 0.05), (0.4, 0.3), (0.9, 0.4), (1.1, 0.2)])
    spec = _spec(grid={"tau1": (taus[:, 0] * CASE.tau_star).tolist(),
                       "tau2": (taus[:, 1] * CASE.tau_star).tolist()},
                 soil={"contact_growth": False})
    assert spec.runner == "batch"
    for row in spec.run_chunk(0).to_pylist():
        case = cf.Case(tau1=row["tau1"], tau2=row["tau2"])
        t_rest = max(cf.stop_times(case) + (case.t0,))
        k = max(1, math.ceil(math.log2(t_rest / case.t0)))
        assert abs(t_rest / (case.t0 * 2.0 ** k) - 1.0) > 1e-9       # not at a step end
        sol = cf.solution(case, np.array([t_rest + 0.01]))
        assert row["at_rest"] and row["error"] == "" and row["t_end"] == case.t0 * 2.0 ** k
        for name, ref in (("u_pipe", "U1"), ("u_plug", "U2"), ("W_input", "W_input")):
            assert row[name] == pytest.approx(sol[ref][0], rel=1e-12, abs=1e-15), name


def test_a_refused_value_gives_the_per_case_rows():
    """A negative tau1 or a blow longer than stop_time: every case of the chunk runs as a
    model of its own, the bad one with its error, the others with their results."""
    for raw, soil, word in (({"tau1": [2e4, -1.0]}, {}, "tau1 = -1.0"),
                            ({"duration": [0.05, 2.0]}, {"tau1": 3e4}, "stop_time")):
        spec = _spec(grid=raw, soil=soil, output={"stop_time": 1.0})
        assert spec.runner == "batch"
        table = spec.run_chunk(0)
        assert table.equals(_per_case(spec).run_chunk(0))
        good, bad = table.to_pylist()
        assert good["error"] == "" and good["at_rest"] and word in bad["error"]
