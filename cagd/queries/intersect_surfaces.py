"""Surface–plane sections and surface–surface intersection curves (seed 004, ch. 1 §4,
positional relations between shapes), by subdivision for seeds and marching.

The intersection is the solution set of F(x) = 0, a curve in parameter space:
surface–surface x = (u, v, s, t), F = A(u, v) - B(s, t) (3 equations, 4 unknowns);
surface–plane x = (u, v), F = n.(A(u, v) - o) (the signed distance, 1 equation).

1. Seeds: Bezier patch pairs (patches and the plane) whose control-hull boxes overlap
   are halved, vectorized over all live pairs (Lane & Riesenfeld 1980), down to flat
   pieces of at most 1/16 of the model size; each leaf's midpoint goes to a
   minimum-norm Newton solve dx = -J^T (J J^T)^-1 F, i.e. Newton on F = 0 plus the
   plane constraint that the step is normal to the branch (Barnhill & Kersey, CAGD 7,
   1990; Patrikalakis & Maekawa, "Shape Interrogation for CAD/CAM", 5.8).
2. Marching: the tangent is the kernel of J (the generalized cross product of its
   rows; in 3-D the direction of n_A x n_B), scaled to unit speed in space; predictor
   x + h t, corrector Newton on [F; t.(x - x_pred)] = 0; the step h adapts to the
   curvature so that a cubic interpolant stays within ``tol`` (error ~ 5/384 h^4 k^3),
   the march stops on a domain boundary (solved exactly with the boundary parameter
   fixed), when the loop closes, or at a singular point. Closed but non-periodic
   directions (revolved surfaces, seams) are marched across. All marches advance in
   arrays: one start per cell of 1/16 of the model size, both directions, every lane
   in lock step (one evaluation of both surfaces and one batched corrector per round,
   :meth:`cagd.queries._marching.Marcher.drive`); a lane also ends where it meets
   another start, and the lanes are chained through the starts they met. Starts left
   over (on no chain) are marched one by one, as are pairs with a collapsed edge.
3. Singular points (n_A parallel to n_B: branch crossings such as the Steinmetz and
   Villarceau cases): the kernel vector changes orientation across a simple crossing
   (the determinant of the bordered Jacobian changes sign), so the crossing is found by
   bisection, the branch ends there, and a new branch starts on the other side; at the
   end, branch ends meeting at a crossing with opposite tangents are joined again, so
   a smooth branch through a crossing comes back as one curve (closed if it closes).
4. Every seed lying on a marched branch is absorbed (no duplicates). Each branch is
   fitted by cubic interpolation with chord-length parameters (Piegl & Tiller 9.2.1),
   the same parameters for the parameter-space curves; the achieved tolerance is the
   largest distance of the fitted curve from both surfaces at dense samples (Newton
   projection seeded by the parameter curves); points are added at corrected
   midpoints until it is within ``tol`` (at most a few rounds; otherwise reported).

5. Coincident pieces (a surface lying on the other, or in the plane) are found during
   the seed subdivision by projecting samples (:mod:`cagd.queries._surface_overlaps`)
   and reported as :class:`SurfaceOverlap` parameter boxes in ``overlaps``.
6. Collapsed edges (poles, apexes): branch ends meeting there in 3-D with opposite
   tangents are joined; the 3-D curve counts the point once (chord-length parameters)
   and the parameter curves run along the collapsed edge (:mod:`._branch_fit`).

Parameter curves of closed (periodic or seam) directions live in the covering space:
reduce them modulo the period to evaluate the surface
(:meth:`IntersectionCurve.surface_params`).
"""
from __future__ import annotations

from dataclasses import replace
from typing import List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from . import _subdivision as sd
from . import _surface_overlaps as so
from ._branch_fit import boundary_line as _boundary_line, degenerate as _degenerate, edge_fit as _edge_fit, \
    fit as _fit
from ._marching import Marcher, segments_distance
from ._point_solver import Plane, plane_geometry, run_many, sine_of
from .results import IntersectionCurve, IntersectionPoint, IntersectionResult, SurfaceOverlap
from ._overlaps import overlap_cap as _overlap_cap
from ._surface_system import System
from ._newton import newton, project_onto, refine
from ._numerics import AT_END_RTOL, DEFAULT_ANGLE_TOL, END_MARGIN_RTOL, SLACK_RTOL, TINY, residual_tol, unit
from ._newton import STEP_RTOL

