"""The polynomial pieces of points sampled from a B-spline (issue 17, exactness): a start
for the free-knot run of :mod:`cagd.fitting.free_knots` with the knots near the curve's
own and, above all, the points' parameters near the curve's own.

Measured (16 random cubics and quartics with uneven knots, 300-1000 points at random
places): the free-knot run converges from knots 1% off when the points' parameters are
the curve's (15 of 15), but from the curve's exact knots with centripetal parameters in
only 9 of 15: the parameters of points at random places are no smooth function of the
curve's own. A B-spline is a polynomial of degree p between its knots, and a polynomial
curve fitted to its own points with parameter correction takes their parameters up to
an affine map; so:

- pieces (:func:`polynomial_pieces`): from the first point, runs of consecutive points
  grow (doubling, then bisecting to PIECE_STRIDE points) while one Bezier curve fits
  them within tol (a free-knot run with no interior knot, warm-started from the run
  before); a run of PIECE_POINTS that no Bezier curve fits holds a knot, and the next
  run starts PIECE_STRIDE points later;
- joins (:func:`_join`): between two pieces, in the left piece's variable s, the right
  piece is B_R((s - alpha) / beta) and, with k knots t_i between them (C^(p-1) there,
  the p-th derivative jumping), B_R((s - alpha) / beta) - B_L(s) = sum_i c_i
  (s - t_i)^p: (p + 1) d equations in 2 + k + k d unknowns, solved for (alpha, beta, t)
  by Levenberg-Marquardt with the c_i eliminated (variable projection), k = 1 then 2;
  this gives the right piece's map and the knots to rounding; knots whose jump is
  negligible are none (two runs of one polynomial); a gap where one simple knot does
  not join tries one knot of multiplicity r = 2 .. p (C^(p-r): the terms (s - t)^j, j
  > p - r) before two simple knots (which would fit a double knot only nearly), for
  the least squares on those knots (the free-knot run moves simple knots only);
- more knots in a gap (:func:`_local_join`, k = 3, 4): a free-knot run over the rows
  around it; else the speed |dC/dt| carries on across the gap (continuous for p >= 2)
  and the gap gets three knots or more, their surplus dropped after;
- rows between two joined pieces get their feet on the nearer piece's polynomial
  (:func:`_gap_params`), the other rows no piece holds chord length over the speed.

Where no p + 1 points lie between two knots the data do not fix the curve there (a
different curve passes through the same points); such curves do not come back. The
segmentation by polynomial fits and the join by variable projection are this project's
own; the runs' least squares are Piegl & Tiller 9.4.1 with parameter correction (Hoschek
1988), as in :mod:`cagd.fitting.fit`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, NamedTuple, Optional, Tuple

import numpy as np

from ..basis.bernstein import bernstein_to_power
from .free_knots import _within, free_knot_fit

if TYPE_CHECKING:  # pragma: no cover
    from .fit import _Problem

#: degrees segmented (a quartic run of fewer than about 100 points settled in hundreds of
#: passes, or not: false breaks, 10-17 s a fit, none gained)
PIECE_DEGREES = (2, 3)
#: the shortest run tried (points; a run of a few points fits any Bezier curve of its
#: degree, and the parameters of a short run settle slowly: 8 points took 240 passes)
PIECE_POINTS = 16
#: a run of PIECE_POINTS that misses starts again this many points later
PIECE_STRIDE = 4
#: runs fitted at most (each a free-knot run with no interior knot)
MAX_PIECE_FITS = 300
#: passes of one run's fit at most, its patience (slow passes in a row while within
#: PIECE_FAR tol) and what counts as far
PIECE_PASSES = 150
PIECE_PATIENCE = 10
PIECE_FAR = 100.0
#: a join (:func:`_join`): Levenberg-Marquardt steps at most, the relative residual
#: that accepts it (measured over 28 joins of 5 random cubics: 1e-11 to 4e-6 for a knot
#: found as one, 2.5e-2 to 1.1e-1 for two knots tried as one, which then left 4e-11 to
#: 5e-6), its first and largest damping, the difference step (relative) of its
#: Jacobian, the smallest gap (left piece's variable) it starts from; knots tried per gap
JOIN_STEPS = 60
JOIN_RTOL = 1e-4
JOIN_DAMPING = 1e-3
JOIN_DIFF = 1e-7
JOIN_MIN_GAP = 1e-3
JOIN_DAMPING_MAX = 1e8
#: ... the range of the log of the right piece's scale about its start
JOIN_SCALE_RANGE = 5.0
#: ... and the residual at which it stops early (rounding)
JOIN_ROUNDOFF = 1e-13
JOIN_KNOTS = 2
#: a knot of a join whose jump makes less than this share of the pieces' size over them
#: is none (two pieces of one polynomial, a run that stopped short: 2e-6 against 0.19 to
#: 170 for the knots of the curves)
JOIN_JUMP_RTOL = 1e-4
#: more knots in one gap: a free-knot run on the rows within LOCAL_ROWS of it, with up to
#: LOCAL_KNOTS knots
LOCAL_ROWS = 2 * PIECE_POINTS
LOCAL_KNOTS = 4
#: Newton steps of the rows beyond a piece onto its polynomial (:func:`_feet`)
FEET_STEPS = 8
TINY_DIAG = 1e-300           # keeps the damped diagonal positive where a column vanishes


class Piece(NamedTuple):
    """Rows a .. b - 1 fitted by one Bezier curve (poles (p + 1, d)), their parameters s
    in [0, 1] on it."""
    a: int
    b: int
    poles: np.ndarray
    s: np.ndarray


def _power(P: np.ndarray) -> np.ndarray:
    """Power coefficients c (p + 1, d) of the Bezier curve with poles P, B(s) = sum_j c_j s^j
    (:func:`cagd.basis.bernstein.bernstein_to_power`)."""
    return bernstein_to_power(len(P) - 1) @ P


def _at(C: np.ndarray, s: np.ndarray) -> np.ndarray:
    """B(s) (len(s), d) at every s (outside [0, 1] too: the polynomial) from its power
    coefficients C (Farin, Curves and Surfaces for CAGD, 5.3)."""
    return np.vander(np.asarray(s, dtype=np.float64), len(C), increasing=True) @ C


def _speed(P: np.ndarray, end: int) -> float:
    """|B'| at the start (end 0: p |P_1 - P_0|) or the end (end 1: p |P_p - P_(p-1)|) of
    the Bezier curve with poles P."""
    return (len(P) - 1) * float(np.linalg.norm(P[1] - P[0] if end == 0 else P[-1] - P[-2]))


def polynomial_pieces(problem: "_Problem", tol_n: float, counted: np.ndarray) -> Optional[List[Piece]]:
    """The points' polynomial pieces (module docstring), or None: a degree not in
    PIECE_DEGREES, fewer than 2 PIECE_POINTS points or the fits run out (MAX_PIECE_FITS)."""
    p, Q = problem.p, problem.Q
    m = len(Q)
    least = PIECE_POINTS
    if p not in PIECE_DEGREES or m < 2 * least:
        return None
    fits = [0]

    def fitted(a: int, b: int, start: Optional[Piece]) -> Optional[Piece]:
        """The Bezier fit of rows a .. b - 1 within tol_n, or None."""
        fits[0] += 1
        rows = np.arange(a, b)
        if not counted[rows].any():
            return None
        s0 = _extended(Q, rows, start) if start is not None else _chord(Q[rows])
        if s0 is None:
            return None
        run = free_knot_fit(problem.subset(rows), np.zeros(0), s0, tol_n, counted[rows], [PIECE_PASSES],
                            PIECE_PATIENCE, PIECE_FAR)
        if not _within(run, tol_n, counted[rows]):
            return None
        return Piece(a, b, run[1], run[2])

    pieces: List[Piece] = []
    a = 0
    while a <= m - least:
        if fits[0] >= MAX_PIECE_FITS:
            return None
        good = fitted(a, a + least, None)
        if good is None:
            a += PIECE_STRIDE
            continue
        hi = None                                          # rows a .. hi - 1 do not fit
        while good.b < m:
            trial = fitted(a, min(m, a + 2 * (good.b - a)), good)
            if trial is None:
                hi = min(m, a + 2 * (good.b - a))
                break
            good = trial
        while hi is not None and hi - good.b > PIECE_STRIDE and fits[0] < MAX_PIECE_FITS:
            trial = fitted(a, (good.b + hi) // 2, good)
            if trial is None:
                hi = (good.b + hi) // 2
            else:
                good = trial
        pieces.append(good)
        a = good.b
    if not pieces:
        return None
    if pieces[0].a > 0:                 # the first rows: the first piece grown back to them
        head = fitted(0, pieces[0].b, pieces[0])
        if head is not None:
            pieces[0] = head
    return pieces


def _arc(Q: np.ndarray) -> np.ndarray:
    """Cumulative chord length along the rows Q (0 at the first)."""
    return np.concatenate([[0.0], np.cumsum(np.sqrt((np.diff(Q, axis=0) ** 2).sum(-1)))])


def _chord(Q: np.ndarray) -> Optional[np.ndarray]:
    """Chord-length parameters of the rows Q in [0, 1], or None (coincident ends)."""
    c = _arc(Q)
    return c / c[-1] if c[-1] > 0.0 else None


def _extended(Q: np.ndarray, rows: np.ndarray, piece: Piece) -> Optional[np.ndarray]:
    """Parameters for the run ``rows`` (consecutive, ending at or after the piece's first
    row) from the piece's: its own where it has them, before and beyond it chord length
    over its speed at that end; scaled to [0, 1]."""
    a, b = int(rows[0]), int(rows[-1]) + 1
    lo, hi = max(a, piece.a), min(b, piece.b)
    if hi - lo < 2:
        return None
    s = np.empty(b - a)
    s[lo - a:hi - a] = piece.s[lo - piece.a:hi - piece.a]
    for end, rng in ((0, range(lo, a - 1, -1)), (1, range(hi - 1, b))):
        if len(rng) < 2:
            continue
        speed = _speed(piece.poles, end)
        if not speed > 0.0:
            return None
        idx = np.fromiter(rng, dtype=np.intp)
        c = _arc(Q[idx]) / speed
        s[idx - a] = s[idx[0] - a] + (c if end else -c)
        s[idx[1:] - a] = _feet(piece.poles, Q[idx[1:]], s[idx[1:] - a])[0]
    s = s - s[0]
    return s / s[-1] if s[-1] > 0.0 else None


def _feet(P: np.ndarray, Q: np.ndarray, s0: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Parameters of the rows Q on the polynomial of the Bezier curve with poles P
    (extended beyond [0, 1]): FEET_STEPS Newton steps on |B(s) - Q|^2 from s0 (the
    points of one polynomial get their own parameters; chord length over the end speed
    is off by its curvature: 6% over a third of a span, where a run stalled 45 tol
    away), kept only where they lower every distance and keep s0's order. Returns the
    parameters and the squared distances |B(s) - Q|^2 there."""
    C = _power(P)
    C1 = C[1:] * np.arange(1, len(C))[:, None]
    C2 = C1[1:] * np.arange(1, len(C1))[:, None]
    s = s0.copy()
    for _ in range(FEET_STEPS):
        r, d1, d2 = _at(C, s) - Q, _at(C1, s), _at(C2, s)
        h = (d1 * d1).sum(1) + (r * d2).sum(1)
        s = s - np.where(h > 0.0, (r * d1).sum(1) / np.where(h > 0.0, h, 1.0), 0.0)
    miss0 = ((_at(C, s0) - Q) ** 2).sum(1)
    miss = ((_at(C, s) - Q) ** 2).sum(1)
    order = np.sign(s0[-1] - s0[0])
    if not (np.all(np.isfinite(s)) and np.all(miss <= miss0) and np.all(order * np.diff(s) >= 0.0)):
        return s0, miss0
    return s, miss


