"""Bezier decomposition and subdivision machinery shared by the intersection and
distance queries (private).

An engine curve or surface is cut at its knots into Bezier pieces once, by
:func:`cagd.queries.bounds.bezier_pieces` (Piegl & Tiller A5.6/A5.7, knot insertion
to multiplicity p); here each piece is kept as homogeneous control points (w P, w)
together with its parameter box. The convex-hull property
of Bezier pieces with positive weights (seed 000, 5.2.3; Farin ch. 4) makes the
axis-aligned box of the projected control points a rigorous bound of the piece;
halving by de Casteljau (Lane & Riesenfeld 1980) is done for all pieces at once.
Candidates are refined on the whole object (:func:`cagd.queries._newton.refine`) by a
bounded, projected (clamped) Newton iteration with a saddle-free Hessian and backtracking (Nocedal & Wright,
Numerical Optimization, 3.4 and 16.7), vectorized over all candidates.
"""
from __future__ import annotations

from typing import NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from .._periodic import clamped
from .._ranks import ranks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from .bounds import Frame, bezier_pieces, closed_directions
from ._numerics import TINY, unit


class Pieces(NamedTuple):
    """Bezier pieces: ``ctrl`` homogeneous control points, shape (M, n+1, D+1) for
    curve pieces or (M, n+1, m+1, D+1) for surface patches; ``lo``/``hi`` (M, k)
    the corners of each piece's parameter box (k = 1 or 2)."""
    ctrl: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    @property
    def k(self) -> int:
        return self.ctrl.ndim - 2

    def take(self, index: Union[np.ndarray, slice]) -> "Pieces":
        return Pieces(self.ctrl[index], self.lo[index], self.hi[index])

    @staticmethod
    def concat(parts: Sequence["Pieces"]) -> "Pieces":
        return Pieces(*(np.concatenate([getattr(q, f) for q in parts]) for f in ("ctrl", "lo", "hi")))


class Geometry:
    """An engine curve or surface seen through its exact NURBS form: parameter count
    ``k``, domain box, periodic flags, its Bezier decomposition (``bezier``, the
    :class:`cagd.queries.bounds.BezierPieces` of the closest-point queries; ``pieces``,
    the same as homogeneous arrays for the pair subdivision) and vectorized
    derivatives evaluated on the pieces."""

    def __init__(self, obj: Union[Curve, Surface], name: str):
        if isinstance(obj, Curve):
            self.k = 1
        elif isinstance(obj, Surface):
            self.k = 2
        else:
            raise CagdError(f"{name}: expected a cagd curve or surface, got {type(obj).__name__}")
        self.obj, self.name = obj, name
        self.triangle = not getattr(obj, "rectangular", True)
        self.nurbs = obj.to_nurbs()
        self.dim = self.nurbs.dim
        nurbs = self.nurbs
        if isinstance(nurbs, BSplineCurve):
            d = nurbs.domain
            self.lo, self.hi = np.array([d[0]]), np.array([d[1]])
            self.periodic = np.array([bool(nurbs.periodic)])
        else:
            (u0, u1), (v0, v1) = nurbs.domain
            self.lo, self.hi = np.array([u0, v0]), np.array([u1, v1])
            self.periodic = np.array([bool(nurbs.periodic_u), bool(nurbs.periodic_v)])
        self.bezier = bezier_pieces(obj)               # one decomposition for bounds and pairs
        self.pieces = Pieces(_hom(self.bezier.control_points, self.bezier.weights),
                             self.bezier.lower.copy(), self.bezier.upper.copy())
        pts = project(self.pieces.ctrl).reshape(-1, self.dim)
        self.size = max(float(np.ptp(pts, axis=0).max()), TINY)

    def reframe(self, frame: Frame) -> None:
        """Work in the normalised ``frame`` (its point map; the parameter map of this
        object's own breaks): pieces, domain and size in frame units, :meth:`user_params`
        mapping back. Points from :meth:`points` are then in frame units
        (``self.frame.outward`` maps them back)."""
        self.frame = frame.with_breaks(self.bezier.breaks)
        if self.frame.identity:
            return
        self.bezier = self.frame.pieces(self.bezier)
        self.pieces = Pieces(_hom(self.bezier.control_points, self.bezier.weights),
                             self.bezier.lower.copy(), self.bezier.upper.copy())
        dom = self.bezier.domain
        self.lo, self.hi = dom[:, 0].copy(), dom[:, 1].copy()
        pts = project(self.pieces.ctrl).reshape(-1, self.dim)
        self.size = max(float(np.ptp(pts, axis=0).max()), TINY)

    def clamp(self, x: np.ndarray) -> np.ndarray:
        """Parameters (N, k) wrapped (periodic directions) or clamped into the domain."""
        return clamped(x, self.lo, self.hi, self.periodic)

    def derivatives(self, x: np.ndarray, order: int, rows: Optional[np.ndarray] = None
                    ) -> Tuple[np.ndarray, Optional[np.ndarray], Optional[np.ndarray]]:
        """Point (N, D), first derivatives (N, k, D) if order >= 1 and second
        derivatives (N, k, k, D) if order == 2 (else None) at parameters x (N, k) inside
        the domain."""
        x = self.clamp(x)
        d = self.bezier.derivatives(self.bezier.locate(x), x, order)
        if self.k == 1:
            first = d[1][:, None, :] if order >= 1 else None
            second = d[2][:, None, None, :] if order >= 2 else None
            return d[0], first, second
        first = np.stack([d[1, 0], d[0, 1]], axis=1) if order >= 1 else None
        second = None
        if order >= 2:
            second = np.stack([np.stack([d[2, 0], d[1, 1]], 1), np.stack([d[1, 1], d[0, 2]], 1)], 1)
        return d[0, 0], first, second

    def points(self, x: np.ndarray) -> np.ndarray:
        return self.derivatives(x, 0)[0]

    @property
    def closed(self) -> np.ndarray:
        """Directions (k,) where the object is periodic or closes on itself (a seam: a
        clamped closed curve's ends, a revolved surface's seam), so that parameters on
        both sides of the seam name the same points (gap <= 1e-11 of the size)."""
        if getattr(self, "_closed", None) is None:
            self._closed = closed_directions(self.points, self.lo, self.hi, self.periodic, self.size)
        return self._closed

    def user_params(self, x: np.ndarray) -> np.ndarray:
        """Parameters of the user's object: curves (N,), surfaces (N, 2); a Bezier
        triangle's collapsed-edge NURBS form S(u, w) = T(u, w (1 - u)) is mapped back."""
        frame = getattr(self, "frame", None)
        if frame is not None:
            x = frame.params(x)
        if self.k == 1:
            return x[:, 0].copy()
        if self.triangle:
            return np.stack([x[:, 0], x[:, 1] * (1.0 - x[:, 0])], axis=1)
        return x.copy()


