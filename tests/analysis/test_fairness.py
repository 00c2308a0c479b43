"""Curve fairness (cagd.analysis.fairness) against closed forms and independent
oracles: circle arcs (no variation, no inflection), an S-curve (one inflection, energy
against finite differences of the closed-form curvature), a C1 cubic spline whose
curvature jumps at a knot (Farin's end-curvature formula on its Bezier pieces)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd.analysis import fairness

S = np.sqrt(0.5)


def circle(R=1.0):
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]]) * R
    return cagd.BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, S, 1, S, 1, S, 1, S, 1])


S_CURVE = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, -1.0], [3.0, 0.0]])


@pytest.mark.parametrize("R", [0.01, 1.0, 250.0])
def test_circle_has_zero_variation_energy_and_no_inflection(R):
    f = fairness(circle(R))
    assert f.inflections == 0
    assert f.energy < 1e-20 / R ** 3                  # (d kappa/ds)^2 ds scales as 1/R^3
    np.testing.assert_allclose(f.curvature, 1 / R, rtol=1e-13)
    np.testing.assert_allclose(np.abs(f.signed_curvature), 1 / R, rtol=1e-13)
    np.testing.assert_allclose(f.length, 2 * np.pi * R, rtol=1e-13)
    assert f.max_knot_jump < 1e-12 / R                # the quarter arcs join G2
    np.testing.assert_array_equal(f.knots, [.25, .5, .75])   # clamped (not periodic): interior knots only
    assert np.all(np.diff(f.arc_length) >= 0)


def test_quarter_arc_in_3d():
    arc = cagd.BSplineCurve([[1, 0, 0], [1, 1, 1], [0, 1, 2]], 2, None, [1, S, 1])  # not a circle: planar conic
    f = fairness(arc)
    assert f.inflections == 0


def test_samples_include_span_ends():
    f = fairness(circle(), samples_per_span=5)
    assert len(f.params) == 4 * 5
    np.testing.assert_array_equal(f.params.reshape(4, 5)[:, [0, -1]], [[0, .25], [.25, .5], [.5, .75], [.75, 1]])
    np.testing.assert_array_equal(f.span, np.repeat(np.arange(4), 5))


def s_curve_oracle(n=200001):
    """Signed curvature of the cubic Bezier S_CURVE in closed form (power basis), its
    arc-length derivative by central differences and the trapezoid rule."""
    t = np.linspace(0.0, 1.0, n)
    b = S_CURVE
    d1 = 3 * ((1 - t) ** 2)[:, None] * (b[1] - b[0]) + 6 * ((1 - t) * t)[:, None] * (b[2] - b[1]) \
        + 3 * (t ** 2)[:, None] * (b[3] - b[2])
    d2 = 6 * (1 - t)[:, None] * (b[2] - 2 * b[1] + b[0]) + 6 * t[:, None] * (b[3] - 2 * b[2] + b[1])
    speed = np.linalg.norm(d1, axis=1)
    k = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed ** 3
    s = np.concatenate([[0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    dk = np.gradient(k, s)
    return np.trapezoid(dk ** 2, s) if hasattr(np, "trapezoid") else np.trapz(dk ** 2, s), s[-1], k


def test_s_curve_has_one_inflection_and_the_oracle_energy():
    f = fairness(cagd.BezierCurve(S_CURVE))
    energy, length, k = s_curve_oracle()
    assert f.inflections == 1
    np.testing.assert_allclose(f.energy, energy, rtol=1e-6)
    np.testing.assert_allclose(f.length, length, rtol=1e-9)
    assert f.knots.size == 0 and f.max_knot_jump == 0.0 and np.isnan(f.jump_parameter)


def test_straight_line_is_fair():
    f = fairness(cagd.BSplineCurve([[0, 0], [1, 1], [2, 2], [3, 3]], 2))
    assert f.energy == 0.0 and f.inflections == 0 and f.max_knot_jump == 0.0
    np.testing.assert_allclose(f.length, 3 * np.sqrt(2), rtol=1e-14)


def bezier_end_curvatures(b):
    """Farin 10.2: signed curvature at t = 0 and t = 1 of a Bezier curve of degree n,
    (n-1)/n (Db0 x Db1) / |Db0|^3 and (n-1)/n (Db_{n-2} x Db_{n-1}) / |Db_{n-1}|^3."""
    n = len(b) - 1
    d = np.diff(b, axis=0)
    cross = lambda a, c: a[0] * c[1] - a[1] * c[0]  # noqa: E731
    return ((n - 1) / n * cross(d[0], d[1]) / np.linalg.norm(d[0]) ** 3,
            (n - 1) / n * cross(d[-2], d[-1]) / np.linalg.norm(d[-1]) ** 3)


@pytest.mark.parametrize("h0, h1", [(1.0, 1.0), (1.0, 2.5)])
def test_c1_spline_curvature_jump_at_the_knot(h0, h1):
    P = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 1.0], [3.0, 0.5], [4.0, -1.0], [5.0, 0.0]])
    knots = [0, 0, 0, 0, h0, h0, h0 + h1, h0 + h1, h0 + h1, h0 + h1]
    c = cagd.BSplineCurve(P, 3, knots)
    # the double knot's Bezier pieces: junction (h1 P2 + h0 P3) / (h0 + h1)
    joint = (h1 * P[2] + h0 * P[3]) / (h0 + h1)
    left = np.array([P[0], P[1], P[2], joint])
    right = np.array([joint, P[3], P[4], P[5]])
    kl, kr = bezier_end_curvatures(left)[1], bezier_end_curvatures(right)[0]
    f = fairness(c)
    assert abs(kl - kr) > 0.1
    np.testing.assert_allclose(f.max_knot_jump, abs(kl - kr), rtol=1e-12)
    assert f.jump_parameter == h0
    np.testing.assert_allclose(f.knot_jumps, [abs(kl - kr)], rtol=1e-12)
    # the plot data keeps both limits at the knot
    i = np.flatnonzero(f.params == h0)
    np.testing.assert_allclose(f.signed_curvature[i], [kl, kr], rtol=1e-12)
    assert f.arc_length[i[0]] == f.arc_length[i[1]]


angles = st.floats(-np.pi, np.pi)


@settings(max_examples=25, deadline=None)
@given(angles, angles, st.floats(0.05, 20.0))
def test_planar_curve_moved_into_3d_keeps_its_metrics(a, b, scale):
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    rot = np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, cb, -sb], [0, sb, cb]])
    P3 = (scale * np.column_stack([S_CURVE, np.zeros(4)])) @ rot.T + [1.0, 2.0, 3.0]
    f2, f3 = fairness(cagd.BezierCurve(S_CURVE)), fairness(cagd.BezierCurve(P3))
    assert f3.inflections == 1
    np.testing.assert_allclose(f3.energy * scale ** 3, f2.energy, rtol=1e-9)
    np.testing.assert_allclose(f3.length / scale, f2.length, rtol=1e-12)
    np.testing.assert_allclose(f3.curvature * scale, f2.curvature, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("call, name", [
    (lambda: fairness("curve"), "curve"),
    (lambda: fairness(cagd.BezierCurve([[0, 0, 0, 0], [1, 1, 1, 1]])), "curve"),
    (lambda: fairness(cagd.BezierCurve(S_CURVE), samples_per_span=1), "samples_per_span"),
    (lambda: fairness(cagd.BezierCurve(S_CURVE), samples_per_span=2.5), "samples_per_span"),
    (lambda: fairness(cagd.BezierCurve([[0, 0], [0, 0], [1, 1]])), "curve"),
])
def test_bad_input_is_a_cagd_error_naming_the_argument(call, name):
    with pytest.raises(cagd.CagdError, match=f"^{name}"):
        call()


def test_periodic_curve_counts_the_seam_as_a_knot():
    # a periodic cubic through a square's corners is C2 everywhere: no jumps, the seam included
    c = cagd.BSplineCurve([[1, 0], [0, 1], [-1, 0], [0, -1]], 3, periodic=True)
    f = fairness(c)
    assert f.knots.size == 4 and f.knots[-1] == c.domain[1]
    assert f.max_knot_jump < 1e-12
    assert f.inflections == 0
    # a periodic uniform quadratic is only C1: curvature jumps at every knot, the seam too;
    # its pieces are the Bezier quadratics (P_{i-1} + P_i)/2, P_i, (P_i + P_{i+1})/2
    P = np.array([[3.0, 0.0], [0.5, 1.0], [-2.0, 0.2], [0.0, -1.5]])
    g = fairness(cagd.BSplineCurve(P, 2, periodic=True))
    ends = [bezier_end_curvatures(np.array([(P[i - 1] + P[i]) / 2, P[i], (P[i] + P[(i + 1) % 4]) / 2]))
            for i in range(4)]
    oracle = [abs(ends[i][1] - ends[(i + 1) % 4][0]) for i in range(4)]
    assert g.knots.size == 4 and min(oracle) > 0.01
    np.testing.assert_allclose(np.sort(g.knot_jumps), np.sort(oracle), rtol=1e-12)


@pytest.mark.parametrize("L", [1e-100, 1e-30, 1e30, 1e100])
def test_extreme_sizes_keep_the_scaling_law(L):
    # energy ~ 1/L^3, length ~ L, inflections unchanged: no over/underflow of |C'|^5
    f1, fl = fairness(cagd.BezierCurve(S_CURVE)), fairness(cagd.BezierCurve(S_CURVE * L))
    np.testing.assert_allclose(fl.energy * L ** 3, f1.energy, rtol=1e-13)
    np.testing.assert_allclose(fl.length / L, f1.length, rtol=1e-13)
    assert fl.inflections == 1
