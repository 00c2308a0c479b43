"""Bezier form of a B-spline, span by span, and the stable evaluation above the power
form's degree (issue 14).

:func:`bezier_spans` gives the Bezier control points of every non-empty span of a
B-spline as blossom values b_j = f(a^(p-j), b^j) on the span [a, b] (Ramshaw; seed 003,
2.2.4; the result of knot insertion to multiplicity p, Piegl & Tiller A5.6), computed by
de Boor's recursion with a's first and then b's, vectorized over all spans: O(p^2) numpy
calls, O(s p^3) arithmetic, memory O(s p), no global insertion.

:class:`BernsteinSpans` evaluates such nets by the direct Bernstein sum
sum_i P_i C(p,i) x^i (1-x)^(p-i), x = (t - a)/(b - a): every term is computed to a few
ulps and all terms are non-negative, so the error is ~ p ulps of the control net
(de Casteljau's accuracy at O(p) rather than O(p^2) work per point).
"""
from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np

from .._checks import frozen
from ..basis.bernstein import bernstein_values
from .._value import Value

_CHUNK_VALUES = 1 << 22      # gathered net values per evaluation chunk (32 MiB of float64)


def bezier_spans(knots: np.ndarray, degree: int, points: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Breaks (s+1,) and Bezier nets (s, p+1, D) of the s non-empty spans of the
    B-spline (knots, degree, points) with len(knots) = len(points) + degree + 1.

    De Boor's step at level L on span i, for k = i-p+L..i:
    P_k^L = ((u_{k+p+1-L} - t) P_{k-1}^{L-1} + (t - u_k) P_k^{L-1}) / (u_{k+p+1-L} - u_k),
    with t = a for the first levels and t = b for the rest (the blossom is symmetric)."""
    u = np.asarray(knots, dtype=np.float64)
    P = np.asarray(points, dtype=np.float64)
    n, p = P.shape[0], degree
    span = np.flatnonzero(u[p:n] < u[p + 1:n + 1]) + p
    a, b = u[span], u[span + 1]
    breaks = np.concatenate([a, b[-1:]])
    if p == 0:
        return breaks, P[span][:, None, :]
    # local control points P_{i-p..i} and knots u_{i-p+1..i+p} of every span
    local = P[span[:, None] - p + np.arange(p + 1)]                      # (s, p+1, D)
    kn = u[span[:, None] - p + 1 + np.arange(2 * p)]                      # kn[:, m] = u_{i-p+1+m}
    if P.shape[1] > p + 1:
        # wide points (surface rows): the extraction matrices M_i (s, p+1, p+1) first,
        # O(s p^4), then nets = M_i P_local at O(s p^2 D) instead of O(s p^3 D)
        M = _blossom_nets(kn, a, b, np.broadcast_to(np.eye(p + 1), (len(span), p + 1, p + 1)), p)
        return breaks, np.einsum("sjk,skd->sjd", M, local)
    return breaks, _blossom_nets(kn, a, b, local, p)


def bezier_spans_many(knots: List[np.ndarray], degree: int,
                      points: List[np.ndarray]) -> List[Tuple[np.ndarray, np.ndarray]]:
    """:func:`bezier_spans` of several B-splines of one degree and point dimension D at
    once (one de Boor pass over all their spans; the same numbers, span by span),
    D <= degree + 1 (the narrow case of :func:`bezier_spans`)."""
    p = degree
    lens_u = np.array([len(u) for u in knots])
    lens_p = np.array([len(P) for P in points])
    U = np.concatenate([np.asarray(u, dtype=np.float64) for u in knots])
    P = np.concatenate([np.asarray(Q, dtype=np.float64) for Q in points])
    ou, op = np.cumsum(lens_u) - lens_u, np.cumsum(lens_p) - lens_p
    owner = np.repeat(np.arange(len(knots)), lens_u)
    i = np.arange(len(U)) - ou[owner]                         # the knot's index in its own vector
    nxt = np.minimum(np.arange(len(U)) + 1, len(U) - 1)
    span = np.flatnonzero((i >= p) & (i < lens_p[owner]) & (U < U[nxt]))
    cid = owner[span]
    a, b = U[span], U[span + 1]
    if p == 0:
        nets = P[op[cid] + i[span]][:, None, :]
    else:
        local = P[(op[cid] + i[span] - p)[:, None] + np.arange(p + 1)]
        kn = U[(span - p + 1)[:, None] + np.arange(2 * p)]
        nets = _blossom_nets(kn, a, b, local, p)
    cuts = np.searchsorted(cid, np.arange(len(knots) + 1))
    return [(np.concatenate([a[lo:hi], b[hi - 1:hi]]), nets[lo:hi]) for lo, hi in zip(cuts[:-1], cuts[1:])]


def _blossom_nets(kn: np.ndarray, a: np.ndarray, b: np.ndarray, local: np.ndarray, p: int) -> np.ndarray:
    """The Bezier points f(a^(p-j), b^j), j = 0..p, of every span from its local points
    (see :func:`bezier_spans`)."""

    def step(level_pts: np.ndarray, L: int, t: np.ndarray) -> np.ndarray:
        # level_pts: (s, p+2-L, D) holds P_k^{L-1} for k = i-p+L-1..i; returns P_k^L, k = i-p+L..i
        c = np.arange(p + 1 - L)                     # k = i-p+L+c
        lo = kn[:, L - 1 + c]                        # u_k         (index m = k - (i-p+1))
        hi = kn[:, p + c]                            # u_{k+p+1-L}
        alpha = ((t[:, None] - lo) / (hi - lo))[..., None]
        return (1.0 - alpha) * level_pts[:, :-1] + alpha * level_pts[:, 1:]

    nets = np.empty((local.shape[0], p + 1, local.shape[2]))
    level = local
    for r in range(p + 1):                           # r levels of a, then p - r levels of b
        if r:
            level = step(level, r, a)
        cur = level
        for L in range(r + 1, p + 1):
            cur = step(cur, L, b)
        nets[:, p - r] = cur[:, 0]
    return nets


class BernsteinSpans(Value):
    """A piecewise polynomial held as Bezier nets (s, p+1, D) on ``breaks`` (s+1,),
    evaluated by the Bernstein sum (see the module doc)."""

    def __init__(self, breaks: np.ndarray, nets: np.ndarray):
        self.breaks = frozen(np.ascontiguousarray(breaks, dtype=np.float64))
        self.nets = frozen(np.ascontiguousarray(nets, dtype=np.float64))
        self.degree = self.nets.shape[1] - 1
        self.dim = self.nets.shape[2]

    def derived(self, order: int) -> "BernsteinSpans":
        """The ``order``-th derivative: hodographs p (P_{i+1} - P_i) / (b - a) per span
        (seed 000, 5.2.1 property 4), applied ``order`` times; zero above the degree."""
        nets, p = self.nets, self.degree
        if order > p:
            return BernsteinSpans(self.breaks, np.zeros((nets.shape[0], 1, nets.shape[2])))
        inv_h = (1.0 / np.diff(self.breaks))[:, None, None]
        for k in range(order):
            nets = (p - k) * np.diff(nets, axis=1) * inv_h
        return BernsteinSpans(self.breaks, nets)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """Values at the flat parameter array ``t`` (clipped into the breaks): (len(t), dim)."""
        t = np.asarray(t, dtype=np.float64).ravel()
        p, D = self.degree, self.dim
        out = np.empty((t.shape[0], D))
        step = max(1, _CHUNK_VALUES // ((p + 1) * max(D, 1)))
        last = len(self.breaks) - 2
        for s in range(0, t.shape[0], step):
            tc = t[s:s + step]
            j = np.clip(np.searchsorted(self.breaks, tc, side="right") - 1, 0, last)
            lo, hi = self.breaks[j], self.breaks[j + 1]
            x = np.clip((tc - lo) / (hi - lo), 0.0, 1.0)
            out[s:s + step] = np.einsum("mi,mid->md", bernstein_values(p, x), self.nets[j])
        return out


def refined_points(knots: np.ndarray, degree: int, points: np.ndarray,
                   new_knots: np.ndarray) -> Optional[np.ndarray]:
    """Control points of the same B-spline on the refined full knot vector ``new_knots``
    (which contains ``knots``): Q_j = f(v_{j+1}, ..., v_{j+p}), the blossom of the piece
    on the old span holding a non-empty new span [v_k, v_{k+1}), j <= k <= j+p (knot
    refinement, Piegl & Tiller 5.3; Ramshaw's blossoming, seed 003, 2.2.4), by de Boor's
    recursion with argument v_{j+r} at level r, vectorized over all j: O(m p^2) work,
    O(m p) memory, no repeated insertions. None when some new basis function's support
    holds no domain span (possible only with repeated knots at an unclamped end; then
    insert one by one)."""
    u = np.asarray(knots, dtype=np.float64)
    v = np.asarray(new_knots, dtype=np.float64)
    P = np.asarray(points, dtype=np.float64)
    n, p = P.shape[0], degree
    m = len(v) - p - 1
    if p == 0:
        span = np.clip(np.searchsorted(u, v[:m], side="right") - 1, 0, n - 1)
        return P[span]
    j = np.arange(m)
    # a non-empty new span k in [j, j+p] (clamped to the domain spans p..m-1)
    nonempty = np.flatnonzero(v[p:m] < v[p + 1:m + 1]) + p              # sorted
    pos = np.searchsorted(nonempty, j, side="left")
    k = nonempty[np.minimum(pos, len(nonempty) - 1)]
    k = np.where(k > j + p, nonempty[np.maximum(pos - 1, 0)], k)
    if np.any((k < j) | (k > j + p)):
        # a new basis function whose support misses the domain (repeated knots at a
        # floating end): its control point is no blossom value of a domain piece
        return None
    # the old span i with u_i <= v_k < u_{i+1}, restricted to the domain spans p..n-1
    i = np.clip(np.searchsorted(u, v[k], side="right") - 1, p, n - 1)
    last = n - 1
    while u[last] == u[last + 1]:
        last -= 1
    i = np.minimum(i, last)
    level = P[i[:, None] - p + np.arange(p + 1)]                         # (m, p+1, D)
    kn = u[i[:, None] - p + 1 + np.arange(2 * p)]                         # kn[:, q] = u_{i-p+1+q}
    for r in range(1, p + 1):
        x = v[j + r][:, None]
        c = np.arange(p + 1 - r)
        lo, hi = kn[:, r - 1 + c], kn[:, p + c]
        alpha = ((x - lo) / (hi - lo))[..., None]
        level = (1.0 - alpha) * level[:, :-1] + alpha * level[:, 1:]
    return level[:, 0]
