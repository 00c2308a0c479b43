"""Triangulation of a trimmed surface's region in (u, v) (issue 15): for plots and STL/OBJ.

The loops' box is scaled to the unit square and cut into a (count + 1)^2 grid of cells.
A cell is *full* when no trim chord comes within half a cell of it (it is not in the
ring around a cell that holds a chord sample, samples at most half a cell apart) and its
centre is inside the trim; a full cell gives two triangles. What is left,
R = (trimmed region) minus (full cells), is bounded by the trim polylines (the loops
flattened to a fraction of a cell, vertices on the curves) and the staircase outlines of
the full cells (cells touching only at a corner are taken apart first, so every outline
is a simple loop). R's loops are grouped into polygons with holes by signed area and
containment, each hole is bridged to its outer loop by a segment to a vertex on its
left that crosses no loop (the leftmost hole first: Mapbox's earcut), and each polygon
is ear-clipped (Meisters, "Polygons have ears", 1975; O'Rourke, "Computational Geometry
in C", 1.6). The staircase vertices are grid vertices shared with the full cells, so the
mesh has no T-junctions. Lawson's edge flips (de Berg et al., "Computational Geometry",
9.1) then remove the slivers of the ear clipping in R, its loops held fixed.

Cost: O(cells) vectorized for the grid; ear clipping is O(k^2) in the k vertices of R's
polygons (the trim polylines and the staircases, O(count) per loop), the triangle test
vectorized over the reflex vertices. Every loop is bounded.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, List, Optional, Tuple

import numpy as np

from .._periodic import wrap
from ._chords import _cartesian, _crossings, closed_chains, orient

if TYPE_CHECKING:
    from .trimmed import TrimmedSurface

CHORD_FRACTION = 0.05      # trim polylines: chord-to-curve bound, in cells (of the smaller cell side)
METRIC_SAMPLES = 9         # grid points per direction where the surface's mean speeds are sampled
MERGE_FRACTION = 1e-9      # trim vertices closer than this (in cells) or twice the trim's tol are one vertex
SAMPLE_SPACING = 0.5       # chord samples at most this far apart, in cells (full cells: >= 1/2 cell off)
DEGENERATE_AREA = 1e-14    # twice a triangle's area in the unit box below which it counts as flat


@dataclass(frozen=True)
class Tessellation:
    """Triangles of a trimmed region in (u, v).

    ``uv`` (n, 2) vertices; ``triangles`` (m, 3) int, counter-clockwise in (u, v);
    ``boundary`` (k, 2) vertex pairs of the trim chords and ``boundary_mid`` (k, 2) the
    (u, v) of the trim curve at each chord's middle parameter (where a chord's distance
    from the true edge is measured); ``fallbacks``: polygons whose ear clipping stalled and
    was finished by clipping convex vertices that were not clean ears (0 normally)."""
    uv: np.ndarray
    triangles: np.ndarray
    boundary: np.ndarray
    boundary_mid: np.ndarray
    fallbacks: int


def tessellation(ts: "TrimmedSurface", count: int) -> Tessellation:
    """The triangulation of ``ts``'s region with cells of 1 / (count + 1) of the loops'
    box's longer side in the surface's mean metric (see the module)."""
    from .trimmed import INSIDE, _flatten_many
    cps = np.concatenate([c.control_points for loop in ts.loops for c in loop])
    lo, hi = cps.min(axis=0), cps.max(axis=0)
    scale = _metric(ts, lo, hi)
    h = 1.0 / (count + 1)
    polys, mids = _trim_polylines(ts, _flatten_many, scale, h)
    allp = np.concatenate(polys)
    lo = allp.min(axis=0)
    S = [(p - lo) * scale for p in polys]
    width = np.concatenate(S).max(axis=0)
    nu, nv = (max(1, int(np.ceil(w / h - 1e-9))) for w in width)
    full = _full_cells(ts, S, nu, nv, h, lo, scale, INSIDE)
    grid = np.stack(np.meshgrid(np.arange(nu + 1), np.arange(nv + 1), indexing="ij"), axis=-1).reshape(-1, 2) * h
    offsets = np.cumsum([len(grid)] + [len(p) for p in S])
    P = np.concatenate([grid] + S)
    loops = [np.arange(offsets[i], offsets[i + 1]) for i in range(len(S))] + _staircases(full)
    tris, fallbacks = [_cell_triangles(full)], 0
    for ring_outer, holes in _components(P, loops):
        ring = ring_outer
        for hole in sorted(holes, key=lambda hl: float(P[hl, 0].min())):
            merged = _bridge(P, ring, hole, loops)
            if merged is None:
                fallbacks += 1
                continue
            ring = merged
        t, stalled = _ear_clip(P, ring)
        tris.append(t)
        fallbacks += stalled
    T = np.concatenate([tris[0], _lawson(P, np.concatenate(tris[1:]).reshape(-1, 3))])
    bnd = np.concatenate([np.stack([ix, np.roll(ix, -1)], axis=1)
                          for ix in (np.arange(offsets[i], offsets[i + 1]) for i in range(len(S)))])
    used = np.zeros(len(P), dtype=bool)
    used[T.ravel()] = True
    used[bnd.ravel()] = True
    new = np.cumsum(used) - 1
    P, T, bnd = P[used], new[T], new[bnd]
    uv = np.concatenate([lo + grid / scale] + polys)[used]
    mid = np.concatenate(mids)
    for d, periodic in enumerate((ts.periodic_u, ts.periodic_v)):
        if not periodic:        # loops may leave a bounded direction by the trim's tol
            uv[:, d] = np.clip(uv[:, d], *ts.surface.domain[d])
            mid[:, d] = np.clip(mid[:, d], *ts.surface.domain[d])
    for arr in (uv, T, bnd, mid):
        arr.flags.writeable = False
    return Tessellation(uv, T, bnd, mid, fallbacks)


def _metric(ts: "TrimmedSurface", lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Per direction, the median speed |S_u|, |S_v| over a grid of the loops' box, divided
    by the box's longer side in that metric (so the box maps into the unit square with
    3-D proportions); the plain box scaling where the surface is degenerate."""
    (u0, u1), (v0, v1) = ts.surface.domain
    us = np.clip(np.linspace(lo[0], hi[0], METRIC_SAMPLES), u0, u1)
    vs = np.clip(np.linspace(lo[1], hi[1], METRIC_SAMPLES), v0, v1)
    U, V = (a.ravel() for a in np.meshgrid(us, vs, indexing="ij"))
    speed = np.array([np.median(np.linalg.norm(ts.surface.derivative(U, V, 1, 0), axis=-1)),
                      np.median(np.linalg.norm(ts.surface.derivative(U, V, 0, 1), axis=-1))])
    side = np.maximum(hi - lo, 1e-300)
    if not (np.all(np.isfinite(speed)) and np.all(speed > 0)):
        speed = 1.0 / side
    return speed / float(np.max(speed * side))


