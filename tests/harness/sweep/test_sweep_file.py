"""Sweep files: the closed key tables, the case values (grid order, random draws independent of
the chunking), and the core's check before any work is submitted."""
import numpy as np
import pytest
from scipy import stats

from pipeplug_harness.errors import UserError
from pipeplug_harness.sweep.check import check_sweep
from pipeplug_harness.sweep.file import sweep_spec
from pipeplug_harness.sweep.sample import uniforms, varied_values

#: the sections a sweep's base case needs (the values they had as the files' defaults)
BASE = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1.0e4}, "soil": {"tau1": 0.0},
        "blows": {"amplitude": 23000.0, "duration": 0.05, "period": 0.1}}


def _spec(**raw):
    sections = {name: dict(keys) for name, keys in BASE.items()}
    for name, keys in raw.items():
        sections.setdefault(name, {}).update(keys)
    if sections.get("sweep", {}).get("kind") == "drive":
        sections["blows"].pop("count", None)
    varied = {**sections.get("grid", {}), **sections.get("random", {})}
    for name in BASE:                   # a varied key's base value is BASE's, not the test's
        for key in varied:
            if key in BASE[name] and key not in raw.get(name, {}):
                sections[name].pop(key)
    return sweep_spec("t", sections)


@pytest.mark.parametrize("raw, words", [
    ({"grid": {"tau1": [1.0]}, "soil": {"tau3": 1.0}}, ["tau3", "tau1, contact_growth"]),
    ({"grid": {"tau1": [1.0]}, "sweep": {"kind": "walk"}}, ["walk", "blow, drive"]),
    ({"grid": {"tau1": [1.0]}, "sweep": {"report": "all"}}, ["all", "none, domains"]),
    ({"grid": {"tau1": [1.0]}, "sweep": {"seeds": 1}}, ["seeds", "kind, seed, samples"]),
    ({"grid": {"count": [1.0]}}, ["count", "L1"]),             # not a number key: not variable
    ({"grid": {"tau1": {"start": 0, "stop": 1, "n": 3}}}, ["start, stop, num, scale"]),
    ({"grid": {"tau1": {"start": 0, "stop": 1, "num": 3, "scale": "exp"}}}, ["linear, log"]),
    ({"random": {"tau1": {"dist": "cauchy"}}, "sweep": {"samples": 3}},
     ["cauchy", "uniform, normal, lognormal, truncnormal"]),
    ({"random": {"tau1": {"dist": "normal", "mean": 1.0}}, "sweep": {"samples": 3}},
     ["mean, sd", "missing: ['sd']"]),
    ({"random": {"tau1": {"dist": "normal", "mean": 1.0, "sd": 0.0}}, "sweep": {"samples": 3}},
     ["sd > 0"]),
    ({"random": {"tau1": {"dist": "uniform", "low": 1.0, "high": 2.0}}}, ["samples"]),
    ({"grid": {"tau1": [1.0]}, "random": {"tau2": {"dist": "uniform", "low": 1.0, "high": 2.0}}},
     ["exactly one of [grid] or [random]"]),
    ({"grid": {"target": [1.0]}}, ["target", "amplitude"]),    # [drive] keys only for drives
    ({"grid": {"tau1": {"start": 0, "stop": 1, "num": 1_000_000_000}}},
     ["num = 1000000000 asks for 1e+09 cases", "--limit cases="]),    # 8 GB allocated before
    ({"grid": {"tau1": {"start": 0, "stop": 1, "num": 100_000},
               "tau2": {"start": 0, "stop": 1, "num": 100_000}}},
     ["1e+10 cases", "--limit cases="]),                 # 4.9 GB in the client, then lost
    ({"random": {"tau1": {"dist": "uniform", "low": 1.0, "high": 2.0}},
      "sweep": {"samples": 10 ** 18}}, ["samples = 1000000000000000000 is outside"]),
    ({"grid": {"tau1": [1.0]}, "pipe": {"R1": 292.3}}, ["R1 = 292.3 m is outside"]),
    # a key the chosen model does not read, fixed or varied (ran, ignored, where a scene refuses)
    ({"grid": {"tau1": [1.0]}, "model": {"elastic": False, "dx": 0.01}},
     ["[model] dx = 0.01", "none with elastic = false"]),
    ({"grid": {"tau1": [1.0], "dx": [0.01, 0.02]}, "model": {"elastic": False}},
     ["[model] dx = [0.01, 0.02]", "none with elastic = false"]),
    ({"grid": {"tau1": [1.0]}, "model": {"elastic": True, "solver": "fd"}},
     ["[model] solver = 'fd'", "none with elastic = true"]),
])
def test_unknown_keys_and_values_name_the_allowed_ones(raw, words):
    with pytest.raises(UserError) as err:
        _spec(**raw)
    for word in words:
        assert word in str(err.value)


