"""The curvature comb (cagd.analysis.curvature_comb) against closed forms: the circle,
the parabola, a helix, and a G1 joint of two arcs where the curvature jumps."""
import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd.analysis import COMB_SIZE, curvature_comb

S = np.sqrt(0.5)


def circle(R=1.0, centre=(0.0, 0.0)):
    """The full circle as a rational quadratic B-spline (four quarter arcs)."""
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]]) * R + centre
    return cagd.BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, S, 1, S, 1, S, 1, S, 1])


@pytest.mark.parametrize("R", [0.01, 1.0, 250.0])
def test_circle_teeth_stand_outwards_with_length_scale_over_radius(R):
    centre = np.array([3.0, -2.0])
    comb = curvature_comb(circle(R, centre), scale=0.5 * R * R)
    radial = comb.base - centre
    np.testing.assert_allclose(np.linalg.norm(radial, axis=1), R, rtol=1e-14, atol=1e-15 * 4)
    np.testing.assert_allclose(comb.curvature, 1.0 / R, rtol=1e-13)
    outward = radial / R
    np.testing.assert_allclose(comb.normals, outward, atol=1e-12)
    # tips = base + scale * kappa * n, n the outward normal (away from the centre of curvature)
    np.testing.assert_allclose(comb.tips, comb.base + 0.5 * R * outward, atol=1e-12 * R)


def test_parabola_against_its_closed_form():
    """C(t) = (x, x^2), x = 2t - 1: kappa = 2 / (1 + 4x^2)^(3/2), the centre of curvature
    above the curve, the teeth along (2x, -1) / sqrt(1 + 4x^2)."""
    parabola = cagd.BezierCurve([[-1, 1], [0, -1], [1, 1]])
    comb = curvature_comb(parabola, samples_per_span=33, scale=0.3)
    x = comb.base[:, 0]
    np.testing.assert_allclose(x, 2 * comb.params - 1, atol=1e-15)
    np.testing.assert_allclose(comb.base[:, 1], x * x, atol=1e-15)
    q = np.sqrt(1 + 4 * x * x)
    kappa = 2 / q ** 3
    n = np.stack([2 * x, -np.ones_like(x)], axis=1) / q[:, None]
    np.testing.assert_allclose(comb.curvature, kappa, rtol=1e-13)
    np.testing.assert_allclose(comb.tips, comb.base + 0.3 * kappa[:, None] * n, atol=1e-14)


def test_twisted_cubic_in_space():
    """A 3-D curve: C(t) = (t, t^2, t^3) has C' x C'' = (6t^2, -6t, 2), so
    kappa = 2 sqrt(9t^4 + 9t^2 + 1) / (1 + 4t^2 + 9t^4)^(3/2), and the principal normal N
    along (C' x C'') x C'; the teeth point along -N."""
    cubic = cagd.BezierCurve([[0, 0, 0], [1 / 3, 0, 0], [2 / 3, 1 / 3, 0], [1, 1, 1]])
    comb = curvature_comb(cubic, samples_per_span=41, scale=0.2)
    t = comb.params
    np.testing.assert_allclose(comb.base, np.stack([t, t * t, t ** 3], axis=1), atol=1e-15)
    d1 = np.stack([np.ones_like(t), 2 * t, 3 * t * t], axis=1)
    b = np.stack([6 * t * t, -6 * t, 2 * np.ones_like(t)], axis=1)
    kappa = 2 * np.sqrt(9 * t ** 4 + 9 * t * t + 1) / (1 + 4 * t * t + 9 * t ** 4) ** 1.5
    N = np.cross(b, d1)
    N /= np.linalg.norm(N, axis=1)[:, None]
    np.testing.assert_allclose(comb.curvature, kappa, rtol=1e-13)
    np.testing.assert_allclose(comb.normals, -N, atol=1e-13)
    np.testing.assert_allclose(comb.tips, comb.base - 0.2 * kappa[:, None] * N, atol=1e-14)


