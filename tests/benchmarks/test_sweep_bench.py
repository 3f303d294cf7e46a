"""The sweep benchmark's pieces (no timing): its two mixes take the paths they are named after,
and the projection's bend is where the workers' share meets the serial part."""
import math

import pytest

from benchmarks.sweep import _projected, blow_sweep, w_max


def test_the_mixes_take_their_paths():
    assert blow_sweep(10, 5).runner == "batch"
    assert blow_sweep(10, 5, mix="per-case").runner == "case"


def test_the_projection_bends_at_w_max():
    c, s, write, b, n = 3e-6, 5e-3, 6e-8, 50_000, 10 ** 8
    w = w_max(c, s, write, b)
    chunks = math.ceil(n / b)
    assert (n * c + chunks * s) / w == pytest.approx(chunks * s + n * write, rel=1e-12)
    assert _projected(n, 2 * w, b, c, s, write, 0.0) == _projected(n, 4 * w, b, c, s, write, 0.0)
    assert _projected(n, w / 2, b, c, s, write, 0.0) == pytest.approx(
        2 * (n * c + chunks * s) / w, rel=1e-12)