@pytest.mark.parametrize("sampling, dist", [
    ("grid", [1e4, 2e4]), ("random", {"dist": "uniform", "low": 1e4, "high": 2e4})])
def test_a_key_both_fixed_and_varied_is_refused_naming_both_places(sampling, dist):
    """[soil] tau1 = 5e4 with tau1 varied: the fixed value was dropped without a word."""
    raw = {name: dict(keys) for name, keys in BASE.items()}
    raw["soil"]["tau1"] = 5e4
    raw[sampling] = {"tau1": dist}
    raw["sweep"] = {"samples": 3} if sampling == "random" else {}
    with pytest.raises(UserError) as err:
        sweep_spec("t", raw)
    assert str(err.value) == (f"tau1 is both fixed in [soil] (tau1 = 50000.0) and varied in "
                              f"[{sampling}]; allowed: one of the two (remove it from [soil] "
                              f"or from [{sampling}])")


@pytest.mark.parametrize("sampling, varied, expected", [
    ("grid", {"tau1": ["10 kPa", "20 kPa"]}, [1e4, 2e4]),
    ("grid", {"tau1": {"start": "0.01 MPa", "stop": 3e4, "num": 3}}, [1e4, 2e4, 3e4]),
    ("grid", {"L1": ["50 cm", "1 km"]}, [0.5, 1000.0]),
    ("random", {"tau1": {"dist": "uniform", "low": "10 kPa", "high": "90 kPa"}}, (1e4, 9e4)),
    ("random", {"tau1": {"dist": "lognormal", "median": "70 kPa", "sigma": 0.2}}, (7e4, 0.2)),
    ("random", {"tau1": {"dist": "truncnormal", "mean": "70 kPa", "sd": "10 kPa",
                         "low": "0.05 MPa", "high": 9e4}}, (7e4, 1e4, 5e4, 9e4)),
])
def test_varied_values_may_carry_their_unit(sampling, varied, expected):
    """docs/files.md: a value is SI as a number or a string with its unit, in a sweep's grid
    and distributions too (they were refused as no finite number)."""
    spec = _spec(**{sampling: varied}, sweep={"samples": 3} if sampling == "random" else {})
    (dim,) = spec.dims
    if sampling == "grid":
        np.testing.assert_allclose(dim.values, expected, rtol=1e-15)
    else:
        np.testing.assert_allclose(dim.args, expected, rtol=1e-15)


