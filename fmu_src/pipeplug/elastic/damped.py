"""The elastic model with Smith damping: shaft friction and end resistance grown by the speed.

Smith damping (docs/physics.md, "Smith damping") makes a sliding resistance ``R`` resist with
``R (1 + J v)``, ``v`` its sliding speed: per cell the soil's shaft friction ``c1 = P1 tau1 dx``
(by the cell's velocity, ``J_shaft``), the plug's inner friction ``c2 = P2 tau2 dx`` (by the
velocity of the pipe cell relative to its plug cell, ``J_shaft``: the plug is soil on steel as
the soil outside is), and at the front cell the end resistances ``Qf = q_face S1`` and ``Qp =
q_plug_face S2`` (by the advancing speed of their end, ``J_face``; nothing while it retreats).
The damper ``J R v`` is 0 at ``v = 0``: a stuck contact keeps its static window, so the
friction stays set-valued and a body held by it stays exactly at rest.

In the explicit step a sliding cell's damped resistance is linear in its new velocity, so each
cell takes it implicitly, at the velocity after the step, as the rigid models' fd scheme does
(:mod:`pipeplug.rigid.damped_fd`): the cell's projection (:mod:`pipeplug.contact.damping`,
windows and dampers of impulses ``dt R``, ``dt J R``) minimises a strictly convex function, so
it is unique, stuck first on a boundary, and a damper never reverses a motion. First order in
time and space, as the scheme's friction.

Energy. The scheme pairs every impulse on a cell with its mean velocity over the step
(:mod:`pipeplug.elastic.cells`), the dampers' too: a contact's whole impulse (Coulomb plus
damper, both against the motion) does the work ``-F (r + x) / 2``, split between the Coulomb
part (``W_friction``, ``W_face``) and the damper (``W_damping``) in the ratio of their
impulses, which act with the same mean velocity. A step in which a sum of those parts over
the rods would be negative takes back shares of the whole impulses as the undamped kernels do
(:func:`pipeplug.elastic.cells.limit`, :func:`book_damped_step`; the front cell's windows of
:mod:`pipeplug.elastic.face`), after which no cell's work is negative. So the works never
decrease and the ledger ``W_input (+ W_ram) = E_kinetic + E_strain + W_friction (+ W_cushion)
+ W_face + W_damping`` closes to round-off as without damping.
``F_outer`` and ``F_inner`` are the whole resistances of shaft and plug, dampers included.

One kernel for every combination of the other effects (:func:`run_damped`: soil friction,
contact growth, a plug, end resistance, a ram), built only when damping acts
(:attr:`pipeplug.params.Params.has_damping`); it steps every cell at every step, like
:func:`pipeplug.elastic.face.run_face`. Without numba it runs as plain Python loops (no
whole-array form): correct, slow for fine grids. Smith's quake is not modelled
(docs/physics.md).
"""
from __future__ import annotations

import numpy as np

from ..contact.coulomb import SLACK
from ..contact.damping import damped_contacts, damped_one
from ..jit import jitable
from .cells import (
    D1,
    D2,
    F1,
    F2,
    R1,
    R2,
    SCRATCH_ROWS,
    W1,
    W2,
    _first_in_contact,
    accumulate,
    free_cells,
    limit,
    soil_weight,
    window,
)
from .face import _both, soil_front, store_forces
from .kernels import (
    C1,
    C2,
    GROWTH,
    JF,
    JS,
    LIMITED,
    M1,
    M2,
    QF,
    QP,
    W_DAMPING,
    W_DAMPING_ERROR,
    W_FACE,
    W_FACE_ERROR,
    _book_friction,
    _finish_step,
    start_step,
)

__all__ = ["run_damped", "damped_pair", "damped_scratch", "G1", "G2"]

# Scratch rows beyond those of pipeplug.elastic.cells: the damper's share [1] of the soil's (G1)
# and the plug's (G2) whole impulse on the cell, which a limited step keeps (it scales both).
G1, G2 = SCRATCH_ROWS, SCRATCH_ROWS + 1
_ROWS = SCRATCH_ROWS + 2


@jitable
def damped_scratch(v1):
    """The scratch of a damped kernel call: the rows of :mod:`pipeplug.elastic.cells` and the
    dampers' shares, a column per pipe cell."""
    return np.zeros((_ROWS, v1.shape[0]))


@jitable
def _share(g, total):
    """The damper's share ``g / total`` [1] of a contact's whole impulse, in [0, 1] (0 for no
    impulse; both act against the motion, so only round-off could take it outside)."""
    if total == 0.0:
        return 0.0
    return min(max(g / total, 0.0), 1.0)


