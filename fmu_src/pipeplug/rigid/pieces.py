"""Pieces of rigid motion between two events, and the events that end them.

A piece starts from an origin state with fixed contact modes and a constant force Q. Its
motion is known in closed form (:class:`~pipeplug.rigid.motion.Motion`), so every quantity at a time
``dt`` after the origin is evaluated from the origin (never accumulated step by step): the
outputs do not depend on how a host slices time.

Kinds of piece (s1 = pipe/soil mode, s2 = pipe/plug mode, 0 = stuck):

* :class:`AtRest`     s1 = 0, s2 = 0: nothing moves; friction forces are static reactions.
* :class:`PlugSlides` s1 = 0, s2 != 0: the pipe is held by the soil, the plug slides in it.
* :class:`Together`   s1 != 0, s2 = 0: pipe and plug move as one body (or the pipe alone when
  there is no plug); ends when it stops, changes contact segment, or the plug breaks away.
* :class:`BothSlide`  s1 != 0, s2 != 0: ends when the pipe stops, changes contact segment, or
  the relative velocity vanishes.

Events are labelled: ``"pipe_rest"``, ``"plug_rest"``, ``"stick"``, ``"segment"``,
``"breakaway+"``/``"breakaway-"`` (the plug starts sliding with s2 = +1/-1).
"""
from __future__ import annotations

import math

from .motion import Motion, refine_root

__all__ = ["AtRest", "PlugSlides", "Together", "BothSlide"]

_INF = math.inf


class _Piece:
    """Common data: origin time ``t0`` [s], modes, struck-end force ``Q`` [N]."""

    s1 = 0
    s2 = 0

    def __init__(self, t0, Q, origin):
        self.t0, self.Q = t0, Q
        self.U1, self.V1, self.U2, self.V2 = origin

    def find_event(self, horizon: float) -> tuple[float, tuple[str, ...]]:
        """Time after ``t0`` of the first event within ``horizon`` [s], and its labels."""
        return _INF, ()

    def _resolution(self, t_lim: float) -> float:
        """The resolution of absolute time near ``t0 + t_lim`` [s]: an event time after
        ``t0`` is not better known than this, so root searches stop there."""
        return 2.0 * math.ulp(self.t0 + t_lim)


class AtRest(_Piece):
    """Pipe stuck to the soil and plug stuck to the pipe (both at rest)."""

    def __init__(self, t0, Q, origin, f1, f2):
        super().__init__(t0, Q, origin)
        self.f1, self.f2 = f1, f2

    def travel(self, dt):
        """Displacements since the origin [m] and velocities [m/s] at ``dt`` [s] after it:
        ``(d1, V1, d2, V2)`` (floats, or arrays for an array ``dt``)."""
        zero = 0.0 * dt
        return zero, zero, zero, zero

    def forces(self, U1):
        """Friction forces on the pipe ``(f1, f2)`` [N] when the pipe is at ``U1``."""
        zero = 0.0 * U1
        return self.f1 + zero, self.f2 + zero

    def friction_work(self, d1, d2):
        """Friction work [J] since the origin, outer and inner, after displacements ``d1``,
        ``d2`` [m] of pipe and plug."""
        zero = 0.0 * d1
        return zero, zero


class PlugSlides(_Piece):
    """Pipe held by the soil; the plug slides with constant deceleration ``s2 F2 / M2``."""

    def __init__(self, t0, Q, origin, s2, f1, F2, M2):
        super().__init__(t0, Q, origin)
        self.s2, self.f1, self.F2 = s2, f1, F2
        self.plug = Motion(self.U2, self.V2, s2 * F2 / M2)

    def travel(self, dt):
        d2, V2 = self.plug.travel(dt)
        zero = 0.0 * dt
        return zero, zero, d2, V2

    def forces(self, U1):
        zero = 0.0 * U1
        return self.f1 + zero, -self.s2 * self.F2 + zero

    def friction_work(self, d1, d2):
        return 0.0 * d1, -self.F2 * self.s2 * d2

    def find_event(self, horizon):
        # The plug moves with sign -s2 (the pipe is at rest).
        return self.plug.time_to_rest(-self.s2), ("plug_rest",)


