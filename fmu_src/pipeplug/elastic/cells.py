"""One internal step of the elastic rods, cell by cell (helpers the compiled kernels call).

Grid (see :mod:`pipeplug.elastic.model`): a rod of ``n`` cells of length ``dx`` carries the velocity
``v[j]`` of cell ``j`` (its centre) and the axial force ``N[f]`` (tension positive) at face
``f = 0..n``; the end faces hold the boundary forces (``N[0] = -Q`` at the struck end, 0 at a
free end). One step of length ``dt`` is

1. kick: trial velocity ``w = v + (dt/m) (N[j+1] - N[j])`` (``m`` the cell mass);
2. friction: the exact nodal Coulomb projection of the trial velocities
   (:mod:`pipeplug.contact.coulomb`, the rigid models' rules), with impulse limits
   ``c = dt * tau * P * (contact length)``;
3. drift: ``N[f] += (E S / dx) dt (v[f] - v[f-1])`` at the inner faces.

Cells at rest whose inputs did not change are skipped (:func:`moving_end`, the kernels): a cell's
step is a function of its velocity, the forces on its faces and its friction limits alone, so it
would give the same result again, velocity 0 and the same static reaction, and a face between
two cells at rest keeps its force (``N + b * 0 == N``). Only the impulse sums of the step need
every cell: the kernels take the last step of a call in full.

The cells on the soil alone and the pipe-plug pairs are stepped in two passes: each cell on its
own, its impulse and friction work stored in a scratch array; then the sums, in the cells'
order. Without a sum carried from one cell to the next, compiled code steps several cells at
once, and the sums are those of a single loop bit for bit.

Friction work per contact and step is ``-I (v_old + v_new) / 2`` (impulse times mean velocity),
which makes the discrete energy balance exact (see :meth:`ElasticModel.energies`). It is
negative only when a step reverses a node's relative velocity; that part is kept apart in
``w_neg`` so that the dissipated work never decreases.
"""
from __future__ import annotations

from ..contact import coulomb
from ..jit import jitable

__all__ = ["free_cells", "soil_cells", "plug_cells", "plug_soil_cells", "drift", "track",
           "soil_start", "soil_weight", "moving_end", "next_end"]

# The projections are the rigid models' own (one source); compiled kernels call them too.
one_contact = jitable(coulomb.one_contact)
pair_contact = jitable(coulomb.pair_contact)
two_contacts = jitable(coulomb.two_contacts)
jitable(coulomb.pattern)
jitable(coulomb._clip)


@jitable
def free_cells(v, N, lo, hi, a):
    """Kick cells ``lo..hi-1`` without friction; ``a = dt/m`` [s/kg]."""
    for j in range(lo, hi):
        v[j] += a * (N[j + 1] - N[j])


@jitable
def soil_cells(v, N, lo, hi, a, m, c, start, scratch):
    """Kick cells ``lo..hi-1`` touching only the soil, then project their velocities.

    The contact of cell ``j`` covers the part of the cell beyond ``start`` (in cells from the
    struck end): :func:`soil_weight` of the full-cell limit ``c`` [N s].
    Two passes, as in :func:`_pairs` (``scratch`` likewise).

    Returns
    -------
    impulse, work, w_neg : float
        Total friction impulse on the rod along +x [N s]; dissipated work [J] (>= 0) and the
        negative part from reversing steps [J].
    """
    n = max(hi - lo, 0)
    impulses, works = scratch[0, :n], scratch[1, :n]
    _soil_pass(v[lo:lo + n], N[lo:lo + n + 1], lo, a, m, c, start, impulses, works)
    return _sums(impulses, works)


@jitable
def _soil_pass(v, N, lo, a, m, c, start, impulses, works):
    """Kick and project the cells ``v`` (a view from cell ``lo``, with the faces ``N`` around
    them) on the soil; their impulses [N s] and friction works [J] go to ``impulses`` and
    ``works``."""
    for k in range(v.shape[0]):
        v_old = v[k]
        limit = c * soil_weight(lo + k, start)
        x, f = one_contact(m, v_old + a * (N[k + 1] - N[k]), limit, 0.0)
        v[k] = x
        impulses[k] = f
        works[k] = -0.5 * f * (v_old + x)


