"""Global minimum distance between two curves, a curve and a surface, or two surfaces,
with a certified lower bound (seed 004, ch. 1 §4, positional relations: minimum
distance).

Branch and bound over pairs of Bezier pieces (Piegl & Tiller A5.6/A5.7 decomposition,
de Casteljau halving): a pair's lower bound is the largest of the distance between
the axis-aligned boxes of the two control hulls, the gap of their projections on the
current best direction and on the centre-to-centre direction (all valid by the
convex-hull property, positive weights) and, once the minimum is found to be
degenerate, the gap of the distances from a centre or an axis fitted to the common
normals of the minima (:mod:`cagd.queries._symmetry`; 1-Lipschitz, so valid for any
centre or axis, and exact along a continuum of minima of concentric, coaxial or
parallel objects, where box and slab bounds only improve as O(h^2) and no
subdivision could reach 1e-9). Upper bounds come from piece corners (points of the
objects) and from projected Newton refinement of the most promising pairs (and, at a
degenerate minimum, of pairs spread over those alive). A pair whose bound is at least
the best distance minus ``tol`` cannot hold a point closer by more than ``tol``: it is
settled, not split; the smallest bound of the pairs alive, settled or dropped at the
pair cap is reported as ``lower_bound``, so the true minimum lies in
[lower_bound, distance].
"""
from __future__ import annotations

from typing import List, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from . import _subdivision as sd
from ._symmetry import FIT_RTOL, Flat, fit_flats, flat_gap
from .bounds import Frame, robust_distance
from .results import DistanceResult
from ._newton import refine
from ._numerics import TINY

RANK_RTOL = 1e-6           # singular values of the normal lines' matrix above this share count
EIGEN_RTOL = 1e-8          # eigenvalues of the refined pair's Hessian above this share of the largest count
SAME_FLAT_RTOL = 1e-9      # two fitted flats with projectors this close are one

DEFAULT_RTOL = 1e-9       # default tol: this share of the size of the larger object
ROUNDING_RTOL = 1e-14     # ... but at least this share of the extent of both together (float64's reach)
ISOLATION_RTOL = 1e-6     # degenerate: growth of |A - B|^2 below this share of the curvature terms
HESSIAN_FLOOR = 1e-12     # ... or below this share of the squared lengths moved (rounding level)
TOUCH_RTOL = 1e-12        # objects closer than this share of their size touch (the contact order decides)
COLLAPSED_RTOL = 1e-16    # parameter directions moving a point by under 1e-8 of the fastest one do not move it
STATIONARY_RTOL = 1e-8    # |dA.r| <= this * |dA| |r|: the parameter is stationary (r normal to A)
NORMAL_RTOL = 1e-12       # ... and for a normal line to feed the fit (its angle error, radians)
FIT_WINDOW = 1e-10        # minima within min(tol, FIT_WINDOW * size) of the best feed the fit
POOL_SIZE = 64            # normal lines kept for the fit
MAX_FLATS = 4             # centres and axes tried per call
POLISH_ROUNDS = 4         # Newton steps of each projection polishing a new best pair (_polished)
POLISH_RTOL = 1e-13       # ... each kept while the distance grows by at most this (rounding)
ANISOTROPY = 1e-3         # a patch is halved one way only where its phi coefficients vary this much less the other way
_PHI4 = 1.1673039782614187   # x^5 = x + 1: the spread starts' fractions j / _PHI4^i mod 1 in their pairs'
_SPREAD = _PHI4 ** -np.arange(1.0, 5.0)  # boxes, i = 1..4 over the parameters (Roberts' R_4 sequence)




