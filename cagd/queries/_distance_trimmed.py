"""Minimum distance with trimmed faces and point sets (issue 15).

A face F = S(D) against an object G (a point set, a curve, a surface or another face):
the minimum of |F(x) - G(y)| is attained either with x on the boundary of D, or with
x inside D, where it is a stationary point of |S(x) - G(y)|^2 in x. So the distance is
the smaller of

- the edges: every loop of the face (its boundary images joined into one curve,
  :func:`cagd.queries.trimmed._joined_loops`) against G, by :func:`min_distance` (which
  honours G's own trim); the point found is moved onto the face, S(c(t)), so the distance
  is attained by points of both faces, and the lower bound subtracts the joined curve's
  error bound (the boundary fits' measured error, 0 for exact iso-curves);
- the interior: the branch and bound of :func:`cagd.queries.distance.min_distance` over
  the untrimmed objects with two changes (:class:`TrimTest`): pairs whose piece lies
  outside D are dropped (box_classes of the chord grid), and so are pairs on which
  d/dx_a |S - G|^2 = 2 S_a . (S - G) cannot vanish for some parameter a (interval
  arithmetic on the hodograph hulls of the homogeneous pieces: S_a = (P^w_a - S w_a) / w);
  only pairs of points of both faces give upper bounds, and the edges' distance is the
  ceiling a pair must beat.

A point set is the nearest of its points' closest points (:func:`cagd.closest_point`,
which honours trims).
"""
from __future__ import annotations

from typing import Any, List, Optional, Tuple
import weakref

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from . import _subdivision as sd
from .bounds import robust_distance
from ._numerics import TINY

#: pieces over at most this many cells of the chord grid are classified chord by chord
#: (box_classes); larger ones that a chord may meet count as crossed
EXACT_CELLS = 16
#: relative margin on the interval of the gradient (rounding of the hull products)
GRADIENT_MARGIN = 1e-12
#: a piece touches a C0 break (where the surface may have a kink) within this share of the domain
BREAK_TOL = 1e-12


class TrimTest:
    """Which (piece of a, piece of b) pairs may hold the minimum between the faces
    (``ta``, ``tb``: the TrimmedSurface of a or b, or None), and which parameter pairs
    lie on both faces; a, b the reframed :class:`sd.Geometry` of the untrimmed objects."""

    def __init__(self, A: sd.Geometry, B: sd.Geometry, ta: object, tb: object):
        self.A, self.B, self.ta, self.tb = A, B, ta, tb
        self.kinks = [None if t is None else _kinks(G) for G, t in ((A, ta), (B, tb))]

    def inside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        ok = np.ones(len(x), dtype=bool)
        for G, t, z in ((self.A, self.ta, x), (self.B, self.tb, y)):
            if t is not None and len(z):
                uv = G.frame.params(np.asarray(z, float))
                ok &= t.contains(uv[:, 0], uv[:, 1])      # type: ignore[attr-defined]
        return ok

    def keep(self, pa: sd.Pieces, pb: sd.Pieces) -> np.ndarray:
        from .trimmed import box_classes
        keep = np.ones(len(pa.ctrl), dtype=bool)
        for side, (G, t, p, q) in enumerate(((self.A, self.ta, pa, pb), (self.B, self.tb, pb, pa))):
            if t is None:
                continue
            lo, hi = G.frame.params(p.lo), G.frame.params(p.hi)
            keep &= box_classes(t, lo, hi, EXACT_CELLS) >= 0         # type: ignore[arg-type]
            i = np.flatnonzero(keep)
            if i.size:
                usable = _usable(self.kinks[side], lo[i], hi[i], G)
                keep[i[_nonstationary(p.ctrl[i], q.ctrl[i], usable)]] = False
        return np.flatnonzero(keep)


