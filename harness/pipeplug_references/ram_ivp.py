"""Reference solution of rigid model I with a ram, piece by exact piece (independent of the core).

Model: a rigid pipe (mass M1) with a rigid plug (mass M2) in the soil, Coulomb friction at both
contacts (model I: the soil's limit F1 = P1 L1 tau1 is constant; the plug's F2 = P2 L2 tau2), a
struck-end force Q(t) and a ram of mass m behind the head::

    M1 U1'' = Q + F + f1 + f2,    M2 U2'' = -f2,    m X'' = -F
    f1 in -F1 Sign(U1'),          f2 in -F2 Sign(U1' - U2')

The ram acts through a cushion that only pushes: with the compression D = X - U1 (0 when a
strike puts the ram at the head), F = k D on the loading line (D at its largest so far, Dmax),
F = (k / e^2) (D - (1 - e^2) Dmax) on the unloading line, and 0 below (ram free). Without a
cushion (k = 0) ram and pipe meet in impacts with restitution e: the ram's and the pipe's
velocities change by the impulse (1 + e) mu w (mu = m M1 / (m + M1), w the closing velocity)
and plug and soil take none. An impact closing slower than ``PLASTIC`` times the fastest since
the strike is plastic (ram and pipe at their momentum's velocity), so that a Zeno sequence of
impacts (a ram following a decelerating pipe) ends after finitely many; then the ram rides on
the pipe (one body) while the pipe alone would decelerate, and is left behind otherwise.

With the soil's end resistance (``q_face``, ``q_plug_face`` in ``params``; model I: the front
end is always in the soil) the equations of :mod:`pipeplug_references.face_ivp` hold with the
cushion's force on the head: ``e1 in -Qf Sign+(U1')`` on the pipe, ``e3 in -Qp Sign+(U2')`` on
the plug; the modes are decided by its three-contact solver
(:func:`pipeplug_references.face_ivp.face_modes`) under Q plus the cushion's force, a sliding
plug's velocity reaching 0 is an event, a held pipe is released where Q plus the cushion's force
leaves the window the joint stuck problem allows, and ``W_face`` is booked from the
displacements (-e1 dU1 - e3 dU2).

Method: as :mod:`pipeplug_references.rigid_ivp`, the motion is cut into pieces of constant
contact modes (pipe, plug, ram: free, loading, unloading, riding); but every such piece is
linear with constant coefficients, so each is propagated exactly, by its matrix exponential
(:class:`_Linear`, checked against scipy's ``expm`` in the tests), not integrated: a ram
bouncing tens of times on a stiff cushion, each bounce's velocities depending on the last's,
grows any per-piece error by 1e4, where DOP853's floor (rtol 3e-14) had shown as 1e-9. The
events of every mode change (a velocity reaching 0, the largest compression, the cushion's
force reaching 0, the compression reaching Dmax again, the ram reaching the cushion, the held
pipe's or the carried plug's force reaching its friction limit) are looked for as solve_ivp
does, a sign change between checks (:data:`STEPS` a period), and located by brentq to an ulp
(:func:`_search`); where the compression turns, ram and pipe take their momentum's velocity.
The events that are levels of the compression are looked for also between its turns
(where it is monotone), as a crossing and back between two checks shows no sign
change at their ends. At every event and at every load change or strike the modes are decided anew by the
joint two-contact Coulomb problem (:func:`pipeplug_references.rigid_ivp.coulomb_modes`) under
Q plus the cushion's force; a friction force that reached its limit by the cushion's growing
force slips in that direction. Works are bookkept from the displacements (Q dU1, F1 |dU1|,
F2 |d(U1 - U2)|); the cushion's loss is (1 - e^2) of the work on the loading line and the
impacts' loss. Written from the equations above; imports numpy and scipy, and the reference's
own Coulomb solver, nothing of the project's core.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from .face_ivp import FaceSystem, face_modes
from .rigid_ivp import FORCE_SLACK, coulomb_modes

__all__ = ["simulate_ram", "OUTPUTS", "PLASTIC"]

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "v_ram", "F_head", "W_input", "W_friction",
           "W_cushion", "E_strain", "E_kinetic", "W_ram", "pipe_mode", "plug_mode", "W_face")
PLASTIC = 1e-10          #: impacts closing slower than this share of the fastest are plastic
MAX_STALLED = 50         #: consecutive pieces without time progress before giving up
MAX_EVENTS = 200_000     #: mode decisions of one run before giving up
FREE, LOAD, UNLOAD, RIDE = "free", "load", "unload", "ride"


class _Ram:
    """The ram's constants and its cushion's law."""

    def __init__(self, m, k, e):
        self.m, self.k, self.e = m, k, e
        self.ku = k / (e * e) if k > 0.0 else 0.0

    def force(self, c, d, dmax):
        """The cushion's force in contact state ``c`` at compression ``d`` (0 when free)."""
        if c == LOAD:
            return self.k * d
        if c == UNLOAD:
            return self.ku * (d - (1.0 - self.e ** 2) * dmax)
        return 0.0


