"""Exact event-driven solver of the rigid model I with Smith damping (to round-off).

Equations (docs/physics.md, "Smith damping"; without damping those of
:mod:`pipeplug.rigid.exact` with end resistance, :mod:`pipeplug.rigid.face`)::

    M1 U1'' = Q + f1 + e1 + f2,         M2 U2'' = -f2 + e3
    f1 in -T1 Sign(U1') - J_shaft T1 U1'                 T1 = P1 L1 tau1
    e1 in -Qf Sign+(U1') - J_face Qf max(U1', 0)         Qf = q_face S1
    f2 in -F2 Sign(U1' - U2') - J_shaft F2 (U1' - U2')   F2 = P2 L2 tau2
    e3 in -Qp Sign+(U2') - J_face Qp max(U2', 0)         Qp = q_plug_face S2

The dampers act only while a contact slides (a stuck contact has no sliding speed), so the
sticking limits are the static ones. Between events the sliding bodies feel constant forces and
linear dampers: the pieces are closed forms of exponentials (:mod:`pipeplug.rigid.linear`; pipe
and plug sliding on each other are a coupled pair, decoupled by its eigenvectors). Every event
is a zero of a constant plus at most two exponentials, located to round-off on monotone parts:

* a sliding body or contact comes to rest (``PIPE_REST``, ``STICK``, ``PLUG_STOP``);
* a static force reaches its limit: the carried plug breaks away (the force it needs changes
  with the velocity now), a pipe held by the soil under a sliding plug breaks loose (the
  plug's damping force on it changes), a plug held by its face under a sliding pipe breaks
  loose (``BREAK_*``).

At each event the modes are decided jointly (:func:`pipeplug.contact.face.face_contacts`, the
sliding contacts' forces, dampers included, taken at the current velocities; while the plug
slides in the pipe, each body apart, :func:`pipeplug.contact.face.sliding_pair`). Outputs are
evaluated from the piece's origin, never accumulated, so they do not depend on the host's
communication points. Model II is refused with damping (:func:`pipeplug.build_model`): the
damper of a growing shaft friction, ``J_shaft P1 tau1 U1 U1'``, is not linear.

Ledger: ``W_input = E_kinetic + W_friction + W_face + W_damping`` to round-off, ``W_face`` the
work of the static end resistances, ``W_damping`` that of every damper. ``F_outer`` and
``F_inner`` are the shaft's and the plug's whole resistance, their dampers' parts included.

Plain Python (no compiled path): a damped model is built only when damping is asked for.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.coulomb import SLACK
from ..contact.face import face_contacts, one_sided, sign, sliding_pair
from ..interface import ModelBase, Outputs
from .linear import LinearPiece
from .stress import axial_extremes

__all__ = ["RigidDamped", "MAX_EVENTS_PER_STEP"]

MAX_EVENTS_PER_STEP = 100_000
#: kinds of piece
REST, PLUG, TOGETHER, BOTH, CORING = range(5)
#: event labels (bits) and what each sets: (velocity rule, kicked contact, direction)
PIPE_REST, STICK, PLUG_STOP = 1, 2, 4
PIPE_FWD, PIPE_BACK, BREAK_POS, BREAK_NEG, FACE_FWD, FACE_BACK = 8, 16, 32, 64, 128, 256
_KICKS = ((PIPE_FWD, 0, 1), (PIPE_BACK, 0, -1), (BREAK_POS, 1, 1), (BREAK_NEG, 1, -1),
          (FACE_FWD, 2, 1), (FACE_BACK, 2, -1))
_STATE_KEYS = ("time", "t0", "q", "U1", "V1", "U2", "V2", "W_in", "W_outer", "W_inner",
               "W_face", "W_damp", "s1", "s2", "s3", "f1s", "f2s", "f3s")


class RigidDamped(ModelBase):
    """Rigid pipe (and plug) of model I with Smith damping, exact stepping (module docstring).

    Parameters
    ----------
    params : Params
        Validated parameters.
    options : Options
        ``solver = "exact"``, ``contact_growth`` false.
    """

    def __init__(self, params, options):
        self.coupled = bool(params.has_plug)
        self.M1 = params.M1
        self.M2 = params.M2 if self.coupled else 0.0
        self.F2 = params.F2 if self.coupled else 0.0
        self.T1, self.Qf = params.F1, params.F_face
        self.Qp = params.F_plug_face if self.coupled else 0.0
        self.a_shaft, self.a_face = params.J_shaft * self.T1, params.J_face * self.Qf
        self.d2 = params.J_shaft * self.F2
        self.a3 = params.J_face * self.Qp
        self.L1, self.L2, self.S1 = params.L1, (params.L2 if self.coupled else 0.0), params.S1
        self.time = 0.0
        self._modes: list[tuple[int, int]] = []
        self._o = dict.fromkeys(_STATE_KEYS, 0.0)
        self._o["q"] = math.nan
        self._searched = 0.0         # events are known absent up to this time after t0
        self._build()

    # -- the piece ----------------------------------------------------------------------------
    def _decide(self, q, v1, v2, kicks) -> tuple:
        """The modes ``(s1, s2, s3)`` from velocities ``v1``, ``v2`` [m/s] under ``q`` [N] and
        the static forces of the stuck contacts (soil on pipe, plug on pipe, soil on plug)."""
        e1 = sign(v1) or kicks[0]
        e2 = (sign(v1 - v2) or kicks[1]) if self.coupled else 0
        e3 = (sign(v2) or kicks[2]) if self.coupled else 0
        c1p, c1m = self.T1 + self.Qf, self.T1
        f1 = f2 = f3 = 0.0                # the sliding contacts' forces, dampers included
        if e1 > 0:
            f1 = -c1p - (self.a_shaft + self.a_face) * v1
        elif e1 < 0:
            f1 = c1m - self.a_shaft * v1
        if e2 != 0:
            f2 = -e2 * self.F2 - self.d2 * (v1 - v2)
        if e3 > 0:
            f3 = -self.Qp - self.a3 * v2
        w1 = (q + f1 + f2) / self.M1
        if self.coupled:
            w2 = (f3 - f2) / self.M2
            c1s, c1ms, c3s = 0.0 if e1 else c1p, 0.0 if e1 else c1m, 0.0 if e3 else self.Qp
            if e2 != 0:                   # the bodies apart, each with its own round-off
                _, _, g1, g2, g3, p1, p2, p3 = sliding_pair(self.M1, self.M2, w1, w2, c1s,
                                                            c1ms, c3s)
            else:
                _, _, g1, g2, g3, p1, p2, p3 = face_contacts(self.M1, self.M2, w1, w2, c1s,
                                                             c1ms, self.F2, c3s, 0.0)
        else:
            cp, cm = (0.0, 0.0) if e1 else (c1p, c1m)
            x1, g1 = one_sided(self.M1, w1, cp, cm, SLACK * (abs(self.M1 * w1) + cp + cm))
            p1, p2, p3, g2, g3 = sign(x1), 0, 0, 0.0, 0.0
        s1, s2 = e1 or p1, e2 or p2
        s3 = e3 or (p3 if s2 != 0 else s1) if self.coupled else 0
        if s2 != 0 and s1 == 0 and s3 == 0:
            # Both bodies held: their contact has no sliding speed and cannot slide, whatever
            # an event's kick asked (its friction stays at the limit it reached, a static
            # force). A load exactly at the pipe's window, Q = T1 + F2, otherwise set a plug
            # breaking away from a pipe that then could not move, and back, without end (fuzz
            # 2071:4481).
            s2 = 0
        return (s1, s2, s3), (f1 + g1, f2 + g2, f3 + g3)

    def _build(self) -> None:
        """The piece of the origin's modes: its kind, closed-form motion and event functions."""
        o = self._o
        s1, s2, s3 = int(o["s1"]), int(o["s2"]), int(o["s3"])
        q = o["q"] if o["q"] == o["q"] else 0.0
        fwd = s1 > 0
        f1c = -(self.T1 + self.Qf) if fwd else self.T1
        a1 = self.a_shaft + (self.a_face if fwd else 0.0)
        f3c = -self.Qp if s3 > 0 else 0.0
        a3 = self.a3 if s3 > 0 else 0.0
        d2, F2 = self.d2, self.F2
        self._events = events = []        # (h0, k over the piece's velocities, label)
        self._first = None
        if s1 == 0 and s2 == 0:
            self.kind, self.body, self.piece = REST, ((0.0, 0.0),), None
            return
        if s1 == 0:                       # the plug slides in a held pipe
            self.kind, self.body = PLUG, ((0.0,), (1.0,))
            p = LinearPiece([self.M2], [[d2 + a3]], [s2 * F2 + f3c], [o["V2"]])
            events.append((0.0, [-s2], STICK))
            # the pipe's static force f1 = -(q + f2), f2 = -s2 F2 + d2 V2, in [-(T1+Qf), T1]
            events.append((self.T1 + q - s2 * F2, [d2], PIPE_BACK))
            events.append((self.T1 + self.Qf - q + s2 * F2, [-d2], PIPE_FWD))
        elif s2 == 0:                     # together (or the pipe alone)
            self.kind = TOGETHER
            self.body = ((1.0,), ((1.0,) if self.coupled else (0.0,)))
            mass = self.M1 + self.M2
            p = LinearPiece([mass], [[a1 + a3]], [q + f1c + f3c], [o["V1"]])
            events.append((0.0, [float(s1)], PIPE_REST))
            if self.coupled:              # the force the plug needs: M2 a - e3, |.| <= F2
                c0, ka = p.acceleration_affine([self.M2])
                need0, kneed = c0 - f3c, ka[0] + a3
                events.append((F2 - need0, [-kneed], BREAK_POS))
                events.append((F2 + need0, [kneed], BREAK_NEG))
        elif s3 != 0:                     # both slide: the coupled pair
            self.kind, self.body = BOTH, ((1.0, 0.0), (0.0, 1.0))
            p = LinearPiece([self.M1, self.M2], [[a1 + d2, -d2], [-d2, d2 + a3]],
                            [q + f1c - s2 * F2, s2 * F2 + f3c], [o["V1"], o["V2"]])
            events.append((0.0, [float(s1), 0.0], PIPE_REST))
            events.append((0.0, [float(s2), -float(s2)], STICK))
            if self.Qp > 0.0:
                events.append((0.0, [0.0, float(s3)], PLUG_STOP))
        else:                             # the plug held by its face, the pipe sliding
            self.kind, self.body = CORING, ((1.0,), (0.0,))
            p = LinearPiece([self.M1], [[a1 + d2]], [q + f1c - s2 * F2], [o["V1"]])
            events.append((0.0, [float(s1)], PIPE_REST | STICK))
            # the face holds f3 = f2 = -s2 F2 - d2 V1 within [-Qp, 0]
            events.append((self.Qp - s2 * F2, [-d2], FACE_FWD))
            events.append((s2 * F2, [d2], FACE_BACK))
        self.piece = p
        self._affine = [(*p.affine(h0, k), label) for h0, k, label in events]

    def _bodies(self, values) -> tuple[float, float]:
        """Pipe and plug quantities of the piece's quantities ``values``."""
        return tuple(sum(b * x for b, x in zip(row, values)) for row in self.body)

    # -- events -------------------------------------------------------------------------------
    def _next_event(self) -> tuple[float, int]:
        """The piece's first event after its origin [s] and its labels (searched once, with no
        horizon: the event does not depend on how far the host looks)."""
        if self._first is None:
            self._first = self._search()
        return self._first

    def _search(self) -> tuple[float, int]:
        if self.kind == REST:
            return math.inf, 0
        times = [(self.piece.first_zero(a, b, math.inf, label >= PIPE_FWD), label)
                 for a, b, label in self._affine]
        t = min(x for x, _ in times)
        if t == math.inf:
            return t, 0
        tol = 8.0 * math.ulp(max(t, 1e-300)) + 1e-15 * t
        return t, sum(label for x, label in times if x <= t + tol)

    def _values(self, dt: float) -> dict:
        """Velocities, positions and works ``dt`` [s] after the origin."""
        o = self._o
        values = dict(o)
        if self.kind == REST:
            return values
        p = self.piece
        v1, v2 = self._bodies(p.velocity(dt))
        d1, d2 = self._bodies(p.displacement(dt))
        s1, s2, s3 = o["s1"], o["s2"], o["s3"]
        q = o["q"] if o["q"] == o["q"] else 0.0
        values.update(U1=o["U1"] + d1, V1=v1, U2=o["U2"] + d2, V2=v2,
                      W_in=o["W_in"] + q * d1,
                      W_outer=o["W_outer"] + self.T1 * s1 * d1,
                      W_inner=o["W_inner"] + max(self.F2 * s2 * (d1 - d2), 0.0),
                      W_face=o["W_face"] + (self.Qf * d1 if s1 > 0 else 0.0)
                      + (self.Qp * d2 if s3 > 0 else 0.0),
                      W_damp=o["W_damp"] + p.dissipation(dt))
        return values

    def _start(self, values: dict, q: float, modes, statics) -> None:
        """A new piece from ``values`` under ``q`` with ``modes`` and static forces."""
        o = self._o
        o.update({k: values[k] for k in ("U1", "V1", "U2", "V2", "W_in", "W_outer", "W_inner",
                                         "W_face", "W_damp")})
        o["t0"], o["q"] = values["time"], q
        o["s1"], o["s2"], o["s3"] = modes
        o["f1s"], o["f2s"], o["f3s"] = statics
        self._searched = 0.0
        self._build()
        if not self._modes or self._modes[-1] != modes[:2]:
            self._modes.append(tuple(int(s) for s in modes[:2]))

    def _restart(self, q: float, t: float, labels: int = 0) -> None:
        """Cut the piece at ``t`` [s] (an event with ``labels``, or a new load ``q``)."""
        o = self._o
        values = self._values(t - o["t0"])
        values["time"] = t
        v1, v2 = values["V1"], values["V2"]
        s1, s2, s3 = int(o["s1"]), int(o["s2"]), int(o["s3"])
        # a velocity that round-off carried past its zero (before the search reached it); a
        # sliding speed is closed as a stick closes it, conserving momentum (a plug 600 times
        # the pipe's mass set to the pipe's velocity took 2.7e-12 J out of the ledger)
        if s1 != 0 and v1 * s1 < 0.0:
            v1 = 0.0
        if s2 != 0 and (v1 - v2) * s2 < 0.0:
            if self.kind == BOTH:
                v1 = (self.M1 * v1 + self.M2 * v2) / (self.M1 + self.M2)
            v2 = v1
        if labels & PIPE_REST:
            v1 = 0.0
            if s2 == 0:
                v2 = 0.0
        if labels & STICK:
            v1 = v2 = (self.M1 * v1 + self.M2 * v2) / (self.M1 + self.M2) if s1 else v1
            if labels & PIPE_REST:
                v1 = v2 = 0.0
        if labels & PLUG_STOP and not labels & STICK:
            v2 = 0.0
        if self.kind == CORING or (s3 == 0 and self.coupled and s2 != 0):
            v2 = 0.0
        if not self.coupled:
            v2 = 0.0
        values["V1"], values["V2"] = v1, v2
        kicks = [0, 0, 0]
        for bit, which, direction in _KICKS:
            if labels & bit:
                kicks[which] = direction
        modes, statics = self._decide(q, v1, v2, kicks)
        self._start(values, q, modes, statics)

    # -- the Model interface ------------------------------------------------------------------
    def _step_to(self, q: float, h: float, t_end: float) -> None:
        o = self._o
        if q != o["q"]:
            self._restart(q, self.time)
        for _ in range(MAX_EVENTS_PER_STEP):
            horizon = t_end - o["t0"]
            if horizon <= self._searched:
                break
            dt, labels = self._next_event()
            if dt == math.inf or o["t0"] + dt > t_end:
                self._searched = horizon
                break
            self._restart(q, o["t0"] + dt, labels)
        else:
            raise RuntimeError(f"more than {MAX_EVENTS_PER_STEP} friction events in one step")
        self.time = t_end

    def at_rest(self) -> bool:
        """Both bodies stuck with no load (none yet, NaN, in a fresh model): a step under
        Q = 0 changes nothing."""
        q = self._o["q"]
        return self.kind == REST and (q == 0.0 or q != q)

    def _forces(self, values: dict) -> tuple[float, float, float]:
        """The shaft's, the plug's and the annulus' force on the pipe [N] (dampers included)."""
        o = self._o
        s1, s2 = int(o["s1"]), int(o["s2"])
        v1, v2 = values["V1"], values["V2"]
        q = o["q"] if o["q"] == o["q"] else 0.0
        if self.kind == REST or self.kind == PLUG:
            f2 = o["f2s"] if self.kind == REST else -s2 * self.F2 + self.d2 * v2
            soil = o["f1s"] if self.kind == REST else -(q + f2)
            shaft = max(soil, -self.T1)   # the shaft holds first, the annulus the rest
            return shaft, f2, soil - shaft
        shaft = -s1 * self.T1 - self.a_shaft * v1
        face = -(self.Qf + self.a_face * v1) if s1 > 0 else 0.0
        if self.kind == TOGETHER:
            if not self.coupled:
                return shaft, 0.0, face
            s3 = int(o["s3"])
            a = (q + shaft + face - (self.Qp + self.a3 * v1 if s3 > 0 else 0.0)) / (
                self.M1 + self.M2)
            e3 = -(self.Qp + self.a3 * v1) if s3 > 0 else 0.0
            return shaft, -(self.M2 * a - e3), face
        return shaft, -s2 * self.F2 - self.d2 * (v1 - v2), face

    def outputs(self) -> Outputs:
        """The contract's outputs at the current time."""
        o = self._o
        values = self._values(self.time - o["t0"])
        v1, v2 = values["V1"], values["V2"]
        f1, f2, face = self._forces(values)
        q = o["q"] if o["q"] == o["q"] else 0.0
        kinetic = 0.5 * (self.M1 * v1 * v1 + self.M2 * v2 * v2)
        low, high = axial_extremes(q, f1, f2, self.L1, self.L1, self.L2, face)
        w_in = values["W_in"]
        return Outputs(v1, v2, values["U1"], values["U2"], f1, f2, w_in,
                       values["W_outer"] + values["W_inner"], values["W_outer"],
                       values["W_inner"], kinetic, 0.0, 0.0, q, 0.0, 0.0, 0.0, w_in,
                       -q / self.S1, float(low) / self.S1, float(high) / self.S1,
                       self.at_rest(), int(o["s1"]), int(o["s2"]), values["W_face"],
                       values["W_damp"], float(self.L2), 0.0, 0.0)     # the plug keeps its length

    def modes(self) -> tuple[tuple[int, int], ...]:
        """Every piece's contact modes (pipe_mode, plug_mode), repeats merged."""
        return tuple(self._modes)

    def get_state(self) -> dict:
        """The piece's origin, modes and static forces, the time and the modes gone through."""
        state = {k: float(v) for k, v in self._o.items()}
        state["time"] = self.time
        state["modes"] = np.array(self._modes, dtype=np.int64).reshape(-1, 2)
        return state

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state`; the piece is rebuilt deterministically."""
        self._o = {k: float(state[k]) for k in _STATE_KEYS}
        self._modes = [(int(a), int(b)) for a, b in np.asarray(state["modes"]).reshape(-1, 2)]
        self.time = float(state["time"])
        self._searched = 0.0
        self._build()
