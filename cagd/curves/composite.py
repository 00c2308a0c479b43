"""Composite curves: pieces joined end to end (seed 004, contents "组合曲线"; seed 000,
5.1.1: a spline is polynomial pieces joined with continuity conditions).

The global parameter is the concatenation of the pieces' domains: piece i with
domain [a_i, b_i] occupies [s_i, s_{i+1}], s_0 = a_0, s_{i+1} = s_i + (b_i - a_i),
and C(t) = C_i(a_i + t - s_i) there. At an interior joint the right piece is
used (right limits), at the end the last piece.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._deprecation import RELATIVE, deprecated, renamed
from ..errors import CagdError
from ..knots.vectors import is_clamped
from .base import Curve
from .bspline import BSplineCurve

if TYPE_CHECKING:
    from ..operations.continuity import ContinuityReport


GAP_TOL = 1e-9       # default relative gap between consecutive pieces


class CompositeCurve(Curve):
    """Curves joined end to end.

    Args:
        curves: a non-empty sequence of :class:`cagd.Curve` of one dimension,
            each starting where the previous one ends.
        rel_tol: relative gap tolerance: |C_{i+1}(a_{i+1}) - C_i(b_i)| <= rel_tol * size,
            size the bounding-box diagonal of all pieces (default GAP_TOL = 1e-9).
        tol: the deprecated name of ``rel_tol`` (one release; ``tol`` is a distance in
            cagd).

    Raises:
        CagdError: empty ``curves``, an element that is not a Curve, mixed
            dimensions, a gap above the tolerance (naming the index and the gap),
            rel_tol not positive.
    """

    def __init__(self, curves: Sequence[Curve], rel_tol: float = GAP_TOL, *, tol: Optional[float] = None):
        from ..operations.continuity import curve_size
        try:
            pieces = tuple(curves)
        except TypeError:
            raise CagdError(f"curves: must be a sequence of curves, got {type(curves).__name__}") from None
        if not pieces:
            raise CagdError("curves: need at least one curve")
        for i, c in enumerate(pieces):
            if not isinstance(c, Curve):
                raise CagdError(f"curves: curves[{i}] is a {type(c).__name__}, not a cagd Curve")
            if c.dim != pieces[0].dim:
                raise CagdError(f"curves: curves[{i}] is {c.dim}-D, curves[0] is {pieces[0].dim}-D")
        if tol is not None:
            rel_tol = renamed("CompositeCurve", "tol", "rel_tol", tol, rel_tol, GAP_TOL, RELATIVE)
        self.rel_tol = _checks.positive(rel_tol, "rel_tol")
        self.curves: Tuple[Curve, ...] = pieces
        self.dim = pieces[0].dim
        self.size = curve_size(*pieces)
        for i in range(len(pieces) - 1):
            end = pieces[i](pieces[i].domain[1])
            start = pieces[i + 1](pieces[i + 1].domain[0])
            gap = float(np.linalg.norm(start - end))
            if gap > self.rel_tol * self.size:
                raise CagdError(f"curves: gap of {gap:.6g} between the end of curves[{i}] and the start of "
                                f"curves[{i + 1}] exceeds rel_tol * size = {self.rel_tol * self.size:.3g}")
        starts = np.array([c.domain[0] for c in pieces])
        lengths = np.array([c.domain[1] - c.domain[0] for c in pieces])
        self._breaks = _checks.frozen(starts[0] + np.concatenate([[0.0], np.cumsum(lengths)]))
        self._joints = _checks.frozen(self._breaks[1:-1])

    # --- basic properties ------------------------------------------------------------
    @property
    def domain(self) -> Tuple[float, float]:
        return float(self._breaks[0]), float(self._breaks[-1])

    @property
    def breakpoints(self) -> np.ndarray:
        """s_0 < s_1 < ... < s_N: where each piece starts, and the end (read-only)."""
        return self._breaks

    @property
    def joints(self) -> np.ndarray:
        """The global parameters s_1..s_{N-1} where consecutive pieces meet (read-only)."""
        return self._joints

    @property
    def is_rational(self) -> bool:
        return any(getattr(c, "is_rational", False) for c in self.curves)

    def __len__(self) -> int:
        return len(self.curves)

    def __repr__(self) -> str:
        return f"<composite curve of {len(self.curves)} pieces, {self.dim}-D, domain {self.domain}>"

    # --- evaluation ------------------------------------------------------------------
    def piece_index(self, t: ArrayLike) -> np.ndarray:
        """Index of the piece evaluated at global parameter(s) t (right piece at a joint)."""
        flat, shape = self._flat_parameters(t)
        return self._index(flat).reshape(shape)

    def _index(self, t: np.ndarray) -> np.ndarray:
        return np.searchsorted(self._breaks[1:-1], t, side="right")

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        out = np.empty((order + 1, t.shape[0], self.dim))
        idx = self._index(t)
        for i, c in enumerate(self.curves):
            mask = idx == i
            if not mask.any():
                continue
            a, b = c.domain
            local = np.clip(a + (t[mask] - self._breaks[i]), a, b)
            out[:, mask] = c._evaluate(local, order)
        return out

    def _breaks_within(self, start: float, end: float) -> np.ndarray:
        inner = [self._breaks[1:-1]]
        for i, c in enumerate(self.curves):
            a, _ = c.domain
            inner.append(self._breaks[i] + (c._breaks_within(*c.domain) - a))
        u = np.unique(np.concatenate(inner))
        return u[(u > start) & (u < end)]

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "CompositeCurve":
        return CompositeCurve([c._affine(A, b) for c in self.curves], self.rel_tol)

    @property
    def tol(self) -> float:
        """Deprecated name of :attr:`rel_tol`."""
        deprecated("CompositeCurve.tol", "use rel_tol (the same relative gap tolerance)")
        return self.rel_tol

    # --- analysis --------------------------------------------------------------------
    def continuity_at_joints(self, rel_tol: Optional[float] = None, *,
                             tol: Optional[float] = None) -> List[ContinuityReport]:
        """A :class:`cagd.operations.continuity.ContinuityReport` for each joint
        (piece i end -> piece i+1 start); ``rel_tol`` defaults to the curve's (``tol`` is
        its deprecated name)."""
        from ..operations.continuity import continuity
        if tol is not None:
            rel_tol = renamed("CompositeCurve.continuity_at_joints", "tol", "rel_tol", tol, rel_tol, None, RELATIVE)
        rel_tol = self.rel_tol if rel_tol is None else rel_tol
        return [continuity(self.curves[i], self.curves[i + 1], rel_tol=rel_tol) for i in range(len(self.curves) - 1)]

    # --- NURBS form ----------------------------------------------------------------
    def to_nurbs(self) -> BSplineCurve:
        """A single clamped B-spline/NURBS: every piece's NURBS form, clamped, elevated
        to the highest degree p (Piegl & Tiller 5.5), made rational with weights 1 if
        any piece is rational, shifted to [s_i, s_{i+1}] and concatenated with knot
        multiplicity p at the joints (Piegl & Tiller 5.4 read backwards: a knot of
        multiplicity p splits a curve into pieces sharing one control point).

        The homogeneous points (w P, w) of each piece are scaled by one constant so
        that its first weight equals the previous piece's last weight (scaling all
        weights of a piece leaves that piece unchanged); the shared joint point is the
        mean of the two pieces' end points, so the result reproduces the composite
        to rounding when the pieces meet, and otherwise differs from it near a
        joint by at most half the gap there."""
        nurbs = [c.to_nurbs() for c in self.curves]
        nurbs = [n.clamped() if (n.periodic or not is_clamped(n.full_knots, n.degree)) else n for n in nurbs]
        p = max(n.degree for n in nurbs)
        nurbs = [n.elevate(p - n.degree) for n in nurbs]
        rational = any(n.is_rational for n in nurbs)
        knots = [np.full(p + 1, self._breaks[0])]
        homs: List[np.ndarray] = []
        prev_w = None
        for i, n in enumerate(nurbs):
            hom = n.homogeneous_control_points
            if rational and not n.is_rational:
                hom = np.hstack([hom, np.ones((hom.shape[0], 1))])
            if rational and prev_w is not None:
                hom = hom * (prev_w / hom[0, -1])
            if homs:
                homs[-1][-1] = 0.5 * (homs[-1][-1] + hom[0])
                hom = hom[1:]
            homs.append(hom.copy())
            prev_w = hom[-1, -1] if rational else None
            a = n.domain[0]
            u = n.full_knots
            inner = u[p + 1:len(u) - p - 1]
            knots.append(self._breaks[i] + (inner - a))
            knots.append(np.full(p if i < len(nurbs) - 1 else p + 1, self._breaks[i + 1]))
        H = np.vstack(homs)
        U = np.concatenate(knots)
        if rational:
            w = H[:, -1]
            return BSplineCurve(H[:, :-1] / w[:, None], p, U, w)
        return BSplineCurve(H, p, U)