@jitable
def plug_cells(v1, N1, v2, N2, j0, a1, a2, m1, m2, c2, scratch):
    """Kick the pipe cells ``j0..`` and the plug cells coupled to them, then project each pair.

    Pipe cell ``j0 + k`` and plug cell ``k`` share a reference section; ``scratch`` is an array
    of shape (2, at least the plug's cells) for :func:`_pairs`. Returns the impulse of the plug
    on the pipe [N s], the dissipated work and its negative part [J].
    """
    return _pairs(v1, N1, v2, N2, j0, v2.shape[0], a1, a2, m1, m2, c2, scratch)


@jitable
def _pairs(v1, N1, v2, N2, j0, hi, a1, a2, m1, m2, c2, scratch):
    """:func:`plug_cells` for the plug cells ``0..hi-1``.

    In two passes: the pairs, each on its own, their impulses and works kept in ``scratch``
    (shape (2, at least hi)); then the sums, in the cells' order. No sum is carried from
    one pair to the next in the first pass, so compiled code projects several pairs at once
    (the pair problem has no branch that it cannot turn into a select).
    """
    n = max(hi, 0)
    impulses, works = scratch[0, :n], scratch[1, :n]
    _pair_pass(v1[j0:j0 + n], N1[j0:j0 + n + 1], v2[:n], N2[:n + 1], a1, a2, m1, m2, c2,
               impulses, works)
    return _sums(impulses, works)


@jitable
def _sums(impulses, works):
    """The sum of ``impulses`` [N s], and of ``works`` [J] split into the dissipated and the
    reversing part (:func:`_book`), in index order (the cells' order)."""
    impulse = 0.0
    work = 0.0
    w_neg = 0.0
    for k in range(impulses.shape[0]):
        impulse += impulses[k]
        work, w_neg = _book(works[k], work, w_neg)
    return impulse, work, w_neg


@jitable
def _pair_pass(p, Np, q, Nq, a1, a2, m1, m2, c2, impulses, works):
    """Kick and project the pairs of pipe cells ``p`` and plug cells ``q`` (views, with the
    faces ``Np``, ``Nq`` around them); their plug impulses [N s] and friction works [J] go to
    ``impulses`` and ``works``."""
    for k in range(p.shape[0]):
        p_old = p[k]
        q_old = q[k]
        x1, x2, f2 = pair_contact(m1, m2, p_old + a1 * (Np[k + 1] - Np[k]),
                                  q_old + a2 * (Nq[k + 1] - Nq[k]), c2)
        p[k] = x1
        q[k] = x2
        impulses[k] = f2
        works[k] = -0.5 * f2 * (p_old - q_old + x1 - x2)


@jitable
def plug_soil_cells(v1, N1, v2, N2, j0, end, a1, a2, m1, m2, c1, c2, start, scratch):
    """As :func:`plug_cells` for the pipe cells ``j0..end-1``, with the soil contact too
    (weights as in :func:`soil_cells`).

    A cell outside the soil's contact (weight 0) is the pair problem of :func:`plug_cells`: not
    the two-contact problem with a zero limit, which within its round-off slack would hold a
    pair of nearly opposite momenta still as if the soil touched it (and costs more).

    Returns the impulses of the soil and of the plug on the pipe [N s], the work dissipated at
    the soil and at the plug contacts, and the negative part of both [J].
    """
    # The cells with weight 0 come first (the contact covers the far end): a loop of their own.
    hi = max(end - j0, 0)
    free = _first_in_contact(j0, hi, start)
    inner, work_inner, w_neg = _pairs(v1, N1, v2, N2, j0, free, a1, a2, m1, m2, c2, scratch)
    outer = 0.0
    work_outer = 0.0
    # One pass here: the two-contact problem tries its patterns in turn (no select for
    # several cells at once), and both contacts add to w_neg, interleaved cell by cell.
    for k in range(free, hi):
        j = j0 + k
        p_old = v1[j]
        q_old = v2[k]
        limit = c1 * soil_weight(j, start)
        x1, x2, f1, f2, _, _ = two_contacts(m1, m2, p_old + a1 * (N1[j + 1] - N1[j]),
                                            q_old + a2 * (N2[k + 1] - N2[k]), limit, c2, 0.0)
        v1[j] = x1
        v2[k] = x2
        outer += f1
        inner += f2
        work_outer, w_neg = _book(-0.5 * f1 * (p_old + x1), work_outer, w_neg)
        work_inner, w_neg = _book(-0.5 * f2 * (p_old - q_old + x1 - x2), work_inner, w_neg)
    return outer, inner, work_outer, work_inner, w_neg


