"""The varied values of any cases of a sweep, from the case indices alone.

A case's values depend only on the sweep and its index ``i``, never on which task or worker
runs it, nor on how the cases are cut into tasks:

* grid: ``i`` is the flat index over the grid in C order (the first name varies slowest);
* random: each name takes ``inverse_cdf(u)`` of its distribution, ``u`` uniform in (0, 1) from a
  counter-based generator (Philox 4x64, keyed by the seed) at counter ``i * K + j // 4``, output
  ``j % 4`` for the ``j``-th name (``K = ceil(names / 4)``). Any range of cases is drawn
  directly, without drawing the cases before it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.special import ndtri

__all__ = ["Dimension", "Distribution", "DISTRIBUTIONS", "GRID_KEYS", "GRID_SCALES",
           "varied_values", "uniforms"]


@dataclass(frozen=True)
class Dimension:
    """One varied name: its grid values, or its distribution and the distribution's numbers."""

    name: str
    values: np.ndarray | None = None
    dist: str | None = None
    args: tuple = ()


class Distribution(NamedTuple):
    keys: tuple          #: its numbers, in order
    inverse: object      #: (u, *numbers) -> values: the inverse of the distribution function
    check: object        #: (*numbers) -> "" or what is wrong
    unitless: tuple = ()     #: its numbers without the varied key's unit (the others have it)


def _truncnormal(u, mean, sd, low, high):
    """scipy's truncated normal quantile, accurate however far the window lies in a tail (the
    difference of two normal CDFs, as it was done before, rounds to 0 there: every case at a
    bound); the clip only keeps the rounding of ``mean + sd x`` inside the window."""
    from scipy.stats import truncnorm
    x = truncnorm.ppf(u, (low - mean) / sd, (high - mean) / sd)
    return np.clip(mean + sd * x, low, high)


def _positive(**numbers) -> str:
    bad = [f"{k} = {v!r}" for k, v in numbers.items() if not v > 0.0]
    return f"needs {', '.join(numbers)} > 0 (got {', '.join(bad)})" if bad else ""


#: name -> its numbers, inverse distribution function and checks
DISTRIBUTIONS = {
    "uniform": Distribution(("low", "high"), lambda u, lo, hi: lo + (hi - lo) * u,
                            lambda lo, hi: "" if hi > lo else f"needs high > low (got {lo}, {hi})"),
    "normal": Distribution(("mean", "sd"), lambda u, m, s: m + s * ndtri(u),
                           lambda m, s: _positive(sd=s)),
    "lognormal": Distribution(("median", "sigma"), lambda u, med, s: med * np.exp(s * ndtri(u)),
                              lambda med, s: _positive(median=med, sigma=s), ("sigma",)),
    "truncnormal": Distribution(("mean", "sd", "low", "high"), _truncnormal,
                                lambda m, s, lo, hi: _positive(sd=s) or (
                                    "" if hi > lo else f"needs high > low (got {lo}, {hi})")),
}


def _linear(start, stop, num, where):
    return np.linspace(start, stop, num)


def _log(start, stop, num, where):
    if not (start > 0.0 and stop > 0.0):
        from pipeplug_harness.errors import UserError
        raise UserError(f"{where}: scale = \"log\" needs start, stop > 0 (got {start}, {stop})")
    return np.geomspace(start, stop, num)


#: the keys of a grid table, and its scales
GRID_KEYS = ("start", "stop", "num", "scale")
GRID_SCALES = {"linear": _linear, "log": _log}


def uniforms(seed: int, start: int, stop: int, names: int) -> np.ndarray:
    """Uniform numbers in (0, 1) of cases ``[start, stop)``: shape (stop - start, names)."""
    per_case = math.ceil(names / 4)
    raw = np.random.Philox(key=seed, counter=start * per_case).random_raw(
        (stop - start) * per_case * 4).reshape(stop - start, per_case * 4)[:, :names]
    return ((raw >> np.uint64(11)).astype(float) + 0.5) * 2.0 ** -53    # 53 bits, never 0 or 1


def varied_values(dims: tuple, sampling: str, seed: int, start: int, stop: int) -> dict:
    """name -> the values of cases ``[start, stop)`` (float arrays)."""
    if sampling == "grid":
        shape = tuple(len(d.values) for d in dims)
        index = np.unravel_index(np.arange(start, stop), shape)
        return {d.name: d.values[k] for d, k in zip(dims, index)}
    u = uniforms(seed, start, stop, len(dims))
    return {d.name: np.asarray(DISTRIBUTIONS[d.dist].inverse(u[:, j], *d.args), dtype=float)
            for j, d in enumerate(dims)}
