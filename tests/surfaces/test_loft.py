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
from cagd.surfaces.loft import (SEAM_SHIFT, aligned_sections, loft, loft_parameters, make_compatible,
                                rotated_start, ruled)
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
    """Polynomial and rational sections of any kind, as given (align=False); rational
    data whose homogeneous interpolation has non-positive control weights is rejected
    (tested separately)."""
    q = min(q, len(sections) - 1)
    for k, c in enumerate(sections):                     # keep consecutive sections apart
        sections[k] = c.transformed(np.eye(3), [0.0, 0.0, 25.0 * k])
    try:
        L = loft(sections, q, method, align=False)       # (closed sections would be re-started)
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
        loft([a, b], 0)
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


# --- degree cap, closed sections, guides ----------------------------------------------------
def test_degree_v_is_capped_by_the_section_count():
    """Two sections give the ruled surface (degree 1 across), three at most degree 2."""
    a = BSplineCurve(RNG.normal(size=(5, 3)), 3)
    b = BSplineCurve(RNG.normal(size=(4, 3)) + [0, 0, 3.0], 2)
    L, R = loft([a, b]), ruled(a, b)
    assert L.degree_v == 1 and L.control_points.shape == R.control_points.shape
    assert np.abs(L.control_points - R.control_points).max() <= 1e-13
    assert loft([a, b, a.transformed(np.eye(3), [0, 0, 6.0])], 3).degree_v == 2


def periodic_circle(radius, z, phase, reverse=False, count=8):
    """A periodic cubic B-spline on ``count`` control points on the circle (radius,
    height z) from angle ``phase``: a closed C2 curve near the circle."""
    ang = phase + (-1.0 if reverse else 1.0) * 2 * np.pi * np.arange(count) / count
    P = np.stack([radius * np.cos(ang), radius * np.sin(ang), np.full(count, z)], 1)
    return BSplineCurve(P, 3, periodic=True)


def rational_circle(radius, z, phase, reverse=False):
    """The exact NURBS circle (radius, height z) starting at angle ``phase`` (clamped,
    closed), clockwise when ``reverse``."""
    c, s, w, knots = arc_parameters(0.0, 2 * np.pi)
    ang = np.arctan2(s, c) * (-1.0 if reverse else 1.0) + phase
    rho = np.hypot(c, s)
    return BSplineCurve(np.stack([radius * rho * np.cos(ang), radius * rho * np.sin(ang), np.full_like(c, z)], 1),
                        2, knots, w)


def angle_of(P):
    return np.arctan2(P[..., 1], P[..., 0])


PHASES, RADII, HEIGHTS = [0.3, 1.9, -2.2, 0.9], [2.0, 2.5, 1.5, 2.2], [0.0, 1.0, 2.5, 4.0]


def test_closed_sections_are_aligned_before_skinning():
    """Coaxial circles started at other angles, two of them running the other way:
    aligned, every section starts at section 0's start angle and runs the same way, so
    the seam S(0, v) stays in one half-plane and the skin does not twist (every point on
    a circle of its height's radius at v_k); without alignment it twists."""
    from cagd.queries import closest_point
    secs = [rational_circle(r, z, f, reverse=(k % 2 == 1)) for k, (r, z, f) in enumerate(zip(RADII, HEIGHTS, PHASES))]
    L = loft(secs)
    v = loft_parameters(aligned_sections(secs))
    seam = L(np.zeros(len(v)), v)
    assert np.abs(angle_of(seam) - 0.3).max() <= 1e-9
    ahead = angle_of(L(np.full(len(v), 0.01), v)) - angle_of(seam)
    assert np.all(ahead > 0)                            # every section runs counter-clockwise
    for vk, c, r in zip(v, secs, RADII):
        assert np.abs(np.hypot(*L(S_, vk)[:, :2].T) - r).max() <= 1e-12 * 4
        assert closest_point(c, L(S_, vk)).distances.max() <= 1e-12 * 4
    twisted = loft(secs, align=False)
    assert np.abs(angle_of(twisted(np.zeros(len(v)), loft_parameters(secs))) - 0.3).max() > 1.0


def test_periodic_sections_loft_closed_and_smooth_across_the_seam():
    """Periodic cubic sections (C2 closed) started elsewhere and reversed: each aligned
    section starts at its point nearest the previous section's start (within SEAM_SHIFT
    of its parameter range), and the skin is
    closed with the sections' C2 across the seam (parametric: equal partials at u = 0, 1)."""
    from cagd.queries import closest_point
    secs = [periodic_circle(r, z, f, reverse=(k % 2 == 1)) for k, (r, z, f) in enumerate(zip(RADII, HEIGHTS, PHASES))]
    al = aligned_sections(secs)
    for prev, c in zip(al, al[1:]):               # started at the foot, or within SEAM_SHIFT of it
        t = float(closest_point(c, prev(0.0)[None]).params[0])
        assert min(t, 1.0 - t) <= SEAM_SHIFT
    moved = [min(t, 1 - t) for t in (float(closest_point(c, p(0.0)[None]).params[0]) for p, c in zip(al, secs[1:]))]
    assert max(moved) > 0.1                         # the sections' own starts were far from the feet
    L = loft(secs)
    vs = np.linspace(0, 1, 23)
    for du in range(3):
        d0 = L.derivatives(np.zeros_like(vs), vs, du, 0)[du, 0]
        d1 = L.derivatives(np.ones_like(vs), vs, du, 0)[du, 0]
        assert np.abs(d0 - d1).max() <= 1e-9 * (1 + np.abs(d0).max())
    for vk, c in zip(loft_parameters(al), secs):
        assert closest_point(c, L(S_, vk)).distances.max() <= 1e-12 * 4


def test_rotated_start_keeps_a_rational_circle():
    """The exact NURBS circle re-started at t = 0.3 (not a knot): the same circle, starting
    at c(0.3), with parameters shifted by 0.3 (mod 1)."""
    c, s, w, knots = arc_parameters(0.0, 2 * np.pi)
    circle = BSplineCurve(np.stack([2 * c, 2 * s], 1), 2, knots, w)
    r, moved = rotated_start(circle, 0.3)
    t = np.linspace(0, 1, 201)
    assert moved <= 1e-15 and r.is_rational
    assert np.abs(np.hypot(*r(t).T) - 2.0).max() <= 1e-14
    assert np.abs(r(t) - circle((t + 0.3) % 1.0)).max() <= 1e-13


def test_loft_with_guides_is_the_gordon_surface():
    """Sections and guides: the Gordon surface (both families interpolated)."""
    from cagd import gordon
    X, Y = np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij")
    patch = BSplineSurface(np.stack([X, Y, np.zeros((5, 5))], -1) + RNG.normal(size=(5, 5, 3)) * 0.2, 3, 3)
    sections = [patch.isocurve("u", u) for u in (0.0, 0.5, 1.0)]
    guides = [patch.isocurve("v", v) for v in (0.0, 0.4, 1.0)]
    S = loft(sections, guides=guides)
    G = gordon(sections, guides).surface
    assert np.abs(S.control_points - G.control_points).max() == 0.0
    for g in guides:
        from cagd.queries import closest_point
        assert closest_point(S, g(np.linspace(*g.domain, 31))).distances.max() <= 1e-6
    with pytest.raises(CagdError, match="degree_v, parameters"):
        loft(sections, 2, guides=guides)
