"""Global minimum distance with a certified lower bound (issue 8): analytic oracles
(sphere-sphere, circle-line, crossing curves), a brute-force oracle (dense sampling)
and OCCT (GeomAPI_ExtremaCurveCurve / ExtremaCurveSurface): the engine's distance is
never larger than OCCT's by more than 1e-9 relative; cases where it is smaller (OCCT
missed the global minimum) are printed. Continua of minima (issue 13: a torus and a
sphere at its centre, concentric spheres and arcs, coaxial cylinders, parallel patches,
a circle about a sphere) converge with isolated=False against closed forms; isolated
minima, also several of equal distance, and touches at one point report isolated=True."""
import dataclasses

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from cagd import BezierCurve, BezierSurface, BSplineCurve, BSplineSurface, CagdError, cylinder, sphere, torus
from cagd.queries.distance import DistanceResult, min_distance
from cagd.surfaces.revolution import arc_parameters

from surface_strategies import bspline_surfaces

W = np.sqrt(0.5)


def circle(center, r):
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float) * r
    return BSplineCurve(P + center, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, W, 1, W, 1, W, 1, W, 1])


def arc(center, r, start, angle, z=None):
    """Rational quadratic arc (Piegl & Tiller A7.1) in the plane, or at height z in 3-D."""
    c, s, w, knots = arc_parameters(start, angle)
    P = np.c_[c, s] * r + center
    return BSplineCurve(P if z is None else np.c_[P, np.full(len(P), z)], 2, knots, w)


def rotation(seed):
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def check_certificate(res):
    assert res.converged, res.message
    assert res.lower_bound <= res.distance and res.gap <= res.tol
    assert abs(np.linalg.norm(res.points[0] - res.points[1]) - res.distance) <= 1e-15 * max(1.0, res.distance)


def check_exact(res, exact):
    """Converged, the true minimum ``exact`` inside [lower_bound, distance] (up to rounding
    of the distance, 1e-12), and the distance within 1e-9 of it."""
    check_certificate(res)
    assert res.lower_bound <= exact <= res.distance + 1e-12 and abs(res.distance - exact) <= 1e-9


@pytest.mark.parametrize("c1, r1", [((3.0, 1.0, 0.0), 0.5), ((0.3, -2.5, 1.2), 0.25)])
def test_sphere_sphere(c1, r1):
    res = min_distance(sphere(1.0, (0, 0, 0)), sphere(r1, c1))
    exact = np.linalg.norm(c1) - 1.0 - r1
    check_certificate(res)
    assert abs(res.distance - exact) <= 1e-9 and res.lower_bound <= exact + 1e-15
    assert res.isolated                                      # one pair of points, on the line of centres
    np.testing.assert_allclose(res.points[0], np.asarray(c1) / np.linalg.norm(c1), atol=1e-7)


def test_circle_line():
    res = min_distance(circle((0.3, 0.2), 1.0), BezierCurve([[-3, 2.5], [3, 1.9]]))
    p0, d = np.array([-3, 2.5]), np.array([6, -0.6])
    n = np.array([-d[1], d[0]]) / np.linalg.norm(d)
    exact = abs((np.array([0.3, 0.2]) - p0) @ n) - 1.0
    check_certificate(res)
    assert abs(res.distance - exact) <= 1e-9 and res.lower_bound <= exact + 1e-15


def test_crossing_curves_have_distance_zero():
    res = min_distance(circle((0, 0), 1.0), circle((1.2, 0.3), 0.8))
    assert res.distance <= 1e-9 and res.lower_bound == 0.0


def test_torus_and_sphere_inside_the_hole():
    res = min_distance(torus(3.0, 1.0, (0, 0, 0)), sphere(0.5, (0.5, 0, 0)))   # hole radius 2
    check_certificate(res)
    assert abs(res.distance - 1.0) <= 1e-9


def test_torus_and_sphere_at_its_centre():
    # the README's example: the minimum 5 is attained on a whole circle (the torus's inner
    # equator, radius 7, against the sphere's equator, radius 2); it ran into the depth
    # limit with 3670 pairs alive and converged=False
    res = min_distance(torus(10, 3), sphere(2.0))
    check_exact(res, 5.0)
    assert not res.isolated
    p, q = res.points
    assert abs(np.hypot(p[0], p[1]) - 7.0) <= 1e-9 and abs(p[2]) <= 1e-9 and abs(np.linalg.norm(q) - 2.0) <= 1e-12
    assert np.linalg.norm(np.cross(p, q)) <= 1e-8                   # on one ray from the centre


