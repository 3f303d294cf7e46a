"""The elastic model with end resistance: the soil at the pipe's front end and the plug's face.

The soil resists the pipe's front end (the steel annulus, x = L1) up to ``Qf = q_face S1``
while it advances, and the plug's front face (x = L1 too: the plug fills the pipe's front
part) up to ``Qp = q_plug_face S2`` (:mod:`pipeplug.contact.face`). In the scheme the end
force acts on the front cell, whose velocity stands for the end's: its projection is the joint
problem of :func:`~pipeplug.contact.face.face_contacts` (the shaft friction of the cell and
the end resistance in one asymmetric window ``[-(c1 + dt Qf), c1]``, the plug's front cell
with its inner friction and its face's window ``[-dt Qp, 0]``), like every other cell's
projection, with limits of impulses. (Model II: the annulus resists from U >= 0 on, the front
end in the soil, as in the rigid model.)

Energy: the front cell's step applies the largest share of its projection (as
:func:`pipeplug.elastic.cells.limit` does, for all its contacts at once,
:func:`~pipeplug.elastic.cells.window`) for which every one of its works, the shaft's, the
plug's friction and the two end resistances', is >= 0: W_face never decreases, and the ledger
``W_input (+ W_ram) = E_kinetic + E_strain + W_friction (+ W_cushion) + W_face`` closes to
round-off as without it. A front cell at rest, held, keeps its whole (static) impulse.

One kernel for every combination of the other effects (:func:`run_face`): it steps every cell
at every step (the kernels of :mod:`pipeplug.elastic.kernels` skip the part of the rods that is
at rest; here a cell at rest at the front need not repeat its last step). Without numba it runs
as plain Python loops (no whole-array form): correct, slow for fine grids.
"""
from __future__ import annotations

from ..contact.face import face_contacts, one_sided
from ..jit import jitable
from .cells import (
    D1,
    D2,
    F1,
    F2,
    R1,
    R2,
    W1,
    W2,
    accumulate,
    free_cells,
    limit,
    plug_cells,
    plug_soil_cells,
    soil_cells,
    soil_start,
    soil_weight,
    sums,
    window,
)
from .kernels import (
    C1,
    C2,
    DX,
    F_IN,
    F_OUT,
    GROWTH,
    LIMITED,
    M1,
    M2,
    QF,
    QP,
    W_FACE,
    W_FACE_ERROR,
    _book_friction,
    _finish_step,
    _scratch,
    start_step,
)

__all__ = ["run_face", "front_cell", "soil_front", "store_forces"]


@jitable
def _both(lo1, hi1, lo2, hi2):
    """The intersection of two windows of shares."""
    return max(lo1, lo2), min(hi1, hi2)


@jitable
def front_cell(v1, N1, v2, N2, dt, coef, c1, on, s, acc):
    """Kick and project the pipe's front cell (and the plug's, coupled to it) with the end
    resistance, apply the largest share whose works are all >= 0, write the cell's shaft and
    plug contact to the scratch ``s`` and add the end resistance's work to ``acc``.

    ``c1`` [N s]: the shaft's impulse limit on the cell; ``on``: 1.0 when the annulus meets the
    soil (model II: the front end at U >= 0), else 0.0.
    """
    j = v1.shape[0] - 1
    n2 = v2.shape[0]
    m1 = coef[M1]
    c1p = c1 + on * dt * coef[QF]
    r1 = v1[j]
    w1 = r1 + (dt / m1) * (N1[j + 1] - N1[j])
    r2 = w2 = x2 = f2 = f3 = 0.0
    if n2 > 0:
        k = n2 - 1
        r2 = v2[k]
        w2 = r2 + (dt / coef[M2]) * (N2[k + 1] - N2[k])
        x1, x2, f1, f2, f3, _, _, _ = face_contacts(m1, coef[M2], w1, w2, c1p, c1,
                                                    dt * coef[C2], dt * coef[QP], 0.0)
    else:
        x1, f1 = one_sided(m1, w1, c1p, c1, 0.0)
    shaft = max(f1, -c1)              # the shaft holds first, the annulus takes the rest
    face = f1 - shaft
    lo, hi = window(shaft, r1, w1, x1)
    lo2, hi2 = window(face, r1, w1, x1)
    lo, hi = _both(lo, hi, lo2, hi2)
    lo2, hi2 = window(f2, r1 - r2, w1 - w2, x1 - x2)
    lo, hi = _both(lo, hi, lo2, hi2)
    lo2, hi2 = window(f3, r2, w2, x2)
    lo, hi = _both(lo, hi, lo2, hi2)
    lam = hi if lo <= hi else 0.0
    if lam != 1.0:
        x1 = w1 + lam * (x1 - w1)
        x2 = w2 + lam * (x2 - w2)
        shaft, face, f2, f3 = lam * shaft, lam * face, lam * f2, lam * f3
    v1[j] = x1
    s[F1, j] = shaft
    s[D1, j] = max(-0.5 * shaft * (r1 + x1), 0.0)
    s[R1, j] = r1
    s[W1, j] = w1
    if n2 > 0:
        v2[n2 - 1] = x2
        s[F2, j] = f2
        s[D2, j] = max(-0.5 * f2 * (r1 - r2 + x1 - x2), 0.0)
        s[R2, j] = r2
        s[W2, j] = w2
    work = -0.5 * face * (r1 + x1) - 0.5 * f3 * (r2 + x2)
    accumulate(acc, W_FACE, W_FACE_ERROR, max(work, 0.0))
    if lam != 1.0:
        acc[LIMITED] += 1.0


