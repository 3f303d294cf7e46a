"""Closed-form pieces against an independent high-accuracy integration of U'' = a0 - k (U - U0)."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pipeplug.rigid.motion import motion, state, time_to_position, time_to_rest

CASES = [(0.3, 2.0, -5.0, 0.0), (0.3, 2.0, -5.0, 40.0), (0.3, 2.0, -5.0, -40.0),
         (0.0, -1.0, 3.0, 1e-10), (1.0, 0.0, 4.0, 900.0), (0.0, 5.0, 1.0, -3.0)]


@pytest.mark.parametrize("U0, V0, a0, k", CASES)
def test_state_matches_numerical_integration(U0, V0, a0, k):
    m = motion(U0, V0, a0, k)
    t = np.linspace(0, 0.4, 41)
    sol = solve_ivp(lambda _, y: [y[1], a0 - k * (y[0] - U0)], (0, 0.4), [U0, V0],
                    t_eval=t, rtol=1e-12, atol=1e-14, method="DOP853")
    got = np.array([state(m, ti) for ti in t]).T
    np.testing.assert_allclose(got, sol.y, rtol=1e-9, atol=1e-11)


@pytest.mark.parametrize("U0, V0, a0, k", CASES)
def test_time_to_rest_is_a_velocity_zero_with_the_right_sign_before(U0, V0, a0, k):
    m = motion(U0, V0, a0, k)
    sgn = 1 if V0 > 0 or (V0 == 0 and a0 > 0) else -1
    t = time_to_rest(m, sgn)
    if not math.isfinite(t):
        assert all(sgn * state(m, s)[1] > 0 for s in np.linspace(1e-6, 50, 200))
        return
    assert abs(state(m, t)[1]) <= 1e-14 * (abs(V0) + abs(a0) * t + 1)
    assert all(sgn * state(m, s)[1] > 0 for s in np.linspace(0, t, 50)[1:-1])


def test_uniform_deceleration_stop_time_is_exact():
    assert time_to_rest(motion(0.0, 10.0, -2.0), 1) == 5.0


def test_time_to_position_hits_the_target():
    m = motion(0.0, 10.0, -2.0, 4.0)
    t = time_to_position(m, 1.0, time_to_rest(m, 1))
    assert state(m, t)[0] == pytest.approx(1.0, abs=1e-15)
    assert time_to_position(m, 100.0, time_to_rest(m, 1)) == math.inf


def test_lag_is_the_harmonic_motions_lag_to_round_off():
    # (x - sin x)/w and (x^2/2 - 1 + cos x)/w^2 against their Taylor series summed in exact
    # rational arithmetic (60 terms: far below an ulp for x <= 8), across the switch at x = 1
    from fractions import Fraction

    from pipeplug.rigid.motion import lag

    def series(x, first):
        total, term, n = Fraction(0), x ** first, first
        for j in range(60):
            total += (-1) ** j * term / math.factorial(n)
            term, n = term * x * x, n + 2
        return total

    w = 7.5e4
    for x in (1e-9, 1e-3, 0.3, 0.999, 1.0, 1.001, 2.0, 8.0):
        t = x / w
        exact_x = Fraction(w) * Fraction(t)
        want_s = series(exact_x, 3) / Fraction(w)
        want_c = series(exact_x, 4) / Fraction(w) ** 2
        got_s, got_c = lag(w * w, w, t)
        assert abs(Fraction(got_s) - want_s) <= 8 * np.finfo(float).eps * want_s
        assert abs(Fraction(got_c) - want_c) <= 8 * np.finfo(float).eps * want_c
        arr_s, arr_c = lag(w * w, w, np.array([t, t]))
        assert arr_s[0] == got_s and arr_c[1] == got_c
