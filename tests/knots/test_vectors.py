"""Knot vectors: construction, validation, periodic extension, Greville abscissae."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BSplineCurve, CagdError
from cagd.knots import (averaged, clamped_uniform, distinct_with_multiplicities, find_span,
                        from_multiplicities, greville, periodic_extend, uniform, validate,
                        validate_period)

from strategies import clamped_knots, floating_knots, periodic_knots


# --- validation -------------------------------------------------------------------------

BAD_FULL = [  # (knots, degree, count, words expected in the message)
    ([0, 0, 0, 1, 1, 1], 2, 4, "expected 7"),                          # wrong length
    ([0, 0, 0, 0.5, 0.4, 1, 1, 1], 2, 5, "non-decreasing"),            # decreasing
    ([0, 0, 0, np.nan, 1, 1, 1], 2, 4, "nan"),                         # NaN
    ([0, 0, 0, np.inf, 1, 1, 1], 2, 4, "inf"),                         # inf
    ([0, 0, 0, 0, 1, 1, 1], 2, 4, "multiplicity"),                     # end multiplicity > p+1
    ([0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1], 2, 6, "multiplicity"),         # interior multiplicity > p
    ([0, 0, 1, 1, 2, 2], 1, 4, "multiplicity"),                        # interior, degree 1
    ([0, 0, 0, 1, 1, 1, 1], 2, 4, "multiplicity"),
    ([0, 0, 1, 1, 1, 1, 2, 3], 3, 4, "empty domain"),                  # u_p == u_n
    ([[0, 0, 1, 1]], 1, 2, "1-d"),                                     # wrong ndim
    (["a", 0, 1, 1], 1, 2, "numeric"),
]


@pytest.mark.parametrize("knots,degree,count,words", BAD_FULL)
def test_validate_rejects(knots, degree, count, words):
    with pytest.raises(CagdError) as exc:
        validate(knots, degree, count)
    msg = str(exc.value)
    assert msg.startswith("knots"), msg
    assert words.lower() in msg.lower(), msg


@pytest.mark.parametrize("knots,degree,count,words", BAD_FULL[:9])
def test_constructor_rejects_bad_knots(knots, degree, count, words):
    P = np.arange(2.0 * count).reshape(count, 2)
    with pytest.raises(CagdError, match=r"^knots"):
        BSplineCurve(P, degree, knots)


def test_cagd_error_is_value_error():
    assert issubclass(CagdError, ValueError)


def test_validate_accepts_and_returns_float_array():
    u = validate([0, 0, 0, 1, 2, 2, 2], 2, 4)
    assert u.dtype == np.float64 and u.shape == (7,)
    validate([0, 0, 0, 1, 1, 2, 2, 2], 2, 5)                           # interior multiplicity = p is fine
    validate([0, 1, 2, 3, 4, 5, 6], 2, 4)                              # floating
    validate([-1, 0, 0, 0, 1, 2, 2, 2, 3], 2, 6)                       # unclamped with an inner clamp


BAD_PERIOD = [  # (period, count, degree, words)
    ([0, 0.5, 1], 3, 2, "4 knots"),
    ([0, 0.6, 0.5, 1], 3, 2, "non-decreasing"),
    ([0, 0, 0, 0], 3, 2, "empty"),
    ([0, 0.5, 0.5, 0.5, 1], 4, 2, "multiplicity"),
    ([0, 0, 0.5, 1, 1], 4, 2, "multiplicity"),                          # seam: 2 + 2 - 1 = 3 > 2
    ([0, 0, 0, 0.5, 1], 4, 2, "multiplicity"),
    ([0, np.nan, 0.5, 1], 3, 2, "nan"),
]


@pytest.mark.parametrize("period,count,degree,words", BAD_PERIOD)
def test_validate_period_rejects(period, count, degree, words):
    with pytest.raises(CagdError) as exc:
        validate_period(period, count, degree)
    assert str(exc.value).startswith("knots")
    assert words.lower() in str(exc.value).lower()
    with pytest.raises(CagdError, match=r"^knots"):
        BSplineCurve(np.random.default_rng(0).normal(size=(count, 2)), degree, period, periodic=True)


def test_validate_period_accepts_seam_multiplicity_up_to_degree():
    validate_period([0, 0, 0.5, 1], 3, 2)
    validate_period([0, 0.5, 1, 1], 3, 2)
    validate_period([0, 0, 0.3, 0.6, 1, 1], 5, 3)


# --- construction -----------------------------------------------------------------------

@pytest.mark.parametrize("count,degree", [(2, 1), (4, 3), (7, 3), (11, 10), (12, 5)])
def test_clamped_uniform(count, degree):
    u = clamped_uniform(count, degree, -2.0, 3.0)
    assert u.shape == (count + degree + 1,)
    np.testing.assert_array_equal(u[:degree + 1], -2.0)
    np.testing.assert_array_equal(u[-degree - 1:], 3.0)
    inner = u[degree:count + 1]
    np.testing.assert_allclose(np.diff(inner), 5.0 / (count - degree), rtol=1e-13)
    validate(u, degree, count)
    assert BSplineCurve(np.zeros((count, 2)), degree, u).domain == (-2.0, 3.0)
    np.testing.assert_array_equal(clamped_uniform(count, degree), clamped_uniform(count, degree, 0.0, 1.0))


@pytest.mark.parametrize("count,degree", [(2, 1), (4, 3), (7, 3), (11, 10), (12, 5)])
def test_uniform(count, degree):
    u = uniform(count, degree, 1.0, 4.0)
    assert u.shape == (count + degree + 1,)
    np.testing.assert_allclose(np.diff(u), 3.0 / (count - degree), rtol=1e-12)
    assert u[degree] == pytest.approx(1.0, abs=1e-14)
    assert u[count] == pytest.approx(4.0, abs=1e-14)
    validate(u, degree, count)


def test_seed_uniform_vectors():
    """The seed's integer knots T = (0..7) are uniform for 4 cubic control points."""
    np.testing.assert_allclose(uniform(4, 3, 3.0, 4.0), np.arange(8.0))
    np.testing.assert_allclose(uniform(4, 2, 2.0, 4.0), np.arange(7.0))
    # the seed's open uniform example T = (0, 0, 0, 2, 4, ... ) shape: ends clamped
    np.testing.assert_allclose(clamped_uniform(5, 2, 0.0, 6.0), [0, 0, 0, 2, 4, 6, 6, 6])


