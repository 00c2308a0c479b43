"""B-spline basis functions (seed 000, 5.3.1; Piegl & Tiller A2.2, A2.3).

All functions are vectorized over the parameters; the loops run over the degree.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError
from ..knots.vectors import find_span


def basis_functions(knots: np.ndarray, degree: int, t: np.ndarray, span: np.ndarray) -> np.ndarray:
    """The p+1 non-zero basis functions N_{span-p..span, p}(t): shape (len(t), p+1).
    Piegl & Tiller A2.2, vectorized over t."""
    return basis_derivatives(knots, degree, t, span, 0)[0]


_CHUNK_VALUES = 1 << 22     # working values (p+1)^2 per parameter: chunks of at most 32 MiB


def basis_derivatives(knots: np.ndarray, degree: int, t: np.ndarray, span: np.ndarray,
                      order: int) -> np.ndarray:
    """Derivatives 0..order of the p+1 non-zero basis functions at t, shape
    (order+1, len(t), p+1); right limits at knots. Piegl & Tiller A2.3, vectorized,
    in chunks of parameters so that the (p+1, p+1) table per parameter stays bounded."""
    degree = _checks.degree(degree, "degree", 0)
    order = _checks.order(order)
    knots = _checks.finite_array(knots, "knots", ndim=1)
    t = _checks.finite_array(t, "t").ravel()
    try:
        span = np.broadcast_to(np.asarray(span), t.shape)
    except ValueError:
        raise CagdError(f"span: expected one span index per parameter ({t.shape[0]})") from None
    if span.size and (not np.issubdtype(span.dtype, np.integer) or span.min() < degree
                      or span.max() + degree + 1 >= len(knots)):
        raise CagdError(f"span: indices must be integers in [degree, len(knots) - degree - 2] = "
                        f"[{degree}, {len(knots) - degree - 2}]")
    step = max(1, _CHUNK_VALUES // (degree + 1) ** 2)
    if t.shape[0] <= step:
        return _basis_derivatives(knots, degree, t, span, order)
    return np.concatenate([_basis_derivatives(knots, degree, t[s:s + step], span[s:s + step], order)
                           for s in range(0, t.shape[0], step)], axis=1)


def _basis_derivatives(knots: np.ndarray, degree: int, t: np.ndarray, span: np.ndarray,
                       order: int) -> np.ndarray:
    p = degree
    m = t.shape[0]
    ndu = np.empty((p + 1, p + 1, m))
    ndu[0, 0] = 1.0
    left = np.empty((p + 1, m))
    right = np.empty((p + 1, m))
    # knot differences in units of the span's own width h (the basis is invariant under
    # affine maps of knots and t): every ndu[j, r] contains the span, so it is >= 1 and
    # spans of subnormal width (1e-310) no longer overflow 1/(u_{i+1} - u_i)
    h = knots[np.minimum(span + 1, len(knots) - 1)] - knots[span] if p else np.ones(m)
    h = np.where(h > 0, h, 1.0)
    for j in range(1, p + 1):
        left[j] = (t - knots[span + 1 - j]) / h
        right[j] = (knots[span + j] - t) / h
        saved = np.zeros(m)
        for r in range(j):
            ndu[j, r] = right[r + 1] + left[j - r]          # lower triangle: knot differences
            temp = ndu[r, j - 1] / ndu[j, r]
            ndu[r, j] = saved + right[r + 1] * temp          # upper triangle: basis values
            saved = left[j - r] * temp
        ndu[j, j] = saved
    ders = np.zeros((order + 1, m, p + 1))
    ders[0] = ndu[:, p].T
    if order == 0:
        return ders
    a = np.zeros((2, p + 1, m))
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0, 0] = 1.0
        for k in range(1, order + 1):
            if k > p:
                break
            d = np.zeros(m)
            rk, pk = r - k, p - k
            if r >= k:
                a[s2, 0] = a[s1, 0] / ndu[pk + 1, rk]
                d = a[s2, 0] * ndu[rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, j] = (a[s1, j] - a[s1, j - 1]) / ndu[pk + 1, rk + j]
                d = d + a[s2, j] * ndu[rk + j, pk]
            if r <= pk:
                a[s2, k] = -a[s1, k - 1] / ndu[pk + 1, r]
                d = d + a[s2, k] * ndu[r, pk]
            ders[k, :, r] = d
            s1, s2 = s2, s1
    fac = float(p)
    with np.errstate(over="ignore"):
        for k in range(1, min(order, p) + 1):
            ders[k] *= fac
            ders[k:] /= h[:, None]               # back from units of h: derivative k divided k times
            fac *= p - k
    return ders


def basis_matrix(knots: np.ndarray, degree: int, t: ArrayLike, count: int, derivative: int = 0) -> np.ndarray:
    """Dense collocation matrix B[j, i] = N_{i,p}^{(derivative)}(t_j), shape (len(t), count)."""
    t = _checks.finite_array(t, "t").ravel()
    derivative = _checks.order(derivative, "derivative")
    span = find_span(knots, degree, t, count)
    local = basis_derivatives(knots, degree, t, span, derivative)[derivative]
    B = np.zeros((t.shape[0], count))
    cols = span[:, None] - degree + np.arange(degree + 1)
    np.put_along_axis(B, cols, local, axis=1)
    return B


def cox_de_boor(knots: ArrayLike, degree: int, t: ArrayLike) -> np.ndarray:
    """All basis functions by the seed's recursion with the convention 0/0 = 0
    (seed 000, 5.3.1): N_{i,0} = [u_i <= t < u_{i+1}],
    N_{i,k} = (t-u_i)/(u_{i+k}-u_i) N_{i,k-1} + (u_{i+k+1}-t)/(u_{i+k+1}-u_{i+1}) N_{i+1,k-1}.
    Returns shape (len(t), len(knots)-degree-1). The half-open intervals make the
    right domain end evaluate to 0 unless the last span is closed; this is the plain
    textbook definition, kept as a reference (use :func:`basis_matrix` for curves)."""
    degree = _checks.degree(degree, "degree", 0)
    u = _checks.finite_array(knots, "knots", ndim=1)
    if len(u) < degree + 2:
        raise CagdError(f"knots: need at least degree + 2 = {degree + 2} values, got {len(u)}")
    t = _checks.finite_array(t, "t").ravel()[:, None]
    N = ((u[:-1] <= t) & (t < u[1:])).astype(np.float64)
    for k in range(1, degree + 1):
        d1 = u[k:-1] - u[:-k - 1]
        d2 = u[k + 1:] - u[1:-k]
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(d1 > 0, (t - u[:-k - 1]) / np.where(d1 > 0, d1, 1.0), 0.0)
            b = np.where(d2 > 0, (u[k + 1:] - t) / np.where(d2 > 0, d2, 1.0), 0.0)
        N = a * N[:, :-1] + b * N[:, 1:]
    return N
