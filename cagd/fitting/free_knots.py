"""Knot recovery for :func:`cagd.fit_curve` (issue 17): fewer control points by moving
the interior knots, so that points sampled from a B-spline can come back as that B-spline.

An adaptive fit (knots placed by equidistributing the error, :mod:`cagd.fitting.fit`)
needs many more control points than the curve the points came from, whose knots it
cannot hit. This stage tries smaller counts with the interior knots as unknowns:

- free-knot least squares (Jupp, SIAM J. Numer. Anal. 15(2), 1978; de Boor & Rice,
  "Least squares cubic spline approximation II: variable knots", Purdue CSD TR 21,
  1968; Piegl & Tiller, The NURBS Book, 9.4 for the fixed-knot problem): the control
  points P and the knot changes dk solve one Gauss-Newton system per pass,

      [ A     C ] [ P  ]   [ B^T M Q ]
      [ C^T   D ] [ dk ] = [ G^T M Q ],   A = B^T M B, C = B^T M G, D = G^T M G,

  B the basis matrix at the points' parameters, G = dC/dk the curve's change with each
  interior knot at fixed control points (:func:`knot_jacobian`, exact), M the
  tangent-distance metric of :meth:`cagd.fitting.fit._Problem.solve` (the points'
  parameters eliminated: Wang, Pottmann & Liu, ACM TOG 25(2), 2006); the banded A is
  eliminated first (a Schur complement in the few knot unknowns), the end points stay
  held. Levenberg-Marquardt damping on dk (Marquardt's diagonal scaling) and on P (the
  point-distance weight mu), a pass kept only when the weighted sum of squared misses at
  the new feet drops; no knot moves by more than MAX_KNOT_MOVE of the smaller gap beside
  it, so the knots stay strictly increasing inside (0, 1). Before the knots move, the
  parameters settle on the starting knots (the fixed-knot fit's parameter correction).
- where to start: the jumps of the p-th derivative of the adaptive fit (a knot of the
  sampled curve shows as a jump of C^(p); de Boor, A Practical Guide to Splines, XII,
  places knots by the same derivative), smoothed and ranked; when the ranked sizes fall
  by JUMP_GAP the jumps before the fall are the knots tried first; and, for a tol near
  the data's precision, the points' own polynomial pieces (:mod:`cagd.fitting.pieces`:
  the knots and, above all, the parameters of the sampled curve, joined piece to
  piece), then a search over the counts from a single span upwards, by knot
  insertion where the misses are (Schwetlick & Schuetze, BIT 35, 1995) and equally
  spaced knots; a count that gains much also tries its closest two knots merged.
- a count is accepted only when every point is within tol at its foot (an upper bound
  of the certified distance that :func:`cagd.fitting.fit._measured` reports after).

Limits (measured, tol 1e-9, centripetal start, random sample parameters,
``python -m benchmarks.knot_recovery``): of 16 random fair cubics and quartics with 4-7
control points all 16 come back (1e-12), with 5-12 control points 16 of 16 (seeds 0 and
1; 14 of 16 with seed 0 before the search also started from the feet of a growth run
again, :func:`cagd.fitting.fit._fit_all`); with their interior knots uniformly random
(``--uneven``: two may be a thousandth apart) 12 and 11 of 16 (11 and 10 before; 7 and 9
without the polynomial pieces, which segment cubics only), the others quartics, or
cubics with three knots among a dozen points, whose shape the points do not fix; the
runs end in a local minimum of the knots (free-knot least squares is not convex: Jupp
1978) within the stage's pass budget (seconds). The
point-distance weight mu may fall to KNOT_DAMPING_MIN: at fit.py's floor of 1e-6 it
outweighed the tangent distance along the valley where the knots and the parameters
slide together (a step there changes the shape by ~1e-4 of the knot move), and the runs
crawled at 3% a pass.
The combination (jump ranking, the count search, the Schur-complement solve with the
tangent-distance metric and held ends, the exact knot derivative through de Boor's
algorithm) is this project's own.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Tuple

import numpy as np

from ..basis.bspline import basis_derivatives
from ..knots import vectors as kv

if TYPE_CHECKING:  # pragma: no cover
    from .fit import _Problem

#: Gauss-Newton passes per knot count at most
MAX_KNOT_PASSES = 250
#: Gauss-Newton passes of the whole stage at most (its time: each pass is a banded solve
#: and a few evaluations of the points)
MAX_STAGE_PASSES = 400
#: ... of which the guided start (the jumps of the adaptive fit) may take this many
GUIDED_PASSES = 100
#: knot counts tried at most (each a free-knot run)
MAX_KNOT_TRIES = 12
#: a pass that lowers the sum of squares by less than this fraction is slow; the run
#: stops after KNOT_SLOW_PASSES slow passes in a row
KNOT_GAIN = 0.02
KNOT_SLOW_PASSES = 3
#: a run stops after KNOT_REJECTS rejected passes in a row, or after one once its
#: largest miss is at the rounding level KNOT_ROUNDOFF (the points' frame is the unit ball)
KNOT_REJECTS = 8
KNOT_ROUNDOFF = 1e-13
#: Marquardt damping of the knot unknowns (and the point-distance weight mu of the control
#: points, whose floor is KNOT_DAMPING_MIN too): first value, bounds, factors after a
#: rejected and an accepted pass
KNOT_DAMPING_START = 1e-2
KNOT_DAMPING_MIN = 1e-12
KNOT_DAMPING_MAX = 1e6
KNOT_DAMPING_UP = 4.0
KNOT_DAMPING_DOWN = 3.0
#: the first point-distance weight mu of a run (small: a larger one holds the parameters
#: back where they must slide along the curve)
POINT_WEIGHT_START = 1e-6
#: a knot moves by at most this fraction of the smaller gap beside it per pass
MAX_KNOT_MOVE = 0.3
#: the window of the smoothed jump (a fraction of the parameter range: knots of the
#: sampled curve closer than this show as one) and the grid steps per window
JUMP_WINDOW = 0.02
JUMP_GRID = 4
#: the ranked jump clusters: a fall by this factor separates the sampled curve's knots
JUMP_GAP = 8.0


def knot_jacobian(U: np.ndarray, p: int, P: np.ndarray, t: np.ndarray) -> np.ndarray:
    """dC(t)/dk for each interior knot k of the clamped U at fixed control points P:
    (len(t), d, q), exact (:func:`local_knot_jacobian`, scattered into the q columns)."""
    n, d = P.shape
    q = len(U) - 2 * (p + 1)
    G = np.zeros((len(t), d, max(q, 0)))
    if q <= 0 or p == 0:
        return G
    L, k = local_knot_jacobian(U, p, P, t)
    rows, js = np.nonzero(k >= 0)
    G[rows, :, k[rows, js]] = L[rows, :, js]
    return G


def local_knot_jacobian(U: np.ndarray, p: int, P: np.ndarray, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """dC(t)/dK_j for the 2p knots K_j = U_(s-p+1+j) of each point's span s at fixed control
    points P, the only knots C(t) depends on: (values (len(t), d, 2p), the interior index
    of each K_j (len(t), 2p), -1 for an end knot), p >= 1; exact: de Boor's algorithm
    (Piegl & Tiller A5.1's triangle; The NURBS Book 3.2) differentiated forward through
    its ratios alpha = (t - a) / (b - a), at once for all points (d alpha / da =
    (t - b) / (b - a)^2, d alpha / db = -(t - a) / (b - a)^2). O(len(t) p^2) work and
    memory, whatever the number of knots."""
    n, d = P.shape
    q = len(U) - 2 * (p + 1)
    s = kv.find_span(U, p, t, n)
    K = U.take(s - p + 1 + np.arange(2 * p)[:, None])                   # (2p, m): U_(s-p+1+j)
    # the points last (every operation's inner loop runs along them, not along d)
    D = np.ascontiguousarray(P.T).take(s - p + np.arange(p + 1)[:, None], axis=1).transpose(1, 0, 2).copy()
    dD = np.zeros((p + 1, 2 * p, d, len(t)))                            # d/dK_j of each D_i, (p + 1, m, d) above
    for r in range(1, p + 1):
        for i in range(p, r - 1, -1):
            a, b = K[i - 1], K[p + i - r]                                # U_(s-p+i), U_(s+i+1-r)
            h = b - a
            alpha = (t - a) / h
            diff = D[i] - D[i - 1]                                      # (d, m)
            dD[i] *= alpha
            dD[i] += (1.0 - alpha) * dD[i - 1]
            dD[i, i - 1] += (t - b) / h ** 2 * diff
            dD[i, p + i - r] -= (t - a) / h ** 2 * diff
            D[i] = D[i - 1] + alpha * diff
    k = s[:, None] - p + 1 + np.arange(2 * p) - (p + 1)                 # interior index of K_j
    return dD[p].transpose(2, 1, 0), np.where((k >= 0) & (k < q), k, -1)


def _joint_solve(problem: "_Problem", U: np.ndarray, t: np.ndarray, T: np.ndarray, mu: float, lam: float,
                 P0: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """One damped Gauss-Newton step of the module docstring's system: the new control
    points (n, d) and the knot changes dk (q,)."""
    from .fit import _accumulate, _blocks, solve_fixed, span_sums
    p, Q, w = problem.p, problem.Q, problem.w
    m, d = Q.shape
    n = len(U) - p - 1
    span = kv.find_span(U, p, t, n)
    N = basis_derivatives(U, p, t, span, 0)[0]
    cols = span[:, None] - p + np.arange(p + 1)
    M = (1.0 + mu) * np.eye(d) - T[:, :, None] * T[:, None, :]
    q = max(len(U) - 2 * (p + 1), 0)
    G, k = local_knot_jacobian(U, p, P0, t) if q else (np.zeros((m, d, 0)), np.zeros((m, 0), np.intp))
    G = np.where(k[:, None, :] >= 0, G, 0.0)                              # (m, d, 2p): end knots held
    k = np.maximum(k, 0)
    start, A = _blocks(n, d, p)
    _accumulate(A, start, cols, N, w, d, M)
    MQ = np.einsum("kab,kb->ka", M, Q)
    MG = np.einsum("kab,kbj->kaj", M, G)                                  # (m, d, 2p)
    # per span (its points share their p + 1 poles and 2p knots): B^T M [Q G] and
    # G^T M [G Q], summed over the span's points by matrix products, scattered once per span
    order = np.argsort(span, kind="stable")
    s_sorted = span.take(order)
    cut = np.flatnonzero(np.r_[True, s_sorted[1:] != s_sorted[:-1]])
    first = order[cut]
    wN = (N * w[:, None]).take(order, axis=0)
    QG = np.concatenate([MQ[:, :, None], MG], axis=2)                     # (m, d, 1 + 2p)
    B = span_sums(cut, wN[:, None, :], QG.reshape(m, 1, -1).take(order, axis=0))
    B = B.reshape(len(cut), p + 1, d, QG.shape[2])                       # (spans, pole, coordinate, [Q, knots])
    wG = np.concatenate([MG, MQ[:, :, None]], axis=2) * w[:, None, None]
    E = span_sums(cut, G.take(order, axis=0), wG.take(order, axis=0))   # (spans, 2p, 2p + 1)
    row = cols[first][:, :, None] * d + np.arange(d)                      # (spans, p + 1, d)
    kk = k[first]                                                         # (spans, 2p)
    rhs = np.zeros((n * d, 1 + q))
    rhs[:, 0] = np.bincount(row.ravel(), B[..., 0].ravel(), minlength=n * d)
    # C = B^T M G and D = G^T M G: each point touches its p + 1 poles and 2p knots only
    cell = (row[:, :, :, None] * q + kk[:, None, None, :]).ravel()
    rhs[:, 1:] = np.bincount(cell, B[..., 1:].ravel(), minlength=n * d * q).reshape(n * d, q)
    Cm = rhs[:, 1:]
    pair = (kk[:, :, None] * q + kk[:, None, :]).ravel()
    Dm = np.bincount(pair, E[:, :, :-1].ravel(), minlength=q * q).reshape(q, q)
    e = np.bincount(kk.ravel(), E[:, :, -1].ravel(), minlength=q)
    scalars = np.array([a for a in range(d)] + [(n - 1) * d + a for a in range(d)])
    values = np.zeros((2 * d, 1 + q))
    values[:d, 0], values[d:, 0] = Q[0], Q[-1]
    X = problem.normal_solve(U, t, A, start, lambda band: solve_fixed(start, band, rhs.copy(), scalars, values))[1]
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


def _ordered_step(inner: np.ndarray, dk: np.ndarray, move: float = MAX_KNOT_MOVE, directed: bool = False
                  ) -> np.ndarray:
    """inner + a dk with the largest a <= 1 that moves no knot by more than ``move`` (< 0.5)
    of the smaller gap beside it (``directed``: of the gap it moves into; two knots then
    close a gap by at most 2 move of it) (0 and 1 the outer neighbours): the knots stay
    strictly increasing inside (0, 1) and a step stays where the linearisation holds."""
    gaps = np.diff(np.concatenate([[0.0], inner, [1.0]]))
    room = move * (np.where(dk > 0, gaps[1:], gaps[:-1]) if directed else np.minimum(gaps[:-1], gaps[1:]))
    big = float(np.max(np.abs(dk) / room, initial=0.0))
    return inner + dk / max(1.0, big)


def _knots(inner: np.ndarray, p: int) -> np.ndarray:
    """The clamped knot vector on [0, 1] with these interior knots."""
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


def free_knot_fit(problem: "_Problem", inner: np.ndarray, t: np.ndarray, tol_n: float, counted: np.ndarray,
                  budget: Optional[List[int]] = None, patience: int = KNOT_SLOW_PASSES,
                  far: float = 0.0) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Interior knots moved from ``inner`` (strictly increasing in (0, 1)) to lower the
    weighted sum of squared distances of the points from the curve (module docstring):
    returns (knots U, control points, parameters, misses at them) of the best pass. The
    knots stay where they are until the parameters have settled (the fixed-knot fit of
    :func:`cagd.fitting.fit._fit_on`, its passes until they gain little: moving knots
    against poor parameters leads them astray). Each free-knot pass takes one from
    ``budget[0]``; none left, the run ends. The run stops after ``patience`` slow passes
    in a row, or KNOT_SLOW_PASSES once its largest miss is above ``far`` times tol_n (a
    run near tol in a flat valley may still get there; one far from it will not)."""
    from .fit import _feet, _fit_on, _jet
    p, Q, w = problem.p, problem.Q, problem.w

    def state(knots_in: np.ndarray, P: np.ndarray, tt: np.ndarray):
        U = _knots(knots_in, p)
        jet = _feet(U, p, P, Q, _jet(U, p, tt))
        D = jet.values(P, 1)
        miss = np.sqrt(((D[0] - Q) ** 2).sum(-1))
        return knots_in, P, jet.t, miss, float((w * miss ** 2).sum()), D[1]

    settled, t, _ = _fit_on(problem, _knots(inner, p), t, np.inf)
    best = state(inner, settled.control_points, t)
    lam, mu, slow, rejects = KNOT_DAMPING_START, POINT_WEIGHT_START, 0, 0
    for _ in range(MAX_KNOT_PASSES):
        if budget is not None:
            if budget[0] <= 0:
                break
            budget[0] -= 1
        if float(best[3].max()) <= KNOT_ROUNDOFF:
            break
        length = np.sqrt((best[5] ** 2).sum(-1))
        with np.errstate(divide="ignore", invalid="ignore"):
            T = np.where(length[:, None] > 0.0, best[5] / length[:, None], 0.0)
        P, dk = _joint_solve(problem, _knots(best[0], p), best[2], T, mu, lam, best[1])
        trial = state(_ordered_step(best[0], dk), P, best[2])
        if not trial[4] < best[4]:
            lam, mu = lam * KNOT_DAMPING_UP, min(mu * KNOT_DAMPING_UP, 1.0)
            rejects += 1
            if lam > KNOT_DAMPING_MAX or rejects >= KNOT_REJECTS:
                break
            continue
        rejects = 0
        gain = 1.0 - trial[4] / best[4]
        best = trial
        lam, mu = max(lam / KNOT_DAMPING_DOWN, KNOT_DAMPING_MIN), max(mu / KNOT_DAMPING_DOWN, KNOT_DAMPING_MIN)
        slow = slow + 1 if gain < KNOT_GAIN else 0
        if slow >= patience or (slow >= KNOT_SLOW_PASSES and float(best[3].max()) > far * tol_n):
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


Run = Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _within(run: Run, tol_n: float, counted: np.ndarray) -> bool:
    """Whether every counted miss of the run is within tol_n."""
    return float(np.max(run[3], where=counted, initial=0.0)) <= tol_n


def recover_knots(problem: "_Problem", guide: Guide, initial: np.ndarray, tol_n: float, counted: np.ndarray,
                  most_inner: int, search: bool) -> Optional[Run]:
    """At most ``most_inner`` interior knots within tol_n by free-knot runs
    (:func:`free_knot_fit`), or None. Three ways, the last two only with ``search``:

    - guided: the guide (U, P, t), a fit of the points with t their parameters on it,
      has ranked jumps of the p-th derivative (:func:`jump_clusters`) that fall by
      JUMP_GAP: the jumps before the fall start a run; on success a knot at a time is
      dropped (the smallest jump on the last success) while the runs stay within tol_n,
      on failure the next jump is added; MAX_KNOT_TRIES runs at most;
    - segmented (:func:`_segmented`): from the points' own polynomial pieces;
    - searched (:func:`_search`): counts from a single span upwards, from each set of
      first parameters in ``initial`` (s, m) in turn until one succeeds, each with
      MAX_STAGE_PASSES - GUIDED_PASSES passes and those the guided way left.

    Returns (U, P, t, misses) of the fewest knots found whose every counted miss (at
    the feet: an upper bound of the distance) is within tol_n."""
    p = problem.p
    budget = [GUIDED_PASSES]
    U, P, start = guide
    pos, mass = jump_clusters(U, p, P)
    q = first_count(mass)[0]
    found = None
    if q is not None and q <= most_inner:
        inner = np.sort(pos[:q])
        for _ in range(MAX_KNOT_TRIES):
            run = free_knot_fit(problem, inner, start, tol_n, counted, budget)
            if _within(run, tol_n, counted):
                found, start = run, run[2]
                if q == 0:
                    break
                inner = _without_least(run, p)
                q -= 1
            elif found is not None or q + 1 > min(most_inner, len(pos)):
                break
            else:
                q += 1
                inner = np.sort(pos[:q])
    if found is None and search:
        found = _segmented(problem, tol_n, counted, most_inner)
    passes = budget[0] + MAX_STAGE_PASSES - GUIDED_PASSES
    for start in initial if search else ():
        if found is not None:
            break
        found = _search(problem, start, tol_n, counted, min(most_inner, MAX_SEARCH_KNOTS), [passes])
    return found


def _segmented(problem: "_Problem", tol_n: float, counted: np.ndarray, most_inner: int
               ) -> Optional[Run]:
    """A run from the points' polynomial pieces (:mod:`cagd.fitting.pieces`: knots and
    parameters near the sampled curve's own), or None. A start whose joins found a knot
    of multiplicity 2 .. p (C^(p-2) .. C^0 there: Bezier pieces joined with a kink) keeps
    its knots: the least squares on them, with parameter correction (the free-knot run
    moves simple knots only), kept when within tol; otherwise the free-knot run from the
    joins with simple knots only, thinned of the knots it does not need (SEGMENT_PASSES
    for the run, as many for the thinning)."""
    from .fit import _fit_on
    from .pieces import PIECE_FAR, PIECE_PATIENCE, joined_start, polynomial_pieces
    pieces = polynomial_pieces(problem, tol_n, counted)
    if pieces is None:
        return None
    start = joined_start(problem, pieces, tol_n, counted, problem.p)
    if start is not None and len(start[0]) <= most_inner and np.any(np.diff(start[0]) == 0.0):
        fitted, t, miss = _fit_on(problem, _knots(start[0], problem.p), start[1], tol_n)
        run = (np.asarray(fitted.knots), fitted.control_points, t, miss)
        if _within(run, tol_n, counted):
            return run
        start = joined_start(problem, pieces, tol_n, counted)
    if start is None or len(start[0]) > most_inner:
        return None
    budget = [SEGMENT_PASSES]
    run = free_knot_fit(problem, start[0], start[1], tol_n, counted, budget, PIECE_PATIENCE, PIECE_FAR)
    while not _within(run, tol_n, counted) and budget[0] > 0 and len(run[0]) > 2 * (problem.p + 1):
        # a knot too many (a join of two runs of one polynomial) stalls the run: the one
        # whose p-th derivative jumps least is dropped while that lowers the largest miss
        trial = free_knot_fit(problem, _without_least(run, problem.p), run[2], tol_n, counted, budget,
                              PIECE_PATIENCE, PIECE_FAR)
        if not float(trial[3][counted].max()) < float(run[3][counted].max()):
            break
        run = trial
    if not _within(run, tol_n, counted):
        return None
    return _thinned(problem, run, tol_n, counted, [SEGMENT_PASSES], PIECE_PATIENCE, PIECE_FAR)


def _without_least(run: Run, p: int) -> np.ndarray:
    """The run's interior knots but the one whose p-th derivative jumps least."""
    return np.delete(run[0][p + 1:-p - 1], int(np.argmin(knot_jumps(run[0], p, run[1])[1])))


#: passes of the run from the polynomial pieces, and of its thinning, at most
SEGMENT_PASSES = 100


def _thinned(problem: "_Problem", run: Run, tol_n: float, counted: np.ndarray, budget: List[int],
             patience: int = KNOT_SLOW_PASSES, far: float = 0.0) -> Run:
    """``run`` (within tol_n) with a knot at a time dropped, the one whose p-th derivative
    jumps least, and the rest moved again (:func:`free_knot_fit` with ``patience`` and
    ``far``), while the runs stay within tol_n and passes are left in ``budget``."""
    p = problem.p
    while len(run[0]) > 2 * (p + 1) and budget[0] > 0:
        trial = free_knot_fit(problem, _without_least(run, p), run[2], tol_n, counted, budget, patience, far)
        if not _within(trial, tol_n, counted):
            break
        run = trial
    return run


#: the searched way tries at most this many interior knots (a 12-pole cubic has 8)
MAX_SEARCH_KNOTS = 10


def _search(problem: "_Problem", initial: np.ndarray, tol_n: float, counted: np.ndarray, most: int,
            budget: List[int]) -> Optional[Run]:
    """Counts q = 0, 1, ..., ``most`` of interior knots, two starts each: the best run
    of the count before with one knot inserted where its misses are
    (:func:`_insert_where`; knot insertion with free-knot optimisation, as in
    Schwetlick & Schuetze, BIT 35, 1995) and q equally spaced knots with the points'
    initial parameters. A count whose best run misses MERGE_GAIN times less than the
    count before also tries q - 1 knots: its closest two merged (:func:`_merged`; a
    knot of the sampled curve found as two). After a run within tol_n, the closest two
    knots are merged while the runs stay within tol_n. Returns the last run within tol_n,
    or None."""
    p, w = problem.p, problem.w * counted

    def ss(run: Run) -> float:
        return float((w * run[3] ** 2).sum())

    prev: Optional[Run] = None
    found: Optional[Run] = None
    for q in range(most + 1):
        if budget[0] <= 0 or found is not None:
            break
        starts = [(np.zeros(0), initial)] if prev is None else [
            (_insert_where(prev[0][p + 1:-p - 1], prev[2], w * prev[3] ** 2), prev[2]),
            (np.linspace(0.0, 1.0, q + 2)[1:-1], initial)]
        best: Optional[Run] = None
        for inner, t in starts:
            run = free_knot_fit(problem, inner, t, tol_n, counted, budget)
            if _within(run, tol_n, counted):
                found = run
                break
            if best is None or ss(run) < ss(best):
                best = run
        if found is None and best is not None and prev is not None and q >= 2 \
                and ss(best) * MERGE_GAIN ** 2 <= ss(prev):
            run = free_knot_fit(problem, _merged(best[0][p + 1:-p - 1], best[0], p, best[1]), best[2], tol_n,
                                counted, budget)
            if _within(run, tol_n, counted):
                found = run
        prev = best
    while found is not None and len(found[0]) > 2 * (p + 1) and budget[0] > 0:
        run = free_knot_fit(problem, _merged(found[0][p + 1:-p - 1], found[0], p, found[1]), found[2], tol_n,
                            counted, budget)
        if not _within(run, tol_n, counted):
            break
        found = run
    return found


#: a count's best run missing this many times less than the count before's also tries
#: one knot fewer (two close knots merged)
MERGE_GAIN = 10.0


def _merged(inner: np.ndarray, U: np.ndarray, p: int, P: np.ndarray) -> np.ndarray:
    """``inner`` with its closest two neighbours (0 and 1 counted as neighbours) made one,
    at their mean weighted by the jumps of the p-th derivative of (U, P) there (a single
    knot next to an end is dropped)."""
    brk = np.concatenate([[0.0], inner, [1.0]])
    i = int(np.argmin(np.diff(brk)))                 # the gap brk[i] .. brk[i + 1]
    if i == 0:
        return inner[1:]
    if i == len(inner):
        return inner[:-1]
    J = knot_jumps(U, p, P)[1]
    a, b = J[i - 1], J[i]
    at = (a * inner[i - 1] + b * inner[i]) / (a + b) if a + b > 0.0 else 0.5 * (inner[i - 1] + inner[i])
    return np.concatenate([inner[:i - 1], [at], inner[i + 1:]])


def _insert_where(inner: np.ndarray, t: np.ndarray, e2: np.ndarray) -> np.ndarray:
    """``inner`` with one more knot: in the span (of 0, inner, 1) holding the largest sum
    of weighted squared misses e2, at their mean parameter, kept within the span's middle
    half."""
    brk = np.concatenate([[0.0], inner, [1.0]])
    span = np.clip(np.searchsorted(brk, t, side="right") - 1, 0, len(brk) - 2)
    score = np.bincount(span, e2, minlength=len(brk) - 1)
    s = int(np.argmax(score))
    a, b = brk[s], brk[s + 1]
    at = float((e2 * t)[span == s].sum() / score[s]) if score[s] > 0.0 else 0.5 * (a + b)
    return np.sort(np.append(inner, np.clip(at, a + 0.25 * (b - a), b - 0.25 * (b - a))))
