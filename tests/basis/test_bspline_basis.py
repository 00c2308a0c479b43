"""B-spline basis functions against scipy.interpolate and the seed's uniform
periodic examples (seed 000, 5.3.1-5.3.2)."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline as SciBSpline

from cagd import BSplineCurve
from cagd.basis import basis_derivatives, basis_functions, basis_matrix, cox_de_boor
from cagd.knots import find_span

from strategies import clamped_knots, floating_knots

# (name, knots, degree): clamped, floating uniform, non-uniform with repeated interior knots
FIXED = [
    ("clamped-cubic", np.array([0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1.0]), 3),
    ("clamped-repeated", np.array([0, 0, 0, 0, 0.3, 0.3, 0.5, 0.8, 0.8, 0.8, 1, 1, 1, 1.0]), 3),
    ("floating-uniform", np.arange(10, dtype=float), 3),
    ("floating-quadratic", np.arange(7, dtype=float) * 0.5 - 1, 2),
    ("nonuniform-repeated", np.array([-1, -0.5, 0, 0, 0.2, 0.9, 0.9, 1.4, 2.0, 2.0, 3.0, 3.5]), 3),
    ("linear-repeated", np.array([0, 0, 1, 1, 2, 3, 3]), 1),
    ("degree5-repeated", np.array([0] * 6 + [0.2, 0.2, 0.2, 0.5, 0.7, 0.7, 0.7, 0.7, 0.7] + [1] * 6, float), 5),
    ("degree10", np.concatenate([np.zeros(11), [0.1, 0.35, 0.35, 0.6], np.ones(11)]), 10),
]


def scipy_basis(knots, degree, t, derivative=0):
    """All basis functions (derivatives) by scipy: a BSpline with identity coefficients.

    scipy takes right limits, and at the right domain end u_n it picks the span
    ending there, which is empty when u_{n-1} = u_n (it then returns 0). The
    left limit at u_n is taken by reflection instead:
    N_{i,p}(t; u) = N_{n-1-i,p}(-t; -u reversed), derivatives times (-1)^k."""
    knots = np.asarray(knots, float)
    t = np.asarray(t, float)
    n = len(knots) - degree - 1
    out = SciBSpline(knots, np.eye(n), degree, extrapolate=False)(t, nu=derivative)
    end = t == knots[n]
    if end.any():
        mirror = SciBSpline(-knots[::-1], np.eye(n), degree, extrapolate=False)(-t[end], nu=derivative)
        out[end] = (-1) ** derivative * mirror[:, ::-1]
    return out


def domain_samples(knots, degree, count=97):
    n = len(knots) - degree - 1
    a, b = knots[degree], knots[n]
    inside = np.unique(knots[(knots >= a) & (knots <= b)])
    return np.unique(np.concatenate([np.linspace(a, b, count), inside]))


@pytest.mark.parametrize("name,knots,degree", FIXED, ids=[f[0] for f in FIXED])
def test_basis_matrix_vs_scipy(name, knots, degree):
    n = len(knots) - degree - 1
    t = domain_samples(knots, degree)
    B = basis_matrix(knots, degree, t, n)
    S = scipy_basis(knots, degree, t)
    np.testing.assert_allclose(B, S, rtol=0, atol=1e-13)
    np.testing.assert_allclose(B, SciBSpline.design_matrix(t, knots, degree).toarray(), rtol=0, atol=1e-13)
    np.testing.assert_allclose(B.sum(axis=1), 1.0, atol=2e-15)     # partition of unity on the domain
    assert np.all(B >= -1e-15)


@pytest.mark.parametrize("name,knots,degree", FIXED, ids=[f[0] for f in FIXED])
def test_basis_derivatives_vs_scipy(name, knots, degree):
    n = len(knots) - degree - 1
    t = domain_samples(knots, degree)
    span = find_span(knots, degree, t, n)
    ders = basis_derivatives(knots, degree, t, span, degree + 1)
    assert ders.shape == (degree + 2, t.size, degree + 1)
    np.testing.assert_array_equal(ders[degree + 1], 0.0)          # beyond the degree
    np.testing.assert_allclose(basis_functions(knots, degree, t, span), ders[0], rtol=0, atol=0)
    hmin = np.diff(np.unique(knots)).min()
    for k in range(1, degree + 1):
        S = scipy_basis(knots, degree, t, k)
        B = basis_matrix(knots, degree, t, n, derivative=k)
        scale = (degree / hmin) ** k
        np.testing.assert_allclose(B, S, rtol=0, atol=1e-12 * scale, err_msg=f"derivative {k}")
        local = np.take_along_axis(S, span[:, None] - degree + np.arange(degree + 1), axis=1)
        np.testing.assert_allclose(ders[k], local, rtol=0, atol=1e-12 * scale)
        # derivative sums vanish (derivative of the partition of unity)
        np.testing.assert_allclose(B.sum(axis=1), 0.0, atol=1e-12 * scale)


@pytest.mark.parametrize("name,knots,degree", FIXED, ids=[f[0] for f in FIXED])
def test_cox_de_boor_vs_scipy_basis_elements(name, knots, degree):
    """The textbook recursion on the whole knot range (outside the domain too),
    against scipy's basis elements; half-open spans [u_i, u_{i+1})."""
    n = len(knots) - degree - 1
    t = np.unique(np.concatenate([np.linspace(knots[0], knots[-1], 301), knots]))
    N = cox_de_boor(knots, degree, t)
    assert N.shape == (t.size, n)
    for i in range(n):
        el = SciBSpline.basis_element(knots[i:i + degree + 2], extrapolate=False)(t)
        el = np.where(np.isnan(el), 0.0, el)
        np.testing.assert_allclose(N[:, i], el, rtol=0, atol=1e-13, err_msg=f"N_{i}")


