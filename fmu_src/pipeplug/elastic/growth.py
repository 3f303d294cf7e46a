"""Model III with a plug that grows (``plug_growth``) and clean-outs.

The plug's front face stays at the pipe's front end. While the pipe's front cell advances
faster than the plug's (coring), soil at rest enters and joins the plug: its length grows by
the relative advance ``h max(v1 - v2, 0)`` of each internal step (of the front cells, after
their projection), up to L1 (then the pipe is plugged: nothing more enters). While the plug's
front advances with the pipe it pushes the soil ahead, and ``q_plug_face`` acts on its face as
without growth (:mod:`pipeplug.elastic.face`); so it does on a plug face that advances while
the pipe cores (the face law is that of :mod:`pipeplug.contact.face`, unchanged). When the pipe
moves back relative to the plug nothing enters and nothing leaves: the length is kept, and the
plug stays coupled at equal reference coordinate, its face at the pipe's front end. Without
plug friction (``tau2 = 0``) the soil that enters is not coupled to the pipe and stays at rest:
the length grows by the front end's advance and nothing else changes.

Discretisation. The plug is Lagrangian: its cells are soil that entered, in order, the front
one at the pipe's front cell, cell k behind it at pipe cell ``n1 - d + k`` (``d`` cells). A
length ``l`` that is not a whole number of cells is carried by the front cell, whose mass and
plug friction limit are ``(l/dx - (d - 1))`` times a full cell's (between 1 and 2 cells' worth
once ``l >= dx``, less while the first cell fills); ``d = max(floor(l/dx), 1)``. A front cell
never lighter than a full one keeps Courant <= 1 stable (it is heavier; its stiffness is a
full cell's; a lone cell has no spring). When the front cell reaches two cells' worth it splits
into two full-speed halves: the plug's cells move one pipe cell back (the soil moved back
relative to the pipe by a cell), the new face between the halves carries no force, and the
scheme's energy is unchanged. The whole plug thus slides back along the pipe as it grows, one
cell at a time (the fraction's friction acts on the front pair: O(dx), like the plug's place).

Accretion conserves momentum: in a step the front cell (mass m, velocity r before the step, x
after its projection) takes the impulse ``J = -dm y`` that brings the entering soil (mass dm,
at rest) to its velocity ``y = m x / (m + dm)``, which it then joins. The scheme pairs an
impulse with the step's mean velocity (:mod:`pipeplug.elastic.cells`), and the soil joins
with the kinetic energy ``dm y^2 / 2``: the scheme's energy changes by
``J (r + y) / 2 + dm y^2 / 2 = -dm y r / 2``, booked as ``W_accretion`` (in the limit, the
familiar ``dm v^2 / 2`` of a mass taken up at rest). A step in which the front cell's velocity
changes sign (``x r < 0``) would create energy; it takes in no soil (the relative advance of
that step is not added: in a step across a reversal of the plug's front). So W_accretion never
decreases, and the ledger ``W_input (+ W_ram) = E_kinetic + E_strain + W_friction (+ W_cushion)
+ W_face + W_accretion + W_removed`` closes to round-off as without growth.

Clean-out (:meth:`GrowthModel.clean_out`): the plug is cut to ``L2_after_cleanout`` rounded
down to whole cells (a length within 1e-9 of a cell's multiple counts as whole): the fraction
leaves from the front cell (at its velocity), whole cells from the rear (the pipe's head side,
where the spoil is taken out), and the cut face becomes the kept plug's free end. The kept
cells keep their scheme momentum through the cut (:mod:`pipeplug.elastic.cleanout` says why),
so what the scheme's energy loses, booked as ``W_removed``, is never negative: at least the
removed soil's kinetic and strain energy. A plug no longer than that is left as it is.

The kernel (:func:`run_growth`) steps every cell at every step, with or without end
resistance, soil friction, contact growth and a ram (loops only, like
:func:`pipeplug.elastic.face.run_face`; without numba it runs as plain Python).
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.face import sign
from ..jit import jitable
from .cells import (
    W2,
    accumulate,
    free_cells,
    plug_cells,
    plug_soil_cells,
    soil_cells,
    soil_weight,
)
from .cleanout import cut_rear
from .damped import (
    book_damped_step,
    damped_front_cell,
    damped_plug_cells,
    damped_plug_soil_cells,
    damped_scratch,
    damped_soil_cells,
)
from .face import book_step_friction, front_cell, soil_front, store_forces
from .grid import _section, build_grid
from .kernels import (
    C1,
    C2,
    DX,
    GROWTH,
    JS,
    K2,
    M1,
    M2,
    N_ACC,
    _finish_step,
    _scratch,
    start_step,
)
from .model import ElasticModel, _rod_energies

__all__ = ["GrowthModel", "run_growth", "run_damped_growth", "LENGTH", "CELLS", "W_ACCRETION", "W_REMOVED"]

# acc beyond the elastic model's: the plug's length [m], its cells d, W_accretion [J] and its
# rounding error, W_removed [J] and its rounding error.
LENGTH, CELLS = N_ACC, N_ACC + 1
W_ACCRETION, W_ACCRETION_ERROR = N_ACC + 2, N_ACC + 3
W_REMOVED, W_REMOVED_ERROR = N_ACC + 4, N_ACC + 5
N_ACC_GROWTH = N_ACC + 6
#: a length within this share of a cell of a whole number of cells is that number
_WHOLE = 1e-9


@jitable
def front_share(length, cells, dx):
    """The front cell's mass and plug friction limit in full cells: ``length / dx - (cells -
    1)`` for ``cells >= 1`` cells of a plug ``length`` [m] long (module docstring)."""
    return length / dx - (cells - 1.0)


@jitable
def accrete(v1, v2, acc, coef, dt, r2, w2, coupled):
    """Soil at rest joins the plug after a step's projection (module docstring): grow the
    length, give the front cell its momentum-conserving velocity, book W_accretion. ``r2``,
    ``w2`` [m/s]: the front plug cell's velocity before the step and after its kick;
    ``coupled``: the plug is simulated (tau2 > 0), else only the length grows."""
    n1 = v1.shape[0]
    front = n1 - 1
    length = acc[LENGTH]
    room = n1 * coef[DX] - length
    if not room > 0.0:
        return
    d = int(acc[CELLS])
    x1 = v1[front]
    if d == 0:
        ds = min(dt * max(x1, 0.0), room)
        if ds > 0.0:
            acc[LENGTH] = length + ds
            if coupled:               # the first cell: soil at rest, no energy changes
                acc[CELLS] = 1.0
        return
    x2 = v2[front]
    ds = min(dt * max(x1 - x2, 0.0), room)
    if not ds > 0.0:
        return
    grown = length + ds
    m_old = coef[M2] * front_share(length, d, coef[DX])
    m_new = coef[M2] * front_share(grown, d, coef[DX])
    y = x2 * (m_old / m_new)
    # the scheme's energy loses dm y r / 2, and the projection's impulses on the cell, now
    # paired with y instead of x, give back their share: what the soil takes
    work = 0.5 * (m_new - m_old) * y * (r2 + (x2 - w2))
    if work < 0.0:                    # it would create energy: no soil this step
        return
    v2[front] = y
    acc[LENGTH] = grown
    accumulate(acc, W_ACCRETION, W_ACCRETION_ERROR, work)


@jitable
def split(v2, N2, u2, acc, dx):
    """Split the front cell while it holds two cells' worth: the plug's cells move one pipe
    cell back, the halves keep the front cell's velocity and displacement, the face between
    them carries no force (the scheme's energy is unchanged)."""
    n1 = v2.shape[0]
    d = int(acc[CELLS])
    while 1 <= d < n1 and acc[LENGTH] / dx >= d + 1.0 - _WHOLE:
        j0 = n1 - d
        for k in range(j0 - 1, n1 - 1):
            v2[k] = v2[k + 1]
            u2[k] = u2[k + 1]
        for f in range(j0 - 1, n1):
            N2[f] = N2[f + 1]
        N2[n1] = 0.0
        d += 1
    acc[CELLS] = d


@jitable
def plug_front(acc, coef, own, n1):
    """The plug now: ``(d, j0)``, its cells and its first pipe cell; ``own`` gets the front
    pair's plug mass and friction limit (its share of a cell, :func:`front_share`)."""
    d = int(acc[CELLS])
    if d > 0:
        share = front_share(acc[LENGTH], d, coef[DX])
        own[M2] = coef[M2] * share
        own[C2] = coef[C2] * share
    return d, n1 - d


@jitable
def end_growth_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, j0, r2,
                    w2, coupled):
    """After a step's projection: soil enters (:func:`accrete`; ``r2``, ``w2`` [m/s] the front
    plug cell's velocity before the step and after its kick), the step's fields and
    displacements are finished, and a front cell of two cells' worth splits."""
    n1 = v1.shape[0]
    accrete(v1, v2, acc, coef, dt, r2, w2, coupled)
    _finish_step(q, dt, v_old, v1, N1, v2[j0:], N2[j0:], coef, cells1, u1, cells2, u2, acc, n1)
    for k in range(j0, n1):
        u2[k] += dt * v2[k]
    split(v2, N2, u2, acc, coef[DX])


