"""Crossings of a curve network, all pairs at once (for :func:`cagd.gordon`).

Every profile f_i must meet every guide g_j once. Most networks are grid-like: the
two curves of a pair cross at a clear angle. For those the crossing is found and proven
unique without the general subdivision of :func:`cagd.intersect`:

- Candidates: the Bezier spans of f and g whose bounding boxes come within tol (a
  curve lies in the convex hull of each span's control points, weights positive).
  Every point where the curves come within tol lies in a candidate pair of spans.
- Uniqueness (the hodograph cone test, Sederberg & Meyers 1988, "Loop detection in
  surface patch intersections", in its curve form): over the candidate span ranges
  every tangent of f lies in the cone of the consecutive control-point differences of
  those spans (for rational spans too: Floater 1992, the derivative of a rational
  Bezier curve is a positive combination of P_j - P_i, j > i). With the double cones of
  f and g apart by an angle beta > 0, two points where the curves come within tol,
  f(s_k) - g(t_k) = e_k, give f(s2) - f(s1) = g(t2) - g(t1) + e2 - e1 with the left in
  f's cone and the first right term in g's, so |f(s2) - f(s1)| <= 2 tol / sin(beta):
  one crossing, up to the tolerance.
- The crossing: Gauss-Newton on |f(s) - g(t)|^2 from the nearest samples of the
  candidate spans, all pairs at once (one evaluation per curve and round).

Pairs where any step does not apply (no candidates, cones that meet, as on a closed
curve or a tangential contact, Newton ending outside the candidates or farther than
tol) are left to the caller's general solver.
"""
from __future__ import annotations

from typing import List, Tuple

import numpy as np

from ..curves.bspline import BSplineCurve

SPAN_SAMPLES = 8          # samples per Bezier span for the starting points
NEWTON_ROUNDS = 40        # Gauss-Newton rounds, at most
STEP_TOL = 1e-15          # ... ending once every step is below this (parameters on [0, 1])
CONE_MARGIN = 1e-6        # radians the double cones must stay apart beyond their half-angles
DEGENERATE = 1e-300       # a control-point difference or a determinant below this is no direction


class _Prepared:
    """One curve's spans: breaks, bounding boxes, unit control-point differences (of the
    Bezier nets of a rational curve; of the poles acting on the span for a polynomial one,
    whose hull and hodograph cone hold the span too: Piegl & Tiller 3.2, 3.3), and
    SPAN_SAMPLES samples per span."""

    def __init__(self, c: BSplineCurve):
        self.curve = c
        if c.is_rational:
            breaks, nets = c.bezier_net()
            P = nets[..., :-1] / nets[..., -1:]
        else:       # span i lies in the hull of poles i-p..i, its tangents in their differences' cone
            U, p = c.knots, c.degree
            spans = np.flatnonzero(U[p:-p - 1] < U[p + 1:-p]) + p
            breaks = np.append(U[spans], U[-1])
            P = c.control_points[spans[:, None] - p + np.arange(p + 1)]
        self.breaks = breaks
        self.lo, self.hi = P.min(axis=1), P.max(axis=1)
        d = np.diff(P, axis=1)
        length = np.linalg.norm(d, axis=-1, keepdims=True)
        self.directions = np.where(length > DEGENERATE, d / np.maximum(length, DEGENERATE), 0.0)
        self.flat = (length[..., 0] <= DEGENERATE).any(axis=1)        # spans with a repeated point
        frac = np.arange(SPAN_SAMPLES) / SPAN_SAMPLES
        self.params = (breaks[:-1, None] + np.diff(breaks)[:, None] * frac).ravel()
        self.points = c(self.params)
        self.span = np.repeat(np.arange(len(breaks) - 1), SPAN_SAMPLES)


def _cone(prep: _Prepared, first: int, last: int) -> Tuple[np.ndarray, float]:
    """(axis, half-angle) of a circular cone holding every direction of spans first..last,
    or half-angle pi when they do not fit in a half-space around their mean."""
    if prep.flat[first:last + 1].any():
        return np.zeros(prep.lo.shape[1]), np.pi
    d = prep.directions[first:last + 1].reshape(-1, prep.lo.shape[1])
    axis = d.sum(axis=0)
    norm = float(np.linalg.norm(axis))
    if norm <= DEGENERATE:
        return axis, np.pi
    axis = axis / norm
    cos = d @ axis
    if cos.min() <= 0.0:
        return axis, np.pi
    return axis, float(np.arccos(min(1.0, cos.min())))


def _box_gap(a: _Prepared, b: _Prepared) -> np.ndarray:
    """Distances between the span boxes of a (rows) and b (columns)."""
    gap = np.maximum(0.0, np.maximum(a.lo[:, None] - b.hi[None], b.lo[None] - a.hi[:, None]))
    return np.linalg.norm(gap, axis=-1)


