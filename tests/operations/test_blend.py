"""Bridge curves (cagd.blend_curve): G1/G2 measured independently at both ends with
the engine's ``continuity`` (tangent angle, curvature-vector test) and ``Curve.curvature``,
G3 with closed-form curvature, d kappa / ds and torsion from the cross products here,
exact end points, the closed form for collinear lines, the automatic tangent scales
against a brute-force grid and the heuristic (energy checked by scipy quadrature),
symmetry, and bad input."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve, CagdError, blend_curve, continuity
from cagd.operations import curvature_variation, curve_size
from cagd.operations.blend import SCALE_BOUNDS
from strategies import point_arrays, positive_weights

TOL = 1e-9          # the bounds: G1 angle (rad), G2 relative curvature difference
ENDS = ("start", "end")
COMBINATIONS = [(e1, e2) for e1 in ENDS for e2 in ENDS]


def arc(center, radius, start, angle):
    """Exact NURBS circle arc (rational quadratic, one span, angle < pi; Piegl & Tiller 7.3)."""
    c, h = np.asarray(center, float), angle / 2.0
    p0 = c + radius * np.array([math.cos(start), math.sin(start)])
    p2 = c + radius * np.array([math.cos(start + angle), math.sin(start + angle)])
    mid = c + radius / math.cos(h) * np.array([math.cos(start + h), math.sin(start + h)])
    return BSplineCurve([p0, mid, p2], 2, [0, 0, 0, 1, 1, 1], [1.0, math.cos(h), 1.0])


LINES = (BezierCurve([[0.0, 0.0], [1.0, 0.5]]), BezierCurve([[3.0, 2.0], [4.0, 1.0]]))
ARCS = (arc([0.0, 0.0], 1.0, 0.2, 1.3), arc([4.0, 1.0], 2.0, 2.0, 1.1))
SPLINES = (BSplineCurve([[0, 0, 0], [1, 2, 0.5], [2, 2.5, -0.5], [3, 1, 1.0], [4, 0, 0.3]], 3,
                        [0, 0, 0, 0, 0.4, 1, 1, 1, 1]),
           BSplineCurve([[6, 1, 2], [7, 3, 1], [8, 2, 3], [9, 4, 2]], 2, [0, 0, 0, 0.5, 1, 1, 1]))
CASES = {"lines": LINES, "arcs": ARCS, "splines": SPLINES}


def end_parameter(c, end):
    return c.domain[1] if end == "end" else c.domain[0]


def joint_reports(c1, end1, c2, end2, bridge):
    """continuity() at c1 -> bridge and bridge -> c2, each pair oriented so the
    joint's tangents should point the same way (a start end is met by the reversed bridge)."""
    t1, t2 = end_parameter(c1, end1), end_parameter(c2, end2)
    r = bridge.reversed()
    first = continuity(c1, bridge, t1, 0.0) if end1 == "end" else continuity(r, c1, 1.0, t1)
    second = continuity(bridge, c2, 1.0, t2) if end2 == "start" else continuity(c2, r, t2, 0.0)
    return first, second


def frenet_data(c, t):
    """(kappa, d kappa / ds, tau, X) at t from a = c', b = c'', d = c''' by cross products:
    kappa = |a x b| / |a|^3, tau = (a x b).d / |a x b|^2, d kappa / ds =
    [(a x b).(a x d) / (|a x b| |a|^3) - 3 |a x b| (a.b) / |a|^5] / |a| and
    X = d(kappa N)/ds = [((a x d) x a + (a x b) x b) / |a|^4 - 4 (a.b) ((a x b) x a) / |a|^6] / |a|
    (kappa N = (a x b) x a / |a|^4); 2-D curves in z = 0."""
    D = c.derivatives(t, 3)
    if D.shape[-1] == 2:
        D = np.concatenate([D, np.zeros((4, 1))], axis=1)
    a, b, d = D[1], D[2], D[3]
    ab = np.cross(a, b)
    na, nab = np.linalg.norm(a), np.linalg.norm(ab)
    X = ((np.cross(np.cross(a, d), a) + np.cross(ab, b)) / na ** 4 - 4.0 * (a @ b) * np.cross(ab, a) / na ** 6) / na
    if nab == 0.0:
        return 0.0, np.nan, np.nan, X
    kappa = nab / na ** 3
    dk = ((ab @ np.cross(a, d)) / (nab * na ** 3) - 3.0 * nab * (a @ b) / na ** 5) / na
    return kappa, dk, (ab @ d) / nab ** 2, X