def test_tilted_circle_in_space():
    """The circle of radius 3 rotated into a tilted plane: kappa = 1/3 and the teeth
    radial, outwards, in that plane."""
    c, s_ = np.cos(0.7), np.sin(0.7)
    Q = np.array([[1, 0, 0], [0, c, -s_], [0, s_, c]]) @ np.array([[c, 0, s_], [0, 1, 0], [-s_, 0, c]])
    flat = circle(3.0)
    P = np.concatenate([flat.control_points, np.zeros((len(flat.control_points), 1))], axis=1) @ Q.T
    space = cagd.BSplineCurve(P, 2, flat.knots, flat.weights)
    comb = curvature_comb(space, scale=1.0)
    np.testing.assert_allclose(comb.curvature, 1 / 3, rtol=1e-13)
    np.testing.assert_allclose(comb.normals, comb.base / 3, atol=1e-13)


def test_g1_joint_of_two_arcs_shows_the_curvature_jump():
    """Arcs of radii 1 and 2 joined with a common tangent at t = 0.5 (a double knot): two
    teeth at the joint, the left with curvature 1, the right with 1/2; uniform sampling
    of the whole domain would put no tooth on the joint at all."""
    P = [[0, -1], [1, -1], [1, 0], [1, 2], [-1, 2]]
    curve = cagd.BSplineCurve(P, 2, [0, 0, 0, .5, .5, 1, 1, 1], [1, S, 1, S, 1])
    report = cagd.continuity(*[cagd.BezierCurve(p.control_points, p.weights) for p in curve.to_bezier()])
    assert report.G1 and not report.G2
    comb = curvature_comb(curve, scale=1.0)
    at = np.flatnonzero(comb.params == 0.5)
    assert at.tolist() == [7, 8] and comb.span[at].tolist() == [0, 1]
    np.testing.assert_allclose(comb.curvature[at], [1.0, 0.5], rtol=1e-13)
    np.testing.assert_allclose(comb.base[at], [[1, 0], [1, 0]], atol=1e-15)
    np.testing.assert_allclose(comb.tips[at], [[2, 0], [1.5, 0]], atol=1e-14)
    np.testing.assert_allclose(comb.curvature[:8], 1.0, rtol=1e-13)
    np.testing.assert_allclose(comb.curvature[8:], 0.5, rtol=1e-13)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 20), st.integers(0, 200), st.integers(1, 12))
def test_every_span_sampled_on_its_closed_interval(per, total, spans):
    """At least ``samples_per_span`` teeth per span (both span ends included), at least
    ``samples`` in all, parameters non-decreasing."""
    knots = np.concatenate([[0, 0, 0], np.sort(np.random.default_rng(spans).uniform(0, 1, spans - 1)), [1, 1, 1]])
    P = np.random.default_rng(per).normal(size=(spans + 2, 2))
    curve = cagd.BSplineCurve(P, 2, knots)
    comb = curvature_comb(curve, samples_per_span=per, samples=total)
    breaks = np.unique(knots)
    assert len(comb.params) >= max(total, per * (len(breaks) - 1))
    assert np.all(np.diff(comb.params) >= 0)
    for j in range(len(breaks) - 1):
        t = comb.params[comb.span == j]
        assert len(t) >= per and t[0] == breaks[j] and t[-1] == breaks[j + 1]


def test_straight_curve_and_default_scale():
    line = cagd.BezierCurve([[0, 0], [1, 1], [3, 3]])
    comb = curvature_comb(line)
    assert comb.scale == 0.0 and np.all(comb.normals == 0) and np.array_equal(comb.tips, comb.base)
    arc = circle(2.0)
    comb = curvature_comb(arc)
    longest = np.linalg.norm(comb.tips - comb.base, axis=1).max()
    np.testing.assert_allclose(longest, COMB_SIZE * np.ptp(comb.base, axis=0).max(), rtol=1e-12)


def test_comb_is_a_frozen_value():
    comb = curvature_comb(circle())
    with pytest.raises(dataclasses.FrozenInstanceError):
        comb.scale = 2.0
    with pytest.raises(ValueError):
        comb.tips[0, 0] = 1.0
    half = comb.scaled(comb.scale / 2)
    np.testing.assert_allclose(half.tips - half.base, (comb.tips - comb.base) / 2, atol=1e-15)


@pytest.mark.parametrize("kwargs, name", [({"samples_per_span": 1}, "samples_per_span"),
                                          ({"samples": -1}, "samples"), ({"scale": float("nan")}, "scale")])
def test_bad_arguments(kwargs, name):
    with pytest.raises(cagd.CagdError, match=name):
        curvature_comb(circle(), **kwargs)
    with pytest.raises(cagd.CagdError, match="curve"):
        curvature_comb(np.zeros((3, 2)))
