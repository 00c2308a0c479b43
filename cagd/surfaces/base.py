"""The common surface interface (seed 003, 1-2.1: tensor-product surfaces, partial
derivatives, normal vector).

Subclasses set ``dim`` and implement ``domain``, ``_evaluate(u, v, du, dv)`` on
flat in-domain parameters (all mixed partials up to (du, dv), shape
(du+1, dv+1, N, dim)), ``_grid(us, vs, du, dv)`` (shape (du+1, dv+1, len(us),
len(vs), dim)), ``to_nurbs`` and ``_affine``. Everything else is shared here.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .._checks import MAX_SAMPLES, affine_map, finite_array, order, parameters
from .._periodic import wrap
from .._value import Value
from ..errors import CagdError

if TYPE_CHECKING:
    from ..curves.bspline import BSplineCurve
    from .bspline import BSplineSurface

NORMAL_TOL = 1e-8    # relative cut-off of "the normal is defined", see unit_normals
#: the coefficients (E, F, G) or (L, M, N) of a fundamental form, each an array
FormCoefficients = Tuple[np.ndarray, np.ndarray, np.ndarray]


def unit_normals(su: ArrayLike, sv: ArrayLike, scale_u: float = 0.0,
                 scale_v: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
    """The unit normal n = (S_u x S_v) / |S_u x S_v| where it is defined (seed 003, 2.1),
    and where that is: ``(n, defined)``, n of shape (..., 3) (2-D partials lifted to
    z = 0) and zero where undefined.

    Defined where |S_u x S_v| > NORMAL_TOL max(|S_u|, scale_u) max(|S_v|, scale_v),
    ``scale_u``, ``scale_v`` the typical sizes of the partials (the surface's size over
    the parameter length of each direction): the partials are not parallel (a patch
    collapsed to a curve) and neither is rounding noise against its scale (a pole, a
    cone's apex, where a whole edge collapses to a point). Rounding of about 1e-16 of
    the scales in the partials then moves n by at most ~1e-16 / NORMAL_TOL = 1e-8; a
    smaller cut-off would call normals "defined" that are mostly rounding next to a
    pole (1e-12: errors up to 1e-4).
    """
    su, sv = _as3(np.asarray(su, dtype=np.float64)), _as3(np.asarray(sv, dtype=np.float64))
    # in the normalised frame: each partial divided by its largest coordinate, so that
    # the cross product neither overflows (1e300) nor underflows (1e-300)
    au = np.max(np.abs(su), axis=-1, keepdims=True)
    av = np.max(np.abs(sv), axis=-1, keepdims=True)
    fu, fv = np.where(au > 0, au, 1.0), np.where(av > 0, av, 1.0)
    nu_, nv_ = su / fu, sv / fv
    n = np.cross(nu_, nv_)
    length = np.linalg.norm(n, axis=-1)
    with np.errstate(over="ignore"):
        ref = (np.maximum(np.linalg.norm(nu_, axis=-1), scale_u / fu[..., 0])
               * np.maximum(np.linalg.norm(nv_, axis=-1), scale_v / fv[..., 0]))
    defined = length > NORMAL_TOL * ref
    with np.errstate(divide="ignore", invalid="ignore"):
        n = np.where(defined[..., None], n / length[..., None], 0.0)
    return n, defined


class Surface(Value):
    """Base class of all surfaces; values like curves (:class:`cagd._value.Value`)."""

    periodic_u: bool = False
    periodic_v: bool = False
    rectangular: bool = True      # False for triangles: the domain is u, v >= 0, u + v <= 1
    dim: int

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        raise NotImplementedError

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        raise NotImplementedError

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        raise NotImplementedError

    def to_nurbs(self) -> BSplineSurface:
        """The exact B-spline/NURBS form (a :class:`cagd.BSplineSurface`)."""
        raise NotImplementedError

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "Surface":
        raise NotImplementedError

    # --- parameters ------------------------------------------------------------------
    def _wrap(self, x: np.ndarray, which: int, periodic: bool, name: str) -> np.ndarray:
        a, b = self.domain[which]
        if periodic:
            return wrap(x, a, b - a)
        tol = 1e-12 * max(b - a, abs(a), abs(b), 1.0)
        if x.size and (x.min() < a - tol or x.max() > b + tol):
            bad = x[(x < a - tol) | (x > b + tol)][0]
            raise CagdError(f"{name}: parameter {float(bad)!r} is outside the domain [{a}, {b}]")
        return np.clip(x, a, b)

    def _flat(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray, Tuple[int, ...]]:
        u, v = parameters(u, "u"), parameters(v, "v")
        try:
            shape = np.broadcast_shapes(u.shape, v.shape)
        except ValueError:
            raise CagdError(f"u, v: shapes {u.shape} and {v.shape} do not broadcast") from None
        uf = self._wrap(np.broadcast_to(u, shape).ravel(), 0, self.periodic_u, "u")
        vf = self._wrap(np.broadcast_to(v, shape).ravel(), 1, self.periodic_v, "v")
        return uf, vf, shape

    # --- evaluation --------------------------------------------------------------------
    def derivatives(self, u: ArrayLike, v: ArrayLike, du: int, dv: int) -> np.ndarray:
        """All partials S_{u^i v^j}, i <= du, j <= dv: shape (du+1, dv+1) + broadcast shape + (dim,)."""
        du, dv = order(du, "du"), order(dv, "dv")
        uf, vf, shape = self._flat(u, v)
        out = self._evaluate(uf, vf, du, dv)
        return out.reshape((du + 1, dv + 1) + shape + (self.dim,))

    def __call__(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Points S(u, v), element-wise with numpy broadcasting: shape broadcast(u, v).shape + (dim,)."""
        return self.derivatives(u, v, 0, 0)[0, 0]

    def derivative(self, u: ArrayLike, v: ArrayLike, du: int = 0, dv: int = 0) -> np.ndarray:
        """The partial derivative d^(du+dv) S / du^du dv^dv at (u, v)."""
        return self.derivatives(u, v, du, dv)[-1, -1]

    def grid(self, us: ArrayLike, vs: ArrayLike, du: int = 0, dv: int = 0) -> np.ndarray:
        """Points (or the partial (du, dv)) on the grid us x vs: shape (len(us), len(vs), dim),
        through local basis blocks and matrix products (the fast path); at most MAX_SAMPLES
        = 10^7 points and orders du, dv at most MAX_ORDER."""
        du, dv = order(du, "du"), order(dv, "dv")
        us = self._wrap(finite_array(us, "us", ndim=1), 0, self.periodic_u, "us")
        vs = self._wrap(finite_array(vs, "vs", ndim=1), 1, self.periodic_v, "vs")
        if len(us) * len(vs) > MAX_SAMPLES:
            raise CagdError(f"us, vs: a grid of {len(us)} x {len(vs)} points exceeds MAX_SAMPLES = {MAX_SAMPLES}; "
                            f"evaluate it in blocks")
        return self._grid_last(us, vs, du, dv)

    def _grid_last(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        """The (du, dv) partial alone on the grid (a surface that can skip the lower
        partials overrides this)."""
        return self._grid(us, vs, du, dv)[-1, -1]

    # --- differential geometry -------------------------------------------------------------
    def normals(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
        """(n, defined): the unit normal (S_u x S_v)/|S_u x S_v| where it is defined and a
        mask of where that is (:func:`unit_normals`, with the scales size / (u1 - u0) and
        size / (v1 - v0)); n is zero elsewhere (a pole, an apex, a collapsed patch)."""
        return self._normals_of(self.derivatives(u, v, 1, 1))

    def _normals_of(self, d: np.ndarray, strict: bool = False) -> Tuple[np.ndarray, np.ndarray]:
        """:meth:`normals` from the partials ``d`` (of :meth:`derivatives`, orders >= 1);
        ``strict``: CagdError where the normal is undefined."""
        (u0, u1), (v0, v1) = self.domain
        n, defined = unit_normals(d[1, 0], d[0, 1], self.size / (u1 - u0), self.size / (v1 - v0))
        if strict and not np.all(defined):
            raise CagdError("u, v: the normal is undefined (degenerate point: S_u x S_v = 0)")
        return n, defined

    def normal(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Unit normal (S_u x S_v)/|S_u x S_v| (seed 003, 2.1); CagdError where it is
        undefined (see :meth:`normals`)."""
        return self._normals_of(self.derivatives(u, v, 1, 1), strict=True)[0]

    @property
    def size(self) -> float:
        """Largest extent of the control net's bounding box (a length scale for tolerances)."""
        if getattr(self, "_size", None) is None:
            net = np.asarray(self.to_nurbs().control_points).reshape(-1, self.dim)
            self._size = max(float(np.ptp(net, axis=0).max()), 1e-300)
        return self._size

    def fundamental_forms(self, u: ArrayLike, v: ArrayLike) -> Tuple[FormCoefficients, FormCoefficients]:
        """First (E, F, G) and second (L, M, N) fundamental forms:
        E = S_u.S_u, F = S_u.S_v, G = S_v.S_v; L = S_uu.n, M = S_uv.n, N = S_vv.n
        (do Carmo, Differential Geometry of Curves and Surfaces, 3.3)."""
        ((E, F, G), (L, M, N)), sigma, _ = self._normalised_forms(u, v)
        with np.errstate(over="ignore", under="ignore"):
            s2 = sigma * sigma
            return (E * s2, F * s2, G * s2), (L * sigma, M * sigma, N * sigma)

    def _normalised_forms(self, u: ArrayLike, v: ArrayLike, strict: bool = True
                          ) -> Tuple[Tuple[FormCoefficients, FormCoefficients], np.ndarray, np.ndarray]:
        """The forms of the partials divided by sigma, the largest coordinate of S_u and S_v
        at each point (a normalised frame: E/sigma^2, L/sigma, ...), sigma, and the mask
        where the normal is defined; the curvatures follow as K = K'/sigma^2, H = H'/sigma,
        free of over/underflow. ``strict``: CagdError where the normal is undefined
        (else the second form is 0 there and the mask says so)."""
        d = self.derivatives(u, v, 2, 2)
        n, defined = self._normals_of(d, strict)
        su, sv = _as3(d[1, 0]), _as3(d[0, 1])
        sigma = np.maximum(np.max(np.abs(su), axis=-1), np.max(np.abs(sv), axis=-1))
        f = np.where(sigma > 0, sigma, 1.0)[..., None]
        su, sv = su / f, sv / f
        dot = lambda a, b: np.einsum("...i,...i->...", a, b)  # noqa: E731
        first = (dot(su, su), dot(su, sv), dot(sv, sv))
        second = (dot(_as3(d[2, 0]) / f, n), dot(_as3(d[1, 1]) / f, n), dot(_as3(d[0, 2]) / f, n))
        return (first, second), sigma, defined

    def _curvatures(self, u: ArrayLike, v: ArrayLike, strict: bool = True) -> Tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray, np.ndarray]:
        """(K, H, D, defined): Gaussian K = (LN - M^2) / (EG - F^2), mean
        H = (EN - 2FM + GL) / (2 (EG - F^2)) (sign follows the normal S_u x S_v) and the
        discriminant D = H^2 - K of the principal curvatures H +- sqrt(D), computed as
        ((GL - EN) / (2W))^2 + (GM - FN)(EM - FL) / W^2, W = EG - F^2 (the eigenvalues of
        the shape operator I^-1 II; no cancellation at umbilics), clipped at 0 (do Carmo,
        Differential Geometry of Curves and Surfaces, 3.3). In the normalised frame:
        K(lambda S) = K(S) / lambda^2, H(lambda S) = H(S) / lambda. ``strict``: CagdError
        where the normal is undefined; else NaN there, and ``defined`` says where. Values
        beyond the floating-point range are inf/NaN: callers check what they use
        (:func:`_representable`)."""
        ((E, F, G), (L, M, N)), sigma, defined = self._normalised_forms(u, v, strict)
        with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
            W = E * G - F * F
            K = (L * N - M * M) / W / sigma / sigma
            H = (E * N - 2 * F * M + G * L) / (2 * W) / sigma
            D = np.maximum((((G * L - E * N) / (2 * W)) ** 2 + (G * M - F * N) * (E * M - F * L) / W / W)
                           / sigma / sigma, 0.0)
        nan = np.float64(np.nan)
        K, H, D = (np.where(defined, x, nan) for x in (K, H, D))
        return K, H, D, defined

    def gaussian_curvature(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """K = (LN - M^2) / (EG - F^2), computed in the normalised frame (scale-invariant:
        K(lambda S) = K(S) / lambda^2); CagdError where the normal is undefined or K
        exceeds the floating-point range (see :meth:`_curvatures`)."""
        return _representable(self._curvatures(u, v)[0], "gaussian_curvature")

    def mean_curvature(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """H = (EN - 2FM + GL) / (2 (EG - F^2)) (sign follows the normal S_u x S_v),
        in the normalised frame (H(lambda S) = H(S) / lambda); CagdError where the
        normal is undefined or H exceeds the floating-point range (see :meth:`_curvatures`)."""
        return _representable(self._curvatures(u, v)[1], "mean_curvature")

    def transformed(self, matrix: ArrayLike, offset: Optional[ArrayLike] = None) -> "Surface":
        """The surface under x -> matrix @ x + offset, applied to the control points."""
        A, b = affine_map(matrix, offset, self.dim, "surface")
        return self._affine(A, b)

    # --- iso-parametric and boundary curves --------------------------------------------------
    def isocurve(self, direction: str, value: float) -> BSplineCurve:
        """The curve u -> S(u, value) (direction "u") or v -> S(value, v) (direction "v")
        as an engine curve, from the NURBS form."""
        return self.to_nurbs().isocurve(direction, value)

    def boundaries(self) -> list:
        """The four boundary curves [S(u, v0), S(u1, v), S(u, v1), S(u0, v)] (not reversed)."""
        (u0, u1), (v0, v1) = self.domain
        return [self.isocurve("u", v0), self.isocurve("v", u1), self.isocurve("u", v1), self.isocurve("v", u0)]


def _representable(x: np.ndarray, what: str) -> np.ndarray:
    """``x`` unless it overflowed (a curvature beyond 1.8e308: a surface about 1e-154 in
    size or smaller), which is a CagdError."""
    if not np.all(np.isfinite(x)):
        raise CagdError(f"u, v: the {what} exceeds the floating-point range there (the surface is too small)")
    return x


def _as3(x: np.ndarray) -> np.ndarray:
    """Lift 2-D vectors to 3-D (z = 0) for cross products."""
    if x.shape[-1] == 3:
        return x
    if x.shape[-1] == 2:
        return np.concatenate([x, np.zeros(x.shape[:-1] + (1,))], axis=-1)
    raise CagdError(f"normal: defined for 2-D and 3-D surfaces, this one is {x.shape[-1]}-D")


def rational_partials(hom: np.ndarray) -> np.ndarray:
    """Cartesian partials S^(k,l) from homogeneous ones (du+1, dv+1, ..., dim+1)
    (Piegl & Tiller A4.4, eq. 4.20)."""
    from math import comb
    A, w = hom[..., :-1], hom[..., -1:]
    du, dv = hom.shape[0] - 1, hom.shape[1] - 1
    S = np.empty_like(A)
    for k in range(du + 1):
        for l in range(dv + 1):
            v = A[k, l].copy(order="K")           # the layout of hom (long inner loops)
            for j in range(1, l + 1):
                v -= comb(l, j) * w[0, j] * S[k, l - j]
            for i in range(1, k + 1):
                v -= comb(k, i) * w[i, 0] * S[k - i, l]
                for j in range(1, l + 1):
                    v -= comb(k, i) * comb(l, j) * w[i, j] * S[k - i, l - j]
            S[k, l] = v / w[0, 0]
    return S
