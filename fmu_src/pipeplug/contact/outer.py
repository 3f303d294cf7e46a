"""Outer (soil/pipe) friction laws of the rigid models.

The friction of the soil on a pipe sliding in direction ``s1`` is ``f1 = -s1 P1 tau1 Lc(U)``:

* :data:`CONSTANT` (model I): ``Lc = L1``.
* :data:`GROWING` (model II, docs/corrections.md C8/F): ``Lc = min(max(U, 0), L1)``; on each of its
  three segments ``f1`` is affine in ``U``, so a sliding body moves harmonically (forward),
  hyperbolically (backward) or uniformly (no contact, or full contact).
* :data:`NONE` (tau1 = 0): absent.

A law is the tuple ``(kind, F1 [N], k [N/m], L1 [m])`` made by :func:`outer_contact_for`
(``F1 = P1 L1 tau1``, ``k = P1 tau1``). For a body at ``U`` sliding in direction ``s1`` it
answers the segment it is on (``f1 = force0 - kappa U`` there, and where the segment ends
ahead), the limit for sticking, and the friction work of a slide. The functions take floats
and tuples only, so that numba compiles them (:func:`pipeplug.jit.jitable`) and Python runs
the same source.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import jitable

__all__ = ["NONE", "CONSTANT", "GROWING", "outer_contact_for", "limit", "segment", "work",
           "contact_length", "face_on"]

#: kinds of law (floats: a law is a tuple of floats)
NONE, CONSTANT, GROWING = 0.0, 1.0, 2.0


@jitable
def outer_contact_for(P1, L1, tau1, growth: bool, q_face=0.0) -> tuple:
    """The outer friction law the parameters call for (``P1`` [m], ``L1`` [m], ``tau1`` [Pa]:
    floats, or arrays for many cases at once, giving arrays).

    An end resistance (``q_face`` [Pa] > 0) needs the law's segments even without friction:
    in model II the front end meets the soil only at U >= 0 (:func:`face_on`).
    """
    on = (tau1 != 0.0) | (q_face != 0.0)
    kind = on * (GROWING if growth else CONSTANT)       # NONE where tau1 = q_face = 0
    return kind, P1 * L1 * tau1, P1 * tau1, L1


@jitable
def limit(law, U):
    """Static friction limit [N] at position ``U`` [m]."""
    kind, F1, k, L1 = law
    if kind == CONSTANT:
        return F1
    if kind == GROWING:
        return k * min(max(U, 0.0), L1)
    return 0.0


@jitable
def face_on(law, U):
    """1.0 where the pipe's front end at ``U`` [m] is in the soil when it advances, else 0.0:
    always in model I; in model II from the surface on (U >= 0, the segment a body moving
    forward from U = 0 enters), so the switch is a segment end, an event of the exact solver."""
    if law[0] == GROWING and U < 0.0:
        return 0.0
    return 1.0


@jitable
def contact_length(law, U):
    """The length of pipe in contact with the soil [m] at position(s) ``U`` [m]."""
    kind, _, _, L1 = law
    if kind == CONSTANT:
        return L1 + 0.0 * U
    if kind == GROWING:
        return np.minimum(np.maximum(U, 0.0), L1)
    return 0.0 * U


@jitable
def segment(law, U, s1):
    """``(force0 [N], kappa [N/m], end [m])``: ``f1 = force0 - kappa U`` on the segment of a body
    at ``U`` [m] sliding in direction ``s1``, until ``end``.

    Segment boundaries belong to the segment the body enters (by its direction).
    """
    kind, F1, k, L1 = law
    if kind == CONSTANT:
        return -s1 * F1, 0.0, s1 * math.inf
    if kind == GROWING:
        if U > L1 or (U == L1 and s1 > 0):
            return -s1 * k * L1, 0.0, (math.inf if s1 > 0 else L1)
        if U < 0.0 or (U == 0.0 and s1 < 0):
            return 0.0, 0.0, (0.0 if s1 > 0 else -math.inf)
        return 0.0, s1 * k, (L1 if s1 > 0 else 0.0)
    return 0.0, 0.0, s1 * math.inf


@jitable
def work(law, Ua, d, s1):
    """Friction work [J] dissipated sliding from ``Ua`` [m] by ``d`` [m] in direction ``s1``.

    The slide stays on the segment of ``Ua`` (a segment end is an event). ``d`` may be an array
    (dense output).
    """
    kind, F1, _, _ = law
    if kind == CONSTANT:
        return s1 * F1 * d
    if kind == GROWING:
        # k * integral of Lc over [Ua, Ua + d], Lc affine on the segment: d times the mean.
        force0, kappa, _ = segment(law, Ua, s1)
        return d * (kappa * (Ua + 0.5 * d) - force0)
    return 0.0 * d
