"""Shared helpers of the stability tests (a module name of its own: test folders share sys.path).

The catalogue of hard cases and its exact references live in the harness
(:mod:`pipeplug_harness.stability.cases`, :mod:`pipeplug_harness.stability.refs`), so that
``pipeplug stability`` prints the same cases the tests check.
"""
from __future__ import annotations

import math

import numpy as np

from pipeplug import Params, build_model

Q0, T0 = 23000.0, 0.05                    # the paper's blow: N, s
BASE = Params()
TAU_STAR = Q0 / (BASE.P1 * BASE.L1)       # Pa: outer friction limit equal to the blow
#: gamma = beta (1 + M1/M2), beta = P2 L2 / (P1 L1) (paper, section 1)
GAMMA = BASE.P2 * BASE.L2 / (BASE.P1 * BASE.L1) * (1.0 + BASE.M1 / BASE.M2)
SOLVERS = {"exact": {"solver": "exact"}, "fd": {"solver": "fd"}, "elastic": {"elastic": True}}
ELASTIC_GRID = {"dx": 0.05}               # 20 cells: fast, and close to the rigid limit


def model(solver: str, params: dict | None = None, growth: bool = False):
    """A fresh core model for ``solver`` ("exact", "fd", "elastic")."""
    params = dict(params or {})
    if solver == "elastic":
        params = {**ELASTIC_GRID, **params}
    return build_model(params, {**SOLVERS[solver], "contact_growth": growth})


def record(m, loads_and_steps) -> dict:
    """Advance ``m`` through ``[(q [N], h [s]), ...]``; the outputs after each step as arrays."""
    rows = []
    for q, h in loads_and_steps:
        m.advance(q, h)
        rows.append(m.outputs())
    return {name: np.array([getattr(r, name) for r in rows]) for name in rows[0]._fields}


def kinetic_energy(m, out) -> float:
    """Kinetic energy [J] of a rigid model from its outputs (v_plug is 0 without a plug)."""
    return 0.5 * (m.M1 * out.v_pipe ** 2 + m.M2 * out.v_plug ** 2)


def all_finite(out) -> bool:
    """True when every output value is finite."""
    return all(math.isfinite(float(x)) for x in out)
