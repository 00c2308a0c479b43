"""Gordon surfaces: the surface through a network of profile and guide curves
(W. J. Gordon, "Spline-blended surface interpolation through curve networks",
J. Math. Mech. 18, 1969; Piegl & Tiller, The NURBS Book, 10.5. Seed 004's contents
list parametric and free-form surfaces (ch. 1 §3, ch. 3 §3) without the text, so the
books are cited).

With the profiles f_i (u along them) meeting the guides g_j (v along them) at
f_i(u_j) = g_j(v_i) = X_ij, the Gordon surface is the Boolean sum

    S = L_f + L_g - T,

L_f the profiles skinned across v (interpolated at v_i), L_g the guides skinned across
u (at u_j), T the tensor-product interpolant of the X_ij; with the same interpolation
(degree, knots) in each direction, S(u, v_i) = f_i(u) and S(u_j, v) = g_j(v). The three
B-spline surfaces are made compatible (degree elevation, knot merging: Piegl & Tiller
5.5, 5.3) and summed exactly. Every profile must meet every guide once, at one
parameter u_j common to all profiles (likewise v_i for the guides); a network whose
curves meet at differing parameters is first reparametrised (:func:`_refit`), which is
an approximation whose error ``max_error`` includes.

``max_error`` bounds the distance of the input curves from the surface: where the
surface contains the curves f~_i (the input curves exactly, or their refits) up to the
network's misses, S(u, v_i) - f~_i(u) = sum_j (g~_j(v_i) - X_ij) a_j(u), a_j the cardinal
interpolation splines along u, is a B-spline whose largest pole bounds it exactly
(convex hull property; likewise along v); a refit adds its sampled deviation from the
input curve. ``certify=True`` also measures the distance by the engine's certified
closest points at samples of every input curve (slower: the surface's closest-point
set-up dominates).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .. import _checks
from .._results import ReadOnlyArrays
from ..basis.bernstein import bernstein_values
from ..basis.bspline import basis_matrix
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..fitting.fit import _values
from ..knots import vectors as kv
from ._crossings import network_crossings
from .bspline import BSplineSurface
from .loft import compatible_plain, plain, rotated_start, unit_nurbs

SKIN_DEGREE = 3          # interpolation degree across the curves (lower with fewer curves)
REPARAM_SHARE = 0.01     # a family is reparametrised when the common parameters move an intersection by > this * tol
REFIT_SHARE = 0.3        # a reparametrised curve is fitted to within this * tol of the original (sampled)
REFIT_ROUNDS = 12        # knot-halving rounds of the refit, at most
REFIT_MAX_POLES = 2000   # poles of a refitted family, at most
REFIT_MIN_DEGREE = 3     # a refit is at least cubic (its error falls as h^(p+1))
REFIT_SAMPLES = 6        # fit samples per knot span
INVERSE_TABLE = 1025     # values of r bracketing r^-1 ...
INVERSE_ROUNDS = 60      # ... then regula falsi rounds, at most ...
INVERSE_RTOL = 2e-15     # ... stopping at this residual or step (r maps [0, 1] onto [0, 1])
ERROR_SAMPLES = 8        # samples per Bezier span of every input curve for max_error ...
ERROR_MIN_SAMPLES = 64   # ... at least this many per curve
MAX_CURVES = 200         # curves per family, at most
MAX_PAIRS = 2500         # profile-guide pairs, at most (one intersect each, ~10 ms)
SEAM_SNAP = 1e-12        # a closed profile meeting guides[0] this close to its start (or end) keeps its start
WEIGHT_RTOL = 1e-10      # crossings' weights match when c_i w_f = d_j w_g holds to this (relative)
INTERSECT_ANGLE_TOL = 1e-6   # cagd.intersect's defaults: tangential contact angle, radians ...
INTERSECT_DEPTH = 64         # ... subdivision depth ...
INTERSECT_PAIRS = 20000      # ... live piece pairs ...
INTERSECT_MIN_TOL = 1e-13    # ... and the smallest tol relative to the objects' size


@dataclass(frozen=True)
class GordonSurface(ReadOnlyArrays):
    """Result of :func:`gordon`: ``surface`` (an exact BSplineSurface on [0, 1]^2, u
    along the profiles, v along the guides); ``max_error`` an upper bound of the distance
    of the input curves from it (module docstring: exact where the surface contains them
    as iso-curves, plus the sampled deviation of a reparametrising refit);
    ``intersections`` (m, n, 2) the (u, v) of profile i and guide j on the surface, in
    the sorted order; ``profile_order``, ``guide_order`` the input indices in that
    order; ``reversed_profiles``, ``reversed_guides`` which inputs (by input index) run
    backwards; ``max_miss`` the largest gap between a profile and a guide where they
    meet; ``reparametrised`` which families ('profiles', 'guides') were refitted;
    ``certified_error`` (``certify=True``, else None) the largest certified closest-point
    distance of samples of the input curves (ERROR_SAMPLES per Bezier span, at least
    ERROR_MIN_SAMPLES per curve) from the surface, at most ``max_error``;
    ``converged`` is False when max_error exceeds tol (``message`` says so, and names a
    refit that did not reach its share REFIT_SHARE * tol)."""
    surface: BSplineSurface
    max_error: float
    intersections: np.ndarray
    profile_order: np.ndarray
    guide_order: np.ndarray
    reversed_profiles: np.ndarray
    reversed_guides: np.ndarray
    max_miss: float
    reparametrised: Tuple[str, ...]
    converged: bool
    message: str = ""
    certified_error: Optional[float] = None


def _family(curves: Sequence[Curve], name: str, tol: float, closed_ok: bool = False) -> List[BSplineCurve]:
    """The curves as polynomial B-splines clamped on [0, 1] (:func:`unit_nurbs`); closed
    ones (ends within tol) only where ``closed_ok`` and then all of them."""
    try:
        curves = list(curves)
    except TypeError:
        raise CagdError(f"{name}: expected a sequence of cagd curves, got {type(curves).__name__}") from None
    if not 2 <= len(curves) <= MAX_CURVES:
        raise CagdError(f"{name}: need 2 to {MAX_CURVES} curves, got {len(curves)}")
    out = [_polynomial_if_constant(unit_nurbs(c, f"{name}[{i}]")) for i, c in enumerate(curves)]
    closed = [_closed(c, tol) for c in out]
    if any(closed) and not closed_ok:
        i = closed.index(True)
        raise CagdError(f"{name}[{i}]: closed guides are not supported by gordon; pass the closed curves as "
                        "the profiles (a network closed both ways is not supported either)")
    if any(closed) and not all(closed):
        i = closed.index(not closed[0])
        raise CagdError(f"{name}[{i}]: is {'closed' if closed[i] else 'open'} while {name}[0] is not; "
                        f"the {name} must be all open or all closed")
    return out


def _polynomial_if_constant(c: BSplineCurve) -> BSplineCurve:
    """Equal weights cancel (sum N_i w P_i / sum N_i w = sum N_i P_i): such a curve is
    polynomial, exactly."""
    w = c.weights
    if w is not None and np.all(w == w[0]):
        return BSplineCurve(c.control_points, c.degree, c.knots)
    return c


def _closed(c: BSplineCurve, tol: float) -> bool:
    """Ends within tol (the curve is clamped: its ends are its end poles)."""
    return bool(np.linalg.norm(c.control_points[0] - c.control_points[-1]) <= tol)


def _intersections(profiles: List[BSplineCurve], guides: List[BSplineCurve], tol: float):
    """(u, v, miss, X) arrays (m, n), (m, n), (m, n), (m, n, dim): each profile-guide
    pair's one meeting point (the midpoint where they miss by up to tol): crossings at a
    clear angle all at once (:func:`._crossings.network_crossings`: box candidates, the
    hodograph cone test, batched Gauss-Newton), the other pairs by the subdivision of
    :func:`cagd.intersect` on curves prepared once (Bezier pieces), and
    :func:`cagd.min_distance` where no point is solved within tol."""
    from ..queries import _subdivision as sd
    from ..queries.distance import min_distance
    from ..queries._point_solver import run_many
    size = max(float(np.ptp(c.control_points, axis=0).max()) for c in profiles + guides)
    if tol < INTERSECT_MIN_TOL * size:
        raise CagdError(f"tol: {tol:g} is below {INTERSECT_MIN_TOL:g} of the network's size {size:.6g}, beyond "
                        "the precision of doubles there; pass a larger tol")
    U, V, miss, proven = network_crossings(profiles, guides, tol)
    # the rest by the general solver, each curve prepared once for all its pairs (what
    # cagd.intersect does per call)
    A: Dict[int, Any] = {}
    B: Dict[int, Any] = {}
    rest = list(zip(*np.nonzero(~proven)))
    for i, j in rest:
        if i not in A:
            A[i] = sd.Geometry(profiles[i], f"profiles[{i}]")
        if j not in B:
            B[j] = sd.Geometry(guides[j], f"guides[{j}]")
    found = run_many([(A[i], B[j]) for i, j in rest], tol, INTERSECT_ANGLE_TOL, INTERSECT_DEPTH, INTERSECT_PAIRS)
    for (i, j), res in zip(rest, found):          # (subdivided in lock step)
        f, g = profiles[i], guides[j]
        if not res.converged:
            raise CagdError(f"profiles[{i}], guides[{j}]: the intersection search did not settle "
                            f"({res.message})")
        if res.overlaps:
            raise CagdError(f"profiles[{i}], guides[{j}]: the curves overlap along a stretch, "
                            "not a network crossing")
        pts = [p for p in res.points if p.residual <= tol]
        if len(pts) > 1:
            spread = max(float(np.linalg.norm(q.point - pts[0].point)) for q in pts)
            if spread > tol:
                a = [round(float(np.asarray(q.param_a)), 6) for q in pts]
                raise CagdError(f"profiles[{i}], guides[{j}]: meet {len(pts)} times (at profile parameters "
                                f"{a}), a network needs exactly one crossing per pair")
        if pts:
            best = min(pts, key=lambda p: p.residual)
            s, t, d = float(np.asarray(best.param_a)), float(np.asarray(best.param_b)), best.residual
        else:
            r = min_distance(f, g)
            s, t, d = float(r.params[0]), float(r.params[1]), float(r.distance)
            if d > tol:
                raise CagdError(f"profiles[{i}], guides[{j}]: do not meet (they miss each other by {d:.3g} "
                                f"> tol {tol:g})")
        U[i, j], V[i, j], miss[i, j] = s, t, d
    X = 0.5 * (np.stack([f(u) for f, u in zip(profiles, U)]) + np.stack([g(v) for g, v in zip(guides, V.T)], axis=1))
    return U, V, miss, X


def _order(P: np.ndarray, name: str, other: str, index: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Order of the other family along the curves of this one (rows of P, their
    parameters at the other family's curves) and which rows run backwards."""
    order = np.argsort(P[0], kind="stable")
    Q = P[:, order]
    d = np.diff(Q, axis=1)
    up, down = np.all(d > 0, axis=1), np.all(d < 0, axis=1)
    bad = ~(up | down)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise CagdError(f"{name}[{index[i]}]: meets the {other} in another order than {name}[{index[0]}] "
                        f"(parameters {np.round(P[i], 6).tolist()}): not a grid-like network")
    return order, down


