"""Exact event-driven solver of the rigid models I and II (to round-off).

Equations (paper eqs. (1)-(3) and (11), docs/corrections.md A6, B4, C7/C8)::

    M1 U1'' = Q + f1 + f2,      M2 U2'' = -f2
    f1 in -P1 Lc tau1 Sign(U1'),   f2 in -P2 L2 tau2 Sign(U1' - U2')

with ``Lc = L1`` (model I) or ``Lc = min(max(U1, 0), L1)`` (model II, ``contact_growth``), and
Sign(0) = [-1, 1] (static limit = sliding limit). Q is constant over each step. Between events
the motion is closed-form (:mod:`pipeplug.rigid.pieces`); at each event the contact modes are
chosen by solving both contacts jointly (:func:`pipeplug.contact.coulomb.two_contacts`).
Exact solution for a rectangular pulse: the closed form of model I, domains I-V.

Energy: W_input = kinetic energy + W_friction holds to round-off.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.coulomb import SLACK, one_contact, two_contacts
from ..contact.outer import outer_contact_for
from ..interface import OUTPUT_NAMES, ModelBase, Outputs
from .pieces import AtRest, BothSlide, PlugSlides, Together

__all__ = ["RigidExact"]

_MAX_EVENTS_PER_STEP = 100_000
_EVENT_SNAP = 1e-13          # relative: an event this close after a step end is taken in it
_SNAP_LIMIT = 1e-9           # relative: largest believable round-off of a segment crossing
_SNAP_FLOOR = 1e-12          # of the pipe length: round-off of positions near a segment end
_STATE_KEYS = ("time", "t0", "U1", "V1", "U2", "V2", "W_in", "W_outer", "W_inner", "Q", "kick",
               "horizon")


class RigidExact(ModelBase):
    """Rigid pipe (and plug), exact stepping. See the module docstring.

    Parameters
    ----------
    params : Params
        Validated parameters.
    options : Options
        ``contact_growth`` selects model II; ``solver`` must be ``"exact"``.
    """

    def __init__(self, params, options):
        self.M1 = params.M1
        self.coupled = params.has_plug
        self.M2 = params.M2 if self.coupled else 0.0
        self.F2 = params.F2 if self.coupled else 0.0
        self.outer = outer_contact_for(params.P1, params.L1, params.tau1, options.contact_growth)
        self._project = self._project_pair if self.coupled else self._project_alone
        self.time = 0.0
        # At rest, under no force yet (Q = nan): the first advance starts the first real piece.
        self._W0, self._kick, self._horizon = (0.0, 0.0, 0.0), 0, 0.0
        self._piece = AtRest(0.0, math.nan, (0.0, 0.0, 0.0, 0.0), 0.0, 0.0)
        self._modes: list[tuple[int, int]] = []      # every piece's (s1, s2), repeats merged
        self._t_event = self._t_snap = self._searched = math.inf
        self._labels = ()

    # Stepping ---------------------------------------------------------------------------
    def _step_to(self, q: float, h: float, t_end: float) -> None:
        """Advance to ``t_end`` [s] under a constant struck-end force ``q`` [N] (events are
        times, so only ``t_end`` matters)."""
        if q == self._piece.Q and t_end < self._t_snap and t_end <= self._searched:
            self.time = t_end            # the common case: no event inside the step
            return
        if q != self._piece.Q:
            self._restart(q, t_end)
        for _ in range(_MAX_EVENTS_PER_STEP):
            if t_end > self._searched:
                self._search(max(t_end - self._piece.t0, 2.0 * self._horizon))
            if t_end < self._t_snap:
                self.time = t_end
                return
            self._take_event()
        raise RuntimeError(f"more than {_MAX_EVENTS_PER_STEP} friction events in one step")

    def _restart(self, q: float, t_end: float) -> None:
        """Start a new piece at the current time under a new force ``q``, looking for its
        events up to ``t_end`` [s]."""
        U1, V1, U2, V2, *works = self._values_at(self.time)
        p = self._piece
        if p.s1 and V1 * p.s1 < 0.0:      # round-off past a stop that was not reached
            V1 = 0.0
        if p.s2 and (V1 - V2) * p.s2 < 0.0:
            V1 = V2 = self._common_velocity(V1, V2) if p.s1 else V1
        self._start_piece(self.time, (U1, V1, U2, V2), works, q, 0, t_end - self.time)

    def _take_event(self) -> None:
        """Move the origin to the next event, set the exact post-event values, re-decide modes."""
        t = self._t_event
        U1, V1, U2, V2, *works = self._values_at(t)
        kick = 0
        for label in self._labels:
            if label == "pipe_rest":
                V1 = 0.0
                if self._piece.s2 == 0:
                    V2 = 0.0
            elif label == "plug_rest" or (label == "stick" and "pipe_rest" in self._labels):
                V2 = V1
            elif label == "stick":
                V1 = V2 = self._common_velocity(V1, V2)
            elif label == "segment":
                U1, U2 = self._snap_to_segment_end(U1, U2)
            else:
                kick = 1 if label == "breakaway+" else -1
        if "segment" in self._labels:
            # The plug reaches its limit just as the pipe changes contact segment: whether it
            # slips depends on the new segment (its required force may stop growing there);
            # the new piece decides, breaking away at once if the force still grows.
            kick = 0
        if not self.coupled:
            U2 = V2 = 0.0
        searched_to = self._piece.t0 + self._horizon
        self._start_piece(t, (U1, V1, U2, V2), works, self._piece.Q, kick,
                          max(searched_to - t, 0.0))

    def _common_velocity(self, V1: float, V2: float) -> float:
        """The velocity [m/s] of pipe and plug sticking together while the pipe slides.

        The stick time is a root to round-off, where the relative velocity is a round-off
        ``d`` (the pipe's deceleration times a few ulps of time). Momentum is conserved: the
        plug's friction is internal, so this is the together-motion's velocity at that time
        to second order, and the kinetic energy changes by only M1 M2 d^2 / (2 (M1 + M2)).
        Setting the plug to the pipe's velocity instead would change it by M2 V2 d, which a
        heavy plug and a hard-braking pipe make visible in the energy balance (4e-12 of the
        work at M2 = 127 M1).
        """
        return (self.M1 * V1 + self.M2 * V2) / (self.M1 + self.M2)

    def _snap_to_segment_end(self, U1: float, U2: float) -> tuple[float, float]:
        """Put the pipe exactly on the segment end it reached (and a plug moving with it).

        The event time is a root to round-off, so the move is round-off; a larger one means
        the event was found at the wrong time, and is raised rather than hidden.
        """
        p = self._piece
        end = p.end
        # Round-off of the position, and the way covered in a few ulps of the event time (a
        # crossing sooner after the piece start than time can resolve is taken at its start).
        dt = 4.0 * math.ulp(max(self._t_event, p.t0 + self._horizon))   # the search's own
        a = abs(p.pipe.acceleration_at(U1))
        allowed = (_SNAP_LIMIT * (abs(end - p.U1) + abs(end)) + dt * (abs(p.V1) + a * dt)
                   + _SNAP_FLOOR * p.outer.L1)     # segments are model II's: L1 sets the scale
        if not abs(U1 - end) <= allowed:
            raise RuntimeError(f"segment event at U1 = {U1!r} m, {end!r} m expected")
        if p.s2 == 0:                     # the plug moves with the pipe: same shift
            U2 += end - U1
        return end, U2

    def _start_piece(self, t0, origin, works, q, kick, horizon=0.0) -> None:
        """Start a piece at ``t0`` from ``origin`` = (U1, V1, U2, V2) with the ``works``
        (input, outer and inner friction [J]) done so far."""
        origin = tuple(map(float, origin))    # numpy scalars from dense output -> floats
        self._W0 = tuple(map(float, works))
        self._kick = kick
        self._piece = self._make_piece(t0, origin, 0.0 if math.isnan(q) else q, kick)
        self._piece.Q = q
        mode = (self._piece.s1, self._piece.s2)
        if not self._modes or self._modes[-1] != mode:
            self._modes.append(mode)
        self._search(horizon)

    def _search(self, horizon: float) -> None:
        """Look for the piece's next event up to ``horizon`` [s] after its origin."""
        self._horizon = horizon
        dt, self._labels = self._piece.find_event(horizon)
        self._t_event = self._piece.t0 + dt
        # A step ending within round-off of an event takes it: otherwise a grazing stop
        # (velocity and acceleration vanishing together) would leave a velocity of 1e-14 m/s
        # that a load at the friction limit never removes.
        self._t_snap = self._t_event - _EVENT_SNAP * self._t_event if dt < math.inf else math.inf
        self._searched = self._piece.t0 + horizon if dt > horizon else math.inf

    # Modes ------------------------------------------------------------------------------
    def _make_piece(self, t0, origin, q, kick):
        """Decide the contact modes at ``origin`` under ``q`` and build the piece."""
        U1, V1, U2, V2 = origin
        s1 = (V1 > 0.0) - (V1 < 0.0)
        s2 = ((V1 > V2) - (V1 < V2)) if self.coupled else 0
        c1 = self.outer.limit(U1)
        f1_sliding = -s1 * c1 if s1 else 0.0
        f2_sliding = -s2 * self.F2
        w1 = (q + f1_sliding + f2_sliding) / self.M1
        w2 = -f2_sliding / self.M2 if self.coupled else 0.0
        p1, p2, f1s, f2s = self._project(w1, w2, 0.0 if s1 else c1, 0.0 if s2 else self.F2)
        s1 = s1 or p1
        s2 = s2 or kick or p2
        origin = (U1, V1, U2, V2)
        if s1 == 0 and s2 == 0:
            return AtRest(t0, q, origin, f1_sliding + f1s, f2_sliding + f2s)
        if s1 == 0:
            return PlugSlides(t0, q, origin, s2, f1_sliding + f1s, self.F2, self.M2)
        if s2 == 0:
            plug_limit = self.F2 / self.M2 if self.coupled else None
            return Together(t0, q, origin, s1, self.outer, self.M1 + self.M2, plug_limit,
                            self.M2)
        return BothSlide(t0, q, origin, s1, s2, self.outer, self.M1, self.F2, self.M2)

    def _project_pair(self, w1, w2, c1, c2):
        _, _, f1, f2, p1, p2 = two_contacts(self.M1, self.M2, w1, w2, c1, c2, 0.0)
        return p1, p2, f1, f2

    def _project_alone(self, w1, w2, c1, c2):
        # The round-off share two_contacts always allows: a load at the limit to round-off
        # (1 ulp above it, as Q = F1 computed in another order) holds the pipe, plug or not.
        x1, f1 = one_contact(self.M1, w1, c1, SLACK * (abs(self.M1 * w1) + c1))
        return (x1 > 0.0) - (x1 < 0.0), 0, f1, 0.0

    def sample(self, q: float, times, names=OUTPUT_NAMES) -> dict:
        """Dense output: advance to ``times[-1]`` under a constant ``q`` [N], recording outputs.

        Each piece is evaluated once for all the sample times it covers (numpy), so a long
        record costs about as much as its events. Same values as :meth:`advance` followed by
        :meth:`outputs` at each time.

        Parameters
        ----------
        q : float
            Struck-end force [N].
        times : array of float
            Increasing absolute times [s], all later than the current time.
        names : sequence of str, optional
            The outputs to record (default: all of :class:`~pipeplug.model.Outputs`).

        Returns
        -------
        dict of arrays
            One array per requested output name.
        """
        times = np.asarray(times, dtype=float)
        rows = [OUTPUT_NAMES.index(name) for name in names]
        table = np.empty((len(rows), len(times)))
        q = float(q)
        if q != self._piece.Q:
            self._restart(q, float(times[-1]))
        # Kinematics alone need no forces or works: evaluate only what is asked for.
        evaluate = self._kinematics_at if max(rows) < 4 else self._outputs_at
        t_last, done = float(times[-1]), 0
        while done < len(times):
            if t_last > self._searched:
                self._search(max(t_last - self._piece.t0, 2.0 * self._horizon))
            upto = int(np.searchsorted(times, self._t_snap, side="left"))
            if upto > done:
                values = evaluate(times[done:upto])
                for i, row in enumerate(rows):
                    table[i, done:upto] = values[row]
                done = upto
            if done < len(times):
                self._take_event()
        self.time = t_last
        return dict(zip(names, table))

    # Outputs and state ------------------------------------------------------------------
    def _values_at(self, t):
        """``(U1, V1, U2, V2, W_input, W_outer, W_inner)`` at absolute time(s) ``t`` [s]."""
        p = self._piece
        d1, V1, d2, V2 = p.travel(t - p.t0)
        W_in, W_outer, W_inner = self._W0
        outer, inner = p.friction_work(d1, d2)
        if p.Q == p.Q:                        # nan before the first step
            W_in = W_in + p.Q * d1
        return p.U1 + d1, V1, p.U2 + d2, V2, W_in, W_outer + outer, W_inner + inner

    def outputs(self) -> Outputs:
        """The contract's outputs at the current time."""
        out = self._outputs_at(self.time)
        return Outputs(*out[:10], bool(out[10]), *out[11:])

    def _kinematics_at(self, t):
        """``(V1, V2, U1, U2)`` at absolute time(s) ``t`` inside the current piece."""
        p = self._piece
        d1, V1, d2, V2 = p.travel(t - p.t0)
        return V1, V2, p.U1 + d1, p.U2 + d2

    def _outputs_at(self, t):
        """Output values at absolute time(s) ``t`` inside the current piece."""
        U1, V1, U2, V2, W_in, W_outer, W_inner = self._values_at(t)
        f1, f2 = self._piece.forces(U1)
        rest = self.at_rest() + 0.0 * U1         # (an array for dense output)
        return (V1, V2, U1, U2, f1, f2, W_in, W_outer + W_inner, W_outer, W_inner, rest,
                self._piece.s1, self._piece.s2)

    def at_rest(self) -> bool:
        """Both bodies stuck with no load: a step under Q = 0 changes nothing but the time."""
        return isinstance(self._piece, AtRest) and self._piece.Q == 0.0

    def energies(self) -> tuple[float, float, float]:
        """Kinetic energy [J]; rigid bodies store no elastic energy and reverse no work."""
        _, V1, _, V2, *_ = self._values_at(self.time)
        return 0.5 * (self.M1 * V1 * V1 + self.M2 * V2 * V2), 0.0, 0.0

    def modes(self) -> tuple[tuple[int, int], ...]:
        """Every piece's contact modes (pipe_mode, plug_mode) in order, repeats merged."""
        return tuple(self._modes)

    def get_state(self) -> dict:
        """The whole state: the current piece's origin, its force and search horizon, and the
        modes gone through."""
        p = self._piece
        state = dict(zip(_STATE_KEYS, (self.time, p.t0, p.U1, p.V1, p.U2, p.V2, *self._W0,
                                       p.Q, self._kick, self._horizon)))
        state["modes"] = np.array(self._modes, dtype=np.int64).reshape(-1, 2)
        return state

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state`; the piece is rebuilt deterministically."""
        s = {k: state[k] for k in _STATE_KEYS}
        self._modes = [tuple(map(int, row)) for row in np.asarray(state["modes"]).reshape(-1, 2)]
        self._start_piece(float(s["t0"]), (float(s["U1"]), float(s["V1"]), float(s["U2"]),
                                           float(s["V2"])),
                          (s["W_in"], s["W_outer"], s["W_inner"]), float(s["Q"]), int(s["kick"]),
                          float(s["horizon"]))
        self.time = float(s["time"])
