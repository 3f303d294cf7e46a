"""The time loops of the elastic model: one kernel per combination of enabled effects.

Every kernel advances the rods by ``n`` internal steps of length ``dt`` [s] under a constant
struck-end force ``q`` [N] (see :mod:`pipeplug.elastic.cells` for one step). The model picks
its kernel once, when it is built (:data:`KERNELS`): a switched-off effect is absent from the
loop, not skipped by an ``if`` in it. All kernels take the same arguments::

    kernel(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc)

``coef`` holds the constants (indices below), ``v1``/``N1`` and ``v2``/``N2`` the pipe and plug
fields (without a plug ``v2`` is empty and ``N2`` one unused face), ``u1``/``u2`` the
displacements [m] of the tracked cells ``cells1``/``cells2`` (``cells1[0]`` is the pipe's front
cell), and ``acc`` the accumulated works (compensated sums) and the last step's friction forces
(indices below).

The loops with soil friction step only the pipe cells before an ``end`` (and the plug cells
coupled to them): the cells beyond are at rest and would repeat their last step
(:func:`pipeplug.elastic.cells.next_end`), which the last step of a call takes in full for its
impulse sums. The results are those of stepping every cell, bit for bit: it saves the work of the
part of the rods that static friction holds in the soil while the rest rings.

These loops are meant to be compiled (:func:`pipeplug.jit.compiled`). Without numba the model
uses :mod:`pipeplug.elastic.vectorised` instead: the same variants as whole-array numpy steps,
with the same results bit for bit.
"""
from __future__ import annotations

import numpy as np

from ..jit import jitable
from .cells import (
    D1,
    D2,
    F1,
    F2,
    SCRATCH_ROWS,
    accumulate,
    drift,
    drift_extremes,
    extremes,
    free_cells,
    limit,
    moving_end,
    next_end,
    node_extremes,
    plug_cells,
    plug_soil_cells,
    soil_cells,
    soil_start,
    sums,
    track,
)
from .head import ram_step

__all__ = ["KERNELS"]

# coef: cell mass [kg] and cell stiffness E S / dx [N/m] of pipe and plug, friction limits
# per full cell P tau dx [N] of the soil and plug contacts, grid step [m]; the ram's mass [kg]
# (0: no ram) and its cushion's loading and unloading stiffness [N/m].
M1, K1, M2, K2, C1, C2, DX, RAM_MASS, K_LOAD, K_UNLOAD = range(10)
# End resistance (:mod:`pipeplug.elastic.face`): Qf = q_face S1 and Qp = q_plug_face S2 [N] (0
# without a plug), and 1.0 with contact growth (the annulus meets the soil from U >= 0 on).
QF, QP, GROWTH = range(10, 13)
# Smith damping (:mod:`pipeplug.elastic.damped`): J_shaft and J_face [s/m].
JS, JF = 13, 14
N_COEF = 15
# acc: W_input [J], friction work at the soil and at the plug contact [J] (each the sum of
# acc[i] and its rounding error acc[i + COMPENSATION]); the last step's soil and plug friction
# forces on the pipe along +x [N]; the number of steps that took back a share of a projection
# (pipeplug.elastic.cells.limit).
W_IN, W_OUTER, W_INNER, F_OUT, F_IN = range(5)
COMPENSATION = 5
LIMITED = 8
# With a ram (coef[RAM_MASS] > 0): the work done on the cushion [J] (less the negative
# recoverable energy a strike in a step of pull leaves to W_RAM, pipeplug.elastic.head) and its
# rounding error; the ram's state from RAM (pipeplug.elastic.head.ram_step: velocity, compression, largest
# compression, force, transferred work and its error). Every model: the smallest and largest
# node-centred axial force [N] of the pipe (pipeplug.elastic.cells.node_forces) during the
# current communication step.
W_CUSHION, W_CUSHION_ERROR = 9, 10
RAM = 11
N_MIN, N_MAX = 17, 18
W_RAM = 19                # the energy strikes brought [J] (pipeplug.elastic.model.strike)
W_FACE, W_FACE_ERROR = 20, 21   # work against the end resistance [J] and its rounding error
W_DAMPING, W_DAMPING_ERROR = 22, 23   # work of the Smith dampers [J] and its rounding error
N_ACC = 24


