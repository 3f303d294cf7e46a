"""Rigid drives through the FMU against the independent model II reference, the energy balance
of every blow, and both refusals (static friction derived by hand; a set threshold)."""
import math

import numpy as np
import pytest

from pipeplug_references.rigid_ivp import simulate

# Default pipe and plug of the paper (L1 = L2 = 1 m, R1 = 35 mm, h1 = 3 mm, rho1 = 7800, rho2 = 1800).
R1, H1, RHO1, RHO2, L1 = 0.035, 0.003, 7800.0, 1800.0, 1.0
P1 = 2.0 * math.pi * (R1 + H1)


def _masses(L2):
    return RHO1 * math.pi * ((R1 + H1) ** 2 - R1 ** 2) * L1, RHO2 * math.pi * R1 ** 2 * L2


def _sections(tau1, tau2, amplitude, duration, period, L2=1.0, **drive):
    return {"pipe": {"L1": L1}, "plug": {"L2": L2, "tau2": tau2}, "soil": {"tau1": tau1},
            "blows": {"amplitude": amplitude, "duration": duration, "period": period},
            "model": {"elastic": False}, "drive": {"refusal_set": 0.0, **drive}}


def _reference(tau1, tau2, amplitude, duration, period, blows, L2=1.0, samples=None):
    """The reference at the window ends k * period, k = 0..blows (and on ``samples``)."""
    segments = [(duration, amplitude), (period - duration, 0.0)] * blows
    params = {"L1": L1, "L2": L2, "tau1": tau1, "tau2": tau2}
    times = np.arange(blows + 1) * period if samples is None else samples
    return simulate(params, segments, times, contact_growth=True)


# Blows 1 and 2 end with the pipe still moving (the next blow hits a moving pipe), the plug slides
# in the pipe both ways, and after a few blows a blow cannot overcome the grown friction.
MOVING = dict(tau1=2.0e5, tau2=3.0e4, amplitude=1.5e4, duration=0.01, period=0.015)
# Every blow ends at rest; the sets fall.
RESTING = dict(tau1=2.0e5, tau2=3.0e4, amplitude=1.5e4, duration=0.01, period=0.03)


@pytest.mark.parametrize("case", [MOVING, RESTING], ids=["moving", "resting"])
def test_every_blow_matches_the_reference(run_drive, case):
    blows = 6
    got = run_drive(_sections(**case, max_blows=blows))
    n = len(got["blows"])
    zero = np.flatnonzero(np.diff(_reference(**case, blows=blows)["u_pipe"]) == 0.0)
    assert n == (zero[0] + 1 if zero.size else blows)      # stops where the reference stops
    assert got["outcome"] == ("static" if zero.size else "max_blows")
    ref = _reference(**case, blows=n)
    fine = _reference(**case, blows=n, samples=np.linspace(0.0, n * case["period"], 4001))
    end = {"penetration": np.array([b["penetration"] for b in got["blows"]])}
    for name in ("W_input", "W_friction_outer", "W_friction_inner"):
        end[name] = np.cumsum([b[name] for b in got["blows"]])
    end["v_pipe"] = np.array([b["v_pipe_end"] for b in got["blows"]])
    end["v_plug"] = np.array([b["v_plug_end"] for b in got["blows"]])
    refs = {"penetration": "u_pipe", "W_input": "W_input", "v_pipe": "v_pipe",
            "v_plug": "v_plug", "W_friction_outer": "W_friction_outer",
            "W_friction_inner": "W_friction_inner"}
    for name, ref_name in refs.items():
        scale = np.abs(fine[ref_name]).max()
        err = np.abs(end[name] - ref[ref_name][1:]).max()
        assert err <= 1e-9 * scale, (name, err, scale)
    if case is MOVING:                                       # the cases are what they say
        assert end["v_pipe"][0] > 1.0 and end["v_pipe"][1] > 1.0 and zero.size
        assert np.ptp(fine["plug_mode"]) == 2              # the plug slides both ways
    else:
        assert not end["v_pipe"].any() and not zero.size


