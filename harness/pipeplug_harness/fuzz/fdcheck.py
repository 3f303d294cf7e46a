"""The fd check: the paper's explicit scheme against the exact solver, its bound and order.

Error measure. The fd runs on a grid of its own steps (one internal step per communication
step, ``dt`` = the largest step) and the exact solver on the same points. The error of an
output is its largest |fd - exact| over the run, measured in units of ``dt`` times the scale
(largest magnitude over the run) of its rate: velocities against the largest acceleration of
pipe or plug, displacements against the largest velocity, works against the largest power
(load, outer or inner friction). Those rates make ``C`` in ``error <= C dt scale`` a plain
number that holds for every case: a scheme of order one is off by a fraction of a step's
change of each quantity (its step velocities are those of the step's middle, for one), while
the scale of a quantity itself would tie ``C`` to each case's time scales, which here span 10
us to 0.2 s. ``E`` is the largest such error over the outputs and ``K = E / dt``.

Grids. An episode is the time between two consecutive events of the reference (load edges
included); each gets equal steps of ``min(T / N0, its length / RESOLVE) / 2**level``, so the
fd resolves every episode with at least ``RESOLVE`` steps at the coarsest level; levels 0, 1,
2 halve every step. Load edges are grid points. Every other event of the reference (stops,
sticks, breakaways, reaching 0 or L1) sits in the middle of a step at every level: the O(dt)
error an event leaves depends on where in its step it falls, and that phase would otherwise
change from level to level and scatter the observed order. A case whose coarsest grid would
need more than ``BUDGET`` steps (thousands of events) is not resolved and is not run.

Grazing. A case is grazing when the sequence of contact modes of the reference changes when
every load is scaled by ``1 - GRAZE`` or ``1 + GRAZE``: then the solution passes within a
relative ``GRAZE`` (about the fd's relative error at the coarsest level) of an event it does
not take, or takes one it barely reaches (a stop with vanishing acceleration, a static force
at its limit, a load exactly at a friction limit). The fd may then take another sequence of
events, and its error is not first order in dt there.

Checks. ``fd bound``: ``K <= C`` on every resolved case. ``fd order``: the least-squares
slope of log E over log dt, levels 0-2, within 1 +- 0.1 on resolved cases without grazing
whose error is not negligible (``K >= K_FLOOR``: a case whose first-order error term is
smaller than that, e.g. a short blow followed by a slow slide, shows the second-order terms
at these steps instead).

Constant. ``C`` (:data:`~pipeplug_harness.fuzz.checks.FD_C`) was fitted once with
:func:`fit_constant` (``pipeplug fuzz --fit-fd-constant``): see its docstring.
"""
from __future__ import annotations

import re
from typing import NamedTuple

import numpy as np

from .cases import Case, edges_of, loads_on
from .checks import CONTINUOUS, Body
from .runners import COLUMN, run_grid, run_reference

__all__ = ["FdResult", "fd_measure", "fd_grids", "grazing", "mode_sequence", "N0",
           "RESOLVE", "BUDGET", "GRAZE", "K_FLOOR"]

N0 = 100          #: steps over the whole run at the coarsest level (at most)
RESOLVE = 8       #: steps per episode at least, at the coarsest level
LEVELS = 3        #: dt, dt/2, dt/4
BUDGET = 4000     #: largest number of steps at the coarsest level
GRAZE = 1e-2      #: relative load perturbation that must not change the event sequence
K_FLOOR = 0.02    #: smallest K whose order is measured

_MODES = re.compile(r"pipe ([+-]\d+), plug ([+-]\d+)$")
_FAMILY = {"v_pipe": 1, "v_plug": 1, "u_pipe": 0, "u_plug": 0}      # else 2 (works)


class FdResult(NamedTuple):
    """Outcome of the fd check of one case."""

    resolved: bool
    grazing: bool
    K: float              #: largest E / dt over the levels
    order: float          #: observed order (nan if not measured)
    steps: int            #: fd steps over all levels


