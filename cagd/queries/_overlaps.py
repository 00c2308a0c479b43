"""Overlaps of curves: pieces of one curve lying on the other (within tol) found by
projecting samples, merged into maximal parameter intervals whose ends are moved
out (by steps, then sectioning the last one) to where the distance exceeds tol, and
snapped to the domain ends (see :mod:`cagd.queries.intersect`)."""
from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np

from . import _subdivision as sd
from .results import Overlap
from ._newton import project_onto
from ._numerics import AT_END_RTOL, END_MARGIN_RTOL, SAME_PARAM_RTOL


UNSETTLED = "an end was not located: the overlap may extend further"
#: an overlap's end is where the distance passes (1 - END_TOL_SHARE) tol: located by
#: bisection at the distance tol itself, another measure of it (the branch fit's foot
#: points) read 1.0000014e-9 at tol 1e-9, rounding, and the fillet edge of occ22470.igs
#: SOLID[2] x [3] was reported 'fitted within 1.00e-09 > tol' (issue 16)
END_TOL_SHARE = 1e-3
SECTIONS = 32                 # overlap ends: a bracket is cut into this many parts a round
END_STEPS = 16                # ... after at most this many steps out (h, 2h, 4h, ...) ...
END_ROUNDS = 60               # ... and this many rounds of sectioning




# a piece lying within tol of the other object is coincident (an overlap) when it is
# larger than OVERLAP_CAP sqrt(tol size): a tangency at a curvature radius R <= size
# keeps only a cap of diameter 2 sqrt(2 R tol) <= OVERLAP_CAP sqrt(tol size) within tol.
# It was 100: at tol = 1e-3 no piece of a unit object passed, so coincident spheres
# gave 8,490 contact points (19-90 s) and coincident planes 6,013 (26 s), no overlap
OVERLAP_CAP = 2.0 * np.sqrt(2.0)


def overlap_cap(tol: float, size: float) -> float:
    """The smallest extent of a piece lying within tol of the other object that is an
    overlap: OVERLAP_CAP sqrt(tol size), and 0 once tol reaches the objects' size
    (then every piece within tol is one: intersect(sphere(1e-100), itself) at the
    default tol 1e-9 ran 75 s into 5,191 contact points)."""
    return 0.0 if tol >= size else float(OVERLAP_CAP * np.sqrt(tol * size))


def coincident(A, B, pa: sd.Pieces, pb: sd.Pieces, tol: float, self_mode: bool):
    """Pairs whose a-piece lies on B or whose b-piece lies on A (5 samples within tol).
    Returns the hit mask and fragments (s0, s1, y0, y1) (curve pieces; y0, y1 the
    k_B parameters on B matching s0, s1)."""
    M = len(pa.ctrl)
    fr = np.linspace(0.0, 1.0, 5)
    hits = np.zeros(M, bool)
    rows = []
    for P, Q, G, H, swap in ((pa, pb, A, B, False), (pb, pa, B, A, True)):
        if G.k != 1:
            continue
        x = P.lo[:, None, :] + fr[None, :, None] * (P.hi - P.lo)[:, None, :]          # (M, 5, 1)
        seed = 0.5 * (Q.lo + Q.hi)
        y = np.zeros((M, 5, H.k))
        dist = np.full((M, 5), np.inf)
        # the middle samples first: the others only where it lies on H (each projection
        # depends on its own sample only, so the same answer with fewer projections);
        # a middle sample farther than tol from Q's control hull is off Q without one (a
        # foot on another piece of H is found by the pair with that piece: the sample and
        # the foot lie within tol, so neither their boxes nor slabs part the two pieces)
        middle = G.points(x[:, 2])
        near = np.flatnonzero(sd.hull_gap(middle, Q.ctrl) <= tol)
        for at, cols in ((near, [2]), (None, [0, 1, 3, 4])):
            at = np.flatnonzero(dist[:, 2] <= tol) if at is None else at
            if not at.size:
                continue
            xs = x[at][:, cols].reshape(-1, 1)
            pts = middle[at] if cols == [2] else G.points(xs)
            ys, ds = project_onto(H, pts, np.repeat(seed[at], len(cols), axis=0))
            if self_mode:             # the sample itself is no evidence of an overlap
                ds[np.abs(ys[:, 0] - xs[:, 0]) <= SAME_PARAM_RTOL * (A.hi[0] - A.lo[0])] = np.inf
            y[at[:, None], cols] = ys.reshape(len(at), len(cols), -1)
            dist[at[:, None], cols] = ds.reshape(len(at), len(cols))
        ok = np.all(dist <= tol, axis=1) & ~hits
        if ok.any():
            s0, s1 = P.lo[ok, 0], P.hi[ok, 0]
            if H.k == 1:
                t0, t1 = y[ok, 0, 0], y[ok, -1, 0]
                rows.append(np.stack([t0, t1, s0, s1] if swap else [s0, s1, t0, t1], axis=1))
            elif not swap:                               # a curve piece lying in a surface
                rows.append(np.concatenate([s0[:, None], s1[:, None], y[ok, 0], y[ok, -1]], axis=1))
        hits |= ok
    return hits, (np.concatenate(rows) if rows else np.empty((0, 2 + 2 * B.k)))


