"""The single-case benchmark (no timing): it runs every case of the cost study and times the API
through the same calls as the study, whose results it does not change."""
import numpy as np

import pipeplug
from benchmarks.single_case import NAMES, main
from pipeplug_harness.cost.cases import default_cases
from pipeplug_references.closed_form import solution


def test_every_case_and_the_median_are_printed(capsys):
    assert main(["--rounds", "1", "--batch", "1"]) == 0
    out = capsys.readouterr().out
    for bench in default_cases():
        assert f"\n{bench.name} " in out
    assert "\nmedian " in out and "slowest case" in out


def test_the_timed_calls_give_the_closed_form():
    bench = default_cases()[0]                 # model I: the closed form applies
    model = pipeplug.build_model(bench.params, dict(bench.options, solver="exact"))
    values = model.sample(bench.loads, bench.times, NAMES)
    ref = solution(bench.case, bench.times)
    scale = np.max(np.abs(ref["V1"]))
    assert np.max(np.abs(values["v_pipe"] - ref["V1"])) <= 1e-12 * scale
    assert np.max(np.abs(values["v_plug"] - ref["V2"])) <= 1e-12 * scale
