"""Curves through or near given points: Bezier through n+1 points (seed 000, 5.2.6),
global B-spline interpolation and least-squares approximation (Piegl & Tiller,
The NURBS Book, 9.2.1 and 9.4.1).
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bernstein import bernstein
from ..basis.banded import solve_banded_rows
from ..basis.bspline import basis_functions
from ..curves.bezier import BezierCurve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from .parameters import ParameterSpec, averaged_parameters, option


def parametrize(points: ArrayLike, parameters: ParameterSpec = "chord", *,
                method: Optional[ParameterSpec] = None) -> np.ndarray:
    """Parameters u_0 = 0 < u_1 < ... < u_n = 1 for the points Q_0..Q_n
    (Piegl & Tiller 9.2.1), ``parameters`` one of :data:`cagd.fitting.PARAMETERS`:

    * ``"uniform"``: u_k = k/n (equally spaced, eq. 9.3);
    * ``"chord"``: u_k = u_{k-1} + |Q_k - Q_{k-1}| / d, d the total chord length (eq. 9.5);
    * ``"centripetal"``: the same with |Q_k - Q_{k-1}|^(1/2) (eq. 9.6).

    Explicit values are returned as given after checking they are strictly increasing.
    ``method=`` is the deprecated name of ``parameters=`` (one release).

    Raises:
        CagdError: fewer than 2 points, an unknown name, coincident consecutive
            points (chord/centripetal), explicit parameters of the wrong length or
            not strictly increasing.
    """
    parameters = option(parameters, {"method": method}, "parametrize", "chord")
    Q = _checks.points(points, "points", min_count=2)
    if isinstance(parameters, str):
        return averaged_parameters(Q[:, None, :], parameters, "points", "points")
    return _checks.increasing(parameters, Q.shape[0], "parameters")


def bezier_through_points(points: ArrayLike, parameters: ParameterSpec = "uniform") -> BezierCurve:
    """The degree-n Bezier curve through the n+1 points Q_i at t_i (seed 000, 5.2.6
    "反求 Bezier 曲线控制点"): solve the (n+1)x(n+1) system
    Q_i = sum_j C(n,j) t_i^j (1-t_i)^(n-j) P_j for the control points P_j.
    The seed takes t_i = i/n (``"uniform"``); ``"chord"``, ``"centripetal"`` or
    explicit parameters 0 = t_0 < ... < t_n = 1 are also accepted.

    Solved in the points' normalised frame; the curve must then pass through its points
    within FIT_RESIDUAL_TOL = 1e-9 of their spread (the Bernstein system's condition
    grows like 2^n: uniform parameters reach it near degree 30).

    Raises:
        CagdError: fewer than 2 or more than MAX_DEGREE + 1 points, bad parameters
            (see :func:`parametrize`), explicit parameters not starting at 0 and
            ending at 1, a singular or ill-conditioned system.
    """
    Q = _checks.points(points, "points", min_count=2)
    t = parametrize(Q, parameters)
    if t[0] != 0.0 or t[-1] != 1.0:
        raise CagdError(f"parameters: a Bezier curve lives on [0, 1]; the parameters must start at 0 "
                        f"and end at 1, got {t[0]} .. {t[-1]}")
    n = _checks.degree(Q.shape[0] - 1, "points (their count - 1 is the degree)")
    center, scale = _frame(Q)
    try:
        P = np.linalg.solve(bernstein(n, t), (Q - center) / scale) * scale + center
    except np.linalg.LinAlgError:
        raise CagdError(f"parameters: the degree-{n} Bernstein system is singular for these parameters") from None
    P[0], P[-1] = Q[0], Q[-1]
    if not np.all(np.isfinite(P)):
        raise CagdError(f"points: the degree-{n} Bezier curve through them has control points beyond the "
                        f"floating-point range")
    curve = BezierCurve(P)
    _check_residual(curve(t), Q, scale, "bezier_through_points", f"degree {n}")
    return curve


def interpolate(points: ArrayLike, degree: int = 3, parameters: ParameterSpec = "chord",
                knots: Optional[ArrayLike] = None) -> BSplineCurve:
    """Global B-spline interpolation (Piegl & Tiller 9.2.1): the degree-p curve
    C(u) = sum_i N_{i,p}(u) P_i with C(u_k) = Q_k for all n+1 points.

    Parameters u_k by :func:`parametrize`; knots by averaging (eq. 9.8,
    :func:`cagd.knots.averaged`) unless a full knot vector of len(points) +
    degree + 1 values is given. The control points solve the collocation system
    [N_{i,p}(u_k)] P = Q.

    Raises:
        CagdError: fewer than 2 points, degree out of 1..min(len(points)-1, MAX_DEGREE),
            bad parameters, invalid knots, parameters outside the knots' domain,
            knots violating the Schoenberg-Whitney condition N_{k,p}(u_k) > 0
            (the system would be singular), an ill-conditioned system (see above).
    """
    Q = _checks.points(points, "points", min_count=2)
    count = Q.shape[0]
    p = _checks.degree(degree, "degree", 1, count - 1)
    u = parametrize(Q, parameters)
    if knots is None:
        U = kv.averaged(u, p)
    else:
        U = kv.validate(knots, p, count)
        a, b = U[p], U[count]
        if u[0] < a or u[-1] > b:
            raise CagdError(f"knots: the domain [{a}, {b}] does not contain the parameters "
                            f"[{u[0]}, {u[-1]}]")
    curve = collocate(Q, p, u, U)
    _check_residual(curve(u), Q, _frame(Q)[1], "interpolate", f"degree {p}, {count} points")
    return curve


def collocate(Q: np.ndarray, p: int, u: np.ndarray, U: np.ndarray) -> BSplineCurve:
    """The degree-p B-spline on the knots U through the points Q at the increasing
    parameters u (validated by the caller): the banded collocation solve of
    :func:`interpolate` without its residual check, for callers that measure the
    curve's error themselves (the intersection branch fit, whose tolerance is a distance).

    Raises:
        CagdError: Schoenberg-Whitney violated, or a singular system."""
    span = kv.find_span(U, p, u, len(Q))
    N = basis_functions(U, p, u, span)                      # (count, p+1): the band of each row
    _schoenberg_whitney(N, span - p, u)
    center, scale = _frame(Q)
    P = solve_banded_rows(span - p, N, (Q - center) / scale, "points") * scale + center
    ends = N[[0, -1], [0, -1]] == 1.0                 # clamped ends interpolate exactly
    P[0] = Q[0] if ends[0] else P[0]
    P[-1] = Q[-1] if ends[1] else P[-1]
    return BSplineCurve(P, p, U)


#: Largest accepted miss of a fitted curve at its points, relative to the point spread
#: (the bounding-box diagonal): interpolation must hit its points (issue 14).
FIT_RESIDUAL_TOL = 1e-9


def _frame(Q: np.ndarray) -> tuple:
    """(center, scale) of the points' bounding box, scale > 0 (its half diagonal), so that
    (Q - center) / scale lies in the unit ball: solves run in a normalised frame and
    cannot overflow (points at 1e300)."""
    lo, hi = Q.min(axis=0), Q.max(axis=0)
    center = 0.5 * lo + 0.5 * hi
    half = 0.5 * hi - 0.5 * lo
    scale = float(np.max(np.abs(half))) * np.sqrt(Q.shape[1])
    if not scale > 0.0:
        scale = max(float(np.max(np.abs(center))), 1.0)
    return center, scale


def _check_residual(values: np.ndarray, Q: np.ndarray, scale: float, func: str, what: str) -> None:
    """CagdError unless the curve's values at the parameters are within FIT_RESIDUAL_TOL
    of the points (relative to ``scale``)."""
    with np.errstate(over="ignore", invalid="ignore"):
        miss = float(np.max(np.abs(values - Q))) / scale
    if not miss <= FIT_RESIDUAL_TOL:
        raise CagdError(f"points: {func} ({what}) is ill-conditioned: the solved curve misses its points by "
                        f"{miss:.3g} of their spread (more than FIT_RESIDUAL_TOL = {FIT_RESIDUAL_TOL}); "
                        f"use a lower degree or fewer points")


def _schoenberg_whitney(N: np.ndarray, start: np.ndarray, u: np.ndarray) -> None:
    """A square collocation matrix with increasing sites is invertible iff its
    diagonal N_{k,p}(u_k) is non-zero (Schoenberg-Whitney; de Boor, A Practical
    Guide to Splines, XIII). ``N`` holds row k's non-zeros from column start[k]."""
    k = np.arange(len(u))
    off = k - start
    inside = (off >= 0) & (off < N.shape[1])
    diag = np.where(inside, N[k, np.clip(off, 0, N.shape[1] - 1)], 0.0)
    if np.any(diag <= 1e-14):
        k0 = int(np.argmax(diag <= 1e-14))
        raise CagdError(f"knots: Schoenberg-Whitney condition fails at parameters[{k0}] = {u[k0]} "
                        f"(N_{k0},p(u_{k0}) = {diag[k0]:.3g}); the interpolation system is singular")


