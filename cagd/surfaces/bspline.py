"""Tensor-product B-spline and NURBS surfaces (seed 000, 5.3.3; seed 003, 2.3-2.4;
Piegl & Tiller ch. 3-5).

S(u, v) = sum_i sum_j N_{i,p}(u) N_{j,q}(v) w_ij P_ij / sum_i sum_j N_{i,p}(u) N_{j,q}(v) w_ij.
Knot conventions per direction are those of :class:`cagd.BSplineCurve`. Operations in
one direction (knot insertion, elevation, split, reversal, ...) reuse the curve
algorithms on the rows of the homogeneous control net, seen as one curve whose
"points" are whole rows.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, NamedTuple, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bspline import basis_derivatives
from ..curves.bspline import BSplineCurve
from ..basis.bernstein import bernstein_values
from ..curves.ppform import PP_MAX_DEGREE, PPForm
from ..errors import CagdError
from ..knots import vectors as kv
from .base import Surface, rational_partials

if TYPE_CHECKING:
    from ..knots.removal import KnotRemoval
    from ..knots.reduction import DegreeReduction

_CHUNK = 1 << 14
_GATHER_VALUES = 1 << 22    # local net values gathered per chunk of the basis path (32 MiB)
_GRID_VALUES = 1 << 20      # v-sums of one chunk of a grid evaluation, values of any of its blocks (8 MiB)
_GRID_BLOCK = 1 << 16       # values of a product block that is copied on (512 KiB: in cache for the division)
_GRID_ROWS = 32             # pole rows of a dense local basis block: a product of ~2 x 32 flops per value
_GRID_GEMM_MIN = 1 << 12    # values below which a matrix-product block takes the banded passes instead


class SurfaceOccForm(NamedTuple):
    """Exactly the arguments of OCCT's ``Geom_BSplineSurface`` constructor."""
    poles: np.ndarray                # (nu, nv, 3)
    weights: Optional[np.ndarray]    # (nu, nv) or None
    knots_u: np.ndarray              # distinct knots
    knots_v: np.ndarray
    multiplicities_u: np.ndarray     # int
    multiplicities_v: np.ndarray
    degree_u: int
    degree_v: int
    periodic_u: bool
    periodic_v: bool