def simulate_ram(params: dict, ram: dict, history, times) -> dict:
    """Model I with a ram under loads and strikes.

    Parameters
    ----------
    params : dict
        L1, L2, R1, h1, rho1, rho2, tau1, tau2 (SI) as :func:`pipeplug_references.rigid_ivp.simulate`,
        and the end resistance q_face, q_plug_face [Pa] (default 0).
    ram : dict
        ``mass`` [kg], ``k`` [N/m] (0: direct impacts), ``e`` [1].
    history : list of (time [s], "q" | "strike", value)
        At each time (increasing) the load becomes ``value`` [N] or a strike starts, the ram at
        the head touching an unloaded cushion at ``value`` [m/s].
    times : array
        Increasing sample times [s] (samples at a history time are taken after it).

    Returns
    -------
    dict of arrays (:data:`OUTPUTS`) at ``times`` and ``events``: (time, description).
    """
    s = FaceSystem(params, False)
    s.face = s.qf > 0.0 or s.qp > 0.0
    r = _Ram(float(ram["mass"]), float(ram.get("k", 0.0)), float(ram.get("e", 1.0)))
    times = np.asarray(times, dtype=float)
    out = {name: np.zeros(times.size) for name in OUTPUTS}
    events = []
    out["events"] = events
    y = np.zeros(6)                   # U1, V1, U2, V2, D (compression), VR (ram velocity)
    st = dict(q=0.0, p=0, rr=0, g=0, c=FREE, dmax=0.0, struck=False, w_in=0.0, w_fo=0.0,
              w_fi=0.0, w_c=0.0, w_ram=0.0, w_face=0.0, vscale=0.0, kick1=0, kick2=0)
    marks = [h[0] for h in history] + [float(times[-1]) if times.size else 0.0]
    k = 0
    t = 0.0
    pending = list(history)
    _decide(s, r, y, st, events, t, "start")
    stalled = 0
    for t_next in marks:
        while t < t_next:
            t_end, y_end, fired, sol = _piece(s, r, y, st, t, t_next)
            stalled = stalled + 1 if t_end <= t else 0
            if stalled > MAX_STALLED or len(events) > MAX_EVENTS:
                raise RuntimeError(f"no progress at t = {t!r} s ({fired})")
            m = int(np.searchsorted(times, t_end, side="left"))
            if m > k:
                _fill(s, r, out, np.arange(k, m), sol.sol(times[k:m]), y, st)
                k = m
            _bookkeep(s, r, y, y_end, st)
            y[:] = y_end
            t = t_end
            if fired is not None:
                _event(s, r, y, st, fired)
                _decide(s, r, y, st, events, t, fired)
        while pending and pending[0][0] == t_next:
            _, kind, value = pending.pop(0)
            if kind == "q":
                st["q"] = float(value)
            else:
                _strike(s, r, y, st, float(value))
            _decide(s, r, y, st, events, t, kind)
    if k < times.size:
        _fill(s, r, out, np.arange(k, times.size), np.repeat(y[:, None], times.size - k, 1),
              y, st)
    for name in ("pipe_mode", "plug_mode"):
        out[name] = out[name].astype(int)
    return out


def _strike(s, r, y, st, v):
    """A strike: the ram at the head, unloaded cushion, at ``v``; a direct strike faster than
    the head hits it at once."""
    if st["c"] in (LOAD, UNLOAD):
        st["w_c"] += r.force(st["c"], y[4], st["dmax"]) ** 2 / (2.0 * r.ku)
    st["w_ram"] += 0.5 * r.m * (v * v - y[5] ** 2)
    y[4], y[5] = 0.0, v
    st.update(dmax=0.0, struck=True, vscale=0.0, c=FREE)
    if r.k == 0.0 and v > y[1]:
        _impact(s, r, y, st)


def _impact(s, r, y, st):
    w = y[5] - y[1]
    st["vscale"] = max(st["vscale"], w)
    mu = r.m * s.M1 / (r.m + s.M1)
    if w <= PLASTIC * st["vscale"]:
        y[1] = y[5] = (r.m * y[5] + s.M1 * y[1]) / (r.m + s.M1)
        st["w_c"] += 0.5 * mu * w * w
        return
    j = (1.0 + r.e) * mu * w
    y[1] += j / s.M1
    y[5] -= j / r.m
    st["w_c"] += 0.5 * (1.0 - r.e ** 2) * mu * w * w