def _join(left: Piece, right: Piece, p: int, count: int, multiplicity: int = 1
          ) -> Optional[Tuple[float, float, np.ndarray]]:
    """``count`` knots between two pieces (module docstring), in the left piece's variable
    s: the right piece's r = (s - alpha) / beta and the knots t_i with
    B_R((s - alpha) / beta) - B_L(s) = sum_i c_i (s - t_i)^p (the jump of the p-th
    derivative at each knot; C^(p-1) elsewhere), solved for (alpha, beta, t) by
    Gauss-Newton with the c_i eliminated (variable projection: linear least squares at
    2 (p + 1) + count nodes over both pieces), started from the speed ratio. A knot of
    ``multiplicity`` r (C^(p-r) there) has the terms sum_(j = p-r+1..p) c_ij (s - t_i)^j
    (Piegl & Tiller 2.2: a knot of multiplicity r leaves C^(p-r)); at r = p (C^0: the
    pieces' polynomials only meet at t) beta is free and stays at the speed ratio.
    Returns (alpha, beta, knots, each repeated r times) when the relative residual is
    within JOIN_RTOL, else None."""
    PL, PR = left.poles, right.poles
    vL, vR = _speed(PL, 1), _speed(PR, 0)
    if not (vL > 0.0 and vR > 0.0):
        return None
    beta0 = vR / vL                                       # the speed carries on: |B_R'| / beta = |B_L'|
    gap = max(float(np.linalg.norm(PR[0] - PL[-1])) / vL, JOIN_MIN_GAP)
    alpha0 = 1.0 + gap
    z = np.concatenate([[alpha0, np.log(beta0)], 1.0 + gap * np.arange(1, count + 1) / (count + 1)])
    end = alpha0 + beta0
    nodes = np.linspace(0.0, end, 2 * (p + 1) + count)
    CR = _power(PR)
    BL = _at(_power(PL), nodes)
    size = float(np.abs(BL - BL.mean(0)).max())
    # the unknowns stay in a box (a knot with no jump has no gradient and would run away;
    # the right piece's offset within the nodes' reach, its scale within JOIN_SCALE_RANGE
    # of the speed ratio's), so every evaluation stays finite
    lower = np.concatenate([[0.0, z[1] - JOIN_SCALE_RANGE], np.zeros(count)])
    upper = np.concatenate([[end, z[1] + JOIN_SCALE_RANGE], np.full(count, end)])
    powers = np.arange(p - multiplicity + 1, p + 1)
    free_scale = multiplicity == p          # C^0: the scale stays at the speed ratio (it drifted to the box's edge)

    def residual(z: np.ndarray, jumps: bool = False) -> np.ndarray:
        """The relative misfit at the nodes (or, ``jumps``, each knot's share: the largest
        |c_ij| max |s - t_i|^j / size of its terms)."""
        alpha, beta = z[0], np.exp(z[1])
        D = _at(CR, (nodes - alpha) / beta) - BL
        E = ((nodes[:, None] - z[2:][None, :])[:, :, None] ** powers).reshape(len(nodes), -1)
        c, *_ = np.linalg.lstsq(E, D, rcond=None)
        if jumps:
            share = np.linalg.norm(c, axis=1) * np.abs(E).max(axis=0) / size
            return share.reshape(count, multiplicity).max(axis=1)
        return ((D - E @ c) / size).ravel()

    R = residual(z)
    lam = JOIN_DAMPING
    for _ in range(JOIN_STEPS):
        h = JOIN_DIFF * np.maximum(np.abs(z), 1.0)
        Jac = np.stack([np.zeros_like(R) if i == 1 and free_scale else
                        (residual(z + h[i] * np.eye(len(z))[i]) - R) / h[i] for i in range(len(z))], axis=1)
        A = Jac.T @ Jac
        if free_scale:
            A[1, 1] = 1.0                           # (its column is zero: the step keeps beta)
        try:
            with np.errstate(under="ignore"):       # (a column with no gradient: lam * TINY_DIAG)
                step = np.linalg.solve(A + lam * np.diag(np.diag(A) + TINY_DIAG), -Jac.T @ R)
        except np.linalg.LinAlgError:
            break
        trial = np.clip(z + step, lower, upper)
        R2 = residual(trial)
        if np.linalg.norm(R2) < np.linalg.norm(R):
            z, R, lam = trial, R2, lam / 3.0
            if float(np.abs(R).max()) <= JOIN_ROUNDOFF:
                break
        else:
            lam *= 4.0
            if lam > JOIN_DAMPING_MAX:
                break
    if not float(np.abs(R).max()) <= JOIN_RTOL:
        return None
    knots = np.sort(z[2:][residual(z, True) > JOIN_JUMP_RTOL])      # (a knot with no jump may be anywhere)
    if knots.size and not (knots[0] > 0.0 and knots[-1] < z[0] + np.exp(z[1])):
        return None
    return float(z[0]), float(np.exp(z[1])), np.repeat(knots, multiplicity)