@jitable
def start_step(q, N1, coef, acc):
    """The head force of a call's first step, ``-(q + F)`` with the cushion's force ``F`` (0
    without a ram), written ``0 - ...`` for +0.0 under no load, as a fresh model holds it;
    and the pipe's node-centred axial forces now counted in the extremes of the communication
    step."""
    N1[0] = 0.0 - (q + acc[RAM + 3]) if coef[RAM_MASS] > 0.0 else 0.0 - q
    acc[N_MIN], acc[N_MAX] = extremes(N1, acc[N_MIN], acc[N_MAX])


@jitable
def _finish_step(q, dt, v_first_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end):
    """Add the input work of the step [J]; then drift the forces of the pipe cells before
    ``end`` and of the plug cells coupled to them, the displacements, and the ram with its
    cushion (one branch per step, none per cell); then count the pipe's node-centred forces
    that changed (the head's and those of the cells up to ``end``) in the extremes."""
    _add_work(acc, W_IN, 0.5 * q * dt * (v_first_old + v1[0]))
    acc[N_MIN], acc[N_MAX] = drift_extremes(v1, N1, coef[K1] * dt, end, acc[N_MIN], acc[N_MAX])
    drift(v2, N2, coef[K2] * dt, end - (v1.shape[0] - v2.shape[0]))
    track(u1, cells1, v1, dt)
    track(u2, cells2, v2, dt)
    if coef[RAM_MASS] > 0.0:
        finish_ram(q, dt, v_first_old, v1[0], N1, coef, acc)
    acc[N_MIN], acc[N_MAX] = node_extremes(N1, 1, acc[N_MIN], acc[N_MAX])


@jitable
def finish_ram(q, dt, v_head_old, v_head, N1, coef, acc):
    """The ram and its cushion after the pipe's step (:func:`pipeplug.elastic.head.ram_step`;
    the head cell's velocity went from ``v_head_old`` to ``v_head`` [m/s]): the head force of
    the next step."""
    head = ram_step(q, dt, v_head_old, v_head, coef[RAM_MASS], coef[K_LOAD],
                    coef[K_UNLOAD], acc[RAM:RAM + 6], acc, W_CUSHION, W_CUSHION_ERROR)
    N1[0] = 0.0 - head


@jitable
def _add_work(acc, index, work):
    """Add a step's work [J] to the compensated sum ``acc[index]`` (W_IN, W_OUTER or W_INNER)."""
    accumulate(acc, index, index + COMPENSATION, work)


@jitable
def _book_friction(acc, outer, inner):
    """Add a step's friction works at the soil and the plug [J]: each >= 0 but for round-off
    (after :func:`pipeplug.elastic.cells.limit`), which is dropped."""
    _add_work(acc, W_OUTER, max(outer, 0.0))
    _add_work(acc, W_INNER, max(inner, 0.0))


@jitable
def _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start, end, s):
    """One step of the pipe cells before ``end`` on the soil (scratch ``s``)."""
    v_old = v1[0]
    soil_cells(v1, N1, 0, end, dt / coef[M1], coef[M1], dt * coef[C1], start, s)
    outer = sums(s, D1, 0, end)
    if outer < 0.0:
        limit(v1, v2, 0, s, 0, end, 0, 0, 0, 0)
        outer = sums(s, D1, 0, end)
        acc[LIMITED] += 1.0
    _book_friction(acc, outer, 0.0)
    _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end)


@jitable
def _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start, end, s):
    """One step of the pipe cells before ``end``, the plug cells coupled to them and the soil
    (scratch ``s``)."""
    v_old = v1[0]
    j0 = v1.shape[0] - v2.shape[0]
    a1 = dt / coef[M1]
    c1 = dt * coef[C1]
    alone = min(j0, end)
    soil_cells(v1, N1, 0, alone, a1, coef[M1], c1, start, s)
    both = j0 + plug_soil_cells(v1, N1, v2, N2, j0, end, a1, dt / coef[M2], coef[M1],
                                coef[M2], c1, dt * coef[C2], start, s)
    outer = sums(s, D1, 0, alone) + sums(s, D1, both, end)
    inner = sums(s, D2, j0, end)
    if outer < 0.0 or inner < 0.0:
        limit(v1, v2, j0, s, 0, alone, j0, both, both, end)
        outer = sums(s, D1, 0, alone) + sums(s, D1, both, end)
        inner = sums(s, D2, j0, end)
        acc[LIMITED] += 1.0
    _book_friction(acc, outer, inner)
    _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end)
    return both