def check_g3(c1, end1, c2, end2, B, size, torsion=True):
    """The third arc-length derivative X of the bridge equals that of the curves at both
    ends, relative to 1/size^2; where the curvature is not small (above 1e-3 / size), so
    do the curvature, its arc-length derivative and the torsion (signs by orientation)."""
    for c, end, tb, along in ((c1, end1, 0.0, end1 == "end"), (c2, end2, 1.0, end2 == "start")):
        k1, dk1, tau1, X1 = frenet_data(c, end_parameter(c, end))
        k2, dk2, tau2, X2 = frenet_data(B, tb)
        X1, dk1 = (X1, dk1) if along else (-X1, -dk1)
        assert np.linalg.norm(X2 - X1) <= TOL * max(np.linalg.norm(X1), np.linalg.norm(X2), size ** -2), (X1, X2)
        assert abs(k2 - k1) <= TOL * max(k1, k2, 1.0 / size)
        if min(k1, k2) > 1e-3 / size:
            assert abs(dk2 - dk1) <= TOL * max(abs(dk1), abs(dk2), size ** -2), (dk1, dk2)
            if torsion:
                assert abs(tau2 - tau1) <= TOL * max(abs(tau1), abs(tau2), 1.0 / size), (tau1, tau2)


def check(c1, end1, c2, end2, k, scales=None, torsion=True):
    res = blend_curve(c1, end1, c2, end2, continuity=k, tangent_scales=scales)
    B = res.curve
    assert isinstance(B, BezierCurve) and B.degree == 2 * k + 1
    t1, t2 = end_parameter(c1, end1), end_parameter(c2, end2)
    assert np.array_equal(B(0.0), c1(t1)) and np.array_equal(B(1.0), c2(t2))      # exactly at the ends
    # the ends are exact (above); the report's gap compares derivatives()[0] of both curves, each
    # rounded on its own (a rational's by several ulps: 6.4 and 9 eps of the size seen): the gap is
    # within those roundings, |D[0] - c(t)| of each curve at its end, and that of the subtraction
    r = B.reversed()
    rounding = sum(float(np.linalg.norm(c.derivatives(t, 2)[0] - c(t)))          # as continuity() evaluates
                   for c, t in ((c1, t1), (c2, t2), (B, 0.0), (B, 1.0), (r, 0.0), (r, 1.0)))
    magnitude = max(float(np.abs(c1(t1)).max()), float(np.abs(c2(t2)).max()))
    for rep in joint_reports(c1, end1, c2, end2, B):
        assert rep.C0 and rep.gap <= rounding + 4 * np.finfo(float).eps * magnitude
        assert rep.tangent_angle <= TOL and rep.G1, rep
        if k >= 2:
            assert rep.G2, rep
    if k >= 2:                                       # curvature, independently of the vector test
        size = curve_size(c1, c2)
        for kc, kb in ((c1.curvature(t1), B.curvature(0.0)), (c2.curvature(t2), B.curvature(1.0))):
            assert abs(kb - kc) <= TOL * max(kc, kb, 1.0 / size)
        assert max(res.curvature_gaps) <= TOL
    if k == 3:
        check_g3(c1, end1, c2, end2, B, curve_size(c1, c2), torsion)
        assert max(res.curvature_derivative_gaps) <= TOL
    if scales is not None:
        assert res.tangent_scales == tuple(scales)
    assert max(res.g1_angles) <= TOL and res.converged and res.continuity == k
    return res


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("end1, end2", COMBINATIONS)
@pytest.mark.parametrize("k", [1, 2, 3])
def test_fixed_configurations(case, end1, end2, k):
    c1, c2 = CASES[case]
    check(c1, end1, c2, end2, k)
    check(c1, end1, c2, end2, k, scales=(0.4, 2.5))