@pytest.mark.parametrize("sampling, varied, words", [
    ("grid", {"tau1": ["10 kPa", "20 kg"]}, ["[grid] tau1: 1 = '20 kg'", "dimension of Pa"]),
    ("grid", {"L1": {"start": "1 m", "stop": "2 s", "num": 2}},
     ["[grid] L1: stop = '2 s'", "dimension of m"]),
    ("random", {"tau1": {"dist": "uniform", "low": "10 kPa", "high": "9 m"}},
     ["[random] tau1: high = '9 m'", "dimension of Pa"]),
    ("random", {"tau1": {"dist": "lognormal", "median": "70 kPa", "sigma": "0.2 kPa"}},
     ["[random] tau1: sigma = '0.2 kPa'", "dimension of 1"]),
    ("random", {"tau1": {"dist": "normal", "mean": "70 kPaa", "sd": 1.0}},
     ["[random] tau1: mean = '70 kPaa'", "a quantity with its unit"]),
])
def test_a_varied_value_of_another_dimension_is_refused(sampling, varied, words):
    with pytest.raises(UserError) as err:
        _spec(**{sampling: varied}, sweep={"samples": 3} if sampling == "random" else {})
    for word in words:
        assert word in str(err.value)


def test_grid_cases_in_c_order_first_name_slowest():
    spec = _spec(grid={"tau2": [1.0, 2.0], "tau1": {"start": 0.0, "stop": 20.0, "num": 3}},
                 sweep={"chunk": 4})
    assert (spec.n_cases, spec.n_chunks, [d.name for d in spec.dims]) == (6, 2, ["tau2", "tau1"])
    v = varied_values(spec.dims, "grid", 0, 0, 6)
    assert v["tau2"].tolist() == [1.0, 1.0, 1.0, 2.0, 2.0, 2.0]
    assert v["tau1"].tolist() == [0.0, 10.0, 20.0, 0.0, 10.0, 20.0]
    log = _spec(grid={"L1": {"start": 1.0, "stop": 100.0, "num": 3, "scale": "log"}})
    assert log.dims[0].values.tolist() == pytest.approx([1.0, 10.0, 100.0], rel=1e-15)


def test_random_values_depend_on_the_case_index_only():
    """Any range of cases draws what drawing all cases gives there; another seed differs."""
    whole = uniforms(7, 0, 1000, 6)
    for start, stop in ((0, 1), (3, 17), (999, 1000), (250, 750)):
        assert np.array_equal(uniforms(7, start, stop, 6), whole[start:stop])
    assert 0.0 < whole.min() and whole.max() < 1.0
    assert not np.array_equal(uniforms(8, 0, 1000, 6), whole)


@pytest.mark.parametrize("dist, frozen", [
    ({"dist": "normal", "mean": 2e4, "sd": 3e3}, stats.norm(2e4, 3e3)),
    ({"dist": "lognormal", "median": 7e4, "sigma": 0.2}, stats.lognorm(0.2, scale=7e4)),
    ({"dist": "uniform", "low": 1.0, "high": 3.0}, stats.uniform(1.0, 2.0)),
    ({"dist": "truncnormal", "mean": 0.0, "sd": 1.0, "low": -0.5, "high": 2.0},
     stats.truncnorm(-0.5, 2.0)),
])
def test_each_distribution_is_its_inverse_cdf_of_the_uniforms(dist, frozen):
    """The values are scipy.stats' quantile functions at the case's uniform numbers, and a
    large sample passes the Kolmogorov-Smirnov test against the distribution."""
    spec = _spec(random={"tau2": dist}, sweep={"samples": 20000, "seed": 3})
    got = varied_values(spec.dims, "random", 3, 0, 20000)["tau2"]
    u = uniforms(3, 0, 20000, 1)[:, 0]
    np.testing.assert_allclose(got, frozen.ppf(u), rtol=1e-9, atol=1e-12)
    assert stats.kstest(got, frozen.cdf).pvalue > 1e-3


