"""Local refinement and second-order bounds for the closest-point search (vectorized over
(point, box) pairs; k = 1 or 2 parameters).

g(x) = |S(x) - X|^2, grad g = 2 J^T r, Hess g = 2 (J^T J + sum_d r_d d2S_d), r = S - X
(Piegl & Tiller 6.1, point inversion as Newton's method on the stationarity condition).
"""
from __future__ import annotations

import numpy as np

from .. import _periodic as periodic

_DECREASE = 1e-15     # relative slack when comparing squared distances (rounding)
BLOCK = 2             # cells within this many grid steps of x*'s cell are bounded from x*


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
        hg = Hg[0] * (1.0 + 1e-12) + 1e-300
        h = np.where(h > 0, h, hg)
        return (-g[0] / h)[None]
    steps = []
    f0, f1 = fixed[0], fixed[1]
    either = f0 | f1
    for H, shift in ((Hf, 0.0), (Hg, 1e-12)):
        a, b, c = H
        tr = shift * (a + c)
        a, c = a + tr + 1e-300, c + tr + 1e-300
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
    floor = (1e-15 * proj.size) ** 2
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
        fixed = ~wrapc & (((xa <= la) & (grad > 0)) | ((xa >= ha) & (grad < 0)))
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
            small |= (move <= tol) | ((move <= 1e-2 * pm) & (move ** 3 <= 1e-3 * tol * pm ** 2))
        if param_tol is not None:
            pr = prev[act]
            small |= (np.abs(taken) <= param_tol * width).all(0) | \
                ((rel <= 1e-2 * pr) & (rel ** 3 <= 1e-3 * param_tol * pr ** 2))
        prev[act], prev_move[act] = rel, move
        if small.any():
            # the last (tiny) step is taken when it does not increase g, with a point
            # evaluation only; S, J, H2 stay those at the previous point (returned as xe)
            conv[act[small]] = True
            i = np.flatnonzero(small)
            gs = ((ev(xn[:, i].T, 0, act[i]).T - Pa[:, i]) ** 2).sum(0)
            # near the minimum g is flat to rounding (a foot error d moves it by ~d^2):
            # compare with a few ulps of slack, or the last Newton correction is lost
            better = gs <= g[act[i]] * (1.0 + 1e-14) + floor
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
        tiny = -0.5 * (grad * step).sum(0) <= 1e-12 * ga + floor
        ok = (gn <= ga * (1.0 + _DECREASE) + floor) | tiny
        bad = np.flatnonzero(~ok)
        t = 1.0
        if bad.size:
            halved = np.zeros(len(ok), dtype=bool)
            halved[bad] = True
            for _ in range(10):
                if not bad.size:
                    break
                t *= 0.5
                xb = _place(xa[:, bad] + t * step[:, bad], la[:, bad], ha[:, bad], wrapc, a, b)
                gb = ((ev(xb.T, 0, act[bad]).T - Pa[:, bad]) ** 2).sum(0)
                good = gb <= ga[bad] * (1.0 + _DECREASE) + floor
                xn[:, bad[good]], ok[bad[good]] = xb[:, good], True
                bad = bad[~good]
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