@jitable
def damped_pair(m1, m2, w1, w2, c2, d2):
    """Pipe and plug cells without the soil: ``(x1, x2, f2, g2)``, the rates after the step,
    the Coulomb impulse and the damper's on the pipe (the plug takes their opposite).

    Stuck together at the momentum average when the static reaction is within ``c2`` (as
    :func:`pipeplug.contact.coulomb.pair_contact`), else sliding: the relative rate
    ``(mu (w1 - w2) - c2 s) / (mu + d2)``, ``mu`` the reduced mass, ``d2`` the damper's
    impulse per unit of relative rate; the momentum is kept.
    """
    x = (m1 * w1 + m2 * w2) / (m1 + m2)
    f2 = -m2 * (x - w2)
    if abs(f2) - c2 <= SLACK * (abs(m1 * w1) + abs(m2 * w2) + c2):
        return x, x, min(max(f2, -c2), c2), 0.0
    f2 = -c2 if w1 > w2 else c2
    mu = m1 * m2 / (m1 + m2)
    g2 = -d2 * (mu * (w1 - w2) + f2) / (mu + d2)
    return w1 + (f2 + g2) / m1, w2 - (f2 + g2) / m2, f2, g2


@jitable
def damped_soil_cells(v, N, lo, hi, a, m, c, js, start, s):
    """Kick cells ``lo..hi-1`` touching only the soil, then project each with its damped
    friction (limit ``c`` [N s] times the soil's weight, damper ``js`` times that [N s^2/m]);
    whole impulses, works, damper shares and velocities go to the scratch ``s`` (rows F1, D1,
    G1, R1, W1; as :func:`pipeplug.elastic.cells.soil_cells`)."""
    for j in range(lo, hi):
        r = v[j]
        w = r + a * (N[j + 1] - N[j])
        cj = c * soil_weight(j, start)
        x, f, g = damped_one(m, w, cj, cj, js * cj, js * cj, 0.0)
        total = f + g
        v[j] = x
        s[F1, j] = total
        s[D1, j] = -0.5 * total * (r + x)
        s[G1, j] = _share(g, total)
        s[R1, j] = r
        s[W1, j] = w


@jitable
def _store_pair(s, j, p, q, w1, w2, x1, x2, f2, g2):
    """The plug contact of pipe cell ``j`` in the scratch ``s`` (rows F2, D2, G2, R1, W1, R2,
    W2): velocities ``p, q`` before, ``w1, w2`` after the kick, ``x1, x2`` after the step."""
    total = f2 + g2
    s[F2, j] = total
    s[D2, j] = -0.5 * total * (p - q + x1 - x2)
    s[G2, j] = _share(g2, total)
    s[R1, j] = p
    s[W1, j] = w1
    s[R2, j] = q
    s[W2, j] = w2


@jitable
def damped_plug_cells(v1, N1, v2, N2, j0, lo, hi, a1, a2, m1, m2, c2, d2, s):
    """Kick the plug cells ``lo..hi-1`` and the pipe cells ``j0 + lo..`` coupled to them, then
    project each pair with its damped inner friction (:func:`damped_pair`)."""
    for k in range(lo, hi):
        j = j0 + k
        p = v1[j]
        q = v2[k]
        w1 = p + a1 * (N1[j + 1] - N1[j])
        w2 = q + a2 * (N2[k + 1] - N2[k])
        x1, x2, f2, g2 = damped_pair(m1, m2, w1, w2, c2, d2)
        v1[j] = x1
        v2[k] = x2
        _store_pair(s, j, p, q, w1, w2, x1, x2, f2, g2)


@jitable
def damped_plug_soil_cells(v1, N1, v2, N2, j0, end, a1, a2, m1, m2, c1, c2, js, start, s):
    """As :func:`damped_plug_cells` for the pipe cells ``j0..end-1``, with the damped soil
    contact where the soil's weight is above 0 (the joint problem of
    :func:`pipeplug.contact.damping.damped_contacts`); returns the first plug cell in the
    soil's contact (as :func:`pipeplug.elastic.cells.plug_soil_cells`)."""
    hi = max(end - j0, 0)
    free = _first_in_contact(j0, hi, start)
    damped_plug_cells(v1, N1, v2, N2, j0, 0, free, a1, a2, m1, m2, c2, js * c2, s)
    for k in range(free, hi):
        j = j0 + k
        p = v1[j]
        q = v2[k]
        w1 = p + a1 * (N1[j + 1] - N1[j])
        w2 = q + a2 * (N2[k + 1] - N2[k])
        cj = c1 * soil_weight(j, start)
        x1, x2, f1, f2, _, g1, g2, _, _, _, _ = damped_contacts(
            m1, m2, w1, w2, cj, cj, c2, 0.0, js * cj, js * cj, js * c2, 0.0, 0.0)
        v1[j] = x1
        v2[k] = x2
        total = f1 + g1
        s[F1, j] = total
        s[D1, j] = -0.5 * total * (p + x1)
        s[G1, j] = _share(g1, total)
        _store_pair(s, j, p, q, w1, w2, x1, x2, f2, g2)
    return free


