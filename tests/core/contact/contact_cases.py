"""Inputs of the two-contact problem shared by the contact tests."""
from __future__ import annotations

import numpy as np


def cases(n=4000, seed=1):
    """``(m1, m2, w1, w2, c1, c2)``: scales over six decades, a fifth with the pipe exactly at
    its soil limit (a stick/slip boundary)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        m1, m2 = 10.0 ** rng.uniform(-3, 3, 2)
        w1, w2 = rng.normal(0, 1, 2) * 10.0 ** rng.uniform(-2, 2, 2)
        c1, c2 = 10.0 ** rng.uniform(-3, 3, 2) * (rng.random(2) > 0.1)
        if rng.random() < 0.2:       # place the case exactly on a stick/slip boundary
            w1 = c1 / m1 * rng.choice([-1, 1])
        yield m1, m2, w1, w2, c1, c2


def boundary_cases(n=4000, seed=2):
    """As :func:`cases`, each on a boundary or a degenerate point: a body exactly at its limit,
    pipe and plug at equal rates, rates and limits of zero (either sign)."""
    rng = np.random.default_rng(seed)
    for (m1, m2, w1, w2, c1, c2), kind in zip(cases(n, seed), rng.integers(0, 6, n)):
        sign = rng.choice([-1.0, 1.0])
        if kind == 0:               # the plug exactly at its limit on a pipe at rest
            w1, w2 = 0.0, sign * c2 / m2
        elif kind == 1:             # pipe and plug loaded to both limits at once
            w1, w2 = sign * (c1 + c2) / m1, -sign * c2 / m2
        elif kind == 2:             # equal rates: the plug has no reason to slide
            w2 = w1
        elif kind == 3:             # no load at all
            w1, w2 = sign * 0.0, rng.choice([-1.0, 1.0]) * 0.0
        elif kind == 4:             # no friction at one contact
            c1, c2 = (0.0, c2) if sign > 0 else (c1, 0.0)
        else:                       # no friction and no load
            w1, c1, c2 = sign * 0.0, 0.0, 0.0
        yield m1, m2, w1, w2, c1, c2


def as_arrays(rows):
    """The cases as six arrays ``m1, m2, w1, w2, c1, c2``."""
    return tuple(np.array(list(rows), dtype=float).T)