@jitable
def book_step_friction(v1, v2, j0, s, alone, both, front, n1, soil, acc):
    """Book one step's friction works [J] in ``acc``: the soil's on the cells it holds
    (``0..alone`` alone, ``both..n1`` with the plug in the contact) and the plug's (``j0..n1``),
    from their shares in ``s``; a negative one (the step created energy) is limited first
    (:func:`pipeplug.elastic.cells.limit`) and taken again. A pair cell out of the soil's
    contact keeps a stale D1 of an earlier step, so it is not summed."""
    outer = sums(s, D1, 0, alone) + sums(s, D1, both, n1)
    inner = sums(s, D2, j0, n1)
    if outer < 0.0 or inner < 0.0:
        if soil:
            limit(v1, v2, j0, s, 0, alone, j0, both, both, front)
        else:
            limit(v1, v2, j0, s, 0, 0, j0, front, 0, 0)
        outer = sums(s, D1, 0, alone) + sums(s, D1, both, n1)
        inner = sums(s, D2, j0, n1)
        acc[LIMITED] += 1.0
    _book_friction(acc, outer, inner)


@jitable
def soil_front(u1, n1, coef, growth):
    """``(start, on)``: where the soil's contact starts along the pipe [cells] (model II), and
    1.0 when the annulus meets the soil (the front end at U >= 0), else 0.0."""
    if not growth:
        return 0.0, 1.0
    return soil_start(u1[0], n1, coef[DX]), 1.0 if u1[0] >= 0.0 else 0.0


@jitable
def store_forces(s, acc, j0, last_both, n1, dt, soil):
    """F_outer and F_inner [N] of the call's last step from the scratch ``s``."""
    front = n1 - 1
    acc[F_OUT] = (sums(s, F1, 0, min(j0, front)) + sums(s, F1, last_both, n1)) / dt \
        if soil else 0.0
    acc[F_IN] = sums(s, F2, j0, n1) / dt


@jitable
def run_face(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe (and plug, soil friction, contact growth, ram: as ``coef`` has them) with end
    resistance: every cell at every step (module docstring)."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    n2 = v2.shape[0]
    j0 = n1 - n2
    front = n1 - 1
    alone = min(j0, front)
    a1 = dt / coef[M1]
    c1 = dt * coef[C1]
    soil = coef[C1] > 0.0
    growth = coef[GROWTH] > 0.0
    s = _scratch(v1)
    last_both = front
    for _ in range(n):
        start, on = soil_front(u1, n1, coef, growth)
        v_old = v1[0]
        if soil:
            soil_cells(v1, N1, 0, alone, a1, coef[M1], c1, start, s)
        else:
            free_cells(v1, N1, 0, alone, a1)
        both = front
        if n2 > 1 and soil:
            both = j0 + plug_soil_cells(v1, N1, v2, N2, j0, front, a1, dt / coef[M2], coef[M1],
                                        coef[M2], c1, dt * coef[C2], start, s)
        elif n2 > 1:
            plug_cells(v1, N1, v2, N2, j0, 0, n2 - 1, a1, dt / coef[M2], coef[M1], coef[M2],
                       dt * coef[C2], s)
        front_cell(v1, N1, v2, N2, dt, coef, c1 * soil_weight(front, start), on, s, acc)
        book_step_friction(v1, v2, j0, s, alone, both, front, n1, soil, acc)
        _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, n1)
        last_both = both
    store_forces(s, acc, j0, last_both, n1, dt, soil)
