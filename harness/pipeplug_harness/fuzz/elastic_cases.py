"""Random cases of model III (elastic rods), each generated from ``(seed, index)`` alone.

A case is an elastic pipe (and plug), a train of rectangular blows and the communication grids
it is run on. Domains drawn (SI units):

* pipe: length 0.5-30 m in 6-60 cells (log-uniform), inner radius 0.02-0.6 m, wall 0.002-0.04 m,
  density 7000-8000 kg/m3; plug: none (30 %: ``tau2 = 0`` or ``L2 = 0``), partial (35 %, 1 to
  n1 - 1 cells) or full (35 %), density 1200-2200 kg/m3; Young's moduli of both 1e7-3e11 Pa
  (log-uniform, so either rod may be the faster);
* friction: soil ``tau1`` 0 (30 %) or 1e2-1e5 Pa, plug ``tau2`` 1e2-1e5 Pa (log-uniform);
  contact growth (model II's penetrated length) for half of the cases;
* Courant number 1 for 70 % of the cases, else 0.2-1; ``x_monitor`` anywhere on the pipe; half
  of the cases marked for the reference are free rods at Courant 1 (no friction), which it
  solves exactly;
* blows: 1-50 (log-uniform), each lasting 1 internal step to most of its period, the train
  500-8000 internal steps long in all; amplitudes 0.1-10 times the friction the rods can take
  (or the force that moves the pipe at 1 m/s through its impedance, without friction), one in
  ten a pull; every blow edge on the grid of internal steps ``h = courant dx / c_fastest``
  (computed here by the contract's formulas, not by the core), followed by 0-3 of the blows'
  periods of ringing; for 30 % of the cases but the free rods (a stream of its own,
  ``spawn_key=(index, 8)``) every edge moved off that grid by 0.05-0.95 of a step, so that a
  step takes the mean load over it and the results must still not depend on the host's
  points;
* a ram for 40 % of the cases: 0.05-20 pipe masses (at least 1.5 cells), striking directly or
  through a cushion of 1e-3-1 times a cell's stiffness (within the internal step's limit), with
  restitution 0.5-1 (1 for a third); 70 % of its blows are strikes at 0.5-10 m/s instead of a
  force (a strike starts at the blow's start);
* end resistance (a stream of its own, ``spawn_key=(index, 5)``; none for the free rods):
  ``q_face`` 0 (half of the cases) or ``q_face S1`` 0.01-3 times the blows' force scale,
  ``q_plug_face`` 0 (half) or ``q_plug_face S2`` 0.1-10 times the plug's limit (log-uniform);
* a plug that grows (a stream of its own, ``spawn_key=(index, 6)``; none for the free rods):
  ``plug_growth`` for 30 % of the cases, the plug starting empty for a third of them, with
  ``L2_after_cleanout`` anywhere in [0, L1] (a whole number of cells for half of the cases)
  and a clean-out at the start of each blow with probability 0.3 (none for a case marked for
  the FMU: the fuzz's FMU host drives no clean-outs);
* Smith damping (a stream of its own, ``spawn_key=(index, 7)``; none for the free rods): half
  of the other cases, plugs that grow included, draw ``J_shaft``,
  ``J_face`` as the rigid cases draw them (:func:`.cases._damping`: each 0, 0.01-1 s/m or, one
  draw in ten, 1-100 s/m; never both 0); cases without damping have no ``J_*`` (they stay the
  cases of before).

Grids (all end at the stop time and hold every blow edge and the common sample times, which
are grid points): ``multiples`` (steps of 1-40 internal steps), ``random`` (random points, most
between grid points), ``irregular`` (clusters 1e-9 to 1 internal step after the edges). Each
holds at most about 800 points.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from pipeplug_harness.load import Load

from .cases import Plan, _damping

__all__ = ["ElasticCase", "generate_elastic", "internal_step", "plug_simulated", "GRIDS",
           "OFF_GRID_SHARE"]

GRIDS = ("multiples", "random", "irregular")
#: the share of the cases (not the free rods) whose blow edges are off the grid of internal steps
OFF_GRID_SHARE = 0.3
_POINTS = 800                     # most communication points of a grid
_PLAN = Plan(model="elastic")
_DAMPED_SHARE = 0.5               # of the cases that may be damped


@dataclass(frozen=True)
class ElasticCase:
    """One model III fuzz case (plain data, JSON round trip exact).

    ``edges`` are the times [s] where the load changes, ``loads`` the force [N] from each edge
    to the next (0 before the first and after the last); ``grids`` map a grid name to its
    communication points [s]; ``samples`` the times [s] every grid holds.
    """

    seed: int
    index: int
    growth: bool
    params: dict
    edges: tuple
    loads: tuple
    stop: float
    samples: tuple
    grids: dict
    host_h: float
    checks: tuple = ("core",)
    strikes: tuple = ()           #: (time [s], ram velocity [m/s]) of each strike
    plug_growth: bool = False     #: the plug grows (pipeplug.elastic.growth)
    cleanouts: tuple = ()         #: times [s] of the clean-outs (blow starts)
    note: str = field(default="", compare=False)
    kind: str = "elastic"

    @property
    def model(self) -> str:
        """``"III+II"`` (with contact growth) or ``"III"``, ``+growth`` with a growing plug,
        `` damped`` with Smith damping."""
        return (("III+II" if self.growth else "III") + ("+growth" if self.plug_growth else "")
                + (" damped" if "J_shaft" in self.params else ""))

    @property
    def options(self) -> dict:
        return {"elastic": True, "contact_growth": self.growth, "plug_growth": self.plug_growth}

    def load_at(self, t) -> np.ndarray:
        """The force [N] on steps starting at ``t`` [s] (right-continuous)."""
        return Load(self.edges, (*self.loads, 0.0)).on_steps(t)


def internal_step(params: dict, plug_growth: bool = False) -> float:
    """The contract's internal step courant dx / c_fastest [s] (c = sqrt(E / rho); the plug's
    speed counts when the plug is simulated: with ``plug_growth`` whenever tau2 > 0)."""
    speed = math.sqrt(params["E1"] / params["rho1"])
    if plug_simulated(params) or (plug_growth and params["tau2"] > 0.0):
        speed = max(speed, math.sqrt(params["E2"] / params["rho2"]))
    return params["courant"] * params["dx"] / speed


def plug_simulated(params: dict) -> bool:
    """The contract's rule: the plug is simulated when tau2 > 0 and L2 > 0."""
    return params["tau2"] > 0.0 and params["L2"] > 0.0