def test_circle_of_minima_with_a_small_pair_cap():
    res = min_distance(torus(3.0, 1.0, (0, 0, 0)), sphere(0.5, (0, 0, 0)), max_pairs=2000)
    check_exact(res, 1.5)
    assert not res.isolated


@pytest.mark.parametrize("seed", [0, 1])
def test_concentric_spheres(seed):
    # every point of the inner sphere is 2 from the outer one: a 2-D continuum of minima;
    # turned about their centre the two parametrisations do not line up
    c = np.array([0.3, -1.2, 0.7])
    outer = sphere(3.0, (0, 0, 0)).transformed(rotation(seed), c)
    res = min_distance(sphere(1.0, c), outer)
    check_exact(res, 2.0)
    assert not res.isolated


def test_parallel_patches():
    # two planar bilinear patches 1 apart, overlapping in a square: every point of the overlap
    P = np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]], float)
    R, t = rotation(3), np.array([0.1, 0.2, 0.3])
    a, b = BezierSurface(P).transformed(R, t), BezierSurface(P + [0.3, 0.2, 1.0]).transformed(R, t)
    res = min_distance(a, b)
    check_exact(res, 1.0)
    assert not res.isolated


def test_coaxial_cylinders():
    res = min_distance(cylinder(1.0, 2.0), cylinder(3.0, 2.0, (0, 0, 0.5)))
    check_exact(res, 2.0)
    assert not res.isolated
    assert 0.5 - 1e-9 <= res.points[0][2] <= 2.0 + 1e-9       # where the two overlap in height


def test_concentric_arcs():
    c = (0.2, 0.1)
    res = min_distance(arc(c, 1.0, 0.0, 2.0), arc(c, 2.5, 0.5, 2.5))
    check_exact(res, 1.5)
    assert not res.isolated
    angle = np.arctan2(res.points[0][1] - c[1], res.points[0][0] - c[0])
    assert 0.5 - 1e-9 <= angle <= 2.0 + 1e-9                    # where the two overlap


@pytest.mark.parametrize("height, exact", [(0.0, 2.0), (1.0, np.sqrt(10.0) - 1.0)])
def test_circle_at_constant_distance_from_a_sphere(height, exact):
    # a horizontal circle of radius 3 about the sphere's axis: the equator (a knot of the
    # sphere) or, lifted, a parallel inside a Bezier patch, halved across it only
    res = min_distance(arc((0, 0), 3.0, 0.0, 2 * np.pi, z=height), sphere(1.0))
    check_exact(res, exact)
    assert not res.isolated


def test_circle_about_a_cylinder():
    res = min_distance(arc((0, 0), 3.0, 0.0, 2 * np.pi, z=1.0), cylinder(1.0, 2.0))
    check_exact(res, 2.0)
    assert not res.isolated


def test_equal_isolated_minima_are_isolated():
    # a circle inside the concentric ellipse with semi-axes 3, 2: distance 1 at (0, +-1),
    # two strict minima, point-symmetric
    c, s, w, knots = arc_parameters(0.0, 2 * np.pi)
    ellipse = BSplineCurve(np.c_[3 * c, 2 * s], 2, knots, w)
    res = min_distance(arc((0, 0), 1.0, 0.0, 2 * np.pi), ellipse)
    check_exact(res, 1.0)
    assert res.isolated
    np.testing.assert_allclose(np.abs(res.points[1]), [0.0, 2.0], atol=1e-6)


def test_sphere_between_two_equal_minima_is_isolated():
    # a sphere inside the ellipsoid with semi-axes 3, 2, 2.5 (the sphere's net scaled):
    # distance 1 at (0, +-2, 0)
    s = sphere(1.0)
    ellipsoid = BSplineSurface(np.asarray(s.control_points) * [3.0, 2.0, 2.5], 2, 2, s.knots_u, s.knots_v,
                               s.weights, s.periodic_u, s.periodic_v)
    res = min_distance(s, ellipsoid)
    check_exact(res, 1.0)
    assert res.isolated


