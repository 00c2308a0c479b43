"""Hermite curves and C1 Hermite splines (seed 000, 5.1.2; seed 004, 1.3 "tangent vector")."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import CubicHermiteSpline

from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.curves.hermite import HermiteCurve, HermiteSpline, hermite_basis
from cagd.curves.polynomial import HERMITE_M
from cagd.knots import distinct_with_multiplicities
from strategies import gaps, point_arrays, relative_error

SETTINGS = settings(max_examples=40, deadline=None)
U = np.linspace(0.0, 1.0, 101)


def size_of(values):
    return max(float(np.abs(values).max()), 1.0)


@st.composite
def hermite_curves(draw):
    dim = draw(st.integers(1, 3))
    G = draw(point_arrays(4, dim))
    return HermiteCurve(*G)


@st.composite
def hermite_splines(draw):
    n = draw(st.integers(1, 8))
    dim = draw(st.integers(1, 3))
    P = draw(point_arrays(n + 1, dim))
    m = draw(point_arrays(n + 1, dim))
    t = draw(st.floats(-5, 5)) + np.concatenate([[0.0], np.cumsum(draw(gaps(n)) * draw(st.floats(0.5, 4)))])
    return HermiteSpline(P, m, t)


# --- the basis ---------------------------------------------------------------------------------
def test_basis_is_T_times_M_h():
    """[H0 H1 H2 H3] = T M_h with T = [t^3 t^2 t 1] (seed 000, 5.1.2)."""
    T = np.stack([U ** 3, U ** 2, U, np.ones_like(U)], axis=-1)
    np.testing.assert_allclose(hermite_basis(U), T @ HERMITE_M, rtol=0, atol=2e-16 * 8)


def test_basis_is_the_seeds_printed_polynomials_and_shapes():
    u = np.array([0.0, 0.25, 0.5, 1.0])
    H = hermite_basis(u)
    np.testing.assert_allclose(H[:, 0], 2 * u ** 3 - 3 * u ** 2 + 1, atol=1e-16)
    np.testing.assert_allclose(H[:, 1], -2 * u ** 3 + 3 * u ** 2, atol=1e-16)
    np.testing.assert_allclose(H[:, 2], u ** 3 - 2 * u ** 2 + u, atol=1e-16)
    np.testing.assert_allclose(H[:, 3], u ** 3 - u ** 2, atol=1e-16)
    np.testing.assert_allclose(H[:, 0] + H[:, 1], 1.0, atol=1e-16)   # reproduces constants
    assert hermite_basis(0.5).shape == (4,)
    assert hermite_basis(np.zeros((2, 3))).shape == (2, 3, 4)
    with pytest.raises(CagdError, match="u"):
        hermite_basis([0.0, np.nan])


# --- one segment -------------------------------------------------------------------------------------
@SETTINGS
@given(hermite_curves())
def test_end_conditions_and_basis_sum(c):
    d = c.derivatives(np.array([0.0, 1.0]), 1)
    s = size_of(c.geometric_form)
    assert relative_error(d[0], np.stack([c.p0, c.p1]), s) < 1e-14
    assert relative_error(d[1], np.stack([c.t0, c.t1]), s) < 1e-13
    # p = sum H_i G_i through the basis equals the Horner evaluation of A = M B
    assert relative_error(c(U), hermite_basis(U) @ c.geometric_form, s) < 1e-13


@SETTINGS
@given(hermite_curves())
def test_hermite_to_nurbs_and_bezier_are_exact(c):
    nurbs = c.to_nurbs()
    assert isinstance(nurbs, BSplineCurve) and nurbs.degree == 3
    ref = c.derivatives(U, 3)
    s = size_of(ref)
    for k in range(4):
        assert relative_error(nurbs.derivative(U, k) if k else nurbs(U), ref[k], s) < 1e-12
    assert isinstance(c.to_bezier(), BezierCurve)
    assert relative_error(c.to_bezier().de_casteljau(U), ref[0], s) < 1e-12
    assert relative_error(c.to_polynomial().to_hermite(), c.geometric_form, s) < 1e-13


@SETTINGS
@given(hermite_curves(), st.data())
def test_hermite_affine(c, data):
    A = data.draw(point_arrays(c.dim, c.dim))
    b = data.draw(point_arrays(1, c.dim))[0]
    m = c.transformed(A, b)
    np.testing.assert_allclose(m.t0, A @ c.t0)           # tangents: linear part only
    np.testing.assert_allclose(m.p0, A @ c.p0 + b)
    scale = size_of(c.geometric_form) * size_of(A) + size_of(b)
    assert relative_error(m(U), c(U) @ A.T + b, scale) < 1e-12
    assert relative_error(m.derivative(U, 1), c.derivative(U, 1) @ A.T, scale) < 1e-12


def test_from_directions_scales_unit_directions():
    c = HermiteCurve.from_directions([0, 0], [1, 0], [3, 4], [0, -2], 10.0, 0.5)
    np.testing.assert_allclose(c.t0, [6.0, 8.0])
    np.testing.assert_allclose(c.t1, [0.0, -0.5])
    with pytest.raises(CagdError, match="direction1"):
        HermiteCurve.from_directions([0, 0], [1, 0], [1, 0], [0, 0], 1, 1)
    with pytest.raises(CagdError, match="k0"):
        HermiteCurve.from_directions([0, 0], [1, 0], [1, 0], [0, 1], -1, 1)
    with pytest.raises(CagdError, match="k1"):
        HermiteCurve.from_directions([0, 0], [1, 0], [1, 0], [0, 1], 1, np.inf)
    with pytest.raises(CagdError, match="direction0"):
        HermiteCurve.from_directions([0, 0], [1, 0], [1, 0, 0], [0, 1], 1, 1)


def test_mismatched_dimensions():
    with pytest.raises(CagdError, match="t1"):
        HermiteCurve([0, 0], [1, 0], [1, 0], [1, 0, 0])
    with pytest.raises(CagdError, match="p0"):
        HermiteCurve([[0, 0]], [1, 0], [1, 0], [1, 0])


# --- the seed's worked example (seed 004, 1.3, fig. 1.1.3) ----------------------------------------------
def seed_curve(k):
    return HermiteCurve.from_directions([4.0, 4.0, 0.0], [24.0, 4.0, 0.0], [0.832, 0.5547, 0.0],
                                        [0.832, -0.5547, 0.0], k, k)


def polyline_crossings(pts):
    """Pairs of non-adjacent polyline segments that properly cross (2-D)."""
    a, b = pts[:-1, None, :2], pts[1:, None, :2]
    c, d = pts[None, :-1, :2], pts[None, 1:, :2]

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    cross = (orient(a, b, c) * orient(a, b, d) < 0) & (orient(c, d, a) * orient(c, d, b) < 0)
    i, j = np.nonzero(cross)
    return [(x, y) for x, y in zip(i, j) if y > x + 1]


def test_seed_example_loops_when_k_is_four_chords():
    chord = 20.0
    c = seed_curve(4 * chord)
    pts = c(np.linspace(0, 1, 401))
    assert np.any(np.diff(pts[:, 0]) < 0)              # x(u) turns back
    assert len(polyline_crossings(pts)) >= 1           # and the curve crosses itself
    # by the symmetry x(1-u) = 28 - x(u), y(1-u) = y(u) the double point is where x = 14
    coeffs = c.to_polynomial().coefficients[:, 0].copy()
    coeffs[0] -= 14.0
    roots = np.roots(coeffs[::-1])
    u1 = min(r.real for r in roots if abs(r.imag) < 1e-9 and 0 < r.real < 0.5 - 1e-6)
    np.testing.assert_allclose(c(u1), c(1 - u1), atol=1e-12 * 24)
    assert 1 - 2 * u1 > 0.1                            # two different parameters


def test_seed_example_is_simple_for_k_equal_to_the_chord():
    pts = seed_curve(20.0)(np.linspace(0, 1, 401))
    assert np.all(np.diff(pts[:, 0]) > 0)
    assert polyline_crossings(pts) == []


# --- C1 Hermite spline ---------------------------------------------------------------------------------------
@SETTINGS
@given(hermite_splines())
def test_spline_matches_scipy_cubic_hermite(s):
    oracle = CubicHermiteSpline(s.parameters, s.points, s.tangents, axis=0)
    t = np.linspace(*s.domain, 301)
    got = s.derivatives(t, 3)
    for k in range(4):
        want = oracle(t, k)
        assert relative_error(got[k], want, size_of(want)) < 1e-12
    assert relative_error(s(s.parameters), s.points, size_of(s.points)) < 1e-13
    # derivative scale: the tangents, or |P| / h (rounding in P divided by the span length)
    dscale = max(size_of(s.tangents), size_of(s.points) / np.diff(s.parameters).min())
    assert relative_error(s.derivative(s.parameters, 1), s.tangents, dscale) < 1e-12


@SETTINGS
@given(hermite_splines())
def test_spline_to_nurbs_is_exact_with_doubled_knots(s):
    nurbs = s.to_nurbs()
    values, mults = distinct_with_multiplicities(nurbs.knots)
    np.testing.assert_array_equal(values, s.parameters)
    assert mults.tolist() == [4] + [2] * (len(values) - 2) + [4]
    t = np.linspace(*s.domain, 301)
    for k in range(3):
        ref = s.derivative(t, k) if k else s(t)
        assert relative_error(nurbs.derivative(t, k) if k else nurbs(t), ref, size_of(ref)) < 1e-12


def test_spline_to_nurbs_with_very_uneven_intervals():
    P = np.array([[0.0, 0.0], [3.0, 1.0], [3.001, 1.0], [3.002, 1.001], [6.0, 0.0], [5.0, 3.0]])
    m = np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, -1.0], [0.0, 1.0], [2.0, 2.0]])
    s = HermiteSpline(P, m, [0.0, 3.0, 3.001, 3.002, 6.0, 9.0])
    t = np.unique(np.concatenate([np.linspace(*s.domain, 2001), s.parameters]))
    assert relative_error(s.to_nurbs()(t), s(t), size_of(P)) < 1e-13


@SETTINGS
@given(hermite_splines())
def test_spline_segments_and_C1_joins(s):
    h = np.diff(s.parameters)
    segs = s.segments()
    assert len(segs) == len(h)
    for j, seg in enumerate(segs):
        tt = s.parameters[j] + U * h[j]
        assert relative_error(seg(U), s(tt), size_of(s.points)) < 1e-12
    for j in range(1, len(segs)):   # left/right limits of C and dC/dt agree at interior knots
        left, right = segs[j - 1].derivatives(1.0, 1), segs[j].derivatives(0.0, 1)
        np.testing.assert_allclose(left[0], right[0], rtol=0, atol=1e-13 * size_of(s.points))
        np.testing.assert_allclose(left[1] / h[j - 1], right[1] / h[j], rtol=0,
                                   atol=1e-12 * size_of(s.tangents))


@SETTINGS
@given(hermite_splines(), st.data())
def test_spline_affine(s, data):
    A = data.draw(point_arrays(s.dim, s.dim))
    b = data.draw(point_arrays(1, s.dim))[0]
    m = s.transformed(A, b)
    t = np.linspace(*s.domain, 51)
    scale = size_of(s.derivatives(t, 1)) * size_of(A) + size_of(b)
    assert relative_error(m(t), s(t) @ A.T + b, scale) < 1e-12
    assert relative_error(m.derivative(t, 1), s.derivative(t, 1) @ A.T, scale) < 1e-12


def test_default_parameters_and_arc_length_of_a_line():
    P = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]])
    s = HermiteSpline(P, np.ones_like(P))                 # the line (t, t)
    assert s.domain == (0.0, 3.0)
    np.testing.assert_allclose(s(np.array([0.5, 2.25])), [[0.5, 0.5], [2.25, 2.25]], atol=1e-15)
    assert s.arc_length() == pytest.approx(3 * np.sqrt(2), rel=1e-12)


@pytest.mark.parametrize("kwargs, name", [
    (dict(points=np.zeros((3, 2)), tangents=np.zeros((2, 2))), "tangents"),
    (dict(points=np.zeros((3, 2)), tangents=np.zeros((3, 3))), "tangents"),
    (dict(points=np.zeros((3, 2)), tangents=np.zeros((3, 2)), parameters=[0, 1, 1]), "parameters"),
    (dict(points=np.zeros((3, 2)), tangents=np.zeros((3, 2)), parameters=[0, 2, 1]), "parameters"),
    (dict(points=np.zeros((3, 2)), tangents=np.zeros((3, 2)), parameters=[0, 1]), "parameters"),
    (dict(points=[[0, 0], [1, np.nan]], tangents=np.zeros((2, 2))), "points"),
    (dict(points=[[0, 0]], tangents=np.zeros((1, 2))), "points"),
])
def test_spline_errors(kwargs, name):
    with pytest.raises(CagdError, match=name):
        HermiteSpline(**kwargs)
