"""Polynomial curves in algebraic (power) form and the cubic's geometric form.

P(u) = a_0 + a_1 u + ... + a_n u^n, u = (t - a)/(b - a) in [0, 1] (seed 004, 1.3
"algebraic and geometric form", eq. 1-1-1; seed 000, 5.1.1 C = GM). For a cubic
the geometric (Hermite) form B = [P0, P1, P0', P1'] and the algebraic form
A = [a3, a2, a1, a0] are related by A = M B and B = M^-1 A (seed 004, eqs.
1-1-6, 1-1-7; seed 000, 5.1.2 M_h).
"""
from __future__ import annotations

from math import factorial
from typing import TYPE_CHECKING, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bernstein import bernstein_to_power, power_to_bernstein
from ..errors import CagdError
from .base import Curve
from .bspline import BSplineCurve

if TYPE_CHECKING:
    from .bezier import BezierCurve
    from .hermite import HermiteCurve


#: The Hermite matrix M (seed 004, 1.3; seed 000, 5.1.2 M_h): F = U M with
#: U = [u^3 u^2 u 1] gives the blending functions F1..F4 (= H0..H3), and the
#: algebraic coefficients [a3 a2 a1 a0]^T = M [P0 P1 P0' P1']^T.
HERMITE_M = _checks.frozen([[2, -2, 1, 1],
                            [-3, 3, -2, -1],
                            [0, 0, 1, 0],
                            [1, 0, 0, 0]], np.float64)

#: Its inverse as printed in seed 004, 1.3 (and as the coefficient matrix of the
#: end conditions p(0), p(1), p'(0), p'(1) in seed 000, 5.1.2):
#: [P0 P1 P0' P1']^T = M^-1 [a3 a2 a1 a0]^T.
HERMITE_M_INV = _checks.frozen([[0, 0, 0, 1],
                                [1, 1, 1, 1],
                                [0, 0, 1, 0],
                                [3, 2, 1, 0]], np.float64)

#: Power coefficients (rows: 1, u, u^2, u^3) of the cubic through four points at
#: u = 0, 1/3, 2/3, 1 (columns: the points): the Lagrange basis on those nodes,
#: i.e. the inverse of the Vandermonde matrix V[i, k] = u_i^k. All entries are
#: halves, so the matrix is exact in binary floating point.
FOUR_POINT_MATRIX = _checks.frozen([[1.0, 0.0, 0.0, 0.0],
                                    [-5.5, 9.0, -4.5, 1.0],
                                    [9.0, -22.5, 18.0, -4.5],
                                    [-4.5, 13.5, -13.5, 4.5]], np.float64)


def _domain(value: ArrayLike, name: str = "domain") -> Tuple[float, float]:
    d = _checks.finite_array(value, name, ndim=1)
    if d.shape[0] != 2:
        raise CagdError(f"{name}: expected two values (start, end), got {d.shape[0]}")
    if not d[0] < d[1]:
        raise CagdError(f"{name}: need start < end, got ({d[0]}, {d[1]})")
    return float(d[0]), float(d[1])