def _decide(s, r, y, st, events, t, cause):
    """Choose the contact modes at ``t`` (after snapping in :func:`_event`)."""
    q = st["q"]
    c = FREE
    if st["struck"]:
        if r.k > 0.0:
            touch = (1.0 - r.e ** 2) * st["dmax"]
            closing = y[5] - y[1]
            if y[4] >= st["dmax"] and (closing > 0.0 or y[4] > 0.0):
                c = LOAD if closing > 0.0 else UNLOAD
            elif y[4] > touch or (y[4] >= touch and closing > 0.0):
                c = UNLOAD
        elif y[4] >= 0.0 and y[5] == y[1]:
            c = RIDE
    force = r.force(c, y[4], st["dmax"])
    pipe_sign = int(np.sign(y[1])) or st["kick1"]
    rel_sign = (int(np.sign(y[1] - y[3])) or st["kick2"]) if s.plug else 0
    plug_sign = int(np.sign(y[3])) if s.plug else 0
    p, rr, g = _modes(s, q + force, y[0], pipe_sign, rel_sign, plug_sign)
    if c == RIDE:
        a_alone = _accel(s, r, q, p, rr, g, FREE, 0.0)[0]
        if not a_alone < 0.0:
            c = FREE
        else:
            heavy = type(s).__new__(type(s))
            heavy.__dict__.update(s.__dict__)
            heavy.M1 = s.M1 + r.m
            p, rr, g = _modes(heavy, q, y[0], pipe_sign, rel_sign, plug_sign)
    if p == 0:
        y[1] = 0.0
    if rr == 0 and s.plug:
        y[3] = y[1]
    if g == 0 and s.plug and s.face:
        y[3] = 0.0
    if c == RIDE:
        y[5] = y[1]
    st.update(p=p, rr=rr, g=g, c=c, kick1=0, kick2=0)
    events.append((t, f"{cause}: pipe {p:+d}, plug {rr:+d}, soil {g:+d}, ram {c}"))


def _modes(s, q, u1, pipe_sign, rel_sign, plug_sign):
    """``(p, rr, g)``: the modes of pipe/soil, pipe/plug and plug/soil (the last the plug's
    velocity's sign, 0 held; as the pipe's without end resistance) under ``q`` [N]."""
    if s.face:
        return face_modes(s, q, u1, pipe_sign, rel_sign, plug_sign)[0]
    p, rr, _, _ = coulomb_modes(s, q, u1, pipe_sign, rel_sign)
    return p, rr, 0


def _ends(s, p, rr, g):
    """The soil's end forces (e1 on the pipe, e3 on the plug) [N] of sliding bodies in modes
    (p, rr, g): -Qf, -Qp advancing, 0 retreating (a carried plug moves as the pipe)."""
    e1 = -s.qf if p > 0 else 0.0
    moving = p if rr == 0 else g
    e3 = -s.qp if (s.plug and moving > 0) else 0.0
    return e1, e3


def _accel(s, r, q, p, rr, g, c, force):
    """(a1, a2, a_ram) in modes (p, rr, g, c) under the cushion's ``force``."""
    F1 = s.c1_full
    e1, e3 = _ends(s, p, rr, g)
    if p == 0:
        a1 = 0.0
        a2 = (rr * s.c2 + e3) / s.M2 if rr and (g or not s.face) else 0.0
    elif rr == 0:
        mass = s.M1 + s.M2 + (r.m if c == RIDE else 0.0)
        a1 = (q - p * F1 + e1 + e3 + force) / mass
        a2 = a1 if s.plug else 0.0
    else:
        a1 = (q - p * F1 + e1 - rr * s.c2 + force) / (s.M1 + (r.m if c == RIDE else 0.0))
        a2 = (rr * s.c2 + e3) / s.M2 if (g or not s.face) else 0.0
    a_ram = a1 if c == RIDE else -force / r.m
    return a1, a2, a_ram


