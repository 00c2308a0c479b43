"""Closest points on a trimmed face (issue 15): the nearest point of the face itself,
interior or on a boundary edge, with a certified lower bound.

The face F = S(D) is a part of its surface S, so the untrimmed answer (certified over S)
is F's wherever its foot lies in D. The untrimmed search is certified only for the
points whose Newton foot lies in D (``Projector._closest``'s defer: the others' search
below stands on its own). For the other points F's distance is the smaller of

- the distance to the boundary S(dD): each loop's 3-D image (``boundary()``: exact
  iso-curves, or fits within their reported error), its curves joined into one curve
  (one query per loop), the foot then moved onto the face itself, S(c(t)), so the
  distance found is attained by a point of F;
- an interior minimum inside D: branch and bound over the surface's Bezier cells, each
  classified against the trim (a cell outside D is dropped, only feet inside D count),
  with the projector's second-order lower bounds (Piegl & Tiller 6.1 for the Newton step;
  the bounds as in :mod:`cagd.queries.closest`). Where g = |S - X|^2 is strongly convex
  on a box (the bound's m > 0), the face's minimum over box & D, unless on dD, is g's
  minimiser over the box, which the bound's quadratic confines to a small box about the
  Newton point: the box is cut down to it (and then usually classified outside D). A
  box whose bound reaches the edges' lower bound is closed (it cannot lower the
  certificate). Before that, a point is settled at once where g is strongly convex on
  a box B about its untrimmed foot whose minimiser lies outside D, and on the box
  spanned by B and its open cells (:func:`_hull_settled`): the face's minimum there is
  on dD. Boxes smaller than the loops' chord bounds are classified by the curve pieces
  themselves (``_Flattened.pieces_meet``), so that the halving ends.

The lower bound reported is the largest of the untrimmed one and the minimum of the
boundary curves' bounds (less FIT_ERROR_SAFETY times the fits' measured error, where an
edge is a fit: that part of the certificate rests on the fit's sampled error) and the
bounds of the cells left.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, Optional, Tuple
import weakref

import numpy as np
from numpy.typing import ArrayLike

from .._ranks import ranks
from ..errors import CagdError
from ._cells import split_boxes
from .bounds import box_lower_bound, robust_distance
from ._numerics import BOUND_SHRINK_RTOL, SIZE_ROUNDING, SLACK_RTOL, TINY, smallest_per_group

if TYPE_CHECKING:
    from ..curves.bspline import BSplineCurve
    from ..surfaces.base import Surface
    from ..surfaces.trimmed import TrimBoundary, TrimmedSurface
    from .closest import ClosestPoints, Projector
    from .results import IntersectionResult

#: relative gap below which a cell's lower bound counts as reaching the distance found
CELL_GAP = 1e-10
#: outside points whose branch and bound runs together (the row bound holds per group)
TRIM_POINT_CHUNK = 8192
#: rounds of the branch and bound at most (each halves the open cells' boxes)
MAX_TRIM_ROUNDS = 60
#: open (point, box) rows at most per round (bounded work: the bound reached is reported)
MAX_TRIM_ROWS = 2_000_000
#: margin on the gradient's variation bound before a box is said to hold no stationary point
CRITICAL_SAFETY = 1.0 + 1e-9
#: cells per direction of the grid of chord boxes (box_classes)
GRID = 128
#: grid cells of boxes expanded at once
GRID_CHUNK = 1 << 18
#: a box is tested against a loop's curve pieces, not the chord, where the chord's bound
#: exceeds this share of the box's larger side (the chords alone cannot split it further)
FINE_BOX = 0.25
#: the boundary fits' error is measured at samples (TrimBoundary.error), not bounded: the
#: lower bound from a fitted edge subtracts this multiple of it
FIT_ERROR_SAFETY = 4.0
#: a box touches a crease when its side is within KINK_TOL (relative to the domain) of it
KINK_TOL = 1e-12
#: (point, box) rows evaluated at once by the stationary-point test
ROW_CHUNK = 1 << 16
#: points that descend the projector's hierarchy of cells at once
TREE_CHUNK = 2048
#: a foot on a joined loop within this share of its domain from a joint is at the joint
JOINT_TOL = 1e-12
#: margin on the reach of a convex box's minimiser (rounding in its bound)
CONVEX_SAFETY = 1.0 + 1e-6
#: a box cut down to its minimiser's reach by at least this factor per side is not halved
SHRUNK = 0.5
#: half-widths tried for the convex box about an untrimmed foot, as shares of its cell (largest first)
CONVEX_BOX_SHARES = (1.0, 0.5, 0.25, 0.125)
#: cells of the box spanned by a point's open rows at most, tested for convexity (:func:`_hull_settled`)
MAX_HULL_CELLS = 64
#: quarterings of the cells where that test fails (each quarter expanded at its own centre)
HULL_SPLITS = 2
#: halvings of the open boxes before a point outside the trim goes to the branch and bound
SETTLE_LEVELS = 3

_PREPARED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _prepared(ts: "TrimmedSurface", p: "Projector") -> Tuple["TrimBoundary", np.ndarray]:
    """The face's 3-D boundary curves, computed once per face (the face is a value), and
    the classes (:func:`box_classes`) of the projector's cells, once per projector (a
    face has one per tier: a light one for a few points, the default for many)."""
    try:
        hit = _PREPARED.get(ts)
    except TypeError:
        hit = None
    if hit is None:
        per_projector: Dict[int, Tuple[weakref.ref, np.ndarray]] = {}
        hit = (ts._image_boundary(), per_projector)
        try:
            _PREPARED[ts] = hit
        except TypeError:
            pass
    bd, classes = hit
    entry = classes.get(id(p))
    if entry is None or entry[0]() is not p:
        cls = box_classes(ts, p.frame.params(p.lo), p.frame.params(p.hi))
        for key in [k for k, (ref, _) in classes.items() if ref() is None]:     # projectors gone
            del classes[key]
        classes[id(p)] = entry = (weakref.ref(p), cls)
    return bd, entry[1]


class _ChordGrid:
    """The loops' chord boxes (cmin, cmax) registered in a GRID x GRID grid over their
    extent (CSR: cell -> chords), so that a parameter box meets only the chords of the
    cells it covers."""

    def __init__(self, A: np.ndarray, B: np.ndarray, r: np.ndarray):
        cmin, cmax = np.minimum(A, B) - r[:, None], np.maximum(A, B) + r[:, None]
        self.cmin, self.cmax, self.A, self.r = cmin, cmax, A, r
        d = B - A
        length = np.hypot(d[:, 0], d[:, 1])
        self.normal = np.where(length[:, None] > 0, np.stack([-d[:, 1], d[:, 0]], axis=1)
                               / np.maximum(length, TINY)[:, None], 0.0)
        self.lo, hi = cmin.min(axis=0), cmax.max(axis=0)
        self.step = np.maximum((hi - self.lo) / GRID, TINY)
        i0, i1 = self._cells(cmin), self._cells(cmax)
        cu, cv = i1[:, 0] - i0[:, 0] + 1, i1[:, 1] - i0[:, 1] + 1
        n = cu * cv
        chord = np.repeat(np.arange(len(cmin)), n)
        k = ranks(n)
        cell = (i0[chord, 0] + k // cv[chord]) * GRID + i0[chord, 1] + k % cv[chord]
        order = np.argsort(cell, kind="stable")
        self.chords = chord[order]
        self.start = np.searchsorted(cell[order], np.arange(GRID * GRID + 1))

    def _cells(self, x: np.ndarray) -> np.ndarray:
        return np.clip(np.floor((x - self.lo) / self.step), 0, GRID - 1).astype(np.int64)

    def meets(self, lo: np.ndarray, hi: np.ndarray, flat: Any = None) -> np.ndarray:
        """Per box [lo, hi]: whether some chord box meets it (in chunks of pairs); with
        ``flat`` (the loops' chords), pairs where the chord's bound exceeds FINE_BOX times
        the box's larger side are decided by the curve pieces themselves
        (``flat.pieces_meet``): boxes below the chords' resolution are classified too."""
        n = len(lo)
        out = np.zeros(n, dtype=bool)
        i0, i1 = self._cells(lo), self._cells(hi)
        away = np.any((hi < self.lo) | (lo > self.lo + GRID * self.step), axis=1)
        cu, cv = i1[:, 0] - i0[:, 0] + 1, i1[:, 1] - i0[:, 1] + 1
        cells = np.where(away, 0, cu * cv)
        ends = np.cumsum(cells)
        b0 = 0
        while b0 < n:                                # boxes -> cells -> chords, GRID_CHUNK cells at a time
            b1 = max(int(np.searchsorted(ends, ends[b0] - cells[b0] + GRID_CHUNK, side="right")), b0 + 1)
            m = cells[b0:b1]
            box = np.repeat(np.arange(b0, b1), m)
            k = ranks(m)
            cell = (i0[box, 0] + k // cv[box]) * GRID + i0[box, 1] + k % cv[box]
            cnt = self.start[cell + 1] - self.start[cell]
            pb = np.repeat(box, cnt)
            off = ranks(cnt)
            seg = self.chords[np.repeat(self.start[cell], cnt) + off]
            hit = np.all((self.cmin[seg] <= hi[pb]) & (self.cmax[seg] >= lo[pb]), axis=1)
            seg, pb = seg[hit], pb[hit]
            # ... and the chord's line (widened by its bound) meets the box (separating axis)
            nrm, c, h = self.normal[seg], 0.5 * (lo[pb] + hi[pb]), 0.5 * (hi[pb] - lo[pb])
            reach = np.abs(nrm[:, 0]) * h[:, 0] + np.abs(nrm[:, 1]) * h[:, 1] + self.r[seg]
            hit = np.abs(np.einsum("nk,nk->n", nrm, c - self.A[seg])) <= reach * (1.0 + SLACK_RTOL)
            if flat is not None:
                k = np.flatnonzero(hit)
                coarse = self.r[seg[k]] > FINE_BOX * np.max(hi[pb[k]] - lo[pb[k]], axis=1)
                k = k[coarse]
                if k.size:
                    hit[k] = flat.pieces_meet(seg[k], lo[pb[k]], hi[pb[k]], FINE_BOX)
            out[np.unique(pb[hit])] = True
            b0 = b1
        return out


def box_classes(ts: "TrimmedSurface", lo: np.ndarray, hi: np.ndarray, exact_cells: Optional[int] = None
                ) -> np.ndarray:
    """Per parameter box [lo, hi] (model parameters, (n, 2)): -1 outside the trimmed domain
    D, 1 inside it, 0 where a loop may cross it (a chord's box, widened by its bound,
    meets the box; or, with ``exact_cells``, the box covers more than that many cells of
    the chord grid, one of them met by a chord: large boxes are not tested chord by chord).
    Periodic faces: every box 0 (no pruning)."""
    n = len(lo)
    out = np.zeros(n, dtype=np.int8)
    if ts.periodic_u or ts.periodic_v or not n:
        return out
    flat = ts._flattened()
    grid: Optional[_ChordGrid] = getattr(flat, "_box_grid", None)
    if grid is None:
        grid = _ChordGrid(flat.A, flat.B, flat.bound + flat.band)
        setattr(flat, "_box_grid", grid)           # derived from the immutable loops: kept with them
    table = getattr(grid, "_table", None)
    if table is None:
        table = _state_table(ts, grid)
        setattr(grid, "_table", table)
    # first from the grid's cells: a box over cells of one side only is on that side
    i0, i1 = grid._cells(lo), grid._cells(hi)
    away = np.any((lo < grid.lo) | (hi > grid.lo + GRID * grid.step), axis=1)
    n = (i1[:, 0] - i0[:, 0] + 1) * (i1[:, 1] - i0[:, 1] + 1)

    def count(P: np.ndarray) -> np.ndarray:
        a0, a1, b0, b1 = i0[:, 0], i1[:, 0] + 1, i0[:, 1], i1[:, 1] + 1
        return P[a1, b1] - P[a0, b1] - P[a1, b0] + P[a0, b0]
    out[(count(table[0]) == n) & ~away] = 1
    out[count(table[1]) == n] = -1
    rest = np.flatnonzero(out == 0) if exact_cells is None else np.flatnonzero((out == 0) & (n <= exact_cells))
    if rest.size:                                  # small boxes over a cell that a chord meets
        crossed = grid.meets(lo[rest], hi[rest], flat)
        c = 0.5 * (lo[rest] + hi[rest])
        inside = ts.contains(c[:, 0], c[:, 1])
        out[rest[~crossed]] = np.where(inside[~crossed], 1, -1)
    return out


def _state_table(ts: "TrimmedSurface", grid: _ChordGrid) -> np.ndarray:
    """Summed-area tables (2, GRID + 1, GRID + 1) of the grid's cells that no chord box
    meets with their centre inside D (0) and outside it (1): such a cell lies on one side
    of every loop (each loop lies in its chords' widened boxes)."""
    empty = (grid.start[1:] - grid.start[:-1]).reshape(GRID, GRID) == 0
    k = (np.arange(GRID) + 0.5)
    cu, cv = np.meshgrid(grid.lo[0] + k * grid.step[0], grid.lo[1] + k * grid.step[1], indexing="ij")
    inside = ts.contains(cu.ravel(), cv.ravel()).reshape(GRID, GRID)
    out = np.zeros((2, GRID + 1, GRID + 1), dtype=np.int64)
    out[0, 1:, 1:] = np.cumsum(np.cumsum(empty & inside, axis=0), axis=1)
    out[1, 1:, 1:] = np.cumsum(np.cumsum(empty & ~inside, axis=0), axis=1)
    return out


def closest_on_trimmed(ts: "TrimmedSurface", points: ArrayLike, p: "Projector",
                       stop: Tuple[Optional[float], Optional[float]], max_iterations: int) -> "ClosestPoints":
    """The closest points of the face ``ts`` (see the module docstring); ``p`` the
    projector of its untrimmed surface, ``stop`` its (tol, param_tol) in frame units."""
    from dataclasses import replace
    # the untrimmed search, certified only where Newton's foot is on the face (elsewhere the
    # boundary and the cells below bound the face's distance by themselves)
    base = p._closest(points, stop[0], stop[1], max_iterations, defer=lambda x: ~ts.contains(x[:, 0], x[:, 1]))
    uv = base.params
    inside = ts.contains(uv[:, 0], uv[:, 1])
    if inside.all():
        return base
    model = p._points(points)
    o = np.flatnonzero(~inside)
    Xm = model[o]
    surface = ts.untrimmed
    # --- the boundary: every loop curve's 3-D image, the foot moved onto the face
    bd, cls = _prepared(ts, p)
    best = np.full(len(o), np.inf)
    best_uv = np.zeros((len(o), 2))
    best_ok = np.ones(len(o), dtype=bool)
    lb_edge = np.full(len(o), np.inf)
    from .closest import _closest_point
    # each loop (its curves' images joined into one curve), the outer one first, is asked
    # for the points its control-point ball does not rule out
    for loop, C, starts, offsets, err in _joined_loops(ts, bd):
        P = C.control_points
        centre = 0.5 * (P.min(axis=0) + P.max(axis=0))
        radius = float(np.sqrt(((P - centre) ** 2).sum(-1)).max())
        ball = robust_distance(Xm, np.broadcast_to(centre, Xm.shape)) - radius
        ask = np.flatnonzero(ball - err < best)
        rest = np.setdiff1d(np.arange(len(o)), ask)
        lb_edge[rest] = np.minimum(lb_edge[rest], np.maximum(ball[rest] - err, 0.0))
        if not ask.size:
            continue
        r = _closest_point(C, Xm[ask], tol=None, max_iterations=max_iterations)
        j = np.clip(np.searchsorted(offsets, r.params, side="right") - 1, 0, len(loop) - 1)
        q = np.empty((len(j), 2))
        for i in np.unique(j):                    # the joined parameter back to its loop curve's
            m = j == i
            c = loop[i]
            q[m] = c(np.clip(r.params[m] - offsets[i] + starts[i], *c.domain))
        q = _on_domain(surface, q)
        d = robust_distance(surface(q[:, 0], q[:, 1]), Xm[ask])
        win = d < best[ask]
        w = ask[win]
        # a foot at a joint is the corner between two curves (no stationary point there:
        # Newton stops on the kink unconverged; the lower bound certifies it)
        width = float(C.domain[1] - C.domain[0])
        ok = r.point_converged | (np.abs(r.params[:, None] - offsets[None, 1:]) <= JOINT_TOL * width).any(axis=1)
        best[w], best_uv[w], best_ok[w] = d[win], q[win], ok[win]
        lb_edge[ask] = np.minimum(lb_edge[ask], np.maximum(r.lower_bounds - err, 0.0))
    # --- the interior: branch and bound over the cells that meet D, TRIM_POINT_CHUNK
    # points at a time (the work bound holds per group)
    X, _far = p._inward(Xm)
    xs = _inner_params(p, uv[o])                  # the untrimmed feet, frame parameters
    s = p.frame.scale
    U = best / s
    LB = np.full(len(o), np.inf)
    x_best = np.full((len(o), 2), np.nan)
    stopped = np.zeros(len(o), dtype=bool)
    for c0 in range(0, len(o), TRIM_POINT_CHUNK):
        sl = slice(c0, c0 + TRIM_POINT_CHUNK)
        U[sl], x_best[sl], best_ok[sl], LB[sl], stopped[sl] = _interior(ts, p, X[sl], U[sl], best_ok[sl], cls, stop,
                                                                         max_iterations, lb_edge[sl] / s, xs[sl])
    newton_ok = best_ok.copy()
    best_ok &= ~stopped
    interior = np.flatnonzero(np.isfinite(x_best[:, 0]))
    uv_o, feet_o = best_uv.copy(), surface(best_uv[:, 0], best_uv[:, 1])
    if interior.size:
        uv_o[interior] = p.frame.params(x_best[interior])
        feet_o[interior] = p.frame.outward(p.value(x_best[interior]))
    d_o = robust_distance(feet_o, Xm)
    lower_o = np.maximum(base.lower_bounds[o], np.minimum(lb_edge, LB * s))
    lower_o = np.minimum(lower_o * (1.0 - BOUND_SHRINK_RTOL), d_o)
    params, feet, dist = base.params.copy(), base.feet.copy(), base.distances.copy()
    lower, conv = base.lower_bounds.copy(), base.point_converged.copy()
    params[o], feet[o], dist[o], lower[o], conv[o] = uv_o, feet_o, d_o, lower_o, best_ok
    if not np.all(np.isfinite(dist)):
        raise CagdError("points: a distance to the face exceeds the float64 range")
    parts = [base.message] if base.message else []
    bad = np.flatnonzero(~newton_ok)
    if bad.size and not base.message:
        parts.append(f"Newton did not converge at {bad.size} of {len(conv)} points (first: index {int(o[bad[0]])}); "
                     f"their distances are the best found, lower_bounds still hold")
    if stopped.any():
        parts.append(f"trimmed face: the branch and bound stopped at its work bound (MAX_TRIM_ROUNDS = "
                     f"{MAX_TRIM_ROUNDS}, MAX_TRIM_ROWS = {MAX_TRIM_ROWS}) at {int(stopped.sum())} points (first: "
                     f"index {int(o[np.flatnonzero(stopped)[0]])}); their lower_bounds still hold")
    message = "; ".join(parts)
    return replace(base, params=params, feet=feet, distances=dist, lower_bounds=lower, point_converged=conv,
                   converged=bool(conv.all()), message=message)


def _joined_loops(ts: "TrimmedSurface", bd: "TrimBoundary") -> list:
    """Per loop of ``ts``: (its 2-D curves, the joined 3-D curve, the curves' own start
    parameters, where each starts on the joined curve, the error bound): the loop's
    boundary images as one clamped B-spline (degrees raised to the highest, knots
    shifted to follow on, full multiplicity at the joints, weights scaled to agree
    there), each curve's first control point set to the previous curve's last (the
    joined curve is within that gap of the images: the partition of unity), so the
    bound is the fits' (FIT_ERROR_SAFETY times the error, 0 for exact iso-curves) plus
    the largest gap. Cached with the boundary (an immutable value)."""
    hit = getattr(bd, "_joined_loops", None)
    if hit is not None:
        return hit
    from ..curves.bspline import BSplineCurve
    out = []
    for loop, images, exact in zip(ts.loops, bd.curves, bd.exact):
        p = max(C.degree for C in images)
        parts = [C.elevate(p - C.degree) if C.degree < p else C for C in images]
        err = 0.0 if all(exact) else FIT_ERROR_SAFETY * bd.error
        P, W = [parts[0].control_points], [_weights(parts[0])]
        K: list = [parts[0].knots[:-1]]
        starts = [float(parts[0].domain[0])]
        offsets = [float(parts[0].domain[0])]
        end = float(parts[0].domain[1])
        rational = any(C.weights is not None for C in parts)
        for C in parts[1:]:
            gap = float(np.linalg.norm(C.control_points[0] - P[-1][-1]))
            err = max(err, (0.0 if all(exact) else FIT_ERROR_SAFETY * bd.error) + gap)
            w = _weights(C)
            W.append((w * (W[-1][-1] / w[0]))[1:])
            P.append(C.control_points[1:])
            t0, t1 = C.domain
            starts.append(float(t0))
            offsets.append(end)
            K.append(C.knots[p + 1:-1] - t0 + end)
            end += float(t1 - t0)
        K.append([end])
        J = BSplineCurve(np.concatenate(P), p, np.concatenate([np.asarray(k, float) for k in K]),
                         np.concatenate(W) if rational else None)
        out.append((loop, J, np.array(starts), np.array(offsets), err))
    try:
        object.__setattr__(bd, "_joined_loops", out)
    except (AttributeError, TypeError):
        pass
    return out


def _weights(C: "BSplineCurve") -> np.ndarray:
    return np.ones(len(C.control_points)) if C.weights is None else np.asarray(C.weights, float)


def _on_domain(surface: "Surface", uv: np.ndarray) -> np.ndarray:
    """(u, v) of loop curves clipped into the surface's bounded directions (files'
    pcurves leave the range by up to 2e-5 of it): cagd.surfaces.trimmed's clip."""
    from ..surfaces.trimmed import _inside_domain
    return np.stack(_inside_domain(surface, uv[:, 0], uv[:, 1]), axis=1)


def _interior(ts: "TrimmedSurface", p: "Projector", X: np.ndarray, U: np.ndarray, best_ok: np.ndarray,
              cls: np.ndarray, stop: Tuple[Optional[float], Optional[float]], max_iterations: int,
              edge: np.ndarray, xs: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Branch and bound for points X (frame units) with upper bounds U: (U, the frame
    parameters of interior feet that beat U (NaN where none), their Newton flags, the
    lower bounds over the cells, and which points kept boxes open at the work bound).
    ``edge``: the boundary's lower bounds (frame units); a box whose bound reaches it
    is closed (the certificate, min(edge, cells), cannot be lowered by it: a fitted
    edge's error is then the gap). ``xs``: the untrimmed feet (frame parameters), about
    which :func:`_convex_settled` settles points at once."""
    U, best_ok = U.copy(), best_ok.copy()
    LB = np.full(len(X), np.inf)
    pid_l, cell_l = [], []
    cut = np.zeros(len(X), dtype=bool)
    t = np.minimum(U, edge)
    for c0 in range(0, len(X), TREE_CHUNK):     # the cells' hierarchy: the cells whose bounds are below t
        i = np.arange(c0, min(c0 + TREE_CHUNK, len(X)))
        a, c, _, rest = p._tree_pairs(X[i], t[i], False)
        low = rest < t[i]                         # a point held too many cells: some left out
        LB[i[low]] = np.minimum(LB[i[low]], rest[low])
        cut[i[low]] = True
        inside = cls[c] >= 0
        pid_l.append(i[a[inside]])
        cell_l.append(c[inside])
    pid, cell = np.concatenate(pid_l), np.concatenate(cell_l)
    lo, hi = p.lo[cell], p.hi[cell]
    # the cells' second-order bounds at their midpoints (stored S, J, H: no evaluation)
    lb = np.sqrt(np.maximum(p._mid_bound(X, pid, cell, lo, hi), 0.0))
    closed = lb >= np.minimum(U[pid] - (CELL_GAP * U[pid] + SIZE_ROUNDING * p.size), edge[pid])
    np.minimum.at(LB, pid[closed], lb[closed])
    pid, cell, lo, hi = pid[~closed], cell[~closed], lo[~closed], hi[~closed]
    flat = _no_critical_point(p, X, pid, cell, lo, hi)         # f has no stationary point there
    pid, cell, lo, hi = pid[~flat], cell[~flat], lo[~flat], hi[~flat]
    settled, lb_settled = _convex_settled(ts, p, X, pid, cell, lo, hi, xs, U, edge)
    LB = np.minimum(LB, lb_settled)
    keep = ~settled[pid]
    pid, cell, lo, hi = pid[keep], cell[keep], lo[keep], hi[keep]
    box = cls[cell]
    x_best = np.full((len(X), 2), np.nan)
    for rnd in range(MAX_TRIM_ROUNDS):
        if not len(pid):
            break
        gap = CELL_GAP * U + SIZE_ROUNDING * p.size
        if rnd:                                                 # (the first round's rows are tested above)
            flat = _no_critical_point(p, X, pid, cell, lo, hi)
            pid, cell, lo, hi, box = pid[~flat], cell[~flat], lo[~flat], hi[~flat], box[~flat]
        if not len(pid):
            break
        y, g2, ok = p._newton_rows(X, pid, 0.5 * (lo + hi), lo, hi, p._cell_piece[cell], max_iterations, *stop)
        dy = np.sqrt(g2)
        yuv = p.frame.params(y)
        admit = (box == 1) | ts.contains(yuv[:, 0], yuv[:, 1])
        cand = np.flatnonzero(admit & (dy < U[pid]))
        if cand.size:
            first = cand[smallest_per_group(pid[cand], dy[cand])]
            U[pid[first]], x_best[pid[first]] = dy[first], y[first]
            best_ok[pid[first]] = ok[first]
        lb, reach = _convex_bound(p, X, pid, cell, lo, hi, y)
        lb = np.sqrt(np.maximum(lb, 0.0))
        closed = lb >= np.minimum(U[pid] - gap[pid], edge[pid])
        np.minimum.at(LB, pid[closed], lb[closed])
        keep = ~closed
        pid, cell, lo, hi, box, lb, y = pid[keep], cell[keep], lo[keep], hi[keep], box[keep], lb[keep], y[keep]
        reach = (reach[0][keep], reach[1][keep])
        # where g is strongly convex on the box, the face's minimum over box & D, unless on
        # the boundary of D (the edges), is g's minimiser over the box: within reach of y
        t0, t1 = reach
        pad = (CONVEX_SAFETY - 1.0) * (t1 - t0) + KINK_TOL * (hi - lo)
        nlo, nhi = np.maximum(lo, y + t0 - pad), np.minimum(hi, y + t1 + pad)
        shrunk = np.all(nhi - nlo <= SHRUNK * (hi - lo), axis=1)
        lo, hi = nlo, nhi
        if len(pid) + np.count_nonzero(~shrunk) > MAX_TRIM_ROWS:
            break
        s_ = np.flatnonzero(shrunk)
        g_ = np.flatnonzero(~shrunk)
        pid2, cell2, lo2, hi2, lb2 = split_boxes(pid[g_], cell[g_], lo[g_], hi[g_], lb[g_], p.L[cell[g_]])
        pid = np.concatenate([pid[s_], pid2])
        cell = np.concatenate([cell[s_], cell2])
        lo, hi = np.concatenate([lo[s_], lo2]), np.concatenate([hi[s_], hi2])
        lb = np.concatenate([lb[s_], lb2])
        box = np.concatenate([box[s_], box[g_], box[g_]])
        flat = _no_critical_point(p, X, pid, cell, lo, hi)     # before the (costlier) trim test
        pid, cell, lo, hi, box, lb = pid[~flat], cell[~flat], lo[~flat], hi[~flat], box[~flat], lb[~flat]
        straddle = np.flatnonzero(box == 0)
        if straddle.size:                    # the halves of a crossed box: classify again
            b = box_classes(ts, p.frame.params(lo[straddle]), p.frame.params(hi[straddle]))
            box[straddle] = b
        keep = box >= 0
        pid, cell, lo, hi, box, lb = pid[keep], cell[keep], lo[keep], hi[keep], box[keep], lb[keep]
    stopped = cut.copy()
    if len(pid):                                 # boxes left open: their bounds still hold
        np.minimum.at(LB, pid, lb)
        stopped[np.unique(pid[lb < np.minimum(U[pid] - CELL_GAP * U[pid] - SIZE_ROUNDING * p.size, edge[pid])])] = True
    return U, x_best, best_ok, LB, stopped


def _inner_params(p: "Projector", uv: np.ndarray) -> np.ndarray:
    """Model parameters (n, k) in the projector's frame (the inverse of ``Frame.params``:
    per direction the piecewise linear map of the breaks, clamped to them)."""
    out = np.array(uv, dtype=np.float64)
    for a, (b, inner) in enumerate(zip(p.frame.breaks, p.frame.inner)):
        if inner is not None:
            j = np.clip(np.searchsorted(b, out[:, a], side="right") - 1, 0, len(b) - 2)
            f = np.clip((out[:, a] - b[j]) / (b[j + 1] - b[j]), 0.0, 1.0)
            out[:, a] = (1.0 - f) * inner[j] + f * inner[j + 1]
    return out


def _c2_run(p: "Projector", x: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Per point x (frame parameters, (n, 2)): the box of the C2-connected run of pieces
    that holds it (lo, hi), where S has no crease."""
    ep = p._power.piece_indices(x) if p._power is not None else \
        [np.clip(np.searchsorted(b, x[:, a], side="right") - 1, 0, len(b) - 2) for a, b in enumerate(p.pieces.breaks)]
    lo, hi = np.empty(x.shape), np.empty(x.shape)
    for a in range(x.shape[1]):
        pb, run = p.pieces.breaks[a], p._run[a]
        r = run[ep[a]]
        lo[:, a] = pb[np.searchsorted(run, r, side="left")]
        hi[:, a] = pb[np.searchsorted(run, r, side="right")]
    return lo, hi


def _convex_box(ts: "TrimmedSurface", p: "Projector", X: np.ndarray, xs: np.ndarray
                ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, Tuple[np.ndarray, np.ndarray]]:
    """Per point: a box B about its untrimmed foot x* (xs) on which g = |S - X|^2 is
    strongly convex and whose minimiser x^ over B lies outside D, as (lo, hi, ok, the box
    about x* that holds x^): B the
    largest of x* +- CONVEX_BOX_SHARES of the foot's cell (within the cells next to it
    and the C2 runs of its piece) where the expansion at x* with the bounds over those
    cells gives m > 0 (:func:`cagd.queries.bounds.box_lower_bound`), and the box about
    x* that holds x^ classified outside D (:func:`box_classes`). Then for y in B & D the
    segment from y to x^ stays in B and leaves D at some z on dD, where
    g(z) <= max(g(y), g(x^)) = g(y) (convexity): g >= the edges' bound on B & D."""
    n = len(X)
    S, J, H = p.evaluate(xs, 2)
    home = p.cells.locate(xs)
    nv = p.cells.shape[1]
    ci = (home // nv, home % nv)
    run_lo, run_hi = _c2_run(p, xs)
    wlo, whi, width = np.empty((n, 2)), np.empty((n, 2)), np.empty((n, 2))
    for a in range(2):                          # the cells next to the foot's, in its C2 runs
        cb, i = p.cells.breaks[a], ci[a]
        wlo[:, a] = np.maximum(cb[np.maximum(i - 1, 0)], run_lo[:, a])
        whi[:, a] = np.minimum(cb[np.minimum(i + 2, len(cb) - 1)], run_hi[:, a])
        width[:, a] = cb[i + 1] - cb[i]
    Lb, Mb, Tb = (B[1, home] for B in p.block)
    lo, hi = np.array(xs), np.array(xs)
    found = np.zeros(n, dtype=bool)
    t0, t1 = np.zeros((n, 2)), np.zeros((n, 2))
    reach_lo, reach_hi = np.array(xs), np.array(xs)
    for share in CONVEX_BOX_SHARES:             # the largest box first
        i = np.flatnonzero(~found)
        if not i.size:
            break
        blo = np.clip(xs[i] - share * width[i], wlo[i], whi[i])
        bhi = np.clip(xs[i] + share * width[i], wlo[i], whi[i])
        _, m, (r0, r1) = box_lower_bound(X[i], blo, bhi, xs[i], S[i], J[i], H[i], Lb[i], Mb[i], Tb[i],
                                         convexity=True)
        good = (m > 0) & np.all(r0 <= r1, axis=1)
        g = i[good]
        lo[g], hi[g], t0[g], t1[g], found[g] = blo[good], bhi[good], r0[good], r1[good], True
    ok = np.flatnonzero(found)
    if ok.size:
        pad = (CONVEX_SAFETY - 1.0) * (t1[ok] - t0[ok]) + KINK_TOL * (hi[ok] - lo[ok])
        rlo = np.maximum(lo[ok], xs[ok] + t0[ok] - pad)
        rhi = np.minimum(hi[ok], xs[ok] + t1[ok] + pad)
        found[ok] = box_classes(ts, p.frame.params(rlo), p.frame.params(rhi)) == -1
        reach_lo[ok], reach_hi[ok] = rlo, rhi
    return lo, hi, found, (reach_lo, reach_hi)


def _quarters(lo: np.ndarray, hi: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The four quarters (lo, hi) of each 2-D box [lo, hi], four rows per box in order."""
    mid = np.repeat(0.5 * (lo + hi), 4, axis=0)
    up = np.tile(np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=bool), (len(lo), 1))
    return np.where(up, mid, np.repeat(lo, 4, axis=0)), np.where(up, np.repeat(hi, 4, axis=0), mid)


def _hull_settled(p: "Projector", X: np.ndarray, pid: np.ndarray, lo: np.ndarray, hi: np.ndarray, xs: np.ndarray,
                  blo: np.ndarray, bhi: np.ndarray, reach: Tuple[np.ndarray, np.ndarray], ok: np.ndarray) -> np.ndarray:
    """Per point of X with a convex box B (``ok``, :func:`_convex_box`): whether g is
    strongly convex on the box K spanned by B and the point's open rows [lo, hi], each
    cell's part of K shown so by the cell's own bounds expanded at its midpoint
    (:func:`cagd.queries.bounds.box_lower_bound`, m > 0; g is C2 on K: K lies in the
    foot's C2 runs). B's minimiser (within ``reach``, outside D) is then K's when it
    keeps off the sides of B inside K, and for y in K & D the segment to it leaves D
    at z on dD with g(z) <= g(y): the rows hold no minimum below the edges'."""
    out = np.zeros(len(X), dtype=bool)
    klo, khi = blo.copy(), bhi.copy()
    np.minimum.at(klo, pid, lo)
    np.maximum.at(khi, pid, hi)
    run_lo, run_hi = _c2_run(p, xs)
    rlo, rhi = reach
    cand = ok & np.all((klo >= run_lo) & (khi <= run_hi), axis=1)
    cand &= np.all(((rlo > blo) | (blo <= klo)) & ((rhi < bhi) | (bhi >= khi)), axis=1)
    i = np.flatnonzero(cand)
    if not i.size:
        return out
    first, count = [], []
    for a in range(2):                            # the cells that meet K
        cb = p.cells.breaks[a]
        c0 = np.clip(np.searchsorted(cb, klo[i, a], side="right") - 1, 0, len(cb) - 2)
        c1 = np.clip(np.searchsorted(cb, khi[i, a], side="left") - 1, c0, len(cb) - 2)
        first.append(c0)
        count.append(c1 - c0 + 1)
    tiles = count[0] * count[1]
    small = tiles <= MAX_HULL_CELLS
    i, first, count, tiles = i[small], [f[small] for f in first], [c[small] for c in count], tiles[small]
    point = np.repeat(i, tiles)
    k = ranks(tiles)
    r = np.repeat(np.arange(len(i)), tiles)
    cu = first[0][r] + k // count[1][r]
    cv = first[1][r] + k % count[1][r]
    cell = cu * p.cells.shape[1] + cv
    tlo, thi = np.maximum(p.lo[cell], klo[point]), np.minimum(p.hi[cell], khi[point])
    out[i] = True
    for level in range(HULL_SPLITS + 1):
        convex = np.empty(len(cell), dtype=bool)
        for c0 in range(0, len(cell), ROW_CHUNK):
            sl = slice(c0, c0 + ROW_CHUNK)
            ce = cell[sl]
            if level:                             # the tile's own centre
                c = 0.5 * (tlo[sl] + thi[sl])
                S, J, H = p.evaluate(c, 2, p._cell_piece[ce])
            else:                                 # the cell's midpoint (stored: no evaluation)
                c, S, J, H = p.mids[ce], p.mid_points[ce], p.mid_jacobians[ce], p.mid_hessians[ce]
            _, m, _ = box_lower_bound(X[point[sl]], tlo[sl], thi[sl], c, S, J, H, p.L[ce], p.M[ce], p.T3[ce],
                                      convexity=True, hessian=p.hull(X[point[sl]], ce, tlo[sl], thi[sl]))
            convex[sl] = m > 0
        bad = ~convex & out[point]
        if level == HULL_SPLITS or not bad.any():
            out[point[bad]] = False
            break
        point, cell, tlo, thi = np.repeat(point[bad], 4), np.repeat(cell[bad], 4), *_quarters(tlo[bad], thi[bad])
    return out


def _convex_settled(ts: "TrimmedSurface", p: "Projector", X: np.ndarray, pid: np.ndarray, cell: np.ndarray,
                    lo: np.ndarray, hi: np.ndarray, xs: np.ndarray, U: np.ndarray, edge: np.ndarray
                    ) -> Tuple[np.ndarray, np.ndarray]:
    """Per point of X: whether its open (point, box) rows need no branch and bound (the
    face's minimum over them is on the edges), and the lower bound over the boxes closed
    on the way. A box B about the untrimmed foot (:func:`_convex_box`) covers its part of
    them, and all of them where g is convex on their hull (:func:`_hull_settled`); else
    the rest are halved, SETTLE_LEVELS times at most, and a part is dropped inside
    B, where g has no stationary point (:func:`_no_critical_point`: D's minimum, unless
    on dD, is one), where its bound reaches min(U, edge) (closed) or outside D. A point
    with a part left is not settled (its rows go to the branch and bound)."""
    n = len(X)
    settled = np.zeros(n, dtype=bool)
    LB = np.full(n, np.inf)
    if not len(pid) or p.k != 2 or ts.periodic_u or ts.periodic_v:
        return settled, LB
    pts = np.unique(pid)
    blo, bhi, rlo, rhi = (np.zeros((n, 2)) for _ in range(4))
    ok = np.zeros(n, dtype=bool)
    blo[pts], bhi[pts], ok[pts], (rlo[pts], rhi[pts]) = _convex_box(ts, p, X[pts], xs[pts])
    # a point whose rows lie in a box where g is strongly convex is settled at once
    hull = _hull_settled(p, X, pid, lo, hi, xs, blo, bhi, (rlo, rhi), ok)
    keep = ~hull[pid]
    pid, cells, lo, hi = pid[keep], cell[keep], lo[keep], hi[keep]
    alive = ok.copy()                            # points still to settle
    for level in range(SETTLE_LEVELS + 1):
        keep = alive[pid] & ~np.all((lo >= blo[pid]) & (hi <= bhi[pid]), axis=1)
        pid, cells, lo, hi = pid[keep], cells[keep], lo[keep], hi[keep]
        if level:
            flat = _no_critical_point(p, X, pid, cells, lo, hi)
            pid, cells, lo, hi = pid[~flat], cells[~flat], lo[~flat], hi[~flat]
            c = 0.5 * (lo + hi)
            gap = CELL_GAP * U[pid] + SIZE_ROUNDING * p.size
            need = np.minimum(U[pid] - gap, edge[pid])
            lb = np.sqrt(np.maximum(p._bound(X, pid, cells, lo, hi, c, need), 0.0))
            closed = lb >= need
            np.minimum.at(LB, pid[closed], lb[closed])
            pid, cells, lo, hi = pid[~closed], cells[~closed], lo[~closed], hi[~closed]
            if len(pid):
                out = box_classes(ts, p.frame.params(lo), p.frame.params(hi)) == -1
                pid, cells, lo, hi = pid[~out], cells[~out], lo[~out], hi[~out]
        if level == SETTLE_LEVELS or not len(pid):
            break
        # the parts left: halved in both directions (quarters)
        pid, cells, (lo, hi) = np.repeat(pid, 4), np.repeat(cells, 4), _quarters(lo, hi)
    settled = alive.copy()
    settled[pid] = False
    LB[~settled] = np.inf
    return settled, LB


def _convex_bound(p: "Projector", X: np.ndarray, pid: np.ndarray, cell: np.ndarray, lo: np.ndarray,
                  hi: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, Tuple[np.ndarray, np.ndarray]]:
    """The projector's second-order lower bound of g = |S - X|^2 over each box, expanded
    at y in the box, and the offsets (t0, t1) (n, k) from y of a box that holds g's
    minimiser over the box (the whole box where g is not shown strongly convex there):
    :func:`cagd.queries.bounds.box_lower_bound`."""
    out, t0, t1 = np.empty(len(pid)), np.empty((len(pid), p.k)), np.empty((len(pid), p.k))
    for c0 in range(0, len(pid), ROW_CHUNK):
        sl = slice(c0, c0 + ROW_CHUNK)
        ce = cell[sl]
        S, J, H = p.evaluate(y[sl], 2, p._cell_piece[ce])
        out[sl], _, (t0[sl], t1[sl]) = box_lower_bound(X[pid[sl]], lo[sl], hi[sl], y[sl], S, J, H, p.L[ce],
                                                       p.M[ce], p.T3[ce], convexity=True,
                                                       hessian=p.hull(X[pid[sl]], ce, lo[sl], hi[sl]))
        out[sl] = p.pole_bound(X[pid[sl]], ce, lo[sl], hi[sl], out[sl])
    return out, (t0, t1)


def _no_critical_point(p: "Projector", X: np.ndarray, pid: np.ndarray, cell: np.ndarray, lo: np.ndarray,
                       hi: np.ndarray) -> np.ndarray:
    """True for the (point, box) rows where f = |S - X|^2 has no stationary point in the
    box: some component of grad f = 2 J^T r at the centre c exceeds its variation over
    the box, |g_a(z) - g_a(c)| <= sum_b 2 (L_a L_b + R M_ab) h_b (mean value theorem;
    H_ab = 2 (S_a . S_b + r . S_ab), L and M the cell's derivative bounds, h the box's
    half-widths, R >= |r| over the box). The face's minimum is at a stationary point
    inside D or on the boundary, so such boxes cannot hold it, except where f is not
    smooth: a component a is not used on a box that touches a crease across a (a break
    between the pieces' C2 runs, where S may have a kink and the minimum sit on it
    without a stationary point) or an end of the domain in a (which a trim may reach)."""
    out = np.zeros(len(pid), dtype=bool)
    usable = np.ones((len(pid), p.k), dtype=bool)
    for a in range(p.k):
        b, run = p.pieces.breaks[a], p._run[a]
        kinks = b[1:-1][run[1:] != run[:-1]]
        if not p.wrap[a]:
            kinks = np.concatenate([[b[0]], kinks, [b[-1]]])
        eps = KINK_TOL * float(b[-1] - b[0])
        usable[:, a] = np.searchsorted(kinks, hi[:, a] + eps, side="right") == \
            np.searchsorted(kinks, lo[:, a] - eps, side="left")
    for c0 in range(0, len(pid), ROW_CHUNK):
        sl = slice(c0, c0 + ROW_CHUNK)
        c = 0.5 * (lo[sl] + hi[sl])
        h = 0.5 * (hi[sl] - lo[sl])
        ce = cell[sl]
        S, J = p.evaluate(c, 1, p._cell_piece[ce])[:2]
        r = S - X[pid[sl]]
        g = 2.0 * np.einsum("nd,ndk->nk", r, J)
        L, M = p.L[ce], p.M[ce]
        R = np.linalg.norm(r, axis=1) + (L * h).sum(axis=1)
        var = 2.0 * (L * (L * h).sum(axis=1, keepdims=True) + R[:, None] * np.einsum("nab,nb->na", M, h))
        out[sl] = np.any((np.abs(g) > CRITICAL_SAFETY * var) & usable[sl], axis=1)
    return out




# --- intersections clipped to the trims ----------------------------------------------------------
#: samples per branch (at least; more per span of its 3-D curve) where the trims are tested
CLIP_SAMPLES = 512
#: ... per span of the branch's curve
CLIP_SAMPLES_PER_SPAN = 16
#: bisection steps locating where a branch leaves a trim (the parameter to 2^-48 of a step)
CLIP_BISECTIONS = 48


def _branch_inside(branch: object, a: object, b: object, t: np.ndarray) -> np.ndarray:
    """Whether the branch's points at t lie on both faces (inside both trims)."""
    from ..surfaces.trimmed import TrimmedSurface
    uva, uvb = branch.surface_params(t)            # type: ignore[attr-defined]
    ok = np.ones(len(t), dtype=bool)
    if isinstance(a, TrimmedSurface):
        ok &= a.contains(uva[:, 0], uva[:, 1])
    if isinstance(b, TrimmedSurface) and uvb is not None:
        ok &= b.contains(uvb[:, 0], uvb[:, 1])
    return ok


def _clip_branch(branch: object, a: object, b: object) -> list:
    """The pieces of one branch on both faces: the curve sampled, each change of
    inside/outside located by bisection, the curve and its parameter curves cut there
    (their ends 'trim'). Excursions shorter than a sample step may be missed."""
    from dataclasses import replace
    c = branch.curve                                # type: ignore[attr-defined]
    t0, t1 = c.domain
    spans = max(len(np.unique(c.knots)) - 1, 1)
    t = np.linspace(t0, t1, max(CLIP_SAMPLES, CLIP_SAMPLES_PER_SPAN * spans) + 1)
    ok = _branch_inside(branch, a, b, t)
    if ok.all():
        return [branch]
    if not ok.any():
        return []
    k = np.flatnonzero(ok[1:] != ok[:-1])
    lo, hi, lo_ok = t[k], t[k + 1], ok[k]
    for _ in range(CLIP_BISECTIONS):
        mid = 0.5 * (lo + hi)
        m_ok = _branch_inside(branch, a, b, mid)
        same = m_ok == lo_ok
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    cuts = np.where(lo_ok, lo, hi)                  # the last inside parameter of each change
    bounds = np.concatenate([[t0], cuts, [t1]])
    inside_runs = np.concatenate([[ok[0]], ~lo_ok])  # whether each run between cuts is inside
    closed = bool(branch.closed)                    # type: ignore[attr-defined]
    curves = (c, branch.params_a, branch.params_b)  # type: ignore[attr-defined]
    runs = []
    for j, inside in enumerate(inside_runs):
        s, e = float(bounds[j]), float(bounds[j + 1])
        if inside and e > s:
            runs.append((j, [None if x is None else x.segment(s, e) for x in curves]))
    if closed and len(runs) > 1 and inside_runs[0] and inside_runs[-1]:
        # a loop cut open: its last run goes on through the seam into its first
        (_, last), (_, first) = runs[-1], runs[0]
        runs = [(1, [None if x is None or y is None else _joined(x, y) for x, y in zip(last, first)])] + runs[1:-1]
    pieces = []
    for j, (cv, pa, pb) in runs:
        start = branch.ends[0] if (j == 0 and not closed) else "trim"           # type: ignore[attr-defined]
        end = branch.ends[1] if (j == len(inside_runs) - 1 and not closed) else "trim"  # type: ignore[attr-defined]
        pieces.append(replace(branch, curve=cv, params_a=pa, params_b=pb, closed=False,  # type: ignore[type-var]
                              ends=(start, end)))
    return pieces


def _joined(a: "BSplineCurve", b: "BSplineCurve") -> "BSplineCurve":
    """a then b, b moved to start where a ends (a loop's parameter curves differ by a
    period across the seam) and re-parametrised to follow on: one clamped curve, C0 at
    the joint (knot multiplicity p there)."""
    from ..curves.bspline import BSplineCurve
    if b.degree < a.degree:
        b = b.elevate(a.degree - b.degree)
    elif a.degree < b.degree:
        a = a.elevate(b.degree - a.degree)
    p = a.degree
    a1, b0 = a.domain[1], b.domain[0]
    Pb = b.control_points + (a.control_points[-1] - b.control_points[0])
    wa, wb = a.weights, b.weights
    weights = None
    if wa is not None or wb is not None:
        wa = np.ones(len(a.control_points)) if wa is None else wa
        wb = np.ones(len(Pb)) if wb is None else wb
        weights = np.concatenate([wa, (wb * (wa[-1] / wb[0]))[1:]])
    knots = np.concatenate([a.knots[:-1], b.knots[p + 1:] - b0 + a1])
    return BSplineCurve(np.concatenate([a.control_points, Pb[1:]]), p, knots, weights)


def clip_to_trims(res: "IntersectionResult", a: object, b: object) -> "IntersectionResult":
    """An intersection of the untrimmed surfaces restricted to the faces: points whose
    parameters lie outside a trim are dropped, branches cut where they leave a trim
    (their ends there 'trim'), overlaps restricted to their parts on both faces
    (:func:`clip_overlap`; dropped where none is left)."""
    from dataclasses import replace
    from ..surfaces.trimmed import TrimmedSurface

    def on(obj: object, param: object) -> bool:
        if not isinstance(obj, TrimmedSurface):
            return True
        uv = np.asarray(param, float).reshape(-1, 2)
        return bool(obj.contains(uv[:, 0], uv[:, 1]).all())

    points = tuple(p for p in res.points if on(a, p.param_a) and on(b, p.param_b))
    curves = tuple(piece for branch in res.curves for piece in _clip_branch(branch, a, b))
    overlaps = tuple(o for o in (clip_overlap(ov, a, b) for ov in res.overlaps) if o is not None)
    return replace(res, points=points, curves=curves, overlaps=overlaps)


# --- overlaps clipped to the trims -------------------------------------------------------------------
#: cells per side of the overlap box at the first level of the clipping quadtree
OVERLAP_START = 16
#: halvings of the cells a trim boundary crosses (the smallest cells 2^-OVERLAP_DEPTH of the first)
OVERLAP_DEPTH = 7
#: samples per side of a cell (corners, edge midpoints and centre) classified against the trims
OVERLAP_SAMPLES = 3
#: Gauss-Legendre nodes per direction of a cell's area
OVERLAP_GAUSS = 2
#: edge cells halved per level at most (their samples are projected onto b): beyond, they stay edge cells
MAX_OVERLAP_CELLS = 1 << 15


def _surface_of(a: object) -> "Surface":
    """The (untrimmed) surface of a face or surface."""
    from typing import cast
    from ..surfaces.trimmed import TrimmedSurface
    return a.untrimmed if isinstance(a, TrimmedSurface) else cast("Surface", a)


def _on_both(a: object, b: object, uv: np.ndarray) -> np.ndarray:
    """Whether the points S_a(uv) of a's surface are on both faces: uv inside a's trim,
    and the point's foot on b's surface (a certified closest point) inside b's trim."""
    from ..surfaces.trimmed import TrimmedSurface
    from .closest import closest_point
    ok = np.ones(len(uv), dtype=bool)
    if isinstance(a, TrimmedSurface):
        ok &= a.contains(uv[:, 0], uv[:, 1])
    if isinstance(b, TrimmedSurface) and ok.any():
        k = np.flatnonzero(ok)
        surface = _surface_of(a)
        foot = closest_point(b.untrimmed, surface(*_on_domain(surface, uv[k]).T)).params
        ok[k] = b.contains(foot[:, 0], foot[:, 1])
    return ok


def _cell_areas(surface: "Surface", cells: np.ndarray) -> np.ndarray:
    """Areas int |S_u x S_v| du dv of parameter cells (K, 4) (u0, v0, u1, v1), by
    OVERLAP_GAUSS x OVERLAP_GAUSS Gauss-Legendre points (exact for a bilinear patch)."""
    if not len(cells):
        return np.zeros(0)
    x, w = np.polynomial.legendre.leggauss(OVERLAP_GAUSS)
    s = 0.5 * (x + 1.0)
    lo, hi = cells[:, :2], cells[:, 2:]
    U = lo[:, None, None, 0] + (hi - lo)[:, None, None, 0] * s[None, :, None]
    V = lo[:, None, None, 1] + (hi - lo)[:, None, None, 1] * s[None, None, :]
    shape = (len(cells), OVERLAP_GAUSS, OVERLAP_GAUSS)
    U, V = np.broadcast_to(U, shape), np.broadcast_to(V, shape)
    uv = _on_domain(surface, np.stack([U.ravel(), V.ravel()], axis=1))
    d = surface.derivatives(uv[:, 0], uv[:, 1], 1, 1)
    jac = np.linalg.norm(np.cross(d[1, 0], d[0, 1]), axis=-1).reshape(U.shape)
    weights = 0.25 * np.outer(w, w)
    return np.einsum("kij,ij->k", jac, weights) * np.prod(hi - lo, axis=1)


def clip_overlap(ov: object, a: object, b: object) -> Optional[object]:
    """An overlap of the untrimmed surfaces (a :class:`SurfaceOverlap`) restricted to
    the faces, or None where nothing of it is on both: a quadtree of cells over
    ``box_a`` (OVERLAP_START per side), each classified at OVERLAP_SAMPLES^2 samples
    (:func:`_on_both`): all on both faces, kept; none, dropped; else halved, down to
    OVERLAP_DEPTH levels (or while at most MAX_OVERLAP_CELLS are), where it stays an edge
    cell. The area is the kept cells' plus
    half the edge cells', within half the edge cells' (:func:`_cell_areas`).
    Approximate: a cell whose samples all agree is taken whole (a trim excursion between
    samples is missed), and ``box_b`` is the box of the region's samples' feet on b."""
    from dataclasses import replace
    from ..surfaces.trimmed import TrimmedSurface
    from .closest import closest_point
    box = ov.box_a                                                           # type: ignore[attr-defined]
    surface = _surface_of(a)
    s = np.linspace(0.0, 1.0, OVERLAP_SAMPLES)
    grid = np.stack(np.meshgrid(s, s, indexing="ij"), axis=-1).reshape(-1, 2)
    e = np.linspace(0.0, 1.0, OVERLAP_START + 1)
    (u0, u1), (v0, v1) = box
    gu, gv = u0 + (u1 - u0) * e, v0 + (v1 - v0) * e
    I, J = np.meshgrid(np.arange(OVERLAP_START), np.arange(OVERLAP_START), indexing="ij")
    live = np.stack([gu[I.ravel()], gv[J.ravel()], gu[I.ravel() + 1], gv[J.ravel() + 1]], axis=1)
    kept, edge, depth = [], np.empty((0, 4)), OVERLAP_DEPTH
    for level in range(OVERLAP_DEPTH + 1):
        if not len(live):
            break
        lo, hi = live[:, :2], live[:, 2:]
        uv = (lo[:, None, :] + (hi - lo)[:, None, :] * grid[None]).reshape(-1, 2)
        ok = _on_both(a, b, uv).reshape(len(live), -1)
        kept.append(live[ok.all(axis=1)])
        mixed = live[ok.any(axis=1) & ~ok.all(axis=1)]
        if level == OVERLAP_DEPTH or len(mixed) > MAX_OVERLAP_CELLS:
            edge, depth = mixed, level
            break
        mid = 0.5 * (mixed[:, :2] + mixed[:, 2:])
        live = np.concatenate([np.stack([mixed[:, 0], mixed[:, 1], mid[:, 0], mid[:, 1]], axis=1),
                               np.stack([mid[:, 0], mixed[:, 1], mixed[:, 2], mid[:, 1]], axis=1),
                               np.stack([mixed[:, 0], mid[:, 1], mid[:, 0], mixed[:, 3]], axis=1),
                               np.stack([mid[:, 0], mid[:, 1], mixed[:, 2], mixed[:, 3]], axis=1)])
    inner = np.concatenate(kept) if kept else np.empty((0, 4))
    if not len(inner) and not len(edge):
        return None
    half = 0.5 * float(_cell_areas(surface, edge).sum())
    area = float(_cell_areas(surface, inner).sum()) + half
    region = np.concatenate([inner, edge])
    lo, hi = region[:, :2].min(axis=0), region[:, 2:].max(axis=0)
    box_a = ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))
    box_b = ov.box_b                                                         # type: ignore[attr-defined]
    if box_b is not None and isinstance(b, TrimmedSurface):
        centres = 0.5 * (region[:, :2] + region[:, 2:])
        foot = closest_point(b.untrimmed, surface(*_on_domain(surface, centres).T)).params
        blo, bhi = foot.min(axis=0), foot.max(axis=0)
        box_b = ((float(blo[0]), float(bhi[0])), (float(blo[1]), float(bhi[1])))
    note = (f"clipped to the trims on cells ({len(inner)} inside, {len(edge)} on a trim's edge at "
            f"2^-{depth} of {OVERLAP_START} per side): area within {half:.3g}")
    message = ov.message + "; " + note if ov.message else note                # type: ignore[attr-defined]
    return replace(ov, box_a=box_a, box_b=box_b, message=message, cells_a=_frozen(inner),    # type: ignore[type-var]
                   edge_cells_a=_frozen(edge), area=area, area_error=half)


def _frozen(x: np.ndarray) -> np.ndarray:
    x = np.ascontiguousarray(x, dtype=np.float64)
    x.setflags(write=False)
    return x


__all__ = ["closest_on_trimmed", "box_classes", "clip_to_trims", "clip_overlap"]