@jitable
def step_constants(dt, coef):
    """``(a1, a2, c1, soil, growth, coupled)`` of a growing plug's kernel call: the cells'
    kicks per unit force [m/(N s)], the shaft's impulse limit per cell [N s], and whether soil
    friction, contact growth and the plug's coupling act."""
    a2 = dt / coef[M2] if coef[M2] > 0.0 else 0.0
    return (dt / coef[M1], a2, dt * coef[C1], coef[C1] > 0.0, coef[GROWTH] > 0.0,
            coef[C2] > 0.0)


@jitable
def run_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe and a growing plug (soil friction, contact growth, end resistance, ram: as
    ``coef`` has them): every cell at every step. ``v2``, ``N2``, ``u2`` hold a pipe's length
    of plug cells, the plug in the last ``acc[CELLS]`` of them (module docstring)."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    front = n1 - 1
    a1, a2, c1, soil, growth, coupled = step_constants(dt, coef)
    s = _scratch(v1)
    own = coef.copy()                 # the front pair's: its plug cell's mass and limit
    j0 = last_both = n1
    for _ in range(n):
        d, j0 = plug_front(acc, coef, own, n1)
        pv = v2[j0:]
        pN = N2[j0:]
        start, on = soil_front(u1, n1, coef, growth)
        v_old = v1[0]
        alone = min(j0, front)
        if soil:
            soil_cells(v1, N1, 0, alone, a1, coef[M1], c1, start, s)
        else:
            free_cells(v1, N1, 0, alone, a1)
        both = front
        if d > 1 and soil:
            both = j0 + plug_soil_cells(v1, N1, pv, pN, j0, front, a1, a2, coef[M1], coef[M2],
                                        c1, dt * coef[C2], start, s)
        elif d > 1:
            plug_cells(v1, N1, pv, pN, j0, 0, d - 1, a1, a2, coef[M1], coef[M2],
                       dt * coef[C2], s)
        r2 = v2[front]
        front_cell(v1, N1, pv, pN, dt, own, c1 * soil_weight(front, start), on, s, acc)
        book_step_friction(v1, pv, j0, s, alone, both, front, n1, soil, acc)
        end_growth_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, j0,
                        r2, s[W2, front] if d > 0 else 0.0, coupled)
        last_both = both
    store_forces(s, acc, j0, last_both, n1, dt, soil)


