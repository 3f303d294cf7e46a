"""The joint two-contact Coulomb problem, the one source every solver uses.

Coulomb's law holds, the solution is the minimiser of the convex problem, the pattern returned
is the first consistent one of the table, and the compiled form (numba) gives the same bits.
"""
import numpy as np
import pytest

from pipeplug import jit
from pipeplug.contact.coulomb import (
    PATTERNS,
    SLACK,
    one_contact,
    pair_contact,
    pattern,
    two_contacts,
)


def _objective(m1, m2, w1, w2, c1, c2, x1, x2):
    return (0.5 * m1 * (x1 - w1) ** 2 + 0.5 * m2 * (x2 - w2) ** 2 + c1 * abs(x1)
            + c2 * abs(x1 - x2))


def _cases(n=4000, seed=1):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        m1, m2 = 10.0 ** rng.uniform(-3, 3, 2)
        w1, w2 = rng.normal(0, 1, 2) * 10.0 ** rng.uniform(-2, 2, 2)
        c1, c2 = 10.0 ** rng.uniform(-3, 3, 2) * (rng.random(2) > 0.1)
        if rng.random() < 0.2:       # place the case exactly on a stick/slip boundary
            w1 = c1 / m1 * rng.choice([-1, 1])
        yield m1, m2, w1, w2, c1, c2


def test_coulomb_law_and_momentum_hold():
    for m1, m2, w1, w2, c1, c2 in _cases():
        x1, x2, f1, f2, s1, s2 = two_contacts(m1, m2, w1, w2, c1, c2, 0.0)
        scale = abs(m1 * w1) + abs(m2 * w2) + c1 + c2
        assert abs(m1 * x1 - m1 * w1 - f1 - f2) <= 1e-12 * scale
        assert abs(m2 * x2 - m2 * w2 + f2) <= 1e-12 * scale
        assert abs(f1) <= c1 and abs(f2) <= c2
        if s1 != 0:
            assert np.sign(x1) == s1 and f1 == -c1 * s1
        else:
            assert x1 == 0.0
        if s2 != 0:
            assert np.sign(x1 - x2) == s2 and f2 == -c2 * s2
        else:
            assert x1 == x2


def test_solution_minimises_the_convex_objective():
    rng = np.random.default_rng(7)
    for m1, m2, w1, w2, c1, c2 in list(_cases(600, seed=3)):
        x1, x2, *_ = two_contacts(m1, m2, w1, w2, c1, c2, 0.0)
        j0 = _objective(m1, m2, w1, w2, c1, c2, x1, x2)
        size = abs(w1) + abs(w2) + 1e-9
        for d1, d2 in rng.normal(0, size, (20, 2)) * 10.0 ** rng.uniform(-6, 0, (20, 1)):
            assert j0 <= _objective(m1, m2, w1, w2, c1, c2, x1 + d1, x2 + d2) * (1 + 1e-12)


def test_load_exactly_at_the_limit_sticks():
    # Static limit = sliding limit: a body loaded exactly to its limit does not move.
    x1, x2, f1, f2, s1, s2 = two_contacts(2.0, 3.0, 5.0, 0.0, 10.0, 1e9, 0.0)
    assert (x1, x2, s1, s2) == (0.0, 0.0, 0, 0) and f1 == -10.0
    assert one_contact(2.0, 5.0, 10.0, 0.0) == (0.0, -10.0)


@pytest.mark.parametrize("w1, expected", [(3.0, 1.0), (-3.0, -1.0), (0.5, 0.0)])
def test_one_contact(w1, expected):
    x, f = one_contact(1.0, w1, 2.0, 0.0)
    assert x == expected and f == pytest.approx(-(w1 - x))


def test_sliding_plug_drags_a_stopped_pipe():
    # docs/corrections.md B4: with F2 > F1 a plug sliding forward drags a stopped pipe (the paper's
    # sequential test with k2 = 0 would leave the pipe at rest).
    m1, m2, F1, F2 = 1.0, 1.0, 1.0, 3.0
    # accelerations: pipe at rest, plug moving forward relative to it -> f2 = +F2 on the pipe
    x1, x2, f1, f2, s1, s2 = two_contacts(m1, m2, F2 / m1, -F2 / m2, F1, 0.0, 0.0)
    assert s1 == 1 and x1 == pytest.approx((F2 - F1) / m1)


def test_the_first_consistent_pattern_of_the_table_is_returned():
    """Ties on a stick/slip boundary go to the most stuck pattern: the table's order."""
    for m1, m2, w1, w2, c1, c2 in _cases(2000, seed=5):
        x1, x2, f1, f2, s1, s2 = two_contacts(m1, m2, w1, w2, c1, c2, 0.0)
        scale = SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1 + c2)
        consistent = [p for p in PATTERNS if pattern(m1, m2, w1, w2, c1, c2, *p)[4] <= scale]
        assert consistent and (s1, s2) == consistent[0]


def test_pair_contact_is_two_contacts_without_soil():
    for m1, m2, w1, w2, _, c2 in _cases(2000, seed=11):
        x1, x2, f2 = pair_contact(m1, m2, w1, w2, c2)
        ref = two_contacts(m1, m2, w1, w2, 0.0, c2, 0.0)
        # Both exact to round-off in momentum; a light body turns that into velocity.
        scale = (abs(m1 * w1) + abs(m2 * w2) + abs(f2) + c2) / min(m1, m2)
        np.testing.assert_allclose([x1, x2], ref[:2], rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(f2, ref[3], rtol=0,
                                   atol=1e-12 * (abs(m1 * w1) + abs(m2 * w2) + c2))


def test_stick_at_the_limit_and_never_reverse():
    assert one_contact(2.0, 3.0, 6.0, 0.0) == (0.0, -6.0)       # exactly at the limit: stuck
    x1, x2, _ = pair_contact(1.0, 1.0, 2.0, 0.0, 1.0)          # |w1 - w2| m / 2 = 1 = c2
    assert x1 == x2 == 1.0
    x, f = one_contact(2.0, 3.0, 5.0, 0.0)                      # above it: slowed, not reversed
    assert 0.0 < x < 3.0 and f == -5.0


def test_compiled_projections_give_the_same_bits():
    """The elastic kernels call these functions compiled by numba: same results, bit for bit."""
    assert jit.enabled(), "the test environment has numba (the 'fast' extra)"
    import numba

    @numba.njit
    def compiled(m1, m2, w1, w2, c1, c2):
        return (one_contact(m1, w1, c1, 0.0), pair_contact(m1, m2, w1, w2, c2),
                two_contacts(m1, m2, w1, w2, c1, c2, 0.0))

    for m1, m2, w1, w2, c1, c2 in _cases(3000, seed=13):
        plain = (one_contact(m1, w1, c1, 0.0), pair_contact(m1, m2, w1, w2, c2),
                 two_contacts(m1, m2, w1, w2, c1, c2, 0.0))
        assert compiled(m1, m2, w1, w2, c1, c2) == plain