def box_lower_bound(Xp: np.ndarray, lo: np.ndarray, hi: np.ndarray, c: np.ndarray, S: np.ndarray, J: np.ndarray,
                    H2: np.ndarray, L: np.ndarray, M: np.ndarray, T: np.ndarray, convexity: bool = False):
    """A certified lower bound of g over each box [lo, hi] (inside cell ``cell``), from the
    expansion at c: g(x) >= g(c) + grad g(c).(x - c) + m/2 |x - c|^2 with m a lower bound
    of the smallest Hessian eigenvalue over the box, the larger of

    * 2 [(sigma_min(J(c)) - |dJ|)_+^2 - (|r(c)| + L.delta) lambda_max(M)], with
      |dJ| <= sqrt(sum_a (sum_b M_ab delta_b)^2) (Weyl's inequality), and
    * lambda_min(H(c)) - 2 |E|_F, E bounding the change of J^T J + r.d2S over the box:
      |E_ab| <= D_a |S_b| + |S_a| D_b + D_a D_b + (L.delta) M_ab + |r(c)| sum_e T_abe delta_e,
      D_a = sum_e M_ae delta_e,

    delta = the box's reach from c (c need not lie in the box), L, M, T bounds of the
    first, second and third partials valid on the hull of c and the box; S, J, H2 the
    point, first and second partials at c. The quadratic is minimised over the box
    exactly (it is separable). The bound is taken in the variables y_a = s_a x_a, s_a the
    power of two nearest the first-derivative bound L_a (at least a quarter of the
    largest), so that a large second derivative along one direction is weighed against
    the first derivative along that direction: m bounds the smallest eigenvalue of
    diag(s)^-1 H diag(s)^-1, i.e. H >= m diag(s)^2.

    ``convexity``: also return m and, for c in the box, the box (tlo, thi) (n, k) of offsets
    from c that holds g's minimiser x^ over the box where m > 0 (g strongly convex there:
    g(x^) >= g(c) + the quadratic at x^ - c, and g(x^) <= g(c); the whole box where
    m <= 0)."""
    n, dim = S.shape
    k = c.shape[1]
    r = [S[:, d] - Xp[:, d] for d in range(dim)]
    f2 = r[0] * r[0]
    for d in range(1, dim):
        f2 = f2 + r[d] * r[d]
    f = np.sqrt(f2)
    Jc = [[J[:, d, a] for d in range(dim)] for a in range(k)]
    grad, sc, si, delta, Sn = [], [], [], [], []
    for a in range(k):
        g = r[0] * Jc[a][0]
        nn = Jc[a][0] * Jc[a][0]
        for d in range(1, dim):
            g = g + r[d] * Jc[a][d]
            nn = nn + Jc[a][d] * Jc[a][d]
        grad.append(2.0 * g)
        sc.append(np.sqrt(nn))
    # scales from the first-derivative bounds over the cell, within a factor 4 of the
    # largest (degenerate directions, e.g. at a pole)
    top = L.max(axis=1)
    top = np.where(top > 0, top, 1.0)
    for a in range(k):
        nrm = sc[a]
        sa = np.exp2(np.round(np.log2(np.maximum(L[:, a], 0.25 * top))))
        sc[a] = sa
        si.append(1.0 / sa)
        Sn.append(nrm / sa)                                            # |S_a(c)| scaled
        delta.append(np.maximum(np.abs(c[:, a] - lo[:, a]), np.abs(hi[:, a] - c[:, a])) * sa)
    Jh = [[Jc[a][d] * si[a] for d in range(dim)] for a in range(k)]
    Mh = [[M[:, a, b] * (si[a] * si[b]) for b in range(k)] for a in range(k)]
    D = []
    for a in range(k):
        v = Mh[a][0] * delta[0]
        for b in range(1, k):
            v = v + Mh[a][b] * delta[b]
        D.append(v)
    Ld = L[:, 0] * delta[0] * si[0]
    for a in range(1, k):
        Ld = Ld + L[:, a] * delta[a] * si[a]
    if k == 1:
        dJ = D[0]
        lam = Mh[0][0]
        sig = Sn[0]
    else:
        dJ = np.sqrt(D[0] * D[0] + D[1] * D[1])
        lam = 0.5 * (Mh[0][0] + Mh[1][1]) + np.sqrt(0.25 * (Mh[0][0] - Mh[1][1]) ** 2 + Mh[0][1] ** 2)
        u, v = Jh
        aa, cc = Sn[0] * Sn[0], Sn[1] * Sn[1]
        bb = u[0] * v[0]
        for d in range(1, dim):
            bb = bb + u[d] * v[d]
        if dim == 3:
            det = (u[1] * v[2] - u[2] * v[1]) ** 2 + (u[2] * v[0] - u[0] * v[2]) ** 2 + (u[0] * v[1] - u[1] * v[0]) ** 2
        elif dim == 2:
            det = (u[0] * v[1] - u[1] * v[0]) ** 2
        else:
            det = np.maximum(aa * cc - bb * bb, 0.0)
        lmax = 0.5 * (aa + cc) + np.sqrt(0.25 * (aa - cc) ** 2 + bb * bb)
        with np.errstate(divide="ignore", invalid="ignore"):
            lmin = np.where(lmax > 0, det / lmax, 0.0)
        sig = np.sqrt(lmin) * (1.0 - 1e-10)
    m1 = 2.0 * (np.maximum(sig - dJ, 0.0) ** 2 - (f + Ld) * lam)
    # half Hessian J^T J + r.d2S at c and the bound E of its change over the box
    pairs = [(0, 0)] if k == 1 else [(0, 0), (0, 1), (1, 1)]
    half, E2, scale = {}, 0.0, 0.0
    for a, b in pairs:
        jj = Jh[a][0] * Jh[b][0]
        rh = r[0] * H2[:, 0, a, b]
        for d in range(1, dim):
            jj = jj + Jh[a][d] * Jh[b][d]
            rh = rh + r[d] * H2[:, d, a, b]
        h = jj + rh * (si[a] * si[b])
        half[a, b] = h
        tt = T[:, a, b, 0] * (si[0] * delta[0])
        for e in range(1, k):
            tt = tt + T[:, a, b, e] * (si[e] * delta[e])
        e_ab = D[a] * Sn[b] + Sn[a] * D[b] + D[a] * D[b] + Ld * Mh[a][b] + f * tt * (si[a] * si[b])
        w = 1.0 if a == b else 2.0
        E2 = E2 + w * e_ab * e_ab
        scale = scale + w * np.abs(h)
    if k == 1:
        lmin_h = half[0, 0]
    else:
        A, B, C = half[0, 0], half[0, 1], half[1, 1]
        lmin_h = 0.5 * (A + C) - np.sqrt(0.25 * (A - C) ** 2 + B * B)
    m2 = 2.0 * (lmin_h - np.sqrt(E2) - 1e-12 * scale)
    m = np.maximum(m1, m2)
    q = 0.0
    parts = []
    for a in range(k):
        ma = m * (sc[a] * sc[a])
        g = grad[a]
        tlo, thi = lo[:, a] - c[:, a], hi[:, a] - c[:, a]
        qa = np.minimum(g * tlo + 0.5 * ma * tlo ** 2, g * thi + 0.5 * ma * thi ** 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            ts = np.clip(np.where(ma > 0, -g / ma, 0.0), tlo, thi)
        qa = np.minimum(qa, g * ts + 0.5 * ma * ts ** 2)
        q = q + qa
        parts.append((g, ma, tlo, thi, qa))
    bound = f2 + q - 1e-15 * f2
    if not convexity:
        return bound
    # the minimiser x^ over the box has g(x^) <= g(c), so sum_a q_a(t_a) <= 0 at t = x^ - c,
    # q_a(t) = grad_a t + m_a t^2 / 2 >= its minimum qmin_a over the box's range: each
    # q_a(t_a) <= qmin_a - sum_b qmin_b (+ a rounding margin), an interval of t_a
    lo_t, hi_t = [], []
    for g, ma, tlo, thi, qa in parts:
        rhs = qa - q + 1e-13 * f2 + 1e-300
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            root = np.sqrt(g * g + 2.0 * ma * rhs)
            a0 = np.where(m > 0, (-g - root) / ma, -np.inf)
            a1 = np.where(m > 0, (-g + root) / ma, np.inf)
        lo_t.append(np.maximum(a0, tlo))
        hi_t.append(np.minimum(a1, thi))
    return bound, m, (np.stack(lo_t, axis=1), np.stack(hi_t, axis=1))


def pair_distances(X: np.ndarray, pid: np.ndarray, Y: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """|X[pid] - Y[cell]| coordinate by coordinate (fast for long pair lists)."""
    acc = np.zeros(len(pid))
    for a in range(X.shape[1]):
        t = X[:, a].take(pid) - Y[:, a].take(cell)
        acc += t * t
    return np.sqrt(acc)


def block_max(B: np.ndarray, shape, reach: int = BLOCK) -> np.ndarray:
    """Per cell, the maximum of the bounds B over the cells within ``reach`` grid steps."""
    G = B.reshape(tuple(shape) + B.shape[1:])
    out = G.copy()
    for a in range(len(shape)):
        src = out.copy()
        for s in range(1, reach + 1):
            lo = [slice(None)] * G.ndim
            hi = [slice(None)] * G.ndim
            lo[a], hi[a] = slice(0, -s), slice(s, None)
            out[tuple(lo)] = np.maximum(out[tuple(lo)], src[tuple(hi)])
            out[tuple(hi)] = np.maximum(out[tuple(hi)], src[tuple(lo)])
    return out.reshape(B.shape)


def split_boxes(pid, cell, lo, hi, lb):
    """Halve every open box along its widest side relative to its cell."""
    w = hi - lo
    axis = np.argmax(w, axis=1)
    mid = 0.5 * (lo[np.arange(len(lo)), axis] + hi[np.arange(len(lo)), axis])
    lo2, hi1 = lo.copy(), hi.copy()
    lo2[np.arange(len(lo)), axis] = mid
    hi1[np.arange(len(lo)), axis] = mid
    return (np.concatenate([pid, pid]), np.concatenate([cell, cell]), np.concatenate([lo, lo2]),
            np.concatenate([hi1, hi]), np.concatenate([lb, lb]))


def _bernstein_to_power(p: int) -> np.ndarray:
    """(p+1, p+1) matrix C with power coefficients c_a = sum_i C[a, i] P_i of a degree-p
    Bezier polynomial on [0, 1] written in the centred variable s = 2 t - 1 in [-1, 1]:
    B_i(t) = C(p, i) 2^-p (1 + s)^i (1 - s)^(p - i)."""
    from math import comb
    P = np.polynomial.polynomial
    C = np.zeros((p + 1, p + 1))
    for i in range(p + 1):
        c = P.polymul(P.polypow([1.0, 1.0], i), P.polypow([1.0, -1.0], p - i)) * (comb(p, i) / 2.0 ** p)
        C[:len(c), i] = c
    return C


def _horner(coef, s, order):
    """[P, P', P''/2] (up to ``order``) of sum_a coef[a] s^a by Horner's scheme with
    derivatives; ``coef`` a list of arrays (or a callable giving them), highest last."""
    n = len(coef) - 1
    p0 = coef[n]
    p1 = p2 = None
    for a in range(n - 1, -1, -1):
        if order >= 2 and p1 is not None:
            p2 = p1 if p2 is None else p2 * s + p1
        if order >= 1:
            p1 = p0 if p1 is None else p1 * s + p0
        p0 = p0 * s + coef[a]
    out = [p0]
    shape = np.broadcast_shapes(np.shape(p0), np.shape(s))
    if order >= 1:
        out.append(p1 if p1 is not None else np.zeros(shape))
    if order >= 2:
        out.append(p2 if p2 is not None else np.zeros(shape))
    return out


class PowerTable:
    """Per Bezier piece, the power coefficients of the (homogeneous) piece in the centred
    local variables s in [-1, 1] per direction; points and partials up to order 2 by
    nested Horner with 1-D gathers (the patch-table design of the engine's B-spline
    surfaces), in cache-sized chunks. Rational pieces by the quotient rule (Piegl &
    Tiller eq. 4.8, 4.20)."""

    CHUNK = 1 << 14

    def __init__(self, pieces):
        self.k, self.dim = pieces.k, pieces.dim
        self.degrees = pieces.degrees
        self.rational = pieces.weights is not None
        hom = np.asarray(pieces.homogeneous, dtype=np.float64)           # (m, p+1[, q+1], D)
        self.D = hom.shape[-1]
        for a, p in enumerate(self.degrees):
            hom = np.moveaxis(np.tensordot(_bernstein_to_power(p), hom, axes=([1], [1 + a])), 0, 1 + a)
        m = hom.shape[0]
        # rows ((a * (q+1) + b) * D + d), columns the pieces: take() on contiguous rows
        self.table = np.ascontiguousarray(hom.reshape(m, -1).T)
        self.breaks = [np.asarray(b, dtype=np.float64) for b in pieces.breaks]
        self.shape = tuple(len(b) - 1 for b in self.breaks)
        self.mid = [0.5 * (b[1:] + b[:-1]) for b in self.breaks]
        self.inv_half = [2.0 / (b[1:] - b[:-1]) for b in self.breaks]
        self.uniform = []
        for b in self.breaks:
            w = b[-1] - b[0]
            self.uniform.append(bool(np.allclose(np.diff(b), w / (len(b) - 1), rtol=1e-13, atol=0.0)))

    def piece_indices(self, x: np.ndarray):
        """Per direction, the index of the piece that evaluates x (n, k)."""
        out = []
        for a, b in enumerate(self.breaks):
            t = x[:, a]
            n = len(b) - 1
            if self.uniform[a]:
                j = ((t - b[0]) * (n / (b[-1] - b[0]))).astype(np.intp)
                np.clip(j, 0, n - 1, out=j)
            else:
                j = np.clip(np.searchsorted(b, t, side="right") - 1, 0, n - 1)
            out.append(j)
        return out

    def _local(self, x: np.ndarray, index=None):
        """Flat piece index and local variables s (one array per direction); ``index``:
        the flat pieces to use (one-sided partials on a piece boundary)."""
        if index is None:
            js = self.piece_indices(x)
        elif self.k == 1:
            js = [index]
        else:
            js = [index // self.shape[1], index % self.shape[1]]
        idx = None
        s = []
        for a, j in enumerate(js):
            s.append((x[:, a] - self.mid[a].take(j)) * self.inv_half[a].take(j))
            idx = j if idx is None else idx * self.shape[a] + j
        return idx, s

    def evaluate(self, x: np.ndarray, order: int, index=None):
        """As Projector.evaluate: S (n, dim), and for order >= 1 J (n, dim, k), for order 2
        the second partials (n, dim, k, k)."""
        x = np.asarray(x, dtype=np.float64).reshape(-1, self.k)
        n, k, dim = len(x), self.k, self.dim
        # component-first storage (contiguous rows per partial and coordinate); the
        # returned arrays are transposed views with the usual (n, dim[, k, k]) shapes
        S = np.empty((dim, n))
        J = np.empty((k, dim, n)) if order >= 1 else None
        H = np.empty((k, k, dim, n)) if order >= 2 else None
        for c0 in range(0, n, self.CHUNK):
            sl = slice(c0, min(n, c0 + self.CHUNK))
            parts = self._chunk(x[sl], order, None if index is None else index[sl])
            self._store(parts, S, J, H, sl, order)
        if order == 0:
            return S.T
        assert J is not None
        if order == 1:
            return S.T, J.T
        assert H is not None
        return S.T, J.T, H.T

    def _chunk(self, x, order, index=None):
        """Per homogeneous coordinate, the partials in the object's parameters: curves
        [C, C', C''], surfaces [S, Su, Sv, Suu, Suv, Svv] (as far as ``order``)."""
        idx, s = self._local(x, index)
        # the rows' coefficients gathered at once ((p+1)[(q+1)] D, n); Horner runs on all
        # coordinates (and u-indices) together: per element the same operations as one
        # coordinate at a time (results bit for bit), in a few numpy calls (a Newton step
        # of a handful of points costs its number of calls, not its arithmetic)
        D, n = self.D, len(idx)
        C = self.table[:, idx]
        if self.k == 1:
            p = self.degrees[0]
            ih = self.inv_half[0].take(idx)
            C = C.reshape(p + 1, D, n)
            r = _horner([C[a] for a in range(p + 1)], s[0], order)
            if order >= 1:
                r[1] = r[1] * ih
            if order >= 2:
                r[2] = 2.0 * r[2] * ih * ih
            return [[part[d] for part in r] for d in range(D)]
        p, q = self.degrees
        nv = self.shape[1]
        ihu, ihv = self.inv_half[0].take(idx // nv), self.inv_half[1].take(idx % nv)
        su, sv = s
        C = C.reshape(p + 1, q + 1, D, n)
        Q = _horner([C[:, b] for b in range(q + 1)], sv, order)          # each (p+1, D, n)
        r0 = _horner([Q[0][a] for a in range(p + 1)], su, order)         # each (D, n)
        if order == 0:
            return [[r0[0][d]] for d in range(D)]
        r1 = _horner([Q[1][a] for a in range(p + 1)], su, order - 1)
        res = [r0[0], r0[1] * ihu, r1[0] * ihv]
        if order >= 2:
            r2 = _horner([Q[2][a] for a in range(p + 1)], su, 0)
            res += [2.0 * r0[2] * ihu * ihu, r1[1] * (ihu * ihv), 2.0 * r2[0] * ihv * ihv]
        return [[part[d] for part in res] for d in range(D)]

    def _store(self, parts, S, J, H, sl, order):
        k, dim = self.k, self.dim
        if self.rational:
            w = parts[-1]
            iw = 1.0 / w[0]
            cart = []
            for d in range(dim):
                A = parts[d]
                c = [A[0] * iw]
                if k == 1:
                    if order >= 1:
                        c.append((A[1] - w[1] * c[0]) * iw)
                    if order >= 2:
                        c.append((A[2] - 2.0 * w[1] * c[1] - w[2] * c[0]) * iw)
                else:
                    if order >= 1:
                        c.append((A[1] - w[1] * c[0]) * iw)
                        c.append((A[2] - w[2] * c[0]) * iw)
                    if order >= 2:
                        c.append((A[3] - 2.0 * w[1] * c[1] - w[3] * c[0]) * iw)
                        c.append((A[4] - w[1] * c[2] - w[2] * c[1] - w[4] * c[0]) * iw)
                        c.append((A[5] - 2.0 * w[2] * c[2] - w[5] * c[0]) * iw)
                cart.append(c)
            parts = cart
        for d in range(dim):
            c = parts[d]
            S[d, sl] = c[0]
            if order >= 1:
                for a in range(k):
                    J[a, d, sl] = c[1 + a]
            if order >= 2:
                if k == 1:
                    H[0, 0, d, sl] = c[2]
                else:
                    H[0, 0, d, sl] = c[3]
                    H[0, 1, d, sl] = c[4]
                    H[1, 0, d, sl] = c[4]
                    H[1, 1, d, sl] = c[5]
