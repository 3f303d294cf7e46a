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

Friction work per contact and step is ``-I (v_old + v_new) / 2`` (impulse times mean velocity):
what the friction takes from the scheme's energy (:mod:`pipeplug.elastic.model`), exactly. A
cell's term is negative in one kind of step only: the kick alone would reverse the relative
velocity, and friction then stops or holds it (the energy pairs the impulse with the step's
mean velocity, whose sign is the old one). Summed over the rods such terms are outweighed by the
work of the sliding cells, except where little else moves; a step whose sum at either contact
would be negative creates energy, and such steps pumped the ringing of rods held in the soil
until they diverged. That step applies, at each cell whose term is negative, only the share of
its impulse for which the term is 0 (:func:`share`, :func:`limit`). Every other step applies the
projection as it is, so a body held by static friction stays exactly at rest.

Cells at rest whose inputs did not change are skipped (:func:`moving_end`, the kernels): a cell's
step is a function of its velocity, the forces on its faces and its friction limits alone, so it
would give the same result again, velocity 0 and the same static reaction, and a face between
two cells at rest keeps its force (``N + b * 0 == N``). Only the impulse sums of the step need
every cell: the kernels take the last step of a call in full.

The cells on the soil alone and the pipe-plug pairs are stepped in two passes: each cell on its
own, its impulse and friction work stored in a scratch array; then the sums, in the cells'
order. Without a sum carried from one cell to the next, compiled code steps several cells at
once, and the sums are those of a single loop bit for bit.
"""
from __future__ import annotations

import numpy as np

from ..contact import coulomb
from ..jit import jitable

__all__ = ["free_cells", "soil_cells", "plug_cells", "plug_soil_cells", "sums", "limit", "drift",
           "drift_extremes", "node_extremes", "extremes",
           "node_forces",
           "track", "soil_start", "soil_weight", "moving_end", "next_end", "share", "window",
           "joint_share", "accumulate", "SCRATCH_ROWS"]

# The projections are the rigid models' own (one source); compiled kernels call them too.
one_contact = jitable(coulomb.one_contact)
pair_contact = jitable(coulomb.pair_contact)
two_contacts = jitable(coulomb.two_contacts)
jitable(coulomb.pattern)
jitable(coulomb._clip)


@jitable
def share(f, r, w, x):
    """The share of a contact's projected impulse a step applies, in [0, 1].

    Parameters
    ----------
    f : float
        The projection's friction impulse on the contact [N s].
    r, w, x : float
        The contact's relative velocity before the step, after the kick and after the
        projection [m/s].

    Returns
    -------
    float
        The largest ``lam`` for which the contact's friction work with the impulse ``lam f``,
        ``-lam f (r + w + lam (x - w)) / 2``, is not negative: 1 unless the projection's own
        work ``-f (r + x) / 2`` is negative.
    """
    # The work is lam (a + lam b) / 2: a / 2 its slope at lam = 0, (a + b) / 2 at lam = 1.
    a = -f * (r + w)
    b = -f * (x - w)
    if a + b >= 0.0:
        return 1.0
    if a <= 0.0:
        return 0.0
    return a / -b             # b < -a < 0: the work is 0 there


@jitable
def window(f, r, w, x):
    """The shares of a contact's projected impulse (arguments of :func:`share`) whose friction
    work is not negative: ``lo <= lam <= hi`` (and ``lam = 0``); ``lo > hi`` when only
    ``lam = 0`` is."""
    a = -f * (r + w)
    b = -f * (x - w)
    if b >= 0.0:
        if a >= 0.0:
            return 0.0, 1.0
        if a + b >= 0.0:
            return a / -b, 1.0          # the work grows with lam through 0 at -a / b
        return 1.0, 0.0
    if a + b >= 0.0:
        return 0.0, 1.0
    if a > 0.0:
        return 0.0, a / -b
    return 1.0, 0.0


@jitable
def joint_share(f1, r1, w1, x1, f2, r2, w2, x2):
    """The largest share of both contacts' projected impulses of a cell (arguments of
    :func:`share` for the soil and the plug contact) for which neither friction work is
    negative; 0 when only none is."""
    lo1, hi1 = window(f1, r1, w1, x1)
    lo2, hi2 = window(f2, r2, w2, x2)
    hi = min(hi1, hi2)
    return hi if max(lo1, lo2) <= hi else 0.0


@jitable
def _applied(lam, w, x):
    """The velocity after a step that applies the share ``lam`` of the projection ``w -> x``
    (``x`` itself for the whole impulse, bit for bit)."""
    return x if lam == 1.0 else w + lam * (x - w)


# Rows of a step's scratch (shape (8, pipe cells), indexed by pipe cell; plug quantities at the
# pipe cell coupled to the plug cell): friction impulse [N s] and work [J] at the soil (1) and
# plug (2) contact, and the velocities before the step and after its kick [m/s] of the pipe (1)
# and plug (2) cell: what :func:`limit` needs to take back part of a projection.
F1, D1, F2, D2, R1, W1, R2, W2 = range(8)
SCRATCH_ROWS = 8


@jitable
def free_cells(v, N, lo, hi, a):
    """Kick cells ``lo..hi-1`` without friction; ``a = dt/m`` [s/kg]."""
    for j in range(lo, hi):
        v[j] += a * (N[j + 1] - N[j])


@jitable
def soil_cells(v, N, lo, hi, a, m, c, start, s):
    """Kick cells ``lo..hi-1`` touching only the soil, then project their velocities; their
    impulses, works and velocities go to the scratch ``s`` (rows :data:`F1`, :data:`D1`,
    :data:`R1`, :data:`W1`).

    The contact of cell ``j`` covers the part of the cell beyond ``start`` (in cells from the
    struck end): :func:`soil_weight` of the full-cell limit ``c`` [N s]; ``a = dt/m`` [s/kg],
    ``m`` the cell mass [kg]. No sum is carried from one cell to the next, so compiled code
    projects several cells at once.
    """
    for j in range(lo, hi):
        r = v[j]
        w = r + a * (N[j + 1] - N[j])
        x, f = one_contact(m, w, c * soil_weight(j, start), 0.0)
        v[j] = x
        s[F1, j] = f
        s[D1, j] = -0.5 * f * (r + x)
        s[R1, j] = r
        s[W1, j] = w


@jitable
def plug_cells(v1, N1, v2, N2, j0, lo, hi, a1, a2, m1, m2, c2, s):
    """Kick the plug cells ``lo..hi-1`` and the pipe cells ``j0 + lo..`` coupled to them (pipe
    cell ``j0 + k`` and plug cell ``k`` share a reference section), then project each pair;
    impulses, works and velocities go to the scratch ``s`` (rows :data:`F2`, :data:`D2`,
    :data:`R1`, :data:`W1`, :data:`R2`, :data:`W2`) at the pipe cells.

    The pair problem has no branch that compiled code cannot turn into a select: it projects
    several pairs at once.
    """
    for k in range(lo, hi):
        j = j0 + k
        p = v1[j]
        q = v2[k]
        w1 = p + a1 * (N1[j + 1] - N1[j])
        w2 = q + a2 * (N2[k + 1] - N2[k])
        x1, x2, f2 = pair_contact(m1, m2, w1, w2, c2)
        v1[j] = x1
        v2[k] = x2
        s[F2, j] = f2
        s[D2, j] = -0.5 * f2 * (p - q + x1 - x2)
        s[R1, j] = p
        s[W1, j] = w1
        s[R2, j] = q
        s[W2, j] = w2


@jitable
def plug_soil_cells(v1, N1, v2, N2, j0, end, a1, a2, m1, m2, c1, c2, start, s):
    """As :func:`plug_cells` for the pipe cells ``j0..end-1``, with the soil contact too
    (weights as in :func:`soil_cells`; rows :data:`F1` and :data:`D1` as well).

    A cell outside the soil's contact (weight 0) is the pair problem of :func:`plug_cells`: not
    the two-contact problem with a zero limit, which within its round-off slack would hold a
    pair of nearly opposite momenta still as if the soil touched it (and costs more).

    Returns the first plug cell in the soil's contact (the pipe cells from ``j0`` plus it on
    touch the soil).
    """
    # The cells with weight 0 come first (the contact covers the far end): a loop of their own.
    hi = max(end - j0, 0)
    free = _first_in_contact(j0, hi, start)
    plug_cells(v1, N1, v2, N2, j0, 0, free, a1, a2, m1, m2, c2, s)
    # One loop here: the two-contact problem tries its patterns in turn (no select for several
    # cells at once).
    for k in range(free, hi):
        j = j0 + k
        p = v1[j]
        q = v2[k]
        w1 = p + a1 * (N1[j + 1] - N1[j])
        w2 = q + a2 * (N2[k + 1] - N2[k])
        x1, x2, f1, f2, _, _ = two_contacts(m1, m2, w1, w2, c1 * soil_weight(j, start), c2, 0.0)
        v1[j] = x1
        v2[k] = x2
        s[F1, j] = f1
        s[D1, j] = -0.5 * f1 * (p + x1)
        s[F2, j] = f2
        s[D2, j] = -0.5 * f2 * (p - q + x1 - x2)
        s[R1, j] = p
        s[W1, j] = w1
        s[R2, j] = q
        s[W2, j] = w2
    return free


@jitable
def sums(s, row, lo, hi):
    """The sum of scratch row ``row`` over the pipe cells ``lo..hi-1``, in their order."""
    total = 0.0
    for j in range(lo, hi):
        total += s[row, j]
    return total


@jitable
def limit(v1, v2, j0, s, soil_lo, soil_hi, pair_lo, pair_hi, both_lo, both_hi):
    """Take back the share of the projection (:func:`share`) of every cell whose friction work
    is negative: the soil-only pipe cells ``soil_lo..soil_hi-1``, the pairs of pipe cells
    ``pair_lo..pair_hi-1`` (plug cell = pipe cell - ``j0``) and the pipe cells
    ``both_lo..both_hi-1`` touching soil and plug (one share for both of their contacts,
    :func:`joint_share`).

    A step calls it when a contact's friction work summed over the rods is negative: in such
    a step the cells whose kick reversed their velocity booked more negative work than the
    others dissipated. Afterwards every cell's work at each contact is >= 0 (0 where a share
    was taken), so the step creates no energy.
    """
    for j in range(soil_lo, soil_hi):
        if s[D1, j] < 0.0:
            lam = share(s[F1, j], s[R1, j], s[W1, j], v1[j])
            v1[j] = _applied(lam, s[W1, j], v1[j])
            _scale(s, F1, D1, j, lam, s[R1, j] + v1[j])
    for j in range(pair_lo, pair_hi):
        if s[D2, j] < 0.0:
            k = j - j0
            lam = share(s[F2, j], s[R1, j] - s[R2, j], s[W1, j] - s[W2, j], v1[j] - v2[k])
            _apply_pair(v1, v2, j, k, s, lam)
    for j in range(both_lo, both_hi):
        if s[D1, j] < 0.0 or s[D2, j] < 0.0:
            k = j - j0
            lam = joint_share(s[F1, j], s[R1, j], s[W1, j], v1[j],
                              s[F2, j], s[R1, j] - s[R2, j], s[W1, j] - s[W2, j], v1[j] - v2[k])
            _apply_pair(v1, v2, j, k, s, lam)
            _scale(s, F1, D1, j, lam, s[R1, j] + v1[j])


@jitable
def _apply_pair(v1, v2, j, k, s, lam):
    """Apply the share ``lam`` to pipe cell ``j``, plug cell ``k`` and their plug contact."""
    v1[j] = _applied(lam, s[W1, j], v1[j])
    v2[k] = _applied(lam, s[W2, j], v2[k])
    _scale(s, F2, D2, j, lam, s[R1, j] - s[R2, j] + v1[j] - v2[k])


@jitable
def _scale(s, impulse, work, j, lam, speeds):
    """Scale the impulse of row ``impulse`` at cell ``j`` by ``lam``; its work (row ``work``)
    from the sum of relative velocities before and after the step ``speeds`` [m/s]."""
    f = lam * s[impulse, j]
    s[impulse, j] = f
    s[work, j] = -0.5 * f * speeds


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
def drift_extremes(v, N, b, end, low, high):
    """:func:`drift`, and the smallest and largest of ``low``, ``high`` and the node-centred
    forces [N] (:func:`node_forces`) of the cells ``1..min(end, n-1)`` (``n`` cells), those
    of the cells from 1 on whose faces drifted; cell 0's waits for the head force of the next
    step (:func:`node_extremes`), and the cells beyond keep theirs, which the caller counted."""
    last = min(end + 1, v.shape[0])
    if last < 2:
        return low, high
    behind = N[1] + b * (v[1] - v[0])
    N[1] = behind
    for f in range(2, last):
        ahead = N[f] + b * (v[f] - v[f - 1])
        N[f] = ahead
        mean = 0.5 * (behind + ahead)
        low = min(low, mean)
        high = max(high, mean)
        behind = ahead
    mean = 0.5 * (behind + N[last])        # the cell whose far face did not drift
    return min(low, mean), max(high, mean)


@jitable
def node_extremes(N, cells, low, high):
    """The smallest and largest of ``low``, ``high`` and the node-centred forces [N] of the
    head face ``N[0]`` and of the cells ``0..cells-1`` (:func:`node_forces`)."""
    low = min(low, N[0])
    high = max(high, N[0])
    for j in range(cells):
        value = 0.5 * (N[j] + N[j + 1])
        low = min(low, value)
        high = max(high, value)
    return low, high


@jitable
def extremes(N, low, high):
    """The smallest and largest of ``low``, ``high`` and every node-centred force of a rod
    [N] (:func:`node_forces`)."""
    low, high = node_extremes(N, N.shape[0] - 1, low, high)
    return min(low, N[-1]), max(high, N[-1])


def node_forces(N):
    """The axial forces [N] a rod reports, at its nodes: the head face's at x = 0, the mean of
    the two faces of cell ``j`` at its centre x = (j + 1/2) dx, the far face's at x = L.

    Why not the faces themselves: at Courant 1 the scheme carries the two characteristic
    invariants ``P_j = N[j] - Z v[j]`` and ``Q_j = N[j+1] + Z v[j]`` (Z the impedance) exactly
    from cell to cell, friction impulses included, and they alone fix the mean of a cell's
    faces, ``(N[j] + N[j+1]) / 2 = (P_j + Q_j) / 2``. A face itself follows from the chain
    ``N[j+1] = P_j + Q_j - N[j]`` from the head, which sums the invariants' O(dx) errors (a
    cell starting to slide takes a whole step's friction where the front crosses it halfway;
    their sign alternates from cell to cell) into an odd-even pattern of O(f x), f the
    friction per metre, that does not shrink with dx (docs/elastic.md, root cause 8). The
    velocities of the cells carry the same pattern; the mean of two neighbours does not.
    """
    return np.concatenate((N[:1], 0.5 * (N[:-1] + N[1:]), N[-1:]))


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
    would repeat (the projection of a cell at rest keeps its whole impulse: :func:`share`).
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
def accumulate(acc, index, compensation, value):
    """Add ``value`` to the running sum ``acc[index]``, compensated (Neumaier): the rounding
    error of every addition is summed in ``acc[compensation]``, so that a sum over the
    millions of steps of a drive stays exact to a few units of its last place."""
    total = acc[index]
    added = total + value
    if abs(total) >= abs(value):
        acc[compensation] += (total - added) + value
    else:
        acc[compensation] += (value - added) + total
    acc[index] = added
