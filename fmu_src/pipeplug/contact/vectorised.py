"""The two-contact Coulomb problem for many nodes at once: numpy arrays instead of scalars.

The vectorised form of :mod:`pipeplug.contact.coulomb` (the problem, the sign patterns and their
order are described there), for the elastic model's path without numba. It uses the same table
(:data:`~pipeplug.contact.coulomb.PATTERNS`, :data:`~pipeplug.contact.coulomb.SLACK`) and, element
by element, the same floating-point operations in the same order, so for finite inputs every
result equals the scalar form's bit for bit, signed zeros included. Rates are arrays over the
nodes; masses and limits floats or arrays over the nodes. Nothing here is compiled: each
function is a fixed, short sequence of whole-array operations.

:func:`two_contacts` evaluates every pattern of the table at every node (four kinds of
patterns, each with its own formulas, a kind at a time) and takes the first consistent one at
each node; :class:`TwoContacts` does the same with what depends only on masses and limits
computed once, for a kernel that projects the same cells step after step.
"""
from __future__ import annotations

import numpy as np

from .coulomb import PATTERNS, SLACK

__all__ = ["one_contact", "pair_contact", "two_contacts", "TwoContacts"]

_S1 = np.array([s1 for s1, _ in PATTERNS])
_S2 = np.array([s2 for _, s2 in PATTERNS])
_ROWS = len(PATTERNS)


def _kind(stuck1: bool, stuck2: bool) -> slice:
    """The table rows whose contact 1 (and 2) is stuck or not."""
    rows = np.flatnonzero(((_S1 == 0) == stuck1) & ((_S2 == 0) == stuck2))
    if not np.array_equal(rows, np.arange(rows[0], rows[-1] + 1)):
        raise ImportError("the vectorised projection needs the patterns of a kind adjacent "
                          "in coulomb.PATTERNS")
    return slice(rows[0], rows[-1] + 1)


# The patterns fall into four kinds, each with its own formulas (coulomb.pattern); a kind is
# computed for all its patterns at once: the kind's patterns are rows, the nodes columns.
_BOTH_STUCK, _PIPE_STUCK, _TOGETHER, _SLIDING = (
    _kind(a, b) for a, b in ((True, True), (True, False), (False, True), (False, False)))


def _signs(rows: slice):
    """The signs ``s1, s2`` of the patterns ``rows`` as float columns (broadcast over nodes)."""
    return _S1[rows].astype(float)[:, None], _S2[rows].astype(float)[:, None]


def one_contact(m, w, c, slack):
    """Coulomb projection of bodies on a fixed support (:func:`coulomb.one_contact`).

    Parameters
    ----------
    m : float or ndarray
        Masses [kg].
    w : ndarray
        Free rates (accelerations [m/s^2] or trial velocities [m/s]).
    c : float or ndarray
        Friction limits in the units of ``m w`` (forces [N] or impulses [N s]), >= 0.
    slack : float
        Round-off allowance in the units of ``c``: a load within it of the limit sticks.

    Returns
    -------
    x, f : ndarray
        The rates after friction and the friction terms along +x.
    """
    p = m * w
    size = np.abs(p)
    # A stuck body's reaction -p, clipped to the limit; a sliding one's is the limit against p.
    minus_p = -p
    f = np.where(size <= c, minus_p, np.copysign(c, minus_p))
    x = np.where(size <= c + slack, 0.0, w + f / m)
    return x, f


def pair_contact(m1, m2, w1, w2, c2):
    """Pipe and plug nodes without a soil contact: ``(x1, x2, f2)`` (:func:`coulomb.pair_contact`)."""
    mw1 = m1 * w1
    mw2 = m2 * w2
    x = (mw1 + mw2) / (m1 + m2)
    f_stuck = -m2 * (x - w2)
    size = np.abs(f_stuck)
    stuck = size - c2 <= SLACK * (np.abs(mw1) + np.abs(mw2) + c2)
    f_slide = np.where(w1 > w2, -c2, c2)
    x1 = np.where(stuck, x, w1 + f_slide / m1)
    x2 = np.where(stuck, x, w2 - f_slide / m2)
    f2 = np.where(stuck, _clip(f_stuck, c2, size), f_slide)
    return x1, x2, f2


def two_contacts(m1, m2, w1, w2, c1, c2, slack):
    """Solve the joint two-contact problem node by node (:func:`coulomb.two_contacts`).

    Parameters
    ----------
    m1, m2 : float or ndarray
        Pipe and plug masses [kg], positive.
    w1, w2 : ndarray, one dimension
        Free rates of pipe and plug.
    c1, c2 : float or ndarray
        Friction limits of contact 1 (soil/pipe) and 2 (pipe/plug), >= 0.
    slack : float
        Round-off allowance in the units of ``c``.

    Returns
    -------
    x1, x2, f1, f2 : ndarray
        Rates after friction and friction terms on the pipe (``-f2`` acts on the plug).
    s1, s2 : ndarray of int
        The sign patterns, as :func:`coulomb.two_contacts` returns them.
    """
    solve = TwoContacts(m1, m2, c2, slack, np.broadcast(w1, w2).size)
    x1, x2, f1, f2 = solve(w1, w2, c1)
    return x1, x2, f1, f2, _S1[solve.chosen], _S2[solve.chosen]


