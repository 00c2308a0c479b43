"""Bernstein polynomials and the Bezier matrices (seed 000, 5.2.1 properties 1-7, 5.2.3)."""
from math import comb

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.polynomial import polynomial as npoly

from cagd.basis import (bernstein, bernstein_to_power, bezier_matrix, elevation_matrix,
                        power_to_bernstein, product_matrix)

DEGREES = range(0, 16)
T = np.linspace(0.0, 1.0, 201)


def direct(i, n, t):
    """C(n,i) t^i (1-t)^(n-i), the seed's definition (5.2.1) written out."""
    return comb(n, i) * t ** i * (1.0 - t) ** (n - i)


@pytest.mark.parametrize("n", DEGREES)
def test_definition_shape_and_nonnegativity(n):
    B = bernstein(n, T)
    assert B.shape == (T.size, n + 1)
    for i in range(n + 1):
        np.testing.assert_allclose(B[:, i], direct(i, n, T), rtol=1e-14, atol=1e-300)
    assert np.all(B >= 0.0)                                   # property 1
    assert bernstein(n, 0.3).shape == (n + 1,)
    assert bernstein(n, np.zeros((2, 3))).shape == (2, 3, n + 1)


@pytest.mark.parametrize("n", DEGREES)
def test_partition_of_unity(n):                               # property 2
    np.testing.assert_allclose(bernstein(n, T).sum(axis=-1), 1.0, rtol=0, atol=4e-15)


@pytest.mark.parametrize("n", DEGREES)
def test_symmetry(n):                                         # property 3
    np.testing.assert_allclose(bernstein(n, T), bernstein(n, 1.0 - T)[:, ::-1], rtol=1e-13, atol=1e-16)


