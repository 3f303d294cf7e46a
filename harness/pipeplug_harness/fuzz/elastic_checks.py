"""The checks of model III cases, as functions of run outputs (tolerances: :data:`.checks.CHECKS`).

Masses, impedances and friction limits are computed here from the parameters (the contract's
formulas), not taken from the core.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pipeplug.interface import LEDGER_SOURCES, LEDGER_TERMS, ledger_residual
from pipeplug_references.rods import Load, free_rod_cell_velocity

from .checks import relative_error
from .elastic_cases import ElasticCase, internal_step
from .runners import COLUMN

__all__ = ["RodBody", "LEDGER_BASE", "LEDGER_PER_STEP", "ledger_error", "ledger_roundoff",
           "energy_violations",
           "bound_ratio", "free_rod_error"]

_WORKS = LEDGER_SOURCES + LEDGER_TERMS + ("W_friction_outer", "W_friction_inner")


class RodBody(NamedTuple):
    """What the bounds need of a case's rods [kg, N s/m, N]."""

    M1: float          #: pipe mass
    Z1: float          #: pipe impedance S1 sqrt(E1 rho1)
    F1: float          #: soil friction limit over the whole pipe
    F2: float          #: plug friction limit (0 when the plug is not simulated)
    m_ram: float = 0.0  #: the ram's mass (0: no ram)
    m_cell: float = 0.0  #: one cell of the pipe
    F_face: float = 0.0  #: the end resistances q_face S1 + q_plug_face S2 (a simulated plug)

    @classmethod
    def of(cls, p: dict, plug_growth: bool = False) -> RodBody:
        """The body of parameters ``p``; a plug that grows may fill the pipe (its friction
        limit is that of L1)."""
        S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
        plug = p["tau2"] > 0.0 and (p["L2"] > 0.0 or plug_growth)
        L2 = p["L1"] if plug_growth else p["L2"]
        face = (p.get("q_face", 0.0) * S1
                + (p.get("q_plug_face", 0.0) * math.pi * p["R1"] ** 2 if plug else 0.0))
        return cls(p["rho1"] * S1 * p["L1"], S1 * math.sqrt(p["E1"] * p["rho1"]),
                   2 * math.pi * (p["R1"] + p["h1"]) * p["L1"] * p["tau1"],
                   2 * math.pi * p["R1"] * L2 * p["tau2"] if plug else 0.0,
                   p.get("ram_mass", 0.0), p["rho1"] * S1 * p["dx"], face)


def _column(rows, name: str) -> np.ndarray:
    return rows[:, COLUMN[name]]


def _largest_work(rows) -> float:
    return max(float(np.max(np.abs(_column(rows, n)), initial=0.0)) for n in _WORKS)


#: The ledger's allowance: 1e-12 of the largest work, plus the round-off of the fields, which
#: grows by about one unit of the last place of the energy per internal step (measured: up to
#: 0.7 of it, with a plug stuck to a ringing pipe; the works are compensated sums).
LEDGER_BASE, LEDGER_PER_STEP = 1e-12, 2.2e-16


def ledger_error(rows, times, h: float) -> float:
    """Largest |W_input - E_kinetic - E_strain - W_friction - W_numerical| over its allowance
    (1e-12 + 2.2e-16 n) x the largest work or energy of the run, n the internal steps taken
    by ``times`` [s] (steps of ``h`` [s])."""
    balance = ledger_residual({name: _column(rows, name) for name in COLUMN})
    return relative_error(balance / _relative_allowance(times, h), 0.0, _largest_work(rows))


def _relative_allowance(times, h: float):
    """(1e-12 + 2.2e-16 n) [1], n the internal steps of ``h`` [s] taken by ``times`` [s]."""
    return LEDGER_BASE + LEDGER_PER_STEP * np.floor(np.asarray(times) / h + 1e-6)


def ledger_roundoff(rows, times, h: float):
    """The ledger's allowance at ``times`` [s] in joules: (1e-12 + 2.2e-16 n) x the largest
    work or energy of the run, n the internal steps of ``h`` [s] taken (0 without times)."""
    if times is None or h <= 0.0:
        return 0.0
    return _relative_allowance(times, h) * _largest_work(rows)


def energy_violations(rows, m_ram: float = 0.0, times=None, h: float = 0.0) -> float:
    """Points where a term of the ledger is negative (the cushion's loss below the ledger's
    round-off at ``times``, :func:`ledger_roundoff`), the cushion's loss falls by more than
    that round-off (a strike or a separation never lowers it: :mod:`pipeplug.elastic.head`),
    W_numerical is
    not 0, the friction work exceeds the work put in (force and ram) by more than that
    round-off, an output is not
    finite, or the model claims rest while pipe or plug move or anything but a ram of
    ``m_ram`` [kg] holds kinetic energy."""
    c = COLUMN
    bad = ~np.all(np.isfinite(rows), axis=1)
    # W_cushion is the work on the cushion less what it holds: 0 on its lines, to the ledger's
    # round-off (``times`` [s] at steps of ``h`` [s] give the steps taken)
    roundoff = ledger_roundoff(rows, times, h)
    for name in LEDGER_TERMS:
        floor = -roundoff if name == "W_cushion" else 0.0
        bad |= _column(rows, name) < floor
    # a loss: never falls, at strikes and separations included (pipeplug.elastic.head)
    bad |= np.diff(_column(rows, "W_cushion"), prepend=0.0) < -roundoff
    bad |= _column(rows, "W_numerical") != 0.0
    # soil taken in at rest never gives energy back
    bad |= np.diff(_column(rows, "W_accretion"), prepend=0.0) < 0.0
    # The scheme creates no energy. From the ledger: W_input + W_ram = the stored energies +
    # every loss + residual, every term >= 0 (the cushion's to round-off) and |residual| <=
    # roundoff, so W_friction <= W_input + W_ram + roundoff. The round-off matters where pushes
    # and pulls cancel: W_input a few ulps below 0 with the bodies at rest and no friction work.
    bad |= (_column(rows, "W_friction")
            > _column(rows, "W_input") + _column(rows, "W_ram") + roundoff)
    resting = rows[:, c["at_rest"]] != 0.0
    # At rest only a ram flying off the head may still move (its energy is all E_kinetic).
    v_ram = _column(rows, "v_ram")
    bad |= resting & ((_column(rows, "v_pipe") != 0.0) | (_column(rows, "v_plug") != 0.0)
                      | ~np.isclose(_column(rows, "E_kinetic"), 0.5 * m_ram * v_ram * v_ram,
                                    rtol=1e-12, atol=0.0))
    return float(np.count_nonzero(bad))


