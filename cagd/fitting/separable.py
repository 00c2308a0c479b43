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

A rank-deficient system (no Schoenberg-Whitney matching of the interior poles to the
interior sites, :func:`cagd.fitting.fit._determined`: e.g. a knot span without a site)
gets the minimum-norm least squares (the SVD pseudo-inverse, singular values below
RANK_RTOL of the largest dropped): a fit still, measured like any other. The QR of such a
system need not show it (an 8 x 30 grid's v direction at 30 poles: its smallest singular
value 2.5e-17, the smallest |R_ii| 6.6e-7 of the largest; its inverse made poles of 1e14).
"""
from __future__ import annotations

from typing import Dict, Tuple

import numpy as np

from ..basis.bspline import basis_matrix
from .fit import _determined, _knots, span_sums

#: |R_ii| below this share of the largest: the reduced QR is not trusted (rank deficient or
#: nearly), the pseudo-inverse is used instead, its singular values below this share of
#: the largest dropped
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
        if A.shape[0] >= A.shape[1] and _determined(U, p, t, c):
            Qr, R = np.linalg.qr(A)
            diag = np.abs(np.diag(R))
            if diag.size and diag.min() > RANK_RTOL * diag.max():
                pinv = np.linalg.solve(R, Qr.T)
        if pinv is None:
            pinv = np.linalg.pinv(A, RANK_RTOL)
        F[1:-1, 1:-1] = pinv
        F[1:-1, 0] = -pinv @ N[1:-1, 0]
        F[1:-1, -1] = -pinv @ N[1:-1, -1]
    return N, F


#: the blend weights towards the sites' own breakpoints tried by :func:`interlaced`
INTERLACE_STEPS = (0.25, 0.5, 0.75, 1.0)
#: poles above this share of the sites: :func:`interlaced` checks the conditioning too
INTERLACE_SHARE = 0.5
#: the largest Lebesgue constant (max row sum of |F|, the ends-held operator: how much the
#: fit can amplify the data) :func:`interlaced` accepts (the sites' own knots: 1.7 - 2.6
#: on the 8 x 30 grids of the tests; 1e13 made a net of 1e14)
LEBESGUE_MAX = 10.0


def site_breaks(t: np.ndarray, p: int, count: int) -> np.ndarray:
    """``count`` spans on [0, 1] placed by the m sites t (sorted, distinct, t_0 = 0,
    t_(m-1) = 1) alone, for n = count + p <= m poles: the averaging knots (Piegl & Tiller,
    The NURBS Book, eq. 9.8: knot j = the mean of s_j .. s_(j+p-1)) of n sites s taken
    evenly by index from t (all of them at n = m: interpolation), which satisfy the
    Schoenberg-Whitney condition with s (de Boor, A Practical Guide to Splines, XIII). On
    400 random cases with m/2 <= n <= m their ends-held Lebesgue constant had the median
    8.0 (90 %: 108), Piegl & Tiller's knots for least squares (eq. 9.69) 40 (90 %: 1e7)."""
    n = count + p
    sub = t[np.round(np.linspace(0.0, len(t) - 1.0, n)).astype(int)]
    c = np.concatenate([[0.0], np.cumsum(sub)])
    j = np.arange(1, count)
    return np.concatenate([[0.0], (c[j + p] - c[j]) / p, [1.0]])


def periodic_site_breaks(t: np.ndarray, count: int) -> np.ndarray:
    """``count`` periodic spans on [0, 1] placed by the m sites t (sorted, distinct, in
    [0, 1), t_0 = 0) alone: the cyclic analogue of :func:`site_breaks`, breakpoint j at
    the position j m / count along the sites (linear between them, t_m = 1)."""
    m = len(t)
    return np.interp(np.arange(count + 1) * (m / count), np.arange(m + 1.0), np.append(t, 1.0))