@jitable
def _first_in_contact(j0, hi, start):
    """The first plug cell ``k < hi`` whose pipe cell ``j0 + k`` has a soil weight above 0
    (:func:`soil_weight`), else ``hi``."""
    k = min(max(int(start) - j0 - 1, 0), hi)     # a guess from below, then the exact test
    while k > 0 and soil_weight(j0 + k, start) > 0.0:
        k -= 1
    while k < hi and soil_weight(j0 + k, start) <= 0.0:
        k += 1
    return k


@jitable
def soil_weight(j, start):
    """The share of pipe cell ``j`` that the soil's contact covers, beyond ``start`` (in cells
    from the struck end): ``clip(j + 1 - start, 0, 1)``."""
    return min(max(j + 1.0 - start, 0.0), 1.0)


@jitable
def drift(v, N, b, end):
    """Update the inner-face forces from the new velocities; ``b = E S dt / dx`` [N s/m].

    Only the faces of the cells before ``end`` (the faces beyond lie between cells at rest)."""
    for f in range(1, min(end + 1, v.shape[0])):
        N[f] += b * (v[f] - v[f - 1])


@jitable
def track(u, cells, v, dt):
    """Advance the displacements ``u[i]`` of the tracked cells ``cells[i]`` by ``dt v``."""
    for i in range(cells.shape[0]):
        u[i] += dt * v[cells[i]]


@jitable
def moving_end(v1, v2, j0, end):
    """One past the last pipe cell before ``end`` that moves, itself or the plug cell coupled
    to it (pipe cell ``j0 + k`` and plug cell ``k``); 0 when none does."""
    for j in range(end - 1, -1, -1):
        if v1[j] != 0.0 or (j >= j0 and v2[j - j0] != 0.0):
            return j + 1
    return 0


@jitable
def next_end(moved, moved_before, n):
    """The pipe cells the next step must take, from ``moved`` and ``moved_before``
    (:func:`moving_end` after this step and after the one before; cells from there on are at
    rest, the rest of the ``n`` cells too).

    A cell from ``max(moved + 1, moved_before)`` on was at rest before this step and after it,
    and so were its neighbours after it: its velocity, the forces on its faces and, as the front
    end (the last cell) did not move, its soil contact are those of this step, whose result it
    would repeat.
    """
    return min(n, max(moved + 1, moved_before))


@jitable
def soil_start(u_front, n_cells, dx):
    """Start of the penetrated contact, in cells from the struck end (contact growth).

    The contact covers reference x >= L1 - Lc with Lc = min(max(s, 0), L1) and s the front
    end's displacement [m]; ``L1 = n_cells * dx``.
    """
    return n_cells - min(max(u_front / dx, 0.0), float(n_cells))


@jitable
def _book(d, work, w_neg):
    """Add one contact's friction work ``d`` [J] to the dissipated or the reversing part."""
    # Both sums take a term, one of them 0.0, which leaves it unchanged: no branch, whose
    # outcome the ringing of a rod, reversing contacts at random, would keep mispredicting.
    return work + max(d, 0.0), w_neg + min(d, 0.0)
