"""The common curve interface: evaluation, derivatives and differential geometry.

Every family implements ``_evaluate(t, order)`` on a flat array of parameters
inside its domain and returns the derivatives 0..order stacked as
(order+1, len(t), dim); everything else (shapes, domain checks, tangent,
curvature, torsion, Frenet frame, arc length) is shared here.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .._checks import affine_map, parameters, positive, scalar
from .._checks import order as _order
from .._deprecation import changed
from .._periodic import wrap
from .._quadrature import adaptive
from .._value import Value
from ..errors import CagdError

if TYPE_CHECKING:
    from .bspline import BSplineCurve

# Gauss-Legendre rule for arc length (Numerical Recipes 4.6; Piegl & Tiller don't cover this)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
ARC_LENGTH_TOL = 1e-12      # default error bound of arc_length, relative to the length
#: smallest accepted rel_tol of arc_length
ARC_LENGTH_MIN_REL_TOL = 1e-15
#: smallest accepted tol of arc_length, relative to the curve's size (its largest coordinate)
ARC_LENGTH_MIN_TOL = 1e-15
#: work bounds of arc_length: halvings, and live intervals (each 30 evaluations per level)
ARC_LENGTH_MAX_LEVELS = 30
ARC_LENGTH_MAX_INTERVALS = 1 << 16
#: a curve whose coordinates over its domain's length times this overflow is measured on
#: its copy over [0, 1] (|C'| of the given one could leave the float range)
DOMAIN_HEADROOM = 1e8


@dataclass(frozen=True)
class ArcLength:
    """Result of :meth:`Curve.arc_length_report`: the ``length`` (negative for end <
    start), the quadrature's ``error`` estimate (sum of |halves - whole| over the
    intervals), ``converged`` (the bound was met), a ``message`` and the number of
    ``intervals`` evaluated."""
    length: float
    error: float
    converged: bool
    message: str
    intervals: int


class Curve(Value):
    """Base class of all curves. Subclasses set ``dim`` and implement
    ``domain``, ``_evaluate``, ``to_nurbs`` and ``_affine``. Curves are values
    (:class:`cagd._value.Value`): read-only arrays, attributes bound once."""

    periodic: bool = False
    dim: int

    # --- to implement ----------------------------------------------------------------
    @property
    def domain(self) -> Tuple[float, float]:
        raise NotImplementedError

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        raise NotImplementedError

    def to_nurbs(self) -> BSplineCurve:
        """The exact B-spline/NURBS form of this curve (a :class:`cagd.BSplineCurve`)."""
        raise NotImplementedError

    def _affine(self, matrix: np.ndarray, offset: np.ndarray) -> "Curve":
        raise NotImplementedError

    # --- evaluation --------------------------------------------------------------------
    def _flat_parameters(self, t: ArrayLike) -> Tuple[np.ndarray, Tuple[int, ...]]:
        t = parameters(t)
        shape = t.shape
        flat = t.ravel()
        a, b = self.domain
        if self.periodic:
            flat = wrap(flat, a, b - a)
        else:
            tol = 1e-12 * max(b - a, abs(a), abs(b), 1.0)
            lo, hi = (flat.min(), flat.max()) if flat.size else (a, b)
            if lo < a - tol or hi > b + tol:
                bad = flat[(flat < a - tol) | (flat > b + tol)][0]
                raise CagdError(f"t: parameter {float(bad)!r} is outside the domain [{a}, {b}]")
            if lo < a or hi > b:                            # within tol outside: onto the ends
                flat = np.minimum(np.maximum(flat, a), b)   # np.clip, without its dispatch cost
        return flat, shape

    def derivatives(self, t: ArrayLike, order: int) -> np.ndarray:
        """Derivatives 0..order at ``t``: shape (order+1,) + np.shape(t) + (dim,);
        ``order`` at most :data:`cagd.MAX_ORDER`."""
        order = _order(order, "order")
        flat, shape = self._flat_parameters(t)
        with np.errstate(over="ignore", invalid="ignore"):
            out = self._evaluate(flat, order)
        if not np.isfinite(out).all():
            k = int(np.argmax(~np.isfinite(out).reshape(order + 1, -1).all(axis=1)))
            raise CagdError(f"t: the derivative of order {k} overflows there (beyond the floating-point range; "
                            f"coordinates up to {float(np.abs(self.to_nurbs().control_points).max()):.3g})")
        return out.reshape((order + 1,) + shape + (self.dim,))

    def __call__(self, t: ArrayLike) -> np.ndarray:
        """Points at ``t`` (float or array): shape np.shape(t) + (dim,)."""
        return self.derivatives(t, 0)[0]

    def derivative(self, t: ArrayLike, order: int = 1) -> np.ndarray:
        """The ``order``-th derivative d^k C / dt^k at ``t``: shape np.shape(t) + (dim,)."""
        return self.derivatives(t, order)[-1]

    # --- transforms --------------------------------------------------------------------
    def transformed(self, matrix: ArrayLike, offset: Optional[ArrayLike] = None) -> "Curve":
        """The curve under the affine map x -> matrix @ x + offset, applied to the
        defining points (affine invariance, seed 000, 5.2.2; seed 004, 1.2)."""
        A, b = affine_map(matrix, offset, self.dim, "curve")
        return self._affine(A, b)

    def translated(self, offset: ArrayLike) -> "Curve":
        """The curve moved by the vector ``offset`` (the identity map plus ``offset``)."""
        return self.transformed(np.eye(self.dim), offset)

    # --- differential geometry ---------------------------------------------------------
    # Rule for undefined values (issue 14): tangent, curvature, torsion, normal, binormal
    # and the Frenet frame raise CagdError (naming t and the first bad parameter)
    # wherever the quantity is undefined: where C' vanishes (a stationary point: no
    # tangent, no curvature) and, for torsion, normal and binormal, where the curvature
    # vanishes (a straight piece: no principal normal). Never NaN. Everything is computed
    # from derivatives divided by their own largest coordinate (a normalised frame), so
    # the results are scale-invariant (kappa(lambda C) = kappa(C) / lambda up to
    # rounding) and neither overflow at 1e300 nor underflow at 1e-300.
    def _geometry_derivatives(self, t: ArrayLike, order: int) -> np.ndarray:
        """Derivatives 0..order for the differential geometry: those of the curve itself,
        or, when its domain is narrower than 1e-100 or wider than 1e100 (derivatives
        would overflow or underflow by the parameter scale alone), those of the same
        curve affinely reparametrised onto [0, 1] at the matching parameters (tangent,
        curvature and torsion do not depend on the parametrisation). CagdError where
        they overflow all the same (one span 1e-300 wide among unit ones)."""
        a, b = self.domain
        h = b - a
        if not self._needs_unit_domain():
            out = self.derivatives(t, order)
        else:
            flat, shape = self._flat_parameters(t)
            x = np.clip((flat - a) / h, 0.0, 1.0)
            out = self._unit_copy().derivatives(x, order).reshape((order + 1,) + shape + (self.dim,))
        finite = np.all(np.isfinite(out), axis=(0, -1))
        if not np.all(finite):
            raise CagdError(f"t: the derivatives overflow at t = {_first_bad(~finite, t)} (a span far narrower "
                            f"than the others); the differential geometry is not representable there")
        return out

    def _needs_unit_domain(self) -> bool:
        """True where derivatives are computed on the copy over [0, 1]: a domain width
        outside [GEOMETRY_DOMAIN_MIN, 1 / GEOMETRY_DOMAIN_MIN], or coordinates so large
        for the width that |C'| could overflow (size / width * DOMAIN_HEADROOM)."""
        a, b = self.domain
        h = b - a
        if a == 0.0 and b == 1.0:                    # already the unit copy's domain
            return False
        if not GEOMETRY_DOMAIN_MIN <= h <= 1.0 / GEOMETRY_DOMAIN_MIN:
            return True
        with np.errstate(over="ignore"):
            return not np.isfinite(float(np.abs(self.to_nurbs().control_points).max()) / h * DOMAIN_HEADROOM)

    def _unit_copy(self) -> "Curve":
        """This curve on the parameter domain [0, 1] (its NURBS form reparametrised), cached."""
        if getattr(self, "_unit", None) is None:
            self._unit = self.to_nurbs().reparametrized(0.0, 1.0)
        return self._unit

    def tangent(self, t: ArrayLike) -> np.ndarray:
        """Unit tangent C'/|C'|; CagdError where the derivative vanishes."""
        d = self._geometry_derivatives(t, 1)
        u1, s1 = _normalised(d[1])
        _regular(u1, s1, t)
        return u1 / np.linalg.norm(u1, axis=-1, keepdims=True)

    def curvature(self, t: ArrayLike) -> np.ndarray:
        """kappa = |C''_perp| / |C'|^2 with C''_perp = C'' - (C''.T) T, T = C'/|C'|
        (= |C' x C''| / |C'|^3 in any dimension, without the cancellation of
        |C'|^2 |C''|^2 - (C'.C'')^2); 0 on straight pieces; CagdError where C' vanishes."""
        d = self._geometry_derivatives(t, 2)
        u1, s1 = _normalised(d[1])
        v2, s2 = _normalised(d[2])
        _regular(u1, s1, t)
        n1 = np.linalg.norm(u1, axis=-1, keepdims=True)
        T = u1 / n1
        perp = v2 - np.einsum("...i,...i->...", v2, T)[..., None] * T
        with np.errstate(over="ignore", under="ignore"):
            return np.linalg.norm(perp, axis=-1) * (s2[..., 0] / s1[..., 0]) / s1[..., 0] / n1[..., 0] ** 2

    def torsion(self, t: ArrayLike) -> np.ndarray:
        """tau = (C' x C'') . C''' / |C' x C''|^2 (3-D curves; 0 for planar 2-D curves);
        CagdError where C' or the curvature vanishes (relative CURVATURE_ZERO_TOL)."""
        d = self._geometry_derivatives(t, 3)
        if self.dim == 2:
            return np.zeros(d.shape[1:-1])
        if self.dim != 3:
            raise CagdError(f"torsion: defined for 2-D and 3-D curves, this one is {self.dim}-D")
        u1, s1 = _normalised(d[1])
        v2, s2 = _normalised(d[2])
        w3, s3 = _normalised(d[3])
        _regular(u1, s1, t)
        c = np.cross(u1, v2)
        _curved(c, u1, v2, t)
        with np.errstate(over="ignore", under="ignore"):
            ratio = (s3[..., 0] / s1[..., 0]) / s2[..., 0]
            return np.einsum("...i,...i->...", c, w3) / np.einsum("...i,...i->...", c, c) * ratio

    def frenet(self, t: ArrayLike) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Frenet frame (T, N, B) of a 3-D curve (2-D curves are lifted to z = 0).
        CagdError where C' vanishes or the curvature vanishes (N undefined)."""
        d = self._geometry_derivatives(t, 2)
        if self.dim == 2:
            d = np.concatenate([d, np.zeros(d.shape[:-1] + (1,))], axis=-1)
        elif self.dim != 3:
            raise CagdError(f"frenet: defined for 2-D and 3-D curves, this one is {self.dim}-D")
        u1, s1 = _normalised(d[1])
        v2, _ = _normalised(d[2])
        _regular(u1, s1, t)
        c = np.cross(u1, v2)
        _curved(c, u1, v2, t)
        T = u1 / np.linalg.norm(u1, axis=-1, keepdims=True)
        B = c / np.linalg.norm(c, axis=-1, keepdims=True)
        return T, np.cross(B, T), B

    def normal(self, t: ArrayLike) -> np.ndarray:
        """Principal unit normal N of the Frenet frame; CagdError where undefined."""
        return self.frenet(t)[1]

    def binormal(self, t: ArrayLike) -> np.ndarray:
        """Unit binormal B = T x N of the Frenet frame; CagdError where undefined."""
        return self.frenet(t)[2]

    def arc_length(self, start: Optional[float] = None, end: Optional[float] = None, tol: Optional[float] = None, *,
                   rel_tol: Optional[float] = None) -> float:
        """Length of the curve between two parameters by adaptive Gauss-Legendre
        quadrature of |C'(t)| (:meth:`arc_length_report`, which also says whether the
        bound was met); a RuntimeWarning when it was not within the work bound.

        The bound is ``tol``, a length in model units, or ``rel_tol`` times the length
        (default ARC_LENGTH_TOL = 1e-12 relative). Until cagd 0.1 ``tol`` was relative
        (now ``rel_tol``); passing ``tol`` warns (FutureWarning) for one release.

        Raises:
            CagdError: see :meth:`arc_length_report`; a length beyond the
                floating-point range."""
        report = self.arc_length_report(start, end, tol, rel_tol=rel_tol)
        if not np.isfinite(report.length):
            raise CagdError("start, end: the arc length exceeds the floating-point range")
        if not report.converged:
            warnings.warn(f"arc_length: {report.message}", RuntimeWarning, stacklevel=2)
        return report.length

    def arc_length_report(self, start: Optional[float] = None, end: Optional[float] = None,
                          tol: Optional[float] = None, *, rel_tol: Optional[float] = None) -> "ArcLength":
        """Length of the curve between two parameters with its error estimate.

        Adaptive Gauss-Legendre quadrature of |C'(t)| (10 points per interval;
        Numerical Recipes 4.6): intervals split in halves until the two halves agree
        with the whole, on every interval, within its share (its parameter length over
        end - start) of the error bound. The bound is ``tol`` (a length in model units,
        at least ARC_LENGTH_MIN_TOL = 1e-15 times the curve's size, the largest
        coordinate on it: rounding in C' is of that order) or ``rel_tol`` times the
        length (at least ARC_LENGTH_MIN_REL_TOL = 1e-15; the floor from the size applies
        too). The work is bounded: at most ARC_LENGTH_MAX_LEVELS = 30 halvings and
        ARC_LENGTH_MAX_INTERVALS = 2^16 live intervals; beyond them the result comes back
        with ``converged`` False and the estimate reached.

        Raises:
            CagdError: ``tol``/``rel_tol`` not a number, NaN, not positive or below its
                minimum; ``start``/``end`` not numbers or outside the domain."""
        if tol is not None:
            changed("arc_length", "tol is a length in model units now (the error bound of the quadrature); "
                                  "it was relative to the length, which is rel_tol= now")
            tol = positive(tol, "tol")
        rel = ARC_LENGTH_TOL if rel_tol is None else positive(rel_tol, "rel_tol")
        if rel < ARC_LENGTH_MIN_REL_TOL:
            raise CagdError(f"rel_tol: {rel!r} is below ARC_LENGTH_MIN_REL_TOL = {ARC_LENGTH_MIN_REL_TOL} "
                            f"(the quadrature cannot resolve a smaller relative error)")
        a, b = self.domain
        start = a if start is None else scalar(start, "start")
        end = b if end is None else scalar(end, "end")
        self._flat_parameters(np.array([start, end]))          # inside the domain
        sign = 1.0
        if end < start:
            start, end, sign = end, start, -1.0
        if start == end:
            return ArcLength(0.0, 0.0, True, "empty parameter range", 0)
        h = b - a
        if self._needs_unit_domain():                                  # |C'| may leave the float
            unit = self._unit_copy()                                   # range: the length does not
            report = unit.arc_length_report(min(max((start - a) / h, 0.0), 1.0),   # depend on the
                                            min(max((end - a) / h, 0.0), 1.0), tol, rel_tol=rel_tol)
            return ArcLength(sign * report.length, report.error, report.converged, report.message,
                             report.intervals)                         # parametrisation
        size = float(np.abs(self(np.linspace(start, end, 17))).max())
        floor = ARC_LENGTH_MIN_TOL * size
        if tol is not None and tol < floor:
            raise CagdError(f"tol: {tol!r} is below ARC_LENGTH_MIN_TOL = {ARC_LENGTH_MIN_TOL} times the "
                            f"curve's size ({size:.3g}), what rounding in the derivative allows; "
                            f"use tol >= {floor:.3g}")
        edges = np.unique(np.concatenate([[start, end], self._breaks_within(start, end)]))
        lo, hi = edges[:-1], edges[1:]
        bound = tol if tol is not None else max(rel * abs(float(self._gl(lo, hi).sum())), floor)
        if not bound > 0.0:                                     # a constant curve at the origin
            return ArcLength(0.0, 0.0, True, "the curve is a point", len(lo))
        q = adaptive(lambda a, b, _: self._gl(a, b), lo, hi, None, bound, 0.0, ARC_LENGTH_MAX_LEVELS,
                     ARC_LENGTH_MAX_INTERVALS, "ARC_LENGTH_MAX_LEVELS, ARC_LENGTH_MAX_INTERVALS")
        return ArcLength(sign * q.value, q.error, q.converged, q.message, q.intervals)

    def _gl(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        half = 0.5 * (hi - lo)
        t = (0.5 * (hi + lo))[:, None] + half[:, None] * _GL_X
        d1, s1 = _normalised(self.derivative(t, 1))
        with np.errstate(over="ignore"):
            speed = np.linalg.norm(d1, axis=-1) * s1[..., 0]       # |C'| without squaring C' (1e300)
            return half * (speed @ _GL_W)

    def _breaks_within(self, start: float, end: float) -> np.ndarray:
        """Parameters where the curve may be non-smooth (knots); none by default."""
        return np.empty(0)


#: domain widths outside [GEOMETRY_DOMAIN_MIN, 1 / GEOMETRY_DOMAIN_MIN] are mapped onto
#: [0, 1] for the differential geometry (see Curve._geometry_derivatives)
GEOMETRY_DOMAIN_MIN = 1e-100
#: C' counts as vanishing where |C'| <= TANGENT_TOL times the largest |C'| of the call
#: (and where it is exactly zero): rounding noise next to a stationary point.
TANGENT_TOL = 1e-14
#: the curvature counts as vanishing where |C' x C''| <= CURVATURE_ZERO_TOL |C'| |C''|
#: (the derivatives parallel to rounding: a straight piece): torsion and N are undefined.
CURVATURE_ZERO_TOL = 1e-12


def _normalised(v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(v / s, s) with s (..., 1) the largest |coordinate| of each vector (v kept and
    s = 0 where v = 0): the normalised frame, |v / s| in [1, sqrt(dim)]."""
    s = np.max(np.abs(v), axis=-1, keepdims=True)
    return v / np.where(s > 0, s, 1.0), s


def _first_bad(bad: np.ndarray, t: ArrayLike) -> str:
    tt = np.broadcast_to(np.asarray(t, dtype=np.float64), bad.shape)
    return repr(float(tt[np.unravel_index(int(np.argmax(bad)), bad.shape)]))


def _regular(u1: np.ndarray, s1: np.ndarray, t: ArrayLike) -> None:
    """CagdError where C' vanishes (see TANGENT_TOL)."""
    top = float(s1.max()) if s1.size else 0.0
    length = np.linalg.norm(u1, axis=-1) * (s1[..., 0] / top if top > 0 else s1[..., 0])
    bad = (s1[..., 0] == 0.0) | (length <= TANGENT_TOL)
    if np.any(bad):
        raise CagdError(f"t: the first derivative vanishes (singular point) at t = {_first_bad(bad, t)}; "
                        f"tangent, curvature, torsion and the Frenet frame are undefined there")


def _curved(c: np.ndarray, u1: np.ndarray, v2: np.ndarray, t: ArrayLike) -> None:
    """CagdError where the curvature vanishes (see CURVATURE_ZERO_TOL); c = u1 x v2."""
    ref = np.linalg.norm(u1, axis=-1) * np.linalg.norm(v2, axis=-1)
    bad = np.linalg.norm(c, axis=-1) <= CURVATURE_ZERO_TOL * ref
    if np.any(bad):
        raise CagdError(f"t: the curvature vanishes (no principal normal) at t = {_first_bad(bad, t)}; "
                        f"torsion, normal and binormal are undefined there")


def rational_derivatives(hom: np.ndarray) -> np.ndarray:
    """Cartesian derivatives from homogeneous ones (order+1, N, dim+1):
    C^(k) = (A^(k) - sum_{i=1..k} C(k,i) w^(i) C^(k-i)) / w (Piegl & Tiller eq. 4.8)."""
    from math import comb
    A, w = hom[..., :-1], hom[..., -1:]
    out = np.empty_like(A)
    for k in range(hom.shape[0]):
        v = A[k].copy()
        for i in range(1, k + 1):
            v -= comb(k, i) * w[i] * out[k - i]
        out[k] = v / w[0]
    return out