def _kinks(G: sd.Geometry) -> List[np.ndarray]:
    """Per direction, the parameters (the object's own) where it may be only C0: the
    domain's ends and the inner knots of multiplicity >= the degree."""
    n: Any = G.nurbs
    out = []
    for knots, p, (a, b) in ((n.knots_u, n.degree_u, n.domain[0]), (n.knots_v, n.degree_v, n.domain[1])):
        kv = np.asarray(knots, float)
        vals, counts = np.unique(kv, return_counts=True)
        inner = vals[(counts >= p) & (vals > a) & (vals < b)]
        out.append(np.concatenate([[a], inner, [b]]))
    return out


def _usable(kinks: Optional[List[np.ndarray]], lo: np.ndarray, hi: np.ndarray, G: sd.Geometry) -> np.ndarray:
    """(M, 2): the directions a along which the stationarity test may be used on a piece:
    its sides across a touch no kink (there the minimum may sit without a stationary point)."""
    assert kinks is not None
    out = np.ones(lo.shape, dtype=bool)
    for a, k in enumerate(kinks):
        eps = BREAK_TOL * float(k[-1] - k[0])
        out[:, a] = np.searchsorted(k, hi[:, a] + eps, side="right") == np.searchsorted(k, lo[:, a] - eps, side="left")
    return out


def _iprod(alo, ahi, blo, bhi):
    """Interval product [alo, ahi] * [blo, bhi] (elementwise)."""
    c = np.stack([alo * blo, alo * bhi, ahi * blo, ahi * bhi])
    return c.min(axis=0), c.max(axis=0)


def _nonstationary(ca: np.ndarray, cb: np.ndarray, usable: np.ndarray) -> np.ndarray:
    """(M,): for surface patches ``ca`` (M, n+1, m+1, D+1, homogeneous) against pieces
    ``cb`` of the other object, whether some usable direction a has S_a . (S - G) of one
    sign over the pair: S_a w = P^w_a - S w_a, P^w_a and w_a in the hulls of the
    hodograph's control points, S and G in their control boxes."""
    lo_a, hi_a = sd.boxes(ca)
    lo_b, hi_b = sd.boxes(cb)
    rlo, rhi = lo_a - hi_b, hi_a - lo_b
    D = ca.shape[-1] - 1
    out = np.zeros(len(ca), dtype=bool)
    for a in range(2):
        H = np.diff(ca, axis=1 + a).reshape(len(ca), -1, D + 1)
        plo, phi = H[..., :D].min(axis=1), H[..., :D].max(axis=1)
        wlo, whi = H[..., D].min(axis=1)[:, None], H[..., D].max(axis=1)[:, None]
        qlo, qhi = _iprod(lo_a, hi_a, wlo, whi)
        elo, ehi = plo - qhi, phi - qlo
        dlo, dhi = _iprod(elo, ehi, rlo, rhi)
        glo, ghi = dlo.sum(axis=1), dhi.sum(axis=1)
        margin = GRADIENT_MARGIN * (np.abs(dlo).sum(axis=1) + np.abs(dhi).sum(axis=1)) + TINY
        out |= usable[:, a] & ((glo > margin) | (ghi < -margin))
    return out


_BOUNDARIES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _boundary(ts: Any, tol: float) -> Any:
    """The face's boundary fitted within min(BOUNDARY_TOL * size, tol / (4 FIT_ERROR_SAFETY))
    (the edges' error bound a quarter of tol; their own gap is asked within tol / 2),
    cached per face and tol."""
    from ..surfaces.trimmed import BOUNDARY_TOL
    from .trimmed import FIT_ERROR_SAFETY
    fit = min(BOUNDARY_TOL * ts.size, tol / (4.0 * FIT_ERROR_SAFETY))
    try:
        cache = _BOUNDARIES.setdefault(ts, {})
    except TypeError:
        cache = {}
    if fit not in cache:
        cache[fit] = ts._image_boundary(fit)
    return cache[fit]


def _size(obj: Any) -> np.ndarray:
    from ..surfaces.trimmed import TrimmedSurface
    if isinstance(obj, TrimmedSurface):
        obj = obj.untrimmed
    if isinstance(obj, (Curve, Surface)):
        return sd.project(sd.Geometry(obj, "a").pieces.ctrl).reshape(-1, obj.to_nurbs().dim)
    return np.asarray(obj, float).reshape(-1, np.shape(obj)[-1])


