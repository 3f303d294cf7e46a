"""The one numerical piece of the rigid models: the plug sliding in the pipe while it grows.

With ``plug_growth`` the plug is the soil inside the pipe, its front face at the pipe's front
end (docs/physics.md, "A plug that grows"): while the plug slides in the pipe its length follows
the relative displacement, ``L2' = V1 - V2``, and with it its mass ``mu L2`` (``mu = rho2 S2``)
and its friction limit ``k L2`` (``k = P2 tau2``). Soil entering at rest adds no momentum; soil
leaving through the front end carries the plug's::

    M1 V1' = Q + f1(U1) + e1 - s2 k L2                  (s1 != 0; V1 = 0 while s1 = 0)
    P'     = s2 k L2 + e3 - mu (V2 - V1)+ V2,   V2 = P / (mu L2)     (P = 0 while s3 = 0)
    L2'    = V1 - V2,   W_accretion' = mu |V1 - V2| V2^2 / 2,   G' = V2 - V1

``G = L1 - L2``, the gap between the plug and the head, is integrated beside ``L2`` and carried
from piece to piece: the plug fills the pipe where ``G = 0``, a root known to the precision of
the gap itself, where ``L1 - L2`` with ``L2`` near ``L1`` is only known to round-off of ``L1``
(a plug pulled 1e-8 m out and driven back filled the pipe 1e-16 m off, and the velocity a
share of 1e-9 off after it: fuzz growth 4043:6960).

``f1`` is the soil's shaft friction on the piece's contact segment (affine in U1), ``e1``, ``e3``
the end resistances of the piece's modes. The plug's momentum ``P``, not its velocity, is
integrated: a plug growing from ``L2 = 0`` has ``V2 = P/(mu L2)`` smooth (``V2 ~ k t / (2 mu)``),
where ``V2'`` itself holds ``(V1 - V2) V2 / L2``. A plug that leaves through the front end with
no face resistance on it is the other way round: its momentum and its length vanish together
where it leaves, ``P/(mu L2)`` is 0/0 there (a plug 2.8e-9 m long took a velocity of round-off
size times 1e9 and booked 3.9e-6 J of W_accretion that no energy paid for: fuzz growth
4092:3357), while its velocity is smooth, ``V2' = s2 k / mu`` (the soil that leaves takes its
own momentum): the entry ``P`` then holds ``V2`` itself (:attr:`Slide.carries_v2`).

This piece has no closed form (the pipe's force depends on the relative displacement, the
plug's mass on it too): it is integrated by the classical Runge-Kutta method on step doubling
with Richardson extrapolation (order 5), with a step control on the doubling's error estimate,
on a grid of steps that starts at the piece's origin and never depends on where the host's
communication points fall. An event is a root of one of the piece's event functions on the
extrapolated step from the node before it (a bracketed secant, Illinois), so the values at an
event and between nodes are those of one order-5 step from a node.

Everything here is plain Python on floats (the numba-compiled exact solver never runs it).
"""
from __future__ import annotations

import math

__all__ = ["Slide", "RTOL", "ORDER", "STATE_SIZE", "step", "PIPE_REST", "STICK", "PLUG_STOP",
           "SEGMENT", "FULL", "EMPTY", "PIPE_GO", "PLUG_GO"]

#: the order of the extrapolated step (classical RK4 doubled, Richardson: 4 + 1)
ORDER = 5
#: the relative error per step the step control keeps (of the piece's scales)
RTOL = 1e-13
#: the most steps one piece takes before the solver reports it
MAX_STEPS = 200_000

#: events of a piece (bits): the pipe stops; the relative velocity vanishes; the plug stops in
#: the soil (its face's force switches); the pipe reaches its contact segment's end; the plug
#: fills the pipe; the plug leaves the pipe entirely; a held pipe starts sliding (its needed
#: force left the soil's window); a plug held by its face starts moving
PIPE_REST, STICK, PLUG_STOP, SEGMENT, FULL, EMPTY, PIPE_GO, PLUG_GO = (
    1, 2, 4, 8, 16, 32, 64, 128)

#: the most passes of the look at an event found (each takes an earlier crossing of another
#: of the at most 8 event functions)
_PASSES = 8

# the state vector's entries
_U1, _V1, _U2, _P, _L2, _WO, _WI, _WF, _WA, _GAP = range(10)
#: the length of the state vector
STATE_SIZE = 10


