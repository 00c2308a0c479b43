"""Fitting one marched intersection branch (private, for
:mod:`cagd.queries.intersect_surfaces`): cubic interpolation with chord-length
parameters (Piegl & Tiller 9.2.1) of the 3-D points and of their parameters, with
corrected midpoints inserted until both are within tol; points whose 3-D images
coincide but whose parameters differ (a run along a collapsed edge: a pole, an apex)
count once in 3-D, and the parameter curves run along the edge there."""
from __future__ import annotations

from typing import List, Tuple

import numpy as np

from ..errors import CagdError
from ._newton import newton
from ._surface_system import System
from ._numerics import AT_END_RTOL, COLLAPSED_SPEED_RTOL, TINY, residual_tol

STALL_ROUNDS = 2             # fit: rounds in a row that may fail to cut the error ...
STALL_FACTOR = 2.0           # ... by this factor before the fit stops
GN_SHIFT_RTOL = 1e-14        # Gauss-Newton shift of the foot projections, share of trace(J^T J)
FOOT_STEP_RTOL = 1e-15       # foot projections: steps below this share of the width end the iteration


#: the branch fit's collocation is used while it hits its points within this fraction of
#: their spread (interpolate asks 1e-9; beyond this the solve has lost the points)
BRANCH_RESIDUAL_TOL = 1e-6
#: edge_fit: rounds of rows added where the other surface's parameter curve is off
EDGE_ROUNDS = 4


def _interpolate(Q, deg: int, t):
    """The degree-deg B-spline through the points Q at the increasing parameters t
    (averaged knots, Piegl & Tiller 9.2.1), without interpolate's residual check: the
    fit measures its own error against tol (a 5,671-point branch of occ22470.igs missed
    interpolate's relative 1e-9 by 3e-9 and the pair raised, issue 16). Where the
    collocation is singular or misses the points by more than BRANCH_RESIDUAL_TOL of their
    spread it falls back to the polyline through
    the points (exact at them, degree-elevated to deg); the measured error says how good."""
    from ..curves.bspline import BSplineCurve
    from ..fitting.interpolation import collocate
    from ..knots.vectors import averaged
    Q, t = np.asarray(Q, float), np.asarray(t, float)
    deg = min(deg, len(Q) - 1)
    if deg >= 2:
        try:
            c = collocate(Q, deg, t, averaged(t, deg))
            lo, hi = Q.min(axis=0), Q.max(axis=0)
            with np.errstate(over="ignore", invalid="ignore"):
                if float(np.max(np.abs(c(t) - Q))) <= BRANCH_RESIDUAL_TOL * max(float(np.linalg.norm(hi - lo)), TINY):
                    return c
        except CagdError:
            pass
    up = np.concatenate([[True], np.diff(t) > 0])           # a knot at most twice (degree 1)
    Q, t = Q[up], t[up]
    if len(t) < 2:
        raise CagdError("parameters: the branch's points have one parameter")
    line = BSplineCurve(Q, 1, np.concatenate([t[:1], t, t[-1:]]))
    deg = min(deg, len(t) - 1)
    return line.elevate(deg - 1) if deg > 1 else line


def degenerate(S: System, x) -> bool:
    """x lies where a surface's parametrization collapses (a pole, an apex, a
    triangle's collapsed corner): a first partial vanishes there."""
    xw = S.wrap(np.asarray(x, float)[None])
    for k, g in enumerate(g for g in (S.A, S.B) if g is not None):
        d = S._partials(k, xw[:, 2 * k:2 * k + 2])[1][0]
        if np.linalg.norm(d, axis=1).min() <= COLLAPSED_SPEED_RTOL * g.size:
            return True
    return False


#: consecutive points closer than SAME_POINT_TOL * tol (+ SAME_POINT_REL of the size) are one 3-D point
SAME_POINT_TOL = 1e-3
SAME_POINT_REL = 1e-13
#: one 3-D point with parameters differing by more than JUMP_REL of the parameter span: a jump
#: along a collapsed edge (less: the same point twice)
JUMP_REL = 1e-7


def _same_and_jumps(S: System, xs, P, tol):
    """Per consecutive pair: (one 3-D point, and a parameter jump between them)."""
    gap = np.linalg.norm(np.diff(P, axis=0), axis=1)
    jump = (np.abs(S.wrapdiff(np.diff(xs, axis=0))) / S.span).max(axis=1) >= JUMP_REL
    return gap <= SAME_POINT_TOL * tol + SAME_POINT_REL * S.size, jump