def trimmed_min_distance(a: Any, b: Any, tol: Optional[float], *, max_depth: int, max_pairs: int,
                         refine_per_level: int, ceiling: Optional[float] = None) -> Any:
    """:func:`cagd.min_distance` where a or b is a TrimmedSurface or a point set (see the
    module docstring). ``ceiling``: a distance known (model units); a result of
    distance inf says nothing beat it (the lower bound still holds)."""
    from ..surfaces.trimmed import TrimmedSurface
    from .distance import DEFAULT_RTOL, ROUNDING_RTOL, DistanceResult, min_distance
    objs: List[Any] = []
    for obj, name in ((a, "a"), (b, "b")):
        if isinstance(obj, (Curve, Surface)):
            objs.append(obj)
        else:
            pts = _checks.finite_array(obj, name)
            if pts.ndim == 1:
                pts = pts[None]
            if pts.ndim != 2 or not len(pts):
                raise CagdError(f"{name}: expected a curve, a surface or an (N, dim) point set, got shape {pts.shape}")
            objs.append(pts)
    a, b = objs
    Pa, Pb = _size(a), _size(b)
    if Pa.shape[1] != Pb.shape[1]:
        raise CagdError(f"a, b: objects of different dimension ({Pa.shape[1]}-D and {Pb.shape[1]}-D)")
    if tol is None:
        size = max(float(np.ptp(Pa, axis=0).max()), float(np.ptp(Pb, axis=0).max()))
        extent = float(np.ptp(np.concatenate([Pa, Pb]), axis=0).max())
        tol = max(DEFAULT_RTOL * size, ROUNDING_RTOL * extent, TINY)
    else:
        tol = _checks.positive(tol, "tol")
    if not isinstance(a, (Curve, Surface)) or not isinstance(b, (Curve, Surface)):
        return _points(a, b, tol)
    kw: Any = dict(max_depth=max_depth, max_pairs=max_pairs, refine_per_level=refine_per_level)
    # an upper bound first: samples of a face against the other object (closest points,
    # its trim honoured): the edges and the interior only look for pairs that beat it
    best = _sampled(a, b)
    if ceiling is not None and ceiling < best[0]:
        best = (float(ceiling), None, None, True)
    lower = best[0]
    messages = []
    # the edges: each trimmed face's loops against the other object (its trim honoured)
    for side, (t, other) in enumerate(((a, b), (b, a))):
        if not isinstance(t, TrimmedSurface):
            continue
        from .trimmed import _joined_loops, _on_domain
        for loop, C, starts, offsets, err in _joined_loops(t, _boundary(t, tol)):
            first, second = (C, other) if side == 0 else (other, C)
            r = min_distance(first, second, 0.5 * tol, **kw, _ceiling=best[0])
            lower = min(lower, r.lower_bound - err)
            if not r.converged and r.message:
                messages.append(r.message)
            if not np.isfinite(r.distance):
                continue
            tc = float(r.params[side])
            j = int(np.clip(np.searchsorted(offsets, tc, side="right") - 1, 0, len(loop) - 1))
            c = loop[j]
            uv = _on_domain(t.untrimmed, c(np.clip(np.array([tc - offsets[j] + starts[j]]), *c.domain)))
            foot = t.untrimmed(uv[:, 0], uv[:, 1])[0]
            q = r.points[1 - side]
            d = float(robust_distance(foot, q))
            if d < best[0]:
                uv0 = uv[0].copy()
                params = (uv0, r.params[1]) if side == 0 else (r.params[0], uv0)
                points = (foot, q) if side == 0 else (q, foot)
                best = (d, params, points, r.isolated)
    # the interior: pairs of points inside both trims that beat the edges
    ua = a.untrimmed if isinstance(a, TrimmedSurface) else a
    ub = b.untrimmed if isinstance(b, TrimmedSurface) else b
    ta = a if isinstance(a, TrimmedSurface) else None
    tb = b if isinstance(b, TrimmedSurface) else None
    r = min_distance(ua, ub, tol, **kw, _trims=(ta, tb), _ceiling=best[0])
    lower = min(lower, r.lower_bound)
    if not r.converged and r.message:
        messages.append(r.message)
    if np.isfinite(r.distance) and r.distance < best[0]:
        best = (r.distance, r.params, r.points, r.isolated)
    distance, params, points, isolated = best
    lower = max(min(lower, distance), 0.0)
    converged = distance - lower <= tol
    message = "" if converged else ("; ".join(messages) or f"the gap {distance - lower:.3g} exceeds tol {tol:.3g}")
    if params is None:                   # nothing beat the caller's ceiling
        return DistanceResult(np.inf, (None, None), (None, None), float(lower), float(tol), bool(converged), True,
                              message)
    for v in (*params, *points):
        if isinstance(v, np.ndarray):
            v.flags.writeable = False
    return DistanceResult(float(distance), params, points, float(lower), float(tol), bool(converged), bool(isolated),
                          message)