@pytest.mark.parametrize("mean, sd, low, high", [
    (7e4, 1e4, 1.5e5, 3e5),          # 8 sd above the mean to 23 sd
    (7e4, 1e4, 2e5, 3e5),            # 13 sd to 23 sd: every case was at high
    (-7e4, 1e4, -3e5, -2e5),         # the same in the lower tail
    (7e4, 1e4, 1.4e5, 1.4001e5),     # a narrow window 7 sd out
])
def test_a_truncnormal_far_in_a_tail_follows_its_distribution(mean, sd, low, high):
    """The difference of two normal CDFs rounded to 0 beyond about 8 sd: samples piled up at
    a bound. Against scipy.stats.truncnorm's CDF (Kolmogorov-Smirnov at a fixed seed): no
    sample at or outside a bound, and the sample's mean that of the distribution."""
    dist = {"dist": "truncnormal", "mean": mean, "sd": sd, "low": low, "high": high}
    spec = _spec(random={"tau2": dist}, sweep={"samples": 5000, "seed": 11})
    got = varied_values(spec.dims, "random", 11, 0, 5000)["tau2"]
    frozen = stats.truncnorm((low - mean) / sd, (high - mean) / sd, loc=mean, scale=sd)
    assert np.all((got > low) & (got < high))
    assert stats.kstest(got, frozen.cdf).pvalue > 1e-3
    assert abs(got.mean() - frozen.mean()) < 5 * frozen.std() / np.sqrt(got.size)


def test_the_core_checks_the_corners_before_any_work():
    # L2 <= L1 fails only at the corner L1 = 1, L2 = 1.5 (a linear rule between parameters)
    spec = _spec(grid={"L1": [1.0, 2.0], "L2": [0.5, 1.5]})
    with pytest.raises(UserError, match=r"L1 = 1.0, L2 = 1.5: L2 = 1.5 is not allowed"):
        check_sweep(spec)
    # a normal tau1 around 0 draws negative values: named with the allowed range
    spec = _spec(random={"tau1": {"dist": "normal", "mean": 0.0, "sd": 1.0}},
                 sweep={"samples": 5000})
    with pytest.raises(UserError, match=r"tau1 = -\d.*allowed: finite, >= 0"):
        check_sweep(spec)
    # drives: the target beyond the pipe
    spec = _spec(sweep={"kind": "drive"}, grid={"target": [0.5, 1.5]},
                 model={"elastic": False})
    with pytest.raises(UserError, match=r"target = 1.5.*<= L1"):
        check_sweep(spec)
    ok = _spec(grid={"tau1": {"start": 0.0, "stop": 1e5, "num": 2000}})
    assert "corners" in check_sweep(ok)


@pytest.mark.parametrize("raw, runner, chunk", [
    # single rigid exact blows from rest, no mode sequence: the batch API, 100,000 a task
    ({"model": {"elastic": False}}, "batch", 100_000),
    ({"model": {"elastic": False}, "output": {"modes": True}}, "case", 2000),
    ({"model": {"elastic": False, "solver": "fd"}}, "case", 2000),
    ({"model": {"elastic": False}, "sweep": {"chunk": 7}}, "batch", 7),
    ({"model": {"elastic": False, "solver": "fd"}, "sweep": {"chunk": 7}}, "case", 7),
])
def test_the_default_chunk_follows_the_runner(raw, runner, chunk):
    """Without a chunk in the file a task holds 100,000 blows on the batch API (a few
    microseconds each) and 2000 blows built one model each (hundreds of microseconds each)."""
    spec = _spec(grid={"tau1": [1e4, 2e4]}, **raw)
    assert (spec.runner, spec.chunk) == (runner, chunk)
    assert spec.digest == _spec(grid={"tau1": [1e4, 2e4]},
                                **{**raw, "sweep": {"chunk": chunk}}).digest