def test_touches():
    # a sphere on a sphere: one point; a cylinder on a plane: a line; crossing spheres: a circle
    on_sphere = min_distance(sphere(1.0), sphere(1.0, (2.0, 0, 0)))
    assert on_sphere.distance <= 1e-12 and on_sphere.converged and on_sphere.isolated
    wall = BezierSurface(np.array([[[-2, -1, -1], [-2, -1, 3]], [[2, -1, -1], [2, -1, 3]]], float))
    line = min_distance(cylinder(1.0, 2.0), wall)
    assert line.distance <= 1e-12 and line.converged and not line.isolated
    crossing = min_distance(sphere(1.0), sphere(1.0, (1.0, 0.3, 0)))
    assert crossing.distance <= 1e-12 and not crossing.isolated
    # two plane curves crossing transversally meet at isolated points
    assert min_distance(circle((0, 0), 1.0), circle((1.2, 0.3), 0.8)).isolated


def test_result_is_a_frozen_value():
    res = min_distance(sphere(1.0), sphere(0.5, (3, 1, 0)))
    assert isinstance(res, DistanceResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.distance = 0.0
    with pytest.raises(ValueError):
        res.points[0][0] = 1.0                                    # read-only arrays
    with pytest.raises(ValueError):
        res.params[1][0] = 1.0
    assert res.gap == res.distance - res.lower_bound


def test_pair_cap_at_the_start_keeps_the_certificate():
    # 9 x 9 pieces each: 6561 pairs of pieces at the start, more than the cap
    rng = np.random.default_rng(5)
    knots = np.r_[[0.0] * 3, np.linspace(0, 1, 10), [1.0] * 3]
    g = np.linspace(0, 1, 12)
    P = np.stack([*np.meshgrid(g, g, indexing="ij"), 0.05 * rng.standard_normal((12, 12))], axis=-1)
    a = BSplineSurface(P, 3, 3, knots, knots)
    b = BSplineSurface(P + [0.0, 0.0, 0.5], 3, 3, knots, knots)
    res = min_distance(a, b, max_pairs=1000)
    dense = dense_min(a, b, 41)
    assert res.lower_bound <= dense and res.lower_bound <= res.distance
    assert res.converged or "pair cap" in res.message


def test_bad_input():
    a = circle((0, 0), 1.0)
    for tol in (0.0, -1.0, float("nan")):
        with pytest.raises(CagdError, match="tol"):
            min_distance(a, circle((3, 0), 1.0), tol=tol)
    with pytest.raises(CagdError, match="dimension"):
        min_distance(a, sphere(1.0, (0, 0, 0)))
    with pytest.raises(CagdError, match="b"):
        min_distance(a, np.zeros((3, 2)))
    for name in ("max_depth", "max_pairs", "refine_per_level"):
        with pytest.raises(CagdError, match=name):
            min_distance(a, circle((3, 0), 1.0), **{name: -1})


def brute_force(a, b, n=401):
    """Dense sampling: an upper bound of the true minimum (so of the lower bound)."""
    t = np.linspace(*a.domain, n)
    if isinstance(b, BSplineSurface):
        (u0, u1), (v0, v1) = b.domain
        pb = b.grid(np.linspace(u0, u1, 121), np.linspace(v0, v1, 121)).reshape(-1, 3)
    else:
        pb = b(np.linspace(*b.domain, n))
    pa = a(t)
    return min(np.linalg.norm(pa[i:i + 50, None] - pb[None], axis=-1).min() for i in range(0, len(pa), 50))


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10 ** 6), st.integers(2, 3))
def test_curve_curve_brute_force(seed, dim):
    rng = np.random.default_rng(seed)
    a = BSplineCurve(rng.random((7, dim)), 3)
    b = BSplineCurve(rng.random((6, dim)) + 0.6, 3, weights=rng.uniform(0.5, 2, 6))
    res = min_distance(a, b)
    check_certificate(res)
    assert res.lower_bound <= brute_force(a, b) + 1e-15


try:                                  # the OCCT oracles need OCP; the rest of the module does not
    from cagd import occ
except ImportError:
    occ = None
needs_occ = pytest.mark.skipif(occ is None, reason="OCP (cagd.occ) is not installed")


