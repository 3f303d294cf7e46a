"""Exact solutions for elastic rods (model III references); they never import the core.

A rod of length ``L`` [m], wave speed ``c`` [m/s] and impedance ``Z = S sqrt(E rho)`` [N s/m]
is loaded by an axial force ``Q(t)`` [N] at its struck end x = 0 (compressive for Q > 0, so the
force there is N(0, t) = -Q); the other end is free.

* :func:`free_rod_velocity`, :func:`free_rod_cell_velocity`: no friction, any piecewise-constant
  ``Q`` (d'Alembert, with every reflection). Both ends are force ends and reflect a velocity wave
  with its sign: ``v(x, t) = sum_k [Q(t - (2kL + x)/c) + Q(t - (2(k+1)L - x)/c)] / Z``. The
  average over a cell is the same sum of impulse differences ``I(a) - I(b)`` (``I`` the integral
  of Q), exact for any piecewise-constant load;
* :class:`FrictionRod`: uniform Coulomb friction ``f`` [N/m] along a long rod at rest, ``Q``
  constant from t = 0. Behind the front x < c t, while t <= 2 Q / (c f)::

      v = (Q - c f t / 2) / Z          N = -Q + f x / 2

  (checked against rho S v_t = N_x - f, N_t = E S v_x and the front's jump N = -Z v). At
  t* = 2 Q / (c f) the whole moving part stops at once and stays stuck (|N_x| = f/2 < f), with
  set Q^2 / (Z c f) at x = 0, input work Q^3 / (Z c f), of which 2/3 was dissipated by friction
  and 1/3 stays as strain energy.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Load", "free_rod_velocity", "free_rod_cell_velocity", "FrictionRod"]


@dataclass(frozen=True)
class Load:
    """A piecewise-constant force: ``values[i]`` [N] on ``[edges[i], edges[i + 1])`` [s], 0
    before ``edges[0]`` and after ``edges[-1]``."""

    edges: tuple
    values: tuple

    def at(self, t):
        """Q at times ``t`` [s] (right-continuous)."""
        t = np.asarray(t, dtype=float)
        edges = np.asarray(self.edges, dtype=float)
        index = np.searchsorted(edges, t, side="right") - 1
        inside = (index >= 0) & (index < len(self.values))
        values = np.asarray(self.values, dtype=float)
        return np.where(inside, values[np.clip(index, 0, len(self.values) - 1)], 0.0)

    def impulse(self, t):
        """The integral of Q from -inf to ``t`` [N s] (array): the impulse up to the edge
        before ``t`` plus the force since it."""
        t = np.asarray(t, dtype=float)
        edges = np.asarray(self.edges, dtype=float)
        values = np.append(np.asarray(self.values, dtype=float), 0.0)
        before = np.concatenate(([0.0], np.cumsum(values[:-1] * np.diff(edges))))
        index = np.searchsorted(edges, t, side="right") - 1
        inside = index >= 0
        index = np.clip(index, 0, len(edges) - 1)
        return np.where(inside, before[index] + values[index] * (t - edges[index]), 0.0)


def _images(L: float, c: float, t_max: float) -> int:
    """How many round trips the waves make by ``t_max`` [s]: the sums' number of terms."""
    return int(c * t_max / (2.0 * L)) + 1


def free_rod_velocity(load: Load, x: float, t, L: float, c: float, Z: float):
    """Velocity [m/s] of the free rod at section ``x`` [m] at times ``t`` [s]."""
    t = np.asarray(t, dtype=float)
    v = np.zeros_like(t)
    for k in range(_images(L, c, float(t.max(initial=0.0)))):
        v += load.at(t - (2 * k * L + x) / c) + load.at(t - (2 * (k + 1) * L - x) / c)
    return v / Z


def free_rod_cell_velocity(load: Load, a, b, t, L: float, c: float, Z: float):
    """Average velocity [m/s] of the free rod over the cells ``a <= x <= b`` [m] at times
    ``t`` [s] (exact for the piecewise-constant load; ``a``, ``b`` and ``t`` broadcast)."""
    a, b, t = np.broadcast_arrays(*(np.asarray(z, dtype=float) for z in (a, b, t)))
    v = np.zeros_like(t)
    impulse = load.impulse
    for k in range(_images(L, c, float(t.max(initial=0.0)))):
        # the incident wave of image k (arrives at x after (2kL + x)/c) and its reflection
        v += impulse(t - (2 * k * L + a) / c) - impulse(t - (2 * k * L + b) / c)
        v += impulse(t - (2 * (k + 1) * L - b) / c) - impulse(t - (2 * (k + 1) * L - a) / c)
    return v * c / ((b - a) * Z)


@dataclass(frozen=True)
class FrictionRod:
    """The rod with uniform friction ``f`` [N/m] under a constant end force ``Q`` [N] from
    t = 0 (module docstring); ``c`` [m/s] and ``Z`` [N s/m] of the rod, which must be longer
    than :attr:`reach`."""

    Q: float
    f: float
    c: float
    Z: float

    @property
    def stop(self) -> float:
        """The instant the rod stops for good [s]: 2 Q / (c f)."""
        return 2.0 * self.Q / (self.c * self.f)

    @property
    def reach(self) -> float:
        """The length set moving [m]: 2 Q / f."""
        return 2.0 * self.Q / self.f

    def velocity(self, x, t):
        """Velocity [m/s] at sections ``x`` [m] and times ``t`` [s] (broadcast)."""
        x, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(t, float))
        moving = (x <= self.c * t) & (t < self.stop)
        return np.where(moving, (self.Q - 0.5 * self.c * self.f * t) / self.Z, 0.0)

    def force(self, x, t):
        """Axial force [N] (tension positive) at sections ``x`` [m] and times ``t`` [s]."""
        x, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(t, float))
        behind = x <= self.c * np.minimum(t, self.stop)
        return np.where(behind, -self.Q + 0.5 * self.f * x, 0.0)

    def displacement(self, x, t):
        """Displacement [m] at sections ``x`` [m] and times ``t`` [s]: the integral of the
        velocity from the front's arrival x / c to t (to the stop at most)."""
        x, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(t, float))
        start, end = x / self.c, np.minimum(t, self.stop)
        end = np.maximum(end, start)
        return (self.Q * (end - start) - 0.25 * self.c * self.f * (end * end - start * start)
                ) / self.Z

    @property
    def set(self) -> float:
        """The final displacement of the struck end [m]: Q^2 / (Z c f)."""
        return self.Q ** 2 / (self.Z * self.c * self.f)

    @property
    def input_work(self) -> float:
        """The work of Q [J]: Q^3 / (Z c f)."""
        return self.Q * self.set

    @property
    def friction_work(self) -> float:
        """Friction work [J]: 2/3 of the input work."""
        return 2.0 * self.input_work / 3.0

    @property
    def strain_energy(self) -> float:
        """Strain energy left in the stuck rod [J]: 1/3 of the input work (the integral of
        N^2 / (2 E S) with E S = Z c)."""
        return self.Q ** 3 / (3.0 * self.f * self.Z * self.c)

