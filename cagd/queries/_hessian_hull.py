"""The half Hessian of the squared distance over a Bezier cell, entry by entry as a
Bezier polynomial whose coefficients are affine in the query point (issue 16: bounds
over a cell tight enough to close the box that holds the foot at once); on a rational
cell, that of w^4 times it (:class:`RationalHessianHull`).

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
from typing import Callable, List, Optional, Tuple

import numpy as np

from ._numerics import row_max, row_min
from .bounds import BezierPieces, restriction_matrix, symmetric_pairs as _pairs

ROWS_MIN = 64        # cells' rows stored at least this many at a time
ROWS_CHUNK = 256     # rational intervals: (point, cell) rows per pass (the coefficients in cache)
RESTRICT_ULPS = 4    # rounding of a restriction to a cell: this many ulps per de Casteljau level, of the largest
                     # coefficient of the piece (convex combinations; the matrices' entries likewise)


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


class _CellRows:
    """Arrays of rows per cell (shapes ``shapes`` per row) computed by ``fill`` for the
    cells first asked for and kept in slots: memory in proportion to the cells used (a
    search touches a few of a large net's cells), grown by doubling, at most one row per
    cell."""

    def __init__(self, m: int, shapes: List[Tuple[int, ...]], fill: Callable[[np.ndarray], List[np.ndarray]]):
        self._slot = np.full(m, -1, dtype=np.intp)
        self._arrays = [np.empty((0,) + s) for s in shapes]
        self._used = 0
        self._fill = fill

    def __call__(self, cell: np.ndarray) -> np.ndarray:
        """The slots of the rows of ``cell`` (filled first where new)."""
        new = np.unique(cell[self._slot[cell] < 0])
        if new.size:
            need = self._used + len(new)
            if need > len(self._arrays[0]):
                cap = min(len(self._slot), max(need, 2 * len(self._arrays[0]), ROWS_MIN))
                grown = [np.empty((cap,) + a.shape[1:]) for a in self._arrays]
                for g, a in zip(grown, self._arrays):
                    g[:self._used] = a[:self._used]
                self._arrays = grown
            slots = np.arange(self._used, need)
            for a, v in zip(self._arrays, self._fill(new)):
                a[slots] = v
            self._slot[new] = slots
            self._used = need
        return self._slot[cell]

    @property
    def arrays(self) -> List[np.ndarray]:
        """The stored rows, indexed by the slots :meth:`__call__` returns."""
        return self._arrays

    @property
    def nbytes(self) -> int:
        return int(sum(a.nbytes for a in self._arrays))


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
        # one column block per pair
        self._widths = [1 if op is None else op[3].shape[2] for op in self.ops]
        self._rows = _CellRows(len(cells), [(sum(self._widths),)], self._fill)
        self._starts = np.cumsum([0] + self._widths[:-1])
        # X . V of every pair side by side: (P . X) @ W, column block ab divided by h_a h_b
        self._W = np.zeros((prod(self.sizes), sum(self._widths)))
        for s0, w, op in zip(self._starts, self._widths, self.ops):
            if op is not None and op[5] is not None:
                self._W[:, s0:s0 + w] = op[5]

    def _fill(self, idx: np.ndarray) -> List[np.ndarray]:
        """[C] of the cells ``idx``."""
        Pf = self.P[idx].reshape(len(idx), -1, self.P.shape[-1])
        h = self.h[idx]
        out = np.empty((len(idx), sum(self._widths)))
        col = 0
        for (a, b), op, w in zip(self.pairs, self.ops, self._widths):
            if op is None:
                out[:, col] = 0.0
            else:
                Da, Db, Dab, T1, T2, _ = op
                Sa = (Da @ Pf) / h[:, a, None, None]                      # (m, na, D)
                Sb = (Db @ Pf) / h[:, b, None, None]
                C = (Sa @ Sb.transpose(0, 2, 1)).reshape(len(idx), -1) @ T1.reshape(-1, w)
                if Dab is not None:
                    Sab = (Dab @ Pf) / (h[:, a] * h[:, b])[:, None, None]
                    C = C + (Pf @ Sab.transpose(0, 2, 1)).reshape(len(idx), -1) @ T2.reshape(-1, w)
                out[:, col:col + w] = C
            col += w
        return [out]

    def intervals(self, X: np.ndarray, cell: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (n, k, k): H_ab over the whole cell ``cell[i]`` lies in [lo_ab, hi_ab] for
        the query point X[i] (X (n, D))."""
        n, k = len(cell), self.k
        PX = (self.P[cell].reshape(n, -1, X.shape[1]) @ X[:, :, None])[:, :, 0]
        h = self.h[cell]
        per = np.stack([1.0 / (h[:, a] * h[:, b]) for a, b in self.pairs], axis=1)      # (n, pairs)
        slots = self._rows(cell)                     # (fills new cells: before reading the arrays)
        vals = self._rows.arrays[0][slots] - (PX @ self._W) * np.repeat(per, self._widths, axis=1)
        return _symmetric(np.minimum.reduceat(vals, self._starts, axis=1),
                          np.maximum.reduceat(vals, self._starts, axis=1), self.pairs, n, k)

    def divisors(self, cell: np.ndarray) -> None:
        """None: H itself is bounded (no w^4 to divide by)."""
        return None

    @property
    def nbytes(self) -> int:
        """Bytes of the coefficients stored so far."""
        return self._rows.nbytes


def _symmetric(mins: np.ndarray, maxs: np.ndarray, pairs: List[Tuple[int, int]], n: int, k: int
               ) -> Tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (n, k, k) symmetric matrices from the per-pair columns of mins and maxs."""
    lo, hi = np.empty((n, k, k)), np.empty((n, k, k))
    for j, (a, b) in enumerate(pairs):
        lo[:, a, b] = lo[:, b, a] = mins[:, j]
        hi[:, a, b] = hi[:, b, a] = maxs[:, j]
    return lo, hi


# --- rational cells ---------------------------------------------------------------------
# With A = w S the homogeneous numerator (Farin 13.1) and N_a = A_a w - A w_a, the partials
# are S_a = N_a / w^2 and S_ab = K_ab / w^3, K_ab = A_ab w^2 - (A_a w_b + A_b w_a) w
# - A w_ab w + 2 A w_a w_b (the quotient rule twice), so w^4 H_ab = N_a . N_b
# + (A - X w) . K_ab: polynomials again, of degree 4p per direction, whose coefficients are
# affine in X. H = G / w^4 with G symmetric and w^4 > 0 on the cell: the smallest eigenvalue
# of H is that of G divided by w^4, bounded by the extreme coefficients of w. Cells cut from
# a piece take G's coefficients of the piece restricted to their part (de Casteljau), with
# a bound of that rounding added to the intervals: against G in long double, 50-300 times
# closer than the products on each cell (1e-14 against 1e-12 of the largest coefficient).

def _raised(c: np.ndarray, k: int, sizes: Tuple[int, ...]) -> np.ndarray:
    """Batched Bernstein coefficients c (m, *s, e) raised to ``sizes`` per direction: the
    product with the constant 1 (Farin 5.1, degree elevation)."""
    ones = np.ones((1,) + tuple(n - s + 1 for n, s in zip(sizes, c.shape[1:1 + k])) + (1,))
    return c if c.shape[1:1 + k] == sizes else _product(c, ones, k)


def _product(a: np.ndarray, b: np.ndarray, k: int) -> np.ndarray:
    """Bernstein coefficients of the products of batches of tensor-product Bezier
    polynomials a (m, *sa, e) and b (m, *sb, e) on the unit box (Farin 5.8 per direction:
    the binomially scaled coefficients convolve), the trailing axes broadcast; a loop over
    the coefficients of the smaller factor, each step one array operation over the batch."""
    sa, sb = a.shape[1:1 + k], b.shape[1:1 + k]
    if prod(sa) > prod(sb):
        a, b, sa, sb = b, a, sb, sa
    sc = tuple(x + y - 1 for x, y in zip(sa, sb))
    As = a * _binomials(sa)[..., None]
    Bs = b * _binomials(sb)[..., None]
    m = max(a.shape[0], b.shape[0])
    out = np.zeros((m,) + sc + (max(a.shape[-1], b.shape[-1]),))
    for idx in np.ndindex(*sa):
        where = (slice(None),) + tuple(slice(i, i + n) for i, n in zip(idx, sb))
        out[where] += As[(slice(None),) + idx].reshape((a.shape[0],) + (1,) * k + (a.shape[-1],)) * Bs
    return out / _binomials(sc)[..., None]


def _partial(c: np.ndarray, k: int, a: int) -> np.ndarray:
    """Bernstein coefficients of d/dx_a of batched polynomials on the unit box (the hodograph,
    Farin 5.3): p times the forward differences; the constant 0 where the degree is 0."""
    n = c.shape[1 + a] - 1
    if n == 0:
        return np.zeros_like(c)
    return n * np.diff(c, axis=1 + a)


def _sum(terms: List[Tuple[float, np.ndarray]], k: int) -> np.ndarray:
    """sum f_i c_i over polynomials of different degrees, raised to the largest per direction."""
    sizes = tuple(max(c.shape[1 + a] for _, c in terms) for a in range(k))
    out = terms[0][0] * _raised(terms[0][1], k, sizes)
    for f, c in terms[1:]:
        out = out + f * _raised(c, k, sizes)
    return out


@lru_cache(maxsize=None)
def _restriction(degree: int, j: int, c: int) -> np.ndarray:
    """The restriction matrix of a degree to [j / c, (j + 1) / c] (the parts of a piece's
    cells recur across pieces and objects: built once)."""
    R = restriction_matrix(degree, j / c, (j + 1) / c)
    R.setflags(write=False)
    return R


class RationalHessianHull:
    """Bounds of the half Hessian over rational cells (see the comment above): per (point,
    cell) row, intervals of the entries of G = w^4 H (:meth:`intervals`) and of w^4
    (:meth:`divisors`), the weights of each cell scaled to a largest of 1."""

    def __init__(self, cells: BezierPieces, pieces: Optional[BezierPieces] = None,
                 piece_of: Optional[List[np.ndarray]] = None):
        """``pieces``, ``piece_of``: the Bezier pieces that ``cells`` cut into equal parts
        per direction (:meth:`BezierPieces.subdivided`) and each cell's piece index per
        direction; the rows are then computed per piece and restricted to its cells (the
        products once per piece, not per cell: a real face's first bounds fill 60-160
        cells of a few pieces)."""
        self.k = k = cells.k
        w = np.asarray(cells.weights, dtype=np.float64)
        top = row_max(w)
        self.w = w / top.reshape((-1,) + (1,) * k)
        self.A = np.asarray(cells.control_points, dtype=np.float64) * self.w[..., None]
        self.h = cells.upper - cells.lower
        self.pairs = _pairs(k)
        sizes = self.w.shape[1:]
        self._final = tuple(4 * (s - 1) + 1 for s in sizes)      # G's coefficients per direction
        self._n = prod(self._final)                              # ... per entry
        m, D, width = len(cells), self.A.shape[-1], len(self.pairs) * self._n
        row: Tuple[int, ...] = (width,)
        bound: Tuple[int, ...] = (len(self.pairs),)              # a rounding bound per entry
        self._rows = _CellRows(m, [row] * (1 + D) + [bound] * (1 + D), self._fill if pieces is None else self._restrict)
        flat = self.w.reshape(m, -1)
        self._div = (row_min(flat) ** 4, row_max(flat) ** 4)
        self._parent: Optional[RationalHessianHull] = None       # the pieces' hull the rows come from
        if pieces is not None:
            assert piece_of is not None
            self._parent = RationalHessianHull(pieces)
            shape = tuple(len(b) - 1 for b in pieces.breaks)
            self._piece = piece_of[0] if k == 1 else (piece_of[0][:, None] * shape[1] + piece_of[1][None, :]).ravel()
            # per direction, each cell's part j of the c parts of its piece: the restriction
            # to [j / c, (j + 1) / c] (as the cells' own nets were made)
            self._parts = [(np.arange(len(of)) - np.searchsorted(of, of), np.bincount(of, minlength=n)[of])
                           for of, n in zip(piece_of, shape)]
            # G is homogeneous of degree 4 in the weights: the piece's scaling to the cell's
            top_piece = row_max(np.asarray(pieces.weights, dtype=np.float64))
            self._rescale = (top_piece[self._piece] / top) ** 4

    def _fill(self, idx: np.ndarray) -> List[np.ndarray]:
        """[C, V_1 .. V_D] of the cells ``idx``: G_ab = C_ab - X . V_ab, pairs side by side."""
        k = self.k
        D = self.A.shape[-1]
        out = [np.empty((len(idx), len(self.pairs) * self._n)) for _ in range(1 + D)]
        A, w = self.A[idx], self.w[idx][..., None]
        Aa = [_partial(A, k, a) for a in range(k)]
        wa = [_partial(w, k, a) for a in range(k)]
        N = [_sum([(1.0, _product(Aa[a], w, k)), (-1.0, _product(A, wa[a], k))], k) for a in range(k)]
        h = self.h[idx]
        final = tuple(4 * (s - 1) + 1 for s in self.w.shape[1:])
        ww = _product(w, w, k)
        for j, (a, b) in enumerate(self.pairs):
            K = _sum([(1.0, _product(_partial(Aa[a], k, b), ww, k)),
                      (-1.0, _product(_sum([(1.0, _product(Aa[a], wa[b], k)), (1.0, _product(Aa[b], wa[a], k)),
                                            (1.0, _product(A, _partial(wa[a], k, b), k))], k), w, k)),
                      (2.0, _product(A, _product(wa[a], wa[b], k), k))], k)
            C = _sum([(1.0, _product(N[a], N[b], k)), (1.0, _product(A, K, k))], k).sum(-1)
            V = _raised(_product(w, K, k), k, final)
            s = 1.0 / (h[:, a] * h[:, b])
            cols = slice(j * self._n, (j + 1) * self._n)
            out[0][:, cols] = _raised(C[..., None], k, final).reshape(len(idx), -1) * s[:, None]
            for d in range(D):
                out[1 + d][:, cols] = V[..., d].reshape(len(idx), -1) * s[:, None]
        return out + [np.zeros((len(idx), len(self.pairs)))] * (1 + D)     # (computed on the cell itself)

    def _restrict(self, idx: np.ndarray) -> List[np.ndarray]:
        """[C, V_1 .. V_D] of the cells ``idx`` from their pieces' rows: each entry's
        Bernstein coefficients restricted to the cell's part of its piece (de Casteljau
        per direction, :func:`cagd.queries.bounds.restriction_matrix`; Farin 4.2), in
        the object's parameters already, times the weights' rescaling to the cell."""
        parent = self._parent
        assert parent is not None
        slots = parent._rows(self._piece[idx])
        nk = len(self.pairs)
        along = [idx] if self.k == 1 else list(np.divmod(idx, len(self._parts[1][0])))    # per direction
        Rs = []
        for a, ((j, c), i) in enumerate(zip(self._parts, along)):
            pairs, inv = np.unique(np.stack([j[i], c[i]], axis=1), axis=0, return_inverse=True)
            mats = np.stack([_restriction(self._final[a] - 1, int(jj), int(cc)) for jj, cc in pairs])
            Rs.append(mats[inv.reshape(-1)])
        out, err = [], []
        D = len(parent._rows.arrays) // 2 - 1
        for arr in parent._rows.arrays[:1 + D]:
            rows = arr[slots].reshape((len(idx), nk) + self._final)
            # de Casteljau's convex combinations: each level's rounding at most a few ulps of
            # the piece's largest coefficient (the matrices' own entries likewise)
            err.append(RESTRICT_ULPS * sum(self._final) * np.finfo(float).eps * self._rescale[idx, None]
                       * np.abs(rows).reshape(len(idx), nk, -1).max(axis=2))
            rows = np.matmul(Rs[0][:, None], rows if self.k == 2 else rows[..., None])    # (batched products)
            if self.k == 2:
                rows = np.matmul(rows, Rs[1].transpose(0, 2, 1)[:, None])
            out.append(rows.reshape(len(idx), -1) * self._rescale[idx, None])
        return out + err

    def intervals(self, X: np.ndarray, cell: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (n, k, k): G_ab = w^4 H_ab over the whole cell ``cell[i]`` lies in
        [lo_ab, hi_ab] for the query point X[i] (X (n, D))."""
        n, k = len(cell), self.k
        slots = self._rows(cell)                     # (fills new cells: before reading the arrays)
        arrays = self._rows.arrays
        C, *V = arrays[:len(arrays) // 2]
        E = arrays[len(arrays) // 2:]                # rounding bounds of the restricted rows, per pair
        starts = np.arange(len(self.pairs)) * self._n
        mins, maxs = np.empty((n, len(starts))), np.empty((n, len(starts)))
        vals, term = np.empty((min(n, ROWS_CHUNK), C.shape[1])), np.empty((min(n, ROWS_CHUNK), C.shape[1]))
        for s0 in range(0, n, ROWS_CHUNK):          # rows in cache-sized chunks, coordinate by coordinate
            at, x = slots[s0:s0 + ROWS_CHUNK], X[s0:s0 + ROWS_CHUNK]
            v, t = vals[:len(at)], term[:len(at)]
            np.take(C, at, axis=0, out=v)
            for d, Vd in enumerate(V):
                np.take(Vd, at, axis=0, out=t)
                t *= x[:, d, None]
                v -= t
            mins[s0:s0 + len(at)] = np.minimum.reduceat(v, starts, axis=1)
            maxs[s0:s0 + len(at)] = np.maximum.reduceat(v, starts, axis=1)
        e = E[0][slots] + sum(np.abs(X[:, d, None]) * Ed[slots] for d, Ed in enumerate(E[1:]))
        return _symmetric(mins - e, maxs + e, self.pairs, n, k)

    def divisors(self, cell: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (n,): w^4 over the cell lies between them (its weights' extremes)."""
        return self._div[0][cell], self._div[1][cell]

    @property
    def nbytes(self) -> int:
        """Bytes of the coefficients stored so far (with the pieces' the cells come from)."""
        return self._rows.nbytes + (0 if self._parent is None else self._parent.nbytes)
