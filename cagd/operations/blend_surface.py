"""Blend surfaces between two surface edges and edge matching (issue 18): the surface
analogues of :func:`cagd.blend_curve` (Farin, Curves and Surfaces for CAGD, 14.1 and
16.5 on G1/G2 joins and Hermite-type blends; Piegl & Tiller, The NURBS Book, 3.4
(derivatives of a B-spline surface at a boundary), 5.3 and 5.5 (knot refinement and
degree elevation for compatible knot vectors)).

Edges are named as in :func:`cagd.edge_continuity`: "u0" (u = u_min, running in v),
"u1", "v0", "v1". At an edge of a clamped B-spline/NURBS surface with cross degree p,
control rows P_0 (the edge), P_1, P_2 (rows counted from the edge) and cross knots at
distances d_1 = |u_(p+1) - u_edge|, d_2 = |u_(p+2) - u_edge| from it, the boundary
derivatives with respect to the inward cross parameter s (Piegl & Tiller eq. 3.17
applied to the rows) are B-spline curves in the along-edge parameter with the rows

    H   = P_0,
    H_s = p / d_1 (P_1 - P_0),
    H_ss = p (p - 1) / d_1 ((P_2 - P_1) / d_2 - (P_1 - P_0) / d_1)

(homogeneous rows (w P, w) for a NURBS: the projected surface's derivatives up to order
k at the edge depend only on the homogeneous ones, so everything below is done on them
and rational surfaces are handled exactly). The along-edge curves of the two sides are
made compatible (one degree, one knot vector, linear maps of the edges' domains onto
each other) by degree elevation and knot refinement, which keep them exactly.

blend_surface: the blend B(u, v) has u along edge1 (its domain mapped onto [0, 1]) and
v across, a Bezier of degree n = 2k + 1 in v (3 for G1, 5 for G2) with the rows

    R_0 = H1, R_1 = R_0 + (a / n) D1, R_2 = 2 R_1 - R_0 + a^2 / (n (n - 1)) H1_ss,
    R_n = H2, R_(n-1) = R_n - (b / n) H2_s, R_(n-2) = 2 R_(n-1) - R_n + b^2 / (n (n - 1)) H2_ss,

D1 = -H1_s the derivative leaving s1, H2_s the one entering s2 (Farin's Hermite
construction: B_v(u, 0) = a D1, B_vv(u, 0) = a^2 H1_ss). B then agrees to order k with
s1 reparametrised by s = -a v (and with s2 by s = b (v - 1)) with the along-edge
parameter kept, i.e. it is C^k across both edges up to a constant parameter scale,
which implies G^k (G2 by the linkage curve theorem: Pegna and Wolter, J. Mech. Des.
114, 1992). The scales a, b are constant along the edge: a = alpha d / m1 with d the
mean distance between corresponding edge points, m1 the mean |D1| (projected) at 50
stations, so the first control leg is about d / n long (blend_curve's chord / degree);
(alpha, beta) = ``tangent_scales``, default (1, 1). For rational data the Hermite rows
are those of phi(t) H instead of H (phi(0) = 1, phi'(0), phi''(0) constants fitted to keep
the new rows' weights flat; the same projected surface, so nothing above changes): the
weights of the inner rows are R_1's w_0 + (phi' w_0 - a w_s) / n etc., and when the
weights vary fast across an edge (w_s, w_ss large against w_0) and the scale is large
they can still turn non-positive. Then the default scale of that side is shortened to
WEIGHT_MARGIN times the largest scale that keeps them positive (the message says so),
and explicit ``tangent_scales`` are refused (CagdError naming tangent_scales[0] or [1]
and the value below which the weights stay positive). Polynomial surfaces and weights
that are products of a function along and one across the edge (surfaces of
revolution, extrusions of conics: phi makes those flat exactly) have no such limit.

match_surface: rows 0..k of ``s`` next to ``edge`` are replaced so that s meets
``target`` at ``target_edge`` with C^k up to constant scales: row 0 = rho T0 (T the
target's homogeneous edge rows, rho the least-squares weight level of s's edge row, 1
for polynomials), and s's inward derivatives -lambda rho T_s, lambda^2 rho T_ss, lambda =
|H_s| / |rho T_s| the ratio of the norms of s's own inward derivative rows and the new
direction's (the cross-parameter scale of s kept; exact when they are proportional, so a
pair that already meets with C^k up to a constant scale is left unchanged). Rows beyond
k are those of s after the refinement that made its along-edge knots compatible with
the target's.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .. import _checks
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from .blend import _continuity, _scales
from .continuity import CONTINUITY_TOL

#: stations along an edge at which the results are measured (the issue's oracle: 50)
STATIONS = 50
#: an edge (or an edge distance) shorter than this times the size counts as a point
DEGENERATE_TOL = 1e-12
#: the fraction of the largest admissible scale used when the default tangent scale
#: would give a rational blend non-positive weights
WEIGHT_MARGIN = 0.5


@dataclass(frozen=True)
class BlendSurface:
    """A blend surface and what it achieves along both edges.

    surface: the blend, u along edge1 (edge1's domain mapped onto [0, 1]), v across
    (v = 0 on edge1, v = 1 on edge2), degree 2k + 1 in v; continuity: k (1 or 2);
    max_angle: the largest tangent-plane angle (radians) across both edges at
    STATIONS stations (:func:`cagd.edge_continuity`); max_curvature_gap: for G2 the
    largest relative difference |k1 - k2| / max(|k1|, |k2|, 1 / size) of the normal
    curvatures across the edges (direction n x T, T the edge tangent), None for G1;
    max_gap: the largest position gap; reversed: edge2 runs against edge1 (the blend's
    v = 1 edge is edge2 traversed backwards); converged: all the measurements within
    CONTINUITY_TOL (gaps relative to the size); message: a summary.
    """
    surface: BSplineSurface
    continuity: int
    max_angle: float
    max_curvature_gap: Optional[float]
    max_gap: float
    reversed: bool
    converged: bool
    message: str


@dataclass(frozen=True)
class MatchSurface:
    """``s`` modified next to one edge to meet a target surface, and the measurements.

    surface: the modified s (same domain; the along-edge direction may have more
    poles, a higher degree, and becomes rational when the target is); continuity: k
    (0, 1, 2); max_angle, max_curvature_gap (None unless k = 2), max_gap, reversed,
    converged, message: as in :class:`BlendSurface`, measured between the result and
    the target (max_angle is reported for k = 0 too but not required); moved_rows: the
    control rows replaced (k + 1, counted from the edge); poles_along: the along-edge
    pole count (before, after) of s.
    """
    surface: BSplineSurface
    continuity: int
    max_angle: float
    max_curvature_gap: Optional[float]
    max_gap: float
    reversed: bool
    converged: bool
    message: str
    moved_rows: int
    poles_along: Tuple[int, int]


# --- arguments ------------------------------------------------------------------------------
def _surface(s: object, name: str) -> BSplineSurface:
    from ..surfaces.trimmed import TrimmedSurface
    if not isinstance(s, Surface):
        raise CagdError(f"{name}: must be a cagd Surface, got {type(s).__name__}")
    if not s.rectangular or isinstance(s, TrimmedSurface):
        raise CagdError(f"{name}: a {type(s).__name__} has no parameter-box edges u0/u1/v0/v1 to blend; "
                        f"pass a plain rectangular surface (a TrimmedSurface's untrimmed surface)")
    if s.dim != 3:
        raise CagdError(f"{name}: blends and matches are built for 3-D surfaces, this one is {s.dim}-D")
    try:
        b = s.to_nurbs()
    except NotImplementedError:
        raise CagdError(f"{name}: a {type(s).__name__} has no exact NURBS form") from None
    return b.clamped() if (b.periodic_u or b.periodic_v) else b


def _edge(e: object, name: str) -> str:
    from ..surfaces.continuity import EDGES             # (at import time: a cycle through cagd.operations)
    if not isinstance(e, str) or e not in EDGES:
        raise CagdError(f"{name}: must be one of {EDGES}, got {e!r}")
    return e


# --- the net seen from one edge -----------------------------------------------------------------
@dataclass(frozen=True)
class _Side:
    """A clamped surface's homogeneous net seen from ``edge``: net[i, j] is row i counted
    from the edge, pole j along it; dist the cross knots' distances from the edge (p + 1
    zeros first); along the along-edge knots (the surface's own), q their degree."""
    net: np.ndarray
    dist: np.ndarray
    p: int
    along: np.ndarray
    q: int


def _side(b: BSplineSurface, edge: str, homogeneous: bool) -> _Side:
    P = b.control_points
    if homogeneous:
        W = np.ones(P.shape[:2]) if b.weights is None else b.weights
        P = np.concatenate([P * W[..., None], W[..., None]], axis=2)
    if edge[0] == "u":
        net, cross, p, along, q = P, b.knots_u, b.degree_u, b.knots_v, b.degree_v
    else:
        net, cross, p, along, q = P.transpose(1, 0, 2), b.knots_v, b.degree_v, b.knots_u, b.degree_u
    cross = np.asarray(cross, dtype=float)
    if edge[1] == "1":
        net, dist = net[::-1], cross[-1] - cross[::-1]
    else:
        dist = cross - cross[0]
    return _Side(np.ascontiguousarray(net), dist, p, np.asarray(along, dtype=float), q)


def _derivative_rows(side: _Side, k: int) -> np.ndarray:
    """(k + 1, poles, D): the rows of H, H_s, H_ss at the edge, s the inward cross
    parameter (module docstring)."""
    N, d, p = side.net, side.dist, side.p
    out = [N[0]]
    if k >= 1:
        out.append(p / d[p + 1] * (N[1] - N[0]))
    if k >= 2:
        if p >= 2:
            out.append(p * (p - 1) / d[p + 1] * ((N[2] - N[1]) / d[p + 2] - (N[1] - N[0]) / d[p + 1]))
        else:
            out.append(np.zeros_like(N[0]))
    return np.stack(out)


def _rows_from_derivatives(R: np.ndarray, dist: np.ndarray, p: int) -> np.ndarray:
    """The inverse of :func:`_derivative_rows`: control rows 0..k from H, H_s, H_ss."""
    out = [R[0]]
    if len(R) >= 2:
        out.append(R[0] + dist[p + 1] / p * R[1])
    if len(R) >= 3:
        out.append(out[1] + dist[p + 2] * (R[2] * dist[p + 1] / (p * (p - 1)) + (out[1] - out[0]) / dist[p + 1]))
    return np.stack(out)


def _unit(knots: np.ndarray, q: int) -> np.ndarray:
    a, b = knots[q], knots[-q - 1]
    t = (knots - a) / (b - a)
    t[:q + 1], t[-q - 1:] = 0.0, 1.0
    return t


def _along_curve(rows: np.ndarray, knots01: np.ndarray, q: int, reverse: bool = False) -> BSplineCurve:
    """Rows (r, poles, D) as one polynomial curve on [0, 1] along the edge whose points
    are the r rows' poles side by side (r D coordinates)."""
    pts = rows.transpose(1, 0, 2).reshape(rows.shape[1], -1)
    if reverse:
        pts, knots01 = pts[::-1], (1.0 - knots01)[::-1]
    return BSplineCurve(np.ascontiguousarray(pts), q, knots01)


def _from_along(c: BSplineCurve, rows: int) -> np.ndarray:
    P = c.control_points
    return P.reshape(P.shape[0], rows, -1).transpose(1, 0, 2)


def _compatible(curves: List[BSplineCurve]) -> List[BSplineCurve]:
    from ..surfaces.loft import compatible_plain
    return compatible_plain(curves)


# --- evaluation at stations -------------------------------------------------------------------
def _project(c: BSplineCurve, rows: int, t: np.ndarray, rational: bool) -> Tuple[np.ndarray, np.ndarray]:
    """Projected points and first cross derivatives at t of the along-edge curve whose
    rows are (H, H_s, ...): (len(t), 3) each."""
    V = c(t).reshape(len(t), rows, -1)
    if not rational:
        return V[:, 0], V[:, 1] if rows > 1 else np.zeros_like(V[:, 0])
    w = V[:, 0, -1:]
    S = V[:, 0, :-1] / w
    if rows == 1:
        return S, np.zeros_like(S)
    return S, (V[:, 1, :-1] - V[:, 1, -1:] * S) / w


def _mean_norm(x: np.ndarray) -> float:
    return float(np.mean(np.linalg.norm(x, axis=-1)))


def _reversed_edges(A: np.ndarray, B: np.ndarray) -> bool:
    """Whether edge B (points at the stations) runs against edge A: its points taken
    backwards are closer to A's on average (closed edges too, unlike a corner test)."""
    straight = np.linalg.norm(A - B, axis=-1).sum()
    crossed = np.linalg.norm(A - B[::-1], axis=-1).sum()
    return bool(crossed < straight)


def _normalised(*surfaces: BSplineSurface) -> Tuple[float, List[BSplineSurface]]:
    """(f, the surfaces scaled by f): f the power of two that brings the larger size near
    1, so that squares of coordinates and derivatives neither overflow nor underflow
    (the scaling is exact, and undone exactly on the result)."""
    size = max(float(s.size) for s in surfaces)
    f = float(np.ldexp(1.0, -int(np.clip(np.frexp(size)[1], -1020, 1020))))
    if f == 1.0:
        return f, list(surfaces)
    return f, [s._affine(np.eye(3) * f, np.zeros(3)) for s in surfaces]


def _scaled_back(s: BSplineSurface, f: float) -> BSplineSurface:
    return s if f == 1.0 else s._affine(np.eye(3) / f, np.zeros(3))


def _cross_span(s: BSplineSurface, edge: str) -> float:
    (u0, u1), (v0, v1) = s.domain
    return (u1 - u0) if edge[0] == "u" else (v1 - v0)


def _edge_length(S: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(S, axis=0), axis=-1).sum())


