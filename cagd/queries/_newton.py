"""The Newton solvers of the queries, in one module (issue 16, layout), vectorized over
rows of starts; each keeps its parameters in their domain the same way (clamped to a
box, wrapped in periodic directions; a coordinate at a bound whose gradient points out
of the box is held: :func:`held_at_bounds`, projected Newton) and, where it minimises,
backtracks by step halving until the objective does not increase (:func:`backtrack`).

- :func:`projected_newton`: closest points, min |S(x) - X|^2 over a box per row
  (Piegl & Tiller 6.1, point inversion; Newton where the Hessian is positive definite,
  else Gauss-Newton), used by :mod:`cagd.queries.closest`.
- :func:`refine`: min |A(x) - B(y)|^2 / 2 of two objects (Gauss-Newton to a transversal
  root, or full Newton to a tangential contact), used by the intersections and
  :func:`cagd.queries.min_distance`; :func:`project_onto` projects points with it.
- :func:`newton`: roots of the surface intersection system F(x) = 0 (minimum-norm step,
  or with one constraint row per point: the marching's corrector; Patrikalakis &
  Maekawa, "Shape Interrogation for CAD/CAM", 5.8).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Optional, Tuple, Union

import numpy as np

from .. import _periodic as periodic
from .._periodic import clamped, step_across
from ._numerics import LEVENBERG_RTOL, SLACK_RTOL, TINY, ULP_RTOL

QUADRATIC_CONTRACTION = 1e-2  # a step below this share of the previous one contracts quadratically ...
EXTRAPOLATED_SHARE = 1e-3     # ... and ends the iteration when its successor would be this share of tol
FLAT_RTOL = 1e-14            # near a minimum g is flat to rounding: a last step may raise it this much
EIGEN_FLOOR_RTOL = 1e-13     # refine: eigenvalues of the Hessian floored at this share of the largest
STALL_STEP_RTOL = 1e-10      # refine: a step this short (share of the width) that cannot decrease f ends it
NEWTON_FTOL = 1e-12          # newton: the default residual |F|
STEP_RTOL = 1e-14            # newton: a step below this share of the width is converged
STAGNANT_SHARE = 0.5         # newton with a constraint row: |F| <= ftol and a step above this share of the
                             # previous one: the steps are rounding of an ill-conditioned J, converged

if TYPE_CHECKING:
    from ._subdivision import Geometry
    from ._surface_system import System

BOUND_SLACK = 1e-15     # refine: a coordinate within this share of its range of a bound is at it

_DECREASE = 1e-15     # relative slack when comparing squared distances (rounding)

NEWTON_ITERATIONS = 12
BACKTRACK_TRIES = 30      # refine: step halvings at most (t = 1, 1/2, ...)
BACKTRACK_BLOCK = 8       # refine: at most this many halvings evaluated together


def held_at_bounds(x: np.ndarray, grad: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                   periodic: np.ndarray) -> np.ndarray:
    """The coordinates a projected Newton step holds: at a bound of the box [lo, hi] with
    the gradient of the objective pointing out of it (a minimiser there stays there);
    never in ``periodic`` directions. Any layout that broadcasts."""
    return ~periodic & (((x <= lo) & (grad > 0)) | ((x >= hi) & (grad < 0)))


def backtrack(rows: np.ndarray, trial: Callable, accept: Callable, tries: int, t: float = 1.0):
    """Step halving for the rows still to place: ``trial(rows, t)`` -> (x, f) at t times
    their steps, ``accept(rows, f)`` -> mask; yields (rows, accepted mask, x, f) per try,
    t = t, t/2, ... (``tries`` of them), the rows not accepted going on to the next."""
    for _ in range(tries):
        if not rows.size:
            return
        x, f = trial(rows, t)
        good = accept(rows, f)
        yield rows, good, x, f
        rows = rows[~good]
        t *= 0.5


def _system(R: np.ndarray, Jc: np.ndarray, Hc: np.ndarray):
    """From component-first arrays R = S - X (dim, n), J (k, dim, n), d2S (k, k, dim, n):
    grad g = 2 J^T r (k, n) and the upper triangles of Hess g = 2 (J^T J + r.d2S) and of
    the Gauss-Newton matrix 2 J^T J, as lists [h00] or [h00, h01, h11] of (n,) arrays."""
    k = Jc.shape[0]
    grad = 2.0 * np.stack([(R * Jc[a]).sum(0) for a in range(k)])
    pairs = [(0, 0)] if k == 1 else [(0, 0), (0, 1), (1, 1)]
    Hg = [2.0 * (Jc[a] * Jc[b]).sum(0) for a, b in pairs]
    Hf = [hg + 2.0 * (R * Hc[a, b]).sum(0) for hg, (a, b) in zip(Hg, pairs)]
    return grad, Hf, Hg


def _solve(Hf, Hg, grad: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """Newton step -H^-1 grad (k, n) on the free coordinates (fixed (k, n)); H the full
    Hessian where it is positive definite, else the Gauss-Newton matrix 2 J^T J (+ a
    tiny Levenberg shift). H given by its upper triangle (see :func:`_system`)."""
    g = np.where(fixed, 0.0, grad)
    if len(Hf) == 1:
        h = Hf[0]
        hg = Hg[0] * (1.0 + LEVENBERG_RTOL) + TINY
        h = np.where(h > 0, h, hg)
        return (-g[0] / h)[None]
    steps = []
    f0, f1 = fixed[0], fixed[1]
    either = f0 | f1
    for H, shift in ((Hf, 0.0), (Hg, LEVENBERG_RTOL)):
        a, b, c = H
        tr = shift * (a + c)
        a, c = a + tr + TINY, c + tr + TINY
        b = np.where(either, 0.0, b)
        a, c = np.where(f0, 1.0, a), np.where(f1, 1.0, c)
        det = a * c - b * b
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.stack([(b * g[1] - c * g[0]) / det, (b * g[0] - a * g[1]) / det])
        pd = (a > 0) & (det > 0) & np.isfinite(step).all(0)
        steps.append((step, pd))
    (newton, descent), (shifted, _) = steps
    out = np.where(descent, newton, shifted)    # the shifted (Gauss-Newton) step where the Newton one is not a descent
    return np.where(np.isfinite(out), out, 0.0)


def _place(x: np.ndarray, lo: np.ndarray, hi: np.ndarray, wrap: np.ndarray, a: np.ndarray,
           b: np.ndarray) -> np.ndarray:
    """Clamp to the box, or wrap into the domain [a, b) in periodic directions
    (component-first (k, n) arrays; wrap, a, b of shape (k, 1))."""
    out = np.minimum(np.maximum(x, lo), hi)
    if wrap.any():
        out = np.where(wrap, periodic.wrap(x, a, b - a), out)
    return out


def projected_newton(proj, X: np.ndarray, pid: np.ndarray, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                     wrap: np.ndarray, max_iterations: int, tol, param_tol=None, piece=None):
    """Minimise |S(x) - X[pid]|^2 for every row of x0 inside its box [lo, hi] (wrapped
    instead of clamped along ``wrap``): Newton with an active set at the box faces and
    step halving (at most 10 halvings) so that g never increases. A step d ends the
    iteration without a further evaluation when it moves the foot by |J d| <= ``tol``
    (a distance) or, with ``param_tol``, when every |d_i| <= param_tol * range_i; so does
    a step d_k whose successor, at the quadratic rate of the last two full steps, would
    be below a thousandth of that (|d_k|^3 / |d_k-1|^2 in the same measure). Either
    tolerance may be None (not used), not both.
    Returns (x, g, converged, (S, J, H2, xe)): S, J, H2 at xe, the last point where
    they were evaluated (x itself or x before its last step);
    converged means the last step met one of those tests. ``piece``: the flat Bezier
    piece of every row when each box lies in one piece (evaluated there, one-sided at
    its ends, without locating x: the search was a quarter of the time on 1e4-piece
    curves); None: located."""
    def ev(x, order, rows):
        if piece is None:
            return proj.value(x) if order == 0 else proj.evaluate(x, order)
        return proj.evaluate_in(x, order, piece[rows])

    xc = np.array(np.asarray(x0, dtype=np.float64).T)                  # (k, n)
    loc, hic = np.ascontiguousarray(np.asarray(lo, dtype=np.float64).T), \
        np.ascontiguousarray(np.asarray(hi, dtype=np.float64).T)
    Xc = np.ascontiguousarray(X.T)
    k, n = xc.shape
    a, b = proj.domain[:, 0][:, None], proj.domain[:, 1][:, None]
    wrapc = np.asarray(wrap, dtype=bool)[:, None]
    conv = np.zeros(n, dtype=bool)
    S, J, H2 = ev(xc.T, 2, slice(None))
    xe = xc.copy()                                                     # where S, J, H2 hold
    Sc, Jc, Hc = np.array(S.T), np.array(J.T), np.array(H2.T)          # the values at x, kept
    P = Xc if len(pid) == Xc.shape[1] and np.array_equal(pid, np.arange(len(pid))) else Xc[:, pid]
    R = Sc - P
    g = (R * R).sum(0)
    floor = (ULP_RTOL * proj.size) ** 2
    act = np.arange(n)
    prev = np.zeros(n)                  # size of the previous step, relative to the range (0: none)
    prev_move = np.zeros(n)             # how far it moved the foot
    width = proj.width[:, None]
    Ja, Ha, Ra, Pa = Jc, Hc, R, P
    for _ in range(max_iterations):
        if not act.size:
            break
        xa, la, ha = xc[:, act], loc[:, act], hic[:, act]
        grad, Hf, Hg = _system(Ra, Ja, Ha)
        fixed = held_at_bounds(xa, grad, la, ha, wrapc)
        step = _solve(Hf, Hg, grad, fixed)
        xn = _place(xa + step, la, ha, wrapc, a, b)
        taken = np.where(wrapc, step, xn - xa)
        # a small step ends the iteration before evaluating: x (and S, J, H2 there) is
        # kept, within the tolerance of the Newton point; so does one whose successor, at
        # the quadratic rate seen over the last two steps (|d_k+1| ~ |d_k|^3 / |d_k-1|^2),
        # is a thousandth of the tolerance (only when the steps really contract
        # quadratically: a slow linear rate would make the extrapolation stop far from
        # the minimum)
        rel = (np.abs(taken) / width).max(0)
        move = _foot_move(Ja, taken)
        step_move = _foot_move(Ja, step)
        small = np.zeros(len(act), dtype=bool)
        if tol is not None:
            pm = prev_move[act]
            small |= (move <= tol) | ((move <= QUADRATIC_CONTRACTION * pm)
                                      & (move ** 3 <= EXTRAPOLATED_SHARE * tol * pm ** 2))
        if param_tol is not None:
            pr = prev[act]
            small |= (np.abs(taken) <= param_tol * width).all(0) | \
                ((rel <= QUADRATIC_CONTRACTION * pr) & (rel ** 3 <= EXTRAPOLATED_SHARE * param_tol * pr ** 2))
        prev[act], prev_move[act] = rel, move
        if small.any():
            # the last (tiny) step is taken when it does not increase g, with a point
            # evaluation only; S, J, H2 stay those at the previous point (returned as xe)
            conv[act[small]] = True
            i = np.flatnonzero(small)
            gs = ((ev(xn[:, i].T, 0, act[i]).T - Pa[:, i]) ** 2).sum(0)
            # near the minimum g is flat to rounding (a foot error d moves it by ~d^2):
            # compare with a few ulps of slack, or the last Newton correction is lost
            better = gs <= g[act[i]] * (1.0 + FLAT_RTOL) + floor
            j = act[i[better]]
            xc[:, j], g[j] = xn[:, i[better]], gs[better]
            go = ~small
            act, xa, la, ha, xn, step, grad, Pa = act[go], xa[:, go], la[:, go], ha[:, go], xn[:, go], \
                step[:, go], grad[:, go], Pa[:, go]
            step_move = step_move[go]
            if not act.size:
                break
        Sn, Jn, H2n = ev(xn.T, 2, act)
        Sn, Jn, H2n = Sn.T, Jn.T, H2n.T
        rn = Sn - Pa
        gn = (rn * rn).sum(0)
        ga = g[act]
        # below the rounding level of g the comparison is noise: trust the Newton step
        tiny = -0.5 * (grad * step).sum(0) <= SLACK_RTOL * ga + floor
        ok = (gn <= ga * (1.0 + _DECREASE) + floor) | tiny
        bad = np.flatnonzero(~ok)
        if bad.size:
            halved = np.zeros(len(ok), dtype=bool)
            halved[bad] = True

            def trial(rows, t):
                xb = _place(xa[:, rows] + t * step[:, rows], la[:, rows], ha[:, rows], wrapc, a, b)
                return xb, ((ev(xb.T, 0, act[rows]).T - Pa[:, rows]) ** 2).sum(0)

            def accept(rows, gb):
                return gb <= ga[rows] * (1.0 + _DECREASE) + floor

            for rows, good, xb, _ in backtrack(bad, trial, accept, 10, 0.5):
                xn[:, rows[good]], ok[rows[good]] = xb[:, good], True
            redo = np.flatnonzero(ok & halved)
            prev[act[halved]] = prev_move[act[halved]] = 0.0        # not in the quadratic regime
            if redo.size:
                Sr, Jr, H2r = ev(xn[:, redo].T, 2, act[redo])
                Sn, Jn, H2n = np.array(Sn), np.array(Jn), np.array(H2n)
                Sn[:, redo], Jn[..., redo], H2n[..., redo] = Sr.T, Jr.T, H2r.T
                rn[:, redo] = Sn[:, redo] - Pa[:, redo]
                gn[redo] = (rn[:, redo] ** 2).sum(0)
        # accept improved steps; a stalled line search ends the iteration for that pair
        if ok.all():
            xc[:, act], xe[:, act], g[act] = xn, xn, gn
            Sc[:, act], Jc[..., act], Hc[..., act] = Sn, Jn, H2n
            done = gn == 0.0
            conv[act[done]] = True
        else:
            ao = act[ok]
            xc[:, ao], xe[:, ao], g[ao] = xn[:, ok], xn[:, ok], gn[ok]
            Sc[:, ao], Jc[..., ao], Hc[..., ao] = Sn[:, ok], Jn[..., ok], H2n[..., ok]
            done = ~ok | (gn == 0.0)
            # a line search that cannot decrease g even at 2^-10 of the step is at the
            # rounding floor of a stationary point when that step is short
            stalled = np.zeros(len(ok), dtype=bool)
            if tol is not None:
                stalled |= step_move <= 1024.0 * np.sqrt(tol * proj.size)
            if param_tol is not None:
                stalled |= (np.abs(step) <= 1024.0 * np.sqrt(param_tol) * width).all(0)
            stalled &= ~ok
            conv[act[done]] = (stalled | (ok & (gn == 0.0)))[done]
        if done.any():
            keep = ~done
            act, Pa = act[keep], Pa[:, keep]
            Ja, Ha, Ra = Jn[..., keep], H2n[..., keep], rn[:, keep]
        else:
            Ja, Ha, Ra = Jn, H2n, rn
    return xc.T.copy(), g, conv, [Sc.T, Jc.T, Hc.T, xe.T]


def _foot_move(Jc: np.ndarray, d: np.ndarray) -> np.ndarray:
    """|J d| per column: how far the parameter step d (k, n) moves the point, to first
    order, from component-first partials J (k, dim, n)."""
    with np.errstate(over="ignore", invalid="ignore"):      # a wild step (at a centre of curvature)
        v = (Jc * d[:, None, :]).sum(0)
        return np.sqrt((v * v).sum(0))


# --- two objects ---------------------------------------------------------------------------
def refine(A: Union[Geometry, FixedPoints], B: Geometry, x: np.ndarray, y: np.ndarray, full_hessian: bool,
           iters: int = 40) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Minimize f = |A(x) - B(y)|^2 / 2 from the starts (x, y) (N, k_a), (N, k_b).

    ``full_hessian`` False: Gauss-Newton H = J^T J (quadratic convergence to a
    transversal root A(x) = B(y)); True: Newton with the second-order terms
    r . A_xx, -r . B_yy (quadratic convergence to a regular minimum of the distance,
    e.g. a tangential contact). Variables at a non-periodic domain bound whose
    gradient points outwards are held fixed (projected Newton); negative curvature
    is flipped (|lambda|); steps are halved until f decreases (at most 30 times).
    Returns (x, y, distance, converged): converged when a step changed no parameter
    by more than 1e-15 of its domain or moved no foot by more than 1e-15 of the larger
    object's size (to first order, |dA/dx_i| |dx_i|: a parameter along a collapsed edge
    moves nothing), f reached 0, or no decrease was possible with
    a Newton step below 1e-10 of the domain (rounding level).
    """
    ka, n = A.k, A.k + B.k
    z = np.concatenate([x, y], axis=1).astype(float)
    lo = np.concatenate([A.lo, B.lo])
    hi = np.concatenate([A.hi, B.hi])
    per = np.concatenate([A.periodic, B.periodic])
    span = hi - lo
    scale = max(getattr(A, "size", 0.0), B.size)

    def clamp(w):
        return clamped(w, lo, hi, per)

    def residual(w, order, rows):
        pa, da, ha = A.derivatives(w[:, :ka], order, rows)
        pb, db, hb = B.derivatives(w[:, ka:], order, rows)
        return pa - pb, da, db, ha, hb

    z = clamp(z)
    r = residual(z, 0, None)[0]
    f = 0.5 * np.einsum("nd,nd->n", r, r)
    converged = np.zeros(len(z), bool)
    active = np.ones(len(z), bool)
    for _ in range(iters):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        zi = z[idx]
        r, da, db, ha, hb = residual(zi, 2 if full_hessian else 1, idx)
        J = np.concatenate([da, -db], axis=1)                       # (N, n, D)
        g = np.einsum("nkd,nd->nk", J, r)
        H = np.einsum("nkd,nld->nkl", J, J)
        if full_hessian:
            H[:, :ka, :ka] += np.einsum("nkld,nd->nkl", ha, r)
            H[:, ka:, ka:] -= np.einsum("nkld,nd->nkl", hb, r)
        fixed = held_at_bounds(zi, g, lo + BOUND_SLACK * span, hi - BOUND_SLACK * span, per)
        g = np.where(fixed, 0.0, g)
        keep = ~fixed[:, :, None] & ~fixed[:, None, :]
        H = np.where(keep, H, 0.0) + np.eye(n) * fixed[:, :, None]
        lam, V = np.linalg.eigh(H)
        top = np.maximum(np.abs(lam).max(axis=1, keepdims=True), TINY)
        lam = np.maximum(np.abs(lam), EIGEN_FLOOR_RTOL * top)
        step = -np.einsum("nkl,nl->nk", V, np.einsum("nlk,nl->nk", V, g) / lam)
        f0 = f[idx]
        accepted = np.zeros(idx.size, bool)
        znew = zi.copy()
        fnew = f0.copy()

        def trial(rows, t):
            w = clamp(zi[rows] + t[:, None] * step[rows])
            rt = residual(w, 0, idx[rows])[0]
            return w, 0.5 * np.einsum("nd,nd->n", rt, rt)

        small = np.all(np.abs(step) <= STALL_STEP_RTOL * span, axis=1)
        # step halving, t = 1, 1/2, ... (BACKTRACK_TRIES of them), the first t where f does
        # not increase taken; the halvings of the rows still to place are evaluated in
        # blocks of 1, 2, 4, ... BACKTRACK_BLOCK values of t (one evaluation a block, the
        # same result as one at a time).
        # A short step that cannot decrease f at full length is at the rounding floor: it
        # is not halved (the halvings would only chase rounding)
        rows, t, left, m = np.arange(idx.size), 1.0, BACKTRACK_TRIES, 1
        while rows.size and left:
            m = min(m, left)
            ts = t * 0.5 ** np.arange(m)
            wz, ft = trial(np.repeat(rows, m), np.tile(ts, rows.size))
            good = (ft <= f0[np.repeat(rows, m)]).reshape(rows.size, m)
            hit = good.any(axis=1)
            pick = np.flatnonzero(hit) * m + np.argmax(good[hit], axis=1)
            znew[rows[hit]], fnew[rows[hit]] = wz[pick], ft[pick]
            accepted[rows[hit]] = True
            rows = rows[~hit]
            if left == BACKTRACK_TRIES:
                rows = rows[~small[rows]]
            t, left = t * 0.5 ** m, left - m
            m = 1 if left == BACKTRACK_TRIES - 1 else min(2 * m, BACKTRACK_BLOCK)
        moved = np.abs(step_across(znew, zi, span, per))
        # a coordinate is settled when it moved by rounding in the parameter or in space
        # (|dP/dz| |dz|): along a collapsed edge (a pole) the parameter is arbitrary, and the
        # steps along it, which leave f unchanged, went on to the last iteration
        speed = np.sqrt(np.einsum("nkd,nkd->nk", J, J))
        settled = (moved <= ULP_RTOL * span) | (moved * speed <= ULP_RTOL * scale)
        ok = (accepted & np.all(settled, axis=1)) | (fnew == 0) | (~accepted & small)
        z[idx], f[idx] = znew, fnew
        converged[idx[ok]] = True
        active[idx[ok | ~accepted]] = False
    return z[:, :ka], z[:, ka:], np.sqrt(2.0 * f), converged