@settings(max_examples=50, deadline=None)
@given(data=st.data(), degree=st.integers(1, 10))
def test_multiplicities_round_trip(data, degree):
    u = data.draw(clamped_knots(degree) | floating_knots(degree))
    values, mults = distinct_with_multiplicities(u)
    assert np.all(np.diff(values) > 0)
    assert mults.sum() == len(u)
    np.testing.assert_array_equal(from_multiplicities(values, mults), u)
    for v, m in zip(values, mults):
        assert np.count_nonzero(u == v) == m


def test_distinct_with_tolerance():
    v, m = distinct_with_multiplicities([0, 1e-12, 0.5, 1, 1 + 1e-13], param_tol=1e-9)
    np.testing.assert_array_equal(m, [2, 1, 2])
    np.testing.assert_array_equal(v, [0, 0.5, 1])
    with pytest.warns(DeprecationWarning, match="param_tol"):          # the old keyword, one release
        old = distinct_with_multiplicities([0, 1e-12, 0.5, 1, 1 + 1e-13], tol=1e-9)
    np.testing.assert_array_equal(old[0], v)
    np.testing.assert_array_equal(old[1], m)


# --- periodic extension -----------------------------------------------------------------

def test_periodic_extend_worked_example():
    period = np.array([0.0, 0.0, 0.3, 0.6, 1.0])
    np.testing.assert_allclose(periodic_extend(period, 3),
                               [-1.0, -0.7, -0.4, 0.0, 0.0, 0.3, 0.6, 1.0, 1.0, 1.3, 1.6])
    np.testing.assert_allclose(periodic_extend(np.arange(5.0), 2), np.arange(-2.0, 7.0))


@pytest.mark.parametrize("period,degree", [([0.1, 0.7, 1.3, 1.3], 2), ([-1.82711018e-185, 1.0, 1.0], 2),
                                           ([0.24140059544213371, 1.2414005954421337, 2.241400595442134,
                                             3.241400595442134, 3.741400595442134, 4.241400595442133,
                                             4.241400595442133], 4)])