@pytest.mark.parametrize("name,knots,degree", FIXED, ids=[f[0] for f in FIXED])
def test_cox_de_boor_equals_basis_matrix_inside_domain(name, knots, degree):
    n = len(knots) - degree - 1
    t = domain_samples(knots, degree)
    t = t[t < knots[n]]                                             # the right end is the documented exception
    np.testing.assert_allclose(cox_de_boor(knots, degree, t), basis_matrix(knots, degree, t, n), atol=1e-14)


def test_cox_de_boor_right_end_of_clamped_vector_is_zero():
    """Documented: the half-open definition gives 0 at the right end of a clamped vector."""
    knots = np.array([0, 0, 0, 1, 2, 2, 2.0])
    np.testing.assert_array_equal(cox_de_boor(knots, 2, [2.0]), 0.0)
    np.testing.assert_allclose(basis_matrix(knots, 2, [2.0], 4), [[0, 0, 0, 1]])


@settings(max_examples=40, deadline=None)
@given(data=st.data(), degree=st.integers(1, 10), clamped=st.booleans())
def test_random_knots_vs_scipy(data, degree, clamped):
    knots = data.draw(clamped_knots(degree) if clamped else floating_knots(degree))
    n = len(knots) - degree - 1
    t = domain_samples(knots, degree, 31)
    B = basis_matrix(knots, degree, t, n)
    np.testing.assert_allclose(B, scipy_basis(knots, degree, t), atol=1e-12)
    np.testing.assert_allclose(B.sum(axis=1), 1.0, atol=1e-14)
    k = data.draw(st.integers(1, degree))
    hmin = np.diff(np.unique(knots)).min()
    np.testing.assert_allclose(basis_matrix(knots, degree, t, n, derivative=k), scipy_basis(knots, degree, t, k),
                               rtol=0, atol=1e-11 * (degree / hmin) ** k)


# --- seed 000, 5.3.2: uniform periodic quadratic and cubic B-splines ----------------------

def seed_quadratic_bez03(t):
    """BEZ_{0,3}(t) for knots 0..6 as printed in seed 000, 5.3.2."""
    t = np.asarray(t, float)
    return np.select([(0 <= t) & (t < 1), (1 <= t) & (t < 2), (2 <= t) & (t < 3)],
                     [0.5 * t ** 2, 0.5 * t * (2 - t) + 0.5 * (t - 1) * (3 - t), 0.5 * (3 - t) ** 2], 0.0)


def test_seed_uniform_quadratic_basis():
    knots = np.arange(7, dtype=float)
    t = np.linspace(0, 6, 601)[:-1]
    N = cox_de_boor(knots, 2, t)
    for i in range(4):                                  # BEZ_{i,3}(t) = BEZ_{0,3}(t - i)
        np.testing.assert_allclose(N[:, i], seed_quadratic_bez03(t - i), atol=1e-14, err_msg=f"BEZ_{i},3")
    # the curve's range is t_{k-1} = 2 .. t_{n+1} = 4, where the functions sum to 1
    inside = (t >= 2) & (t <= 4)
    np.testing.assert_allclose(N[inside].sum(axis=1), 1.0, atol=1e-15)
    assert np.all(N[~inside].sum(axis=1) < 1.0)
    ts = np.linspace(2, 4, 41)
    # the pieces are continuous, so the closed right end t = 4 agrees too
    np.testing.assert_allclose(basis_matrix(knots, 2, ts, 4),
                               np.stack([seed_quadratic_bez03(ts - i) for i in range(4)], 1), atol=1e-14)


SEED_CUBIC = [  # seed 000, 5.3.2, t in [0, 1]
    lambda t: (-t ** 3 + 3 * t ** 2 - 3 * t + 1) / 6,
    lambda t: (3 * t ** 3 - 6 * t ** 2 + 4) / 6,
    lambda t: (-3 * t ** 3 + 3 * t ** 2 + 3 * t + 1) / 6,
    lambda t: t ** 3 / 6,
]
SEED_M_BEZ = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]]) / 6.0


def test_seed_uniform_cubic_basis_functions():
    """On a unit span of the uniform knots 0..7 (the span [3, 4]) the four non-zero
    cubic basis functions are the seed's pieces in the local parameter s = t - 3."""
    knots = np.arange(8, dtype=float)
    s = np.linspace(0, 1, 101)
    B = basis_matrix(knots, 3, 3 + s, 4)
    for i in range(4):
        np.testing.assert_allclose(B[:, i], SEED_CUBIC[i](s), atol=1e-15, err_msg=f"BEZ_{i},4")
    np.testing.assert_allclose(B, np.vander(s, 4) @ SEED_M_BEZ, atol=1e-15)


