"""Coincident pieces of two surfaces (or of a surface and a plane) for
:mod:`cagd.queries.intersect_surfaces`: during the seed subdivision a piece whose
samples all project onto the other object within ``tol`` lies on it (like the curve
overlaps of :mod:`cagd.queries._overlaps`); such pieces are taken out of the
subdivision, merged into connected parameter boxes whose edges are moved out by
bisection to where the surfaces separate, and reported as :class:`SurfaceOverlap`."""
from __future__ import annotations

from typing import List, Optional

import numpy as np

from .._periodic import wrap, wrapped_difference
from . import _subdivision as sd
from .results import SurfaceOverlap
from ._newton import project_onto
from ._numerics import AT_END_RTOL, COLLAPSED_SPEED_RTOL, END_MARGIN_RTOL, SLACK_RTOL

_N = 5                        # samples per direction on a piece (odd: the centre is one)
#: projection starts lie this fraction of a piece inside it: a start on a collapsed edge
#: (a pole) cannot move along it (the partial vanishes there) and Newton stopped at the
#: pole, 0.34 from the foot (boxed_sphere.step Document[190] x [191], issue 16)
SEED_INSET = 1e-3




def _grid(lo: np.ndarray, hi: np.ndarray, n: int = _N) -> np.ndarray:
    """n x n parameter samples (M, n*n, 2) of the boxes (lo, hi) (M, 2), corners included."""
    s = np.linspace(0.0, 1.0, n)
    fu, fv = np.meshgrid(s, s, indexing="ij")
    f = np.stack([fu.ravel(), fv.ravel()], axis=1)
    return lo[:, None, :] + f[None] * (hi - lo)[:, None, :]


def distances(G: sd.Geometry, H, pl, x: np.ndarray, seed: Optional[np.ndarray]):
    """Distance of G(x) (x (N, 2)) from H (projection seeded by ``seed``) or from the
    plane pl; returns (distances (N,), parameters on H (N, 2) or None)."""
    P = G.points(x)
    if H is None:
        o, nrm = pl
        return np.abs((P - o) @ nrm), None
    assert seed is not None                     # the callers seed every projection onto H
    y, d = project_onto(H, P, seed)
    return d, y


def grid_seeds(H: sd.Geometry, P: np.ndarray, lo: np.ndarray, hi: np.ndarray, n: int = 6) -> np.ndarray:
    """Starts (N, 2) for projecting the points P (N, 3) onto H: the nearest of n x n
    samples of H's parameter boxes (lo, hi) (N, 2) or (1, 2). Robust where one start for
    a whole piece is not: at poles and apexes, where Newton from a piece's centre can
    stop far from the foot of a corner. Each distinct box is sampled once (the points of
    one piece share its box: 25 x fewer evaluations in :func:`lying_on`)."""
    boxes, which = np.unique(np.concatenate([np.broadcast_to(lo, P.shape[:1] + (2,)),
                                             np.broadcast_to(hi, P.shape[:1] + (2,))], axis=1),
                             axis=0, return_inverse=True)
    which = which.reshape(-1)
    blo, bhi = boxes[:, :2], boxes[:, 2:]
    inset = SEED_INSET * (bhi - blo)
    x = _grid(blo + inset, bhi - inset, n)    # (boxes, n*n, 2)
    Q = H.points(x.reshape(-1, 2)).reshape(len(boxes), n * n, -1)[which]
    k = np.argmin(np.einsum("nsd,nsd->ns", Q - P[:, None], Q - P[:, None]), axis=1)
    return x[which, k]


def lying_on(G: sd.Geometry, H, pl, lo, hi, lo_h, hi_h, tol: float, ctrl_h: Optional[np.ndarray] = None):
    """Which pieces (boxes lo, hi of G) lie on H (or the plane): all _N x _N samples
    within tol, each projected from the nearest sample of H's piece (lo_h, hi_h).
    Returns the mask and the parameters on H of the piece centres (of the pieces that
    lie on H; the others' rows are undefined).

    With H's pieces' control nets ``ctrl_h`` (M, ..., D + 1), a centre farther than tol
    from its H piece's control hull (its box, or its slab along the piece's corner
    normal: convex hull property) is off that piece without a projection. A foot on
    another piece of H is found by the pair with that piece, which the subdivision
    keeps (the centre and the foot lie within tol, so neither the pieces' boxes nor
    their slabs part them).

    The centres go first: a piece whose centre is off H fails whatever its other
    samples do, and each sample's projection depends on that sample only, so only the
    pieces whose centre lies on H project the other _N^2 - 1 (the same answer; nearly
    parallel neighbours meeting along an edge are tested at every level of the seed
    subdivision and almost never lie on each other: 25 x fewer projections on
    trj3_s1-al-214.stp space_ship[82] x [85], issue 16)."""
    centre = (_N * _N) // 2
    x = _grid(lo, hi)                                                            # (M, _N^2, 2)
    near = np.arange(len(x))
    if ctrl_h is not None and H is not None and len(x):
        near = np.flatnonzero(sd.hull_gap(G.points(x[:, centre]), ctrl_h) <= tol)
    ok = np.zeros(len(x), bool)
    mid = np.full((len(x), 2), np.nan)
    if near.size:
        lo_n, hi_n = (None, None) if lo_h is None else (lo_h[near], hi_h[near])      # (a plane has none)
        ok[near], got = _samples_on(G, H, pl, x[near, centre], lo_n, hi_n, tol)
        if got is not None:
            mid[near] = got
    rest = np.flatnonzero(ok)
    if rest.size:
        x = np.delete(x[rest], centre, axis=1)                                  # (R, _N^2 - 1, 2)
        per = x.shape[1]
        on, _ = _samples_on(G, H, pl, x.reshape(-1, 2), np.repeat(lo_h[rest], per, axis=0),
                            np.repeat(hi_h[rest], per, axis=0), tol)
        ok[rest] = np.all(on.reshape(len(rest), per), axis=1)
    return ok, mid