SAME_POINT_RTOL = 1e-6   # points closer than this share of the size are one isolated point
TANGENCY_SINE = 1e-4     # seeds whose normals are nearer parallel than this are tangency candidates
JOIN_GAP_RTOL = 1e-9     # branch ends within max(10 tol, this share of the size) are joined
SEEN_RTOL = 1e-5         # a seed within this share of the size of a seen point is not marched again

__all__ = ["IntersectionCurve", "SurfaceOverlap", "surface_plane", "surface_surface"]


_SEED_FRACTION = 1.0 / 16      # leaves of the seed subdivision: at most this fraction of the model size
_REL_FLAT = 2e-2


# --- seeds -------------------------------------------------------------------------------
class _Hulls(NamedTuple):
    """Per pair of pieces: the boxes of both control hulls and the pieces' corner normals
    (:func:`cagd.queries._subdivision.corner_normal`)."""
    lo_a: np.ndarray
    hi_a: np.ndarray
    lo_b: np.ndarray
    hi_b: np.ndarray
    n_a: np.ndarray
    n_b: np.ndarray

    def take(self, index: np.ndarray) -> "_Hulls":
        return _Hulls(*(f[index] for f in self))

    @staticmethod
    def concat(parts: Sequence["_Hulls"]) -> "_Hulls":
        return _Hulls(*(np.concatenate(f) for f in zip(*parts)))


def _separated(pa: sd.Pieces, pb: sd.Pieces, tol: float) -> Tuple[np.ndarray, _Hulls]:
    """Pairs proven apart by more than tol: their control-hull boxes, or their hulls
    projected on the normal of either piece (convex hull property; the slab along a
    normal separates nearly parallel sheets long before their boxes do). Returns them
    and the hulls (the normals are set on the pairs not proven apart)."""
    lo_a, hi_a = sd.boxes(pa.ctrl)
    lo_b, hi_b = sd.boxes(pb.ctrl)
    out = sd.box_gap(lo_a, hi_a, lo_b, hi_b) > tol
    normals = []
    for P in (pa, pb):
        keep = np.flatnonzero(~out)
        n = np.zeros((len(out), 3))
        if keep.size:
            n[keep] = sd.corner_normal(P.ctrl[keep])
            out[keep] = sd.slab_gap(pa.ctrl[keep], pb.ctrl[keep], n[keep]) > tol
        normals.append(n)
    return out, _Hulls(lo_a, hi_a, lo_b, hi_b, normals[0], normals[1])


def _children(pa: sd.Pieces, pb: sd.Pieces, split_a, split_b, tol: float, chunk: int = 2048
              ) -> Tuple[sd.Pieces, sd.Pieces, _Hulls]:
    """Child pairs of the pairs (pa, pb) that are not proven apart, and their hulls, made
    a chunk of parents at a time so that the dead children of a large level never
    coexist."""
    out_a: List[sd.Pieces] = []
    out_b: List[sd.Pieces] = []
    hulls: List[_Hulls] = []
    for k in range(0, len(pa.ctrl), chunk):
        sl = slice(k, k + chunk)
        ca, cb, _ = sd.split_pairs(pa.take(sl), pb.take(sl), split_a[sl], split_b[sl])
        apart, h = _separated(ca, cb, tol)
        keep = np.flatnonzero(~apart)
        out_a.append(ca.take(keep))
        out_b.append(cb.take(keep))
        hulls.append(h.take(keep))
    return sd.Pieces.concat(out_a), sd.Pieces.concat(out_b), _Hulls.concat(hulls)