def test_seed_cubic_matrix_from_basis_derivatives():
    """M_BEZ rows are the Taylor coefficients of the basis at the span start:
    row r (power 3-r) = N^(3-r)(3) / (3-r)!."""
    knots = np.arange(8, dtype=float)
    ders = basis_derivatives(knots, 3, np.array([3.0]), np.array([3]), 3)[:, 0, :]
    taylor = ders / np.array([1, 1, 2, 6])[:, None]
    np.testing.assert_allclose(taylor[::-1], SEED_M_BEZ, atol=1e-15)


P4 = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.5], [4.0, -1.0]])


def test_seed_periodic_cubic_end_conditions():
    """p(0) = (P0 + 4P1 + P2)/6, p'(0) = (P2 - P0)/2, p(1) = (P1 + 4P2 + P3)/6,
    p'(1) = (P3 - P1)/2 for unit knot spacing (seed 000, 5.3.2)."""
    P0, P1, P2, P3 = P4
    c = BSplineCurve(P4, 3, knots=[0, 1, 2, 3, 4], periodic=True)
    np.testing.assert_allclose(c(0.0), (P0 + 4 * P1 + P2) / 6, atol=1e-14)
    np.testing.assert_allclose(c.derivative(0.0), (P2 - P0) / 2, atol=1e-14)
    np.testing.assert_allclose(c(1.0), (P1 + 4 * P2 + P3) / 6, atol=1e-14)
    np.testing.assert_allclose(c.derivative(1.0), (P3 - P1) / 2, atol=1e-14)
    # the same segment as a floating uniform (non-periodic) cubic on knots 0..7
    f = BSplineCurve(P4, 3, knots=np.arange(8.0))
    assert f.domain == (3.0, 4.0)
    np.testing.assert_allclose(f(3.0), (P0 + 4 * P1 + P2) / 6, atol=1e-14)
    np.testing.assert_allclose(f(4.0), (P1 + 4 * P2 + P3) / 6, atol=1e-14)
    np.testing.assert_allclose(f.derivative(3.0), (P2 - P0) / 2, atol=1e-14)
    np.testing.assert_allclose(f.derivative(4.0), (P3 - P1) / 2, atol=1e-14)
    s = np.linspace(0, 1, 21)
    np.testing.assert_allclose(f(3 + s), np.vander(s, 4) @ SEED_M_BEZ @ P4, atol=1e-14)
    np.testing.assert_allclose(c(s), f(3 + s), atol=1e-14)


def test_seed_periodic_quadratic_end_conditions():
    """p_start = (P0 + P1)/2, p'_start = P1 - P0, p_end = (P2 + P3)/2,
    p'_end = P3 - P2 (seed 000, 5.3.2, knots 0..6, range [2, 4])."""
    P0, P1, P2, P3 = P4
    f = BSplineCurve(P4, 2, knots=np.arange(7.0))
    assert f.domain == (2.0, 4.0)
    np.testing.assert_allclose(f(2.0), (P0 + P1) / 2, atol=1e-14)
    np.testing.assert_allclose(f.derivative(2.0), P1 - P0, atol=1e-14)
    np.testing.assert_allclose(f(4.0), (P2 + P3) / 2, atol=1e-14)
    np.testing.assert_allclose(f.derivative(4.0), P3 - P2, atol=1e-14)
    c = BSplineCurve(P4, 2, knots=[0, 1, 2, 3, 4], periodic=True)
    np.testing.assert_allclose(c(0.0), (P0 + P1) / 2, atol=1e-14)
    np.testing.assert_allclose(c.derivative(0.0), P1 - P0, atol=1e-14)
    np.testing.assert_allclose(c(2.0), (P2 + P3) / 2, atol=1e-14)
    np.testing.assert_allclose(c.derivative(2.0), P3 - P2, atol=1e-14)
    # closed: the fourth segment starts at the midpoint of P3 and P0, and t = 4 is t = 0
    np.testing.assert_allclose(c(3.0), (P3 + P0) / 2, atol=1e-14)
    np.testing.assert_allclose(c.derivative(3.0), P0 - P3, atol=1e-14)
    np.testing.assert_allclose(c(4.0), (P0 + P1) / 2, atol=1e-14)


def test_uniform_basis_is_translation_invariant():
    """BEZ_{i,k}(t) = BEZ_{0,k}(t - i dt) (seed 000, 5.3.2)."""
    knots = np.arange(12, dtype=float) * 0.5
    t = np.linspace(0, 5.5, 551)[:-1]
    N = cox_de_boor(knots, 3, t)
    N0 = cox_de_boor(knots, 3, t - 0.5 * np.arange(1, 8)[:, None]).reshape(7, -1, 8)
    for i in range(1, 8):
        np.testing.assert_allclose(N[:, i], N0[i - 1][:, 0], atol=1e-14)