def _corners(ctrl: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Corner control points (points of the object: clamped Bezier pieces interpolate
    them) with their local corner parameters in {0, 1}^k."""
    P = sd.project(ctrl)
    if ctrl.ndim == 3:
        return np.stack([P[:, 0], P[:, -1]], 1), np.array([[0.0], [1.0]])
    return (np.stack([P[:, 0, 0], P[:, -1, 0], P[:, 0, -1], P[:, -1, -1]], 1),
            np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]))


def _bounds(pa: sd.Pieces, pb: sd.Pieces, direction, flats):
    """Lower bounds (M,) of the distance within each pair, and how to split each pair:
    (bound, split_a, split_b, modes_a, modes_b). The larger piece by box diagonal is
    halved (both when comparable); where a flat gives the bound, the piece with the
    wider range of phi, across the parameter along which its coefficients vary (a
    continuum along a parallel of a surface of revolution is halved across it only)."""
    lo_a, hi_a = sd.boxes(pa.ctrl)
    lo_b, hi_b = sd.boxes(pb.ctrl)
    bound = sd.box_gap(lo_a, hi_a, lo_b, hi_b)
    centre = 0.5 * (lo_b + hi_b) - 0.5 * (lo_a + hi_a)
    bound = np.maximum(bound, sd.slab_gap(pa.ctrl, pb.ctrl, centre))
    if direction is not None:
        bound = np.maximum(bound, sd.slab_gap(pa.ctrl, pb.ctrl, np.broadcast_to(direction, centre.shape)))
    da, db = np.linalg.norm(hi_a - lo_a, axis=1), np.linalg.norm(hi_b - lo_b, axis=1)
    split_a, split_b = da >= 0.5 * db, db >= 0.5 * da
    modes_a = modes_b = None
    for flat in flats:
        fg = flat_gap(pa.ctrl, pb.ctrl, flat)
        wins = fg.gap > bound
        bound = np.maximum(bound, fg.gap)
        if wins.any():
            sa, sb = fg.width_a >= 0.5 * fg.width_b, fg.width_b >= 0.5 * fg.width_a
            both_exact = ~sa & ~sb
            split_a = np.where(wins & ~both_exact, sa, split_a)
            split_b = np.where(wins & ~both_exact, sb, split_b)
            modes_a = _modes(pa, modes_a, wins, fg.variation_a)
            modes_b = _modes(pb, modes_b, wins, fg.variation_b)
    return bound, split_a, split_b, modes_a, modes_b


def _modes(p: sd.Pieces, modes, wins: np.ndarray, variation: np.ndarray):
    """Split modes (:func:`sd.split_modes`) of surface patches, across u only (1) or v
    only (2) where ``wins`` and the coefficients vary ANISOTROPY times less the other way."""
    if p.k == 1:
        return None
    modes = sd.split_modes(p.ctrl) if modes is None else modes
    vu, vv = variation[:, 0], variation[:, 1]
    flat_way = np.where(vv <= ANISOTROPY * vu, 1, np.where(vu <= ANISOTROPY * vv, 2, modes))
    return np.where(wins, flat_way, modes)


def _jet(A: sd.Geometry, B: sd.Geometry, x: np.ndarray, y: np.ndarray, order: int):
    """r = A(x) - B(y) (N, D), J = d r / d(x, y) (N, k, D) and, if order == 2, the second
    derivatives T = d2 r (N, k, k, D) and the curvature part S = r . T (N, k, k) of the
    Hessian J J^T + S of |r|^2 / 2 (else None, None)."""
    pa, da, ha = A.derivatives(x, order)
    pb, db, hb = B.derivatives(y, order)
    assert da is not None and db is not None                # order >= 1
    r, J = pa - pb, np.concatenate([da, -db], axis=1)
    if order < 2:
        return r, J, None, None
    assert ha is not None and hb is not None
    k, ka = J.shape[1], A.k
    T = np.zeros((len(r), k, k, r.shape[1]))
    T[:, :ka, :ka], T[:, ka:, ka:] = ha, -hb
    return r, J, T, np.einsum("nijd,nd->nij", T, r)


def _stationary(r: np.ndarray, J: np.ndarray, rtol: float = STATIONARY_RTOL) -> np.ndarray:
    """(N, k): r . dr/dz_i is zero to ``rtol`` of |dr/dz_i| |r| (r normal to the object there)."""
    g = np.einsum("nkd,nd->nk", J, r)
    return np.abs(g) <= rtol * np.linalg.norm(J, axis=2) * np.linalg.norm(r, axis=1)[:, None]


def _foot_newton(G: sd.Geometry, q: np.ndarray, x: np.ndarray, dist: float) -> Tuple[np.ndarray, float]:
    """Newton on the gradient of |G(x) - q|^2 / 2 from x (Piegl & Tiller 6.1):
    (J J^T + r . G_xx) dx = -J r, each step kept while |J r| falls and the distance grows by
    at most POLISH_RTOL. No line search on the distance: near a foot it changes by the
    square of the parameter error and is lost in rounding at 1e-8 (relative) from the foot,
    where the gradient is still plainly measurable."""
    def grad(z):
        p, d, h = G.derivatives(z[None], 2)
        r = p[0] - q
        return r, d[0], h[0]
    r, J, H2 = grad(x)
    g = J @ r
    for _ in range(POLISH_ROUNDS):
        H = J @ J.T + np.einsum("ijd,d->ij", H2, r)
        try:
            step = -np.linalg.solve(H, g)
        except np.linalg.LinAlgError:
            break
        z = G.clamp((x + step)[None])[0]
        r2, J2, H22 = grad(z)
        g2 = J2 @ r2
        d2 = float(np.linalg.norm(r2))
        if not (np.linalg.norm(g2) < np.linalg.norm(g) and d2 <= dist * (1.0 + POLISH_RTOL)):
            break
        x, r, J, H2, g, dist = z, r2, J2, H22, g2, d2
    return x, dist


def _polished(A: sd.Geometry, B: sd.Geometry, x: np.ndarray, y: np.ndarray, dist: float
              ) -> Tuple[np.ndarray, np.ndarray, float]:
    """(x, y, distance) after a projection of b's point onto a, then of a's point onto b,
    each by :func:`_foot_newton`. On a continuum of minima the joint minimisation
    (:func:`cagd.queries._newton.refine`) is singular along the continuum and stops with gradients of 1e-8
    relative; the two projections are regular problems that make each gradient vanish,
    as the stationarity test of :func:`_isolated` needs (concentric spheres placed at
    random were reported isolated and hit the pair cap, issue 16)."""
    x, dist = _foot_newton(A, B.points(y[None])[0], x, dist)
    y, dist = _foot_newton(B, A.points(x[None])[0], y, dist)
    return x, y, dist


def _isolated(A: sd.Geometry, B: sd.Geometry, x: np.ndarray, y: np.ndarray, touching: bool) -> bool:
    """Whether the minimum at (x, y) is non-degenerate (see :class:`DistanceResult`):
    the smallest eigenvalue of the Hessian J J^T + S of |A - B|^2 / 2 over the free
    parameters, in the metric G of the points' displacements (|dA|^2 + |dB|^2), exceeds
    ISOLATION_RTOL |S|_G + HESSIAN_FLOOR. A parameter is held (not free) where the
    gradient along it is not zero (STATIONARY_RTOL): at a minimum that is a domain bound
    or a crease (a seam closed only C0), where the distance grows at first order; and
    directions that do not move the points (COLLAPSED_RTOL: along a pole, at a point
    where a surface's partials are parallel) are left out. Where the objects are
    ``touching`` (distance <= TOUCH_RTOL * size: no gradient to tell) no parameter is held by its
    gradient and, if the Hessian is flat, the order of contact decides
    (:func:`_point_contact`)."""
    r, J, T, S = (v[0] for v in _jet(A, B, x[None], y[None], 2))
    free = np.arange(len(J)) if touching else np.flatnonzero(_stationary(r[None], J[None])[0])
    owner = np.r_[np.zeros(A.k, int), np.ones(B.k, int)][free]
    Jf = J[free]
    lam, U = np.linalg.eigh((Jf @ Jf.T) * (owner[:, None] == owner[None, :]))
    moves = lam > COLLAPSED_RTOL * max(float(lam.max(initial=0.0)), TINY)   # not along a pole or
    if not moves.any():                                                     # a degenerate point
        return True
    Linv = U[:, moves].T / np.sqrt(lam[moves])[:, None]       # G^(-1/2) on the directions that move a point
    Sn = Linv @ S[np.ix_(free, free)] @ Linv.T
    lam, V = np.linalg.eigh(Linv @ Jf @ Jf.T @ Linv.T + Sn)
    flat = lam <= ISOLATION_RTOL * float(np.abs(np.linalg.eigvalsh(Sn)).max()) + HESSIAN_FLOOR
    if not flat.any():
        return True
    if not touching:
        return False
    Tn = np.einsum("ai,bj,ijd->abd", Linv, Linv, T[np.ix_(free, free)])
    return _point_contact(Linv @ Jf, Tn, V[:, flat])


def _point_contact(M: np.ndarray, T: np.ndarray, N: np.ndarray) -> bool:
    """At a touch (r = 0), with first derivatives M (k, D) and second derivatives
    T (k, k, D) of r in metric-normalized parameters and the flat directions N (k, m):
    the contact is one point when the second-order term Q(v) = P T[v, v] (P: projection
    across the span of M, the common tangent space) vanishes on no flat direction v:
    |Q(v)| > ISOLATION_RTOL |T| for m = 1, a definite form on N for m = 2 with one
    normal direction (a sphere resting on a plane or on a sphere); otherwise the touch is
    a curve (a cylinder on a plane, surfaces crossing) or more."""
    U, sv, _ = np.linalg.svd(M.T)
    rank = int(np.count_nonzero(sv > RANK_RTOL * max(float(sv.max()), TINY)))
    normals = U[:, rank:]                                     # (D, D - rank)
    scale = ISOLATION_RTOL * max(float(np.abs(T).max()), TINY)
    Q = np.einsum("ijd,ia,jb,dc->abc", T, N, N, normals)     # (m, m, D - rank)
    if N.shape[1] == 1:
        return bool(np.linalg.norm(Q[0, 0]) > scale)
    if N.shape[1] == 2 and normals.shape[1] == 1:
        e = np.linalg.eigvalsh(Q[..., 0])
        return bool(e[0] * e[1] > 0 and np.abs(e).min() > scale)
    return False


def _normal_lines(A: sd.Geometry, B: sd.Geometry, x: np.ndarray, y: np.ndarray, keep: np.ndarray,
                  steps: int = 3):
    """Points on a (m, D), unit normals towards b and the mask (N,) of the candidates
    ``keep`` that are stationary in every parameter to NORMAL_RTOL at a positive
    distance (r normal to both objects there), after ``steps`` Newton steps on the
    gradient J r = 0 with the pseudo-inverse of the Hessian (eigenvalues below 1e-8 of
    the largest dropped: the directions along the continuum). :func:`cagd.queries._newton.refine` stops
    near 1e-9 (relative gradient) on a continuum, where the decrease of |r|^2 that it
    requires is lost in rounding; a line that far off would miss the centre by 1e-9."""
    ka = A.k
    for _ in range(steps):
        r, J, _, S = _jet(A, B, x, y, 2)
        g = np.einsum("nkd,nd->nk", J, r)
        lam, V = np.linalg.eigh(np.einsum("nkd,nld->nkl", J, J) + S)
        big = np.abs(lam) > EIGEN_RTOL * np.abs(lam).max(axis=1, keepdims=True)
        inv = np.where(big, 1.0 / np.where(big, lam, 1.0), 0.0)
        step = np.einsum("nkl,nl->nk", V, inv * np.einsum("nlk,nl->nk", V, g))
        x, y = A.clamp(x - step[:, :ka]), B.clamp(y - step[:, ka:])
    r, J, _, _ = _jet(A, B, x, y, 1)
    d = np.linalg.norm(r, axis=1)
    ok = keep & (d > 0) & np.all(_stationary(r, J, NORMAL_RTOL), axis=1)
    return A.points(x[ok]), -r[ok] / d[ok, None], ok


def _same_flat(f: Flat, g: Flat, size: float) -> bool:
    return bool(np.abs(f.projector - g.projector).max() <= SAME_FLAT_RTOL
                and np.linalg.norm((f.origin - g.origin) @ f.projector) <= 10 * FIT_RTOL * size)


def _children(pa: sd.Pieces, pb: sd.Pieces, split_a, split_b, modes_a, modes_b) -> np.ndarray:
    """Number of child pairs (M,) that :func:`sd.split_pairs` makes of each pair."""
    def count(p, flag, modes):
        if p.k == 1:
            return np.where(flag, 2, 1)
        modes = sd.split_modes(p.ctrl) if modes is None else modes
        return np.where(flag, np.where(modes == 0, 4, 2), 1)
    return count(pa, split_a, modes_a) * count(pb, split_b, modes_b)


def _first_pairs(a: sd.Pieces, b: sd.Pieces, max_pairs: int, chunk: int = 1 << 20):
    """Index pairs (i, j) of the Bezier pieces to start from: all of them, or the
    ``max_pairs`` whose boxes are nearest, with the smallest box gap of those dropped
    (inf if none), in row blocks of at most ``chunk`` pairs (bounded memory)."""
    Ka, Kb = len(a.ctrl), len(b.ctrl)
    if Ka * Kb <= max_pairs:
        return np.repeat(np.arange(Ka), Kb), np.tile(np.arange(Kb), Ka), np.inf
    lo_a, hi_a = sd.boxes(a.ctrl)
    lo_b, hi_b = sd.boxes(b.ctrl)
    rows = max(1, chunk // Kb)
    ia, ib, gap, floor = np.empty(0, int), np.empty(0, int), np.empty(0), np.inf
    for r in range(0, Ka, rows):
        i = np.repeat(np.arange(r, min(r + rows, Ka)), Kb)
        j = np.tile(np.arange(Kb), len(i) // Kb)
        ia, ib = np.concatenate([ia, i]), np.concatenate([ib, j])
        gap = np.concatenate([gap, sd.box_gap(lo_a[i], hi_a[i], lo_b[j], hi_b[j])])
        if len(gap) > max_pairs:
            order = np.argpartition(gap, max_pairs)
            floor = min(floor, float(gap[order[max_pairs:]].min()))
            ia, ib, gap = ia[order[:max_pairs]], ib[order[:max_pairs]], gap[order[:max_pairs]]
    return ia, ib, floor


def min_distance(a: Union[Curve, Surface, ArrayLike], b: Union[Curve, Surface, ArrayLike],
                 tol: Optional[float] = None, *, max_depth: int = 40, max_pairs: int = 20000, refine_per_level: int = 8,
                 _trims: tuple = (None, None), _ceiling: Optional[float] = None) -> DistanceResult:
    """The global minimum distance between ``a`` and ``b`` (engine curves or surfaces of
    the same dimension), with a certified lower bound.

    A :class:`cagd.TrimmedSurface` counts as the face itself, not its untrimmed surface
    (:mod:`cagd.queries._distance_trimmed`: its boundary edges, and the pairs inside its
    trim); against a face the other object may also be an (N, dim) point set: the
    nearest of its points' closest points on the face (:func:`cagd.closest_point`; the
    parameter on the point set is the point's index).

    Stops when distance - lower_bound <= ``tol``, an absolute distance in model units
    (default DEFAULT_RTOL = 1e-9 times the size of the larger object, but at least
    ROUNDING_RTOL = 1e-14 times the extent of both together: objects 1e155 apart have
    their distance to 14 digits), after ``max_depth`` halvings, or when
    splitting the pairs alive would make more than ``max_pairs`` pairs (then the pairs
    with the largest bounds are dropped, their bounds kept in the certificate; at most
    ``max_pairs`` pairs exist at once). ``refine_per_level`` pairs are refined by Newton
    per level. Returns a :class:`DistanceResult`; a continuum of minima (concentric,
    coaxial, parallel objects) is certified through a fitted centre or axis and
    reported with ``isolated=False``. The work is done in the frame of both objects
    (:class:`cagd.queries.bounds.Frame`: translated and scaled to O(1)), so any model
    scale from 1e-300 to 1e300 gives the same answer scaled.

    Raises:
        CagdError: not curves/surfaces, different dimensions, tol <= 0 or NaN, bad
            limits; a distance beyond the float64 range.
    """
    from ..surfaces.trimmed import TrimmedSurface
    if _trims == (None, None) and (isinstance(a, TrimmedSurface) or isinstance(b, TrimmedSurface)):
        from ._distance_trimmed import trimmed_min_distance
        return trimmed_min_distance(a, b, tol, max_depth=max_depth, max_pairs=max_pairs,
                                    refine_per_level=refine_per_level, ceiling=_ceiling)
    A, B = sd.Geometry(a, "a"), sd.Geometry(b, "b")      # type: ignore[arg-type]
    if A.dim != B.dim:
        raise CagdError(f"a, b: objects of different dimension ({A.dim}-D and {B.dim}-D)")
    # work in the frame of both objects together (O(1): no squared distance overflows or
    # underflows at any model scale); distances and tolerances scale back by frame.scale
    frame = Frame.of(np.concatenate([A.bezier.control_points.reshape(-1, A.dim),
                                     B.bezier.control_points.reshape(-1, B.dim)]))
    scale = frame.scale
    given = None if tol is None else _checks.positive(tol, "tol")
    A.reframe(frame)
    B.reframe(frame)
    size = max(A.size, B.size)
    if given is None:
        # a distance between objects farther apart than their sizes is resolved to
        # ROUNDING_RTOL of their common extent at best: the default never asks for less
        extent = float(np.ptp(np.concatenate([sd.project(A.pieces.ctrl).reshape(-1, A.dim),
                                              sd.project(B.pieces.ctrl).reshape(-1, B.dim)]), axis=0).max())
        tol = max(DEFAULT_RTOL * size, ROUNDING_RTOL * extent)
    else:
        with np.errstate(over="ignore", under="ignore"):
            tol = float(np.float64(given) / scale)
        if tol == 0.0:
            raise CagdError(f"tol: {given!r} is below float64's resolution at the scale of the objects")
    max_depth = _checks.integer(max_depth, "max_depth", 0, 200)
    max_pairs = _checks.integer(max_pairs, "max_pairs", 16)
    refine_per_level = _checks.integer(refine_per_level, "refine_per_level", 1, 4096)
    ceiling = np.inf if _ceiling is None else float(_ceiling) / scale     # a distance known (frame units)
    trims = None
    if _trims != (None, None):
        from ._distance_trimmed import TrimTest
        trims = TrimTest(A, B, *_trims)
    ia, ib, floor = _first_pairs(A.pieces, B.pieces, max_pairs)   # floor: bounds of pairs dropped at the cap
    pa, pb = A.pieces.take(ia), B.pieces.take(ib)
    best = np.inf
    bx: Optional[np.ndarray] = None
    by: Optional[np.ndarray] = None
    settled = np.inf               # smallest bound among pairs settled (bound >= best - tol)
    direction: Optional[np.ndarray] = None
    flats: List[Flat] = []
    degenerate = False
    pool_p, pool_n, pool_d = np.empty((0, A.dim)), np.empty((0, A.dim)), np.empty(0)
    frac = np.mod(np.arange(1, refine_per_level + 1)[:, None] * _SPREAD[:A.k + B.k], 1.0)
    spread_a, spread_b = frac[:, :A.k], frac[:, A.k:]
    message = "" if not np.isfinite(floor) else f"pair cap {max_pairs} reached at the start; pairs beyond it dropped"

    def improve(x, y, dist):
        nonlocal best, bx, by, direction, degenerate
        if trims is not None:               # only pairs of points of the faces count
            on = trims.inside(x, y)
            if not on.any():
                return
            x, y, dist = x[on], y[on], dist[on]
        k = int(np.argmin(dist))
        if dist[k] < best:
            best, bx, by = float(dist[k]), x[k], y[k]
            px, py, pd = _polished(A, B, bx, by, best)
            if trims is None or trims.inside(px[None], py[None])[0]:
                bx, by, best = px, py, pd
            if best > 0:
                direction = B.points(by[None])[0] - A.points(bx[None])[0]
            degenerate = not _isolated(A, B, bx, by, best <= TOUCH_RTOL * size)

    def learn(x, y, dist):
        """Pool the normal lines of the minima near the best; fit centres and axes to them."""
        nonlocal pool_p, pool_n, pool_d, flats
        near = min(tol, FIT_WINDOW * size)
        p, n, ok = _normal_lines(A, B, x, y, dist <= best + near)
        keep = pool_d <= best + near
        pool_p = np.concatenate([pool_p[keep], p])[-POOL_SIZE:]
        pool_n = np.concatenate([pool_n[keep], n])[-POOL_SIZE:]
        pool_d = np.concatenate([pool_d[keep], dist[ok]])[-POOL_SIZE:]
        new = [f for f in fit_flats(pool_p, pool_n, size) if not any(_same_flat(f, g, size) for g in flats)]
        flats = flats + new[:MAX_FLATS - len(flats)]

    for depth in range(max_depth + 1):
        if trims is not None:               # pairs off the faces, or with no stationary point, go
            keep = trims.keep(pa, pb)
            pa, pb = pa.take(keep), pb.take(keep)
            if not len(pa.ctrl):
                lower = min(floor, settled, best, ceiling)
                break
        bound, split_a, split_b, modes_a, modes_b = _bounds(pa, pb, direction, flats)
        # upper bounds: corners, then Newton from the most promising pairs
        ca, la = _corners(pa.ctrl)
        cb, lb = _corners(pb.ctrl)
        d = np.linalg.norm(ca[:, :, None] - cb[:, None, :], axis=-1).reshape(len(ca), -1)
        m = int(np.argmin(d.min(axis=1)))
        i, j = divmod(int(np.argmin(d[m])), cb.shape[1])
        improve((pa.lo[m] + la[i] * (pa.hi[m] - pa.lo[m]))[None], (pb.lo[m] + lb[j] * (pb.hi[m] - pb.lo[m]))[None],
                d[m, i * cb.shape[1] + j][None])
        pick = np.argsort(bound)[:refine_per_level]
        xs, ys = 0.5 * (pa.lo[pick] + pa.hi[pick]), 0.5 * (pb.lo[pick] + pb.hi[pick])
        x, y, dist, _ = refine(A, B, xs, ys, True, 20)
        improve(x, y, dist)
        known = len(flats)
        if degenerate and best > 0:
            # a continuum of minima: fit a centre or an axis to the normal lines of the minima, at
            # first also of minima from points spread over the pairs that may hold the minimum
            learn(x, y, dist)
            open_ = np.flatnonzero(bound < min(best, ceiling) - tol)
            if not flats and open_.size:
                pick = open_[np.linspace(0, open_.size - 1, refine_per_level).astype(int)]
                xs = pa.lo[pick] + spread_a * (pa.hi[pick] - pa.lo[pick])
                ys = pb.lo[pick] + spread_b * (pb.hi[pick] - pb.lo[pick])
                x, y, dist, _ = refine(A, B, xs, ys, True, 20)
                improve(x, y, dist)
                learn(x, y, dist)
            if len(flats) > known:
                bound, split_a, split_b, modes_a, modes_b = _bounds(pa, pb, direction, flats)
        cap = min(best, ceiling)
        alive = bound < cap - tol
        if not alive.all():
            settled = min(settled, float(bound[~alive].min()))
        lower = min(float(bound[alive].min()) if alive.any() else np.inf, floor, settled, cap)
        if cap - lower <= tol:
            break
        if not alive.any():            # only pairs dropped at the cap could hold a closer point
            message = (f"pair cap {max_pairs} reached: the pairs dropped there bound the distance from "
                       f"below by {floor * scale:.6g}")
            break
        if depth == max_depth:
            message = (f"depth limit {max_depth} reached with {np.count_nonzero(alive)} pairs alive"
                       + (f" (and pairs dropped at the cap {max_pairs})" if np.isfinite(floor) else ""))
            break
        go = np.flatnonzero(alive)
        go = go[np.argsort(bound[go], kind="stable")]          # at most max_pairs children, nearest first
        modes_a = None if modes_a is None else modes_a[go]
        modes_b = None if modes_b is None else modes_b[go]
        count = _children(pa.take(go), pb.take(go), split_a[go], split_b[go], modes_a, modes_b)
        fits = np.cumsum(count) <= max_pairs
        if not fits.all():
            floor = min(floor, float(bound[go[~fits]].min()))
            message = f"pair cap {max_pairs} reached; pairs beyond it dropped with their bounds kept"
        go = go[fits]
        pa, pb, _ = sd.split_pairs(pa.take(go), pb.take(go), split_a[go], split_b[go],
                                   None if modes_a is None else modes_a[fits],
                                   None if modes_b is None else modes_b[fits])
    if bx is None or by is None:            # trimmed: no pair of face points beat the ceiling
        return DistanceResult(np.inf, (None, None), (None, None), float(lower) * scale, tol * scale,
                              bool(min(best, ceiling) - lower <= tol), True, message)
    # polish the best point (the Hessian test wants a stationary point)
    x, y, dist, _ = refine(A, B, bx[None], by[None], True, 20)
    improve(x, y, dist)
    lower = min(lower, best, ceiling)
    converged = min(best, ceiling) - lower <= tol
    pA, pB = frame.outward(A.points(bx[None]))[0], frame.outward(B.points(by[None]))[0]
    pA.flags.writeable = pB.flags.writeable = False
    distance = float(robust_distance(pA, pB))
    if not np.isfinite(distance):
        raise CagdError("a, b: their distance exceeds the float64 range")
    return DistanceResult(distance, (_param(A, bx), _param(B, by)), (pA, pB), min(float(lower) * scale, distance),
                          tol * scale, bool(converged), not degenerate, "" if converged else message)


def _param(G: sd.Geometry, x: np.ndarray) -> Union[float, np.ndarray]:
    u = G.user_params(x[None])[0]
    if G.k == 1:
        return float(u)
    u.flags.writeable = False
    return u