def _runs(S: System, xs, P, tol):
    """The points without repeats (a point equal to its predecessor in 3-D and in
    parameters, as Newton-corrected midpoints can land on a pole twice) and the index
    ranges [a, b) between parameter jumps (consecutive points with one 3-D image but
    different parameters: a run along a collapsed edge). A run of one point between two
    jumps is dropped: its neighbours are the same 3-D point and the parameter curve
    joins them along the collapsed edge directly (two jumps in a row gave repeated
    fitting parameters: boxed_sphere.step Document[190] x [191], issue 16)."""
    for _ in range(len(P)):
        same, jump = _same_and_jumps(S, xs, P, tol)
        b = np.concatenate([[0], np.flatnonzero(same & jump) + 1, [len(P)]])
        lone = b[1:-2][np.diff(b)[1:-1] == 1]                  # interior runs of one point
        rep = np.flatnonzero(same & ~jump) + 1                  # the later of each repeat ...
        rep[rep == len(P) - 1] -= 1                             # ... but the branch keeps its end
        drop = np.union1d(rep[rep > 0], lone)
        if not drop.size or len(P) - drop.size < 2:
            return xs, P, list(zip(b[:-1], b[1:]))
        xs, P = np.delete(xs, drop, axis=0), np.delete(P, drop, axis=0)
    raise AssertionError("unreachable: every round drops a point")


def _piecewise(runs_t, runs_x):
    """One C0 cubic B-spline through the runs: each run interpolated (chord-length
    parameters given), consecutive runs joined by straight segments (along the
    collapsed edge) on the short parameter gaps between them."""
    from ..curves.bspline import BSplineCurve
    pieces = []
    for i, (t, x) in enumerate(zip(runs_t, runs_x)):
        if i:
            pieces.append(BSplineCurve(np.array([runs_x[i - 1][-1], x[0]]), 1, [runs_t[i - 1][-1]] * 2 + [t[0]] * 2))
        if len(t) >= 2:
            pieces.append(_interpolate(x, 3, t) if len(t) > 2 else
                          BSplineCurve(x, 1, [t[0], t[0], t[1], t[1]]))
    pieces = [c.elevate(3 - c.degree) if c.degree < 3 else c for c in pieces]
    ctrl, knots = [pieces[0].control_points], list(pieces[0].knots[:-1])
    for c in pieces[1:]:
        ctrl.append(c.control_points[1:])
        knots += list(c.knots[4:-1])
    knots.append(pieces[-1].knots[-1])
    return BSplineCurve(np.concatenate(ctrl), 3, np.array(knots))


def _thin(xs, P):
    """Drop points closer than a quarter of the next segment to the previous kept one
    (a run of one point, at a branch end after a jump, stays one point)."""
    if len(P) < 2:
        return xs, P
    keep = [0]
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    for i in range(1, len(P) - 1):
        d = np.linalg.norm(P[i] - P[keep[-1]])
        if d >= 0.25 * max(seg[i], TINY):
            keep.append(i)
    last = len(P) - 1
    if len(keep) > 1 and np.linalg.norm(P[last] - P[keep[-1]]) < 0.25 * np.linalg.norm(P[keep[-1]] - P[keep[-2]]):
        keep.pop()
    keep.append(last)
    return xs[keep], P[keep]


