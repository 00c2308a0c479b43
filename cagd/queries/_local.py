"""Local refinement and second-order bounds for the closest-point search (vectorized over
(point, box) pairs; k = 1 or 2 parameters).

g(x) = |S(x) - X|^2, grad g = 2 J^T r, Hess g = 2 (J^T J + sum_d r_d d2S_d), r = S - X
(Piegl & Tiller 6.1, point inversion as Newton's method on the stationarity condition).
"""
from __future__ import annotations

import numpy as np

_DECREASE = 1e-15     # relative slack when comparing squared distances (rounding)
BLOCK = 2             # cells within this many grid steps of x*'s cell are bounded from x*


def _solve(Hf: np.ndarray, Hg: np.ndarray, grad: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """Newton step -H^-1 grad on the free coordinates; H the full Hessian where it is
    positive definite, else the Gauss-Newton matrix 2 J^T J (+ a tiny Levenberg shift)."""
    g = np.where(fixed, 0.0, grad)
    if Hf.shape[1] == 1:
        h = Hf[:, 0, 0]
        hg = Hg[:, 0, 0] * (1.0 + 1e-12) + 1e-300
        h = np.where(h > 0, h, hg)
        return (-g[:, 0] / h)[:, None]
    out = None
    for H, shift in ((Hf, 0.0), (Hg, 1e-12)):
        a, b, c = H[:, 0, 0].copy(), H[:, 0, 1].copy(), H[:, 1, 1].copy()
        a, c = a + shift * (a + c) + 1e-300, c + shift * (a + c) + 1e-300
        f0, f1 = fixed[:, 0], fixed[:, 1]
        b[f0 | f1] = 0.0
        a[f0], c[f1] = 1.0, 1.0
        det = a * c - b * b
        with np.errstate(divide="ignore", invalid="ignore"):
            step = -np.stack([(c * g[:, 0] - b * g[:, 1]) / det, (a * g[:, 1] - b * g[:, 0]) / det], axis=1)
        pd = (a > 0) & (det > 0) & np.all(np.isfinite(step), axis=1)
        out = step if out is None else np.where(use_gn[:, None], step, out)
        use_gn = ~pd
    return np.where(np.isfinite(out), out, 0.0)


def _place(x: np.ndarray, lo: np.ndarray, hi: np.ndarray, wrap: np.ndarray, a: np.ndarray,
           b: np.ndarray) -> np.ndarray:
    """Clamp to the box, or wrap into the domain [a, b) in periodic directions."""
    return np.where(wrap, a + np.mod(x - a, b - a), np.clip(x, lo, hi))


def projected_newton(proj, X: np.ndarray, pid: np.ndarray, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                     wrap: np.ndarray, max_iterations: int, tol: float):
    """Minimise |S(x) - X[pid]|^2 for every row of x0 inside its box [lo, hi] (wrapped
    instead of clamped along ``wrap``): Newton with an active set at the box faces and
    step halving (at most 10 halvings) so that g never increases.
    Returns (x, g, converged, (S, J, H2) at x); converged means the last step was below
    tol * range."""
    x = np.array(x0, dtype=np.float64)
    n = len(x)
    a, b = proj.domain[:, 0], proj.domain[:, 1]
    step_tol = tol * proj.width
    conv = np.zeros(n, dtype=bool)
    S, J, H2 = proj.evaluate(x, 2)
    last = [S.copy(), J.copy(), H2.copy()]
    r = S - X[pid]
    g = (r * r).sum(1)
    floor = (1e-15 * proj.size) ** 2
    act = np.arange(n)
    for _ in range(max_iterations):
        if not act.size:
            break
        xa, la, ha = x[act], lo[act], hi[act]
        grad = 2.0 * np.einsum("nd,ndk->nk", r, J)
        JtJ = np.einsum("nda,ndb->nab", J, J)
        Hf = 2.0 * (JtJ + np.einsum("nd,ndab->nab", r, H2))
        fixed = ~wrap & (((xa <= la) & (grad > 0)) | ((xa >= ha) & (grad < 0)))
        step = _solve(Hf, 2.0 * JtJ, grad, fixed)
        xn = _place(xa + step, la, ha, wrap, a, b)
        taken = np.where(wrap, step, xn - xa)
        small = np.all(np.abs(taken) <= step_tol, axis=1)
        Sn, Jn, H2n = proj.evaluate(xn, 2)
        rn = Sn - X[pid[act]]
        gn = (rn * rn).sum(1)
        # below the rounding level of g the comparison is noise: trust the Newton step
        tiny = -0.5 * (grad * step).sum(1) <= 1e-12 * g[act] + floor
        ok = (gn <= g[act] * (1.0 + _DECREASE) + floor) | tiny
        bad = np.flatnonzero(~ok & ~small)
        t = 1.0
        for _ in range(10):
            if not bad.size:
                break
            t *= 0.5
            xb = _place(xa[bad] + t * step[bad], la[bad], ha[bad], wrap, a, b)
            gb = ((proj.value(xb) - X[pid[act[bad]]]) ** 2).sum(1)
            good = gb <= g[act[bad]] * (1.0 + _DECREASE) + floor
            xn[bad[good]], ok[bad[good]] = xb[good], True
            bad = bad[~good]
        redo = np.flatnonzero(ok & (t < 1.0))
        if redo.size:
            Sr, Jr, H2r = proj.evaluate(xn[redo], 2)
            Sn[redo], Jn[redo], H2n[redo] = Sr, Jr, H2r
            rn[redo] = Sr - X[pid[act[redo]]]
            gn[redo] = (rn[redo] ** 2).sum(1)
        # accept improved steps; a stalled line search ends the iteration for that pair
        x[act[ok]], g[act[ok]] = xn[ok], gn[ok]
        for arr, new in zip(last, (Sn, Jn, H2n)):
            arr[act[ok]] = new[ok]
        done = small | ~ok | (gn == 0.0)
        # a line search that cannot decrease g even at 2^-10 of the step is at the
        # rounding floor of a stationary point when that step is short
        stalled = ~ok & np.all(np.abs(step) <= 1024.0 * np.sqrt(tol) * proj.width, axis=1)
        conv[act[done]] = (small | stalled | (ok & (gn == 0.0)))[done]
        keep = ~done
        act = act[keep]
        S, J, H2, r = Sn[keep], Jn[keep], H2n[keep], rn[keep]
        # pairs whose step was rejected keep their old point (already stored in x, g)
    return x, g, conv, last


def _sigma_min(J: np.ndarray) -> np.ndarray:
    """Smallest singular value of J (n, dim, k), k = 1 or 2, computed from above-safe
    formulas (lambda_min = det / lambda_max of J^T J, det by Lagrange's identity)."""
    if J.shape[2] == 1:
        return np.sqrt((J[:, :, 0] ** 2).sum(1))
    u, v = J[:, :, 0], J[:, :, 1]
    a, c, bb = (u * u).sum(1), (v * v).sum(1), (u * v).sum(1)
    if J.shape[1] == 3:
        det = (np.cross(u, v) ** 2).sum(1)
    elif J.shape[1] == 2:
        det = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) ** 2
    else:
        det = np.maximum(a * c - bb * bb, 0.0)
    lmax = 0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + bb * bb)
    with np.errstate(divide="ignore", invalid="ignore"):
        lmin = np.where(lmax > 0, det / lmax, 0.0)
    return np.sqrt(lmin) * (1.0 - 1e-10)