def _piece(s, r, y, st, t, tb):
    q, p, rr, g, c, dmax = st["q"], st["p"], st["rr"], st["g"], st["c"], st["dmax"]

    evs = []

    def add(fun, direction, name, band=0.0):
        # At the piece's start a level met within ``band`` (round-off of its terms, or the
        # slack with which the modes were decided) counts as met: a plug carried at its limit
        # when a strike starts (the forces balanced to the last digit) leaves at once as the
        # cushion loads, whichever side of 0 it starts on.
        def event(tt, z):           # z: a state (6,) or states (6, n) at times tt
            g = fun(z)
            return np.where((np.abs(g) <= band) & (tt == t), -direction * 1e-300, g)
        event.terminal, event.direction, event.name, event.fun = True, direction, name, fun
        evs.append(event)

    if p != 0:
        add(lambda z: z[1], -p, "pipe stops")
    if rr != 0:
        add(lambda z: z[1] - z[3], -rr, "plug sticks")
    if p != 0 and rr != 0 and g != 0 and s.face and s.qp > 0.0:
        add(lambda z: z[3], -g, "plug stops")
    if p == 0 and c in (LOAD, UNLOAD):
        # held while the joint stuck problem has a solution: with the plug stuck too, f2 in
        # [-c2, c2], e3 = f2 in [-Qp, 0]; with the plug sliding, f2 = -rr c2
        f2 = -rr * s.c2
        ahead = s.c1_full + s.qf + (min(s.qp, s.c2) if rr == 0 and s.plug else 0.0)
        # The mode solvers hold a force within their slack of its limit (stuck wins at
        # equality); a force that starts there and goes on past the limit cannot be held for
        # any time: it breaks away at once, whichever side of the limit round-off put it
        # (fuzz 4051:6110: Q = F1 + 1 ulp, held for good as the cushion loaded)
        slack = FORCE_SLACK * (abs(q + r.force(c, y[4], dmax)) + s.c1_full + s.qf + s.c2
                               + s.qp)
        add(lambda z: ahead - (q + r.force(c, z[4], dmax) + f2), -1, "pipe breaks away +",
            slack)
        add(lambda z: s.c1_full + (q + r.force(c, z[4], dmax) + f2), -1, "pipe breaks away -",
            slack)
    if p != 0 and rr == 0 and s.plug and c in (LOAD, UNLOAD):
        e3 = _ends(s, p, 0, 0)[1]

        def required(z):        # the plug's force on the pipe is -(M2 a - e3)
            return s.M2 * _accel(s, r, q, p, 0, 0, c, r.force(c, z[4], dmax))[0] - e3
        band = 1e-12 * s.c2
        add(lambda z: s.c2 - required(z), -1, "plug breaks away +", band)
        add(lambda z: s.c2 + required(z), -1, "plug breaks away -", band)
    if c == LOAD:
        add(lambda z: z[5] - z[1], -1, "largest compression")
    if c == UNLOAD:
        touch = (1.0 - r.e ** 2) * dmax
        add(lambda z: z[4] - touch, -1, "cushion unloaded")
        add(lambda z: z[4] - dmax, 1, "reloading")
    if c in (LOAD, UNLOAD):
        # the compression's turns: between two it is monotone, and so is every event that is
        # a level of it; a crossing of such a level and back within one step of the
        # integrator (or before the step's end past a terminal event) hides from the events
        # above, and shows between the turns around it
        add(lambda z: z[5] - z[1], 0, "turn")
        evs[-1].terminal = False
    touch = (1.0 - r.e ** 2) * dmax if r.k > 0.0 else 0.0
    # A flying ram's compression is a quadratic (the pipe's acceleration is constant in a
    # piece): with no relative velocity and acceleration (a ram left against a pipe that has
    # stopped) it stays where it is and meets nothing.
    still = y[5] == y[1] and _accel(s, r, q, p, rr, g, FREE, 0.0)[0] == 0.0
    if c == FREE and st["struck"] and not still:
        add(lambda z: z[4] - touch, 1, "ram reaches the head")
        # the compression's largest value: a crossing of ``touch`` and back within one step
        # of the integrator hides from the event above; it shows past this one
        add(lambda z: z[5] - z[1], -1, "closest approach")
        evs[-1].terminal = False
    sol = _search(_Linear(s, r, st, t, y), t, tb, evs)
    if c == RIDE:
        # A riding ram is one body with the pipe: its velocity is the pipe's and the
        # compression stays. Integrated apart, the two velocities end a round-off apart (the
        # stages' sums round the components differently), which the next decision (a load
        # change) would take for the ram leaving a pipe that still presses on it.
        sol.sol = _riding(sol.sol, y[4])
    t_end, y_end, name = tb, sol.y[:, -1].copy(), None
    if sol.status == 1:
        i = next(i for i, te in enumerate(sol.t_events) if len(te) and evs[i].terminal)
        t_end, name = float(sol.t_events[i][-1]), evs[i].name
        y_end = sol.sol(t_end)
    if c in (LOAD, UNLOAD):
        t_end, y_end, name = _hidden_levels(evs, sol, t, y, t_end, y_end, name)
    if c == RIDE:
        y_end[4], y_end[5] = y[4], y_end[1]
    for i, event in enumerate(evs):
        if event.name == "closest approach" and y[4] < touch:
            hidden = [tt for tt, z in zip(sol.t_events[i], sol.y_events[i])
                      if tt <= t_end and z[4] >= touch]
            if hidden:
                t_end = _root(lambda tt: sol.sol(tt)[4] - touch, t, hidden[0])
                y_end, name = sol.sol(t_end), "ram reaches the head"
    if (c == FREE and st["struck"] and not still and name != "ram reaches the head"
            and y[4] < touch <= y_end[4]):
        # a terminal event (the pipe stopping) cut short the check in which the ram rose
        # through the touch, its closest approach after that end (fuzz 4061:2580): the
        # compression, a quadratic, crossed upward once between the piece's ends
        t_end = _root(lambda tt: sol.sol(tt)[4] - touch, t, t_end)
        y_end, name = sol.sol(t_end), "ram reaches the head"
    return t_end, y_end, name, sol


