"""The common curve interface: evaluation, derivatives and differential geometry.

Every family implements ``_evaluate(t, order)`` on a flat array of parameters
inside its domain and returns the derivatives 0..order stacked as
(order+1, len(t), dim); everything else (shapes, domain checks, tangent,
curvature, torsion, Frenet frame, arc length) is shared here.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .._checks import affine_map, parameters, positive
from .._checks import order as _order
from .._deprecation import changed
from .._periodic import wrap
from .._value import Value
from ..errors import CagdError

if TYPE_CHECKING:
    from .bspline import BSplineCurve

# Gauss-Legendre rule for arc length (Numerical Recipes 4.6; Piegl & Tiller don't cover this)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
ARC_LENGTH_TOL = 1e-12      # default error bound of arc_length, relative to the length


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
            if flat.size and (flat.min() < a - tol or flat.max() > b + tol):
                bad = flat[(flat < a - tol) | (flat > b + tol)][0]
                raise CagdError(f"t: parameter {float(bad)!r} is outside the domain [{a}, {b}]")
            flat = np.clip(flat, a, b)
        return flat, shape

    def derivatives(self, t: ArrayLike, order: int) -> np.ndarray:
        """Derivatives 0..order at ``t``: shape (order+1,) + np.shape(t) + (dim,);
        ``order`` at most :data:`cagd.MAX_ORDER`."""
        order = _order(order, "order")
        flat, shape = self._flat_parameters(t)
        out = self._evaluate(flat, order)
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
    def tangent(self, t: ArrayLike) -> np.ndarray:
        """Unit tangent C'/|C'|; CagdError where the derivative vanishes."""
        d1 = self.derivative(t, 1)
        return _unit(d1, "t", "the first derivative vanishes (singular point)")

    def curvature(self, t: ArrayLike) -> np.ndarray:
        """kappa = |C' x C''| / |C'|^3, written sqrt(|C'|^2 |C''|^2 - (C'.C'')^2)/|C'|^3 for any dim."""
        d = self.derivatives(t, 2)
        d1, d2 = d[1], d[2]
        n1 = np.einsum("...i,...i->...", d1, d1)
        cross2 = n1 * np.einsum("...i,...i->...", d2, d2) - np.einsum("...i,...i->...", d1, d2) ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            k = np.sqrt(np.maximum(cross2, 0.0)) / n1 ** 1.5
        return k

    def torsion(self, t: ArrayLike) -> np.ndarray:
        """tau = (C' x C'') . C''' / |C' x C''|^2 (3-D curves; 0 for planar 2-D curves)."""
        d = self.derivatives(t, 3)
        if self.dim == 2:
            return np.zeros(d.shape[1:-1])
        if self.dim != 3:
            raise CagdError(f"torsion: defined for 2-D and 3-D curves, this one is {self.dim}-D")
        c = np.cross(d[1], d[2])
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.einsum("...i,...i->...", c, d[3]) / np.einsum("...i,...i->...", c, c)

    def frenet(self, t: ArrayLike) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Frenet frame (T, N, B) of a 3-D curve (2-D curves are lifted to z = 0).
        CagdError where the curvature vanishes (N undefined)."""
        d = self.derivatives(t, 2)
        if self.dim == 2:
            d = np.concatenate([d, np.zeros(d.shape[:-1] + (1,))], axis=-1)
        elif self.dim != 3:
            raise CagdError(f"frenet: defined for 2-D and 3-D curves, this one is {self.dim}-D")
        T = _unit(d[1], "t", "the first derivative vanishes (singular point)")
        B = _unit(np.cross(d[1], d[2]), "t", "the curvature vanishes (no principal normal)")
        return T, np.cross(B, T), B

    def arc_length(self, start: Optional[float] = None, end: Optional[float] = None, tol: Optional[float] = None, *,
                   rel_tol: Optional[float] = None) -> float:
        """Length of the curve between two parameters by adaptive Gauss-Legendre
        quadrature of |C'(t)| (10 points per interval; intervals split in halves
        until the two halves agree with the whole, on every interval, within its share
        (its parameter length over end - start) of the error bound).

        The bound is ``tol``, a length in model units, or ``rel_tol`` times the length
        (default ARC_LENGTH_TOL = 1e-12 relative). Until cagd 0.1 ``tol`` was relative
        (now ``rel_tol``); passing ``tol`` warns (FutureWarning) for one release."""
        if tol is not None:
            changed("arc_length", "tol is a length in model units now (the error bound of the quadrature); "
                                  "it was relative to the length, which is rel_tol= now")
            tol = positive(tol, "tol")
        rel_tol = ARC_LENGTH_TOL if rel_tol is None else positive(rel_tol, "rel_tol")
        a, b = self.domain
        start = a if start is None else float(start)
        end = b if end is None else float(end)
        sign = 1.0
        if end < start:
            start, end, sign = end, start, -1.0
        edges = np.unique(np.concatenate([[start, end], self._breaks_within(start, end)]))
        lo, hi = edges[:-1], edges[1:]
        whole = self._gl(lo, hi)
        bound = tol if tol is not None else rel_tol * max(abs(whole.sum()), 1e-300)
        total = 0.0
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            left, right = self._gl(lo, mid), self._gl(mid, hi)
            done = np.abs(left + right - whole) <= bound * (hi - lo) / (end - start)
            total += (left + right)[done].sum()
            if done.all():
                return sign * total
            keep = ~done
            lo, hi = np.concatenate([lo[keep], mid[keep]]), np.concatenate([mid[keep], hi[keep]])
            whole = np.concatenate([left[keep], right[keep]])
        return sign * (total + whole.sum())

    def _gl(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        half = 0.5 * (hi - lo)
        t = (0.5 * (hi + lo))[:, None] + half[:, None] * _GL_X
        speed = np.linalg.norm(self.derivative(t, 1), axis=-1)
        return half * (speed @ _GL_W)

    def _breaks_within(self, start: float, end: float) -> np.ndarray:
        """Parameters where the curve may be non-smooth (knots); none by default."""
        return np.empty(0)


def _unit(v: np.ndarray, name: str, problem: str) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    scale = max(float(np.abs(v).max()) if v.size else 0.0, 1e-300)
    if np.any(n <= 1e-14 * scale) or scale <= 1e-300:
        raise CagdError(f"{name}: {problem}")
    return v / n


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
