"""The rigid pipe's stress extremes: the plain-Python path's float form gives numpy's values
bit for bit, signs of zeros and NaN included (numpy's maximum of two equal values is the second,
Python's ``max`` the first)."""
from __future__ import annotations

import itertools
import random

import numpy as np

from pipeplug.rigid.stress import _array_extremes, _scalar_extremes, axial_extremes

EDGES = [0.0, -0.0, 1.0, -1.0, 5e4, -5e4, 1e-300, float("nan")]


def _same(a, b) -> bool:
    return np.float64(a).tobytes() == np.float64(b).tobytes() or (a != a and b != b)


def test_the_float_form_gives_numpys_bits_on_edge_values_and_random_ones():
    rng = random.Random(3)
    cases = [(h, o, i, f, 10.0, lc, l2) for h, o, i, f in itertools.product(EDGES, repeat=4)
             for lc, l2 in ((0.0, 0.0), (10.0, 10.0), (4.0, 0.0))]
    cases += [(*(rng.uniform(-1e5, 1e5) for _ in range(4)), 17.0, rng.uniform(0.0, 17.0),
               rng.choice([0.0, 17.0, rng.uniform(0.0, 17.0)])) for _ in range(2000)]
    for head, outer, inner, face, L1, Lc, L2 in cases:
        fast = _scalar_extremes(head, outer, inner, L1, Lc, L2, face)
        ufunc = _array_extremes(head, outer, inner, L1, Lc, L2, face)
        assert all(map(_same, fast, ufunc)), (head, outer, inner, face, Lc, L2, fast, ufunc)


def test_arrays_take_numpys_form():
    head = np.array([1.0, -2.0, 3e4])
    low, high = axial_extremes(head, 0.5 * head, 0.25 * head, 10.0, 10.0, 5.0)
    ref = _array_extremes(head, 0.5 * head, 0.25 * head, 10.0, 10.0, 5.0)
    assert np.array_equal(low, ref[0]) and np.array_equal(high, ref[1])