def inside_overlaps(A, overlaps, x: np.ndarray) -> np.ndarray:
    """Rows of a's parameters x (N, 1) inside one of the overlaps' intervals on a (margin
    END_MARGIN_RTOL of the width)."""
    m = END_MARGIN_RTOL * (A.hi[0] - A.lo[0])
    out = np.zeros(len(x), bool)
    for ov in overlaps:
        s0, s1 = ov.param_a
        out |= (x[:, 0] >= s0 - m) & (x[:, 0] <= s1 + m)
    return out


def merge_overlaps(A, B, frags, tol: float, self_mode: bool, grown: Optional[list] = None) -> List[Overlap]:
    """Merge coincident fragments (s0, s1, y0, y1) into maximal intervals and move each
    end out to where the distance to the other object exceeds tol (:func:`_edge`).
    ``grown``: the overlaps grown by earlier calls on the same objects (appended to): a
    group of fragments inside one of them is that overlap, its ends are not searched
    again (the subdivision merges its growing list of fragments at every level that
    finds new ones, and the same overlaps come back with a few more fragments each;
    occ22470.igs SOLID[2] x [3] searched 38 ends for 4 overlaps, issue 16)."""
    if not frags:
        return []
    kb = B.k
    F = np.concatenate(frags)
    flip = F[:, 0] > F[:, 1]
    F[flip] = F[flip][:, [1, 0] + list(range(2 + kb, 2 + 2 * kb)) + list(range(2, 2 + kb))]
    F = F[np.argsort(F[:, 0])]
    ea, eb = AT_END_RTOL * (A.hi[0] - A.lo[0]), AT_END_RTOL * (B.hi[0] - B.lo[0])
    groups: List[List[float]] = []
    for f in F:
        for g in groups:
            if kb == 1:
                blo, bhi = min(g[2], g[3]), max(g[2], g[3])
                same = f[0] <= g[1] + ea and min(f[2], f[3]) <= bhi + eb and max(f[2], f[3]) >= blo - eb
            else:                     # a curve in a surface: one interval of the curve
                same = f[0] <= g[1] + ea
            if same:
                if f[1] > g[1]:
                    g[1], g[2 + kb:] = f[1], f[2 + kb:]
                break
        else:
            groups.append(list(f))
    out: List[Overlap] = []
    # the ends of the groups not inside an overlap grown earlier, searched together
    spans = [(g[0], g[1], np.array(g[2:2 + kb]), np.array(g[2 + kb:])) for g in groups]
    earlier = [_grown(grown, s0, s1, t0, t1, ea, eb, kb) for s0, s1, t0, t1 in spans]
    search = [i for i, ends in enumerate(earlier) if ends is None]
    starts = []
    for i in search:
        s0, s1, t0, t1 = spans[i]
        starts += [(s0, t0, -1.0, 0.25 * (s1 - s0)), (s1, t1, 1.0, 0.25 * (s1 - s0))]
    found = _edges(A, B, starts, tol, self_mode)
    searched = {i: (*found[2 * k], *found[2 * k + 1]) for k, i in enumerate(search)}
    mine: list = []                             # the overlaps grown by this call
    for i, g in enumerate(groups):
        s0, s1, t0, t1 = spans[i]
        ends = earlier[i] or _grown(mine, s0, s1, t0, t1, ea, eb, kb)
        if ends is None:                  # (a group inside an overlap grown before it in this call is that one)
            ends = searched[i]
            mine.append(ends)
        s0, t0, found0, s1, t1, found1 = ends
        settled = bool(found0 and found1)
        message = "" if settled else UNSETTLED
        s0, t0 = _snap(A, B, s0, t0, tol)
        s1, t1 = _snap(A, B, s1, t1, tol)
        if kb == 2:
            if out and s0 <= out[-1].param_a[1] + ea:      # grown into the previous one
                if s1 > out[-1].param_a[1]:
                    out[-1] = Overlap((out[-1].param_a[0], float(s1)), (out[-1].param_b[0], B.user_params(t1[None])[0]),
                                      settled, message)
                continue
            u0, u1 = B.user_params(np.array([t0, t1]))
            out.append(Overlap((float(s0), float(s1)), (u0, u1), settled, message))
            continue
        if self_mode and t0[0] < s0:
            continue                  # the same overlap seen from its other side
        out.append(Overlap((float(s0), float(s1)), (float(t0[0]), float(t1[0])), settled, message))
    if grown is not None:
        grown += mine
    return out


