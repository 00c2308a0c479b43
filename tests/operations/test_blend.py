"""Bridge curves (cagd.blend_curve): G1/G2 measured independently at both ends with
the engine's ``continuity`` (tangent angle, curvature-vector test) and ``Curve.curvature``,
exact end points, the closed form for collinear lines, and bad input."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve, CagdError, blend_curve, continuity
from cagd.operations import curve_size
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


def check(c1, end1, c2, end2, k, scales=None):
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
        if k == 2:
            assert rep.G2, rep
    if k == 2:                                       # curvature, independently of the vector test
        size = curve_size(c1, c2)
        for kc, kb in ((c1.curvature(t1), B.curvature(0.0)), (c2.curvature(t2), B.curvature(1.0))):
            assert abs(kb - kc) <= TOL * max(kc, kb, 1.0 / size)
        assert max(res.curvature_gaps) <= TOL
    assert max(res.g1_angles) <= TOL and res.converged and res.continuity == k
    return res


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("end1, end2", COMBINATIONS)
@pytest.mark.parametrize("k", [1, 2])
def test_fixed_configurations(case, end1, end2, k):
    c1, c2 = CASES[case]
    check(c1, end1, c2, end2, k)
    check(c1, end1, c2, end2, k, scales=(0.4, 2.5))


def test_collinear_lines_give_the_uniform_segment():
    """Closed form: tangents along the chord -> control points equally spaced on it."""
    c1, c2 = BezierCurve([[0.0, 0.0], [1.0, 0.0]]), BezierCurve([[3.0, 0.0], [4.0, 0.0]])
    for k in (1, 2):
        n = 2 * k + 1
        P = blend_curve(c1, "end", c2, "start", k).curve.control_points
        assert np.allclose(P, np.column_stack([np.linspace(1.0, 3.0, n + 1), np.zeros(n + 1)]), rtol=0, atol=1e-15)


def test_tangent_scales_set_the_end_legs():
    c1, c2 = ARCS
    for k in (1, 2):
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
@given(end_curves(), end_curves(), st.sampled_from(ENDS), st.sampled_from(ENDS), st.sampled_from([1, 2]),
       st.tuples(st.floats(0.2, 5.0), st.floats(0.2, 5.0)))
def test_random_configurations(c1, c2, end1, end2, k, scales):
    size = curve_size(c1, c2)
    p, q = c1(end_parameter(c1, end1)), c2(end_parameter(c2, end2))
    assume(np.linalg.norm(p - q) > 0.05 * size)
    for c, e in ((c1, end1), (c2, end2)):
        assume(np.linalg.norm(c.derivative(end_parameter(c, e))) > 1e-2 * size)
    check(c1, end1, c2, end2, k, scales)


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
