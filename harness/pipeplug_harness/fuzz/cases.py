"""Random fuzz cases, each generated from ``(seed, index)`` alone.

A case is a rigid model (I or II), its parameters, a piecewise-constant load history and the
communication grids it is run on. The random stream of case ``index`` is
``SeedSequence(seed, spawn_key=(index,))``, so any case can be generated (and run) on its own,
in any order or process, and a file holding one case replays it exactly.

Domains drawn (SI units):

* pipe length ``L1``: 1 m, or 0.3-3 m (log-uniform);
* plug: none (``L2 = 0`` or ``tau2 = 0``), or a plug of ``L2 = L1`` or ``0.01-1 L1`` whose mass
  is 1e-6 to 1e3 times the pipe's (log-uniform; ``rho2`` set from it), with an inner limit
  ``F2 = P2 L2 tau2`` of 10 N to 100 kN (log-uniform);
* load: 1-6 segments of 10 us to 0.2 s (log-uniform), Q uniform in +-60 kN, or exactly at a
  friction limit: +-F1, +-(F1 + F2), +-F2, +-(F1 - F2), +-F2 (M1 + M2)/M2 (the load at which a
  plug moving with a free pipe needs exactly F2), +-(F1 + F2 (M1 + M2)/M2), F1/2, or zero (those up to 120 kN);
* outer limit ``tau1``: 0, or 0-1.3 times ``max|Q| / (P1 L1)`` (the stress that holds the
  largest load over the whole length), or exactly that stress;
* model II (contact growth) for 60 % of the cases: the pipe penetrates past ``L1`` and is
  pulled back past 0;
* stop time: the end of the loads plus 0-0.3 s, or inside the last segment;
* end resistance (from a stream of its own, ``spawn_key=(index, 1)``, so that everything else
  is the case it was before): ``q_face`` 0 (half of the cases) or such that ``Qf = q_face S1``
  is 0-1.3 times ``max|Q|``; ``q_plug_face`` 0 (half) or ``Qp = q_plug_face S2`` 0.1-10 times
  the plug's limit ``F2`` (log-uniform: a plug held by its face, coring, or carried); a quarter
  of the loads then moved exactly to a limit of the window: +-(F1 + Qf), F1 + Qf + min(F2, Qp).
* Smith damping (a stream of its own, ``spawn_key=(index, 2)``; model I only: the exact
  solver refuses damping with contact growth): a third of the model I cases draw ``J_shaft``
  and ``J_face`` [s/m], each 0 (a quarter), 0.01-1 s/m (log-uniform), or, one draw in ten,
  1-100 s/m; never both 0. A damped case is compared with the reference only where the
  reference can afford it (its steps are capped by the largest damping rate:
  :func:`damping_rate` x stop <= :data:`REFERENCE_STIFFNESS`), and runs no fd check (the fd
  bound's constant was fitted without damping). Cases without damping have no ``J_*``
  parameters at all and are the cases they were before.

Grids (all start at 0, end at the stop time and hold every load edge before it, plus the
case's common sample times): ``coarse`` (2-5 uniform points), ``fine`` (150-400 uniform
points), ``irregular`` (random points, half of them clustered within 1e-9 to 1e-3 s after load
edges). The FMU host step ``host_h`` gives 10-300 steps over the run.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from pipeplug_harness import paper
from pipeplug_harness.load import Load

__all__ = ["Case", "OnBase", "Plan", "generate", "edges_of", "load_at", "loads_on", "host_calls", "calls_of",
           "case_to_json", "case_from_json", "RIGID_PARAMETERS", "GRIDS",
           "strikes_on_calls", "damping_rate", "DAMPED_SHARE", "REFERENCE_STIFFNESS"]

#: the parameters of the rigid models (the reference's names, the contract's names)
RIGID_PARAMETERS = paper.RIGID_PARAMETERS
#: the communication grids every case is run on
GRIDS = ("coarse", "fine", "irregular")
#: pipe geometry and density (the contract's defaults; the fuzz varies L1 only)
_R1, _H1, _RHO1 = 0.035, 0.003, 7800.0
_Q_MAX = 60e3                    # N, largest random load
_DURATIONS = (1e-5, 0.2)         # s, shortest and longest segment
_LIMIT_MAX = 2.0 * _Q_MAX        # N, largest load at a friction limit (a 1e-6 plug's is MN)
#: share of the model I cases with Smith damping
DAMPED_SHARE = 1.0 / 3.0
_J_RANGE, _J_LARGE = (0.01, 1.0), (1.0, 100.0)    # s/m, log-uniform
#: largest damping rate x stop time [1] of a damped case compared with the reference
#: (DOP853 takes up to about half as many steps per piece)
REFERENCE_STIFFNESS = 4e3


@dataclass(frozen=True)
class Plan:
    """Which cases get the costly checks: every ``reference``-th case is compared with the
    reference, every ``fmu``-th runs through the FMU, every ``fd``-th through the fd scheme
    (0 = never). Case 0 gets them all."""

    reference: int = 10
    fmu: int = 20
    fd: int = 100
    model: str = "rigid"     #: "rigid" (models I and II) or "elastic" (model III)

    def checks_for(self, index: int) -> tuple[str, ...]:
        """The check families of case ``index``: always ``"core"``, then the costly ones."""
        families = ["core"]
        for name in ("reference", "fmu", "fd"):
            every = getattr(self, name)
            if every and index % every == 0:
                families.append(name)
        return tuple(families)


@dataclass(frozen=True)
class Case:
    """One fuzz case (plain data, JSON round trip exact).

    ``segments`` are ``(duration [s], Q [N])`` applied one after another from t = 0, Q = 0
    after the last; ``grids`` map a grid name to its communication points [s]; ``samples``
    are the times [s] every grid holds; ``checks`` the check families to run.
    """

    seed: int
    index: int
    growth: bool
    params: dict
    segments: tuple
    stop: float
    samples: tuple
    grids: dict
    host_h: float
    checks: tuple = ("core",)
    note: str = field(default="", compare=False)

    @property
    def model(self) -> str:
        """``"II"`` (contact growth), ``"I damped"`` (Smith damping) or ``"I"``."""
        if self.growth:
            return "II"
        return "I damped" if "J_shaft" in self.params else "I"

    @property
    def options(self) -> dict:
        """The exact solver's options for this case."""
        return {"solver": "exact", "contact_growth": self.growth}