def _reparametrisation(x: np.ndarray, y: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """A monotone function r with r(x_j) = y_j (both increasing from 0 to 1): the C2
    cubic spline interpolant on averaged knots (Piegl & Tiller 9.2.1) when its B-spline
    coefficients increase (then r' >= 0: the derivative's coefficients are positive,
    Piegl & Tiller 3.3), else the monotone C1 cubic of :func:`_pchip`."""
    return _reparametrisations(x, y[None])[0]


def _reparametrisations(x: np.ndarray, Y: np.ndarray) -> List[Callable[[np.ndarray], np.ndarray]]:
    """:func:`_reparametrisation` for every row of Y on the same x: one solve and one pp
    form for all the splines (a curve with a coordinate per row)."""
    deg = min(3, len(x) - 1)
    knots = kv.averaged(x, deg)
    coef = np.linalg.solve(basis_matrix(knots, deg, x, len(x)), Y.T)          # (len(x), rows)
    increasing = np.all(np.diff(coef, axis=0) > 0, axis=0)
    pp = BSplineCurve(coef, deg, knots).ppform if increasing.any() else None  # s in [0, 1]: the pp form directly

    def spline(k: int) -> Callable[[np.ndarray], np.ndarray]:
        assert pp is not None
        return lambda s: np.minimum(np.maximum(pp(np.asarray(s, dtype=float))[:, k], 0.0), 1.0)
    return [spline(k) if up else _pchip(x, y) for k, (up, y) in enumerate(zip(increasing, Y))]


def _pchip(x: np.ndarray, y: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """Monotone piecewise cubic Hermite interpolant of increasing data (Fritsch & Carlson
    1980, the slopes of Fritsch & Butland): a reparametrisation function."""
    h, delta = np.diff(x), np.diff(y) / np.diff(x)
    d = np.zeros_like(x)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    d[1:-1] = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
    d[0], d[-1] = delta[0], delta[-1]

    def r(s: np.ndarray) -> np.ndarray:
        k = np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(h) - 1)
        t = (s - x[k]) / h[k]
        h00, h10, h01, h11 = (1 + 2 * t) * (1 - t) ** 2, t * (1 - t) ** 2, t * t * (3 - 2 * t), t * t * (t - 1)
        return np.clip(h00 * y[k] + h10 * h[k] * d[k] + h01 * y[k + 1] + h11 * h[k] * d[k + 1], 0.0, 1.0)
    return r


def _refit(curves: List[BSplineCurve], old: np.ndarray, new: np.ndarray, tol: float,
           name: str) -> Tuple[List[BSplineCurve], float, bool]:
    """Curves c_k reparametrised so that c~_k(new_j) = c_k(old_kj): c~_k ~ c_k o r_k, r_k
    monotone with r_k(new_j) = old_kj (:func:`_reparametrisation`), fitted by least squares
    on one common knot vector (the curves' simple knots mapped by r_k^-1, averaged; their
    multiple knots, kinks, mapped exactly and kept at their multiplicity) with the
    c_k(old_kj) as equality constraints (Piegl & Tiller 9.4.2, constrained fitting through
    the Lagrange system), spans halved where the parametric error (sampled between the
    fitting points, then bounded once the samples pass) exceeds
    REFIT_SHARE * tol; degree at least REFIT_MIN_DEGREE. Returns the curves, a bound of
    the largest |c~_k(s) - c_k(r_k(s))| (:func:`_deviation_bounds`) and whether it met
    REFIT_SHARE * tol."""
    p = max(max(c.degree for c in curves), REFIT_MIN_DEGREE)
    maps = _reparametrisations(new, np.asarray(old, dtype=float))
    mapped, sharp, sharp_mult, kinks = [], [], [], []
    for c, r in zip(curves, maps):
        e = c.elevate(p - c.degree) if c.degree < p else c
        interior = e.knots[p + 1:-p - 1]
        values, mult = kv.distinct_with_multiplicities(interior) if interior.size else (interior, interior)
        pre = _inverse(r, values)                                       # r^-1 of the curve's knots, exactly
        mapped.append(pre[mult == 1])                                   # the smooth ones averaged below,
        sharp.append(pre[mult > 1])                                     # the kinks kept exactly,
        sharp_mult.append(mult[mult > 1])                               # at their multiplicity
        kinks.append(_kinks(r, new, pre))
    if len({len(t) for t in mapped}) == 1:
        inner = np.mean(mapped, axis=0)                              # knot by knot
    else:
        pool = np.sort(np.concatenate(mapped))
        k = max(len(t) for t in mapped)
        inner = np.quantile(pool, np.arange(1, k + 1) / (k + 1))
    kink_at, kink_mult = _merged(np.concatenate(sharp), np.concatenate(sharp_mult).astype(int))
    breaks = np.unique(np.concatenate([[0.0], inner, kink_at, [1.0]]))
    homs = [_homogeneous(c) if c.is_rational else None for c in curves]
    target = REFIT_SHARE * tol
    err = np.inf
    ends = np.stack([c(o) for c, o in zip(curves, old)])                 # the constraints c_k(old_kj)
    for _ in range(REFIT_ROUNDS):
        mult = np.ones(len(breaks), int)
        mult[np.searchsorted(breaks, kink_at)] = kink_mult
        knots = np.concatenate([np.zeros(p + 1), np.repeat(breaks[1:-1], mult[1:-1]), np.ones(p + 1)])
        npoles = len(knots) - p - 1
        if npoles > REFIT_MAX_POLES:
            raise CagdError(f"{name}: reparametrising the curves to common intersection parameters needs more "
                            f"than {REFIT_MAX_POLES} poles for {target:g}; raise tol")
        frac = (np.arange(REFIT_SAMPLES) + 0.5) / REFIT_SAMPLES
        s = (breaks[:-1, None] + np.diff(breaks)[:, None] * frac).ravel()
        chk = (breaks[:-1, None] + np.diff(breaks)[:, None] * (frac + 0.5 / REFIT_SAMPLES)[:-1]).ravel()
        ns, nc = len(s), len(chk)
        B = basis_matrix(knots, p, np.concatenate([s, chk, new]), npoles)         # one basis call a round
        N, C = B[:ns], B[ns + nc:]
        at = np.stack([c(r(np.concatenate([s, chk]))) for c, r in zip(curves, maps)])   # one evaluation a curve
        ncon = len(new)
        K = np.zeros((npoles + ncon, npoles + ncon))
        K[:npoles, :npoles] = N.T @ N
        K[:npoles, npoles:], K[npoles:, :npoles] = C.T, C
        rhs = np.concatenate([np.einsum("ka,ckd->cad", N, at[:, :ns]), ends], axis=1)   # (count, npoles + ncon, dim)
        count, dim = rhs.shape[0], rhs.shape[2]
        try:
            sol = np.linalg.solve(K, rhs.transpose(1, 0, 2).reshape(npoles + ncon, -1))
        except np.linalg.LinAlgError:
            raise CagdError(f"{name}: the reparametrising fit is singular") from None
        sol = sol.reshape(npoles + ncon, count, dim)
        poles = sol[:npoles].transpose(1, 0, 2)                                  # (count, npoles, dim)
        # samples between the fitting points first (cheap); the bound once they pass
        at_chk = np.einsum("ka,acd->ckd", B[ns:ns + nc], sol[:npoles])
        dev = np.linalg.norm(at_chk - at[:, ns:], axis=2)
        if dev.max() > target:
            err = float(dev.max())
            bad = chk[np.any(dev > target, axis=0)]
        else:
            starts, bounds = _deviation_bounds(knots, p, poles, curves, homs, maps, np.concatenate(kinks))
            err = float(bounds.max())
            if err <= target:
                return [BSplineCurve(P, p, knots) for P in poles], err, True
            bad = starts[np.any(bounds > target, axis=0)]
        bad_spans = np.unique(np.clip(np.searchsorted(breaks, bad, side="right") - 1, 0, len(breaks) - 2))
        breaks = np.unique(np.concatenate([breaks, 0.5 * (breaks[bad_spans] + breaks[bad_spans + 1])]))
    # out of rounds: the last fit's error is reported as a bound too (it may have been sampled)
    err = max(err, float(_deviation_bounds(knots, p, poles, curves, homs, maps, np.concatenate(kinks))[1].max()))
    return [BSplineCurve(P, p, knots) for P in poles], err, False


def _merged(at: np.ndarray, mult: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Distinct interior values (0 < at < 1) with the largest multiplicity given to each."""
    keep = (at > 0.0) & (at < 1.0)
    at, mult = at[keep], mult[keep]
    values, index = np.unique(at, return_inverse=True)
    most = np.zeros(len(values), int)
    np.maximum.at(most, index, mult)
    return values, most


def _inverse(r: Callable[[np.ndarray], np.ndarray], y: np.ndarray) -> np.ndarray:
    """s with r(s) = y for an increasing r on [0, 1] with r(0) = 0, r(1) = 1: bracketed
    in a table of INVERSE_TABLE values, then the Illinois variant of regula falsi
    (superlinear; Dowell & Jarratt 1971), vectorized, at most INVERSE_ROUNDS rounds,
    stopping once every residual or step is within INVERSE_RTOL."""
    if y.size == 0:
        return y.copy()
    grid = np.linspace(0.0, 1.0, INVERSE_TABLE)
    table = r(grid)
    k = np.clip(np.searchsorted(table, y, side="right") - 1, 0, INVERSE_TABLE - 2)   # r(grid_k) <= y
    lo, hi = grid[k], grid[k + 1]
    flo, fhi = table[k] - y, table[k + 1] - y
    hit = np.where(flo == 0.0, lo, np.where(fhi == 0.0, hi, np.nan))      # y a table value
    exact = ~np.isnan(hit)
    s = hit                                   # NaN: no step taken yet
    last = np.zeros(y.shape, bool)            # the previous round moved lo
    done = exact
    for _ in range(INVERSE_ROUNDS):
        before = s
        with np.errstate(invalid="ignore", divide="ignore"):
            s = np.where(fhi > flo, lo - flo * (hi - lo) / (fhi - flo), 0.5 * (lo + hi))
        s = np.where(done, before, np.where((s > lo) & (s < hi), s, 0.5 * (lo + hi)))
        f = r(s) - y
        done = done | (np.abs(f) <= INVERSE_RTOL) | (np.abs(s - before) <= INVERSE_RTOL)   # settled: kept
        if done.all():
            break
        left = f < 0                      # the root is right of s: s becomes lo
        again = left == last              # the same end moved twice: the kept end's f halves
        lo, flo = np.where(left, s, lo), np.where(left, f, np.where(again, 0.5 * flo, flo))
        hi, fhi = np.where(left, hi, s), np.where(left, np.where(again, 0.5 * fhi, fhi), f)
        last = left
    return s


def _kinks(r: Callable[[np.ndarray], np.ndarray], x: np.ndarray, preimages: np.ndarray) -> np.ndarray:
    """Where c o r may break: the breaks of r (at most x and the interior knots of its
    spline on averaged knots, :func:`_reparametrisation`) and the ``preimages`` r^-1 of
    c's interior knots."""
    averaged = np.unique(kv.averaged(x, min(3, len(x) - 1)))[1:-1]
    return np.concatenate([x[1:-1], averaged, preimages])


def _deviation_bounds(knots: np.ndarray, p: int, poles: np.ndarray, curves: List[BSplineCurve],
                      homs: List[Optional[BSplineCurve]], maps: List[Callable[[np.ndarray], np.ndarray]],
                      kinks: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """A rigorous bound of |fitted_k(s) - c_k(r_k(s))| piece by piece for every curve k,
    the fitted curves of degree p on one knot vector with ``poles`` (count, npoles, dim):
    (piece starts, bounds (count, pieces)). Between the fitted knots and all the curves'
    ``kinks`` (:func:`_kinks`), w(r(s)) fitted(s) - C(r(s)) (C = w c the homogeneous
    numerator, w = 1 for a polynomial c; r piecewise cubic) is a polynomial of degree at
    most p + 3q (max(p, 3q) when w = 1); its Bernstein coefficients, found by
    interpolation at Chebyshev points, bound it (convex hull property, Farin ch. 5), and
    dividing by c's smallest weight bounds the deviation. Rounding: the coefficients
    carry about 1e3 ulps of the curves' size."""
    deg = max(p + 3 * c.degree if c.is_rational else max(p, 3 * c.degree) for c in curves)
    cuts = np.unique(np.concatenate([[0.0, 1.0], np.unique(knots)[1:-1], kinks]))
    a, h = cuts[:-1], np.diff(cuts)
    a, h = a[h > 0], h[h > 0]
    nodes = 0.5 - 0.5 * np.cos(np.pi * np.arange(deg + 1) / deg)           # Chebyshev-Lobatto on [0, 1]
    s = (a[:, None] + h[:, None] * nodes).ravel()
    count, npoles, dim = poles.shape
    fitted = _values(knots, p, poles.transpose(1, 0, 2).reshape(npoles, -1), s, 0)[0].reshape(len(s), count, dim)
    values = np.empty_like(fitted)
    smallest = np.ones(count)
    for k, (c, hom, r) in enumerate(zip(curves, homs, maps)):
        if hom is None:                                                    # w = 1
            values[:, k] = fitted[:, k] - c(r(s))
        else:
            H = hom(r(s))                                                  # (w c, w) = _homogeneous(c)
            values[:, k] = H[:, -1:] * fitted[:, k] - H[:, :-1]
            smallest[k] = float(hom.control_points[:, -1].min())
    coef = np.linalg.solve(bernstein_values(deg, nodes), values.reshape(len(a), deg + 1, -1))    # per piece
    norms = np.linalg.norm(coef.reshape(len(a), deg + 1, count, dim), axis=-1).max(axis=1)    # (pieces, count)
    return a, (norms / smallest).T


def _skin_coefficients(params: np.ndarray, degree: int, periodic: bool = False) -> Tuple[np.ndarray, np.ndarray]:
    """Knots and the matrix A (poles x data) of the interpolation at ``params``: clamped
    on averaged knots (Piegl & Tiller eq. 9.8, 9.2.1), A the inverse collocation matrix;
    or ``periodic`` with period 1 (params in [0, 1), params[0] = 0, ``degree`` odd: the
    knots are the parameters), A the poles of the periodic cardinal splines (interpolating
    the columns of the identity) after exact conversion to clamped knots on [0, 1]."""
    if not periodic:
        knots = kv.averaged(params, degree)
        return knots, np.linalg.inv(basis_matrix(knots, degree, params, len(params)))
    n = len(params)
    period = np.append(params, 1.0)
    collocation = BSplineCurve(np.eye(n), degree, period, periodic=True)(params)   # [N_i(t_k)]
    try:
        cardinal = BSplineCurve(np.linalg.inv(collocation), degree, period, periodic=True).clamped()
    except np.linalg.LinAlgError:
        raise CagdError(f"guides: the periodic interpolation through {n} guides at u = "
                        f"{np.round(params, 6).tolist()} is singular") from None
    return cardinal.knots, cardinal.control_points


def _compatible_nets(nets: List[Tuple[np.ndarray, int, np.ndarray]]) -> List[Tuple[np.ndarray, int, np.ndarray]]:
    """Nets (rows, ..., dim) with (degree, knots) along the rows made compatible along
    that direction: each as one curve with flattened points (compatible_plain, exact)."""
    curves = [BSplineCurve(P.reshape(P.shape[0], -1), p, k) for P, p, k in nets]
    out = compatible_plain(curves)
    return [(c.control_points.reshape((-1,) + P.shape[1:]), c.degree, c.knots) for c, (P, _, _) in zip(out, nets)]


def _boolean_sum(profiles: List[BSplineCurve], guides: List[BSplineCurve], us: np.ndarray, vs: np.ndarray,
                 X: np.ndarray, closed: bool = False) -> Tuple[np.ndarray, int, int, np.ndarray, np.ndarray,
                                                            np.ndarray, np.ndarray]:
    """S = L_f + L_g - T on [0, 1]^2 (profiles and guides each compatible, any dimension:
    also homogeneous coordinates): (poles, pu, pv, U, V, Df, Dg), Df the poles of
    S(u, v_i) - f_i(u) for every i and Dg those of S(u_j, v) - g_j(v) (their largest
    norms bound the distances exactly, by the convex hull property). ``closed``: the last
    guide repeats the first at u = 1 and the skin along u is the periodic cubic through
    the distinct guides, so L_g and T are as smooth across the seam as inside."""
    m, n = len(profiles), len(guides)
    dv = min(SKIN_DEGREE, m - 1)
    if closed:
        du = SKIN_DEGREE                                 # n - 1 >= 3 distinct guides
        Ku, Au = _skin_coefficients(us[:-1], du, periodic=True)
        Au = np.concatenate([Au, np.zeros((len(Au), 1))], axis=1)    # the repeated guide adds nothing
    else:
        du = min(SKIN_DEGREE, n - 1)
        Ku, Au = _skin_coefficients(us, du)              # along u, through the guides
    Kv, Av = _skin_coefficients(vs, dv)                  # along v, through the profiles
    F = np.stack([c.control_points for c in profiles])  # (m, nu, dim)
    G = np.stack([c.control_points for c in guides])    # (n, nv, dim)
    Lf = np.einsum("ai,ikd->kad", Av, F)                 # (nu, m, dim): poles along v interpolate
    Lg = np.einsum("aj,jkd->akd", Au, G)                 # (n, nv, dim)
    T = np.einsum("aj,bi,ijd->abd", Au, Av, X)           # (n, m, dim)
    pf, Uf = profiles[0].degree, profiles[0].knots
    qg, Vg = guides[0].degree, guides[0].knots
    # along u: Lf (pf, Uf), Lg and T (du, Ku); then along v: Lf and T (dv, Kv), Lg (qg, Vg)
    (Lf, pu, U), (Lg, _, _), (T, _, _) = _compatible_nets([(Lf, pf, Uf), (Lg, du, Ku), (T, du, Ku)])
    sw = [np.swapaxes(a, 0, 1) for a in (Lf, Lg, T)]
    (Lf, pv, V), (Lg, _, _), (T, _, _) = _compatible_nets([(sw[0], dv, Kv), (sw[1], qg, Vg), (sw[2], dv, Kv)])
    P = np.swapaxes(Lf + Lg - T, 0, 1)
    # S(u, v_i) - f_i(u) = sum_j (g_j(v_i) - X_ij) a_j(u), a_j the cardinal splines along u
    # (Lf(u, v_i) = f_i(u), T(u, v_i) = sum_j X_ij a_j(u)); likewise along v
    # the family's curves share degree and knots: one basis matrix each way
    Gv = np.einsum("ia,jad->ijd", basis_matrix(Vg, qg, vs, G.shape[1]), G)    # (m, n, dim): g_j(v_i)
    Fu = np.einsum("ja,iad->ijd", basis_matrix(Uf, pf, us, F.shape[1]), F)    # (m, n, dim): f_i(u_j)
    Df = np.einsum("aj,ijd->iad", Au, Gv - X)
    Dg = np.einsum("bi,ijd->jbd", Av, Fu - X)
    return P, pu, pv, U, V, Df, Dg


def gordon(profiles: Sequence[Curve], guides: Sequence[Curve], tol: float = 1e-6, *,
           certify: bool = False) -> GordonSurface:
    """The Gordon surface through a network of profiles and guides (Gordon 1969; Piegl &
    Tiller 10.5): S = L_f + L_g - T (module docstring), u along the profiles, v along the
    guides, on [0, 1]^2, skinned with degree min(3, count - 1) on averaged knots.

    Every profile must cross every guide exactly once (found by :func:`cagd.intersect`;
    curves missing each other by up to ``tol``, a distance in model units, are accepted
    and met at the midpoint; ``max_miss`` reports the largest gap), and both ends of
    every curve must lie on the first and last curve of the other family. The curves may
    come in any order and direction: they are sorted along profile 0 and guide 0 and
    reversed as needed (profile 0 keeps its direction). Where the curves of a family meet
    the other family at parameters that differ by more than REPARAM_SHARE * tol (as
    points), they are reparametrised approximately onto common parameters
    (:func:`_refit`); otherwise the curves are used exactly (degree elevation and knot
    merging) and the surface contains them as iso-curves up to the network's misses. ``max_error`` bounds the
    distance of the input curves either way (module docstring); ``certify`` measures it
    by certified closest points too.

    Rational curves (NURBS circles, conics): where the curves meet at common parameters
    and their weights match at the crossings up to one constant per curve (curves made
    alike, such as circles of one construction), the surface is the exact rational
    Gordon surface through them (:func:`_rational_sum`); otherwise the rational family is
    approximated by polynomial B-splines (:func:`_refit`, to REFIT_SHARE * tol, counted in
    ``max_error``, named in ``reparametrised`` and ``message``).

    Closed networks (a fuselage): closed profiles (ends within tol; all or none) around
    open guides give a surface closed in u: every ring is started (split and rejoined
    exactly, the joint pole the midpoint of its ends) where it meets ``guides[0]``,
    which becomes the seam S(0, v) = S(1, v) and is repeated at u = 1 in
    ``guide_order`` and ``intersections`` (n + 1 columns). The skin across the guides is
    the periodic cubic through them, so the surface is as smooth across the seam as the
    profiles are there (C2 for smooth rings). Closed guides are rejected (pass them as
    the profiles), and so is a network closed both ways.
    Bounded: at most MAX_CURVES curves per family and MAX_PAIRS pairs, one bounded :func:`cagd.intersect` per
    pair, at most REFIT_ROUNDS refits of at most REFIT_MAX_POLES poles.

    Raises:
        CagdError: fewer than 2 curves in a family (or more than MAX_CURVES, or more
            than MAX_PAIRS profile-guide pairs), a non-curve, a closed guide, open and
            closed profiles mixed, a closed network with fewer than 3 guides, curves of
            different dimensions, tol <= 0, a pair that does not meet within tol, meets
            more than once or whose intersection search does not settle (naming the
            pair), a curve meeting the other family in another order or not ending on
            its first and last curve, a reparametrisation needing more than
            REFIT_MAX_POLES.
    """
    tol = _checks.positive(tol, "tol")
    F, G = _family(profiles, "profiles", tol, closed_ok=True), _family(guides, "guides", tol)
    if len({c.dim for c in F + G}) > 1:
        raise CagdError("profiles, guides: all curves must have the same dimension")
    if len(F) * len(G) > MAX_PAIRS:
        raise CagdError(f"profiles, guides: {len(F)} x {len(G)} curves make more than {MAX_PAIRS} pairs to "
                        "intersect; split the network")
    inputs = F + G
    U, V, miss, X = _intersections(F, G, tol)
    pi, gi = np.arange(len(F)), np.arange(len(G))
    closed = _closed(F[0], tol)
    seam = 0.0
    if closed:      # every profile started where it meets guides[0], that guide repeated at u = 1
        if len(G) < 3:
            raise CagdError(f"guides: a closed network needs at least 3 guides, got {len(G)}")
        for i in range(len(F)):
            a = float(U[i, 0])
            if SEAM_SNAP < a < 1.0 - SEAM_SNAP:
                F[i], gap = rotated_start(F[i], a)
                seam = max(seam, gap)
            U[i] = np.mod(U[i] - a, 1.0)
            U[i, 0] = 0.0
        inner, rev_p = _order(U[:, 1:], "profiles", "guides", pi)
        gorder = np.concatenate([[0], 1 + inner])
        F = [c.reversed() if r else c for c, r in zip(F, rev_p)]
        U[rev_p, 1:] = 1.0 - U[rev_p, 1:]
        U, V, X, gi = U[:, gorder], V[:, gorder], X[:, gorder], gi[gorder]
        U = np.concatenate([U, np.ones((len(F), 1))], axis=1)
        V, X, gi = np.concatenate([V, V[:, :1]], axis=1), np.concatenate([X, X[:, :1]], axis=1), np.append(gi, gi[0])
        flip_p = np.zeros(len(F), bool)          # reversed already
    else:
        gorder, rev_p = _order(U, "profiles", "guides", pi)
        U, V, X, gi = U[:, gorder], V[:, gorder], X[:, gorder], gi[gorder]
        flip_p = rev_p
    porder, rev_g = _order(V.T, "guides", "profiles", gi)
    U, V, X, pi = U[porder], V[porder], X[porder], pi[porder]
    rev_p, flip_p = rev_p[porder], flip_p[porder]
    F = [F[i].reversed() if r else F[i] for i, r in zip(pi, flip_p)]
    G = [G[j].reversed() if r else G[j] for j, r in zip(gi, rev_g)]
    U = np.where(flip_p[:, None], 1.0 - U, U)
    V = np.where(rev_g[None, :], 1.0 - V, V)
    _ends(F, U, tol, "profiles", "guides", pi, gi)
    _ends(G, V.T, tol, "guides", "profiles", gi, pi)
    U[:, 0], U[:, -1], V[0], V[-1] = 0.0, 1.0, 0.0, 1.0
    us, vs = U.mean(axis=0), V.mean(axis=1)
    notes: List[str] = []
    refitted: List[str] = []
    exact = _rational_sum(F, G, U, V, us, vs, X, tol, closed) if any(c.is_rational for c in F + G) else None
    if exact is not None:
        S, iso_f, iso_g = exact
        fit_f = fit_g = 0.0
    else:
        F, fit_f, _ = _compatible_family(F, U, us, tol, "profiles", notes, refitted)
        G, fit_g, _ = _compatible_family(G, V.T, vs, tol, "guides", notes, refitted)
        P, pu, pv, Ku, Kv, Df, Dg = _boolean_sum(F, G, us, vs, X, closed)
        S = BSplineSurface(P, pu, pv, Ku, Kv)
        iso_f, iso_g = _largest(Df), _largest(Dg)
    err = max(fit_f + iso_f + seam, fit_g + iso_g)
    ok = err <= tol                      # a refit short of its share of tol is fine if the total is within
    if not ok:
        notes.append(f"max_error {err:.3g} > tol {tol:g}")
    certified = _certified_error(S, inputs) if certify else None
    grid = np.stack(np.broadcast_arrays(us[None, :], vs[:, None]), axis=-1)
    reversed_p = np.zeros(len(pi), bool)
    reversed_p[pi] = rev_p
    reversed_g = np.zeros(len(gi), bool)
    reversed_g[gi] = rev_g
    return GordonSurface(S, err, grid, pi, gi, reversed_p, reversed_g, float(miss.max()), tuple(refitted), ok,
                         "; ".join(notes), certified)


def _certified_error(surface: BSplineSurface, curves: Sequence[BSplineCurve]) -> float:
    """Largest certified closest-point distance of samples of the curves from the surface."""
    from ..queries.closest import closest_point
    pts = []
    for c in curves:
        spans = max(len(np.unique(c.knots)) - 1, 1)
        pts.append(c(np.linspace(0.0, 1.0, max(ERROR_MIN_SAMPLES, ERROR_SAMPLES * spans))))
    return float(closest_point(surface, np.concatenate(pts)).distances.max())


def _ends(curves: List[BSplineCurve], P: np.ndarray, tol: float, name: str, other: str, index: np.ndarray,
          other_index: np.ndarray) -> None:
    """Both ends of every curve (clamped: its end poles) lie on the first and last curve
    of the other family."""
    for k, c in enumerate(curves):
        met = c(np.array([P[k, 0], P[k, -1]]))
        for end, col, at in ((0.0, 0, met[0]), (1.0, -1, met[1])):
            gap = float(np.linalg.norm(c.control_points[col] - at))
            if gap > tol:
                which = "start" if end == 0.0 else "end"
                raise CagdError(f"{name}[{index[k]}]: its {which} is {gap:.3g} from where it meets "
                                f"{other}[{other_index[col]}]; every curve must end on the first and last "
                                f"curve of the other family")


def _largest(D: np.ndarray) -> float:
    return float(np.linalg.norm(D, axis=-1).max())


def _moved(curves: List[BSplineCurve], P: np.ndarray, common: np.ndarray) -> float:
    """How far the curves' points at the common parameters are from their meeting points."""
    n = len(common)

    def moved(c: BSplineCurve, p: np.ndarray) -> float:
        both = c(np.concatenate([common, p]))                     # one evaluation a curve
        return float(np.linalg.norm(both[:n] - both[n:], axis=1).max())
    return max(moved(c, p) for c, p in zip(curves, P))


def _compatible_family(curves: List[BSplineCurve], P: np.ndarray, common: np.ndarray, tol: float, name: str,
                       notes: List[str], refitted: List[str]) -> Tuple[List[BSplineCurve], float, bool]:
    """The family as polynomial B-splines on one degree and knot vector, meeting the other
    family at ``common``: exact (compatible_plain) when the curves are polynomial and the
    parameters P agree to REPARAM_SHARE * tol as points, else refitted (:func:`_refit`:
    also the polynomial approximation of rational curves)."""
    rational = any(c.is_rational for c in curves)
    if not rational and _moved(curves, P, common) <= REPARAM_SHARE * tol:
        return compatible_plain(curves), 0.0, True
    out, err, ok = _refit(curves, P, common, tol, name)
    refitted.append(name)
    if rational:
        notes.append(f"{name}: rational curves approximated by polynomial B-splines to {err:.3g} (the exact "
                     "rational surface needs curves meeting at common parameters with matching weights)")
    if not ok:
        notes.append(f"{name}: the reparametrising fit reached {err:.3g}, not {REFIT_SHARE * tol:g}")
    return out, err, ok


def _homogeneous(c: BSplineCurve) -> BSplineCurve:
    """(w P, w) as a polynomial B-spline (w = 1 for a polynomial curve)."""
    if c.is_rational:
        return plain(c)
    return BSplineCurve(np.column_stack([c.control_points, np.ones(len(c.control_points))]), c.degree, c.knots)


def _rational_sum(F: List[BSplineCurve], G: List[BSplineCurve], U: np.ndarray, V: np.ndarray, us: np.ndarray,
                  vs: np.ndarray, X: np.ndarray, tol: float, closed: bool
                  ) -> Optional[Tuple[BSplineSurface, float, float]]:
    """The exact rational Gordon surface (S, bound along the profiles, bound along the
    guides), or None where it does not exist this way. The Boolean sum is taken of the
    homogeneous curves (w P, w) (Piegl & Tiller 10.5 apply to them unchanged): with
    constants c_i, d_j such that c_i w_fi(u_j) = d_j w_gj(v_i) at every crossing, the
    curves c_i f_i^w and d_j g_j^w meet in homogeneous space and the sum contains every
    one of them. Needs curves already meeting at common parameters (no refit: a
    reparametrisation of a rational curve is not rational of its degree), log-ratios
    log(w_g / w_f) additive in i and j to WEIGHT_RTOL (then c, d are their row and
    column parts; a closed network also needs the seam guide's constant at both ends)
    and positive weights in the sum. The bounds: with delta, eps the position and weight
    parts of S^w - f^w and sigma S's weight, S - f = (delta - f eps) / sigma (taken about
    the network's centre, the sum being affine invariant)."""
    if max(_moved(F, U, us), _moved(G, V.T, vs)) > REPARAM_SHARE * tol:
        return None
    Hf, Hg = [_homogeneous(c) for c in F], [_homogeneous(c) for c in G]
    wf = np.stack([h(u)[:, -1] for h, u in zip(Hf, U)])                  # (m, n): w_fi at the crossings
    wg = np.stack([h(v)[:, -1] for h, v in zip(Hg, V.T)], axis=1)        # (m, n): w_gj there
    R = np.log(wg / wf)
    a, b = R.mean(axis=1), R.mean(axis=0) - R.mean()                     # R ~ a_i + b_j
    seam_ok = not closed or abs(b[-1] - b[0]) <= WEIGHT_RTOL
    if not (np.abs(R - a[:, None] - b[None, :]).max() <= WEIGHT_RTOL and seam_ok):
        return None
    c, d = np.exp(a), np.exp(-b)
    W = 0.5 * (c[:, None] * wf + d[None, :] * wg)
    Xh = np.concatenate([X * W[..., None], W[..., None]], axis=-1)
    Hf = compatible_plain([BSplineCurve(h.control_points * k, h.degree, h.knots) for h, k in zip(Hf, c)])
    Hg = compatible_plain([BSplineCurve(h.control_points * k, h.degree, h.knots) for h, k in zip(Hg, d)])
    P, pu, pv, Ku, Kv, Df, Dg = _boolean_sum(Hf, Hg, us, vs, Xh, closed)
    w = P[..., -1]
    if not w.min() > 0:
        return None
    pts = np.concatenate([h.control_points for h in F + G])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    reach = float(np.linalg.norm(pts - centre, axis=1).max())

    def bound(D: np.ndarray) -> float:
        delta = D[..., :-1] - centre * D[..., -1:]
        return float((np.linalg.norm(delta, axis=-1).max() + reach * np.abs(D[..., -1]).max()) / w.min())
    return BSplineSurface(P[..., :-1] / w[..., None], pu, pv, Ku, Kv, weights=w), bound(Df), bound(Dg)
