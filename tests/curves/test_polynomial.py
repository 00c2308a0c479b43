"""Polynomial curves: algebraic and geometric form (seed 004, 1.3; seed 000, 5.1.1-5.1.2)."""
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.polynomial import polynomial as npoly

from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.curves.polynomial import (FOUR_POINT_MATRIX, HERMITE_M, HERMITE_M_INV, PolynomialCurve,
                                    four_point_cubic)
from strategies import point_arrays, relative_error

SETTINGS = settings(max_examples=40, deadline=None)


@st.composite
def polynomial_curves(draw, max_degree=8):
    n = draw(st.integers(0, max_degree))
    dim = draw(st.integers(1, 3))
    a = draw(st.floats(-5.0, 5.0))
    h = draw(st.floats(0.1, 10.0))
    return PolynomialCurve(draw(point_arrays(n + 1, dim)), (a, a + h))


def size_of(values):
    return max(float(np.abs(values).max()), 1.0)


# --- the seed's matrices ------------------------------------------------------------------
def test_hermite_matrices_are_the_seeds_printed_entries():
    # seed 004, 1.3 (M and M^-1 printed after eq. 1-1-5); seed 000, 5.1.2 (M_h and its inverse)
    assert HERMITE_M.tolist() == [[2, -2, 1, 1], [-3, 3, -2, -1], [0, 0, 1, 0], [1, 0, 0, 0]]
    assert HERMITE_M_INV.tolist() == [[0, 0, 0, 1], [1, 1, 1, 1], [0, 0, 1, 0], [3, 2, 1, 0]]
    assert not HERMITE_M.flags.writeable and not HERMITE_M_INV.flags.writeable


def test_hermite_matrices_are_inverse():
    np.testing.assert_array_equal(HERMITE_M @ HERMITE_M_INV, np.eye(4))
    np.testing.assert_array_equal(HERMITE_M_INV @ HERMITE_M, np.eye(4))


def test_m_inverse_rows_are_the_end_conditions():
    """Rows of M^-1 are U(0), U(1), U'(0), U'(1) with U = [u^3 u^2 u 1]: p(0), p(1),
    p'(0), p'(1) of p = U A (seed 000, 5.1.2 "substituting the boundary conditions")."""
    def U(u):
        return [u ** 3, u ** 2, u, 1.0]

    def dU(u):
        return [3 * u ** 2, 2 * u, 1.0, 0.0]

    np.testing.assert_array_equal(HERMITE_M_INV, np.array([U(0.0), U(1.0), dU(0.0), dU(1.0)]))


def test_blending_functions_F_equal_UM():
    """F = U M with F1..F4 as printed in seed 004, 1.3 (eq. 1-1-2)."""
    u = np.linspace(0, 1, 51)
    U = np.stack([u ** 3, u ** 2, u, np.ones_like(u)], axis=-1)
    F = np.stack([2 * u ** 3 - 3 * u ** 2 + 1, -2 * u ** 3 + 3 * u ** 2,
                  u ** 3 - 2 * u ** 2 + u, u ** 3 - u ** 2], axis=-1)
    np.testing.assert_allclose(U @ HERMITE_M, F, atol=1e-15)


# --- evaluation -------------------------------------------------------------------------------
@SETTINGS
@given(polynomial_curves(), st.integers(0, 10))
def test_horner_matches_numpy_polyval_and_polyder(curve, order):
    a, b = curve.domain
    t = np.linspace(a, b, 37)
    u = (t - a) / (b - a)
    got = curve.derivatives(t, order)
    assert got.shape == (order + 1, t.size, curve.dim)
    for k in range(order + 1):
        c = npoly.polyder(curve.coefficients, k, axis=0) if k else curve.coefficients
        want = npoly.polyval(u, c).T / (b - a) ** k   # chain rule du/dt = 1/(b - a)
        assert relative_error(got[k], want, size_of(want)) < 1e-12


def test_scalar_and_shaped_parameters():
    c = PolynomialCurve([[1.0, 2.0], [3.0, -1.0], [0.5, 0.5]])
    assert c(0.5).shape == (2,)
    assert c(np.zeros((3, 4))).shape == (3, 4, 2)
    np.testing.assert_allclose(c(0.5), [1 + 1.5 + 0.125, 2 - 0.5 + 0.125])
    assert c.derivative(0.2, 5).tolist() == [0.0, 0.0]