#: (u, v) samples per direction of a face for the first upper bound
SAMPLES = 12


def _sampled(a: Any, b: Any) -> tuple:
    """(distance, params, points, isolated) of the nearest of a face's samples (a grid
    over its loops' box kept inside the trim, and points of its loop curves) to the
    other object, by :func:`cagd.closest_point`: points of both objects, an upper bound."""
    from ..surfaces.trimmed import TrimmedSurface
    from .closest import _closest_point
    swap = not isinstance(a, TrimmedSurface)
    t, other = (b, a) if swap else (a, b)
    assert isinstance(t, TrimmedSurface)
    curves = [c for loop in t.loops for c in loop]
    uv = np.concatenate([c(np.linspace(*c.domain, 5)) for c in curves])
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    g = (np.arange(SAMPLES) + 0.5) / SAMPLES
    gu, gv = np.meshgrid(lo[0] + g * (hi[0] - lo[0]), lo[1] + g * (hi[1] - lo[1]), indexing="ij")
    grid = np.stack([gu.ravel(), gv.ravel()], axis=1)
    from .trimmed import _on_domain
    uv = _on_domain(t.untrimmed, np.concatenate([grid[t.contains(grid[:, 0], grid[:, 1])], uv]))
    X = t.untrimmed(uv[:, 0], uv[:, 1])
    r = _closest_point(other, X)
    k = int(np.argmin(r.distances))
    mine, theirs = uv[k].copy(), r.params[k]
    theirs = np.array(theirs) if np.ndim(theirs) else float(theirs)
    foot = np.array(r.feet[k])
    params = (theirs, mine) if swap else (mine, theirs)
    points = (foot, X[k].copy()) if swap else (X[k].copy(), foot)
    return float(r.distances[k]), params, points, True


def _points(a: Any, b: Any, tol: float) -> Any:
    """A point set against an object: the nearest of the points' closest points."""
    from .closest import _closest_point
    from .distance import DistanceResult
    swap = not isinstance(a, (Curve, Surface))
    obj, pts = (b, a) if swap else (a, b)
    r = _closest_point(obj, pts)
    k = int(np.argmin(r.distances))
    lower = float(min(r.lower_bounds.min(), r.distances[k]))
    param = r.params[k]
    if np.ndim(param):
        param = np.array(param)
        param.flags.writeable = False
    else:
        param = float(param)
    foot, point = np.array(r.feet[k]), np.array(pts[k], float)
    foot.flags.writeable = point.flags.writeable = False
    d = float(r.distances[k])
    params: Tuple = (k, param) if swap else (param, k)
    points: Tuple = (point, foot) if swap else (foot, point)
    converged = d - lower <= tol
    return DistanceResult(d, params, points, lower, float(tol), bool(converged), True,
                          "" if converged else (r.message or f"the gap {d - lower:.3g} exceeds tol {tol:.3g}"))