#: phi_j(x) = sum_n (-1)^n x^(2n) / (2n + j)!, j = 1..4, to below an ulp for |x| < 1 (14 terms)
_PHI = [(-1.0) ** np.arange(14) / np.array([np.prod(np.arange(1.0, 2 * n + j + 1)) for n in range(14)])
        for j in range(5)]
STEPS = 64               #: event checks per period of the cushion's oscillation
MIN_STEPS = 16           #: event checks of a piece at the least


def _phis(x):
    """``(phi1, phi2, phi3, phi4)`` of the oscillation's phase ``x = omega tau`` (an array):
    sin x / x, (1 - cos x) / x^2, (x - sin x) / x^3, (x^2/2 - 1 + cos x) / x^4, the
    functions of the matrix exponential of ``D'' = -omega^2 D + const`` (1, 1/2, 1/6, 1/24
    at x = 0). A power series in x^2 below |x| = 1, where the direct forms cancel."""
    x = np.asarray(x, dtype=float)
    y = x * x
    small = np.abs(x) < 1.0
    series = [np.polyval(_PHI[j][::-1], y) for j in range(1, 5)]
    xs = np.where(small, 1.0, x)
    sin, cos = np.sin(xs), np.cos(xs)
    direct = [sin / xs, (1.0 - cos) / xs ** 2, (xs - sin) / xs ** 3,
              (0.5 * xs * xs - 1.0 + cos) / xs ** 4]
    return [np.where(small, a, b) for a, b in zip(series, direct)]


class _Linear:
    """The exact motion of one piece, from the piece's start ``t`` in state ``y``.

    In a piece every force is constant but the cushion's, ``f = kc D + f0`` (kc = k loading,
    k / e^2 unloading, 0 free or riding), which acts on what moves with the head with the
    compliance ``h1`` (1 / its mass; 0 held) and on the ram with -1/m: the compression obeys
    ``D'' = -omega^2 D + const``, omega^2 = kc (1/m + h1), and every velocity is its start's
    plus its start's acceleration times tau plus h kc times an integral of D - D0. Written
    with the functions phi_j of the system's matrix exponential (:func:`_phis`), each term
    to round-off (the reference's tests check the form against scipy's expm)::

        D = D0 + W0 tau phi1 + A0 tau^2 phi2,           W = D' = W0 cos x + A0 tau phi1
        int (D - D0) = W0 tau^2 phi2 + A0 tau^3 phi3,   int int (D - D0) = W0 tau^3 phi3 + A0 tau^4 phi4

    (W0, A0 the relative velocity and acceleration at the start, x = omega tau).
    """

    def __init__(self, s, r, st, t, y):
        q, p, rr, g, c, dmax = st["q"], st["p"], st["rr"], st["g"], st["c"], st["dmax"]
        self.t, self.y = t, y.copy()
        f = r.force(c, y[4], dmax)
        self.a1, self.a2, a_ram = _accel(s, r, q, p, rr, g, c, f)
        if not s.plug:
            self.a2 = 0.0
        kc = {LOAD: r.k, UNLOAD: r.ku}.get(c, 0.0)
        ride = r.m if c == RIDE else 0.0
        if p == 0:
            h1 = 0.0
        elif rr == 0:
            h1 = 1.0 / (s.M1 + s.M2 + ride)
        else:
            h1 = 1.0 / (s.M1 + ride)
        h2 = h1 if (s.plug and p != 0 and rr == 0) else 0.0
        self.g1, self.g2 = h1 * kc, h2 * kc
        self.w = np.sqrt(kc * (1.0 / r.m + h1))
        self.w0, self.acc0 = y[5] - y[1], a_ram - self.a1

    def __call__(self, tt):
        tau = np.asarray(tt, dtype=float) - self.t
        y, w0, acc0 = self.y, self.w0, self.acc0
        x = self.w * tau
        p1, p2, p3, p4 = _phis(x)
        t2 = tau * tau
        i1 = w0 * t2 * p2 + acc0 * t2 * tau * p3           # int (D - D0)
        i2 = w0 * t2 * tau * p3 + acc0 * t2 * t2 * p4       # int int (D - D0)
        v1 = y[1] + self.a1 * tau + self.g1 * i1
        v2 = y[3] + self.a2 * tau + self.g2 * i1
        z = np.array([y[0] + tau * (y[1] + 0.5 * self.a1 * tau) + self.g1 * i2, v1,
                      y[2] + tau * (y[3] + 0.5 * self.a2 * tau) + self.g2 * i2, v2,
                      y[4] + w0 * tau * p1 + acc0 * t2 * p2,
                      v1 + w0 * np.cos(x) + acc0 * tau * p1])
        return z

    def rate(self, tt):
        """The state's rate of change at time(s) ``tt`` [s]: (V1, a1, V2, a2, D', a_ram)."""
        tau = np.asarray(tt, dtype=float) - self.t
        x = self.w * tau
        p1, p2, _, _ = _phis(x)
        dd = self.w0 * tau * p1 + self.acc0 * tau * tau * p2          # D - D0
        z = self(tt)
        a1 = self.a1 + self.g1 * dd
        return np.array([z[1], a1, z[3], self.a2 + self.g2 * dd, z[5] - z[1],
                         a1 + self.acc0 * np.cos(x) - self.w0 * x * p1 * self.w])


