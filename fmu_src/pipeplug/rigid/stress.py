"""Axial force along a rigid pipe from its equilibrium (the rigid models' stress outputs).

A rigid pipe of mass ``M1`` and length ``L1`` accelerates as one body under the head force
``F_head`` (at x = 0, positive into the soil), the soil's friction ``F_outer`` spread evenly
over its contact (the last ``Lc`` of the pipe), the plug's ``F_inner`` spread evenly over the
plug (the last ``L2``) and the soil's end resistance ``F_face`` (<= 0) on its front end, x = L1.
The axial force (tension positive) is then piecewise linear::

    N(x) = -F_head + (F_head + F_outer + F_inner + F_face) x / L1
           - F_outer max(0, x - (L1 - Lc)) / Lc - F_inner max(0, x - (L1 - L2)) / L2

(the inertia of the part before x less the friction on it), F_face at x = L1; its extremes lie
at x = 0, L1 - Lc, L1 - L2 or L1.
"""
from __future__ import annotations

import numpy as np

from ..interface import profile_sections
from ..jit import compiled_form, jitable

__all__ = ["axial_force_at", "axial_extremes", "RigidProfiles"]


@jitable
def _spread(force, start, length, x):
    """The part of ``force`` spread evenly over [start, start + length] that lies before x
    (the pipe ends at start + length, so nothing lies past it: a length of 0 gives 0)."""
    return force * np.maximum(x - start, 0.0) / np.maximum(length, 1e-300)


@jitable
def axial_force_at(x, head, outer, inner, L1, Lc, L2, face=0.0):
    """N(x) [N] (module docstring); forces may be arrays (dense output), ``face`` [N] a float."""
    total = head + outer + inner
    if face != 0.0:                   # (no addition of 0: the signs of zeros stay those of before)
        total = total + face
    return (-head + total * (x / L1) - _spread(outer, L1 - Lc, Lc, x)
            - _spread(inner, L1 - L2, L2, x))


def _maximum(a, b):
    """``np.maximum(a, b)`` of two floats, value and sign of zero (of two equal values the
    second; NaN if either is), without a ufunc call's cost."""
    return a if (a > b or a != a) else b


def _minimum(a, b):
    """``np.minimum(a, b)`` of two floats, likewise."""
    return a if (a < b or a != a) else b


def _scalar_extremes(head, outer, inner, L1, Lc, L2, face):
    """:func:`axial_extremes` of floats, operation for operation, with :func:`_maximum` and
    :func:`_minimum` for numpy's (the plain-Python path calls it at every step)."""
    def force_at(x):
        total = head + outer + inner
        if face != 0.0:
            total = total + face
        return (-head + total * (x / L1)
                - outer * _maximum(x - (L1 - Lc), 0.0) / _maximum(Lc, 1e-300)
                - inner * _maximum(x - (L1 - L2), 0.0) / _maximum(L2, 1e-300))

    at_contact, at_plug = force_at(L1 - Lc), force_at(L1 - L2)
    end = 0.0 * head if face == 0.0 else face + 0.0 * head
    low = _minimum(_minimum(-head, end), _minimum(at_contact, at_plug))
    high = _maximum(_maximum(-head, end), _maximum(at_contact, at_plug))
    return low, high


@jitable
def _array_extremes(head, outer, inner, L1, Lc, L2, face=0.0):
    """:func:`axial_extremes` with numpy's operations: floats or arrays (the compiled form)."""
    at_contact = axial_force_at(L1 - Lc, head, outer, inner, L1, Lc, L2, face)
    at_plug = axial_force_at(L1 - L2, head, outer, inner, L1, Lc, L2, face)
    end = 0.0 * head if face == 0.0 else face + 0.0 * head
    low = np.minimum(np.minimum(-head, end), np.minimum(at_contact, at_plug))
    high = np.maximum(np.maximum(-head, end), np.maximum(at_contact, at_plug))
    return low, high


@compiled_form(_array_extremes)
def axial_extremes(head, outer, inner, L1, Lc, L2, face=0.0):
    """The smallest and largest axial force along the pipe [N]: of N at the head (-F_head), at
    the front end (F_face, 0 without end resistance) and at the two breaks; floats, or arrays
    over times (dense output)."""
    if isinstance(head, float) and isinstance(Lc, float):
        return _scalar_extremes(head, outer, inner, L1, Lc, L2, face)
    return _array_extremes(head, outer, inner, L1, Lc, L2, face)


class RigidProfiles:
    """The profiles of a rigid model (:data:`pipeplug.interface.PROFILES`): its velocities and
    displacement are the same at every section; the axial stress is N(x) / S1 at the sections,
    with the outputs' head and friction forces and the contact length of their instant.

    Parameters
    ----------
    params : Params
        The model's parameters.
    growth : bool
        Model II: the soil's contact is the penetrated length min(max(u_pipe, 0), L1).
    n : int
        Number of sections.
    """

    def __init__(self, params, growth: bool, n: int):
        self.x, _ = profile_sections(params.L1, params.L2, n)
        self.L1, self.S1, self.growth = params.L1, params.S1, growth
        self.L2 = params.L2 if params.has_plug else 0.0

    def __call__(self, model) -> tuple:
        o = model.outputs()
        Lc = min(max(o.u_pipe, 0.0), self.L1) if self.growth else self.L1
        stress = axial_force_at(self.x, o.F_head, o.F_outer, o.F_inner, self.L1, Lc,
                                self.L2) / self.S1
        n = self.x.size
        return (np.full(n, o.v_pipe), np.full(n, o.u_pipe), stress, np.full(n, o.v_plug))
