"""Coons patches: surfaces from four boundary curves by Boolean sums of blended
curves (Farin, Curves and Surfaces for CAGD, 5th ed., ch. 22; Piegl & Tiller don't
cover them and neither do the seeds).

Orientation convention for all patches on [0, 1]^2: c0(u) = S(u, 0), c1(u) = S(u, 1),
d0(v) = S(0, v), d1(v) = S(1, v); every curve's own domain [a, b] is mapped linearly
onto [0, 1] (the derivatives below are with respect to that unit parameter).

S = Lc + Ld - B with Lc = sum_j h_j(v) C_j(u) (curves in u blended in v),
Ld = sum_i h_i(u) D_i(v), and B = sum_ij h_i(u) h_j(v) G_ij the tensor-product
interpolant of the corner data G_ij. Evaluation and all partial derivatives follow
from the curves' derivatives and the blend polynomials.
"""
from __future__ import annotations

from math import comb
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .. import _checks
from .._deprecation import RELATIVE, deprecated, renamed
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from .base import Surface
from .bspline import BSplineSurface
from .loft import compatible_plain, multiplicities, plain, snapped, union_breaks, unit_nurbs

# blend functions h_k: power coefficients (ascending) and Bernstein coefficients
CORNER_TOL = 1e-9     # default relative corner tolerance of the Coons patches

_LINEAR = (_checks.frozen([[1.0, -1.0], [0.0, 1.0]]), _checks.frozen([[1.0, 0.0], [0.0, 1.0]]))
# the cubic Hermite basis of seed 000, 5.1.2 in the slot order value at 0, derivative at 0,
# derivative at 1, value at 1, i.e. the seed's H0, H2, H3, H1 (Bernstein: H0 = B0 + B1,
# H2 = B1 / 3, H3 = -B2 / 3, H1 = B2 + B3)
_CUBIC = (_checks.frozen([[1.0, 0.0, -3.0, 2.0], [0.0, 1.0, -2.0, 1.0], [0.0, 0.0, -1.0, 1.0], [0.0, 0.0, 3.0, -2.0]]),
          _checks.frozen([[1.0, 1.0, 0.0, 0.0], [0.0, 1 / 3, 0.0, 0.0], [0.0, 0.0, -1 / 3, 0.0], [0.0, 0.0, 1.0, 1.0]]))


def _blend(power: np.ndarray, t: np.ndarray, order: int) -> np.ndarray:
    """Derivatives 0..order of the blend polynomials at t: (order+1, nblend, len(t))."""
    n = power.shape[1]
    out = np.zeros((order + 1, power.shape[0], t.shape[0]))
    T = t[None, :] ** np.arange(n)[:, None]                     # (n, N)
    c = power.copy()
    for k in range(min(order, n - 1) + 1):
        out[k] = c @ T
        c = c[:, 1:] * np.arange(1, c.shape[1])                 # d/dt of the power form
        c = np.pad(c, ((0, 0), (0, 1)))
    return out


def _unit_derivatives(curve: Curve, t: np.ndarray, order: int) -> np.ndarray:
    """Derivatives 0..order of s -> curve(a + s (b - a)): (order+1, len(t), dim)."""
    a, b = curve.domain
    d = curve.derivatives(a + t * (b - a), order)
    return d * ((b - a) ** np.arange(order + 1))[:, None, None]


def _product(f: BSplineCurve, g: BSplineCurve) -> BSplineCurve:
    """The product f g of two polynomial splines on [0, 1] (one of them scalar), exact:
    both are split into Bezier pieces on the union of their knots and multiplied piece
    by piece, h_k = sum_{i+j=k} C(p,i) C(q,j) / C(p+q,k) f_i g_j (Farin, 5th ed., 5.10),
    joined with knots of multiplicity p + q (C0 form of the same function)."""
    reps = union_breaks([f.knots, g.knots])
    pieces = []
    for c in (f, g):
        c = snapped(c, reps)
        new = np.repeat(reps, c.degree - multiplicities(c.knots, reps))
        c = c.refine(new) if new.size else c
        P = c.control_points
        idx = c.degree * np.arange(len(reps) + 1)[:, None] + np.arange(c.degree + 1)
        pieces.append(P[idx])                                   # (nseg, deg+1, dim)
    F, G = pieces
    p, q = f.degree, g.degree
    H = np.zeros((F.shape[0], p + q + 1, max(F.shape[2], G.shape[2])))
    for i in range(p + 1):
        for j in range(q + 1):
            H[:, i + j] += comb(p, i) * comb(q, j) / comb(p + q, i + j) * F[:, i] * G[:, j]
    points = np.concatenate([H[0]] + [h[1:] for h in H[1:]])
    r = p + q
    knots = np.concatenate([np.zeros(r + 1), np.repeat(reps, r), np.ones(r + 1)])
    return BSplineCurve(points, r, knots)