def _seeds_pair(A: sd.Geometry, B: sd.Geometry, tol: float, max_pairs: int):
    i, j = sd.box_pairs(A.pieces, B.pieces, tol)
    pa, pb = A.pieces.take(i), B.pieces.take(j)
    size = max(A.size, B.size)
    leaf = _SEED_FRACTION * size
    seeds, complete = [], True
    cov: Tuple[List[np.ndarray], ...] = ([], [], [], [])  # covered boxes of a, their params on b; the same for b
    hulls: Optional[_Hulls] = None
    for level in range(40):
        if len(pa.ctrl) == 0:
            break
        # (children come from _children, which kept only the pairs _separated does not part)
        if hulls is None:
            apart, hulls = _separated(pa, pb, tol)
            live = ~apart
        else:
            live = np.ones(len(pa.ctrl), bool)
        live &= ~so.covered(pa.lo, pa.hi, cov[0]) & ~so.covered(pb.lo, pb.hi, cov[2])
        dev_a, ext_a = sd.flatness(pa.ctrl)
        dev_b, ext_b = sd.flatness(pb.ctrl)
        # coincident pieces: nearly parallel and too large for a tangency to fake it. No
        # flatness is asked of them (lying_on projects samples: curved pieces are tested as
        # well): with "flat-ish" (dev <= 0.15 ext) the first flat pieces of a unit sphere
        # were 0.54 across, below the cap 2 sqrt(2 tol size) from tol = 1.8e-2 on, and
        # intersect(sphere, sphere, tol=2e-2) gave 8,914 contact points in 50 s
        sine = np.linalg.norm(np.cross(hulls.n_a, hulls.n_b), axis=1)
        test = np.flatnonzero(live & (sine < 0.05) & (np.minimum(ext_a, ext_b) >= _overlap_cap(tol, size)))
        if test.size:
            for P, Q, G, H, k in ((pa, pb, A, B, 0), (pb, pa, B, A, 2)):
                hit, mid = so.lying_on(G, H, None, P.lo[test], P.hi[test], Q.lo[test], Q.hi[test], tol,
                                        Q.ctrl[test])
                if hit.any():
                    cov[k].append(np.concatenate([P.lo[test][hit], P.hi[test][hit]], axis=1))
                    cov[k + 1].append(mid[hit])
            live &= ~so.covered(pa.lo, pa.hi, cov[0]) & ~so.covered(pb.lo, pb.hi, cov[2])
        da = np.linalg.norm(hulls.hi_a - hulls.lo_a, axis=1)
        db = np.linalg.norm(hulls.hi_b - hulls.lo_b, axis=1)
        done = live & (dev_a <= _REL_FLAT * ext_a + tol) & (dev_b <= _REL_FLAT * ext_b + tol) \
            & (da <= leaf) & (db <= leaf)
        go = np.flatnonzero(live & ~done)
        if done.any():
            seeds.append(_midpoints(pa, pb, done))
        if go.size == 0:
            break
        ca, cb, hulls = _children(pa.take(go), pb.take(go), da[go] >= 0.5 * db[go], db[go] >= 0.5 * da[go], tol)
        if len(ca.ctrl) > max_pairs:          # too many: the open pairs' midpoints become seeds
            complete = False
            seeds.append(_midpoints(pa, pb, go))
            break
        pa, pb = ca, cb
    if cov[0]:
        regions = so.regions(A, B, None, cov[0], cov[1], tol)
    else:
        regions = so.regions(B, A, None, cov[2], cov[3], tol, swap=True)
    return (np.concatenate(seeds) if seeds else np.empty((0, 4))), complete, regions


def _midpoints(pa: sd.Pieces, pb: sd.Pieces, sel) -> np.ndarray:
    return np.concatenate([0.5 * (pa.lo[sel] + pa.hi[sel]), 0.5 * (pb.lo[sel] + pb.hi[sel])], 1)


def _seeds_plane(A: sd.Geometry, pl, tol: float, max_pairs: int):
    o, nrm = pl
    p = A.pieces
    leaf = _SEED_FRACTION * A.size
    seeds, complete = [], True
    cov = []
    for _ in range(40):
        if len(p.ctrl) == 0:
            break
        P = sd.project(p.ctrl).reshape(len(p.ctrl), -1, 3)
        d = (P - o) @ nrm
        live = (d.min(axis=1) <= tol) & (d.max(axis=1) >= -tol)
        # convex hull: the piece lies in the plane; an overlap only where a tangency could
        # not fake it (a cap of radius sqrt(2 R tol) lies within tol of its tangent plane)
        diag = np.linalg.norm(P.max(axis=1) - P.min(axis=1), axis=1)
        inplane = live & (np.abs(d).max(axis=1) <= tol) & (diag >= _overlap_cap(tol, A.size))
        if inplane.any():
            cov.append(np.concatenate([p.lo[inplane], p.hi[inplane]], axis=1))
            live &= ~inplane
        dev, ext = sd.flatness(p.ctrl)
        done = live & (dev <= _REL_FLAT * ext + tol) & (diag <= leaf)
        go = np.flatnonzero(live & ~done)
        if go.size * 4 > max_pairs:
            complete = False
            done, go = live, go[:0]
        if done.any():
            seeds.append(0.5 * (p.lo[done] + p.hi[done]))
        if go.size == 0:
            break
        p = sd.split(p.take(go))[0]
    regions = so.regions(A, None, pl, cov, [], tol)
    return (np.concatenate(seeds) if seeds else np.empty((0, 2))), complete, regions