def fit(S: System, xs, P, closed, tol, rounds=10):
    """Cubic interpolation of the branch points and of their parameters (chord-length
    parameters); midpoints (corrected onto the branch) are inserted in segments whose
    samples are off either surface or whose parameter curves are off the 3-D curve
    by more than tol. Returns (curve, params_a, params_b, max_distance, params_max_distance).
    Bounded: at most ``rounds`` rounds, and it stops once STALL_ROUNDS rounds in a row have
    not cut the largest distance by STALL_FACTOR (a cubic's error falls like h^4: points
    that do not help are not on a smooth curve at this tol, e.g. surfaces touching
    nearly tangentially, where the rounds ran to 11,738 points in 127 s on occ22470.igs
    SOLID[2] x [3] without getting closer). The round with the smallest distance is
    returned (a round's corrected midpoints can make it worse: 3e-9 -> 8e-7 on a branch
    along a shared edge of trj3_s1-al-214.stp)."""
    history: List[float] = []
    best = None
    for r in range(rounds + 1):
        xs, P, runs = _runs(S, xs, P, tol)
        parts = [_thin(xs[a:b], P[a:b]) for a, b in runs]
        xs = np.concatenate([q[0] for q in parts])
        P = np.concatenate([q[1] for q in parts])
        if closed:
            P[-1] = P[0]
        starts = np.cumsum([0] + [len(q[1]) for q in parts])[1:-1]      # second point of each jump
        keep = np.setdiff1d(np.arange(len(P)), starts)                 # one 3-D point per jump
        chord = np.linalg.norm(np.diff(P[keep], axis=0), axis=1)
        t = np.concatenate([[0.0], np.cumsum(chord)])
        L = max(t[-1], TINY)
        t = t / L
        deg = min(3, len(keep) - 1)
        curve = _interpolate(P[keep], deg, t)
        if len(parts) == 1:
            pa = _interpolate(xs[:, :2], deg, t)
            pb = _interpolate(xs[:, 2:], deg, t) if S.n == 4 else None
            seg = np.arange(len(P) - 1)
        else:                 # the parameter curves run along the collapsed edge on [t - d, t + d]
            tx = np.empty(len(P))
            tx[keep] = t
            d = min(0.1 * tol / L, 0.25 * np.diff(t).min())
            base = tx[starts - 1].copy()
            tx[starts - 1] = np.where(starts - 1 == 0, base, base - d)
            tx[starts] = np.where(starts == len(P) - 1, base, base + d)
            bounds = np.concatenate([[0], starts, [len(P)]])
            rt = [tx[a:b] for a, b in zip(bounds[:-1], bounds[1:])]
            pa = _piecewise(rt, [xs[a:b, :2] for a, b in zip(bounds[:-1], bounds[1:])])
            pb = _piecewise(rt, [xs[a:b, 2:] for a, b in zip(bounds[:-1], bounds[1:])]) if S.n == 4 else None
            seg = keep[1:] - 1                          # original segment of each 3-D segment
        xs_all = xs
        d_s, d_p = _span_maxima(S, curve, pa, pb, t)
        worst = float(d_s.max()) if d_s.size else 0.0
        worst_p = float(d_p.max()) if d_p.size else 0.0
        history.append(max(worst, worst_p))
        if best is None or history[-1] < max(best[3], best[4]):
            best = (curve, pa, pb, worst, worst_p)
        stalled = len(history) > STALL_ROUNDS and all(
            history[-i] > history[-i - 1] / STALL_FACTOR for i in range(1, STALL_ROUNDS + 1))
        if (worst <= tol and worst_p <= tol) or r == rounds or stalled:
            return best
        err = np.maximum(d_s, d_p)
        sel = np.flatnonzero(err > 0.5 * tol)
        bad = seg[sel]
        xs = xs_all
        # a cubic's error falls like h^4: cut the span into m = (err / (tol / 2))^(1/4)
        m = np.clip(np.ceil((err[sel] / (0.25 * tol)) ** 0.25), 2, 8).astype(int)
        at = np.repeat(bad, m - 1)
        frac = np.concatenate([np.arange(1, k) / k for k in m])[:, None]
        d = xs[at + 1] - xs[at]
        guess = xs[at] + frac * d
        y, ok = newton(S, guess, d, np.einsum("nk,nk->n", d, guess), residual_tol(tol, S.size))
        y, at = y[ok], at[ok]
        if len(y) == 0:
            return best
        xs = np.insert(xs, at + 1, y, axis=0)
        P = S.eval(xs)[2]