def fd_measure(case: Case, exact, fd, events) -> FdResult:
    """Run the fd check of ``case`` (``exact``, ``fd``: builders; ``events``: the reference's
    event list of the case)."""
    grids = fd_grids(case, events)
    if grids is None:
        return FdResult(False, False, float("nan"), float("nan"), 0)
    body = Body.of(case.params, case.growth)
    finest, _ = run_grid(exact, case, grids[-1])
    rates = _rates(finest, loads_on(case.segments, grids[-1][:-1]), body)
    errors, steps = [], []
    for grid in grids:
        dt = float(np.max(np.diff(grid)))
        ex = finest if grid is grids[-1] else run_grid(exact, case, grid)[0]
        approx, _ = run_grid(fd, case, grid, params={**case.params, "dt": dt},
                             options={"solver": "fd", "contact_growth": case.growth})
        errors.append(max(_error(approx[:, COLUMN[n]], ex[:, COLUMN[n]],
                                 rates[_FAMILY.get(n, 2)]) for n in CONTINUOUS))
        steps.append(dt)
    errors, steps = np.array(errors), np.array(steps)
    K = float(np.max(errors / steps))
    is_grazing = grazing(case, events)
    order = float("nan")
    if not is_grazing and np.all(errors > 0.0) and errors[0] / steps[0] >= K_FLOOR:
        order = float(np.polyfit(np.log(steps), np.log(errors), 1)[0])
    return FdResult(True, is_grazing, K, order, int(sum(len(g) - 1 for g in grids)))


def _error(a, b, rate: float) -> float:
    d = float(np.max(np.abs(a - b), initial=0.0))
    return 0.0 if d == 0.0 else (d / rate if rate > 0.0 else np.inf)


def _rates(rows, loads, body: Body) -> tuple[float, float, float]:
    """Scales of the rates: (largest velocity, acceleration, power) over the run."""
    c = COLUMN
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    f1, f2 = rows[:, c["F_outer"]], rows[:, c["F_inner"]]
    a1 = (loads + f1 + f2) / body.M1
    a2 = -f2 / body.M2 if body.plug else 0.0 * f2
    peak = lambda *xs: max(float(np.max(np.abs(x), initial=0.0)) for x in xs)  # noqa: E731
    return peak(v1, v2), peak(a1, a2), peak(loads * v1, f1 * v1, f2 * (v1 - v2))


def fd_grids(case: Case, events) -> list[np.ndarray] | None:
    """The fd grids of levels 0, 1, 2 (see the module docstring), or None over budget."""
    stop = case.stop
    knots = {e for e in edges_of(case.segments) if 0.0 < e < stop} | {stop}
    switches = {t for t, text in events if 0.0 < t < stop} - knots
    marks = sorted({0.0} | knots | switches)
    gaps = np.diff(marks)
    grids = []
    for level in range(LEVELS):
        steps = np.minimum(stop / N0, gaps / RESOLVE) / 2 ** level   # per episode
        points, x = [0.0], 0.0
        for i, b in enumerate(marks[1:]):
            if b in switches:               # one step centred on the event
                w = min(steps[i], steps[i + 1])
                points.extend(_uniform(x, b - 0.5 * w, steps[i]))
                x = b + 0.5 * w
                points.append(x)
            else:
                points.extend(_uniform(x, b, steps[i]))
                x = b
        if level == 0 and len(points) - 1 > BUDGET:
            return None
        grids.append(np.array(points))
    return grids


def _uniform(a: float, b: float, h: float) -> list[float]:
    """Points after ``a`` up to ``b`` splitting [a, b] into equal steps of at most ``h``."""
    if not b > a:
        return []
    n = max(int(np.ceil((b - a) / h)), 1)
    return list(np.linspace(a, b, n + 1)[1:])


def mode_sequence(events) -> list[tuple[int, int]]:
    """The reference's contact modes (pipe, plug) after each decision, repeats removed."""
    modes = []
    for _, text in events:
        m = _MODES.search(text)
        pair = (int(m.group(1)), int(m.group(2)))
        if not modes or modes[-1] != pair:
            modes.append(pair)
    return modes


def grazing(case: Case, events) -> bool:
    """True when scaling every load by 1 +- GRAZE changes the reference's mode sequence."""
    nominal = mode_sequence(events)
    for factor in (1.0 - GRAZE, 1.0 + GRAZE):
        scaled = Case(**{**case.__dict__, "segments": tuple((d, q * factor)
                                                            for d, q in case.segments)})
        if mode_sequence(run_reference(scaled, [case.stop])["events"]) != nominal:
            return True
    return False
