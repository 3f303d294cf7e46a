"""The rigid models I and II with a plug that grows (``plug_growth``) and clean-outs.

The plug is the soil inside the pipe, its front face at the pipe's front end (docs/physics.md,
"A plug that grows"). Its length ``L2`` changes only while it slides in the pipe:

* the pipe advances over it (``V1 > V2``, coring): soil at rest enters and joins it, ``L2``
  grows by the relative advance (momentum conserved; the energy lost is ``W_accretion``);
* the pipe moves back relative to it (``V1 < V2``): the plug moves out through the front end,
  ``L2`` shrinks by the relative retreat, and the soil that leaves, with the plug's velocity,
  comes to rest in the ground ahead (its kinetic energy joins ``W_accretion``); a plug that
  leaves entirely is gone (``L2 = 0``: the pipe alone, coring again as soon as it advances);
* it fills the pipe (``L2 = L1``): no more soil can enter, the pipe is plugged. The plug's
  rear end meets the head in a plastic impact (momentum conserved, the loss in
  ``W_accretion``), and pipe and plug move as one body, the plug's face pushing the soil
  ahead (``q_plug_face``), until the pipe is pulled back relative to the plug (the plug needs
  more than its friction limit to follow the pipe's deceleration): the plug slides ahead and
  shrinks as above.

A clean-out (:meth:`RigidGrowth.clean_out`) removes the plug down to ``L2_after_cleanout`` at
once; the removed soil's kinetic energy is ``W_removed``.

Exactness. A piece in which ``L2`` is constant (both at rest, the pipe carrying the plug, the
pipe alone, a plugged pipe) is the exact solver's own closed form (:mod:`pipeplug.rigid.pieces`,
:mod:`pipeplug.rigid.face`, run as plain Python on a parameter record that carries the current
``L2``). A piece in which the plug slides in the pipe changes ``L2`` with the relative
displacement: a nonlinear ODE without closed form, integrated to order 5
(:mod:`pipeplug.rigid.coring`).
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.outer import contact_length, face_on, limit, outer_contact_for, segment
from ..interface import ModelBase, Outputs
from . import coring
from .face import face_modes, face_work_at
from .motion import acceleration_at, time_to_position, ulp
from .pieces import AT_REST, SEGMENT, find_event, forces_of, law_of, pipe_of
from .record import (
    END,
    FACE1,
    KIND,
    N_STATE,
    P_COUPLED,
    P_F2,
    P_FACE,
    P_L2,
    P_LAW,
    P_M1,
    P_M2,
    P_QF,
    P_QP,
    S1,
    S2,
    T0,
    U1,
    W_FACE,
    Q,
    parameter_record,
    state_record,
)
from .stepping import (
    MAX_EVENTS_PER_STEP,
    pipe_plug_events,
    settle,
    start_piece,
    values_at,
)
from .stress import axial_extremes

__all__ = ["RigidGrowth"]

_EVENT_SNAP = 1e-13            # as the exact solver's: an event this close after a step's end
_EMPTY = 1e-10                 # of L1: a shorter plug is gone (at the start of a piece)
_EXTRUDE = 1 << 20             # a plugged pipe's plug starts sliding ahead (merged pieces)
_SLIDE_KEYS = 2 * coring.STATE_SIZE + 11   # origin y, node y, a Slide's scalars in a state


class RigidGrowth(ModelBase):
    """Rigid pipe and a plug that grows; exact pieces where the plug's length is constant, the
    plug's slides integrated (module docstring).

    Parameters
    ----------
    params : Params
        Validated parameters (``tau2 > 0``).
    options : Options
        ``contact_growth`` selects model II; ``plug_growth`` is on.
    """

    has_ram = False

    def __init__(self, params, options):
        self.params = params
        base = parameter_record(params, options.contact_growth)
        base[P_FACE] = 1.0              # modes always from the joint problem with end forces
        # A plugged pipe's front takes the plug's face resistance too, in model II from U1 = 0
        # on: the law needs that segment end even without shaft friction and q_face.
        law = outer_contact_for(params.P1, params.L1, params.tau1, options.contact_growth,
                                params.q_face + params.q_plug_face)
        base[P_LAW:P_LAW + 4] = law
        self._base = base
        self._law = law_of(base)
        self.M1 = params.M1
        self._mu = params.rho2 * params.S2      # plug mass per length [kg/m]
        self._k = params.P2 * params.tau2       # plug friction limit per length [N/m]
        self._qp, self._qf = params.F_plug_face, params.F_face
        self._l2 = float(params.L2)
        self._gap = float(params.L1 - params.L2)   # L1 - L2, exact near a full plug (coring)
        self._w_acc = self._w_rem = 0.0
        self._u2_keep = 0.0             # the plug's displacement while there is none
        self._merged = False            # plugged: pipe and plug one body of the exact solver
        self._gripped = False           # a plug of length 0 carried by the pipe (_grips)
        self._merge_origin = (0.0, 0.0)  # (U1, U2) where the merged piece started
        self._st = state_record()
        self._par = self._par_for(self._l2, False)
        self._slide: coring.Slide | None = None
        self._slide_w_in = 0.0          # the input work at the slide's origin [J]
        self._q = math.nan
        self._time = 0.0
        self._modes: list[tuple[int, int]] = []

    # protocol ----------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """The model's time [s]."""
        return self._time

    @time.setter
    def time(self, value: float) -> None:
        self._time = float(value)

    @property
    def M2(self) -> float:
        """The plug's mass now [kg]."""
        return self._mu * self._l2

    def _step_to(self, q: float, h: float, t_end: float) -> None:
        if q != self._q:
            self._restart(q)
        for _ in range(MAX_EVENTS_PER_STEP):
            if not self._next_event(t_end):
                self._time = t_end
                return
        raise RuntimeError(f"more than {MAX_EVENTS_PER_STEP} friction events in one step")

    def at_rest(self) -> bool:
        """Both bodies stuck with no load (none yet, NaN, in a fresh model): a step under
        Q = 0 changes nothing."""
        q = self._q
        return self._slide is None and self._st[KIND] == AT_REST and (q == 0.0 or q != q)

    def modes(self) -> tuple[tuple[int, int], ...]:
        """Every piece's contact modes (pipe_mode, plug_mode) in order, repeats merged."""
        return tuple(self._modes)

    def clean_out(self) -> None:
        """Remove the plug down to ``L2_after_cleanout`` now (nothing if it is shorter); the
        removed soil's kinetic energy is booked as ``W_removed``."""
        u1, v1, u2, v2, w = self._values(self._time)
        self._l2, self._w_acc, self._gap = w[5], w[4], w[6]      # a slide's, now
        keep = min(self.params.L2_after_cleanout, self._l2)
        if keep == self._l2:
            return
        self._w_rem += 0.5 * self._mu * (self._l2 - keep) * v2 * v2
        self._set_length(keep, u2)
        self._start(self._time, u1, v1, u2, v2 if keep > 0.0 else 0.0, w, self._q)

    def outputs(self) -> Outputs:
        """The contract's outputs at the current time."""
        t = self._time
        u1, v1, u2, v2, (w_in, w_outer, w_inner, w_face, w_acc, l2, _) = self._values(t)
        f1, f2, face1 = self._forces(t, u1)
        q = self._q if self._q == self._q else 0.0
        area = self.params.S1
        low, high = axial_extremes(q, f1, f2, self.params.L1, contact_length(self._law, u1),
                                   l2, face1)
        kinetic = 0.5 * (self.M1 * v1 * v1 + self._mu * l2 * v2 * v2)
        s1, s2 = self._modes[-1] if self._modes else (0, 0)
        return Outputs(v1, v2, u1, u2, f1, f2, w_in, w_outer + w_inner, w_outer, w_inner,
                       kinetic, 0.0, 0.0, q, 0.0, 0.0, 0.0, w_in, -q / area, float(low) / area,
                       float(high) / area, self.at_rest(), s1, s2, w_face,
                       0.0, l2, w_acc, self._w_rem)          # W_damping: no damping here

    # the plug's length -------------------------------------------------------------------
    def _par_for(self, l2: float, merged: bool) -> list:
        """The exact solver's constants for a plug of length ``l2`` [m]; ``merged``: pipe and
        plug as one body whose front end takes both end resistances."""
        par = list(self._base)
        coupled = l2 > 0.0
        par[P_L2] = l2
        if merged:
            par[P_M1] = self.M1 + self._mu * l2
            par[P_M2] = par[P_F2] = par[P_COUPLED] = par[P_QP] = 0.0
            par[P_QF] = self._qf + self._qp
        else:
            par[P_M2] = self._mu * l2 if coupled else 0.0
            par[P_F2] = self._k * l2 if coupled else 0.0
            par[P_COUPLED] = 1.0 if coupled else 0.0
            par[P_QP] = self._qp if coupled else 0.0
        return par

    def _set_length(self, l2: float, u2: float, gap: float | None = None) -> None:
        """The plug's length ``l2`` [m] and its gap to the head ``gap`` [m] (default
        ``L1 - l2``); ``u2`` [m] the plug's displacement, kept where it is gone."""
        if l2 <= 0.0:
            l2, gap, self._u2_keep = 0.0, None, u2
        self._l2 = l2
        self._gap = self.params.L1 - l2 if gap is None else gap

    # pieces ------------------------------------------------------------------------------
    def _values(self, t):
        """``(U1, V1, U2, V2, works)`` at ``t`` [s], works ``(W_input, W_outer, W_inner,
        W_face, W_accretion)`` [J] followed by the plug's length and its gap to the head [m]."""
        if self._slide is not None:
            sl = self._slide
            y = sl.value_at(t - sl.node_t)
            w_in = self._slide_w_in + sl.q * (y[0] - sl.u1_origin)
            v1 = y[1] if sl.s1 != 0 else 0.0
            return y[0], v1, y[2], sl.velocity2(y), (w_in, y[5], y[6], y[7], y[8], y[4], y[9])
        st, par = self._st, self._par
        u1, v1, u2, v2, w_in, w_outer, w_inner = values_at(st, par, t)
        w_face = face_work_at(st, t - st[T0])
        if self._merged or self._gripped:
            u2, v2 = self._merge_origin[1] + (u1 - self._merge_origin[0]), v1
        elif self._l2 == 0.0:
            u2, v2 = self._u2_keep, 0.0
        return u1, v1, u2, v2, (w_in, w_outer, w_inner, w_face, self._w_acc, self._l2,
                                self._gap)

    def _forces(self, t, u1):
        """``(F_outer, F_inner, the soil's force on the pipe's front end)`` [N] at ``t``."""
        if self._slide is not None:
            sl = self._slide
            f1, f2, e1, _ = sl.forces(sl.value_at(t - sl.node_t))
            return f1, f2, e1
        st, par = self._st, self._par
        f1, f2 = forces_of(st, par, u1)
        face1 = st[FACE1]
        if self._merged:                # the plug's share of the body's end force, its force
            e3 = self._plug_face_share()
            a = acceleration_at(pipe_of(st), u1) if st[KIND] != AT_REST else 0.0
            f2, face1 = -(self.M2 * a - e3) if st[KIND] != AT_REST else 0.0, face1 - e3
        return f1, f2, face1

    def _plug_face_share(self) -> float:
        """The plug's face force in a merged piece [N]: -Qp while the body advances (model II:
        from U1 >= 0 on, with the annulus)."""
        st = self._st
        on = face_on(self._law, st[U1])
        return -self._qp * on if st[KIND] != AT_REST and st[S1] > 0 else 0.0

    def _restart(self, q: float) -> None:
        """A new force ``q`` [N] from now: a new piece."""
        t = self._time
        u1, v1, u2, v2, w = self._values(t)
        self._l2, self._w_acc, self._gap = w[5], w[4], w[6]      # a slide's, now
        if self._slide is None:
            v1, v2 = settle(self._st, self._par, self._par[P_M1], v1, v2)
            if self._merged or self._l2 == 0.0:
                v2 = v1 if self._merged else 0.0
        self._start(t, u1, v1, u2, v2, w, q)

    def _start(self, t, u1, v1, u2, v2, w, q, kick=0):
        """Start the piece the modes at ``t`` [s] call for: a slide when the plug slides in the
        pipe (or the pipe advances with no plug: coring from nothing), else an exact piece."""
        self._q = q
        load = 0.0 if q != q else q
        if 0.0 < self._l2 <= _EMPTY * self.params.L1:
            # Shorter than round-off of the pipe's length: the plug is gone (its velocity, P
            # over a vanishing mass, no longer tells a mode); moving with the pipe, it may
            # grip it (_grips).
            self._set_length(0.0, u2)
            self._gripped = self._gripped or v2 == v1
            v2 = 0.0
        l2 = self._l2
        real = self._par_for(l2, False)
        coupled = l2 > 0.0
        s1, s2, s3, _, _, _ = face_modes(real, self.M1, load, u1, v1, v2 if coupled else 0.0,
                                         kick, 0)          # no ram pushes a held pipe here
        plugged = self._gap <= 0.0
        if coupled and s2 != 0 and not (plugged and s2 > 0):
            self._begin_slide(t, u1, v1, u2, v2, w, load, (s1, s2, s3))
        elif not coupled and s1 > 0 and not self._grips(u1, v1, load):
            self._begin_slide(t, u1, v1, u2, 0.0, w, load, (s1, 1, 0 if self._qp > 0 else 1))
        else:
            self._gripped = self._gripped and not coupled and s1 > 0
            self._begin_exact(t, u1, v1, u2, v2, w, q, kick, coupled and plugged)

    def _grips(self, u1, v1, load) -> bool:
        """Whether the soil at the front of an advancing pipe with no plug grips it instead of
        entering: the soil at the front moves with the pipe (the pipe starts from rest, or it
        gripped it already, or a plug of vanishing length stuck to it), there is no face
        resistance to hold it back, and the pipe's acceleration a1 is at most k/mu.

        That is the limit of a plug of vanishing length eps stuck to the pipe: it stays stuck
        while the force it needs, mu eps a1, is within its friction limit, k eps, whatever eps.
        A plug of length 0 from rest also admits a growing solution when a1 > k/(3 mu) (the
        self-similar V2 = c a1 t, c = k/(3 mu a1) < 1, :meth:`_nascent`), but for
        k/mu >= a1 it is not the limit of any plug of positive length, and for c > 5/7 it is
        unstable (its perturbations grow as t^lam, lam the larger root of
        lam^2 - (r - 5) lam + 6 = 0, r = 2c/(1 - c)): round-off then makes the plug catch up,
        stick, and leave the pipe again below round-off of L1, without end. The gripped
        plug keeps length 0, moving with the pipe, while the pipe advances with a1 <= k/mu."""
        if not (self._gripped or v1 == 0.0) or self._qp > 0.0:
            self._gripped = False
            return False
        force0, kappa, _ = segment(self._law, u1, 1.0)
        a1 = (load + force0 - kappa * u1 - self._qf * face_on(self._law, u1)) / self.M1
        self._gripped = self._k >= a1 * self._mu
        return self._gripped

    def _begin_exact(self, t, u1, v1, u2, v2, w, q, kick, merged):
        self._slide = None
        self._merged = merged
        self._par = par = self._par_for(self._l2, merged)
        st = self._st
        if merged or self._gripped:
            self._merge_origin, kick = (u1, u2), 0
        w_in, w_outer, w_inner, w_face = w[:4]
        st[W_FACE] = w_face
        start_piece(st, par, [], t, u1, v1, u2 if par[P_COUPLED] else 0.0,
                    v2 if par[P_COUPLED] else 0.0, w_in, w_outer, w_inner, q, kick, 0.0)
        s2 = int(st[S2]) if par[P_COUPLED] else 0
        self._log(int(st[S1]), s2)

    def _begin_slide(self, t, u1, v1, u2, v2, w, q, modes):
        s1, _, s3 = modes
        v2 = 0.0 if s3 == 0 else v2
        w_in, w_outer, w_inner, w_face, w_acc = w[:5]
        y0 = [u1, v1 if s1 != 0 else 0.0, u2, self._mu * self._l2 * v2, self._l2, w_outer,
              w_inner, w_face, w_acc, self._gap]
        if self._l2 == 0.0 and v1 == 0.0 and s3 != 0:
            t, y0, v2, w_in = self._nascent(t, y0, q, w_in)
        self._make_slide(t, y0, v2, modes, q, w_in)
        self._log(s1, modes[1])

    def _nascent(self, t, y0, q, w_in):
        """A plug growing from nothing behind a pipe starting from rest: the start is singular
        (V2 = P/(mu L2), both 0), so the slide starts after a time ``tau`` from its
        self-similar solution, V1 = a1 t, V2 = c a1 t, L2 = (1 - c) a1 t^2/2 with
        c = k/(3 mu a1) < 1/3 (:meth:`_grips`: stable); ``tau = 1e-8 sqrt(M1/k)`` leaves the next order,
        (k/M1) tau^2, below round-off. Returns the slide's origin ``(t, y0, V2, W_input)``."""
        u1 = y0[0]
        force0, kappa, _ = segment(self._law, u1, 1.0)
        face = self._qf * face_on(self._law, u1)
        a1 = (q + force0 - kappa * u1 - face) / self.M1
        c = self._k / (3.0 * self._mu * a1)
        tau = 1e-8 * math.sqrt(self.M1 / self._k)
        v1, d1 = a1 * tau, 0.5 * a1 * tau * tau
        v2, l2 = c * v1, (1.0 - c) * d1
        slip = (1.0 - c) * a1                   # V1 - V2 = slip t
        y = [u1 + d1, v1, y0[2] + c * d1, self._mu * l2 * v2, l2,
             y0[5] - (force0 - kappa * u1) * d1, y0[6] + self._k * (1.0 - c) * a1 * slip
             * tau ** 4 / 8.0, y0[7] + face * d1,
             y0[8] + self._mu * slip * (c * a1) ** 2 * tau ** 4 / 8.0, y0[9] - l2]
        return t + tau, y, v2, w_in + q * d1

    def _make_slide(self, t, y0, v2, modes, q, w_in):
        """The slide from ``y0`` at ``t`` [s] (:class:`~pipeplug.rigid.coring.Slide`), its
        constants from the pipe's position there."""
        s1 = modes[0]
        law, u1 = self._law, y0[0]
        on = face_on(law, u1)
        c = {"m1": self.M1, "mu": self._mu, "k": self._k, "L1": self.params.L1,
             "qp": self._qp, "face1": -self._qf * on if s1 > 0 else 0.0,
             "t1p": limit(law, u1) + self._qf * on, "t1m": limit(law, u1)}
        c["force0"], c["kappa"], c["end"] = (segment(law, u1, float(s1)) if s1 != 0
                                             else (0.0, 0.0, math.inf))
        self._slide = coring.Slide(t, y0, v2, modes, q, c)
        self._slide_w_in = w_in
        self._merged = False

    def _log(self, s1: int, s2: int) -> None:
        if not self._modes or self._modes[-1] != (s1, s2):
            self._modes.append((s1, s2))

    # events ------------------------------------------------------------------------------
    def _next_event(self, t_end: float) -> bool:
        """Take the piece's next event if it comes before ``t_end`` [s] (True), else False."""
        if self._slide is not None:
            t, y, labels = self._slide.first_event(t_end)
            if t is None:
                return False
            self._take_slide_event(t, y, labels)
            return True
        st, par = self._st, self._par
        horizon = max(t_end - st[T0], 0.0)
        dt, labels = find_event(st, par, horizon)
        if self._merged:
            dx = self._extrusion_time(min(dt, horizon))
            if dx < dt:
                dt, labels = dx, _EXTRUDE
        t_event = st[T0] + dt
        if not t_event - _EVENT_SNAP * t_event <= t_end:
            return False
        self._take_exact_event(t_event, labels)
        return True

    def _extrusion_time(self, t_lim) -> float:
        """In a merged piece: when, within ``t_lim`` [s], the plug needs more than its friction
        limit to follow the body's deceleration (``M2 a - e3 = -F2``), so that it slides ahead
        (model II: the acceleration changes with the position; model I: constant, decided at
        the start)."""
        st = self._st
        pipe = pipe_of(st)
        if st[KIND] == AT_REST or pipe[3] == 0.0 or not t_lim > 0.0:
            return math.inf
        target = (self._plug_face_share() - self._k * self._l2) / self.M2
        return time_to_position(pipe, st[U1] + (pipe[2] - target) / pipe[3], t_lim,
                                2.0 * ulp(st[T0] + t_lim))

    def _take_exact_event(self, t, labels):
        st, par = self._st, self._par
        u1, v1, u2, v2, w = self._values(t)
        m1 = par[P_M1]
        kick = 0
        if labels != _EXTRUDE:
            v1, v2, kick = pipe_plug_events(st, par, labels & ~_EXTRUDE, m1, v1, v2)
        if labels & SEGMENT:
            if st[S2] == 0:
                u2 += st[END] - u1
            u1, kick = st[END], 0
        if self._merged:
            v2, kick = v1, (-1 if labels & _EXTRUDE else 0)
        elif self._l2 == 0.0:
            self._u2_keep, v2 = u2, 0.0
        self._start(t, u1, v1, u2, v2, w, st[Q], kick)

    def _take_slide_event(self, t, y, labels):
        sl = self._slide
        u1, u2, l2, gap = y[0], y[2], y[4], y[9]
        v1 = y[1] if sl.s1 != 0 else 0.0
        v2 = sl.velocity2(y)
        w_in = self._slide_w_in + sl.q * (u1 - sl.u1_origin)
        w_acc = y[8]
        s1, s2, s3 = sl.s1, sl.s2, sl.s3
        if labels & coring.PIPE_REST:
            v1 = 0.0
        if labels & coring.PLUG_STOP:
            v2 = 0.0
        if labels & coring.SEGMENT:
            u1 = sl.c["end"]
        if labels & coring.STICK:
            m2 = self._mu * l2
            v1 = v2 = (self.M1 * v1 + m2 * v2) / (self.M1 + m2) if s1 != 0 else 0.0
        if labels & coring.FULL:        # the plug meets the head: a plastic impact
            l2, gap = self.params.L1, 0.0
            m2 = self._mu * l2
            v = (self.M1 * v1 + m2 * v2) / (self.M1 + m2)
            w_acc += 0.5 * (self.M1 * v1 * v1 + m2 * v2 * v2 - (self.M1 + m2) * v * v)
            v1 = v2 = v
        self._w_acc = w_acc
        self._set_length(0.0 if labels & coring.EMPTY else l2, u2, gap)
        if self._l2 == 0.0:
            v2 = 0.0
        w = (w_in, y[5], y[6], y[7], w_acc)
        if labels in (coring.PIPE_GO, coring.PLUG_GO):
            # A held body starts moving: the direction its load leaves the window (deciding
            # again would hold it, the load being at the limit).
            if labels == coring.PIPE_GO:
                s1 = 1 if sl.q - s2 * self._k * l2 > 0.0 else -1
            else:
                s3 = 1 if s2 * self._k * l2 > 0.0 else -1
            self._q = sl.q
            self._begin_slide(t, u1, v1, u2, v2, w, sl.q, (s1, s2, s3))
            return
        self._start(t, u1, v1, u2, v2, w, self._q)

    # state -------------------------------------------------------------------------------
    def get_state(self) -> dict:
        """The whole state: the plug's length and losses, the exact piece's record, the slide's
        origin and node (zeros when none), the modes gone through."""
        slide = np.zeros(_SLIDE_KEYS)
        sl = self._slide
        if sl is not None:
            n = coring.STATE_SIZE
            slide[:n], slide[n:2 * n] = sl.y0, sl.node_y
            slide[2 * n:] = (1.0, sl.t0, sl.v2_origin, sl.s1, sl.s2, sl.s3, sl.q, sl.node_t, sl.h,
                          sl.steps, self._slide_w_in)
        return {"time": self._time, "q": self._q, "L2_now": self._l2, "gap": self._gap,
                "W_accretion": self._w_acc,
                "W_removed": self._w_rem, "u2_keep": self._u2_keep,
                "merged": float(self._merged), "gripped": float(self._gripped),
                "merge_u1": self._merge_origin[0],
                "merge_u2": self._merge_origin[1], "record": np.array(self._st, dtype=float),
                "slide": slide, "modes": np.array(self._modes, dtype=np.int64).reshape(-1, 2)}

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state`."""
        self._time, self._q = float(state["time"]), float(state["q"])
        self._l2, self._w_acc = float(state["L2_now"]), float(state["W_accretion"])
        self._gap = float(state["gap"])
        self._w_rem, self._u2_keep = float(state["W_removed"]), float(state["u2_keep"])
        self._merged, self._gripped = bool(state["merged"]), bool(state["gripped"])
        self._merge_origin = (float(state["merge_u1"]), float(state["merge_u2"]))
        self._st = [float(x) for x in np.asarray(state["record"])][:N_STATE]
        self._par = self._par_for(self._l2, self._merged)
        self._modes = [(int(a), int(b)) for a, b in np.asarray(state["modes"]).reshape(-1, 2)]
        slide = [float(x) for x in np.asarray(state["slide"])]
        self._slide = None
        n = coring.STATE_SIZE
        if slide[2 * n] == 1.0:
            t0, v2, s1, s2, s3, q, node_t, h, steps, w_in = slide[2 * n + 1:]
            self._make_slide(t0, slide[:n], v2, (int(s1), int(s2), int(s3)), q, w_in)
            sl = self._slide
            sl.node_t, sl.node_y, sl.h, sl.steps = node_t, slide[n:2 * n], h, int(steps)
