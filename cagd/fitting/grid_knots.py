"""Fewer control points for the separable grid fit of :func:`cagd.fit_surface` (issue 17)
by moving its interior knots: free-knot least squares on a grid.

After the grow / shrink / trim rounds (:mod:`cagd.fitting.fit_surface`), whose knots
equidistribute the error by de Boor's model (A Practical Guide to Splines, XII), a count
with one span fewer in a direction usually misses tol only because its knots sit where
the model, not the data, puts them. This stage tries such counts with the interior
breakpoints of both directions as unknowns (free-knot least squares: de Boor & Rice,
"Least squares cubic spline approximation II: variable knots", Purdue CSD TR 21, 1968;
Jupp, SIAM J. Numer. Anal. 15(2), 1978; the curve stage :mod:`cagd.fitting.free_knots`):

- the control points stay the separable least squares of the grid on the knots
  (variable projection: the grid's values of the fit are S_u Q S_v^T per coordinate, S_u =
  N_u F_u the ends-held smoothing operator of one direction,
  :func:`cagd.fitting.separable.ends_held_operator`), so the unknowns are the knots only;
- the objective is the L_p norm of the grid points' misses, p = TUNE_POWER (towards the
  largest miss, which tol bounds, yet smooth), minimised by Levenberg-Marquardt with
  Marquardt's diagonal scaling on the Gauss-Newton system of the reweighted least
  squares (weights e_k^(p-2): the gradient of sum e_k^p; the system times p - 1, the
  Newton step of sum e_k^p where the misses are linear in the knots); the step is
  stretched along its direction to the multiple of TUNE_STRETCH or p - 1 whose
  linearised misses have the smallest norm (far from the minimum Newton's method on e^p
  gains only 1/(p - 1) a pass), and no knot moves by more than TUNE_MOVE of the gap it
  moves into (:func:`cagd.fitting.free_knots._ordered_step`); a run that ends within
  TUNE_NEAR tol goes on with the norm of power TUNE_POLISH_POWER;
- the Jacobian is analytic (:meth:`_Direction.derivative`): the derivative of the
  ends-held projector (Golub & Pereyra, SIAM J. Numer. Anal. 10(2), 1973) with the knot
  derivative of the basis on the p + 2 columns a breakpoint touches
  (:func:`cagd.fitting.free_knots.knot_jacobian`), a few batched products per direction
  instead of one operator and one grid product per knot (the forward differences it
  replaced);
- a count is accepted as soon as every grid point is within tol at its parameters (an
  upper bound of its certified distance, which the caller measures) and the least
  squares on its knots stays conditioned; a count with one span fewer starts from the
  equidistributed knots (:func:`cagd.fitting.fit_surface._placed`), then from the
  accepted knots with the interior knot removed whose removal misses least (Tiller's
  idea of knot removal, Piegl & Tiller 5.4, scored by the refit instead of a bound);
  grids of COARSE_SITES a direction are tuned on every other site first. A count with
  no more spans per direction than one that failed is not tried, a run is ended when
  its rate of gain cannot reach its target in the passes left (:func:`_hopeless`), and
  the stage is skipped where the rounds' own fit is not conditioned with few poles per
  site (the degree's constant: degree 5's ends-held least squares is 15 on even sites).

On the 100 x 100 anchor of ``benchmarks/fitting.py`` (degree 3) the rounds' knots took
12 x 12 poles at tol 0.01 and 18 x 17 at 0.001; the moved knots 11 x 10 and 17 x 15 (the
next counts, 16 x 15 and 17 x 14, stayed at 1.1-1.25 tol: a local minimum or the count's
limit), in 0.23 s and 0.41 s CPU with the rounds (0.84 s and 1.8 s with forward
differences and plain Newton steps, the same session; degree="auto", whose later degrees
are not measured where they cannot win, 0.30 s and 0.64 s against 1.3 s and 2.3 s;
OPENBLAS_NUM_THREADS=1, min of 3 on a shared machine). The stage's work is bounded by
TUNE_EVALS, TUNE_PASSES, TUNE_MAX_ENTRIES. The combination (variable projection through
the separable operators, the L_p reweighting) is this project's own.
"""
from __future__ import annotations

