"""Trimmed surfaces (issue 15): classification against exact point-in-disk and
point-in-polygon oracles (points off the ON band), areas against closed forms (disk,
annulus, half disk on the domain edge, hemisphere with a pole and a seam, a collapsed
triangle patch) and scipy's dblquad, a periodic face trimmed across its seam against the
same trim away from it, boundary curves against S(c(t)), tessellations, validation
errors naming the loop and curve, values."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy import integrate

import cagd
from cagd import BezierCurve, BSplineCurve, BSplineSurface, CagdError, TrimmedSurface
from cagd.surfaces.trimmed import INSIDE, ON, ON_BAND, OUTSIDE, hermite_fit

RNG = np.random.default_rng(15)
from trim_shapes import (CIRCLE_KNOTS, CIRCLE_WEIGHTS, UNIT, W, circle, circle3d, curved_patch, line,  # noqa: E402,F401
                         periodic_tube, rectangle, square_patch)


# --- the disk ----------------------------------------------------------------------------------
def test_disk_area_and_contains():
    r, c = 0.3, (0.5, 0.45)
    ts = TrimmedSurface(square_patch(2.0), [[circle(c, r)]])
    rep = ts.area_report()
    assert rep.converged and rep.error < 1e-11
    assert ts.area() == pytest.approx(4 * math.pi * r * r, rel=1e-13)
    u, v = RNG.random(200_000), RNG.random(200_000)
    d = np.hypot(u - c[0], v - c[1]) - r
    far = np.abs(d) > 1e-10
    k = ts.classify(u, v)
    assert np.array_equal(k[far], np.where(d[far] < 0, INSIDE, OUTSIDE))
    assert np.array_equal(ts.contains(u, v)[far], d[far] < 0)


@pytest.mark.parametrize("eps", [1e-3, 1e-7, 1e-10])
def test_disk_just_inside_and_outside(eps):
    """Points eps off the circle (rational pieces, refined below the flattening bound)."""
    r, c = 0.3, (0.5, 0.5)
    ts = TrimmedSurface(square_patch(), [[circle(c, r)]])
    th = RNG.random(5000) * 2 * np.pi
    for sign, want in ((1, OUTSIDE), (-1, INSIDE)):
        k = ts.classify(c[0] + (r + sign * eps) * np.cos(th), c[1] + (r + sign * eps) * np.sin(th))
        assert np.all(k == want)


def test_on_band():
    """Points on the circle (to rounding) are ON; ON never reaches 10 ON bands away."""
    r, c = 0.3, (0.5, 0.5)
    ts = TrimmedSurface(square_patch(), [[circle(c, r)]])
    th = RNG.random(2000) * 2 * np.pi
    assert np.all(ts.classify(c[0] + r * np.cos(th), c[1] + r * np.sin(th)) == ON)
    far = 10 * ON_BAND * 2 * r
    assert np.all(ts.classify(c[0] + (r + far) * np.cos(th), c[1] + (r + far) * np.sin(th)) == OUTSIDE)


def test_classify_shapes_and_broadcast():
    ts = TrimmedSurface(square_patch(), [[circle((0.5, 0.5), 0.3)]])
    k = ts.classify(np.linspace(0, 1, 5)[:, None], np.array([[0.5, 0.1]]))
    assert k.shape == (5, 2) and k.dtype == np.int8
    assert k[2, 0] == INSIDE and k[0, 0] == OUTSIDE and k[2, 1] == OUTSIDE
    assert ts.contains(0.5, 0.5).shape == () and bool(ts.contains(0.5, 0.5))


# --- an annulus, a trim on the domain edge, the whole domain --------------------------------------
def test_annulus():
    ts = TrimmedSurface(square_patch(2.0), [[circle((0.5, 0.5), 0.4)], [circle((0.5, 0.5), 0.15, clockwise=True)]])
    assert ts.reoriented == ()
    assert ts.area() == pytest.approx(4 * math.pi * (0.4 ** 2 - 0.15 ** 2), rel=1e-13)
    u, v = RNG.random(100_000), RNG.random(100_000)
    d = np.hypot(u - 0.5, v - 0.5)
    far = (np.abs(d - 0.4) > 1e-10) & (np.abs(d - 0.15) > 1e-10)
    assert np.array_equal(ts.contains(u, v)[far], ((d > 0.15) & (d < 0.4))[far])


def test_half_disk_touching_the_domain_boundary():
    """A half disk whose diameter lies on the edge v = 0 of the domain."""
    r = 0.3
    half = BSplineCurve(UNIT[:5] * r + [0.5, 0.0], 2, [0, 0, 0, .5, .5, 1, 1, 1], CIRCLE_WEIGHTS[:5])
    ts = TrimmedSurface(square_patch(2.0), [[line((0.2, 0.0), (0.8, 0.0)), half]])
    assert ts.area() == pytest.approx(2 * math.pi * r * r, rel=1e-13)
    assert ts.contains(0.5, 0.1) and not ts.contains(0.5, 0.31) and not ts.contains(0.1, 0.05)


def test_whole_domain_loop_is_the_surface_area():
    s = curved_patch()
    ts = TrimmedSurface(s, [rectangle(0, 1, 0, 1)])
    oracle = integrate.dblquad(lambda v, u: float(_jac(s, u, v)), 0, 1, 0, 1, epsabs=1e-13, epsrel=1e-13)[0]
    assert ts.area() == pytest.approx(oracle, rel=1e-10)


def _jac(s, u, v):
    d = s.derivatives(u, v, 1, 1)
    return np.linalg.norm(np.cross(d[1, 0], d[0, 1]))


def test_curved_disk_area_against_dblquad():
    """A disk on a curved bicubic patch: Green's theorem vs scipy's polar dblquad."""
    s = curved_patch()
    r, c = 0.35, (0.5, 0.5)
    ts = TrimmedSurface(s, [[circle(c, r)]])

    def f(rho, th):
        return rho * float(_jac(s, c[0] + rho * math.cos(th), c[1] + rho * math.sin(th)))
    oracle = integrate.dblquad(f, 0, 2 * math.pi, 0, r, epsabs=1e-13, epsrel=1e-12)[0]
    assert ts.area() == pytest.approx(oracle, rel=1e-10)


# --- periodic face across its seam; a pole ------------------------------------------------------------
def test_periodic_face_trimmed_across_its_seam():
    s = periodic_tube()
    across = TrimmedSurface(s, [[circle((0.0, 0.5), 0.1)]])           # u from -0.1 to 0.1
    away = TrimmedSurface(s, [[circle((0.5, 0.5), 0.1)]])             # the same, 4 spans on
    assert across.area() == pytest.approx(away.area(), rel=1e-12)
    u, v = RNG.random(50_000), RNG.random(50_000)
    assert np.array_equal(across.classify(u, v), away.classify(np.mod(u + 0.5, 1.0), v))
    assert across.contains(0.97, 0.5) and across.contains(0.03, 0.5) and not across.contains(0.5, 0.5)


def test_hemisphere_with_a_pole_and_a_seam():
    """The sphere's u = 0 edge is a pole (degenerate), v = 0 and v = 1 its seam; u = 1/2
    is the equator (a knot): the loop u <= 1/2 is a hemisphere, 2 pi R^2."""
    R = 1.5
    s = cagd.sphere(R)
    ts = TrimmedSurface(s, [rectangle(0.0, 0.5, 0.0, 1.0)])
    assert ts.area() == pytest.approx(2 * math.pi * R * R, rel=1e-12)
    b = ts.boundary()
    assert b.exact == ((True, True, True, True),)
    pole = b.curves[0][3](np.linspace(0, 1, 7))                      # the u = 0 edge: one point
    assert np.ptp(pole, axis=0).max() < 1e-14
    equator = b.curves[0][1](np.linspace(0, 1, 50))
    assert np.allclose(np.linalg.norm(equator, axis=1), R, rtol=0, atol=1e-13)
    assert ts.contains(0.01, 0.5) and ts.contains(0.25, 0.999) and not ts.contains(0.75, 0.5)


def test_collapsed_patch_pole():
    """A bilinear patch whose edge v = 1 collapses to a point: |S_u x S_v| = 1 - v."""
    P = np.array([[[0, 0, 0], [0.5, 1, 0]], [[1, 0, 0], [0.5, 1, 0]]], float)
    s = BSplineSurface(P, 1, 1)
    ts = TrimmedSurface(s, [rectangle(0.2, 0.8, 0.0, 1.0)])
    assert ts.area() == pytest.approx(0.3, rel=1e-13)
    assert ts.contains(0.5, 0.999999) and not ts.contains(0.1, 0.5)


# --- twenty curves against a brute-force polygon ----------------------------------------------------
def star(count=20, center=(0.5, 0.5)):
    """A closed chain of ``count`` cubic Bezier curves (a wavy star)."""
    t = np.linspace(0, 2 * np.pi, 3 * count + 1)
    rho = 0.3 + 0.08 * np.sin(5 * t)
    P = np.stack([center[0] + rho * np.cos(t), center[1] + rho * np.sin(t)], axis=1)
    P[-1] = P[0]
    return [BezierCurve(P[3 * i:3 * i + 4]) for i in range(count)]


def test_twenty_curves_against_a_dense_polygon():
    loop = star()
    ts = TrimmedSurface(square_patch(), [loop])
    t = np.linspace(0, 1, 401)
    poly = np.concatenate([c(t)[:-1] for c in loop])
    u, v = RNG.random(10_000), RNG.random(10_000)
    inside = _point_in_polygon(u, v, poly)
    # the dense polygon is within 1e-5 of the curves; its every 4th vertex within 1e-3 of
    # every curve point: compare the points farther than 2e-3 from those
    dist = np.min(np.hypot(u[:, None] - poly[None, ::4, 0], v[:, None] - poly[None, ::4, 1]), axis=1)
    far = dist > 2e-3
    assert far.sum() > 9_000
    assert np.array_equal(ts.contains(u, v)[far], inside[far])


def _point_in_polygon(u, v, poly):
    a, b = poly, np.roll(poly, -1, axis=0)
    inside = np.zeros(len(u), dtype=bool)
    for s in range(0, len(u), 500):
        pu, pv = u[s:s + 500, None], v[s:s + 500, None]
        cond = (a[None, :, 1] > pv) != (b[None, :, 1] > pv)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = a[None, :, 0] + (pv - a[None, :, 1]) * (b[None, :, 0] - a[None, :, 0]) / (b[None, :, 1] - a[None, :, 1])
        inside[s:s + 500] = (np.count_nonzero(cond & (pu < x), axis=1) % 2) == 1
    return inside


def test_star_area_against_the_polygon():
    """On the flat patch the area is side^2 times the loop's own area (Green on the
    exact curves: oint u dv, by Gauss on each cubic: exact)."""
    loop = star()
    ts = TrimmedSurface(square_patch(2.0), [loop])
    x, w = np.polynomial.legendre.leggauss(8)
    t = 0.5 * (x + 1)
    enclosed = sum(float(np.sum(0.5 * w * c(t)[:, 0] * c.derivative(t)[:, 1])) for c in loop)
    assert ts.area() == pytest.approx(4 * enclosed, rel=1e-13)


# --- boundary, tessellation ---------------------------------------------------------------------------
def test_boundary_composes_exactly_or_fits():
    """A circle on the bicubic bump composes exactly (degree 2 (3 + 3) = 12, to rounding),
    the square hole's sides are iso-curves; a quintic pcurve (degree 5 (3 + 3) = 30 >
    MAX_COMPOSED_DEGREE) is fitted within tol; all against S(c(t)) at 301 points."""
    s = curved_patch()
    ts = TrimmedSurface(s, [[circle((0.5, 0.5), 0.3)], [line((0.4, 0.4), (0.4, 0.6)), line((0.4, 0.6), (0.6, 0.6)),
                                                         line((0.6, 0.6), (0.6, 0.4)), line((0.6, 0.4), (0.4, 0.4))]])
    b = ts.boundary(tol=1e-10)
    assert b.converged and b.error == 0.0
    assert b.exact == ((True,), (True, True, True, True))
    assert b.source == (("composition",), ("iso",) * 4)
    assert b.curves[0][0].degree == 12
    for loop, images in zip(ts.loops, b.curves):
        for c, img in zip(loop, images):
            t = np.linspace(*c.domain, 301)
            uv = c(t)
            assert np.abs(img(t) - s(uv[:, 0], uv[:, 1])).max() <= 1e-14
    quintic = BSplineCurve([[0.8, 0.5], [0.7, 0.7], [0.55, 0.9], [0.45, 0.6], [0.3, 0.8], [0.2, 0.5]], 5)
    closer = line((0.2, 0.5), (0.8, 0.5))
    ft = TrimmedSurface(s, [[quintic, closer]])
    b = ft.boundary(tol=1e-10)
    assert b.converged and 0.0 < b.error <= 1e-10
    assert b.source == (("fit", "iso"),) and b.exact == ((False, True),)
    t = np.linspace(0.0, 1.0, 301)
    uv = quintic(t)
    assert np.abs(b.curves[0][0](t) - s(uv[:, 0], uv[:, 1])).max() <= 1.5e-10
    assert b.deviation[0][0] == b.error


def test_hermite_fit_of_a_known_function():
    f = lambda t: np.stack([np.sin(3 * t), np.exp(t)], axis=1)            # noqa: E731
    df = lambda t: np.stack([3 * np.cos(3 * t), np.exp(t)], axis=1)       # noqa: E731
    c, err, ok = hermite_fit(f, df, np.array([0.0, 2.0]), 1e-9)
    t = np.linspace(0, 2, 1001)
    assert ok and np.abs(c(t) - f(t)).max() <= 2e-9 and err <= 1e-9


def test_tessellation_covers_the_annulus():
    s = square_patch(2.0)
    ts = TrimmedSurface(s, [[circle((0.5, 0.5), 0.4)], [circle((0.5, 0.5), 0.15, clockwise=True)]])
    uv, tri = ts.tessellate_uv(12)
    a, b, c = uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]]
    signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert np.all(signed > 0)
    assert signed.sum() == pytest.approx(math.pi * (0.4 ** 2 - 0.15 ** 2), rel=1e-3)
    centroid = (a + b + c) / 3
    assert np.all(ts.contains(centroid[:, 0], centroid[:, 1]))
    V, T = ts.tessellate(12)
    assert V.shape == (len(uv), 3) and np.array_equal(T, tri)


# --- validation, orientation, values --------------------------------------------------------------------
def test_clockwise_outer_loop_is_reversed():
    ts = TrimmedSurface(square_patch(2.0), [[circle((0.5, 0.5), 0.3, clockwise=True)]])
    assert ts.reoriented == (0,)
    assert ts.area() == pytest.approx(4 * math.pi * 0.09, rel=1e-13)


@pytest.mark.parametrize("loops, message", [
    ([[line((0.1, 0.1), (0.9, 0.1)), line((0.9, 0.1), (0.5, 0.9)), line((0.5, 0.9), (0.1, 0.2))]],
     r"loops\[0\]\[2\]: ends at .* gap of 0.1 "),
    ([[circle((0.5, 0.5), 0.6)]], r"loops\[0\]\[0\]: leaves the surface's domain"),
    ([[circle((0.4, 0.5), 0.3)], [circle((0.7, 0.5), 0.2, clockwise=True)]],
     r"loops: loops\[0\]\[0\] crosses loops\[1\]"),
    ([[circle((0.3, 0.3), 0.2)], [circle((0.75, 0.75), 0.1, clockwise=True)]], r"loops\[1\]: the hole lies outside"),
    ([[circle((0.5, 0.5), 0.4)], [circle((0.5, 0.5), 0.3, True)], [circle((0.5, 0.5), 0.1, True)]],
     r"loops\[2\]: the hole lies inside the hole loops\[1\]"),
    ([[BSplineCurve([[0, 0, 0], [1, 1, 1]], 1)]], r"loops\[0\]\[0\]: expected a 2-D curve"),
    ([], r"loops: expected a non-empty"),
    ([[]], r"loops\[0\]: expected a non-empty"),
    ([["x"]], r"loops\[0\]\[0\]: expected an engine curve"),
    ([[line((0.2, 0.2), (0.8, 0.2)), line((0.8, 0.2), (0.2, 0.2))]], r"loops\[0\]: encloses no area"),
    ([[BSplineCurve([[0.1, 0.1], [0.9, 0.1], [0.1, 0.9], [0.6, 0.9], [0.1, 0.1]], 1)]],     # a bow tie, one curve
     r"loops: loops\[0\]\[0\] crosses itself near \(u, v\) = \(0.407692308, 0.592307692\)"),
    ([[BSplineCurve([[0.2, 0.2], [0.5, 0.2], [0.8, 0.2], [0.5, 0.5], [0.3, 0.7], [0.5, 0.7], [0.7, 0.7],
                     [0.5, 0.5], [0.2, 0.2]], 3)]],                                         # a cubic figure eight
     r"loops: loops\[0\]\[0\] crosses itself near \(u, v\) = \(0\.49\d*, 0\.50"),
])
def test_invalid_loops(loops, message):
    with pytest.raises(CagdError, match=message):
        TrimmedSurface(square_patch(), loops)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _segments_cross(P):
    """Brute force: two non-adjacent sides of the closed polygon P properly cross."""
    n = len(P)
    for a in range(n):
        for b in range(a + 2, n):
            if (b + 1) % n == a:
                continue
            p, q, r, s = P[a], P[(a + 1) % n], P[b], P[(b + 1) % n]
            o = [_cross(q - p, r - p), _cross(q - p, s - p), _cross(s - r, p - r), _cross(s - r, q - r)]
            if o[0] * o[1] < 0 and o[2] * o[3] < 0:
                return True
    return False


@settings(max_examples=80, deadline=None)
@given(st.lists(st.tuples(st.floats(0.05, 0.95), st.floats(0.05, 0.95)), min_size=3, max_size=9, unique=True))
def test_a_polygon_as_one_curve_is_refused_iff_its_sides_cross(pts):
    """A loop of one degree-1 curve crosses itself exactly where two of its sides cross
    (brute force over the sides); before, pieces of one curve were never compared and a
    self-crossing loop was taken, its area and tessellation wrong."""
    P = np.array(pts)
    twice = np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1])
    sides = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    assume(abs(twice) > 1e-3 and sides.min() > 1e-3)
    crossing = _segments_cross(P)
    # near-touching configurations (within the crossing test's rounding) are left out
    D = _cross(np.roll(P, -1, axis=0) - P, P[:, None] - P)        # D[a, b]: P[a] against side b
    assume(np.abs(D)[np.abs(D) > 0].min() > 1e-9)
    loop = BSplineCurve(np.vstack([P, P[:1]]), 1)
    if crossing:
        with pytest.raises(CagdError, match=r"loops\[0\]\[0\] crosses itself"):
            TrimmedSurface(square_patch(1.0), [[loop]])
    else:
        ts = TrimmedSurface(square_patch(1.0), [[loop]])
        assert ts.area() == pytest.approx(abs(twice) / 2, rel=1e-12)


def test_invalid_surface_and_tol():
    ts = TrimmedSurface(square_patch(), [[circle((0.5, 0.5), 0.3)]])
    with pytest.raises(CagdError, match="surface: expected an engine Surface"):
        TrimmedSurface(ts, [[circle((0.5, 0.5), 0.3)]])
    with pytest.raises(CagdError, match="tol: must be positive"):
        TrimmedSurface(square_patch(), [[circle((0.5, 0.5), 0.3)]], tol=0.0)
    with pytest.raises(CagdError, match="u, v: shapes"):
        ts.classify(np.zeros(3), np.zeros(4))


def test_a_gap_within_tol_is_closed():
    loop = [line((0.1, 0.1), (0.9, 0.1)), line((0.9, 0.1), (0.5, 0.9)), line((0.5, 0.9), (0.1, 0.1 + 1e-6))]
    ts = TrimmedSurface(square_patch(1.0), [loop], tol=1e-5)
    assert ts.area() == pytest.approx(0.5 * 0.8 * 0.8, rel=1e-5)


def test_value_and_delegation():
    s = curved_patch()
    ts = TrimmedSurface(s, [[circle((0.5, 0.5), 0.3)]])
    with pytest.raises(AttributeError):
        ts.loops = ()
    assert not ts.loops[0][0].control_points.flags.writeable
    assert ts.untrimmed is s and ts.domain == s.domain
    u, v = RNG.random(10), RNG.random(10)
    assert np.array_equal(ts(u, v), s(u, v))
    assert np.array_equal(ts.normals(u, v)[0], s.normals(u, v)[0])
    moved = ts.transformed(np.eye(3), [1.0, 2.0, 3.0])
    assert isinstance(moved, TrimmedSurface) and np.allclose(moved(u, v), s(u, v) + [1, 2, 3])
    assert moved.area() == pytest.approx(ts.area(), rel=1e-13)


# --- boundary(): exact compositions and known edge curves ------------------------------------------------
def test_disk_on_a_plane_composes_to_the_exact_circle():
    """S(u, v) = (2 u, 2 v, 0) and the circle of centre (0.5, 0.5), radius 0.3: S(c(t)) is
    the circle of centre (1, 1, 0), radius 0.6 (closed form), a rational quartic
    (degree 2 (1 + 1)) equal to S(c(t)) at the same t; both to 1e-12 (measured 2e-16)."""
    s = square_patch(2.0)
    ts = TrimmedSurface(s, [[circle((0.5, 0.5), 0.3)]])
    b = ts.boundary()
    assert b.source == (("composition",),) and b.exact == ((True,),) and b.error == 0.0
    C = b.curves[0][0]
    assert C.degree == 4 and C.is_rational and C.domain == ts.loops[0][0].domain
    t = np.linspace(*C.domain, 2001)
    P = C(t)
    assert np.abs(np.hypot(P[:, 0] - 1.0, P[:, 1] - 1.0) - 0.6).max() <= 1e-12
    assert np.abs(P[:, 2]).max() <= 1e-12
    uv = ts.loops[0][0](t)
    assert np.abs(P - s(uv[:, 0], uv[:, 1])).max() <= 1e-12
    assert b.deviation[0][0] <= 1e-12


def test_polynomial_pcurve_across_knot_lines_composes_exactly():
    """A cubic pcurve crossing the knot lines u = v = 1/2 of a bicubic with an interior
    knot in each direction: degree 3 (3 + 3) = 18,
    C0 pieces split at the crossings, S(c(t)) to 1e-12 at 3001 points."""
    x = np.linspace(0, 1, 5)
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = 0.2 * np.sin(4 * X + 1) * np.cos(3 * Y)
    knots = [0, 0, 0, 0, 0.5, 1, 1, 1, 1]
    s = BSplineSurface(np.stack([X, Y, Z], axis=-1), 3, 3, knots, knots)
    a = BSplineCurve([[0.1, 0.2], [0.5, 0.05], [0.9, 0.3], [0.9, 0.9]], 3)
    back = BSplineCurve([[0.9, 0.9], [0.5, 0.95], [0.1, 0.6], [0.1, 0.2]], 3)
    ts = TrimmedSurface(s, [[a, back]])
    b = ts.boundary()
    assert b.source == (("composition", "composition"),)
    for c, img in zip(ts.loops[0], b.curves[0]):
        assert img.degree == 18
        t = np.linspace(*c.domain, 3001)
        uv = c(t)
        assert np.abs(img(t) - s(uv[:, 0], uv[:, 1])).max() <= 1e-12


def test_known_edges_are_the_boundary_with_their_measured_distance():
    """edges given to the constructor come back from boundary() as they are, with their
    distance from S(c(t)): 0 for the exact image, 1e-3 for one lifted by 1e-3 (closed
    form), to 1e-12; a curve without an edge (None) is composed."""
    s = square_patch(2.0)
    disk, hole = circle((0.5, 0.5), 0.3), circle((0.5, 0.5), 0.1, clockwise=True)
    lifted = circle3d((1.0, 1.0, 1e-3), 0.6)
    ts = TrimmedSurface(s, [[disk], [hole]], edges=[[lifted], [None]])
    assert ts.edges == ((lifted,), (None,))
    b = ts.boundary()
    assert b.source == (("edge",), ("composition",)) and b.exact == ((False,), (True,))
    assert b.curves[0][0] is lifted
    assert b.deviation[0][0] == pytest.approx(1e-3, abs=1e-12) and b.edge_error == b.deviation[0][0]
    exact = TrimmedSurface(s, [[disk]], edges=[[circle3d((1.0, 1.0, 0.0), 0.6)]]).boundary()
    assert exact.edge_error <= 1e-12


def test_edges_follow_reorientation_and_affine_maps():
    """A clockwise outer loop is reversed with its edges (each edge still starts where its
    pcurve's image starts); transformed() moves the edges with the surface."""
    s = square_patch(2.0)
    cw = circle((0.5, 0.5), 0.3, clockwise=True)
    edge = circle3d((1.0, 1.0, 0.0), 0.6).reversed()
    ts = TrimmedSurface(s, [[cw]], edges=[[edge]])
    assert ts.reoriented == (0,)
    (e,), (c,) = ts.edges[0], ts.loops[0]
    t = np.linspace(*c.domain, 101)
    uv = c(t)
    assert np.abs(e(t) - s(uv[:, 0], uv[:, 1])).max() <= 1e-12
    A = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0]])
    moved = ts.transformed(A, [1.0, 2.0, 3.0])
    assert np.allclose(moved.edges[0][0](t), e(t) @ A.T + [1.0, 2.0, 3.0], rtol=0, atol=1e-13)
    assert moved.boundary().edge_error <= 1e-12