# --- the trim polylines ---------------------------------------------------------------------------
def _trim_polylines(ts: "TrimmedSurface", flatten: Callable, scale: np.ndarray,
                    h: float) -> Tuple[List[np.ndarray], List[np.ndarray]]:
    """Per loop: points on the trim curves (the flattening's piece ends, pieces longer than
    a cell split at equal parameter steps) and the curve points at the middle parameter
    of each chord; holes of a periodic direction moved into the outer loop's period."""
    tol = CHORD_FRACTION * h / float(np.max(scale))
    merge = max(MERGE_FRACTION * h, 2 * ts.tol * float(np.max(scale)))
    chains = closed_chains(ts.loops)
    curves = [c for _, chain, _ in chains for c in chain]
    nets = [Q for Q, _ in flatten(curves, tol)]
    polys, mids, k = [], [], 0
    for _, chain, _ in chains:
        starts, middles = [], []
        for Q in nets[k:k + len(chain)]:
            chord = (_cartesian(Q[:, -1]) - _cartesian(Q[:, 0])) * scale
            n = np.maximum(np.ceil(np.linalg.norm(chord, axis=1) / h).astype(np.int64), 1)
            j = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
            R = np.repeat(Q, n, axis=0)
            starts.append(_de_casteljau(R, j / np.repeat(n, n)))
            middles.append(_de_casteljau(R, (j + 0.5) / np.repeat(n, n)))
        k += len(chain)
        start, mid = np.concatenate(starts), np.concatenate(middles)
        step = np.linalg.norm((np.roll(start, -1, axis=0) - start) * scale, axis=1)
        keep = step > merge          # a joint's gap closer (up to the trim's tol): one vertex, not two
        if np.count_nonzero(keep) < 3:            # a loop this small keeps every distinct vertex
            keep = step > 0
        polys.append(start[keep])
        mids.append(mid[keep])
    periods = ts._shifts()
    lo0 = polys[0].min(axis=0)
    for i in range(1, len(polys)):
        shift = np.array([wrap(polys[i][0, d], lo0[d], T) - polys[i][0, d] if T > 0 else 0.0
                          for d, T in enumerate(periods)])
        polys[i], mids[i] = polys[i] + shift, mids[i] + shift
    return polys, mids


