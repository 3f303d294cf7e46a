"""The fd check: the paper's explicit scheme against the exact solver, its bound and order.

Error measure. The fd runs on a grid of its own steps (one internal step per communication
step, ``dt`` = the largest step) and the exact solver on the same points. The error of an
output is its largest |fd - exact| over the run, in units of ``dt`` times the scale of what
drives it, ``R``, and of the growth factor ``G`` of the run (below). For velocities ``R`` is
the largest acceleration of pipe or plug; for displacements the largest velocity plus the
largest acceleration times the run's duration T (a velocity error, first order, is carried
along and integrated over the run: a pipe pulled out of the soil in model II flies on with
it); for works the largest power plus the largest force times that accumulated velocity.
These scales make ``C`` in ``error <= C dt R G`` a plain number for every case: a scheme of
order one is off by a share of a step's change of each quantity (its step velocities are the
step's mean velocities, for one), while the quantity's own scale would tie ``C`` to each
case's time scales, which here span 10 us to 0.2 s. ``E`` is the largest such error over the
outputs, ``K = E / dt``.

Growth. In model II a pipe sliding backward inside the contact region obeys
``M U'' = Q + P1 tau1 U``: unstable, an error grows like ``exp(t sqrt(P1 tau1 / M))``. ``G``
is that factor over all such slides of the exact run (1 if there are none); it is a property
of the problem, not of the scheme.

Entries. In model II the pipe's end resistance ``Qf`` acts from U1 = 0 on, so the scheme's
position error ``du`` at the pipe's entry into the soil, at speed ``v``, moves the entry by
``du / v``, and the force jump ``Qf`` over that time leaves a velocity error of ``Qf du / (M1
v)``: a pipe pulled out of the soil that flies back into it carries its velocity error of the
slide into a position error over the flight, then into a velocity error at the entry (case
9177:1600: K = 0.97 on the velocities against C = 0.6, first order all the same, 0.95). That
part of the error is explained by the position error, itself checked: from each entry on, the
velocities' error less ``Qf du / (M1 v) + k1 du t / M1`` (t the time since the entry: the
soil's friction, growing with the penetration by ``k1 = P1 tau1`` per metre, is ``k1 du`` off
too) and the displacements' less its integral are measured (``du`` the larger of the two grid
points around the entry, on the same grid; nothing for an entry at speed 0), from the earlier
of the two runs' entries on. Like ``G`` it is the problem's conditioning, but
measured on the run, so that a scheme worse elsewhere is not excused.

Grids. An episode is the time between two consecutive events of the reference (load edges
included); each gets equal steps of ``min(T / N0, 1 / (W_STEPS w), its length / RESOLVE) /
2**level`` (``w = sqrt(P1 tau1 / M1)``, the rate of the harmonic and exponential pieces of
model II), so the fd resolves every episode with ``RESOLVE`` steps and 1/w with ``W_STEPS`` at
the coarsest level; levels 0, 1, 2 halve every step. (With 16 steps per 1/w, 19 of the 2,393
cases measured in one fit run, all model II, showed orders of 0.74-1.26: the error's second-
order part was still 10-20 % of it.) Load edges are grid points. Every other event of the
reference (stops, sticks, breakaways, reaching 0 or L1) sits in the middle of a step at every
level: the O(dt) error an event leaves depends on where in its step it falls, and that phase
would otherwise change from level to level and scatter the observed order. A case whose
coarsest grid would need more than ``BUDGET`` steps (thousands of events) is not resolved and
is not run.

Grazing. A case is grazing when the sequence of contact modes of the reference changes when
every load is scaled by ``1 - GRAZE`` or ``1 + GRAZE``: then the solution passes within a
relative ``GRAZE`` of an event it does not take, or takes one it barely reaches (a stop with
vanishing acceleration, a static force at its limit, a load exactly at a friction limit).
The fd may then take another sequence of events, and its error is not first order in dt.

Checks. ``fd bound``: ``K <= C`` on every resolved case. ``fd order``: the least-squares
slope over log dt, levels 0-2, of the log of the works' error (``E`` over the works only),
within 1 +- 0.1 on resolved cases without grazing,
with ``G <= G_MAX`` (an error amplified more than that leaves the fd at these steps on
another sequence of events) and a nonzero error (a case where nothing moves is exact). The
works integrate the scheme's velocities against the forces over the run: their error is the
scheme's global error. The velocities' own error adds the local offset of a step's mean
velocity from the end velocity, -a dt / 2, whose peak moves between the kinks of the
acceleration from one level to the next: fitted on all outputs, 9 of the 4,725 cases
measured in two fit runs (seeds 22, 23; all model II) showed orders of 0.88-1.56, on the works
0.98-1.00 (seed 24, on the works: 0.977-1.004 for 98 % of 2,372, none outside 0.9-1.1). When
the slope is outside 0.9-1.1 all the same, the case is refined by up to ``EXTRA_LEVELS`` more
halvings and the slope of the last three levels counts (the first-order term may not yet
dominate at the coarsest steps).

Constant. ``C`` (:data:`~pipeplug_harness.fuzz.checks.FD_C`) was fitted once with
``pipeplug fuzz --fit-fd-constant``: see :func:`~pipeplug_harness.fuzz.command.fit_fd_constant`.
"""
from __future__ import annotations

