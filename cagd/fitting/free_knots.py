"""Knot recovery for :func:`cagd.fit_curve` (issue 17): fewer control points by moving
the interior knots, so that points sampled from a B-spline come back as that B-spline.

An adaptive fit (knots placed by equidistributing the error, :mod:`cagd.fitting.fit`)
needs many more control points than the curve the points came from, whose knots it
cannot hit. This stage tries smaller counts with the interior knots as unknowns:

- free-knot least squares (Jupp, SIAM J. Numer. Anal. 15(2), 1978; de Boor & Rice,
  "Least squares cubic spline approximation II: variable knots", Purdue CSD TR 21,
  1968; Piegl & Tiller, The NURBS Book, ch. 9 for the fixed-knot problem): the control
  points P and the knot changes dk solve one Gauss-Newton system per pass,

      [ A     C ] [ P  ]   [ B^T M Q ]
      [ C^T   D ] [ dk ] = [ G^T M Q ],   A = B^T M B, C = B^T M G, D = G^T M G,

  B the basis matrix at the points' parameters, G = dC/dk the curve's change with each
  interior knot at fixed control points (central differences), M the tangent-distance
  metric of :meth:`cagd.fitting.fit._Problem.solve` (the points' parameters eliminated:
  Wang, Pottmann & Liu 2006); the banded A is eliminated first (a Schur complement in the
  few knot unknowns), the end points stay held. Levenberg-Marquardt damping on dk
  (Marquardt's diagonal scaling) and on P (the point-distance weight mu), a pass kept
  only when the weighted sum of squared misses at the new feet drops; every step is
  shortened so that no gap between neighbouring knots (or the ends) shrinks below
  MIN_GAP_KEPT of itself: the knots stay strictly increasing inside (0, 1).
- starting knots from the jumps of the p-th derivative of the adaptive fit (a knot of
  the sampled curve shows as a cluster of large jumps |C^(p)(u+) - C^(p)(u-)| of a fit
  with many knots; de Boor, A Practical Guide to Splines, XII, uses the same
  derivative to place knots): the clusters are ranked by their summed jump, and the
  count q of interior knots is tried from where the ranked sums fall by a factor
  JUMP_GAP (the knots of the sampled curve stand out), upwards.

The combination (cluster ranking, the count search, the Schur-complement solve with the
tangent-distance metric and held ends) is this project's own.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Sequence, Tuple

import numpy as np

from ..basis.bspline import basis_derivatives
from ..knots import vectors as kv

if TYPE_CHECKING:  # pragma: no cover
    from .fit import _Problem

#: Gauss-Newton passes per knot count at most
MAX_KNOT_PASSES = 40
#: knot counts tried at most (each a free-knot run)
MAX_KNOT_TRIES = 12
#: a pass that lowers the sum of squares by less than this fraction is slow; the run
#: stops after KNOT_SLOW_PASSES slow passes in a row
KNOT_GAIN = 0.1
KNOT_SLOW_PASSES = 3
#: a run stops after KNOT_REJECTS rejected passes in a row, or after one once its
#: largest miss is at the rounding level KNOT_ROUNDOFF (the points' frame is the unit ball)
KNOT_REJECTS = 8
KNOT_ROUNDOFF = 1e-13
#: Marquardt damping of the knot unknowns (and the point-distance weight mu of the control
#: points): first value, bounds, factors after a rejected and an accepted pass
KNOT_DAMPING_START = 1e-2
KNOT_DAMPING_MIN = 1e-12
KNOT_DAMPING_MAX = 1e6
KNOT_DAMPING_UP = 4.0
KNOT_DAMPING_DOWN = 3.0
#: a knot moves by at most this fraction of the smaller gap beside it per pass
MAX_KNOT_MOVE = 0.3
#: central-difference step for dC/dk, as a fraction of the smaller neighbouring gap
KNOT_DIFF_STEP = 1e-5
#: the window of the smoothed jump (a fraction of the parameter range: knots of the
#: sampled curve closer than this show as one) and the grid steps per window
JUMP_WINDOW = 0.02
JUMP_GRID = 4
#: the ranked jump clusters: a fall by this factor separates the sampled curve's knots
JUMP_GAP = 8.0


def knot_jacobian(U: np.ndarray, p: int, P: np.ndarray, t: np.ndarray) -> np.ndarray:
    """dC(t)/dk for each simple interior knot k of U at fixed control points P:
    (len(t), d, q), by central differences (step KNOT_DIFF_STEP times the smaller gap
    beside the knot); only the points in the knot's support [U_(i-p-1), U_(i+p+1)] are
    evaluated (the others do not move)."""
    from .fit import _values
    inner = np.arange(p + 1, len(U) - p - 1)
    G = np.zeros((len(t), P.shape[1], len(inner)))
    for j, i in enumerate(inner):
        h = KNOT_DIFF_STEP * min(U[i] - U[i - 1], U[i + 1] - U[i])
        sel = np.flatnonzero((t >= U[i - p - 1]) & (t <= U[i + p + 1]))
        if not sel.size:
            continue
        Up, Um = U.copy(), U.copy()
        Up[i] += h
        Um[i] -= h
        G[sel, :, j] = (_values(Up, p, P, t[sel], 0)[0] - _values(Um, p, P, t[sel], 0)[0]) / (2.0 * h)
    return G


def _joint_solve(problem: "_Problem", U: np.ndarray, t: np.ndarray, T: np.ndarray, mu: float, lam: float,
                 P0: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """One damped Gauss-Newton step of the module docstring's system: the new control
    points (n, d) and the knot changes dk (q,)."""
    from .fit import _accumulate, _blocks, solve_fixed
    p, Q, w = problem.p, problem.Q, problem.w
    m, d = Q.shape
    n = len(U) - p - 1
    span = kv.find_span(U, p, t, n)
    N = basis_derivatives(U, p, t, span, 0)[0]
    cols = span[:, None] - p + np.arange(p + 1)
    M = (1.0 + mu) * np.eye(d) - T[:, :, None] * T[:, None, :]
    G = knot_jacobian(U, p, P0, t)                                        # (m, d, q)
    q = G.shape[2]
    start, A = _blocks(n, d, p)
    _accumulate(A, start, cols, N, w, d, M)
    A += problem._energies(U, t, n, d, start, A.shape[1])
    MQ = np.einsum("kab,kb->ka", M, Q)
    MG = np.einsum("kab,kbq->kaq", M, G)                                  # (m, d, q)
    rhs = np.zeros((n * d, 1 + q))
    wN = N * w[:, None]
    for a in range(d):
        idx = (cols * d + a).ravel()
        rhs[:, 0] += np.bincount(idx, (wN * MQ[:, a, None]).ravel(), minlength=n * d)
        for j in range(q):
            rhs[:, 1 + j] += np.bincount(idx, (wN * MG[:, a, j, None]).ravel(), minlength=n * d)
    Cm = rhs[:, 1:].copy()
    Dm = np.einsum("k,kaq,kar->qr", w, G, MG)
    e = np.einsum("k,kaq,ka->q", w, G, MQ)
    scalars = np.array([a for a in range(d)] + [(n - 1) * d + a for a in range(d)])
    values = np.zeros((2 * d, 1 + q))
    values[:d, 0], values[d:, 0] = Q[0], Q[-1]
    X = solve_fixed(start, A, rhs, scalars, values)
    S = Dm - Cm.T @ X[:, 1:]
    S = 0.5 * (S + S.T)
    S[np.diag_indices(q)] *= 1.0 + lam
    try:
        dk = np.linalg.solve(S, e - Cm.T @ X[:, 0]) if q else np.zeros(0)
    except np.linalg.LinAlgError:
        dk = np.zeros(q)
    P = (X[:, 0] - X[:, 1:] @ dk).reshape(n, d)
    P[0], P[-1] = Q[0], Q[-1]
    return P, dk


def _ordered_step(inner: np.ndarray, dk: np.ndarray) -> np.ndarray:
    """inner + a dk with the largest a <= 1 that moves no knot by more than MAX_KNOT_MOVE
    of the smaller gap beside it (0 and 1 the outer neighbours): the knots stay strictly
    increasing inside (0, 1) and a step stays where the linearisation holds."""
    gaps = np.diff(np.concatenate([[0.0], inner, [1.0]]))
    room = MAX_KNOT_MOVE * np.minimum(gaps[:-1], gaps[1:])
    big = float(np.max(np.abs(dk) / room, initial=0.0))
    return inner + dk / max(1.0, big)


def _knots(inner: np.ndarray, p: int) -> np.ndarray:
    """The clamped knot vector on [0, 1] with these simple interior knots."""
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


def free_knot_fit(problem: "_Problem", inner: np.ndarray, t: np.ndarray, tol_n: float, counted: np.ndarray
                  ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Interior knots moved from ``inner`` (strictly increasing in (0, 1)) to lower the
    weighted sum of squared distances of the points from the curve (module docstring):
    returns (knots U, control points, parameters, misses at them) of the best pass."""
    from .fit import _feet, _values
    p, Q, w = problem.p, problem.Q, problem.w

    def state(knots_in: np.ndarray, P: np.ndarray, tt: np.ndarray):
        U = _knots(knots_in, p)
        tt = _feet(U, p, P, Q, tt)
        D = _values(U, p, P, tt, 1)
        miss = np.sqrt(((D[0] - Q) ** 2).sum(-1))
        return knots_in, P, tt, miss, float((w * miss ** 2).sum()), D[1]

    U0 = _knots(inner, p)
    best = state(inner, problem.solve(U0, t)[0], t)
    lam, mu, slow, rejects = KNOT_DAMPING_START, 1e-2, 0, 0
    for passes in range(MAX_KNOT_PASSES):
        if best[4] == 0.0:
            break
        length = np.sqrt((best[5] ** 2).sum(-1))
        with np.errstate(divide="ignore", invalid="ignore"):
            T = np.where(length[:, None] > 0.0, best[5] / length[:, None], 0.0)
        P, dk = _joint_solve(problem, _knots(best[0], p), best[2], T, mu, lam, best[1])
        trial = state(_ordered_step(best[0], dk), P, best[2])
        if not trial[4] < best[4]:
            lam, mu = lam * KNOT_DAMPING_UP, min(mu * KNOT_DAMPING_UP, 1.0)
            rejects += 1
            if lam > KNOT_DAMPING_MAX or rejects >= KNOT_REJECTS or float(best[3].max()) <= KNOT_ROUNDOFF:
                break
            continue
        rejects = 0
        gain = 1.0 - trial[4] / best[4]
        best = trial
        lam, mu = max(lam / KNOT_DAMPING_DOWN, KNOT_DAMPING_MIN), max(mu / KNOT_DAMPING_DOWN, 1e-6)
        slow = slow + 1 if gain < KNOT_GAIN else 0
        worst = float(best[3].max())
        if slow >= KNOT_SLOW_PASSES or worst <= KNOT_ROUNDOFF:
            break
    return _knots(best[0], p), best[1], best[2], best[3]


