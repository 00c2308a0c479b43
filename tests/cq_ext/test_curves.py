"""The curve methods on the stack: edge/wire types, pending edges that CadQuery's
close/extrude/revolve/sweep/loft consume (volumes against Green's theorem, Pappus and
the frustum formula), placement on rotated/offset workplanes (plane.toWorldCoords of
the engine curve), interpolation properties (points, end conditions, chord/centripetal
parameters) and the G2 join (cagd.continuity on the curves read back)."""
import math

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cagd import CagdError  # noqa: E402

from cq_helpers import (edge_derivatives, edge_points, edge_range, green_area, nurbs_volume,  # noqa: E402
                        span_quad)

BLOB = [(3, 0), (2, 2), (0, 3), (-2, 1.5), (-3, -1), (0, -2.5), (2, -2)]


def closed_spline(points):
    P = np.array(list(points) + [points[0]], dtype=float)
    return cagd.natural_cubic_spline(P, "periodic", "chord")


# --- types and pending edges -----------------------------------------------------------------
@pytest.mark.parametrize("call, kind", [
    (lambda w: w.bezierCurve([(0, 0), (1, 1), (2, 0)]), cq.Edge),
    (lambda w: w.bezierCurve([(0, 0), (1, 1), (2, 0)], makeWire=True), cq.Wire),
    (lambda w: w.nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1)], weights=[1, 2, 1, 1]), cq.Edge),
    (lambda w: w.interpCurve([(0, 0), (1, 1), (2, 0)]), cq.Edge),
    (lambda w: w.interpCurve(BLOB, end_condition="periodic"), cq.Wire),
    (lambda w: w.hermiteCurve((0, 0), (1, 0), (1, 1), (1, -1)), cq.Edge),
    (lambda w: w.cagdCurve(cagd.four_point_cubic(np.array([(0.0, 0), (1, 1), (2, 1), (3, 0)]))), cq.Edge),
])
def test_result_types_and_pending(call, kind):
    wp = call(cq.Workplane("XY"))
    assert [type(o) for o in wp.vals()] == [kind]
    assert wp.val().isValid()
    pending = wp.ctx.pendingWires if kind is cq.Wire else wp.ctx.pendingEdges
    assert len(pending) == 1


@pytest.mark.parametrize("name, args", [
    ("bezierCurve", ([(0, 0), (1, 1), (2, 0)],)), ("nurbsCurve", ([(0, 0), (1, 1), (2, 0), (3, 1)],)),
    ("interpCurve", ([(0, 0), (1, 1), (2, 0)],)), ("hermiteCurve", ((0, 0), (1, 0), (1, 1), (1, -1))),
    ("joinCurves", ([(0, 0), (1, 1), (2, 0)],))])
def test_for_construction_is_not_pending(name, args):
    wp = getattr(cq.Workplane("XY"), name)(*args, forConstruction=True)
    assert wp.vals() and not wp.ctx.pendingEdges and not wp.ctx.pendingWires


def test_periodic_interp_extrudes_to_area_times_height():
    wp = cq.Workplane("XY").interpCurve(BLOB, end_condition="periodic")
    wire = wp.val()
    assert wire.IsClosed() and len(wire.Edges()) == 1
    solid = wp.extrude(2.5).val()
    assert isinstance(solid, cq.Solid) and solid.isValid()
    area = abs(green_area(closed_spline(BLOB)))
    # shoelace on dense samples: an independent check of the quadrature
    c = closed_spline(BLOB)
    P = c(np.linspace(*c.domain, 200001))
    assert abs(0.5 * np.sum(P[:-1, 0] * P[1:, 1] - P[1:, 0] * P[:-1, 1])) == pytest.approx(area, rel=1e-9)
    assert nurbs_volume(solid) == pytest.approx(area * 2.5, rel=1e-9)


def test_periodic_interp_is_c2_at_the_seam():
    e = cq.Workplane("XY").interpCurve(BLOB, end_condition="periodic").val().Edges()[0]
    a, b = edge_range(e)
    p0, d0, s0 = edge_derivatives(e, a)
    p1, d1, s1 = edge_derivatives(e, b)
    assert np.abs(p0 - p1).max() <= 1e-12 * 3
    assert np.abs(d0 - d1).max() <= 1e-12 * np.abs(d0).max()
    assert np.abs(s0 - s1).max() <= 1e-9 * np.abs(s0).max()
    assert np.allclose(p0, (3, 0, 0), atol=1e-12)