def _times(f: BSplineCurve, w: Optional[BSplineCurve]) -> BSplineCurve:
    return f if w is None else _product(f, w)


def _over_common_denominator(curves: List[BSplineCurve]) -> Tuple[Optional[BSplineCurve], List[BSplineCurve]]:
    """Unit NURBS curves C_k = A_k / w_k written as N_k / W with one denominator W, the
    product of their distinct weight functions (weight functions proportional to
    within 1e-14 relative count once: A / (lam w) = (A / lam) / w). Returns (W or None,
    numerators N_k), all polynomial splines."""
    rational = [k for k, c in enumerate(curves) if c.weights is not None]
    if not rational:
        return None, [plain(c) for c in curves]
    ws = compatible_plain([BSplineCurve(c.weights, c.degree, c.knots) for c in curves if c.weights is not None])
    groups: List[BSplineCurve] = []
    member: Dict[int, Tuple[int, float]] = {}
    for k, w in zip(rational, ws):
        for m, base in enumerate(groups):
            ratio = w.control_points[:, 0] / base.control_points[:, 0]
            if np.ptp(ratio) <= 1e-14 * ratio.mean():
                member[k] = (m, ratio.mean())
                break
        else:
            member[k] = (len(groups), 1.0)
            groups.append(w)
    W = groups[0]
    for g in groups[1:]:
        W = _product(W, g)
    numerators = []
    for k, c in enumerate(curves):
        A = BSplineCurve(c.control_points, c.degree, c.knots)
        if k not in member or c.weights is None:
            numerators.append(_product(A, W))
            continue
        m, lam = member[k]
        A = BSplineCurve(c.control_points * (c.weights / lam)[:, None], c.degree, c.knots)
        for other, g in enumerate(groups):
            if other != m:
                A = _product(A, g)
        numerators.append(A)
    return W, numerators