class OnBase:
    """A case made of a rigid case ``base`` (:class:`Case`) and more (a ram's strikes, a
    growing plug's clean-outs): every other attribute is the base's."""

    def __getattr__(self, name):
        if name.startswith("__") or name == "base":       # copying and pickling
            raise AttributeError(name)
        return getattr(self.base, name)        # seed, index, params, segments, grids, ...


def generate(seed: int, index: int, plan: Plan = Plan(), faces: bool = True,
             damping: bool = True) -> Case:
    """Case ``index`` of the fuzz run ``seed`` (see the module docstring); ``faces=False``:
    without end resistance, ``damping=False``: without Smith damping (the case as it was
    before each existed)."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
    growth = bool(rng.random() < 0.6)
    L1 = 1.0 if rng.random() < 0.7 else float(10.0 ** rng.uniform(math.log10(0.3), math.log10(3)))
    S1 = math.pi * ((_R1 + _H1) ** 2 - _R1 ** 2)
    S2, P1, P2 = math.pi * _R1 ** 2, 2.0 * math.pi * (_R1 + _H1), 2.0 * math.pi * _R1
    M1 = _RHO1 * S1 * L1
    L2, rho2, tau2 = _plug(rng, L1, M1, S2, P2)
    n = int(rng.integers(1, 7))
    durations = 10.0 ** rng.uniform(*np.log10(_DURATIONS), n)
    loads = rng.uniform(-_Q_MAX, _Q_MAX, n)
    q_max = float(np.max(np.abs(loads)))
    tau_hold = q_max / (P1 * L1)            # holds the largest load over the whole length
    r = rng.random()
    tau1 = 0.0 if r < 0.15 else (tau_hold if r < 0.22 else float(rng.uniform(0, 1.3) * tau_hold))
    F1, F2 = P1 * L1 * tau1, P2 * L2 * tau2
    M2 = rho2 * S2 * L2
    at_limit = _limit_loads(F1, F2, M1, M2)
    for k in range(n):
        if rng.random() < 0.25:
            loads[k] = at_limit[int(rng.integers(len(at_limit)))]
    segments = tuple((float(d), float(q)) for d, q in zip(durations, loads))
    end = float(np.sum(durations))
    stop = (end + float(rng.uniform(0.0, 0.3)) if rng.random() < 0.85
            else end - float(rng.uniform(0.0, 1.0)) * float(durations[-1]))
    stop = max(stop, float(durations[0]) * 0.5)
    samples = tuple(sorted(float(t) for t in rng.uniform(0.0, stop, 4))) + (stop,)
    params = dict(L1=L1, L2=L2, R1=_R1, h1=_H1, rho1=_RHO1, rho2=rho2, tau1=tau1, tau2=tau2)
    if faces:
        face = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, 1)))
        params.update(_faces(face, q_max, F2, S1, S2))
        segments = _face_limit_loads(face, segments, F1, F2, params, S1, S2)
    grids = _grids(rng, segments, stop, samples)
    host_h = stop / int(rng.integers(10, 301))
    checks = plan.checks_for(index)
    if damping and not growth:
        params.update(_damping(np.random.default_rng(
            np.random.SeedSequence(seed, spawn_key=(index, 2)))))
        if "J_shaft" in params:
            stiff = damping_rate(params) * stop > REFERENCE_STIFFNESS
            checks = tuple(c for c in checks if c != "fd" and not (stiff and c == "reference"))
    return Case(seed, index, growth, params, segments, stop, samples, grids, host_h, checks)


def _damping(rng, share: float = DAMPED_SHARE) -> dict:
    """``J_shaft``, ``J_face`` [s/m] for a ``share`` of the cases, else nothing (module
    docstring)."""
    if rng.random() >= share:
        return {}
    values = []
    for _ in range(2):
        r = rng.random()
        low, high = _J_LARGE if r < 0.1 else _J_RANGE
        values.append(0.0 if r > 0.75 else float(10.0 ** rng.uniform(math.log10(low),
                                                                      math.log10(high))))
    if values == [0.0, 0.0]:
        values[0] = float(10.0 ** rng.uniform(*np.log10(_J_RANGE)))
    return {"J_shaft": values[0], "J_face": values[1]}


def damping_rate(params: dict) -> float:
    """A bound [1/s] of the largest damping rate of model I with ``params`` (every damper
    over the mass it acts on, from the paper's formulas), 0 without damping."""
    js, jf = params.get("J_shaft", 0.0), params.get("J_face", 0.0)
    R1, h1 = params["R1"], params["h1"]
    S1, S2 = math.pi * ((R1 + h1) ** 2 - R1 ** 2), math.pi * R1 ** 2
    M1 = params["rho1"] * S1 * params["L1"]
    F1 = 2.0 * math.pi * (R1 + h1) * params["L1"] * params["tau1"]
    rate = (js * F1 + jf * params.get("q_face", 0.0) * S1) / M1
    if params["L2"] > 0.0 and params["tau2"] > 0.0:
        M2 = params["rho2"] * S2 * params["L2"]
        F2 = 2.0 * math.pi * R1 * params["L2"] * params["tau2"]
        rate += js * F2 / M1 + (js * F2 + jf * params.get("q_plug_face", 0.0) * S2) / M2
    return rate


def _plug(rng, L1: float, M1: float, S2: float, P2: float) -> tuple[float, float, float]:
    """``(L2, rho2, tau2)``: no plug, or a plug of 1e-6 to 1e3 pipe masses."""
    r = rng.random()
    if r < 0.08:
        return 0.0, 1800.0, float(rng.uniform(0.0, 2e5))            # L2 = 0
    L2 = L1 if rng.random() < 0.5 else float(L1 * 10.0 ** rng.uniform(-2.0, 0.0))
    rho2 = float(10.0 ** rng.uniform(-6.0, 3.0) * M1 / (S2 * L2))
    tau2 = 0.0 if r < 0.16 else float(10.0 ** rng.uniform(1.0, 5.0) / (P2 * L2))
    return L2, rho2, tau2


def _faces(rng, q_max: float, F2: float, S1: float, S2: float) -> dict:
    """``q_face``, ``q_plug_face`` [Pa] (module docstring)."""
    qf = float(rng.uniform(0.0, 1.3) * q_max) if rng.random() < 0.5 else 0.0
    qp = float(F2 * 10.0 ** rng.uniform(-1.0, 1.0)) if rng.random() < 0.5 else 0.0
    return {"q_face": qf / S1, "q_plug_face": qp / S2}


def _face_limit_loads(rng, segments, F1: float, F2: float, params: dict, S1: float,
                      S2: float) -> tuple:
    """A quarter of the loads moved to a limit of the end resistance's window (none without
    one)."""
    qf, qp = params["q_face"] * S1, params["q_plug_face"] * S2
    if qf == 0.0 and qp == 0.0:
        return segments
    limits = (F1 + qf, -(F1 + qf), F1 + qf + min(F2, qp), F1 + min(F2, qp))
    out = []
    for d, q in segments:
        pick = int(rng.integers(len(limits)))
        out.append((d, float(limits[pick]) if rng.random() < 0.25 else q))
    return tuple(out)


def _limit_loads(F1: float, F2: float, M1: float, M2: float) -> tuple[float, ...]:
    """Loads exactly at a friction limit, both signs (see the module docstring)."""
    free_plug = F2 * (M1 + M2) / M2 if M2 > 0.0 and F2 > 0.0 else 0.0
    values = (F1, F1 + F2, F2, F1 - F2, free_plug, F1 + free_plug)
    loads = tuple(s * v for v in values for s in (1.0, -1.0)) + (0.5 * F1, 0.0)
    return tuple(q for q in loads if abs(q) <= _LIMIT_MAX)


def _grids(rng, segments, stop: float, samples) -> dict:
    """The communication grids of a case (see the module docstring)."""
    edges = edges_of(segments)
    inner = [e for e in edges if 0.0 < e < stop]
    base = np.array([0.0, *inner, *samples])
    coarse = np.linspace(0.0, stop, int(rng.integers(2, 6)))
    fine = np.linspace(0.0, stop, int(rng.integers(150, 401)))
    m = int(rng.integers(30, 301))
    after_edges = (np.array([0.0, *inner])[rng.integers(0, len(inner) + 1, m // 2)]
                   + 10.0 ** rng.uniform(-9.0, -3.0, m // 2))
    irregular = np.concatenate([rng.uniform(0.0, stop, m - m // 2), after_edges])
    grids = {}
    for name, points in zip(GRIDS, (coarse, fine, irregular)):
        grid = np.unique(np.concatenate([base, points[(points >= 0.0) & (points <= stop)]]))
        grids[name] = tuple(float(t) for t in grid)
    return grids


def edges_of(segments) -> list[float]:
    """Load edges [s]: 0, then each segment's end, summed in order (as the reference does)."""
    return list(Load.from_segments(segments).times)


def load_at(segments, t: float) -> float:
    """The load [N] on a step starting at ``t`` [s] (right-continuous; 0 after the last)."""
    return Load.from_segments(segments).at(float(t))


def loads_on(segments, starts) -> np.ndarray:
    """The load [N] on steps starting at ``starts`` [s] (as :func:`load_at`, vectorised)."""
    return Load.from_segments(segments).on_steps(starts)


def host_calls(case: Case, style: str) -> list[tuple[float, float]]:
    """An FMU host's ``(currentCommunicationPoint, communicationStepSize)`` calls for ``case``
    (:func:`calls_of` with its load edges, stop time and host step)."""
    return calls_of(edges_of(case.segments), case.stop, case.host_h, style)


def calls_of(edges, stop: float, h: float, style: str) -> list[tuple[float, float]]:
    """An FMU host's ``(currentCommunicationPoint, communicationStepSize)`` calls to ``stop``.

    ``style`` ``"t+=h"``: the host adds each step of ``h`` [s] to its time; ``"t=k*h"``: it
    computes its points as ``k * h``. Either host also stops at every load edge of ``edges``
    [s] (as fmpy does for an input signal with duplicated time stamps) and at ``stop``.
    """
    edges = [e for e in edges if 0.0 < e < stop] + [stop]
    calls = []
    if style == "t+=h":
        t = 0.0
        while t < stop:
            nxt = min(t + h, next(e for e in edges if e > t))
            calls.append((t, nxt - t))
            t = t + (nxt - t)
    elif style == "t=k*h":
        n = int(math.floor(stop / h))
        points = sorted({k * h for k in range(n + 1)} | set(edges))
        points = [p for p in points if p <= stop]
        calls = [(a, b - a) for a, b in zip(points[:-1], points[1:])]
    else:
        raise ValueError(f"host style {style!r}; allowed: 't+=h', 't=k*h'")
    return calls


def strikes_on_calls(calls, strikes) -> dict[int, float]:
    """Which of an FMU host's ``calls`` starts each strike ``(time [s], velocity [m/s])``:
    call index -> velocity; a call starting within 1e-9 max(1, |t|) of the strike's time (a
    host adding up its steps reaches an edge only to round-off)."""
    starts = np.array([t for t, _ in calls])
    found = {}
    for time, velocity in strikes:
        i = int(np.argmin(np.abs(starts - time)))
        if abs(starts[i] - time) > 1e-9 * max(1.0, abs(time)):
            raise ValueError(f"no call starts at the strike's time {time!r} s")
        found[i] = float(velocity)
    return found


def case_to_json(case: Case) -> dict:
    """The case as JSON-ready data (floats round-trip exactly through :mod:`json`)."""
    data = asdict(case)
    data["segments"] = [list(s) for s in case.segments]
    data["grids"] = {k: list(v) for k, v in case.grids.items()}
    return data


def case_from_json(data: dict) -> Case:
    """The case written by :func:`case_to_json`."""
    data = dict(data)
    data["segments"] = tuple(tuple(float(x) for x in s) for s in data["segments"])
    data["grids"] = {k: tuple(float(t) for t in v) for k, v in data["grids"].items()}
    data["samples"] = tuple(float(t) for t in data["samples"])
    data["checks"] = tuple(data.get("checks", ("core",)))
    return Case(**data)
