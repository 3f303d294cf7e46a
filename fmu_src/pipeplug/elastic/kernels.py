"""The time loops of the elastic model: one kernel per combination of enabled effects.

Every kernel advances the rods by ``n`` internal steps of length ``dt`` [s] under a constant
struck-end force ``q`` [N] (see :mod:`pipeplug.elastic.cells` for one step). The model picks
its kernel once, when it is built (:data:`KERNELS`): a switched-off effect is absent from the
loop, not skipped by an ``if`` in it. All kernels take the same arguments::

    kernel(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc)

``coef`` holds the constants (indices below), ``v1``/``N1`` and ``v2``/``N2`` the pipe and plug
fields (without a plug ``v2`` is empty and ``N2`` one unused face), ``u1``/``u2`` the displacements [m] of the
tracked cells ``cells1``/``cells2`` (``cells1[0]`` is the pipe's front cell), and ``acc`` the
accumulated works and the last step's friction forces (indices below).

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
    drift,
    free_cells,
    moving_end,
    next_end,
    plug_cells,
    plug_soil_cells,
    soil_cells,
    soil_start,
    track,
)

__all__ = ["KERNELS"]

# coef: cell mass [kg] and cell stiffness E S / dx [N/m] of pipe and plug, friction limits
# per full cell P tau dx [N] of the soil and plug contacts, grid step [m].
M1, K1, M2, K2, C1, C2, DX = range(7)
N_COEF = 7
# acc: W_input [J], friction work dissipated at the soil and at the plug contact [J],
# negative friction work of reversing steps [J], last step's soil and plug friction forces on
# the pipe along +x [N].
W_IN, W_OUTER, W_INNER, W_NEG, F_OUT, F_IN = range(6)
N_ACC = 6


@jitable
def _finish_step(q, dt, v_first_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end):
    """Add the input work of the step [J]; then drift the forces of the pipe cells before
    ``end`` and of the plug cells coupled to them, and the displacements."""
    acc[W_IN] += 0.5 * q * dt * (v_first_old + v1[0])
    drift(v1, N1, coef[K1] * dt, end)
    drift(v2, N2, coef[K2] * dt, end - (v1.shape[0] - v2.shape[0]))
    track(u1, cells1, v1, dt)
    track(u2, cells2, v2, dt)


@jitable
def _add_work(acc, contact, work, w_neg):
    """Accumulate the friction work of a step at ``contact`` (W_OUTER or W_INNER): dissipated
    [J] and reversing part [J]."""
    acc[contact] += work
    acc[W_NEG] += w_neg


@jitable
def _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start, end,
               scratch):
    """One step of the pipe cells before ``end`` on the soil (``scratch`` for
    :func:`pipeplug.elastic.cells.soil_cells`); returns the soil's impulse on them [N s]."""
    v_old = v1[0]
    outer, work, w_neg = soil_cells(v1, N1, 0, end, dt / coef[M1], coef[M1], dt * coef[C1],
                                    start, scratch)
    _add_work(acc, W_OUTER, work, w_neg)
    _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end)
    return outer


@jitable
def _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start, end,
                    scratch):
    """One step of the pipe cells before ``end``, the plug cells coupled to them and the soil
    (``scratch`` for :func:`pipeplug.elastic.cells.plug_soil_cells`); returns the soil's and
    plug's impulses on them [N s]."""
    v_old = v1[0]
    j0 = v1.shape[0] - v2.shape[0]
    a1 = dt / coef[M1]
    c1 = dt * coef[C1]
    outer, work, w_neg = soil_cells(v1, N1, 0, min(j0, end), a1, coef[M1], c1, start,
                                    scratch)
    _add_work(acc, W_OUTER, work, w_neg)
    outer2, inner, work_outer, work_inner, w_neg = plug_soil_cells(
        v1, N1, v2, N2, j0, end, a1, dt / coef[M2], coef[M1], coef[M2], c1, dt * coef[C2],
        start, scratch)
    _add_work(acc, W_OUTER, work_outer, 0.0)
    _add_work(acc, W_INNER, work_inner, w_neg)
    _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, end)
    return outer + outer2, inner


@jitable
def run_pipe(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe alone, no friction."""
    N1[0] = -q
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
    N1[0] = -q
    n1 = v1.shape[0]
    outer = 0.0
    end = moved = n1
    scratch = _scratch(v1)
    for i in range(n):
        outer = _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, 0.0, end,
                           scratch)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = outer / dt
    acc[F_IN] = 0.0


@jitable
def run_pipe_soil_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe on the soil over the penetrated length."""
    N1[0] = -q
    n1 = v1.shape[0]
    outer = 0.0
    end = moved = n1
    scratch = _scratch(v1)
    for i in range(n):
        start = soil_start(u1[0], n1, coef[DX])
        outer = _soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc, start,
                           end, scratch)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = outer / dt
    acc[F_IN] = 0.0


@jitable
def run_pipe_plug(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe and plug, no soil friction."""
    N1[0] = -q
    j0 = v1.shape[0] - v2.shape[0]
    inner = 0.0
    scratch = _scratch(v1)
    for _ in range(n):
        v_old = v1[0]
        free_cells(v1, N1, 0, j0, dt / coef[M1])
        inner, work, w_neg = plug_cells(v1, N1, v2, N2, j0, dt / coef[M1], dt / coef[M2],
                                        coef[M1], coef[M2], dt * coef[C2], scratch)
        _add_work(acc, W_INNER, work, w_neg)
        _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc,
                     v1.shape[0])
    acc[F_OUT] = 0.0
    acc[F_IN] = inner / dt


@jitable
def run_pipe_plug_soil(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe, plug and soil over the whole pipe length."""
    N1[0] = -q
    n1 = v1.shape[0]
    outer = inner = 0.0
    end = moved = n1
    scratch = _scratch(v1)
    for i in range(n):
        outer, inner = _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2,
                                       acc, 0.0, end, scratch)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = outer / dt
    acc[F_IN] = inner / dt


@jitable
def run_pipe_plug_soil_growth(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe, plug and soil over the penetrated length."""
    N1[0] = -q
    n1 = v1.shape[0]
    outer = inner = 0.0
    end = moved = n1
    scratch = _scratch(v1)
    for i in range(n):
        start = soil_start(u1[0], n1, coef[DX])
        outer, inner = _plug_soil_step(dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2,
                                       acc, start, end, scratch)
        end, moved = _next(v1, v2, n1, end, moved, i + 2 == n)
    acc[F_OUT] = outer / dt
    acc[F_IN] = inner / dt


@jitable
def _scratch(v1):
    """Room for the impulses and works of the cells that one call of ``soil_cells``,
    ``plug_cells`` or ``plug_soil_cells`` steps in a pass (reused by each). The pipe ``v1`` has
    the most cells (L2 <= L1): the loops do not check their bounds."""
    return np.empty((2, v1.shape[0]))


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