def test_collinear_lines_give_the_uniform_segment():
    """Closed form: tangents along the chord -> control points equally spaced on it."""
    c1, c2 = BezierCurve([[0.0, 0.0], [1.0, 0.0]]), BezierCurve([[3.0, 0.0], [4.0, 0.0]])
    for k in (1, 2, 3):
        n = 2 * k + 1
        res = blend_curve(c1, "end", c2, "start", k)                 # automatic: every (a, b) is straight
        assert res.tangent_scales == (1.0, 1.0) and res.energy <= 1e-20
        P = res.curve.control_points
        assert np.allclose(P, np.column_stack([np.linspace(1.0, 3.0, n + 1), np.zeros(n + 1)]), rtol=0, atol=1e-15)


def test_collinear_lines_stay_straight_at_any_scales():
    c1 = BezierCurve([[0.0, 0.0, 0.0], [1.0, 1.0, 2.0]])
    c2 = BezierCurve([[3.0, 3.0, 6.0], [5.0, 5.0, 10.0]])
    e = np.array([1.0, 1.0, 2.0]) / math.sqrt(6.0)
    for k in (1, 2, 3):
        for scales in (None, (0.3, 2.0)):
            P = blend_curve(c1, "end", c2, "start", k, scales).curve.control_points
            off = (P - [1.0, 1.0, 2.0]) - np.outer((P - [1.0, 1.0, 2.0]) @ e, e)
            assert np.abs(off).max() <= 1e-14
            assert np.all(np.diff(P @ e) > 0.0)                      # in order along the line


def test_tangent_scales_set_the_end_legs():
    c1, c2 = ARCS
    for k in (1, 2, 3):
        n = 2 * k + 1
        chord = np.linalg.norm(c2(c2.domain[0]) - c1(c1.domain[1]))
        P = blend_curve(c1, "end", c2, "start", k, tangent_scales=(0.5, 3.0)).curve.control_points
        assert np.isclose(np.linalg.norm(P[1] - P[0]), 0.5 * chord / n, rtol=1e-14)
        assert np.isclose(np.linalg.norm(P[-1] - P[-2]), 3.0 * chord / n, rtol=1e-14)


def test_g1_reports_the_curvature_mismatch():
    res = blend_curve(*ARCS[:1], "end", ARCS[1], "start", 1)
    assert res.converged and max(res.curvature_gaps) > 1e-3      # a cubic does not match curvature


@st.composite
def end_curves(draw):
    pts = draw(point_arrays(4, 3))
    w = draw(st.one_of(st.none(), st.lists(positive_weights, min_size=4, max_size=4)))
    return BezierCurve(pts, w)


@settings(max_examples=25, deadline=None)
@given(end_curves(), end_curves(), st.sampled_from(ENDS), st.sampled_from(ENDS), st.sampled_from([1, 2, 3]),
       st.tuples(st.floats(0.2, 5.0), st.floats(0.2, 5.0)))
def test_random_configurations(c1, c2, end1, end2, k, scales):
    size = curve_size(c1, c2)
    p, q = c1(end_parameter(c1, end1)), c2(end_parameter(c2, end2))
    assume(np.linalg.norm(p - q) > 0.05 * size)
    for c, e in ((c1, end1), (c2, end2)):
        assume(np.linalg.norm(c.derivative(end_parameter(c, e))) > 1e-2 * size)
    check(c1, end1, c2, end2, k, scales, torsion=False)


