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
   directions (revolved surfaces, seams) are marched across.
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

Parameter curves of closed (periodic or seam) directions live in the covering space:
reduce them modulo the period to evaluate the surface.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Tuple

import numpy as np

from ..errors import CagdError
from . import _subdivision as sd
from ._marching import Marcher, segments_distance
from ._surface_system import System, newton, unit

__all__ = ["IntersectionCurve", "surface_plane", "surface_surface"]

_SEED_FRACTION = 1.0 / 16      # leaves of the seed subdivision: at most this fraction of the model size
_REL_FLAT = 2e-2


@dataclass
class IntersectionCurve:
    """One branch of a surface–surface or surface–plane intersection.

    curve: 3-D BSplineCurve through the marched points (chord-length parameters);
    params_a, params_b: 2-D BSplineCurves (same parameter) on a and b (params_b is None
    for a plane); closed: the branch is a loop; tolerance: the largest distance of the
    curve from both surfaces measured at dense samples (Newton projection);
    params_tolerance: the largest |A(params_a(t)) - curve(t)|, |B(params_b(t)) - curve(t)|
    at the same samples; converged: the march and the fit met their bounds (both
    tolerances <= tol); ends: how each end stopped ('boundary',
    'singular', 'closed', 'stalled', 'limit')."""
    curve: object
    params_a: object
    params_b: object
    closed: bool
    tolerance: float
    params_tolerance: float = 0.0
    converged: bool = True
    ends: Tuple[str, str] = ("closed", "closed")


# --- seeds -------------------------------------------------------------------------------
def _seeds_pair(A: sd.Geometry, B: sd.Geometry, tol: float, max_pairs: int):
    Ka, Kb = len(A.pieces.ctrl), len(B.pieces.ctrl)
    i, j = np.repeat(np.arange(Ka), Kb), np.tile(np.arange(Kb), Ka)
    pa, pb = A.pieces.take(i), B.pieces.take(j)
    leaf = _SEED_FRACTION * max(A.size, B.size)
    seeds, complete = [], True
    for _ in range(40):
        if len(pa.ctrl) == 0:
            break
        lo_a, hi_a = sd.boxes(pa.ctrl)
        lo_b, hi_b = sd.boxes(pb.ctrl)
        live = sd.box_gap(lo_a, hi_a, lo_b, hi_b) <= tol
        dev_a, ext_a = sd.flatness(pa.ctrl)
        dev_b, ext_b = sd.flatness(pb.ctrl)
        da = np.linalg.norm(hi_a - lo_a, axis=1)
        db = np.linalg.norm(hi_b - lo_b, axis=1)
        done = live & (dev_a <= _REL_FLAT * ext_a + tol) & (dev_b <= _REL_FLAT * ext_b + tol) \
            & (da <= leaf) & (db <= leaf)
        go = np.flatnonzero(live & ~done)
        if go.size * 16 > max_pairs:
            complete = False
            done = live
            go = go[:0]
        if done.any():
            seeds.append(np.concatenate([0.5 * (pa.lo[done] + pa.hi[done]), 0.5 * (pb.lo[done] + pb.hi[done])], 1))
        if go.size == 0:
            break
        pa, pb = pa.take(go), pb.take(go)
        pa, pb, _ = sd.split_pairs(pa, pb, da[go] >= 0.5 * db[go], db[go] >= 0.5 * da[go])
    return (np.concatenate(seeds) if seeds else np.empty((0, 4))), complete


def _seeds_plane(A: sd.Geometry, pl, tol: float, max_pairs: int):
    o, nrm = pl
    p = A.pieces
    leaf = _SEED_FRACTION * A.size
    seeds, complete = [], True
    for _ in range(40):
        if len(p.ctrl) == 0:
            break
        P = sd.project(p.ctrl).reshape(len(p.ctrl), -1, 3)
        d = (P - o) @ nrm
        live = (d.min(axis=1) <= tol) & (d.max(axis=1) >= -tol)
        dev, ext = sd.flatness(p.ctrl)
        diag = np.linalg.norm(P.max(axis=1) - P.min(axis=1), axis=1)
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
    return (np.concatenate(seeds) if seeds else np.empty((0, 2))), complete