class _BlendedPatch(Surface):
    """S = sum_j h_j(v) C_j(u) + sum_i h_i(u) D_i(v) - sum_ij h_i(u) h_j(v) G_ij."""

    _power: np.ndarray
    _bern: np.ndarray
    _c_names: Tuple[str, ...]
    _d_names: Tuple[str, ...]
    _order: Tuple[int, ...]                  # derivative order of each slot
    _corner: Tuple[int, ...]                 # the parameter (0 or 1) of each slot

    def _setup(self, c_curves: Sequence[Optional[Curve]], d_curves: Sequence[Optional[Curve]], rel_tol: float,
               tol: Optional[float] = None) -> None:
        if tol is not None:
            rel_tol = renamed(type(self).__name__, "tol", "rel_tol", tol, rel_tol, CORNER_TOL, RELATIVE)
        self.rel_tol = _checks.scalar(rel_tol, "rel_tol")
        if self.rel_tol < 0:
            raise CagdError(f"rel_tol: must be non-negative, got {self.rel_tol}")
        given = list(zip(self._c_names + self._d_names, list(c_curves) + list(d_curves)))
        boundaries = {self._c_names[0], self._c_names[-1], self._d_names[0], self._d_names[-1]}
        for name, c in given:                 # the four boundary curves are never optional
            if c is None and name in boundaries:
                raise CagdError(f"{name}: expected a cagd curve (a boundary of the patch), got None")
        named = [(n, c) for n, c in given if c is not None]
        for name, c in named:
            if not isinstance(c, Curve):
                raise CagdError(f"{name}: expected a cagd curve, got {type(c).__name__}")
        dims = {c.dim for _, c in named}
        if len(dims) > 1:
            raise CagdError(f"{', '.join(n for n, _ in named)}: curves of different dimensions {sorted(dims)}")
        self.dim = dims.pop()
        self._c = tuple(c_curves)
        self._d = tuple(d_curves)
        nb = len(self._order)
        G = np.zeros((nb, nb, self.dim))
        for i in range(nb):
            for j in range(nb):
                C, D = self._c[j], self._d[i]
                if C is None or D is None:
                    continue
                x = _unit_derivatives(C, np.array([float(self._corner[i])]), self._order[i])[-1, 0]
                y = _unit_derivatives(D, np.array([float(self._corner[j])]), self._order[j])[-1, 0]
                gap = float(np.linalg.norm(x - y))
                if gap > self.rel_tol * max(1.0, float(np.abs(x).max()), float(np.abs(y).max())):
                    pc, pd = "'" * self._order[i], "'" * self._order[j]
                    raise CagdError(f"corner ({self._corner[i]},{self._corner[j]}): "
                                    f"{self._c_names[j]}{pc}({self._corner[i]}) and {self._d_names[i]}{pd}"
                                    f"({self._corner[j]}) differ by {gap:.3g} (rel_tol {self.rel_tol:g})")
                G[i, j] = 0.5 * (x + y)
        self._G = _checks.frozen(G)

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        return (0.0, 1.0), (0.0, 1.0)

    @property
    def tol(self) -> float:
        """Deprecated name of :attr:`rel_tol`."""
        deprecated(f"{type(self).__name__}.tol", "use rel_tol (the same relative corner tolerance)")
        return self.rel_tol

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        hu, hv = _blend(self._power, u, du), _blend(self._power, v, dv)
        out = -np.einsum("kin,ljn,ijd->klnd", hu, hv, self._G)
        for j, C in enumerate(self._c):
            if C is not None:
                out += _unit_derivatives(C, u, du)[:, None] * hv[None, :, j, :, None]
        for i, D in enumerate(self._d):
            if D is not None:
                out += hu[:, None, i, :, None] * _unit_derivatives(D, v, dv)[None]
        return out

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        hu, hv = _blend(self._power, us, du), _blend(self._power, vs, dv)
        out = -np.einsum("kim,ljn,ijd->klmnd", hu, hv, self._G)
        for j, C in enumerate(self._c):
            if C is not None:
                out += _unit_derivatives(C, us, du)[:, None, :, None, :] * hv[None, :, j, None, :, None]
        for i, D in enumerate(self._d):
            if D is not None:
                out += hu[:, None, i, :, None, None] * _unit_derivatives(D, vs, dv)[None, :, None, :, :]
        return out

    def to_nurbs(self) -> BSplineSurface:
        """The exact NURBS form. Every term is a sum of tensor products (u-spline) x
        (v-spline); over the common denominators W_u(u) of the c-side curves and W_v(v)
        of the d-side curves (products of their weight functions, 1 if polynomial):
        S = [sum_j N_j(u) (h_j W_v)(v) + sum_i (h_i W_u)(u) M_i(v)
             - sum_i (h_i W_u)(u) (sum_j h_j G_ij W_v)(v)] / (W_u(u) W_v(v)),
        with C_j = N_j / W_u and D_i = M_i / W_v. All u factors are brought to one degree
        and knot vector (elevation, refinement), likewise in v, and the control nets of
        the tensor products summed. Polynomial boundaries give degrees
        (max(p_c, blend), max(p_d, blend)); rational ones raise the degrees by the
        denominators (exact, never approximated)."""
        cached = getattr(self, "_nurbs", None)
        if cached is not None:
            return cached
        self._nurbs = self._build_nurbs()
        return self._nurbs

    def _build_nurbs(self) -> BSplineSurface:
        deg = self._power.shape[1] - 1
        blends = [BSplineCurve(b, deg, np.repeat([0.0, 1.0], deg + 1)) for b in self._bern]
        cs = [(j, unit_nurbs(c)) for j, c in enumerate(self._c) if c is not None]
        ds = [(i, unit_nurbs(d)) for i, d in enumerate(self._d) if d is not None]
        Wu, Nc = _over_common_denominator([c for _, c in cs])
        Wv, Nd = _over_common_denominator([d for _, d in ds])
        terms = [(N, _times(blends[j], Wv)) for (j, _), N in zip(cs, Nc)]
        terms += [(_times(blends[i], Wu), M) for (i, _), M in zip(ds, Nd)]
        for i in range(len(blends)):
            if np.any(self._G[i]):
                g = BSplineCurve(-self._bern.T @ self._G[i], deg, blends[0].knots)
                terms.append((_times(blends[i], Wu), _times(g, Wv)))
        if Wu is not None or Wv is not None:
            one = BSplineCurve(np.ones(2), 1, [0.0, 0.0, 1.0, 1.0])
            terms.append((one if Wu is None else Wu, one if Wv is None else Wv))
        us = compatible_plain([t[0] for t in terms])
        vs = compatible_plain([t[1] for t in terms])
        products = [a.control_points[:, None, :] * b.control_points[None, :, :] for a, b in zip(us, vs)]
        if Wu is None and Wv is None:
            net = sum(products)
            return BSplineSurface(net, us[0].degree, vs[0].degree, us[0].knots, vs[0].knots)
        net, weight = sum(products[:-1]), products[-1][..., 0]
        return BSplineSurface(net / weight[..., None], us[0].degree, vs[0].degree, us[0].knots,
                              vs[0].knots, weight)