class _Solution:
    """What :func:`_search` found: the dense motion ``sol``, ``status`` (1: a terminal event
    ended the piece), ``t_events`` and ``y_events`` per event, the end's state ``y[:, -1]``."""

    def __init__(self, dense, status, t_events, y_events, y_end):
        self.sol, self.status, self.t_events, self.y_events = dense, status, t_events, y_events
        self.y = y_end[:, None]


def _root(fun, a, b):
    """The root [s] of ``fun`` between ``a`` and ``b`` (a sign change), to an ulp of it or to
    4 eps of the bracket's width, whichever is wider: near t = 0 an ulp would be 1e-300 s,
    a thousand halvings away (brentq gave up after 100)."""
    eps = np.finfo(float).eps
    return brentq(fun, a, b, xtol=max(4.0 * eps * (b - a), 1e-300), rtol=4.0 * eps)


def _before(event, dense, g_start):
    """``event`` along ``dense`` for brentq from a step's start where it was ``g_start``
    (not 0), an exact 0 counted on the start's side: near a piece's start a level snapped onto
    (the cushion's touch) stays exactly met for a few ulps of time while the motion's change
    rounds away, where brentq would stop at once (the ram leaving the cushion found it again
    an ulp later, piece after piece); so the root is the first time past the level."""
    side = np.copysign(1e-300, g_start)

    def g(tt):
        value = float(event(tt, dense(tt)))
        return value if value != 0.0 else side
    return g


def _search(dense, t, tb, evs):
    """The events ``evs`` of the exact motion ``dense`` from ``t`` to ``tb`` [s], as solve_ivp
    looks for them: a sign change in an event's direction between two checks (STEPS per period
    of the oscillation, MIN_STEPS per piece at the least), its root refined by brentq to an
    ulp; the piece ends at the first terminal event."""
    span = tb - t
    n = MIN_STEPS
    if dense.w > 0.0:
        n = max(n, int(min(np.ceil(span * dense.w * STEPS / (2.0 * np.pi)), 1e7)))
    t_events = [[] for _ in evs]
    y_events = [[] for _ in evs]
    start = 0
    block = 256
    while start < n:
        stop = min(start + block, n)
        grid = t + span * np.arange(start, stop + 1) / n
        grid[-1] = tb if stop == n else grid[-1]
        grid[0] = t if start == 0 else grid[0]
        zs = dense(grid)
        values = np.array([np.broadcast_to(ev(grid, zs), grid.shape) for ev in evs])
        for j in range(grid.size - 1):
            a, b = grid[j], grid[j + 1]
            found = []
            for i, ev in enumerate(evs):
                ga, gb = values[i, j], values[i, j + 1]
                up, down = ga <= 0.0 <= gb, ga >= 0.0 >= gb
                if not ((ev.direction > 0 and up) or (ev.direction < 0 and down)
                        or (ev.direction == 0 and (up or down))):
                    continue
                if ga == 0.0:
                    root = a
                elif gb == 0.0:
                    root = b
                else:
                    root = _root(_before(ev, dense, ga), a, b)
                found.append((root, i))
            terminal = [root for root, i in found if evs[i].terminal]
            if found and terminal:
                t_hit = min(terminal)
                for root, i in sorted(found):
                    if root <= t_hit:
                        t_events[i].append(root)
                        y_events[i].append(dense(root))
                return _Solution(dense, 1, [np.array(x) for x in t_events], y_events,
                                 dense(t_hit))
            for root, i in sorted(found):
                t_events[i].append(root)
                y_events[i].append(dense(root))
        start = stop
    return _Solution(dense, 0, [np.array(x) for x in t_events], y_events, dense(tb))


