"""Bezier decomposition of any engine curve or surface, with certified bounds per piece.

Every curve and surface converts exactly to NURBS (``to_nurbs()``); knot insertion
to full multiplicity cuts it into rational Bezier pieces (Piegl & Tiller A5.6, A5.7)
laid out on a tensor grid of parameter boxes. On a piece with non-negative weights
the object lies in the convex hull of its control points (Farin, Curves and
Surfaces for CAGD, 3.3 and 16.2), which gives bounding boxes and spheres; the
hodograph control points bound the derivatives (see :meth:`BezierPieces.derivative_bounds`).
These are the ingredients of the global queries (seed 004, ch. 1 §4): closest points,
minimum distance and intersections discard every piece whose bound cannot matter.

Conventions: a piece is a box ``lower[i] <= x <= upper[i]`` in the object's own
parameters (k = 1 for curves, 2 for surfaces); pieces are numbered row-major on the
grid ``shape`` (u index slowest); control points are Euclidean, weights ``None`` for
polynomial objects.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from math import comb, factorial
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union, cast

import numpy as np
from numpy.typing import ArrayLike

from .._ranks import ranks
from ..curves.base import Curve, rational_derivatives
from .._checks import frozen
from ..errors import CagdError
from ..surfaces.base import Surface, rational_partials
from ._numerics import SLACK_RTOL, TINY, ULP_RTOL, column_extremes, eigenvalue_2x2, lead_sum, row_max, row_min, \
    squared_norms

CLOSED_RTOL = 1e-11           # a direction whose opposite sides meet within this share of the size is closed
SHRINK_RTOL = 1e-10           # the smallest singular value of J, lowered by this share for rounding
BOUND_MARGIN_RTOL = 1e-13     # the convexity intervals' rounding margin, share of g
SCALE_FLOOR_RTOL = 1e-6       # box bounds: a direction's scale (its first-derivative bound), at least this share of
                              # the largest
SPLIT_RATIOS = (1 / 16, 1 / 4, 1.0, 4.0, 16.0)   # box bounds: Gershgorin splits of the mixed term tried

__all__ = ["BezierPieces", "bezier_pieces", "bernstein_derivatives", "restriction_matrix", "Frame", "net_box",
           "robust_distance"]


_POWER: Dict[Tuple[int, int], np.ndarray] = {}


def _bernstein_power(degree: int, order: int) -> np.ndarray:
    """Power-basis coefficients c[r, k, i] with B^(r)_{i,p}(x) = sum_k c[r, k, i] x^k:
    B_{i,p} = C(p, i) sum_k C(p - i, k - i) (-1)^(k - i) x^k, differentiated r times."""
    key = (degree, order)
    if key not in _POWER:
        p = degree
        c0 = np.zeros((p + 1, p + 1))                       # c0[k, i]
        for i in range(p + 1):
            for k in range(i, p + 1):
                c0[k, i] = comb(p, i) * comb(p - i, k - i) * (-1) ** (k - i)
        out = np.zeros((order + 1, p + 1, p + 1))
        for r in range(min(order, p) + 1):
            for k in range(p + 1 - r):
                out[r, k] = c0[k + r] * (factorial(k + r) / factorial(k))
        _POWER[key] = out
    return _POWER[key]


def bernstein_derivatives(degree: int, x: np.ndarray, order: int) -> np.ndarray:
    """Bernstein polynomials B_{i,p}(x) on [0, 1] and their derivatives up to ``order``:
    shape (order+1, len(x), p+1); B^(r)_{i,p} = p!/(p-r)! sum_j (-1)^(r-j) C(r, j) B_{i-j,p-r}
    (Farin 5.3), the lower-degree bases by the recursion B_{i,n} = (1-x) B_{i,n-1} + x B_{i-1,n-1}.
    Up to degree 3 (coefficients <= 12 in size, no cancellation beyond 1e-15 on [0, 1])
    through the power basis with cached coefficients: one matrix product."""
    x = np.asarray(x, dtype=np.float64)
    if degree <= 3:
        X = x[:, None] ** np.arange(degree + 1)[None]        # (n, p+1)
        return np.matmul(X[None], _bernstein_power(degree, order))
    levels = [np.ones((x.shape[0], 1))]
    for n in range(1, degree + 1):
        prev, cur = levels[-1], np.zeros((x.shape[0], n + 1))
        cur[:, :n] = prev * (1.0 - x)[:, None]
        cur[:, 1:] += prev * x[:, None]
        levels.append(cur)
    out = np.zeros((order + 1, x.shape[0], degree + 1))
    for r in range(min(order, degree) + 1):
        b, f = levels[degree - r], factorial(degree) / factorial(degree - r)
        for j in range(r + 1):
            out[r, :, j:j + degree - r + 1] += (f * (-1) ** (r - j) * comb(r, j)) * b
    return out


def restriction_matrix(degree: int, start: float, end: float) -> np.ndarray:
    """(p+1, p+1) matrix R with Q = R @ P the Bezier control points of the restriction
    of a degree-p Bezier (on [0, 1]) to [start, end]: Q_j = b[start^(p-j), end^j], the
    blossom by de Casteljau with one argument per level (Farin 4.2; seed 000, 5.2)."""
    R = np.empty((degree + 1, degree + 1))
    for j in range(degree + 1):
        pts = np.eye(degree + 1)
        for u in [end] * j + [start] * (degree - j):
            pts = (1.0 - u) * pts[:-1] + u * pts[1:]
        R[j] = pts[0]
    return R


@dataclass(frozen=True)
class BezierPieces:
    """Rational Bezier pieces of a curve (k = 1) or surface (k = 2) on a tensor grid.

    Attributes:
        control_points: (m, p+1, dim) or (m, p+1, q+1, dim) Euclidean control points.
        weights: (m, p+1) or (m, p+1, q+1) positive weights, or None (polynomial).
        breaks: k arrays of breakpoints; piece (i, j) covers [breaks[0][i], breaks[0][i+1]] x ...
        periodic: k flags (the object is closed in that direction).
    """
    control_points: np.ndarray
    weights: Optional[np.ndarray]
    breaks: Tuple[np.ndarray, ...]
    periodic: Tuple[bool, ...]

    # --- shape ------------------------------------------------------------------------
    @property
    def k(self) -> int:
        """Number of parameters: 1 for a curve, 2 for a surface."""
        return len(self.breaks)

    @property
    def shape(self) -> Tuple[int, ...]:
        return tuple(len(b) - 1 for b in self.breaks)

    @property
    def degrees(self) -> Tuple[int, ...]:
        return tuple(s - 1 for s in self.control_points.shape[1:1 + self.k])

    @property
    def dim(self) -> int:
        return self.control_points.shape[-1]

    @property
    def domain(self) -> np.ndarray:
        """(k, 2) parameter domain."""
        return np.array([[b[0], b[-1]] for b in self.breaks])

    def __len__(self) -> int:
        return self.control_points.shape[0]

    @property
    def lower(self) -> np.ndarray:
        """(m, k) lower corners of the parameter boxes."""
        return self._corners(0)

    @property
    def upper(self) -> np.ndarray:
        """(m, k) upper corners of the parameter boxes."""
        return self._corners(1)

    def _corners(self, side: int) -> np.ndarray:
        key = "_corners%d" % side
        if key not in self.__dict__:
            grids = np.meshgrid(*[b[side:len(b) - 1 + side] for b in self.breaks], indexing="ij")
            object.__setattr__(self, key, np.stack([g.ravel() for g in grids], axis=1))
        return self.__dict__[key]

    @property
    def homogeneous(self) -> np.ndarray:
        """(w P, w) control points, or P when polynomial."""
        if self.weights is None:
            return self.control_points
        return np.concatenate([self.control_points * self.weights[..., None], self.weights[..., None]], axis=-1)

    def locate(self, params: np.ndarray) -> np.ndarray:
        """Flat index of the piece holding each parameter row (N, k) (clamped to the domain)."""
        params = np.asarray(params, dtype=np.float64).reshape(-1, self.k)
        index = np.zeros(params.shape[0], dtype=np.intp)
        for a, b in enumerate(self.breaks):          # (minimum/maximum: np.clip costs 6 us a call)
            i = np.minimum(np.maximum(np.searchsorted(b, params[:, a], side="right") - 1, 0), len(b) - 2)
            index = index * (len(b) - 1) + i
        return index

    # --- refinement --------------------------------------------------------------------
    def subdivided(self, counts: Union[int, Sequence[ArrayLike]]) -> "BezierPieces":
        """Every piece cut into equal parts per direction, by restriction matrices on the
        homogeneous control points. ``counts``: an int (all directions), or one entry per
        direction, each an int or an array giving the parts of every piece index along
        that direction (pieces stay on a tensor grid)."""
        k, shape = self.k, self.shape
        if np.isscalar(counts):
            entries: List[ArrayLike] = [counts] * k
        else:                           # numpy's isscalar narrows only its True branch
            entries = list(cast("Sequence[ArrayLike]", counts))
        if len(entries) != k:
            raise CagdError(f"counts: expected {k} entries (one per direction), got {len(entries)}")
        per = []
        for a, entry in enumerate(entries):
            c = np.asarray(entry)
            if c.ndim == 0:
                c = np.full(shape[a], c)
            if c.shape != (shape[a],) or not np.all(c == np.round(c)) or c.min() < 1:
                raise CagdError(f"counts: expected positive integers (one per direction, or {shape[a]} "
                                f"for direction {a}), got {counts}")
            per.append(c.astype(np.intp))
        hom = self.homogeneous.reshape(shape + self.control_points.shape[1:-1] + (-1,))
        breaks = []
        for a, (c, p, b) in enumerate(zip(per, self.degrees, self.breaks)):
            src = np.repeat(np.arange(shape[a]), c)
            j = ranks(c)
            cache: Dict[Tuple[int, int], np.ndarray] = {}
            for jj, cc in set(zip(j.tolist(), c[src].tolist())):
                cache[(jj, cc)] = restriction_matrix(p, jj / cc, (jj + 1) / cc)
            R = np.stack([cache[(jj, cc)] for jj, cc in zip(j.tolist(), c[src].tolist())])
            h = np.take(hom, src, axis=a)
            if k == 1:
                hom = np.einsum("nji,nid->njd", R, h)
            elif a == 0:
                hom = np.einsum("uji,uvild->uvjld", R, h)
            else:
                hom = np.einsum("vjl,uvild->uvijd", R, h)
            breaks.append(np.concatenate([np.linspace(b[i], b[i + 1], int(c[i]) + 1)[:-1] for i in range(len(b) - 1)]
                                         + [b[-1:]]))
        hom = hom.reshape((-1,) + hom.shape[k:])
        if self.weights is None:
            return BezierPieces(hom, None, tuple(breaks), self.periodic)
        w = hom[..., -1]
        return BezierPieces(hom[..., :-1] / w[..., None], w, tuple(breaks), self.periodic)

    # --- bounds ------------------------------------------------------------------------
    def hull_boxes(self) -> Tuple[np.ndarray, np.ndarray]:
        """Axis-aligned boxes (lo, hi), each (m, dim), containing each piece (convex hull)."""
        if "_boxes" not in self.__dict__:
            P = self.control_points.reshape(len(self), -1, self.dim)
            lo, hi = P[:, 0].copy(), P[:, 0].copy()
            for i in range(1, P.shape[1]):          # (a reduction over the middle axis is slow)
                np.minimum(lo, P[:, i], out=lo)
                np.maximum(hi, P[:, i], out=hi)
            object.__setattr__(self, "_boxes", (frozen(lo), frozen(hi)))
        return self.__dict__["_boxes"]

    def hull_spheres(self) -> Tuple[np.ndarray, np.ndarray]:
        """Spheres (centers (m, dim), radii (m,)) containing each piece: the centre of its
        bounding box and the largest distance from it to a control point."""
        if "_spheres" not in self.__dict__:
            lo, hi = self.hull_boxes()
            c = 0.5 * (lo + hi)
            P = self.control_points.reshape(len(self), -1, self.dim)
            r = np.sqrt(row_max(squared_norms(P - c[:, None])))
            object.__setattr__(self, "_spheres", (frozen(c), frozen(r)))
        return self.__dict__["_spheres"]

    def partial_bounds(self, order: int) -> Dict[Tuple[int, ...], np.ndarray]:
        """Certified bounds B[alpha] (m,) of |d^alpha X| on each piece for every multi-index
        alpha with |alpha| <= order (alpha = (i,) for curves, (i, j) for surfaces), in the
        object's own parameters.

        With Q the hull-sphere centre, A = sum w_i (P_i - Q) B_i, so X - Q = A / w and
        |X - Q| <= R (convex hull). Leibniz on A = w (X - Q) gives
        d^a X = (d^a A - sum_{b < a} C(a, b) d^(a-b) w d^b X) / w, hence
        B[a] = (B_A[a] + sum_{b < a} C(a, b) B_w[a-b] B[b]) / min w, B[0] = R, where a
        derivative of a Bezier piece is bounded by its hodograph control points,
        |d^a A| <= prod p!/(p-a)! / h^a max |Delta^a A_ij| (Farin 5.3; Piegl & Tiller 3.3).
        For polynomial pieces (w = 1) this is the hodograph bound alone. The bounds of the
        highest order asked so far are kept (the pieces are immutable)."""
        known = self.__dict__.get("_partials")
        if known is not None and known[0] >= order:
            return {al: b for al, b in known[1].items() if sum(al) <= order}
        m, k, deg = len(self), self.k, self.degrees
        Q, R = self.hull_spheres()
        w = np.ones(self.control_points.shape[:-1]) if self.weights is None else self.weights
        A = self.control_points - Q.reshape((m,) + (1,) * k + (-1,))
        if self.weights is not None:            # (times w = 1 changes nothing)
            A = w[..., None] * A
        h = self.upper - self.lower
        wmin = row_min(w)
        nets = {"A": A, "w": w[..., None]}
        diffs: Dict[Tuple[str, Tuple[int, ...]], np.ndarray] = {}

        def differenced(net: str, alpha: Tuple[int, ...]) -> np.ndarray:
            """nets[net] differenced alpha[0] times along u, then alpha[1] times along v;
            each from the one with a difference less in the last direction (np.diff with
            n > 1 differences n times: the same values, each difference taken once)."""
            if not any(alpha):
                return nets[net]
            if (net, alpha) not in diffs:
                last = max(a for a, n in enumerate(alpha) if n)
                prev = tuple(n - int(a == last) for a, n in enumerate(alpha))
                diffs[(net, alpha)] = np.diff(differenced(net, prev), axis=1 + last)
            return diffs[(net, alpha)]

        bounds: Dict[Tuple[str, Tuple[int, ...]], np.ndarray] = {}

        def hodograph_bound(net, alpha):
            if (net, alpha) not in bounds:           # (the weights' ones recur in every Leibniz sum)
                scale = np.ones(m)
                for a, n in enumerate(alpha):
                    for j in range(n):
                        scale = scale * (deg[a] - j) / h[:, a]
                out = differenced(net, alpha)
                bounds[(net, alpha)] = np.zeros(m) if out.size == 0 else scale * np.sqrt(row_max(squared_norms(out)))
            return bounds[(net, alpha)]

        alphas = sorted((al for al in itertools.product(range(order + 1), repeat=k) if sum(al) <= order), key=sum)
        B: Dict[Tuple[int, ...], np.ndarray] = {(0,) * k: R}
        for al in alphas[1:]:
            acc = hodograph_bound("A", al)
            if self.weights is None:            # w = 1: no Leibniz terms
                B[al] = acc
                continue
            for be in alphas:
                if be == al or any(b > a for a, b in zip(al, be)):
                    continue
                coef = float(np.prod([comb(a, b) for a, b in zip(al, be)]))
                diff = tuple(a - b for a, b in zip(al, be))
                acc = acc + coef * hodograph_bound("w", diff) * B[be]
            B[al] = acc / wmin
        B = {al: frozen(b) for al, b in B.items()}
        object.__setattr__(self, "_partials", (order, B))
        return dict(B)

    def derivative_bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """First and second derivative bounds from :meth:`partial_bounds`: L (m, k) with
        |d_a X| <= L[:, a], and M (m, k, k) with |d_a d_b X| <= M[:, a, b]."""
        return _tensors(self.partial_bounds(2), len(self), self.k)[:2]

    def third_derivative_bounds(self) -> np.ndarray:
        """T (m, k, k, k) with |d_a d_b d_c X| <= T[:, a, b, c]."""
        return _tensors(self.partial_bounds(3), len(self), self.k)[2]

    # --- evaluation --------------------------------------------------------------------
    def derivatives(self, index: np.ndarray, params: np.ndarray, order: int) -> np.ndarray:
        """Euclidean partials up to ``order`` per direction of piece ``index[n]`` at the
        parameters ``params[n]`` (N, k) (inside that piece's box): curves (order+1, N, dim),
        surfaces (order+1, order+1, N, dim) (Bernstein form, rational by Piegl & Tiller
        eq. 4.8 / A4.4)."""
        index = np.asarray(index, dtype=np.intp)
        params = np.asarray(params, dtype=np.float64).reshape(-1, self.k)
        lo, hi = self.lower[index], self.upper[index]
        h = hi - lo
        x = (params - lo) / h
        hom = self._hom_cache()[index]
        r = np.arange(order + 1)
        if self.k == 1:
            B = bernstein_derivatives(self.degrees[0], x[:, 0], order)          # (r, n, p+1)
            out = np.matmul(B.transpose(1, 0, 2), hom).transpose(1, 0, 2)     # (r, n, D)
            if order:
                out /= (h[:, 0][None, :] ** r[:, None])[..., None]
            return out if self.weights is None else rational_derivatives(out)
        p, q = self.degrees
        n, D = len(index), hom.shape[-1]
        Bu = bernstein_derivatives(p, x[:, 0], order).transpose(1, 0, 2)       # (n, r, p+1)
        Bv = bernstein_derivatives(q, x[:, 1], order).transpose(1, 0, 2)       # (n, r, q+1)
        T = np.matmul(Bu, hom.reshape(n, p + 1, (q + 1) * D)).reshape(n, order + 1, q + 1, D)
        out = np.matmul(Bv[:, None], T).transpose(1, 2, 0, 3)                 # (r, r, n, D)
        if order:
            scale = (h[:, 0][None, None, :] ** r[:, None, None]) * (h[:, 1][None, None, :] ** r[None, :, None])
            out = out / scale[..., None]
        return out if self.weights is None else rational_partials(out)

    def _hom_cache(self) -> np.ndarray:
        if "_hom" not in self.__dict__:
            object.__setattr__(self, "_hom", np.ascontiguousarray(self.homogeneous))
        return self.__dict__["_hom"]


def _tensors(B: Dict[Tuple[int, ...], np.ndarray], m: int, k: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Multi-index bounds as symmetric tensors (m, k), (m, k, k), (m, k, k, k)."""
    out = []
    for order in (1, 2, 3):
        T = np.zeros((m,) + (k,) * order)
        for idx in itertools.product(range(k), repeat=order):
            al = tuple(idx.count(a) for a in range(k))
            if al in B:
                T[(slice(None),) + idx] = B[al]
        out.append(T)
    return out[0], out[1], out[2]


def closed_directions(value: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray,
                      periodic: np.ndarray, size: float, samples: int = 9) -> np.ndarray:
    """Directions (k,) where an object with parameter box [lo, hi] and evaluator
    ``value`` (N, k) -> (N, D) is periodic or closes on itself (a seam: a clamped closed
    curve's ends, a revolved surface's longitude), so that parameters on both sides of
    the seam name the same points: S at the two ends agree within 1e-11 of ``size`` at
    ``samples`` points along the other direction."""
    k = len(lo)
    out = np.array(periodic, dtype=bool)
    s = np.linspace(0.0, 1.0, samples)
    for d in range(k):
        if out[d]:
            continue
        x0 = np.empty((samples, k))
        if k == 2:
            x0[:, 1 - d] = lo[1 - d] + s * (hi[1 - d] - lo[1 - d])
        x1 = x0.copy()
        x0[:, d], x1[:, d] = lo[d], hi[d]
        out[d] = np.linalg.norm(value(x0) - value(x1), axis=1).max() <= CLOSED_RTOL * size
    return out


def bezier_pieces(obj: Union[Curve, Surface]) -> BezierPieces:
    """The Bezier decomposition of an engine curve or surface (through ``to_nurbs()``).

    A Bezier triangle decomposes through its collapsed-edge NURBS form, whose
    parameters (s, t) map to the triangle's by u = s, v = t (1 - s).
    Raises CagdError for anything else."""
    if isinstance(obj, Curve):
        c = obj.to_nurbs()
        breaks, nets = c.bezier_net()
        P, W = _euclidean(nets, c.is_rational)
        return BezierPieces(P, W, (np.asarray(breaks, dtype=np.float64),), (bool(c.periodic),))
    if isinstance(obj, Surface):
        s = obj.to_nurbs()
        bu, bv, nets = s.bezier_net()
        P, W = _euclidean(nets.reshape((-1,) + nets.shape[2:]), s.is_rational)
        per = (bool(s.periodic_u), bool(s.periodic_v))
        return BezierPieces(P, W, (np.asarray(bu, dtype=np.float64), np.asarray(bv, dtype=np.float64)), per)
    raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")


def _euclidean(hom: np.ndarray, rational: bool) -> Tuple[np.ndarray, Optional[np.ndarray]]:
    """(control points, weights or None) of homogeneous nets."""
    if not rational:
        return np.ascontiguousarray(hom), None
    w = hom[..., -1]
    return hom[..., :-1] / w[..., None], np.ascontiguousarray(w)


# --- normalised frame -------------------------------------------------------------------------
FRAME_MODERATE = 1e8        # objects with extent in [1/FRAME_MODERATE, FRAME_MODERATE], centred within
FRAME_OFFCENTRE = 16.0      # FRAME_OFFCENTRE extents of the origin, are left in their own coordinates
PARAM_SPAN_FLOOR = 1e-12    # inner parameter width of a Bezier piece, relative to the domain, at least
FAR_POINT = 1e50            # query points farther than this (frame units) are moved in along their direction


def _pow2(x: float) -> float:
    """The power of two nearest to x > 0 (scaling by it is exact)."""
    return float(np.ldexp(1.0, int(np.clip(np.round(np.log2(x)), -1020, 1020))))


def _breaks_map(b: np.ndarray) -> Optional[np.ndarray]:
    """Inner breakpoints for the breakpoints ``b`` of one direction, or None when ``b``
    serve as they are: a domain of moderate width (FRAME_MODERATE) near the origin,
    without pieces narrower than PARAM_SPAN_FLOOR of it. Otherwise the inner domain is
    [0, 1], every piece at least PARAM_SPAN_FLOOR wide (a knot span 1e-300 wide makes
    the derivative bounds h^-2 overflow), the map piecewise linear (affine per piece)."""
    scale = _pow2(float(np.max(np.abs(b))) or 1.0)
    bs = b / scale                                      # |bs| <= 2: differences stay finite
    w = np.diff(bs)
    W = float(bs[-1] - bs[0])
    rel = w / W
    moderate = 1.0 / FRAME_MODERATE <= b[-1] - b[0] <= FRAME_MODERATE \
        and abs(float(b[0])) <= FRAME_MODERATE * (b[-1] - b[0])
    if moderate and rel.min() >= PARAM_SPAN_FLOOR:
        return None
    inner = np.concatenate([[0.0], np.cumsum(np.maximum(rel, PARAM_SPAN_FLOOR))])
    inner /= inner[-1]
    inner[-1] = 1.0
    return inner


@dataclass(frozen=True)
class Frame:
    """The affine map between an object's model coordinates and parameters and the
    normalised ones a query works in: points p = (X - centre) / scale (scale a power of
    two: exact), so that the object is O(1) and squared distances neither overflow nor
    underflow at any model scale; parameters per direction by a piecewise linear map of
    the breakpoints (``inner`` per direction, None: unchanged). ``identity`` when both
    are the identity (moderate objects keep their coordinates bit for bit)."""
    centre: np.ndarray
    scale: float
    breaks: Tuple[np.ndarray, ...]
    inner: Tuple[Optional[np.ndarray], ...]

    @property
    def identity(self) -> bool:
        return self.scale == 1.0 and not np.any(self.centre) and all(i is None for i in self.inner)

    @staticmethod
    def of(points: np.ndarray, breaks: Tuple[np.ndarray, ...] = ()) -> "Frame":
        """The frame of the control points ``points`` (n, dim) (their box) and breaks."""
        P = points.reshape(-1, points.shape[-1])
        lo, hi = column_extremes(P)
        mag = _pow2(float(max(np.abs(hi).max(), np.abs(lo).max())) or 1.0)
        extent = float(((hi / mag - lo / mag).max())) * mag          # no overflow for |P| ~ 1e308
        centre = lo / 2 + hi / 2
        if extent == 0.0:
            extent = max(float(np.abs(centre).max()), 1.0)
        moderate = 1.0 / FRAME_MODERATE <= extent <= FRAME_MODERATE
        if moderate and float(np.abs(centre).max()) <= FRAME_OFFCENTRE * extent:
            centre, scale = np.zeros_like(centre), 1.0
        else:
            scale = _pow2(extent)
            if float(np.abs(centre).max()) <= FRAME_OFFCENTRE * extent:
                centre = np.zeros_like(centre)
        return Frame(centre, scale, tuple(breaks), tuple(_breaks_map(b) for b in breaks))

    def with_breaks(self, breaks: Tuple[np.ndarray, ...]) -> "Frame":
        """The same point map for another object (own breaks, own parameter map)."""
        return Frame(self.centre, self.scale, tuple(breaks), tuple(_breaks_map(b) for b in breaks))

    # --- points -----------------------------------------------------------------------------
    def inward(self, X: np.ndarray) -> np.ndarray:
        """Model points (N, dim) in frame units, ``X / scale - centre / scale`` (finite
        for any finite X: the scale is at most 2^1020)."""
        if self.identity:
            return X
        with np.errstate(over="ignore"):
            return X / self.scale - self.centre / self.scale

    def outward(self, p: np.ndarray) -> np.ndarray:
        """Frame points back in model coordinates."""
        return p if self.identity else self.centre + self.scale * p

    # --- parameters ---------------------------------------------------------------------------
    def pieces(self, pieces: "BezierPieces") -> "BezierPieces":
        """``pieces`` in frame units and inner parameters."""
        if self.identity:
            return pieces
        P = (pieces.control_points - self.centre) / self.scale if np.any(self.centre) or self.scale != 1.0 \
            else pieces.control_points
        breaks = tuple(b if i is None else i for b, i in zip(pieces.breaks, self.inner))
        return BezierPieces(np.ascontiguousarray(P), pieces.weights, breaks, pieces.periodic)

    def params(self, x: np.ndarray) -> np.ndarray:
        """Inner parameters (N, k) as the object's own (affine per piece)."""
        if all(i is None for i in self.inner):
            return x
        out = np.array(x, dtype=np.float64)
        for a, (b, inner) in enumerate(zip(self.breaks, self.inner)):
            if inner is not None:
                j = np.clip(np.searchsorted(inner, out[:, a], side="right") - 1, 0, len(inner) - 2)
                f = np.clip((out[:, a] - inner[j]) / (inner[j + 1] - inner[j]), 0.0, 1.0)
                out[:, a] = np.where(f >= 1.0, b[j + 1], (1.0 - f) * b[j] + f * b[j + 1])
        return out


def net_box(obj: Union[Curve, Surface]) -> Tuple[Frame, np.ndarray, np.ndarray]:
    """(frame, lower, upper): the axis-aligned box (1, dim) of the control points of
    ``obj``'s NURBS form, in the frame of those points (:meth:`Frame.of`). The object
    lies in it: in the convex hull of its control points, its weights being positive
    (Farin, Curves and Surfaces for CAGD, 3.3 and 16.2; Piegl & Tiller 4.2). No Bezier
    decomposition: a bound for the cost of ``to_nurbs()`` and a pass over the net (issue 16,
    many objects: a far object is dismissed before any set-up)."""
    P = np.asarray(obj.to_nurbs().control_points, dtype=np.float64)
    P = P.reshape(-1, P.shape[-1])
    frame = Frame.of(P)
    Pf = frame.inward(P)
    lo, hi = column_extremes(Pf)
    return frame, lo[None], hi[None]


def robust_distance(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """|X - Y| along the last axis without overflow or underflow on the way (both scaled
    by their largest coordinate per row; inf only when the distance exceeds float64)."""
    m = np.maximum(np.abs(X).max(axis=-1), np.abs(Y).max(axis=-1))
    safe = np.where(m > 0, m, 1.0)[..., None]
    with np.errstate(over="ignore"):
        return m * np.sqrt(((X / safe - Y / safe) ** 2).sum(-1))


# --- second-order bounds of the closest-point search -------------------------------------
#: (lo, hi, div) of a half-Hessian hull: see ``hessian`` in :func:`box_lower_bound`
HullIntervals = Tuple[np.ndarray, np.ndarray, Optional[Tuple[np.ndarray, np.ndarray]]]

# g(x) = |S(x) - X|^2, grad g = 2 J^T r, Hess g = 2 (J^T J + sum_d r_d d2S_d), r = S - X
BLOCK = 2             # cells within this many grid steps of x*'s cell are bounded from x*


def box_lower_bound(Xp: np.ndarray, lo: np.ndarray, hi: np.ndarray, c: np.ndarray, S: np.ndarray, J: np.ndarray,
                    H2: np.ndarray, L: np.ndarray, M: np.ndarray, T: np.ndarray, convexity: bool = False,
                    hessian: Optional[Callable[[np.ndarray], HullIntervals]] = None,
                    target: Optional[np.ndarray] = None
                    ) -> Union[np.ndarray, Tuple[np.ndarray, np.ndarray, Tuple[np.ndarray, np.ndarray]]]:
    """A certified lower bound of g over each box [lo, hi] (inside cell ``cell``), from the
    expansion at c: g(x) >= g(c) + grad g(c).(x - c) + m/2 |x - c|^2 with m a lower bound
    of the smallest Hessian eigenvalue over the box, the larger of

    * 2 [(sigma_min(J(c)) - |dJ|)_+^2 - (|r(c)| + L.delta) lambda_max(M)], with
      |dJ| <= sqrt(sum_a (sum_b M_ab delta_b)^2) (Weyl's inequality), and
    * lambda_min(H(c)) - 2 |E|_F, E bounding the change of J^T J + r.d2S over the box:
      |E_ab| <= D_a |S_b| + |S_a| D_b + D_a D_b + (L.delta) M_ab + |r(c)| sum_e T_abe delta_e,
      D_a = sum_e M_ae delta_e,

    delta = the box's reach from c (c need not lie in the box), L, M, T bounds of the
    first, second and third partials valid on the hull of c and the box; S, J, H2 the
    point, first and second partials at c (M, T and H2 symmetric in their parameter
    indices a, b: only the entries a <= b are read). The quadratic is minimised over the box
    exactly (it is separable). The bound is taken in the variables y_a = s_a x_a, s_a the
    power of two nearest the first-derivative bound L_a (at least SCALE_FLOOR_RTOL of
    the largest), so that a large second derivative along one direction is weighed
    against the first derivative along that direction: m bounds the smallest eigenvalue of
    diag(s)^-1 H diag(s)^-1, i.e. H >= m diag(s)^2.

    ``hessian``: given row indices, (lo, hi, div): (lo, hi) (len, k, k) bounds of G =
    d (J^T J + r.d2S) over those rows' boxes, d a positive function, and div None (d = 1)
    or the bounds (dlo, dhi) (len,) of d there (:mod:`cagd.queries._hessian_hull`: per
    entry, the extreme Bezier coefficients over the box's cell; d = w^4 on rational cells;
    (-inf, inf) for a row it declines); asked for the rows where it can help (the half
    Hessian at c positive definite, m above not positive), m there is also at least twice
    the smallest eigenvalue mu of any symmetric matrix within them (for k = 2, (A + C)/2 -
    sqrt(((A - C)/2)^2 + B^2) at the lower ends of A and C and the largest |B|: that
    eigenvalue grows with A and C and falls with |B|), divided by dhi where mu > 0 and
    by dlo where not (lambda_min(G / d) = lambda_min(G) / d);
    ``target`` (n,): asked only where the bound would reach it with m at its best (twice
    the half Hessian's smallest eigenvalue at c: no bound over a box containing c
    exceeds it), i.e. where the hull can close the box.

    ``convexity``: also return m and, for c in the box, the box (tlo, thi) (n, k) of offsets
    from c that holds g's minimiser x^ over the box where m > 0 (g strongly convex there:
    g(x^) >= g(c) + the quadratic at x^ - c, and g(x^) <= g(c); the whole box where
    m <= 0)."""
    n, dim = S.shape
    k = c.shape[1]
    # component-first arrays (..., n), rows contiguous (S, J, H2 are transposed views of
    # such storage): one numpy call per operation whatever n (a point's closest point
    # bounds a handful of boxes a round), reductions over leading axes fast for long n
    r = S.T - Xp.T                                                     # (dim, n)
    f2 = squared_norms(r.T)
    f = np.sqrt(f2)
    Jt = J.T                                                           # (k, dim, n)
    grad = 2.0 * lead_sum((r * Jt).swapaxes(0, 1))                   # (k, n)
    nrm = np.sqrt(squared_norms(Jt.transpose(0, 2, 1)))              # |S_a(c)|
    # scales from the first-derivative bounds over the cell, at least SCALE_FLOOR_RTOL of
    # the largest (a direction degenerate over the whole cell). Issue 16: a floor of a
    # quarter of the largest made a sliver's short direction (L 1/300 of the long one's)
    # look degenerate: m ~ 1e-4 of the true one, boxes ~1/30 of the curvature radius
    # before any closed (a 0.1 x 10 mm face, points 1e-6 off: 70x the time)
    Lt = L.T
    top = Lt.max(axis=0)
    top = np.where(top > 0, top, 1.0)
    sc = np.exp2(np.round(np.log2(np.maximum(Lt, SCALE_FLOOR_RTOL * top))))  # (k, n) powers of two
    si = 1.0 / sc
    Sn = nrm / sc                                                      # |S_a(c)| scaled
    ct = c.T
    tlo, thi = lo.T - ct, hi.T - ct                                    # the box's offsets from c
    delta = np.maximum(-tlo, thi) * sc                                 # its reach from c, scaled
    Jh = Jt * si[:, None]
    pa, pb, w2 = _PAIRS[k]                                             # (0, 0)[, (0, 1), (1, 1)]
    sij = si[pa] * si[pb]                                              # (pairs, n)
    Mh = M[:, pa, pb].T * sij
    if k == 1:
        D = Mh * delta
        dJ, lam, sig = D[0], Mh[0], Sn[0]
    else:
        D = Mh[[0, 1]] * delta[0] + Mh[[1, 2]] * delta[1]               # D_a = sum_b Mh_ab delta_b
        dJ = np.sqrt(squared_norms(D.T))
        lam = eigenvalue_2x2(Mh[0], Mh[1], Mh[2], 1.0)
        u, v = Jh
        aa, cc = Sn[0] * Sn[0], Sn[1] * Sn[1]
        bb = lead_sum(u * v)
        if dim == 3:
            w = u[[1, 2, 0]] * v[[2, 0, 1]] - u[[2, 0, 1]] * v[[1, 2, 0]]          # u x v
            det = squared_norms(w.T)
        elif dim == 2:
            det = (u[0] * v[1] - u[1] * v[0]) ** 2
        else:
            det = np.maximum(aa * cc - bb * bb, 0.0)
        lmax = eigenvalue_2x2(aa, bb, cc, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            lmin = np.where(lmax > 0, det / lmax, 0.0)
        sig = np.sqrt(lmin) * (1.0 - SHRINK_RTOL)
    Ld = lead_sum(Lt * delta * si)
    m1 = 2.0 * (np.maximum(sig - dJ, 0.0) ** 2 - (f + Ld) * lam)
    # half Hessian J^T J + r.d2S at c and the bound E of its change over the box (pairs, n)
    half = (lead_sum((Jh[pa] * Jh[pb]).swapaxes(0, 1))
            + lead_sum(r[:, None] * H2[:, :, pa, pb].transpose(1, 2, 0)) * sij)
    tt = lead_sum(T[:, pa, pb].transpose(2, 1, 0) * (si * delta)[:, None])
    change = D[pa] * Sn[pb] + Sn[pa] * D[pb] + D[pa] * D[pb] + Ld * Mh + f * tt * sij
    E2 = lead_sum(w2 * (change * change))            # |E|_F^2 (off-diagonal entries twice)
    scale = lead_sum(w2 * np.abs(half))
    lmin_h = half[0] if k == 1 else eigenvalue_2x2(half[0], half[1], half[2], -1.0)
    m2 = 2.0 * (lmin_h - np.sqrt(E2) - SLACK_RTOL * scale)
    m = np.maximum(m1, m2)
    if hessian is not None:
        ask = (lmin_h > 0) & (m <= 0)
        if target is not None:          # ... and only where the best m it could give closes the box
            ask[ask] = f2[ask] + _quadratic_minimum(2.0 * lmin_h[ask], grad[:, ask], sc[:, ask], tlo[:, ask],
                                                    thi[:, ask])[0] >= target[ask]
        i = np.flatnonzero(ask)
        if i.size:                      # (rows it declines: -inf, inf, nothing gained)
            m = m.copy()
            with np.errstate(invalid="ignore"):
                hl, hh, div = hessian(i)
                mu = _interval_eigenvalue(hl, hh, si[:, i])
                if div is not None:
                    mu = mu / np.where(mu > 0, div[1], div[0])
                m[i] = np.fmax(m[i], mu)
    if k == 2:          # ... or a curvature per direction (where one direction is concave): in one call
        qs, (ma, qa) = _quadratic_minimum(_split_curvatures(m, half, change, SLACK_RTOL * scale), grad, sc, tlo, thi)
        q = np.maximum(qs[0], qs[1:].max(axis=0))
        ma, qa = ma[0], qa[0]                         # the isotropic m's terms
    else:
        q, (ma, qa) = _quadratic_minimum(m, grad, sc, tlo, thi)
    bound = f2 + q - ULP_RTOL * f2
    if not convexity:
        return bound
    # the minimiser x^ over the box has g(x^) <= g(c), so sum_a q_a(t_a) <= 0 at t = x^ - c,
    # q_a(t) = grad_a t + m_a t^2 / 2 >= its minimum qmin_a over the box's range: each
    # q_a(t_a) <= qmin_a - sum_b qmin_b (+ a rounding margin), an interval of t_a
    rhs = qa - q + BOUND_MARGIN_RTOL * f2 + TINY
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        root = np.sqrt(grad * grad + 2.0 * ma * rhs)
        a0 = np.where(m > 0, (-grad - root) / ma, -np.inf)
        a1 = np.where(m > 0, (-grad + root) / ma, np.inf)
    return bound, m, (np.maximum(a0, tlo).T, np.minimum(a1, thi).T)


def symmetric_pairs(k: int) -> List[Tuple[int, int]]:
    """The entries (a, b), a <= b, of a symmetric k x k matrix (k = 1, 2)."""
    return [(0, 0)] if k == 1 else [(0, 0), (0, 1), (1, 1)]


# the entries of symmetric_pairs(k) as index arrays (a, b), and their weights in a sum
# over the whole matrix (off-diagonal entries twice), as a column
_PAIRS = {k: (np.array([a for a, _ in symmetric_pairs(k)]), np.array([b for _, b in symmetric_pairs(k)]),
              np.array([[1.0 if a == b else 2.0] for a, b in symmetric_pairs(k)])) for k in (1, 2)}


def _quadratic_minimum(m: np.ndarray, grad: np.ndarray, sc: np.ndarray, tlo: np.ndarray, thi: np.ndarray
                       ) -> Tuple[np.ndarray, Tuple[np.ndarray, np.ndarray]]:
    """The minimum over the box tlo <= t <= thi of sum_a grad_a t_a + m_a s_a^2 t_a^2 / 2
    (separable: per direction, the ends and the clipped vertex); grad, sc, tlo, thi
    (k, n) component-first, m (n,) one curvature for every direction or (..., k, n) one
    per direction, leading axes for several at once; and the per-direction terms
    (m_a s_a^2, that direction's minimum)."""
    ma = m * (sc * sc)
    with np.errstate(divide="ignore", invalid="ignore"):
        ts = np.negative(grad) / np.where(ma > 0, ma, np.inf)           # the vertex (0 where not convex)
    ts = np.minimum(np.maximum(ts, tlo), thi)
    qa = np.minimum(np.minimum(grad * tlo + ma * (0.5 * tlo * tlo), grad * thi + ma * (0.5 * thi * thi)),
                    ts * (grad + 0.5 * ma * ts))
    return lead_sum(qa.swapaxes(0, -2)), (ma, qa)


def _split_curvatures(m: np.ndarray, half: np.ndarray, change: np.ndarray, slack: Union[float, np.ndarray]
                      ) -> np.ndarray:
    """The curvatures (1 + len(SPLIT_RATIOS), 2, n) per direction of separable quadratics
    below the box's (see :func:`box_lower_bound`): first m in both directions, then per
    ratio rho in SPLIT_RATIOS: with the half Hessian's entries (pairs, n) within h_ab +-
    e_ab over the box (scaled variables) and 2 |t_u t_v| <= rho t_u^2 + t_v^2 / rho,
    t^T H t >= (A - B rho) t_u^2 + (C - B / rho) t_v^2, A = h_uu - e_uu, C = h_vv - e_vv,
    B = |h_uv| + e_uv (Gershgorin's split). Where the isotropic bound m is negative
    because one direction is concave (a foot on the domain's edge: g's curvature across
    it may be negative, its slope there positive), the other direction keeps its own
    curvature."""
    A = half[0] - change[0] - slack
    C = half[2] - change[2] - slack
    B = np.abs(half[1]) + change[1]
    rho = np.array(SPLIT_RATIOS)[:, None]
    out = np.empty((1 + len(SPLIT_RATIOS), 2, len(m)))
    out[0] = m
    out[1:, 0] = 2.0 * (A - B * rho)
    out[1:, 1] = 2.0 * (C - B / rho)
    return out


def _interval_eigenvalue(hl: np.ndarray, hh: np.ndarray, si: np.ndarray) -> np.ndarray:
    """Twice a lower bound of the smallest eigenvalue of every symmetric matrix between
    hl and hh (n, k, k), in the variables scaled by 1 / si (k, n) (see
    :func:`box_lower_bound`), lowered by SLACK_RTOL of its entries for rounding."""
    s0 = si[0]
    A = hl[:, 0, 0] * (s0 * s0)
    big = np.maximum(np.abs(A), np.abs(hh[:, 0, 0]) * (s0 * s0))
    if len(si) == 1:
        return 2.0 * (A - SLACK_RTOL * big)
    s1 = si[1]
    C = hl[:, 1, 1] * (s1 * s1)
    B = np.maximum(np.abs(hl[:, 0, 1]), np.abs(hh[:, 0, 1])) * (s0 * s1)
    big = big + np.maximum(np.abs(C), np.abs(hh[:, 1, 1]) * (s1 * s1)) + 2.0 * B
    return 2.0 * (eigenvalue_2x2(A, B, C, -1.0) - SLACK_RTOL * big)


def block_max(B: np.ndarray, shape: Sequence[int], reach: int = BLOCK) -> np.ndarray:
    """Per cell, the maximum of the bounds B over the cells within ``reach`` grid steps."""
    G = B.reshape(tuple(shape) + B.shape[1:])
    out = G.copy()
    for a in range(len(shape)):
        src = out.copy()
        for s in range(1, reach + 1):
            lo = [slice(None)] * G.ndim
            hi = [slice(None)] * G.ndim
            lo[a], hi[a] = slice(0, -s), slice(s, None)
            out[tuple(lo)] = np.maximum(out[tuple(lo)], src[tuple(hi)])
            out[tuple(hi)] = np.maximum(out[tuple(hi)], src[tuple(lo)])
    return out.reshape(B.shape)