@pytest.mark.parametrize("case", [MOVING, RESTING], ids=["moving", "resting"])
def test_energy_balance_of_every_blow(run_drive, case):
    """Input work = change of kinetic energy + friction work, blow by blow, to round-off."""
    got = run_drive(_sections(**case, max_blows=6))["blows"]
    M1, M2 = _masses(1.0)
    kinetic = [0.0] + [0.5 * (M1 * b["v_pipe_end"] ** 2 + M2 * b["v_plug_end"] ** 2) for b in got]
    scale = sum(b["W_input"] for b in got)
    for b, k0, k1 in zip(got, kinetic[:-1], kinetic[1:]):
        residual = b["W_input"] - (k1 - k0) - b["W_friction_outer"] - b["W_friction_inner"]
        assert abs(residual) <= 1e-12 * scale, (b["blow"], residual)


@pytest.mark.parametrize("excess, stops", [(1e-3, True), (-1e-3, False)])
def test_static_friction_refusal_derived_by_hand(run_drive, excess, stops):
    """A blow of amplitude A cannot move a pipe at rest at penetration U when A <= P1 tau1 U.

    At rest under Q the soil must hold Q with the friction of the penetrated length U, limit
    P1 tau1 U (model II); the plug rides inside the pipe and has no contact with the soil, so it
    adds nothing to the limit, and with Q <= P1 tau1 U stuck soil and stuck plug solve the
    equations (Coulomb: the static force within the limit). Blow 1, from U = 0 with the plug
    held (checked below): (M1 + M2) U'' = A - k U, k = P1 tau1, so U = (A/k)(1 - cos w t),
    w^2 = k / (M1 + M2), while it lasts (t_d <= pi/w); after it, (M1 + M2) U'' = -k U, harmonic
    about 0, so the pipe stops at U* = sqrt(U^2 + (U'/w)^2) = (2A/k) sin(w t_d / 2). Blow 2
    moves the pipe iff A > k U*, i.e. iff w t_d < pi/3. The plug stays held while its required
    force M2 |Q - k U| / (M1 + M2) <= M2 A / (M1 + M2) is within its limit P2 L2 tau2.
    """
    tau1, tau2, A = 1.0e6, 2.0e5, 5.0e4
    M1, M2 = _masses(1.0)
    k = P1 * tau1
    w = math.sqrt(k / (M1 + M2))
    assert M2 * A / (M1 + M2) < 2.0 * math.pi * R1 * 1.0 * tau2        # the plug is held
    duration = math.pi / 3.0 * (1.0 + excess) / w
    u_star = 2.0 * A / k * math.sin(w * duration / 2.0)
    assert u_star < L1
    got = run_drive(_sections(tau1, tau2, A, duration, 0.1, max_blows=2))
    first, second = got["blows"]
    assert first["penetration"] == pytest.approx(u_star, rel=1e-12)
    assert first["W_friction_inner"] == 0.0 and first["v_plug_peak"] == first["v_pipe_peak"]
    if stops:
        assert got["outcome"] == "static"
        assert second["set"] == 0.0 and second["W_input"] == 0.0
    else:
        assert got["outcome"] == "max_blows" and second["set"] > 0.0


@pytest.mark.parametrize("form", ["per_blow", "per_length"])
def test_set_threshold_refusal(run_drive, form):
    """Refusal at the first blow whose set (or whose last 3 blows' advance) is below the
    threshold, the sets taken from the reference."""
    blows = 8
    sets = np.diff(_reference(**RESTING, blows=blows)["u_pipe"])
    if form == "per_blow":
        threshold = 0.5 * (sets[3] + sets[4])             # blow 5 is the first below
        drive = {"refusal_set": threshold}
        below = sets < threshold
    else:
        window = np.convolve(sets, np.ones(3), mode="valid")   # blows 1-3, 2-4, ...
        threshold = 0.5 * (window[2] + window[3])
        drive = {"refusal_count": 3, "refusal_length": threshold}
        below = np.r_[False, False, window < threshold]
    expected = int(np.argmax(below)) + 1
    sections = _sections(**RESTING, max_blows=blows)
    sections["drive"] = {"max_blows": blows, **drive}
    got = run_drive(sections)
    assert got["outcome"] == "set" and len(got["blows"]) == expected < blows
