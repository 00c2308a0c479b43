"""A B-spline curve within a tolerance of given points, with as few control points as
the tolerance allows (issue 17).

Seed 002 (1.1) separates interpolation (through the points) from approximation and
fitting (near them) but gives no fitting algorithm; this follows the standard literature:

- least squares with the end points held (Piegl & Tiller, The NURBS Book, 9.4.1,
  eq. 9.63-9.67), weighted, plus an optional smoothing energy
  ``smoothing * int_0^1 |C^(r)(u)|^2 du`` (r = 2 or 3; Dierckx, Curve and Surface Fitting
  with Splines, 5.2), in the points' normalised frame; REGULARISATION times the same
  energy (each span's part scaled to its width) keeps the normal equations definite
  where the points leave a control point undetermined (a knot span without a point, no
  Schoenberg-Whitney matching of the poles to the points);
- end tangent directions held exactly: P_1 = P_0 + a T_0 (and P_(n-1) = P_n - b T_1) with
  the magnitudes a, b chosen by the least squares too (the reduced problem in a, b is
  quadratic: two extra right-hand sides and a 2 x 2 solve);
- parameter correction (Hoschek 1988; Piegl & Tiller 9.4.1): between solves every
  point's parameter moves to its foot on the current curve (Newton on
  (C(t) - Q) . C'(t) = 0);
- knot placement by equidistributing the error (de Boor, A Practical Guide to Splines,
  XII: a degree-p fit misses by about c h^(p+1) on a span of width h): a span whose
  points miss by E_i is worth (E_i / tol)^(1/(p+1)) spans, the new breakpoints divide
  that density into equal parts; rounds grow the count until every point is within tol
  (a growth whose largest miss stalls while the count grows stops: tol is below the
  points' noise, :func:`stalled`, or the first parameters are far from the curve's own:
  after a stall, or a miss at the cap, the growth runs again from the best fit's feet,
  each round from the last one's feet, kept when it meets tol; this project's); a
  growth that reaches the cap of one control point per point without meeting tol takes
  the curve through every point instead (global
  interpolation, Piegl & Tiller 9.2.1, on the points' parameters with averaged knots:
  within any tol; :func:`_interpolant`; periodic: a break at every point's parameter),
  then shrink it while they stay, then Tiller's knot
  removal (:mod:`cagd.knots.removal`) takes out what its bound allows and the curve is
  fitted once more on those knots;
- knot recovery (:mod:`cagd.fitting.free_knots`; no smoothing, no held tangents, not
  periodic): fewer control points with the interior knots as unknowns (free-knot least
  squares, Jupp 1978; de Boor & Rice 1968), started at the jumps of the fit's p-th
  derivative, and below SEARCH_TOL a search over the counts, so that points sampled from
  a B-spline come back as it; a smaller count is kept only when every point stays within
  tol;
- many points (this project's): above FIT_SAMPLE_POINTS the rounds above
  run on an evenly spaced sample of the points, the knots they end with are fitted to
  every point (from its foot on the sample's curve) and kept when every point is within
  tol, else the rounds go on with every point from those knots; the knot recovery runs
  on at most RECOVERY_POINTS of them the same way: every pass costs O(points);
- the error reported is the certified closest-point distance of every point from the
  result (:func:`cagd.closest_point`), not the distance at the fitting parameters.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._periodic import wrapped_difference
from .._ranks import ranks
from .._results import ReadOnlyArrays
from ..basis.banded import banded_product, solve_banded_rows
from ..basis.bspline import basis_derivatives
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from .interpolation import _frame, collocate, parametrize
from .parameters import ParameterSpec

#: rounds of fitting at most (each: a solve, parameter correction, a new knot vector)
MAX_FIT_ROUNDS = 40
#: parameter-correction passes per round at most (each: Newton feet, then a new solve);
#: they stop early when the largest miss improves by less than CORRECTION_GAIN
MAX_CORRECTIONS = 64
CORRECTION_GAIN = 0.1
#: ... in SLOW_PASSES accepted passes in a row: a damped Levenberg-Marquardt pass gains
#: little before its weight settles, and one slow pass stopped a fit with the right
#: knots 5% of the data's size off (500 points of a 7-pole cubic then took 23 poles at
#: tol 1e-3 and failed at 1e-8 with 500; now 24 and 402, converged; the anchor curve
#: 16 / 36 / 62 -> 13 / 26 / 57 poles at tol 0.1 / 0.01 / 0.001, in about twice the time)
SLOW_PASSES = 3
#: a fit whose largest miss is this many times tol after four passes, and still shrinks by
#: less than FAST_GAIN per pass, stops correcting
FAR_FROM_TOL = 3.0
FAST_GAIN = 0.5
FAR_PASSES = 4
#: Newton steps of one parameter-correction pass
FOOT_NEWTON_STEPS = 2
#: relative weight of the regulariser int |C''|^2 (int |C'|^2 for degree 1), added only
#: where the points alone leave the curve undetermined
REGULARISATION = 1e-9
#: while the fit misses tol, the new knots equidistribute the error for GROW_TARGET * tol
GROW_TARGET = 0.7
#: the error model's span count for tol is tried with this margin first
SHRINK_SAFETY = 1.08
#: the search for the smallest span count stops when it is known within this fraction
SHRINK_RESOLUTION = 0.05
#: one shrinking step keeps at least this fraction of the spans (the error model of a
#: least-squares fit is optimistic: its misses are not local)
MAX_SHRINK = 0.7
#: a span's error counts at least ERROR_FLOOR * tol in the density (every part of the
#: curve keeps some knots)
ERROR_FLOOR = 1e-2
#: growth of the span count per round at most
MAX_GROWTH = 16.0
#: the growth stops short of tol (it cannot be met: the points' noise is finer than tol, more
#: control points only chase it) when the largest miss of the last STALL_ROUNDS growth rounds
#: is still above STALL_GAIN times the one STALL_ROUNDS rounds before while the control points
#: grew (a resolved shape's miss falls like h^(p+1): 1/16 per halved span for a cubic) ...
STALL_GAIN = 0.5
STALL_ROUNDS = 2
#: ... and the fit has at least STALL_FILL control points per point (below it a flat miss is
#: a shape the knots do not resolve yet; a shape that needs more is sampled at fewer than
#: about 3 points per knot span per surface direction). The 1,341-point noise cloud
#: (sigma 1, tol 0.01): 36 x 36 poles (the cap) in 11 s -> 11 x 11 in 0.9 s; the 2,000-point
#: anchor curve with noise sigma = 10 tol: 2,000 poles (the cap) -> 22 to 532
STALL_FILL = 0.125


@dataclass(frozen=True)
class CurveFit(ReadOnlyArrays):
    """The result of :func:`fit_curve`.

    curve: the fitted B-spline; max_error / rms_error: the largest and the root-mean-square
    certified distance of the points from it (closest points, not fitting parameters);
    params: (m,) the points' foot parameters on it; rounds: fitting rounds run;
    converged: max_error <= tol (else ``message`` says what stopped the fit)."""
    curve: BSplineCurve
    max_error: float
    rms_error: float
    params: np.ndarray
    rounds: int
    converged: bool
    message: str


class _Problem:
    """The data of one fit in the normalised frame: points Qn (m, d), weights w (m,),
    degree p, smoothing energy order r and weight lam, end tangent directions; periodic:
    the knots are the unwrapped vector of :func:`cagd.knots.periodic_extend` and its
    n + p control points the n distinct ones and the first p again (the unknowns are the
    n, folded so that the cyclic normal matrix is banded: :func:`_fold`)."""

    def __init__(self, Qn: np.ndarray, w: np.ndarray, p: int, lam: float, r: int,
                 tangents: Tuple[Optional[np.ndarray], Optional[np.ndarray]], periodic: bool = False):
        w = w / w.max()
        self.Q, self.w, self.p, self.lam, self.r = Qn, w / w.sum(), p, lam, r
        self.tangents, self.periodic = tangents, periodic
        self.least = p + 1                                  # the fewest control points allowed
        self._cached: Tuple[bytes, np.ndarray] = (b"", np.zeros((0, 0)))

    def subset(self, rows: np.ndarray) -> "_Problem":
        """The same problem on the points ``rows`` only (their weights relative as here)."""
        out = _Problem(self.Q[rows], self.w[rows], self.p, self.lam, self.r, self.tangents, self.periodic)
        out.least = self.least
        return out

    def layout(self, cols: np.ndarray, n: int) -> np.ndarray:
        """The unknowns' positions of the unwrapped pole indices ``cols``."""
        return _fold(cols % n, n) if self.periodic else cols

    def _energies(self, U: np.ndarray, t: np.ndarray, n: int, d: int, start: np.ndarray,
                  width: int, force: bool = False) -> np.ndarray:
        """The band of lam E_r, plus REGULARISATION E_2 where the data alone may not fix
        the curve (fewer weighted points than control points, a knot span without one,
        or, ends held, no Schoenberg-Whitney matching: :func:`_determined`) or with
        ``force``, each span's part scaled to its width (:func:`_energy`, ``local``),
        1 / (number of spans) of the data term's scale. Cached for the last knot vector
        (the parameter corrections of one round share it)."""
        p = self.p
        brk = np.unique(U[p:len(U) - p])
        counted = t[self.w > 0]
        held = np.bincount(np.clip(np.searchsorted(brk, counted, side="right") - 1, 0, len(brk) - 2),
                           minlength=len(brk) - 1)
        regularise = bool(force or np.count_nonzero(self.w) < n or held.min() == 0
                          or not (self.periodic or _determined(U, p, counted, n)))
        key = U.tobytes() + bytes([regularise])
        if self._cached[0] != key:
            band = np.zeros((n * d, width))
            spans = len(brk) - 1
            if self.lam > 0.0 and self.r <= p:
                _energy(band, start, U, p, d, self.r, self.lam / _energy_unit(U, p, self.r),
                        lambda c: self.layout(c, n))
            if regularise:
                _energy(band, start, U, p, d, min(2, p), REGULARISATION / spans, lambda c: self.layout(c, n),
                        local=True)
            self._cached = (key, band)
        return self._cached[1]

    def solve(self, U: np.ndarray, jet: "_Jet", T: Optional[np.ndarray] = None, mu: float = 0.0) -> np.ndarray:
        """Control points (n, d) minimising sum_k w_k |M_k (C(t_k) - Q_k)|^2 + lam E_r
        + REGULARISATION E_2 with P_0 = Q_0, P_n = Q_m and the tangent directions held,
        the basis at the parameters t on U from ``jet`` (:func:`_jet`). M_k = I (point distance), or with the
        unit tangents T (m, d) of the current curve at t_k, M_k^T M_k = mu I
        + (I - T_k T_k^T): the tangent distance, i.e. Gauss-Newton on the distances with
        the feet eliminated (Wang, Pottmann & Liu, ACM TOG 25(2), 2006), which converges
        where alternating with parameter correction alone crawls."""
        p, Q = self.p, self.Q
        d = Q.shape[1]
        full = len(U) - p - 1
        n = full - p if self.periodic else full
        t, span, N = jet.t, jet.span, jet.basis[0]
        cols = self.layout(span[:, None] - p + np.arange(p + 1), n)
        M = None if T is None else (1.0 + mu) * np.eye(d) - T[:, :, None] * T[:, None, :]
        start, A = _blocks(n, d, p, self.periodic)
        _accumulate(A, start, cols, N, self.w, d, M)
        MQ = Q if M is None else np.einsum("kab,kb->ka", M, Q)
        rhs = np.bincount((cols[:, :, None] * d + np.arange(d)).ravel(),
                          ((N * self.w[:, None])[:, :, None] * MQ[:, None, :]).ravel(), minlength=n * d)
        if self.periodic:                                  # nothing held; back to pole order
            X = self.normal_solve(U, t, A, start, lambda band: solve_banded_rows(
                start, band, rhs[:, None], "points"))[1][:, 0].reshape(n, d)
            P = X[_fold(np.arange(n), n)]
            return P[np.arange(full) % n]
        # fixed poles: P_0, P_n, and P_1 = P_0 + a T0, P_(n-1) = P_n - b T1
        fixed = {0: [Q[0]], n - 1: [Q[-1]]}
        free_dirs = []
        T0, T1 = self.tangents
        if T0 is not None:
            fixed[1] = [Q[0], T0]
            free_dirs.append(1)
        if T1 is not None:
            fixed[n - 2] = [Q[-1], -T1]
            free_dirs.append(n - 2)
        k = 1 + len(free_dirs)
        idx = sorted(fixed)
        values = np.zeros((len(idx), d, k))                 # per fixed pole and coordinate
        for row, f in enumerate(idx):
            values[row, :, 0] = fixed[f][0]
            if len(fixed[f]) > 1:
                values[row, :, 1 + free_dirs.index(f)] = fixed[f][1]
        B = np.zeros((n * d, k))
        B[:, 0] = rhs
        scalars = np.array([f * d + a for f in idx for a in range(d)])
        band, X = self.normal_solve(U, t, A, start, lambda band: solve_fixed(
            start, band, B.copy(), scalars, values.reshape(-1, k)))
        x0 = X[:, 0]
        if k == 1:
            P = x0.reshape(n, d)
        else:
            # the reduced problem in the tangent magnitudes: x(a) = x0 + sum a_j x_j
            xs = X[:, 1:]
            Ax = banded_product(start, band, xs)
            G = xs.T @ Ax
            g = xs.T @ (banded_product(start, band, x0[:, None])[:, 0] - rhs)
            mag = _magnitudes(G, g)
            P = (x0 + xs @ mag).reshape(n, d)
            for row, f in enumerate(idx):                  # the constraints, bit for bit
                P[f] = values[row, :, 0] + values[row, :, 1:] @ mag
        for row, f in enumerate(idx):
            if len(fixed[f]) == 1:
                P[f] = values[row, :, 0]
        return P

    def normal_solve(self, U: np.ndarray, t: np.ndarray, A: np.ndarray, start: np.ndarray,
                     solve: Callable[[np.ndarray], np.ndarray]) -> Tuple[np.ndarray, np.ndarray]:
        """(band, solve(band)): the data's normal band A (kept) plus :meth:`_energies`;
        when the banded solve finds that singular (the points leave a pole undetermined
        where the checks there did not see it), again with the regulariser forced (then
        definite: E_2 vanishes only on straight lines, which the held ends or the points
        fix)."""
        n = A.shape[0] // self.Q.shape[1]
        for force in (False, True):
            band = A + self._energies(U, t, n, self.Q.shape[1], start, A.shape[1], force)
            try:
                return band, solve(band.copy())
            except CagdError:
                if force:
                    raise
        raise AssertionError("unreachable")


