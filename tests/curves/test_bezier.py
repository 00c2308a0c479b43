"""Bezier curves (seed 000, 5.2; seed 003, 2.2.4 blossoms)."""
import math
from math import comb

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BSplineCurve, CagdError

from strategies import point_arrays, positive_weights

SETTINGS = settings(max_examples=50, deadline=None)
T = np.linspace(0.0, 1.0, 57)


@st.composite
def bezier_curves(draw, min_degree=1, max_degree=10, rational=None, dims=(1, 3)):
    n = draw(st.integers(min_degree, max_degree))
    P = draw(point_arrays(n + 1, draw(st.integers(*dims))))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=n + 1, max_size=n + 1))) if is_rational else None
    return BezierCurve(P, w)


def scale(c):
    return max(1.0, float(np.abs(c.control_points).max()))


def direct_sum(c, t):
    """sum_i C(n,i) t^i (1-t)^(n-i) w_i P_i / sum_i C(n,i) t^i (1-t)^(n-i) w_i, written out."""
    n = c.degree
    w = np.ones(n + 1) if c.weights is None else c.weights
    B = np.stack([comb(n, i) * t ** i * (1 - t) ** (n - i) for i in range(n + 1)], axis=-1) * w
    return (B @ c.control_points) / B.sum(axis=-1, keepdims=True)


@SETTINGS
@given(c=bezier_curves())
def test_three_evaluations_agree(c):
    """de Casteljau == Bernstein sum == evaluation, and all equal the written-out formula."""
    ref = direct_sum(c, T)
    tol = 1e-13 * scale(c)
    np.testing.assert_allclose(c.de_casteljau(T), ref, atol=tol)
    np.testing.assert_allclose(c.bernstein_evaluate(T), ref, atol=tol)
    np.testing.assert_allclose(c(T), ref, atol=tol)
    np.testing.assert_allclose(c.de_casteljau(T), c(T), atol=tol)
    assert c.de_casteljau(0.5).shape == (c.dim,)
    assert c.bernstein_evaluate(np.zeros((2, 3))).shape == (2, 3, c.dim)


@SETTINGS
@given(c=bezier_curves(rational=False, min_degree=2))
def test_seed_endpoint_derivatives(c):
    """p(0) = P0, p(1) = Pn, p'(0) = n(P1 - P0), p'(1) = n(Pn - Pn-1),
    p''(0) = n(n-1)(P2 - 2P1 + P0), p''(1) = n(n-1)(Pn-2 - 2Pn-1 + Pn) (seed 000, 5.2.2)."""
    P, n = c.control_points, c.degree
    d0, d1 = c.derivatives(0.0, 2), c.derivatives(1.0, 2)
    tol = 1e-12 * scale(c) * n * n
    np.testing.assert_allclose(d0[0], P[0], atol=tol)
    np.testing.assert_allclose(d1[0], P[-1], atol=tol)
    np.testing.assert_allclose(d0[1], n * (P[1] - P[0]), atol=tol)
    np.testing.assert_allclose(d1[1], n * (P[-1] - P[-2]), atol=tol)
    np.testing.assert_allclose(d0[2], n * (n - 1) * (P[2] - 2 * P[1] + P[0]), atol=tol)
    np.testing.assert_allclose(d1[2], n * (n - 1) * (P[-3] - 2 * P[-2] + P[-1]), atol=tol)


def test_seed_cubic_second_derivatives():
    """p''(0) = 6(P0 - 2P1 + P2), p''(1) = 6(P1 - 2P2 + P3) (seed 000, 5.2.2)."""
    P = np.array([[0.0, 0.0], [1.0, 3.0], [4.0, 3.0], [5.0, 0.0]])
    c = BezierCurve(P)
    np.testing.assert_allclose(c.derivative(0.0, 2), 6 * (P[0] - 2 * P[1] + P[2]), atol=1e-13)
    np.testing.assert_allclose(c.derivative(1.0, 2), 6 * (P[1] - 2 * P[2] + P[3]), atol=1e-13)


@SETTINGS
@given(P=point_arrays(3, 2))
def test_seed_quadratic_midpoint(P):
    """p(1/2) = (P1 + (P0 + P2)/2)/2: the midpoint of the median from P1 (seed 000, 5.2.3)."""
    c = BezierCurve(P)
    np.testing.assert_allclose(c(0.5), 0.5 * (P[1] + 0.5 * (P[0] + P[2])), atol=1e-14 * scale(c))
    np.testing.assert_allclose(c.derivative(0.0), 2 * (P[1] - P[0]), atol=1e-13 * scale(c))
    np.testing.assert_allclose(c.derivative(1.0), 2 * (P[2] - P[1]), atol=1e-13 * scale(c))