def _grown(grown: Optional[list], s0: float, s1: float, t0: np.ndarray, t1: np.ndarray, ea: float, eb: float,
           kb: int):
    """The ends (s0, t0, found0, s1, t1, found1) of the overlap grown earlier that holds
    the fragments [s0, s1] (curves: their partners [t0, t1] too), or None."""
    for g in grown or ():
        inside = g[0] - ea <= s0 and s1 <= g[3] + ea
        if inside and kb == 1:
            lo, hi = min(g[1][0], g[4][0]), max(g[1][0], g[4][0])
            inside = lo - eb <= min(t0[0], t1[0]) and max(t0[0], t1[0]) <= hi + eb
        if inside:
            return g[0], g[1].copy(), g[2], g[3], g[4].copy(), g[5]
    return None


def _edges(A, B, starts: List[Tuple[float, np.ndarray, float, float]], tol: float, self_mode: bool
           ) -> List[Tuple[float, np.ndarray, bool]]:
    """For each start (s_in, t_in, sign, h): the last parameter (and its partner on B)
    past s_in, in direction ``sign``, where A still lies within (1 - END_TOL_SHARE) tol
    of B: march by steps h, 2h, 4h, ..., then section the last step until its ends are
    neighbouring doubles, SECTIONS - 1 points a round projected at once (the first one
    off B closes the bracket: 5 bits a round; a bisection, one projection at a time,
    took 37 per end on occ22470.igs, issue 16). All ends go together, one projection a
    round (trj3_s1-al-214.stp faces 4 x 6: 14 ends of 7 overlaps, 127 projections one
    end at a time). Returns (s, t, found) per start: found is False when END_STEPS steps
    neither left B nor reached the domain's end (the overlap may go on)."""
    E = len(starts)
    s_in = [float(st[0]) for st in starts]
    t_in = [np.asarray(st[1], float) for st in starts]
    sign = [st[2] for st in starts]
    h = [float(st[3]) for st in starts]
    lim = [A.hi[0] if sg > 0 else A.lo[0] for sg in sign]
    s_out: List[Optional[float]] = [None] * E
    result: List[Optional[Tuple[float, np.ndarray, bool]]] = [None] * E
    steps, sections = [0] * E, [0] * E
    width = A.hi[0] - A.lo[0]
    while True:
        samples, owner, pending = [], [], []
        for e in range(E):
            if result[e] is not None:
                continue
            so = s_out[e]
            if so is None:                      # marching out: the whole step is sampled
                # (the curve may leave B and come back within it: trj3_s1-al-214.stp faces
                # 8 x 12, an edge touching its neighbour at 7 places grew into one overlap
                # 1.3e-3 off, issue 16)
                if s_in[e] == lim[e] or steps[e] == END_STEPS:
                    result[e] = (s_in[e], t_in[e], s_in[e] == lim[e])
                    continue
                s_try = min(s_in[e] + h[e], lim[e]) if sign[e] > 0 else max(s_in[e] - h[e], lim[e])
                s_k = s_in[e] + np.arange(1, SECTIONS + 1) / SECTIONS * (s_try - s_in[e])
                s_k[-1] = s_try
                s_k = s_k[s_k != s_in[e]]
            else:                               # sectioning [s_in, s_out]
                if sections[e] == END_ROUNDS or 0.5 * (s_in[e] + so) in (s_in[e], so):
                    result[e] = (s_in[e], t_in[e], True)
                    continue
                s_k = s_in[e] + np.arange(1, SECTIONS) / SECTIONS * (so - s_in[e])
                s_k = s_k[(s_k != s_in[e]) & (s_k != so)]
            samples.append(s_k)
            owner.append(np.full(len(s_k), e))
            pending.append(e)
        if not pending:
            break
        s_all, who = np.concatenate(samples), np.concatenate(owner)
        good_all, y = np.zeros(0, bool), np.zeros((0, B.k))
        if len(who):
            y, d = project_onto(B, A.points(s_all[:, None]), np.stack([t_in[e] for e in who]))
            itself = self_mode & (np.abs(y[:, 0] - s_all) <= SAME_PARAM_RTOL * width)
            good_all = (d <= (1.0 - END_TOL_SHARE) * tol) & ~itself
        for e in pending:
            rows = np.flatnonzero(who == e)
            good, s_k, t_k = good_all[rows], s_all[rows], y[rows]
            bad = np.flatnonzero(~good)
            last = (bad[0] if bad.size else len(s_k)) - 1    # the last good point before the first bad one
            if last >= 0:
                s_in[e], t_in[e] = float(s_k[last]), t_k[last]
            if s_out[e] is None:
                steps[e] += 1
                if bad.size:
                    s_out[e] = float(s_k[bad[0]])
                else:
                    h[e] *= 2.0                 # a small fragment may grow to the whole curve
            else:
                sections[e] += 1
                if bad.size:
                    s_out[e] = float(s_k[bad[0]])
    return [r for r in result if r is not None]