class Slide:
    """A piece in which the plug slides in the pipe (``s2 != 0``) and its length changes.

    Parameters
    ----------
    t0 : float
        The piece's origin [s].
    y0 : list of float
        ``[U1, V1, U2, P, L2, W_outer, W_inner, W_face, W_accretion, G]`` at the origin [m,
        m/s, m, kg m/s, m, J, J, J, J, m] (``P`` the plug's momentum, ``G = L1 - L2`` the gap
        to the head).
    v2 : float
        The plug's velocity at the origin [m/s] (the one defined where ``L2 = 0``).
    modes : tuple of int
        ``(s1, s2, s3)``: pipe/soil, pipe/plug (+1: the pipe advances over the plug), plug/soil
        (0: held by its face, ``P = 0``).
    q : float
        The struck-end force [N].
    c : dict
        The constants: ``m1`` [kg], ``mu`` [kg/m], ``k`` [N/m], ``L1`` [m], ``qp`` [N] (the plug
        face's limit), ``face1`` [N] (the soil's force on the sliding pipe's annulus, <= 0),
        ``force0`` [N], ``kappa`` [N/m], ``end`` [m] (the shaft friction ``force0 - kappa U1`` up
        to ``end``), ``t1p``, ``t1m`` [N] (a held pipe's window, forward and backward).
    """

    def __init__(self, t0, y0, v2, modes, q, c):
        self.t0, self.q, self.c = float(t0), float(q), c
        self.s1, self.s2, self.s3 = modes
        self.v2_origin = float(v2)
        self.u1_origin = y0[_U1]
        #: the entry P holds the plug's velocity: it leaves with no face resistance on it
        self.carries_v2 = self.s2 < 0 and (self.s3 < 0 or (self.s3 > 0 and c["qp"] == 0.0))
        self.y0 = list(y0)
        self.scale = _scales(y0, v2, q, c)
        if self.carries_v2:
            self.y0[_P] = self.v2_origin
            self.scale[_P] = self.scale[_V1]
        self.node_t, self.node_y = self.t0, list(self.y0)
        self.h = self._first_step()
        self.steps = 0
        self._next = None             # the step after the node: (h, y, h_next), once computed

    # the model --------------------------------------------------------------------------
    def velocity2(self, y):
        """The plug's velocity [m/s] in the state ``y``."""
        if self.s3 == 0:
            return 0.0
        if self.carries_v2:
            return y[_P]
        mass = self.c["mu"] * y[_L2]
        return y[_P] / mass if mass > 0.0 else self.v2_origin

    def forces(self, y):
        """``(f1, f2, e1, e3)`` [N]: the soil's shaft friction and the plug's friction on the
        pipe, the soil's end forces on the pipe's annulus and on the plug's face (a held body's:
        its static reaction, the shaft holding first)."""
        c, s2 = self.c, self.s2
        f2 = -s2 * c["k"] * y[_L2]
        e3 = (-c["qp"] if self.s3 > 0 else 0.0) if self.s3 != 0 else f2
        if self.s1 != 0:
            return c["force0"] - c["kappa"] * y[_U1], f2, c["face1"], e3
        needed = -(self.q + f2)
        shaft = min(max(needed, -c["t1m"]), c["t1m"])
        return shaft, f2, needed - shaft, e3

    def rate(self, y):
        """The time derivative of the state ``y``."""
        c, s2 = self.c, self.s2
        v1 = y[_V1] if self.s1 != 0 else 0.0
        v2 = self.velocity2(y)
        f1, f2, e1, e3 = self.forces(y)
        a1 = (self.q + f1 + e1 + f2) / c["m1"] if self.s1 != 0 else 0.0
        dp = 0.0
        if self.carries_v2:           # mu L2 V2' = s2 k L2 (e3 = 0): the soil leaving takes
            dp = s2 * c["k"] / c["mu"]    # its own momentum
        elif self.s3 != 0:
            dp = -f2 + e3
            if s2 < 0:                # soil leaves at the plug's velocity, with its momentum
                dp -= c["mu"] * (v2 - v1) * v2
        slip = s2 * (v1 - v2)         # >= 0 in the piece
        return [v1, a1, v2, dp, v1 - v2, -f1 * v1, c["k"] * y[_L2] * slip, -e1 * v1 - e3 * v2,
                0.5 * c["mu"] * slip * v2 * v2, v2 - v1]

    def events(self, y):
        """The event functions at ``y``: positive inside the piece, each with its label."""
        c = self.c
        v1 = y[_V1] if self.s1 != 0 else 0.0
        v2 = self.velocity2(y)
        out = [(self.s2 * (v1 - v2), STICK)]
        if self.s1 != 0:
            out.append((self.s1 * v1, PIPE_REST))
            if math.isfinite(c["end"]):
                out.append((self.s1 * (c["end"] - y[_U1]), SEGMENT))
        else:
            net = self.q - self.s2 * c["k"] * y[_L2]
            out.append((c["t1p"] - net, PIPE_GO))
            out.append((c["t1m"] + net, PIPE_GO))
        if self.s3 != 0:
            if c["qp"] > 0.0:
                out.append((self.s3 * v2, PLUG_STOP))
        else:
            load = self.s2 * c["k"] * y[_L2]     # the friction pushing the held plug ahead
            out.append((c["qp"] - load, PLUG_GO))
            out.append((load, PLUG_GO))
        out.append((y[_GAP], FULL) if self.s2 > 0 else (y[_L2], EMPTY))
        return out

    # integration -------------------------------------------------------------------------
    def _first_step(self):
        """A first step [s] far below the piece's time scales (the control grows it)."""
        c, y = self.c, self.node_y
        force = abs(self.q) + c["t1p"] + c["t1m"] + c["k"] * c["L1"] + c["qp"] + 1e-300
        mass = c["m1"] + c["mu"] * max(y[_L2], 1e-6 * c["L1"])
        return 1e-6 * math.sqrt(mass * c["L1"] / force)

    def _extrapolated(self, y, h):
        """One step of ``h`` [s] from ``y``: the extrapolated value and its error estimate."""
        big = _rk4(self.rate, y, h)
        half = _rk4(self.rate, _rk4(self.rate, y, 0.5 * h), 0.5 * h)
        err = max(abs(b - a) / (sc + RTOL * abs(b))
                  for a, b, sc in zip(big, half, self.scale))
        # The plug's velocity P/(mu L2) to the same share where the plug is short (a plug
        # leaving the pipe with its face held back decelerates as 1/L2).
        length = abs(half[_L2])
        if self.s2 > 0:
            # A growing plug's length to a share of itself (it only grows here): a plug
            # growing from nothing is self-similar, L2 ~ t^2, and would otherwise take steps
            # of its own age with an error of its own size.
            # (No finer than the round-off of the positions it is the difference of.)
            floor = 1e-15 * (abs(half[_U1]) + abs(half[_U2])) + 1e-300
            err = max(err, abs(half[_L2] - big[_L2]) / (RTOL * length + floor))
        else:
            length = max(length, 1e-9 * self.c["L1"])
        if not self.carries_v2:
            mass = self.c["mu"] * length
            err = max(err, abs(half[_P] - big[_P]) / (mass * self.scale[_V1]
                                                       + RTOL * abs(half[_P]) + 1e-300))
        return [h2 + (h2 - h1) / 15.0 for h1, h2 in zip(big, half)], err

    def value_at(self, dt_node, y=None):
        """The state ``dt_node`` [s] after the current node (within its next step)."""
        y = self.node_y if y is None else y
        if dt_node <= 0.0:
            return list(y)
        return self._extrapolated(y, dt_node)[0]

    def next_step(self):
        """The step after the current node: ``(h, y_next)``, computed once (step control on the
        doubling's error: accepted when it is at most the tolerance)."""
        if self._next is None:
            h = self.h
            for _ in range(200):
                y1, err = self._extrapolated(self.node_y, h)
                if err <= 1.0:
                    grow = 4.0 if err == 0.0 else min(4.0, 0.9 * err ** (-1.0 / ORDER))
                    self._next = (h, y1, h * grow)
                    break
                h *= max(0.1, 0.9 * err ** (-1.0 / ORDER))
            else:
                raise RuntimeError("the growing plug's step control found no step")
        return self._next[:2]

    def accept(self):
        """Move the node to the end of its next step."""
        h, y1, h_next = self._next
        self.node_t, self.node_y, self.h = self.node_t + h, y1, h_next
        self._next = None
        self.steps += 1
        if self.steps > MAX_STEPS:
            raise RuntimeError(f"more than {MAX_STEPS} steps in one growing plug's piece")

    def first_event(self, t_end):
        """Integrate to the first event before ``t_end`` [s] or past ``t_end``.

        Returns
        -------
        (t, y, labels) : the event's time [s], state and labels, or ``(None, None, 0)`` when
        no event comes before ``t_end`` (the node then lies at or before ``t_end``, its next
        step past it).
        """
        while True:
            h, y1 = self.next_step()
            found = self._event_in(h, y1)
            if found is not None:
                dt, labels = found
                t = self.node_t + dt
                if t <= t_end:
                    return t, self.value_at(dt), labels
                return None, None, 0
            if self.node_t + h > t_end:
                return None, None, 0
            self.accept()

    def _event_in(self, h, y1):
        """The first event within the node's next step: ``(dt, labels)`` or None.

        A function positive at both ends of the step may have gone through zero and back
        inside it, before the event found there: the plug's length, monotone in a piece, turns
        back past a stick, the step's end lying beyond it (fuzz growth 4081:3405, a plug
        sliding back into a held pipe went 1.9e-6 m past L1 as it stopped). So the functions
        are looked at again at the event found, and an earlier crossing taken from there."""
        found = self._crossing(h, y1)
        for _ in range(_PASSES):
            if found is None or not found[0] > 0.0:
                break
            dt, labels = found
            y = self.value_at(dt)
            if all(g > 0.0 or label & labels for g, label in self.events(y)):
                break
            found = self._crossing(dt, y)
        return found

    def _crossing(self, h, y1):
        """The first zero of a function negative (or 0) at ``y1``, ``h`` [s] after the node:
        ``(dt, labels)`` or None."""
        ends = self.events(y1)
        if all(g > 0.0 for g, _ in ends):
            return None
        starts = self.events(self.node_y)
        best, labels = math.inf, 0
        for k, (g1, label) in enumerate(ends):
            if g1 > 0.0:
                continue
            g0 = starts[k][0]
            dt = 0.0 if g0 <= 0.0 and self.node_t > self.t0 else self._root(k, g0, g1, h)
            if dt < best - _tol(best, self.node_t):
                best, labels = dt, label
            elif dt <= best + _tol(best, self.node_t):
                labels |= label
        return best, labels

    def _root(self, k, g0, g1, h):
        """The zero of event function ``k`` in (0, h] (``g0 > 0 >= g1``; Illinois secant)."""
        if g0 <= 0.0:                 # at the origin: a function starting at 0, going down
            g0, a = 0.0, 0.0
            return a if g1 < 0.0 and self._going_down(k) else self._first_sign(k, h)
        a, b, ga, gb = 0.0, h, g0, g1
        side = 0
        xtol = 4.0 * math.ulp(self.node_t + h)
        for _ in range(200):
            if b - a <= xtol:
                break
            m = (a * gb - b * ga) / (gb - ga) if ga != gb else 0.5 * (a + b)
            if not a < m < b:
                m = 0.5 * (a + b)
            gm = self.events(self.value_at(m))[k][0]
            if gm > 0.0:
                a, ga = m, gm
                if side == 1:
                    gb *= 0.5
                side = 1
            else:
                b, gb = m, gm
                if side == -1:
                    ga *= 0.5
                side = -1
        return b

    def _going_down(self, k):
        """True when event function ``k``, zero at the origin, is negative just after it."""
        dt = 1e-9 * self.h
        return self.events(self.value_at(dt))[k][0] <= 0.0

    def _first_sign(self, k, h):
        """An event function zero at the origin, positive just after it: its next zero in the
        step, by bisection on its values (None of them: the step's end)."""
        a, b = 1e-9 * self.h, h
        xtol = 4.0 * math.ulp(self.node_t + h)
        while b - a > xtol:
            m = 0.5 * (a + b)
            if self.events(self.value_at(m))[k][0] > 0.0:
                a = m
            else:
                b = m
        return b


