"""Bezier pieces of 2-D curves in homogeneous form (x w, y w, w) and their chords: the
primitives of trimmed-surface classification and validation (cagd.surfaces.trimmed,
cagd.surfaces._trim_check). A piece lies in the convex hull of its Cartesian control
points (positive weights), so the largest distance of a control point from the chord
bounds the piece's distance from it (Farin, "Curves and Surfaces for CAGD", 5th ed.,
ch. 5 and 13: de Casteljau subdivision, rational convex hull)."""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np

from ..curves.base import Curve
from ..curves.bspline import BSplineCurve


# --- Bezier pieces in homogeneous form (x w, y w, w) ----------------------------------------
def _hom_pieces(curve: BSplineCurve) -> Tuple[np.ndarray, np.ndarray]:
    """(breaks (m + 1,), nets (m, p + 1, 3)) of a 2-D curve: its Bezier pieces with the
    weight as a third coordinate (1 for a polynomial curve)."""
    breaks, nets = curve.bezier_net()
    if not curve.is_rational:
        nets = np.concatenate([nets, np.ones(nets.shape[:-1] + (1,))], axis=-1)
    return breaks, nets


def _end(c: Curve, side: int) -> np.ndarray:
    """``c(c.domain[side])`` (side 0: the start, 1: the end): for a clamped end of a
    B-spline its control point, which evaluation gives there bit for bit
    (:meth:`cagd.BSplineCurve._clamped_ends`), without the evaluation."""
    if isinstance(c, BSplineCurve) and not c.periodic:
        u, p, n = c._u, c.degree, len(c._hom)
        if (u[0] == u[p]) if side == 0 else (u[-1] == u[n]):
            return np.array(c.control_points[0 if side == 0 else -1], dtype=np.float64)
    return c(c.domain[side])


def _halves(Q: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """de Casteljau at 1/2 of many homogeneous nets (k, p + 1, 3): the two halves."""
    left, right = [Q[:, 0]], [Q[:, -1]]
    cur = Q
    for _ in range(Q.shape[1] - 1):
        cur = 0.5 * (cur[:, :-1] + cur[:, 1:])
        left.append(cur[:, 0])
        right.append(cur[:, -1])
    return np.stack(left, axis=1), np.stack(right[::-1], axis=1)


def _cartesian(Q: np.ndarray) -> np.ndarray:
    return Q[..., :2] / Q[..., 2:]


def orient(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Twice the signed area of the triangle (p, q, r) in the plane: > 0 counter-clockwise
    (points (..., 2), broadcast)."""
    return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points p to segments [a, b] (broadcast over leading axes)."""
    d = b - a
    dd = np.einsum("...i,...i->...", d, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(dd > 0, np.einsum("...i,...i->...", p - a, d) / np.where(dd > 0, dd, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    q = a + t[..., None] * d
    return np.linalg.norm(p - q, axis=-1)


def _hull_bound(Q: np.ndarray) -> np.ndarray:
    """Distance bound of each piece from its chord: the largest distance of a Cartesian
    control point from the chord (the curve lies in their convex hull)."""
    P = _cartesian(Q)
    a, b = P[:, :1], P[:, -1:]
    return _segment_distance(P, a, b).max(axis=1)


Chain = Tuple[int, List[BSplineCurve], List[int]]


def closed_chains(loops: Sequence[Sequence[BSplineCurve]]) -> List[Chain]:
    """Per loop (its index, its curves with a straight closer inserted after each curve
    whose end is not exactly the next one's start, their names: the curve's index in
    the loop, -1 for a closer)."""
    chains: List[Chain] = []
    for i, loop in enumerate(loops):
        chain: List[BSplineCurve] = []
        names: List[int] = []
        for j, c in enumerate(loop):
            chain.append(c)
            names.append(j)
            end, start = _end(c, 1), _end(loop[(j + 1) % len(loop)], 0)
            if np.any(end != start):
                chain.append(BSplineCurve(np.stack([end, start]), 1))
                names.append(-1)
        chains.append((i, chain, names))
    return chains


def _crossings(pu: np.ndarray, pv: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed crossings (+1 upwards, -1 downwards) of the chords a -> b with the ray
    from (pu, pv) along +u, half-open in v (a chord counts at its lower end only)."""
    av, bv = a[..., 1], b[..., 1]
    up = (av <= pv) & (pv < bv)
    down = (bv <= pv) & (pv < av)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[..., 0] + (pv - av) * (b[..., 0] - a[..., 0]) / (bv - av)
    hit = (up | down) & (x > pu)
    return np.where(hit, np.where(up, 1, -1), 0).astype(np.int64)
