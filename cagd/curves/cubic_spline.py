"""Interpolating C2 cubic splines (seed 000, 5.1.2 "natural cubic spline interpolation").

The spline through p_0..p_n at parameters t_0 < ... < t_n is stored in Hermite
form: on [t_i, t_{i+1}] (h_i = t_{i+1} - t_i, delta_i = (p_{i+1} - p_i)/h_i) it
is the Hermite cubic with the knot derivatives m_i, m_{i+1}. C2 continuity at an
interior knot t_i is the tridiagonal equation (de Boor, A Practical Guide to
Splines, ch. IV; Farin, Curves and Surfaces for CAGD, 9.3)

    h_i m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_{i-1} m_{i+1} = 3 (h_i delta_{i-1} + h_{i-1} delta_i),

obtained by equating S''(t_i-) = (2 m_{i-1} + 4 m_i - 6 delta_{i-1}) / h_{i-1} and
S''(t_i+) = (6 delta_i - 4 m_i - 2 m_{i+1}) / h_i. The two missing equations come
from the end condition.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError
from .._deprecation import deprecated
from ..fitting.parameters import ParameterSpec
from ..fitting.parameters import chords as _chords, interval_lengths, option, rule, spline_parameters  # noqa: F401
from ..knots.vectors import periodic_extend
from .bspline import BSplineCurve
from .hermite import HermiteSpline, _blossom_control_points

END_CONDITIONS = ("natural", "clamped", "periodic", "virtual")


# --- banded solvers -------------------------------------------------------------------------
def solve_tridiagonal(lower: ArrayLike, diag: ArrayLike, upper: ArrayLike, rhs: ArrayLike) -> np.ndarray:
    """Solve the tridiagonal system lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1]
    = rhs[i] by the Thomas algorithm (Gaussian elimination without pivoting;
    stable for diagonally dominant matrices). lower[0] and upper[-1] are ignored.
    ``rhs`` is (n,) or (n, k): the k right-hand sides are solved together.

    Raises:
        CagdError: mismatched lengths, or a zero pivot (singular, or a matrix that
            needs pivoting).
    """
    a, b, c = (_checks.finite_array(v, name) for v, name in ((lower, "lower"), (diag, "diag"), (upper, "upper")))
    d = _checks.finite_array(rhs, "rhs")
    n = b.shape[0] if b.ndim == 1 else 0
    if n < 1 or d.ndim not in (1, 2) or a.shape != (n,) or c.shape != (n,) or d.shape[0] != n:
        raise CagdError(f"rhs: lower, diag, upper need shape ({n},) and rhs {n} rows; got "
                        f"{a.shape}, {b.shape}, {c.shape}, {d.shape}")
    # pivots once (they depend on the matrix only), then each column; plain floats
    # because the recurrences are sequential (a Python loop beats per-row numpy calls)
    av, cv = a.tolist(), c.tolist()
    den, cp = b.tolist(), [0.0] * n
    for i in range(n):
        if i:
            den[i] -= av[i] * cp[i - 1]
        if den[i] == 0.0:
            raise CagdError(f"diag: zero pivot in row {i} (singular matrix, or one that needs pivoting)")
        cp[i] = cv[i] / den[i]
    cols = (d[:, None] if d.ndim == 1 else d.reshape(n, -1)).T.tolist()
    for x in cols:
        x[0] /= den[0]
        for i in range(1, n):
            x[i] = (x[i] - av[i] * x[i - 1]) / den[i]
        for i in range(n - 2, -1, -1):
            x[i] -= cp[i] * x[i + 1]
    out = np.array(cols).T.reshape(d.shape)
    if not np.all(np.isfinite(out)):
        raise CagdError("diag: the solution overflows (a nearly singular system)")
    return out


def solve_cyclic_tridiagonal(lower: ArrayLike, diag: ArrayLike, upper: ArrayLike, rhs: ArrayLike) -> np.ndarray:
    """Solve the cyclic tridiagonal system whose corners are lower[0] (row 0, column
    n-1) and upper[-1] (row n-1, column 0), n >= 2, by the Sherman-Morrison formula
    around the Thomas algorithm (Numerical Recipes, 2.7 "cyclic"): one tridiagonal
    solve with two sets of right-hand sides, no dense matrix.

    Raises:
        CagdError: n < 2, mismatched lengths, or a zero pivot.
    """
    a, b, c = (_checks.finite_array(v, name) for v, name in ((lower, "lower"), (diag, "diag"), (upper, "upper")))
    d = _checks.finite_array(rhs, "rhs")
    n = b.shape[0] if b.ndim == 1 else 0
    if d.ndim not in (1, 2):
        raise CagdError(f"rhs: expected shape (n,) or (n, k), got {d.shape}")
    if n < 2:
        raise CagdError(f"diag: a cyclic system needs at least 2 unknowns, got {n}")
    if a.shape != (n,) or c.shape != (n,) or d.shape[0] != n:
        raise CagdError(f"rhs: lower, diag, upper need shape ({n},) and rhs {n} rows; got "
                        f"{a.shape}, {b.shape}, {c.shape}, {d.shape}")
    beta, alpha = a[0], c[-1]
    gamma = -b[0]
    if gamma == 0.0:
        raise CagdError("diag: zero pivot in row 0")
    bb = b.copy()
    bb[0] -= gamma
    bb[-1] -= alpha * beta / gamma
    vec = d.ndim == 1
    d2 = d[:, None] if vec else d
    u = np.zeros((n, 1))
    u[0, 0], u[-1, 0] = gamma, alpha
    sol = solve_tridiagonal(a, bb, c, np.hstack([d2, u]))
    x, z = sol[:, :-1], sol[:, -1]
    denom = 1.0 + z[0] + beta * z[-1] / gamma
    if denom == 0.0:
        raise CagdError("diag: the cyclic matrix is singular")
    x = x - np.outer(z, (x[0] + beta * x[-1] / gamma) / denom)
    if not np.all(np.isfinite(x)):
        raise CagdError("diag: the solution overflows (a nearly singular system)")
    return x[:, 0] if vec else x


# --- the spline ---------------------------------------------------------------------------------
def _natural_tangents(P: np.ndarray, t: np.ndarray, ends: Optional[np.ndarray] = None) -> np.ndarray:
    """Knot derivatives of the C2 spline: S''(t_0) = S''(t_n) = 0 ("natural",
    2 m_0 + m_1 = 3 delta_0 and m_{n-1} + 2 m_n = 3 delta_{n-1}), or the given end
    derivatives ``ends = (d0, dn)`` ("clamped": m_0 = d0, m_n = dn)."""
    h = np.diff(t)
    with np.errstate(over="ignore", invalid="ignore"):
        delta = np.diff(P, axis=0) / h[:, None]
        interior = 3.0 * (h[1:, None] * delta[:-1] + h[:-1, None] * delta[1:])
    if ends is None:
        lower = np.concatenate([[0.0], h[1:], [1.0]])
        diag = np.concatenate([[2.0], 2.0 * (h[:-1] + h[1:]), [2.0]])
        upper = np.concatenate([[1.0], h[:-1], [0.0]])
        rhs = np.vstack([3.0 * delta[:1], interior, 3.0 * delta[-1:]])
    else:
        lower = np.concatenate([[0.0], h[1:], [0.0]])
        diag = np.concatenate([[1.0], 2.0 * (h[:-1] + h[1:]), [1.0]])
        upper = np.concatenate([[0.0], h[:-1], [0.0]])
        rhs = np.vstack([ends[:1], interior, ends[1:]])
    _finite_system(t, diag, rhs)
    return solve_tridiagonal(lower, diag, upper, rhs)


def _finite_system(t: np.ndarray, *parts: np.ndarray) -> None:
    """The tangent system's coefficients must be finite (a parameter step of 5e-324 makes
    the chord slopes overflow): CagdError naming the parameters."""
    with np.errstate(over="ignore", invalid="ignore"):
        ok = all(np.all(np.isfinite(x)) for x in parts)
    if not ok:
        raise CagdError("parameters: the spline's tangent system overflows (parameter steps of "
                        f"{float(np.diff(t).min()):.3g} against point spacing; use chord or uniform spacing)")


def _periodic_tangents(P: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The C2 equations at every knot, indices modulo n (t_{-1} = t_{n-1} - T):
    a cyclic tridiagonal system in m_0..m_{n-1}; m_n = m_0."""
    h = np.diff(t)
    delta = np.diff(P, axis=0) / h[:, None]
    hp, dp = np.roll(h, 1), np.roll(delta, 1, axis=0)           # h_{i-1}, delta_{i-1}
    with np.errstate(over="ignore", invalid="ignore"):
        rhs = 3.0 * (h[:, None] * dp + hp[:, None] * delta)
    _finite_system(t, rhs)
    m = solve_cyclic_tridiagonal(h, 2.0 * (hp + h), hp, rhs)
    return np.vstack([m, m[:1]])


