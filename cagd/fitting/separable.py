"""The separable least squares of a grid fit (issue 17, :func:`cagd.fit_surface`), as
dense per-direction operators built once per knot vector.

For a grid Q (m, n, d) at the parameters u (m), v (n) the tensor-product least squares
with the ends held separates (Piegl & Tiller 9.4.3): fit every column along u, then every
row of the result along v. Along one direction with the collocation matrix N (m x c) the
ends-held fit (P&T 9.4.1, eq. 9.63-9.67: P_0 = Q_0, P_(c-1) = Q_(m-1), the interior
poles the least squares of the interior sites) is linear in the data: P = F Q with

    F[1:-1, 1:-1] = A^+,  F[1:-1, 0] = -A^+ N[1:-1, 0],  F[1:-1, -1] = -A^+ N[1:-1, -1],
    A = N[1:-1, 1:-1],  A^+ = R^-1 Q^T from the reduced QR of A,

so the surface's poles are P = F_u Q F_v^T (per coordinate), its values at the grid
N_u P N_v^T, and the residuals of the one-direction fits N_u F_u Q (columns along u
alone) and Q F_v^T N_v^T (rows along v alone): matrix products of the grid's size, with
no n x n matrix over the net. The operators of a knot vector are cached per direction
(the grow / shrink / trim rounds of :mod:`cagd.fitting.fit_surface` try many knot
vectors of one direction against the same one of the other).

A rank-deficient system (a knot span without an interior site) gets the minimum-norm
least squares (numpy's SVD pseudo-inverse): a fit still, measured like any other.
"""
from __future__ import annotations

from typing import Dict, Tuple

import numpy as np

from ..basis.bspline import basis_matrix
from .fit import _knots

#: |R_ii| below this share of the largest: the reduced QR is not trusted (rank deficient or
#: nearly), the pseudo-inverse is used instead
RANK_RTOL = 1e-10
#: operators (m x count entries of one direction) kept per grid, the most recent
CACHE_OPERATORS = 64