class CoonsPatch(_BlendedPatch):
    """Bilinearly blended Coons patch (Farin ch. 22.2):
    S(u, v) = (1-v) c0(u) + v c1(u) + (1-u) d0(v) + u d1(v)
              - [(1-u)(1-v) P00 + u(1-v) P10 + (1-u) v P01 + u v P11]
    with the corners P00 = c0(0) = d0(0), P10 = c0(1) = d1(0), P01 = c1(0) = d0(1),
    P11 = c1(1) = d1(1) (the mean of the two curves' ends). S interpolates all four
    boundary curves (within half a corner gap accepted by ``rel_tol``); :meth:`to_nurbs`
    is exact for polynomial and rational curves.

    Args:
        c0, c1, d0, d1: engine curves of one dimension (see the module docstring).
        rel_tol: the two curve ends at a corner may differ by
            rel_tol * max(1, |coordinates|) (default CORNER_TOL = 1e-9).
        tol: the deprecated name of ``rel_tol`` (one release; ``tol`` is a distance in cagd).

    Raises:
        CagdError: a non-curve, mixed dimensions, a corner mismatch (naming the corner,
            the two curves and the gap), a negative rel_tol.
    """

    _power, _bern = _LINEAR
    _c_names, _d_names = ("c0", "c1"), ("d0", "d1")
    _order, _corner = (0, 0), (0, 1)

    def __init__(self, c0: Curve, c1: Curve, d0: Curve, d1: Curve, rel_tol: float = CORNER_TOL, *,
                 tol: Optional[float] = None):
        self._setup([c0, c1], [d0, d1], rel_tol, tol)

    @classmethod
    def from_loop(cls, curves: Sequence[Curve], rel_tol: float = CORNER_TOL, *,
                  tol: Optional[float] = None) -> "CoonsPatch":
        """The Coons patch bounded by four curves in any order and direction that form
        a closed loop (the edges of a wire, say): ``curves[0]`` becomes c0, its end
        the corner P10, and the others are chained end to end, reversed where needed
        (exact reversal of the NURBS form, :meth:`cagd.BSplineCurve.reversed`). The
        ends must meet within ``rel_tol`` times the loop's size (at least 1), the
        corners as for :class:`CoonsPatch`; ``tol`` is the deprecated name of ``rel_tol``.

        Raises:
            CagdError: not four curves, or they do not chain into one loop within
                ``rel_tol`` relative to the loop's size.
        """
        if tol is not None:
            rel_tol = renamed("CoonsPatch.from_loop", "tol", "rel_tol", tol, rel_tol, CORNER_TOL, RELATIVE)
        curves = list(curves)
        if len(curves) != 4 or not all(isinstance(c, Curve) for c in curves):
            raise CagdError(f"curves: need four cagd curves forming a loop, got {len(curves)} items")
        ends = [tuple(c(np.array(c.domain, dtype=float))) for c in curves]
        size = max(float(np.ptp(np.array([e for pair in ends for e in pair]), axis=0).max()), 1.0)
        chain, rest, point = [curves[0]], [1, 2, 3], ends[0][1]
        for k in range(3):
            gaps = [(min(np.linalg.norm(ends[i][0] - point), np.linalg.norm(ends[i][1] - point)), i) for i in rest]
            gap, i = min(gaps)
            if gap > rel_tol * size:
                raise CagdError(f"curves: no curve starts or ends where curve {k} of the loop ends "
                                f"(nearest gap {gap:.3g}, allowed rel_tol * size = {rel_tol * size:.3g})")
            rest.remove(i)
            forward = np.linalg.norm(ends[i][0] - point) <= np.linalg.norm(ends[i][1] - point)
            chain.append(curves[i] if forward else curves[i].to_nurbs().reversed())
            point = ends[i][1] if forward else ends[i][0]
        if np.linalg.norm(point - ends[0][0]) > rel_tol * size:
            raise CagdError(f"curves: the loop does not close (gap {np.linalg.norm(point - ends[0][0]):.3g})")
        c0, d1, c1_rev, d0_rev = chain
        return cls(c0, c1_rev.to_nurbs().reversed(), d0_rev.to_nurbs().reversed(), d1, rel_tol)

    def __repr__(self) -> str:
        return f"<bilinearly blended Coons patch, {self.dim}-D>"

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "CoonsPatch":
        c0, c1, d0, d1 = (c.transformed(A, b) for c in self._c + self._d if c is not None)
        return CoonsPatch(c0, c1, d0, d1, rel_tol=self.rel_tol)