class Together(_Piece):
    """Pipe (and plug, if coupled) sliding as one body of mass ``Mj`` on the soil."""

    def __init__(self, t0, Q, origin, s1, outer, Mj, plug_limit, M2):
        super().__init__(t0, Q, origin)
        self.s1, self.outer = s1, outer
        force0, kappa, self.end = outer.segment(self.U1, s1)
        self.force0, self.kappa = force0, kappa
        a0 = (Q + force0 - kappa * self.U1) / Mj
        self.pipe = Motion(self.U1, self.V1, a0, kappa / Mj)   # the pipe carries the plug
        self.plug_limit, self.M2 = plug_limit, M2   # plug_limit = F2/M2, or None (no plug)

    def travel(self, dt):
        d1, V1 = self.pipe.travel(dt)
        if self.plug_limit is None:
            return d1, V1, 0.0 * d1, 0.0 * d1
        return d1, V1, d1, V1

    def forces(self, U1):
        f1 = self.force0 - self.kappa * U1
        if self.plug_limit is None:
            return f1, 0.0 * U1
        return f1, -self.M2 * self.pipe.acceleration_at(U1)

    def friction_work(self, d1, d2):
        return self.outer.work(self.U1, d1, self.s1), 0.0 * d1

    def find_event(self, horizon):
        body, s1 = self.pipe, self.s1
        t_rest = body.time_to_rest(s1)
        t_lim = min(t_rest, horizon)
        found = [(t_rest, "pipe_rest")]
        found.append((body.time_to_position(self.end, t_lim, self._resolution(t_lim)),
                      "segment"))
        if self.plug_limit is not None and body.k != 0.0:
            found.extend(self._breakaways(t_lim))
        return _earliest(found)

    def _breakaways(self, t_lim):
        """Times at which the plug's static force reaches its limit, with their labels.

        The plug needs -f2 = M2 a(U), a(U) = a0 - k (U - U0); it breaks away where s a(U)
        reaches F2/M2 (s = +1: breakaway+, s = -1: breakaway-). The piece may start with
        s a0 at the limit to round-off (it was chosen by the projection's slack): then the
        plug breaks away at once if s a grows as the body moves, else never on this side.
        """
        body, limit = self.pipe, self.plug_limit
        moving = self.s1 * body.k             # s a(U) grows as the body moves iff -s moving > 0
        for s, label in ((1, "breakaway+"), (-1, "breakaway-")):
            if s * body.a0 >= limit:
                if -s * moving > 0.0:
                    yield 0.0, label
                continue
            U_lim = self.U1 + (body.a0 - s * limit) / body.k
            yield body.time_to_position(U_lim, t_lim, self._resolution(t_lim)), label


class BothSlide(_Piece):
    """Pipe sliding on the soil and the plug sliding in the pipe."""

    def __init__(self, t0, Q, origin, s1, s2, outer, M1, F2, M2):
        super().__init__(t0, Q, origin)
        self.s1, self.s2, self.outer, self.F2 = s1, s2, outer, F2
        force0, kappa, self.end = outer.segment(self.U1, s1)
        self.force0, self.kappa = force0, kappa
        a0 = (Q + force0 - kappa * self.U1 - s2 * F2) / M1
        self.pipe = Motion(self.U1, self.V1, a0, kappa / M1)
        self.plug = Motion(self.U2, self.V2, s2 * F2 / M2)

    def travel(self, dt):
        d1, V1 = self.pipe.travel(dt)
        d2, V2 = self.plug.travel(dt)
        return d1, V1, d2, V2

    def forces(self, U1):
        return self.force0 - self.kappa * U1, -self.s2 * self.F2 + 0.0 * U1

    def friction_work(self, d1, d2):
        # The plug's work is >= 0 (its force opposes the relative motion), but the relative
        # displacement is a difference of two: a piece that starts at zero relative velocity
        # and acceleration (a breakaway) and is cut short by another event can leave it below
        # their round-off, of either sign (-1e-33 J once). Dissipation is never negative.
        inner = self.F2 * self.s2 * (d1 - d2)
        return self.outer.work(self.U1, d1, self.s1), inner * (inner > 0.0)

    def find_event(self, horizon):
        pipe = self.pipe
        t_rest = pipe.time_to_rest(self.s1)
        t_lim = min(t_rest, horizon)
        xtol = self._resolution(t_lim)
        found = [(t_rest, "pipe_rest"), (pipe.time_to_position(self.end, t_lim, xtol), "segment"),
                 (self._time_to_stick(t_lim), "stick")]
        return _earliest(found)

    def _time_to_stick(self, t_lim: float) -> float:
        """First zero in (0, t_lim] of g(t) = V1(t) - V2(t), of sign s2 at the start.

        g'' = -k V1 keeps one sign inside the piece (V1 does not change sign), so g' is
        monotone: split at the zero of g' (a position crossing, U1 = U1_0 + (a0 - a2)/k) and
        search each monotone part for a sign change.
        """
        pipe, plug, s2 = self.pipe, self.plug, self.s2
        da = pipe.a0 - plug.a0
        if pipe.k == 0.0:   # g is linear
            g0 = s2 * (self.V1 - self.V2)
            return g0 / (-s2 * da) if s2 * da < 0.0 else _INF
        if not math.isfinite(t_lim):
            return _INF

        def g(t):
            return pipe.travel(t)[1] - plug.travel(t)[1]

        def dg(t):
            return pipe.acceleration_at(pipe.state(t)[0]) - plug.a0

        xtol = self._resolution(t_lim)
        t_mid = min(pipe.time_to_position(self.U1 + da / pipe.k, t_lim, xtol), t_lim)
        a = 0.0
        for b in (t_mid, t_lim):
            if b <= a:
                continue
            gb = s2 * g(b)
            if gb <= 0.0:
                if s2 * g(a) > 0.0:
                    return b if gb == 0.0 else refine_root(g, dg, a, b, xtol)
                if a > 0.0 or self.V1 != self.V2:
                    return a
                # Started at zero relative velocity (a breakaway): there the relative
                # acceleration is zero too, and the plug's mode says which way the relative
                # velocity goes. A first part going the other way is round-off, not a stick.
            a = b
        return _INF


def _earliest(found):
    """The earliest time and every label within round-off of it."""
    t_min = min(t for t, _ in found)
    if t_min == _INF:
        return _INF, ()
    tol = 8.0 * math.ulp(max(t_min, 1e-300)) + 1e-15 * t_min
    return t_min, tuple(label for t, label in found if t <= t_min + tol)