def test_algebraic_form_of_seed_eq_1_1_1():
    """P(u) = a3 u^3 + a2 u^2 + a1 u + a0 with ascending rows a0..a3."""
    A = np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 0.0], [3.0, 0.0, -1.0], [-2.0, 4.0, 1.0]])
    u = 0.3
    np.testing.assert_allclose(PolynomialCurve(A)(u), A[3] * u ** 3 + A[2] * u ** 2 + A[1] * u + A[0],
                               rtol=1e-15)


# --- Bezier and NURBS forms ---------------------------------------------------------------------
@SETTINGS
@given(polynomial_curves())
def test_to_nurbs_is_exact(curve):
    nurbs = curve.to_nurbs()
    assert isinstance(nurbs, BSplineCurve)
    assert nurbs.domain == curve.domain
    t = np.linspace(*curve.domain, 101)
    ref = curve(t)
    assert relative_error(nurbs(t), ref, size_of(ref)) < 1e-12
    d2 = curve.derivative(t, 2)
    assert relative_error(nurbs.derivative(t, 2), d2, size_of(d2)) < 1e-11


@SETTINGS
@given(polynomial_curves())
def test_bezier_round_trip(curve):
    bez = curve.to_bezier()
    a, b = curve.domain
    u = np.linspace(0, 1, 41)
    ref = curve(a + u * (b - a))
    assert relative_error(bez.de_casteljau(u), ref, size_of(ref)) < 1e-12
    back = PolynomialCurve.from_bezier(bez, curve.domain)
    k = curve.degree + 1
    assert relative_error(back.coefficients[:k], curve.coefficients, size_of(curve.coefficients)) < 1e-10
    assert np.abs(back.coefficients[k:]).max(initial=0.0) < 1e-10 * size_of(curve.coefficients)


def test_from_bezier_is_the_power_form():
    P = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])
    c = PolynomialCurve.from_bezier(BezierCurve(P))
    u = np.linspace(0, 1, 11)
    np.testing.assert_allclose(c(u), BezierCurve(P).bernstein_evaluate(u), atol=1e-14)
    # a_0 = P0, a_1 = 3 (P1 - P0) (end tangent of a cubic Bezier, seed 000, 5.2.1)
    np.testing.assert_allclose(c.coefficients[:2], [P[0], 3 * (P[1] - P[0])])


def test_from_bezier_rejects_rational_and_other_types():
    with pytest.raises(CagdError, match="bezier"):
        PolynomialCurve.from_bezier(BezierCurve([[0, 0], [1, 1], [2, 0]], weights=[1, 2, 1]))
    with pytest.raises(CagdError, match="bezier"):
        PolynomialCurve.from_bezier(np.zeros((3, 2)))


# --- geometric (Hermite) form ----------------------------------------------------------------------
@SETTINGS
@given(polynomial_curves(max_degree=3))
def test_to_hermite_holds_end_points_and_u_tangents(curve):
    B = curve.to_hermite()
    a, b = curve.domain
    d = curve.derivatives(np.array([a, b]), 1)
    want = np.stack([d[0, 0], d[0, 1], d[1, 0] * (b - a), d[1, 1] * (b - a)])
    assert relative_error(B, want, size_of(want)) < 1e-12
    back = PolynomialCurve.from_hermite(B, curve.domain)
    t = np.linspace(a, b, 21)
    assert relative_error(back(t), curve(t), size_of(curve(t))) < 1e-12


def test_from_hermite_matches_seed_solution():
    """a0 = P0, a1 = P0', a2 = -3P0 + 3P1 - 2P0' - P1', a3 = 2P0 - 2P1 + P0' + P1' (seed 004, 1.3)."""
    P0, P1, D0, D1 = np.array([[4.0, 4.0], [24.0, 4.0], [1.0, 2.0], [3.0, -1.0]])
    c = PolynomialCurve.from_hermite(np.stack([P0, P1, D0, D1]))
    want = np.stack([P0, D0, -3 * P0 + 3 * P1 - 2 * D0 - D1, 2 * P0 - 2 * P1 + D0 + D1])
    np.testing.assert_allclose(c.coefficients, want, rtol=1e-15)


