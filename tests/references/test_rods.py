"""Checks of the elastic-rod references against their own physics (quadrature and the PDE)."""
from __future__ import annotations

import numpy as np
import pytest

from pipeplug_references.rods import (
    FrictionRod,
    Load,
    free_rod_cell_velocity,
    free_rod_velocity,
)

L, C, Z = 2.0, 5000.0, 3.0e5      # a free rod of 2 m, wave speed 5000 m/s (0.8 ms round trip)


def _random_load(seed):
    rng = np.random.default_rng(seed)
    edges = np.cumsum(np.r_[rng.uniform(0, 2e-4), rng.uniform(1e-5, 6e-4, 6)])
    return Load(tuple(edges), tuple(rng.uniform(-3e4, 3e4, len(edges) - 1)))


@pytest.mark.parametrize("seed", range(4))
def test_cell_averages_are_the_averages_of_the_point_velocities(seed):
    load = _random_load(seed)
    t = np.linspace(0.0, 6e-3, 37)[1:]              # several round trips
    a, b = 0.3, 0.35
    x = np.linspace(a, b, 4001)
    points = np.array([free_rod_velocity(load, xi, t, L, C, Z) for xi in x])
    average = np.trapezoid(points, x, axis=0) / (b - a)
    exact = free_rod_cell_velocity(load, a, b, t, L, C, Z)
    assert np.abs(exact - average).max() <= 2e-3 * np.abs(exact).max()


@pytest.mark.parametrize("seed", range(4))
def test_the_rods_momentum_is_the_impulse_of_the_load(seed):
    """Integral of rho S v over the rod = integral of Q (no other force acts)."""
    load = _random_load(seed)
    n = 400
    edges = np.linspace(0.0, L, n + 1)
    for t in (1.3e-3, 4.1e-3, 9.7e-3):
        cells = free_rod_cell_velocity(load, edges[:-1], edges[1:], t, L, C, Z)
        momentum = (Z / C) * (L / n) * np.sum(cells)       # rho S = Z / c
        assert momentum == pytest.approx(float(load.impulse(t)), rel=1e-12, abs=1e-9)


def test_a_pulse_doubles_at_the_free_end_and_returns_with_its_sign():
    load = Load((0.0, 1e-4), (1e4,))
    far = free_rod_velocity(load, L, np.array([L / C + 5e-5]), L, C, Z)
    back = free_rod_velocity(load, 0.5, np.array([(2 * L - 0.5) / C + 5e-5]), L, C, Z)
    assert far[0] == pytest.approx(2e4 / Z) and back[0] == pytest.approx(1e4 / Z)


ROD = FrictionRod(Q=4.0e5, f=3.0e4, c=C, Z=Z)


def test_friction_rod_satisfies_its_equations():
    """rho S v_t = N_x - f (v > 0) and N_t = E S v_x behind the front (finite differences),
    N(0) = -Q, and the front's jump N = -Z v (a wave running to +x)."""
    rho_s, es = Z / C, Z * C
    x, t, d = 0.8 * ROD.reach * 0.4, 0.6 * ROD.stop, 1e-7
    v_t = (ROD.velocity(x, t + d) - ROD.velocity(x, t - d)) / (2 * d)
    n_x = (ROD.force(x + d * C, t) - ROD.force(x - d * C, t)) / (2 * d * C)
    assert rho_s * v_t == pytest.approx(n_x - ROD.f, rel=1e-6)
    n_t = (ROD.force(x, t + d) - ROD.force(x, t - d)) / (2 * d)
    v_x = (ROD.velocity(x + d * C, t) - ROD.velocity(x - d * C, t)) / (2 * d * C)
    assert n_t == pytest.approx(es * v_x, abs=1e-6 * ROD.Q)
    assert ROD.force(0.0, t) == pytest.approx(-ROD.Q)
    front = C * t
    assert ROD.force(front * (1 - 1e-12), t) == pytest.approx(-Z * ROD.velocity(
        front * (1 - 1e-12), t), rel=1e-9)


def test_friction_rod_balances_its_energy():
    """Q x set = friction work + strain energy (integrals of f v and N^2 / (2 E S)), 2/3 and
    1/3 of it; the set is the integral of the head's velocity."""
    t = np.linspace(0.0, ROD.stop, 4001)
    x = np.linspace(0.0, ROD.reach, 4001)
    head = np.trapezoid(ROD.velocity(0.0, t), t)
    assert head == pytest.approx(ROD.set, rel=1e-6)
    assert ROD.displacement(0.0, 2 * ROD.stop) == pytest.approx(ROD.set, rel=1e-12)
    friction = np.trapezoid([ROD.f * np.trapezoid(ROD.velocity(x, ti), x) for ti in t], t)
    strain = np.trapezoid(ROD.force(x, ROD.stop * (1 - 1e-12)) ** 2, x) / (2 * Z * C)
    assert friction == pytest.approx(ROD.friction_work, rel=1e-3)
    assert strain == pytest.approx(ROD.strain_energy, rel=1e-6)
    assert ROD.friction_work + ROD.strain_energy == pytest.approx(ROD.input_work, rel=1e-12)
    assert ROD.strain_energy == pytest.approx(ROD.input_work / 3, rel=1e-12)