def test_bezier_close_extrude():
    ctrl = np.array([(0.0, 0), (1, 2), (3, 2), (4, 0)])
    solid = cq.Workplane("XY").bezierCurve(ctrl).close().extrude(1.5).val()
    assert solid.isValid() and len(solid.Faces()) == 4
    # the area under the cubic (the chord closes it on the x axis): int y dx
    bz = cagd.BezierCurve(ctrl)
    area = abs(span_quad(lambda t: bz(np.array([t]))[0, 1] * bz.derivative(np.array([t]), 1)[0, 0], bz))
    assert area == pytest.approx(4.2, rel=1e-12)           # int_0^1 y x' dt = int 6t(1-t)(3+6t-6t^2) dt = 21/5
    assert nurbs_volume(solid) == pytest.approx(area * 1.5, rel=1e-9)


def test_include_current_starts_at_the_current_point():
    wp = cq.Workplane("XY").moveTo(1, 1).bezierCurve([(2, 3), (4, 0)], includeCurrent=True)
    e = wp.val()
    assert np.allclose(e.startPoint().toTuple(), (1, 1, 0), atol=1e-15)
    solid = wp.close().extrude(1).val()
    assert solid.isValid()


def test_nurbs_curve_as_sweep_path():
    ctrl = [(0, 0), (0, 5), (5, 10), (10, 10)]
    path = cq.Workplane("XZ").nurbsCurve(ctrl, degree=3)
    assert isinstance(path.val(), cq.Edge)
    r = 0.5
    solid = cq.Workplane("XY").circle(r).sweep(path).val()
    assert solid.isValid()
    eng = cagd.BSplineCurve(np.array(ctrl, dtype=float), 3)
    assert eng.curvature(np.linspace(0, 1, 401)).max() * r < 0.1      # a tube without self-overlap
    # Pappus for a tube along a planar path: pi r^2 L (OCCT's sweep approximates: measured 7.8e-7)
    assert nurbs_volume(solid) == pytest.approx(math.pi * r * r * eng.arc_length(), rel=1e-5)
    # the path edge is the engine curve on the XZ plane: (x, y) -> (x, 0, y)
    t = np.linspace(0, 1, 11)
    P = eng(t)
    assert np.abs(edge_points(path.val(), t) - np.column_stack([P[:, 0], 0 * t, P[:, 1]])).max() <= 1e-12 * 10


def test_loft_between_two_periodic_interp_wires():
    small = [(0.5 * x, 0.5 * y) for x, y in BLOB]
    solid = cq.Workplane("XY").interpCurve(BLOB, end_condition="periodic").workplane(offset=3) \
        .interpCurve(small, end_condition="periodic").loft().val()
    assert solid.isValid()
    # similar sections (scaled about the axis): a frustum, V = h/3 (A1 + A2 + sqrt(A1 A2))
    A1 = abs(green_area(closed_spline(BLOB)))
    A2 = A1 / 4
    assert nurbs_volume(solid) == pytest.approx(3 / 3 * (A1 + A2 + math.sqrt(A1 * A2)), rel=1e-9)


def test_interp_profile_revolved_by_cadquery_pappus():
    pts = [(1, 0), (2, 1), (1.5, 2), (1, 3)]
    solid = cq.Workplane("XY").interpCurve(pts).close().revolve(360, (0, 0, 0), (0, 1, 0)).val()
    assert solid.isValid()
    c = cagd.natural_cubic_spline(np.array(pts, dtype=float))
    # V = 2 pi int int x dA = pi |oint x^2 dy|; the closing segment x = 1 from y = 3 to 0 adds -3
    line = span_quad(lambda t: c(np.array([t]))[0, 0] ** 2 * c.derivative(np.array([t]), 1)[0, 1], c)
    assert nurbs_volume(solid) == pytest.approx(math.pi * abs(line - 3.0), rel=1e-9)


# --- placement -------------------------------------------------------------------------------
PLANES = [cq.Plane.named("XZ"), cq.Plane.named("YZ"), cq.Plane.named("right"),
          cq.Plane(origin=(1, -2, 3), xDir=(1, 1, 1), normal=(0, -1, 1)),
          cq.Plane(origin=(1, -2, 3), xDir=(1, 1, 0), normal=(0, -1, 1))]    # xDir not perpendicular