def _de_casteljau(Q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points of homogeneous Bezier nets Q (m, p + 1, 3) at parameters t (m,) in [0, 1]."""
    R = Q
    w = t[:, None, None]
    for _ in range(Q.shape[1] - 1):
        R = (1 - w) * R[:, :-1] + w * R[:, 1:]
    return _cartesian(R[:, 0])


# --- the grid: full cells and their outlines ------------------------------------------------------
def _full_cells(ts: "TrimmedSurface", S: List[np.ndarray], nu: int, nv: int, h: float, lo: np.ndarray,
                scale: np.ndarray, inside: int) -> np.ndarray:
    """(nu, nv) bool: cells half a cell or more from every chord with their centre inside,
    without two full cells meeting only at a corner."""
    near = np.zeros((nu + 2, nv + 2), dtype=bool)
    top = np.array([nu - 1, nv - 1])
    for p in S:
        a, b = p / h, np.roll(p, -1, axis=0) / h
        k = np.maximum(np.ceil(np.linalg.norm(b - a, axis=1) / SAMPLE_SPACING).astype(np.int64), 1)
        t = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k, k)
        q = np.repeat(a, k, axis=0) + t[:, None] * np.repeat(b - a, k, axis=0)
        c = np.clip(np.floor(q).astype(np.int64), 0, top) + 1
        near[c[:, 0], c[:, 1]] = True
    ring = near.copy()
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            ring[1:-1, 1:-1] |= near[1 + di:nu + 1 + di, 1 + dj:nv + 1 + dj]
    full = np.zeros((nu, nv), dtype=bool)
    i, j = np.nonzero(~ring[1:-1, 1:-1])
    if len(i):
        full[i, j] = ts._flattened().classify(lo[0] + (i + 0.5) * h / scale[0],
                                              lo[1] + (j + 0.5) * h / scale[1]) == inside
    for _ in range(nu * nv):
        diag = full[:-1, :-1] & full[1:, 1:] & ~full[1:, :-1] & ~full[:-1, 1:]
        anti = full[1:, :-1] & full[:-1, 1:] & ~full[:-1, :-1] & ~full[1:, 1:]
        if not (diag.any() or anti.any()):
            break
        full[:-1, :-1] &= ~diag
        full[1:, :-1] &= ~anti
    return full


def _cell_triangles(full: np.ndarray) -> np.ndarray:
    n1 = full.shape[1] + 1
    i, j = np.nonzero(full)
    a = i * n1 + j
    b, c, d = a + n1, a + n1 + 1, a + 1
    return np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)]).astype(np.int64)


def _staircases(full: np.ndarray) -> List[np.ndarray]:
    """The outlines of the full cells as loops of grid-vertex indices, oriented with the
    full cells on their right (R on the left)."""
    F = np.pad(full, 1)
    n1 = full.shape[1] + 1
    i, j = np.nonzero(full)
    node = i * n1 + j
    edges = []
    # a cell's counter-clockwise sides, kept where the neighbour across is not full; reversed
    for keep, s, e in ((~F[i + 1, j], node + n1, node),                 # bottom: (i,j)->(i+1,j)
                       (~F[i + 2, j + 1], node + n1 + 1, node + n1),    # right
                       (~F[i + 1, j + 2], node + 1, node + n1 + 1),     # top
                       (~F[i, j + 1], node, node + 1)):                 # left
        edges.append(np.stack([s[keep], e[keep]], axis=1))
    E = np.concatenate(edges)
    size = (full.shape[0] + 1) * n1
    succ = np.full(size, -1, dtype=np.int64)
    succ[E[:, 0]] = E[:, 1]
    seen = np.zeros(size, dtype=bool)
    loops: List[np.ndarray] = []
    for s0 in E[:, 0]:
        if seen[s0]:
            continue
        loop = [s0]
        seen[s0] = True
        x = succ[s0]
        for _ in range(len(E)):
            if x == s0 or x < 0:
                break
            loop.append(x)
            seen[x] = True
            x = succ[x]
        loops.append(np.array(loop, dtype=np.int64))
    return loops


# --- polygons with holes ----------------------------------------------------------------------------
def _signed_area2(P: np.ndarray) -> float:
    return float(np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]))


def _winding(p: np.ndarray, Q: np.ndarray) -> int:
    return int(_crossings(p[0], p[1], Q, np.roll(Q, -1, axis=0)).sum())


def _components(P: np.ndarray, loops: List[np.ndarray]) -> List[Tuple[np.ndarray, List[np.ndarray]]]:
    """Outer loops (counter-clockwise) with the holes (clockwise) whose smallest
    enclosing outer loop they are."""
    areas = [_signed_area2(P[lp]) for lp in loops]
    outers = [k for k, a in enumerate(areas) if a > 0]
    holes: List[List[np.ndarray]] = [[] for _ in outers]
    for k, a in enumerate(areas):
        if a >= 0:
            continue
        best: Optional[int] = None
        for n, o in enumerate(outers):
            if _winding(P[loops[k][0]], P[loops[o]]) != 0 and (best is None or areas[o] < areas[outers[best]]):
                best = n
        if best is not None:
            holes[best].append(loops[k])
    return [(loops[o], holes[n]) for n, o in enumerate(outers)]


def _bridge(P: np.ndarray, ring: np.ndarray, hole: np.ndarray, loops: List[np.ndarray]) -> Optional[np.ndarray]:
    """``ring`` with ``hole`` spliced in through a segment from the hole's leftmost vertex
    to the nearest ring vertex on its left (used once in the ring) that crosses and touches
    no loop edge; None when there is none."""
    h = int(np.lexsort((P[hole, 1], P[hole, 0]))[0])
    M = P[hole[h]]
    R = P[ring]
    uniq, inv, cnt = np.unique(ring, return_inverse=True, return_counts=True)
    cand = np.flatnonzero((R[:, 0] <= M[0]) & (cnt[inv] == 1))
    if not len(cand):
        return None
    cand = cand[np.argsort(np.linalg.norm(R[cand] - M, axis=1), kind="stable")]
    E0 = np.concatenate([P[lp] for lp in loops] + [R])
    E1 = np.concatenate([P[np.roll(lp, -1)] for lp in loops] + [np.roll(R, -1, axis=0)])
    for k in cand:
        if not _blocked(M, R[k], E0, E1):
            return np.concatenate([ring[:k + 1], np.roll(hole, -h), [hole[h]], ring[k:]])
    return None


def _blocked(M: np.ndarray, V: np.ndarray, E0: np.ndarray, E1: np.ndarray) -> bool:
    """Whether the open segment M-V crosses an edge or passes through an edge's vertex."""
    d = V - M
    length2 = float(d @ d)
    if length2 == 0.0:
        return True
    o1, o2 = orient(M, V, E0), orient(M, V, E1)
    o3, o4 = orient(E0, E1, M), orient(E0, E1, V)
    if np.any((o1 * o2 < 0) & (o3 * o4 < 0)):
        return True
    t = (E0 - M) @ d / length2
    flat = np.abs(o1) <= DEGENERATE_AREA
    return bool(np.any(flat & (t > 0) & (t < 1) & np.any(E0 != M, axis=1) & np.any(E0 != V, axis=1)))


def _ear_clip(P: np.ndarray, ring: np.ndarray) -> Tuple[np.ndarray, int]:
    """Ear clipping of one counter-clockwise ring (vertex indices into P, a hole bridge
    visiting two vertices twice): (triangles, 1 if it stalled and fell back else 0).

    An ear is a convex vertex whose triangle holds no reflex (or flat) vertex of the ring
    except copies of its own corners. On a pass without an ear the test is relaxed:
    first vertices on the triangle's sides are allowed, then flat vertices are clipped
    (a zero-area triangle keeps the staircase conforming), last any convex vertex."""
    m = len(ring)
    X = P[ring]
    prv, nxt = np.roll(np.arange(m), 1), np.roll(np.arange(m), -1)
    alive = np.ones(m, dtype=bool)
    turn = orient(X[prv], X, X[nxt])
    tris: List[Tuple[int, int, int]] = []
    i, left, misses, stage, stalled = 0, m, 0, 0, 0
    for _ in range(8 * m * m + 8):
        if left < 3:
            break
        a, c = prv[i], nxt[i]
        if _is_ear(X, alive, turn, a, i, c, stage, left):
            tris.append((ring[a], ring[i], ring[c]))
            alive[i] = False
            nxt[a], prv[c] = c, a
            left -= 1
            for k in (a, c):
                turn[k] = orient(X[prv[k]], X[k], X[nxt[k]])
            i, misses, stage = c, 0, 0
            continue
        i = nxt[i]
        misses += 1
        if misses > left:
            misses, stage = 0, stage + 1
            if stage == 3:          # last resort: the most convex vertex (the region stays covered)
                stalled = 1
                live = np.flatnonzero(alive)
                i = int(live[np.argmax(turn[live])])
    return np.array(tris, dtype=np.int64).reshape(-1, 3), stalled


def _is_ear(X: np.ndarray, alive: np.ndarray, turn: np.ndarray, a: int, b: int, c: int, stage: int,
            left: int) -> bool:
    if left == 3 or stage == 3:
        return True
    if stage == 2:
        return abs(turn[b]) <= DEGENERATE_AREA
    if turn[b] <= DEGENERATE_AREA:
        return False
    r = np.flatnonzero(alive & (turn <= DEGENERATE_AREA))
    if not len(r):
        return True
    pa, pb, pc = X[a], X[b], X[c]
    Q = X[r]
    Q = Q[~(np.all(Q == pa, axis=1) | np.all(Q == pb, axis=1) | np.all(Q == pc, axis=1))]
    if not len(Q):
        return True
    d1, d2, d3 = orient(pa, pb, Q), orient(pb, pc, Q), orient(pc, pa, Q)
    if stage == 0:          # vertices on (or within DEGENERATE_AREA of) the sides block
        return not np.any((d1 >= -DEGENERATE_AREA) & (d2 >= -DEGENERATE_AREA) & (d3 >= -DEGENERATE_AREA))
    return not np.any((d1 > DEGENERATE_AREA) & (d2 > DEGENERATE_AREA) & (d3 > DEGENERATE_AREA))


# --- Lawson flips ---------------------------------------------------------------------------------
MIN_FLIP_PASSES = 64       # Lawson passes at most: this plus one per triangle (each pass flips at least
#                            one edge; a fan of k slivers takes about k passes: 1-2 x count measured)
FLIP_TOL = 1e-12           # incircle / orientation margin of a flip, relative to the quad's size


def _lawson(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Lawson's edge flips towards the constrained Delaunay triangulation (de Berg et al.,
    Computational Geometry, 9.1): an edge shared by triangles (a, b, c) and (b, a, d) is
    flipped to (c, d) when d lies inside the circumcircle of (a, b, c) and the quad is
    convex; edges of one triangle (the trim loops) stay fixed. ``P`` is scaled to the
    loops' box. Bounded by MIN_FLIP_PASSES + m passes for m triangles."""
    T = np.array(T, dtype=np.int64).reshape(-1, 3)
    if len(T) < 2:
        return T
    m = len(T)
    for _ in range(MIN_FLIP_PASSES + m):
        ks = np.arange(3)
        a = T[:, ks].ravel()
        b = T[:, (ks + 1) % 3].ravel()
        key = np.minimum(a, b) * len(P) + np.maximum(a, b)
        order = np.argsort(key, kind="stable")
        same = np.flatnonzero(key[order][1:] == key[order][:-1])
        if not len(same):
            break
        h1, h2 = order[same], order[same + 1]
        t1, k1, t2, k2 = h1 // 3, h1 % 3, h2 // 3, h2 % 3
        A, B = T[t1, k1], T[t1, (k1 + 1) % 3]
        C, D = T[t1, (k1 + 2) % 3], T[t2, (k2 + 2) % 3]
        pa, pb, pc, pd = P[A], P[B], P[C], P[D]
        ad, bd, cd = pa - pd, pb - pd, pc - pd
        inc = ((ad ** 2).sum(1) * (bd[:, 0] * cd[:, 1] - bd[:, 1] * cd[:, 0])
               - (bd ** 2).sum(1) * (ad[:, 0] * cd[:, 1] - ad[:, 1] * cd[:, 0])
               + (cd ** 2).sum(1) * (ad[:, 0] * bd[:, 1] - ad[:, 1] * bd[:, 0]))
        size2 = np.maximum.reduce([(ad ** 2).sum(1), (bd ** 2).sum(1), (cd ** 2).sum(1)])   # the quad's
        ok = ((inc > FLIP_TOL * size2 ** 2) & (orient(pc, pa, pd) > FLIP_TOL * size2)       # own scale
              & (orient(pd, pb, pc) > FLIP_TOL * size2))
        cand = np.flatnonzero(ok)
        if not len(cand):
            break
        # a set of disjoint flips: each triangle's best candidate (largest incircle value,
        # ties by position), flipped where it is the best of both its triangles
        rank = np.empty(len(cand), dtype=np.int64)
        rank[np.argsort(-inc[cand], kind="stable")] = np.arange(len(cand))[::-1]
        best = np.full(m, -1, dtype=np.int64)
        np.maximum.at(best, t1[cand], rank)
        np.maximum.at(best, t2[cand], rank)
        e = cand[(best[t1[cand]] == rank) & (best[t2[cand]] == rank)]
        T[t1[e]] = np.stack([C[e], A[e], D[e]], axis=1)
        T[t2[e]] = np.stack([D[e], B[e], C[e]], axis=1)
    return T
