"""Global minimum distance between two curves, a curve and a surface, or two surfaces,
with a certified lower bound (seed 004, ch. 1 §4, positional relations: minimum
distance).

Branch and bound over pairs of Bezier pieces (Piegl & Tiller A5.6/A5.7 decomposition,
de Casteljau halving): a pair's lower bound is the larger of the distance between
the axis-aligned boxes of the two control hulls and the gap of their projections
on the current best direction and on the centre-to-centre direction (both valid by
the convex-hull property, positive weights). Upper bounds come from piece corners
(points of the objects) and from projected Newton refinement of the most promising
pairs. Pairs whose lower bound exceeds the best distance are pruned; the smallest
bound of the pairs still alive (and of any dropped at the pair cap) is reported as
``lower_bound``, so the true minimum lies in [lower_bound, distance].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .. import _checks
from ..errors import CagdError
from . import _subdivision as sd


@dataclass
class DistanceResult:
    """``distance`` attained at ``params`` = (parameter on a, parameter on b) and
    ``points`` = (a point, b point); the global minimum is certified to be at least
    ``lower_bound``. ``converged`` is False when the gap distance - lower_bound did not
    reach ``tol`` within the depth/pair limits (``message`` says which)."""
    distance: float
    params: tuple
    points: tuple
    lower_bound: float
    tol: float
    converged: bool
    message: str = ""

    @property
    def gap(self) -> float:
        return self.distance - self.lower_bound


def _corners(ctrl: np.ndarray) -> np.ndarray:
    """Corner control points (points of the object: clamped Bezier pieces interpolate
    them) with their local corner parameters in {0, 1}^k."""
    P = sd.project(ctrl)
    if ctrl.ndim == 3:
        return np.stack([P[:, 0], P[:, -1]], 1), np.array([[0.0], [1.0]])
    return (np.stack([P[:, 0, 0], P[:, -1, 0], P[:, 0, -1], P[:, -1, -1]], 1),
            np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]))


def min_distance(a, b, tol: Optional[float] = None, *, max_depth: int = 40, max_pairs: int = 20000,
                 refine_per_level: int = 8) -> DistanceResult:
    """The global minimum distance between ``a`` and ``b`` (engine curves or surfaces of
    the same dimension), with a certified lower bound.

    Stops when distance - lower_bound <= ``tol`` (default 1e-9 times the size of the
    objects), after ``max_depth`` halvings, or when more than ``max_pairs`` pairs are
    alive (then the pairs with the largest bounds are dropped, their bounds kept in
    the certificate). Returns a :class:`DistanceResult`.

    Raises:
        CagdError: not curves/surfaces, different dimensions, tol <= 0 or NaN.
    """
    A, B = sd.Geometry(a, "a"), sd.Geometry(b, "b")
    if A.dim != B.dim:
        raise CagdError(f"a, b: objects of different dimension ({A.dim}-D and {B.dim}-D)")
    size = max(A.size, B.size)
    if tol is None:
        tol = 1e-9 * size
    tol = _checks.positive(tol, "tol")
    max_depth = _checks.integer(max_depth, "max_depth", 0, 200)
    max_pairs = _checks.integer(max_pairs, "max_pairs", 16)
    Ka, Kb = len(A.pieces.ctrl), len(B.pieces.ctrl)
    pa = A.pieces.take(np.repeat(np.arange(Ka), Kb))
    pb = B.pieces.take(np.tile(np.arange(Kb), Ka))
    best, bx, by = np.inf, None, None
    floor = np.inf                 # smallest bound among pairs dropped at the cap
    direction = None
    lower = 0.0
    message = ""
    for depth in range(max_depth + 1):
        lo_a, hi_a = sd.boxes(pa.ctrl)
        lo_b, hi_b = sd.boxes(pb.ctrl)
        bound = sd.box_gap(lo_a, hi_a, lo_b, hi_b)
        centre = 0.5 * (lo_b + hi_b) - 0.5 * (lo_a + hi_a)
        bound = np.maximum(bound, sd.slab_gap(pa.ctrl, pb.ctrl, centre))
        if direction is not None:
            bound = np.maximum(bound, sd.slab_gap(pa.ctrl, pb.ctrl, np.broadcast_to(direction, centre.shape)))
        # upper bounds: corners, then Newton from the most promising pairs
        ca, la = _corners(pa.ctrl)
        cb, lb = _corners(pb.ctrl)
        d = np.linalg.norm(ca[:, :, None] - cb[:, None, :], axis=-1).reshape(len(ca), -1)
        m = int(np.argmin(d.min(axis=1)))
        if d[m].min() < best:
            i, j = divmod(int(np.argmin(d[m])), cb.shape[1])
            bx = pa.lo[m] + la[i] * (pa.hi[m] - pa.lo[m])
            by = pb.lo[m] + lb[j] * (pb.hi[m] - pb.lo[m])
            best = float(d[m].min())
        pick = np.argsort(bound)[:refine_per_level]
        x, y, dist, _ = sd.refine(A, B, 0.5 * (pa.lo[pick] + pa.hi[pick]), 0.5 * (pb.lo[pick] + pb.hi[pick]), True, 20)
        k = int(np.argmin(dist))
        if dist[k] < best:
            best, bx, by = float(dist[k]), x[k], y[k]
        if best > 0:
            direction = B.points(by[None])[0] - A.points(bx[None])[0]
        alive = bound <= best
        lower = min(float(bound[alive].min()) if alive.any() else best, floor, best)
        if best - lower <= tol:
            break
        if not alive.any():            # only pairs dropped at the cap could hold a closer point
            message = (f"pair cap {max_pairs} reached: the pairs dropped there bound the distance from "
                       f"below by {floor:.6g}")
            break
        if depth == max_depth:
            message = (f"depth limit {max_depth} reached with {np.count_nonzero(alive)} pairs alive"
                       + (f" (and pairs dropped at the cap {max_pairs})" if np.isfinite(floor) else ""))
            break
        go = np.flatnonzero(alive)
        # split the larger piece of every pair (both when comparable)
        da = np.linalg.norm(hi_a[go] - lo_a[go], axis=1)
        db = np.linalg.norm(hi_b[go] - lo_b[go], axis=1)
        pa, pb, parent = sd.split_pairs(pa.take(go), pb.take(go), da >= 0.5 * db, db >= 0.5 * da)
        if len(parent) > max_pairs:
            order = np.argsort(bound[go][parent], kind="stable")
            floor = min(floor, float(bound[go][parent][order[max_pairs]]))
            keep = order[:max_pairs]
            pa, pb = pa.take(keep), pb.take(keep)
            message = f"pair cap {max_pairs} reached; pairs beyond it dropped with their bounds kept"
    converged = best - lower <= tol
    pA, pB = A.points(bx[None])[0], B.points(by[None])[0]
    return DistanceResult(float(np.linalg.norm(pA - pB)), (_param(A, bx), _param(B, by)), (pA, pB),
                          float(min(lower, best)), tol, bool(converged), "" if converged else message)


def _param(G: sd.Geometry, x: np.ndarray):
    u = G.user_params(x[None])[0]
    return float(u) if G.k == 1 else u