class PolynomialCurve(Curve):
    """P(t) = sum_k a_k u^k with u = (t - start)/(end - start), evaluated by Horner's
    scheme (seed 004, 1.3 eq. 1-1-1; seed 000, 5.1.1).

    Args:
        coefficients: (n+1, dim) array; row k is a_k, the coefficient of u^k
            (a 1-D array is n+1 scalars, a 1-D curve).
        domain: (start, end), start < end; default (0, 1) so that u = t.

    Raises:
        CagdError: NaN/inf or a wrong shape in ``coefficients``; a domain that is
            not two finite increasing numbers.
    """

    def __init__(self, coefficients: ArrayLike, domain: Tuple[float, float] = (0.0, 1.0)):
        A = _checks.points(coefficients, "coefficients", min_count=1)
        _checks.degree(A.shape[0] - 1, "coefficients (their count - 1 is the degree)", 0)
        self.coefficients = _checks.frozen(A)
        self.degree = A.shape[0] - 1
        self.dim = A.shape[1]
        self._dom = _domain(domain)

    @property
    def domain(self) -> Tuple[float, float]:
        return self._dom

    def __repr__(self) -> str:
        return f"<polynomial curve degree {self.degree}, {self.dim}-D, domain {self._dom}>"

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        """d^r P/dt^r = h^-r sum_{k>=r} k!/(k-r)! a_k u^(k-r), each by Horner."""
        a, b = self._dom
        h = b - a
        u = ((t - a) / h)[:, None]
        c, n = self.coefficients, self.degree
        out = np.zeros((order + 1, t.shape[0], self.dim))
        for r in range(min(order, n) + 1):
            fall = np.array([factorial(k) / factorial(k - r) for k in range(r, n + 1)])
            dc = c[r:] * fall[:, None]
            acc = np.repeat(dc[-1:], t.shape[0], axis=0)
            for k in range(n - r - 1, -1, -1):
                acc *= u
                acc += dc[k]
            out[r] = acc / h ** r
        return out

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "PolynomialCurve":
        """a_0 -> A a_0 + b; a_k -> A a_k for k >= 1 (they are derivatives, i.e.
        vectors, so the offset does not apply)."""
        c = self.coefficients @ A.T
        c[0] += b
        return PolynomialCurve(c, self._dom)

    # --- Bezier form -----------------------------------------------------------------
    def _padded(self, degree: int) -> np.ndarray:
        c = np.zeros((degree + 1, self.dim))
        c[:self.degree + 1] = self.coefficients
        return c

    def to_bezier(self) -> BezierCurve:
        """The same polynomial as a :class:`cagd.BezierCurve` in u on [0, 1]; control
        points P = B a with B = power_to_bernstein(n) (Farin 5.x; rounding only).
        A degree-0 curve comes back as a degree-1 Bezier with two equal points."""
        from .bezier import BezierCurve
        n = max(self.degree, 1)
        return BezierCurve(power_to_bernstein(n) @ self._padded(n))

    @classmethod
    def from_bezier(cls, bezier: BezierCurve, domain: Tuple[float, float] = (0.0, 1.0)) -> "PolynomialCurve":
        """Power coefficients a = bernstein_to_power(n) P of a polynomial Bezier curve,
        put on ``domain``.

        Raises:
            CagdError: ``bezier`` is not a BezierCurve, or it is rational.
        """
        from .bezier import BezierCurve
        if not isinstance(bezier, BezierCurve):
            raise CagdError(f"bezier: expected a BezierCurve, got {type(bezier).__name__}")
        if bezier.is_rational:
            raise CagdError("bezier: a rational Bezier curve has no polynomial (power) form")
        return cls(bernstein_to_power(bezier.degree) @ bezier.control_points, domain)

    def to_nurbs(self) -> BSplineCurve:
        """The Bezier control points on the knots [start]*(n+1) + [end]*(n+1)."""
        n = max(self.degree, 1)
        a, b = self._dom
        knots = np.concatenate([np.full(n + 1, a), np.full(n + 1, b)])
        return BSplineCurve(power_to_bernstein(n) @ self._padded(n), n, knots)

    # --- geometric (Hermite) form of a cubic ------------------------------------------
    def to_hermite(self) -> np.ndarray:
        """The geometric form B = [P0, P1, P0', P1'] = M^-1 A with A = [a3, a2, a1, a0]
        (seed 004, 1.3 eq. 1-1-7). The tangents are derivatives with respect to u,
        as in the seed (d/dt = d/du / (end - start)). Shape (4, dim).

        Raises:
            CagdError: the degree is above 3.
        """
        if self.degree > 3:
            raise CagdError(f"coefficients: the geometric (Hermite) form needs degree <= 3, "
                            f"this curve has degree {self.degree}")
        return HERMITE_M_INV @ self._padded(3)[::-1]

    @classmethod
    def from_hermite(cls, geometric: Union[HermiteCurve, ArrayLike],
                     domain: Tuple[float, float] = (0.0, 1.0)) -> "PolynomialCurve":
        """The cubic with A = M B (seed 004, 1.3 eq. 1-1-6), B = [P0, P1, P0', P1']
        a (4, dim) array (tangents with respect to u), or a HermiteCurve.

        Raises:
            CagdError: ``geometric`` is not four finite points of one dimension.
        """
        from .hermite import HermiteCurve
        if isinstance(geometric, HermiteCurve):
            geometric = geometric.geometric_form
        B = _checks.points(geometric, "geometric")
        if B.shape[0] != 4:
            raise CagdError(f"geometric: expected 4 rows [P0, P1, P0', P1'], got {B.shape[0]}")
        return cls((HERMITE_M @ B)[::-1], domain)


def four_point_cubic(points: ArrayLike) -> PolynomialCurve:
    """The cubic P(u), u in [0, 1], with P(i/3) = points[i], i = 0..3 (seed 004,
    contents "four-point curve"; the seed's remark in 1.3 that four points may
    replace the end tangents): a = FOUR_POINT_MATRIX @ points.

    Raises:
        CagdError: not exactly four finite points.
    """
    P = _checks.points(points, "points")
    if P.shape[0] != 4:
        raise CagdError(f"points: a four-point curve takes exactly 4 points, got {P.shape[0]}")
    return PolynomialCurve(FOUR_POINT_MATRIX @ P)