def _gap_params(Q: np.ndarray, left: Piece, right: Piece, maps: Tuple[float, float, float, float]
                ) -> Optional[np.ndarray]:
    """Parameters t of the rows between two joined pieces (maps: origin and scale of the
    left and of the right piece, t = origin + scale s): each row's foot on the nearer of
    the two pieces' polynomials (:func:`_feet`, from chord length over the end speed);
    chord alone put a row beside a corner (a C^0 knot) on the wrong side of it, and the
    fit stopped 1.2e-3 off. None where an end speed vanishes."""
    e, a = left.b - 1, right.a
    vL, vR = _speed(left.poles, 1), _speed(right.poles, 0)
    if not (vL > 0.0 and vR > 0.0):
        return None
    rows = Q[e + 1:a]
    c = _arc(Q[e:a + 1])
    sL, dL = _feet(left.poles, rows, left.s[-1] + c[1:-1] / vL)
    sR, dR = _feet(right.poles, rows, right.s[0] - (c[-1] - c[1:-1]) / vR)
    origin, scale, origin_r, scale_r = maps
    return np.where(dL <= dR, origin + scale * sL, origin_r + scale_r * sR)


def _join_kinds(p: int, most: int) -> List[Tuple[int, int]]:
    """(knots, multiplicity) tried at a gap, fewest terms first (count x multiplicity, a
    simple knot before a multiple one): a double knot before two simple ones, which
    would fit it only nearly (two knots close together), three knots at most."""
    kinds = [(1, r) for r in range(1, min(most, p) + 1)] + [(c, 1) for c in range(2, JOIN_KNOTS + 1)]
    return sorted(kinds, key=lambda k: (k[0] * k[1], k[0]))