BAD = [
    (dict(c1=np.zeros((2, 2))), "c1"),
    (dict(c2="curve"), "c2"),
    (dict(c2=SPLINES[1]), "c2: dimension"),
    (dict(end1="middle"), "end1"),
    (dict(end2=1), "end2"),
    (dict(continuity=4), "continuity"),
    (dict(continuity=0), "continuity"),
    (dict(continuity=True), "continuity"),
    (dict(continuity="G2"), "continuity"),
    (dict(continuity=1.5), "continuity"),
    (dict(tangent_scales=(0.0, 1.0)), "tangent_scales[0]"),
    (dict(tangent_scales=(1.0, -2.0)), "tangent_scales[1]"),
    (dict(tangent_scales=(float("nan"), 1.0)), "tangent_scales[0]"),
    (dict(tangent_scales=(1.0, float("inf"))), "tangent_scales[1]"),
    (dict(tangent_scales=(1.0,)), "tangent_scales"),
    (dict(tangent_scales=3.0), "tangent_scales"),
    (dict(c1=BezierCurve([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0]])), "c1: its first derivative vanishes"),
    (dict(c2=BezierCurve([[3.0, 2.0], [3.0, 2.0], [4.0, 1.0]])), "c2: its first derivative vanishes"),
    (dict(c2=BezierCurve([[1.0, 0.5], [4.0, 1.0]])), "end2: c2's start point coincides"),
]


@pytest.mark.parametrize("kwargs, match", BAD)
def test_bad_input(kwargs, match):
    args = dict(c1=LINES[0], end1="end", c2=LINES[1], end2="start", continuity=2, tangent_scales=None)
    args.update(kwargs)
    with pytest.raises(CagdError, match=match.replace("[", r"\[").replace("]", r"\]")):
        blend_curve(**args)


def test_exports():
    assert cagd.blend_curve is blend_curve and "blend_curve" in cagd.__all__ and "BlendCurve" in cagd.__all__
    res = blend_curve(*LINES[:1], "start", LINES[1], "end", 2)
    with pytest.raises(AttributeError):
        res.converged = False                                      # frozen


# --- the automatic tangent scales -----------------------------------------------------------------
def variation_by_quad(c):
    """L^3 int (d kappa / ds)^2 ds by scipy's adaptive quadrature of the cross-product formulas."""
    integrate = pytest.importorskip("scipy.integrate")
    a, b = c.domain

    def speed(t):
        return float(np.linalg.norm(c.derivative(t)))

    def integrand(t):
        return frenet_data(c, t)[1] ** 2 * speed(t)

    length = integrate.quad(speed, a, b, epsabs=0, epsrel=1e-13, limit=200)[0]
    return length ** 3 * integrate.quad(integrand, a, b, epsabs=0, epsrel=1e-12, limit=200)[0]


#: relative accuracy of the energy's fixed quadrature (32 x 8 Gauss nodes) against scipy's adaptive
#: one: 1e-14 on smooth curvature; the G1 arcs bridge turns through a near-cusp (5e-6 seen) and
#: the G2 spline bridge's curvature nearly vanishes (|kappa| has a rounded corner: 2.7e-5 seen)
QUAD_REL = {("arcs", 1): 2e-5, ("splines", 2): 1e-4, ("splines", 3): 1e-6}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("k", [1, 2, 3])
def test_energy_against_scipy_quadrature(case, k):
    c1, c2 = CASES[case]
    res = blend_curve(c1, "end", c2, "start", k)
    expected = variation_by_quad(res.curve)
    assert res.energy == pytest.approx(expected, rel=QUAD_REL.get((case, k), 1e-9), abs=0)
    assert curvature_variation(res.curve) == pytest.approx(res.energy, rel=1e-13, abs=0)


SCALE_GRID = np.exp(np.linspace(np.log(SCALE_BOUNDS[0]), np.log(SCALE_BOUNDS[1]), 13))