def bound_ratio(rows, loads, steps, body: RodBody, h: float, strikes=(), starts=()) -> float:
    """Largest |v_pipe| over a physical bound at each point: the rigid pipe's velocity under the
    impulse of |Q| so far (the bound of any mean velocity), plus a wave of 2 |Q| / Z1 for every
    change of the load so far (each piece of load sends a wave that doubles at an end, and a
    train in step with the wave's round trip piles them up) and the waves of both frictions and
    end resistances, 2 (F1 + F2 + Qf + Qp) / Z1. The impulse is counted to the next internal
    step (the model applies a step's mean force). A strike at ``v`` [m/s] (``strikes``: (time,
    v); ``starts`` [s] the start of each row's step) adds the impulse 2 m_ram |v| (the ram
    cannot leave faster than it came) and waves of 4 |v| (the head never outruns the ram: a
    wave of |v| at most, doubled at an end, and again by the ram's return). A scheme that
    diverges exceeds it by orders of magnitude; the physics of a free rod (d'Alembert) stays
    within it and can reach it (1e-9 allows for the sums' round-off)."""
    q = np.abs(loads)
    impulse = np.cumsum(q * steps) + q * h
    new_piece = np.r_[True, loads[1:] != loads[:-1]]
    waves = np.cumsum(np.where(new_piece, q, 0.0))
    struck = np.zeros(len(q))
    for t, v in strikes:
        struck[np.asarray(starts) >= t] += abs(v)
    bound = (impulse / body.M1 + 2.0 * (waves + body.F1 + body.F2 + body.F_face) / body.Z1
             + struck * (2.0 * body.m_ram / body.M1 + 4.0)) * (1.0 + 1e-9)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(bound > 0.0, np.abs(_column(rows, "v_pipe")) / bound,
                         np.where(_column(rows, "v_pipe") != 0.0, np.inf, 0.0))
    return float(np.max(ratio, initial=0.0))


def node_rule_weights(x: float, n: int, dx: float) -> dict:
    """The cells' weights [1] of the value at section ``x`` [m] of a rod of ``n`` cells of
    ``dx`` [m] by the contract's section rule: linear between the nodes x = j dx, whose values
    are the head cell's at x = 0, the mean of the two neighbouring cells at a face, the last
    cell's at x = L."""
    s = min(max(x / dx, 0.0), float(n))
    j = min(math.floor(s), n - 1)
    weights: dict = {}
    for node, share in ((j, 1.0 - (s - j)), (j + 1, s - j)):
        cells = ([0] if node <= 0 or n == 1 else [n - 1] if node >= n else [node - 1, node])
        for cell in cells:
            weights[cell] = weights.get(cell, 0.0) + share / len(cells)
    return weights


def free_rod_error(case: ElasticCase, grid, rows) -> float:
    """The free rod at Courant 1 (no friction): v_pipe and u_pipe at every point against the
    exact d'Alembert cell averages (:mod:`pipeplug_references.rods`) at the last internal step
    at or before it, combined at x_monitor by the contract's section rule
    (:func:`node_rule_weights`); u is the sum of the exact cell velocities times the internal
    step, as the scheme integrates it. Largest
    |error| over the largest |v| (|u|) of the reference and over the round-off allowance
    (1e-12 + 2.2e-16 n) of the ledger, n the internal steps so far (the scheme is exact but for
    the round-off its fields accumulate)."""
    p = case.params
    h, dx, L = internal_step(p), p["dx"], p["L1"]
    n = round(L / dx)
    weights = node_rule_weights(p["x_monitor"], n, dx)
    times = np.asarray(grid[1:], dtype=float)
    k = np.floor(times / h + 1e-6).astype(int)
    all_k = np.arange(1, k.max() + 1)
    load = Load(tuple(case.edges), tuple(case.loads))
    c, Z = math.sqrt(p["E1"] / p["rho1"]), RodBody.of(p).Z1
    v = u = 0.0
    for j, w in weights.items():
        cell = free_rod_cell_velocity(load, j * dx, (j + 1) * dx, all_k * h, L, c, Z)
        v, u = v + w * cell, u + w * np.cumsum(h * cell)
    index = np.clip(k - 1, 0, None)
    v_ref = np.where(k > 0, v[index], 0.0)
    u_ref = np.where(k > 0, u[index], 0.0)
    allowance = (LEDGER_BASE + LEDGER_PER_STEP * k) / LEDGER_BASE
    return max(relative_error((_column(rows, "v_pipe") - v_ref) / allowance, 0.0,
                              float(np.max(np.abs(v)))),
               relative_error((_column(rows, "u_pipe") - u_ref) / allowance, 0.0,
                              float(np.max(np.abs(u)))))
