"""The joint two-contact Coulomb problem, the one source every solver uses.

Coulomb's law holds, the solution is the minimiser of the convex problem, the pattern returned
is the first consistent one of the table (by the scalar form, the form compiled by numba and
the vectorised form), and the compiled form gives the same bits.
"""
import numpy as np
import pytest
from contact_cases import as_arrays, boundary_cases, cases

from pipeplug import jit
from pipeplug.contact import vectorised
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


def test_coulomb_law_and_momentum_hold():
    for m1, m2, w1, w2, c1, c2 in cases():
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
    for m1, m2, w1, w2, c1, c2 in list(cases(600, seed=3)):
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


def _scalar_patterns(m1, m2, w1, w2, c1, c2):
    rows = [two_contacts(*case, 0.0)[4:] for case in zip(m1, m2, w1, w2, c1, c2)]
    return tuple(np.array(rows).T)


def _compiled_patterns(m1, m2, w1, w2, c1, c2):
    return _compiled()[1](m1, m2, w1, w2, c1, c2)


def _vectorised_patterns(m1, m2, w1, w2, c1, c2):
    return vectorised.two_contacts(m1, m2, w1, w2, c1, c2, 0.0)[4:]


@pytest.mark.parametrize("form", [_scalar_patterns, _compiled_patterns, _vectorised_patterns],
                         ids=["scalar", "compiled", "vectorised"])
def test_the_first_consistent_pattern_of_the_table_is_returned(form):
    """Ties on a stick/slip boundary go to the most stuck pattern: the table's order."""
    rows = list(cases(2000, seed=5)) + list(boundary_cases(2000, seed=6))
    s1, s2 = form(*as_arrays(rows))
    for (m1, m2, w1, w2, c1, c2), got in zip(rows, zip(s1, s2)):
        scale = SLACK * (abs(m1 * w1) + abs(m2 * w2) + c1 + c2)
        consistent = [p for p in PATTERNS if pattern(m1, m2, w1, w2, c1, c2, *p)[4] <= scale]
        assert consistent and got == consistent[0]


def test_pair_contact_is_two_contacts_without_soil():
    for m1, m2, w1, w2, _, c2 in cases(2000, seed=11):
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


_COMPILED = []


def _compiled():
    """The scalar projections called from code compiled by numba (compiled once): a function of
    scalars returning all three forms' results, and the patterns of arrays of cases."""
    if not _COMPILED:
        assert jit.enabled(), "the test environment has numba (the 'fast' extra)"
        import numba

        # The elastic cells module marks the projections for numba (coulomb never imports it).
        import pipeplug.elastic.cells  # noqa: F401

        @numba.njit
        def projections(m1, m2, w1, w2, c1, c2):
            return (one_contact(m1, w1, c1, 0.0), pair_contact(m1, m2, w1, w2, c2),
                    two_contacts(m1, m2, w1, w2, c1, c2, 0.0))

        @numba.njit
        def patterns(m1, m2, w1, w2, c1, c2):
            s1, s2 = np.empty(m1.size, np.int64), np.empty(m1.size, np.int64)
            for i in range(m1.size):
                s1[i], s2[i] = two_contacts(m1[i], m2[i], w1[i], w2[i], c1[i], c2[i], 0.0)[4:]
            return s1, s2

        _COMPILED.extend((projections, patterns))
    return _COMPILED


def test_compiled_projections_give_the_same_bits():
    """The elastic kernels call these functions compiled by numba: same results, bit for bit."""
    compiled = _compiled()[0]
    for m1, m2, w1, w2, c1, c2 in list(cases(3000, seed=13)) + list(boundary_cases(1000, 14)):
        plain = (one_contact(m1, w1, c1, 0.0), pair_contact(m1, m2, w1, w2, c2),
                 two_contacts(m1, m2, w1, w2, c1, c2, 0.0))
        assert compiled(m1, m2, w1, w2, c1, c2) == plain