@SETTINGS
@given(c=bezier_curves(), s=st.floats(0.01, 0.99))
def test_subdivision(c, s):
    left, right = c.subdivide(s)
    tol = 1e-12 * scale(c)
    np.testing.assert_allclose(left(T), c(s * T), atol=tol)
    np.testing.assert_allclose(right(T), c(s + (1 - s) * T), atol=tol)
    np.testing.assert_allclose(left.control_points[-1], right.control_points[0], atol=tol)
    np.testing.assert_allclose(left.control_points[0], c.control_points[0], atol=0)
    assert (left.weights is None) == (c.weights is None)


@SETTINGS
@given(c=bezier_curves(max_degree=8), r=st.integers(0, 4))
def test_elevation(c, r):
    e = c.elevate(r)
    assert e.degree == c.degree + r
    np.testing.assert_allclose(e(T), c(T), atol=1e-12 * scale(c))


def test_elevation_worked_example():
    """Degree 1 -> 2: Q = (P0, (P0+P1)/2, P1)."""
    e = BezierCurve([[0.0, 0.0], [2.0, 4.0]]).elevate()
    np.testing.assert_allclose(e.control_points, [[0, 0], [1, 2], [2, 4]])


@SETTINGS
@given(c=bezier_curves())
def test_reversal_symmetry(c):
    """P*_i = P_{n-i} traces p(1 - t) (seed 000, 5.2.2 symmetry)."""
    r = c.reversed()
    np.testing.assert_allclose(r(T), c(1 - T), atol=1e-13 * scale(c))
    np.testing.assert_array_equal(r.control_points, c.control_points[::-1])


@SETTINGS
@given(c=bezier_curves(rational=False, min_degree=2))
def test_hodograph(c):
    h = c.hodograph()
    assert h.degree == c.degree - 1
    np.testing.assert_allclose(h.control_points, c.degree * np.diff(c.control_points, axis=0), atol=0)
    np.testing.assert_allclose(h(T), c.derivative(T), atol=1e-12 * scale(c) * c.degree)


def test_hodograph_errors():
    with pytest.raises(CagdError, match="^weights"):
        BezierCurve([[0, 0], [1, 1], [2, 0]], [1, 2, 1]).hodograph()
    with pytest.raises(CagdError, match="^control_points"):
        BezierCurve([[0, 0], [1, 1]]).hodograph()


def test_rational_quarter_circle():
    """Weights 1, sqrt(2)/2, 1 on (1,0), (1,1), (0,1): a quarter of the unit circle."""
    c = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], [1.0, math.sqrt(0.5), 1.0])
    t = np.linspace(0, 1, 1001)
    for pts in (c(t), c.de_casteljau(t), c.bernstein_evaluate(t)):
        assert np.abs(np.linalg.norm(pts, axis=1) - 1.0).max() <= 1e-15 * 4
    assert c.arc_length() == pytest.approx(math.pi / 2, abs=1e-13)
    np.testing.assert_allclose(c.curvature(t), 1.0, rtol=1e-12)
    # the arc is symmetric: p(1/2) = (cos 45, sin 45)
    np.testing.assert_allclose(c(0.5), [math.sqrt(0.5)] * 2, atol=1e-15)
    left, right = c.subdivide(0.5)
    assert np.abs(np.linalg.norm(left(t), axis=1) - 1).max() <= 4e-15


def test_rational_vs_nurbs():
    P = np.array([[0.0, 0.0, 1.0], [1.0, 2.0, 0.0], [3.0, 1.0, 1.0], [4.0, 0.0, 2.0]])
    w = np.array([1.0, 3.0, 0.5, 2.0])
    c = BezierCurve(P, w)
    n = c.to_nurbs()
    assert isinstance(n, BSplineCurve) and n.is_rational and n.degree == 3
    np.testing.assert_allclose(n.full_knots, [0, 0, 0, 0, 1, 1, 1, 1])
    np.testing.assert_allclose(c(T), direct_sum(c, T), atol=1e-14)


# --- blossom (seed 003, 2.2.4) --------------------------------------------------------------