def _lambda_min(H: np.ndarray) -> np.ndarray:
    """Smallest eigenvalue of symmetric (n, k, k), k = 1 or 2."""
    if H.shape[1] == 1:
        return H[:, 0, 0]
    a, b, c = H[:, 0, 0], H[:, 0, 1], H[:, 1, 1]
    return 0.5 * (a + c) - np.sqrt(0.25 * (a - c) ** 2 + b * b)


def box_lower_bound(Xp: np.ndarray, lo: np.ndarray, hi: np.ndarray, c: np.ndarray, S: np.ndarray, J: np.ndarray,
                    H2: np.ndarray, L: np.ndarray, M: np.ndarray, T: np.ndarray) -> np.ndarray:
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
    exactly (it is separable)."""
    r = S - Xp
    f = np.sqrt((r * r).sum(1))
    grad = 2.0 * np.einsum("nd,ndk->nk", r, J)
    delta = np.maximum(np.abs(c - lo), np.abs(hi - c))
    D = np.einsum("nab,nb->na", M, delta)
    dJ = np.sqrt((D ** 2).sum(1))
    if M.shape[1] == 1:
        lam = M[:, 0, 0]
    else:
        lam = 0.5 * (M[:, 0, 0] + M[:, 1, 1]) + np.sqrt(0.25 * (M[:, 0, 0] - M[:, 1, 1]) ** 2 + M[:, 0, 1] ** 2)
    Ld = (L * delta).sum(1)
    m1 = 2.0 * (np.maximum(_sigma_min(J) - dJ, 0.0) ** 2 - (f + Ld) * lam)
    half = np.einsum("nda,ndb->nab", J, J) + np.einsum("nd,ndab->nab", r, H2)
    Sn = np.sqrt((J * J).sum(1))                                   # |S_a(c)|
    E = (D[:, :, None] * Sn[:, None, :] + Sn[:, :, None] * D[:, None, :] + D[:, :, None] * D[:, None, :]
         + Ld[:, None, None] * M + f[:, None, None] * np.einsum("nabe,ne->nab", T, delta))
    scale = np.abs(half).sum((1, 2))
    m2 = 2.0 * (_lambda_min(half) - np.sqrt((E ** 2).sum((1, 2))) - 1e-12 * scale)
    m = np.maximum(m1, m2)[:, None]
    tlo, thi = lo - c, hi - c
    q = np.minimum(grad * tlo + 0.5 * m * tlo ** 2, grad * thi + 0.5 * m * thi ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ts = np.clip(np.where(m > 0, -grad / m, 0.0), tlo, thi)
    q = np.minimum(q, grad * ts + 0.5 * m * ts ** 2)
    return f * f + q.sum(1) - 1e-15 * f * f


def pair_distances(X: np.ndarray, pid: np.ndarray, Y: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """|X[pid] - Y[cell]| coordinate by coordinate (fast for long pair lists)."""
    acc = np.zeros(len(pid))
    for a in range(X.shape[1]):
        t = X[:, a].take(pid) - Y[:, a].take(cell)
        acc += t * t
    return np.sqrt(acc)


def block_max(B: np.ndarray, shape) -> np.ndarray:
    """Per cell, the maximum of the bounds B over the cells within BLOCK grid steps."""
    G = B.reshape(tuple(shape) + B.shape[1:])
    out = G.copy()
    for a in range(len(shape)):
        src = out.copy()
        for s in range(1, BLOCK + 1):
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
