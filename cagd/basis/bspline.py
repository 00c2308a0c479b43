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
    (order+1, len(t), p+1) (a view of a (order+1, p+1, len(t)) array: each function's
    values contiguous); right limits at knots. Piegl & Tiller A2.3, vectorized, in chunks
    of parameters so that the (p+1, p+1) table per parameter stays bounded."""
    degree = _checks.degree(degree, "degree", 0)
    order = _checks.order(order)
    knots = _checks.finite_array(knots, "knots", ndim=1)
    t = _checks.finite_array(t, "t", copy=False).ravel()
    try:
        span = np.broadcast_to(np.asarray(span), t.shape)
    except ValueError:
        raise CagdError(f"span: expected one span index per parameter ({t.shape[0]})") from None
    if span.size and (not np.issubdtype(span.dtype, np.integer) or span.min() < degree
                      or span.max() + degree + 1 >= len(knots)):
        raise CagdError(f"span: indices must be integers in [degree, len(knots) - degree - 2] = "
                        f"[{degree}, {len(knots) - degree - 2}]")
    step = max(1, _CHUNK_VALUES // (degree + 1) ** 2)
    out = np.empty((order + 1, degree + 1, t.shape[0]))
    for s in range(0, t.shape[0], step):
        _basis_derivatives(knots, degree, t[s:s + step], span[s:s + step], order, out[:, :, s:s + step])
    return out.transpose(0, 2, 1)


def _basis_derivatives(knots: np.ndarray, degree: int, t: np.ndarray, span: np.ndarray,
                       order: int, ders: np.ndarray) -> None:
    """A2.2 and A2.3 with every level of the triangle as one array operation (the
    functions of one degree at once, not one by one): N_j[r] = N_(span-j+r, j)(t) from
    N_(j-1) by the Cox-de Boor recurrence with the knot differences D_j[r] = u_(span+r+1)
    - u_(span-j+r+1) (A2.2's ``right[r+1] + left[j-r]``); the k-th derivative of the
    degree-p functions from N_(p-k) by k steps of N'_(i,q) = q (N_(i,q-1) / D_q[.] -
    N_(i+1,q-1) / D_q[.]) (Piegl & Tiller (2.9); the same quotients as A2.3's a_(k,j))."""
    p = degree
    m = t.shape[0]
    # knot differences in units of the span's own width h (the basis is invariant under
    # affine maps of knots and t): every D_j[r] contains the span, so it is >= 1 and
    # spans of subnormal width (1e-310) no longer overflow 1/(u_{i+1} - u_i)
    h = knots.take(np.minimum(span + 1, len(knots) - 1)) - knots.take(span) if p else np.ones(m)
    h = np.where(h > 0, h, 1.0)
    steps = np.arange(1, p + 1)[:, None]
    left = (t - knots.take(span + 1 - steps)) / h             # left[j - 1] = (t - u_(span+1-j)) / h
    right = (knots.take(span + steps) - t) / h                # right[j - 1] = (u_(span+j) - t) / h
    levels = [np.ones((1, m))]                                # N_j, (j + 1, m)
    diffs = [np.ones((0, m))]                                 # D_j, (j, m)
    for j in range(1, p + 1):
        D = right[:j] + left[j - 1::-1]
        temp = levels[-1] / D
        N = np.empty((j + 1, m))
        N[:j] = right[:j] * temp
        N[j] = 0.0
        N[1:] += left[j - 1::-1] * temp
        levels.append(N)
        diffs.append(D)
    ders[0] = levels[p]
    ders[min(order, p) + 1:] = 0.0                            # beyond the degree
    scale = np.ones(m)
    with np.errstate(over="ignore"):
        for k in range(1, min(order, p) + 1):
            out = levels[p - k]
            for q in range(p - k + 1, p + 1):
                x = out / diffs[q]
                out = np.empty((q + 1, m))
                out[:q] = -x
                out[q] = 0.0
                out[1:] += x
                out *= q
            scale = scale / h                                 # back from units of h: derivative k divided k times
            np.multiply(out, scale, out=ders[k])


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