class BSplineSurface(Surface):
    """B-spline surface, NURBS when ``weights`` are given.

    Args:
        control_points: (nu, nv, dim) control net; for a periodic direction the distinct rows.
        degree_u, degree_v: degrees p, q >= 1.
        knots_u, knots_v: per direction as for BSplineCurve (full vector, or one period).
        weights: (nu, nv) positive weights or None.
        periodic_u, periodic_v: closed in that direction.

    Raises:
        CagdError: shapes, counts, knots, multiplicities, weights, NaN/inf, degrees.
    """

    #: the attributes that define the object (equal ones give equal geometry): the
    #: closest-point projectors are cached by them (cagd.queries.closest.content_key)
    _content_fields = ("periodic_u", "periodic_v", "degree_u", "degree_v", "knots_u", "knots_v", "control_points",
                       "weights")

    _modified_copy = "use with_control_points(P), moved_pole((i, j), point) or with_weights(W)"

    def __init__(self, control_points: ArrayLike, degree_u: int, degree_v: int, knots_u: Optional[ArrayLike] = None,
                 knots_v: Optional[ArrayLike] = None, weights: Optional[ArrayLike] = None, periodic_u: bool = False,
                 periodic_v: bool = False):
        P = _checks.finite_array(control_points, "control_points")
        if P.ndim != 3 or P.shape[0] < 2 or P.shape[1] < 2 or P.shape[2] < 1:
            raise CagdError(f"control_points: expected shape (nu >= 2, nv >= 2, dim), got {P.shape}")
        nu, nv = P.shape[:2]
        W = None if weights is None else _weights(weights, (nu, nv))
        pu, pv = bool(periodic_u), bool(periodic_v)
        p = _checks.degree(degree_u, "degree_u", 1, nu if pu else nu - 1)
        q = _checks.degree(degree_v, "degree_v", 1, nv if pv else nv - 1)
        ku, full_u = _direction(knots_u, nu, p, pu, "knots_u")
        kvv, full_v = _direction(knots_v, nv, q, pv, "knots_v")
        self._fill(P, W, (p, ku, full_u, pu), (q, kvv, full_v, pv))

    def _fill(self, P: np.ndarray, W: Optional[np.ndarray], u_dir: tuple, v_dir: tuple) -> None:
        """Bind validated parts, frozen; per direction (degree, knots, unwrapped knots of a
        periodic direction, periodic)."""
        (p, ku, full_u, pu), (q, kvv, full_v, pv) = u_dir, v_dir
        self.periodic_u, self.periodic_v = pu, pv
        self.degree_u, self.degree_v = p, q
        self.knots_u, self.knots_v = _checks.frozen(ku), _checks.frozen(kvv)
        self._u = _checks.frozen(full_u) if pu else self.knots_u          # full (unwrapped) knot vectors
        self._v = _checks.frozen(full_v) if pv else self.knots_v
        self.control_points = _checks.frozen(P)
        self.weights = None if W is None else _checks.frozen(W)
        self.dim = P.shape[2]
        if W is None and not (pu or pv):
            self._hom = self.control_points                     # unwrapped homogeneous net
        else:
            hom = P if W is None else _checks.finite_homogeneous(np.concatenate([P * W[..., None], W[..., None]],
                                                                                axis=2))
            if pu or pv:
                hom = hom[kv.unwrapped_index(P.shape[0], p, pu)][:, kv.unwrapped_index(P.shape[1], q, pv)]
            self._hom = _checks.frozen(hom)

    # --- modified copies (the object itself never changes) --------------------------------
    def _with(self, P: np.ndarray, W: Optional[np.ndarray]) -> "BSplineSurface":
        return BSplineSurface._unchecked(P, W, (self.degree_u, self.knots_u, self._u, self.periodic_u),
                                         (self.degree_v, self.knots_v, self._v, self.periodic_v))

    def with_control_points(self, control_points: ArrayLike) -> "BSplineSurface":
        """The surface with the same degrees, knots, weights and periodicity on a new
        control net of the same shape (checked as in the constructor).

        Raises:
            CagdError: NaN/inf, a shape other than ``control_points.shape``."""
        P = _checks.finite_array(control_points, "control_points")
        return self._with(_checks.same_shape(P, self.control_points.shape, "control_points"), self.weights)

    def moved_pole(self, index: Tuple[int, int], point: ArrayLike) -> "BSplineSurface":
        """The surface with control point ``index`` = (i, j) (row i in u, column j in v;
        negative from the end; distinct points in a periodic direction) moved to
        ``point``, all else kept: the cheap edit for dragging a pole (no knot checks,
        O(nu nv) copies, evaluation tables rebuilt on the next use).

        Raises:
            CagdError: an index that is not two ints in range, a bad point."""
        i, j = _checks.pole_index(index, self.control_points.shape[:2])
        P = self.control_points.copy()
        P[i, j] = _checks.point(point, self.dim)
        return self._with(P, self.weights)

    def with_weights(self, weights: Optional[ArrayLike]) -> "BSplineSurface":
        """The same control net, degrees and knots with new (nu, nv) weights (None: polynomial).

        Raises:
            CagdError: a shape other than (nu, nv), weights not positive, NaN/inf."""
        W = None if weights is None else _weights(weights, self.control_points.shape[:2])
        return self._with(self.control_points, W)

    # --- properties --------------------------------------------------------------------
    @property
    def is_rational(self) -> bool:
        return self.weights is not None

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        p, q = self.degree_u, self.degree_v
        nu, nv = self._hom.shape[:2]
        return (float(self._u[p]), float(self._u[nu])), (float(self._v[q]), float(self._v[nv]))

    @property
    def homogeneous_control_points(self) -> np.ndarray:
        """The unwrapped homogeneous net (w P, w), or P when polynomial (read-only)."""
        return self._hom

    def __repr__(self) -> str:
        kind = "NURBS" if self.is_rational else "B-spline"
        nu, nv = self.control_points.shape[:2]
        return f"<{kind} surface degree ({self.degree_u}, {self.degree_v}), {nu} x {nv} control points>"

    def to_nurbs(self) -> "BSplineSurface":
        return self

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "BSplineSurface":
        return BSplineSurface(self.control_points @ A.T + b, self.degree_u, self.degree_v, self.knots_u,
                              self.knots_v, self.weights, self.periodic_u, self.periodic_v)

    # --- OCCT form ---------------------------------------------------------------------
    def occ_form(self) -> SurfaceOccForm:
        """Poles (nu, nv, 3), weights, distinct knots and multiplicities per direction,
        degrees and periodic flags — what ``Geom_BSplineSurface`` takes; per direction
        as :meth:`cagd.BSplineCurve.occ_form` (periodic poles rolled by the seam shift
        of :func:`cagd.knots.occ_knots`). 2-D nets get z = 0. Degrees above 25 (OCCT's
        maximum) raise CagdError: such surfaces do not convert to OCCT."""
        if self.dim > 3:
            raise CagdError(f"control_points: OCCT surfaces are 3-D at most, this one is {self.dim}-D")
        if max(self.degree_u, self.degree_v) > _checks.OCC_MAX_DEGREE:
            raise CagdError(f"degree_u, degree_v: OCCT's maximum B-spline degree is {_checks.OCC_MAX_DEGREE} "
                            f"(Geom_BSplineSurface::MaxDegree()); this surface has degrees "
                            f"({self.degree_u}, {self.degree_v})")
        poles = np.zeros(self.control_points.shape[:2] + (3,))
        poles[..., :self.dim] = self.control_points
        w = None if self.weights is None else self.weights.copy()
        ku, mu, su = kv.occ_knots(self.knots_u, self.periodic_u)
        kvv, mv, sv = kv.occ_knots(self.knots_v, self.periodic_v)
        poles = np.roll(poles, (-su, -sv), axis=(0, 1))
        w = None if w is None else np.roll(w, (-su, -sv), axis=(0, 1))
        return SurfaceOccForm(poles, w, ku, kvv, mu, mv, self.degree_u, self.degree_v,
                              self.periodic_u, self.periodic_v)

    @classmethod
    def from_occ_form(cls, poles: ArrayLike, weights: Optional[ArrayLike], knots_u: ArrayLike, knots_v: ArrayLike,
                      multiplicities_u: ArrayLike, multiplicities_v: ArrayLike, degree_u: int, degree_v: int,
                      periodic_u: bool = False, periodic_v: bool = False) -> "BSplineSurface":
        """The inverse of :meth:`occ_form` (see :meth:`cagd.BSplineCurve.from_occ_form`).
        Raises CagdError on bad input."""
        P = _checks.finite_array(poles, "poles")
        degree_u = _checks.degree(degree_u, "degree_u", 1)
        degree_v = _checks.degree(degree_v, "degree_v", 1)
        tu = kv.from_occ_knots(knots_u, multiplicities_u, degree_u, periodic_u, "knots_u", "multiplicities_u")
        tv = kv.from_occ_knots(knots_v, multiplicities_v, degree_v, periodic_v, "knots_v", "multiplicities_v")
        w = None
        if weights is not None:
            w = _checks.finite_array(weights, "weights")
            if P.ndim >= 2 and w.shape != P.shape[:2]:
                raise CagdError(f"weights: expected shape {P.shape[:2]} (one per pole), got {w.shape}")
            if w.size and np.all(w == w.flat[0]) and w.flat[0] > 0:
                w = None
        return cls(P, degree_u, degree_v, tu, tv, w, periodic_u, periodic_v)

    # --- evaluation --------------------------------------------------------------------
    def _patch_table(self) -> Optional[Tuple[PPForm, PPForm, List[List[List[np.ndarray]]], int]]:
        """Per span pair (su, sv), the power coefficients of the patch in the centred
        local variables x, y in [-1, 1]: the u-direction pp form of the rows (their
        Taylor coefficients at the u-span midpoints), then the v-direction pp form of
        each coefficient. Returns (pp_u, pp_v, tables[a][b][d] of length Sv*Su), or
        None when the table would exceed ~4e6 values, a degree exceeds PP_MAX_DEGREE
        (the power form's accuracy limit) or a coefficient leaves the float range (a net
        near 1e300: binomial multiples overflow); then the basis path is used."""
        if not hasattr(self, "_table"):
            p, q = self.degree_u, self.degree_v
            nu, nv, D = self._hom.shape
            su = int(np.count_nonzero(self._u[p:nu] < self._u[p + 1:nu + 1]))
            sv = int(np.count_nonzero(self._v[q:nv] < self._v[q + 1:nv + 1]))
            if (p + 1) * (q + 1) * su * sv * D > 4_000_000 or max(p, q) > PP_MAX_DEGREE:
                self._table = None
            else:
                pp_u = PPForm.from_bspline(self._u, p, self._hom.reshape(nu, nv * D))
                cu = pp_u.coefficients.reshape(p + 1, su, nv, D)             # (a, su, j, d)
                pp_v = PPForm.from_bspline(self._v, q, cu.transpose(2, 0, 1, 3).reshape(nv, -1))
                cv = pp_v.coefficients.reshape(q + 1, sv, p + 1, su, D)      # (b, sv, a, su, d)
                if not np.isfinite(cv).all():
                    self._table = None
                    return None
                tables = [[[_checks.frozen(np.ascontiguousarray(cv[b, :, a, :, d]).ravel()) for d in range(D)]
                           for b in range(q + 1)] for a in range(p + 1)]
                self._table = (pp_u, pp_v, tables, su)
        return self._table

    def _evaluate_points(self, u: np.ndarray, v: np.ndarray) -> Optional[np.ndarray]:
        """Points by nested Horner on the patch table (1-D gathers only), chunked."""
        table = self._patch_table()
        if table is None:
            return None
        pp_u, pp_v, tables, su_count = table
        p, q, D = self.degree_u, self.degree_v, self._hom.shape[2]
        out = np.empty((u.shape[0], D))
        for s in range(0, u.shape[0], _CHUNK):
            uc, vc = u[s:s + _CHUNK], v[s:s + _CHUNK]
            ju, jv = pp_u.span_of(uc), pp_v.span_of(vc)
            x, y = pp_u.local(uc, ju), pp_v.local(vc, jv)
            idx = jv * su_count + ju
            for d in range(D):
                acc = None
                for a in range(p, -1, -1):
                    inner = tables[a][q][d].take(idx)
                    for b in range(q - 1, -1, -1):
                        inner *= y
                        inner += tables[a][b][d].take(idx)
                    if acc is None:
                        acc = inner
                    else:
                        acc *= x
                        acc += inner
                out[s:s + _CHUNK, d] = acc
        return out

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        if max(self.degree_u, self.degree_v) > PP_MAX_DEGREE:
            out = self._bernstein_partials(u, v, du, dv)
            return rational_partials(out) if self.is_rational else out
        if du == 0 and dv == 0:
            pts = self._evaluate_points(u, v)
            if pts is not None:
                # on a clamped boundary the basis is exactly 0/1: evaluate those points
                # through the basis so that boundaries reproduce their control points
                # bit for bit (closed seams stay closed exactly)
                on_edge = self._on_clamped_edge(u, v)
                if on_edge.any():
                    pts[on_edge] = self._evaluate_by_basis(u[on_edge], v[on_edge], 0, 0)[0, 0]
                if self.is_rational:
                    pts = pts[:, :-1] / pts[:, -1:]
                return pts[None, None]
        out = self._evaluate_by_basis(u, v, du, dv)
        return rational_partials(out) if self.is_rational else out

    def _patch_nets(self, k: int, l: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(breaks_u, breaks_v, nets) of the (k, l)-th partial: the Bezier nets of the
        patches differentiated k times in u and l times in v (hodographs
        (p - i) (P_{i+1} - P_i) / h per direction; seed 000, 5.2.1 property 4), cached."""
        cache = self.__dict__.setdefault("_nets_cache", {})
        if (k, l) not in cache:
            if (0, 0) not in cache:
                cache[(0, 0)] = self.bezier_net()
            bu, bv, nets = cache[(0, 0)]
            p, q = self.degree_u, self.degree_v
            if k > p or l > q:
                nets = np.zeros(nets.shape[:2] + (1, 1, nets.shape[4]))
            else:
                hu = np.diff(bu)[:, None, None, None, None]
                hv = np.diff(bv)[None, :, None, None, None]
                for i in range(k):
                    nets = (p - i) * np.diff(nets, axis=2) / hu
                for j in range(l):
                    nets = (q - j) * np.diff(nets, axis=3) / hv
            cache[(k, l)] = (bu, bv, nets)
        return cache[(k, l)]

    def _bernstein_partials(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        """Homogeneous partials by the Bernstein sums on the Bezier patches (degrees above
        PP_MAX_DEGREE, where the power form loses digits): O(p q) per point with O(q)
        numpy calls per chunk, memory bounded by _GATHER_VALUES."""
        bu, bv, _ = self._patch_nets(0, 0)
        D = self._hom.shape[2]
        ju = np.clip(np.searchsorted(bu, u, side="right") - 1, 0, len(bu) - 2)
        jv = np.clip(np.searchsorted(bv, v, side="right") - 1, 0, len(bv) - 2)
        x = np.clip((u - bu[ju]) / (bu[ju + 1] - bu[ju]), 0.0, 1.0)
        y = np.clip((v - bv[jv]) / (bv[jv + 1] - bv[jv]), 0.0, 1.0)
        out = np.empty((du + 1, dv + 1, u.shape[0], D))
        for k in range(du + 1):
            for l in range(dv + 1):
                nets = self._patch_nets(k, l)[2]
                P1, Q1 = nets.shape[2:4]
                step = max(1, _GATHER_VALUES // (P1 * D))
                for s in range(0, u.shape[0], step):
                    sl = slice(s, s + step)
                    Bu, Bv = bernstein_values(P1 - 1, x[sl]), bernstein_values(Q1 - 1, y[sl])
                    iu, iv = ju[sl], jv[sl]
                    tmp = np.zeros((len(iu), P1, D))
                    for j in range(Q1):
                        tmp += Bv[:, j, None, None] * nets[iu, iv, :, j, :]
                    out[k, l, sl] = np.einsum("mi,mid->md", Bu, tmp)
        return out

    def _on_clamped_edge(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        p, q = self.degree_u, self.degree_v
        mask = np.zeros(u.shape, dtype=bool)
        for x, knots, deg in ((u, self._u, p), (v, self._v, q)):
            if knots[0] == knots[deg]:
                mask |= x == knots[deg]
            if knots[-1] == knots[-1 - deg]:
                mask |= x == knots[-1 - deg]
        return mask

    def _evaluate_by_basis(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        """Homogeneous partials through the local bases (Piegl & Tiller A3.6, A4.4 input)."""
        p, q = self.degree_u, self.degree_v
        nu, nv, D = self._hom.shape
        out = np.empty((du + 1, dv + 1, u.shape[0], D))
        ii, jj = np.arange(p + 1), np.arange(q + 1)
        step = max(1, min(_CHUNK, _GATHER_VALUES // ((p + 1) * (q + 1) * D)))   # bounded gather per chunk
        for s in range(0, u.shape[0], step):
            uc, vc = u[s:s + step], v[s:s + step]
            su = kv.find_span(self._u, p, uc, nu)
            sv = kv.find_span(self._v, q, vc, nv)
            Nu = basis_derivatives(self._u, p, uc, su, du)          # (du+1, m, p+1)
            Nv = basis_derivatives(self._v, q, vc, sv, dv)          # (dv+1, m, q+1)
            local = self._hom[(su[:, None] - p + ii)[:, :, None], (sv[:, None] - q + jj)[:, None, :]]
            out[:, :, s:s + step] = np.einsum("kmi,lmj,mijd->klmd", Nu, Nv, local, optimize=True)
        return out

    def _grid_last(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        return self._grid(us, vs, du, dv, last_only=True)[0, 0]

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int, last_only: bool = False) -> np.ndarray:
        """Partials on the grid us x vs through the local bases (Piegl & Tiller A2.3 per
        parameter: (p + 1) and (q + 1) values each; A3.6 summed over the grid), one
        direction at a time: C_l[n, i] = sum_j N^(l)_{sv_n - q + j, q}(v_n) P_{i, sv_n - q + j},
        then S^(k,l)[m, n] = sum_i N^(k)_{su_m - p + i, p}(u_m) C_l[n, su_m - p + i].
        Each sum runs over blocks of sorted parameters (:func:`_band_blocks`), a block as
        one matrix product of its small dense local basis (parameters x the few pole rows
        they touch) with those rows (BLAS), or as p + 1 gathered multiply-adds where the
        parameters are too sparse for that. Rows of us are summed in v chunk by chunk (at
        most _GRID_VALUES v-sums); rational points are divided block by block while the
        block is in cache. O(Mu Mv D (p + q)) work, memory O((Mu + Mv)(p + q + 2)) for
        the bases plus the output and bounded blocks, never a (parameters x poles) basis
        matrix (a 2000 x 2000 grid of a 2000 x 2001-pole net took 30 s through the dense
        ones). ``last_only``: the (du, dv) partial alone, shape (1, 1, ...) (a rational
        surface still computes the lower ones per block: the quotient rule needs them)."""
        p, q = self.degree_u, self.degree_v
        nu, nv, D = self._hom.shape
        Mu, Mv = len(us), len(vs)
        rational = self.is_rational
        K, L = (1, 1) if last_only and not rational else (du + 1, dv + 1)      # partials computed
        out = np.empty(((1, 1) if last_only else (du + 1, dv + 1)) + (Mu, Mv, D - 1 if rational else D))
        if Mu == 0 or Mv == 0:
            return out
        ou, u_sorted, su, Nu = _sorted_basis(self._u, p, us, nu, du)
        ov, v_sorted, sv, Nv = _sorted_basis(self._v, q, vs, nv, dv)
        Nu, Nv = Nu[-K:], Nv[-L:]
        vrows, lv = _local_rows(sv, q)
        inv_v = None if v_sorted else np.argsort(ov)
        width = Mv * D
        direct = u_sorted and not rational                            # products written into out itself
        planar = rational and (du > 0 or dv > 0)   # the quotient rule on coordinate planes: long inner loops
        cap = max(1, min(_GRID_BLOCK // width, _GRID_VALUES // _rows_cap(p), Mu))
        buf = np.empty((K, L, 0 if direct else cap, width))                 # products copied on
        tmp: List[np.ndarray] = []                                     # the banded passes' scratch, made once
        max_rows = max(p + 1, _GRID_VALUES // (width * L))    # v-sums of one chunk of us
        # new pole rows a parameter adds to its chunk (sorted spans): min(p + 1, span step)
        added = np.concatenate([[0], np.cumsum(np.minimum(p + 1, np.diff(su)))])
        a0 = 0
        while a0 < Mu:
            b0 = min(max(int(np.searchsorted(added, added[a0] + max_rows - (p + 1), side="right")), a0 + 1), Mu)
            rows, lu = _local_rows(su[a0:b0], p)
            C = _v_sums(Nv, lv, q, _subnet(self._hom, rows, vrows))  # (L, r, Mv D), vs sorted
            if inv_v is not None or planar:
                C = C.reshape(L, len(rows), Mv, D)
                C = C if inv_v is None else C.take(inv_v, axis=2)
                C = (np.ascontiguousarray(C.transpose(0, 1, 3, 2)) if planar else C).reshape(L, len(rows), width)
            for a, b, gemm in _band_blocks(lu, p, width, cap):
                m = slice(a0 + a, a0 + b)
                for k in range(K):
                    for l in range(L):
                        dest = out[k, l, m].reshape(b - a, width) if direct else buf[k, l, :b - a]
                        _band_block(Nu[k, m], lu[a:b], p, C[l], dest, gemm, tmp)
                if direct:
                    continue
                block = buf[:, :, :b - a].reshape((K, L, b - a) + ((D, Mv) if planar else (Mv, D)))
                where = m if u_sorted else ou[m]
                if not rational:
                    out[:, :, where] = block
                elif du == 0 and dv == 0:
                    # one strided division per coordinate (a broadcast over the last axis of
                    # length dim runs numpy's inner loop per point: 3-5x slower)
                    dest = out[0, 0, m] if u_sorted else np.empty((b - a, Mv, D - 1))
                    for d in range(D - 1):
                        np.divide(block[0, 0, ..., d], block[0, 0, ..., -1], out=dest[..., d])
                    if not u_sorted:
                        out[0, 0, where] = dest
                else:
                    S = rational_partials(block.transpose(0, 1, 2, 4, 3))[-out.shape[0]:, -out.shape[1]:]
                    for d in range(D - 1):
                        out[..., d][:, :, where] = S[..., d]
            a0 = b0
        return out

    # --- one direction at a time: reuse the curve algorithms ---------------------------------
    def _row_curve(self, direction: str) -> BSplineCurve:
        """The net as one curve in ``direction`` whose points are whole (flattened) rows."""
        hom = self._distinct_hom()
        if direction == "u":
            rows = hom.reshape(hom.shape[0], -1)
            return BSplineCurve(rows, self.degree_u, self.knots_u, periodic=self.periodic_u)
        if direction == "v":
            rows = hom.transpose(1, 0, 2).reshape(hom.shape[1], -1)
            return BSplineCurve(rows, self.degree_v, self.knots_v, periodic=self.periodic_v)
        raise CagdError(f"direction: must be 'u' or 'v', got {direction!r}")

    def _distinct_hom(self) -> np.ndarray:
        P, W = self.control_points, self.weights
        return P if W is None else np.concatenate([P * W[..., None], W[..., None]], axis=2)

    def _from_row_curve(self, direction: str, c: BSplineCurve) -> "BSplineSurface":
        D = self._hom.shape[2]
        if direction == "u":
            hom = c.control_points.reshape(len(c.control_points), -1, D)
            du, dv, ku, kvv, pu, pv = c.degree, self.degree_v, c.knots, self.knots_v, c.periodic, self.periodic_v
        else:
            hom = c.control_points.reshape(len(c.control_points), -1, D).transpose(1, 0, 2)
            du, dv, ku, kvv, pu, pv = self.degree_u, c.degree, self.knots_u, c.knots, self.periodic_u, c.periodic
        if self.is_rational:
            w = hom[..., -1]
            return BSplineSurface(hom[..., :-1] / w[..., None], du, dv, ku, kvv, w, pu, pv)
        return BSplineSurface(hom, du, dv, ku, kvv, None, pu, pv)

    def insert_knot(self, direction: str, t: float, times: int = 1) -> "BSplineSurface":
        """Insert a knot in one direction (Boehm, applied to every row; Piegl & Tiller A5.3)."""
        return self._from_row_curve(direction, self._row_curve(direction).insert_knot(t, times))

    def refine(self, direction: str, new_knots: ArrayLike) -> "BSplineSurface":
        return self._from_row_curve(direction, self._row_curve(direction).refine(new_knots))

    def remove_knots(self, tol: float, direction: str) -> "KnotRemoval":
        """Remove as many interior knots of ``direction`` ('u' or 'v') as keep the surface
        within ``tol`` of itself at equal parameters: Tiller's knot removal applied to all
        rows at once, each removal bounded by the largest error over the rows (Piegl &
        Tiller 5.4 and 9.4.4; :mod:`cagd.knots.removal`). A periodic ``direction`` comes
        back clamped.

        Returns a :class:`cagd.knots.removal.KnotRemoval` (``result`` the surface).

        Raises:
            CagdError: ``tol`` not a finite number >= 0, ``direction`` not 'u' or 'v'."""
        from ..knots import removal as rm
        tol = _checks.nonnegative(tol, "tol")
        c = self._row_curve(direction).clamped()
        D = self._hom.shape[2]
        hom = c._hom.reshape(len(c._hom), -1, D)
        htol = rm.homogeneous_tol(hom, tol) if self.is_rational else tol
        u, P, removed, bound = rm.remove_knots(c._u, hom, c.degree, htol)
        out = self._from_row_curve(direction, BSplineCurve(P.reshape(len(P), -1), c.degree, u))
        dev = self._deviation_from(out, direction, c)
        bound = tol * bound / htol if htol > 0 else 0.0
        msg = f"{removed} knot(s) removed in {direction}"
        if (self.periodic_u if direction == "u" else self.periodic_v):
            msg += f"; the periodic {direction} direction came back clamped"
        return rm.KnotRemoval(out, removed, min(bound, tol), dev, True, msg)

    def _deviation_from(self, out: "BSplineSurface", direction: str, c: BSplineCurve) -> float:
        """Largest |self - out| on a grid of DEVIATION_SAMPLES parameters per knot span of
        the row curve c (``direction``) and of the other direction."""
        from ..knots import removal as rm
        t = rm._span_samples(c._u, c.degree)
        other = rm._span_samples(self._v if direction == "u" else self._u,
                                 self.degree_v if direction == "u" else self.degree_u)
        us, vs = (t, other) if direction == "u" else (other, t)
        diff = self.grid(us, vs) - out.grid(us, vs)
        return float(np.sqrt((diff * diff).sum(-1)).max())

    def reduce_degree(self, tol: float, direction: str) -> "DegreeReduction":
        """The surface one degree lower in ``direction`` ('u' or 'v'), every row reduced
        together (:meth:`BSplineCurve.reduce_degree`; Piegl & Tiller 5.6, A5.11): the bound
        is the largest over the rows. A periodic ``direction`` comes back clamped.

        Returns a :class:`cagd.knots.reduction.DegreeReduction` (``result`` the surface).

        Raises:
            CagdError: ``tol`` not a finite number >= 0, ``direction`` not 'u' or 'v', the
                degree in ``direction`` is 1, reduced weights that would not be positive."""
        from ..knots import reduction as rd
        from ..knots import removal as rm
        tol = _checks.nonnegative(tol, "tol")
        c = self._row_curve(direction).clamped()
        if c.degree < 2:
            raise CagdError(f"direction: the degree in {direction} is 1; it cannot be reduced further")
        D = self._hom.shape[2]
        breaks, nets = c.bezier_net()
        unit = rm.homogeneous_tol(self._hom, 1.0) if self.is_rational else 1.0
        u, P, q, bound = rd.reduce_degree(breaks, nets.reshape(nets.shape[:2] + (-1, D)), tol * unit)
        rd.check_weights(P, self.is_rational, c.degree)
        out = self._from_row_curve(direction, BSplineCurve(P.reshape(len(P), -1), q, u))
        bound /= unit
        dev = self._deviation_from(out, direction, c)
        ok = bool(bound <= tol)
        msg = (f"degree {c.degree} -> {q} in {direction}, within {bound:.3g}" if ok else
               f"degree {c.degree} -> {q} in {direction}: the bound {bound:.3g} exceeds tol {tol:g} "
               f"(measured deviation {dev:.3g})")
        return rd.DegreeReduction(out, float(bound), dev, ok, msg)

    def elevate(self, direction: str, times: int = 1) -> "BSplineSurface":
        """Degree elevation in one direction (a periodic direction comes back clamped)."""
        return self._from_row_curve(direction, self._row_curve(direction).elevate(times))

    def segment(self, direction: str, start: float, end: float) -> "BSplineSurface":
        return self._from_row_curve(direction, self._row_curve(direction).segment(start, end))

    def split(self, direction: str, t: float) -> Tuple["BSplineSurface", "BSplineSurface"]:
        a, b = self._row_curve(direction).split(t)
        return self._from_row_curve(direction, a), self._from_row_curve(direction, b)

    def clamped(self) -> "BSplineSurface":
        """Clamped, non-periodic in both directions (same surface)."""
        s = self
        for d in "uv":
            s = s._from_row_curve(d, s._row_curve(d).clamped())
        return s

    def reversed(self, direction: str) -> "BSplineSurface":
        """The surface with ``direction`` ('u' or 'v') traversed backwards, as
        :meth:`cagd.BSplineCurve.reversed` on every row (the normal flips)."""
        if direction not in ("u", "v"):
            raise CagdError(f"direction: must be 'u' or 'v', got {direction!r}")
        axis = 0 if direction == "u" else 1
        p, periodic = (self.degree_u, self.periodic_u) if axis == 0 else (self.degree_v, self.periodic_v)
        P = np.flip(self.control_points, axis)
        W = None if self.weights is None else np.flip(self.weights, axis)
        if periodic:
            P = np.roll(P, p, axis=axis)
            W = None if W is None else np.roll(W, p, axis=axis)
        knots = kv.reflected(self.knots_u if axis == 0 else self.knots_v, *self.domain[axis])
        if not periodic:            # spans below a rounding step at an end: cagd.knots.collapsed_ends
            lead, trail = kv.collapsed_ends(knots, p)
            if lead or trail:
                keep = slice(lead, P.shape[axis] - trail)
                knots = knots[lead:len(knots) - trail]
                P = P[keep] if axis == 0 else P[:, keep]
                W = None if W is None else (W[keep] if axis == 0 else W[:, keep])
        ku, kvv = (knots, self.knots_v) if axis == 0 else (self.knots_u, knots)
        return BSplineSurface(P, self.degree_u, self.degree_v, ku, kvv, W, self.periodic_u, self.periodic_v)

    def reparametrized(self, domain_u: Optional[Tuple[float, float]] = None,
                       domain_v: Optional[Tuple[float, float]] = None) -> "BSplineSurface":
        s = self
        if domain_u is not None:
            s = s._from_row_curve("u", s._row_curve("u").reparametrized(*domain_u))
        if domain_v is not None:
            s = s._from_row_curve("v", s._row_curve("v").reparametrized(*domain_v))
        return s

    def swapped(self) -> "BSplineSurface":
        """The same surface with u and v exchanged (the normal flips)."""
        W = None if self.weights is None else self.weights.T
        return BSplineSurface(self.control_points.transpose(1, 0, 2), self.degree_v, self.degree_u,
                              self.knots_v, self.knots_u, W, self.periodic_v, self.periodic_u)

    def bezier_net(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(breaks_u, breaks_v, nets): the homogeneous Bezier control nets (mu, mv, p + 1,
        q + 1, D) ((w P, w) when rational) of the patches: the span-local Bezier
        extraction of :meth:`cagd.BSplineCurve.bezier_net` (what knot insertion to
        multiplicity p gives) for all rows at once in u, then for all strips at once in v
        (Piegl & Tiller A5.7), as arrays: no surface objects."""
        bu, strips = self._row_curve("u").bezier_net()           # (mu, p + 1, nv * D)
        mu, p1 = strips.shape[:2]
        D = self._hom.shape[2]
        nv = strips.shape[2] // D
        rows = strips.reshape(mu * p1, nv, D).transpose(1, 0, 2).reshape(nv, -1)
        bv, cols = BSplineCurve(rows, self.degree_v, self.knots_v, periodic=self.periodic_v).bezier_net()
        mv, q1 = cols.shape[:2]
        nets = cols.reshape(mv, q1, mu, p1, D).transpose(2, 0, 3, 1, 4)
        return bu, bv, nets

    def bezier_patches(self) -> Tuple[np.ndarray, np.ndarray, List[List["BSplineSurface"]]]:
        """Decomposition into Bezier patches: (breaks_u, breaks_v, patches) with
        patches[i][j] a clamped single-span BSplineSurface (Piegl & Tiller A5.7)."""
        bu, rows = self._row_curve("u").bezier_segments()
        patches = []
        for r in rows:
            strip = self._from_row_curve("u", r)
            bv, cols = strip._row_curve("v").bezier_segments()
            patches.append([strip._from_row_curve("v", c) for c in cols])
        return bu, bv, patches

    def isocurve(self, direction: str, value: float) -> BSplineCurve:
        """u -> S(u, value) ("u") or v -> S(value, v) ("v") as an exact BSplineCurve."""
        other = "v" if direction == "u" else "u"
        if direction not in ("u", "v"):
            raise CagdError(f"direction: must be 'u' or 'v', got {direction!r}")
        value = _checks.scalar(value, "value")
        (u0, u1), (v0, v1) = self.domain
        lo, hi = (v0, v1) if direction == "u" else (u0, u1)
        if not lo - 1e-12 * (hi - lo) <= value <= hi + 1e-12 * (hi - lo):
            raise CagdError(f"value: {value} is outside the {other} domain [{lo}, {hi}]")
        rows = self._row_curve(other)                       # curve in the other direction
        D = self._hom.shape[2]
        hom = rows(min(max(value, lo), hi)).reshape(-1, D)  # the net collapsed at value
        deg = self.degree_u if direction == "u" else self.degree_v
        knots = self.knots_u if direction == "u" else self.knots_v
        periodic = self.periodic_u if direction == "u" else self.periodic_v
        if self.is_rational:
            return BSplineCurve(hom[:, :-1] / hom[:, -1:], deg, knots, hom[:, -1], periodic)
        return BSplineCurve(hom, deg, knots, None, periodic)


def _sorted_basis(knots: np.ndarray, degree: int, t: np.ndarray, count: int,
                  order: int) -> Tuple[np.ndarray, bool, np.ndarray, np.ndarray]:
    """(sorting permutation (identity when t is sorted already), whether it is, spans,
    basis derivatives (order + 1, len(t), degree + 1)) of the parameters t in sorted
    order (equal parameters give equal rows: any order among them will do)."""
    in_order = bool(np.all(t[1:] >= t[:-1]))
    perm = np.arange(len(t)) if in_order else np.argsort(t)
    ts = t if in_order else t[perm]
    spans = kv.find_span(knots, degree, ts, count)
    return perm, in_order, spans, basis_derivatives(knots, degree, ts, spans, order)


def _local_rows(spans: np.ndarray, degree: int) -> Tuple[np.ndarray, np.ndarray]:
    """(rows, local) of nondecreasing spans: the pole rows span - degree .. span they use,
    sorted and distinct (or the whole range between the first and the last when that is
    at most twice as many: then the net's rows are a view), and the index in rows of each
    span - degree (nondecreasing); the rows of spans[a:b] are
    rows[local[a]:local[b - 1] + degree + 1]."""
    distinct = spans[np.concatenate([[True], spans[1:] != spans[:-1]])]
    rows = np.unique(distinct[:, None] - degree + np.arange(degree + 1))
    if rows[-1] - rows[0] + 1 <= 2 * len(rows):
        return np.arange(rows[0], rows[-1] + 1), spans - degree - rows[0]
    return rows, np.searchsorted(rows, spans - degree)


def _subnet(hom: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """hom[rows][:, cols] for sorted distinct indices, a view where they are ranges."""
    def index(ix: np.ndarray):
        return slice(int(ix[0]), int(ix[-1]) + 1) if ix[-1] - ix[0] + 1 == len(ix) else ix
    r, c = index(rows), index(cols)
    if isinstance(r, slice):
        return hom[r][:, c]
    return hom[:, c][r] if isinstance(c, slice) else hom[np.ix_(r, c)]


def _local_basis(N: np.ndarray, local: np.ndarray, degree: int) -> Tuple[np.ndarray, int]:
    """(B, lo): the dense local basis of a block of parameters with nondecreasing local
    first rows, B[m, local[m] - lo + i] = N[m, i], shape (len(local), rows touched)."""
    lo = int(local[0])
    B = np.zeros((len(local), int(local[-1]) - lo + degree + 1))
    B[np.arange(len(local))[:, None], (local - lo)[:, None] + np.arange(degree + 1)] = N
    return B, lo


def _rows_cap(degree: int) -> int:
    return max(_GRID_ROWS, 2 * (degree + 1))


def _band_blocks(local: np.ndarray, degree: int, width: int, cap: int):
    """Blocks (a, b, gemm) of sorted parameters with nondecreasing local first rows, at
    most ``cap`` parameters each: a matrix-product block (gemm) touches at most
    _rows_cap(degree) rows; where such a block would hold fewer than _GRID_GEMM_MIN values
    of ``width`` per parameter (sparse parameters: a BLAS call per few values) the block
    takes ``cap`` parameters and the banded passes."""
    M, rows_cap = len(local), _rows_cap(degree)
    a = 0
    while a < M:
        b = min(int(np.searchsorted(local, local[a] + rows_cap - degree - 1, side="right")), a + cap, M)
        gemm = b == M or (b - a) * width >= _GRID_GEMM_MIN
        if not gemm:
            b = min(a + cap, M)
        yield a, b, gemm
        a = b


def _band_block(N: np.ndarray, local: np.ndarray, degree: int, X: np.ndarray, dest: np.ndarray, gemm: bool,
                scratch: List[np.ndarray]) -> None:
    """dest[m] = sum_i N[m, i] X[local[m] + i] for one block (nondecreasing local): one
    matrix product of the dense local basis (len(local) x the rows touched) with those
    rows of X, or (gemm False) degree + 1 gathers and multiply-adds of whole rows;
    ``scratch`` holds the latter's buffer (made on first use, at least as big as dest)."""
    if gemm:
        B, lo = _local_basis(N, local, degree)
        np.matmul(B, X[lo:lo + B.shape[1]], out=dest)
        return
    if not scratch or scratch[0].size < dest.size:
        scratch[:] = [np.empty(dest.size)]
    tmp = scratch[0][:dest.size].reshape(dest.shape)
    np.take(X, local, axis=0, out=dest, mode="clip")          # indices are in range
    dest *= N[:, 0, None]
    for i in range(1, degree + 1):
        np.take(X, local + i, axis=0, out=tmp, mode="clip")
        tmp *= N[:, i, None]
        dest += tmp


def _v_sums(N: np.ndarray, local: np.ndarray, degree: int, net: np.ndarray) -> np.ndarray:
    """C[k, i, (m, d)] = sum_j N[k, m, j] net[i, local[m] + j, d] for sorted v parameters
    (nondecreasing local), shape (len(N), r, len(local) D), the layout the u direction
    multiplies: per block of :func:`_band_blocks` one product of the pole rows
    (r, rows touched x D) with the Kronecker product of the dense local basis and the
    D x D identity (D-fold flops, no transposed copies), or degree + 1 gathered
    multiply-adds where the parameters are sparse."""
    K, M = N.shape[:2]
    r, _, D = net.shape
    C = np.empty((K, r, M * D))
    cap = max(1, min(_GRID_BLOCK // (r * D), _GRID_VALUES // (_rows_cap(degree) * D * D), M))
    eye = np.eye(D)
    for a, b, gemm in _band_blocks(local, degree, r * D, cap):
        cols = slice(a * D, b * D)
        for k in range(K):
            if gemm:
                B, lo = _local_basis(N[k, a:b], local[a:b], degree)
                kron = np.einsum("nj,de->jdne", B, eye).reshape(B.shape[1] * D, (b - a) * D)
                np.matmul(net[:, lo:lo + B.shape[1]].reshape(r, -1), kron, out=C[k, :, cols])
                continue
            dest = C[k, :, cols]
            for j in range(degree + 1):
                g = net.take(local[a:b] + j, axis=1).reshape(r, -1)
                g *= np.repeat(N[k, a:b, j], D)                  # contiguous: no broadcast over D
                if j == 0:
                    dest[...] = g
                else:
                    dest += g
    return C


def _weights(weights: ArrayLike, shape: Tuple[int, ...]) -> np.ndarray:
    """Positive finite weights, one per control point of the net."""
    W = _checks.finite_array(weights, "weights")
    if W.shape != tuple(shape):
        raise CagdError(f"weights: expected shape {tuple(shape)} (one per control point), got {W.shape}")
    if np.any(W <= 0):
        i = tuple(int(k) for k in np.argwhere(W <= 0)[0])
        raise CagdError(f"weights: must be positive (weights[{i[0]}, {i[1]}]={W[i]!r})")
    return W


def _direction(knots: Optional[ArrayLike], count: int, degree: int, periodic: bool,
               name: str) -> Tuple[np.ndarray, np.ndarray]:
    """(given knots, full unwrapped knots) for one direction."""
    if periodic:
        t = np.linspace(0.0, 1.0, count + 1) if knots is None else kv.validate_period(knots, count, degree, name)
        return t, kv.periodic_extend(t, degree)
    t = kv.clamped_uniform(count, degree) if knots is None else kv.validate(knots, degree, count, name)
    return t, t
