"""Exact references of the hard cases, independent of the solvers.

* :func:`closed_form_sequence` -- :mod:`pipeplug_references.closed_form` for each pulse, started
  from rest after the previous motion has ended. Model I is invariant under translation and
  under the mirror x -> -x, so a pull is the mirrored push and the responses add up.
* :func:`single_body_train` -- one body on one contact under blows that all arrive while it
  slides forward: uniform acceleration (Q - F1)/M1 on each piece, then a stop.
* :func:`free_rod_motion` -- a free elastic pipe (no friction) under an end force
  (d'Alembert): the travelling waves Q(t - s/c)/Z over the image distances s.
"""
from __future__ import annotations

import math

import numpy as np

from pipeplug_harness.paper import SYMBOLS
from pipeplug_references import closed_form as cf

__all__ = ["closed_form_sequence", "single_body_train", "free_rod_motion",
           "monitored_free_rod"]

_PAIRS = tuple(SYMBOLS.items())


def closed_form_sequence(case, times) -> dict:
    """Exact model I response to pulses that each start from rest.

    Parameters
    ----------
    case : HardCase
    times : array of float
        Sample times [s].

    Returns
    -------
    dict
        ``v_pipe``, ``v_plug`` [m/s], ``u_pipe``, ``u_plug`` [m] at ``times``.

    Raises
    ------
    ValueError
        If a pulse starts before the motion of the previous one has ended.
    """
    times = np.asarray(times, dtype=float)
    total = {ours: np.zeros_like(times) for ours, _ in _PAIRS}
    free_from = 0.0
    for start, duration, amplitude in sorted(case.pulses):
        if start < free_from * (1.0 - 1e-12):
            raise ValueError(f"{case.name}: a pulse at {start} s meets a motion lasting to "
                             f"{free_from} s; no closed form")
        one = case.rigid_case(amplitude, duration)
        free_from = start + max(*cf.stop_times(one), duration)
        late = times >= start
        sol = cf.solution(one, np.where(late, times - start, 0.0))
        sign = math.copysign(1.0, amplitude)
        for ours, theirs in _PAIRS:
            total[ours] += np.where(late, sign * sol[theirs], 0.0)
    return total


def single_body_train(case, times) -> dict:
    """One body (no plug) on one contact under blows >= 0 that all arrive while it moves.

    Velocity is piecewise linear: slope (Q - F1)/M1 between load edges, then a final
    deceleration F1/M1 to rest; displacement is its exact integral (trapezoids).

    Raises
    ------
    ValueError
        If the body comes to rest between two blows (the formula does not apply).
    """
    c = case.rigid_case()
    edges = sorted({0.0} | {e for s, d, _ in case.pulses for e in (s, s + d)})
    knot_t, knot_v = [0.0], [0.0]
    for a, b in zip(edges[:-1], edges[1:]):
        v = knot_v[-1] + (case.load(0.5 * (a + b)) - c.F1) / c.M1 * (b - a)
        if v <= 0.0:
            raise ValueError(f"{case.name}: the body stops within {a}..{b} s, between blows")
        knot_t.append(b)
        knot_v.append(v)
    knot_t.append(edges[-1] + knot_v[-1] * c.M1 / c.F1)     # the final stop
    knot_v.append(0.0)
    knot_t, knot_v = np.array(knot_t), np.array(knot_v)
    knot_u = np.concatenate([[0.0], np.cumsum(0.5 * (knot_v[1:] + knot_v[:-1])
                                              * np.diff(knot_t))])
    t = np.minimum(np.asarray(times, dtype=float), knot_t[-1])
    piece = np.clip(np.searchsorted(knot_t, t, side="right") - 1, 0, len(knot_t) - 2)
    v = np.interp(t, knot_t, knot_v)
    u = knot_u[piece] + 0.5 * (knot_v[piece] + v) * (t - knot_t[piece])
    zero = np.zeros_like(t)
    return {"v_pipe": v, "v_plug": zero, "u_pipe": u, "u_plug": zero}


def free_rod_motion(case, times, x: float, c: float, impedance: float):
    """d'Alembert velocity [m/s] and displacement [m] at section ``x`` [m] of a free pipe.

    v(x, t) = sum_k [Q(t - (2kL + x)/c) + Q(t - (2(k+1)L - x)/c)] / Z: both ends are force
    ends, so each reflects a velocity wave with its sign; u is the same sum of the impulses
    I(t - s/c) = integral of Q. ``c`` is the wave speed [m/s], ``impedance`` Z = rho c S [N s/m].
    """
    t = np.asarray(times, dtype=float)
    L = case.rigid_case().L1
    v, u = np.zeros_like(t), np.zeros_like(t)
    for k in range(int(c * t.max() / (2.0 * L)) + 1):
        for s in (2 * k * L + x, 2 * (k + 1) * L - x):
            arrival = np.maximum(t - s / c, 0.0)
            v += np.where(t - s / c >= 0.0, [case.load(a) for a in arrival], 0.0)
            u += _impulse(case, arrival)
    return v / impedance, u / impedance


def _impulse(case, t):
    """Impulse of the load from 0 to ``t`` [N s] (array)."""
    return sum((a * np.clip(t - s, 0.0, d) for s, d, a in case.pulses), np.zeros_like(t))


def monitored_free_rod(case, times, dx: float, c: float, impedance: float) -> dict:
    """The contract's monitored pipe velocity of a free pipe: linear interpolation between
    the two cell centres around ``x_monitor`` of the d'Alembert solution (plug outputs 0)."""
    L1 = case.rigid_case().L1
    s = min(max(case.params.get("x_monitor", 0.5) / dx - 0.5, 0.0), L1 / dx - 1.0)
    a = min(math.floor(s), round(L1 / dx) - 2)
    w = s - a
    va, ua = free_rod_motion(case, times, (a + 0.5) * dx, c, impedance)
    vb, ub = free_rod_motion(case, times, (a + 1.5) * dx, c, impedance)
    zero = np.zeros_like(va)
    return {"v_pipe": (1.0 - w) * va + w * vb, "v_plug": zero,
            "u_pipe": (1.0 - w) * ua + w * ub, "u_plug": zero}