def network_crossings(profiles: List[BSplineCurve], guides: List[BSplineCurve], tol: float
                      ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(s, t, miss, proven) arrays (m, n): the crossing parameters of every profile-guide
    pair, their distance, and whether the pair was settled here (module docstring);
    unsettled pairs hold NaN."""
    m, n = len(profiles), len(guides)
    A, B = [_Prepared(c) for c in profiles], [_Prepared(c) for c in guides]
    S, T = np.full((m, n), np.nan), np.full((m, n), np.nan)
    ranges = np.zeros((m, n, 4), int)
    usable = np.zeros((m, n), bool)
    for i, a in enumerate(A):
        for j, b in enumerate(B):
            near = _box_gap(a, b) <= tol
            if not near.any():
                continue
            ra, rb = np.flatnonzero(near.any(axis=1)), np.flatnonzero(near.any(axis=0))
            (ax, ha), (bx, hb) = _cone(a, ra[0], ra[-1]), _cone(b, rb[0], rb[-1])
            apart = float(np.arccos(min(1.0, abs(float(ax @ bx)))))
            if not apart > ha + hb + CONE_MARGIN:
                continue
            sa, sb = np.isin(a.span, ra), np.isin(b.span, rb)        # samples of the candidate spans
            d = np.linalg.norm(a.points[sa][:, None] - b.points[sb][None], axis=-1)
            k, l = np.unravel_index(int(np.argmin(d)), d.shape)
            S[i, j], T[i, j] = a.params[sa][k], b.params[sb][l]
            ranges[i, j] = ra[0], ra[-1], rb[0], rb[-1]
            usable[i, j] = True
    if not usable.any():
        return S, T, np.full((m, n), np.nan), usable
    S, T, miss = _newton(profiles, guides, np.where(usable, S, 0.0), np.where(usable, T, 0.0))
    # the crossing must lie in the candidate spans (where the cones hold)
    span_a = np.stack([np.clip(np.searchsorted(a.breaks, S[i], side="right") - 1, 0, len(a.lo) - 1)
                       for i, a in enumerate(A)])
    span_b = np.stack([np.clip(np.searchsorted(b.breaks, T[:, j], side="right") - 1, 0, len(b.lo) - 1)
                       for j, b in enumerate(B)], axis=1)
    inside = ((span_a >= ranges[..., 0]) & (span_a <= ranges[..., 1])
              & (span_b >= ranges[..., 2]) & (span_b <= ranges[..., 3]))
    proven = usable & inside & (miss <= tol)
    return np.where(proven, S, np.nan), np.where(proven, T, np.nan), np.where(proven, miss, np.nan), proven


def _jet(c: BSplineCurve, t: np.ndarray) -> np.ndarray:
    """(point, first derivative) at t in the curve's domain, from its cached pp form and
    that form's own derivative (enough for Newton steps; the Bernstein path above the pp
    form's degree limit)."""
    if c._by_bernstein:
        return c.derivatives(t, 1)
    H, dH = c.ppform(t), c.ppform(t, 1)
    if not c.is_rational:
        return np.stack([H, dH])
    w, dw = H[:, -1:], dH[:, -1:]
    P = H[:, :-1] / w
    return np.stack([P, (dH[:, :-1] - P * dw) / w])


def _newton(profiles: List[BSplineCurve], guides: List[BSplineCurve], S: np.ndarray, T: np.ndarray
            ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss-Newton on |f_i(s) - g_j(t)|^2 for every pair at once, s and t held in [0, 1]:
    (s, t, distance)."""
    for _ in range(NEWTON_ROUNDS):
        F = np.stack([_jet(f, S[i]) for i, f in enumerate(profiles)], axis=1)        # (2, m, n, dim)
        G = np.stack([_jet(g, T[:, j]) for j, g in enumerate(guides)], axis=2)
        D, fd, gd = F[0] - G[0], F[1], G[1]
        a, b, c = (fd * fd).sum(-1), -(fd * gd).sum(-1), (gd * gd).sum(-1)
        r1, r2 = -(fd * D).sum(-1), (gd * D).sum(-1)
        det = a * c - b * b
        ok = np.abs(det) > DEGENERATE
        safe = np.where(ok, det, 1.0)
        ds, dt = np.where(ok, (r1 * c - b * r2) / safe, 0.0), np.where(ok, (a * r2 - b * r1) / safe, 0.0)
        S2, T2 = np.clip(S + ds, 0.0, 1.0), np.clip(T + dt, 0.0, 1.0)
        step = max(float(np.abs(S2 - S).max()), float(np.abs(T2 - T).max()))
        S, T = S2, T2
        if step <= STEP_TOL:
            break
    P = np.stack([f(S[i]) for i, f in enumerate(profiles)])
    Q = np.stack([g(T[:, j]) for j, g in enumerate(guides)], axis=1)
    return S, T, np.linalg.norm(P - Q, axis=-1)