def _snap(A, B, s: float, t: np.ndarray, tol: float) -> Tuple[float, np.ndarray]:
    """An overlap end within 1e-6 of a domain end of B (curves) or of A is put on that
    end, its partner by projection, when that end lies within tol of the other object
    ((1 - END_TOL_SHARE) tol, as the ends searched): the bisection alone stops where the
    distance reaches tol (an end of A 6e-6 off B, occ22470.igs faces 1 x 16, was snapped
    on and its branch fitted 6e-6 off)."""
    for end in ((B.lo[0], B.hi[0]) if B.k == 1 else ()):
        if abs(t[0] - end) <= END_MARGIN_RTOL * (B.hi[0] - B.lo[0]):
            x, d = project_onto(A, B.points(np.array([[end]])), np.array([[s]]))
            if float(d[0]) <= (1.0 - END_TOL_SHARE) * tol:
                return float(x[0, 0]), np.array([end])
    for end in (A.lo[0], A.hi[0]):
        if abs(s - end) <= END_MARGIN_RTOL * (A.hi[0] - A.lo[0]):
            y, d = project_onto(B, A.points(np.array([[end]])), t.reshape(1, -1))
            if float(d[0]) <= (1.0 - END_TOL_SHARE) * tol:
                return float(end), y[0]
    return s, t
