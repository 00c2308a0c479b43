"""Bezier curves, polynomial and rational (seed 000, 5.2; seed 003, 2.2.4 blossoms)."""
from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bernstein import bernstein, elevation_matrix
from ..errors import CagdError
from .base import Curve
from .bspline import BSplineCurve

_CHUNK_VALUES = 1 << 22     # net values per chunk of de Casteljau (32 MiB)


class BezierCurve(Curve):
    """p(t) = sum_i P_i BEZ_{i,n}(t), t in [0, 1] (seed 000, 5.2.1); with weights
    p(t) = sum w_i P_i BEZ_{i,n} / sum w_i BEZ_{i,n}.

    Raises:
        CagdError: fewer than 2 or more than MAX_DEGREE + 1 control points, NaN/inf,
            weights of the wrong count or not positive.
    """

    _modified_copy = BSplineCurve._modified_copy

    def __init__(self, control_points: ArrayLike, weights: Optional[ArrayLike] = None):
        P = _checks.points(control_points, "control_points", min_count=2)
        n = _checks.degree(P.shape[0] - 1, "control_points (their count - 1 is the degree)")
        self._fill(BSplineCurve(P, n, np.concatenate([np.zeros(n + 1), np.ones(n + 1)]), weights))

    def _fill(self, nurbs: BSplineCurve) -> None:
        """Everything from the single-span NURBS form (which shares its frozen arrays)."""
        self._nurbs = nurbs
        self.control_points, self.weights = nurbs.control_points, nurbs.weights
        self.degree, self.dim = nurbs.degree, nurbs.dim

    # --- modified copies ----------------------------------------------------------------
    def with_control_points(self, control_points: ArrayLike) -> "BezierCurve":
        """The same degree and weights on new control points of the same shape.

        Raises:
            CagdError: NaN/inf, a shape other than ``control_points.shape``."""
        return BezierCurve._unchecked(self._nurbs.with_control_points(control_points))

    def moved_pole(self, index: int, point: ArrayLike) -> "BezierCurve":
        """The curve with control point ``index`` (an int, negative from the end) moved to
        ``point`` (see :meth:`cagd.BSplineCurve.moved_pole`).

        Raises:
            CagdError: an index out of range, a bad point."""
        return BezierCurve._unchecked(self._nurbs.moved_pole(index, point))

    def with_weights(self, weights: Optional[ArrayLike]) -> "BezierCurve":
        """The same control points with new weights (None: polynomial).

        Raises:
            CagdError: a count other than degree + 1, weights not positive."""
        return BezierCurve._unchecked(self._nurbs.with_weights(weights))

    @property
    def domain(self) -> Tuple[float, float]:
        return 0.0, 1.0

    @property
    def is_rational(self) -> bool:
        return self.weights is not None

    def __repr__(self) -> str:
        kind = "rational Bezier" if self.is_rational else "Bezier"
        return f"<{kind} curve degree {self.degree}, {self.dim}-D>"

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        return self._nurbs._evaluate(t, order)

    def to_nurbs(self) -> BSplineCurve:
        return self._nurbs

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "BezierCurve":
        return BezierCurve(self.control_points @ A.T + b, self.weights)

    @property
    def homogeneous_control_points(self) -> np.ndarray:
        return self._nurbs.homogeneous_control_points

    @classmethod
    def _from_homogeneous(cls, hom: np.ndarray, rational: bool) -> "BezierCurve":
        if rational:
            return cls(hom[..., :-1] / hom[..., -1:], hom[..., -1])
        return cls(hom)

    # --- the seed's evaluation algorithms --------------------------------------------
    def bernstein_evaluate(self, t: ArrayLike) -> np.ndarray:
        """Direct Bernstein sum (seed 000, 5.2.1), shape np.shape(t) + (dim,)."""
        B = bernstein(self.degree, _checks.parameters(t))
        hom = B @ self.homogeneous_control_points
        return hom[..., :-1] / hom[..., -1:] if self.is_rational else hom

    def de_casteljau(self, t: ArrayLike) -> np.ndarray:
        """De Casteljau's recursion P_i^r = (1-t) P_i^{r-1} + t P_{i+1}^{r-1}
        (seed 000, 5.2.4), vectorized over t; shape np.shape(t) + (dim,)."""
        t = _checks.parameters(t)
        hom = self.homogeneous_control_points
        flat = t.ravel()
        out = np.empty((flat.shape[0], hom.shape[1]))
        step = max(1, _CHUNK_VALUES // hom.size)           # bounded memory: one level per chunk
        for s in range(0, flat.shape[0], step):
            tt = flat[s:s + step, None, None]
            level = np.broadcast_to(hom, tt.shape[:1] + hom.shape)
            for _ in range(self.degree):
                level = (1.0 - tt) * level[:, :-1] + tt * level[:, 1:]
            out[s:s + step] = level[:, 0]
        pts = out.reshape(t.shape + (hom.shape[1],))
        return pts[..., :-1] / pts[..., -1:] if self.is_rational else pts

    def _casteljau_pyramid(self, t: np.ndarray) -> List[np.ndarray]:
        """Levels r = 0..n of the homogeneous de Casteljau triangle, each of shape
        np.shape(t) + (n+1-r, dim')."""
        tt = np.asarray(t, dtype=np.float64)[..., None, None]
        level = np.broadcast_to(self.homogeneous_control_points, tt.shape[:-2] + self.homogeneous_control_points.shape)
        levels = [level]
        for _ in range(self.degree):
            level = (1.0 - tt) * level[..., :-1, :] + tt * level[..., 1:, :]
            levels.append(level)
        return levels

    # --- operations -------------------------------------------------------------------------
    def subdivide(self, t: float = 0.5) -> Tuple["BezierCurve", "BezierCurve"]:
        """Split at t into two Bezier curves, each on [0, 1]; their control points are
        the two edges of the de Casteljau triangle (seed 000, 5.2.4)."""
        t = _checks.scalar(t, "t")
        if not 0.0 < t < 1.0:
            raise CagdError(f"t: subdivision parameter must lie in (0, 1), got {t}")
        levels = self._casteljau_pyramid(np.array(t))
        left = np.array([lv[0] for lv in levels])
        right = np.array([lv[-1] for lv in levels[::-1]])
        return (self._from_homogeneous(left, self.is_rational),
                self._from_homogeneous(right, self.is_rational))

    def elevate(self, times: int = 1) -> "BezierCurve":
        """Degree elevation n -> n + times (Farin 6.1; homogeneous for rational curves);
        n + times at most :data:`cagd.MAX_DEGREE`."""
        times = _checks.elevation(times, self.degree)
        E = elevation_matrix(self.degree, times)
        return self._from_homogeneous(E @ self.homogeneous_control_points, self.is_rational)

    def reversed(self) -> "BezierCurve":
        """P*_i = P_{n-i}: the same curve traversed backwards (symmetry, seed 000, 5.2.2)."""
        w = None if self.weights is None else self.weights[::-1]
        return BezierCurve(self.control_points[::-1], w)

    def hodograph(self) -> "BezierCurve":
        """The derivative curve, degree n-1 with control points n (P_{i+1} - P_i)
        (seed 000, 5.2.1 property 4). Polynomial curves only."""
        if self.is_rational:
            raise CagdError("weights: the hodograph of a rational Bezier curve is not a Bezier curve of degree n-1")
        if self.degree < 2:
            raise CagdError("control_points: the hodograph of a line segment is a constant, not a curve")
        return BezierCurve(self.degree * np.diff(self.control_points, axis=0))

    def blossom(self, *args: ArrayLike) -> np.ndarray:
        """The polar form f(t_1, ..., t_n): symmetric, multi-affine, f(t, ..., t) = p(t),
        and the control points are its values P_i = f(0^(n-i), 1^i) (seed 003, 2.2.4).
        Each argument may be an array; they broadcast. De Casteljau with t_r at level r."""
        n = self.degree
        if len(args) != n:
            raise CagdError(f"args: the blossom of a degree-{n} curve takes {n} parameters, got {len(args)}")
        ts = [_checks.parameters(a, f"t{r + 1}") for r, a in enumerate(args)]
        shape = np.broadcast_shapes(*(t.shape for t in ts))
        hom = self.homogeneous_control_points
        level = np.broadcast_to(hom, shape + hom.shape)
        for tr in ts:
            tt = np.broadcast_to(tr, shape)[..., None, None]
            level = (1.0 - tt) * level[..., :-1, :] + tt * level[..., 1:, :]
        pt = level[..., 0, :]
        return pt[..., :-1] / pt[..., -1:] if self.is_rational else pt

    def matrix_form(self) -> np.ndarray:
        """Coefficients C with p(t) = [t^n ... t 1] C (seed 000, 5.2.3 matrix forms);
        polynomial curves only."""
        from ..basis.bernstein import bezier_matrix
        if self.is_rational:
            raise CagdError("weights: a rational Bezier curve has no polynomial matrix form")
        return bezier_matrix(self.degree) @ self.control_points
