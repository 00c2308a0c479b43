"""High degrees (issue 14): every accepted degree evaluates within 1e-12 (relative to the
control net) of de Casteljau in exact fractions; above MAX_DEGREE a CagdError.
Oracles: exact rational de Casteljau, scipy.interpolate.BSpline."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve, BSplineSurface, BezierSurface, CagdError
from cagd.curves.bezier_spans import bezier_spans
from cagd.curves.ppform import PP_MAX_DEGREE

scipy_interpolate = pytest.importorskip("scipy.interpolate")


def exact_casteljau(P: np.ndarray, t: float) -> np.ndarray:
    """De Casteljau in exact rational arithmetic, rounded once at the end."""
    tt = Fraction(t)
    level = [[Fraction(float(x)) for x in row] for row in P]
    while len(level) > 1:
        level = [[(1 - tt) * a + tt * b for a, b in zip(level[i], level[i + 1])] for i in range(len(level) - 1)]
    return np.array([float(x) for x in level[0]])


TS = [0.0, 0.001, 0.1, 0.3, 0.5, 0.77, 0.9, 0.999, 1.0]


def test_degree_60_at_0999_matches_exact_the_reported_case():
    # reported: (0.717, 0.605, 0.574) where exact gives (0.734, 0.859, 0.158)
    P = np.random.default_rng(60).random((61, 3))
    c = BezierCurve(P)
    assert np.allclose(c(0.999), exact_casteljau(P, 0.999), rtol=0, atol=1e-12)


@pytest.mark.parametrize("n", [5, PP_MAX_DEGREE, PP_MAX_DEGREE + 1, 55, 60, 70, 80, 100, cagd.MAX_DEGREE])
def test_every_degree_matches_exact_de_casteljau(n):
    P = np.random.default_rng(n).random((n + 1, 3)) * 2 - 1
    v = BezierCurve(P)(np.array(TS))
    exact = np.array([exact_casteljau(P, t) for t in TS])
    assert np.abs(v - exact).max() <= 1e-12 * np.abs(P).max()


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, cagd.MAX_DEGREE), seed=st.integers(0, 2**32 - 1),
       k=st.integers(0, 2**16), scale=st.sampled_from([1e-100, 1.0, 1e100]))
def test_property_any_degree_matches_exact(n, seed, k, scale):
    t = k / 2**16                       # short binary fractions keep the exact arithmetic quick
    P = (np.random.default_rng(seed).random((n + 1, 2)) - 0.5) * scale
    v = BezierCurve(P)(t)
    assert np.abs(v - exact_casteljau(P, t)).max() <= 1e-12 * np.abs(P).max()


@pytest.mark.parametrize("p", [3, 25, 60, 128])
def test_bspline_high_degree_matches_scipy_values_and_derivatives(p):
    rng = np.random.default_rng(p)
    n = p + 9
    P = rng.random((n, 3))
    inner = np.sort(rng.random(n - p - 1))
    knots = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    c = BSplineCurve(P, p, knots)
    t = np.linspace(0, 1, 57)
    ref = scipy_interpolate.BSpline(knots, P, p)
    d = c.derivatives(t, 2)
    for k in range(3):
        expect = ref(t, nu=k)
        assert np.abs(d[k] - expect).max() <= 1e-12 * max(np.abs(expect).max(), np.abs(P).max()), k


@pytest.mark.parametrize("n", [30, 100])
def test_high_degree_derivatives_match_exact_hodograph(n):
    P = np.random.default_rng(n).random((n + 1, 2))
    c = BezierCurve(P)
    H = n * np.diff(P, axis=0)                      # exact up to one rounding per difference
    for t in (0.2, 0.999):
        assert np.abs(c.derivative(t, 1) - exact_casteljau(H, t)).max() <= 1e-12 * np.abs(H).max()


def test_rational_high_degree_matches_exact():
    n = 90
    rng = np.random.default_rng(9)
    P, w = rng.random((n + 1, 3)), rng.random(n + 1) + 0.5
    hom = np.hstack([P * w[:, None], w[:, None]])
    c = BezierCurve(P, w)
    for t in (0.05, 0.5, 0.999):
        e = exact_casteljau(hom, t)
        assert np.abs(c(t) - e[:3] / e[3]).max() <= 1e-12


def test_bezier_spans_reproduce_the_curve_and_knot_insertion():
    rng = np.random.default_rng(3)
    c = BSplineCurve(rng.random((12, 2)), 3, [0, 0, 0, 0, 0.1, 0.1, 0.4, 0.5, 0.5, 0.5, 0.7, 0.9, 1, 1, 1, 1])
    breaks, nets = bezier_spans(c.full_knots, c.degree, c.homogeneous_control_points)
    b2, nets2 = c.bezier_net()                  # knot insertion (Piegl & Tiller A5.6)
    assert np.array_equal(breaks, b2)
    assert np.allclose(nets, nets2, atol=1e-14)


@pytest.mark.parametrize("p,q", [(30, 2), (2, 64)])
def test_high_degree_surface_matches_scipy_tensor_product(p, q):
    rng = np.random.default_rng(p + q)
    nu, nv = p + 3, q + 2
    P = rng.random((nu, nv, 3))
    ku = np.concatenate([np.zeros(p + 1), np.sort(rng.random(nu - p - 1)), np.ones(p + 1)])
    kv = np.concatenate([np.zeros(q + 1), np.sort(rng.random(nv - q - 1)), np.ones(q + 1)])
    s = BSplineSurface(P, p, q, ku, kv)
    u = np.linspace(0, 1, 7)
    v = np.linspace(0, 1, 5)
    # scipy: rows in u, then the v direction on the results
    rows = scipy_interpolate.BSpline(ku, P, p)(u)                      # (7, nv, 3)
    expect = scipy_interpolate.BSpline(kv, np.moveaxis(rows, 1, 0), q)(v)   # (5, 7, 3)
    expect = np.moveaxis(expect, 0, 1)
    got = s(u[:, None], v[None, :])
    assert np.abs(got - expect).max() <= 1e-12
    assert np.abs(s.grid(u, v) - expect).max() <= 1e-12
    # the mixed partial S_uv (and S_uu) against scipy's derivatives
    for du, dv in ((1, 1), (2, 0)):
        rows = scipy_interpolate.BSpline(ku, P, p)(u, nu=du)
        ref = np.moveaxis(scipy_interpolate.BSpline(kv, np.moveaxis(rows, 1, 0), q)(v, nu=dv), 0, 1)
        d = s.derivative(u[:, None], v[None, :], du, dv)
        assert np.abs(d - ref).max() <= 1e-12 * max(np.abs(ref).max(), 1.0)


def test_degree_above_max_is_a_cagd_error_everywhere():
    M = cagd.MAX_DEGREE
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BezierCurve(np.zeros((M + 2, 2)) + np.arange(M + 2)[:, None])
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BSplineCurve(np.random.rand(M + 5, 2), M + 1)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BezierSurface(np.random.rand(M + 2, 2, 3))
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BSplineSurface(np.random.rand(3, M + 3, 3), 2, M + 1)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BezierCurve(np.random.rand(4, 2)).elevate(M)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BSplineCurve(np.random.rand(6, 2), 3).elevate(10**18)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        BezierSurface(np.random.rand(3, 3, 3)).elevate(10**18, 0)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        cagd.interpolate(np.random.rand(M + 10, 2), M + 1)
    with pytest.raises(CagdError, match="MAX_DEGREE"):
        cagd.bezier_through_points(np.random.rand(M + 2, 2))
    # the maximum itself is accepted
    assert BezierCurve(np.random.rand(M + 1, 2)).degree == M


def test_bounded_orders():
    c = BSplineCurve(np.random.rand(6, 2), 3)
    s = BezierSurface(np.random.rand(3, 3, 3))
    for call in (lambda: c.derivatives(0.5, 10**18), lambda: c.derivative(0.5, cagd.MAX_ORDER + 1),
                 lambda: s.grid([0.5], [0.5], du=10**18), lambda: s.derivatives(0.5, 0.5, 0, 10**18)):
        with pytest.raises(CagdError, match="MAX_ORDER"):
            call()
    # orders above the degree up to the maximum are zeros
    assert np.all(c.derivatives(0.5, cagd.MAX_ORDER)[4:] == 0)


def test_degrees_above_occt_maximum_do_not_convert():
    """OCCT's maximum degree is 25: the conversion raises CagdError, not an OCCT exception."""
    occ = pytest.importorskip("cagd.occ")
    rng = np.random.default_rng(26)
    assert occ.to_occ(BezierCurve(rng.random((26, 3)))) is not None          # degree 25 converts
    with pytest.raises(CagdError, match="maximum B-spline degree is 25"):
        occ.to_occ(BezierCurve(rng.random((27, 3))))
    with pytest.raises(CagdError, match="maximum B-spline degree is 25"):
        occ.to_occ(BezierSurface(rng.random((3, 30, 3))))