@pytest.mark.parametrize("edges, message", [
    ([[None], [None]], r"edges: expected one sequence of edge curves \(or None\) per loop \(1\)"),
    ([[None, None]], r"edges\[0\]: expected one edge curve \(or None\) per curve of loops\[0\] \(1\)"),
    ([["x"]], r"edges\[0\]\[0\]: expected an engine curve or None, got str"),
    ([[circle((0.5, 0.5), 0.3)]], r"edges\[0\]\[0\]: a 2-D curve for a 3-D surface"),
    ([[circle3d((1, 1, 0), 0.6).reparametrized(0.0, 2.0)]], r"edges\[0\]\[0\]: runs over \[0, 2\], its pcurve"),
])
def test_invalid_edges(edges, message):
    with pytest.raises(CagdError, match=message):
        TrimmedSurface(square_patch(2.0), [[circle((0.5, 0.5), 0.3)]], edges=edges)


def test_edges_all_none_is_no_edges_and_values_keep_them():
    import copy
    import pickle
    s = square_patch(2.0)
    assert TrimmedSurface(s, [[circle((0.5, 0.5), 0.3)]], edges=[[None]]).edges is None
    ts = TrimmedSurface(s, [[circle((0.5, 0.5), 0.3)]], edges=[[circle3d((1, 1, 0), 0.6)]])
    with pytest.raises(AttributeError, match="engine objects are values"):
        ts.edges = None
    assert copy.deepcopy(ts) is ts
    back = pickle.loads(pickle.dumps(ts))
    assert np.array_equal(back.edges[0][0].control_points, ts.edges[0][0].control_points)
    assert not back.edges[0][0].control_points.flags.writeable