def _samples_on(G: sd.Geometry, H, pl, x: np.ndarray, lo_h, hi_h, tol: float):
    """Whether G(x) lies within tol of H (projected from the nearest of H's samples in the
    boxes (lo_h, hi_h), one per row of x) or of the plane; and the feet on H (or None)."""
    seed = None if H is None else grid_seeds(H, G.points(x), lo_h, hi_h)
    d, y = distances(G, H, pl, x, seed)
    return d <= tol, y


def covered(lo: np.ndarray, hi: np.ndarray, boxes: List[np.ndarray]) -> np.ndarray:
    """Pieces (lo, hi) inside one of the covered boxes (rows lo0, lo1, hi0, hi1); each
    distinct piece is tested once (a piece appears in many pairs)."""
    if not boxes or len(lo) == 0:
        return np.zeros(len(lo), bool)
    pieces, where = np.unique(np.concatenate([lo, hi], axis=1), axis=0, return_inverse=True)
    out = np.zeros(len(pieces), bool)
    B = np.concatenate(boxes)
    e = SLACK_RTOL
    for b in np.array_split(B, max(1, len(B) // 256)):
        out |= np.any(np.all(pieces[:, None, :2] >= b[None, :, :2] - e, axis=2)
                      & np.all(pieces[:, None, 2:] <= b[None, :, 2:] + e, axis=2), axis=1)
    return out[np.ravel(where)]


def _components(B: np.ndarray) -> List[np.ndarray]:
    """Bounding boxes of the connected components of touching boxes."""
    n = len(B)
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    e = SLACK_RTOL
    touch = np.all(B[:, None, :2] <= B[None, :, 2:] + e, axis=2) & np.all(B[None, :, :2] <= B[:, None, 2:] + e, axis=2)
    for i, j in zip(*np.nonzero(np.triu(touch, 1))):
        parent[find(i)] = find(j)
    roots = np.array([find(i) for i in range(n)])
    return [np.concatenate([B[roots == r, :2].min(0), B[roots == r, 2:].max(0)]) for r in np.unique(roots)]


def _grow(G, H, pl, box, seed_y, tol):
    """Move each edge of box (lo0, lo1, hi0, hi1) outwards while the whole edge (9
    samples) stays within tol of H: steps h, 2h, ... then 40 bisections. Returns (box,
    found): found is False when an edge neither left H in 16 steps nor reached the
    domain's end."""
    box, found = box.copy(), True
    for side in range(4):
        d, up = side % 2, side >= 2                 # parameter direction, moving the high edge
        lim = G.hi[d] if up else G.lo[d]
        o = 1 - d
        s = np.linspace(0.0, 1.0, 9)

        def edge_ok(val, seed):
            x = np.empty((9, 2))
            x[:, d] = val
            x[:, o] = box[o] + s * (box[2 + o] - box[o])
            dist, y = distances(G, H, pl, x, seed)
            if H is not None and not np.all(dist <= tol):     # the start may sit across H's
                P = G.points(x)                                # seam: retry from H's grid
                d2, y2 = distances(G, H, pl, x, grid_seeds(H, P, H.lo[None], H.hi[None], 12))
                better = d2 < dist
                dist, y = np.where(better, d2, dist), np.where(better[:, None], y2, y)
            return bool(np.all(dist <= tol)), y
        cur = box[2 + d] if up else box[d]
        _, seed = edge_ok(cur, None if H is None else np.repeat(seed_y[None], 9, axis=0))
        h = 0.25 * (box[2 + d] - box[d])
        out = None
        for _ in range(16):
            if cur == lim:
                break
            trial = min(cur + h, lim) if up else max(cur - h, lim)
            good, y = edge_ok(trial, seed)
            if not good:
                out = trial
                break
            cur, seed, h = trial, y, 2 * h
        found &= out is not None or cur == lim
        if out is not None:
            for _ in range(40):
                mid = 0.5 * (cur + out)
                good, y = edge_ok(mid, seed)
                if good:
                    cur, seed = mid, y
                else:
                    out = mid
        if up:
            box[2 + d] = cur
        else:
            box[d] = cur
    return box, found


def regions(G: sd.Geometry, H, pl, boxes: List[np.ndarray], seeds: List[np.ndarray], tol: float,
            swap: bool = False) -> List[SurfaceOverlap]:
    """Merge the covered boxes of G into connected components, grow each to where the
    surfaces separate and find the matching box on H."""
    if not boxes:
        return []
    B = np.concatenate(boxes)
    Y = np.concatenate(seeds) if H is not None else None
    out: List[SurfaceOverlap] = []
    grown: List[np.ndarray] = []
    for comp in _components(B):
        centre = 0.5 * (comp[:2] + comp[2:])
        y0 = None
        if Y is not None:
            mids = 0.5 * (B[:, :2] + B[:, 2:])
            y0 = Y[np.argmin(np.linalg.norm(mids - centre, axis=1))]
        box, found = _grow(G, H, pl, comp, y0, tol)
        if any(np.all(box[:2] >= g[:2] - SLACK_RTOL) and np.all(box[2:] <= g[2:] + SLACK_RTOL) for g in grown):
            continue
        grown.append(box)
        ba = ((float(box[0]), float(box[2])), (float(box[1]), float(box[3])))
        bb = None
        if H is not None:
            x = _grid(box[None, :2], box[None, 2:], 7)[0]
            P = G.points(x)
            y, _ = project_onto(H, P, grid_seeds(H, P, H.lo[None], H.hi[None], 16))
            speed = np.linalg.norm(H.derivatives(y, 1)[1], axis=-1)               # (49, 2)
            valid = np.all(speed > COLLAPSED_SPEED_RTOL * H.size, axis=1).reshape(7, 7)
            lo, hi = _unwrapped_box(y.reshape(7, 7, 2), H.lo, H.hi, H.closed, valid)
            bb = ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))
        message = "" if found else "an edge of the box was not located: the overlap may extend further"
        if swap:
            assert bb is not None                   # swapped only between two surfaces
            out.append(SurfaceOverlap(bb, ba, bool(found), message))
        else:
            out.append(SurfaceOverlap(ba, bb, bool(found), message))
    return out