def generate_elastic(seed: int, index: int, plan: Plan = _PLAN) -> ElasticCase:
    """Case ``index`` of the model III fuzz run ``seed`` (see the module docstring)."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 3)))
    checks = tuple(c for c in plan.checks_for(index) if c != "fd")     # fd: rigid only
    params = _params(rng)
    if "reference" in checks and rng.random() < 0.5:
        params.update(tau1=0.0, tau2=0.0, courant=1.0)     # a free rod: the exact reference
    growing = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 6)))
    plug_growth = _plug_growth(growing, params)
    h = internal_step(params, plug_growth)
    ram = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 4)))
    params.update(_ram(ram, params, h))
    face = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 5)))
    params.update(_faces(face, params))
    if not _free(params):
        params.update(_damping(np.random.default_rng(
            np.random.SeedSequence(seed, spawn_key=(index, 7))), _DAMPED_SHARE))
    edges, loads, stop = _blows(rng, params, h)
    if not _free(params):
        edges = _off_the_grid(np.random.default_rng(
            np.random.SeedSequence(seed, spawn_key=(index, 8))), edges, h, stop)
    strikes = ()
    if params["ram_mass"] > 0.0:
        edges, loads, strikes = _strikes(ram, edges, loads)
    cleanouts = ()
    if plug_growth and "fmu" not in checks:
        cleanouts = tuple(t for t in edges[::2] if growing.random() < 0.3)
    steps = round(stop / h)
    samples = tuple(sorted({float(k * h) for k in rng.integers(1, steps + 1, 4)} | {stop}))
    grids = _grids(rng, h, steps, edges, samples)
    host_h = stop / int(rng.integers(20, 300))
    return ElasticCase(seed, index, bool(rng.random() < 0.5), params, edges, loads, stop,
                       samples, grids, host_h, checks, strikes=strikes,
                       plug_growth=plug_growth, cleanouts=cleanouts)


def _plug_growth(rng, params: dict) -> bool:
    """Whether the plug grows, and then its starting length and ``L2_after_cleanout``
    (module docstring), set in ``params``."""
    if _free(params) or rng.random() >= 0.3:
        return False
    dx, n1 = params["dx"], round(params["L1"] / params["dx"])
    if rng.random() < 1 / 3:
        params["L2"] = 0.0
    cells = float(rng.integers(0, n1 + 1)) if rng.random() < 0.5 else rng.uniform(0.0, n1)
    params["L2_after_cleanout"] = min(cells * dx, params["L1"])
    return True


def _ram(rng, params: dict, h: float) -> dict:
    """The ram's parameters (module docstring; none for 60 % of the cases)."""
    if rng.random() >= 0.4:
        return dict(ram_mass=0.0, cushion_stiffness=0.0, cushion_restitution=1.0)
    p = params
    S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
    cell_mass, cell_stiffness = p["rho1"] * S1 * p["dx"], p["E1"] * S1 / p["dx"]
    mass = max(_log(rng, 0.05, 20.0) * cell_mass * round(p["L1"] / p["dx"]), 1.5 * cell_mass)
    e = 1.0 if rng.random() < 1 / 3 else float(rng.uniform(0.5, 1.0))
    stiffness = 0.0
    if rng.random() < 0.5:
        # the leapfrog's limit at the head (Gershgorin: ram row and first cell row)
        largest = min(2.0 * mass, 2.0 * cell_mass - cell_stiffness * h * h) / (h * h)
        stiffness = min(_log(rng, 1e-3, 1.0) * cell_stiffness, 0.9 * largest) * e * e
    return dict(ram_mass=mass, cushion_stiffness=stiffness, cushion_restitution=e)


