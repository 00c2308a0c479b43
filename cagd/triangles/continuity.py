"""Continuity of two Bezier triangles across a shared edge, through the blossom
(seed 003, 3.2; Farin, Curves and Surfaces for CAGD, ch. 17).

Layout. t1's domain vertices V0, V1, V2 are e1, e2, e3 of its barycentric coordinates.
``edge`` e in {0, 1, 2} is the edge opposite V_e (x_e = 0), from V_{e+1} to V_{e+2}
(indices mod 3). The neighbour t2 has the domain vertices (V_{e+2}, V_{e+1}, D): for
e = 0 this is the seed's T1 = {a, b, c}, T2 = {c, b, d}. So t2's shared edge is its
k = 0 edge (control points P_{i,j,0}) and row l of t2 is the triples with k = l.
``apex`` D is given in t1's barycentric coordinates (a triple summing to 1), or as a
point (u, v) of t1's parameter plane; default V_{e+1} + V_{e+2} - V_e (the reflection of
V_e through the edge midpoint). It must lie across the edge (D_e < 0).

Conditions (seed 003, 3.2, for degree n). Let h be t1's polynomial continued over t2's
domain, h_ijk = f(V_{e+2}^i, V_{e+1}^j, D^k) with f t1's blossom. t2 joins t1 with C^r
iff its rows l = 0..r equal h's: C0 is f(b, .., c) = g(b, .., c) on the edge, C1 adds
g(d, b^j, c^k) = f(d, b^j, c^k) with d = D in t1's coordinates. Rational triangles are
compared in homogeneous coordinates (w P, w) (sufficient for geometric C^r).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._deprecation import RELATIVE, renamed
from ..operations.continuity import CONTINUITY_TOL
from ..errors import CagdError
from . import basis as tb
from ._input import _key
from .bezier_triangle import BezierTriangle


def neighbor_vertices(edge: int = 0, apex: Optional[ArrayLike] = None) -> np.ndarray:
    """t2's domain vertices (V_{e+2}, V_{e+1}, D) as rows of barycentric coordinates
    w.r.t. t1 (see the module docstring); a t2-barycentric y is the t1 point y @ M.

    Raises:
        CagdError: edge not 0, 1, 2; apex not a triple summing to 1 or a (u, v) pair;
            apex not across the edge."""
    e = _checks.integer(edge, "edge", 0, 2)
    E = np.eye(3)
    if apex is None:
        D = E[(e + 1) % 3] + E[(e + 2) % 3] - E[e]
    else:
        a = _checks.finite_array(apex, "apex", ndim=1)
        if a.shape == (2,):
            D = np.array([a[0], a[1], 1.0 - a[0] - a[1]])
        elif a.shape == (3,):
            D = tb.barycentric(a, "apex")
        else:
            raise CagdError(f"apex: expected a barycentric triple or a (u, v) point, got shape {a.shape}")
    if not D[e] < -tb.TOL:
        raise CagdError(f"apex: {D.tolist()} must lie across edge {e} (barycentric coordinate {e} < 0)")
    return np.array([E[(e + 2) % 3], E[(e + 1) % 3], D])


def _lifted(hom: np.ndarray, rational: bool) -> np.ndarray:
    return hom if rational else np.concatenate([hom, np.ones((hom.shape[0], 1))], axis=1)


@dataclass(frozen=True)
class TriangleContinuity:
    """Measured deviations of t2 from the C^r conditions, r = 0..order.

    control_deviations[l]: max |g - h| over t2's row l (the seed's blossom conditions;
        homogeneous (w P, w) if either triangle is rational).
    derivative_deviations[l]: max over samples on the edge of |D^l t1 - D^l t2|, D the
        derivative towards the apex expressed in each triangle's own coordinates.
    scale: max(1, largest control point coordinate) of the two triangles.
    """
    order: int
    control_deviations: Tuple[float, ...]
    derivative_deviations: Tuple[float, ...]
    scale: float

    def is_continuous(self, r: int, rel_tol: float = CONTINUITY_TOL, *, tol: Optional[float] = None) -> bool:
        """C^r within rel_tol * scale (control point conditions); ``tol`` is the deprecated
        name of ``rel_tol`` (one release)."""
        if tol is not None:
            rel_tol = renamed("TriangleContinuity.is_continuous", "tol", "rel_tol", tol, rel_tol, CONTINUITY_TOL,
                              RELATIVE)
        r = _checks.integer(r, "r", 0, self.order)
        return all(d <= rel_tol * self.scale for d in self.control_deviations[:r + 1])

    def continuity_order(self, rel_tol: float = CONTINUITY_TOL, *, tol: Optional[float] = None) -> int:
        """The largest r <= order with C^r within rel_tol * scale; -1 if not even C0
        (``tol``: the deprecated name of ``rel_tol``)."""
        if tol is not None:
            rel_tol = renamed("TriangleContinuity.continuity_order", "tol", "rel_tol", tol, rel_tol,
                              CONTINUITY_TOL, RELATIVE)
        r = -1
        while r < self.order and self.is_continuous(r + 1, rel_tol):
            r += 1
        return r


def triangle_continuity(t1: BezierTriangle, t2: BezierTriangle, edge: int = 0, apex: Optional[ArrayLike] = None,
                        order: int = 1, samples: int = 9) -> TriangleContinuity:
    """Measure how far t2 is from joining t1 with C^0..C^order along t1's ``edge``, t2
    laid out as in the module docstring (seed 003, 3.2).

    Raises:
        CagdError: not BezierTriangles, different degrees or dimensions, bad edge/apex,
            order outside 0..degree, samples < 2."""
    for t, name in ((t1, "t1"), (t2, "t2")):
        if not isinstance(t, BezierTriangle):
            raise CagdError(f"{name}: expected a BezierTriangle, got {type(t).__name__}")
    if t1.degree != t2.degree:
        raise CagdError(f"t2: degree {t2.degree} differs from t1's degree {t1.degree} (elevate one first)")
    if t1.dim != t2.dim:
        raise CagdError(f"t2: dimension {t2.dim} differs from t1's {t1.dim}")
    n = t1.degree
    order = _checks.integer(order, "order", 0, n)
    samples = _checks.integer(samples, "samples", 2)
    M = neighbor_vertices(edge, apex)
    rational = t1.is_rational or t2.is_rational
    h = _lifted(t1._subnet(*M), t1.is_rational)
    g = _lifted(t2.homogeneous_control_points, t2.is_rational)
    if not rational:
        h, g = h[:, :-1], g[:, :-1]
    K = tb.triple_arrays(n)[2]
    ctrl = tuple(float(np.max(np.linalg.norm(g[K == l] - h[K == l], axis=1))) for l in range(order + 1))
    s = np.linspace(0.0, 1.0, samples)
    x1 = np.outer(1.0 - s, M[1]) + np.outer(s, M[0])           # edge points, t1 coordinates
    x2 = np.stack([s, 1.0 - s, np.zeros_like(s)], axis=1)      # the same points, t2 coordinates
    d1, d2 = M[2] - x1, np.array([0.0, 0.0, 1.0]) - x2         # towards the apex
    deriv = []
    for l in range(order + 1):
        a = t1.directional_derivative(x1[:, 0], x1[:, 1], d1, l)
        b = t2.directional_derivative(x2[:, 0], x2[:, 1], d2, l)
        deriv.append(float(np.max(np.linalg.norm(a - b, axis=1))))
    scale = max(1.0, float(np.abs(t1.control_points).max()), float(np.abs(t2.control_points).max()))
    return TriangleContinuity(order, ctrl, tuple(deriv), scale)


def c1_neighbor(t1: BezierTriangle, edge: int = 0, apex: Optional[ArrayLike] = None,
                free: Optional[Mapping[Tuple[int, int, int], ArrayLike]] = None,
                free_weights: Optional[Mapping[Tuple[int, int, int], float]] = None) -> BezierTriangle:
    """A neighbour t2 of t1 across ``edge`` with domain apex ``apex`` (module docstring)
    joining t1 with C1 (seed 003, 3.2): rows k = 0, 1 of t2 are t1's blossom values
    h_ijk = f(V_{e+2}^i, V_{e+1}^j, D^k) (the edge row, then g(d, b^j, c^i) = f(d, b^j, c^i)
    in the seed's notation). The rows k >= 2 are free:
    by default they are filled with the same blossom values (the polynomial continuation,
    so t2 then joins with C^n), and ``free`` = {(i, j, k): point} (k >= 2) overrides them;
    ``free_weights`` = {(i, j, k): weight} sets their weights (the neighbour of a
    polynomial t1 becomes rational, with weight 1 on rows 0, 1).

    Raises:
        CagdError: bad edge/apex; a free triple with k <= 1, not of degree n, or a bad
            point/weight; non-positive weights of a rational continuation."""
    if not isinstance(t1, BezierTriangle):
        raise CagdError(f"t1: expected a BezierTriangle, got {type(t1).__name__}")
    n, triples = t1.degree, tb.index_triples(t1.degree)
    M = neighbor_vertices(edge, apex)
    hom = t1._subnet(*M)
    if t1.is_rational:
        W = hom[:, -1].copy()
        P = hom[:, :-1] / W[:, None]
        bad = W[tb.triple_arrays(n)[2] <= 1] <= 0
        if np.any(bad):
            raise CagdError("apex: the continuation of the rational t1 has non-positive weights in the "
                            "C1 rows at this apex; choose an apex closer to the edge")
    else:
        P, W = hom.copy(), None
    for table, name in ((free, "free"), (free_weights, "free_weights")):
        if table is None:
            continue
        if not isinstance(table, Mapping):
            raise CagdError(f"{name}: expected a mapping {{(i, j, k): value}}, got {type(table).__name__}")
        for key, val in table.items():
            t = _key(key, name)
            if sum(t) != n:
                raise CagdError(f"{name}: triple {t} does not sum to the degree {n}")
            if t[2] <= 1:
                raise CagdError(f"{name}: triple {t} is fixed by C1 (rows k = 0, 1 next to the shared edge)")
            r = tb.triple_position(n, t[0], t[1])
            if name == "free":
                p = _checks.finite_array(val, f"free[{t}]", ndim=1)
                if p.shape != (t1.dim,):
                    raise CagdError(f"free: point for triple {t} has {p.shape[0]} coordinates, expected {t1.dim}")
                P[r] = p
            else:
                if W is None:
                    W = np.ones(len(triples))
                W[r] = _checks.scalar(val, f"free_weights[{t}]")
    if W is not None and np.any(W <= 0):
        t = triples[int(np.argmax(W <= 0))]
        raise CagdError(f"free_weights: the weight of the free triple {t} is {float(W[triples.index(t)])!r} (the "
                        "rational continuation's value unless given); give a positive weight")
    return BezierTriangle(P, W)