def _unwrapped_box(y: np.ndarray, lo: np.ndarray, hi: np.ndarray, closed: np.ndarray,
                   valid: Optional[np.ndarray] = None):
    """Parameter box of a grid of parameters y (n, n, 2) that may cross the seam of a
    closed direction: neighbours are unwrapped to within half a period, outwards from
    the middle row, the box starts in the domain and runs past its end when it crosses
    the seam (the covering-space convention of IntersectionCurve), and is the whole
    period when it wraps round. Samples not ``valid`` (at a pole, where the parameter
    along the collapsed edge is arbitrary) are carried over and left out of the box in
    the closed directions."""
    n = y.shape[0]
    valid = np.ones(y.shape[:2], bool) if valid is None else valid
    y = y.copy()
    span = hi - lo
    m = n // 2
    for d in np.flatnonzero(closed):
        c = y[..., d]
        out = c.copy()
        for j in range(1, n):                                  # the middle row, left to right
            prev = out[m, j - 1]
            out[m, j] = prev + wrapped_difference(c[m, j], prev, span[d]) if valid[m, j] else prev
        for rows in (range(m + 1, n), range(m - 1, -1, -1)):   # then outwards, column by column
            for i in rows:
                prev = out[i - 1] if i > m else out[i + 1]
                out[i] = np.where(valid[i], prev + wrapped_difference(c[i], prev, span[d]), prev)
        y[..., d] = out
    a, b = y.min(axis=(0, 1)), y.max(axis=(0, 1))
    pick = y[valid] if valid.any() else y.reshape(-1, 2)
    a = np.where(closed, pick.min(axis=0), a)            # a pole's arbitrary value left out
    b = np.where(closed, pick.max(axis=0), b)
    for d in np.flatnonzero(closed):
        if b[d] - a[d] >= span[d] * (1 - AT_END_RTOL):
            a[d], b[d] = lo[d], hi[d]
        else:
            shift = a[d] - wrap(a[d], lo[d], span[d])
            a[d], b[d] = a[d] - shift, b[d] - shift
    return a, b


def inside(x: np.ndarray, regions_: List[SurfaceOverlap], lo: np.ndarray, hi: np.ndarray,
           which: int, closed: np.ndarray) -> np.ndarray:
    """Points x (N, 2) of surface ``which`` (0 = a, 1 = b) inside one of the overlap boxes
    (margin 1e-6 of the domain); in closed directions a box may run past the domain's
    end (across the seam), so x + period is tested too."""
    m = END_MARGIN_RTOL * (hi - lo)
    out = np.zeros(len(x), bool)
    for r in regions_:
        box = r.box_a if which == 0 else r.box_b
        if box is None:
            continue
        hit = np.ones(len(x), bool)
        for d in range(2):
            a, b = box[d]
            c = x[:, d]
            ok = (c >= a - m[d]) & (c <= b + m[d])
            if closed[d]:
                c2 = c + (hi[d] - lo[d])
                ok |= (c2 >= a - m[d]) & (c2 <= b + m[d])
            hit &= ok
        out |= hit
    return out
