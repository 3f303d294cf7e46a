"""Random cases of the rigid models with a plug that grows, each from ``(seed, index)`` alone.

A case is a rigid case of :func:`~.cases.generate` (its pipe, plug, soil, end resistance,
loads, stop time and grids; model I or II) with ``plug_growth`` on, redrawn from the stream
``SeedSequence(seed, spawn_key=(index, 9))`` (SI units):

* the plug: its start length 0 (a quarter of the cases), L1 (a tenth: plugged from the start)
  or the base case's; a plug without friction (tau2 = 0, which refuses a growing plug) gets an
  inner limit per length that gives 10 N to 100 kN over L1 (log-uniform);
* ``L2_after_cleanout``: 0 (half of the cases) or 0-1 L1;
* clean-outs: 0-3, each at a load edge (half of them) or anywhere in the first 80 % of the run;
  every grid holds each clean-out's time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .cases import Case, OnBase, Plan, case_from_json, case_to_json, edges_of, generate

__all__ = ["GrowthCase", "generate_growth", "growth_to_json", "growth_from_json"]

_PLAN = Plan(model="growth")


@dataclass(frozen=True)
class GrowthCase(OnBase):
    """A rigid case with a growing plug (:class:`~.cases.Case`) and the times of its
    clean-outs [s] (plain data, JSON round trip exact)."""

    base: Case
    cleanouts: tuple
    note: str = field(default="", compare=False)
    kind: str = "growth"

    @property
    def model(self) -> str:
        return self.base.model + "+growth"

    @property
    def options(self) -> dict:
        return {"solver": "exact", "contact_growth": self.base.growth, "plug_growth": True}


def generate_growth(seed: int, index: int, plan: Plan = _PLAN) -> GrowthCase:
    """Case ``index`` of the growing plug's fuzz run ``seed`` (module docstring)."""
    base = generate(seed, index, plan, damping=False)      # the growing plug is not damped
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 9)))
    p = dict(base.params)
    L1 = p["L1"]
    r = rng.random()
    if r < 0.25:
        p["L2"] = 0.0
    elif r < 0.35:
        p["L2"] = L1
    if not p["tau2"] > 0.0:
        p["tau2"] = 10.0 ** rng.uniform(1.0, 5.0) / (2.0 * math.pi * p["R1"] * L1)
    p["L2_after_cleanout"] = 0.0 if rng.random() < 0.5 else float(rng.uniform(0.0, L1))
    edges = [e for e in edges_of(base.segments) if 0.0 < e < base.stop]
    cleanouts = set()
    for _ in range(int(rng.integers(0, 4))):
        t = (edges[int(rng.integers(len(edges)))] if edges and rng.random() < 0.5
             else float(rng.uniform(0.0, 0.8 * base.stop)))
        if t > 0.0:
            cleanouts.add(t)
    cleanouts = tuple(sorted(cleanouts))
    grids = {name: tuple(sorted(set(grid) | set(cleanouts)))
             for name, grid in base.grids.items()}
    base = replace(base, params=p, grids=grids,
                   checks=tuple(c for c in base.checks if c not in ("fd", "fmu")))
    return GrowthCase(base, cleanouts)


def growth_to_json(case: GrowthCase) -> dict:
    """The case as JSON-ready data."""
    return {"kind": "growth", "base": case_to_json(case.base),
            "cleanouts": list(case.cleanouts)}


def growth_from_json(data: dict) -> GrowthCase:
    """The case written by :func:`growth_to_json`."""
    return GrowthCase(case_from_json(data["base"]), tuple(float(t) for t in data["cleanouts"]))