@jitable
def damped_front_cell(v1, N1, v2, N2, dt, coef, c1, on, s, acc):
    """Kick and project the pipe's front cell (and the plug's, coupled to it) with its damped
    shaft friction, inner friction and end resistances, apply the largest share whose works
    are all >= 0 (as :func:`pipeplug.elastic.face.front_cell`), write the shaft and plug
    contacts to the scratch ``s`` and add the end resistances' works to ``acc`` (their
    Coulomb parts to W_face, their dampers' to W_damping).

    ``c1`` [N s]: the shaft's impulse limit on the cell; ``on``: 1.0 when the annulus meets the
    soil (model II: the front end at U >= 0), else 0.0.
    """
    j = v1.shape[0] - 1
    n2 = v2.shape[0]
    m1 = coef[M1]
    js, jf = coef[JS], coef[JF]
    cf = on * dt * coef[QF]
    r1 = v1[j]
    w1 = r1 + (dt / m1) * (N1[j + 1] - N1[j])
    r2 = w2 = x2 = f2 = f3 = g2 = g3 = 0.0
    if n2 > 0:
        k = n2 - 1
        r2 = v2[k]
        w2 = r2 + (dt / coef[M2]) * (N2[k + 1] - N2[k])
        c2, cp = dt * coef[C2], dt * coef[QP]
        x1, x2, f1, f2, f3, g1, g2, g3, _, _, _ = damped_contacts(
            m1, coef[M2], w1, w2, c1 + cf, c1, c2, cp, js * c1 + jf * cf, js * c1, js * c2,
            jf * cp, 0.0)
    else:
        x1, f1, g1 = damped_one(m1, w1, c1 + cf, c1, js * c1 + jf * cf, js * c1, 0.0)
    shaft = max(f1, -c1)              # the shaft holds first, the annulus takes the rest
    shaft_g = -js * c1 * x1           # the shaft's damper acts both ways, the annulus' ahead
    shaft_t = shaft + shaft_g
    face_g = g1 - shaft_g
    face_t = f1 - shaft + face_g
    plug_t = f2 + g2
    pface_t = f3 + g3
    lo, hi = window(shaft_t, r1, w1, x1)
    lo2, hi2 = window(face_t, r1, w1, x1)
    lo, hi = _both(lo, hi, lo2, hi2)
    lo2, hi2 = window(plug_t, r1 - r2, w1 - w2, x1 - x2)
    lo, hi = _both(lo, hi, lo2, hi2)
    lo2, hi2 = window(pface_t, r2, w2, x2)
    lo, hi = _both(lo, hi, lo2, hi2)
    lam = hi if lo <= hi else 0.0
    if lam != 1.0:
        x1 = w1 + lam * (x1 - w1)
        x2 = w2 + lam * (x2 - w2)
        acc[LIMITED] += 1.0
    v1[j] = x1
    s[F1, j] = lam * shaft_t
    s[D1, j] = max(-0.5 * lam * shaft_t * (r1 + x1), 0.0)
    s[G1, j] = _share(shaft_g, shaft_t)
    s[R1, j] = r1
    s[W1, j] = w1
    if n2 > 0:
        v2[n2 - 1] = x2
        s[F2, j] = lam * plug_t
        s[D2, j] = max(-0.5 * lam * plug_t * (r1 - r2 + x1 - x2), 0.0)
        s[G2, j] = _share(g2, plug_t)
        s[R2, j] = r2
        s[W2, j] = w2
    face = max(-0.5 * lam * face_t * (r1 + x1), 0.0)
    plug_face = max(-0.5 * lam * pface_t * (r2 + x2), 0.0)
    rho_face, rho_plug = _share(face_g, face_t), _share(g3, pface_t)
    accumulate(acc, W_FACE, W_FACE_ERROR, (1.0 - rho_face) * face + (1.0 - rho_plug) * plug_face)
    accumulate(acc, W_DAMPING, W_DAMPING_ERROR, rho_face * face + rho_plug * plug_face)