@pytest.mark.parametrize("n", range(1, 16))
def test_derivative_formula(n):                               # property 4
    """BEZ'_{i,n} = n (BEZ_{i-1,n-1} - BEZ_{i,n-1}), checked against the derivative
    of the power form of each Bernstein polynomial."""
    low = np.zeros((T.size, n + 2))
    low[:, 1:-1] = bernstein(n - 1, T)                        # BEZ_{-1,n-1} = BEZ_{n,n-1} = 0
    formula = n * (low[:, :n + 1] - low[:, 1:])          # column j of low is BEZ_{j-1,n-1}
    for i in range(n + 1):
        coef = np.zeros(n + 1)
        coef[i] = 1.0
        power = bernstein_to_power(n) @ coef                  # p(t) = sum_k power[k] t^k
        expected = npoly.polyval(T, npoly.polyder(power))
        np.testing.assert_allclose(formula[:, i], expected, rtol=1e-9, atol=1e-9 * comb(n, n // 2) * n)


@pytest.mark.parametrize("n", DEGREES)
def test_integral(n):                                         # property 5
    x, w = np.polynomial.legendre.leggauss(n // 2 + 2)
    t = 0.5 * (x + 1.0)
    integrals = 0.5 * (w @ bernstein(n, t))
    np.testing.assert_allclose(integrals, 1.0 / (n + 1), rtol=1e-13)


@pytest.mark.parametrize("n", range(1, 16))
def test_maximum_at_i_over_n(n):                              # property 6
    t = np.linspace(0.0, 1.0, 20001)
    B = bernstein(n, t)
    peaks = bernstein(n, np.arange(n + 1) / n)[np.arange(n + 1), np.arange(n + 1)]
    assert np.all(B <= peaks * (1 + 1e-14))
    np.testing.assert_allclose(t[np.argmax(B, axis=0)], np.arange(n + 1) / n, atol=1e-4)


@pytest.mark.parametrize("n", range(0, 12))
def test_linear_independence_and_power_conversion(n):         # property 7
    A = bernstein_to_power(n)
    Bp = power_to_bernstein(n)
    np.testing.assert_allclose(A @ Bp, np.eye(n + 1), atol=1e-9)
    np.testing.assert_allclose(Bp @ A, np.eye(n + 1), atol=1e-9)
    # column i of A is the power form of BEZ_{i,n}
    V = np.vander(T, n + 1, increasing=True)
    np.testing.assert_allclose(V @ A, bernstein(n, T), atol=1e-11 * 2 ** n)
    assert np.linalg.matrix_rank(bernstein(n, np.linspace(0, 1, n + 1))) == n + 1


def test_recursion():
    """BEZ_{i,n} = (1-t) BEZ_{i,n-1} + t BEZ_{i-1,n-1} (seed 000, 5.2.1)."""
    for n in range(1, 12):
        low = np.zeros((T.size, n + 2))
        low[:, 1:-1] = bernstein(n - 1, T)
        rec = (1 - T)[:, None] * low[:, 1:] + T[:, None] * low[:, :-1]
        np.testing.assert_allclose(bernstein(n, T), rec, atol=1e-15)


def test_seed_matrices():
    """seed 000, 5.2.3: p(t) = [t^n ... t 1] M [P_0..P_n]^T."""
    np.testing.assert_array_equal(bezier_matrix(1), [[-1, 1], [1, 0]])
    np.testing.assert_array_equal(bezier_matrix(2), [[1, -2, 1], [-2, 2, 0], [1, 0, 0]])
    np.testing.assert_array_equal(bezier_matrix(3), [[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]])


@pytest.mark.parametrize("n", range(1, 12))
def test_bezier_matrix_reproduces_basis(n):
    V = np.vander(T, n + 1)                                   # columns t^n .. t 1
    np.testing.assert_allclose(V @ bezier_matrix(n), bernstein(n, T), atol=1e-11 * 2 ** n)


@settings(max_examples=50, deadline=None)
@given(n=st.integers(1, 10), r=st.integers(0, 5), seed=st.integers(0, 2 ** 32 - 1))
def test_elevation_matrix_vs_sampling(n, r, seed):
    """E @ P gives the same polynomial in the degree n+r basis (sampled)."""
    P = np.random.default_rng(seed).normal(size=(n + 1, 2))
    E = elevation_matrix(n, r)
    assert E.shape == (n + r + 1, n + 1)
    np.testing.assert_allclose(E.sum(axis=1), 1.0, atol=1e-14)   # rows are convex combinations
    assert np.all(E >= 0)
    np.testing.assert_allclose(bernstein(n + r, T) @ (E @ P), bernstein(n, T) @ P, atol=1e-12)


def test_elevation_matrix_degree_1_to_2():
    """Farin 6.1 worked case: Q = (P0, (P0+P1)/2, P1)."""
    np.testing.assert_allclose(elevation_matrix(1), [[1, 0], [0.5, 0.5], [0, 1]])
    np.testing.assert_allclose(elevation_matrix(2), [[1, 0, 0], [1 / 3, 2 / 3, 0], [0, 2 / 3, 1 / 3], [0, 0, 1]])


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 7), st.integers(0, 7), st.integers(0, 10 ** 6))
def test_product_matrix_multiplies_bernstein_polynomials(p, q, seed):
    # (sum f_i B_i,p)(sum g_j B_j,q) = sum h_k B_k,p+q, h = T contracted with f, g (Farin 5.10)
    rng = np.random.default_rng(seed)
    f, g = rng.normal(size=p + 1), rng.normal(size=q + 1)
    h = np.einsum("ijk,i,j->k", product_matrix(p, q), f, g)
    np.testing.assert_allclose(bernstein(p + q, T) @ h, (bernstein(p, T) @ f) * (bernstein(q, T) @ g),
                               rtol=0, atol=1e-12 * (1 + np.abs(f).sum() * np.abs(g).sum()))
    np.testing.assert_allclose(product_matrix(p, q).sum(axis=(0, 1)), 1.0, rtol=1e-14)   # 1 * 1 = 1