def test_de_casteljau_memory_is_bounded():
    """The seed's algorithms at the maximum degree: de Casteljau kept every level of the
    triangle (1e5 points at degree 128: 20 GB); now one level per chunk."""
    import tracemalloc
    rng = np.random.default_rng(11)
    c = BezierCurve(rng.random((cagd.MAX_DEGREE + 1, 3)))
    t = rng.random(20_000)
    tracemalloc.start()
    try:
        v = c.de_casteljau(t)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200e6
    assert np.abs(v - c(t)).max() <= 1e-13
    s = BezierSurface(rng.random((40, 40, 3)))
    u, v = rng.random((50, 40)), rng.random((50, 40))
    assert np.abs(s.de_casteljau(u, v) - s(u, v)).max() <= 1e-13


@settings(max_examples=20, deadline=None)
@given(p=st.integers(1, cagd.MAX_DEGREE), extra=st.integers(0, 6), seed=st.integers(0, 2**32 - 1),
       rational=st.booleans())
def test_property_bspline_any_degree_matches_scipy(p, extra, seed, rational):
    """Random degree up to MAX_DEGREE, random interior knots, polynomial or rational:
    values and first derivatives equal scipy's de Boor evaluation (homogeneous, then
    divided) within 1e-12 of the net."""
    rng = np.random.default_rng(seed)
    n = p + 1 + extra
    P = rng.random((n, 2)) * 2 - 1
    knots = np.concatenate([np.zeros(p + 1), np.sort(rng.random(extra)), np.ones(p + 1)])
    w = rng.random(n) + 0.5 if rational else None
    c = BSplineCurve(P, p, knots, w)
    t = rng.random(20)
    hom = np.hstack([P * (w if rational else np.ones(n))[:, None], (w if rational else np.ones(n))[:, None]])
    ref = scipy_interpolate.BSpline(knots, hom, p)(t)
    assert np.abs(c(t) - ref[:, :2] / ref[:, 2:]).max() <= 1e-12 * np.abs(P).max() * (3 if rational else 1)
    if not rational:
        d = scipy_interpolate.BSpline(knots, P, p)(t, nu=1)
        assert np.abs(c.derivative(t, 1) - d).max() <= 1e-12 * max(np.abs(d).max(), 1.0)