@needs_occ
@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_curve_curve_against_occt(seed):
    from OCP.GeomAPI import GeomAPI_ExtremaCurveCurve
    rng = np.random.default_rng(seed)
    a = BSplineCurve(rng.random((7, 3)), 3)
    b = BSplineCurve(rng.random((7, 3)) + [0.8, 0, 0], int(rng.integers(2, 4)), weights=rng.uniform(0.5, 2, 7))
    res = min_distance(a, b)
    check_certificate(res)
    ext = GeomAPI_ExtremaCurveCurve(occ.to_occ(a), occ.to_occ(b))
    if ext.NbExtrema():
        theirs = ext.LowerDistance()
        assert res.distance <= theirs + 1e-9 * max(theirs, 1.0)
        assert res.lower_bound <= theirs + 1e-15
        if res.distance < theirs - 1e-9:
            print(f"seed {seed}: OCCT ExtremaCurveCurve {theirs:.12g} > engine {res.distance:.12g}")


@needs_occ
@settings(max_examples=8, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_curve_surface_against_occt(seed):
    from OCP.GeomAPI import GeomAPI_ExtremaCurveSurface
    rng = np.random.default_rng(seed)
    a = BSplineCurve(rng.random((7, 3)), 3)
    s = BSplineSurface(rng.random((5, 5, 3)) + [0, 0, 1.0], 3, 3)
    res = min_distance(a, s)
    check_certificate(res)
    assert res.lower_bound <= brute_force(a, s, 101) + 1e-15
    ext = GeomAPI_ExtremaCurveSurface(occ.to_occ(a), occ.to_occ(s))
    if ext.NbExtrema():
        theirs = ext.LowerDistance()
        assert res.distance <= theirs + 1e-9 * max(theirs, 1.0)
        if res.distance < theirs - 1e-9:
            print(f"seed {seed}: OCCT ExtremaCurveSurface {theirs:.12g} > engine {res.distance:.12g} "
                  "(OCCT reports interior extrema only)")


def test_surface_surface_brute_force():
    rng = np.random.default_rng(7)
    s1 = BSplineSurface(rng.random((5, 4, 3)), 3, 2)
    s2 = BSplineSurface(rng.random((4, 5, 3)) + [0, 0, 1.2], 2, 3)
    res = min_distance(s1, s2)
    check_certificate(res)
    g1 = s1.grid(np.linspace(0, 1, 81), np.linspace(0, 1, 81)).reshape(-1, 3)
    g2 = s2.grid(np.linspace(0, 1, 81), np.linspace(0, 1, 81)).reshape(-1, 3)
    dense = min(np.linalg.norm(g1[i:i + 400, None] - g2[None], axis=-1).min() for i in range(0, len(g1), 400))
    assert res.lower_bound <= dense and res.distance <= dense + 1e-12


def dense_min(a, b, n):
    """Dense-sampling minimum of two rectangular surfaces: an upper bound of the true one."""
    def grid(s):
        (u0, u1), (v0, v1) = s.domain
        return s.grid(np.linspace(u0, u1, n), np.linspace(v0, v1, n)).reshape(-1, s.dim)
    g1, g2 = grid(a), grid(b)
    return min(np.linalg.norm(g1[i:i + 400, None] - g2[None], axis=-1).min() for i in range(0, len(g1), 400))


@settings(max_examples=8, deadline=None)
@given(bspline_surfaces(max_degree=3, dims=(3, 3)), bspline_surfaces(max_degree=3, dims=(3, 3)),
       st.floats(0.0, 30.0))
def test_random_surfaces_certificate_holds(a, b, lift):
    b = b.transformed(np.eye(3), [0.0, 0.0, lift])
    res = min_distance(a, b, max_pairs=4000)
    dense = dense_min(a, b, 61)
    slack = 1e-12 * max(1.0, dense)
    assert res.lower_bound <= dense + slack and res.lower_bound <= res.distance
    if res.converged:
        assert res.gap <= res.tol and res.distance <= dense + res.tol + slack
    else:
        assert res.message


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 10 ** 6), st.floats(0.5, 3.0), st.floats(0.1, 2.0), st.booleans())
# hypothesis 6.170's derandomised example: the joint Newton stopped 2e-8 (relative gradient)
# from stationary, the minimum was called isolated and the pair cap was hit (now polished)
@example(seed=1, r=0.5, gap=1.8205533649568226, cylinders=False)
def test_symmetric_continua_anywhere(seed, r, gap, cylinders):
    # concentric spheres or coaxial cylinders, placed and turned at random: the minimum
    # gap is attained on a 2-D set, certified, and not isolated
    rng = np.random.default_rng(seed)
    R, t = rotation(seed), rng.uniform(-5, 5, 3)
    if cylinders:
        a, b = cylinder(r, 2.0), cylinder(r + gap, 3.0, (0, 0, -0.5))
    else:
        a, b = sphere(r), sphere(r + gap)
    res = min_distance(a.transformed(R, t), b.transformed(rotation(seed + 1) if not cylinders else R, t))
    check_exact(res, gap)
    assert not res.isolated