class HermiteCoonsPatch(_BlendedPatch):
    """Bicubically blended Coons patch (Farin ch. 22.4), with the cubic Hermite basis
    of seed 000, 5.1.2 (H0, H1: values at 0 and 1; H2, H3: derivatives at 0 and 1) in
    place of the linear blends:
    S = sum_k F_k(v) C_k(u) + sum_k F_k(u) D_k(v) - sum_kl F_k(u) F_l(v) G_kl with
    F = (H0, H2, H3, H1), C = (c0, c0_v, c1_v, c1), D = (d0, d0_u, d1_u, d1) and G the
    bicubic Hermite corner data (positions, S_u, S_v, twists S_uv).

    With the four cross-boundary derivative curves (tangent ribbons)
    c0_v(u) = S_v(u, 0), c1_v(u) = S_v(u, 1), d0_u(v) = S_u(0, v), d1_u(v) = S_u(1, v)
    (derivatives in the unit parameters) the patch interpolates positions and
    cross-boundary derivatives on all four sides; the corners must be compatible:
    c_j'(i) = d_i_u(j), d_i'(j) = c_j_v(i) and the twists c_j_v'(i) = d_i_u'(j).
    Without them (all four None) only positions are blended (the derivative terms of C,
    D and G are dropped): S still interpolates the boundary, and its cross-boundary
    derivative is the Hermite blend of the neighbouring curves' end tangents, e.g.
    S_v(u, 0) = H0(u) d0'(0) + H1(u) d1'(0) (not zero).

    Raises:
        CagdError: a non-curve, mixed dimensions, only some ribbons given, an
            incompatible corner (naming it, the two curves and the gap), a negative
            rel_tol (relative, as for :class:`CoonsPatch`; ``tol`` its deprecated name).
    """

    _power, _bern = _CUBIC
    _c_names, _d_names = ("c0", "c0_v", "c1_v", "c1"), ("d0", "d0_u", "d1_u", "d1")
    _order, _corner = (0, 1, 1, 0), (0, 0, 1, 1)

    def __init__(self, c0: Curve, c1: Curve, d0: Curve, d1: Curve, c0_v: Optional[Curve] = None,
                 c1_v: Optional[Curve] = None, d0_u: Optional[Curve] = None, d1_u: Optional[Curve] = None,
                 rel_tol: float = CORNER_TOL, *, tol: Optional[float] = None):
        ribbons = (c0_v, c1_v, d0_u, d1_u)
        given = sum(r is not None for r in ribbons)
        if given not in (0, 4):
            raise CagdError("c0_v, c1_v, d0_u, d1_u: give all four cross-boundary derivative curves or none")
        self.has_ribbons = given == 4
        self._setup([c0, c0_v, c1_v, c1], [d0, d0_u, d1_u, d1], rel_tol, tol)

    def __repr__(self) -> str:
        kind = "with tangent ribbons" if self.has_ribbons else "positions only"
        return f"<bicubically blended Coons patch ({kind}), {self.dim}-D>"

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "HermiteCoonsPatch":
        zero = np.zeros_like(b)
        c0, c0v, c1v, c1 = self._c
        d0, d0u, d1u, d1 = self._d
        assert c0 is not None and c1 is not None and d0 is not None and d1 is not None  # boundaries: always given
        lin = [None if r is None else r.transformed(A, zero) for r in (c0v, c1v, d0u, d1u)]
        return HermiteCoonsPatch(c0.transformed(A, b), c1.transformed(A, b), d0.transformed(A, b),
                                 d1.transformed(A, b), lin[0], lin[1], lin[2], lin[3], rel_tol=self.rel_tol)
