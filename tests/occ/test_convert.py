"""``to_occ`` / ``from_occ``: OCCT's own evaluator (D0/D1/D2 of the Geom objects) is the
oracle; conics and elementary surfaces are checked against their closed forms."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

pytest.importorskip("OCP")

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder  # noqa: E402
from OCP.GC import GC_MakeSegment  # noqa: E402
from OCP.Geom import (Geom_BezierCurve, Geom_BezierSurface, Geom_BSplineCurve, Geom_BSplineSurface,  # noqa: E402
                      Geom_Circle, Geom_Ellipse, Geom_Line, Geom_Plane)
from OCP.Geom2d import Geom2d_BSplineCurve  # noqa: E402
from OCP.gp import gp_Ax2, gp_Dir, gp_Pln, gp_Pnt, gp_Pnt2d, gp_Vec, gp_Vec2d  # noqa: E402
from OCP.TopAbs import TopAbs_FACE  # noqa: E402

from cagd import BezierCurve, BezierSurface, BSplineCurve, CagdError, natural_cubic_spline, sphere  # noqa: E402
from cagd.occ import from_occ, subshapes, to_occ  # noqa: E402

from occ_strategies import bezier_curves, bezier_surfaces_3d, periodic_curves  # noqa: E402
from strategies import bspline_curves  # noqa: E402
from surface_strategies import bspline_surfaces  # noqa: E402

FAST = settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def occ_curve(g, t):
    out = np.empty((2, len(t), 3))
    for j, x in enumerate(np.asarray(t, float).tolist()):
        p, v = gp_Pnt(), gp_Vec()
        g.D1(x, p, v)
        out[0, j], out[1, j] = (p.X(), p.Y(), p.Z()), (v.X(), v.Y(), v.Z())
    return out


def occ_surface(g, u, v):
    out = np.empty((3, len(u), 3))
    for j, (a, b) in enumerate(zip(np.asarray(u, float).tolist(), np.asarray(v, float).tolist())):
        p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
        g.D1(a, b, p, du, dv)
        out[:, j] = (p.X(), p.Y(), p.Z()), (du.X(), du.Y(), du.Z()), (dv.X(), dv.Y(), dv.Z())
    return out


def pad3(x):
    out = np.zeros(x.shape[:-1] + (3,))
    out[..., :x.shape[-1]] = x
    return out


def rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


def interior(a, b, n=23):
    return a + (b - a) * (np.arange(n) + 0.618) / n


# --- engine -> OCCT --------------------------------------------------------------------------
@FAST
@given(bspline_curves(max_degree=10, dims=(2, 3)))
def test_to_occ_curve_matches_occt_evaluation(c):
    g = to_occ(c)
    assert isinstance(g, Geom_BSplineCurve)
    assert g.Degree() == c.degree and g.IsPeriodic() == c.periodic and g.IsRational() == (c.weights is not None
                                                                                         and np.ptp(c.weights) > 0)
    a, b = c.domain
    assert (g.FirstParameter(), g.LastParameter()) == (a, b)
    t = np.concatenate([[a, b], interior(a, b)])
    d = occ_curve(g, t)
    # 1e-11: rounding of two different evaluators at degree <= 10 with weights up to 25:1
    # (measured up to 1.4e-12 of max |P| for a periodic degree-9 NURBS)
    scale = max(float(np.abs(c.control_points).max()), 1e-300)
    assert np.abs(d[0] - pad3(c(t))).max() <= 1e-11 * scale
    d1 = pad3(c.derivative(t[2:], 1))
    assert np.abs(d[1][2:] - d1).max() <= 1e-11 * max(np.abs(d1).max(), scale / (b - a))


@FAST
@given(bspline_surfaces(max_degree=4, dims=(3, 3)))
def test_to_occ_surface_matches_occt_evaluation(s):
    g = to_occ(s)
    assert isinstance(g, Geom_BSplineSurface)
    assert (g.UDegree(), g.VDegree()) == (s.degree_u, s.degree_v)
    assert (g.IsUPeriodic(), g.IsVPeriodic()) == (s.periodic_u, s.periodic_v)
    (a, b), (c, d) = s.domain
    assert np.allclose(g.Bounds(), (a, b, c, d), rtol=0, atol=0)
    u, v = np.meshgrid(interior(a, b, 5), interior(c, d, 5), indexing="ij")
    u, v = u.ravel(), v.ravel()
    o = occ_surface(g, u, v)
    D = s.derivatives(u, v, 1, 1)
    scale = max(float(np.abs(s.control_points).max()), 1e-300)
    assert np.abs(o[0] - D[0, 0]).max() <= 1e-12 * scale
    for k, e in ((1, D[1, 0]), (2, D[0, 1])):
        assert np.abs(o[k] - e).max() <= 1e-11 * max(np.abs(e).max(), scale)


@FAST
@given(bezier_curves())
def test_bezier_true_gives_geom_bezier_curve(c):
    g = to_occ(c, bezier=True)
    assert isinstance(g, Geom_BezierCurve)
    assert g.NbPoles() == len(c.control_points)
    t = np.linspace(0, 1, 17)
    scale = max(float(np.abs(c.control_points).max()), 1e-300)
    ratio = 1.0 if c.weights is None else float(c.weights.max() / c.weights.min())
    # OCCT's Bezier evaluator rounds more at high degree (measured 6.3e-12 of max |P|, degree 10, even at t = 1)
    assert np.abs(occ_curve(g, t)[0] - pad3(c(t))).max() <= 1e-11 * ratio * scale


@FAST
@given(bezier_surfaces_3d())
def test_bezier_true_gives_geom_bezier_surface(s):
    g = to_occ(s, bezier=True)
    assert isinstance(g, Geom_BezierSurface)
    assert (g.NbUPoles(), g.NbVPoles()) == s.control_points.shape[:2]
    u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), indexing="ij")
    scale = max(float(np.abs(s.control_points).max()), 1e-300)
    ratio = 1.0 if s.weights is None else float(s.weights.max() / s.weights.min())
    assert np.abs(occ_surface(g, u.ravel(), v.ravel())[0] - s(u.ravel(), v.ravel())).max() <= 1e-11 * ratio * scale


def test_bezier_flag_is_ignored_for_bsplines():
    assert isinstance(to_occ(BSplineCurve([[0, 0], [1, 1], [2, 0]], 2), bezier=True), Geom_BSplineCurve)
    assert isinstance(to_occ(sphere(1.0), bezier=True), Geom_BSplineSurface)


@FAST
@given(periodic_curves())
def test_plane_true_gives_geom2d(c):
    if c.dim != 2:
        with pytest.raises(CagdError, match="plane=True needs a 2-D curve"):
            to_occ(c, plane=True)
        return
    g = to_occ(c, plane=True)
    assert isinstance(g, Geom2d_BSplineCurve) and g.IsPeriodic()
    a, b = c.domain
    t = interior(a, b)
    got = []
    for x in t.tolist():
        p, v = gp_Pnt2d(), gp_Vec2d()
        g.D1(x, p, v)
        got.append((p.X(), p.Y()))
    assert np.abs(np.array(got) - c(t)).max() <= 1e-12 * max(float(np.abs(c.control_points).max()), 1e-300)
    back = from_occ(g)
    assert back.dim == 2
    assert np.abs(back(t) - c(t)).max() <= 1e-12 * max(float(np.abs(c.control_points).max()), 1e-300)


def test_two_dimensional_curve_gets_z_zero():
    c = natural_cubic_spline([[0, 0], [1, 2], [3, 1], [4, 4]])
    g = to_occ(c)
    t = np.linspace(*c.domain, 9)
    d = occ_curve(g, t)
    assert np.all(d[0][:, 2] == 0) and np.abs(d[0][:, :2] - c(t)).max() < 1e-13


# --- OCCT -> engine --------------------------------------------------------------------------
def _ax(origin=(0, 0, 0), normal=(0, 0, 1), xdir=(1, 0, 0)):
    return gp_Ax2(gp_Pnt(*origin), gp_Dir(*normal), gp_Dir(*xdir))


def test_from_occ_circle_is_exact():
    r, centre = 2.5, np.array([1.0, -2.0, 0.5])
    g = Geom_Circle(_ax(centre), r)
    c = from_occ(g)
    assert isinstance(c, BSplineCurve) and c.weights is not None
    a, b = c.domain
    t = np.linspace(a, b, 101)
    radius = np.linalg.norm(c(t) - centre, axis=1)
    assert np.abs(radius - r).max() <= 1e-15 * r * 4
    assert np.abs(c(t)[:, 2] - centre[2]).max() <= 1e-15
    assert abs(c.arc_length() - 2 * math.pi * r) <= 1e-9 * r
    # the rational form has its own parameter (not the angle): compare with OCCT's evaluation of it
    from OCP.GeomConvert import GeomConvert
    o = occ_curve(GeomConvert.CurveToBSplineCurve_s(g), t)[0]
    assert np.abs(o - c(t)).max() <= 1e-15 * 8 * r


def test_from_occ_ellipse_lies_on_the_ellipse():
    g = Geom_Ellipse(_ax(), 3.0, 1.25)
    c = from_occ(g)
    p = c(np.linspace(*c.domain, 201))
    assert np.abs((p[:, 0] / 3.0) ** 2 + (p[:, 1] / 1.25) ** 2 - 1).max() <= 1e-14
    assert np.abs(p[:, 2]).max() == 0.0


def test_from_occ_trimmed_line_and_edge():
    seg = GC_MakeSegment(gp_Pnt(1, 2, 3), gp_Pnt(4, 6, 3)).Value()
    c = from_occ(seg)
    assert np.allclose(c(np.array(c.domain)), [[1, 2, 3], [4, 6, 3]], rtol=0, atol=1e-15)
    edge = BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(0, 0, 7)).Edge()
    e = from_occ(edge)
    assert np.allclose(e(np.array(e.domain)), [[0, 0, 0], [0, 0, 7]], rtol=0, atol=1e-15)
    # an edge on part of a circle: its range only
    arc = BRepBuilderAPI_MakeEdge(Geom_Circle(_ax(), 2.0), 0.0, math.pi / 2).Edge()
    a = from_occ(arc)
    ends = a(np.array(a.domain))
    assert np.allclose(ends, [[2, 0, 0], [0, 2, 0]], rtol=0, atol=1e-14)


def test_from_occ_bezier_curve_matches_occt():
    P = np.array([[0, 0, 0], [1, 2, 0], [3, 3, 1], [4, 0, 2.0]])
    c0 = BezierCurve(P, [1, 2, 0.5, 1])
    g = to_occ(c0, bezier=True)
    c = from_occ(g)
    t = np.linspace(0, 1, 21)
    assert np.abs(c(t) - occ_curve(g, t)[0]).max() <= 1e-14 * 4
    assert np.abs(c(t) - c0(t)).max() <= 1e-14 * 4


def test_from_occ_surfaces_of_faces():
    plane = BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 1), gp_Dir(0, 0, 1)), -1.0, 2.0, -3.0, 4.0).Face()
    s = from_occ(plane)
    u, v = np.meshgrid(np.linspace(*s.domain[0], 5), np.linspace(*s.domain[1], 5), indexing="ij")
    p = s(u, v)
    assert np.all(p[..., 2] == 1.0)
    assert np.allclose([p[..., 0].min(), p[..., 0].max(), p[..., 1].min(), p[..., 1].max()], [-1, 2, -3, 4],
                       rtol=0, atol=1e-15)
    r, h = 1.5, 2.0
    cyl = BRepPrimAPI_MakeCylinder(r, h).Shape()
    lateral = [f for f in subshapes(cyl, TopAbs_FACE) if "Cylindrical" in type(
        __import__("OCP.BRep", fromlist=["BRep_Tool"]).BRep_Tool.Surface_s(f)).__name__]
    assert len(lateral) == 1
    s = from_occ(lateral[0])
    u, v = np.meshgrid(np.linspace(*s.domain[0], 13), np.linspace(*s.domain[1], 5), indexing="ij")
    p = s(u, v)
    assert np.abs(np.hypot(p[..., 0], p[..., 1]) - r).max() <= 1e-14 * r
    assert abs(p[..., 2].min()) <= 1e-15 and abs(p[..., 2].max() - h) <= 1e-14
    box = BRepPrimAPI_MakeBox(1.0, 2.0, 3.0).Shape()
    faces = [from_occ(f) for f in subshapes(box, TopAbs_FACE)]
    assert len(faces) == 6
    from cagd.surfaces.properties import area
    assert sum(area(f).value for f in faces) == pytest.approx(2 * (2 + 3 + 6), rel=1e-13)


def test_from_occ_matches_occt_on_a_converted_surface():
    g = Geom_Plane(gp_Pnt(0, 0, 0), gp_Dir(0, 1, 1))
    from OCP.Geom import Geom_RectangularTrimmedSurface
    t = Geom_RectangularTrimmedSurface(g, 0.0, 2.0, -1.0, 1.0)
    s = from_occ(t)
    u, v = np.meshgrid(np.linspace(0, 2, 4), np.linspace(-1, 1, 4), indexing="ij")
    o = occ_surface(t, u.ravel(), v.ravel())[0]
    assert np.abs(s(u.ravel(), v.ravel()) - o).max() <= 1e-15 * 4


# --- errors ----------------------------------------------------------------------------------
def test_unbounded_geometry_is_refused():
    with pytest.raises(CagdError, match="unbounded"):
        from_occ(Geom_Line(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)))
    with pytest.raises(CagdError, match="unbounded"):
        from_occ(Geom_Plane(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)))


@pytest.mark.parametrize("bad", [None, 3.0, "circle", np.zeros(3), BezierCurve([[0, 0], [1, 1]])])
def test_wrong_types(bad):
    with pytest.raises(CagdError, match="geom: expected"):
        from_occ(bad)
    if not isinstance(bad, BezierCurve):
        with pytest.raises(CagdError, match="obj: expected a cagd Curve or Surface"):
            to_occ(bad)


def test_four_dimensional_curves_are_refused():
    with pytest.raises(CagdError, match="3-D at most"):
        to_occ(BSplineCurve(np.arange(16.0).reshape(4, 4), 3))
    with pytest.raises(CagdError, match="3-D at most"):
        to_occ(BezierCurve(np.arange(12.0).reshape(3, 4)))


def test_four_dimensional_bezier_with_bezier_true_is_refused():
    with pytest.raises(CagdError, match="obj"):
        to_occ(BezierCurve(np.arange(12.0).reshape(3, 4)), bezier=True)


def test_a_shape_that_is_neither_edge_nor_face():
    with pytest.raises(CagdError, match="edge or a face"):
        from_occ(BRepPrimAPI_MakeBox(1.0, 1.0, 1.0).Shape())


def test_bezier_surface_to_occ_and_back_is_bit_exact():
    P = np.random.default_rng(3).normal(size=(3, 4, 3))
    s = BezierSurface(P, np.linspace(0.5, 2, 12).reshape(3, 4))
    b = from_occ(to_occ(s))
    assert np.array_equal(b.control_points, P) and np.array_equal(b.weights, s.weights)
