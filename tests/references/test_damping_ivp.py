"""The ODE reference with Smith damping against closed forms derived here: a plug that slips in
its pipe for a moment and sticks again, and a stiff coupled piece sampled between the
integrator's steps (each once failed: pieces of 4e-16 s without end; 1e-7 of scale)."""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from pipeplug_references.damping_ivp import simulate_damped

R1, H1, RHO1, RHO2, L1 = 0.035, 0.003, 7800.0, 1800.0, 1.0
P2, S1, S2 = 2 * math.pi * R1, math.pi * ((R1 + H1) ** 2 - R1 ** 2), math.pi * R1 ** 2
M1 = RHO1 * S1 * L1


def _exponential(v0, f, c, m):
    """M v' = f - c v from v0: the velocity and its integrals of v and v^2 after t."""
    vinf, lam = f / c, c / m

    def at(t):
        e = math.exp(-lam * t)
        v = vinf + (v0 - vinf) * e
        u = vinf * t + (v0 - vinf) * (1 - e) / lam
        sq = (vinf ** 2 * t + 2 * vinf * (v0 - vinf) * (1 - e) / lam
              + (v0 - vinf) ** 2 * (1 - e * e) / (2 * lam))
        return v, u, sq
    return at


def test_a_plug_slipping_for_a_moment_sticks_again_where_the_closed_form_says():
    # No shaft friction, the annulus' end resistance Qf damped by J_face, a plug without
    # damping (J_shaft = 0). Pushed by Q, pipe and plug move together; at Q's end the pipe
    # decelerates by (Qf + c v) / (M1 + M2) with c = J_face Qf, which needs more than F2 from
    # the plug while v is above v_slip: the plug slips ahead, the pipe's damper weakens as it
    # slows, and the plug sticks again at ts; together then until the pipe stops.
    tau2, L2, q_face, j_face, Q = 6000.0, 0.7, 1.6e6, 0.06, 3000.0
    M2, F2, Qf = RHO2 * S2 * L2, P2 * L2 * tau2, q_face * S1
    c, M = j_face * Qf, M1 + M2
    assert M2 * (Q - Qf) / M < F2           # the push carries the plug
    v_slip = (F2 * M / M2 - Qf) / c
    push = _exponential(0.0, Q - Qf, c, M)
    t0 = brentq(lambda t: push(t)[0] - 1.001 * v_slip, 0.0, 10.0, xtol=1e-15, rtol=1e-15)
    v0 = push(t0)[0]
    # the slip: M1 v1' = F2 - Qf - c v1, M2 v2' = -F2; w = v1 - v2 < 0 until ts
    pipe = _exponential(v0, F2 - Qf, c, M1)

    def w(t):
        return pipe(t)[0] - (v0 - F2 / M2 * t)

    t_min = M1 / c * math.log((c * v0 + Qf - F2) * M2 / (F2 * M1))    # w' = 0
    ts = brentq(w, t_min, 100 * t_min, xtol=1e-16, rtol=1e-15)
    vs = pipe(ts)[0]
    coast = _exponential(vs, -Qf, c, M)
    t_stop = math.log(1 + c * vs / Qf) * M / c

    params = dict(tau1=0.0, tau2=tau2, L2=L2, q_face=q_face, J_face=j_face)
    times = np.array([0.5 * t0, t0 + 0.5 * ts, t0 + ts + 0.5 * t_stop, t0 + ts + 2 * t_stop])
    ref = simulate_damped(params, [(t0, Q)], times, False, max_events=1000)
    sticks = [t for t, what in ref["events"] if what.startswith("plug sticks")]
    assert len(sticks) == 1 and abs(sticks[0] - (t0 + ts)) <= 1e-12 * t0
    stops = [t for t, what in ref["events"] if what.startswith("pipe stops")]
    assert len(stops) == 1 and abs(stops[0] - (t0 + ts + t_stop)) <= 1e-12 * t0
    v1 = [push(times[0])[0], pipe(0.5 * ts)[0], coast(0.5 * t_stop)[0], 0.0]
    v2 = [push(times[0])[0], v0 - F2 / M2 * 0.5 * ts, coast(0.5 * t_stop)[0], 0.0]
    np.testing.assert_allclose(ref["v_pipe"], v1, rtol=0, atol=1e-12 * v0)
    np.testing.assert_allclose(ref["v_plug"], v2, rtol=0, atol=1e-12 * v0)
    # every damper's work: c v1^2 over the push, the slip and the coast
    work = c * (push(t0)[2] + pipe(ts)[2] + coast(t_stop)[2])
    assert abs(ref["W_damping"][-1] - work) <= 1e-12 * work