def _local_join(problem: "_Problem", left: Piece, right: Piece, count: int, tol_n: float, counted: np.ndarray
                ) -> Optional[Tuple[float, float, np.ndarray]]:
    """``count`` knots between two pieces where :func:`_join` has too few equations: a
    free-knot run on the rows within LOCAL_ROWS of the gap (the left piece's parameters,
    the rest by chord over the left piece's end speed; knots spread over the gap), kept
    when every row is within tol_n; the right piece's map from its rows' parameters
    (least squares). As :func:`_join`: (alpha, beta, knots) in the left piece's s."""
    p, Q = problem.p, problem.Q
    e, a = left.b - 1, right.a
    lo, hi = max(left.a, e - LOCAL_ROWS), min(right.b, a + LOCAL_ROWS)
    v = _speed(left.poles, 1)
    if not v > 0.0:
        return None
    s = np.empty(hi - lo)
    s[:e + 1 - lo] = left.s[lo - left.a:]
    s[e - lo:] = left.s[-1] + _arc(Q[e:hi]) / v
    gap_lo, gap_hi = s[e - lo], s[a - lo]
    s0, span = s[0], s[-1] - s[0]
    knots = (gap_lo + (gap_hi - gap_lo) * np.arange(1, count + 1) / (count + 1) - s0) / span
    rows = np.arange(lo, hi)
    run = free_knot_fit(problem.subset(rows), knots, (s - s0) / span, tol_n, counted[rows], [PIECE_PASSES],
                        PIECE_PATIENCE, PIECE_FAR)
    if not _within(run, tol_n, counted[rows]):
        return None
    found = s0 + span * run[0][p + 1:-p - 1]
    sr = s0 + span * run[2][a - lo:]                        # the right rows' s
    beta, alpha = np.polyfit(right.s[:hi - a], sr, 1)
    return float(alpha), float(beta), found