class FixedPoints:
    """A parameterless stand-in for :func:`refine` (k = 0): minimizing
    |FixedPoints - B(y)| projects the points onto B."""
    k = 0
    lo = hi = np.empty(0)
    periodic = np.empty(0, bool)

    def __init__(self, pts: np.ndarray):
        self.pts = pts

    def derivatives(self, x: np.ndarray, order: int, rows: Optional[np.ndarray] = None
                    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        pts = self.pts if rows is None else self.pts[rows]
        N, D = pts.shape
        return pts, np.zeros((N, 0, D)), np.zeros((N, 0, 0, D))


def project_onto(B: Geometry, pts: np.ndarray, y0: np.ndarray, iters: int = 30
                 ) -> Tuple[np.ndarray, np.ndarray]:
    """Local projection of points (N, D) onto B from the starts y0 (N, k):
    (parameters (N, k), distances (N,))."""
    _, y, dist, _ = refine(FixedPoints(pts), B, np.zeros((len(pts), 0)), y0, True, iters)
    return y, dist


# --- the surface intersection system ---------------------------------------------------------
def newton(S: System, x, C=None, g0=None, ftol=NEWTON_FTOL, iters=NEWTON_ITERATIONS, full=False):
    """Newton on [F(x); C.(x) - g0] = 0 (C (N, n) one constraint row per point), or the
    minimum-norm step when C is None. A row is converged at an evaluated x with
    |F(x)| <= ftol whose next step is below STEP_RTOL of the width (a root, not a point
    of a tangency's flat valley where |F| <= ftol over a whole patch), or, with the
    constraint row (a square system, an isolated root), whose step no longer shrinks
    (below STAGNANT_SHARE of the previous one: rounding amplified by a near-tangency's
    condition number, 1e-11 of the width at cond 5e5 on occ22470.igs SOLID[2] x [3], where
    the marching's correctors ran all their iterations at |F| ~ 1e-14); it stops there
    (the rows still moving go on, one evaluation of all of them per iteration). Returns (x, converged), with ``full``
    also :meth:`System.eval`'s arrays at the returned x (F, J, point, normals, da)."""
    x = np.array(x, dtype=float)
    ok = np.zeros(len(x), bool)
    step_tol = STEP_RTOL * S.span
    act = np.arange(len(x))
    out: list = []
    last = np.full(len(x), np.inf)          # the previous step, share of the width

    def keep(rows, ev):
        if not out:
            out.extend(np.empty((len(x),) + np.shape(a)[1:]) for a in ev)
        for o, a in zip(out, ev):
            o[rows] = a

    for _ in range(iters):
        if not act.size:
            break
        xa = x[act]
        ev = S.eval(xa)
        keep(act, ev)
        F, J = ev[0], ev[1]
        res = np.linalg.norm(F, axis=1)
        if C is None:
            JJ = J @ J.transpose(0, 2, 1)
            JJ += np.eye(JJ.shape[1]) * TINY
            try:
                y = np.linalg.solve(JJ, -F[..., None])
            except np.linalg.LinAlgError:
                y = np.einsum("nij,njk->nik", np.linalg.pinv(JJ), -F[..., None])
            dx = (J.transpose(0, 2, 1) @ y)[..., 0]
        else:
            Ca = C[act]
            M = np.concatenate([J, Ca[:, None, :]], axis=1)
            rhs = -np.concatenate([F, (np.einsum("nk,nk->n", Ca, xa) - g0[act])[:, None]], axis=1)
            det = np.abs(np.linalg.det(M))
            good = det > TINY
            dx = np.zeros_like(xa)
            if good.all():
                dx = np.linalg.solve(M, rhs[..., None])[..., 0]
            elif good.any():
                dx[good] = np.linalg.solve(M[good], rhs[good][..., None])[..., 0]
        small = np.all(np.abs(dx) <= step_tol, axis=1)
        conv = (res <= ftol) & small
        if C is not None:         # a square system: a root is isolated, no flat valley to stop in
            size = (np.abs(dx) / S.span).max(axis=1)
            conv |= (res <= ftol) & (size >= STAGNANT_SHARE * last[act])
            last[act] = size
        ok[act[conv]] = True
        go = ~conv
        act = act[go]
        x[act] = S.clip(xa[go] + dx[go])
    if act.size or not out:
        ev = S.eval(x[act])
        keep(act, ev)
        ok[act] = np.linalg.norm(ev[0], axis=1) <= ftol
    return (x, ok, tuple(out)) if full else (x, ok)
