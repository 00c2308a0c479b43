"""Hypothesis strategies for the OCCT bridge tests: one instance of every engine
family (curves and surfaces), built from the shared strategies in
``strategies`` and ``surface_strategies``.

Points are kept apart where a family needs distinct points (splines, Hermite
splines), and the objects are otherwise unconstrained: degenerate normals are
handled by ``verify`` (collapsed points are skipped), degenerate spans cannot
occur (knot gaps >= 0.05).
"""
from __future__ import annotations

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from cagd import (BezierCurve, BezierSurface, BezierTriangle, BSplineCurve, BSplineSurface, CoonsPatch,
                  HermiteCurve, HermiteSpline, PolynomialCurve, ellipsoid, loft, natural_cubic_spline, revolve,
                  sphere, torus)

from strategies import gaps, periodic_knots, point_arrays, positive_weights
from surface_strategies import direction_knots, nets, weight_nets

lengths = st.floats(0.2, 10.0, allow_nan=False, allow_infinity=False)
dims = st.sampled_from((2, 3))


def _separated(P: np.ndarray, closed: bool = False) -> bool:
    """Consecutive points at least 1e-3 of the extent apart (and, for ``closed``,
    the non-closing points pairwise apart)."""
    extent = float(np.ptp(P, axis=0).max()) if len(P) else 0.0
    if extent < 1e-3:
        return False
    Q = P[:-1] if closed else P
    d = np.linalg.norm(np.diff(Q, axis=0), axis=1)
    return bool(d.min() > 1e-3 * extent)


@st.composite
def polynomial_curves(draw):
    deg = draw(st.integers(0, 10))
    A = draw(point_arrays(deg + 1, draw(dims)))
    a = draw(st.floats(-5.0, 5.0))
    return PolynomialCurve(A, (a, a + draw(lengths)))


@st.composite
def hermite_curves(draw):
    d = draw(dims)
    P = draw(point_arrays(4, d))
    return HermiteCurve(P[0], P[1], P[2], P[3])


@st.composite
def hermite_splines(draw):
    d, n = draw(dims), draw(st.integers(2, 6))
    P, m = draw(point_arrays(n, d)), draw(point_arrays(n, d))
    t = draw(st.floats(-3.0, 3.0)) + np.concatenate([[0.0], np.cumsum(draw(gaps(n - 1)))])
    return HermiteSpline(P, m, t)


END_CONDITIONS = ("natural", "clamped", "periodic", "virtual")


@st.composite
def cubic_splines(draw, end_condition=None):
    """A CubicSpline with the given (or any) end condition and parametrization."""
    end = draw(st.sampled_from(END_CONDITIONS)) if end_condition is None else end_condition
    d = draw(dims)
    n = draw(st.integers(4 if end == "periodic" else 2, 8))
    P = draw(point_arrays(n, d))
    if end == "periodic":
        P[-1] = P[0]
    assume(_separated(P, closed=end == "periodic"))
    kw = {}
    if end == "clamped":
        kw["tangents"] = draw(point_arrays(2, d))
    if end == "virtual":
        V = draw(point_arrays(2, d))
        assume(np.linalg.norm(V[0] - P[0]) > 1e-3 and np.linalg.norm(V[1] - P[-1]) > 1e-3)
        kw["virtual_points"] = V
    par = draw(st.sampled_from(("chord", "uniform", "centripetal")))
    return natural_cubic_spline(P, end, par, **kw)


@st.composite
def bezier_curves(draw, rational=None, max_degree: int = 10):
    deg = draw(st.integers(1, max_degree))
    P = draw(point_arrays(deg + 1, draw(dims)))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=deg + 1, max_size=deg + 1))) if is_rational else None
    return BezierCurve(P, w)


@st.composite
def kinked_curves(draw):
    """A clamped B-spline with interior knots of multiplicity = degree (C0 kinks)."""
    p = draw(st.integers(1, 6))
    k = draw(st.integers(1, 3))
    values = draw(st.floats(-5.0, 5.0)) + np.concatenate([[0.0], np.cumsum(draw(gaps(k + 1)))])
    knots = np.repeat(values, [p + 1] + [p] * k + [p + 1])
    n = len(knots) - p - 1
    P = draw(point_arrays(n, draw(dims)))
    w = np.array(draw(st.lists(positive_weights, min_size=n, max_size=n))) if draw(st.booleans()) else None
    return BSplineCurve(P, p, knots, w)


@st.composite
def periodic_curves(draw, uniform=None, repeated_seam=None, rational=None):
    """A periodic B-spline / NURBS curve; ``uniform`` equally spaced simple knots,
    otherwise non-uniform (seam multiplicity per ``repeated_seam``)."""
    p = draw(st.integers(1, 10))
    is_uniform = draw(st.booleans()) if uniform is None else uniform
    if is_uniform:
        n = draw(st.integers(max(p, 2), p + 6))
        h, a = draw(st.floats(0.1, 2.0)), draw(st.floats(-5.0, 5.0))
        knots = a + h * np.arange(n + 1, dtype=np.float64)
    else:
        knots = draw(periodic_knots(p, repeated_seam=repeated_seam))
        n = len(knots) - 1
    P = draw(point_arrays(n, draw(dims)))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=n, max_size=n))) if is_rational else None
    return BSplineCurve(P, p, knots, w, periodic=True)