def test_to_hermite_needs_degree_at_most_3():
    with pytest.raises(CagdError, match="coefficients.*degree"):
        PolynomialCurve(np.ones((5, 2))).to_hermite()
    with pytest.raises(CagdError, match="geometric"):
        PolynomialCurve.from_hermite(np.ones((3, 2)))


# --- four-point curve --------------------------------------------------------------------------------
def test_four_point_matrix_is_the_exact_inverse_vandermonde():
    nodes = [Fraction(i, 3) for i in range(4)]
    V = [[x ** k for k in range(4)] for x in nodes]
    M = [[Fraction(float(v)) for v in row] for row in FOUR_POINT_MATRIX]
    # V @ M = I in exact rational arithmetic: M is the exact inverse
    for i in range(4):
        for j in range(4):
            assert sum(V[i][k] * M[k][j] for k in range(4)) == (1 if i == j else 0)


@SETTINGS
@given(st.integers(1, 3).flatmap(lambda d: point_arrays(4, d)))
def test_four_point_cubic_interpolates(P):
    c = four_point_cubic(P)
    assert isinstance(c, PolynomialCurve) and c.degree == 3
    # the power coefficients reach 36 |P| (row sums of the matrix), hence 1e-13 not 1e-15
    assert relative_error(c(np.arange(4) / 3.0), P, size_of(P)) < 1e-13


def test_four_point_cubic_reproduces_a_cubic():
    A = np.array([[1.0, -2.0], [0.5, 3.0], [2.0, 0.0], [-1.0, 1.0]])
    u = np.arange(4) / 3.0
    c = four_point_cubic(PolynomialCurve(A)(u))
    np.testing.assert_allclose(c.coefficients, A, atol=1e-13)


def test_four_point_cubic_needs_four_points():
    with pytest.raises(CagdError, match="points"):
        four_point_cubic(np.zeros((3, 2)))


# --- affine maps ---------------------------------------------------------------------------------------
@SETTINGS
@given(polynomial_curves(), st.data())
def test_affine_map_moves_the_point_and_only_rotates_derivatives(curve, data):
    A = data.draw(point_arrays(curve.dim, curve.dim))
    b = data.draw(point_arrays(1, curve.dim))[0]
    moved = curve.transformed(A, b)
    t = np.linspace(*curve.domain, 17)
    d, dm = curve.derivatives(t, 2), moved.derivatives(t, 2)
    scale = size_of(d) * size_of(A) + size_of(b)
    assert relative_error(dm[0], d[0] @ A.T + b, scale) < 1e-12
    assert relative_error(dm[1:], d[1:] @ A.T, scale) < 1e-12


# --- errors ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("domain, msg", [((1.0, 1.0), "start < end"), ((0.0, np.nan), "NaN"),
                                         ((0.0, 1.0, 2.0), "two values"), ((2.0, 1.0), "start < end")])
def test_bad_domain(domain, msg):
    with pytest.raises(CagdError, match=f"domain.*{msg}"):
        PolynomialCurve([[0.0], [1.0]], domain)


def test_bad_coefficients_and_parameters():
    with pytest.raises(CagdError, match="coefficients.*NaN"):
        PolynomialCurve([[0.0, np.nan]])
    with pytest.raises(CagdError, match="coefficients"):
        PolynomialCurve(np.zeros((2, 2, 2)))
    with pytest.raises(CagdError, match="outside the domain"):
        PolynomialCurve([[0.0], [1.0]], (0, 2))(2.5)
    with pytest.raises(CagdError, match="order"):
        PolynomialCurve([[0.0], [1.0]]).derivative(0.5, -1)


def test_degree_zero_curve_has_a_nurbs_form():
    c = PolynomialCurve([[1.0, 2.0]], (0.0, 3.0))
    np.testing.assert_array_equal(c.to_nurbs()(np.linspace(0, 3, 5)), np.tile([1.0, 2.0], (5, 1)))
    assert c.to_bezier().degree == 1
