"""Bernstein polynomials BEZ_{i,n}(t) = C(n,i) t^i (1-t)^(n-i) (seed 000, 5.2.1)."""
from __future__ import annotations

from math import comb

import numpy as np
from numpy.typing import ArrayLike

from .._checks import degree as _degree
from .._checks import parameters
from ..errors import CagdError
from .._checks import elevation as _elevation


def bernstein(n: int, t: ArrayLike) -> np.ndarray:
    """All n+1 Bernstein polynomials of degree n at ``t``: shape ``np.shape(t) + (n+1,)``;
    n at most :data:`cagd.MAX_DEGREE` (CagdError beyond)."""
    n = _degree(n, "n", 0)
    B = bernstein_values(n, parameters(t))
    if not np.all(np.isfinite(B)):
        raise CagdError(f"t: the degree-{n} Bernstein polynomials overflow at these parameters (|t| too large)")
    return B


def bernstein_values(n: int, x: np.ndarray) -> np.ndarray:
    """The kernel of :func:`bernstein`, unchecked (hot paths, n and x already valid):
    C(n,i) x^i (1-x)^(n-i), shape ``np.shape(x) + (n+1,)``; in [0, 1] each to a few ulps
    (a subnormal x^i underflows to a negligible term)."""
    i = np.arange(n + 1)
    binom = np.array([comb(n, k) for k in range(n + 1)], dtype=np.float64)
    xx = np.asarray(x, dtype=np.float64)[..., None]
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        return binom * xx ** i * (1.0 - xx) ** (n - i)


def bernstein_to_power(n: int) -> np.ndarray:
    """Matrix A with power coefficients a = A @ P of a degree-n Bezier with control
    points P, so that p(t) = sum_k a_k t^k. A[k, i] = (-1)^(k-i) C(n,k) C(k,i)."""
    n = _degree(n, "n", 0)
    A = np.zeros((n + 1, n + 1))
    for k in range(n + 1):
        for i in range(k + 1):
            A[k, i] = (-1) ** (k - i) * comb(n, k) * comb(k, i)
    return A


def power_to_bernstein(n: int) -> np.ndarray:
    """Inverse of :func:`bernstein_to_power`: P = B @ a, B[i, k] = C(i,k)/C(n,k)."""
    n = _degree(n, "n", 0)
    B = np.zeros((n + 1, n + 1))
    for i in range(n + 1):
        for k in range(i + 1):
            B[i, k] = comb(i, k) / comb(n, k)
    return B


def bezier_matrix(n: int) -> np.ndarray:
    """The seed's matrix form p(t) = [t^n ... t 1] M [P_0..P_n]^T (seed 000, 5.2.3:
    degree 1, 2, 3 matrices are the cases n = 1, 2, 3)."""
    return bernstein_to_power(n)[::-1]


def elevation_matrix(n: int, r: int = 1) -> np.ndarray:
    """(n+r+1, n+1) matrix E with elevated control points Q = E @ P of a degree-n
    Bezier curve raised to degree n+r (Farin, Curves and Surfaces for CAGD, 6.1;
    Piegl & Tiller eq. 5.36): E[i, j] = C(n,j) C(r,i-j) / C(n+r,i)."""
    n = _degree(n, "n", 0)
    r = _elevation(r, n, "r")
    E = np.zeros((n + r + 1, n + 1))
    for i in range(n + r + 1):
        for j in range(max(0, i - r), min(n, i) + 1):
            E[i, j] = comb(n, j) * comb(r, i - j) / comb(n + r, i)
    return E


def product_matrix(p: int, q: int) -> np.ndarray:
    """(p+1, q+1, p+q+1) tensor T of the product of Bernstein polynomials,
    BEZ_{i,p} BEZ_{j,q} = T[i, j, i+j] BEZ_{i+j,p+q} with T[i, j, i+j] = C(p,i) C(q,j) / C(p+q,i+j)
    (Farin, Curves and Surfaces for CAGD, 5th ed., 5.10): the product of f = sum f_i BEZ_{i,p}
    and g = sum g_j BEZ_{j,q} has the coefficients h_k = sum_{i+j=k} T[i, j, k] f_i g_j."""
    p = _degree(p, "p", 0)
    q = _elevation(q, p, "q")
    T = np.zeros((p + 1, q + 1, p + q + 1))
    for i in range(p + 1):
        for j in range(q + 1):
            T[i, j, i + j] = comb(p, i) * comb(q, j) / comb(p + q, i + j)
    return T