# --- issue 14: extreme scales and separations ----------------------------------------------
_CUBIC = BezierCurve([[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 1.0, 1.0], [4.0, 0.0, 0.0]])


@pytest.mark.parametrize("D", [1e155, 1e160, 1e250])
def test_objects_far_apart(D):
    """Objects 1e155 apart raised TypeError/AssertionError (squared distances overflow):
    the distance of a curve and its copy moved by D along x is D - 4 (its x-extent), to
    float64's resolution at that scale (default tol: ROUNDING_RTOL of the extent)."""
    r = min_distance(_CUBIC, _CUBIC.transformed(np.eye(3), [D, 0.0, 0.0]))
    assert r.converged
    assert r.distance == pytest.approx(D - 4.0, rel=1e-14)
    assert r.lower_bound <= r.distance and r.gap <= r.tol <= 1e-13 * D
    assert np.linalg.norm((r.points[1] - r.points[0]) / D) * D == pytest.approx(r.distance, rel=1e-15)


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e100, 1e299])
def test_distance_scale_invariance(scale):
    """A curve and a sphere at every model scale: the distance scales, the parameters
    stay (the work is in the frame of both objects)."""
    b = _CUBIC.transformed(np.eye(3), [0.0, 0.0, 3.0])
    ref = min_distance(_CUBIC, b)
    M = np.eye(3) * scale
    r = min_distance(_CUBIC.transformed(M, [0.0, 0.0, 0.0]), b.transformed(M, [0.0, 0.0, 0.0]))
    assert r.converged and r.distance / scale == pytest.approx(ref.distance, rel=1e-12)
    assert r.lower_bound <= r.distance and r.tol == pytest.approx(ref.tol * scale, rel=1e-12)
    s = min_distance(sphere(1.0).transformed(M, [0.0, 0.0, 0.0]), _CUBIC.transformed(M, [0.0, 0.0, 5.0 * scale]))
    assert s.converged and s.distance / scale == pytest.approx(4.0, rel=1e-9)


def test_tol_below_resolution_is_refused():
    c = _CUBIC.transformed(np.eye(3) * 1e300, [0.0, 0.0, 0.0])
    with pytest.raises(CagdError, match="tol: .* below float64's resolution"):
        min_distance(c, c.transformed(np.eye(3), [0.0, 0.0, 1e300]), tol=1e-300)


def test_distance_beyond_float64_is_refused():
    a = _CUBIC.transformed(np.eye(3), [-1.7e308, 0.0, 0.0])
    with pytest.raises(CagdError, match="distance exceeds the float64 range"):
        min_distance(a, _CUBIC.transformed(np.eye(3), [1.7e308, 0.0, 0.0]))


def test_plane_against_a_far_sphere():
    """A plane patch against a unit sphere centred at 1e12 (reported to hang: the default
    tol 1e-9 of the size is below float64's resolution there): 1e12 - 1, converged, with
    the tol raised to 1e-14 of the common extent."""
    flat = BezierSurface([[[-1, -1, 0], [-1, 1, 0]], [[1, -1, 0], [1, 1, 0]]])
    r = min_distance(flat, sphere(1.0, (0, 0, 1e12)))
    assert r.converged and r.distance == pytest.approx(1e12 - 1.0, rel=1e-14)
    assert r.lower_bound <= r.distance and r.tol <= 1e-13 * 1e12