@jitable
def run_damped_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """:func:`run_growth` with Smith damping: the cells take their damped contacts
    (:mod:`pipeplug.elastic.damped`), the step's works are booked with the dampers' parts,
    and soil enters as without damping (its momentum and W_accretion from the front plug
    cell's velocities, whatever impulses the projection gave it)."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    front = n1 - 1
    a1, a2, c1, soil, growth, coupled = step_constants(dt, coef)
    c2 = dt * coef[C2]
    js = coef[JS]
    s = damped_scratch(v1)
    own = coef.copy()                 # the front pair's: its plug cell's mass and limit
    j0 = last_both = n1
    for _ in range(n):
        d, j0 = plug_front(acc, coef, own, n1)
        pv = v2[j0:]
        pN = N2[j0:]
        start, on = soil_front(u1, n1, coef, growth)
        v_old = v1[0]
        alone = min(j0, front)
        if soil:
            damped_soil_cells(v1, N1, 0, alone, a1, coef[M1], c1, js, start, s)
        else:
            free_cells(v1, N1, 0, alone, a1)
        both = front
        if d > 1 and soil:
            both = j0 + damped_plug_soil_cells(v1, N1, pv, pN, j0, front, a1, a2, coef[M1],
                                               coef[M2], c1, c2, js, start, s)
        elif d > 1:
            damped_plug_cells(v1, N1, pv, pN, j0, 0, d - 1, a1, a2, coef[M1], coef[M2], c2,
                              js * c2, s)
        r2 = v2[front]
        damped_front_cell(v1, N1, pv, pN, dt, own, c1 * soil_weight(front, start), on, s, acc)
        book_damped_step(v1, pv, j0, s, alone, both, front, n1, soil, acc)
        end_growth_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, j0,
                        r2, s[W2, front] if d > 0 else 0.0, coupled)
        last_both = both
    store_forces(s, acc, j0, last_both, n1, dt, soil)


class GrowthModel(ElasticModel):
    """Model III whose plug grows and is cleaned out (module docstring); the same
    parameters as :class:`~pipeplug.elastic.model.ElasticModel`, with ``plug_growth``."""

    def _build_grid(self, params, profile_points: int):
        # the plug is simulated from L2 = 0 on when it can be coupled (tau2 > 0); its fields
        # hold a pipe's length of cells, and the displacements of every plug cell are tracked
        g = build_grid(params, profile_points, plug=params.tau2 > 0.0)
        return g._replace(cells2=np.zeros(0, dtype=np.int64))

    def _choose_kernel(self, options, vectorised: bool):
        from .. import jit
        self.grid.coef[GROWTH] = float(options.contact_growth)
        kernel = run_damped_growth if self.params.has_damping else run_growth
        self.kernel_name = kernel.__name__
        return kernel if vectorised else jit.compiled(kernel)

    def __init__(self, params, options, vectorised: bool | None = None,
                 profile_points: int = 0):
        super().__init__(params, options, vectorised, profile_points)
        g = self.grid
        n2 = g.n2
        self.v2, self.N2, self.u2 = np.zeros(g.n1), np.zeros(g.n1 + 1), np.zeros(g.n1)
        acc = np.zeros(N_ACC_GROWTH)
        acc[:N_ACC] = self.acc
        acc[LENGTH], acc[CELLS] = params.L2, n2
        self.acc = acc
        self._cut = math.floor(params.L2_after_cleanout / params.dx + _WHOLE)
        if profile_points:
            self._profiler = _growth_profiles

    # the plug now ---------------------------------------------------------------------------
    def _plug(self) -> tuple[int, int]:
        """(cells d, first pipe cell j0) of the plug now."""
        d = int(self.acc[CELLS])
        return d, self.grid.n1 - d

    def _plug_section(self, x: float):
        """The section of the plug now at reference ``x`` [m] (nearest plug section), or None
        without plug cells."""
        d, j0 = self._plug()
        return _section(x - j0 * self.grid.coef[DX], d, self.grid.coef[DX]) if d else None

    def _plug_motion(self) -> tuple[float, float]:
        s = self._plug_section(self.params.x_monitor)
        if s is None:
            return 0.0, 0.0
        j0 = self._plug()[1]
        return _at(self.v2, j0, s), _at(self.u2, j0, s)

    def _plug_length(self) -> tuple[float, float, float]:
        acc = self.acc
        return (float(acc[LENGTH]), float(acc[W_ACCRETION] + acc[W_ACCRETION_ERROR]),
                float(acc[W_REMOVED] + acc[W_REMOVED_ERROR]))

    def _monitor_modes(self) -> tuple[int, int]:
        s = self._plug_section(self.params.x_monitor)
        plug_mode = 0
        if s is not None:
            j = self._plug()[1] + s.cell
            plug_mode = sign(self.v1[j] - self.v2[j])
        return sign(self.v1[self.grid.pipe.cell]), plug_mode

    def _plug_energies(self) -> tuple[float, float]:
        d, j0 = self._plug()
        if not d:
            return 0.0, 0.0
        c = self.grid.coef
        v = self.v2[j0:]
        kinetic, strain = _rod_energies(v, self.N2[j0:], c[M2], c[K2], self.clock.h)
        extra = front_share(self.acc[LENGTH], d, c[DX]) - 1.0   # the front cell's own mass
        return kinetic + 0.5 * extra * c[M2] * v[-1] * v[-1], strain

    # the input ------------------------------------------------------------------------------
    def clean_out(self) -> None:
        """Cut the plug to ``L2_after_cleanout`` rounded down to whole cells, now (module
        docstring); nothing when it is no longer. Books ``W_removed``, the scheme's energy
        before less after, never negative (:mod:`pipeplug.elastic.cleanout`).

        Raises
        ------
        RuntimeError
            Should the cut give energy to the kept plug beyond round-off (a defect).
        """
        acc, c = self.acc, self.grid.coef
        kept = self._cut * c[DX]
        if not acc[LENGTH] > kept:
            return
        before = sum(self._plug_energies())
        scale = self._energy_scale()
        d, j0 = self._plug()
        keep = min(self._cut, d)
        # the fraction leaves from the front cell at its velocity (the front cell is a full
        # one again), whole cells from the rear
        acc[LENGTH], acc[CELLS] = kept, keep
        cut = self.grid.n1 - keep
        if 0 < keep < d:
            cut_rear(self.v2[j0:], self.N2[j0:], np.full(d, c[M2]), c[K2], self.clock.h, keep)
        elif d:
            self.v2[j0:cut] = 0.0
            self.N2[j0:cut + 1] = 0.0
        self.u2[j0:cut] = 0.0
        removed = before - sum(self._plug_energies())
        if removed < -1e-12 * scale:
            raise RuntimeError(f"a clean-out gave {-removed!r} J to the kept plug")
        accumulate(acc, W_REMOVED, W_REMOVED_ERROR, max(removed, 0.0))
        self._rest = None

    def _energy_scale(self) -> float:
        """The size of the terms of the plug's energy [J] (the cells' kinetic energies and the
        faces' strain energies, no differences): the scale of its round-off."""
        d, j0 = self._plug()
        if not d:
            return 0.0
        c = self.grid.coef
        v, N = self.v2[j0:], self.N2[j0:]
        # a first cell still filling holds a share below 1: its term is a difference too
        extra = abs(front_share(self.acc[LENGTH], d, c[DX]) - 1.0)
        return float(0.5 * c[M2] * (v @ v + extra * v[-1] * v[-1]) + N @ N / (2.0 * c[K2]))


def _growth_profiles(model: GrowthModel) -> tuple:
    """The profiles of :func:`pipeplug.elastic.model._profiles`, the plug's over the plug
    now (its sections L1 - l + k l / (n - 1), l the length now)."""
    from ..interface import profile_sections
    from .model import _profiles
    v, u, stress, _ = _profiles(model)
    n = len(model.grid.profile)
    plug = np.zeros(n)
    if model._plug()[0]:
        length = float(model.acc[LENGTH])
        xs = profile_sections(model.params.L1, length, n)[1]
        plug = np.array([_plug_at(model, float(x)) for x in xs])
    return v, u, stress, plug


def _plug_at(model: GrowthModel, x: float) -> float:
    """The plug's velocity [m/s] at its section nearest reference ``x`` [m]."""
    s = model._plug_section(x)
    j0 = model._plug()[1]
    return _at(model.v2, j0, s)


def _at(values: np.ndarray, j0: int, s) -> float:
    """The value at section ``s`` of a plug whose cells start at index ``j0`` of ``values``."""
    return float(sum(w * values[j0 + c] for c, w in zip(s.cells, s.weights)))