def _boundary_seeds(A: sd.Geometry, B: Optional[sd.Geometry], pl, tol: float, max_pairs: int,
                    regions=()) -> Tuple[np.ndarray, List[np.ndarray], bool]:
    """Points where the boundary curves of each surface meet the other object (curve–
    surface subdivision of :mod:`cagd.queries.intersect`, rigorous down to its leaves):
    every branch that is not a closed loop ends on a boundary (or at a singular point),
    so these seeds find small branches cut off by a corner, which a leaf-centre seed of
    the surface subdivision can miss (Barnhill & Kersey 1990: boundary points first).
    The parts of a boundary inside a coincident region are left out.

    A boundary piece lying on the other object (two patches sharing an edge, tangent
    along it when joined G1, where marching cannot start) comes back as a ready branch:
    parameter rows along the piece (64 per Bezier span, the other object's parameters
    by projection). Returns (seeds (N, n), edge branches [(M, n)], all boundary runs
    converged)."""
    out: list = []
    edges: List[np.ndarray] = []
    complete = True
    sides = [(A, B, 0)] + ([(B, A, 1)] if B is not None else [])
    found: List[tuple] = []                   # the edge branches of a's boundaries, as branches
    for G, H, k in sides:
        if k == 1 and edges:
            found = [(None, None, A.points(xs[:, :2])) for xs in edges]
        jobs, where = [], []                    # a side's boundary runs, subdivided in lock step
        for d in range(2):                      # d: the fixed parameter of the boundary
            if G.closed[d]:
                continue                        # a seam is no boundary: branches cross it
            for val in (G.lo[d], G.hi[d]):
                surface = G.nurbs
                assert isinstance(surface, BSplineSurface)      # boundary seeds: surfaces only
                C = surface.isocurve("v" if d == 0 else "u", float(val))
                net = np.asarray(C.control_points)
                if np.ptp(net, axis=0).max() <= SLACK_RTOL * G.size:
                    continue                    # a collapsed edge (a pole): a point
                for t0, t1 in _outside(regions, k, d, val, G.lo[1 - d], G.hi[1 - d], G.closed[1 - d]):
                    piece = C if (t0, t1) == (G.lo[1 - d], G.hi[1 - d]) else C.segment(t0, t1)
                    Cg = sd.Geometry(piece, "a")
                    if found and _on_edges(G, d, val, t0, t1, len(Cg.pieces.ctrl), found, tol):
                        continue        # the other surface's edge already found: the same branch
                    jobs.append((Cg, H if H is not None else plane_geometry(Plane(*pl), Cg)))
                    where.append((d, val))
        for (Cg, _), (d, val), res in zip(jobs, where, run_many(jobs, tol, DEFAULT_ANGLE_TOL, 64, max_pairs)):
            complete &= res.converged
            out += _seed_rows(res.points, d, val, H, k)
            for ov in res.overlaps:
                edges.append(_edge_rows(G, H, k, d, val, ov.param_a, len(Cg.pieces.ctrl)))
    n = 4 if B is not None else 2
    return np.array(out).reshape(-1, n), edges, complete


def _on_edges(G: sd.Geometry, d: int, val: float, t0: float, t1: float, pieces: int, found, tol: float) -> bool:
    """The boundary piece of G (parameter d = val, the other from t0 to t1; 16 samples a
    Bezier span) lies on the edge branches ``found`` (:func:`_absorbed`): two faces
    sharing an edge, whose other boundary run would find it again (as an overlap, the
    same branch, dropped in :func:`_trace`) at the cost of a second near-tangent
    subdivision (boxed_sphere.step Document[190] x [191], issue 16)."""
    x = np.empty((16 * max(pieces, 1) + 1, 2))
    x[:, d], x[:, 1 - d] = val, np.linspace(t0, t1, len(x))
    return bool(np.all(_absorbed(G.points(x), found, residual_tol(tol, G.size))))


def _edge_rows(G: sd.Geometry, H, k: int, d: int, val: float, span, pieces: int) -> np.ndarray:
    """Parameter rows (M, n) along G's boundary (parameter d = val) from span[0] to
    span[1], where it lies on H (None: a plane): H's parameters by projection."""
    s = np.linspace(span[0], span[1], 64 * max(pieces, 1) + 1)
    x = np.empty((len(s), 2))
    x[:, d], x[:, 1 - d] = val, s
    if H is None:
        return x
    P = G.points(x)
    y, _ = project_onto(H, P, so.grid_seeds(H, P, H.lo[None], H.hi[None], 16))
    return np.concatenate([x, y], axis=1) if k == 0 else np.concatenate([y, x], axis=1)