@pytest.mark.parametrize("case, end1, end2", [(c, "end", "start") for c in sorted(CASES)])
@pytest.mark.parametrize("k", [1, 2, 3])
def test_automatic_scales_beat_the_heuristic_and_a_grid(case, end1, end2, k):
    """Brute force: the energy of the automatic choice is at most that of (1, 1) and of
    every point of a 13 x 13 log-spaced grid over the search box (not the search's own
    17 x 17 start grid), within rounding, and of its neighbours (a, b) (1 +- 1e-4) in the box."""
    c1, c2 = CASES[case]
    res = blend_curve(c1, end1, c2, end2, k)
    a, b = res.tangent_scales
    assert SCALE_BOUNDS[0] <= a <= SCALE_BOUNDS[1] and SCALE_BOUNDS[0] <= b <= SCALE_BOUNDS[1]
    heuristic = blend_curve(c1, end1, c2, end2, k, (1.0, 1.0)).energy
    assert res.energy <= heuristic
    grid = min(blend_curve(c1, end1, c2, end2, k, (x, y)).energy for x in SCALE_GRID for y in SCALE_GRID)
    assert res.energy <= grid * (1.0 + 1e-12), (res.energy, grid)
    assert res.energy < heuristic * (1.0 - 1e-3)       # and these cases are not at (1, 1)
    lo, hi = SCALE_BOUNDS                                  # a local minimum: no better neighbour at 1e-4
    for da in (-1, 0, 1):
        for db in (-1, 0, 1):
            x = min(max(a * (1.0 + 1e-4 * da), lo), hi)
            y = min(max(b * (1.0 + 1e-4 * db), lo), hi)
            assert res.energy <= blend_curve(c1, end1, c2, end2, k, (x, y)).energy * (1.0 + 1e-13), (da, db)


def mirrored(c, x):
    """c reflected in the plane (or line) through x along the first axis, and reversed."""
    M = np.eye(c.dim)
    M[0, 0] = -1.0
    offset = np.zeros(c.dim)
    offset[0] = 2.0 * x
    return c.transformed(M, offset).reversed()


@pytest.mark.parametrize("c1", [ARCS[0], SPLINES[0], ARCS[1].reversed()])
@pytest.mark.parametrize("k", [1, 2, 3])
def test_symmetric_inputs_give_symmetric_scales(c1, k):
    x = float(c1(c1.domain[1])[0]) + 1.5
    c2 = mirrored(c1, x)
    res = blend_curve(c1, "end", c2, "start", k)
    a, b = res.tangent_scales
    assert abs(a - b) <= 1e-6 * a, (a, b)          # the minimum is flat: rounding of E moves it ~1e-7
    P = res.curve.control_points                          # the bridge is its own mirror image
    Q = P[::-1].copy()
    Q[:, 0] = 2.0 * x - Q[:, 0]
    np.testing.assert_allclose(P, Q, rtol=0, atol=1e-6 * curve_size(c1, c2))


def test_curvature_variation_bad_input_and_closed_form():
    with pytest.raises(CagdError, match=r"^curve: must be a cagd Curve"):
        curvature_variation(np.zeros((4, 2)))
    # a circle arc has constant curvature: no variation; a straight line none either
    assert curvature_variation(ARCS[0]) <= 1e-20 and curvature_variation(LINES[0]) == 0.0
    # the parabola (t, t^2 / 2) on [0, 1]: kappa = (1 + t^2)^(-3/2), d kappa / ds = -3 t (1 + t^2)^(-3),
    # ds = sqrt(1 + t^2) dt, L = (sqrt 2 + asinh 1) / 2
    integrate = pytest.importorskip("scipy.integrate")
    parabola = BezierCurve([[0.0, 0.0], [0.5, 0.0], [1.0, 0.5]])
    E = integrate.quad(lambda t: 9 * t * t * (1 + t * t) ** -5.5, 0.0, 1.0, epsabs=0, epsrel=1e-13)[0]
    L = (math.sqrt(2.0) + math.asinh(1.0)) / 2.0
    assert curvature_variation(parabola) == pytest.approx(L ** 3 * E, rel=1e-12, abs=0)
