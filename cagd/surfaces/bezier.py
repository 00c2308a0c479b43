"""Tensor-product Bezier patches, polynomial and rational (seed 000, 5.2.7;
seed 003, 2.2: de Casteljau in two directions, boundary tangents, blossoms)."""
from __future__ import annotations

from typing import Dict, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bernstein import bernstein, bezier_matrix, elevation_matrix
from ..errors import CagdError
from .base import Surface
from .bspline import BSplineSurface

_CHUNK_VALUES = 1 << 22     # net values per chunk of de Casteljau (32 MiB)


class BezierSurface(Surface):
    """p(u, v) = sum_i sum_j P_ij BEZ_{i,m}(u) BEZ_{j,n}(v) on [0, 1]^2 (seed 000, 5.2.7),
    rational with ``weights`` (seed 003, 2.4).

    Args:
        control_points: (m+1, n+1, dim) control net, m, n >= 1.
        weights: (m+1, n+1) positive weights or None.

    Raises:
        CagdError: shape, NaN/inf, weights.
    """

    _modified_copy = BSplineSurface._modified_copy

    def __init__(self, control_points: ArrayLike, weights: Optional[ArrayLike] = None):
        P = _checks.finite_array(control_points, "control_points")
        if P.ndim != 3 or P.shape[0] < 2 or P.shape[1] < 2:
            raise CagdError(f"control_points: expected shape (m+1 >= 2, n+1 >= 2, dim), got {P.shape}")
        m = _checks.degree(P.shape[0] - 1, "control_points (rows - 1 is the degree in u)")
        n = _checks.degree(P.shape[1] - 1, "control_points (columns - 1 is the degree in v)")
        ku = np.concatenate([np.zeros(m + 1), np.ones(m + 1)])
        kv = np.concatenate([np.zeros(n + 1), np.ones(n + 1)])
        self._fill(BSplineSurface(P, m, n, ku, kv, weights))

    def _fill(self, nurbs: BSplineSurface) -> None:
        """Everything from the single-patch NURBS form (which shares its frozen arrays)."""
        self._nurbs = nurbs
        self.control_points, self.weights = nurbs.control_points, nurbs.weights
        self.degree_u, self.degree_v, self.dim = nurbs.degree_u, nurbs.degree_v, nurbs.dim

    # --- modified copies ----------------------------------------------------------------
    def with_control_points(self, control_points: ArrayLike) -> "BezierSurface":
        """The same degrees and weights on a new control net of the same shape.

        Raises:
            CagdError: NaN/inf, a shape other than ``control_points.shape``."""
        return BezierSurface._unchecked(self._nurbs.with_control_points(control_points))

    def moved_pole(self, index: Tuple[int, int], point: ArrayLike) -> "BezierSurface":
        """The patch with control point ``index`` = (i, j) moved to ``point`` (see
        :meth:`cagd.BSplineSurface.moved_pole`).

        Raises:
            CagdError: an index that is not two ints in range, a bad point."""
        return BezierSurface._unchecked(self._nurbs.moved_pole(index, point))

    def with_weights(self, weights: Optional[ArrayLike]) -> "BezierSurface":
        """The same control net with new (m+1, n+1) weights (None: polynomial).

        Raises:
            CagdError: a wrong shape, weights not positive."""
        return BezierSurface._unchecked(self._nurbs.with_weights(weights))

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        return (0.0, 1.0), (0.0, 1.0)

    @property
    def is_rational(self) -> bool:
        return self.weights is not None

    def __repr__(self) -> str:
        kind = "rational Bezier" if self.is_rational else "Bezier"
        return f"<{kind} surface degree ({self.degree_u}, {self.degree_v})>"

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        return self._nurbs._evaluate(u, v, du, dv)

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        return self._nurbs._grid(us, vs, du, dv)

    def to_nurbs(self) -> BSplineSurface:
        return self._nurbs

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "BezierSurface":
        return BezierSurface(self.control_points @ A.T + b, self.weights)

    @property
    def homogeneous_control_points(self) -> np.ndarray:
        return self._nurbs.homogeneous_control_points

    @classmethod
    def _from_homogeneous(cls, hom: np.ndarray, rational: bool) -> "BezierSurface":
        return cls(hom[..., :-1] / hom[..., -1:], hom[..., -1]) if rational else cls(hom)

    def _project(self, hom: np.ndarray) -> np.ndarray:
        return hom[..., :-1] / hom[..., -1:] if self.is_rational else hom

    # --- the seed's algorithms -------------------------------------------------------
    def bernstein_evaluate(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Direct double sum of Bernstein products (seed 000, 5.2.7), broadcasting u, v."""
        u, v = np.broadcast_arrays(_checks.parameters(u, "u"), _checks.parameters(v, "v"))
        Bu, Bv = bernstein(self.degree_u, u), bernstein(self.degree_v, v)
        return self._project(np.einsum("...i,...j,ijd->...d", Bu, Bv, self.homogeneous_control_points))

    def de_casteljau(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Two-stage de Casteljau (seed 003, 2.2.1): each row of the net reduced at v,
        then the resulting column at u. Broadcasts u and v."""
        u, v = np.broadcast_arrays(_checks.parameters(u, "u"), _checks.parameters(v, "v"))
        hom = self.homogeneous_control_points
        uf, vf = u.ravel(), v.ravel()
        out = np.empty((uf.shape[0], hom.shape[2]))
        step = max(1, _CHUNK_VALUES // hom.size)           # bounded memory: one net per point of a chunk
        for s in range(0, uf.shape[0], step):
            vv = vf[s:s + step, None, None, None]
            net = np.broadcast_to(hom, vv.shape[:1] + hom.shape)
            while net.shape[-2] > 1:
                net = (1 - vv) * net[..., :-1, :] + vv * net[..., 1:, :]
            col = net[..., 0, :]
            uu = uf[s:s + step, None, None]
            while col.shape[-2] > 1:
                col = (1 - uu) * col[..., :-1, :] + uu * col[..., 1:, :]
            out[s:s + step] = col[:, 0]
        return self._project(out.reshape(u.shape + (hom.shape[2],)))

    def matrix_form(self) -> np.ndarray:
        """Coefficients C (per coordinate) with p(u, v) = U C V^T, U = [u^m ... 1],
        V = [v^n ... 1]: C = M_m P M_n^T (seed 000, 5.2.7 bilinear/biquadratic/bicubic)."""
        if self.is_rational:
            raise CagdError("weights: a rational Bezier surface has no polynomial matrix form")
        Mu, Mv = bezier_matrix(self.degree_u), bezier_matrix(self.degree_v)
        return np.einsum("ai,ijd,bj->abd", Mu, self.control_points, Mv)

    def blossom(self, us: Sequence[ArrayLike], vs: Sequence[ArrayLike]) -> np.ndarray:
        """Polar form f(u_1..u_m; v_1..v_n): symmetric and multi-affine in each group,
        f(u..u; v..v) = p(u, v), P_ij = f(0^(m-i) 1^i; 0^(n-j) 1^j) (seed 003, 2.2.4).
        ``us`` has m entries and ``vs`` n entries (each scalar or array; they broadcast)."""
        if len(us) != self.degree_u or len(vs) != self.degree_v:
            raise CagdError(f"us, vs: the blossom takes {self.degree_u} u-values and {self.degree_v} "
                            f"v-values, got {len(us)} and {len(vs)}")
        ua = [_checks.parameters(x, "us") for x in us]
        va = [_checks.parameters(x, "vs") for x in vs]
        shape = np.broadcast_shapes(*(x.shape for x in ua + va))
        hom = self.homogeneous_control_points
        net = np.broadcast_to(hom, shape + hom.shape)
        for t in va:
            tt = np.broadcast_to(t, shape)[..., None, None, None]
            net = (1 - tt) * net[..., :-1, :] + tt * net[..., 1:, :]
        col = net[..., 0, :]
        for t in ua:
            tt = np.broadcast_to(t, shape)[..., None, None]
            col = (1 - tt) * col[..., :-1, :] + tt * col[..., 1:, :]
        return self._project(col[..., 0, :])

    # --- operations ------------------------------------------------------------------------
    def subdivide(self, direction: str, t: float = 0.5) -> Tuple["BezierSurface", "BezierSurface"]:
        """Split at u = t or v = t into two Bezier patches, each on [0, 1]^2 (de Casteljau)."""
        t = _checks.scalar(t, "t")
        if not 0.0 < t < 1.0:
            raise CagdError(f"t: subdivision parameter must lie in (0, 1), got {t}")
        a, b = self._nurbs.split(direction, t)
        unit = ((0.0, 1.0), None) if direction == "u" else (None, (0.0, 1.0))
        a, b = a.reparametrized(*unit), b.reparametrized(*unit)
        return BezierSurface(a.control_points, a.weights), BezierSurface(b.control_points, b.weights)

    def elevate(self, times_u: int = 1, times_v: int = 0) -> "BezierSurface":
        """Degree elevation per direction with the Bernstein elevation matrices."""
        times_u = _checks.elevation(times_u, self.degree_u, "times_u")
        times_v = _checks.elevation(times_v, self.degree_v, "times_v")
        Eu = elevation_matrix(self.degree_u, times_u)
        Ev = elevation_matrix(self.degree_v, times_v)
        hom = np.einsum("ai,ijd,bj->abd", Eu, self.homogeneous_control_points, Ev)
        return self._from_homogeneous(hom, self.is_rational)

    def boundary_tangents(self) -> Dict[str, np.ndarray]:
        """Cross-boundary derivative nets at the four edges (seed 003, 2.2.2):
        S_u(0, v) has Bezier points m (P_1j - P_0j), S_u(1, v): m (P_mj - P_{m-1,j}),
        S_v(u, 0): n (P_i1 - P_i0), S_v(u, 1): n (P_in - P_{i,n-1}). Polynomial patches."""
        if self.is_rational:
            raise CagdError("weights: boundary tangent nets are given here for polynomial patches")
        P, m, n = self.control_points, self.degree_u, self.degree_v
        return {"u0": m * (P[1] - P[0]), "u1": m * (P[-1] - P[-2]),
                "v0": n * (P[:, 1] - P[:, 0]), "v1": n * (P[:, -1] - P[:, -2])}
