"""Helpers of the rigid-model tests: drive a core model with piecewise-constant loads."""
from __future__ import annotations

import numpy as np


def drive(model, pulses, times):
    """Advance ``model`` through the sample ``times`` [s] under rectangular ``pulses``.

    Parameters
    ----------
    pulses : list of (start [s], duration [s], amplitude [N])
        Load is the sum of the active pulses; every pulse edge becomes a step boundary.
    times : array
        Increasing sample times (> 0) at which the outputs are recorded.

    Returns
    -------
    dict of arrays, one per output name.
    """
    edges = sorted({e for s, d, _ in pulses for e in (s, s + d)})
    marks = sorted(set(float(t) for t in times) | {e for e in edges if 0 < e < times[-1]})
    wanted = set(float(t) for t in times)
    rows = []
    for t_next in marks:
        t_mid = 0.5 * (model.time + t_next)
        q = sum(a for s, d, a in pulses if s <= t_mid < s + d)
        model.advance(q, t_next - model.time)
        if t_next in wanted:
            rows.append(model.outputs())
    return {name: np.array([getattr(r, name) for r in rows]) for name in rows[0]._fields}
