"""Cubic Hermite curves and piecewise cubic Hermite (C1) splines.

One segment: p(u) = P0 H0(u) + P1 H1(u) + R0 H2(u) + R1 H3(u), u in [0, 1], with
[H0 H1 H2 H3] = [u^3 u^2 u 1] M_h (seed 000, 5.1.2; seed 004, 1.3, F1..F4).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError
from .base import Curve
from .bspline import BSplineCurve
from .polynomial import HERMITE_M, PolynomialCurve
from .ppform import PPForm

if TYPE_CHECKING:
    from ..fitting.parameters import ParameterSpec
    from .bezier import BezierCurve


def hermite_basis(u: ArrayLike) -> np.ndarray:
    """H0..H3 at ``u``, shape np.shape(u) + (4,) (seed 000, 5.1.2):
    H0 = 2u^3 - 3u^2 + 1, H1 = -2u^3 + 3u^2, H2 = u^3 - 2u^2 + u, H3 = u^3 - u^2,
    computed in the factored forms (1-u)^2 (1+2u), u^2 (3-2u), u (1-u)^2, u^2 (u-1).

    Raises:
        CagdError: NaN/inf in ``u``.
    """
    u = _checks.parameters(u, "u")
    v = 1.0 - u
    return np.stack([v * v * (1.0 + 2.0 * u), u * u * (3.0 - 2.0 * u), u * v * v, -u * u * v], axis=-1)


def _vector(value: ArrayLike, name: str, dim: Optional[int] = None) -> np.ndarray:
    v = _checks.finite_array(value, name)
    if v.ndim == 0:
        v = v[None]
    if v.ndim != 1 or v.shape[0] < 1:
        raise CagdError(f"{name}: expected a point/vector (1-D array), got shape {v.shape}")
    if dim is not None and v.shape[0] != dim:
        raise CagdError(f"{name}: expected {dim} coordinates like p0, got {v.shape[0]}")
    return v


class HermiteCurve(Curve):
    """One cubic Hermite segment on u in [0, 1] with end points p0, p1 and end
    tangent vectors t0 = p'(0), t1 = p'(1) (seed 000, 5.1.2; seed 004, 1.3).

    Raises:
        CagdError: NaN/inf, or the four vectors not all of one dimension.
    """

    def __init__(self, p0: ArrayLike, p1: ArrayLike, t0: ArrayLike, t1: ArrayLike):
        p0 = _vector(p0, "p0")
        self.dim = p0.shape[0]
        B = _checks.frozen(np.stack([p0, _vector(p1, "p1", self.dim), _vector(t0, "t0", self.dim),
                                     _vector(t1, "t1", self.dim)]))
        self._geometric = B
        self.p0, self.p1, self.t0, self.t1 = B          # read-only rows of the geometric form
        self._poly = PolynomialCurve((HERMITE_M @ B)[::-1])

    @classmethod
    def from_directions(cls, p0: ArrayLike, p1: ArrayLike, direction0: ArrayLike, direction1: ArrayLike,
                        k0: float, k1: float) -> "HermiteCurve":
        """Tangents P^u = k t with t the unit direction and k = |P^u| its magnitude
        (seed 004, 1.3 "tangent vector": P0^u = k0 t0, P1^u = k1 t1). The directions
        are normalised here.

        Raises:
            CagdError: a zero direction, a negative or non-finite magnitude.
        """
        p0 = _vector(p0, "p0")
        tangents = []
        for d, k, dn, kn in ((direction0, k0, "direction0", "k0"), (direction1, k1, "direction1", "k1")):
            d = _vector(d, dn, p0.shape[0])
            norm = float(np.linalg.norm(d))
            if norm == 0.0:
                raise CagdError(f"{dn}: the zero vector has no direction")
            k = _checks.scalar(k, kn)
            if k < 0:
                raise CagdError(f"{kn}: a tangent magnitude must be >= 0, got {k}")
            tangents.append(k * d / norm)
        return cls(p0, p1, tangents[0], tangents[1])

    @property
    def geometric_form(self) -> np.ndarray:
        """B = [P0, P1, P0', P1'], shape (4, dim) (seed 004, 1.3 eq. 1-1-5), read-only."""
        return self._geometric

    @property
    def domain(self) -> Tuple[float, float]:
        return 0.0, 1.0

    def __repr__(self) -> str:
        return f"<Hermite cubic, {self.dim}-D>"

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        return self._poly._evaluate(t, order)

    def to_polynomial(self) -> PolynomialCurve:
        """The algebraic form, A = M B (seed 004, eq. 1-1-6)."""
        return self._poly

    def bezier_points(self) -> np.ndarray:
        """P0, P0 + R0/3, P1 - R1/3, P1 (the cubic Bezier derivative at the ends is
        3 (P_1 - P_0), seed 000, 5.2.1)."""
        return np.stack([self.p0, self.p0 + self.t0 / 3.0, self.p1 - self.t1 / 3.0, self.p1])

    def to_bezier(self) -> BezierCurve:
        from .bezier import BezierCurve
        return BezierCurve(self.bezier_points())

    def to_nurbs(self) -> BSplineCurve:
        return BSplineCurve(self.bezier_points(), 3, np.repeat([0.0, 1.0], 4))

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "HermiteCurve":
        """Points map affinely, tangent vectors by the linear part A only."""
        return HermiteCurve(A @ self.p0 + b, A @ self.p1 + b, A @ self.t0, A @ self.t1)


class HermiteSpline(Curve):
    """Piecewise cubic Hermite interpolant, C1: on [t_j, t_{j+1}] (h_j its length)
    the segment with P_j, P_{j+1} and u-tangents R = h_j m_j, h_j m_{j+1}, where m
    are the given derivatives dC/dt (seed 000, 5.1.2 "Hermite interpolation spline").

    Args:
        points: (n+1, dim) points, n >= 1.
        tangents: (n+1, dim) derivatives with respect to the global parameter t.
        parameters: n+1 strictly increasing values, or one of
            :data:`cagd.fitting.PARAMETERS` (:func:`cagd.fitting.spline_parameters`:
            t_0 = 0 and steps 1, the chord or its square root); default "uniform",
            0, 1, ..., n.

    Raises:
        CagdError: fewer than 2 points, NaN/inf, mismatched counts or dimensions,
            parameters not strictly increasing, an unknown parametrisation name.
    """

    def __init__(self, points: ArrayLike, tangents: ArrayLike, parameters: Optional[ParameterSpec] = "uniform"):
        P = _checks.points(points, "points", min_count=2)
        m = _checks.points(tangents, "tangents")
        if m.shape != P.shape:
            raise CagdError(f"tangents: expected shape {P.shape} (one per point), got {m.shape}")
        n = P.shape[0]
        if parameters is None or isinstance(parameters, str):
            from ..fitting.parameters import spline_parameters
            t = spline_parameters(P, "uniform" if parameters is None else parameters)
        else:
            t = _checks.increasing(parameters, n)
        self._fill(P, m, t)

    def _fill(self, P: np.ndarray, m: np.ndarray, t: np.ndarray) -> None:
        self.points, self.tangents, self.parameters = _checks.frozen(P), _checks.frozen(m), _checks.frozen(t)
        self.dim = P.shape[1]
        coefficients = self.unit_coefficients()
        if not np.all(np.isfinite(coefficients)):
            raise CagdError("tangents, parameters: the segment tangents h_j m_j overflow (the curve leaves the "
                            "floating-point range); scale the tangents or the parameters")
        self._pp = PPForm.from_unit_power(self.parameters, coefficients)

    def unit_coefficients(self) -> np.ndarray:
        """Per-span power coefficients in u = (t - t_j)/h_j: [a0 a1 a2 a3] = reversed
        M_h [P_j, P_{j+1}, h_j m_j, h_j m_{j+1}], shape (4, n, dim)."""
        P, m, h = self.points, self.tangents, np.diff(self.parameters)[:, None]
        G = np.stack([P[:-1], P[1:], h * m[:-1], h * m[1:]])          # (4, n, dim)
        return np.einsum("ik,ksd->isd", HERMITE_M, G)[::-1]

    @property
    def domain(self) -> Tuple[float, float]:
        return float(self.parameters[0]), float(self.parameters[-1])

    @property
    def ppform(self) -> PPForm:
        return self._pp

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {len(self.points)} points, {self.dim}-D, domain {self.domain}>"

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        return np.stack([self._pp(t, k) for k in range(order + 1)])

    def _breaks_within(self, start: float, end: float) -> np.ndarray:
        b = self.parameters
        return b[(b > start) & (b < end)]

    def segments(self) -> List[HermiteCurve]:
        """The spans as HermiteCurves in their local u in [0, 1] (tangents h_j m)."""
        P, m, h = self.points, self.tangents, np.diff(self.parameters)
        return [HermiteCurve(P[j], P[j + 1], h[j] * m[j], h[j] * m[j + 1]) for j in range(len(h))]

    def to_nurbs(self) -> BSplineCurve:
        """Cubic B-spline with every interior knot doubled (C1): control points P_0,
        then P_j + h_j m_j / 3, P_{j+1} - h_j m_{j+1} / 3 per span, then P_n (the
        junction points P_j are removable because the curve is C1 there)."""
        t = self.parameters
        knots = np.concatenate([np.full(4, t[0]), np.repeat(t[1:-1], 2), np.full(4, t[-1])])
        return BSplineCurve(_blossom_control_points(knots, len(knots) - 4, t, self.unit_coefficients()), 3, knots)

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "HermiteSpline":
        return HermiteSpline(self.points @ A.T + b, self.tangents @ A.T, self.parameters)


def _blossom_control_points(full_knots: np.ndarray, count: int, breaks: np.ndarray,
                            coefficients: np.ndarray, periodic: bool = False) -> np.ndarray:
    """Control points d_j = f(u_{j+1}, u_{j+2}, u_{j+3}) of a piecewise cubic on the
    knot vector ``full_knots`` (unwrapped by periodic_extend when ``periodic``),
    where f is the blossom of the polynomial piece on a span inside the support
    [u_j, u_{j+4}] (de Boor points are blossom values; seed 003, 2.2.4; Farin
    ch. 8). The longest such span is used, so the blossom arguments lie within
    3 span lengths of it and rounding is not amplified by extrapolation.
    ``coefficients`` (4, s, dim) are power coefficients per span in the local u
    of ``breaks``. Exact (to rounding) when the piecewise cubic lies in the
    spline space of the knots (continuity at each knot at least 3 - multiplicity)."""
    u, p = full_knots, 3
    j = np.arange(count)
    cand = j[:, None] + np.arange(p + 1)                       # spans [u_k, u_{k+1}] in the support
    length = u[cand + 1] - u[cand]
    if periodic:
        s_of = (cand - p) % (len(breaks) - 1)                  # u_k = t_{k-p} up to a period
    else:
        length = np.where((cand >= p) & (cand < count), length, -1.0)   # inside the domain
        s_of = np.clip(np.searchsorted(breaks, u[cand], side="right") - 1, 0, len(breaks) - 2)
    pick = np.argmax(length, axis=1)
    k, s = cand[j, pick], s_of[j, pick]
    lo, h = u[k], u[k + 1] - u[k]
    x1, x2, x3 = ((u[j + r] - lo) / h for r in (1, 2, 3))
    e = [np.ones_like(x1), (x1 + x2 + x3) / 3.0, (x1 * x2 + x1 * x3 + x2 * x3) / 3.0, x1 * x2 * x3]
    c = coefficients[:, s, :]                                   # (4, count, dim)
    return sum(c[r] * e[r][:, None] for r in range(4))