@pytest.mark.parametrize("plane", PLANES, ids=["XZ", "YZ", "right", "tilted", "skew-xDir"])
def test_curve_lands_where_the_plane_maps_it(plane):
    ctrl = np.array([(0.0, 0), (1, 2), (3, 2), (4, -1)])
    w = [1.0, 2.0, 0.5, 1.0]
    e = cq.Workplane(plane).nurbsCurve(ctrl, degree=2, weights=w).val()
    eng = cagd.BSplineCurve(ctrl, 2, weights=w)
    t = np.linspace(0, 1, 17)
    expected = np.array([plane.toWorldCoords(tuple(p)).toTuple() for p in eng(t)])
    assert np.abs(edge_points(e, t) - expected).max() <= 1e-12 * 6
    # and where CadQuery's own spline through the end points starts and ends
    ref = cq.Workplane(plane).spline([tuple(ctrl[-1])], includeCurrent=True).val()
    assert np.abs(edge_points(e, [0.0, 1.0]) - [ref.startPoint().toTuple(), ref.endPoint().toTuple()]).max() \
        <= 1e-12 * 6


def test_transformed_workplane_and_3d_points():
    wp = cq.Workplane("XY").transformed(rotate=(30, 45, 10), offset=(1, 2, 3))
    ctrl = np.array([(0.0, 0, 0), (1, 2, 1), (3, 2, -1), (4, -1, 0)])
    e = wp.bezierCurve(ctrl).val()
    eng = cagd.BezierCurve(ctrl)
    t = np.linspace(0, 1, 17)
    expected = np.array([wp.plane.toWorldCoords(tuple(p)).toTuple() for p in eng(t)])
    assert np.abs(edge_points(e, t) - expected).max() <= 1e-12 * 6
    # the same as CadQuery's own placement of a line between the end points
    line = wp.moveTo(0, 0).lineTo(4, -1).val()
    assert np.allclose(line.endPoint().toTuple(), expected[-1], atol=1e-12)


# --- interpolation and Hermite -----------------------------------------------------------------
PTS = np.array([(0.0, 0.0), (1.0, 2.0), (3.0, 2.5), (4.0, 0.0), (6.0, 1.0)])


@pytest.mark.parametrize("par", ["chord", "centripetal", "uniform"])
def test_interp_parameters_and_points(par):
    e = cq.Workplane("XY").interpCurve(PTS, parametrization=par).val()
    d = np.linalg.norm(np.diff(PTS, axis=0), axis=1)
    step = {"chord": d, "centripetal": np.sqrt(d), "uniform": np.ones_like(d)}[par]
    t = np.concatenate([[0.0], np.cumsum(step)])
    t = t / t[-1] * (edge_range(e)[1] - edge_range(e)[0]) + edge_range(e)[0]
    # the points are reached at the parameters of the chosen parametrization (up to a linear map)
    assert np.abs(edge_points(e, t)[:, :2] - PTS).max() <= 1e-12 * 6
    # natural end condition: zero second derivative at both ends
    for x in edge_range(e):
        _, d1, d2 = edge_derivatives(e, x)
        assert np.linalg.norm(d2) <= 1e-12 * np.linalg.norm(d1) * 10


def test_interp_clamped_tangents():
    tangents = [(1.0, 3.0), (2.0, -4.0)]
    e = cq.Workplane("XY").interpCurve(PTS, end_condition="clamped", tangents=tangents).val()
    a, b = edge_range(e)
    eng = cagd.natural_cubic_spline(PTS, "clamped", "chord", tangents=np.array(tangents))
    assert (a, b) == pytest.approx(eng.domain, abs=1e-12)
    for x, tan in zip((a, b), tangents):
        _, d1, _ = edge_derivatives(e, x)
        assert np.abs(d1 - (*tan, 0.0)).max() <= 1e-12 * 10


def test_hermite_curve_against_the_hermite_basis():
    p0, p1, t0, t1 = np.array([0.0, 0, 1]), np.array([3.0, 1, 0]), np.array([1.0, 2, 0]), np.array([2.0, -1, 1])
    e = cq.Workplane("XY").hermiteCurve(p0, p1, t0, t1).val()
    assert edge_range(e) == (0.0, 1.0)
    s = np.linspace(0, 1, 11)
    H = np.column_stack([2 * s**3 - 3 * s**2 + 1, -2 * s**3 + 3 * s**2, s**3 - 2 * s**2 + s, s**3 - s**2])
    assert np.abs(edge_points(e, s) - H @ np.vstack([p0, p1, t0, t1])).max() <= 1e-12 * 4
    for x, tan in ((0.0, t0), (1.0, t1)):
        assert np.abs(edge_derivatives(e, x)[1] - tan).max() <= 1e-12 * 4