class CubicSpline(HermiteSpline):
    """Interpolating C2 cubic spline through points p_0..p_n (seed 000, 5.1.2).

    Args:
        points: (n+1, dim) points, no two consecutive ones equal.
        end_condition: the two extra equations (seed 000, 5.1.2 (3)):
            "natural": S''(t_0) = S''(t_n) = 0 (the seed's option 1);
            "clamped": S'(t_0) = d0, S'(t_n) = dn with ``tangents = (d0, dn)``,
                derivatives with respect to the parameter t;
            "periodic": closed curve, C2 at the seam. points[-1] must equal
                points[0] within 1e-12 * (bounding-box diagonal) and is then set to
                points[0] exactly; at least 3 distinct points;
            "virtual": the seed's option 2, two virtual points p_{-1}, p_{n+1}
                (``virtual_points``, default the reflections 2 p_0 - p_1 and
                2 p_n - p_{n-1}) make every p_i an interior point. Implemented as:
                the natural spline through p_{-1}, p_0, ..., p_n, p_{n+1} (C2 at all
                of p_0..p_n, S'' = 0 at the virtual points) restricted to
                [t_0, t_n]. The virtual intervals follow the ``parameters`` rule
                (with explicit parameters they copy h_0 and h_{n-1}).
        parameters: one of :data:`cagd.fitting.PARAMETERS`, "uniform", "chord"
            (default) or "centripetal" (see :func:`spline_parameters`), or explicit
            strictly increasing t_0..t_n.
        parametrization: deprecated name of ``parameters`` (one release); so is
            passing explicit parameters as the sixth positional argument.

    Attributes: ``points``, ``tangents`` (the solved knot derivatives m_i),
    ``parameters`` (the values t_i), ``end_condition``, ``parametrization`` (the rule
    they came from, None when they were given, or kept through ``transformed``),
    ``end_tangents``, ``virtual_points``, ``periodic``.

    Raises:
        CagdError: too few points, NaN/inf, coincident consecutive points, an
            unknown end condition or parametrisation, a missing/misshapen
            ``tangents`` or ``virtual_points`` (or one given for another end
            condition), non-increasing or miscounted parameters, an open point
            list for "periodic".
    """

    def __init__(self, points: ArrayLike, end_condition: str = "natural", parameters: ParameterSpec = "chord",
                 tangents: Optional[ArrayLike] = None, virtual_points: Optional[ArrayLike] = None,
                 *old: Optional[ArrayLike], parametrization: Optional[ParameterSpec] = None):
        parameters = _parameters_option(parameters, old, parametrization, type(self).__name__)
        explicit = not isinstance(parameters, str)
        if end_condition not in END_CONDITIONS:
            raise CagdError(f"end_condition: unknown name {end_condition!r}; expected one of {END_CONDITIONS}")
        kind = None if explicit else rule(parameters)
        periodic = end_condition == "periodic"
        P = _checks.points(points, "points", min_count=2)
        if periodic and P.shape[0] < 4:
            raise CagdError(f"points: a periodic spline needs at least 3 distinct points plus the closing "
                            f"point (4 rows), got {P.shape[0]} rows")
        if tangents is not None and end_condition != "clamped":
            raise CagdError(f"tangents: end tangents are used only with end_condition='clamped', not {end_condition!r}")
        if virtual_points is not None and end_condition != "virtual":
            raise CagdError(f"virtual_points: used only with end_condition='virtual', not {end_condition!r}")
        if periodic:
            size = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))
            gap = float(np.linalg.norm(P[-1] - P[0]))
            if gap > 1e-12 * size:
                raise CagdError(f"points: a periodic spline needs points[-1] == points[0] (closed list); "
                                f"they are {gap:.3g} apart")
            P = P.copy()
            P[-1] = P[0]
        n = P.shape[0] - 1
        chords = _chords(P, "points")
        t = _checks.increasing(parameters, n + 1) if kind is None else \
            np.concatenate([[0.0], np.cumsum(interval_lengths(chords, kind))])

        ends = V = None
        if end_condition == "natural":
            m = _natural_tangents(P, t)
        elif end_condition == "clamped":
            if tangents is None:
                raise CagdError("tangents: end_condition='clamped' needs tangents=(d0, dn)")
            ends = _checks.points(tangents, "tangents")
            if ends.shape != (2, P.shape[1]):
                raise CagdError(f"tangents: expected two {P.shape[1]}-D vectors (d0, dn), got shape {ends.shape}")
            m = _natural_tangents(P, t, ends)
        elif periodic:
            m = _periodic_tangents(P, t)
        else:
            V = np.stack([2.0 * P[0] - P[1], 2.0 * P[-1] - P[-2]]) if virtual_points is None else \
                _checks.points(virtual_points, "virtual_points")
            if V.shape != (2, P.shape[1]):
                raise CagdError(f"virtual_points: expected two {P.shape[1]}-D points (p_minus1, p_nplus1), "
                                f"got shape {V.shape}")
            ext = np.vstack([V[:1], P, V[1:]])
            vchords = np.linalg.norm(V - P[[0, -1]], axis=1)
            if np.any(vchords == 0.0):
                i = int(np.argmax(vchords == 0.0))
                raise CagdError(f"virtual_points: virtual point {i} coincides with the end point it extends")
            hv = np.diff(t)[[0, -1]] if kind is None else interval_lengths(vchords, kind)
            text = np.concatenate([[t[0] - hv[0]], t, [t[-1] + hv[1]]])
            m = _natural_tangents(ext, text)[1:-1]
        if not np.all(np.isfinite(m)):
            raise CagdError("parameters: the spline's tangent system overflows (parameter steps of "
                            f"{float(np.diff(t).min()):.3g} against point spacing; use chord or uniform spacing)")
        self._fill(P, m, t, end_condition, kind, ends, V)

    def _fill(self, P: np.ndarray, m: np.ndarray, t: np.ndarray, end_condition: str = "natural",
              parametrization: Optional[str] = None, end_tangents: Optional[np.ndarray] = None,
              virtual_points: Optional[np.ndarray] = None) -> None:
        super()._fill(P, m, t)
        self.end_condition, self.parametrization = end_condition, parametrization
        self.periodic = end_condition == "periodic"
        self.end_tangents = None if end_tangents is None else _checks.frozen(end_tangents)
        self.virtual_points = None if virtual_points is None else _checks.frozen(virtual_points)

    def to_nurbs(self) -> BSplineCurve:
        """The C2 cubic B-spline on the knots t_0 (x4), t_1..t_{n-1}, t_n (x4); for
        "periodic" the periodic B-spline whose period's knots are t_0..t_n. Control
        points are blossom values of the spans (see ``_blossom_control_points``)."""
        t = self.parameters
        n = len(t) - 1
        coef = self.unit_coefficients()
        if self.periodic:
            cps = _blossom_control_points(periodic_extend(t, 3), n, t, coef, periodic=True)
            return BSplineCurve(cps, 3, t, periodic=True)
        knots = np.concatenate([np.full(4, t[0]), t[1:-1], np.full(4, t[-1])])
        return BSplineCurve(_blossom_control_points(knots, n + 3, t, coef), 3, knots)

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "CubicSpline":
        """The spline through the mapped points with the same parameters has the
        knot derivatives A m (the C2 equations are linear), so no new solve."""
        # the parameters are kept, so they no longer follow from the (mapped) points: no parametrization
        return CubicSpline._unchecked(self.points @ A.T + b, self.tangents @ A.T, self.parameters,
                                      self.end_condition, None,
                                      None if self.end_tangents is None else self.end_tangents @ A.T,
                                      None if self.virtual_points is None else self.virtual_points @ A.T + b)