import re
from typing import NamedTuple

import numpy as np

from .cases import Case, edges_of, loads_on
from .checks import CONTINUOUS, Body, worst_of
from .runners import COLUMN, run_grid, run_reference

__all__ = ["FdResult", "fd_measure", "fd_grid", "grazing", "mode_sequence", "N0",
           "RESOLVE", "W_STEPS", "BUDGET", "GRAZE", "G_MAX"]

N0 = 200          #: steps over the whole run at the coarsest level (at least)
RESOLVE = 16      #: steps per episode at least, at the coarsest level
W_STEPS = 64      #: steps per 1/w at least, at the coarsest level
LEVELS = 3        #: dt, dt/2, dt/4
EXTRA_LEVELS = 2  #: further halvings when the order of the last three is outside 0.9-1.1
BUDGET = 20000    #: largest number of steps at the coarsest level
GRAZE = 1e-2      #: relative load perturbation that must not change the event sequence
G_MAX = 10.0      #: largest growth factor whose order is measured

_MODES = re.compile(r"pipe ([+-]\d+), plug ([+-]\d+)(?:, face ([+-]\d+))?$")
_FAMILY = {"v_pipe": 1, "v_plug": 1, "u_pipe": 0, "u_plug": 0}      # else 2 (works)


class FdResult(NamedTuple):
    """Outcome of the fd check of one case."""

    resolved: bool
    grazing: bool
    K: float              #: largest E / dt over the levels
    order: float          #: observed order (nan if not measured)
    steps: int            #: fd steps over all levels
    growth: float         #: error growth factor of the unstable pieces (1: none)
    levels: int           #: levels run (LEVELS, or more where the order was refined)