class TwoContacts:
    """:func:`two_contacts` for given masses, plug limits, slack and number of nodes.

    What depends only on those is computed once, when the solver is made (an elastic kernel
    makes one per call and projects every internal step with it); a call takes the free rates
    and the soil limits.

    Attributes
    ----------
    table : ndarray, shape (5, 9, nodes)
        After a call: ``x1, x2, f1, f2, violation`` of pattern ``PATTERNS[k]`` at node ``j`` in
        ``table[:, k, j]`` (:func:`coulomb.pattern`).
    chosen : ndarray of int
        After a call: the pattern chosen at each node (row of the table).
    """

    def __init__(self, m1, m2, c2, slack, nodes):
        self.m1, self.m2, self.c2, self.slack = m1, m2, c2, slack
        self.table = np.zeros((5, _ROWS, nodes))   # x1 of a stuck pipe stays 0
        self._first = np.arange(nodes)             # position of each node in a table row
        _, s2 = _signs(_PIPE_STUCK)
        s1_together, _ = _signs(_TOGETHER)
        s1, s2_sliding = _signs(_SLIDING)
        f2 = self.table[3]
        # The friction of a sliding plug is its limit, whatever the rates: set once.
        f2[_PIPE_STUCK] = -c2 * s2
        f2[_SLIDING] = -c2 * s2_sliding
        self._dx2_pipe_stuck = f2[_PIPE_STUCK] / m2
        self._dx2_sliding = f2[_SLIDING] / m2
        self._s1_sliding = s1
        self._s1_together = s1_together
        # Sign flips are exact: x * (s m) equals (x s) m, the scalar form's order, bit for bit.
        self._plug_ahead = s2 * m2
        self._together_behind = -s1_together * (m1 + m2)
        self._pipe_behind = -s1 * m1
        self._plug_behind = -s2_sliding * np.minimum(m1, m2)
        # The limits of the chosen f1 and f2, to clip both at once; f2's are fixed.
        self._limits = np.empty((2, nodes))
        self._limits[1] = c2

    def __call__(self, w1, w2, c1):
        """Project free rates ``w1``, ``w2`` with soil limits ``c1``: ``x1, x2, f1, f2``."""
        x1, x2, f1, f2, violation = self.table
        mw1 = self.m1 * w1
        mw2 = np.multiply(self.m2, w2, out=f2[_BOTH_STUCK][0])  # also f2 of both stuck
        size2 = np.abs(mw2)
        scale = SLACK * (np.abs(mw1) + size2 + c1 + self.c2)
        if self.slack:      # otherwise no change: the scale is never negative
            scale = np.maximum(scale, self.slack)
        self._patterns(w1, w2, c1, mw1, mw2, size2)
        consistent = violation <= scale
        self.chosen = consistent.argmax(axis=0)    # the first consistent pattern of the table
        picked = self._pick()
        if not (picked[4] <= scale).all():         # none consistent, unreachable in exact
            missing = ~consistent.any(axis=0)      # arithmetic: as coulomb, the least violated
            self.chosen[missing] = violation[:, missing].argmin(axis=0)
            picked = self._pick()
        limits = self._limits
        limits[0] = c1
        forces = picked[2:4]
        forces = _clip(forces, limits, np.abs(forces))
        return picked[0], picked[1], forces[0], forces[1]

    def _pick(self):
        """The chosen pattern's ``x1, x2, f1, f2, violation`` at each node."""
        table = self.table
        return table.reshape(5, -1)[:, self.chosen * table.shape[2] + self._first]

    def _patterns(self, w1, w2, c1, mw1, mw2, size2):
        """Fill :attr:`table` (f2 of both stuck is ``mw2``, there already; ``size2 = |mw2|``):
        coulomb.pattern's expressions, operation by operation."""
        m1, m2, c2 = self.m1, self.m2, self.c2
        x1, x2, f1, f2, violation = self.table
        static = 0.0 - mw1   # the pipe's static reaction before the plug's share
        minus_c1 = -c1

        rows = _BOTH_STUCK
        f1_ = np.subtract(static, mw2, out=f1[rows])
        np.maximum(np.abs(f1_) - c1, size2 - c2, out=violation[rows])

        rows = _PIPE_STUCK
        x2_ = np.subtract(w2, self._dx2_pipe_stuck, out=x2[rows])
        f1_ = np.subtract(static, f2[rows], out=f1[rows])
        np.maximum(np.abs(f1_) - c1, x2_ * self._plug_ahead, out=violation[rows])

        rows = _TOGETHER
        f1_ = np.multiply(minus_c1, self._s1_together, out=f1[rows])
        x = np.divide(mw1 + mw2 + f1_, m1 + m2, out=x1[rows])
        x2[rows] = x
        f2_ = np.multiply(-m2, x - w2, out=f2[rows])
        np.maximum(x * self._together_behind, np.abs(f2_) - c2, out=violation[rows])

        rows = _SLIDING
        f1_ = np.multiply(minus_c1, self._s1_sliding, out=f1[rows])
        x1_ = np.add(w1, (f1_ + f2[rows]) / m1, out=x1[rows])
        x2_ = np.subtract(w2, self._dx2_sliding, out=x2[rows])
        np.maximum(x1_ * self._pipe_behind, (x1_ - x2_) * self._plug_behind,
                   out=violation[rows])


def _clip(f, c, size):
    """Clip static reactions ``f`` to their limits ``c``; ``size = |f|``. Written with ``where``
    so that a reaction within its limit is returned as it is, signed zero included."""
    return np.where(size > c, np.copysign(c, f), f)