def _outside(regions, k: int, d: int, val: float, lo: float, hi: float, closed: bool = False):
    """Intervals of [lo, hi] (the free parameter of the boundary where parameter d of
    surface k is val) outside the overlap regions' boxes, each cut back by 1e-6; a box
    running past hi in a closed direction also covers [lo, its end - period]."""
    cuts = []
    for r in regions:
        box = (r.box_a, r.box_b)[k]
        # (a box ending 1 ulp short of the domain's end still covers the boundary there)
        reach = AT_END_RTOL * (box[d][1] - box[d][0]) if box is not None else 0.0
        if box is not None and box[d][0] - reach <= val <= box[d][1] + reach:
            a, b = box[1 - d]
            cuts.append((a, min(b, hi)))
            if closed and b > hi:
                cuts.append((lo, b - (hi - lo)))
    free, start = [], lo
    m = END_MARGIN_RTOL * (hi - lo)
    for a, b in sorted(cuts):
        if a - m > start + m:
            free.append((start, a - m))
        start = max(start, b + m)
    if start < hi - m:
        free.append((start, hi))
    return free


def _seed_rows(points, d: int, val: float, H, k: int):
    out = []
    for p in points:
        x = np.empty(2)
        x[d], x[1 - d] = val, p.param_a
        if H is None:
            out.append(x)
            continue
        y = np.array(p.param_b, float)
        if H.triangle:                # user (u, v) -> NURBS (u, w), v = w (1 - u)
            y[1] = y[1] / (1.0 - y[0]) if y[0] < 1.0 else 0.5
        out.append(np.concatenate([x, y]) if k == 0 else np.concatenate([y, x]))
    return out