def _hom(P: np.ndarray, w: Optional[np.ndarray]) -> np.ndarray:
    w = np.ones(P.shape[:-1]) if w is None else np.asarray(w, dtype=float)
    return np.concatenate([P * w[..., None], w[..., None]], axis=-1)


def project(ctrl: np.ndarray) -> np.ndarray:
    """Cartesian control points of homogeneous ones (same leading shape, last axis D)."""
    return ctrl[..., :-1] / ctrl[..., -1:]


def boxes(ctrl: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding boxes (M, D) low and high corners of each piece's control
    hull: by the convex-hull property they contain the piece."""
    M, D = ctrl.shape[0], ctrl.shape[-1] - 1
    h = ctrl.reshape(M, -1, D + 1).transpose(1, 0, 2)
    pts = np.empty((h.shape[0], M, D))             # point-major: the reductions run over whole rows
    np.divide(h[..., :-1], h[..., -1:], out=pts)
    return np.minimum.reduce(pts, axis=0), np.maximum.reduce(pts, axis=0)


def box_gap(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray) -> np.ndarray:
    """Euclidean distance between pairs of axis-aligned boxes (0 when they overlap)."""
    gap = np.maximum(0.0, np.maximum(lo_a - hi_b, lo_b - hi_a))
    return np.sqrt(np.einsum("ij,ij->i", gap, gap))


def box_pairs(a: Pieces, b: Pieces, tol: float, chunk: int = 1 << 22) -> Tuple[np.ndarray, np.ndarray]:
    """Index pairs (i, j) of pieces a[i], b[j] whose control-hull boxes come within tol:
    the broad phase, per piece and not per pair (all pairs of two 27 x 27 patch nets are
    531,441, of which a few hundred meet). A sweep along the first coordinate: b sorted
    by its boxes' lower ends, each a[i] is tested against the b's whose lower end lies in
    [lo - W - tol, hi + tol] (W the widest b box), at most ``chunk`` tests at a time."""
    lo_a, hi_a = boxes(a.ctrl)
    lo_b, hi_b = boxes(b.ctrl)
    if not len(lo_a) or not len(lo_b):
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    order = np.argsort(lo_b[:, 0], kind="stable")
    key = lo_b[order, 0]
    width = float((hi_b[:, 0] - lo_b[:, 0]).max())
    first = np.searchsorted(key, lo_a[:, 0] - width - tol, side="left")
    count = np.searchsorted(key, hi_a[:, 0] + tol, side="right") - first
    count = np.maximum(count, 0)
    ends = np.cumsum(count)
    out_i, out_j = [], []
    r0, n = 0, len(lo_a)
    while r0 < n:
        r1 = max(int(np.searchsorted(ends, ends[r0] - count[r0] + chunk, side="right")), r0 + 1)
        c = count[r0:r1]
        i = np.repeat(np.arange(r0, r1), c)
        k = ranks(c)
        j = order[np.repeat(first[r0:r1], c) + k]
        gap = np.maximum(0.0, np.maximum(lo_a[i] - hi_b[j], lo_b[j] - hi_a[i]))
        hit = np.einsum("nd,nd->n", gap, gap) <= tol * tol
        out_i.append(i[hit])
        out_j.append(j[hit])
        r0 = r1
    i, j = np.concatenate(out_i), np.concatenate(out_j)
    o = np.lexsort((j, i))
    return i[o], j[o]


def slab_gap(ctrl_a: np.ndarray, ctrl_b: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Lower bound of the distance between pieces from their projections on a unit
    ``direction`` (M, D) per pair: min_j d.Q_j - max_i d.P_i (or the reverse), >= 0."""
    n = unit(direction)
    pa = project(ctrl_a).reshape(ctrl_a.shape[0], -1, n.shape[1]) @ n[:, :, None]
    pb = project(ctrl_b).reshape(ctrl_b.shape[0], -1, n.shape[1]) @ n[:, :, None]
    pa, pb = pa[..., 0], pb[..., 0]
    return np.maximum(0.0, np.maximum(pb.min(1) - pa.max(1), pa.min(1) - pb.max(1)))


def corner_normal(ctrl: np.ndarray) -> np.ndarray:
    """Unit normals (M, 3) of patches (M, n+1, m+1, 4) from their corner control points
    (the cross product of the diagonals; 0 where they are parallel)."""
    P = project(ctrl)
    return unit(np.cross(P[:, -1, -1] - P[:, 0, 0], P[:, 0, -1] - P[:, -1, 0]))


def hull_gap(P: np.ndarray, ctrl: np.ndarray) -> np.ndarray:
    """Lower bound (N,) of the distance from points P (N, D) to pieces with control
    points ctrl (N, n, D + 1) (curves) or (N, n, m, D + 1) (patches), one per point,
    by the convex hull property: the gap to the control points' box and, for a 3-D
    patch, to their slab along its corner normal (0 inside both)."""
    lo, hi = boxes(ctrl)
    out = box_gap(P, P, lo, hi)
    if ctrl.ndim == 4 and P.shape[1] == 3:
        point = np.concatenate([P, np.ones((len(P), 1))], axis=1)[:, None]       # one homogeneous point
        out = np.maximum(out, slab_gap(point, ctrl, corner_normal(ctrl)))
    return out


def flatness(ctrl: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(deviation, extent) per piece: the largest distance of a control point from the
    (bi)linear interpolant of the corner control points at the Greville abscissae
    i/n (j/m), and the largest corner-to-corner distance. Small deviation/extent
    means the piece is close to a linearly parametrized segment (parallelogram).
    (Squared distances, one square root per piece: half the time of norms per point.)"""
    P = project(ctrl)
    if ctrl.ndim == 3:
        n = P.shape[1] - 1
        s = (np.arange(n + 1) / n)[None, :, None]
        first = P[:, :1]
        diff = P - first - s * (P[:, -1:] - first)
        chord = P[:, -1] - P[:, 0]
        extent2 = np.einsum("nd,nd->n", chord, chord)
    else:
        n, m = P.shape[1] - 1, P.shape[2] - 1
        s = (np.arange(n + 1) / n)[None, :, None, None]
        t = (np.arange(m + 1) / m)[None, None, :, None]
        c00, c10, c01, c11 = P[:, :1, :1], P[:, -1:, :1], P[:, :1, -1:], P[:, -1:, -1:]
        left = c00 + t * (c01 - c00)                    # the edges u = 0 and u = 1 at v = t_j
        diff = P - left - s * (c10 + t * (c11 - c10) - left)
        d1, d2 = P[:, -1, -1] - P[:, 0, 0], P[:, -1, 0] - P[:, 0, -1]
        extent2 = np.maximum(np.einsum("nd,nd->n", d1, d1), np.einsum("nd,nd->n", d2, d2))
    dev2 = np.einsum("n...d,n...d->n...", diff, diff).reshape(P.shape[0], -1).max(axis=1)
    return np.sqrt(dev2), np.sqrt(extent2)


def halve(ctrl: np.ndarray, axis: int) -> Tuple[np.ndarray, np.ndarray]:
    """de Casteljau subdivision at the parameter midpoint along control axis ``axis``
    (1 = t or u, 2 = v) of every piece at once: (left, right) halves."""
    c = np.moveaxis(ctrl, axis, 0)
    n = c.shape[0] - 1
    left, right = [c[0]], [c[n]]
    cur = c
    for _ in range(n):
        cur = 0.5 * (cur[:-1] + cur[1:])
        left.append(cur[0])
        right.append(cur[-1])
    L = np.moveaxis(np.stack(left), 0, axis)
    R = np.moveaxis(np.stack(right[::-1]), 0, axis)
    return L, R


def split_modes(ctrl: np.ndarray) -> np.ndarray:
    """How to halve each surface patch: 0 both directions, 1 u only, 2 v only. A patch
    whose control polygon is over twice as long one way as the other (a sliver at a
    pole or at a triangle's collapsed corner, a long thin strip) is halved across its
    length only, so that slivers along a collapsed edge do not multiply."""
    P = project(ctrl)
    lu = np.linalg.norm(np.diff(P, axis=1), axis=-1).sum(axis=1).max(axis=1)
    lv = np.linalg.norm(np.diff(P, axis=2), axis=-1).sum(axis=2).max(axis=1)
    return np.where(lu > 2 * lv, 1, np.where(lv > 2 * lu, 2, 0))


def split(p: Pieces, modes: Optional[np.ndarray] = None) -> Tuple[Pieces, np.ndarray]:
    """Halve every piece: curves into 2 children, surfaces into 4 (both directions) or,
    where ``modes`` (default :func:`split_modes`) says so, 2 (one direction). Returns
    the children and the parent index of each child."""
    M = p.ctrl.shape[0]
    parent = np.arange(M)
    if M == 0:
        return p, parent
    if p.k == 1:
        L, R = halve(p.ctrl, 1)
        mid = 0.5 * (p.lo + p.hi)
        return (Pieces(np.concatenate([L, R]), np.concatenate([p.lo, mid]), np.concatenate([mid, p.hi])),
                np.concatenate([parent, parent]))
    modes = split_modes(p.ctrl) if modes is None else modes
    parts = []
    for mode, axes in ((0, (0, 1)), (1, (0,)), (2, (1,))):
        sel = np.flatnonzero(modes == mode)
        if sel.size == 0:
            continue
        kids = [(p.ctrl[sel], p.lo[sel], p.hi[sel])]
        for ax in axes:
            nxt = []
            for c, lo, hi in kids:
                L, R = halve(c, ax + 1)
                mid = 0.5 * (lo[:, ax] + hi[:, ax])
                hi_l, lo_r = hi.copy(), lo.copy()
                hi_l[:, ax], lo_r[:, ax] = mid, mid
                nxt += [(L, lo, hi_l), (R, lo_r, hi)]
            kids = nxt
        parts += [(Pieces(c, lo, hi), sel) for c, lo, hi in kids]
    return Pieces.concat([q[0] for q in parts]), np.concatenate([q[1] for q in parts])


def split_pairs(a: Pieces, b: Pieces, split_a: np.ndarray, split_b: np.ndarray, modes_a: Optional[np.ndarray] = None,
                modes_b: Optional[np.ndarray] = None) -> Tuple[Pieces, Pieces, np.ndarray]:
    """Children of the pairs (a[i], b[i]): a piece flagged in split_a (split_b) is
    halved (:func:`split`, surface patches as ``modes_a`` (``modes_b``) say per pair,
    default :func:`split_modes`), the other kept, and every child of a is paired with every
    child of b. Returns the new pair arrays and the parent pair index of each new pair."""
    def children(p, flag, modes):
        sel = np.flatnonzero(flag)
        keep = np.flatnonzero(~flag)
        kids, par = split(p.take(sel), None if modes is None else np.asarray(modes)[sel])
        owner = np.concatenate([keep, sel[par]])
        order = np.argsort(owner, kind="stable")
        count = np.bincount(owner, minlength=len(flag))
        return Pieces.concat([p.take(keep), kids]).take(order), np.cumsum(count) - count, count
    ca, start_a, na = children(a, np.asarray(split_a, bool), modes_a)
    cb, start_b, nb = children(b, np.asarray(split_b, bool), modes_b)
    total = na * nb
    parent = np.repeat(np.arange(len(total)), total)
    k = ranks(total)
    ia = start_a[parent] + k // nb[parent]
    ib = start_b[parent] + k % nb[parent]
    return ca.take(ia), cb.take(ib), parent


def monotone(ctrl: np.ndarray) -> np.ndarray:
    """Curve pieces (M, n+1, D+1) that cannot cross themselves: every control polygon
    edge has a positive component along the chord, so by variation diminishing
    (positive weights) the piece is strictly monotone along the chord direction."""
    P = project(ctrl)
    chord = P[:, -1] - P[:, 0]
    steps = np.einsum("mid,md->mi", np.diff(P, axis=1), chord)
    return np.all(steps > 0, axis=1)


# --- local refinement -------------------------------------------------------------------------




