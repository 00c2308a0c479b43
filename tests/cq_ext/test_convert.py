"""``to_cq``, ``to_b3d`` and ``from_shape``: the engine object, the CadQuery shape and
the build123d shape evaluate to the same points at the same parameters (measured
~1e-15 relative; bound 1e-12), for generated B-spline/NURBS curves (periodic too) and
surfaces; ``from_shape`` of CadQuery's and build123d's own shapes (circles, splines,
box, sphere and revolution faces) gives engine B-splines on the OCCT geometry.

Each library is evaluated through its own API where it evaluates at a raw parameter
(cq: ``Edge.positionAt(t, mode="parameter")``, ``Face.positionAt(u, v)``; build123d:
``Face.position_at`` on the normalised face domain). build123d's
``Edge.position_at`` is normalised by arc length even in PARAMETER mode
(GCPnts_AbscissaPoint), so its edges are evaluated through ``.wrapped`` and
BRepAdaptor_Curve.
"""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

cq = pytest.importorskip("cadquery")
bd = pytest.importorskip("build123d")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cagd import CagdError  # noqa: E402

from cq_helpers import distance_to_shape, edge_points, edge_range, face_points  # noqa: E402
from occ_strategies import (bezier_curves, bezier_surfaces_3d, bspline_surfaces_3d, kinked_curves,  # noqa: E402
                            periodic_curves)
from strategies import bspline_curves  # noqa: E402