def test_the_drivability_histogram_draws_every_drive_and_quantiles_are_whole_blows(tmp_path):
    """A sample whose longest drive took 489 blows: its bin was past the last edge and the
    drive was not drawn; quantiles came out in fractional blows."""
    import pyarrow as pa

    from pipeplug_harness.sweep import drivability
    blows = [8, 9, 9, 10, 12, 15, 489]
    table = pa.table({"outcome": ["target"] * 7, "blows": blows, "penetration": [1.0] * 7,
                      "error": [""] * 7})
    s = drivability.summarise(table)
    assert all(float(v).is_integer() and v in blows for v in s["quantiles"].values())
    drawn = {}
    spec = _spec(sweep={"kind": "drive"}, grid={"tau1": [1.0]}, model={"elastic": False})
    import matplotlib.axes
    hist = matplotlib.axes.Axes.hist

    def counting(ax, x, *args, **kwargs):
        counts, edges, patches = hist(ax, x, *args, **kwargs)
        drawn["n"] = int(counts.sum())
        return counts, edges, patches

    matplotlib.axes.Axes.hist = counting
    try:
        drivability.plot_blows(tmp_path / "h.png", spec, s)
    finally:
        matplotlib.axes.Axes.hist = hist
    assert drawn["n"] == len(blows)


def test_a_grid_past_the_memory_limit_is_refused_before_its_values_are_made(monkeypatch):
    """With the cases and tasks limits raised, a grid of 1e9 values was still made (8 GB, and
    its digest's text several times that) and the process was killed: the memory limit holds."""
    from pipeplug_harness.limits import Limits
    from pipeplug_harness.sweep import file

    def made(*args):
        raise AssertionError("the grid's values were made")

    monkeypatch.setitem(file.GRID_SCALES, "linear", made)
    raw = {name: dict(keys) for name, keys in BASE.items()}
    del raw["soil"]["tau1"]
    raw["grid"] = {"tau1": {"start": 0, "stop": 1, "num": 1_000_000_000}}
    with pytest.raises(UserError, match="--limit memory="):
        sweep_spec("t", raw, Limits({"cases": 1e10, "tasks": 1e10}))


def test_tasks_past_the_memory_limit_are_refused():
    """Every task carries the campaign (its grid values too): 1e8 tasks of a 2e4-value grid
    were submitted at once with the tasks limit raised."""
    from pipeplug_harness.limits import Limits

    raw = {name: dict(keys) for name, keys in BASE.items()}
    del raw["soil"]["tau1"], raw["plug"]["tau2"]
    raw["grid"] = {"tau1": {"start": 0, "stop": 1, "num": 10_000},
                   "tau2": {"start": 0, "stop": 1, "num": 10_000}}
    raw["sweep"] = {"chunk": 1}
    with pytest.raises(UserError, match="--limit memory="):
        sweep_spec("t", raw, Limits({"tasks": 1e9}))


def test_a_sample_where_every_drive_refuses_draws_no_empty_legend(tmp_path):
    """matplotlib warned 'No artists with labels found to put in legend' on stderr."""
    import warnings

    import pyarrow as pa

    from pipeplug_harness.sweep import drivability
    table = pa.table({"outcome": ["set"] * 3, "blows": [40, 41, 45],
                      "penetration": [0.2, 0.3, 0.25], "error": [""] * 3})
    s = drivability.summarise(table)
    spec = _spec(sweep={"kind": "drive"}, grid={"tau1": [1.0]}, model={"elastic": False})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        drivability.plot_blows(tmp_path / "h.png", spec, s)
    assert (tmp_path / "h.png").stat().st_size > 1000


@pytest.mark.parametrize("cases, seconds, rate", [
    (5, 34.4, "0.145 cases/s"), (3, 1.0, "3 cases/s"), (1234, 100.0, "12.3 cases/s"),
    (10 ** 6, 2.0, "500,000 cases/s")])
def test_the_summary_gives_a_rate_of_slow_runs_in_significant_digits(cases, seconds, rate):
    """A slow run said '0 cases/s'."""
    from pipeplug_harness.sweep.command import _summary
    from pipeplug_harness.sweep.engine import ChunkRun
    run = ChunkRun(chunks=1, written=1, cases=cases, seconds=seconds)
    assert f": {rate}," in _summary(run, 1, "out")