def solve_fixed(start: np.ndarray, A: np.ndarray, B: np.ndarray, scalars: np.ndarray, values: np.ndarray
                ) -> np.ndarray:
    """The banded system A X = B (rows of :func:`_blocks`; A is modified) with the unknowns
    ``scalars`` held at ``values`` (len(scalars), B.shape[1]): their columns move to the
    right-hand side, their rows become identities."""
    size, width = A.shape
    for I, v in zip(scalars, values):
        rows = np.arange(max(0, I - width), min(size, I + width + 1))
        off = I - start[rows]
        inside = (off >= 0) & (off < width)
        rows, off = rows[inside], off[inside]
        B[rows] -= A[rows, off, None] * v[None]
        A[rows, off] = 0.0
    for I, v in zip(scalars, values):
        A[I] = 0.0
        A[I, I - start[I]] = 1.0
        B[I] = v
    return solve_banded_rows(start, A, B, "points")


#: weight mu of the point distance beside the tangent distance in the Gauss-Newton
#: passes (keeps the system definite along the curve, damps the steps): its first value,
#: its range and its factor per pass
TDM_WEIGHT_START = 1e-2
TDM_WEIGHT_MIN = 1e-6
TDM_WEIGHT_MAX = 1.0
TDM_WEIGHT_STEP = 10.0


