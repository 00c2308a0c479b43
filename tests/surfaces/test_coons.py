"""Coons patches (Farin ch. 22; not in the seeds): boundary interpolation, the direct
Boolean-sum formula, reproduction of ruled and bicubic surfaces (projector
properties), cross-boundary derivatives (seed 000 Hermite basis as oracle), exact
to_nurbs for polynomial and rational boundaries, corner errors, affine maps."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import (BezierCurve, BezierSurface, BSplineCurve, BSplineSurface, CagdError, HermiteCurve,
                  PolynomialCurve, hermite_basis, natural_cubic_spline)
from cagd.surfaces.coons import CoonsPatch, HermiteCoonsPatch
from cagd.surfaces.loft import ruled

from strategies import clamped_knots, point_arrays, positive_weights

SETTINGS = settings(max_examples=40, deadline=None)
T = np.linspace(0.0, 1.0, 41)
RNG = np.random.default_rng(11)
RU, RV = RNG.random(500), RNG.random(500)


def unit(curve, s, order=0):
    """curve at a + s (b - a) (derivative w.r.t. s)."""
    a, b = curve.domain
    return curve.derivative(a + s * (b - a), order) * (b - a) ** order if order else curve(a + s * (b - a))


@st.composite
def boundary(draw, start, end, rational=None):
    """A clamped B-spline/NURBS curve from start to end (random degree, knots, weights)."""
    p = draw(st.integers(1, 4))
    knots = draw(clamped_knots(p, max_interior=3))
    n = len(knots) - p - 1
    P = draw(point_arrays(n, 3))
    P[0], P[-1] = start, end
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=n, max_size=n))) if is_rational else None
    return BSplineCurve(P, p, knots, w)


@st.composite
def boundaries(draw, rational=None):
    corners = draw(point_arrays(4, 3))
    P00, P10, P01, P11 = corners
    return (draw(boundary(P00, P10, rational)), draw(boundary(P01, P11, rational)),
            draw(boundary(P00, P01, rational)), draw(boundary(P10, P11, rational)))


def scale_of(curves):
    return max(float(np.abs(c.control_points).max()) for c in curves) + 1.0


def off_knots(t, curves):
    """The parameters t farther than 1e-6 from every knot of the curves (unit domain)."""
    knots = np.concatenate([(c.knots - c.domain[0]) / (c.domain[1] - c.domain[0]) for c in curves])
    return t[np.abs(t[:, None] - knots[None, :]).min(axis=1) > 1e-6]


def coons_formula(c0, c1, d0, d1, u, v):
    """S = (1-v) c0(u) + v c1(u) + (1-u) d0(v) + u d1(v) - bilinear corners, typed out."""
    u, v = u[:, None], v[:, None]
    P00, P10, P01, P11 = unit(c0, 0.0), unit(c0, 1.0), unit(c1, 0.0), unit(c1, 1.0)
    return ((1 - v) * unit(c0, u[:, 0]) + v * unit(c1, u[:, 0]) + (1 - u) * unit(d0, v[:, 0])
            + u * unit(d1, v[:, 0]) - ((1 - u) * (1 - v) * P00 + u * (1 - v) * P10
                                       + (1 - u) * v * P01 + u * v * P11))


# --- the bilinearly blended patch ----------------------------------------------------------------
@SETTINGS
@given(boundaries())
def test_coons_interpolates_the_boundaries_and_matches_the_formula(curves):
    c0, c1, d0, d1 = curves
    S = CoonsPatch(*curves)
    eps = 1e-13 * scale_of(curves)
    assert np.abs(S(T, 0.0) - unit(c0, T)).max() <= eps
    assert np.abs(S(T, 1.0) - unit(c1, T)).max() <= eps
    assert np.abs(S(0.0, T) - unit(d0, T)).max() <= eps
    assert np.abs(S(1.0, T) - unit(d1, T)).max() <= eps
    assert np.abs(S(RU, RV) - coons_formula(c0, c1, d0, d1, RU, RV)).max() <= eps
    assert np.abs(S(T[:, None], T[None, :]) - S.grid(T, T)).max() <= eps


@SETTINGS
@given(boundaries())
def test_coons_to_nurbs_is_exact(curves):
    """Polynomial and rational boundaries (weights differing between curves): the NURBS
    form equals the patch at every sample, partials included (away from the curves'
    knots, where one-sided derivatives may differ)."""
    S = CoonsPatch(*curves)
    N = S.to_nurbs()
    assert isinstance(N, BSplineSurface) and N.domain == ((0.0, 1.0), (0.0, 1.0))
    assert N.is_rational == any(c.is_rational for c in curves)
    eps = 1e-12 * scale_of(curves)
    assert np.abs(N.grid(T, T) - S.grid(T, T)).max() <= eps
    assert np.abs(N(RU, RV) - S(RU, RV)).max() <= eps
    us, vs = off_knots(T, curves[:2]), off_knots(T, curves[2:])
    for du, dv in [(1, 0), (0, 1), (1, 1)]:
        ref = max(1.0, float(np.abs(S.grid(us, vs, du, dv)).max()))
        assert np.abs(N.grid(us, vs, du, dv) - S.grid(us, vs, du, dv)).max() <= 1e-10 * ref


def test_polynomial_coons_degrees_and_proportional_weights():
    """Polynomial boundaries: degrees (max(p_c, 1), max(p_d, 1)). Rational c-curves whose
    weight functions are proportional share one denominator: u-degree p + 1, not 2p + 1."""
    P00, P10, P01, P11 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1.0]])
    c0 = BezierCurve([P00, [0.5, -0.3, 0.2], [0.8, 0.2, 0.1], P10])
    c1 = BezierCurve([P01, [0.4, 1.2, 0.5], [0.7, 0.9, 0.3], P11])
    d0 = BezierCurve([P00, [0.1, 0.5, 0.4], P01])
    d1 = BezierCurve([P10, P11])
    N = CoonsPatch(c0, c1, d0, d1).to_nurbs()
    assert (N.degree_u, N.degree_v, N.is_rational) == (3, 2, False)
    w = np.array([1.0, 2.0, 0.5, 1.5])
    c0r, c1r = BezierCurve(c0.control_points, w), BezierCurve(c1.control_points, 3 * w)
    S = CoonsPatch(c0r, c1r, d0, d1)
    N = S.to_nurbs()
    assert (N.degree_u, N.degree_v) == (4, 2)
    assert np.abs(N.grid(T, T) - S.grid(T, T)).max() <= 1e-14
    N2 = CoonsPatch(c0r, BezierCurve(c1.control_points, w[::-1]), d0, d1).to_nurbs()
    assert N2.degree_u == 7


@SETTINGS
@given(st.integers(1, 4), point_arrays(5, 3), point_arrays(5, 3), st.booleans())
def test_coons_reproduces_ruled_surfaces(p, A, B, rational):
    """Linear precision in v: the Coons patch of the four boundaries of the linear blend
    (1-v) e0(u) + v e1(u) (straight lines d0, d1) is that surface, also for a NURBS e0."""
    e0 = BSplineCurve(A, p, None, np.linspace(0.5, 2.0, 5) if rational else None)
    e1 = BSplineCurve(B, p)
    d0, d1 = BezierCurve([e0(0.0), e1(0.0)]), BezierCurve([e0(1.0), e1(1.0)])
    S = CoonsPatch(e0, e1, d0, d1)
    exact = (1 - RV)[:, None] * e0(RU) + RV[:, None] * e1(RU)
    eps = 1e-13 * (np.abs(A).max() + np.abs(B).max() + 1)
    assert np.abs(S(RU, RV) - exact).max() <= eps
    assert np.abs(S.to_nurbs()(RU, RV) - exact).max() <= eps
    if not rational:                                   # and it is the ruled surface
        assert np.abs(ruled(e0, e1)(RU, RV) - exact).max() <= eps


def test_partials_against_finite_differences():
    c0 = natural_cubic_spline([[0, 0, 0], [0.4, -0.2, 0.3], [1.0, 0.1, 0.0]])
    c1 = PolynomialCurve([[0.0, 1.0, 0.2], [1.0, 0.3, 0.5], [0.0, -0.3, 0.3]], domain=(2.0, 5.0))
    d0 = HermiteCurve(c0(c0.domain[0]), c1(2.0), [0.3, 1.0, 0.0], [-0.2, 1.0, 0.4])
    d1 = BezierCurve([c0(c0.domain[1]), [1.3, 0.5, 0.2], c1(5.0)], [1.0, 0.6, 1.2])
    S = CoonsPatch(c0, c1, d0, d1)
    u, v, h = RU[:50] * 0.9 + 0.05, RV[:50] * 0.9 + 0.05, 1e-5
    fd = {(1, 0): (S(u + h, v) - S(u - h, v)) / (2 * h), (0, 1): (S(u, v + h) - S(u, v - h)) / (2 * h),
          (1, 1): (S(u + h, v + h) - S(u + h, v - h) - S(u - h, v + h) + S(u - h, v - h)) / (4 * h * h),
          (2, 0): (S(u + h, v) - 2 * S(u, v) + S(u - h, v)) / (h * h)}
    for (du, dv), approx in fd.items():
        assert np.abs(S.derivative(u, v, du, dv) - approx).max() <= 1e-4, (du, dv)
    N = S.to_nurbs()
    for du, dv in [(1, 0), (0, 1), (1, 1), (2, 0), (0, 2), (2, 2)]:
        ref = np.abs(S.derivative(u, v, du, dv)).max() + 1
        assert np.abs(N.derivative(u, v, du, dv) - S.derivative(u, v, du, dv)).max() <= 1e-11 * ref


# --- corner errors -----------------------------------------------------------------------------
CORNER_CASES = [(0, "corner (0,0): c0(0) and d0(0)"), (1, "corner (1,0): c0(1) and d1(0)"),
                (2, "corner (0,1): c1(0) and d0(1)"), (3, "corner (1,1): c1(1) and d1(1)")]


@pytest.mark.parametrize("which, message", CORNER_CASES)
def test_corner_mismatch_names_the_corner_and_gap(which, message):
    P = {0: np.zeros(3), 1: np.array([1.0, 0, 0]), 2: np.array([0, 1.0, 0]), 3: np.array([1.0, 1, 0])}
    off = np.array([0.0, 0.0, 0.03])
    ends = {0: (0, 1), 1: (2, 3), 2: (0, 2), 3: (1, 3)}              # c0, c1, d0, d1
    moved = {0: (0, 0), 1: (0, 1), 2: (1, 0), 3: (1, 1)}[which]       # (curve, end) to move
    curves = []
    for k in range(4):
        a, b = P[ends[k][0]].copy(), P[ends[k][1]].copy()
        if k == moved[0]:
            if moved[1] == 0:
                a += off
            else:
                b += off
        curves.append(BezierCurve([a, 0.5 * (a + b) + [0, 0, 0.1], b]))
    with pytest.raises(CagdError, match=r"differ by 0\.03") as info:
        CoonsPatch(*curves)
    assert message in str(info.value)
    with pytest.raises(CagdError) as info:
        HermiteCoonsPatch(*curves)
    assert message in str(info.value)
    CoonsPatch(*curves, rel_tol=0.1)                      # within tolerance: accepted
    with pytest.warns(DeprecationWarning, match="rel_tol"):       # the old keyword, one release
        assert CoonsPatch(*curves, tol=0.1).rel_tol == 0.1


def test_argument_errors():
    c = BezierCurve([[0, 0, 0], [1.0, 0, 0]])
    with pytest.raises(CagdError, match="c1: expected a cagd curve"):
        CoonsPatch(c, "not a curve", c, c)
    flat = BezierCurve([[0, 0], [1.0, 0]])
    with pytest.raises(CagdError, match="different dimensions"):
        CoonsPatch(c, c, flat, c)
    with pytest.raises(CagdError, match="rel_tol"):
        CoonsPatch(c, c, c, c, rel_tol=-1.0)
    with pytest.raises(CagdError, match="c0_v, c1_v, d0_u, d1_u"):
        HermiteCoonsPatch(c, c, c, c, c0_v=c)


# --- the bicubically blended patch -----------------------------------------------------------------
def surface_data(T_surface):
    """Boundaries and cross-boundary derivative curves of a Bezier surface (seed 003,
    2.2.2 boundary tangents)."""
    P, W = T_surface.control_points, T_surface.weights
    assert W is None
    tan = T_surface.boundary_tangents()
    return (BezierCurve(P[:, 0]), BezierCurve(P[:, -1]), BezierCurve(P[0]), BezierCurve(P[-1]),
            BezierCurve(tan["v0"]), BezierCurve(tan["v1"]), BezierCurve(tan["u0"]), BezierCurve(tan["u1"]))


@SETTINGS
@given(st.integers(1, 3), st.integers(1, 3), st.data())
def test_hermite_coons_reproduces_bicubic_surfaces(m, n, data):
    """Cubic Hermite interpolation reproduces cubics, so the Boolean sum of the two
    projectors reproduces every surface of degree <= 3 in u and in v."""
    Tsurf = BezierSurface(data.draw(point_arrays((m + 1) * (n + 1), 3)).reshape(m + 1, n + 1, 3))
    c0, c1, d0, d1, c0v, c1v, d0u, d1u = surface_data(Tsurf)
    S = HermiteCoonsPatch(c0, c1, d0, d1, c0v, c1v, d0u, d1u)
    eps = 1e-12 * (np.abs(Tsurf.control_points).max() + 1)
    assert np.abs(S(RU, RV) - Tsurf(RU, RV)).max() <= eps
    N = S.to_nurbs()
    assert np.abs(N(RU, RV) - Tsurf(RU, RV)).max() <= eps
    assert np.abs(N.derivative(RU, RV, 1, 1) - Tsurf.derivative(RU, RV, 1, 1)).max() <= 100 * eps


def test_hermite_coons_interpolates_positions_and_ribbons():
    """Degree (5, 4) data (not reproducible): S = T and the cross derivatives equal the
    ribbons on all four sides; the NURBS form is exact."""
    Tsurf = BezierSurface(RNG.normal(size=(6, 5, 3)))
    c0, c1, d0, d1, c0v, c1v, d0u, d1u = surface_data(Tsurf)
    S = HermiteCoonsPatch(c0, c1, d0, d1, c0v, c1v, d0u, d1u)
    assert S.has_ribbons
    for u, v, du, dv in [(T, 0.0, 0, 1), (T, 1.0, 0, 1), (0.0, T, 1, 0), (1.0, T, 1, 0)]:
        assert np.abs(S(u, v) - Tsurf(u, v)).max() <= 1e-13
        assert np.abs(S.derivative(u, v, du, dv) - Tsurf.derivative(u, v, du, dv)).max() <= 1e-12
    assert np.abs(S(RU, RV) - Tsurf(RU, RV)).max() > 1e-3          # genuinely different inside
    N = S.to_nurbs()
    assert (N.degree_u, N.degree_v) == (5, 4)
    assert np.abs(N.grid(T, T) - S.grid(T, T)).max() <= 1e-13


@SETTINGS
@given(boundaries())
def test_hermite_positions_only(curves):
    """Without ribbons: the boundaries are interpolated and the cross-boundary derivative
    is the Hermite blend of the side curves' end tangents (seed 000 basis as oracle):
    S_v(u, 0) = H0(u) d0'(0) + H1(u) d1'(0), S_u(0, v) = H0(v) c0'(0) + H1(v) c1'(0)."""
    c0, c1, d0, d1 = curves
    S = HermiteCoonsPatch(*curves)
    assert not S.has_ribbons
    eps = 1e-13 * scale_of(curves)
    assert np.abs(S(T, 0.0) - unit(c0, T)).max() <= eps
    assert np.abs(S(1.0, T) - unit(d1, T)).max() <= eps
    H = hermite_basis(T)
    expected_v = H[:, :1] * unit(d0, 0.0, 1) + H[:, 1:2] * unit(d1, 0.0, 1)
    expected_u = H[:, :1] * unit(c0, 0.0, 1) + H[:, 1:2] * unit(c1, 0.0, 1)
    ref = max(1.0, np.abs(expected_v).max(), np.abs(expected_u).max())
    assert np.abs(S.derivative(T, 0.0, 0, 1) - expected_v).max() <= 1e-12 * ref
    assert np.abs(S.derivative(0.0, T, 1, 0) - expected_u).max() <= 1e-12 * ref
    N = S.to_nurbs()
    assert np.abs(N.grid(T, T) - S.grid(T, T)).max() <= 1e-12 * scale_of(curves)


def test_ribbon_mismatch_errors():
    Tsurf = BezierSurface(RNG.normal(size=(4, 4, 3)))
    c0, c1, d0, d1, c0v, c1v, d0u, d1u = surface_data(Tsurf)
    bad = BezierCurve(c0v.control_points + [[0.5, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]])  # c0_v(0) moved
    with pytest.raises(CagdError, match=r"corner \(0,0\): c0_v\(0\) and d0'\(0\) differ by 0\.5"):
        HermiteCoonsPatch(c0, c1, d0, d1, bad, c1v, d0u, d1u)
    # same ends, different twist at (1,1): move an inner control point of d1_u
    Q = d1u.control_points.copy()
    Q[-2] += [0.0, 0.2, 0.0]
    with pytest.raises(CagdError, match=r"corner \(1,1\): c1_v'\(1\) and d1_u'\(1\) differ by 0\.6"):
        HermiteCoonsPatch(c0, c1, d0, d1, c0v, c1v, d0u, BezierCurve(Q))


def test_affine_maps_commute():
    A = np.array([[0.0, -1.0, 0.3], [1.0, 0.2, 0.0], [0.1, 0.0, 2.0]])
    b = np.array([1.0, 2.0, -3.0])
    Tsurf = BezierSurface(RNG.normal(size=(4, 5, 3)))
    data = surface_data(Tsurf)
    for S in (CoonsPatch(*data[:4]), HermiteCoonsPatch(*data), HermiteCoonsPatch(*data[:4])):
        M = S.transformed(A, b)
        assert type(M) is type(S)
        assert np.abs(M(RU, RV) - (S(RU, RV) @ A.T + b)).max() <= 1e-12


def test_isocurves_and_boundaries_from_the_nurbs_form():
    c0, c1, d0, d1 = surface_data(BezierSurface(RNG.normal(size=(3, 4, 3))))[:4]
    S = CoonsPatch(c0, c1, d0, d1)
    b = S.boundaries()
    assert np.abs(b[0](T) - c0(T)).max() <= 1e-14
    assert np.abs(b[1](T) - d1(T)).max() <= 1e-14


def test_missing_boundary_curves_are_named():
    """CoonsPatch(None, None, None, None) raised KeyError (an empty set of dimensions)
    and a None among valid curves a misleading corner error: each boundary is named."""
    c = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    for i, name in enumerate(("c0", "c1", "d0", "d1")):
        args = [c, c, c, c]
        args[i] = None
        with pytest.raises(CagdError, match=f"^{name}: expected a cagd curve"):
            CoonsPatch(*args)
    with pytest.raises(CagdError, match="^c0: expected a cagd curve"):
        CoonsPatch(None, None, None, None)
    with pytest.raises(CagdError, match="^c1: expected a cagd curve"):
        HermiteCoonsPatch(c, None, c, c)
