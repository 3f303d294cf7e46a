"""Model III against the exact solutions of :mod:`pipeplug_references.rods` and the closed form of
model I (references that never import the core)."""
from __future__ import annotations

import numpy as np
import pytest
from elastic_helpers import elastic, impedance

from pipeplug_references.closed_form import Case, solution
from pipeplug_references.rods import FrictionRod, Load, free_rod_cell_velocity


def _gridded(load: Load, h: float, t_end: float) -> Load:
    """The load as the model applies it: the mean force of each internal step (its impulse)."""
    edges = np.arange(0.0, t_end + 0.5 * h, h)
    values = np.diff(load.impulse(edges)) / h
    return Load(tuple(edges), tuple(values))


@pytest.mark.parametrize("seed", range(6))
def test_free_rod_cells_are_the_exact_averages_under_any_load(seed):
    """No friction, Courant 1: every cell's velocity is the exact d'Alembert average at every
    grid point, over many reflections, for random loads switching between grid points (the
    model then applies each step's mean force; the host's points are random too)."""
    rng = np.random.default_rng(seed)
    model = elastic(dict(L1=1.0, dx=0.05, tau1=0.0, tau2=0.0))
    p, h = model.params, model.grid.h_max
    edges = np.cumsum(np.r_[0.0, rng.uniform(0.3, 40.0, 8)]) * h
    load = Load(tuple(edges), tuple(rng.uniform(-3e4, 3e4, len(edges) - 1)))
    t_end = 400 * h                                   # 10 round trips of the 20 cells
    points = np.union1d(np.cumsum(rng.uniform(0.2, 13.0, 200)) * h, edges)
    points = points[(points > 0.0) & (points <= t_end)]
    t = 0.0
    faces = np.arange(model.grid.n1 + 1) * p.dx
    exact_load = _gridded(load, h, t_end)
    worst, scale = 0.0, np.abs(load.values).max() / impedance(p)
    for t_next in points:
        model.advance_to(float(load.at(t)), t_next, t)
        t = t_next
        grid_time = model.clock.point(model.clock.k)
        exact = free_rod_cell_velocity(exact_load, faces[:-1], faces[1:], grid_time, p.L1,
                                       p.c1, impedance(p))
        worst = max(worst, np.abs(model.v1 - exact).max())
    assert worst <= 1e-12 * scale


def _friction_rod_run(n_cells: int):
    """A 10 m pipe with soil friction (no plug) under Q = 0.3 F1 from t = 0 (reach 6 m):
    the model's head displacement, ledger shares and the exact rod."""
    model = elastic(dict(L1=10.0, L2=0.0, tau2=0.0, tau1=2e4, dx=10.0 / n_cells, x_monitor=0.0))
    p = model.params
    f = p.P1 * p.tau1
    rod = FrictionRod(0.3 * f * p.L1, f, p.c1, impedance(p))
    h = model.grid.h_max
    model.advance(rod.Q, round(1.5 * rod.stop / h) * h)
    out = model.outputs()
    exact_u = float(rod.displacement(0.5 * p.dx, 2 * rod.stop))   # first cell's centre
    return out, rod, exact_u


def test_rod_with_dry_friction_converges_to_the_exact_solution_at_first_order():
    """Set, input work and the friction / strain shares 2/3 and 1/3: errors fitted against dx
    over 4 grids give an order of 1 (dry friction's switching), and the finest is within 1 %."""
    rows = []
    for n in (50, 100, 200, 400):
        out, rod, exact_u = _friction_rod_run(n)
        assert out.v_pipe == 0.0 and out.E_kinetic == 0.0         # stuck for good, as exact
        rows.append((n, abs(out.u_pipe / exact_u - 1), abs(out.W_input / rod.input_work - 1),
                     abs(out.W_friction / out.W_input - 2 / 3),
                     abs(out.E_strain / out.W_input - 1 / 3)))
    rows = np.array(rows)
    dx = 10.0 / rows[:, 0]
    for column in range(1, 5):
        order = np.polyfit(np.log(dx), np.log(rows[:, column]), 1)[0]
        assert 0.9 <= order <= 1.1, (column, order, rows[:, column])
        assert rows[-1, column] <= 1e-2


@pytest.mark.parametrize("tau1, tau2", [(2e4, 1e4), (0.0, 1e4), (6.5e4, 6.5e4)])
def test_long_blows_tend_to_the_rigid_closed_form(tau1, tau2):
    """A blow much longer than the wave round trip 2 L1 / c1: model III approaches model I's
    closed form (independent of the core) as the rods stiffen (round trip / 10 for E x 100):
    the displacements of pipe and plug 0.3 s after the blow's start within 1 % of the pipe's,
    and about 10 times closer for the stiffer rods (at least 8)."""
    case = Case(tau1=tau1, tau2=tau2)
    horizon = 0.3
    exact = solution(case, np.array([horizon]))
    errors = []
    for stiffen in (1.0, 100.0):
        model = elastic(dict(tau1=tau1, tau2=tau2, dx=0.05, E1=1.95e11 * stiffen,
                             E2=6e8 * stiffen))
        model.advance(case.Q0, case.t0)
        model.advance(0.0, horizon - case.t0)
        out = model.outputs()
        got = np.array([out.u_pipe, out.u_plug])
        want = np.array([exact["U1"][0], exact["U2"][0]])
        errors.append(np.abs(got - want).max() / abs(want[0]))
    assert errors[0] < 0.01 and errors[1] <= errors[0] / 8