@jitable
def run_pipe(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe alone, no friction."""
    start_step(q, N1, coef, acc)
    for _ in range(n):
        v_old = v1[0]
        free_cells(v1, N1, 0, v1.shape[0], dt / coef[M1])
        _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc,
                     v1.shape[0])
    acc[F_OUT] = 0.0
    acc[F_IN] = 0.0


@jitable
def run_pipe_soil(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe on the soil over its whole length."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    end = moved = n1
    s = _scratch(v1)
    for i in range(n):
        _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, 0.0, end, s)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = sums(s, F1, 0, n1) / dt
    acc[F_IN] = 0.0


@jitable
def run_pipe_soil_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe on the soil over the penetrated length."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    end = moved = n1
    s = _scratch(v1)
    for i in range(n):
        start = soil_start(u1[0], n1, coef[DX])
        _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start, end, s)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = sums(s, F1, 0, n1) / dt
    acc[F_IN] = 0.0


@jitable
def run_pipe_plug(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe and plug, no soil friction."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    j0 = n1 - v2.shape[0]
    s = _scratch(v1)
    for _ in range(n):
        v_old = v1[0]
        free_cells(v1, N1, 0, j0, dt / coef[M1])
        plug_cells(v1, N1, v2, N2, j0, 0, v2.shape[0], dt / coef[M1], dt / coef[M2], coef[M1],
                   coef[M2], dt * coef[C2], s)
        inner = sums(s, D2, j0, n1)
        if inner < 0.0:
            limit(v1, v2, j0, s, 0, 0, j0, n1, 0, 0)
            inner = sums(s, D2, j0, n1)
            acc[LIMITED] += 1.0
        _book_friction(acc, 0.0, inner)
        _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, n1)
    acc[F_OUT] = 0.0
    acc[F_IN] = sums(s, F2, j0, n1) / dt


@jitable
def run_pipe_plug_soil(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe, plug and soil over the whole pipe length."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    end = moved = both = n1
    s = _scratch(v1)
    for i in range(n):
        both = _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, 0.0,
                               end, s)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    _last_forces(acc, s, n1 - v2.shape[0], both, n1, dt)


@jitable
def run_pipe_plug_soil_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe, plug and soil over the penetrated length."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    end = moved = both = n1
    s = _scratch(v1)
    for i in range(n):
        start = soil_start(u1[0], n1, coef[DX])
        both = _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start,
                               end, s)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    _last_forces(acc, s, n1 - v2.shape[0], both, n1, dt)


@jitable
def _last_forces(acc, s, j0, both, n1, dt):
    """The soil's and the plug's friction forces on the pipe in the last step (every cell) [N],
    from the scratch ``s``: soil on the cells alone (before ``j0``) and on those touching both
    (from ``both``), plug on the coupled cells."""
    acc[F_OUT] = (sums(s, F1, 0, j0) + sums(s, F1, both, n1)) / dt
    acc[F_IN] = sums(s, F2, j0, n1) / dt


@jitable
def _scratch(v1):
    """The scratch of a kernel call (:data:`pipeplug.elastic.cells.SCRATCH_ROWS` rows, a column
    per pipe cell): written by every step before it is read."""
    return np.zeros((SCRATCH_ROWS, v1.shape[0]))


@jitable
def _next(v1, v2, n1, end, moved_before, last):
    """The cells the next step takes (all if it is the ``last`` of the call, for its impulse
    sums), and where the motion ends after this one (the start of a call assumes that every
    cell moved the step before)."""
    moved = moving_end(v1, v2, n1 - v2.shape[0], end)
    return (n1 if last else next_end(moved, moved_before, n1)), moved


#: (plug, soil, growth) -> kernel
KERNELS = {
    (False, False, False): run_pipe,
    (False, False, True): run_pipe,
    (False, True, False): run_pipe_soil,
    (False, True, True): run_pipe_soil_growth,
    (True, False, False): run_pipe_plug,
    (True, False, True): run_pipe_plug,
    (True, True, False): run_pipe_plug_soil,
    (True, True, True): run_pipe_plug_soil_growth,
}
