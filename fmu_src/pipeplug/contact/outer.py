"""Outer (soil/pipe) friction laws of the rigid models, one class per law.

The friction of the soil on a pipe sliding in direction ``s1`` is ``f1 = -s1 P1 tau1 Lc(U)``:

* :class:`ConstantContact` (model I): ``Lc = L1``.
* :class:`GrowingContact` (model II, docs/corrections.md C8/F): ``Lc = min(max(U, 0), L1)``; on each of its
  three segments ``f1`` is affine in ``U``, so a sliding body moves harmonically (forward),
  hyperbolically (backward) or uniformly (no contact, or full contact).
* :class:`NoContact` (tau1 = 0): absent.

Each law answers, for a body at ``U`` sliding in direction ``s1``: the segment it is on
(``f1 = force0 - kappa U`` there, and where the segment ends ahead), the limit for sticking,
and the friction work of a slide from ``Ua`` to ``Ub``.
"""
from __future__ import annotations

import math

__all__ = ["NoContact", "ConstantContact", "GrowingContact", "outer_contact_for"]


class NoContact:
    """No outer friction (tau1 = 0)."""

    def limit(self, U: float) -> float:
        """Static friction limit [N] at position ``U`` [m]."""
        return 0.0

    def segment(self, U: float, s1: int) -> tuple[float, float, float]:
        """``(force0 [N], kappa [N/m], end [m])`` with ``f1 = force0 - kappa U`` until ``end``."""
        return 0.0, 0.0, s1 * math.inf

    def work(self, Ua: float, d, s1: int):
        """Friction work [J] dissipated sliding from ``Ua`` by ``d`` [m] in direction ``s1``.

        The slide stays on the segment of ``Ua`` (a segment end is an event). ``d`` may be a
        numpy array (dense output).
        """
        return 0.0 * d


class ConstantContact(NoContact):
    """Model I: friction over the whole pipe length, limit ``F1 = P1 L1 tau1`` [N]."""

    def __init__(self, F1: float):
        self.F1 = F1

    def limit(self, U: float) -> float:
        return self.F1

    def segment(self, U: float, s1: int) -> tuple[float, float, float]:
        return -s1 * self.F1, 0.0, s1 * math.inf

    def work(self, Ua: float, d, s1: int):
        return s1 * self.F1 * d


class GrowingContact(NoContact):
    """Model II: friction over the penetrated length ``min(max(U, 0), L1)``.

    Parameters
    ----------
    k : float
        Friction limit per unit contact length, ``P1 tau1`` [N/m].
    L1 : float
        Pipe length [m].
    """

    def __init__(self, k: float, L1: float):
        self.k, self.L1 = k, L1

    def limit(self, U: float) -> float:
        return self.k * min(max(U, 0.0), self.L1)

    def segment(self, U: float, s1: int) -> tuple[float, float, float]:
        # Segment boundaries belong to the segment the body enters (by its direction).
        k, L1 = self.k, self.L1
        if U > L1 or (U == L1 and s1 > 0):
            return -s1 * k * L1, 0.0, (math.inf if s1 > 0 else L1)
        if U < 0.0 or (U == 0.0 and s1 < 0):
            return 0.0, 0.0, (0.0 if s1 > 0 else -math.inf)
        return 0.0, s1 * k, (L1 if s1 > 0 else 0.0)

    def work(self, Ua: float, d, s1: int):
        # k * integral of Lc over [Ua, Ua + d], Lc affine on the segment: d times the mean.
        force0, kappa, _ = self.segment(Ua, s1)
        return d * (kappa * (Ua + 0.5 * d) - force0)


def outer_contact_for(P1: float, L1: float, tau1: float, growth: bool) -> NoContact:
    """The outer friction law the parameters call for."""
    if tau1 == 0.0:
        return NoContact()
    if growth:
        return GrowingContact(P1 * tau1, L1)
    return ConstantContact(P1 * L1 * tau1)