def natural_cubic_spline(points: ArrayLike, end_condition: str = "natural", parameters: ParameterSpec = "chord",
                         tangents: Optional[ArrayLike] = None, virtual_points: Optional[ArrayLike] = None,
                         *old: Optional[ArrayLike], parametrization: Optional[ParameterSpec] = None) -> CubicSpline:
    """The interpolating C2 cubic spline (seed 000, 5.1.2); see :class:`CubicSpline`.

    Raises:
        CagdError: as :class:`CubicSpline`.
    """
    parameters = _parameters_option(parameters, old, parametrization, "natural_cubic_spline")
    return CubicSpline(points, end_condition, parameters, tangents, virtual_points)


def _parameters_option(parameters: ParameterSpec, old: Tuple[Optional[ArrayLike], ...],
                       parametrization: Optional[ParameterSpec], func: str) -> ParameterSpec:
    """``parameters`` of the splines, with the old forms for one release: the keyword
    ``parametrization=`` and explicit parameters as the sixth positional argument
    (points, end_condition, parametrization, tangents, virtual_points, parameters)."""
    if len(old) > 1:
        raise CagdError(f"{func}: takes at most 6 positional arguments, got {5 + len(old)}")
    if old and old[0] is not None:
        deprecated(func, "explicit parameters as the sixth positional argument are deprecated; "
                         "pass them as parameters=")
        return old[0]
    return option(parameters, {"parametrization": parametrization}, func, "chord")