def boundary_line(S: System, xs: np.ndarray):
    """(k, d, val) when every row of the branch xs lies within AT_END_RTOL of the boundary
    line "parameter d of surface k = val" (not a seam), else None."""
    for k in range(S.n // 2):
        G = (S.A, S.B)[k]
        if G is None:
            break
        for d in range(2):
            if G.closed[d]:
                continue
            near = AT_END_RTOL * (G.hi[d] - G.lo[d])
            for val in (G.lo[d], G.hi[d]):
                if np.all(np.abs(xs[:, 2 * k + d] - val) <= near):
                    return k, d, float(val)
    return None


def _settled_ends(S: System, xs: np.ndarray, k: int) -> np.ndarray:
    """The rows' parameters on surface k, an end row on a collapsed edge of it (a pole,
    where the parameter along the edge is arbitrary: a projection lands anywhere on it)
    given its neighbour's value in that direction, so the parameter curve does not jump."""
    x = xs[:, 2 * k:2 * k + 2].copy()
    G = (S.A, S.B)[k]
    if G is None or len(x) < 2:
        return x
    for end, neighbour in ((0, 1), (-1, -2)):
        partials = S._partials(k, S.wrap(xs[end][None])[:, 2 * k:2 * k + 2])[1][0]     # (2, dim)
        speed = np.linalg.norm(partials, axis=1)
        j = int(np.argmin(speed))
        if speed[j] <= COLLAPSED_SPEED_RTOL * G.size:
            x[end, j] = x[neighbour, j]
    return x


def edge_fit(S: System, xs: np.ndarray, tol: float):
    """A branch along a boundary of one surface (the rows of boundary pieces lying on
    the other surface, :func:`cagd.queries.intersect_surfaces._edge_rows`: every row
    within AT_END_RTOL of the same boundary line (:func:`boundary_line`; such branches
    are not joined to others), monotone along it) as the exact boundary: the 3-D curve is that surface's
    iso-curve over the rows' range (reparametrised linearly onto [0, 1]), its parameter
    curve the straight boundary line, the other surface's parameter curve the cubic
    through the rows' projections. Two faces sharing an edge, G1 or G2 across it (where
    the surfaces only touch and midpoints cannot be corrected onto F = 0), get the edge
    itself, its distance from the other surface measured as for any branch (two halves
    of a bicubic: 237 fitted poles, 7e-9 off, before). Where that parameter curve's image
    is more than ``tol`` off the edge, the spans' midpoints are projected onto the other
    surface (Gauss-Newton from the curve there; not where it is periodic) and added to
    its rows, EDGE_ROUNDS times at most (the projections of an edge crossing the other
    surface's knot lines have kinks the cubic rounds off: 5e-9 at tol 1e-9 between 64
    rows a span on trj3_s1-al-214.stp faces 4 x 6); the best round is returned. Returns
    what :func:`fit` returns, or None when the rows are not on one boundary line."""
    from ..curves.bspline import BSplineCurve
    from ..surfaces.bspline import BSplineSurface
    found = boundary_line(S, xs)
    if found is None or len(xs) < 2:
        return None
    k, d, val = found
    G = (S.A, S.B)[k]
    if G is None or not isinstance(G.nurbs, BSplineSurface):
        return None
    s = xs[:, 2 * k + 1 - d]
    s0, s1 = float(s[0]), float(s[-1])
    step = np.diff(s) * np.sign(s1 - s0)
    if not s0 != s1 or not np.all(step > 0):
        return None                     # not one monotone run along the boundary
    iso = G.nurbs.isocurve("v" if d == 0 else "u", val)
    a, b = min(s0, s1), max(s0, s1)
    piece = iso.clamped() if (a, b) == tuple(iso.domain) else iso.segment(a, b)     # (a periodic edge: clamped)
    piece = piece.reversed() if s0 > s1 else piece
    knots = (piece.knots - a) / (b - a)
    curve = BSplineCurve(piece.control_points, piece.degree, knots, piece.weights)
    t = (s - s0) / (s1 - s0)
    line = np.zeros((2, 2))
    line[:, d], line[:, 1 - d] = val, (s0, s1)
    on_g = BSplineCurve(line, 1)
    if S.n != 4:
        d_s, d_p = _span_maxima(S, curve, on_g, None, t)
        return curve, on_g, None, float(d_s.max()) if d_s.size else 0.0, float(d_p.max()) if d_p.size else 0.0
    uv = _settled_ends(S, xs, 1 - k)
    H = (S.A, S.B)[1 - k]
    assert H is not None                        # (S.n == 4: two surfaces)
    periodic = bool(S.per[2 * (1 - k):2 * (1 - k) + 2].any())     # (its rows may wrap: not refined)
    best = None
    for _ in range(EDGE_ROUNDS + 1):
        on_h = _interpolate(uv, 3, t)
        pa, pb = (on_g, on_h) if k == 0 else (on_h, on_g)
        d_s, d_p = _span_maxima(S, curve, pa, pb, t)
        worst, worst_p = float(d_s.max()) if d_s.size else 0.0, float(d_p.max()) if d_p.size else 0.0
        if best is None or max(worst, worst_p) < max(best[3], best[4]):
            best = (curve, pa, pb, worst, worst_p)
        bad = np.flatnonzero(d_p > tol)
        if not bad.size or worst_p <= tol or periodic:
            break
        tm = 0.5 * (t[bad] + t[bad + 1])
        got = _foot(S, 1 - k, curve(tm), np.clip(on_h(tm), H.lo, H.hi))[2]
        at = np.searchsorted(t, tm)
        t, uv = np.insert(t, at, tm), np.insert(uv, at, got, axis=0)
    return best


def _span_maxima(S: System, curve, pa, pb, t, n: int = 8):
    """Largest distance in each span [t_i, t_i+1] of both error functions of
    :func:`_distances`: n + 1 samples per span, then the vertex of the parabola through
    the largest sample and its neighbours (successive parabolic interpolation, Brent
    1973, ch. 5), evaluated too: the samples alone under-report a smooth bump by up to
    (pi / 2n)^2 / 2, 2% at n = 8 (6% measured with 7 interior samples)."""
    if len(t) < 2:
        e_s, e_p = _distances(S, curve, pa, pb, t)
        return e_s, e_p
    q = np.arange(n + 1) / n
    h = np.diff(t)
    ts = t[:-1, None] + q[None] * h[:, None]                         # (K, n + 1)
    vals = [v.reshape(ts.shape) for v in _distances(S, curve, pa, pb, ts.ravel())]
    tv = []
    for f in vals:
        i = np.clip(np.argmax(f, axis=1), 1, n - 1)
        r = np.arange(len(f))
        f0, f1, f2 = f[r, i - 1], f[r, i], f[r, i + 1]
        den = f0 - 2 * f1 + f2
        off = np.where(den < 0, 0.5 * (f0 - f2) / np.where(den < 0, den, -1.0), 0.0)
        tv.append(t[:-1] + (i + np.clip(off, -1.0, 1.0)) / n * h)
    # both vertices in one evaluation (the rows are independent: the same values)
    fv = _distances(S, curve, pa, pb, np.concatenate(tv))
    K = len(h)
    return np.maximum(vals[0].max(axis=1), fv[0][:K]), np.maximum(vals[1].max(axis=1), fv[1][K:])


def _foot(S: System, k: int, C: np.ndarray, uv: np.ndarray, iters: int = 6
          ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distance of the points C from surface k by Gauss-Newton on the foot point
    (J^T J) du = J^T (C - S(uv)) from uv, a start within the fit's error of the foot, so
    that it converges at the rate distance x curvature; never below the true distance
    (the least distance from C of the surface points evaluated). A row stops once its
    step changes its parameters by at most FOOT_STEP_RTOL of the width.
    Returns (distance from the foot, distance from the start point S(uv), the feet's
    parameters)."""
    g = (S.A, S.B)[k]
    assert g is not None                        # k = 1 only with a second surface
    uv = np.array(uv, dtype=float)
    width = g.hi - g.lo
    act = np.arange(len(C))
    start = best = np.zeros(len(C))
    for it in range(iters):
        p, d = S._partials(k, uv[act])
        r = C[act] - p
        dist = np.sqrt(np.einsum("nd,nd->n", r, r))
        if it == 0:
            start, best = dist, dist.copy()
        else:
            best[act] = np.minimum(best[act], dist)
        d0, d1 = d[:, 0], d[:, 1]
        a, b, c = np.einsum("nd,nd->n", d0, d0), np.einsum("nd,nd->n", d0, d1), np.einsum("nd,nd->n", d1, d1)
        shift = GN_SHIFT_RTOL * (a + c) + TINY
        a, c = a + shift, c + shift
        g0, g1 = np.einsum("nd,nd->n", d0, r), np.einsum("nd,nd->n", d1, r)
        det = a * c - b * b                     # J^T J + shift: positive definite
        step = np.stack([(c * g0 - b * g1) / det, (a * g1 - b * g0) / det], axis=1)
        new = g.clamp(uv[act] + step)
        done = np.all(np.abs(new - uv[act]) <= FOOT_STEP_RTOL * width, axis=1)
        uv[act] = new
        act = act[~done]
        if not act.size:
            return best, start, uv
    best[act] = np.minimum(best[act], np.linalg.norm(C[act] - S._partials(k, uv[act])[0], axis=1))
    return best, start, uv


def _distances(S: System, curve, pa, pb, t):
    """Distance of curve(t) from both surfaces (Gauss-Newton foot points seeded by the
    parameter curves) and of the parameter curves' images from curve(t)."""
    C = curve(t)
    ua = S.wrap(np.concatenate([pa(t), np.zeros((len(t), S.n - 2))], axis=1))[:, :2]
    ua = np.clip(ua, S.A.lo, S.A.hi)
    dA, dpa, _ = _foot(S, 0, C, ua)
    if S.B is None:
        o, nrm = S.pl
        return np.maximum(dA, np.abs((C - o) @ nrm)), dpa
    ub = S.wrap(np.concatenate([np.zeros((len(t), 2)), pb(t)], axis=1))[:, 2:]
    ub = np.clip(ub, S.B.lo, S.B.hi)
    dB, dpb, _ = _foot(S, 1, C, ub)
    return np.maximum(dA, dB), np.maximum(dpa, dpb)
