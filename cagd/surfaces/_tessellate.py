"""Triangulation of a trimmed surface's region in (u, v) (issue 15): for plots and STL/OBJ.

A region that is its loop's box (:meth:`TrimmedSurface.region_box`: a face of a file
whose boundary is its parameter box, a periodic one's seam anywhere) is the grid of
that box, two triangles a cell. Otherwise the outer loop's box is scaled by the
surface's mean speeds (3-D proportions, longer side 1) and cut into a grid of cells:
square, 1 / (count + 1) of the longer side (MIN_CELLS across the shorter side at least,
the long side of a cell at most MAX_ASPECT times its short one where the grid would have
almost no full cell), or on grid lines the caller chooses
(cagd.mesh places them by curvature). A cell is *full* when no trim chord meets it (it
is not next to a cell that holds a chord sample, samples at most half of the smallest
cell apart) and its centre is inside the trim; a full cell gives two triangles. What is
left,
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

Ears are tried from a stack (the convex vertices, then the two neighbours of each clip,
alternately first: a strip between two rows of collinear vertices zig-zags instead of
fanning from a corner), each test over the reflex vertices of a bucket grid near the
triangle; Lawson's passes test only the triangles that changed. Cost: O(cells)
vectorized for the grid, about O(k) ear tests for the k vertices of R's polygons (the
trim polylines and staircases), passes of Lawson about as many as the longest fan.
Every loop is bounded.

A periodic face whose outer loop spans one period (a tube with its seam, the loop running
down one side of the window and up the other) is tessellated in that window with its
sides as the grid's first and last lines: the seam chords are dropped from the outer loop,
which leaves chains from side to side; a hole crossing a side is cut there (the crossing
found on the trim curve) and its parts moved into the window; the chains are joined along
each side (up the side x0 + T, down x0: the region on the left) through the grid vertices
there. Those side runs are trim chords (the seam) but no chord samples, so the cells along
the seam are full cells like any other; the band's loops are what is left of the trim
loops and staircases after the edges they share the other way round are cancelled. Where
the chains do not join (a hole touching the seam at a vertex) the face is tessellated as
before, holes moved into the window whole. Loops that leave a bounded direction by the
trim's tol are clipped into the domain before all this.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, List, Optional, Tuple

import numpy as np

from .._periodic import wrap
from .._ranks import ranks
from ._chords import _cartesian, _crossings, closed_chains, orient

if TYPE_CHECKING:
    from .trimmed import TrimmedSurface

CHORD_FRACTION = 0.05      # trim polylines: chord-to-curve bound, in cells (of the smaller cell side)
METRIC_SAMPLES = 9         # grid points per direction where the surface's mean speeds are sampled
MERGE_FRACTION = 1e-9      # consecutive trim vertices closer than this (in cells) are one vertex
MIN_CELLS = 8              # cells across the shorter side at least (uniform grid)
MAX_ASPECT = 4.0           # a cell's longer side at most this times its shorter one (uniform grid) ...
FEW_FULL = 0.05            # ... where fewer than this fraction of the longer cells are full
SLIVER_CELL = 0.25         # grid lines closer than this times the median spacing are one line
LINE_GAP = 1e-9            # grid lines closer than this (of the box) are one line
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


def tessellation(ts: "TrimmedSurface", count: int, lines: Optional[Tuple[np.ndarray, np.ndarray]] = None,
                 chord_tol: Optional[float] = None) -> Tessellation:
    """The triangulation of ``ts``'s region (see the module) on a grid of the outer loop's
    box: cells of 1 / (count + 1) of its longer side in the surface's mean metric, or,
    with ``lines`` = (us, vs), the grid lines at those parameters inside the box (and
    its sides). ``chord_tol``: the trim polylines' largest distance from the trim curves
    in (u, v), if smaller than CHORD_FRACTION of the smallest cell."""
    from .trimmed import INSIDE, _flatten_many
    outer = np.concatenate([c.control_points for c in ts.loops[0]])
    lo, hi = outer.min(axis=0), outer.max(axis=0)        # every loop lies inside the outer one
    # a loop may leave a bounded direction by the trim's tol: its polylines, box and grid are
    # clipped into the domain before the triangulation (clipping the triangles' vertices after
    # it flattened the triangles of a pocket outside: wing_fuselage.step face 1, 5e-6 out)
    dlo, dhi = _domain_bounds(ts)
    lo, hi = np.clip(lo, dlo, dhi), np.clip(hi, dlo, dhi)
    seam = _seam_direction(ts, lo, hi)
    if seam is not None:                # the window [lo, lo + period): its sides are grid lines
        hi = hi.copy()
        hi[seam] = lo[seam] + ts._shifts()[seam]
    scale = _metric(ts, lo, hi)
    gu, gv = _grid_lines(lo, hi, scale, count, lines)
    if ts.region_box() is not None:
        return _box_tessellation(ts, lo, scale, gu, gv)
    polys, mids, pieces = _trim_polylines(ts, _flatten_many, scale, lo, gu, gv, chord_tol)
    if lines is None and max(np.diff(gu).max(), np.diff(gv).max()) > MAX_ASPECT * min(np.diff(gu).min(),
                                                                                      np.diff(gv).min()):
        # a thin face's long cells may all be next to a trim sample (11752.stp[381], cells 38:1
        # and six notches: no full cell, the band ear-clipped right across the face); shorter
        # cells there (the polylines do not change: they are split at the cells' short side).
        # Only there: on a thin face with full cells (wing_fuselage.step[5], 191:1) the 4:1
        # grid was 815 rows instead of 18 and the tessellation 3x slower, for nothing
        S = [(p - lo) * scale for p in polys]
        chords = (np.concatenate(S), np.concatenate([np.roll(p, -1, axis=0) for p in S]))
        if np.mean(_full_cells(ts, chords, gu, gv, lo, scale, INSIDE)) < FEW_FULL:
            gu, gv = _grid_lines(lo, hi, scale, count, lines, MAX_ASPECT)
    grid = np.stack(np.meshgrid(gu, gv, indexing="ij"), axis=-1).reshape(-1, 2)
    if seam is not None:
        out = _seam_tessellation(ts, seam, polys, mids, pieces, grid, gu, gv, lo, scale, INSIDE)
        if out is not None:
            return out
    S = [(p - lo) * scale for p in polys]
    offsets = np.cumsum([len(grid)] + [len(p) for p in S])
    trim = [np.arange(offsets[i], offsets[i + 1]) for i in range(len(S))]
    A = np.concatenate(S)
    B = np.concatenate([np.roll(p, -1, axis=0) for p in S])
    out = _triangulate(ts, np.concatenate([grid] + S), np.concatenate([lo + grid / scale] + polys), trim,
                       np.concatenate(mids), (A, B), gu, gv, lo, scale, INSIDE, cancel=False)
    assert out is not None
    return out


def _triangulate(ts: "TrimmedSurface", P: np.ndarray, uv: np.ndarray, trim: List[np.ndarray], mid: np.ndarray,
                 chords: Tuple[np.ndarray, np.ndarray], gu: np.ndarray, gv: np.ndarray, lo: np.ndarray,
                 scale: np.ndarray, inside: int, cancel: bool) -> Optional[Tessellation]:
    """The tessellation of the region bounded by the ``trim`` loops (indices into P, scaled
    coordinates, the grid's vertices first; ``uv`` the same points in (u, v); ``mid`` the
    curve points at the middles of the loops' edges, in order): the full cells of the grid
    (``chords`` (A, B): the trim chords that keep cells from being full), the band between
    them and the loops ear-clipped. ``cancel``: edges of a loop that a staircase runs along
    the other way (a seam side, a grid line) are no part of the band; None where what is
    left is not a set of simple loops."""
    full = _full_cells(ts, chords, gu, gv, lo, scale, inside)
    loops = trim + _staircases(full)
    if cancel:
        cancelled = _cancel(loops, len(P))
        if cancelled is None:
            return None
        loops = cancelled
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
    band = np.concatenate(tris[1:]).reshape(-1, 3) if len(tris) > 1 else np.empty((0, 3), dtype=np.int64)
    T = np.concatenate([tris[0], _lawson(P, band)])
    bnd = np.concatenate([np.stack([ix, np.roll(ix, -1)], axis=1) for ix in trim])
    used = np.zeros(len(P), dtype=bool)
    used[T.ravel()] = True
    used[bnd.ravel()] = True
    new = np.cumsum(used) - 1
    T, bnd = new[T], new[bnd]
    uv = uv[used]
    dlo, dhi = _domain_bounds(ts)           # (rounding of the grid's last line)
    uv, mid = np.clip(uv, dlo, dhi), np.clip(mid, dlo, dhi)
    for arr in (uv, T, bnd, mid):
        arr.flags.writeable = False
    return Tessellation(uv, T, bnd, mid, fallbacks)


def _box_tessellation(ts: "TrimmedSurface", lo: np.ndarray, scale: np.ndarray, gu: np.ndarray,
                      gv: np.ndarray) -> Tessellation:
    """A region that is its loops' box (:meth:`TrimmedSurface.region_box`): the grid's
    cells, two triangles each; the trim chords are the grid's sides, counter-clockwise,
    measured at their middles (the trim curves are those straight sides)."""
    nu, nv = len(gu) - 1, len(gv) - 1
    T = _cell_triangles(np.ones((nu, nv), dtype=bool))
    uv = lo + np.stack(np.meshgrid(gu, gv, indexing="ij"), axis=-1).reshape(-1, 2) / scale
    n1 = nv + 1
    i, j = np.arange(nu + 1), np.arange(nv + 1)
    ring = np.concatenate([i[:-1] * n1, nu * n1 + j[:-1], i[:0:-1] * n1 + nv, j[:0:-1]])
    bnd = np.stack([ring, np.roll(ring, -1)], axis=1)
    for d, periodic in enumerate((ts.periodic_u, ts.periodic_v)):
        if not periodic:        # the loop may leave a bounded direction by the trim's tol
            uv[:, d] = np.clip(uv[:, d], *ts.surface.domain[d])
    mid = 0.5 * (uv[bnd[:, 0]] + uv[bnd[:, 1]])
    for arr in (uv, T, bnd, mid):
        arr.flags.writeable = False
    return Tessellation(uv, T, bnd, mid, 0)


def _domain_bounds(ts: "TrimmedSurface") -> Tuple[np.ndarray, np.ndarray]:
    """The surface's domain per direction, (-inf, inf) in a periodic one."""
    (u0, u1), (v0, v1) = ts.surface.domain
    return (np.array([-np.inf if ts.periodic_u else u0, -np.inf if ts.periodic_v else v0]),
            np.array([np.inf if ts.periodic_u else u1, np.inf if ts.periodic_v else v1]))


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


def _grid_lines(lo: np.ndarray, hi: np.ndarray, scale: np.ndarray, count: int,
                lines: Optional[Tuple[np.ndarray, np.ndarray]], aspect: float = np.inf
                ) -> Tuple[np.ndarray, np.ndarray]:
    """The grid lines (scaled coordinates, from 0) covering the box [lo, hi]; with
    ``lines`` None, cells at most ``aspect`` times longer than wide."""
    width = (hi - lo) * scale
    if lines is None:
        h = 1.0 / (count + 1)
        least = min(count + 1, MIN_CELLS)         # a thin face (a tube, a fillet) still gets width
        n = np.array([max(least, int(np.ceil(w / h - 1e-9))) for w in width])
        if np.isfinite(aspect):
            n = np.maximum(n, np.ceil(width / (aspect * float(np.min(width / n))) - 1e-9).astype(np.int64))
        nu, nv = int(n[0]), int(n[1])
        return np.arange(nu + 1) * (width[0] / nu), np.arange(nv + 1) * (width[1] / nv)
    out = []
    for d in (0, 1):
        x = np.asarray(lines[d], dtype=np.float64)
        x = np.unique(np.concatenate([[lo[d]], x[(x > lo[d]) & (x < hi[d])], [hi[d]]]))
        # lines much closer than the typical spacing (a knot next to the box side) are
        # dropped: a sliver of cells would set the trim polylines' and samples' spacing
        # (the typical spacing is the caller's own: the loops' box may overshoot the lines'
        # by the trim's tol, 5e-7 and 6.6e-7 at both ends on 917_fusee.stp[112], and those
        # slivers must not be the median: the trim pieces were split at their size, 748,403
        # ring vertices, and the ear clipping ran for minutes)
        own = np.diff(np.unique(np.asarray(lines[d], dtype=np.float64)))
        typical = float(np.median(own)) if len(own) else hi[d] - lo[d]
        gap = max(LINE_GAP * (hi[d] - lo[d]), SLIVER_CELL * typical)
        keep = np.concatenate([[True], np.diff(x) > gap])
        keep[-1] = True
        if len(x) > 2 and np.diff(x)[-1] <= gap:
            keep[-2] = False
        out.append((x[keep] - lo[d]) * scale[d])
    return out[0], out[1]


def _cell_sizes(gu: np.ndarray, gv: np.ndarray, S: np.ndarray) -> np.ndarray:
    """The smaller side of the grid cell holding each point S (scaled coordinates)."""
    i = np.clip(np.searchsorted(gu, S[:, 0], side="right") - 1, 0, len(gu) - 2)
    j = np.clip(np.searchsorted(gv, S[:, 1], side="right") - 1, 0, len(gv) - 2)
    return np.minimum(np.diff(gu)[i], np.diff(gv)[j])


# --- the trim polylines ---------------------------------------------------------------------------
def _trim_polylines(ts: "TrimmedSurface", flatten: Callable, scale: np.ndarray, lo: np.ndarray, gu: np.ndarray,
                    gv: np.ndarray, chord_tol: Optional[float] = None
                    ) -> Tuple[List[np.ndarray], List[np.ndarray], List["_Pieces"]]:
    """Per loop: points on the trim curves (the flattening's piece ends, pieces longer than
    the cell they start in split at equal parameter steps), the curve points at the
    middle parameter of each chord and each chord's Bezier piece (where a seam cuts it);
    holes of a periodic direction moved into the outer loop's period."""
    h = float(min(np.diff(gu).min(), np.diff(gv).min()))
    tol = CHORD_FRACTION * h / float(np.max(scale))
    if chord_tol is not None:
        tol = min(tol, chord_tol)
    chains = closed_chains(ts.loops)
    curves = [c for _, chain, _ in chains for c in chain]
    nets = [Q for Q, _ in flatten(curves, tol)]
    bounds = _domain_bounds(ts)
    polys, mids, pieces, k = [], [], [], 0
    for _, chain, names in chains:
        starts, middles, straight, owner, row, ts0, ts1 = [], [], [], [], [], [], []
        loop_nets: List[np.ndarray] = []
        # a gap closer (name -1, a joint's gap up to the trim's tol) adds no vertex: the last
        # chord of the curve before it ends at the next curve's start, and is measured at its
        # own middle (the gap closed straight, as classification and area() close it)
        for q, (Q, name) in enumerate(zip(nets[k:k + len(chain)], names)):
            if name < 0:
                continue
            A = (_cartesian(Q[:, 0]) - lo) * scale
            chord = (_cartesian(Q[:, -1]) - lo) * scale - A
            n = np.maximum(np.ceil(np.linalg.norm(chord, axis=1) / _cell_sizes(gu, gv, A)).astype(np.int64), 1)
            j = ranks(n)
            R = np.repeat(Q, n, axis=0)
            starts.append(_de_casteljau(R, j / np.repeat(n, n)))
            middles.append(_de_casteljau(R, (j + 0.5) / np.repeat(n, n)))
            owner.append(np.full(len(j), len(loop_nets)))
            row.append(np.repeat(np.arange(len(Q)), n))
            ts0.append(j / np.repeat(n, n))
            ts1.append((j + 1) / np.repeat(n, n))
            loop_nets.append(Q)
            closed = np.zeros(len(j), dtype=bool)
            closed[-1] = names[(q + 1) % len(names)] < 0
            straight.append(closed)
        k += len(chain)
        start, mid, gap = np.concatenate(starts), np.concatenate(middles), np.concatenate(straight)
        start, mid = np.clip(start, *bounds), np.clip(mid, *bounds)
        mid[gap] = 0.5 * (start + np.roll(start, -1, axis=0))[gap]
        step = np.linalg.norm((np.roll(start, -1, axis=0) - start) * scale, axis=1)
        keep = step > MERGE_FRACTION * h          # zero-length chords: one vertex, not two
        if np.count_nonzero(keep) < 3:            # a loop this small keeps every distinct vertex
            keep = step > 0
        polys.append(start[keep])
        mids.append(mid[keep])
        pieces.append(_Pieces(loop_nets, np.concatenate(owner)[keep], np.concatenate(row)[keep],
                              np.concatenate(ts0)[keep], np.concatenate(ts1)[keep]))
    periods = ts._shifts()
    lo0 = polys[0].min(axis=0)
    for i in range(1, len(polys)):
        shift = np.array([wrap(polys[i][0, d], lo0[d], T) - polys[i][0, d] if T > 0 else 0.0
                          for d, T in enumerate(periods)])
        polys[i], mids[i] = polys[i] + shift, mids[i] + shift
    return polys, mids, pieces


@dataclass(frozen=True)
class _Pieces:
    """Each chord's Bezier piece: ``nets[owner[k]][row[k]]`` (homogeneous) on [t0[k], t1[k]]."""
    nets: List[np.ndarray]
    owner: np.ndarray
    row: np.ndarray
    t0: np.ndarray
    t1: np.ndarray

    def crossing(self, k: int, d: int, x: float, a: np.ndarray, b: np.ndarray
                 ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where chord k (from a to b) of the loop crosses coordinate d = x: the point on
        the trim curve (coordinate d exactly x) and the curve points at the middles of the
        two parts; on the chord where the curve's piece does not cross (a chord over merged
        vertices or a gap closer)."""
        Q = self.nets[int(self.owner[k])][int(self.row[k])][None]
        t0, t1 = float(self.t0[k]), float(self.t1[k])

        def at(t: np.ndarray) -> np.ndarray:
            return _de_casteljau(np.repeat(Q, len(t), axis=0), t)
        f = at(np.array([t0, t1]))[:, d] - x
        if f[0] * f[1] <= 0 and f[0] != f[1]:
            lo_t, hi_t, f_lo = t0, t1, f[0]
            for _ in range(14):             # 16 parts a round: 16^14 > 1 / 2^-53
                t = np.linspace(lo_t, hi_t, 17)
                g = at(t)[:, d] - x
                i = int(np.argmax(np.sign(g[1:]) != np.sign(f_lo)))
                lo_t, hi_t, f_lo = t[i], t[i + 1], g[i]
                if hi_t - lo_t <= 4e-16 * max(1.0, abs(lo_t)):
                    break
            tx = 0.5 * (lo_t + hi_t)
            X, ma, mb = at(np.array([tx, 0.5 * (t0 + tx), 0.5 * (tx + t1)]))
        else:
            s = float(np.clip((x - a[d]) / (b[d] - a[d]), 0.0, 1.0)) if b[d] != a[d] else 0.5
            X = a + s * (b - a)
            ma, mb = 0.5 * (a + X), 0.5 * (X + b)
        X = X.copy()
        X[d] = x
        return X, ma, mb


def _de_casteljau(Q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points of homogeneous Bezier nets Q (m, p + 1, 3) at parameters t (m,) in [0, 1]."""
    R = Q
    w = t[:, None, None]
    for _ in range(Q.shape[1] - 1):
        R = (1 - w) * R[:, :-1] + w * R[:, 1:]
    return _cartesian(R[:, 0])


# --- the seam of a periodic face -------------------------------------------------------------------
def _seam_direction(ts: "TrimmedSurface", lo: np.ndarray, hi: np.ndarray) -> Optional[int]:
    """The periodic direction in which the outer loop's box spans one period (to the
    trim's tol): the loop runs along the seam, the window's two sides; else None."""
    for d, T in enumerate(ts._shifts()):
        if T > 0 and abs(float(hi[d] - lo[d]) - T) <= max(ts.tol, 1e-9 * T):
            return d
    return None


Chain = Tuple[np.ndarray, np.ndarray, int, int]     # (u, v) points, chord middles, side of first and last


def _seam_chains(ts: "TrimmedSurface", d: int, polys: List[np.ndarray], mids: List[np.ndarray],
                 pieces: List[_Pieces], lo: np.ndarray, h: float, scale: np.ndarray
                 ) -> Optional[Tuple[List[Chain], List[Tuple[np.ndarray, np.ndarray]]]]:
    """The loops in the window [x0, x0 + T] of direction d (x0 = lo[d]): the outer loop
    without its seam chords (chords on a side, to the trim's tol) as chains from side to
    side (0: x0, 1: x0 + T), the holes cut where they cross a side (on the trim curve)
    and each part moved into the window, and the holes that cross no side whole."""
    T = ts._shifts()[d]
    x0, x1 = float(lo[d]), float(lo[d]) + T
    eps = min(max(ts.tol, 1e-9 * T), 0.01 * h / float(scale[d]))
    outer, omid = polys[0].copy(), mids[0]
    on0, on1 = np.abs(outer[:, d] - x0) <= eps, np.abs(outer[:, d] - x1) <= eps
    seam = (on0 & np.roll(on0, -1)) | (on1 & np.roll(on1, -1))
    if not seam.any() or seam.all():
        return None
    outer[on0, d], outer[on1, d] = x0, x1
    outer[:, d] = np.clip(outer[:, d], x0, x1)
    r = int(np.flatnonzero(~seam & np.roll(seam, 1))[0])
    O, M, Sm = np.roll(outer, -r, axis=0), np.roll(omid, -r, axis=0), np.roll(seam, -r)
    n = len(O)
    chains: List[Chain] = []

    def side(p: np.ndarray) -> int:
        return 0 if p[d] == x0 else 1 if p[d] == x1 else -1
    for a, b in zip(np.flatnonzero(~Sm & np.roll(Sm, 1)), np.flatnonzero(~Sm & np.roll(Sm, -1))):
        V = O[np.arange(a, b + 2) % n]
        if side(V[0]) < 0 or side(V[-1]) < 0:
            return None
        chains.append((V, M[a:b + 1], side(V[0]), side(V[-1])))
    closed = []
    unit = np.zeros(2)
    unit[d] = T
    for H, HM, pc in zip(polys[1:], mids[1:], pieces[1:]):
        m = np.floor((H[:, d] - x0) / T)
        if np.all(m == m[0]):
            closed.append((H - m[0] * unit, HM - m[0] * unit))
            continue
        k_ = len(H)
        dm = np.roll(m, -1) - m
        if np.abs(dm).max() > 1:
            return None
        cross = np.flatnonzero(dm != 0)
        line = np.maximum(m[cross], m[(cross + 1) % k_])
        cuts = [pc.crossing(int(k), d, x0 + float(L) * T, H[k], H[(k + 1) % k_]) for k, L in zip(cross, line)]
        for j in range(len(cross)):
            j1 = (j + 1) % len(cross)
            k0, k1 = int(cross[j]), int(cross[j1])
            idx = np.arange(k0 + 1, k1 + 1 if k1 > k0 else k1 + 1 + k_) % k_
            mm = m[idx[0]]
            V = np.concatenate([cuts[j][0][None], H[idx], cuts[j1][0][None]]) - mm * unit
            W = np.concatenate([cuts[j][2][None], HM[idx[:-1]], cuts[j1][1][None]]) - mm * unit
            s0, s1 = (0 if line[j] == mm else 1), (0 if line[j1] == mm else 1)
            if np.linalg.norm((V[1] - V[0]) * scale) <= MERGE_FRACTION * h:       # cut at a vertex
                V, W = V[1:], W[1:]
            if np.linalg.norm((V[-1] - V[-2]) * scale) <= MERGE_FRACTION * h:
                V, W = V[:-1], W[:-1]
            if len(V) < 2:
                return None
            V[0, d], V[-1, d] = (x0, x1)[s0], (x0, x1)[s1]
            chains.append((V, W, s0, s1))
    return chains, closed


def _seam_tessellation(ts: "TrimmedSurface", d: int, polys: List[np.ndarray], mids: List[np.ndarray],
                       pieces: List[_Pieces], grid: np.ndarray, gu: np.ndarray, gv: np.ndarray, lo: np.ndarray,
                       scale: np.ndarray, inside: int) -> Optional[Tessellation]:
    """A face whose outer loop runs along the seam of direction d, in the window whose
    sides are the grid's first and last lines: the chains of :func:`_seam_chains` joined
    along the sides through the grid's vertices there (up the side x0 + T, down the side
    x0 for d = 0: the region on the left), so the cells along the seam are full cells like
    any other and a hole across the seam is spliced into the seam; None where the chains
    do not join (the caller's plain tessellation then)."""
    h = float(min(np.diff(gu).min(), np.diff(gv).min()))
    got = _seam_chains(ts, d, polys, mids, pieces, lo, h, scale)
    if got is None:
        return None
    chains, closed = got
    T = ts._shifts()[d]
    nu, nv = len(gu) - 1, len(gv) - 1
    ge = gv if d == 0 else gu
    G = (gu, gv)[d][-1]
    nodes = ((np.arange(nv + 1), nu * (nv + 1) + np.arange(nv + 1)) if d == 0 else
             (np.arange(nu + 1) * (nv + 1), np.arange(nu + 1) * (nv + 1) + nv))
    uv_grid = lo + grid / scale
    uv_grid[nodes[0], d], uv_grid[nodes[1], d] = lo[d], lo[d] + T
    scaled = []
    for V, _, s0, s1 in chains:
        Sc = (V - lo) * scale
        Sc[0, d], Sc[-1, d] = (0.0, G)[s0], (0.0, G)[s1]
        scaled.append(Sc)
    e = 1 - d
    link = {}
    for sd in (0, 1):
        direction = (1 if sd == 1 else -1) * (1 if d == 0 else -1)
        ends = [(direction * S[-1, e], 0, c) for c, (S, ch) in enumerate(zip(scaled, chains)) if ch[3] == sd]
        starts = [(direction * S[0, e], 1, c) for c, (S, ch) in enumerate(zip(scaled, chains)) if ch[2] == sd]
        pts = sorted(ends + starts)
        key = np.array([p[0] for p in pts])
        kinds = [p[1] for p in pts]
        if len(pts) % 2 or kinds != [0, 1] * (len(pts) // 2) or (len(key) > 1 and np.diff(key).min() <= 0):
            return None
        for (k0, _, c0), (k1, _, c1) in zip(pts[::2], pts[1::2]):
            t = direction * ge
            gap = 0.1 * h
            run = np.flatnonzero((t > k0 + gap) & (t < k1 - gap))
            run = run[np.argsort(t[run])]
            link[c0] = (c1, nodes[sd][run])
    base = np.cumsum([len(grid)] + [len(S) for S in scaled])
    loops, loop_mids = [], []
    seen = np.zeros(len(chains), dtype=bool)
    uv_chain = [V for V, _, _, _ in chains]
    for c0 in range(len(chains)):
        if seen[c0]:
            continue
        parts, mparts = [], []
        c = c0
        while not seen[c]:
            seen[c] = True
            nxt, run = link[c]
            parts += [base[c] + np.arange(len(scaled[c])), run]
            across = np.concatenate([uv_chain[c][-1:], uv_grid[run], uv_chain[nxt][:1]])
            mparts += [chains[c][1], 0.5 * (across[:-1] + across[1:])]
            c = nxt
        if c != c0:
            return None
        loops.append(np.concatenate(parts).astype(np.int64))
        loop_mids.append(np.concatenate(mparts))
    S_closed = [(H - lo) * scale for H, _ in closed]
    start = base[-1]
    for Sh, (_, HM) in zip(S_closed, closed):
        loops.append(start + np.arange(len(Sh)))
        loop_mids.append(HM)
        start += len(Sh)
    A = np.concatenate([S[:-1] for S in scaled] + S_closed)
    B = np.concatenate([S[1:] for S in scaled] + [np.roll(Sh, -1, axis=0) for Sh in S_closed])
    P = np.concatenate([grid] + scaled + S_closed)
    uv = np.concatenate([uv_grid] + uv_chain + [H for H, _ in closed])
    return _triangulate(ts, P, uv, loops, np.concatenate(loop_mids), (A, B), gu, gv, lo, scale, inside,
                        cancel=True)


def _cancel(loops: List[np.ndarray], n: int) -> Optional[List[np.ndarray]]:
    """The loops without the edges that another loop runs along the other way, chained
    again; None where a vertex is left with two ways on (the loops touch)."""
    E = np.concatenate([np.stack([lp, np.roll(lp, -1)], axis=1) for lp in loops])
    key, back = E[:, 0] * n + E[:, 1], E[:, 1] * n + E[:, 0]
    E = E[~np.isin(key, back)]
    if np.bincount(E[:, 0], minlength=n).max(initial=0) > 1 or np.bincount(E[:, 1], minlength=n).max(initial=0) > 1:
        return None
    return _traced(E, n, strict=True)


def _traced(E: np.ndarray, n: int, strict: bool) -> Optional[List[np.ndarray]]:
    """The loops the directed edges E (vertices < n, each left by one edge at most) trace,
    from each start not yet seen; ``strict``: None where a chain does not close (a vertex
    with no way on, or one met again), else such a chain is kept as far as it goes."""
    succ = np.full(n, -1, dtype=np.int64)
    succ[E[:, 0]] = E[:, 1]
    seen = np.zeros(n, dtype=bool)
    out = []
    for s0 in E[:, 0]:
        if seen[s0]:
            continue
        loop = [s0]
        seen[s0] = True
        x = succ[s0]
        for _ in range(len(E)):                      # bounded: each step sees a new vertex
            if x == s0:
                break
            if x < 0 or seen[x]:
                if strict:
                    return None
                break
            loop.append(x)
            seen[x] = True
            x = succ[x]
        out.append(np.array(loop, dtype=np.int64))
    return out


# --- the grid: full cells and their outlines ------------------------------------------------------
def _full_cells(ts: "TrimmedSurface", chords: Tuple[np.ndarray, np.ndarray], gu: np.ndarray, gv: np.ndarray,
                lo: np.ndarray, scale: np.ndarray, inside: int) -> np.ndarray:
    """(nu, nv) bool: cells not next to a cell holding a sample of the chords (A, B)
    (samples at most SAMPLE_SPACING of the smallest cell apart, so no chord meets such a
    cell) with their centre inside, without two full cells meeting only at a corner."""
    nu, nv = len(gu) - 1, len(gv) - 1
    h = float(min(np.diff(gu).min(), np.diff(gv).min()))
    near = np.zeros((nu + 2, nv + 2), dtype=bool)
    a, b = chords
    k = np.maximum(np.ceil(np.linalg.norm(b - a, axis=1) / (SAMPLE_SPACING * h)).astype(np.int64), 1)
    t = ranks(k) / np.repeat(k, k)
    q = np.repeat(a, k, axis=0) + t[:, None] * np.repeat(b - a, k, axis=0)
    i = np.clip(np.searchsorted(gu, q[:, 0], side="right") - 1, 0, nu - 1) + 1
    j = np.clip(np.searchsorted(gv, q[:, 1], side="right") - 1, 0, nv - 1) + 1
    near[i, j] = True
    ring = near.copy()
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            ring[1:-1, 1:-1] |= near[1 + di:nu + 1 + di, 1 + dj:nv + 1 + dj]
    full = np.zeros((nu, nv), dtype=bool)
    i, j = np.nonzero(~ring[1:-1, 1:-1])
    if len(i):
        full[i, j] = ts._flattened().classify(lo[0] + 0.5 * (gu[i] + gu[i + 1]) / scale[0],
                                              lo[1] + 0.5 * (gv[j] + gv[j + 1]) / scale[1]) == inside
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
    loops = _traced(np.concatenate(edges), (full.shape[0] + 1) * n1, strict=False)
    assert loops is not None
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
    left, stage, stalled, clipped, flip = m, 0, 0, True, False
    stack: List[int] = []           # vertices to test: the convex ones, then the neighbours of each clip
    buckets = _Buckets(X)
    for _ in range(8 * m * m + 8):
        if left < 3:
            break
        if not stack:
            if not clipped:         # a whole round without an ear: relax the test
                stage += 1
                stalled = max(stalled, int(stage == 3))
            live = np.flatnonzero(alive)
            if stage >= 3:          # last resort: the most convex vertex (the region stays covered)
                stack = [int(live[np.argmax(turn[live])])]
            elif stage == 2:
                stack = live[np.abs(turn[live]) <= DEGENERATE_AREA][::-1].tolist()
            else:
                stack = live[turn[live] > DEGENERATE_AREA][::-1].tolist()
            clipped = False
            continue
        b = stack.pop()
        if not alive[b]:
            continue
        a, c = prv[b], nxt[b]
        if _is_ear(X, alive, turn, a, b, c, min(stage, 3), left, buckets):
            tris.append((ring[a], ring[b], ring[c]))
            alive[b] = False
            nxt[a], prv[c] = c, a
            left -= 1
            for k in (a, c):
                turn[k] = orient(X[prv[k]], X[k], X[nxt[k]])
            # the next test alternates between the two neighbours: across a strip between two
            # rows of collinear vertices that zig-zags, where always one side fans from a corner
            flip = not flip
            stack.extend((int(a), int(c)) if flip else (int(c), int(a)))
            clipped, stage = True, 0
    return np.array(tris, dtype=np.int64).reshape(-1, 3), stalled


class _Buckets:
    """The ring's vertices in a grid of about 4 per cell over their box (CSR), so that a
    triangle's test looks only at the vertices of the cells its box covers."""

    def __init__(self, X: np.ndarray):
        self.lo = X.min(axis=0)
        self.g = max(1, int(np.sqrt(len(X) / 4.0)))
        self.cell = np.maximum((X.max(axis=0) - self.lo) / self.g, 1e-300)
        ij = np.clip(((X - self.lo) / self.cell).astype(np.int64), 0, self.g - 1)
        key = ij[:, 0] * self.g + ij[:, 1]
        self.order = np.argsort(key, kind="stable")
        self.start = np.searchsorted(key[self.order], np.arange(self.g * self.g + 1))

    def near(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        i0, j0 = np.clip(((lo - self.lo) / self.cell).astype(np.int64) - 1, 0, self.g - 1)
        i1, j1 = np.clip(((hi - self.lo) / self.cell).astype(np.int64) + 1, 0, self.g - 1)
        rows = [self.order[self.start[i * self.g + j0]:self.start[i * self.g + j1 + 1]] for i in range(i0, i1 + 1)]
        return np.concatenate(rows) if len(rows) > 1 else rows[0]


def _is_ear(X: np.ndarray, alive: np.ndarray, turn: np.ndarray, a: int, b: int, c: int, stage: int,
            left: int, buckets: _Buckets) -> bool:
    if left == 3 or stage == 3:
        return True
    if stage == 2:
        return abs(turn[b]) <= DEGENERATE_AREA
    if turn[b] <= DEGENERATE_AREA:
        return False
    pa, pb, pc = X[a], X[b], X[c]
    T = np.stack([pa, pb, pc])
    r = buckets.near(T.min(axis=0), T.max(axis=0))
    r = r[alive[r] & (turn[r] <= DEGENERATE_AREA)]
    if not len(r):
        return True
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


def _neighbours(T: np.ndarray) -> np.ndarray:
    """(m, 3): the triangle across edge k = (T[k], T[k + 1]) of each triangle, -1 on the
    boundary (an edge of one triangle)."""
    m = len(T)
    a, b = T.ravel(), T[:, [1, 2, 0]].ravel()
    key = np.minimum(a, b) * (int(T.max()) + 1) + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    same = np.flatnonzero(key[order][1:] == key[order][:-1])
    N = np.full(3 * m, -1, dtype=np.int64)
    h1, h2 = order[same], order[same + 1]
    N[h1], N[h2] = h2 // 3, h1 // 3
    return N.reshape(m, 3)


def _lawson(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Lawson's edge flips towards the constrained Delaunay triangulation (de Berg et al.,
    Computational Geometry, 9.1): an edge shared by triangles (a, b, c) and (b, a, d) is
    flipped to (c, d) when d lies inside the circumcircle of (a, b, c) and the quad is
    convex; edges of one triangle (the loops of R) stay fixed. Each pass tests the edges
    of the triangles that changed (or could not flip) in the pass before and flips a set
    of them no two of which touch or neighbour each other (the largest incircle value in
    its neighbourhood), keeping the neighbour table current. Bounded by MIN_FLIP_PASSES +
    m passes for m triangles (each flips at least one edge)."""
    T = np.array(T, dtype=np.int64).reshape(-1, 3)
    m = len(T)
    if m < 2:
        return T
    N = _neighbours(T)
    act = np.arange(m)                                      # the triangles whose edges are tested
    active = np.zeros(m, dtype=bool)
    best = np.full(m, -1, dtype=np.int64)
    for _ in range(MIN_FLIP_PASSES + m):
        active[act] = True
        t1, k1 = np.repeat(act, 3), np.tile(np.arange(3), len(act))
        t2 = N[t1, k1]
        keep = (t2 >= 0) & (~active[np.maximum(t2, 0)] | (t1 < t2))      # each shared edge once
        active[act] = False
        t1, k1, t2 = t1[keep], k1[keep], t2[keep]
        if not len(t1):
            break
        k2 = np.argmax(N[t2] == t1[:, None], axis=1)
        A, B, C = T[t1, k1], T[t1, (k1 + 1) % 3], T[t1, (k1 + 2) % 3]
        D = T[t2, (k2 + 2) % 3]
        pa, pb, pc, pd = P[A], P[B], P[C], P[D]
        ad, bd, cd = pa - pd, pb - pd, pc - pd
        inc = ((ad ** 2).sum(1) * (bd[:, 0] * cd[:, 1] - bd[:, 1] * cd[:, 0])
               - (bd ** 2).sum(1) * (ad[:, 0] * cd[:, 1] - ad[:, 1] * cd[:, 0])
               + (cd ** 2).sum(1) * (ad[:, 0] * bd[:, 1] - ad[:, 1] * bd[:, 0]))
        size2 = np.maximum.reduce([(ad ** 2).sum(1), (bd ** 2).sum(1), (cd ** 2).sum(1)])   # the quad's
        ok = ((inc > FLIP_TOL * size2 ** 2) & (orient(pc, pa, pd) > FLIP_TOL * size2)       # own scale
              & (orient(pd, pb, pc) > FLIP_TOL * size2))
        e = np.flatnonzero(ok)
        if not len(e):
            break
        # flips far enough apart to update at once: the best rank in the neighbourhood
        rank = np.empty(len(e), dtype=np.int64)
        rank[np.argsort(-inc[e], kind="stable")] = np.arange(len(e))[::-1]
        np.maximum.at(best, t1[e], rank)
        np.maximum.at(best, t2[e], rank)

        def near(t: np.ndarray) -> np.ndarray:
            return np.maximum(best[t], np.where(N[t] >= 0, best[np.maximum(N[t], 0)], -1).max(axis=1))
        pick = e[(near(t1[e]) == rank) & (near(t2[e]) == rank)]
        best[t1[e]] = best[t2[e]] = -1
        i, j, q1, q2 = t1[pick], t2[pick], k1[pick], k2[pick]
        a_, b_, c_, d_ = A[pick], B[pick], C[pick], D[pick]
        n_bc, n_ca = N[i, (q1 + 1) % 3], N[i, (q1 + 2) % 3]
        n_ad, n_db = N[j, (q2 + 1) % 3], N[j, (q2 + 2) % 3]
        T[i] = np.stack([c_, a_, d_], axis=1)                # edges (c,a) (a,d) (d,c)
        T[j] = np.stack([d_, b_, c_], axis=1)                # edges (d,b) (b,c) (c,d)
        N[i] = np.stack([n_ca, n_ad, j], axis=1)
        N[j] = np.stack([n_db, n_bc, i], axis=1)
        for x, old, new in ((n_ad, j, i), (n_bc, i, j)):     # the outer neighbours that changed sides
            s_ = x >= 0
            xs, olds, news = x[s_], old[s_], new[s_]
            col = np.argmax(N[xs] == olds[:, None], axis=1)
            N[xs, col] = news
        act = np.unique(np.concatenate([t1[e], t2[e]]))      # flipped, or left for a later pass
    return T
