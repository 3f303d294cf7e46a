"""Random cases of model I with a ram at the head, each generated from ``(seed, index)`` alone.

A case is a rigid case of :func:`~.cases.generate` (its pipe, plug, soil, loads, stop time and
grids; always model I, as models II and the fd scheme refuse a ram) with a ram and its
strikes, drawn from the stream ``SeedSequence(seed, spawn_key=(index, 7))`` (SI units):

* ram: 0.1-20 pipe masses (log-uniform); a direct strike for a third of the cases (restitution
  0.3-1), else a cushion whose half sine on the pipe lasts 0.1-30 ms (stiffness
  ``mu (pi / T)^2``, mu the reduced mass of ram and pipe) with restitution 1 (a third) or
  0.3-1;
* strikes: 1-4 at 0.3-10 m/s (log-uniform), each at a load edge (half of them) or anywhere
  in the first 80 % of the run; every grid holds each strike's time, and so does every FMU
  host's grid;
* the soil's end resistance as the rigid cases draw it (:func:`~.cases.generate`, from its own
  stream: a case without it is the case it was before it existed).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .cases import Case, OnBase, Plan, case_from_json, case_to_json, edges_of, generate

__all__ = ["RamCase", "generate_ram", "ram_to_json", "ram_from_json", "RAM_PARAMETERS"]

#: the ram's parameters (the contract's names)
RAM_PARAMETERS = ("ram_mass", "cushion_stiffness", "cushion_restitution")
_PLAN = Plan(model="ram")


@dataclass(frozen=True)
class RamCase(OnBase):
    """A rigid case with a ram (:class:`~.cases.Case`, always model I) and its strikes
    ``(time [s], velocity [m/s])`` (plain data, JSON round trip exact)."""

    base: Case
    strikes: tuple
    note: str = field(default="", compare=False)
    kind: str = "ram"

    @property
    def model(self) -> str:
        return "I+ram"

    @property
    def options(self) -> dict:
        return {"solver": "exact", "contact_growth": False}

    @property
    def edges(self) -> list[float]:
        """Every time [s] where a load changes or a strike starts, in order."""
        return sorted(set(edges_of(self.base.segments)) | {t for t, _ in self.strikes})


def generate_ram(seed: int, index: int, plan: Plan = _PLAN) -> RamCase:
    """Case ``index`` of the ram fuzz run ``seed`` (module docstring)."""
    base = generate(seed, index, plan, damping=False)      # a rigid ram is not damped
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 7)))
    p = base.params
    M1 = p["rho1"] * math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2) * p["L1"]
    mass = M1 * 10.0 ** rng.uniform(-1.0, math.log10(20.0))
    if rng.random() < 1.0 / 3.0:
        stiffness, restitution = 0.0, float(rng.uniform(0.3, 1.0))
    else:
        mu = mass * M1 / (mass + M1)
        pulse = 10.0 ** rng.uniform(-4.0, math.log10(0.03))
        stiffness = mu * (math.pi / pulse) ** 2
        restitution = 1.0 if rng.random() < 1.0 / 3.0 else float(rng.uniform(0.3, 1.0))
    edges = [e for e in edges_of(base.segments) if e < base.stop]
    strikes = {}
    for _ in range(int(rng.integers(1, 5))):
        t = (edges[int(rng.integers(len(edges)))] if rng.random() < 0.5
             else float(rng.uniform(0.0, 0.8 * base.stop)))
        strikes[t] = float(10.0 ** rng.uniform(math.log10(0.3), 1.0))
    strikes = tuple(sorted(strikes.items()))
    params = dict(p, ram_mass=float(mass), cushion_stiffness=float(stiffness),
                  cushion_restitution=restitution)
    grids = {name: tuple(sorted(set(grid) | {t for t, _ in strikes}))
             for name, grid in base.grids.items()}
    base = replace(base, growth=False, params=params, grids=grids,
                   checks=tuple(c for c in base.checks if c != "fd"))   # fd refuses a ram
    return RamCase(base, strikes)


def ram_to_json(case: RamCase) -> dict:
    """The case as JSON-ready data."""
    return {"kind": "ram", "base": case_to_json(case.base),
            "strikes": [list(s) for s in case.strikes]}


def ram_from_json(data: dict) -> RamCase:
    """The case written by :func:`ram_to_json`."""
    return RamCase(case_from_json(data["base"]),
                   tuple((float(t), float(v)) for t, v in data["strikes"]))