#: Design matrices up to this many entries are solved densely by QR (numpy.linalg.lstsq,
#: error ~ cond(N) eps); larger ones by the banded normal equations (memory O(m p)), whose
#: error grows like cond(N)^2 eps, so their answer is checked by iterative refinement.
LSQ_DENSE_MAX = 4_000_000
#: Largest relative correction accepted from the second refinement step of the normal
#: equations; a larger one means cond(N)^2 eps is not small: the fit is refused.
LSQ_REFINE_TOL = 1e-10


def _least_squares(U: np.ndarray, p: int, sites: np.ndarray, count: int, Qn: np.ndarray) -> np.ndarray:
    """Interior control points P_1..P_{n-1} minimising sum |Q_k - C(ubar_k)|^2 with
    P_0 = Q_0, P_n = Q_m fixed (Piegl & Tiller eq. 9.63-9.67). Small systems (at most
    LSQ_DENSE_MAX matrix entries) by QR (numpy.linalg.lstsq); large ones by the normal
    equations (N^T N) P = N^T R, N^T N banded (bandwidth p), accumulated from the p+1
    local basis values of each site (O(m p^2), no dense m x n matrix), solved by block
    LU with two steps of iterative refinement (the second must be below
    LSQ_REFINE_TOL, else the system is too ill-conditioned for them: CagdError).

    Raises:
        CagdError: the system is singular (a knot span without parameters) or, for
            large systems, too ill-conditioned for the normal equations."""
    span = kv.find_span(U, p, sites, count)
    N = basis_functions(U, p, sites, span)                                  # (m-1, p+1)
    cols = span[:, None] - p + np.arange(p + 1)
    R = Qn[1:-1] - N[:, :1] * (cols[:, :1] == 0) * Qn[0] - N[:, -1:] * (cols[:, -1:] == count - 1) * Qn[-1]
    unknown = count - 2                                                     # columns 1..count-2 -> 0..
    c = cols - 1                                                            # unknown index per entry
    keep = (c >= 0) & (c < unknown)
    if len(sites) * unknown <= LSQ_DENSE_MAX:
        A = np.zeros((len(sites), unknown))
        rows = np.broadcast_to(np.arange(len(sites))[:, None], c.shape)
        A[rows[keep], c[keep]] = N[keep]
        sol, _, rank, _ = np.linalg.lstsq(A, R, rcond=None)
        if rank < unknown:
            raise CagdError(f"parameters: the least-squares system is rank deficient ({rank} < {unknown}); "
                            f"some knot span holds no parameter")
        return sol
    w = min(2 * p + 1, unknown)
    start = np.clip(np.arange(unknown) - p, 0, unknown - w)
    band = np.zeros((unknown, w))
    for a in range(p + 1):
        ia = keep[:, a]
        for b in range(p + 1):
            ib = ia & keep[:, b]
            i, j = c[ib, a], c[ib, b]
            np.add.at(band, (i, j - start[i]), N[ib, a] * N[ib, b])

    def gradient(resid: np.ndarray) -> np.ndarray:        # N^T resid, accumulated per local entry
        g = np.zeros((unknown, Qn.shape[1]))
        for a in range(p + 1):
            ia = keep[:, a]
            np.add.at(g, c[ia, a], N[ia, a, None] * resid[ia])
        return g

    def apply(x: np.ndarray) -> np.ndarray:               # N x at the sites
        xs = np.zeros((len(sites), Qn.shape[1]))
        for a in range(p + 1):
            ia = keep[:, a]
            xs[ia] += N[ia, a, None] * x[c[ia, a]]
        return xs

    try:
        x = solve_banded_rows(start, band, gradient(R), "parameters")
        for step in range(2):
            dx = solve_banded_rows(start, band, gradient(R - apply(x)), "parameters")
            x = x + dx
    except CagdError:
        raise CagdError("parameters: the least-squares system is singular; some knot span holds no "
                        "parameter") from None
    size = max(float(np.abs(x).max()), 1.0)
    if not float(np.abs(dx).max()) <= LSQ_REFINE_TOL * size:
        raise CagdError(f"parameters: the least-squares system is too ill-conditioned for the normal "
                        f"equations (refinement still moves the control points by "
                        f"{float(np.abs(dx).max()) / size:.3g} relative); use fewer control points")
    return x