def fd_measure(case: Case, exact, fd, events) -> FdResult:
    """Run the fd check of ``case`` (``exact``, ``fd``: builders; ``events``: the reference's
    event list of the case)."""
    marks = _marks(case, events)
    if len(fd_grid(case, marks, 0)) - 1 > BUDGET:
        return FdResult(False, False, float("nan"), float("nan"), 0, float("nan"), 0)
    body = Body.of(case.params, case.growth)
    finest = fd_grid(case, marks, LEVELS - 1)
    exact_rows, _ = run_grid(exact, case, finest)
    rates, growth = _rates(exact_rows, finest, loads_on(case.segments, finest[:-1]), body,
                           case.stop)
    errors, works, steps, n = [], [], [], 0
    is_grazing = grazing(case, events)
    measured = not is_grazing and growth <= G_MAX
    for level in range(LEVELS + EXTRA_LEVELS):
        grid = fd_grid(case, marks, level)
        dt = float(np.max(np.diff(grid)))
        ex = exact_rows if level == LEVELS - 1 else run_grid(exact, case, grid)[0]
        approx, _ = run_grid(fd, case, grid, params={**case.params, "dt": dt},
                             options={"solver": "fd", "contact_growth": case.growth})
        explained = (*_explained(approx, ex, grid[1:], body)[::-1], 0.0)   # (du, dv, works)
        each = {name: _error(approx[:, COLUMN[name]], ex[:, COLUMN[name]],
                             rates[_FAMILY.get(name, 2)] * growth,
                             explained[_FAMILY.get(name, 2)]) for name in CONTINUOUS}
        errors.append(worst_of(list(each.values())))
        works.append(worst_of([each[name] for name in CONTINUOUS if name not in _FAMILY]))
        steps.append(dt)
        n += len(grid) - 1
        if level + 1 < LEVELS:
            continue
        order = _order(works[-LEVELS:], steps[-LEVELS:]) if measured else float("nan")
        if not abs(order - 1.0) > 0.1:          # in range, or not measured (nan)
            break
    K = float(np.max(np.array(errors) / np.array(steps)))
    return FdResult(True, is_grazing, K, order, n, growth, level + 1)


def _order(errors, steps) -> float:
    """Least-squares slope of log error over log dt (nan if an error is 0: exact)."""
    if not all(e > 0.0 for e in errors):
        return float("nan")
    return float(np.polyfit(np.log(steps), np.log(errors), 1)[0])


def _error(a, b, rate: float, explained=0.0) -> float:
    """Largest |a - b| less the ``explained`` part (a number or one per point), over ``rate``."""
    d = float(np.max(np.abs(a - b) - explained, initial=0.0))
    return 0.0 if d <= 0.0 else (d / rate if rate > 0.0 else np.inf)


def _rates(rows, grid, loads, body: Body, stop: float) -> tuple[tuple, float]:
    """The rate scales (displacements, velocities, works) of an exact run on ``grid`` and
    its growth factor (see the module docstring)."""
    c = COLUMN
    v1, v2 = rows[:, c["v_pipe"]], rows[:, c["v_plug"]]
    f1, f2 = rows[:, c["F_outer"]], rows[:, c["F_inner"]]
    # the end resistance while an end advances (its static share at rest only adds to a1)
    e1, e3 = -body.Qf * (v1 > 0.0), -body.Qp * (v2 > 0.0)
    a1 = (loads + f1 + f2 + e1) / body.M1
    a2 = (e3 - f2) / body.M2 if body.plug else 0.0 * f2
    peak = lambda *xs: max(float(np.max(np.abs(x), initial=0.0)) for x in xs)  # noqa: E731
    V, A = peak(v1, v2), peak(a1, a2)
    P = peak(loads * v1, f1 * v1, f2 * (v1 - v2), e1 * v1, e3 * v2)
    F = max(peak(loads, f1, f2), body.Qf, body.Qp)
    return (V + A * stop, A, P + F * A * stop), _growth(rows, grid, body)


def _entries(rows, body: Body) -> list[tuple[int, float]]:
    """The pipe's entries into the soil (U1 crossing 0 forward, model II with end resistance)
    in ``rows`` of a run: the index of the grid point before each and the speed there [m/s],
    interpolated between the two points around it (see "Entries" in the module docstring)."""
    if not (body.growth and body.Qf > 0.0):
        return []
    u, v = rows[:, COLUMN["u_pipe"]], rows[:, COLUMN["v_pipe"]]
    entry = np.flatnonzero((u[:-1] < 0.0) & (u[1:] >= 0.0))
    share = -u[entry] / (u[entry + 1] - u[entry])         # of the step, before the entry
    speeds = np.abs(v[entry] + share * (v[entry + 1] - v[entry]))
    return [(int(i), float(s)) for i, s in zip(entry, speeds)]