def knot_jumps(U: np.ndarray, p: int, P: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The distinct interior knots u of a clamped curve and the jumps
    |C^(p)(u+) - C^(p)(u-)| of its p-th derivative there (constant per span)."""
    from .fit import _combine
    brk = np.unique(U[p:len(U) - p])
    if len(brk) <= 2 or p == 0:
        return np.zeros(0), np.zeros(0)
    mid = 0.5 * (brk[:-1] + brk[1:])
    span = kv.find_span(U, p, mid, len(P))
    deriv = _combine(basis_derivatives(U, p, mid, span, p)[p][None], P, span - p)[0]
    return brk[1:-1], np.sqrt(((deriv[1:] - deriv[:-1]) ** 2).sum(-1))


def jump_clusters(U: np.ndarray, p: int, P: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Where the p-th derivative of the clamped curve (U, P) on [0, 1] jumps: the smoothed
    jump S(u) = (C^(p-1)(u + W) - 2 C^(p-1)(u) + C^(p-1)(u - W)) / W, W = JUMP_WINDOW (the
    difference of the mean p-th derivatives on either side of u: a jump J at u0 shows as
    the tent J (1 - |u - u0| / W); a fit's wiggles average out), on a grid of step
    W / JUMP_GRID, its local maxima at least W apart taken largest first. Returns
    (positions, sizes |S|), by decreasing size."""
    from .fit import _values
    W = JUMP_WINDOW
    u = np.linspace(W, 1.0 - W, max(2, int(np.ceil((1.0 - 2 * W) / W * JUMP_GRID)) + 1))
    if p == 0 or len(u) < 3:
        return np.zeros(0), np.zeros(0)
    d = p - 1
    S = (_values(U, p, P, u + W, d)[d] - 2.0 * _values(U, p, P, u, d)[d] + _values(U, p, P, u - W, d)[d]) / W
    size = np.sqrt((S * S).sum(-1))
    local = np.flatnonzero((size[1:-1] >= size[:-2]) & (size[1:-1] >= size[2:])) + 1
    order = local[np.argsort(size[local])[::-1]]
    pos: List[float] = []
    mass: List[float] = []
    for i in order:
        if all(abs(u[i] - x) >= W for x in pos):
            pos.append(float(u[i]))
            mass.append(float(size[i]))
    return np.array(pos), np.array(mass)


def first_count(mass: np.ndarray) -> Tuple[Optional[int], float]:
    """The number of ranked jump sizes before their first fall by JUMP_GAP and that
    fall's ratio, or (None, 0) when none falls that much (no knots stand out)."""
    if len(mass) < 2:
        return None, 0.0
    ratio = mass[:-1] / np.maximum(mass[1:], np.finfo(float).tiny)
    big = np.flatnonzero(ratio >= JUMP_GAP)
    return (int(big[0] + 1), float(ratio[big[0]])) if big.size else (None, 0.0)


Guide = Tuple[np.ndarray, np.ndarray, np.ndarray]


def recover_knots(problem: "_Problem", guides: Sequence[Guide], tol_n: float, counted: np.ndarray,
                  most_inner: int) -> Optional[Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """At most ``most_inner`` interior knots within tol_n by free-knot runs
    (:func:`free_knot_fit`). The last of the guides, fits (U, P, t) of the points (t
    their parameters), gives the start: its ranked jumps (:func:`jump_clusters`) before
    their first fall by JUMP_GAP; on success a knot
    at a time is dropped (the one with the smallest jump of the p-th derivative on the
    last success) while the runs stay within tol_n, on failure the next jump is added.
    Without such a fall only a single span is tried.
    MAX_KNOT_TRIES runs at most. Returns (U, P, t, misses) of the fewest knots whose
    every counted miss (at the feet: an upper bound of the distance) is within tol_n,
    or None."""
    p = problem.p
    U, P, start = guides[-1]
    pos, mass = jump_clusters(U, p, P)
    q = first_count(mass)[0]
    if q is None or q > most_inner:
        pos, q = np.zeros(0), 0
    found = None
    inner = np.sort(pos[:q])
    for _ in range(MAX_KNOT_TRIES):
        run = free_knot_fit(problem, inner, start, tol_n, counted)
        if float(run[3][counted].max()) <= tol_n:
            found, start = run, run[2]
            if q == 0:
                break
            inner = np.delete(run[0][p + 1:-p - 1], int(np.argmin(knot_jumps(run[0], p, run[1])[1])))
            q -= 1
        elif found is not None or q + 1 > min(most_inner, len(pos)):
            break
        else:
            q += 1
            inner = np.sort(pos[:q])
    return found