# --- surfaces ---------------------------------------------------------------------------------
@st.composite
def bspline_surfaces_3d(draw, kind_u=None, kind_v=None, max_degree_u: int = 4, max_degree_v: int = 4,
                        rational=None):
    """A 3-D BSplineSurface with the given kinds ("clamped", "floating",
    "nonuniform", "periodic") per direction (any when None)."""
    kinds = ("clamped", "floating", "nonuniform", "periodic")
    ku_kind = draw(st.sampled_from(kinds)) if kind_u is None else kind_u
    kv_kind = draw(st.sampled_from(kinds)) if kind_v is None else kind_v
    p, q = draw(st.integers(1, max_degree_u)), draw(st.integers(1, max_degree_v))
    ku, nu, per_u = draw(direction_knots(ku_kind, p))
    kv, nv, per_v = draw(direction_knots(kv_kind, q))
    assume(nu * nv <= 400)
    P = draw(nets(nu, nv, 3))
    is_rational = draw(st.booleans()) if rational is None else rational
    W = draw(weight_nets(nu, nv)) if is_rational else None
    return BSplineSurface(P, p, q, ku, kv, W, per_u, per_v)


@st.composite
def kinked_surfaces(draw):
    """Clamped in both directions, interior knots of multiplicity = degree in u."""
    p, q = draw(st.integers(1, 4)), draw(st.integers(1, 3))
    k = draw(st.integers(1, 2))
    values = np.concatenate([[0.0], np.cumsum(draw(gaps(k + 1)))])
    ku = np.repeat(values, [p + 1] + [p] * k + [p + 1])
    kv = np.repeat([0.0, 1.0], q + 1)
    nu, nv = len(ku) - p - 1, q + 1
    W = draw(weight_nets(nu, nv)) if draw(st.booleans()) else None
    return BSplineSurface(draw(nets(nu, nv, 3)), p, q, ku, kv, W)


@st.composite
def bezier_surfaces_3d(draw, rational=None, max_degree: int = 6):
    m, n = draw(st.integers(1, max_degree)), draw(st.integers(1, max_degree))
    P = draw(nets(m + 1, n + 1, 3))
    is_rational = draw(st.booleans()) if rational is None else rational
    return BezierSurface(P, draw(weight_nets(m + 1, n + 1)) if is_rational else None)


@st.composite
def revolved_surfaces(draw):
    """A random 3-D B-spline profile revolved (full turn, or a partial angle)."""
    p = draw(st.integers(1, 4))
    n = draw(st.integers(p + 1, p + 4))
    P = draw(point_arrays(n, 3))
    prof = BSplineCurve(P, p)
    if draw(st.booleans()):
        return revolve(prof)
    return revolve(prof, angle=draw(st.floats(0.3, 6.0)), start_angle=draw(st.floats(-3.0, 3.0)))


@st.composite
def quadrics(draw):
    """A sphere, torus or one ellipsoid patch with random sizes."""
    kind = draw(st.sampled_from(("sphere", "torus", "ellipsoid")))
    c = np.array(draw(point_arrays(1, 3)))[0]
    if kind == "sphere":
        return sphere(draw(lengths), c)
    if kind == "torus":
        r = draw(lengths)
        return torus(r + draw(lengths), r, c)
    return ellipsoid(draw(lengths), draw(lengths), draw(lengths))[draw(st.integers(0, 7))]


@st.composite
def _boundary(draw, a: np.ndarray, b: np.ndarray):
    """A random rational or polynomial Bezier / B-spline curve from a to b."""
    kind = draw(st.sampled_from(("bezier", "bspline")))
    if kind == "bezier":
        deg = draw(st.integers(1, 4))
        P = np.vstack([a, draw(point_arrays(deg - 1, 3)).reshape(-1, 3), b])
        w = None
        if draw(st.booleans()):
            w = np.array(draw(st.lists(positive_weights, min_size=deg + 1, max_size=deg + 1)))
        return BezierCurve(P, w)
    p = draw(st.integers(1, 3))
    n = draw(st.integers(p + 1, p + 3))
    P = np.vstack([a, draw(point_arrays(n - 2, 3)).reshape(-1, 3), b])
    return BSplineCurve(P, p)


@st.composite
def coons_patches(draw):
    C = draw(point_arrays(4, 3))          # corners S(0,0), S(1,0), S(0,1), S(1,1)
    c0 = draw(_boundary(C[0], C[1]))
    c1 = draw(_boundary(C[2], C[3]))
    d0 = draw(_boundary(C[0], C[2]))
    d1 = draw(_boundary(C[1], C[3]))
    return CoonsPatch(c0, c1, d0, d1)


@st.composite
def lofts(draw):
    k = draw(st.integers(2, 5))
    sections = []
    for _ in range(k):
        p = draw(st.integers(1, 3))
        n = draw(st.integers(p + 1, p + 3))
        sections.append(BSplineCurve(draw(point_arrays(n, 3)), p))
    # distinct sections (loft parametrises by chord length between them)
    for s, t in zip(sections, sections[1:]):
        assume(np.abs(s(np.linspace(0, 1, 7)) - t(np.linspace(0, 1, 7))).max() > 1e-2)
    return loft(sections, degree_v=draw(st.integers(1, min(3, k - 1))))


@st.composite
def bezier_triangles(draw, rational=None):
    n = draw(st.integers(1, 6))
    count = (n + 1) * (n + 2) // 2
    P = draw(point_arrays(count, 3))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=count, max_size=count))) if is_rational else None
    return BezierTriangle(P, w)


def curves_of_every_family():
    return st.one_of(polynomial_curves(), hermite_curves(), hermite_splines(), cubic_splines(), bezier_curves(),
                     kinked_curves(), periodic_curves())