def approximation_knots(params: ArrayLike, count: int, degree: int) -> np.ndarray:
    """Clamped knots for least-squares fitting with ``count`` = n+1 control points
    to m+1 parameters (Piegl & Tiller eq. 9.68, 9.69): d = (m+1)/(n-p+1) and for
    j = 1..n-p, i = int(j d), alpha = j d - i,
    u_{p+j} = (1 - alpha) ubar_{i-1} + alpha ubar_i. Every knot span then holds
    at least one parameter, so the normal equations are positive definite.

    Raises:
        CagdError: params not finite and 1-D, degree out of 1..MAX_DEGREE, count
            not in [degree + 1, len(params)]."""
    ub = _checks.finite_array(params, "params", ndim=1)
    degree = _checks.degree(degree, "degree", 1)
    count = _checks.integer(count, "count", degree + 1, max(len(ub), degree + 1))
    m, n, p = len(ub) - 1, count - 1, degree
    d = (m + 1) / (n - p + 1)
    jd = np.arange(1, n - p + 1) * d
    i = np.floor(jd).astype(int)
    alpha = jd - i
    inner = (1.0 - alpha) * ub[i - 1] + alpha * ub[i]
    return np.concatenate([np.full(p + 1, ub[0]), inner, np.full(p + 1, ub[-1])])


