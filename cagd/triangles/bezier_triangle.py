"""Total-degree Bezier triangles, polynomial and rational (seed 003, 3.1: blossoms,
barycentric coordinates, Bernstein form, triangular de Casteljau; Farin, Curves and
Surfaces for CAGD, ch. 17).

T(u, v) = sum_{i+j+k=n} n!/(i! j! k!) u^i v^j w^k P_ijk, w = 1 - u - v, on the triangle
u >= 0, v >= 0, u + v <= 1; with weights the projection of the same sum over the
homogeneous points (w_ijk P_ijk, w_ijk). The blossom f(x_1, ..., x_n) takes barycentric
triples x_r = (x_r1, x_r2, x_r3) and P_ijk = f(e1^i, e2^j, e3^k).

A BezierTriangle is a :class:`cagd.Surface` with domain ((0, 1), (0, 1)) restricted by
u + v <= 1 (checked on every evaluation); its (u, v) partials are the directional
derivatives along the barycentric directions (1, 0, -1) and (0, 1, -1).
"""
from __future__ import annotations

from math import comb, factorial
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..curves.base import rational_derivatives
from ..errors import CagdError
from ..surfaces.base import Surface, rational_partials
from . import basis as tb
from ._input import TriangleData, parse_points, parse_weights

if TYPE_CHECKING:
    from ..curves.bezier import BezierCurve
    from ..curves.bspline import BSplineCurve
    from ..surfaces.bezier import BezierSurface
    from ..surfaces.bspline import BSplineSurface

_CHUNK = 1 << 13      # points per pass at most
_CHUNK_VALUES = 1 << 22   # values of a pass's (chunk, n+1, n+1, D) net or (chunk, N) basis (32 MiB)