def test_composition_across_a_periodic_seam_and_on_a_torus():
    """A disk across the seam of the periodic tube (u from -0.1 to 0.1: spans found by
    whole periods) and one on the torus (rational both ways): exact compositions of
    degree 8, against S(c(t)) at 2001 points to 1e-14 of the size (measured 6.7e-16 and
    6e-16)."""
    for s, c in ((periodic_tube(), circle((0.0, 0.5), 0.1)), (cagd.torus(10, 3), circle((0.5, 0.5), 0.3))):
        ts = TrimmedSurface(s, [[c]])
        b = ts.boundary()
        assert b.source == (("composition",),) and b.curves[0][0].degree == 8
        t = np.linspace(*c.domain, 2001)
        uv = c(t)
        assert np.abs(b.curves[0][0](t) - s(uv[:, 0], uv[:, 1])).max() <= 1e-14 * ts.size


def test_area_of_a_loop_leaving_the_domain_counts_only_the_surface():
    """A loop may leave a bounded direction by its tol (11752.stp face 407: by 8e-4 in u):
    there is no surface there, so the sliver adds nothing. Before, the density at the
    clipped point was integrated over it (that face: 3.8e-4 of its area too much; now it
    agrees with BRepGProp and a fine mesh to 5e-8). Square patch of side 2: area 4 x the
    (u, v) area of the rectangle clipped to [0, 1]^2."""
    from trim_shapes import rectangle, square_patch
    for u0, v1 in ((-8e-4, 0.7), (0.2, 1.0 + 5e-4)):
        ts = TrimmedSurface(square_patch(), [rectangle(u0, 0.9, 0.1, v1)], tol=1e-3)
        clipped = (0.9 - max(u0, 0.0)) * (min(v1, 1.0) - 0.1)
        assert ts.area() == pytest.approx(4.0 * clipped, rel=1e-12)
