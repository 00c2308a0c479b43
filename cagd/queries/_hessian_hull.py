"""The half Hessian of the squared distance over a polynomial Bezier cell, entry by
entry as a Bezier polynomial whose coefficients are affine in the query point (issue 16:
bounds over a cell tight enough to close the box that holds the foot at once).

With g(x) = |S(x) - X|^2, half its Hessian is H_ab(x) = S_a . S_b + (S - X) . S_ab
(Piegl & Tiller 6.1, eq. 6.6 written for surfaces). On a polynomial Bezier cell both
products are polynomials of the same degree; in Bernstein form (the product formula,
Farin, Curves and Surfaces for CAGD, 5.8: sum a_i B_i^m * sum b_j B_j^n =
sum_l [sum_(i+j=l) C(m,i) C(n,j) / C(m+n,l) a_i b_j] B_l^(m+n), per direction)
H_ab = sum_l (C_l - X . V_l) B_l, C the coefficients of S_a . S_b + S . S_ab and V
those of S_ab raised to that degree. By the convex-hull property H_ab(x) lies between
the smallest and largest coefficient over the whole cell, so over any box in it. The
direction of every vector is kept: where the partials are nearly orthogonal to the
second derivatives (a height field of small slope), these intervals are far tighter
than products of norm bounds.

Every step is a fixed linear map on the flattened control net (hodographs, products,
raising), built once per degree from unit coefficient arrays. C is computed per cell on
first use and kept (``n_C`` numbers per cell, about 100 for a bicubic); X . V per row
is (P . X) times a fixed matrix."""
from __future__ import annotations

from functools import lru_cache
from math import comb, prod
from typing import List, Optional, Tuple

import numpy as np

from .bounds import BezierPieces


def _binomials(sizes: Tuple[int, ...]) -> np.ndarray:
    """prod_a C(n_a - 1, i_a) over the multi-indices of a coefficient array of ``sizes``."""
    out = np.ones(())
    for n in sizes:
        out = np.multiply.outer(out, np.array([comb(n - 1, i) for i in range(n)], dtype=np.float64))
    return out


def _product_matrix(sa: Tuple[int, ...], sb: Tuple[int, ...]) -> np.ndarray:
    """T (|sa|, |sb|, |sc|): the Bezier coefficients of the product of two tensor-product
    Bezier polynomials of coefficient shapes sa and sb are c_l = sum_ij a_i b_j T[i, j, l]
    (Farin 5.8 per direction; flattened multi-indices)."""
    sc = tuple(x + y - 1 for x, y in zip(sa, sb))
    wa, wb, wc = _binomials(sa).ravel(), _binomials(sb).ravel(), _binomials(sc)
    T = np.zeros((prod(sa), prod(sb)) + sc)
    for i, ia in enumerate(np.ndindex(*sa)):
        for j, jb in enumerate(np.ndindex(*sb)):
            T[(i, j) + tuple(x + y for x, y in zip(ia, jb))] = wa[i] * wb[j]
    return (T / wc).reshape(prod(sa), prod(sb), prod(sc))


def _hodograph_matrix(sizes: Tuple[int, ...], alpha: Tuple[int, ...]) -> Optional[Tuple[np.ndarray, Tuple[int, ...]]]:
    """(Dm, shape): the Bezier coefficients of d^alpha of a polynomial with coefficient
    shape ``sizes`` on the unit box are Dm @ (its flattened coefficients), of ``shape``
    (p!/(p-r)! times the r-th forward differences, Farin 5.3); None where an order
    exceeds the degree (the partial is zero)."""
    E = np.eye(prod(sizes)).reshape((-1,) + sizes)
    for a, r in enumerate(alpha):
        p = sizes[a] - 1
        if r > p:
            return None
        if r:
            E = np.diff(E, n=r, axis=1 + a) * float(np.prod(np.arange(p - r + 1, p + 1)))
    shape: Tuple[int, ...] = tuple(E.shape)
    return E.reshape(shape[0], -1).T, shape[1:]


def _pairs(k: int) -> List[Tuple[int, int]]:
    """The entries (a, b), a <= b, of a symmetric k x k matrix."""
    return [(0, 0)] if k == 1 else [(0, 0), (0, 1), (1, 1)]