def approximate(points: ArrayLike, count: int, degree: int = 3, parameters: ParameterSpec = "chord") -> BSplineCurve:
    """Least-squares B-spline approximation with ``count`` control points that
    interpolates the first and last point (Piegl & Tiller 9.4.1).

    With points Q_0..Q_m, parameters ubar_k (:func:`parametrize`) and knots from
    :func:`approximation_knots` (eq. 9.69, meant for n < m; with ``count`` =
    len(points) they give a badly conditioned square system, condition ~3e5 for
    17 cubic points, so the interpolation knots of eq. 9.8 are used instead and
    the result is :func:`interpolate`'s curve), P_0 = Q_0, P_n = Q_m and the interior P_1..P_{n-1}
    minimise sum_{k=1}^{m-1} |Q_k - C(ubar_k)|^2, i.e. solve
    N P = R with R_k = Q_k - N_{0,p}(ubar_k) Q_0 - N_{n,p}(ubar_k) Q_m in the
    least-squares sense (eq. 9.63-9.67) in the points' normalised frame (points at 1e300
    or 1e-300 give the scaled curve): by QR for small systems, by the banded normal
    equations with iterative refinement for large ones (O(m p^2) time, no dense matrix;
    see LSQ_DENSE_MAX).

    Raises:
        CagdError: fewer than 2 points, ``count`` < degree + 1 or > len(points),
            degree < 1, bad parameters.
    """
    Q = _checks.points(points, "points", min_count=2)
    total = Q.shape[0]
    p = _checks.degree(degree, "degree", 1)
    count = _checks.integer(count, "count")
    if count < p + 1:
        raise CagdError(f"count: a degree-{p} curve needs at least degree + 1 = {p + 1} control points, "
                        f"got count = {count}")
    if count > total:
        raise CagdError(f"count: at most len(points) = {total} control points can be fitted "
                        f"to {total} points, got count = {count}")
    ub = parametrize(Q, parameters)
    U = kv.averaged(ub, p) if count == total else approximation_knots(ub, count, p)
    center, scale = _frame(Q)
    Qn = (Q - center) / scale
    P = np.empty((count, Q.shape[1]))
    P[0], P[-1] = Qn[0], Qn[-1]
    if count > 2:
        P[1:-1] = _least_squares(U, p, ub[1:-1], count, Qn)
    P = P * scale + center
    P[0], P[-1] = Q[0], Q[-1]                      # the ends are the points, bit for bit
    if count == total:
        curve = BSplineCurve(P, p, U)
        _check_residual(curve(ub), Q, scale, "approximate", f"degree {p}, {count} points")
        return curve
    return BSplineCurve(P, p, U)
