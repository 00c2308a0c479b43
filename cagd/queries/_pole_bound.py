"""A first-order bound of the distance on cells with a collapsed edge (a pole: the nose of a
fuselage, the apex of a cone, the tip of a revolved dome), where the second-order bounds
fail: there S_v = 0 along the edge, the Hessian of g = |S - X|^2 is indefinite next to
it and the foot's v is not determined, so boxes around a foot at the pole never closed
(issue 16: 1,497 of 2,000 points near a cone's apex ended unproven, bounds 1e-6 below
their distances).

On a Bezier cell whose control row at the edge s = 0 (s the local coordinate across it) is
one point C up to eps = max_j |P_0j - C|, the numerator of S - C is divisible by s:
B_i^p(s) = s (p / i) B_(i-1)^(p-1)(s) for i >= 1 (Farin 5.1), so

    S - C = s E / w + R,  E = sum_(i>=1, j) (p / i) w_ij (P_ij - C) B_(i-1)^(p-1)(s) B_j^q(v),

|R| <= eps max_j w_0j / w (the edge row's term; w = 1, w_ij = 1 for polynomial cells).
With a = C - X, |S - X| >= |a + s E / w| - |R| and |a + s E / w|^2 >= |a|^2 + 2 s (a . E) / w,
a . E bounded below by its smallest Bernstein coefficient (the convex hull property,
Farin 3.3) and w by the cell's weights. Where that coefficient is not negative the point
C is the nearest of the whole cell: the bound is |a| itself, whatever v."""
from __future__ import annotations

from typing import Optional

import numpy as np

from ._numerics import SIZE_ROUNDING, row_max, squared_norms
from .bounds import BezierPieces


class _Side:
    """The pole cells ``which`` whose collapsed edge is ``side`` (0: u = lo, 1: u = hi,
    2: v = lo, 3: v = hi): the edge's point C, eps, the coefficients of E, the weights'
    extremes."""

    def __init__(self, cells: BezierPieces, which: np.ndarray, side: int):
        self.direction, self.start = side // 2, side % 2 == 0        # across u or v; the edge at s = 0 or 1
        self.lower, self.upper = cells.lower[which], cells.upper[which]
        net = _edge_first(np.asarray(cells.control_points, dtype=np.float64)[which], side)   # (n, p+1, q+1, D)
        w = np.ones(net.shape[:3]) if cells.weights is None else \
            _edge_first(np.asarray(cells.weights, dtype=np.float64)[which][..., None], side)[..., 0]
        self.C = net[:, 0, 0]
        self.eps = np.sqrt(row_max(squared_norms(net[:, 0] - self.C[:, None]))) * row_max(w[:, 0])
        p = net.shape[1] - 1
        scale = (p / np.arange(1, p + 1))[None, :, None, None]
        self.E = ((net[:, 1:] - self.C[:, None, None]) * w[:, 1:, :, None] * scale).reshape(len(which), -1,
                                                                                            net.shape[-1])
        flat = w.reshape(len(which), -1)
        self.wmin, self.wmax = flat.min(axis=1), flat.max(axis=1)

    def squared_bound(self, X: np.ndarray, j: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """The bound of g on rows (X, lo, hi) of this side's cells ``j``."""
        a = self.C[j] - X
        m1 = (self.E[j] @ a[:, :, None])[:, :, 0].min(axis=1)        # a . E >= m1 (Bernstein coefficients)
        m1 = m1 / np.where(m1 >= 0, self.wmax[j], self.wmin[j])       # ... and a . E / w >= this
        d = self.direction
        width = self.upper[j, d] - self.lower[j, d]
        t_lo, t_hi = (lo[:, d] - self.lower[j, d]) / width, (hi[:, d] - self.lower[j, d]) / width
        s_lo, s_hi = (t_lo, t_hi) if self.start else (1.0 - t_hi, 1.0 - t_lo)
        s = np.clip(np.where(m1 >= 0, s_lo, s_hi), 0.0, 1.0)          # where 2 s m1 is least over the box
        g = np.maximum((a * a).sum(-1) + 2.0 * s * m1, 0.0)
        return np.maximum(np.sqrt(g) - self.eps[j] / self.wmin[j], 0.0) ** 2


class PoleCells:
    """The cells of a surface's ``cells`` with a collapsed edge, per side
    (:class:`_Side`); :meth:`squared_bound` for (point, box) rows."""

    def __init__(self, cells: BezierPieces, cell: np.ndarray, side: np.ndarray):
        self.side = np.full(len(cells), -1, dtype=np.intp)
        self.index = np.full(len(cells), -1, dtype=np.intp)
        self.sides = {}
        for sd in np.unique(side):
            which = cell[side == sd]
            self.side[which], self.index[which] = sd, np.arange(len(which))
            self.sides[int(sd)] = _Side(cells, which, int(sd))

    @classmethod
    def of(cls, cells: BezierPieces, size: float) -> Optional["PoleCells"]:
        """The pole cells of ``cells`` (an edge row within SIZE_ROUNDING of the size of one
        point; one edge per cell, the first), None where there are none (curves, ordinary
        surfaces)."""
        if cells.k != 2 or min(cells.degrees) < 1:
            return None
        P = np.asarray(cells.control_points, dtype=np.float64)
        rows = [P[:, 0], P[:, -1], P[:, :, 0], P[:, :, -1]]
        spread2 = np.stack([row_max(squared_norms(r - r[:, :1])) for r in rows], axis=1)
        hit = spread2 <= (SIZE_ROUNDING * size) ** 2
        if not hit.any():
            return None
        cell, side = np.nonzero(hit)
        first = np.unique(cell, return_index=True)[1]
        return cls(cells, cell[first], side[first])

    def squared_bound(self, X: np.ndarray, cell: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """A lower bound of g = |S - X|^2 over each box [lo, hi] of ``cell`` (rows; X the
        points (n, D)), 0 on rows whose cell has no pole."""
        out = np.zeros(len(cell))
        sd = self.side[cell]
        for k, side in self.sides.items():
            r = np.flatnonzero(sd == k)
            if r.size:
                out[r] = side.squared_bound(X[r], self.index[cell[r]], lo[r], hi[r])
        return out


def _edge_first(net: np.ndarray, side: int) -> np.ndarray:
    """Nets (n, p+1, q+1, e) turned so that the control row at ``side`` comes first along
    axis 1 (v-sides transposed)."""
    t = net if side < 2 else net.transpose(0, 2, 1, 3)
    return t if side % 2 == 0 else t[:, ::-1]