@lru_cache(maxsize=None)
def _operators(sizes: Tuple[int, ...]) -> List[Optional[tuple]]:
    """Per pair (a, b), a <= b, for cells of coefficient shape ``sizes``: (Da, Db, Dab,
    T1, T2, W) with C = (Da P . Db P) T1 + (P . Dab P) T2 and X . V = (P . X) W on the unit
    box (Dab, T2, W None where S_ab = 0)."""
    k = len(sizes)
    ops: List[Optional[tuple]] = []
    for a, b in _pairs(k):
        ea = tuple(int(i == a) for i in range(k))
        eb = tuple(int(i == b) for i in range(k))
        ha, hb = _hodograph_matrix(sizes, ea), _hodograph_matrix(sizes, eb)
        hab = _hodograph_matrix(sizes, tuple(x + y for x, y in zip(ea, eb)))
        if ha is None or hb is None:                   # degree 0 along a direction: S_a = 0
            ops.append(None)
            continue
        T1 = _product_matrix(ha[1], hb[1])
        if hab is None:
            ops.append((ha[0], hb[0], None, T1, None, None))
            continue
        T2 = _product_matrix(sizes, hab[1])
        # S_ab raised to the product's degree: its product with the constant 1 of shape sizes
        W = hab[0].T @ _product_matrix(hab[1], sizes).sum(axis=1)
        ops.append((ha[0], hb[0], hab[0], T1, T2, W))
    return ops


class HessianHull:
    """Bounds of the half Hessian H = J^T J + (S - X) . d2S over polynomial cells
    ``cells``, per (point, cell) row (:meth:`intervals`)."""

    def __init__(self, cells: BezierPieces):
        self.k = cells.k
        self.P = np.asarray(cells.control_points, dtype=np.float64)
        self.sizes = tuple(self.P.shape[1:1 + self.k])
        self.h = cells.upper - cells.lower
        self.ops = _operators(self.sizes)
        self.pairs = _pairs(self.k)
        m = len(cells)
        self._have = np.zeros(m, dtype=bool)
        # one column block per pair; np.empty: only the cells filled take memory
        self._widths = [1 if op is None else op[3].shape[2] for op in self.ops]
        self._C = np.empty((m, sum(self._widths)))
        self._starts = np.cumsum([0] + self._widths[:-1])
        # X . V of every pair side by side: (P . X) @ W, column block ab divided by h_a h_b
        self._W = np.zeros((prod(self.sizes), sum(self._widths)))
        for s0, w, op in zip(self._starts, self._widths, self.ops):
            if op is not None and op[5] is not None:
                self._W[:, s0:s0 + w] = op[5]

    def _fill(self, idx: np.ndarray) -> None:
        """C of the cells ``idx`` (unique, not yet known)."""
        Pf = self.P[idx].reshape(len(idx), -1, self.P.shape[-1])
        h = self.h[idx]
        col = 0
        for (a, b), op, w in zip(self.pairs, self.ops, self._widths):
            if op is None:
                self._C[idx, col] = 0.0
            else:
                Da, Db, Dab, T1, T2, _ = op
                Sa = (Da @ Pf) / h[:, a, None, None]                      # (m, na, D)
                Sb = (Db @ Pf) / h[:, b, None, None]
                C = (Sa @ Sb.transpose(0, 2, 1)).reshape(len(idx), -1) @ T1.reshape(-1, w)
                if Dab is not None:
                    Sab = (Dab @ Pf) / (h[:, a] * h[:, b])[:, None, None]
                    C = C + (Pf @ Sab.transpose(0, 2, 1)).reshape(len(idx), -1) @ T2.reshape(-1, w)
                self._C[idx, col:col + w] = C
            col += w
        self._have[idx] = True

    def intervals(self, X: np.ndarray, cell: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (n, k, k): H_ab over the whole cell ``cell[i]`` lies in [lo_ab, hi_ab] for
        the query point X[i] (X (n, D))."""
        new = cell[~self._have[cell]]
        if new.size:
            self._fill(np.unique(new))
        n, k = len(cell), self.k
        PX = (self.P[cell].reshape(n, -1, X.shape[1]) @ X[:, :, None])[:, :, 0]
        h = self.h[cell]
        per = np.stack([1.0 / (h[:, a] * h[:, b]) for a, b in self.pairs], axis=1)      # (n, pairs)
        vals = self._C[cell] - (PX @ self._W) * np.repeat(per, self._widths, axis=1)
        mins = np.minimum.reduceat(vals, self._starts, axis=1)
        maxs = np.maximum.reduceat(vals, self._starts, axis=1)
        lo, hi = np.empty((n, k, k)), np.empty((n, k, k))
        for j, (a, b) in enumerate(self.pairs):
            lo[:, a, b] = lo[:, b, a] = mins[:, j]
            hi[:, a, b] = hi[:, b, a] = maxs[:, j]
        return lo, hi