@jitable
def _parts(s, work, damper, lo, hi):
    """The Coulomb and the damper's parts [J] of scratch row ``work`` over the pipe cells
    ``lo..hi-1`` (shares in row ``damper``), each summed in the cells' order."""
    coulomb = 0.0
    damped = 0.0
    for j in range(lo, hi):
        coulomb += (1.0 - s[damper, j]) * s[work, j]
        damped += s[damper, j] * s[work, j]
    return coulomb, damped


@jitable
def _split_works(s, alone, both, j0, n1):
    """The step's works [J] at the soil and the plug, each split into its Coulomb part and its
    dampers' (:func:`_parts`): ``(outer, outer_damped, inner, inner_damped)``."""
    outer_a, damped_a = _parts(s, D1, G1, 0, alone)
    outer_b, damped_b = _parts(s, D1, G1, both, n1)
    inner, inner_damped = _parts(s, D2, G2, j0, n1)
    return outer_a + outer_b, damped_a + damped_b, inner, inner_damped


@jitable
def book_damped_step(v1, v2, j0, s, alone, both, front, n1, soil, acc):
    """Book one step's works [J] (as :func:`pipeplug.elastic.face.book_step_friction`): the
    Coulomb part of each contact's work summed over the rods to W_friction, the dampers' to
    W_damping. A step in which any of the four sums is negative is limited first
    (:func:`pipeplug.elastic.cells.limit` on the contacts' whole impulses): afterwards every
    cell's whole work at each contact is >= 0, and so is each of its parts. (Limiting on the
    whole works alone is not enough: a stuck cell whose kick reversed it books a negative
    Coulomb work and no damper's, which the sliding cells' dampers may outweigh in the whole
    sum but not in its Coulomb part.)"""
    outer, outer_damped, inner, inner_damped = _split_works(s, alone, both, j0, n1)
    if min(outer, outer_damped, inner, inner_damped) < 0.0:
        if soil:
            limit(v1, v2, j0, s, 0, alone, j0, both, both, front)
        else:
            limit(v1, v2, j0, s, 0, 0, j0, front, 0, 0)
        outer, outer_damped, inner, inner_damped = _split_works(s, alone, both, j0, n1)
        acc[LIMITED] += 1.0
    _book_friction(acc, outer, inner)
    accumulate(acc, W_DAMPING, W_DAMPING_ERROR, max(outer_damped + inner_damped, 0.0))


@jitable
def run_damped(n, dt, q, coef, v1, N1, v2, N2, cells1, u1, cells2, u2, acc):
    """Pipe (and plug, soil friction, contact growth, end resistance, ram: as ``coef`` has
    them) with Smith damping: every cell at every step (module docstring)."""
    start_step(q, N1, coef, acc)
    n1 = v1.shape[0]
    n2 = v2.shape[0]
    j0 = n1 - n2
    front = n1 - 1
    alone = min(j0, front)
    m1, m2 = coef[M1], coef[M2]
    a1 = dt / m1
    c1 = dt * coef[C1]
    js = coef[JS]
    soil = coef[C1] > 0.0
    growth = coef[GROWTH] > 0.0
    s = damped_scratch(v1)
    last_both = front
    for _ in range(n):
        start, on = soil_front(u1, n1, coef, growth)
        v_old = v1[0]
        if soil:
            damped_soil_cells(v1, N1, 0, alone, a1, m1, c1, js, start, s)
        else:
            free_cells(v1, N1, 0, alone, a1)
        both = front
        if n2 > 1 and soil:
            both = j0 + damped_plug_soil_cells(v1, N1, v2, N2, j0, front, a1, dt / m2, m1, m2,
                                               c1, dt * coef[C2], js, start, s)
        elif n2 > 1:
            damped_plug_cells(v1, N1, v2, N2, j0, 0, n2 - 1, a1, dt / m2, m1, m2,
                              dt * coef[C2], js * dt * coef[C2], s)
        damped_front_cell(v1, N1, v2, N2, dt, coef, c1 * soil_weight(front, start), on, s, acc)
        book_damped_step(v1, v2, j0, s, alone, both, front, n1, soil, acc)
        _finish_step(q, dt, v_old, v1, N1, v2, N2, coef, cells1, u1, cells2, u2, acc, n1)
        last_both = both
    store_forces(s, acc, j0, last_both, n1, dt, soil)