def _riding(dense, d):
    """The dense output ``dense`` with the ram's state pinned to the pipe's: compression ``d``,
    the pipe's velocity."""
    def at(tt):
        z = dense(tt)
        z[4], z[5] = d, z[1]
        return z
    return at


#: the events that are levels of the compression alone (Q, the modes and Dmax fixed)
_LEVELS = ("cushion unloaded", "reloading", "pipe breaks away +", "pipe breaks away -",
           "plug breaks away +", "plug breaks away -")


#: the events of a velocity (or a relative one) reaching 0: its rate is a level of the
#: compression (the accelerations are affine in the cushion's force), monotone between the
#: compression's turns, so the velocity has one extreme at most between two turns
_STOPS = ("pipe stops", "plug sticks", "plug stops")


def _extremes(fun, dense, bounds):
    """``bounds`` (the piece's start, the compression's turns, its end) with the times between
    them where ``fun`` (linear in the state) of the motion ``dense`` is extreme, its rate
    ``fun(dense.rate)`` crossing 0: between two of these, ``fun`` is monotone. A velocity
    that dips through 0 and back between two checks of :func:`_search` (a carried pair just
    released, decelerating while the cushion's force grows: fuzz 2029:5270) shows there."""
    out = [bounds[0]]
    for a, b in zip(bounds[:-1], bounds[1:]):
        ra, rb = fun(dense.rate(a)), fun(dense.rate(b))
        if ra * rb < 0.0:
            out.append(_root(lambda tt: fun(dense.rate(tt)), a, b))
        out.append(b)
    return out


def _hidden_levels(evs, sol, t, y, t_end, y_end, name):
    """The first crossing, in its direction, of a level of the compression between ``t``, the
    compression's turns and ``t_end`` (where it is monotone), or of a velocity between these
    and its extremes (:func:`_extremes`), when earlier than ``t_end``: ``(t_end, y_end,
    name)`` of the piece's end."""
    turns = next(te for te, ev in zip(sol.t_events, evs) if ev.name == "turn")
    bounds = [t] + sorted(tt for tt in turns if t < tt < t_end) + [t_end]

    def at(tt):
        return y if tt == t else y_end if tt == t_end else sol.sol(tt)

    best = (t_end, None)
    for event in evs:
        if event.name in _STOPS:
            own = _extremes(event.fun, sol.sol, bounds)
        elif event.name in _LEVELS:
            own = bounds
        else:
            continue
        g = [event(tt, at(tt)) for tt in own]
        for a, b, ga, gb in zip(own[:-1], own[1:], g[:-1], g[1:]):
            if not event.direction * ga < 0.0 or event.direction * gb < 0.0:
                continue
            if a == t and abs(ga) == 1e-300 and event.name in _STOPS:
                # a velocity exactly at 0 at the start (a body just set sliding at its
                # breakaway, its acceleration round-off there): a dip of round-off, not a
                # stop (fuzz 4051:400 went on in steps of 5e-301 s)
                continue
            root = b if gb == 0.0 else _root(lambda tt, ev=event: ev(tt, at(tt)), a, b)
            if root < best[0]:
                best = (root, event.name)
            break
    if best[1] is None:
        return t_end, y_end, name
    return best[0], sol.sol(best[0]), best[1]