def ends_held_operator(U: np.ndarray, p: int, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(N (m, c), F (c, m)) on the clamped knots U (c = len(U) - p - 1) at the sites t
    (t_0 = U_0, t_(m-1) = U_(-1)): the collocation matrix and the ends-held least-squares
    operator of the module docstring (P = F Q)."""
    c = len(U) - p - 1
    m = len(t)
    N = basis_matrix(U, p, t, c)
    F = np.zeros((c, m))
    F[0, 0] = 1.0
    F[-1, -1] = 1.0
    if c > 2:
        A = N[1:-1, 1:-1]
        pinv = None
        if A.shape[0] >= A.shape[1]:
            Qr, R = np.linalg.qr(A)
            diag = np.abs(np.diag(R))
            if diag.size and diag.min() > RANK_RTOL * diag.max():
                pinv = np.linalg.solve(R, Qr.T)
        if pinv is None:
            pinv = np.linalg.pinv(A)
        F[1:-1, 1:-1] = pinv
        F[1:-1, 0] = -pinv @ N[1:-1, 0]
        F[1:-1, -1] = -pinv @ N[1:-1, -1]
    return N, F


class SeparableGrid:
    """The grid Q (m, n, d) at the parameters u, v with the degrees (pu, pv): separable
    fits on breakpoint vectors (:meth:`fit`), their misses and the per-direction
    residuals (:meth:`residuals`), the operators cached per direction."""

    def __init__(self, Q: np.ndarray, u: np.ndarray, v: np.ndarray, pu: int, pv: int):
        self.Q, self.u, self.v, self.pu, self.pv = Q, u, v, pu, pv
        self.m, self.n, self.d = Q.shape
        self._ops: Tuple[Dict[bytes, Tuple[np.ndarray, np.ndarray]], ...] = ({}, {})
        self._rows: Dict[bytes, np.ndarray] = {}
        self._res: Tuple[Dict[bytes, np.ndarray], ...] = ({}, {})

    def operator(self, axis: int, breaks: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(N, F) of direction ``axis`` (0: u, 1: v) on the breakpoints, cached."""
        cache = self._ops[axis]
        key = np.ascontiguousarray(breaks, dtype=float).tobytes()
        hit = cache.get(key)
        if hit is None:
            p, t = (self.pu, self.u) if axis == 0 else (self.pv, self.v)
            hit = ends_held_operator(_knots(breaks, p), p, t)
            if len(cache) >= CACHE_OPERATORS:
                cache.pop(next(iter(cache)))
            cache[key] = hit
        return hit

    def _along_u(self, bu: np.ndarray) -> np.ndarray:
        """F_u Q: every column fitted along u, (cu, n, d), cached by the u breakpoints."""
        key = np.ascontiguousarray(bu, dtype=float).tobytes()
        rows = self._rows.get(key)
        if rows is None:
            F = self.operator(0, bu)[1]
            rows = (F @ self.Q.reshape(self.m, -1)).reshape(-1, self.n, self.d)
            if len(self._rows) >= CACHE_OPERATORS:
                self._rows.pop(next(iter(self._rows)))
            self._rows[key] = rows
        return rows

    def poles(self, bu: np.ndarray, bv: np.ndarray) -> np.ndarray:
        """P = F_u Q F_v^T (cu, cv, d): the separable least-squares poles."""
        rows = self._along_u(bu)
        cu = rows.shape[0]
        F = self.operator(1, bv)[1]
        P = F @ rows.transpose(1, 0, 2).reshape(self.n, cu * self.d)           # (cv, cu d)
        return P.reshape(-1, cu, self.d).transpose(1, 0, 2)

    def values(self, P: np.ndarray, bu: np.ndarray, bv: np.ndarray) -> np.ndarray:
        """N_u P N_v^T (m, n, d): the surface of the poles P at the grid's parameters."""
        Nu, Nv = self.operator(0, bu)[0], self.operator(1, bv)[0]
        cu, cv, d = P.shape
        Y = (Nu @ P.reshape(cu, cv * d)).reshape(self.m, cv, d)
        return np.matmul(Y.transpose(0, 2, 1), Nv.T).transpose(0, 2, 1)

    def fit(self, bu: np.ndarray, bv: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(P (cu, cv, d), misses |S(u_k, v_l) - Q_kl| (m, n))."""
        P = self.poles(bu, bv)
        return P, _norms(self.values(P, bu, bv) - self.Q)

    def residual(self, axis: int, breaks: np.ndarray) -> np.ndarray:
        """The misses (m, n) of the grid's columns fitted along u alone on the breakpoints
        (axis 0: N_u F_u Q) or of its rows fitted along v alone (axis 1: Q F_v^T N_v^T),
        cached: each direction's knots' share of the error."""
        cache = self._res[axis]
        key = np.ascontiguousarray(breaks, dtype=float).tobytes()
        r = cache.get(key)
        if r is None:
            N, F = self.operator(axis, breaks)
            if axis == 0:
                rows = self._along_u(breaks)
                along = (N @ rows.reshape(rows.shape[0], -1)).reshape(self.Q.shape)
            else:
                Qt = self.Q.transpose(1, 0, 2).reshape(self.n, -1)
                along = (N @ (F @ Qt)).reshape(self.n, self.m, self.d).transpose(1, 0, 2)
            r = _norms(along - self.Q)
            if len(cache) >= CACHE_OPERATORS:
                cache.pop(next(iter(cache)))
            cache[key] = r
        return r

    def residuals(self, bu: np.ndarray, bv: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(ru, rv) (m, n): :meth:`residual` of both directions."""
        return self.residual(0, bu), self.residual(1, bv)


def _norms(D: np.ndarray) -> np.ndarray:
    """|D| over the last axis."""
    return np.sqrt(np.einsum("...i,...i->...", D, D))


def cell_normal_band(band: np.ndarray, start: np.ndarray, cols: np.ndarray, B: np.ndarray, w: np.ndarray) -> None:
    """band += sum_k w_k B_k B_k^T at the unknowns cols[k] (k, q) (w >= 0; the rows of
    :func:`cagd.basis.banded.solve_banded_rows`: entry (i, j) at band[i, j - start[i]]):
    the points grouped by their knot cell (their first unknown) into bins of at most
    s = ceil(points / cells) rows of one cell each, each bin's q x q sum one product of
    its zero-padded rows sqrt(w) B (a batched matmul over (bins, s, q), bins <= points / s +
    cells, so at most twice the points' entries), scattered into the band once per bin.
    The same sums as :func:`cagd.fitting.fit._accumulate` (d = 1, no coupling), with less
    memory traffic."""
    n, q = B.shape
    order = np.argsort(cols[:, 0], kind="stable")
    first = cols[order, 0]
    cut = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
    counts = np.diff(np.r_[cut, n])
    size = max(1, -(-n // len(cut)))
    slot = np.arange(n) - np.repeat(cut, counts)                 # the row's place in its cell
    per = -(-counts // size)                                     # bins per cell
    base = np.r_[0, np.cumsum(per)[:-1]]
    binn = np.repeat(base, counts) + slot // size
    padded = np.zeros((int(per.sum()), size, q))
    padded[binn, slot % size] = B[order] * np.sqrt(w[order])[:, None]
    G = np.matmul(padded.transpose(0, 2, 1), padded)                         # (bins, q, q)
    cc = np.repeat(cols[order[cut]], per, axis=0)                            # each bin's unknowns
    rows = cc[:, :, None]
    index = np.broadcast_to(rows * band.shape[1] + cc[:, None, :] - start[rows], G.shape)
    band.ravel()[:] += np.bincount(index.ravel(), G.ravel(), minlength=band.size)