def test_periodic_extend_seam_is_exact(period, degree):
    """Every copy of the seam knot unwraps to exactly t_0 (left) or t_n (right), so
    the full vector is non-decreasing and the seam multiplicity is exact (t_j - T
    alone lands an ulp away: 1.3 - (1.3 - 0.1) != 0.1)."""
    period = np.array(period)
    u = periodic_extend(period, degree)
    assert np.all(np.diff(u) >= 0)
    seam = np.count_nonzero(period == period[0]) + np.count_nonzero(period == period[-1]) - 1
    assert np.count_nonzero(u == period[0]) == seam
    assert np.count_nonzero(u == period[-1]) == seam


@settings(max_examples=50, deadline=None)
@given(data=st.data(), degree=st.integers(1, 10))
def test_periodic_extend_definition(data, degree):
    """u_k = t_{k-p} with t_{j+n} = t_j + T (bi-infinite periodic continuation)."""
    period = data.draw(periodic_knots(degree))
    n = len(period) - 1
    T = period[-1] - period[0]
    u = periodic_extend(period, degree)
    assert u.shape == (n + 2 * degree + 1,)

    def t(j):
        return period[j % n] + (j // n) * T

    expected = np.array([t(k - degree) for k in range(n + 2 * degree + 1)])
    np.testing.assert_allclose(u, expected, rtol=0, atol=1e-13)
    assert np.all(np.diff(u) >= 0)
    # the result is a valid full knot vector for n + p control points
    validate(u, degree, n + degree)


# --- Greville abscissae, averaged knots, spans ---------------------------------------------

@settings(max_examples=50, deadline=None)
@given(data=st.data(), degree=st.integers(1, 10))
def test_greville_is_knot_average(data, degree):
    u = data.draw(clamped_knots(degree) | floating_knots(degree))
    n = len(u) - degree - 1
    g = greville(u, degree)
    expected = np.array([u[i + 1:i + degree + 1].mean() for i in range(n)])
    np.testing.assert_allclose(g, expected, rtol=0, atol=1e-13)
    assert np.all(np.diff(g) >= -1e-15)
    # the Greville abscissae reproduce linear functions: sum_i g_i N_i(t) = t
    from cagd.basis import basis_matrix
    t = np.linspace(u[degree], u[n], 23)
    np.testing.assert_allclose(basis_matrix(u, degree, t, n) @ g, t, atol=1e-12)


def test_greville_seed_values():
    np.testing.assert_allclose(greville(np.array([0, 0, 0, 1, 2, 2, 2.0]), 2), [0, 0.5, 1.5, 2])
    np.testing.assert_allclose(greville(np.array([0, 0, 1, 2, 2.0]), 1), [0, 1, 2])


def test_averaged_knots():
    """Piegl & Tiller eq. 9.8: u_{j+p} = (1/p) sum_{i=j}^{j+p-1} params_i, j = 1..n-p."""
    params = np.array([0.0, 0.1, 0.25, 0.5, 0.6, 0.9, 1.0])
    p = 3
    u = averaged(params, p)
    n = len(params)
    inner = [params[j:j + p].mean() for j in range(1, n - p)]
    np.testing.assert_allclose(u, np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)]), atol=1e-15)
    validate(u, p, n)


@settings(max_examples=50, deadline=None)
@given(data=st.data(), degree=st.integers(1, 10))
def test_find_span(data, degree):
    u = data.draw(clamped_knots(degree) | floating_knots(degree))
    n = len(u) - degree - 1
    a, b = u[degree], u[n]
    t = np.unique(np.concatenate([np.linspace(a, b, 57), u[(u >= a) & (u <= b)]]))
    span = find_span(u, degree, t, n)
    assert np.all((span >= degree) & (span <= n - 1))
    assert np.all(u[span] < u[span + 1])                       # never an empty span
    inner = t < b
    assert np.all((u[span[inner]] <= t[inner]) & (t[inner] < u[span[inner] + 1]))
    assert np.all(u[span[~inner] + 1] == b)                    # the right end: last non-empty span
