"""The grid of the elastic model: cells, constants, monitored sections, internal step.

The pipe occupies reference x in [0, L1] and is cut into ``n1 = L1/dx`` cells; the plug occupies
[L1 - L2, L1] and is cut into ``n2 = L2/dx`` cells, so that plug cell ``k`` and pipe cell
``n1 - n2 + k`` cover the same reference section (the coupling at equal reference coordinate).
Every cell carries the full mass ``rho S dx`` and the friction of its length ``dx``.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..interface import profile_sections
from ..params import ParameterError
from .head import stable_cushion
from .kernels import (
    C1,
    C2,
    DX,
    JF,
    JS,
    K1,
    K2,
    K_LOAD,
    K_UNLOAD,
    M1,
    M2,
    N_COEF,
    QF,
    QP,
    RAM_MASS,
)

__all__ = ["Section", "Grid", "build_grid", "cell_count"]

_WHOLE = 1e-9  # relative tolerance of "a whole number of cells"


class Section(NamedTuple):
    """A section of a rod: value = sum of ``weights[i] f[cells[i]]`` over three cells.

    The values a rod reports lie on its nodes, linearly between them (:func:`_section`)."""

    cells: tuple      #: three cell indices (a repeated one with weight 0 where fewer count)
    weights: tuple    #: their weights [1], summing to 1
    cell: int         #: the cell containing the section (the node whose modes are reported)


class Grid(NamedTuple):
    """Everything the elastic model derives once from the parameters."""

    n1: int              #: pipe cells
    n2: int              #: plug cells (0: no plug simulated)
    soil: bool           #: soil friction simulated (tau1 > 0)
    coef: np.ndarray     #: kernel constants (see pipeplug.elastic.kernels)
    h_max: float         #: largest internal step courant*dx/c_fastest [s]
    pipe: Section        #: monitored pipe section
    plug: Section        #: monitored plug section (cells of the plug)
    cells1: np.ndarray   #: tracked pipe cells: [front, *pipe.cells, *each profile section's]
    cells2: np.ndarray   #: tracked plug cells: plug.cells, or empty
    profile: tuple       #: pipe sections of the profiles (their cells tracked after the 3 above)
    profile_plug: tuple  #: plug sections of the profiles (empty without a plug)


def cell_count(length: float, dx: float) -> int:
    """Number of cells of ``length`` [m], which must be a whole multiple of ``dx`` [m]."""
    ratio = length / dx
    count = round(ratio)
    if abs(ratio - count) > _WHOLE * max(1.0, ratio):
        raise ParameterError("dx", dx, "L1 and L2 must be whole multiples of dx")
    return int(count)


def _node_weights(j: int, n: int) -> dict:
    """The cells' weights of node ``j`` (x = j dx) of a rod of ``n`` cells: the head's cell at
    x = 0, the far end's at x = L, the mean of the two cells at every face between.

    Why not the cells themselves: at Courant 1 their velocities carry an odd-even pattern of
    +-f x / (2 Z) (f the friction per metre, Z the impedance) that does not shrink with dx,
    the same as the faces' forces (:func:`pipeplug.elastic.cells.node_forces`, docs/elastic.md,
    root cause 8); the mean of two neighbouring cells does not carry it."""
    if j <= 0 or n == 1:
        return {0: 1.0}
    if j >= n:
        return {n - 1: 1.0}
    return {j - 1: 0.5, j: 0.5}


def _section(x: float, n: int, dx: float) -> Section:
    """The section at ``x`` [m] from a rod's rear end (nearest inside the rod if beyond it):
    linear between the nodes (:func:`_node_weights`) at ``floor(x/dx) dx`` and the next."""
    s = min(max(x / dx, 0.0), float(n))       # in node units, clamped to the rod
    j = min(int(math.floor(s)), n - 1)
    w = s - j
    weights: dict = {}
    for node, share in ((j, 1.0 - w), (j + 1, w)):
        for k, c in _node_weights(node, n).items():
            weights[k] = weights.get(k, 0.0) + share * c
    cells = sorted(weights)
    cells += [cells[-1]] * (3 - len(cells))
    shares = [weights[k] for k in cells[:len(weights)]] + [0.0] * (3 - len(weights))
    cell = min(max(int(math.floor(x / dx + _WHOLE)), 0), n - 1)
    return Section(tuple(cells), tuple(shares), cell)


def build_grid(params, profile_points: int = 0, plug: bool | None = None) -> Grid:
    """Derive the grid from validated parameters (raises ParameterError for a bad ``dx``), with
    the sections of ``profile_points`` profile points (0: none; their displacements are tracked
    like the monitored section's, so element k equals the output with x_monitor = x_k).
    ``plug`` says whether the plug is simulated (default: ``params.has_plug``; a plug that
    grows is simulated from L2 = 0 on, :mod:`pipeplug.elastic.growth`)."""
    p = params
    dx = p.dx
    n1 = cell_count(p.L1, dx)
    simulated = p.has_plug if plug is None else plug
    n2 = cell_count(p.L2, dx) if simulated else 0
    coef = np.zeros(N_COEF)
    coef[M1], coef[K1] = p.rho1 * p.S1 * dx, p.E1 * p.S1 / dx
    coef[C1], coef[DX] = p.P1 * p.tau1 * dx, dx
    speed = p.c1
    if simulated:
        coef[M2], coef[K2], coef[C2] = p.rho2 * p.S2 * dx, p.E2 * p.S2 / dx, p.P2 * p.tau2 * dx
        speed = max(speed, p.c2)
    coef[QF], coef[QP] = p.F_face, (p.F_plug_face if simulated else 0.0)
    coef[JS], coef[JF] = p.J_shaft, p.J_face
    h_max = p.courant * dx / speed
    if p.has_ram:
        _ram_coefficients(p, coef, h_max)
    pipe = _section(p.x_monitor, n1, dx)
    plug = (_section(p.x_monitor - (p.L1 - p.L2), n2, dx) if n2
            else Section((0, 0, 0), (1.0, 0.0, 0.0), 0))
    profile = profile_plug = ()
    if profile_points:
        xs, xs_plug = profile_sections(p.L1, p.L2, profile_points)
        profile = tuple(_section(float(x), n1, dx) for x in xs)
        if n2:
            profile_plug = tuple(_section(float(x) - (p.L1 - p.L2), n2, dx) for x in xs_plug)
    cells1 = np.array([n1 - 1, *pipe.cells, *(c for s in profile for c in s.cells)],
                      dtype=np.int64)
    cells2 = np.array(plug.cells if n2 else [], dtype=np.int64)
    return Grid(n1, n2, p.tau1 > 0.0, coef, h_max, pipe, plug, cells1, cells2, profile,
                profile_plug)


def _ram_coefficients(p, coef, h_max: float) -> None:
    """The ram's mass and its cushion's stiffnesses (:mod:`pipeplug.elastic.head`: a direct
    strike unloads with one cell's stiffness), refused when the internal step cannot carry them
    stably (naming what to change)."""
    e2 = p.cushion_restitution ** 2
    load = p.cushion_stiffness if p.cushion_stiffness > 0.0 else e2 * coef[K1]
    unload = load / e2
    largest = stable_cushion(unload, p.ram_mass, coef[M1], coef[K1], h_max)
    # a direct strike at Courant 1 sits exactly on the bound (the head cell is then like any
    # interior cell); the margin keeps round-off of the two sides from refusing it
    if not unload <= largest * (1.0 + 1e-12):
        if p.cushion_stiffness > 0.0:
            raise ParameterError("cushion_stiffness", p.cushion_stiffness,
                                 f"at most {largest * e2:.6g} N/m with this ram, restitution "
                                 f"and dx (its unloading stiffness / e^2 must stay below the "
                                 f"internal step's limit; a finer dx allows more)")
        raise ParameterError("ram_mass", p.ram_mass,
                             f">= {unload / (2.0 / h_max ** 2):.6g} kg for a direct strike with "
                             f"this dx (half a cell's mass; a finer dx allows lighter rams)")
    coef[RAM_MASS], coef[K_LOAD], coef[K_UNLOAD] = p.ram_mass, load, unload
