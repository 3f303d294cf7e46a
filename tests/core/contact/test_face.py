"""The contact problem with end resistance (pipeplug.contact.face) against its own definition:
the returned rates and forces satisfy the balance of both bodies, every window, and every
contact's sign rule (the conditions that characterise the unique minimiser of the convex
problem), and it reduces to the symmetric two-contact problem without end resistance."""
import numpy as np
import pytest

from pipeplug.contact.coulomb import two_contacts
from pipeplug.contact.face import PATTERNS, face_contacts, one_sided, sliding_pair

TOL = 1e-9


def _window_holds(f, x, cp, cm, scale):
    """f is -cp if x > 0, cm if x < 0, within [-cp, cm] if x == 0."""
    tol = TOL * scale
    if x > 0.0:
        return abs(f + cp) <= tol
    if x < 0.0:
        return abs(f - cm) <= tol
    return -cp - tol <= f <= cm + tol


def _problems(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        m1, m2 = rng.uniform(0.1, 10.0, 2)
        w1, w2 = rng.normal(0.0, 3.0, 2)
        c1 = rng.choice([0.0, rng.uniform(0, 10)])
        qf = rng.choice([0.0, rng.uniform(0, 10)])
        c2 = rng.choice([0.0, rng.uniform(0, 10)])
        c3 = rng.choice([0.0, rng.uniform(0, 10)])
        yield m1, m2, w1, w2, c1 + qf, c1, c2, c3


def test_thirteen_consistent_patterns():
    assert len(PATTERNS) == len(set(PATTERNS)) == 13
    assert PATTERNS[0] == (0, 0, 0)
    for s1, s2, s3 in PATTERNS:        # sign(x1), sign(x1 - x2), sign(x2) of some rates
        found = any(np.sign(a) == s1 and np.sign(a - b) == s2 and np.sign(b) == s3
                    for a in (-2, -1, 0, 1, 2) for b in (-2, -1, 0, 1, 2))
        assert found, (s1, s2, s3)


@pytest.mark.parametrize("seed", [0, 1])
def test_solution_satisfies_balance_windows_and_signs(seed):
    seen = set()
    for m1, m2, w1, w2, c1p, c1m, c2, c3 in _problems(1000, seed):
        x1, x2, f1, f2, f3, s1, s2, s3 = face_contacts(m1, m2, w1, w2, c1p, c1m, c2, c3, 0.0)
        seen.add((s1, s2, s3))
        scale = abs(m1 * w1) + abs(m2 * w2) + c1p + c1m + c2 + c3
        assert abs(m1 * x1 - (m1 * w1 + f1 + f2)) <= TOL * scale
        assert abs(m2 * x2 - (m2 * w2 - f2 + f3)) <= TOL * scale
        assert (np.sign(x1), np.sign(x1 - x2), np.sign(x2)) == (s1, s2, s3)
        assert _window_holds(f1, x1, c1p, c1m, scale)
        assert _window_holds(f2, x1 - x2, c2, c2, scale)
        assert _window_holds(f3, x2, c3, 0.0, scale)
    assert len(seen) >= 12             # the random problems reach nearly every pattern


def test_without_end_resistance_the_rates_are_the_two_contact_problems():
    for m1, m2, w1, w2, _, c1, c2, _ in _problems(500, 2):
        a = face_contacts(m1, m2, w1, w2, c1, c1, c2, 0.0, 0.0)
        b = two_contacts(m1, m2, w1, w2, c1, c2, 0.0)
        assert a[0] == pytest.approx(b[0], abs=1e-12) and a[1] == pytest.approx(b[1], abs=1e-12)


def test_a_plug_held_by_its_face_while_the_pipe_slides_over_it():
    # pipe pushed hard (w1 = 5), plug dragged forward by c2 = 1 but its face holds up to 3
    x1, x2, f1, f2, f3, s1, s2, s3 = face_contacts(1.0, 1.0, 5.0, 0.0, 2.0, 1.0, 1.0, 3.0, 0.0)
    assert (s1, s2, s3) == (1, 1, 0) and x2 == 0.0
    assert x1 == pytest.approx(5.0 - 2.0 - 1.0) and f3 == pytest.approx(-1.0)


@pytest.mark.parametrize("w, x, f", [(3.0, 0.0, -3.0),      # held against advance up to cp = 4
                                     (5.0, 1.0, -4.0),      # advances, resisted by cp
                                     (-0.5, 0.0, 0.5),      # held against retreat up to cm = 1
                                     (-3.0, -2.0, 1.0)])    # retreats, resisted by cm only
def test_one_sided_window(w, x, f):
    assert one_sided(1.0, w, 4.0, 1.0, 0.0) == pytest.approx((x, f))


def test_a_plug_below_the_pipes_round_off_is_decided_on_its_own_forces():
    # fuzz 4071:4781: the pipe/plug contact slides (the pipe advances over the plug, whose
    # friction 6e-9 N pushes it ahead, w2 = 6e-9 N / m2); its face holds up to 14.5 N; the
    # pipe decelerates under 6.2e4 N. By hand the plug is held: x2 = 0, f3 = -6e-9 N, s3 = 0
    # (and the pipe goes on decelerating, x1 = w1). All forces together put the wrong pattern
    # "plug carried backward" (violated by 6e-9 N) within their round-off of 6.2e-9 N.
    m1, m2, w1, friction, qp = 5.366, 3.289e-14, -11599.6, 5.57e-9, 14.5
    x1, x2, f1, f2, f3, s1, s2, s3 = sliding_pair(m1, m2, w1, friction / m2, 0.0, 0.0, qp)
    assert (x1, x2, f1, f2, s1, s2, s3) == (w1, 0.0, 0.0, 0.0, -1, -1, 0)
    assert f3 == pytest.approx(-friction, rel=1e-15)