def _free(params: dict) -> bool:
    """A free rod: no friction at Courant 1 (the exact reference's case)."""
    return params["tau1"] == 0.0 and params["tau2"] == 0.0 and params["courant"] == 1.0


def _faces(rng, params: dict) -> dict:
    """``q_face``, ``q_plug_face`` [Pa] (module docstring)."""
    p = params
    if _free(p):
        return dict(q_face=0.0, q_plug_face=0.0)      # the free rods keep their reference
    S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
    S2 = math.pi * p["R1"] ** 2
    F2 = 2 * math.pi * p["R1"] * p["L2"] * p["tau2"]
    qf = _log(rng, 0.01, 3.0) * _scale_force(p) / S1 if rng.random() < 0.5 else 0.0
    qp = _log(rng, 0.1, 10.0) * F2 / S2 if (rng.random() < 0.5 and F2 > 0.0) else 0.0
    return dict(q_face=qf, q_plug_face=qp)


def _strikes(rng, edges, loads):
    """Turn 70 % of the blows into strikes (the force of the blow 0, a strike at its start)."""
    loads, strikes = list(loads), []
    for k in range(0, len(edges), 2):
        if rng.random() < 0.7:
            loads[k] = 0.0
            strikes.append((edges[k], _log(rng, 0.5, 10.0)))
    return edges, tuple(loads), tuple(strikes)


def _log(rng, low: float, high: float) -> float:
    return float(10.0 ** rng.uniform(math.log10(low), math.log10(high)))


def _params(rng) -> dict:
    n1 = int(round(_log(rng, 6, 60)))
    L1 = _log(rng, 0.5, 30.0)
    dx = L1 / n1
    L1 = n1 * dx                              # a whole number of cells, to round-off
    R1 = _log(rng, 0.02, 0.6)
    r = rng.random()
    n2 = 0 if r < 0.3 else (n1 if r < 0.65 else int(rng.integers(1, n1)))
    tau2 = 0.0 if (r < 0.15) else _log(rng, 1e2, 1e5)
    return dict(L1=L1, L2=n2 * dx, R1=R1, h1=min(_log(rng, 0.002, 0.04), R1),
                rho1=float(rng.uniform(7000, 8000)), rho2=float(rng.uniform(1200, 2200)),
                E1=_log(rng, 1e7, 3e11), E2=_log(rng, 1e7, 3e11),
                tau1=0.0 if rng.random() < 0.3 else _log(rng, 1e2, 1e5), tau2=tau2, dx=dx,
                courant=1.0 if rng.random() < 0.7 else float(rng.uniform(0.2, 1.0)),
                x_monitor=float(rng.uniform(0.0, L1)))