def joined_start(problem: "_Problem", pieces: List[Piece], tol_n: float, counted: np.ndarray,
                 most: int = 1) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(interior knots, parameters of every point) from the pieces, scaled to [0, 1]
    (module docstring); a gap that joins with no simple knot is tried with one knot of
    multiplicity 2 .. ``most``. None where a speed vanishes or the knots would not
    increase (or repeat more than p times)."""
    Q, p = problem.Q, problem.p
    m = len(Q)
    t = np.full(m, np.nan)
    inner: List[float] = []

    def spread(lo: float, hi: float, rows: int, least: int) -> None:
        count = max(least, 1 + rows // PIECE_POINTS)
        inner.extend(lo + (hi - lo) * np.arange(1, count + 1) / (count + 1))

    first = pieces[0]
    scale, origin = 1.0, 0.0                               # t = origin + scale * s on the piece
    t[first.a:first.b] = first.s
    for left, right in zip(pieces, pieces[1:]):
        e, a = left.b - 1, right.a
        joint = None
        for count, r in _join_kinds(p, most):
            joint = _join(left, right, p, count, r)
            if joint is not None:
                break
        for count in range(JOIN_KNOTS + 1, LOCAL_KNOTS + 1):
            if joint is not None:
                break
            joint = _local_join(problem, left, right, count, tol_n, counted)
        if joint is not None:
            alpha, beta, knots = joint
            inner.extend(origin + scale * knots)
            scale_r, origin_r = scale * beta, origin + scale * alpha
            t[a:right.b] = origin_r + scale_r * right.s
            if a - e > 1:                                  # rows between: their feet, else by chord
                between = _gap_params(Q, left, right, (origin, scale, origin_r, scale_r))
                if between is None or np.any(np.diff(np.concatenate([[t[e]], between, [t[a]]])) < 0.0):
                    c = _arc(Q[e:a + 1])
                    between = t[e] + (t[a] - t[e]) * c[1:-1] / c[-1]
                t[e + 1:a] = between
        else:
            v = _speed(left.poles, 1) / scale         # |dC/dt| at the left piece's end
            v0 = _speed(right.poles, 0)
            if not (v > 0.0 and v0 > 0.0):
                return None
            t[e:a + 1] = t[e] + _arc(Q[e:a + 1]) / v
            spread(t[e], t[a], a - e - 1, JOIN_KNOTS + 1)
            scale_r, origin_r = v0 / v, t[a]
            t[a:right.b] = origin_r + scale_r * right.s
        scale, origin = scale_r, origin_r
    if first.a > 0:                                        # rows before the first piece
        v = _speed(first.poles, 0)
        if not v > 0.0:
            return None
        c = _arc(Q[:first.a + 1])
        t[:first.a] = t[first.a] - (c[-1] - c[:-1]) / v
        before = len(inner)
        spread(t[0], t[first.a], first.a - 1, 1)
        inner[:] = inner[before:] + inner[:before]
    last = pieces[-1]
    if last.b < m:                                         # rows after the last piece
        v = _speed(last.poles, 1) / scale
        if not v > 0.0:
            return None
        e = last.b - 1
        t[e:] = t[e] + _arc(Q[e:]) / v
        spread(t[e], t[-1], m - 1 - e - 1, 1)
    t0, span = t[0], t[-1] - t[0]
    if not (span > 0.0 and np.all(np.isfinite(t))):
        return None
    knots = (np.asarray(inner) - t0) / span
    t = (t - t0) / span
    t[0], t[-1] = 0.0, 1.0
    steps = np.diff(np.concatenate([[0.0], knots, [1.0]]))
    if steps[0] <= 0.0 or steps[-1] <= 0.0 or np.any(steps < 0.0) or np.any(np.diff(t) < 0.0) \
            or np.unique(knots, return_counts=True)[1].max(initial=0) > p:
        return None
    return knots, t