# --- driver ------------------------------------------------------------------------------
def _trace(S: System, seeds: np.ndarray, tol: float, regions=(), edges=()):
    M = Marcher(S, tol)
    x, ok = newton(S, seeds, None, None, M.ftol, iters=30)
    inside = np.zeros(len(x), bool)
    if regions:                       # roots inside a coincident region are part of the overlap
        xw = S.wrap(x)
        inside = so.inside(xw[:, :2], regions, S.A.lo, S.A.hi, 0, S.per[:2])
        if S.B is not None:
            inside |= so.inside(xw[:, 2:], regions, S.B.lo, S.B.hi, 1, S.per[2:])
    touches = _near_misses(S, x[~ok & ~inside], tol)
    ok &= ~inside
    flat, at = _tangencies(S, x[ok], tol)
    touches = np.concatenate([touches, at])
    x = x[ok][~flat]
    P = S.eval(x)[2] if len(x) else np.empty((0, 3))
    alive = np.ones(len(x), bool)
    branches: List[tuple] = []            # (xs (K, n), ends (start, end), other-side starts)
    isolated = list(touches)
    problems = []
    for xs in edges:                  # boundary pieces lying on the other object
        Pb = S.eval(xs)[2]
        if branches and _absorbed(Pb[len(Pb) // 2:len(Pb) // 2 + 1], branches, M.ftol)[0]:
            continue                  # the same shared edge, seen from the other surface
        branches.append((xs, ["boundary", "boundary"], Pb))
        if len(x):
            alive &= ~_absorbed(P, [branches[-1]], M.ftol)
    queue: List[np.ndarray] = []
    if alive.any() and not S.collapsed:      # one start per cell of 1/16 of the size, all marched at once
        # (not where a surface has a pole: a lane reaching it from inside ends there as singular,
        # on an arbitrary parameter along the collapsed edge; the one-by-one march starts there)
        pick = np.flatnonzero(alive)
        pick = pick[_spread(P[pick], _SEED_FRACTION * S.size)]
        chains, used, queue = M.march_seeds(x[pick])
        alive[pick[used]] = False
        for xs, ends in chains:
            problems += [e for e in ends if e in ("stalled", "limit")]
            branches.append((xs, list(ends), S.eval(xs)[2]))
        if chains and alive.any():
            rest = np.flatnonzero(alive)
            alive[rest[_absorbed(P[rest], branches[-len(chains):], M.ftol)]] = False
    order = list(range(len(x)))
    while True:
        if queue:
            start = queue.pop(0)
        else:
            idx = next((i for i in order if alive[i]), None)
            if idx is None:
                break
            alive[idx] = False
            start = x[idx]
        Pst = S.eval(start[None])[2]
        if branches and _absorbed(Pst, branches, M.ftol)[0]:
            continue
        (fw, end_f, other_f), back = M.march_both(start)
        if back is None:
            xs, ends = np.array(fw), ("closed", "closed")
        else:
            bw, end_b, other_b = back
            xs = np.array(bw[::-1] + fw[1:])
            ends = (end_b, end_f)
            if other_b is not None:
                queue.append(other_b)
        if other_f is not None:
            queue.append(other_f)
        if len(xs) < 2:
            F, J, Pp, na, nb, _ = S.eval(xs[:1])
            isolated.append(xs[0])
            alive &= np.linalg.norm(P - Pp[0], axis=1) > SAME_POINT_RTOL * S.size
            continue
        for e in ends:
            if e in ("stalled", "limit"):
                problems.append(e)
        Pb = S.eval(xs)[2]
        branches.append((xs, list(ends), Pb))
        if alive.any():
            rest = np.flatnonzero(alive)
            alive[rest[_absorbed(P[rest], [branches[-1]], M.ftol)]] = False
    return branches, isolated, problems


def _spread(P: np.ndarray, cell: float) -> np.ndarray:
    """Indices of the first point in each cube of edge ``cell`` (in their order)."""
    key = np.floor((P - P.min(axis=0)) / max(cell, TINY)).astype(np.int64)
    _, first = np.unique(key, axis=0, return_index=True)
    return np.sort(first)


def _near_misses(S: System, x: np.ndarray, tol: float) -> np.ndarray:
    """Seeds where Newton found no root but stopped (Gauss-Newton: at a local minimum of
    |F|) with |F| <= tol: the surfaces touch within tol without crossing (a miss by less
    than tol counts as a tangential contact, as for curves); polished by :func:`_touch`."""
    if len(x) == 0:
        return np.empty((0, S.n))
    x = x[np.linalg.norm(S.eval(x)[0], axis=1) <= tol]
    y, dist = _touch(S, x)
    return y[dist <= tol]


def _touch(S: System, x: np.ndarray):
    """The nearest contact of the surfaces from x: surface pairs by minimizing the
    distance (:func:`cagd.queries._newton.refine`, second order), a surface and a
    plane by Newton on grad (n . A) = 0 (the normal along n). Returns (x, distance)."""
    if len(x) == 0:
        return x, np.empty(0)
    if S.B is not None:
        xw = S.wrap(x)
        xa, xb, dist, _ = refine(S.A, S.B, xw[:, :2], xw[:, 2:], True, 40)
        return np.concatenate([xa, xb], axis=1), dist
    nrm = S.pl[1]
    for _ in range(20):
        _, d1, d2 = S.A.derivatives(S.wrap(x), 2)
        g = d1 @ nrm                                             # (N, 2)
        H = d2 @ nrm                                             # (N, 2, 2)
        det = H[:, 0, 0] * H[:, 1, 1] - H[:, 0, 1] ** 2
        good = np.abs(det) > TINY
        step = np.zeros_like(x)
        step[good] = -np.linalg.solve(H[good], g[good][..., None])[..., 0]
        x = S.clip(x + step)
        if np.all(np.abs(step) <= STEP_RTOL * S.span):
            break
    return x, np.abs(S.eval(x)[0][:, 0])


def _tangencies(S: System, x: np.ndarray, tol: float, angle: float = DEFAULT_ANGLE_TOL
                ) -> Tuple[np.ndarray, np.ndarray]:
    """Roots x where the surfaces are nearly tangent (sine < 1e-4) and the nearest
    contact from there (:func:`_touch`) is a tangency (sine <= ``angle``, within tol):
    the root lies in the flat valley round a touch point (|F| <= ftol over a cap of
    radius ~ sqrt(ftol R)), where Newton may stop anywhere and no branch passes; a
    branch crossing at a small angle keeps its roots. Returns the mask and the touches."""
    if len(x) == 0:
        return np.zeros(0, bool), np.empty((0, S.n))
    _, _, _, na, nb, _ = S.eval(x)
    weak = np.flatnonzero(np.linalg.norm(np.cross(na, nb), axis=1) < TANGENCY_SINE)
    out = np.zeros(len(x), bool)
    if weak.size == 0:
        return out, np.empty((0, S.n))
    y, dist = _touch(S, x[weak])
    _, _, _, na, nb, _ = S.eval(y)
    hit = (dist <= tol) & (np.linalg.norm(np.cross(na, nb), axis=1) <= angle)
    out[weak[hit]] = True
    return out, y[hit]


def _absorbed(Q, branches, ftol):
    """Points within a tenth of the nearest segment's length (plus 10 ftol) of a branch's
    polyline."""
    hit = np.zeros(len(Q), bool)
    for _, _, Pb in branches:
        within = 0.1 * float(np.linalg.norm(np.diff(Pb, axis=0), axis=1).max(initial=0.0)) + 10 * ftol
        d, L = segments_distance(Q, Pb, within=within)
        hit |= d <= 0.1 * L + 10 * ftol
    return hit


def _join(S: System, branches, tol):
    """Join branch ends meeting at a crossing with opposite tangents."""
    items = [[b[0], list(b[1]), b[2]] for b in branches]
    gap = max(10 * tol, JOIN_GAP_RTOL * S.size)
    changed = True
    while changed:
        changed = False
        ends = []
        for bi, (xs, e, P) in enumerate(items):
            if _boundary_line(S, xs) is not None:
                continue                # a shared edge stays one exact boundary curve (edge_fit)
            for side, k, k1 in ((0, 0, 1), (1, -1, -2)):
                if len(P) >= 2 and (e[side] == "singular" or (e[side] == "boundary" and _degenerate(S, xs[k]))):
                    ends.append((bi, side, P[k], unit(P[k1] - P[k])))
        best = None
        for i in range(len(ends)):
            for j in range(i + 1, len(ends)):
                a, b = ends[i], ends[j]
                if a[0] == b[0] and len(items[a[0]][0]) < 4:
                    continue
                if np.linalg.norm(a[2] - b[2]) <= gap and a[3] @ b[3] < -0.9:
                    score = a[3] @ b[3]
                    if best is None or score < best[0]:
                        best = (score, a, b)
        if best is None:
            break
        _, a, b = best
        jump = _degenerate(S, items[a[0]][0][-1 if a[1] else 0])    # a collapsed edge: keep both params
        if a[0] == b[0]:                                   # one branch closes through the crossing
            xs, e, P = items[a[0]]
            xs = xs.copy()
            if not jump:
                xs[-1] = xs[-2] + S.wrapdiff(xs[0] - xs[-2])
            P = P.copy()
            P[-1] = P[0]
            items[a[0]] = [xs, ["closed", "closed"], P]
        else:
            ia, ib = a[0], b[0]
            xa, ea, Pa = items[ia]
            xb, eb, Pb = items[ib]
            if a[1] == 0:
                xa, Pa, ea = xa[::-1], Pa[::-1], ea[::-1]
            if b[1] == 1:
                xb, Pb, eb = xb[::-1], Pb[::-1], eb[::-1]
            shift = xa[-1] + S.wrapdiff(xb[0] - xa[-1]) - xb[0]
            xb = xb + shift
            k = 0 if jump else 1          # at a collapsed edge the branch runs along it: one 3-D point, two params
            xs = np.concatenate([xa, xb[k:]])
            P = np.concatenate([Pa, Pb[k:]])
            items = [it for k, it in enumerate(items) if k not in (ia, ib)] + [[xs, [ea[0], eb[1]], P]]
        changed = True
    return items


def _solve(S: System, seeds, complete, tol, angle_tol, regions=(), edges=()):
    branches, isolated, problems = _trace(S, seeds, tol, regions, edges)
    items = _join(S, branches, tol)
    curves = []
    messages = []
    for xs, ends, P in items:
        closed = ends[0] == "closed"
        fitted = None if closed else _edge_fit(S, xs, tol)
        if fitted is None or max(fitted[3], fitted[4]) > tol:       # not an edge, or its parameter curve
            fit = _fit(S, xs, P, closed, tol)                         # on the other surface is off: the fit
            fitted = fit if fitted is None or max(fit[3], fit[4]) < max(fitted[3], fitted[4]) else fitted
        curve, pa, pb, worst, worst_p = fitted
        why = [f"fitted within {max(worst, worst_p):.2e} > tol"] if max(worst, worst_p) > tol else []
        why += [f"the march {e} at an end" for e in ends if e in ("stalled", "limit")]
        doms = [(S.lo[k:k + 2], S.hi[k:k + 2], S.per[k:k + 2]) for k in range(0, S.n, 2)]
        curves.append(IntersectionCurve(curve, pa, pb, closed, worst, worst_p, not why, tuple(ends),
                                        (doms[0], doms[1] if S.n == 4 else None), "; ".join(why)))
        if max(worst, worst_p) > tol:
            messages.append(f"a branch was fitted within {max(worst, worst_p):.2e} > tol")
    points: List[IntersectionPoint] = []
    seen: List[np.ndarray] = []
    X = np.array(isolated).reshape(-1, S.n)
    Fs, _, Ps, nas, nbs, _ = S.eval(X)
    # (a degenerate point (a pole) where a march could not start, on a branch: not a point)
    off = ~_absorbed(Ps, [(None, None, it[2]) for it in items], Marcher(S, tol).ftol) if items and len(X) \
        else np.ones(len(X), bool)
    for i in np.flatnonzero(off):
        x, F, P = X[i], Fs[i], Ps[i]
        if seen and np.linalg.norm(np.array(seen) - P, axis=1).min() <= SEEN_RTOL * S.size:
            continue          # the same contact reached from several seeds
        seen.append(P)
        sine = float(np.linalg.norm(np.cross(nas[i], nbs[i])))
        pb_ = S.B.user_params(S.wrap(x)[None, 2:])[0] if S.B is not None else None
        residual = float(np.linalg.norm(F))
        points.append(IntersectionPoint(S.A.user_params(S.wrap(x)[None, :2])[0], pb_, P,
                                        sine <= sine_of(max(angle_tol, DEFAULT_ANGLE_TOL)), residual, residual <= tol,
                                        "" if residual <= tol else f"residual {residual:.3g} above tol"))
    if len(points) >= 5:
        Q = np.array([p.point for p in points])
        gaps = np.linalg.norm(Q[:, None] - Q[None], axis=-1)
        np.fill_diagonal(gaps, np.inf)
        if np.all(gaps.min(axis=1) <= 0.25 * S.size):
            text = (f"{len(points)} contact points lie along a curve (a curve of tangency, "
                    "which is not traced as a branch)")
            messages.append(text)
            points = [replace(p, converged=False, message=text) for p in points]
    if problems:
        messages.append(f"marching did not converge at {len(problems)} branch end(s) ({', '.join(problems)})")
    if not complete:
        messages.append("the seed subdivision (or a boundary curve's) hit max_pairs")
    converged = not messages
    return IntersectionResult(tuple(points), tuple(regions), tuple(curves), tol, converged, "; ".join(messages))


def surface_surface(a: Union[Surface, sd.Geometry], b: Union[Surface, sd.Geometry], tol: float,
                    angle_tol: float = DEFAULT_ANGLE_TOL,
                    max_pairs: int = 20000) -> IntersectionResult:
    """Intersection curves of two surfaces (see the module docstring); returns an
    :class:`IntersectionResult` whose ``curves`` are :class:`IntersectionCurve` branches."""
    A = a if isinstance(a, sd.Geometry) else sd.Geometry(a, "a")       # or prepared by intersect
    B = b if isinstance(b, sd.Geometry) else sd.Geometry(b, "b")
    if A.k != 2 or B.k != 2:
        raise CagdError("a, b: surface_surface needs two surfaces")
    if A.dim != 3 or B.dim != 3:
        raise CagdError(f"a, b: surface intersection needs 3-D surfaces, got {A.dim}-D and {B.dim}-D")
    seeds, complete, regions = _seeds_pair(A, B, tol, max_pairs)
    bseeds, edges, done = _boundary_seeds(A, B, None, tol, max_pairs, regions)
    return _solve(System(A, B), np.concatenate([bseeds, seeds]), complete and done, tol, angle_tol, regions,
                  edges)


def surface_plane(a: Surface, pl: Plane, tol: float, angle_tol: float = DEFAULT_ANGLE_TOL,
                  max_pairs: int = 20000) -> IntersectionResult:
    """Section of a surface by a plane (``pl`` from :func:`cagd.queries.plane`): the
    level set n.(A(u, v) - o) = 0 marched like a surface–surface intersection."""
    A = sd.Geometry(a, "a")
    if A.k != 2:
        raise CagdError("a: surface_plane needs a surface")
    if A.dim != 3:
        raise CagdError(f"a: a plane lives in 3-D, the surface is {A.dim}-D")
    o, nrm = np.asarray(pl.origin, float), np.asarray(pl.normal, float)
    seeds, complete, regions = _seeds_plane(A, (o, nrm), tol, max_pairs)
    bseeds, edges, done = _boundary_seeds(A, None, (o, nrm), tol, max_pairs, regions)
    seeds, complete = np.concatenate([bseeds, seeds]), complete and done
    return _solve(System(A, None, (o, nrm)), seeds, complete, tol, angle_tol, regions, edges)