def _edge_params(s: Surface, edge: str, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    (u0, u1), (v0, v1) = s.domain
    if edge[0] == "u":
        return np.full_like(t, u0 if edge == "u0" else u1), v0 + t * (v1 - v0)
    return u0 + t * (u1 - u0), np.full_like(t, v0 if edge == "v0" else v1)


def _cross_curvatures(s: Surface, edge: str, t: np.ndarray, n: Optional[np.ndarray] = None,
                      d: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Normal curvatures II(w, w) / I(w, w) of s at its edge stations t in the direction
    d (default n x T, T the along-edge tangent, n the unit normal), S_u w_u + S_v w_v = d
    solved in the least-squares sense, II taken with the normal n (default s's own).
    Returns (kappa, n, d)."""
    u, v = _edge_params(s, edge, t)
    D = s.derivatives(u, v, 2, 2)
    Su, Sv = D[1, 0], D[0, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        if n is None or d is None:
            c = np.cross(Su, Sv)
            n = c / np.linalg.norm(c, axis=-1, keepdims=True)
            T = Sv if edge[0] == "u" else Su
            d = np.cross(n, T)
        E, F, G = (np.einsum("ij,ij->i", a, b) for a, b in ((Su, Su), (Su, Sv), (Sv, Sv)))
        bu, bv = np.einsum("ij,ij->i", Su, d), np.einsum("ij,ij->i", Sv, d)
        det = E * G - F * F
        wu, wv = (G * bu - F * bv) / det, (E * bv - F * bu) / det
        L, M, N = (np.einsum("ij,ij->i", X, n) for X in (D[2, 0], D[1, 1], D[0, 2]))
        k = (L * wu * wu + 2 * M * wu * wv + N * wv * wv) / (E * wu * wu + 2 * F * wu * wv + G * wv * wv)
    return k, n, d


def curvature_gap(s1: Surface, edge1: str, s2: Surface, edge2: str, reverse: bool = False,
                  samples: int = STATIONS) -> float:
    """The largest relative difference |k1 - k2| / max(|k1|, |k2|, 1 / size) of the
    normal curvatures of s1 and s2 across their shared edge, in the direction n1 x T1
    (n1 the unit normal of s1, T1 its edge tangent), both taken with the normal n1 (so
    that a G1 pair with opposite orientations compares like for like), at ``samples``
    equally spaced fractions of the edges (the second at 1 - t when ``reverse``);
    stations where a normal is undefined (:meth:`Surface.normals`) are skipped (nan when none is left). Two
    surfaces meeting G1 are G2 exactly when this vanishes (the linkage curve theorem).

    Raises:
        CagdError: not rectangular 3-D surfaces, an unknown edge, samples < 2."""
    for name, s in (("s1", s1), ("s2", s2)):
        if not isinstance(s, Surface) or not s.rectangular or s.dim != 3:
            raise CagdError(f"{name}: must be a rectangular 3-D cagd Surface, got {type(s).__name__}")
    edge1, edge2 = _edge(edge1, "edge1"), _edge(edge2, "edge2")
    samples = _checks.integer(samples, "samples", 2, _checks.MAX_SAMPLES)
    t = np.linspace(0.0, 1.0, samples)
    t2 = t[::-1].copy() if reverse else t
    k1, n, d = _cross_curvatures(s1, edge1, t)
    k2, _, _ = _cross_curvatures(s2, edge2, t2, n, d)
    size = max(float(s1.size), float(s2.size))
    ok = np.isfinite(k1) & np.isfinite(k2) & s1.normals(*_edge_params(s1, edge1, t))[1] \
        & s2.normals(*_edge_params(s2, edge2, t2))[1]
    if not ok.any():
        return float("nan")
    gaps = np.abs(k1[ok] - k2[ok]) / np.maximum(np.maximum(np.abs(k1[ok]), np.abs(k2[ok])), 1.0 / size)
    return float(gaps.max())


def _measure(a: Surface, edge_a: str, b: Surface, edge_b: str, reverse: bool,
             k: int) -> Tuple[float, float, Optional[float], float]:
    """(tangent-plane angle, position gap, curvature gap or None, size) across the edge."""
    from ..surfaces.continuity import edge_continuity
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):   # extreme scales: inf/nan
        rep = edge_continuity(a, b, edge_a, edge_b, samples=STATIONS, reverse=reverse)
        gap = curvature_gap(a, edge_a, b, edge_b, reverse) if k == 2 else None
    return rep.normal_angle, rep.gap, gap, rep.size


def _reweighted(G: np.ndarray, ref: Optional[np.ndarray] = None) -> np.ndarray:
    """Homogeneous Hermite rows G = (H, H', H'') (derivatives along a cross parameter t;
    the last coordinate the weight) replaced by those of phi(t) H, phi(0) = 1 and the
    constants phi'(0), phi''(0) fitted (least squares over the poles) so that the weight
    rows of H' and H'' come as close as possible to ``ref``'s (default 0: weights as flat
    as possible across the edge). phi H projects onto the same surface as H, so every
    projected derivative is kept exactly; only the weights of the new rows change (they
    stay positive for larger tangent scales)."""
    if G.shape[0] < 2:
        return G
    w0 = G[0, :, -1]
    den = float(w0 @ w0)
    goal = np.zeros(G.shape[:2]) if ref is None else ref[..., -1]
    out = G.copy()
    phi1 = float((goal[1] - G[1, :, -1]) @ w0) / den
    out[1] = G[1] + phi1 * G[0]
    if G.shape[0] > 2:
        rest = G[2] + 2.0 * phi1 * G[1]
        phi2 = float((goal[2] - rest[:, -1]) @ w0) / den
        out[2] = rest + phi2 * G[0]
    return out


def _hermite_rows(H: np.ndarray, scale: float, n: int, rational: bool) -> np.ndarray:
    """The blend's control rows next to one edge, counted from it: Q_0 = E_0,
    Q_1 = Q_0 + E_1 / n, Q_2 = 2 Q_1 - Q_0 + E_2 / (n (n - 1)) for the Hermite data
    E_i = (-scale)^i H_(s^i) (derivatives along the blend's parameter running away from
    the edge, s = -scale t; reweighted when rational, :func:`_reweighted`)."""
    E = H * (-scale) ** np.arange(len(H))[:, None, None]
    if rational:
        E = _reweighted(E)
    Q = np.empty_like(E)
    Q[0] = E[0]
    if len(E) > 1:
        Q[1] = E[0] + E[1] / n
    if len(E) > 2:
        Q[2] = 2.0 * Q[1] - Q[0] + E[2] / (n * (n - 1))
    return Q


def _weight_limit(H: np.ndarray, scale: float, n: int) -> float:
    """The largest fraction of ``scale`` for which the rows of :func:`_hermite_rows`
    keep positive weights (they do as the scale goes to 0): halvings down to the first
    admissible power of two (0 if none above 2^-1000), then bisection above it."""
    def positive(x: float) -> bool:
        return bool(np.all(_hermite_rows(H, x * scale, n, True)[..., -1] > 0.0))

    lo = 1.0
    while not positive(lo):
        lo *= 0.5
        if lo < 2.0 ** -1000:
            return 0.0
    hi = 2.0 * lo
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if positive(mid):
            lo = mid
        else:
            hi = mid
    return lo


def _surface_from_net(P: np.ndarray, rational: bool, degree_u: int, degree_v: int, knots_u: np.ndarray,
                      knots_v: np.ndarray, name: str) -> BSplineSurface:
    if not rational:
        return BSplineSurface(P, degree_u, degree_v, knots_u, knots_v)
    W = P[..., -1]
    if not np.all(W > 0.0):
        raise CagdError(f"{name}: the constructed rows get non-positive weights (min {W.min():.3g}); "
                        f"the rational data's weights vary too fast across the edge")
    return BSplineSurface(P[..., :-1] / W[..., None], degree_u, degree_v, knots_u, knots_v, W)


# --- blend ----------------------------------------------------------------------------------------
def blend_surface(s1: Surface, edge1: str, s2: Surface, edge2: str, continuity: int = 1,
                  tangent_scales: Optional[Sequence[float]] = None) -> BlendSurface:
    """A surface bridging ``edge1`` of s1 and ``edge2`` of s2, G1 (``continuity=1``,
    cubic across) or G2 (``continuity=2``, quintic across) to both along the whole
    edges (construction, scales and references in the module docstring). The edges
    are matched at equal fractions of their domains; edge2 is run backwards when its
    points are closer to edge1's on average that way (``reversed``; closed edges too).
    Rational surfaces are blended exactly in homogeneous coordinates (the blend is
    rational then; a default tangent scale is shortened where its weights would not stay
    positive, see the module docstring). Periodic surfaces are clamped first.

    Raises:
        CagdError: s1/s2 not rectangular 3-D surfaces (TrimmedSurfaces: pass the
            untrimmed one), edge1/edge2 not "u0"/"u1"/"v0"/"v1", continuity not 1 or 2,
            tangent_scales not two positive numbers, an edge collapsed to a point
            (naming it), a cross derivative vanishing all along an edge (naming the
            surface), coincident edges, rational data whose blend weights would turn
            non-positive (naming tangent_scales[0] or [1] and the largest value that works).
    """
    b1, b2 = _surface(s1, "s1"), _surface(s2, "s2")
    e1, e2 = _edge(edge1, "edge1"), _edge(edge2, "edge2")
    k = _continuity(continuity, (1, 2), "1: G1, a cubic blend; 2: G2, a quintic")
    alpha, beta = _scales(tangent_scales) or (1.0, 1.0)
    f, (b1, b2) = _normalised(b1, b2)
    rational = b1.is_rational or b2.is_rational
    side1, side2 = _side(b1, e1, rational), _side(b2, e2, rational)
    c1 = _along_curve(_derivative_rows(side1, k), _unit(side1.along, side1.q), side1.q)
    c2 = _along_curve(_derivative_rows(side2, k), _unit(side2.along, side2.q), side2.q)

    t = np.linspace(0.0, 1.0, STATIONS)
    S1, D1 = _project(c1, k + 1, t, rational)
    S2, D2 = _project(c2, k + 1, t, rational)
    for name, S, b_ in (("edge1", S1, b1), ("edge2", S2, b2)):
        if not _edge_length(S) > DEGENERATE_TOL * b_.size:
            raise CagdError(f"{name}: the edge collapses to a point (length {_edge_length(S) / f:.3g}); "
                            f"a blend needs an edge curve")
    rev = _reversed_edges(S1, S2)
    if rev:
        c2 = _along_curve(_from_along(c2, k + 1), c2.knots, c2.degree, reverse=True)
        S2, D2 = S2[::-1], D2[::-1]
    distance = _mean_norm(S2 - S1)
    if not distance > DEGENERATE_TOL * max(b1.size, b2.size):
        raise CagdError(f"edge2: coincides with edge1 (mean distance {distance / f:.3g}); a blend needs two "
                        f"distinct edges")
    for name, edge, D, b_ in (("s1", e1, D1, b1), ("s2", e2, D2, b2)):
        if not _mean_norm(D) * _cross_span(b_, edge) > DEGENERATE_TOL * b_.size:
            raise CagdError(f"{name}: its cross derivative vanishes along {edge}; no tangent plane to match")
    a = alpha * distance / _mean_norm(D1)
    b = beta * distance / _mean_norm(D2)

    c1, c2 = _compatible([c1, c2])
    A, B = _from_along(c1, k + 1), _from_along(c2, k + 1)        # (k + 1, poles, D): H, H_s, H_ss
    n = 2 * k + 1
    R = np.empty((n + 1,) + A.shape[1:])
    used = [alpha, beta]
    for i, (H, scale, given, name) in enumerate(((A, a, alpha, "edge1"), (B, b, beta, "edge2"))):
        Q = _hermite_rows(H, scale, n, rational)
        if rational and not np.all(Q[..., -1] > 0.0):
            fraction = _weight_limit(H, scale, n)
            if tangent_scales is not None or not fraction > 0.0:
                raise CagdError(f"tangent_scales[{i}]: the blend's weights next to {name} turn non-positive at "
                                f"{given:g} (the rational data's weights vary fast across it); they stay "
                                f"positive below about {fraction * given:.3g}")
            used[i] = WEIGHT_MARGIN * fraction                       # the default shortened to fit
            Q = _hermite_rows(H, used[i] * scale, n, rational)
        if i == 0:
            R[:k + 1] = Q
        else:
            R[n - k:] = Q[::-1]
    net = R.transpose(1, 0, 2)                                    # u along, v across
    bezier = np.concatenate([np.zeros(n + 1), np.ones(n + 1)])
    surface = _surface_from_net(net, rational, c1.degree, n, c1.knots, bezier, "tangent_scales")

    ang1, gap1, cg1, size1 = _measure(surface, "v0", b1, e1, False, k)
    ang2, gap2, cg2, size2 = _measure(surface, "v1", b2, e2, rev, k)
    max_angle = max(ang1, ang2)
    max_gap = max(gap1, gap2)
    cgap = None if cg1 is None or cg2 is None else max(cg1, cg2)
    ok = bool(max_angle <= CONTINUITY_TOL and max_gap <= CONTINUITY_TOL * max(size1, size2)
              and (cgap is None or cgap <= CONTINUITY_TOL))
    max_gap /= f
    message = (f"G{k} blend of degree {n} across, {net.shape[0]} poles along: tangent-plane angle "
               f"{max_angle:.3g} rad, gap {max_gap:.3g}"
               + ("" if cgap is None else f", relative curvature gap {cgap:.3g}")
               + f" at {STATIONS} stations per edge; scales a = {a * used[0]:.6g}, b = {b * used[1]:.6g}"
               + ("" if used == [alpha, beta] else
                  f" (the default tangent scales shortened to ({used[0]:.3g}, {used[1]:.3g}) to keep the "
                  f"rational blend's weights positive)")
               + ("; edge2 reversed" if rev else "")
               + ("" if ok else f" (above the tolerance {CONTINUITY_TOL:g})"))
    return BlendSurface(_scaled_back(surface, f), k, max_angle, cgap, max_gap, rev, ok, message)


# --- match ----------------------------------------------------------------------------------------
def match_surface(s: Surface, edge: str, target: Surface, target_edge: str, continuity: int = 1) -> MatchSurface:
    """``s`` with its first ``continuity`` + 1 control rows next to ``edge`` replaced so
    that it meets ``target`` at ``target_edge`` G0 (the edge moves onto the target's
    edge), G1 or G2 (C1/C2 up to a constant cross-parameter scale that keeps s's own;
    module docstring), Rhino's MatchSrf without the refit options. The along-edge
    direction of s is first made compatible with the target's edge (degree elevation,
    knot insertion: the same surface, ``poles_along`` reports the pole counts); the
    edges are matched at equal fractions of their domains, target_edge run backwards
    when that brings its points closer on average (``reversed``). The opposite edge's
    row stays in place: s needs at least continuity + 2 rows across and a cross degree
    >= continuity. Rational data is handled in homogeneous coordinates (s becomes rational
    when the target is). Periodic surfaces are clamped first.

    Raises:
        CagdError: s/target not rectangular 3-D surfaces, an unknown edge or
            target_edge, continuity not 0, 1 or 2, s with too few rows or too low a
            degree across edge (naming s), a collapsed target edge, a target cross
            derivative vanishing along its edge, non-positive weights of the new rows.
    """
    bs, bt = _surface(s, "s"), _surface(target, "target")
    e, te = _edge(edge, "edge"), _edge(target_edge, "target_edge")
    k = _continuity(continuity, (0, 1, 2), "0: G0, 1: G1, 2: G2")
    f, (bs, bt) = _normalised(bs, bt)
    rational = bs.is_rational or bt.is_rational
    ss, ts = _side(bs, e, rational), _side(bt, te, rational)
    rows = ss.net.shape[0]
    if ss.p < k:
        raise CagdError(f"s: its degree across {e} is {ss.p}, below the continuity {k} (elevate it first)")
    if rows < k + 2:
        raise CagdError(f"s: {rows} control rows across {e}; G{k} moves {k + 1} and the opposite edge's row "
                        f"must stay (insert knots across first)")
    t = np.linspace(0.0, 1.0, STATIONS)
    ct = _along_curve(_derivative_rows(ts, max(k, 1)), _unit(ts.along, ts.q), ts.q)
    cs = _along_curve(ss.net, _unit(ss.along, ss.q), ss.q)
    St, Dt = _project(ct, max(k, 1) + 1, t, rational)
    Ss = _project(cs, rows, t, rational)[0]
    if not _edge_length(St) > DEGENERATE_TOL * bt.size:
        raise CagdError(f"target_edge: the target's edge collapses to a point (length {_edge_length(St) / f:.3g})")
    if k >= 1 and not _mean_norm(Dt) * _cross_span(bt, te) > DEGENERATE_TOL * bt.size:
        raise CagdError(f"target: its cross derivative vanishes along {te}; no tangent plane to match")
    rev = _reversed_edges(Ss, St)
    if rev:
        ct = _along_curve(_from_along(ct, max(k, 1) + 1), ct.knots, ct.degree, reverse=True)
    before = ss.net.shape[1]
    cs, ct = _compatible([cs, ct])
    net = _from_along(cs, rows).copy()
    T = _from_along(ct, max(k, 1) + 1)
    old = _derivative_rows(_Side(net, ss.dist, ss.p, ss.along, ss.q), k)
    if rational:
        w_old, w_t = old[0][:, -1], T[0][:, -1]
        rho = float(w_old @ w_t / (w_t @ w_t))
    else:
        rho = 1.0
    R = [rho * T[0]]
    if k >= 1:
        goal = -rho * T[1]
        lam = float(np.linalg.norm(old[1]) / np.linalg.norm(goal))
        lam = lam if lam > 0.0 else 1.0
        R.append(lam * goal)
        if k == 2:
            R.append(lam * lam * rho * T[2])
    G = np.stack(R)
    if rational:
        G = _reweighted(G, old)
    net[:k + 1] = _rows_from_derivatives(G, ss.dist, ss.p)
    along = cs.knots
    lo, hi = ss.along[ss.q], ss.along[-ss.q - 1]
    along = lo + along * (hi - lo)
    along[:cs.degree + 1], along[-cs.degree - 1:] = lo, hi
    cross = bs.knots_u if e[0] == "u" else bs.knots_v
    if e[1] == "1":
        net = net[::-1]
    if e[0] == "u":
        surface = _surface_from_net(net, rational, bs.degree_u, cs.degree, cross, along, "target")
    else:
        surface = _surface_from_net(net.transpose(1, 0, 2), rational, cs.degree, bs.degree_v, along, cross, "target")

    angle, gap, cgap, msize = _measure(surface, e, bt, te, rev, k)
    ok = bool(gap <= CONTINUITY_TOL * msize and (k == 0 or angle <= CONTINUITY_TOL)
              and (cgap is None or cgap <= CONTINUITY_TOL))
    after = net.shape[1]
    message = (f"G{k} match of {e} to the target's {te}: {k + 1} row(s) moved, {before} -> {after} poles along; "
               f"gap {gap / f:.3g}, tangent-plane angle {angle:.3g} rad"
               + ("" if cgap is None else f", relative curvature gap {cgap:.3g}")
               + f" at {STATIONS} stations" + ("; target edge reversed" if rev else "")
               + ("" if ok else f" (above the tolerance {CONTINUITY_TOL:g})"))
    return MatchSurface(_scaled_back(surface, f), k, angle, cgap, gap / f, rev, ok, message, k + 1, (before, after))