def test_a_stiff_coupled_piece_is_accurate_between_the_integrators_steps():
    # Pipe and plug both sliding under Q, coupled by the plug's damper d2 = J_shaft F2 (rate
    # d2 (1/M1 + 1/M2) near 5e3/s over 17 ms): M v' = g - C v, in closed form by the
    # eigenvectors of M^-1 C (numpy's), sampled at points no step of the integrator ends on.
    tau2, L2, q_face, j_shaft, j_face, Q, T0 = 6.67e4, 0.472, 1e5, 1.6, 0.95, 41600.0, 0.0173
    M2, F2, Qf = RHO2 * S2 * L2, P2 * L2 * tau2, q_face * S1
    d2, a1 = j_shaft * F2, j_face * Qf
    A = -np.array([[(a1 + d2) / M1, -d2 / M1], [-d2 / M2, d2 / M2]])
    b = np.array([(Q - Qf - F2) / M1, F2 / M2])
    lam, vec = np.linalg.eig(A)
    steady = -np.linalg.solve(A, b)              # v(t) = steady + V e^(lam t) V^-1 (0 - steady)
    coef = np.linalg.solve(vec, -steady)
    times = T0 * np.arange(1, 11) / 10.0
    exact = np.array([steady + vec @ (np.exp(lam * t) * coef) for t in times])
    params = dict(tau1=0.0, tau2=tau2, L2=L2, q_face=q_face, J_shaft=j_shaft, J_face=j_face)
    ref = simulate_damped(params, [(T0, Q)], times, False)
    assert np.all(ref["plug_mode"] == 1) and np.all(ref["pipe_mode"] == 1)
    scale = np.max(np.abs(exact))
    assert np.max(np.abs(ref["v_pipe"] - exact[:, 0])) <= 1e-12 * scale
    assert np.max(np.abs(ref["v_plug"] - exact[:, 1])) <= 1e-12 * scale


def test_a_pipe_coring_a_held_plug_stops_where_the_closed_form_says():
    # The plug held by its face (Qp > F2) while the pipe slides over it: M1 v' = Q - T1 - Qf -
    # F2 - c v (c = J_face Qf), then -(T1 + Qf + F2) - c v to its stop; then all at rest.
    # (a case whose stop the integrator hits at exactly U1' = 0: the sliding speed integrated
    # beside it then kept a round-off of its own, and no mode was consistent)
    tau1, tau2, L2 = 1463.9469055238735, 18699.942956213617, 0.7424860623396188
    q_face, q_plug, j_face = 520780.67886684294, 4144054.1498948266, 0.09269895146041544
    Q, t0 = 34060.261700845265, 0.0754180835858043
    P1 = 2 * math.pi * (R1 + H1)
    T1, F2, Qf = P1 * L1 * tau1, P2 * L2 * tau2, q_face * S1
    assert q_plug * S2 > F2
    c = j_face * Qf
    push = _exponential(0.0, Q - T1 - Qf - F2, c, M1)
    v0 = push(t0)[0]
    t_stop = math.log(1 + c * v0 / (T1 + Qf + F2)) * M1 / c
    params = dict(tau1=tau1, tau2=tau2, L2=L2, q_face=q_face, q_plug_face=q_plug,
                  J_face=j_face)
    times = t0 * np.arange(1, 41) / 10.0
    assert times[-1] > t0 + t_stop
    ref = simulate_damped(params, [(t0, Q)], times, False, max_events=1000)
    stops = [t for t, what in ref["events"] if what.startswith("pipe stops")]
    assert len(stops) == 1 and abs(stops[0] - (t0 + t_stop)) <= 1e-12 * t0
    brake = _exponential(v0, -(T1 + Qf + F2), c, M1)
    v = [push(t)[0] if t <= t0 else (brake(t - t0)[0] if t < t0 + t_stop else 0.0)
         for t in times]
    np.testing.assert_allclose(ref["v_pipe"], v, rtol=0, atol=1e-12 * v0)
    assert np.all(ref["v_plug"] == 0.0)