from typing import Callable, Dict, Iterator, List, Optional, Tuple

import numpy as np

from ..knots.vectors import find_span
from .fit import _knots
from .free_knots import KNOT_DAMPING_DOWN, KNOT_DAMPING_MAX, KNOT_DAMPING_MIN, KNOT_DAMPING_START, \
    KNOT_DAMPING_UP, _ordered_step, knot_jacobian
from .separable import INTERLACE_SHARE, LEBESGUE_MAX, SeparableGrid, ends_held_operator, lebesgue

#: the power p of the L_p norm of the misses the knots minimise
TUNE_POWER = 8
#: Levenberg-Marquardt passes per count at most (each: a Jacobian and at least one trial
#: solve)
TUNE_PASSES = 20
#: separable evaluations (one direction's operator and one grid product each; a Jacobian
#: counts one per breakpoint, the forward differences it replaced) of the whole stage at
#: most, each counted as its work over that of a 100 x 100 grid's, (m + n) m n /
#: TUNE_UNIT, at least one (smaller grids: the calls' overhead; a 120 x 40 grid at degree
#: 1, 92 knots: 81 x 28 -> 72 x 28 poles in 3.3 s with forward differences, 0.17 s
#: without the stage; the 100 x 100 anchor now takes 630 at tol 0.01, 1,430 at 0.001)
TUNE_EVALS = 3000
TUNE_UNIT = 200 * 100 * 100
#: the stage is skipped where its Jacobian (m n d values per interior knot) or a
#: direction's smoothing operator (m x m) would hold more values than this (80 MB; the
#: passes hold up to four arrays of the Jacobian's size: it, its weighted rows, a
#: direction's block and a product's temporary)
TUNE_MAX_ENTRIES = 10 ** 7
#: a breakpoint moves by at most this fraction of the gap it moves into per pass (the
#: curve stage's MAX_KNOT_MOVE is 0.3, of the smaller gap; the grid's knots start far
#: from their places, and each pass costs a Jacobian)
TUNE_MOVE = 0.45
#: a pass that lowers the largest miss by less than this fraction counts as slow; the
#: count is given up after TUNE_SLOW slow passes in a row
TUNE_GAIN = 0.01
TUNE_SLOW = 2
#: a run that ends within TUNE_NEAR tol (above tol) goes on with the L_p norm of this power
#: (nearer the largest miss; on a 30 x 25 grid at tol 3e-4 a start ended at 1.002 tol)
TUNE_NEAR = 1.05
TUNE_POLISH_POWER = 16
#: the operators of this many breakpoint vectors per direction are kept by a tuner (fewer
#: where their m x m smoothing operators would hold more than TUNE_MAX_ENTRIES values, two
#: at least: the operators of a pass and of its trial step)
TUNE_CACHE = 8
_NOTHING = np.empty((0, 0, 0))


