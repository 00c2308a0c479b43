"""Fairing a B-spline curve within a tolerance, the ends' continuity held (issue 17; the
seeds do not treat fairing; the energy is the standard curvature-variation functional,
e.g. Moreton & Sequin 1992, and the least-squares form follows Farin, Curves and
Surfaces for CAGD, 23).

On the curve's own knots and degree the new control points minimise

    (1/m) sum_k |C(t_k) - C0(t_k)|^2 + mu int |C'''(t)|^2 dt

(C0 the original, t_k FAIR_SAMPLES parameters per knot span; |C''|^2 for degree 2) with
the first and last 1, 2 or 3 control points held (keep "G0", "G1", "G2": the end points,
their tangents and their curvatures are the original's exactly, so the curve still joins
its neighbours as before). The weight mu is the largest found by bisection (on log mu,
FAIR_BISECTIONS steps) whose certified deviation stays within tol: the difference of the
two curves is the B-spline with control points P - P0, so |C(t) - C0(t)| <= max |P_i - P0_i|
for every t (the convex hull property), and that bound is what is held.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Tuple

import numpy as np

from .. import _checks
from .._results import ReadOnlyArrays
from ..basis.bspline import basis_derivatives
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from .fit import _accumulate, _blocks, _energy, _gauss, solve_fixed
from .interpolation import _frame

if TYPE_CHECKING:
    from ..surfaces.bspline import BSplineSurface

#: parameters per knot span at which the faired curve is held near the original
FAIR_SAMPLES = 8
#: bisection steps on log10(mu) over [FAIR_LOG_MU_MIN, FAIR_LOG_MU_MAX]
FAIR_BISECTIONS = 40
FAIR_LOG_MU_MIN, FAIR_LOG_MU_MAX = -16.0, 8.0
#: control points held at each end per kept continuity
KEEP = {"G0": 1, "G1": 2, "G2": 3}
#: curvature values below this fraction of the largest count as zero for the inflections
INFLECTION_TOL = 1e-9


@dataclass(frozen=True)
class Fairing(ReadOnlyArrays):
    """The result of :func:`fair_curve`: ``curve`` (same knots and degree); the energy
    int |C'''|^2 (|C''|^2 for degree 2) before and after; the inflections (sign changes
    of the curvature, in the curve's best-fit plane) before and after; ``max_deviation``
    the certified bound of |C(t) - C0(t)| (at most tol); ``mu`` the weight used;
    ``converged`` True (the original itself is within tol) and ``message``."""
    curve: BSplineCurve
    energy_before: float
    energy_after: float
    inflections_before: int
    inflections_after: int
    max_deviation: float
    mu: float
    converged: bool
    message: str


def energy(curve: BSplineCurve, order: int = 3) -> float:
    """int |C^(order)(t)|^2 dt over the domain, by Gauss-Legendre per knot span (exact)."""
    t, w = _gauss(np.asarray(curve.full_knots), curve.degree)
    D = curve.derivatives(t, order)[order]
    return float((w * (D * D).sum(-1)).sum())


def inflections(curve: BSplineCurve, samples_per_span: int = 64) -> int:
    """Sign changes of the curvature along the curve: of (C' x C'') . n, n the normal of
    the best-fit plane of the control points (the z axis for 2-D curves); values below
    INFLECTION_TOL of the largest are skipped."""
    brk = np.unique(curve.full_knots[curve.degree:len(curve.full_knots) - curve.degree])
    f = np.linspace(0.0, 1.0, samples_per_span + 1)[:-1]
    t = np.append((brk[:-1, None] + f * np.diff(brk)[:, None]).ravel(), brk[-1])
    D = curve.derivatives(t, 2)
    if curve.dim == 2:
        k = D[1][:, 0] * D[2][:, 1] - D[1][:, 1] * D[2][:, 0]
    else:
        P = curve.control_points - curve.control_points.mean(axis=0)
        normal = np.linalg.svd(P, full_matrices=False)[2][-1]
        k = np.cross(D[1], D[2]) @ normal
    big = np.abs(k) > INFLECTION_TOL * float(np.abs(k).max(initial=0.0))
    s = np.sign(k[big])
    return int(np.count_nonzero(s[1:] != s[:-1]))


def _largest_weight(solve, bound, tol: float, start: np.ndarray) -> Tuple[float, np.ndarray]:
    """(mu, solve(mu)) for the largest mu whose bound(solve(mu)) <= tol: FAIR_LOG_MU_MAX
    if it is within, else FAIR_BISECTIONS bisections on log10 mu (mu = 0 and ``start``,
    the original, when none is)."""
    best_mu, best = 0.0, start
    lo, hi = FAIR_LOG_MU_MIN, FAIR_LOG_MU_MAX
    X = solve(10.0 ** hi)
    if bound(X) <= tol:
        return 10.0 ** hi, X
    for _ in range(FAIR_BISECTIONS):
        mid = 0.5 * (lo + hi)
        X = solve(10.0 ** mid)
        if bound(X) <= tol:
            lo, best_mu, best = mid, 10.0 ** mid, X
        else:
            hi = mid
    return best_mu, best


def fair_curve(curve: BSplineCurve, tol: float, keep: str = "G2") -> Fairing:
    """The curve with its curvature variation lowered while it stays within ``tol`` (a
    distance, certified) of itself, ``keep`` ("G0", "G1" or "G2") held exactly at both
    ends; see the module docstring.

    Raises:
        CagdError: not a polynomial (non-rational) BSplineCurve, a bad tol or keep, too
            few control points to move any (degree + 1 and 2 * the held count)."""
    if not isinstance(curve, BSplineCurve):
        raise CagdError(f"curve: expected a cagd BSplineCurve, got {type(curve).__name__}")
    if curve.is_rational:
        raise CagdError("curve: fair_curve works on polynomial B-splines; rebuild a rational curve first "
                        "(cagd.rebuild)")
    tol = _checks.nonnegative(tol, "tol")
    if not isinstance(keep, str) or keep not in KEEP:
        raise CagdError(f"keep: one of {', '.join(KEEP)}, got {keep!r}")
    c0 = curve.clamped()
    p, n, d = c0.degree, len(c0.control_points), c0.dim
    held = KEEP[keep]
    if n <= 2 * held:
        raise CagdError(f"curve: {n} control points, all held by keep={keep!r}; nothing can move")
    order = 3 if p >= 3 else 2
    U = np.asarray(c0.knots, float)
    brk = np.unique(U[p:len(U) - p])
    f = np.linspace(0.0, 1.0, FAIR_SAMPLES + 1)[:-1]
    t = np.append((brk[:-1, None] + f * np.diff(brk)[:, None]).ravel(), brk[-1])
    center, scale = _frame(c0.control_points)
    P0 = (c0.control_points - center) / scale
    span = kv.find_span(U, p, t, n)
    N = basis_derivatives(U, p, t, span, 0)[0]
    cols = span[:, None] - p + np.arange(p + 1)
    start, data = _blocks(n, d, p)
    _accumulate(data, start, cols, N, np.full(len(t), 1.0 / len(t)), d)
    E = np.zeros_like(data)
    _energy(E, start, U, p, d, order, 1.0)
    h = float(np.diff(brk).min()) if len(brk) > 1 else 1.0
    E *= h ** (2 * order - 1)                              # mu dimensionless per span width
    rhs = _banded_apply(start, data, P0.reshape(-1))       # the data term's right-hand side: N^T N P0
    ends = np.r_[np.arange(held), np.arange(n - held, n)]
    scalars = np.array([i * d + a for i in ends for a in range(d)])
    values = P0[ends].reshape(-1, 1)
    tol_n = tol / scale

    def solve(mu: float) -> np.ndarray:
        X = solve_fixed(start, data + mu * E, rhs[:, None].copy(), scalars, values.copy())
        return X[:, 0].reshape(n, d)

    def bound(P: np.ndarray) -> float:
        return float(np.sqrt(((P - P0) ** 2).sum(-1)).max())

    best_mu, best = _largest_weight(solve, bound, tol_n, P0)
    out_P = best * scale + center
    out_P[ends] = c0.control_points[ends]                  # the held ends, bit for bit
    out = BSplineCurve(out_P, p, U)
    dev = float(np.sqrt(((out_P - c0.control_points) ** 2).sum(-1)).max())
    e0, e1 = energy(c0, order), energy(out, order)
    i0, i1 = inflections(c0), inflections(out)
    msg = (f"energy int |C^({order})|^2 {e0:.4g} -> {e1:.4g}, inflections {i0} -> {i1}, within {dev:.3g} "
           f"(tol {tol:g}), {keep} held at both ends")
    return Fairing(out, e0, e1, i0, i1, dev, best_mu, True, msg)


def _banded_apply(start: np.ndarray, A: np.ndarray, x: np.ndarray) -> np.ndarray:
    from ..basis.banded import banded_product
    return banded_product(start, A, x[:, None])[:, 0]


#: poles held along every boundary edge per kept continuity of a surface: rows 0 and 1
#: carry the edge and its cross-boundary tangent, row 2 the cross curvature
SURFACE_KEEP = {"G0": 1, "G1": 2, "G2": 3}


@dataclass(frozen=True)
class SurfaceFairing(ReadOnlyArrays):
    """The result of :func:`fair_surface`: ``surface`` (same knots and degrees), the
    thin-plate energy int int |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2 du dv before and after,
    ``max_deviation`` the certified bound max |P - P0| of |S(u, v) - S0(u, v)| (at most
    tol), ``mu`` the weight used, ``converged`` True and ``message``."""
    surface: object
    energy_before: float
    energy_after: float
    max_deviation: float
    mu: float
    converged: bool
    message: str


def _thin_plate_band(Uu: np.ndarray, pu: int, Uv: np.ndarray, pv: int) -> Tuple[np.ndarray, np.ndarray]:
    """(start, band) of the thin-plate energy matrix G2u (x) G0v + 2 G1u (x) G1v + G0u (x) G2v
    over the net's poles in row-major order (i nv + j): |I - J| <= pu nv + pv
    (:func:`cagd.fitting.surface_net._kron_band`)."""
    from .surface_net import Direction, _kron_band, thin_plate_terms
    du, dv = Direction(Uu, pu), Direction(Uv, pv)
    return _kron_band(thin_plate_terms(du, dv), du, dv)


def fair_surface(surface: "BSplineSurface", tol: float, keep: str = "G1") -> SurfaceFairing:
    """The surface with its thin-plate energy lowered while it stays within ``tol`` (a
    distance, certified by the convex hull: max |P - P0|) of itself, with ``keep`` ("G0",
    "G1", "G2") held exactly along all four boundary edges: the first 1, 2 or 3 rows of
    control points at every edge are fixed, so the edges, their cross-boundary tangents
    (G1 to any neighbour stays as it was) and cross curvatures are the original's. The new
    control points minimise |P - P0|^2 + mu E_thin-plate(P) (one banded solve per mu, the
    band pu nv + pv wide), mu the largest found by FAIR_BISECTIONS bisections on log mu.

    Raises:
        CagdError: not a polynomial BSplineSurface, a bad tol or keep, a net too small
            to move any control point."""
    from ..surfaces.bspline import BSplineSurface     # noqa: F811 (the class at run time)
    if not isinstance(surface, BSplineSurface):
        raise CagdError(f"surface: expected a cagd BSplineSurface, got {type(surface).__name__}")
    if surface.is_rational:
        raise CagdError("surface: fair_surface works on polynomial B-spline surfaces; rebuild a rational one "
                        "first (cagd.rebuild)")
    tol = _checks.nonnegative(tol, "tol")
    if not isinstance(keep, str) or keep not in SURFACE_KEEP:
        raise CagdError(f"keep: one of {', '.join(SURFACE_KEEP)}, got {keep!r}")
    S0 = surface
    if S0.periodic_u or S0.periodic_v:
        raise CagdError("surface: a periodic surface has no boundary to hold; fair_surface takes open nets")
    P0 = np.asarray(S0.control_points, float)
    nu, nv, d = P0.shape
    held = SURFACE_KEEP[keep]
    if nu <= 2 * held or nv <= 2 * held:
        raise CagdError(f"surface: a {nu} x {nv} net has no control point free of the {held} boundary "
                        f"row(s) keep={keep!r} holds")
    Uu, Uv = np.asarray(S0.knots_u, float), np.asarray(S0.knots_v, float)
    start, E = _thin_plate_band(Uu, S0.degree_u, Uv, S0.degree_v)
    center, scale = _frame(P0.reshape(-1, d))
    X0 = ((P0 - center) / scale).reshape(-1, d)
    ring = np.zeros((nu, nv), bool)
    ring[:held], ring[-held:], ring[:, :held], ring[:, -held:] = True, True, True, True
    fixed = np.flatnonzero(ring.ravel())
    eye = np.zeros_like(E)
    eye[np.arange(nu * nv), np.arange(nu * nv) - start] = 1.0
    unit = float(np.abs(E).max()) or 1.0
    tol_n = tol / scale

    def solve(mu: float) -> np.ndarray:
        return solve_fixed(start, eye + (mu / unit) * E, X0.copy(), fixed, X0[fixed].copy())

    def bound(X: np.ndarray) -> float:
        return float(np.sqrt(((X - X0) ** 2).sum(-1)).max())

    best_mu, best = _largest_weight(solve, bound, tol_n, X0)
    P = (best * scale + center).reshape(nu, nv, d)
    P[ring] = P0[ring]                                   # the held rows, bit for bit
    out = BSplineSurface(P, S0.degree_u, S0.degree_v, Uu, Uv)
    from ..basis.banded import banded_product

    def thin_plate(Q: np.ndarray) -> float:
        flat = Q.reshape(-1, d)
        return float((flat * banded_product(start, E, flat)).sum())
    e0, e1 = thin_plate(P0), thin_plate(P)
    dev = float(np.sqrt(((P - P0) ** 2).sum(-1)).max())
    msg = (f"thin-plate energy {e0:.4g} -> {e1:.4g}, within {dev:.3g} (tol {tol:g}), {keep} held along "
           f"the four edges")
    return SurfaceFairing(out, e0, e1, dev, best_mu, True, msg)