def lebesgue(breaks: np.ndarray, p: int, s: np.ndarray, periodic: bool = False) -> float:
    """The Lebesgue constant of the least squares of the sites s on the breakpoints (max
    row sum of |F|, F the operator from the sites' values to the poles: how much the fit
    can amplify the data; clamped: ends held, :func:`ends_held_operator`, after the
    Schoenberg-Whitney check :func:`cagd.fitting.fit._determined`; periodic: the wrapped
    basis), inf where the sites do not determine the poles."""
    if periodic:
        from .surface_net import direction
        N = direction(breaks, p, s, True).N
        w = np.linalg.svd(N, compute_uv=False)
        if w.size == 0 or w[-1] <= RANK_RTOL * w[0]:
            return np.inf
        F = np.linalg.pinv(N)
    else:
        U = _knots(breaks, p)
        if not _determined(U, p, s, len(breaks) - 1 + p):
            return np.inf
        F = ends_held_operator(U, p, s)[1]
    return float(np.abs(F).sum(axis=1).max())


def interlaced(breaks: np.ndarray, t: np.ndarray, p: int, periodic: bool = False) -> np.ndarray:
    """The breakpoints, or, where the sites t leave the least squares on them (clamped:
    ends held) undetermined (no Schoenberg-Whitney matching of the poles to the sites,
    :func:`cagd.fitting.fit._determined`) or, with more poles than INTERLACE_SHARE of the
    sites, ill-conditioned (a Lebesgue constant above LEBESGUE_MAX), moved towards the
    sites' own breakpoints (:func:`site_breaks`, :func:`periodic_site_breaks`) by the
    first weight of INTERLACE_STEPS that passes (none: the one with the smallest
    Lebesgue constant, :func:`lebesgue`). Error
    equidistribution (de Boor) puts knots where the miss is; near the number of sites it
    puts more of them into a stretch than it has sites (an 8 x 30 grid at its cap: poles
    of 1e14), or so many that a site barely holds its pole (a Schoenberg-Whitney matching,
    a Lebesgue constant of 1e13), or, with about one site per span, chases one round's
    misses from one stretch to another (a periodic tube of 20 rows: 18 -> 19 -> 20 poles,
    the largest miss 0.023 -> 0.065 -> 0.21)."""
    s = np.unique(t)
    count = len(breaks) - 1
    n = count if periodic else count + p
    if periodic:
        if n > len(s) or n <= INTERLACE_SHARE * len(s) or len(s) < 2 or s[0] != 0.0 or s[-1] >= 1.0:
            return breaks                        # the regulariser of the net's fit holds it
    elif n > len(s) or len(s) < 2 or s[0] != 0.0 or s[-1] != 1.0:
        return breaks                            # more poles than sites, or not a grid's sites
    elif n <= INTERLACE_SHARE * len(s):
        if _determined(_knots(breaks, p), p, s, n):
            return breaks
    home = periodic_site_breaks(s, count) if periodic else site_breaks(s, p, count)
    tried = []
    for w in (0.0,) + INTERLACE_STEPS:
        trial = (1.0 - w) * breaks + w * home
        tried.append((lebesgue(trial, p, s, periodic), w, trial))
        if tried[-1][0] <= LEBESGUE_MAX:
            return trial
    return min(tried, key=lambda x: x[:2])[2]


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
    the points grouped by their knot cell (their first unknown), each cell's q x q sum the
    products of zero-padded blocks of at most ceil(points / cells) of its rows sqrt(w) B
    (:func:`cagd.fitting.fit.span_sums`: at most twice the points' entries), scattered
    into the band once per cell. The same sums as :func:`cagd.fitting.fit._accumulate`
    (d = 1, no coupling), with less memory traffic."""
    n, q = B.shape
    order = np.argsort(cols[:, 0], kind="stable")
    first = cols[order, 0]
    cut = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
    X = (B[order] * np.sqrt(w[order])[:, None])[:, None, :]
    G = span_sums(cut, X, X, max(1, -(-n // len(cut))))                      # (cells, q, q)
    cc = cols[order[cut]]                                                    # each cell's unknowns
    rows = cc[:, :, None]
    index = np.broadcast_to(rows * band.shape[1] + cc[:, None, :] - start[rows], G.shape)
    band.ravel()[:] += np.bincount(index.ravel(), G.ravel(), minlength=band.size)