def test_cagd_curve_and_to_cq_agree():
    c = cagd.HermiteSpline(np.array([(0.0, 0), (1, 1), (3, 0)]), np.array([(1.0, 0), (1, 1), (0, -1)]),
                           np.array([0.0, 1.0, 2.5]))
    e = cq.Workplane("XY").cagdCurve(c).val()
    t = np.linspace(*c.domain, 13)
    assert np.abs(edge_points(e, t)[:, :2] - c(t)).max() <= 1e-12 * 3


# --- G1/G2 join --------------------------------------------------------------------------------
@pytest.mark.parametrize("beta", [0.0, 1.5])
def test_join_curves_g2(beta):
    wp = cq.Workplane("XY").joinCurves([(0, 0), (1, 2), (3, 2), (4, 0)], continuity="G2", alpha=1.3, beta=beta)
    edges = wp.vals()
    assert len(edges) == 2 and all(isinstance(e, cq.Edge) for e in edges)
    assert len(wp.ctx.pendingEdges) == 2
    c1, c2 = (cq_ext.from_shape(e, dim=2) for e in edges)
    rep = cagd.continuity(c1, c2)
    assert rep.G1 and rep.G2, rep
    assert rep.gap <= 1e-12 and rep.curvature_difference <= 1e-9
    # the two pending edges make one wire with CadQuery's own wire builder
    wire = cq.Wire.assembleEdges(edges)
    assert wire.isValid() and len(wire.Edges()) == 2


def test_join_curves_g1_is_not_g2():
    """Negative control: a G1 join generally has a curvature jump, and continuity sees it."""
    wp = cq.Workplane("XY").joinCurves([(0, 0), (1, 2), (3, 2), (4, 0)], continuity="G1",
                                      rest_points=[(6, 2), (7, 0)])
    c1, c2 = (cq_ext.from_shape(e, dim=2) for e in wp.vals())
    rep = cagd.continuity(c1, c2)
    assert rep.G1 and not rep.G2
    assert rep.curvature_difference > 1e-3


# --- errors -----------------------------------------------------------------------------------
@pytest.mark.parametrize("call, word", [
    (lambda w: w.nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1)], weights=[1, -1, 1, 1]), "weights"),
    (lambda w: w.nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1)], weights=[1, 0, 1, 1]), "weights"),
    (lambda w: w.bezierCurve([(0, 0), (1, 1), (2, 0)], weights=[1, -2, 1]), "weights"),
    (lambda w: w.nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1)], knots=[0, 0, 1]), "knots"),
    (lambda w: w.nurbsCurve([(0, 0), (1, 1)], degree=3), "degree"),
    (lambda w: w.interpCurve([(0, 0), (1, 1), (2, 0)], end_condition="foo"), "end_condition"),
    (lambda w: w.interpCurve([(0, 0), (1, 1), (2, 0)], parametrization="foo"), "parametrisation 'foo'"),
    (lambda w: w.interpCurve([(0, 0), (1, 1), (2, 0)], end_condition="clamped"), "tangents"),
    (lambda w: w.cagdCurve("abc"), "curve"),
    (lambda w: w.cagdCurve(cagd.sphere(1.0, (0, 0, 0))), "curve"),
    (lambda w: w.hermiteCurve("ab", (1, 0), (1, 0), (0, 1)), "p0"),
    (lambda w: w.hermiteCurve((0, 0), (1, 0, 0), (1, 0), (0, 1)), "p1"),
    (lambda w: w.joinCurves([(0, 0), (1, 1), (2, 0)], continuity="G3"), "continuity"),
    (lambda w: w.joinCurves("abc"), "control_points"),
])
def test_bad_arguments(call, word):
    with pytest.raises(CagdError, match=word) as info:
        call(cq.Workplane("XY"))
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("call", [lambda w: w.bezierCurve([1, 2, 3]), lambda w: w.nurbsCurve([1, 2, 3, 4])])
def test_one_dimensional_points_are_refused(call):
    with pytest.raises(CagdError, match="control_points"):
        call(cq.Workplane("XY"))