class _Direction:
    """One direction's ends-held least squares on the breakpoints at the sites t (t_0 = 0,
    t_(m-1) = 1): N (m, c), F (c, m) (:func:`cagd.fitting.separable.ends_held_operator`),
    S = N F, and (built on first use) dN (K, m, p + 2): the derivative of N in each of the
    K interior breakpoints b_j (:func:`cagd.fitting.free_knots.knot_jacobian`: de Boor's
    triangle differentiated in the knots, of p + 1 curves whose poles pick the basis
    functions by their index mod p + 1; m (p + 1) K values, not m c K), on the only
    columns it touches, j - 1 .. j + p (the basis functions whose support holds b_j)."""

    def __init__(self, breaks: np.ndarray, p: int, t: np.ndarray):
        self.breaks, self.p, self.t = breaks, p, t
        self.U = _knots(breaks, p)
        self.N, self.F = ends_held_operator(self.U, p, t)
        self.S = self.N @ self.F
        self._dN: Optional[np.ndarray] = None

    @property
    def dN(self) -> np.ndarray:
        if self._dN is None:
            p, c, K = self.p, self.N.shape[1], len(self.breaks) - 2
            # poles e_(i mod (p + 1)): on a span the p + 1 basis functions have distinct
            # residues, so coordinate r of the curve is the one of them with residue r
            residue = (np.arange(c)[:, None] % (p + 1) == np.arange(p + 1)).astype(float)
            G = knot_jacobian(self.U, p, residue, self.t)                       # (m, p + 1, K)
            cols = np.arange(K)[:, None] + np.arange(p + 2)                      # columns j - 1 .. j + p of b_j
            span = find_span(self.U, p, self.t, c)[None, :, None]
            live = (cols[:, None, :] >= span - p) & (cols[:, None, :] <= span)  # N_col non-zero at the site
            self._dN = np.where(live, G[:, cols % (p + 1), np.arange(K)[:, None]].transpose(1, 0, 2), 0.0)
        return self._dN

    def derivative(self, Y: np.ndarray, SY: np.ndarray, out: np.ndarray) -> None:
        """out (K, m, k) <- d(S Y) / d b_j for the data Y (m, k) (SY = S Y given). With the
        ends held, S Y = E + P (Y_int - E) on the interior rows (P = A A^+ the projector on
        the columns of A = N[1:-1, 1:-1], E the end poles' share), the end rows fixed; by
        the derivative of the projector (Golub & Pereyra, SIAM J. Numer. Anal. 10(2), 1973,
        Lemma 4.1: dP = (I - P) dA A^+ + (A^+)^T dA^T (I - P)) and (A^+)^T = A A^+ (A^+)^T:

            d(S Y)_int = G - A (A^+ G + A^+ (A^+)^T dA^T (S Y - Y)_int),  G = dN_int (F Y),

        with dN on its p + 2 columns (G: a product of that width per breakpoint), Z by
        products of c - 2 rows, A Z written into ``out``."""
        N, F, dN = self.N, self.F, self.dN
        K, m, w = dN.shape
        c, k = N.shape[1], Y.shape[1]
        out[:, 0] = 0.0
        out[:, -1] = 0.0
        if K == 0:
            return
        A, Ainv = N[1:-1, 1:-1], F[1:-1, 1:-1]
        cols = np.arange(K)[:, None] + np.arange(w)                        # b_j's columns j - 1 .. j + p
        dNi = dN[:, 1:-1]                                                  # (K, m - 2, p + 2)
        YZ = np.empty((K, 2 * w, k))
        YZ[:, :w] = (F @ Y)[cols]                                          # F Y on those columns
        YZ[:, w:] = dNi.transpose(0, 2, 1) @ (SY - Y)[1:-1]                # dA^T (S Y - Y)_int (ends: 0 below)
        inner = (cols >= 1) & (cols <= c - 2)
        C = Ainv @ Ainv.T
        L = np.empty((K, c - 2, 2 * w))
        L[:, :, :w] = Ainv @ dNi                                           # A^+ dN_int
        L[:, :, w:] = np.where(inner[:, None, :], C[:, np.clip(cols - 1, 0, c - 3)].transpose(1, 0, 2), 0.0)
        inside = out[:, 1:-1]
        np.matmul(A, L @ YZ, out=inside)                                   # A Z
        np.subtract(dNi @ YZ[:, :w], inside, out=inside)                   # G - A Z