def _scale_force(params: dict) -> float:
    """The force [N] the rods' friction can take (both contacts over their lengths), or
    without friction the force moving the pipe at 1 m/s through its impedance."""
    p = params
    outer = 2 * math.pi * (p["R1"] + p["h1"]) * p["L1"] * p["tau1"]
    inner = 2 * math.pi * p["R1"] * p["L2"] * p["tau2"]
    if outer + inner > 0.0:
        return outer + inner
    S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
    return S1 * math.sqrt(p["E1"] * p["rho1"])


def _blows(rng, params: dict, h: float) -> tuple[tuple, tuple, float]:
    """Blow edges (on the grid of internal steps ``h``), the force after each, the stop."""
    count = int(round(_log(rng, 1, 50)))
    total = int(round(_log(rng, 500, 8000)))
    period = max(2, total // count)
    edges, loads = [], []
    force = _scale_force(params)
    for k in range(count):
        duration = int(rng.integers(1, max(2, int(period * rng.uniform(0.05, 0.9)))))
        start = k * period
        amplitude = _log(rng, 0.1, 10.0) * force * (-1.0 if rng.random() < 0.1 else 1.0)
        edges += [float(start * h), float((start + duration) * h)]
        loads += [amplitude, 0.0]
    stop_steps = count * period + int(rng.integers(0, 3 * period + 1))
    stop_steps = max(stop_steps, round(edges[-1] / h))
    return tuple(edges), tuple(loads[:-1]), float(stop_steps * h)


def _off_the_grid(rng, edges, h: float, stop: float, share: float = OFF_GRID_SHARE) -> tuple:
    """For a ``share`` of the cases, every blow edge moved off the grid of internal steps by
    0.05-0.95 of a step ``h`` [s] (but the edges within a step of the ``stop`` [s]): a blow
    then starts and ends within a step, whose load is the mean over it."""
    if rng.random() >= share:
        return edges
    shifts = rng.uniform(0.05, 0.95, len(edges))
    return tuple(float(e + u * h) if e + h < stop else e for e, u in zip(edges, shifts))


def _grids(rng, h: float, steps: int, edges, samples) -> dict:
    """The communication grids (see the module docstring)."""
    stop = float(steps * h)
    base = np.array([*(e for e in edges if 0.0 < e < stop), *samples])
    m = max(int(rng.integers(1, 41)), -(-steps // _POINTS))
    multiples = np.arange(1, steps // m + 1) * m * h
    n = min(_POINTS, steps)
    random = rng.uniform(0.0, stop, n)
    starts = np.array([0.0, *base])[rng.integers(0, base.size + 1, n // 2)]
    irregular = np.concatenate([starts + h * 10.0 ** rng.uniform(-9.0, 0.0, n // 2),
                                rng.uniform(0.0, stop, n - n // 2)])
    grids = {}
    for name, points in zip(GRIDS, (multiples, random, irregular)):
        grid = np.unique(np.concatenate([[0.0], base, points[(points > 0.0) & (points <= stop)]]))
        grids[name] = tuple(float(t) for t in grid)
    return grids


def elastic_to_json(case: ElasticCase) -> dict:
    """The case as JSON-ready data (floats round-trip exactly through :mod:`json`)."""
    data = asdict(case)
    data["grids"] = {k: list(v) for k, v in case.grids.items()}
    return data


def elastic_from_json(data: dict) -> ElasticCase:
    """The case written by :func:`elastic_to_json`."""
    data = dict(data)
    for key in ("edges", "loads", "samples", "checks"):
        data[key] = tuple(data[key])
    data["strikes"] = tuple(tuple(float(x) for x in s) for s in data.get("strikes", ()))
    data["cleanouts"] = tuple(float(t) for t in data.get("cleanouts", ()))
    data["grids"] = {k: tuple(float(t) for t in v) for k, v in data["grids"].items()}
    return ElasticCase(**data)