def _explained(approx, exact, times, body: Body) -> tuple[np.ndarray, np.ndarray]:
    """The velocity [m/s] and displacement [m] errors of the fd run ``approx`` that its position
    errors at the pipe's entries into the soil explain, at each point of ``times`` [s] (the
    grid of both runs; zeros without an entry)."""
    dv, du = np.zeros(len(times)), np.zeros(len(times))
    miss = np.abs(approx[:, COLUMN["u_pipe"]] - exact[:, COLUMN["u_pipe"]])
    entries = _entries(exact, body)
    theirs = _entries(approx, body)
    if len(theirs) != len(entries):          # not paired: from the exact run's entries alone
        theirs = entries
    for (i, speed), (j, _) in zip(entries, theirs):
        if speed > 0.0:
            error = max(miss[i], miss[i + 1])
            jump = body.Qf / body.M1 * error / speed          # [m/s]
            drift = body.k1 / body.M1 * error                   # [m/s^2], the soil's slope
            first = min(i, j)                                   # the earlier of the two entries
            since = times[first + 1:] - times[first]
            dv[first + 1:] += jump + drift * since
            du[first + 1:] += (jump + 0.5 * drift * since) * since
    return dv, du


def _growth(rows, grid, body: Body) -> float:
    """exp of the integral of sqrt(P1 tau1 / M) over the backward slides inside the contact
    region of model II (1 elsewhere): how much those unstable pieces amplify an error."""
    if not (body.growth and body.k1 > 0.0):
        return 1.0
    c = COLUMN
    u, pipe, plug = rows[:, c["u_pipe"]], rows[:, c["pipe_mode"]], rows[:, c["plug_mode"]]
    mass = np.where((plug == 0) & body.plug, body.M1 + body.M2, body.M1)
    back = (pipe == -1) & (u > 0.0) & (u < body.L1)
    return float(np.exp(np.sum(np.diff(grid)[back] * np.sqrt(body.k1 / mass[back]))))


def _marks(case: Case, events) -> tuple[list, set]:
    """The episode ends (0, load edges, the reference's events, the stop time) and which of
    them are events to centre a step on."""
    stop = case.stop
    knots = {e for e in edges_of(case.segments) if 0.0 < e < stop} | {stop}
    switches = {t for t, _ in events if 0.0 < t < stop} - knots
    return sorted({0.0} | knots | switches), switches


def fd_grid(case: Case, marks, level: int) -> np.ndarray:
    """The fd grid of ``level`` (see the module docstring); ``marks`` from :func:`_marks`."""
    ends, switches = marks
    gaps = np.diff(ends)
    body = Body.of(case.params, case.growth)
    period = 1.0 / np.sqrt(body.k1 / body.M1) if body.growth and body.k1 > 0.0 else np.inf
    steps = np.minimum(min(case.stop / N0, period / W_STEPS), gaps / RESOLVE) / 2 ** level
    points, x = [0.0], 0.0
    for i, b in enumerate(ends[1:]):
        if b in switches:                   # one step centred on the event
            w = min(steps[i], steps[i + 1])
            points.extend(_uniform(x, b - 0.5 * w, steps[i]))
            x = b + 0.5 * w
            points.append(x)
        else:
            points.extend(_uniform(x, b, steps[i]))
            x = b
    return np.array(points)


def _uniform(a: float, b: float, h: float) -> list[float]:
    """Points after ``a`` up to ``b`` splitting [a, b] into equal steps of at most ``h``."""
    if not b > a:
        return []
    n = max(int(np.ceil((b - a) / h)), 1)
    return list(np.linspace(a, b, n + 1)[1:])


def mode_sequence(events) -> list[tuple[int, ...]]:
    """The reference's contact modes (pipe, plug, and the plug's face with end resistance)
    after each decision, repeats removed."""
    modes = []
    for _, text in events:
        m = _MODES.search(text)
        pair = tuple(int(g) for g in m.groups() if g is not None)
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