class _Tuner:
    """The residuals S_u Q S_v^T - Q of the grid (m, n, d) for breakpoints per direction,
    and their Jacobian in the interior breakpoints; ``evals`` counts the work done. The
    directions' operators of the last TUNE_CACHE breakpoint vectors and the products
    Q S_v^T, S_u Q of the last ones are kept (a start's scoring moves one direction)."""

    def __init__(self, grid: SeparableGrid):
        self.grid = grid
        self.evals = 0.0
        self.unit = max(1.0, (grid.m + grid.n) * grid.m * grid.n / TUNE_UNIT)    # one evaluation's work
        self._scratch: Optional[np.ndarray] = None
        self._dirs: Tuple[Dict[bytes, _Direction], ...] = ({}, {})
        self._held: List[Tuple[bytes, np.ndarray]] = [(b"", _NOTHING), (b"", _NOTHING)]   # (key, S_u Q), (key, Q S_v^T)
        self._last = (b"", b"")

    def _direction(self, axis: int, breaks: np.ndarray) -> Tuple[bytes, _Direction]:
        key = breaks.tobytes()
        cache = self._dirs[axis]
        hit = cache.get(key)
        if hit is None:
            g = self.grid
            hit = _Direction(breaks, g.pu, g.u) if axis == 0 else _Direction(breaks, g.pv, g.v)
            sites = g.m if axis == 0 else g.n
            if len(cache) >= max(2, min(TUNE_CACHE, TUNE_MAX_ENTRIES // sites ** 2)):
                cache.pop(next(iter(cache)))
            cache[key] = hit
        return key, hit

    def _product(self, axis: int, key: bytes, S: np.ndarray) -> np.ndarray:
        """S_u Q (axis 0) or Q S_v^T (axis 1), (m, n, d), kept for the last key."""
        if self._held[axis][0] != key:
            Q = self.grid.Q
            self._held[axis] = (key, self._along_u(S, Q) if axis == 0 else self._along_v(S, Q))
        return self._held[axis][1]

    def _along_v(self, Sv: np.ndarray, X: np.ndarray) -> np.ndarray:
        """X (m, n, d) with S_v applied along v (every row), as one matrix product."""
        m, n, d = X.shape
        Y = Sv @ X.transpose(1, 0, 2).reshape(n, m * d)
        return Y.reshape(n, m, d).transpose(1, 0, 2)

    def _along_u(self, Su: np.ndarray, X: np.ndarray) -> np.ndarray:
        """X (m, n, d) with S_u applied along u (every column), as one matrix product."""
        return (Su @ X.reshape(X.shape[0], -1)).reshape(X.shape)

    def residuals(self, bu: np.ndarray, bv: np.ndarray) -> Tuple[np.ndarray, _Direction, _Direction]:
        self.evals += self.unit
        (ku, du), (kv, dv) = self._direction(0, bu), self._direction(1, bv)
        if ku == self._last[0] and kv != self._last[1]:                 # only v moved: S_u Q kept
            F = self._along_v(dv.S, self._product(0, ku, du.S))
        else:
            F = self._along_u(du.S, self._product(1, kv, dv.S))
        self._last = (ku, kv)
        return F - self.grid.Q, du, dv

    def jacobian(self, R: np.ndarray, du: _Direction, dv: _Direction, out: np.ndarray) -> np.ndarray:
        """out (interior breakpoints of u then of v, m n d) <- dR / d breakpoint
        (transposed), analytic (:meth:`_Direction.derivative`: R = S_u (Q S_v^T) - Q, one
        direction's operator moving, the other's product kept); counted as one evaluation
        per breakpoint (the forward differences it replaced: one operator each)."""
        Q = self.grid.Q
        m, n, d = Q.shape
        ku, kv = len(du.breaks) - 2, len(dv.breaks) - 2
        F = R + Q                                                          # S_u Q S_v^T
        Yv = self._product(1, dv.breaks.tobytes(), dv.S).reshape(m, n * d)     # Q S_v^T
        du.derivative(Yv, F.reshape(m, n * d), out[:ku].reshape(ku, m, n * d))
        if kv:
            Yu = self._product(0, du.breaks.tobytes(), du.S).transpose(1, 0, 2).reshape(n, m * d)   # S_u Q
            if self._scratch is None or self._scratch.shape != (kv, n, m * d):
                self._scratch = np.empty((kv, n, m * d))
            dv.derivative(Yu, F.transpose(1, 0, 2).reshape(n, m * d), self._scratch)
            out[ku:].reshape(kv, m, n, d)[...] = self._scratch.reshape(kv, n, m, d).transpose(0, 2, 1, 3)
        self.evals += (ku + kv) * self.unit
        return out


def _norms(R: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("...i,...i->...", R, R))


def tune_knots(tuner: _Tuner, bu: np.ndarray, bv: np.ndarray, tol: float, reach: Optional[float] = None,
               power: int = TUNE_POWER) -> Tuple[np.ndarray, np.ndarray, float]:
    """The breakpoints (bu, bv) moved by Levenberg-Marquardt on the L_p norm (p = power)
    of the grid's misses (module docstring) until every miss is within tol, the passes
    run out (TUNE_PASSES, TUNE_SLOW slow ones in a row, the damping beyond
    KNOT_DAMPING_MAX, :func:`_hopeless` towards ``reach``, default tol) or the
    evaluations (TUNE_EVALS). Returns the breakpoints with the smallest largest miss and
    that miss."""
    R, du, dv = tuner.residuals(bu, bv)
    e = _norms(R)
    best = (bu, bv, float(e.max()))
    lam, slow = KNOT_DAMPING_START, 0
    history = [best[2]]
    ku = len(bu) - 2
    Jt = np.empty((ku + len(bv) - 2, R.size))                 # the Jacobian's rows, reused by the passes
    Js = np.empty_like(Jt)                                    # ... times the square roots of the weights
    for _ in range(TUNE_PASSES):
        if best[2] <= tol or tuner.evals >= TUNE_EVALS or ku + len(bv) - 2 == 0:
            break
        top = float(e.max())
        w = np.repeat(((e / top) ** (power // 2 - 1)).ravel(), R.shape[-1])
        tuner.jacobian(R, du, dv, Jt)
        np.multiply(Jt, w, out=Js)
        A = Js @ Js.T
        g = Js @ (w * R.ravel())
        f0 = float(((e / top) ** power).sum())
        while True:
            try:
                dk = -np.linalg.solve((power - 1) * (A + lam * np.diag(np.diag(A) + 1e-300)), g)
            except np.linalg.LinAlgError:
                dk = np.zeros_like(g)
            for (nu, nv), needed in _stretched(Jt, R, top, dk, bu, bv, power, f0):
                R2, du2, dv2 = tuner.residuals(nu, nv)
                e2 = _norms(R2)
                f2 = float(((e2 / top) ** power).sum())
                if f2 < needed:
                    break
            if f2 < needed:
                bu, bv, R, du, dv, e = nu, nv, R2, du2, dv2, e2
                lam = max(lam / KNOT_DAMPING_DOWN, KNOT_DAMPING_MIN)
                break
            lam *= KNOT_DAMPING_UP
            if lam > KNOT_DAMPING_MAX or tuner.evals >= TUNE_EVALS:
                return best
        slow = slow + 1 if float(e.max()) > (1.0 - TUNE_GAIN) * best[2] else 0
        if float(e.max()) < best[2]:
            best = (bu, bv, float(e.max()))
        history.append(best[2])
        if slow >= TUNE_SLOW or _hopeless(history, tol if reach is None else reach):
            break
    return best


def _hopeless(history: List[float], reach: float) -> bool:
    """Whether the smallest largest misses of the passes so far (``history``, the start
    first), falling on at the mean rate of the last TUNE_SLOW passes through the passes
    left of TUNE_PASSES, would still miss ``reach`` (the runs that failed crept down by
    2-3 % a pass from twice tol; the ones that met tol fell faster)."""
    k = len(history) - 1
    if k < TUNE_SLOW:
        return False
    rate = (history[-1] / history[-1 - TUNE_SLOW]) ** (1.0 / TUNE_SLOW)
    return history[-1] * rate ** (TUNE_PASSES - k) > reach


#: the multiples of the Newton step of the L_p norm tried along its direction (the misses
#: predicted by the linearisation), and p - 1 (the step of the weighted least squares):
#: far from the minimum the largest miss dominates the sum, where Newton's method on e^p
#: gains only 1/(p - 1) of the way per pass (the starts' largest miss fell by 6/7 a pass
#: at p = 8)
TUNE_STRETCH = (1.0, 2.0, 3.0, 5.0)
#: a stretched step is taken if it gains at least this share of its predicted gain
TUNE_RATIO = 0.25


def _stretched(Jt: np.ndarray, R: np.ndarray, top: float, dk: np.ndarray, bu: np.ndarray, bv: np.ndarray,
               power: int, f0: float) -> List[Tuple[Tuple[np.ndarray, np.ndarray], float]]:
    """The breakpoints to try for the Newton step dk, each with the value of the L_p
    objective (f0 now) it must go below to be taken: the multiple of TUNE_STRETCH or
    p - 1 whose misses, linearised (R + J^T (a dk), each direction's step kept ordered by
    :func:`cagd.fitting.free_knots._ordered_step`), have the smallest L_p norm, taken if
    it gains at least TUNE_RATIO of the predicted gain (the trust-region ratio test,
    Nocedal & Wright 4.1), then (if that is not a) the step itself, taken if it gains."""
    ku = len(bu) - 2
    steps, fractions = [], []
    for a in TUNE_STRETCH + (power - 1.0,):
        su = _ordered_step(bu[1:-1], a * dk[:ku], TUNE_MOVE, directed=True)
        sv = _ordered_step(bv[1:-1], a * dk[ku:], TUNE_MOVE, directed=True)
        steps.append((np.concatenate([[0.0], su, [1.0]]), np.concatenate([[0.0], sv, [1.0]])))
        fractions.append((_fraction(bu[1:-1], su, dk[:ku]), _fraction(bv[1:-1], sv, dk[ku:])))
    D = np.stack([dk[:ku] @ Jt[:ku], dk[ku:] @ Jt[ku:]]).reshape((2,) + R.shape)    # J^T dk per direction
    X = R + np.tensordot(np.array(fractions), D, axes=1)                              # linearised misses per a
    f = ((np.einsum("a...i,a...i->a...", X, X) / top ** 2) ** (power // 2)).reshape(len(steps), -1).sum(axis=1)
    best = int(np.argmin(f))                                 # the first on a tie: the smaller step
    if best == 0:
        return [(steps[0], f0)]
    return [(steps[best], f0 - TUNE_RATIO * (f0 - f[best])), (steps[0], f0)]


def _fraction(inner: np.ndarray, moved: np.ndarray, dk: np.ndarray) -> float:
    """a with moved = inner + a dk (0 where dk is 0)."""
    k = int(np.argmax(np.abs(dk))) if dk.size else 0
    return float((moved[k] - inner[k]) / dk[k]) if dk.size and dk[k] != 0.0 else 0.0


def _starts(tuner: _Tuner, best: tuple, axis: int, placed: np.ndarray) -> Iterator[Tuple[np.ndarray, np.ndarray]]:
    """The starts of a count with one span fewer along ``axis``: ``placed`` (the
    equidistributed breakpoints), then (scored only when asked for) the fit's own
    breakpoints with one interior one removed (the knots tuned for the count before keep
    their places), the one whose grid fit has the smallest largest miss."""
    own = best[1 + axis]

    def pair(b: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        return (b, best[2]) if axis == 0 else (best[1], b)
    yield pair(placed)
    scored = [(float(_norms(tuner.residuals(*pair(np.delete(own, j)))[0]).max()), j) for j in range(1, len(own) - 1)]
    if scored:
        yield pair(np.delete(own, min(scored)[1]))


def _conditioned(grid: SeparableGrid, bu: np.ndarray, bv: np.ndarray) -> bool:
    """Whether the least squares on the tuned breakpoints amplifies the data by at most
    LEBESGUE_MAX per direction (:func:`cagd.fitting.separable.lebesgue`: the sites
    determine the poles and no pole hangs on a site or two; knots moved close together
    could leave a span with few sites)."""
    return (lebesgue(bu, grid.pu, np.unique(grid.u)) <= LEBESGUE_MAX
            and lebesgue(bv, grid.pv, np.unique(grid.v)) <= LEBESGUE_MAX)


#: grids with at least this many sites a direction are tuned on every other site first
#: (towards COARSE_TARGET * tol: the sites between miss more), and on all of them only
#: where that came within COARSE_REACH * tol
COARSE_SITES = 40
COARSE_TARGET = 0.9
COARSE_REACH = 1.0


def _coarse(grid: SeparableGrid) -> Optional[_Tuner]:
    """A tuner of every other site of the grid in both directions (the last kept: the ends
    held), or None below COARSE_SITES: about an eighth of the work per evaluation; a
    count that misses tol there misses it on the whole grid too (the same knots and a
    subset of the points, their least squares refitted: not a bound, a cheap filter)."""
    if min(grid.m, grid.n) < COARSE_SITES:
        return None
    iu = np.unique(np.r_[np.arange(0, grid.m, 2), grid.m - 1])
    iv = np.unique(np.r_[np.arange(0, grid.n, 2), grid.n - 1])
    return _Tuner(SeparableGrid(grid.Q[np.ix_(iu, iv)], grid.u[iu], grid.v[iv], grid.pu, grid.pv))


def fewer_spans(grid: SeparableGrid, best: tuple, tol: float,
                fewer: Callable[[tuple, int], np.ndarray]) -> Tuple[tuple, int]:
    """From the grid fit ``best`` = (poles, breaks_u, breaks_v, largest miss, misses (m, n))
    within tol: one span fewer along the direction with more spans (then the other),
    ``fewer(fit, axis)`` its breakpoints, the knots of both directions tuned
    (:func:`tune_knots`), kept while every point stays within tol and the least squares
    stays conditioned (:func:`_conditioned`); until both directions fail or TUNE_EVALS
    (none where the Jacobian would exceed TUNE_MAX_ENTRIES). A count with no more spans
    per direction than one that failed is not tried (more spans hold the fewer: a knot
    inserted keeps the spline, Piegl & Tiller 5.2; the tuner is local, so this is the
    likely outcome, not a bound). Returns (best, counts tried)."""
    tuner, coarse = _Tuner(grid), _coarse(grid)
    tries = 0
    failed: List[Tuple[int, int]] = []
    knots = len(best[1]) + len(best[2]) - 4
    if max(grid.m * grid.n * grid.d * knots, grid.m ** 2, grid.n ** 2) > TUNE_MAX_ENTRIES:
        return best, tries
    sparse = all(len(b) - 1 + p <= INTERLACE_SHARE * len(np.unique(t))
                 for b, p, t in ((best[1], grid.pu, grid.u), (best[2], grid.pv, grid.v)))
    if sparse and not _conditioned(grid, best[1], best[2]):
        return best, tries               # the degree's own constant, not the sites': fewer spans keep it
    while best[3] <= tol and tuner.evals < TUNE_EVALS:
        spans = (len(best[1]) - 1, len(best[2]) - 1)
        order = (0, 1) if spans[0] >= spans[1] else (1, 0)
        found: Optional[tuple] = None
        for axis in order:
            count = (spans[0] - (axis == 0), spans[1] - (axis == 1))
            if spans[axis] <= 1 or tuner.evals >= TUNE_EVALS or any(f[0] >= count[0] and f[1] >= count[1]
                                                                     for f in failed):
                continue
            for bu, bv in _starts(tuner, best, axis, fewer(best, axis)):
                tries += 1
                if coarse is not None:             # first on every other site: a miss there is one
                    bu, bv, near = tune_knots(coarse, bu, bv, COARSE_TARGET * tol, COARSE_REACH * tol)
                    tuner.evals += coarse.evals
                    coarse.evals = 0.0
                    if near > COARSE_REACH * tol:
                        continue
                bu, bv, near = tune_knots(tuner, bu, bv, tol)
                if tol < near <= TUNE_NEAR * tol:     # close: on with the norm nearer the largest miss
                    bu, bv, _ = tune_knots(tuner, bu, bv, tol, power=TUNE_POLISH_POWER)
                P, miss = grid.fit(bu, bv)
                if float(miss.max()) <= tol and _conditioned(grid, bu, bv):
                    found = (P, bu, bv, float(miss.max()), miss)
                    break
            if found is not None:
                break
            failed.append(count)
        if found is None:
            break
        best = found
    return best, tries