def _blocks(n: int, d: int, p: int, periodic: bool = False) -> Tuple[np.ndarray, np.ndarray]:
    """(start, zero band) of the banded n d x n d normal matrix, unknowns pole-major
    (pole i, coordinate a at i d + a): rows reach p poles either side, or 2 p + 1
    positions when periodic (the folded order of :func:`_fold`)."""
    reach = 2 * p + 1 if periodic else p
    width = min((2 * reach + 1) * d, n * d)
    start = np.clip((np.arange(n * d) // d - reach) * d, 0, n * d - width)
    return start, np.zeros((n * d, width))


def _fold(i: np.ndarray, n: int) -> np.ndarray:
    """Position of pole i of a cyclic sequence in the folded order 0, n-1, 1, n-2, 2, ...:
    neighbours within p of each other (cyclically) are within 2 p + 1 positions, so the
    cyclic band of a periodic fit becomes an ordinary band (no n x n matrix)."""
    return np.where(i < (n + 1) // 2, 2 * i, 2 * (n - 1 - i) + 1)


def _determined(U: np.ndarray, p: int, t: np.ndarray, n: int) -> bool:
    """Whether the points' parameters t determine the interior poles 1 .. n - 2 of the
    clamped (U, p) with the end poles held: the Schoenberg-Whitney condition of least
    squares, increasing parameters t_(j_1) < ... < t_(j_(n-2)) with U_i < t_(j_i) <
    U_(i+p+1) (the collocation matrix of those poles then has full column rank: de Boor,
    A Practical Guide to Splines, XIII and XIV). The greedy matching is optimal for
    supports whose ends increase with i: pole i takes the first parameter beyond U_i and
    beyond its predecessor's, j_i = max(j_(i-1) + 1, a_i), so j_i - i is the running
    maximum of a_i - i."""
    s = np.unique(t)
    i = np.arange(1, n - 1)
    if not i.size:
        return True
    j = i + np.maximum.accumulate(np.searchsorted(s, U[i], side="right") - i)
    return bool(j[-1] < len(s) and np.all(s[j] < U[i + p + 1]))


#: the smallest tangent magnitude |P_1 - P_0| (normalised frame): a held tangent keeps its
#: sense even where the least squares would reverse it
MIN_TANGENT = 1e-6


def _magnitudes(G: np.ndarray, g: np.ndarray) -> np.ndarray:
    """argmin a^T G a + 2 g^T a subject to a >= MIN_TANGENT (at most two unknowns: the
    unconstrained minimum, else each bound fixed in turn)."""
    k = len(g)
    best, value = np.full(k, MIN_TANGENT), np.inf
    for fixed in range(1 << k):                      # the active set: bounds held at MIN_TANGENT
        a = np.full(k, MIN_TANGENT)
        free = [i for i in range(k) if not fixed >> i & 1]
        if free:
            Gf = G[np.ix_(free, free)]
            rhs = -g[free] - G[np.ix_(free, [i for i in range(k) if fixed >> i & 1])] @ a[
                [i for i in range(k) if fixed >> i & 1]]
            try:
                a[free] = np.linalg.solve(Gf, rhs)
            except np.linalg.LinAlgError:
                continue
        if np.all(a >= MIN_TANGENT):
            f = float(a @ G @ a + 2 * g @ a)
            if f < value:
                best, value = a, f
    return best


#: points per chunk when the normal matrix is accumulated (bounded working memory: the
#: products of one point are (p + 1)^2 d^2 numbers, 144 for a cubic in 3-D)
ACCUMULATE_POINTS = 16384
#: rows of one product block when the coupled sums are formed by matrix products: at most
#: this many, at most about the mean number of points per knot span (the blocks of a
#: span are padded with zero rows)
GRAM_ROWS = 32


def _span_blocks(cut: np.ndarray, m: int, R: Optional[int] = None) -> Tuple[np.ndarray, np.ndarray]:
    """Rows of the points sorted by span cut into blocks of at most R rows that never
    straddle two spans (by default a power of two near the mean span's count, <=
    GRAM_ROWS): (index (blocks, R) into the rows, m where a block is padded; the first
    block of every span)."""
    sizes = np.diff(np.append(cut, m))
    if R is None:
        R = int(min(GRAM_ROWS, 1 << max(0, int(np.log2(max(1.0, m / len(cut)))))))
    count = -(-sizes // R)                                         # blocks per span
    first = np.concatenate([[0], np.cumsum(count)[:-1]])
    span = np.repeat(np.arange(len(cut)), count)
    top = cut[span] + ranks(count) * R                              # each block's first row
    index = top[:, None] + np.arange(R)
    end = (cut + sizes)[span]
    return np.where(index < end[:, None], index, m), first


def span_sums(cut: np.ndarray, left: np.ndarray, right: np.ndarray, rows: Optional[int] = None) -> np.ndarray:
    """Per knot span, sum_k left_k^T right_k over its points (sorted by span, span i's
    first at cut[i]): (spans, a, b) from left (m, r, a) and right (m, r, b) (r rows per
    point), as matrix products of blocks of a span's points (:func:`_span_blocks`, of at
    most ``rows`` points), no (m, a, b) array of the products."""
    m, r = left.shape[:2]
    block, head = _span_blocks(cut, m, rows)
    R = block.shape[1]

    def stacked(x: np.ndarray) -> np.ndarray:
        padded = np.concatenate([x.reshape(m, -1), np.zeros((1, x[0].size))])
        return padded.take(block, axis=0).reshape(len(block), R * r, x.shape[2])
    return np.add.reduceat(np.matmul(stacked(left).transpose(0, 2, 1), stacked(right)), head, axis=0)


def _accumulate(band: np.ndarray, start: np.ndarray, cols: np.ndarray, V: np.ndarray, w: np.ndarray,
                d: int, M: Optional[np.ndarray] = None) -> None:
    """band += sum_k w_k (V_k V_k^T) (x) M_k at the poles cols[k] (the normal matrix
    N^T W N, coordinates coupled by M_k (m, d, d), or M_k = I when None). The products
    are summed per knot span first (over the points sorted by span: np.add.reduceat, or,
    coupled, sum_k vec(w_k V_k V_k^T) vec(M_k)^T by :func:`span_sums`), then added to the
    band once per span: the scatter is O(spans), not O(points); at most ACCUMULATE_POINTS
    points at a time (a span cut by a chunk's end is added in two parts)."""
    width = band.shape[1]
    flat = band.ravel()
    a = np.arange(d)
    q = V.shape[1]
    order = np.argsort(cols[:, 0], kind="stable")
    for c0 in range(0, len(order), ACCUMULATE_POINTS):
        rows = order[c0:c0 + ACCUMULATE_POINTS]
        first = cols[rows, 0]
        cut = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
        VV = V.take(rows, axis=0)
        vv = VV[:, :, None] * VV[:, None, :] * w.take(rows)[:, None, None]          # (m, q, q)
        cc = cols[rows[cut]]                                                    # (spans, q)
        if M is None:
            S = np.add.reduceat(vv, cut, axis=0)
            I = cc[:, :, None, None] * d + a
            J = cc[:, None, :, None] * d + a
            S = np.broadcast_to(S[..., None], S.shape + (d,))
        else:
            S = span_sums(cut, vv.reshape(-1, 1, q * q), M.take(rows, axis=0).reshape(-1, 1, d * d))
            S = S.reshape(-1, q, q, d, d)
            I = cc[:, :, None, None, None] * d + a[:, None]
            J = cc[:, None, :, None, None] * d + a
        index = np.broadcast_to(I * width + J - start[I], S.shape)
        flat += np.bincount(index.ravel(), S.ravel(), minlength=flat.size)


def _gauss(U: np.ndarray, p: int) -> Tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre points and weights, p + 1 per non-empty knot span (exact for the
    products of basis derivatives)."""
    x, wt = np.polynomial.legendre.leggauss(p + 1)
    brk = np.unique(U[p:len(U) - p])
    a, b = brk[:-1, None], brk[1:, None]
    return (0.5 * (a + b) + 0.5 * (b - a) * x).ravel(), (0.5 * (b - a) * wt).ravel()


def _energy(band: np.ndarray, start: np.ndarray, U: np.ndarray, p: int, d: int, order: int,
            weight: float, layout=None, local: bool = False) -> None:
    """band += weight * [int N_i^(order) N_j^(order)] (x) I_d (pole indices through
    ``layout`` when given: a periodic fit's folded positions); ``local``: each span's
    integral times h^(2 order - 1), h its width (the unit hat's energy there: every span's
    part of the same size, however narrow or wide it is beside the others)."""
    n = len(U) - p - 1
    t, wt = _gauss(U, p)
    if local:
        wt = wt * np.repeat(np.diff(np.unique(U[p:len(U) - p])), p + 1) ** (2 * order - 1)
    span = kv.find_span(U, p, t, n)
    D = basis_derivatives(U, p, t, span, order)[order]
    cols = span[:, None] - p + np.arange(p + 1)
    _accumulate(band, start, cols if layout is None else layout(cols), D, wt * weight, d)


def _energy_unit(U: np.ndarray, p: int, order: int) -> float:
    """The scale of int |N^(order)|^2 on these knots (the energy of the unit hat sum of
    one span), so that the regulariser is relative to the data term."""
    h = float(np.diff(np.unique(U[p:len(U) - p])).min())
    return max(h ** (1 - 2 * order), 1.0)


def _values(U: np.ndarray, p: int, P: np.ndarray, t: np.ndarray, order: int) -> np.ndarray:
    """C and its derivatives up to ``order`` at t from the local basis: (order + 1, len(t), d)."""
    span = kv.find_span(U, p, t, len(P))
    D = basis_derivatives(U, p, t, span, order)                    # (order + 1, len(t), p + 1)
    return _combine(D, P, span - p)


def _combine(D: np.ndarray, P: np.ndarray, first: np.ndarray) -> np.ndarray:
    """sum_j D[..., j] P[first + j]: (k, len(t), d) from the local basis values (k, len(t), q),
    computed coordinate-first (every inner loop along the points, not along d) and
    returned as a (k, len(t), d) view."""
    PT = np.ascontiguousarray(P.T)
    Dj = D.transpose(0, 2, 1)                                              # (k, q, len(t))
    out = Dj[:, 0, None, :] * PT.take(first, axis=1)                       # (k, d, len(t))
    for j in range(1, D.shape[-1]):
        out += Dj[:, j, None, :] * PT.take(first + j, axis=1)
    return out.transpose(0, 2, 1)


class _Jet(NamedTuple):
    """The basis functions and their first two derivatives (3, len(t), p + 1) at t on one
    knot vector, and the spans: what the curve, its feet and the next solve all need at t
    (a control-point change leaves it valid)."""
    t: np.ndarray
    span: np.ndarray
    basis: np.ndarray

    def values(self, P: np.ndarray, order: int, rows: slice = slice(None)) -> np.ndarray:
        """C and its derivatives up to ``order`` (<= 2) at t[rows]: (order + 1, len, d)."""
        return _combine(self.basis[:order + 1, rows], P, self.span[rows] - (self.basis.shape[-1] - 1))


def _jet(U: np.ndarray, p: int, t: np.ndarray) -> _Jet:
    span = kv.find_span(U, p, t, len(U) - p - 1)
    return _Jet(t, span, basis_derivatives(U, p, t, span, 2))


def _feet(U: np.ndarray, p: int, P: np.ndarray, Q: np.ndarray, jet: _Jet, periodic: bool = False) -> _Jet:
    """Parameters moved towards the points' feet from the jet at the first parameters (the
    jet at the last returned): FOOT_NEWTON_STEPS of Newton on f(t) = (C(t) - Q) . C'(t),
    Gauss-Newton where f' is small; the ends stay at 0 and 1 (periodic: every parameter
    moves, modulo the period 1)."""
    t = jet.t.copy()
    inner = slice(None) if periodic else slice(1, -1)
    for newton in range(FOOT_NEWTON_STEPS):
        if newton:
            jet = _jet(U, p, t)
        D = jet.values(P, 2, inner)
        r = D[0] - Q[inner]
        f = (r * D[1]).sum(-1)
        g2 = (D[1] * D[1]).sum(-1)
        df = g2 + (r * D[2]).sum(-1)
        df = np.where(df > 0.25 * g2, df, g2)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(df > 0.0, f / df, 0.0)
        moved = t[inner] - step
        t[inner] = np.mod(moved, 1.0) if periodic else np.clip(moved, 0.0, 1.0)
    return _jet(U, p, t)


def _misses(U: np.ndarray, p: int, P: np.ndarray, Q: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.sqrt(((_values(U, p, P, t, 0)[0] - Q) ** 2).sum(-1))


def _fit_on(problem: _Problem, U: np.ndarray, t: np.ndarray, tol: float
            ) -> Tuple[BSplineCurve, np.ndarray, np.ndarray]:
    """The least-squares curve on the knots U, then Gauss-Newton passes: a tangent-distance
    solve at the points' feet on the best curve so far, new feet (parameter correction);
    the point-distance weight mu follows Levenberg-Marquardt (divided by TDM_WEIGHT_STEP
    after a pass that lowers the largest miss, multiplied after one that does not, which
    is then dropped). Returns the best curve, its feet and the misses there. Passes stop
    when the largest miss improves by less than CORRECTION_GAIN in SLOW_PASSES accepted
    passes in a row, or is still
    FAR_FROM_TOL * tol after four and converging slowly (more knots are needed anyway)."""
    p, Q = problem.p, problem.Q

    def feet(P: np.ndarray, start: _Jet) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, _Jet]:
        jet = _feet(U, p, P, Q, start, problem.periodic)
        D = jet.values(P, 1)
        return P, jet.t, np.sqrt(((D[0] - Q) ** 2).sum(-1)), D[1], jet

    first = _jet(U, p, t)
    best = feet(problem.solve(U, first), first)
    mu = TDM_WEIGHT_START
    slow = 0
    for passes in range(MAX_CORRECTIONS):
        length = np.sqrt((best[3] ** 2).sum(-1))
        with np.errstate(divide="ignore", invalid="ignore"):
            T = np.where(length[:, None] > 0.0, best[3] / length[:, None], 0.0)
        trial = feet(problem.solve(U, best[4], T, mu), best[4])
        if not trial[2].max() < best[2].max():
            mu *= TDM_WEIGHT_STEP
            if mu > TDM_WEIGHT_MAX:
                break
            continue
        gain = 1.0 - trial[2].max() / best[2].max()
        best, mu = trial, max(mu / TDM_WEIGHT_STEP, TDM_WEIGHT_MIN)
        slow = slow + 1 if gain < CORRECTION_GAIN else 0
        slow_and_far = passes + 1 >= FAR_PASSES and best[2].max() > FAR_FROM_TOL * tol and gain < FAST_GAIN
        if slow >= SLOW_PASSES or slow_and_far:
            break
    return BSplineCurve(best[0], p, U), best[1], best[2]


def stalled(history: Sequence[Tuple[int, float]], points: int) -> Optional[str]:
    """Why a fit's growth should stop short of tol, or None: ``history`` the (control
    points, largest miss) of every growth round so far, ``points`` the number of points;
    the rule of STALL_GAIN, STALL_ROUNDS and STALL_FILL (this project's; the noise of
    the points bounds how close a least-squares fit gets, however many poles)."""
    if len(history) <= STALL_ROUNDS:
        return None
    (n0, e0), (n1, _) = history[-1 - STALL_ROUNDS], history[-1]
    recent = min(e for _, e in history[-STALL_ROUNDS:])
    if n1 <= n0 or n1 < STALL_FILL * points or recent <= STALL_GAIN * e0:
        return None
    return (f"the growth stopped early: its largest miss at the fitting parameters stayed at {recent:.3g} "
            f"(from {e0:.3g}) while its control points grew from {n0} to {n1}: tol is below the points' noise")


def _knots(breaks: np.ndarray, p: int) -> np.ndarray:
    return np.concatenate([np.zeros(p), breaks, np.ones(p)])


def _span_errors(breaks: np.ndarray, t: np.ndarray, e: np.ndarray) -> np.ndarray:
    """E_i, the largest miss of the points whose parameter lies in span i."""
    s = len(breaks) - 1
    span = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, s - 1)
    E = np.zeros(s)
    np.maximum.at(E, span, e)
    return E


def _worth(E: np.ndarray, tol: float, p: int) -> np.ndarray:
    """Spans each old span is worth for the error tol: (E_i / tol)^(1/(p+1)), E_i at least
    ERROR_FLOOR * tol."""
    return (np.maximum(E, ERROR_FLOOR * tol) / tol) ** (1.0 / (p + 1))


def _redistributed(breaks: np.ndarray, c: np.ndarray, count: int) -> np.ndarray:
    """``count`` spans whose breakpoints divide the piecewise constant density c_i / h_i
    (c_i per old span) into equal parts."""
    cum = np.concatenate([[0.0], np.cumsum(c)])
    new = np.interp(np.linspace(0.0, cum[-1], count + 1), cum, breaks)
    new[0], new[-1] = 0.0, 1.0
    return np.unique(new)


def fit_curve(points: ArrayLike, tol: float, degree: int = 3, parameters: ParameterSpec = "centripetal", *,
              start_tangent: Optional[ArrayLike] = None, end_tangent: Optional[ArrayLike] = None,
              weights: Optional[ArrayLike] = None, smoothing: float = 0.0, smoothing_order: Optional[int] = None,
              max_control_points: Optional[int] = None, periodic: bool = False) -> CurveFit:
    """A clamped degree-p B-spline on [0, 1] through the first and the last point and
    within ``tol`` (a distance) of every point, with few control points (see the module
    docstring for the method and its sources); with ``periodic`` a closed curve, C^(p-1)
    at its seam, through no point in particular (the points in order round the loop; a
    last point equal to the first is dropped).

    Args:
        points: (m, d) points in order along the curve, m >= 2.
        tol: the largest allowed distance of a point from the curve (> 0).
        degree: 1 .. MAX_DEGREE.
        parameters: the initial parameters: a rule of :data:`cagd.fitting.PARAMETERS` or m values.
        start_tangent, end_tangent: directions the curve must leave the first point and
            arrive at the last with (held exactly; the magnitudes are fitted).
        weights: (m,) non-negative weights of the points in the least squares (the
            tolerance holds for every point with a positive weight).
        smoothing: weight of int |C^(smoothing_order)|^2 against the mean squared miss,
            in the points' frame scaled to the unit ball and parameters on [0, 1].
        smoothing_order: 2 (bending, the default; 1 for degree 1) or 3 (curvature
            variation), at most the degree.
        max_control_points: a cap on the count (default: the number of points).
        periodic: fit a closed periodic curve (no end tangents then).

    Returns:
        CurveFit; ``converged`` False (with the achieved error) when the cap or
        MAX_FIT_ROUNDS is reached before tol is met, or the growth stalls (:func:`stalled`:
        tol below the points' noise, also when grown again from the best fit's feet; the
        first growth's fit with the smallest largest miss then).
        At a cap of one control point per point (the default) the curve through every
        point is taken, within any tol, unless points are weighted 0, tangents are held
        or smoothing is asked for.

    Raises:
        CagdError: bad points, tol, degree, parameters, tangents, weights or smoothing.
    """
    Q = _checks.points(points, "points", min_count=2)
    m, d = Q.shape
    tol = _checks.positive(tol, "tol")
    p = _checks.degree(degree, "degree", 1)
    smoothing = _checks.nonnegative(smoothing, "smoothing")
    r = min(2, p) if smoothing_order is None else _checks.integer(smoothing_order, "smoothing_order", 1, p)
    w = np.ones(m) if weights is None else _checks.finite_array(weights, "weights", ndim=1)
    if w.shape != (m,) or np.any(w < 0) or not w.max() > 0:
        raise CagdError(f"weights: expected {m} non-negative values, not all zero")
    periodic = bool(periodic)
    if periodic:
        if m > 2 and np.array_equal(Q[0], Q[-1]):
            Q, w = Q[:-1], w[:-1]
            m -= 1
        if start_tangent is not None or end_tangent is not None:
            raise CagdError("start_tangent: a periodic curve has no ends; leave the tangents out")
        distinct = int(np.count_nonzero(_first_of_repeats(Q)))
        if distinct < p + 1:
            raise CagdError(f"points: a closed degree-{p} fit needs at least {p + 1} distinct points, got {distinct}")
        u = _with_repeats(Q, parameters, _closed_parameters)
    else:
        u = _with_repeats(Q, parameters, parametrize)
        u = (u - u[0]) / (u[-1] - u[0])
    tangents: List[Optional[np.ndarray]] = []
    for name, T in (("start_tangent", start_tangent), ("end_tangent", end_tangent)):
        if T is None:
            tangents.append(None)
            continue
        T = _checks.finite_array(T, name, ndim=1)
        length = float(np.linalg.norm(T)) if T.shape == (d,) else 0.0
        if not length > 0.0:
            raise CagdError(f"{name}: expected a non-zero vector of {d} coordinates")
        tangents.append(T / length)
    if p == 1 and any(T is not None for T in tangents):
        raise CagdError("start_tangent: a degree-1 curve cannot hold end tangents; use degree >= 2")
    least = p + 1 + (tangents[0] is not None and tangents[1] is not None and p < 3)
    held = sum(T is not None for T in tangents)          # each held tangent frees one more pole
    most = max(least, m + held if max_control_points is None else
               min(_checks.integer(max_control_points, "max_control_points", least), max(least, m + held)))
    center, scale = _frame(Q)
    problem = _Problem((Q - center) / scale, w, p, smoothing, r, (tangents[0], tangents[1]), periodic)
    problem.least = least
    tol_n = tol / scale
    if not tol_n > 0.0:
        raise CagdError(f"tol: {tol!r} is below the floating-point resolution of points {scale:.3g} in size")
    counted = w > 0
    most_spans = most if periodic else most - p          # a periodic curve has one pole per span
    # one Bezier span (two for p < 3 with tangents); periodic: p + 1 spans, the fewest
    breaks = np.linspace(0.0, 1.0, (p + 2) if periodic else (least - p + 1))
    floor = (p + 1 if periodic else least - p) - 1
    recover = smoothing == 0.0 and not any(T is not None for T in tangents)
    plan = _Plan(p, periodic, most, most_spans, tol_n, scale, recover,
                 recover and bool(np.all(w > 0)) and most == m)
    fits = 0
    done: Optional[Tuple[BSplineCurve, np.ndarray, Optional[str]]] = None
    if m > FIT_SAMPLE_POINTS:
        # the knots searched on a sample of the points, then fitted to all of them
        rows = _sample_rows(m, FIT_SAMPLE_POINTS)
        if problem.w[rows].max() > 0.0:
            cap = max(least, min(most, len(rows) + held))     # the sample's own cap, as the points'
            sample = plan._replace(most=cap, most_spans=cap if periodic else cap - p)
            c_s, t_s, ok_s, fits, why, breaks = _fit_all(problem.subset(rows), u[rows], breaks, floor,
                                                         counted[rows], sample)
            if ok_s or why is not None:
                U = np.asarray(c_s.knots)
                jet = _feet_from(U, p, c_s.control_points, problem.Q, rows, t_s, u if periodic else None)
                fits += 1
                if why is not None:       # the sample's growth stalled: tol is below the points'
                    fitted, tt, _ = _fit_on(problem, U, jet.t, tol_n)      # noise; its knots on all
                    done = (fitted, tt, why)
                else:
                    done = _settled(problem, U, jet, tol_n, counted)
                    if done is None:                     # a miss between the sampled points:
                        floor = len(breaks) - 1          # on with every point from these knots
    if done is None:
        curve, t, _, more, why, breaks = _fit_all(problem, u, breaks, floor, counted, plan)
        fits += more
    else:
        curve, t, why = done
    if periodic:
        n = len(breaks) - 1
        result = BSplineCurve(curve.control_points[:n] * scale + center, p, breaks, periodic=True)
        return _measured(result, Q, t, counted, tol, fits, why)
    P = curve.control_points * scale + center
    P[0], P[-1] = Q[0], Q[-1]                      # the end points, bit for bit
    if tangents[0] is not None:                    # the tangent lines, in the model's frame
        P[1] = Q[0] + tangents[0] * max(float((P[1] - Q[0]) @ tangents[0]), MIN_TANGENT * scale)
    if tangents[1] is not None:
        P[-2] = Q[-1] - tangents[1] * max(float((Q[-1] - P[-2]) @ tangents[1]), MIN_TANGENT * scale)
    result = BSplineCurve(P, p, curve.knots)
    return _measured(result, Q, t, counted, tol, fits, why)


class _Plan(NamedTuple):
    """What a fit's search needs besides its points: the degree, periodic, the control-point
    cap ``most`` and its span count, tol_n and the frame's scale (the stall messages are
    in model units), whether the knot-recovery stage runs, and whether a growth to the cap
    takes the curve through every point (:func:`_interpolant`; periodic: the least squares
    with a break at every point's parameter): every point weighted, no held tangents, no
    smoothing, a cap of one control point per point."""
    p: int
    periodic: bool
    most: int
    most_spans: int
    tol_n: float
    scale: float
    recover: bool
    interpolable: bool


#: the fit rounds (of MAX_FIT_ROUNDS) a growth again from the best fit's feet leaves to
#: the shrink after it
REGROWTH_RESERVE = 8


#: above this many points the knots are searched on FIT_SAMPLE_POINTS of them (evenly
#: spaced in their order, the first and the last among them), then fitted to all of them
#: and checked there; where a point between the sampled ones misses, the search goes on
#: with every point from those knots; where the sample's growth stalled (tol below the
#: noise), its knots fitted to every point are the result (converged False, the message
#: says why). Each correction pass costs O(points): 100,000 points of the anchor curve
#: took 11 s, 20,000 took 18 s (the knot-recovery stage, see RECOVERY_POINTS)
FIT_SAMPLE_POINTS = 4000


#: Newton rounds (:func:`_feet`, FOOT_NEWTON_STEPS steps each) that take every point to its
#: foot on a curve fitted to a sample of them, before the fit to all of them
SAMPLE_FEET_ROUNDS = 3


def _feet_from(U: np.ndarray, p: int, P: np.ndarray, Q: np.ndarray, rows: np.ndarray, t_rows: np.ndarray,
               u: Optional[np.ndarray] = None) -> _Jet:
    """The jet at the feet of every point Q on the curve (U, P) fitted to the sampled points
    ``rows``, whose feet are ``t_rows``: the others' parameters interpolated between them
    (``u``: a periodic curve's, the points' initial parameters, along which the sampled
    feet are unwrapped across the seam), then SAMPLE_FEET_ROUNDS rounds of :func:`_feet`
    (clamped: the ends stay at 0 and 1; periodic: every parameter moves modulo 1)."""
    index = np.arange(len(Q))
    if u is None:
        t = np.interp(index, rows, t_rows)
    else:
        t = np.mod(np.interp(index, rows, u[rows] + wrapped_difference(t_rows, u[rows], 1.0)), 1.0)
    jet = _jet(U, p, t)
    for _ in range(SAMPLE_FEET_ROUNDS):
        jet = _feet(U, p, P, Q, jet, u is not None)
    return jet


def _settled(problem: _Problem, U: np.ndarray, jet: _Jet, tol_n: float, counted: np.ndarray
             ) -> Optional[Tuple[BSplineCurve, np.ndarray, Optional[str]]]:
    """The fit of every point on the knots U (a sample's) from the jet at their feet on the
    sample's curve: one least-squares solve and new feet, kept when every counted point is
    within tol_n there; else the corrected fit (:func:`_fit_on`) when that is; else None."""
    p = problem.p
    P = problem.solve(U, jet)
    after = _feet(U, p, P, problem.Q, jet, problem.periodic)
    if float(np.sqrt(((after.values(P, 0)[0] - problem.Q) ** 2).sum(-1))[counted].max()) <= tol_n:
        return BSplineCurve(P, p, U), after.t, None
    fitted, tt, ee = _fit_on(problem, U, jet.t, tol_n)
    return (fitted, tt, None) if float(ee[counted].max()) <= tol_n else None


def _sample_rows(m: int, count: int) -> np.ndarray:
    """``count`` row indices evenly spaced over 0 .. m - 1, both ends among them."""
    return np.unique(np.round(np.linspace(0.0, m - 1.0, count)).astype(np.intp))


def _fit_all(problem: _Problem, u: np.ndarray, breaks: np.ndarray, floor: int, counted: np.ndarray, plan: _Plan
             ) -> Tuple[BSplineCurve, np.ndarray, bool, int, Optional[str], np.ndarray]:
    """The fit's search (:func:`fit_curve`; the module docstring) from the breakpoints
    ``breaks`` with the points' initial parameters u:
    grow until every point is within tol (or the cap, or a stall: tol below the noise;
    after a stall or a miss at the cap, grow again from the best fit's feet, kept when
    it meets tol), shrink by bisection down to ``floor`` + 1 spans (a count known or taken to miss),
    then (not periodic) Tiller's knot removal and the knot-recovery stage. Returns
    (curve, parameters, within tol, fits run, why the growth stalled or None, its
    breakpoints); a periodic curve comes back unwrapped (its knots
    :func:`cagd.knots.periodic_extend` of the breakpoints)."""
    p, tol_n, most_spans = plan.p, plan.tol_n, plan.most_spans
    knots = (lambda b: kv.periodic_extend(b, p)) if plan.periodic else (lambda b: _knots(b, p))
    fits = 0

    def attempt(b: np.ndarray, start: np.ndarray) -> Tuple[BSplineCurve, np.ndarray, np.ndarray, float]:
        nonlocal fits
        fits += 1
        c, tt, ee = _fit_on(problem, knots(b), start, tol_n)
        return c, tt, ee * counted, float(ee[counted].max())

    def grow(breaks: np.ndarray, start: np.ndarray, follow: bool, rival: Optional[tuple] = None,
             rounds: int = MAX_FIT_ROUNDS) -> Tuple[tuple, Optional[str]]:
        """Until every point is within tol (or the cap, ``rounds`` fits in all, or a
        stall: tol below the noise), every round from the parameters ``start``
        (``follow``: from the last round's feet); (the fit, why it stalled or None).
        ``rival``: a fit (as the returned one) this growth stops at once it has more
        spans and misses no less (it stalled there)."""
        curve, t, e, worst = attempt(breaks, start)
        best = (curve, t, e, breaks, worst)              # the grown fit with the smallest largest miss
        history = [(len(curve.control_points), worst * plan.scale)]
        why = None
        while worst > tol_n and fits < rounds:
            s = len(breaks) - 1
            if s >= most_spans:
                break
            E = _span_errors(breaks, t, e)
            c = _worth(E, GROW_TARGET * tol_n, p)
            count = int(np.clip(max(np.ceil(c.sum()), s + np.count_nonzero(E > tol_n)), s + 1,
                                min(most_spans, MAX_GROWTH * s + 1)))
            breaks = _redistributed(breaks, c, count)
            curve, t, e, worst = attempt(breaks, t if follow else start)
            if worst < best[4]:
                best = (curve, t, e, breaks, worst)
            history.append((len(curve.control_points), worst * plan.scale))
            why = stalled(history, int(np.count_nonzero(counted))) if worst > tol_n else None
            if rival is not None and not why and len(breaks) > len(rival[3]) and worst >= rival[4]:
                why = "no nearer than the growth before"
            if why:
                break
        return (best if why else (curve, t, e, breaks, worst)), why

    best, why = grow(breaks, u, False)
    regrown = fits < MAX_FIT_ROUNDS - REGROWTH_RESERVE and best[4] > tol_n and \
        (why is not None or len(best[3]) - 1 >= most_spans)
    feet = u                                     # of the nearer growth (the recovery's first start)
    if regrown:
        # a stall, or a miss at the cap, may be the first parameters' fault, not noise
        # (centripetal parameters of points sampled unevenly, 2.7e-6 .. 0.44 apart: a
        # quartic's 658 points took 285 control points for a miss of 6.9e-5 at tol 1e-7):
        # the growth again from the best fit's feet, each round from the last one's (125
        # control points within tol), kept when it meets tol (noise stalls it again, or
        # it stops once it has more spans than the first growth's best and misses no
        # less); the feet of the nearer growth start the knot-recovery search (at tol
        # 1e-9 that quartic's 10 control points came back from them, not from the first)
        again, _ = grow(breaks, best[1], True, best, MAX_FIT_ROUNDS - REGROWTH_RESERVE)
        feet = again[1] if again[4] < best[4] else best[1]
        if again[4] <= tol_n:
            best, why = again, None
    if best[4] > tol_n and len(best[3]) - 1 >= most_spans and plan.interpolable:
        if plan.periodic:           # one span per point: the points at the breaks (odd degree)
            d = np.unique(u)        # or between them (even); repeated points once
            b = np.append(d, 1.0) if p % 2 else np.concatenate([[0.0], 0.5 * (d[1:] + d[:-1]), [1.0]])
            curve, t, e, worst = attempt(b, u)
            best = (curve, t, e, b, worst) if worst < best[4] else best
        else:
            best = _interpolant(problem, u, counted) or best
    # shrink: bisect the span count between the last miss and the best fit, the knots
    # equidistributing the best fit's error (the growth's misses had other knots: no
    # lower bound for the search but ``floor``)
    failed = floor
    while best[4] <= tol_n and fits < MAX_FIT_ROUNDS:
        hi = len(best[3]) - 1
        c = _worth(_span_errors(best[3], best[1], best[2]), tol_n, p)
        guess = max(int(np.ceil(SHRINK_SAFETY * c.sum())), int(np.ceil(MAX_SHRINK * hi)))
        step = max(1, int(np.ceil(SHRINK_RESOLUTION * hi)))
        if hi - failed <= step:
            break
        count = min(guess, hi - step) if failed == 0 else (failed + hi) // 2
        trial = _redistributed(best[3], c, count)
        curve, t, e, worst = attempt(trial, best[1])
        if worst <= tol_n:
            best = (curve, t, e, trial, worst)
        else:
            failed = count
    curve, t, ok = best[0], best[1], best[4] <= tol_n
    if plan.periodic:
        return curve, t, ok, fits, why, best[3]
    if ok:
        curve, t = _after_removal(problem, curve, t, tol_n, counted)
    if plan.recover:
        starts = np.stack([feet, u]) if regrown else u[None]
        curve, t, fits = _recovered(problem, curve, t, starts, ok, plan.most, tol_n, counted, fits, regrown)
        ok = float(_misses(np.asarray(curve.knots), p, curve.control_points, problem.Q, t)[counted].max()) <= tol_n
    return curve, t, ok, fits, why, np.unique(np.asarray(curve.knots))


def _interpolant(problem: _Problem, u: np.ndarray, counted: np.ndarray
                 ) -> Optional[Tuple[BSplineCurve, np.ndarray, np.ndarray, np.ndarray, float]]:
    """The curve through every point at its parameter u (global interpolation, Piegl &
    Tiller 9.2.1: averaged knots, eq. 9.8, which meet the Schoenberg-Whitney condition):
    one control point per point, the count a growth reaches when the least squares on its
    error-placed knots keep missing (50 points of a random walk, tol 1e-6: 50 control
    points 0.65 off; a repeated point's copies share one parameter and one control
    point). Returns (curve, u, misses, breakpoints, largest miss) as the growth's fits,
    or None where the points admit no interpolant (fewer distinct points than degree + 1)."""
    p = problem.p
    once = np.r_[True, np.diff(u) > 0]                  # repeated points: through one of them
    try:
        U = kv.averaged(u[once], p)
        curve = collocate(problem.Q[once], p, u[once], U)
    except CagdError:
        return None
    e = _misses(U, p, curve.control_points, problem.Q, u) * counted
    return curve, u, e, np.unique(U), float(e.max())


def _with_repeats(Q: np.ndarray, parameters: ParameterSpec,
                  rule: Callable[[np.ndarray, ParameterSpec], np.ndarray]) -> np.ndarray:
    """The points' parameters by ``rule`` (``parametrize`` or :func:`_closed_parameters`)
    with consecutive repeats of a point (a scan's duplicates) allowed: the rule runs on the
    distinct points (the chord rules need non-zero chords), each repeat takes its
    predecessor's parameter (the least squares weighs it twice). Explicit parameters go
    to the rule as given.

    Raises:
        CagdError: every point the same."""
    if not isinstance(parameters, str):
        return rule(Q, parameters)
    keep = _first_of_repeats(Q)
    if keep.all():
        return rule(Q, parameters)
    if np.count_nonzero(keep) < 2:
        raise CagdError("points: all points coincide; a fit needs at least two distinct points")
    return rule(Q[keep], parameters)[np.cumsum(keep) - 1]


def _first_of_repeats(Q: np.ndarray) -> np.ndarray:
    """True for the points that differ from their predecessor (the first point: True)."""
    return np.r_[True, np.any(Q[1:] != Q[:-1], axis=1)]


def _closed_parameters(Q: np.ndarray, parameters: ParameterSpec) -> np.ndarray:
    """Parameters 0 = t_0 < ... < t_(m-1) < 1 of points round a closed loop: the rule's
    interval lengths of the m chords, the closing one (last to first) included; explicit
    values must be increasing in [0, 1)."""
    from .parameters import chords, interval_lengths
    if not isinstance(parameters, str):
        t = _checks.increasing(parameters, len(Q), "parameters")
        if t[0] < 0.0 or t[-1] >= 1.0:
            raise CagdError(f"parameters: a closed fit's parameters lie in [0, 1), got {t[0]} .. {t[-1]}")
        return t
    h = interval_lengths(chords(np.vstack([Q, Q[:1]]), "points"), parameters)
    cum = np.concatenate([[0.0], np.cumsum(h)])
    return cum[:-1] / cum[-1]


def _after_removal(problem: _Problem, curve: BSplineCurve, t: np.ndarray, tol_n: float,
                   counted: np.ndarray) -> Tuple[BSplineCurve, np.ndarray]:
    """Tiller's knot removal within the slack tol - max miss, then one more fit on the
    knots left; kept only if every point stays within tol."""
    slack = tol_n - float(_misses(curve.knots, problem.p, curve.control_points, problem.Q, t)[counted].max())
    if not slack > 0.0 or len(curve.knots) <= 2 * (problem.p + 1):
        return curve, t
    removal = curve.remove_knots(slack)
    if removal.removed == 0:
        return curve, t
    reduced = removal.result
    assert isinstance(reduced, BSplineCurve)
    if len(reduced.control_points) < problem.least:       # held tangents need their poles
        return curve, t
    U = np.asarray(reduced.knots)
    c2, t2, e2 = _fit_on(problem, U, t, tol_n)
    if float(e2[counted].max()) <= tol_n:
        return c2, t2
    return curve, t


def _recovered(problem: _Problem, curve: BSplineCurve, t: np.ndarray, initial: np.ndarray, ok: bool, most: int,
               tol_n: float, counted: np.ndarray, fits: int, regrown: bool = False
               ) -> Tuple[BSplineCurve, np.ndarray, int]:
    """The knot-recovery stage (:func:`cagd.fitting.free_knots.recover_knots`, guided by
    the fit ``curve`` with the points' parameters t on it; ``initial`` (s, m) sets of
    parameters its search starts from: the regrowth's feet, then the points' first
    parameters): fewer control points than ``curve`` has (than ``most`` + 1 when it
    misses tol) with the interior knots moved, kept when every point is within tol. The
    search over counts runs only for a tol below SEARCH_TOL (the points' frame is the
    unit ball) when the adaptive fit missed it, needed SEARCH_FILL control points per
    point or more, or was ``regrown`` (its first growth stalled or missed at the cap): the
    exactness case, a sampled B-spline asked back, whose smooth pieces the adaptive
    knots cannot follow to that tol (ordinary data is spared the search's seconds: the
    anchor curve at tol 1e-5 takes 191 poles for 2,000 points)."""
    from .free_knots import recover_knots
    p = problem.p
    n = len(curve.control_points) if ok else most + 1
    if n <= problem.least:
        return curve, t, fits
    search = bool(tol_n <= SEARCH_TOL and (not ok or regrown or n >= SEARCH_FILL * np.count_nonzero(counted)))
    m = len(problem.Q)
    rows = _sample_rows(m, RECOVERY_POINTS) if m > RECOVERY_POINTS else np.arange(m)
    sub = problem if len(rows) == m or not problem.w[rows].max() > 0.0 else problem.subset(rows)
    rows = rows if sub is not problem else np.arange(m)
    found = recover_knots(sub, (np.asarray(curve.knots), curve.control_points, t[rows]), initial[:, rows], tol_n,
                          counted[rows], n - p - 2, search)
    if found is None:
        return curve, t, fits
    if sub is problem:
        return BSplineCurve(found[1], p, found[0]), found[2], fits + 1
    # the knots found on the sample, fitted to every point (from their feet on its curve,
    # started between the sampled points' own)
    start = _feet_from(found[0], p, found[1], problem.Q, rows, found[2]).t
    fitted, t2, e2 = _fit_on(problem, found[0], start, tol_n)
    if float(e2[counted].max()) > tol_n:
        return curve, t, fits + 1
    return fitted, t2, fits + 2


#: the knot-recovery stage runs on at most this many of the points (evenly spaced in their
#: order, both ends among them: its passes cost O(points) each, and 20,000 points of the
#: anchor curve spent 15 of their 18 s there, in vain); the knots it finds are then fitted
#: to every point and kept only when every point is within tol
RECOVERY_POINTS = 2000


#: the knot-recovery stage searches the counts below this tol (in the unit-ball frame),
#: when the adaptive fit misses tol or takes at least SEARCH_FILL control points per point
SEARCH_TOL = 1e-6
SEARCH_FILL = 0.5


def _measured(curve: BSplineCurve, Q: np.ndarray, t: np.ndarray, counted: np.ndarray, tol: float,
              rounds: int, why: Optional[str] = None) -> CurveFit:
    """The result measured by certified closest points; ``why`` the growth stopped short of
    tol (:func:`stalled`), for the message."""
    from ..queries.closest import closest_point
    near = closest_point(curve, Q)
    at_t = np.sqrt(((curve(t) - Q) ** 2).sum(-1))
    dist = np.minimum(near.distances, at_t)
    params = np.where(near.distances <= at_t, near.params, t)
    dist_c = dist[counted]
    worst, rms = float(dist_c.max()), float(np.sqrt(np.mean(dist_c ** 2)))
    ok = worst <= tol
    n = curve.control_points.shape[0]
    message = (f"{n} control points, every point within {worst:.3g} (tol {tol:g})" if ok else
               f"tol {tol:g} not met: {n} control points, largest distance {worst:.3g} "
               f"(the cap or {MAX_FIT_ROUNDS} rounds reached)" if why is None else
               f"tol {tol:g} not met: returned the grown fit with the smallest largest miss, {n} control points, "
               f"largest distance {worst:.3g} ({why})")
    return CurveFit(curve, worst, rms, params, rounds, ok, message)
