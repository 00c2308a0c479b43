"""The Bezier cells of the closest-point search in power form (:class:`PowerTable`,
evaluation of points and partials up to second order, vectorized over (point, cell)
rows), and the bookkeeping of (point, box) pairs."""
from __future__ import annotations

from functools import lru_cache

import numpy as np

UNIFORM_RTOL = 1e-13         # breaks equally spaced to this share: a uniform grid (pieces found by division)


def pair_distances(X: np.ndarray, pid: np.ndarray, Y: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """|X[pid] - Y[cell]| coordinate by coordinate (fast for long pair lists)."""
    acc = np.zeros(len(pid))
    for a in range(X.shape[1]):
        t = X[:, a].take(pid) - Y[:, a].take(cell)
        acc += t * t
    return np.sqrt(acc)


def split_boxes(pid, cell, lo, hi, lb, speed=None):
    """Halve every open box along its longest side: the parameter width times ``speed``
    (n, k), a bound of the first partial per direction over the box's cell, i.e. the
    longest side of the box's image (issue 16: a sliver's box is halved along its long
    direction only; the width alone halved a 0.1 x 10 mm face's cells across 4 times
    first); None: the parameter width."""
    w = hi - lo if speed is None else (hi - lo) * speed
    axis = np.argmax(w, axis=1)
    mid = 0.5 * (lo[np.arange(len(lo)), axis] + hi[np.arange(len(lo)), axis])
    lo2, hi1 = lo.copy(), hi.copy()
    lo2[np.arange(len(lo)), axis] = mid
    hi1[np.arange(len(lo)), axis] = mid
    return (np.concatenate([pid, pid]), np.concatenate([cell, cell]), np.concatenate([lo, lo2]),
            np.concatenate([hi1, hi]), np.concatenate([lb, lb]))


@lru_cache(maxsize=64)
def _bernstein_to_power(p: int) -> np.ndarray:
    """(p+1, p+1) matrix C with power coefficients c_a = sum_i C[a, i] P_i of a degree-p
    Bezier polynomial on [0, 1] written in the centred variable s = 2 t - 1 in [-1, 1]:
    B_i(t) = C(p, i) 2^-p (1 + s)^i (1 - s)^(p - i)."""
    from math import comb
    P = np.polynomial.polynomial
    C = np.zeros((p + 1, p + 1))
    for i in range(p + 1):
        c = P.polymul(P.polypow([1.0, 1.0], i), P.polypow([1.0, -1.0], p - i)) * (comb(p, i) / 2.0 ** p)
        C[:len(c), i] = c
    C.setflags(write=False)                # shared by every table of degree p
    return C


def _horner(coef, s, order):
    """[P, P', P''/2] (up to ``order``) of sum_a coef[a] s^a by Horner's scheme with
    derivatives; ``coef`` a list of arrays (or a callable giving them), highest last."""
    n = len(coef) - 1
    p0 = coef[n]
    p1 = p2 = None
    for a in range(n - 1, -1, -1):
        if order >= 2 and p1 is not None:
            p2 = p1 if p2 is None else p2 * s + p1
        if order >= 1:
            p1 = p0 if p1 is None else p1 * s + p0
        p0 = p0 * s + coef[a]
    out = [p0]
    shape = np.broadcast_shapes(np.shape(p0), np.shape(s))
    if order >= 1:
        out.append(p1 if p1 is not None else np.zeros(shape))
    if order >= 2:
        out.append(p2 if p2 is not None else np.zeros(shape))
    return out


class PowerTable:
    """Per Bezier piece, the power coefficients of the (homogeneous) piece in the centred
    local variables s in [-1, 1] per direction; points and partials up to order 2 by
    nested Horner with 1-D gathers (the patch-table design of the engine's B-spline
    surfaces), in cache-sized chunks. Rational pieces by the quotient rule (Piegl &
    Tiller eq. 4.8, 4.20)."""

    CHUNK = 1 << 14

    def __init__(self, pieces):
        self.k, self.dim = pieces.k, pieces.dim
        self.degrees = pieces.degrees
        self.rational = pieces.weights is not None
        hom = np.asarray(pieces.homogeneous, dtype=np.float64)           # (m, p+1[, q+1], D)
        self.D = hom.shape[-1]
        for a, p in enumerate(self.degrees):
            hom = np.moveaxis(np.tensordot(_bernstein_to_power(p), hom, axes=([1], [1 + a])), 0, 1 + a)
        m = hom.shape[0]
        # rows ((a * (q+1) + b) * D + d), columns the pieces: take() on contiguous rows
        self.table = np.ascontiguousarray(hom.reshape(m, -1).T)
        self.breaks = [np.asarray(b, dtype=np.float64) for b in pieces.breaks]
        self.shape = tuple(len(b) - 1 for b in self.breaks)
        self.mid = [0.5 * (b[1:] + b[:-1]) for b in self.breaks]
        self.inv_half = [2.0 / (b[1:] - b[:-1]) for b in self.breaks]
        self.uniform = []
        for b in self.breaks:
            w = b[-1] - b[0]
            self.uniform.append(bool(np.allclose(np.diff(b), w / (len(b) - 1), rtol=UNIFORM_RTOL, atol=0.0)))

    def piece_indices(self, x: np.ndarray):
        """Per direction, the index of the piece that evaluates x (n, k)."""
        out = []
        for a, b in enumerate(self.breaks):
            t = x[:, a]
            n = len(b) - 1
            if self.uniform[a]:
                j = ((t - b[0]) * (n / (b[-1] - b[0]))).astype(np.intp)
                np.clip(j, 0, n - 1, out=j)
            else:
                j = np.clip(np.searchsorted(b, t, side="right") - 1, 0, n - 1)
            out.append(j)
        return out

    def _local(self, x: np.ndarray, index=None):
        """Flat piece index and local variables s (one array per direction); ``index``:
        the flat pieces to use (one-sided partials on a piece boundary)."""
        if index is None:
            js = self.piece_indices(x)
        elif self.k == 1:
            js = [index]
        else:
            js = [index // self.shape[1], index % self.shape[1]]
        idx = None
        s = []
        for a, j in enumerate(js):
            s.append((x[:, a] - self.mid[a].take(j)) * self.inv_half[a].take(j))
            idx = j if idx is None else idx * self.shape[a] + j
        return idx, s

    def evaluate(self, x: np.ndarray, order: int, index=None):
        """As Projector.evaluate: S (n, dim), and for order >= 1 J (n, dim, k), for order 2
        the second partials (n, dim, k, k)."""
        x = np.asarray(x, dtype=np.float64).reshape(-1, self.k)
        n, k, dim = len(x), self.k, self.dim
        # component-first storage (contiguous rows per partial and coordinate); the
        # returned arrays are transposed views with the usual (n, dim[, k, k]) shapes
        S = np.empty((dim, n))
        J = np.empty((k, dim, n)) if order >= 1 else None
        H = np.empty((k, k, dim, n)) if order >= 2 else None
        for c0 in range(0, n, self.CHUNK):
            sl = slice(c0, min(n, c0 + self.CHUNK))
            parts = self._chunk(x[sl], order, None if index is None else index[sl])
            self._store(parts, S, J, H, sl, order)
        if order == 0:
            return S.T
        assert J is not None
        if order == 1:
            return S.T, J.T
        assert H is not None
        return S.T, J.T, H.T

    def _chunk(self, x, order, index=None):
        """Per homogeneous coordinate, the partials in the object's parameters: curves
        [C, C', C''], surfaces [S, Su, Sv, Suu, Suv, Svv] (as far as ``order``)."""
        idx, s = self._local(x, index)
        # the rows' coefficients gathered at once ((p+1)[(q+1)] D, n); Horner runs on all
        # coordinates (and u-indices) together: per element the same operations as one
        # coordinate at a time (results bit for bit), in a few numpy calls (a Newton step
        # of a handful of points costs its number of calls, not its arithmetic)
        D, n = self.D, len(idx)
        C = self.table[:, idx]
        if self.k == 1:
            p = self.degrees[0]
            ih = self.inv_half[0].take(idx)
            C = C.reshape(p + 1, D, n)
            r = _horner([C[a] for a in range(p + 1)], s[0], order)
            if order >= 1:
                r[1] = r[1] * ih
            if order >= 2:
                r[2] = 2.0 * r[2] * ih * ih
            return [[part[d] for part in r] for d in range(D)]
        p, q = self.degrees
        nv = self.shape[1]
        ihu, ihv = self.inv_half[0].take(idx // nv), self.inv_half[1].take(idx % nv)
        su, sv = s
        C = C.reshape(p + 1, q + 1, D, n)
        Q = _horner([C[:, b] for b in range(q + 1)], sv, order)          # each (p+1, D, n)
        r0 = _horner([Q[0][a] for a in range(p + 1)], su, order)         # each (D, n)
        if order == 0:
            return [[r0[0][d]] for d in range(D)]
        r1 = _horner([Q[1][a] for a in range(p + 1)], su, order - 1)
        res = [r0[0], r0[1] * ihu, r1[0] * ihv]
        if order >= 2:
            r2 = _horner([Q[2][a] for a in range(p + 1)], su, 0)
            res += [2.0 * r0[2] * ihu * ihu, r1[1] * (ihu * ihv), 2.0 * r2[0] * ihv * ihv]
        return [[part[d] for part in res] for d in range(D)]

    def _store(self, parts, S, J, H, sl, order):
        k, dim = self.k, self.dim
        if self.rational:
            w = parts[-1]
            iw = 1.0 / w[0]
            cart = []
            for d in range(dim):
                A = parts[d]
                c = [A[0] * iw]
                if k == 1:
                    if order >= 1:
                        c.append((A[1] - w[1] * c[0]) * iw)
                    if order >= 2:
                        c.append((A[2] - 2.0 * w[1] * c[1] - w[2] * c[0]) * iw)
                else:
                    if order >= 1:
                        c.append((A[1] - w[1] * c[0]) * iw)
                        c.append((A[2] - w[2] * c[0]) * iw)
                    if order >= 2:
                        c.append((A[3] - 2.0 * w[1] * c[1] - w[3] * c[0]) * iw)
                        c.append((A[4] - w[1] * c[2] - w[2] * c[1] - w[4] * c[0]) * iw)
                        c.append((A[5] - 2.0 * w[2] * c[2] - w[5] * c[0]) * iw)
                cart.append(c)
            parts = cart
        for d in range(dim):
            c = parts[d]
            S[d, sl] = c[0]
            if order >= 1:
                for a in range(k):
                    J[a, d, sl] = c[1 + a]
            if order >= 2:
                if k == 1:
                    H[0, 0, d, sl] = c[2]
                else:
                    H[0, 0, d, sl] = c[3]
                    H[0, 1, d, sl] = c[4]
                    H[1, 0, d, sl] = c[4]
                    H[1, 1, d, sl] = c[5]
