"""The growing plug's reference (pipeplug_references.growth_ivp) against closed forms derived
here: a pipe whose front soil grips it, a plug that slides ahead and leaves the pipe."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug_references.growth_ivp import simulate_growth

# model I, L1 = 3 m, R1 = 0.035 m, h1 = 3 mm, rho1 = 7800, rho2 = 1800 kg/m3 (the defaults)
PIPE = dict(L1=3.0, R1=0.035, h1=0.003, rho1=7800.0, rho2=1800.0, tau2=1e4)
M1 = 7800.0 * math.pi * (0.038 ** 2 - 0.035 ** 2) * 3.0
KAPPA = 2.0 * 1e4 / (1800.0 * 0.035)             # k/mu = P2 tau2/(rho2 S2) [m/s^2]


def test_front_soil_grips_a_pipe_starting_with_at_most_k_over_mu():
    # a1 = k/(2.7 mu) (c = 0.9): the front soil moves with the pipe, L2 stays 0 (the limit of a
    # plug of length eps stuck to it); the pipe alone without shaft friction: V1 = a1 t.
    a1 = KAPPA / 2.7
    times = np.array([0.002, 0.01])
    out = simulate_growth(dict(PIPE, tau1=0.0, L2=0.0), [(0.02, M1 * a1)], times)
    assert np.all(out["L2_now"] == 0.0) and np.all(out["W_accretion"] == 0.0)
    np.testing.assert_allclose(out["v_pipe"], a1 * times, rtol=1e-12)
    np.testing.assert_allclose(out["u_pipe"], 0.5 * a1 * times ** 2, rtol=1e-12)
    assert np.all(out["v_plug"] == out["v_pipe"])


def test_a_plug_sliding_ahead_of_a_held_pipe_leaves_it_entirely():
    # A plugged pipe (L2 = L1 = 0.5 m, tau2 = 1 kPa) pushed, then stopped by its shaft: the
    # plug slides ahead at V2' = -k/mu exactly (the soil leaving takes its own momentum), so
    # from the pipe's stop (t_s, L_s, V_s) it leaves at t_s + tau, where its length is 0 (no
    # face holds it back): L_s = V_s tau - k/mu tau^2/2; its displacement is kept there,
    # U2 = U2_s + L_s (fuzz 4092:2590: leaving 1e-10 L1 early, it was 2.2e-7 m short).
    # (The momentum P = mu L2 V2 integrated before: V2 = P/(mu L2) was 0/0 there, the plug's
    # end was missed and L2 fell below 0.)
    params = dict(PIPE, L1=0.5, L2=0.5, tau1=6e4, tau2=1e3)
    kappa = 2.0 * 1e3 / (1800.0 * 0.035)
    load = [(0.002, 60e3)]
    out = simulate_growth(params, load, np.linspace(0.001, 0.05, 50))
    stops = [t for t, text in out["events"] if "pipe stops" in text]
    leaves = [t for t, text in out["events"] if "plug leaves the pipe" in text]
    assert len(stops) == 1 and len(leaves) == 1
    at_stop = simulate_growth(params, load, [stops[0]])
    length, speed = at_stop["L2_now"][0], at_stop["v_plug"][0]
    tau = (speed - math.sqrt(speed * speed - 2.0 * kappa * length)) / kappa
    assert leaves[0] == pytest.approx(stops[0] + tau, rel=1e-12)
    assert np.all(out["L2_now"] >= 0.0) and out["L2_now"][-1] == 0.0
    assert out["u_plug"][-1] == pytest.approx(at_stop["u_plug"][0] + length, rel=1e-12)


def test_a_heavy_plug_closes_the_ledger():
    # fuzz 4043:100: a plug of 270 pipe masses, the pipe without shaft friction pushed back
    # and held by its annulus while the plug cores past it backward: works of a few J, where
    # the load's impulse over the pipe's mass estimated 2e6 J; W_accretion was 1.6e-3 off its
    # own value. W_input = E_kinetic + W_friction + W_face + W_accretion + W_removed exactly.
    params = dict(L1=2.0776129330690627, L2=0.05512573859779427, R1=0.035, h1=0.003,
                  rho1=7800.0, rho2=13899896.677086992, tau1=0.0, tau2=50344.41998828079,
                  q_face=39876788.56302614, q_plug_face=0.0, L2_after_cleanout=1.7978923779411766)
    segments = [(0.19087329750681503, 26772.51557697181), (0.026205174804841653, -610.314482714613),
                (0.17709503195355833, 1169.6767374358897)]
    out = simulate_growth(params, segments, np.linspace(0.2, 0.3, 11), cleanouts=(0.2170784723116567,))
    works = ("W_friction_outer", "W_friction_inner", "W_face", "W_accretion", "W_removed")
    balance = out["W_input"] - out["E_kinetic"] - sum(out[n] for n in works)
    assert out["W_accretion"][-1] > 1e-5
    assert np.max(np.abs(balance)) <= 1e-13 * np.max(out["W_input"])


def test_the_plug_filling_the_pipe_is_seen_within_a_long_step():
    # fuzz 4043:1710: a pipe coring a heavy plug held by its face moves in a quadratic, which
    # DOP853 takes in one step: the plug filled the pipe and, the velocity turning past the
    # pipe's stop, the length came back below L1 before the step's end, the event unseen
    # (L2 1.9e-2 m past L1). The fill is an event, and L2 never exceeds L1.
    params = dict(L1=1.0, L2=1.0, R1=0.035, h1=0.003, rho1=7800.0, rho2=333090.7430787556,
                  tau1=47135.079687518264, tau2=157.3475209728314, q_face=0.0,
                  q_plug_face=14919.94631710386, L2_after_cleanout=0.994025135393172)
    segments = [(0.006150408446427141, -52628.12670486324),
                (0.007955883397041133, 51502.939938659954)]
    out = simulate_growth(params, segments, np.array([0.1, 0.1895]),
                          cleanouts=(0.006150408446427141,))
    assert any("plug fills the pipe" in text for _, text in out["events"])
    assert np.all(out["L2_now"] <= 1.0)


def test_a_plug_held_back_by_its_face_leaves_the_pipe():
    # fuzz 4043:4590: the pipe retreating fast, the plug ahead held back by its face slows as
    # qp/(mu L2) and would stop some 1e-17 m before its end: DOP853 ran out of step size. It
    # leaves where it is shorter than round-off of L1 (as at any decision), its rest's kinetic
    # energy booked in W_accretion: the ledger closes.
    params = dict(L1=1.0, L2=1.0, R1=0.035, h1=0.003, rho1=7800.0, rho2=6402.224676442344,
                  tau1=227765.97180737316, tau2=371.62791584518527, q_face=0.0,
                  q_plug_face=14564.690082333302, L2_after_cleanout=0.9388675492199381)
    segments = [(3.909692426342999e-05, 10724.181079052098),
                (0.0018869061023766434, 31661.740710995116),
                (0.03785006863220124, -23351.584820672084)]
    out = simulate_growth(params, segments, np.linspace(0.01, 0.04, 7), True,
                          cleanouts=(0.004033814291839236,))
    assert any("plug leaves the pipe" in text for _, text in out["events"])
    works = ("W_friction_outer", "W_friction_inner", "W_face", "W_accretion", "W_removed")
    balance = out["W_input"] - out["E_kinetic"] - sum(out[n] for n in works)
    assert np.max(np.abs(balance)) <= 1e-12 * np.max(out["W_input"])


def test_a_plugged_pipe_stopped_behind_the_surface_goes_on_to_the_soil():
    # fuzz 4043:6970: model II, a full plug (L2 = L1), no shaft friction: the body (M1 + M2)
    # pushed back by -Q0 for t0, then forward by Q < Qp. It stops at U_s < 0, where nothing
    # resists it (the plug's face, the body's front, meets the soil from U1 = 0 on): by hand,
    # it comes back, enters the soil and stops for good at U_f, Q (U_f - U_s) = Qp U_f.
    # (The reference held the full plug as a plug of its own at rest: its face took Qp at
    # U1 < 0 and kept the pipe at U_s.)
    params = dict(L1=1.0, L2=1.0, R1=0.035, h1=0.003, rho1=7800.0, rho2=1800.0, tau1=0.0,
                  tau2=1e5, q_plug_face=1e6)
    qp = 1e6 * math.pi * 0.035 ** 2
    m = 7800.0 * math.pi * (0.038 ** 2 - 0.035 ** 2) + 1800.0 * math.pi * 0.035 ** 2
    q0, t0, q = 1000.0, 0.01, 2000.0
    v0, u0 = -q0 * t0 / m, -q0 * t0 ** 2 / (2.0 * m)
    u_s = u0 - v0 * v0 * m / (2.0 * q)
    u_f = -q * u_s / (qp - q)
    t_s = t0 + q0 * t0 / q                  # the stop; the velocity's scale is measured
    times = np.sort(np.append(np.linspace(0.002, 0.2, 100), t_s))    # on the samples
    out = simulate_growth(params, [(t0, -q0), (1.0, q)], times, True)
    assert u_s < 0.0 < u_f
    np.testing.assert_allclose(np.min(out["u_pipe"]), u_s, rtol=1e-12)
    np.testing.assert_allclose(out["u_pipe"][-1], u_f, rtol=1e-12)
    np.testing.assert_allclose(out["W_face"][-1], qp * u_f, rtol=1e-12)
    assert out["v_pipe"][-1] == 0.0
    np.testing.assert_allclose(out["u_plug"], out["u_pipe"], rtol=0.0, atol=1e-15)


def test_a_plugged_pipes_plug_breaks_away_ahead_where_its_friction_ends():
    # fuzz 4043:7540: model II, a full plug pushed with the pipe as one body (M = M1 + M2)
    # against the growing shaft friction k1 U1 and the plug's face Qp. The plug follows the
    # body's deceleration a while the force it needs from the pipe, M2 a + Qp, is at least
    # -c2 (c2 = k L1; the head pushes it, only friction pulls it): by hand, it breaks away
    # ahead at M (Q - k1 U_b - Qp)/M = -(c2 + Qp)/M2. (The reference counted Qp twice in
    # the body's deceleration there and broke it away 7.9e-4 m early.)
    r1, tau1, tau2, q_plug = 0.035, 199437.7242976858, 57.684789699749395, 9730.594191097429
    params = dict(L1=1.0, L2=1.0, R1=r1, h1=0.003, rho1=7800.0, rho2=15.98900618559651,
                  tau1=tau1, tau2=tau2, q_plug_face=q_plug)
    s2 = math.pi * r1 ** 2
    m2 = 15.98900618559651 * s2
    m = 7800.0 * math.pi * (0.038 ** 2 - r1 ** 2) + m2
    k1, c2, qp, q = 2.0 * math.pi * 0.038 * tau1, 2.0 * math.pi * r1 * tau2, q_plug * s2, 36718.0
    u_b = (q - qp + m * (c2 + qp) / m2) / k1
    out = simulate_growth(params, [(0.03, q)], np.linspace(0.001, 0.03, 30), True)
    breaks = [t for t, text in out["events"] if "plug breaks away ahead" in text]
    assert len(breaks) == 1 and u_b < 1.0
    at_break = simulate_growth(params, [(0.03, q)], np.append(np.linspace(0.001, 0.017, 17),
                                                              breaks[0]), True)
    assert at_break["u_pipe"][-1] == pytest.approx(u_b, rel=1e-12)
    assert np.all(out["L2_now"] <= 1.0) and np.all(out["W_accretion"] >= 0.0)


def test_a_plug_stopping_ahead_of_a_held_pipe_books_the_soil_it_sheds():
    # fuzz 4091:3320 (model II): after the pipe stops, the plug slides on ahead at V2' = -k/mu
    # (no face resistance) and sticks where V2 = 0. The soil it sheds leaves with its
    # velocity: W_accretion' = mu V2^3/2, so from any t_a in that piece, where V2 = v_a,
    # W_accretion grows by mu v_a^4/(8 k/mu) until the stick, at t_a + v_a mu/k. The accretion
    # rate written with |V1 - V2| has a kink at the stick, and the last step's dense output,
    # on which the stick is found, was 13 times that off (7e-3 J against 5.9e-4 J).
    params = dict(L1=1.0, L2=0.0, R1=0.035, h1=0.003, rho1=7800.0, rho2=1800.0,
                  tau1=158250.8680974062, tau2=163715.96432152102, L2_after_cleanout=0.8)
    segments = [(0.0005619137708489526, 47197.37918852264),
                (0.00019218692575400265, -20469.71183983107),
                (0.1409240986952473, 37784.14211256542),
                (0.0017459515727168713, -21345.07131669808),
                (0.06891714128761589, -37784.14211256542)]
    kappa = 2.0 * 163715.96432152102 / (1800.0 * 0.035)
    mu = 1800.0 * math.pi * 0.035 ** 2
    events = simulate_growth(params, segments, [0.2], True)["events"]
    stop = [t for t, text in events if "pipe stops" in text][-1]
    stick = [t for t, text in events if "plug sticks" in text and t > stop][0]
    t_a = stop + 0.9 * (stick - stop)
    out = simulate_growth(params, segments, [t_a, stick + 1e-4], True)
    v_a = out["v_plug"][0]
    assert out["v_pipe"][0] == 0.0 and v_a > 1.0
    assert stick == pytest.approx(t_a + v_a / kappa, rel=1e-12)
    gained = out["W_accretion"][1] - out["W_accretion"][0]
    assert gained == pytest.approx(mu * v_a ** 4 / (8.0 * kappa), rel=1e-9)
