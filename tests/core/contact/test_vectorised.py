"""The vectorised two-contact projection gives the scalar form's numbers, bit for bit.

Its choice of pattern is checked against the table in test_coulomb (with the scalar and
compiled forms); here every number it returns is compared with the scalar form's, signed zeros
included, on random cases, on stick/slip boundaries and on degenerate points.
"""
import numpy as np
import pytest
from contact_cases import as_arrays, boundary_cases, cases

from pipeplug.contact import coulomb, vectorised

ROWS = list(cases(3000, seed=21)) + list(boundary_cases(3000, seed=22))


def _bits(values):
    """The bytes of float64 values (distinguishes -0.0 from 0.0)."""
    return np.asarray(values, dtype=float).tobytes()


def _assert_same_bits(scalar_rows, vectorised_columns):
    got = np.column_stack(vectorised_columns).astype(float)
    for i, expected in enumerate(scalar_rows):
        assert _bits(expected) == _bits(got[i]), (i, ROWS[i], expected, got[i])


@pytest.mark.parametrize("slack", [0.0, 1e-3])
def test_two_contacts_equal_the_scalar_form(slack):
    expected = [coulomb.two_contacts(*row, slack) for row in ROWS]
    _assert_same_bits(expected, vectorised.two_contacts(*as_arrays(ROWS), slack))


def test_pair_and_one_contact_equal_the_scalar_forms():
    m1, m2, w1, w2, c1, c2 = as_arrays(ROWS)
    expected = [coulomb.pair_contact(a, b, x, y, c) for a, b, x, y, c in zip(m1, m2, w1, w2, c2)]
    _assert_same_bits(expected, vectorised.pair_contact(m1, m2, w1, w2, c2))
    for slack in (0.0, 1e-3):
        expected = [coulomb.one_contact(a, x, c, slack) for a, x, c in zip(m1, w1, c1)]
        _assert_same_bits(expected, vectorised.one_contact(m1, w1, c1, slack))


def test_a_solver_made_once_serves_every_step():
    """As the elastic kernels use it: fixed scalar masses and plug limit, soil limits an array
    or a float, called again and again on new rates (its table is reused)."""
    rng = np.random.default_rng(3)
    m1, m2, c2, nodes = 3.0, 0.7, 2.0, 64
    solve = vectorised.TwoContacts(m1, m2, c2, 0.0, nodes)
    for call in range(20):
        w1, w2 = rng.normal(0, 3, (2, nodes))
        w2[::7] = w1[::7]
        c1 = rng.uniform(0, 5, nodes) if call % 2 else 4.0
        c1_nodes = np.broadcast_to(c1, nodes)
        expected = [coulomb.two_contacts(m1, m2, a, b, c, c2, 0.0)[:4]
                    for a, b, c in zip(w1, w2, c1_nodes)]
        got = np.column_stack(solve(w1, w2, c1))
        assert all(_bits(e) == _bits(g) for e, g in zip(expected, got))


def test_the_least_violated_pattern_when_none_is_consistent(monkeypatch):
    """Unreachable with the real slack; forced here in both forms with a negative relative
    slack (and an absolute one of -inf, so that the scale may be negative)."""
    monkeypatch.setattr(coulomb, "SLACK", -1e-3)
    monkeypatch.setattr(vectorised, "SLACK", -1e-3)
    m1, m2, w1, w2, c1, c2 = arrays = as_arrays(ROWS)
    table = vectorised.TwoContacts(m1, m2, c2, -np.inf, m1.size)
    table(w1, w2, c1)
    scale = -1e-3 * (abs(m1 * w1) + abs(m2 * w2) + c1 + c2)
    none = ~(table.table[4] <= scale).any(axis=0)
    assert 0 < none.sum() < none.size     # both ways through the code
    expected = [coulomb.two_contacts(*row, -np.inf) for row in ROWS]
    _assert_same_bits(expected, vectorised.two_contacts(*arrays, -np.inf))