def _chunks(count: int, per_point: int = 1) -> List[slice]:
    """Slices of at most _CHUNK points and _CHUNK_VALUES / per_point points (a degree-128
    de Casteljau pass of 8,192 points held 3.3 GB)."""
    step = max(1, min(_CHUNK, _CHUNK_VALUES // max(per_point, 1)))
    return [slice(s, s + step) for s in range(0, max(count, 1), step)]


class BezierTriangle(Surface):
    """A degree-n Bezier triangle (seed 003, 3.1 Bernstein form).

    Args:
        control_points: a mapping {(i, j, k): point} (or a list of ((i, j, k), point)
            pairs) with all (n+1)(n+2)/2 triples i + j + k = n, n >= 1; or an (N, dim)
            array in :meth:`index_triples` order (i descending, then j descending).
        weights: positive weights given the same way (mapping or (N,) array), or None.

    Attributes:
        control_points: (N, dim) in canonical order; weights: (N,) or None; degree; dim.

    Raises:
        CagdError: missing, extra or duplicated triples, a count that is not triangular,
            inconsistent dimensions, NaN/inf, non-positive weights (the message names the
            argument and the triple).
    """

    rectangular = False
    _modified_copy = "use with_control_points(P), moved_pole((i, j, k), point) or with_weights(w)"

    def __init__(self, control_points: TriangleData, weights: Optional[TriangleData] = None):
        P, n = parse_points(control_points, "control_points")
        self._fill(P, parse_weights(weights, n, "weights"), n)

    def _fill(self, P: np.ndarray, W: Optional[np.ndarray], n: int) -> None:
        """Bind validated canonical points and weights (frozen) and the dense net."""
        self.degree, self.dim = n, P.shape[1]
        self.control_points = _checks.frozen(P)
        self.weights = None if W is None else _checks.frozen(W)
        self._hom = self.control_points if W is None else \
            _checks.frozen(_checks.finite_homogeneous(np.concatenate([P * W[:, None], W[:, None]], axis=1)))
        self._net = _checks.frozen(tb.to_dense(self._hom, n))

    # --- modified copies (the object itself never changes) --------------------------------
    def with_control_points(self, control_points: TriangleData) -> "BezierTriangle":
        """The same degree and weights on new control points, given as the constructor
        takes them (a mapping {(i, j, k): point} or an (N, dim) array), of the same
        degree and dimension.

        Raises:
            CagdError: as the constructor; another degree or dimension."""
        P, n = parse_points(control_points, "control_points")
        _checks.same_shape(P, self.control_points.shape, "control_points")
        return BezierTriangle._unchecked(P, self.weights, n)

    def moved_pole(self, index: Union[int, Tuple[int, int, int]], point: ArrayLike) -> "BezierTriangle":
        """The triangle with control point ``index`` moved to ``point``: ``index`` is the
        triple (i, j, k), i + j + k = degree, or the flat position in
        :meth:`index_triples` order (an int, negative from the end). The cheap edit for
        dragging a pole (O(N) copies).

        Raises:
            CagdError: a triple that does not sum to the degree, a position out of
                range, a bad point."""
        P = self.control_points.copy()
        P[self._position(index)] = _checks.point(point, self.dim)
        return BezierTriangle._unchecked(P, self.weights, self.degree)

    def with_weights(self, weights: Optional[TriangleData]) -> "BezierTriangle":
        """The same control points with new weights (mapping or (N,) array; None: polynomial).

        Raises:
            CagdError: as the constructor's weights."""
        return BezierTriangle._unchecked(self.control_points, parse_weights(weights, self.degree, "weights"),
                                         self.degree)

    def _position(self, index: Any) -> int:
        """The flat position of a triple (i, j, k) or of a flat index."""
        if not isinstance(index, (tuple, list)) and np.ndim(index) == 0:
            return _checks.pole_index(index, self.control_points.shape[:1])[0]
        if len(index) != 3:
            raise CagdError(f"index: expected a triple (i, j, k) or a flat index, got {index!r}")
        return self._triple_position(tuple(_checks.integer(x, "index", 0) for x in index), "index")

    def _triple_position(self, t: Tuple[int, ...], name: str) -> int:
        if sum(t) != self.degree:
            raise CagdError(f"{name}: {t} does not sum to the degree {self.degree}")
        return tb.triple_position(self.degree, t[0], t[1])

    index_triples = staticmethod(tb.index_triples)

    # --- properties -------------------------------------------------------------------
    @property
    def is_rational(self) -> bool:
        return self.weights is not None

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        return (0.0, 1.0), (0.0, 1.0)

    @property
    def homogeneous_control_points(self) -> np.ndarray:
        """(N, dim+1) rows (w P, w) for a rational triangle, else (N, dim) points (read-only)."""
        return self._hom

    def control_point(self, i: int, j: int, k: int) -> np.ndarray:
        """P_ijk (raises CagdError unless i + j + k = degree, all >= 0)."""
        t = tuple(_checks.integer(x, name, 0) for x, name in zip((i, j, k), "ijk"))
        return self.control_points[self._triple_position(t, "i, j, k")].copy()

    def as_dict(self) -> Dict[Tuple[int, int, int], np.ndarray]:
        """{(i, j, k): P_ijk}."""
        return {t: p.copy() for t, p in zip(tb.index_triples(self.degree), self.control_points)}

    def __repr__(self) -> str:
        kind = "rational Bezier" if self.is_rational else "Bezier"
        return f"<{kind} triangle degree {self.degree}, {self.dim}-D>"

    @classmethod
    def _from_homogeneous(cls, hom: np.ndarray, rational: bool) -> "BezierTriangle":
        return cls(hom[:, :-1] / hom[:, -1:], hom[:, -1]) if rational else cls(hom)

    def _project(self, hom: np.ndarray) -> np.ndarray:
        return hom[..., :-1] / hom[..., -1:] if self.is_rational else hom

    # --- Surface interface --------------------------------------------------------------
    def _flat(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray, Tuple[int, ...]]:
        uf, vf, shape = super()._flat(u, v)
        out = uf + vf > 1.0 + tb.TOL
        if np.any(out):
            r = int(np.argmax(out))
            raise CagdError(f"u, v: ({float(uf[r])!r}, {float(vf[r])!r}) is outside the triangle u >= 0, v >= 0, "
                            f"u + v <= 1 (u + v = {float(uf[r] + vf[r])!r})")
        return uf, vf, shape

    def _points(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, Tuple[int, ...]]:
        """Validated barycentric points (N, 3) and the broadcast shape."""
        uf, vf, shape = self._flat(u, v)
        return np.stack([uf, vf, 1.0 - uf - vf], axis=-1), shape

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        """All partials d^(a+b)/du^a dv^b, a <= du, b <= dv: the difference nets
        n!/(n-a-b)! Delta_u^a Delta_v^b P (Delta_u P_ijk = P_{i+1,j,k} - P_{i,j,k+1},
        Delta_v P_ijk = P_{i,j+1,k} - P_{i,j,k+1}; Farin ch. 17) in the Bernstein basis of
        degree n-a-b."""
        n = self.degree
        D = self._net.shape[-1]
        out = np.zeros((du + 1, dv + 1, u.shape[0], D))
        row = self._net
        for a in range(min(du, n) + 1):
            net = row
            for b in range(min(dv, n - a) + 1):
                m = n - a - b
                coef = factorial(n) / factorial(m)
                flat = tb.to_flat(net)
                for c in _chunks(u.shape[0], len(flat)):      # the (chunk, N) basis bounded
                    out[a, b, c] = coef * (tb._bernstein(m, u[c], v[c]) @ flat)
                net = net[:-1, 1:] - net[:-1, :-1]
            row = row[1:, :-1] - row[:-1, :-1]
        if not self.is_rational:
            return out
        if du == 0 and dv == 0:
            return out[..., :-1] / out[..., -1:]
        return rational_partials(out)

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        """The grid us x vs; every grid point must lie in the triangle."""
        if us.size and vs.size and us.max() + vs.max() > 1.0 + tb.TOL:
            raise CagdError(f"us, vs: the grid point ({float(us.max())!r}, {float(vs.max())!r}) is outside the "
                            "triangle u + v <= 1")
        U, V = np.meshgrid(us, vs, indexing="ij")
        out = self._evaluate(U.ravel(), V.ravel(), du, dv)
        return out.reshape(out.shape[:2] + U.shape + (self.dim,))

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "BezierTriangle":
        return BezierTriangle(self.control_points @ A.T + b, self.weights)

    def isocurve(self, direction: str, value: float) -> BSplineCurve:
        """The exact curve u -> T(u, value), u in [0, 1 - value] (direction "u") or
        v -> T(value, v), v in [0, 1 - value] ("v"), a clamped single-span BSplineCurve of
        degree n whose control points are the blossom values f(A^(n-r), B^r) at the
        segment ends A, B (seed 003, 3.1).

        Raises:
            CagdError: direction not "u"/"v", value outside [0, 1) (the line v = 1 meets
                the triangle in one point)."""
        from ..curves.bspline import BSplineCurve
        if direction not in ("u", "v"):
            raise CagdError(f"direction: must be 'u' or 'v', got {direction!r}")
        c = _checks.scalar(value, "value")
        if not -tb.TOL <= c < 1.0:
            raise CagdError(f"value: {c} must lie in [0, 1); the isocurve at 1 is a single point")
        c = max(c, 0.0)
        if direction == "u":
            A, B = np.array([0.0, c, 1.0 - c]), np.array([1.0 - c, c, 0.0])
        else:
            A, B = np.array([c, 0.0, 1.0 - c]), np.array([c, 1.0 - c, 0.0])
        n = self.degree
        args = [np.array([A] * (n - r) + [B] * r) for r in range(n + 1)]
        hom = tb.multilinear(self._net, np.transpose(np.array(args), (1, 0, 2)))
        knots = np.concatenate([np.zeros(n + 1), np.full(n + 1, 1.0 - c)])
        if self.is_rational:
            return BSplineCurve(hom[:, :-1] / hom[:, -1:], n, knots, hom[:, -1])
        return BSplineCurve(hom, n, knots)

    def boundaries(self) -> List[BezierCurve]:
        """The three edges as BezierCurves, counter-clockwise: vertex 1 -> 2 (k = 0,
        points P_{n-r,r,0}), 2 -> 3 (i = 0, P_{0,n-r,r}), 3 -> 1 (j = 0, P_{r,0,n-r})."""
        from ..curves.bezier import BezierCurve
        n, r = self.degree, np.arange(self.degree + 1)
        edges = []
        for I, J in ((n - r, r), (0 * r, n - r), (r, 0 * r)):
            pos = [tb.triple_position(n, int(i), int(j)) for i, j in zip(I, J)]
            w = None if self.weights is None else self.weights[pos]
            edges.append(BezierCurve(self.control_points[pos], w))
        return edges

    # --- the seed's algorithms ------------------------------------------------------------
    def bernstein_evaluate(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Direct Bernstein sum over all triples (seed 003, 3.1 Bernstein form),
        broadcasting u and v: shape broadcast + (dim,).

        Raises:
            CagdError: NaN/inf, (u, v) outside the triangle."""
        x, shape = self._points(u, v)
        hom = np.concatenate([tb._bernstein(self.degree, x[c, 0], x[c, 1]) @ self._hom
                              for c in _chunks(len(x), len(self._hom))])
        return self._project(hom).reshape(shape + (self.dim,))

    def de_casteljau(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Triangular de Casteljau (seed 003, 3.1): n levels of
        b^r_ijk = u b^{r-1}_{i+1,j,k} + v b^{r-1}_{i,j+1,k} + w b^{r-1}_{i,j,k+1},
        vectorized over points; shape broadcast + (dim,).

        Raises:
            CagdError: NaN/inf, (u, v) outside the triangle."""
        x, shape = self._points(u, v)
        hom = np.concatenate([tb.multilinear(self._net, [x[c]] * self.degree)
                              for c in _chunks(len(x), self._net[..., 0].size * self._net.shape[-1])])
        return self._project(hom).reshape(shape + (self.dim,))

    def blossom(self, *args: ArrayLike, homogeneous: bool = False) -> np.ndarray:
        """The blossom (polar form) f(x_1, ..., x_n) at n barycentric triples (seed 003,
        3.1): symmetric, multi-affine, f(x, ..., x) = T(x), P_ijk = f(e1^i, e2^j, e3^k).
        Each argument is a triple or an array (..., 3) summing to 1 (any affine point of
        the plane, also outside the triangle); they broadcast. For a rational triangle the
        homogeneous blossom (multi-affine) is returned with ``homogeneous=True``, its
        projection otherwise.

        Raises:
            CagdError: wrong number of arguments, not triples, sums other than 1, NaN/inf."""
        n = self.degree
        if len(args) != n:
            raise CagdError(f"args: the blossom of a degree-{n} triangle takes {n} barycentric triples, "
                            f"got {len(args)}")
        xs = [tb.barycentric(a, f"x{r + 1}") for r, a in enumerate(args)]
        try:
            np.broadcast_shapes(*(x.shape for x in xs))
        except ValueError:
            raise CagdError(f"args: shapes {[x.shape for x in xs]} do not broadcast") from None
        hom = tb.multilinear(self._net, xs)
        return hom if homogeneous else self._project(hom)

    def directional_derivative(self, u: ArrayLike, v: ArrayLike, direction: ArrayLike, order: int = 1) -> np.ndarray:
        """D_d^r T at (u, v) along the barycentric direction d = (d_u, d_v, d_w),
        d_u + d_v + d_w = 0: D_d^r p(x) = n!/(n-r)! f(d^r, x^(n-r)) (blossom with r
        direction arguments; Farin ch. 17); rational: the same on the homogeneous form and
        the quotient rule (Piegl & Tiller eq. 4.8). ``direction`` is a triple or an array
        (..., 3) broadcasting with u and v.

        Raises:
            CagdError: direction not summing to 0, order < 0, (u, v) outside the triangle."""
        order = _checks.order(order, "order")
        d = tb.barycentric(direction, "direction", direction=True)
        u, v = _checks.parameters(u, "u"), _checks.parameters(v, "v")
        try:
            shape = np.broadcast_shapes(u.shape, v.shape, d.shape[:-1])
        except ValueError:
            raise CagdError(f"u, v, direction: shapes {u.shape}, {v.shape}, {d.shape} do not broadcast") from None
        x, _ = self._points(np.broadcast_to(u, shape), np.broadcast_to(v, shape))
        d = np.broadcast_to(d, shape + (3,)).reshape(-1, 3)
        n = self.degree
        rs = range(order + 1) if self.is_rational else [order]
        hom = np.zeros((len(rs), x.shape[0], self._net.shape[-1]))
        for s, r in enumerate(rs):
            if r <= n:
                coef = factorial(n) / factorial(n - r)
                for c in _chunks(len(x), self._net[..., 0].size * self._net.shape[-1]):
                    hom[s, c] = coef * tb.multilinear(self._net, [d[c]] * r + [x[c]] * (n - r))
        res = rational_derivatives(hom)[-1] if self.is_rational else hom[-1]
        return res.reshape(shape + (self.dim,))

    # --- operations -----------------------------------------------------------------------
    def _subnet(self, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> np.ndarray:
        """Homogeneous canonical net of the same polynomial over the triangle with
        barycentric vertices a, b, c: Q_ijk = f(a^i, b^j, c^k) (seed 003, 3.1)."""
        n = self.degree
        V = np.array([a, b, c], dtype=np.float64)
        I, J, _ = tb.triple_arrays(n)
        r = np.arange(n)[:, None]
        which = np.where(r < I, 0, np.where(r < I + J, 1, 2))      # (n, N): vertex at level r
        return tb.multilinear(self._net, list(V[which]))

    def subtriangle(self, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> "BezierTriangle":
        """The same surface over the triangle with barycentric vertices a, b, c (each
        summing to 1; they may lie outside, giving the polynomial continuation), as a
        triangle whose own barycentric (s1, s2, s3) is the point s1 a + s2 b + s3 c:
        Q_ijk = f(a^i, b^j, c^k) (seed 003, 3.1 blossom control points).

        Raises:
            CagdError: vertices not barycentric triples; a rational continuation with
                non-positive weights."""
        V = [tb.barycentric(p, name) for p, name in zip((a, b, c), "abc")]
        for x, name in zip(V, "abc"):
            if x.shape != (3,):
                raise CagdError(f"{name}: a vertex must be one barycentric triple, got shape {x.shape}")
        return self._from_homogeneous(self._subnet(*V), self.is_rational)

    def subdivide(self, point: ArrayLike = (1 / 3, 1 / 3, 1 / 3)) -> List["BezierTriangle"]:
        """Three triangles meeting at the interior barycentric ``point`` p: the r-th has
        vertex r replaced by p, [(p, e2, e3), (e1, p, e3), (e1, e2, p)], each via blossoms.

        Raises:
            CagdError: p not a barycentric triple strictly inside the triangle."""
        p = tb.barycentric(point, "point")
        if p.shape != (3,) or np.any(p <= tb.TOL):
            raise CagdError(f"point: must be one barycentric triple strictly inside the triangle, got {p.tolist()}")
        E = np.eye(3)
        return [self.subtriangle(*[p if s == r else E[s] for s in range(3)]) for r in range(3)]

    def subdivide_midpoints(self) -> List["BezierTriangle"]:
        """Four triangles at the edge midpoints m12, m23, m31:
        [(e1, m12, m31), (m12, e2, m23), (m31, m23, e3), (m23, m31, m12)] (the last is the
        central one), all with the original orientation."""
        e1, e2, e3 = np.eye(3)
        m12, m23, m31 = (e1 + e2) / 2, (e2 + e3) / 2, (e3 + e1) / 2
        return [self.subtriangle(*t) for t in ((e1, m12, m31), (m12, e2, m23), (m31, m23, e3), (m23, m31, m12))]

    def degree_elevate(self, times: int = 1) -> "BezierTriangle":
        """Degree n -> n + times: Q_ijk = (i P_{i-1,j,k} + j P_{i,j-1,k} + k P_{i,j,k-1}) / (n+1)
        per step (Farin ch. 17), on homogeneous points for rational triangles.

        Raises:
            CagdError: ``times`` not an integer >= 0, n + times > :data:`cagd.MAX_DEGREE`."""
        times = _checks.elevation(times, self.degree)
        net = self._net
        for _ in range(times):
            n = net.shape[0] - 1
            pad = np.zeros((n + 3, n + 3, net.shape[-1]))
            pad[1:n + 2, 1:n + 2] = net                       # pad[i+1, j+1] = P_ij
            i = np.arange(n + 2)[:, None, None]
            j = np.arange(n + 2)[None, :, None]
            k = np.maximum(n + 1 - i - j, 0)
            net = (i * pad[:-1, 1:] + j * pad[1:, :-1] + k * pad[1:, 1:]) / (n + 1)
        return self._from_homogeneous(tb.to_flat(net), self.is_rational)

    def relabeled(self, order: Sequence[int]) -> "BezierTriangle":
        """The same surface with vertices renamed: new vertex r is old vertex order[r]
        (a permutation of 0, 1, 2); new barycentric y has y[r] = x[order[r]]."""
        try:
            perm = [int(x) for x in order]
        except (TypeError, ValueError):
            perm = []
        if sorted(perm) != [0, 1, 2]:
            raise CagdError(f"order: must be a permutation of (0, 1, 2), got {order!r}")
        n = self.degree
        new = np.array(tb.index_triples(n))
        old = np.empty_like(new)
        old[:, perm] = new
        pos = [tb.triple_position(n, int(i), int(j)) for i, j, _ in old]
        return self._from_homogeneous(self._hom[pos], self.is_rational)

    # --- conversion --------------------------------------------------------------------------
    def to_bezier_surface(self) -> BezierSurface:
        """The exact degree (n, n) tensor-product Bezier patch S(s, t) = T(s, (1 - s) t)
        (the Duffy map u = s, v = (1 - s) t, w = (1 - s)(1 - t)); the edge s = 1 collapses
        to vertex 1 (u = 1, P_n00). Through the tensor blossom
        F(s_1..s_n; t_1..t_n) = mean over pairings of f(x(s_r, t_sigma(r))), x bilinear:
        Q_ab = sum_m C(n-a, m) C(a, b-m) / C(n, b) P_{a, m, n-a-m} (homogeneous if rational)."""
        from ..surfaces.bezier import BezierSurface
        n = self.degree
        T = np.zeros(((n + 1) * (n + 1), len(self._hom)))
        for a in range(n + 1):
            for b in range(n + 1):
                for m in range(max(0, b - a), min(n - a, b) + 1):
                    T[a * (n + 1) + b, tb.triple_position(n, a, m)] = comb(n - a, m) * comb(a, b - m) / comb(n, b)
        hom = (T @ self._hom).reshape(n + 1, n + 1, -1)
        if self.is_rational:
            return BezierSurface(hom[..., :-1] / hom[..., -1:], hom[..., -1])
        return BezierSurface(hom)

    def to_nurbs(self) -> BSplineSurface:
        """The exact NURBS form: :meth:`to_bezier_surface` as a clamped single-patch
        :class:`cagd.BSplineSurface` (collapsed edge s = 1; T(u, v) = S(u, v / (1 - u)))."""
        return self.to_bezier_surface().to_nurbs()