EXACT = 1e-12
# OCCT's own evaluator loses digits with the degree (measured against the engine, 400
# generated curves: <= 2.3e-14 relative up to degree 6, 1.1e-13 at 7, 5e-13 at 9-10, once
# 1.04e-12 at degree 10; the engine's values agree with exact rational de Boor
# evaluation to ~6e-16 on the same curves), so degrees above 6 get 1e-11.
HIGH_DEGREE = 1e-11
FAST = settings(max_examples=20, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def pad3(P):
    P = np.asarray(P, dtype=float)
    return np.hstack([P, np.zeros((len(P), 3 - P.shape[1]))]) if P.shape[1] < 3 else P


def scale(curve_or_surface) -> float:
    n = curve_or_surface.to_nurbs()
    return max(float(np.abs(n.control_points).max()), 1.0)


def check_curve(curve):
    a, b = curve.domain
    ts = np.linspace(a, b, 23)
    expected = pad3(curve(ts))
    tol = (EXACT if curve.to_nurbs().degree <= 6 else HIGH_DEGREE) * scale(curve)
    e = cq_ext.to_cq(curve)
    assert isinstance(e, cq.Edge) and e.isValid()
    assert np.allclose(edge_range(e), (a, b), rtol=0, atol=1e-12 * max(1.0, abs(a), abs(b)))
    got = np.array([e.positionAt(t, mode="parameter").toTuple() for t in ts])
    assert np.abs(got - expected).max() <= tol
    f = cq_ext.to_b3d(curve)
    assert isinstance(f, bd.Edge)
    assert np.abs(edge_points(f, ts) - expected).max() <= tol
    # back to the engine, from both libraries
    for shape in (e, f):
        back = cq_ext.from_shape(shape, dim=curve.dim)
        assert back.domain == pytest.approx((a, b), abs=1e-12 * max(1.0, abs(a), abs(b)))
        assert np.abs(back(ts) - curve(ts)).max() <= tol


@FAST
@given(bspline_curves())
def test_bspline_curves(curve):
    check_curve(curve)


@FAST
@given(periodic_curves())
def test_periodic_curves(curve):
    check_curve(curve)
    e = cq_ext.to_cq(curve)
    assert e.IsClosed()


@FAST
@given(st.one_of(bezier_curves(), kinked_curves()))
def test_bezier_and_kinked_curves(curve):
    check_curve(curve)


def flat(surface) -> bool:
    """Collapsed to a curve or a point (no surface for OCCT to make a face of)."""
    (a, b), (c, d) = surface.domain
    u, v = np.meshgrid(np.linspace(a, b, 7)[1:-1], np.linspace(c, d, 7)[1:-1], indexing="ij")
    D = surface.to_nurbs().derivatives(u.ravel(), v.ravel(), 1, 1)
    n = np.linalg.norm(np.cross(D[1, 0], D[0, 1]), axis=-1).max()
    return bool(n <= 1e-6 * np.linalg.norm(D[1, 0], axis=-1).max() * np.linalg.norm(D[0, 1], axis=-1).max())


def check_surface(surface, generated=True):
    if generated:
        assume(not flat(surface))
    (a, b), (c, d) = surface.domain
    s, t = np.linspace(0, 1, 7), np.linspace(0, 1, 6)
    S, T = np.meshgrid(s, t, indexing="ij")
    U, V = a + S * (b - a), c + T * (d - c)
    expected = surface(U, V).reshape(-1, 3)
    tol = EXACT * scale(surface)
    f = cq_ext.to_cq(surface, nurbs=True)      # the NURBS face: the engine's own parametrisation
    assert isinstance(f, cq.Face)
    bounds = f._uvBounds()
    assert np.allclose(bounds, (a, b, c, d), rtol=0, atol=1e-12 * max(1.0, *map(abs, (a, b, c, d))))
    got = np.array([f.positionAt(u, v).toTuple() for u, v in zip(U.ravel(), V.ravel())])
    assert np.abs(got - expected).max() <= tol
    g = cq_ext.to_b3d(surface, nurbs=True)
    assert isinstance(g, bd.Face)
    got = np.array([tuple(g.position_at(x, y)) for x, y in zip(S.ravel(), T.ravel())])
    # build123d maps the normalised (x, y) to u = a + x (b - a): one rounding more
    assert np.abs(got - expected).max() <= tol
    for shape in (f, g):
        back = cq_ext.from_shape(shape)
        assert np.abs(back(U, V).reshape(-1, 3) - expected).max() <= tol


@FAST
@given(bspline_surfaces_3d(max_degree_u=3, max_degree_v=3))
def test_bspline_surfaces(surface):
    check_surface(surface)


@FAST
@given(bspline_surfaces_3d(kind_u="periodic", max_degree_u=3, max_degree_v=3))
def test_periodic_surfaces(surface):
    check_surface(surface)


@FAST
@given(bezier_surfaces_3d(max_degree=4))
def test_bezier_surfaces(surface):
    check_surface(surface)


def test_the_sphere_and_a_triangle_through_their_nurbs_forms():
    for s in (cagd.sphere(2.0, (1.0, -1.0, 0.5)), cagd.torus(3.0, 1.0, (0.0, 0.0, 1.0))):
        check_surface(s, generated=False)
    tri = cagd.BezierTriangle([(0, 0, 0), (1, 0, 0.5), (2, 0, 0), (0, 1, 0.5), (1, 1, 1), (0, 2, 0)])
    face = cq_ext.to_cq(tri)
    # the collapsed-edge form: T(u, v) = S(u, v / (1 - u)) on the triangle u + v <= 1
    N = tri.to_nurbs()
    u, v = np.meshgrid(np.linspace(0, 0.9, 5), np.linspace(0, 1, 5), indexing="ij")
    assert np.abs(face_points(face, u, v) - N(u, v).reshape(-1, 3)).max() <= EXACT * 2


@pytest.mark.parametrize("make, kind", [(lambda: cagd.sphere(2.0, (1.0, -1.0, 0.5)), "SPHERE"),
                                        (lambda: cagd.torus(3.0, 1.0), "TORUS"),
                                        (lambda: cagd.cylinder(1.0, 2.0), "CYLINDER"),
                                        (lambda: cagd.cone(1.0, 2.0), "CONE"),
                                        (lambda: cagd.revolve(cagd.BezierCurve([[1, 0, 0], [2, 0, 1.0], [1, 0, 2]])),
                                         "REVOLUTION")])
def test_primitives_become_analytic_faces(make, kind):
    """to_cq / to_b3d of an engine surface of revolution: OCCT's analytic surface, the
    engine's points on it (BRepExtrema); nurbs=True the B-spline face."""
    s = make()
    f, g = cq_ext.to_cq(s), cq_ext.to_b3d(s)
    assert f.geomType() == kind and g.geom_type.name == kind and f.isValid()
    (u0, u1), (v0, v1) = s.domain
    u, v = np.meshgrid(np.linspace(u0, u1, 5), np.linspace(v0, v1, 7), indexing="ij")
    points = s(u, v).reshape(-1, 3)
    assert distance_to_shape(f, points).max() <= EXACT * scale(s)
    assert cq_ext.to_cq(s, nurbs=True).geomType() == "BSPLINE"
    assert cq_ext.to_b3d(s, nurbs=True).geom_type.name == "BSPLINE"


# --- from_shape of CadQuery's and build123d's own shapes ------------------------------------
def samples(curve, n=41):
    return curve(np.linspace(*curve.domain, n))


@pytest.mark.parametrize("make", [lambda: cq.Edge.makeCircle(2.5, cq.Vector(1, 2, 3), cq.Vector(1, 1, 1)),
                                  lambda: bd.Edge.make_circle(2.5, bd.Plane(origin=(1, 2, 3), z_dir=(1, 1, 1)))])
def test_from_shape_circle(make):
    edge = make()
    c = cq_ext.from_shape(edge)
    assert isinstance(c, cagd.BSplineCurve) and c.is_rational
    P = samples(c)
    center, normal = np.array([1.0, 2, 3]), np.array([1.0, 1, 1]) / math.sqrt(3)
    assert np.abs(np.linalg.norm(P - center, axis=1) - 2.5).max() <= 1e-12 * 2.5
    assert np.abs((P - center) @ normal).max() <= 1e-12 * 2.5
    assert c.arc_length() == pytest.approx(2 * math.pi * 2.5, rel=1e-9)
    # the engine curve's ends are the edge's ends (a full circle: its seam vertex)
    assert np.abs(c(np.array(c.domain)) - edge_points(edge, edge_range(edge))).max() <= 1e-12 * 2.5


def test_from_shape_partial_circle_keeps_the_edge_range():
    edge = cq.Edge.makeCircle(2.0, angle1=30, angle2=200)
    c = cq_ext.from_shape(edge)
    ends = c(np.array(c.domain))
    assert np.abs(ends[0] - edge.startPoint().toTuple()).max() <= 1e-12
    assert np.abs(ends[1] - edge.endPoint().toTuple()).max() <= 1e-12
    assert c.arc_length() == pytest.approx(math.radians(170) * 2.0, rel=1e-9)
    assert np.abs(np.linalg.norm(samples(c), axis=1) - 2.0).max() <= 1e-12 * 2


def test_from_shape_ellipse():
    edge = cq.Edge.makeEllipse(3.0, 1.0)
    P = samples(cq_ext.from_shape(edge))
    assert np.abs((P[:, 0] / 3) ** 2 + P[:, 1] ** 2 - 1).max() <= 1e-12
    assert np.abs(P[:, 2]).max() == 0


def test_from_shape_cadquery_spline_same_parameters():
    pts = [(0, 0, 0), (1, 2, 0), (3, 1, 1), (4, 3, -1)]
    edge = cq.Edge.makeSpline([cq.Vector(*p) for p in pts])
    c = cq_ext.from_shape(edge)
    ts = np.linspace(*c.domain, 31)
    assert np.abs(c(ts) - edge_points(edge, ts)).max() <= 1e-12 * 4
    assert distance_to_shape(edge, c(ts)).max() <= 1e-9 * 4
    # it interpolates the points: each at distance ~0 from the engine curve's dense samples
    dense = c(np.linspace(*c.domain, 20001))
    for p in pts:
        assert np.linalg.norm(dense - p, axis=1).min() <= 1e-3
    assert np.allclose(c(np.array(c.domain)), [pts[0], pts[-1]], atol=1e-12)


def test_from_shape_box_faces():
    box = cq.Workplane().box(2, 3, 4).translate((1, 1, 1))
    for face in box.faces().vals():
        s = cq_ext.from_shape(face)
        n = np.array(face.normalAt().toTuple())
        p0 = np.array(face.Center().toTuple())
        u = np.linspace(0, 1, 5)
        (a, b), (c, d) = s.domain
        P = s.grid(a + u * (b - a), c + u * (d - c)).reshape(-1, 3)
        assert np.abs((P - p0) @ n).max() <= 1e-12 * 4
        corners = s(np.array([a, b, a, b]), np.array([c, c, d, d]))
        vertices = np.array([v.toTuple() for v in face.Vertices()])
        # the natural domain's corners are the face's vertices
        assert all(np.linalg.norm(vertices - q, axis=1).min() <= 1e-12 for q in corners)


@pytest.mark.parametrize("lib", ["cq", "b3d"])
def test_from_shape_sphere_faces(lib):
    if lib == "cq":
        faces = cq.Solid.makeSphere(2.0, cq.Vector(0.5, 0, 0), angleDegrees1=-90).Faces()
    else:
        faces = bd.Solid.make_sphere(2.0).moved(bd.Location((0.5, 0, 0))).faces()
    assert faces
    for face in faces:
        s = cq_ext.from_shape(face)
        (a, b), (c, d) = s.domain
        u, v = np.linspace(a, b, 9), np.linspace(c, d, 9)
        P = s.grid(u, v).reshape(-1, 3)
        assert np.abs(np.linalg.norm(P - (0.5, 0, 0), axis=1) - 2.0).max() <= 1e-9 * 2
        assert distance_to_shape(face, P[::7]).max() <= 1e-9 * 2


def test_from_shape_revolve_faces():
    solid = cq.Workplane("XZ").moveTo(1, 0).lineTo(2, 0).spline([(1.8, 1.0), (1.2, 2.0)], includeCurrent=True) \
        .close().revolve(270, (0, 0, 0), (0, 1, 0)).val()
    kinds = set()
    for face in solid.Faces():
        kinds.add(face.geomType())
        s = cq_ext.from_shape(face)
        (a, b), (c, d) = s.domain
        P = s.grid(np.linspace(a, b, 6), np.linspace(c, d, 6)).reshape(-1, 3)
        if face.geomType() == "PLANE":
            # trimmed by a non-rectangular loop: the engine surface is the plane's bounding rectangle
            n, p0 = np.array(face.normalAt().toTuple()), np.array(face.Center().toTuple())
            assert np.abs((P - p0) @ n).max() <= 1e-12 * 2
        else:
            assert distance_to_shape(face, P).max() <= 1e-9 * 2
    assert "REVOLUTION" in kinds


def test_from_shape_of_a_workplane():
    wp = cq.Workplane().bezierCurve([(0, 0), (1, 1), (2, 0)])
    c = cq_ext.from_shape(wp, dim=2)
    assert c.dim == 2
    ref = cagd.BezierCurve(np.array([(0.0, 0), (1, 1), (2, 0)]))
    t = np.linspace(0, 1, 9)
    assert np.abs(c(t) - ref(t)).max() <= 1e-15 * 4


@pytest.mark.parametrize("bad, kind", [("abc", "str"), (3, "int"), (None, "NoneType"), (np.zeros(3), "numpy ndarray")])
def test_bad_arguments(bad, kind):
    expected = f"^shape: expected a CadQuery or build123d shape or a TopoDS_Shape, got {kind}$"
    with pytest.raises(CagdError, match=expected):
        cq_ext.from_shape(bad)
    with pytest.raises(CagdError, match="obj"):
        cq_ext.to_cq(bad)
    with pytest.raises(CagdError, match="obj"):
        cq_ext.to_b3d(bad)


def test_from_shape_rejects_solids_vertices_and_crowded_workplanes():
    box = cq.Workplane().box(1, 1, 1)
    assert issubclass(CagdError, ValueError)
    with pytest.raises(CagdError, match="edge or a face"):
        cq_ext.from_shape(box.val())
    with pytest.raises(CagdError, match="edge or a face"):
        cq_ext.from_shape(box.vertices().val())
    with pytest.raises(CagdError, match="got a CadQuery Workplane holding 6 faces"):
        cq_ext.from_shape(box.faces())