@SETTINGS
@given(c=bezier_curves(max_degree=7), data=st.data())
def test_blossom_properties(c, data):
    n = c.degree
    rng = np.random.default_rng(data.draw(st.integers(0, 2 ** 32 - 1)))
    args = [rng.uniform(-0.5, 1.5, 5) for _ in range(n)]
    f = c.blossom(*args)
    tol = 1e-11 * scale(c)
    # symmetric
    perm = rng.permutation(n)
    np.testing.assert_allclose(c.blossom(*[args[i] for i in perm]), f, atol=tol)
    # diagonal = curve
    np.testing.assert_allclose(c.blossom(*[T] * n), c(T), atol=tol)
    # control points P_i = f(0^(n-i), 1^i)
    for i in range(n + 1):
        np.testing.assert_allclose(c.blossom(*([0.0] * (n - i) + [1.0] * i)), c.control_points[i], atol=tol)
    if c.weights is None:
        # multi-affine: affine in each argument (polynomial case; the rational blossom is
        # affine in the homogeneous space only)
        lam = rng.uniform(-1, 2)
        x, y = rng.uniform(0, 1, 2)
        for k in range(n):
            a1 = list(args)
            a2 = list(args)
            a3 = list(args)
            a1[k], a2[k], a3[k] = x, y, lam * x + (1 - lam) * y
            np.testing.assert_allclose(c.blossom(*a3), lam * c.blossom(*a1) + (1 - lam) * c.blossom(*a2), atol=tol * 10)


def test_blossom_errors():
    c = BezierCurve([[0, 0], [1, 1], [2, 0]])
    with pytest.raises(CagdError, match="^args"):
        c.blossom(0.5)
    with pytest.raises(CagdError, match="^t2"):
        c.blossom(0.5, np.nan)


def test_blossom_gives_subdivision_points():
    """The left piece on [0, s] has control points f(0^(n-i), s^i) (seed 003, 2.2.4)."""
    P = np.array([[0.0, 0.0], [1.0, 3.0], [4.0, 3.0], [5.0, 0.0]])
    c = BezierCurve(P)
    left, _ = c.subdivide(0.3)
    for i in range(4):
        np.testing.assert_allclose(left.control_points[i], c.blossom(*([0.0] * (3 - i) + [0.3] * i)), atol=1e-14)


# --- matrix form (seed 000, 5.2.3) -------------------------------------------------------------

SEED_M = {1: [[-1, 1], [1, 0]], 2: [[1, -2, 1], [-2, 2, 0], [1, 0, 0]],
          3: [[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]]}


@pytest.mark.parametrize("n", [1, 2, 3])
def test_matrix_form_seed(n):
    P = np.random.default_rng(n).normal(size=(n + 1, 3))
    c = BezierCurve(P)
    C = c.matrix_form()
    np.testing.assert_allclose(C, np.array(SEED_M[n], float) @ P, atol=1e-14)
    np.testing.assert_allclose(np.vander(T, n + 1) @ C, c(T), atol=1e-13)


@SETTINGS
@given(c=bezier_curves(rational=False))
def test_matrix_form_reproduces_curve(c):
    C = c.matrix_form()
    np.testing.assert_allclose(np.vander(T, c.degree + 1) @ C, c(T), atol=1e-11 * scale(c) * 2 ** c.degree)


def test_matrix_form_rational_error():
    with pytest.raises(CagdError, match="^weights"):
        BezierCurve([[0, 0], [1, 1]], [1, 2]).matrix_form()


# --- invariants and errors ---------------------------------------------------------------------

@SETTINGS
@given(c=bezier_curves(dims=(2, 3)), data=st.data())
def test_convex_hull_and_affine_invariance(c, data):
    pts = c(T)
    P = c.control_points
    tol = 1e-12 * scale(c)
    assert np.all(pts >= P.min(axis=0) - tol) and np.all(pts <= P.max(axis=0) + tol)
    A = data.draw(point_arrays(c.dim, c.dim))
    b = data.draw(point_arrays(1, c.dim))[0]
    moved = c.transformed(A, b)
    assert isinstance(moved, BezierCurve)
    np.testing.assert_allclose(moved(T), pts @ A.T + b, atol=1e-12 * max(scale(c), 1) * max(1, np.abs(A).max()) * 10)


@pytest.mark.parametrize("kwargs,name", [
    (dict(control_points=[[0, 0]]), "control_points"),
    (dict(control_points=[[0, 0], [1, np.nan]]), "control_points"),
    (dict(control_points=[[0, 0], [1, 1]], weights=[1, 0]), "weights"),
    (dict(control_points=[[0, 0], [1, 1]], weights=[1, -1]), "weights"),
    (dict(control_points=[[0, 0], [1, 1]], weights=[1, 1, 1]), "weights"),
])
def test_constructor_errors(kwargs, name):
    with pytest.raises(CagdError, match=f"^{name}"):
        BezierCurve(**kwargs)


def test_operation_errors():
    c = BezierCurve([[0, 0], [1, 1], [2, 0]])
    for bad in (0.0, 1.0, -0.5, 2.0):
        with pytest.raises(CagdError, match="^t"):
            c.subdivide(bad)
    with pytest.raises(CagdError, match="^t"):
        c(1.5)
    with pytest.raises(CagdError, match="^times"):
        c.elevate(-1)