def _event(s, r, y, st, fired):
    """Snap the state onto the event that ended a piece."""
    dmax = st["dmax"]
    if fired == "pipe stops":
        y[1] = 0.0
        if st["rr"] == 0 and s.plug:
            y[3] = 0.0
        if st["c"] == RIDE:
            y[5] = 0.0
    elif fired == "plug sticks":
        m1 = s.M1 + (r.m if st["c"] == RIDE else 0.0)
        moving = st["p"] != 0
        y[1] = y[3] = (m1 * y[1] + s.M2 * y[3]) / (m1 + s.M2) if moving else y[1]
        if st["c"] == RIDE:
            y[5] = y[1]
    elif fired == "plug stops":
        y[3] = 0.0
    elif fired.startswith("pipe breaks away"):
        st["kick1"] = 1 if fired.endswith("+") else -1
        if fired.endswith("+") and s.face and s.plug and st["rr"] == 0 and s.qp > s.c2:
            st["kick2"] = 1       # released at F1 + Qf + F2: the pipe slides over the plug
    elif fired.startswith("plug breaks away"):
        st["kick2"] = 1 if fired.endswith("+") else -1
    elif fired == "largest compression":
        st["dmax"] = y[4]
        _turn(s, r, y, st)
    elif fired == "cushion unloaded":
        y[4] = (1.0 - r.e ** 2) * dmax
    elif fired == "reloading":
        y[4] = dmax
    elif fired == "ram reaches the head":
        y[4] = (1.0 - r.e ** 2) * dmax if r.k > 0.0 else 0.0
        if r.k == 0.0 and y[5] > y[1]:
            _impact(s, r, y, st)



def _turn(s, r, y, st):
    """Ram and what moves with the pipe at the velocity of their momentum where the
    compression turns (no relative velocity there): the event's time is off by its
    location's tolerance, where the relative velocity is the relative acceleration times that
    (1e-10 m/s at 1e5 m/s^2); setting the ram to the pipe's velocity would change the momentum
    by m times that at every turn. A held pipe stays at rest and the ram with it."""
    if st["p"] == 0:
        y[5] = y[1]
        return
    carried = s.plug and st["rr"] == 0
    mass = s.M1 + (s.M2 if carried else 0.0)
    y[1] = y[5] = (r.m * y[5] + mass * y[1]) / (r.m + mass)
    if carried:
        y[3] = y[1]


def _bookkeep(s, r, y0, y1, st):
    """Works over a piece from ``y0`` to ``y1``."""
    d1 = y1[0] - y0[0]
    st["w_in"] += st["q"] * d1
    st["w_fo"] += abs(st["p"]) * s.c1_full * abs(d1)
    if st["rr"]:
        st["w_fi"] += s.c2 * abs((y1[0] - y1[2]) - (y0[0] - y0[2]))
    e1, e3 = _ends(s, st["p"], st["rr"], st["g"])
    st["w_face"] += -e1 * d1 - e3 * (y1[2] - y0[2])
    if st["c"] == LOAD:
        st["w_c"] += 0.5 * (1.0 - r.e ** 2) * r.k * (y1[4] ** 2 - y0[4] ** 2)
        st["dmax"] = max(st["dmax"], y1[4])


def _fill(s, r, out, idx, ys, y0, st):
    """Outputs at samples ``idx`` with states ``ys`` (6 x n) inside the piece from ``y0``."""
    u1, v1, u2, v2, d, vr = ys
    c = st["c"]
    force = np.array([max(r.force(c, x, max(st["dmax"], x) if c == LOAD else st["dmax"]), 0.0)
                      for x in np.atleast_1d(d)])
    if c == RIDE:
        force = np.full(d.shape, max(0.0, -r.m * _accel(s, r, st["q"], st["p"], st["rr"],
                                                          st["g"], c, 0.0)[0]))
    d1 = u1 - y0[0]
    w_c = st["w_c"] + (0.5 * (1.0 - r.e ** 2) * r.k * (d * d - y0[4] ** 2) if c == LOAD else 0.0)
    w_fi = st["w_fi"] + (s.c2 * np.abs((u1 - u2) - (y0[0] - y0[2])) if st["rr"] else 0.0)
    e1, e3 = _ends(s, st["p"], st["rr"], st["g"])
    w_face = st["w_face"] - e1 * d1 - e3 * (u2 - y0[2]) + 0.0 * u1
    values = dict(v_pipe=v1, v_plug=v2 if s.plug else 0.0 * v1, u_pipe=u1,
                  u_plug=u2 if s.plug else 0.0 * u1, v_ram=vr, F_head=st["q"] + force,
                  W_input=st["w_in"] + st["q"] * d1,
                  W_friction=st["w_fo"] + abs(st["p"]) * s.c1_full * np.abs(d1) + w_fi,
                  W_cushion=w_c + 0.0 * u1,
                  E_strain=force ** 2 / (2.0 * r.ku) if r.k > 0.0 else 0.0 * u1,
                  E_kinetic=0.5 * (s.M1 * v1 ** 2 + s.M2 * v2 ** 2 + r.m * vr ** 2),
                  W_ram=st["w_ram"] + 0.0 * u1, pipe_mode=st["p"] + 0.0 * u1,
                  plug_mode=st["rr"] + 0.0 * u1, W_face=w_face)
    for name, value in values.items():
        out[name][idx] = value

