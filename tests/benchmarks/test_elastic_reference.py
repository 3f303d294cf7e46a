"""The benchmarks' own numpy codings of the elastic scheme agree with the core (so that the
timings compare the same computation)."""
from __future__ import annotations

import numpy as np
import pytest

from benchmarks.elastic_reference import run_numpy, run_numpy_full
from pipeplug import build_model

FIELDS = ("v1", "N1", "v2", "N2", "u1", "u2", "acc")


@pytest.mark.parametrize("runner, changes, growth", [
    (run_numpy, dict(tau1=0.0, tau2=1e4, L2=0.6), False),
    (run_numpy_full, dict(tau1=7e4, tau2=3.5e4, L2=0.6), True),
    (run_numpy_full, dict(tau1=7e4, tau2=3.5e4), True),
])
def test_numpy_references_agree_with_the_core(runner, changes, growth):
    core = build_model(dict(changes, dx=0.05), {"elastic": True, "contact_growth": growth})
    ref = build_model(dict(changes, dx=0.05), {"elastic": True, "contact_growth": growth})
    g = ref.grid
    for q, h in ((23000.0, 0.01), (-3000.0, 0.003), (0.0, 0.01), (23000.0, 0.004)):
        core.advance(q, h)
        n = ref.steps_for(h)
        runner(n, h / n, q, g.coef, ref.v1, ref.N1, ref.v2, ref.N2, g.cells1, ref.u1,
               g.cells2, ref.u2, ref.acc)
    # the plug's friction worked, and the soil's when on
    assert core.acc[2] > 0.0 and (core.acc[1] > 0.0) == (changes["tau1"] > 0.0)
    for name in FIELDS:
        a, b = getattr(core, name), getattr(ref, name)
        if name == "acc":       # the reference books the works and forces, not the extremes
            a, b = a[:5], b[:5]
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.abs(a).max(), err_msg=name)