def step(rate, y, h):
    """One extrapolated step (for the order test): RK4 twice at ``h/2`` and once at ``h``,
    combined by Richardson's rule."""
    big = _rk4(rate, y, h)
    half = _rk4(rate, _rk4(rate, y, 0.5 * h), 0.5 * h)
    return [h2 + (h2 - h1) / 15.0 for h1, h2 in zip(big, half)]


def _rk4(rate, y, h):
    """One classical Runge-Kutta step of ``h`` [s] from ``y``."""
    k1 = rate(y)
    k2 = rate([a + 0.5 * h * b for a, b in zip(y, k1)])
    k3 = rate([a + 0.5 * h * b for a, b in zip(y, k2)])
    k4 = rate([a + h * b for a, b in zip(y, k3)])
    return [a + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4)
            for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4)]


def _scales(y, v2, q, c):
    """Absolute error scales of the state's entries (RTOL of the piece's own magnitudes)."""
    force = abs(q) + c["t1p"] + c["t1m"] + c["k"] * c["L1"] + c["qp"]
    mass = c["m1"] + c["mu"] * c["L1"]
    v = max(abs(y[_V1]), abs(v2), math.sqrt(force * c["L1"] / mass), 1e-300)
    length = c["L1"]
    work = force * length + 0.5 * mass * v * v
    return [RTOL * s for s in (length, v, length, c["mu"] * length * v, length, work, work,
                               work, work, length)]


def _tol(t, t0):
    """Event times closer than this [s] are one event."""
    return 8.0 * math.ulp(max(abs(t0) + abs(t) if math.isfinite(t) else 1.0, 1e-300))