# --- driver ------------------------------------------------------------------------------
def _trace(S: System, seeds: np.ndarray, tol: float):
    M = Marcher(S, tol)
    x, ok = newton(S, seeds, None, None, M.ftol, iters=30)
    x = x[ok]
    P = S.eval(x)[2] if len(x) else np.empty((0, 3))
    alive = np.ones(len(x), bool)
    branches = []            # (xs (K, n), ends (start, end), other-side starts)
    isolated = []
    problems = []
    queue: List[np.ndarray] = []
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
        fw, end_f, other_f = M.march(start, 1.0)
        if end_f == "closed":
            xs, ends = np.array(fw), ("closed", "closed")
        else:
            bw, end_b, other_b = M.march(start, -1.0)
            xs = np.array(bw[::-1] + fw[1:])
            ends = (end_b, end_f)
            if other_b is not None:
                queue.append(other_b)
        if other_f is not None:
            queue.append(other_f)
        if len(xs) < 2:
            F, J, Pp, na, nb, _ = S.eval(xs[:1])
            isolated.append(xs[0])
            alive &= np.linalg.norm(P - Pp[0], axis=1) > 1e-6 * S.size
            continue
        for e in ends:
            if e in ("stalled", "limit"):
                problems.append(e)
        Pb = S.eval(xs)[2]
        branches.append((xs, list(ends), Pb))
        if alive.any():
            idx = np.flatnonzero(alive)
            alive[idx[_absorbed(P[idx], [branches[-1]], M.ftol)]] = False
    return branches, isolated, problems, ok


def _absorbed(Q, branches, ftol):
    hit = np.zeros(len(Q), bool)
    for _, _, Pb in branches:
        d, L = segments_distance(Q, Pb)
        hit |= d <= 0.1 * L + 10 * ftol
    return hit


def _join(S: System, branches, tol):
    """Join branch ends meeting at a crossing with opposite tangents."""
    items = [[b[0], list(b[1]), b[2]] for b in branches]
    gap = max(10 * tol, 1e-9 * S.size)
    changed = True
    while changed:
        changed = False
        ends = []
        for bi, (xs, e, P) in enumerate(items):
            if e[0] == "singular" and len(P) >= 2:
                ends.append((bi, 0, P[0], unit(P[1] - P[0])))
            if e[1] == "singular" and len(P) >= 2:
                ends.append((bi, 1, P[-1], unit(P[-2] - P[-1])))
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
        if a[0] == b[0]:                                   # one branch closes through the crossing
            xs, e, P = items[a[0]]
            xs = xs.copy()
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
            xs = np.concatenate([xa, xb[1:]])
            P = np.concatenate([Pa, Pb[1:]])
            items = [it for k, it in enumerate(items) if k not in (ia, ib)] + [[xs, [ea[0], eb[1]], P]]
        changed = True
    return items


def _thin(xs, P):
    """Drop points closer than a quarter of the next segment to the previous kept one."""
    keep = [0]
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    for i in range(1, len(P) - 1):
        d = np.linalg.norm(P[i] - P[keep[-1]])
        if d >= 0.25 * max(seg[i], 1e-300):
            keep.append(i)
    last = len(P) - 1
    if len(keep) > 1 and np.linalg.norm(P[last] - P[keep[-1]]) < 0.25 * np.linalg.norm(P[keep[-1]] - P[keep[-2]]):
        keep.pop()
    keep.append(last)
    return xs[keep], P[keep]


def _fit(S: System, xs, P, closed, tol, rounds=10):
    """Cubic interpolation of the branch points and of their parameters (chord-length
    parameters); midpoints (corrected onto the branch) are inserted in segments whose
    samples are off either surface or whose parameter curves are off the 3-D curve
    by more than tol. Returns (curve, params_a, params_b, tolerance, params_tolerance)."""
    from ..fitting.interpolation import interpolate
    for r in range(rounds + 1):
        xs, P = _thin(xs, P)
        if closed:
            P[-1] = P[0]
        chord = np.linalg.norm(np.diff(P, axis=0), axis=1)
        t = np.concatenate([[0.0], np.cumsum(chord)])
        t = t / max(t[-1], 1e-300)
        deg = min(3, len(P) - 1)
        curve = interpolate(P, deg, t)
        pa = interpolate(xs[:, :2], deg, t)
        pb = interpolate(xs[:, 2:], deg, t) if S.n == 4 else None
        q = (np.arange(1, 8) / 8.0)
        ts = (t[:-1, None] + q[None] * np.diff(t)[:, None])
        d_s, d_p = _distances(S, curve, pa, pb, ts.ravel())
        d_s, d_p = d_s.reshape(ts.shape).max(axis=1), d_p.reshape(ts.shape).max(axis=1)
        e_s, e_p = _distances(S, curve, pa, pb, t)
        worst = max(float(d_s.max()) if d_s.size else 0.0, float(e_s.max()))
        worst_p = max(float(d_p.max()) if d_p.size else 0.0, float(e_p.max()))
        if (worst <= tol and worst_p <= tol) or r == rounds:
            return curve, pa, pb, worst, worst_p
        bad = np.flatnonzero(np.maximum(d_s, d_p) > 0.5 * tol)
        mid = 0.5 * (xs[bad] + xs[bad + 1])
        d = xs[bad + 1] - xs[bad]
        y, ok = newton(S, mid, d, np.einsum("nk,nk->n", d, mid), max(1e-3 * tol, 1e-14 * S.size))
        y, bad = y[ok], bad[ok]
        if len(y) == 0:
            return curve, pa, pb, worst, worst_p
        xs = np.insert(xs, bad + 1, y, axis=0)
        P = S.eval(xs)[2]


