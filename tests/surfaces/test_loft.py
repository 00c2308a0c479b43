"""Compatible curves, ruled and skinned surfaces (Piegl & Tiller 8.4, 10.3): every
curve unchanged by make_compatible, ruled = the linear blend (rational: the same
rulings), loft through every section exactly, the v columns equal scipy's
interpolating splines, lofted circles stay on their cylinder, errors."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.interpolate import make_interp_spline

from cagd import BezierCurve, BSplineCurve, BSplineSurface, CagdError, HermiteCurve, natural_cubic_spline
from cagd.surfaces.loft import loft, loft_parameters, make_compatible, ruled
from cagd.surfaces.revolution import arc_parameters

from strategies import bspline_curves

SETTINGS = settings(max_examples=40, deadline=None)
S_ = np.linspace(0.0, 1.0, 61)
RNG = np.random.default_rng(5)


def unit(curve, s):
    a, b = curve.domain
    return curve(a + s * (b - a))


def scale_of(curves):
    return max(float(np.abs(c.control_points).max()) for c in curves) + 1.0


curve_lists = st.lists(bspline_curves(dims=(3, 3), max_degree=5), min_size=1, max_size=4)


# --- make_compatible -----------------------------------------------------------------------------
@SETTINGS
@given(curve_lists)
def test_make_compatible_keeps_every_curve(curves):
    out = make_compatible(curves)
    p = max(c.degree for c in curves)
    assert all(c.degree == p for c in out)
    assert all(np.array_equal(c.knots, out[0].knots) for c in out)
    assert out[0].knots[0] == 0.0 and out[0].knots[-1] == 1.0
    rational = any(c.is_rational for c in curves)
    assert all(c.is_rational == rational for c in out)
    for c, d in zip(curves, out):
        assert np.abs(d(S_) - unit(c, S_)).max() <= 1e-11 * scale_of([c])


def test_make_compatible_any_engine_curve_and_errors():
    curves = [BezierCurve([[0, 0, 0], [1, 2, 0], [2, 0, 1.0]]),
              HermiteCurve([0, 0, 0], [1, 1, 1], [1, 0, 0], [0, 1, 0]),
              natural_cubic_spline([[0, 0, 0], [1, 1, 0], [2, 0, 0], [3, 1, 1.0]])]
    out = make_compatible(curves)
    for c, d in zip(curves, out):
        assert np.abs(d(S_) - unit(c, S_)).max() <= 1e-14 * 4
    # knots: the union of the spline's breakpoints (chord parameters) and nothing else
    a, b = curves[2].domain
    inner = (curves[2].parameters[1:-1] - a) / (b - a)
    assert np.allclose(np.unique(out[0].knots[(out[0].knots > 0) & (out[0].knots < 1)]), inner, rtol=1e-14)
    with pytest.raises(CagdError, match="curves"):
        make_compatible([])
    with pytest.raises(CagdError, match=r"curves\[1\]"):
        make_compatible([curves[0], 3.0])
    with pytest.raises(CagdError, match="same dimension"):
        make_compatible([curves[0], BezierCurve([[0, 0], [1, 1.0]])])


def test_knots_a_few_ulps_apart_are_merged():
    """1/3 reached by two different roundings is one knot, not two tiny spans."""
    c1 = BSplineCurve(RNG.normal(size=(5, 3)), 3, [0, 0, 0, 0, 1 / 3, 1, 1, 1, 1])
    c2 = BSplineCurve(RNG.normal(size=(5, 3)), 3, [0, 0, 0, 0, 1, 3, 3, 3, 3])
    out = make_compatible([c1, c2])
    assert len(out[0].knots) == 9
    for c, d in zip([c1, c2], out):
        assert np.abs(d(S_) - unit(c, S_)).max() <= 1e-14 * 4


# --- ruled surfaces --------------------------------------------------------------------------------
@SETTINGS
@given(bspline_curves(dims=(3, 3), max_degree=5, rational=False),
       bspline_curves(dims=(3, 3), max_degree=5, rational=False))
def test_ruled_is_the_linear_blend(c0, c1):
    R = ruled(c0, c1)
    assert isinstance(R, BSplineSurface) and R.degree_v == 1
    u, v = RNG.random(300), RNG.random(300)
    expected = (1 - v)[:, None] * unit(c0, u) + v[:, None] * unit(c1, u)
    assert np.abs(R(u, v) - expected).max() <= 1e-11 * scale_of([c0, c1])


@SETTINGS
@given(bspline_curves(dims=(3, 3), max_degree=4, rational=True),
       bspline_curves(dims=(3, 3), max_degree=4))
def test_ruled_rational_has_the_same_rulings(c0, c1):
    """Homogeneous blend: S = c0 + lam (c1 - c0), lam = v w1 / ((1 - v) w0 + v w1), with
    w0, w1 the curves' weight functions (the weights' own B-spline)."""
    R = ruled(c0, c1)
    a, b = make_compatible([c0, c1])
    u, v = RNG.random(300), RNG.random(300)
    w0 = BSplineCurve(a.weights, a.degree, a.knots)(u)[:, 0]
    w1 = BSplineCurve(b.weights, b.degree, b.knots)(u)[:, 0]
    lam = (v * w1 / ((1 - v) * w0 + v * w1))[:, None]
    expected = unit(c0, u) + lam * (unit(c1, u) - unit(c0, u))
    assert np.abs(R(u, v) - expected).max() <= 1e-11 * scale_of([c0, c1])


# --- skinning --------------------------------------------------------------------------------------
@SETTINGS
@given(st.lists(bspline_curves(dims=(3, 3), max_degree=4), min_size=2, max_size=6),
       st.integers(1, 5), st.sampled_from(["chord", "centripetal", "uniform"]))
def test_loft_passes_through_every_section(sections, q, method):
    """Polynomial and rational sections of any kind; rational data whose homogeneous
    interpolation has non-positive control weights is rejected (tested separately)."""
    q = min(q, len(sections) - 1)
    for k, c in enumerate(sections):                     # keep consecutive sections apart
        sections[k] = c.transformed(np.eye(3), [0.0, 0.0, 25.0 * k])
    try:
        L = loft(sections, q, method)
    except CagdError as exc:
        assert "non-positive weights" in str(exc) and any(c.is_rational for c in sections)
        assume(False)
    v = loft_parameters(sections, method)
    assert L.degree_v == q and v[0] == 0.0 and v[-1] == 1.0 and np.all(np.diff(v) > 0)
    eps = 1e-10 * scale_of(sections)
    for vk, c in zip(v, sections):
        assert np.abs(L(S_, vk) - unit(c, S_)).max() <= eps
        iso = L.isocurve("u", vk)
        assert np.abs(iso(S_) - unit(c, S_)).max() <= eps


def test_loft_columns_are_scipy_interpolants():
    """Each column of the net is the interpolating spline of the sections' control
    points at the chord parameters with averaged knots (scipy.make_interp_spline)."""
    sections = [BSplineCurve(RNG.normal(size=(6, 3)) + [0, 0, 2.0 * k], 3) for k in range(5)]
    L = loft(sections, 3)
    v = loft_parameters(sections)
    Q = np.stack([c.control_points for c in sections])             # (5, 6, 3)
    knots = np.concatenate([[0] * 4, [(v[1] + v[2] + v[3]) / 3], [1] * 4])
    assert np.allclose(L.knots_v, knots, rtol=0, atol=1e-15)
    for i in range(6):
        spl = make_interp_spline(v, Q[:, i], k=3, t=knots)
        assert np.abs(L.control_points[i] - spl.c).max() <= 1e-12
    # chord parameters: the average over the columns of the normalised cumulative chords
    d = np.linalg.norm(np.diff(Q, axis=0), axis=2)
    expected = np.concatenate([[0], np.mean(np.cumsum(d, axis=0) / d.sum(axis=0), axis=1)])
    assert np.allclose(v, expected, rtol=0, atol=1e-15)


def test_lofted_circles_stay_on_the_cylinder():
    """Rational sections (circles of radius 2 at heights z_k) interpolated in homogeneous
    space: every point has x^2 + y^2 = 4 and the isocurves at v_k are the circles."""
    c, s, w, knots = arc_parameters(0.0, 2 * np.pi)
    heights = [0.0, 1.0, 1.5, 4.0, 4.5]
    sections = [BSplineCurve(np.stack([2 * c, 2 * s, np.full_like(c, z)], 1), 2, knots, w) for z in heights]
    L = loft(sections)
    P = L.grid(np.linspace(0, 1, 101), np.linspace(0, 1, 101))
    assert np.abs(np.hypot(P[..., 0], P[..., 1]) - 2.0).max() <= 1e-14 * 5
    for vk, z in zip(loft_parameters(sections), heights):
        assert np.abs(L(S_, vk)[:, 2] - z).max() <= 1e-14 * 5


def test_loft_errors():
    a = BSplineCurve(RNG.normal(size=(4, 3)), 3)
    b = BSplineCurve(RNG.normal(size=(4, 3)), 2)
    with pytest.raises(CagdError, match="sections"):
        loft([a])
    with pytest.raises(CagdError, match="degree_v"):
        loft([a, b], 3)
    with pytest.raises(CagdError, match=r"sections\[0\] and sections\[1\] coincide"):
        loft([a, a, b], 2)
    with pytest.raises(CagdError, match="parameters"):
        loft([a, b, a], 2, "arc")
    with pytest.raises(CagdError, match="parameters"):
        loft([a, b, a], 2, [0.0, 0.7, 0.5])
    with pytest.raises(CagdError, match="parameters"):
        loft([a, b, a], 2, [0.0, 1.0])
    L = loft([a, b, a], 2, [0.0, 0.25, 1.0])                    # explicit parameters
    assert np.abs(L(S_, 0.25) - b(S_)).max() <= 1e-13
    w = BSplineCurve(a.control_points, 3, None, [1.0, 50.0, 50.0, 1.0])
    z = BSplineCurve(b.control_points, 2, None, [50.0, 0.02, 0.02, 50.0])
    with pytest.raises(CagdError, match="non-positive weights"):
        loft([w, z, w, z], 3, "uniform")