def _distances(S: System, curve, pa, pb, t):
    """Distance of curve(t) from both surfaces (Newton projection seeded by the parameter
    curves) and of the parameter curves' images from curve(t)."""
    C = curve(t)
    ua = S.wrap(np.concatenate([pa(t), np.zeros((len(t), S.n - 2))], axis=1))[:, :2]
    ua = np.clip(ua, S.A.lo, S.A.hi)
    _, dA = sd.project_onto(S.A, C, ua)
    dpa = np.linalg.norm(S._partials(0, ua)[0] - C, axis=1)
    if S.B is None:
        o, nrm = S.pl
        return np.maximum(dA, np.abs((C - o) @ nrm)), dpa
    ub = S.wrap(np.concatenate([np.zeros((len(t), 2)), pb(t)], axis=1))[:, 2:]
    ub = np.clip(ub, S.B.lo, S.B.hi)
    _, dB = sd.project_onto(S.B, C, ub)
    dpb = np.linalg.norm(S._partials(1, ub)[0] - C, axis=1)
    return np.maximum(dA, dB), np.maximum(dpa, dpb)


def _solve(S: System, seeds, complete, tol, angle_tol):
    from .intersect import IntersectionPoint, IntersectionResult
    branches, isolated, problems, _ = _trace(S, seeds, tol)
    items = _join(S, branches, tol)
    curves = []
    messages = []
    for xs, ends, P in items:
        closed = ends[0] == "closed"
        curve, pa, pb, worst, worst_p = _fit(S, xs, P, closed, tol)
        ok = max(worst, worst_p) <= tol and not any(e in ("stalled", "limit") for e in ends)
        curves.append(IntersectionCurve(curve, pa, pb, closed, worst, worst_p, ok, tuple(ends)))
        if max(worst, worst_p) > tol:
            messages.append(f"a branch was fitted within {max(worst, worst_p):.2e} > tol")
    points = []
    for x in isolated:
        F, J, P, na, nb, _ = S.eval(x[None])
        sine = float(np.linalg.norm(np.cross(na[0], nb[0])))
        pb_ = S.B.user_params(S.wrap(x)[None, 2:])[0] if S.B is not None else None
        points.append(IntersectionPoint(S.A.user_params(S.wrap(x)[None, :2])[0], pb_, P[0],
                                        sine <= max(angle_tol, 1e-6), float(np.linalg.norm(F))))
    if problems:
        messages.append(f"marching did not converge at {len(problems)} branch end(s) ({', '.join(problems)})")
    if not complete:
        messages.append("seed subdivision hit max_pairs")
    converged = not messages
    return IntersectionResult(points, [], curves, tol, converged, "; ".join(messages))


def surface_surface(a, b, tol: float, angle_tol: float = 1e-6, max_pairs: int = 20000):
    """Intersection curves of two surfaces (see the module docstring); returns an
    :class:`IntersectionResult` whose ``curves`` are :class:`IntersectionCurve` branches."""
    A, B = sd.Geometry(a, "a"), sd.Geometry(b, "b")
    if A.k != 2 or B.k != 2:
        raise CagdError("a, b: surface_surface needs two surfaces")
    if A.dim != 3 or B.dim != 3:
        raise CagdError(f"a, b: surface intersection needs 3-D surfaces, got {A.dim}-D and {B.dim}-D")
    seeds, complete = _seeds_pair(A, B, tol, max_pairs)
    return _solve(System(A, B), seeds, complete, tol, angle_tol)


def surface_plane(a, pl, tol: float, angle_tol: float = 1e-6, max_pairs: int = 20000):
    """Section of a surface by a plane (``pl`` from :func:`cagd.queries.plane`): the
    level set n.(A(u, v) - o) = 0 marched like a surface–surface intersection."""
    A = sd.Geometry(a, "a")
    if A.k != 2:
        raise CagdError("a: surface_plane needs a surface")
    if A.dim != 3:
        raise CagdError(f"a: a plane lives in 3-D, the surface is {A.dim}-D")
    o, nrm = np.asarray(pl.origin, float), np.asarray(pl.normal, float)
    seeds, complete = _seeds_plane(A, (o, nrm), tol, max_pairs)
    return _solve(System(A, None, (o, nrm)), seeds, complete, tol, angle_tol)
