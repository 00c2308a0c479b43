"""Workplane.fitCurve / rebuild / removeKnots (issue 17): the edge on the stack is within
tol of the points (measured on the edge read back through OCCT, by certified closest
points), end tangents held, workplane placement applied, the vertices on the stack used
when no points are given; rebuild and removeKnots replace the stack's edges and faces with
the asked size / within tol of the originals."""
import numpy as np
import pytest

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402,F401
from cagd import CagdError  # noqa: E402
from cq_ext import from_shape  # noqa: E402

S = np.linspace(0.0, 1.0, 300)
PTS = np.stack([60 * S, 10 * np.sin(5 * S), 3 * np.cos(4 * S)], axis=1)


def test_fit_curve_edge_within_tol():
    wp = cq.Workplane("XY").fitCurve(PTS, tol=0.01)
    edge = wp.val()
    assert isinstance(edge, cq.Edge) and len(wp.ctx.pendingEdges) == 1
    back = from_shape(edge)
    assert float(cagd.closest_point(back, PTS).distances.max()) <= 0.01 + 1e-9


def test_fit_curve_on_an_offset_workplane_and_from_vertices():
    wp = cq.Workplane("XZ", origin=(0, 5, 0)).fitCurve(PTS[:, :2], tol=0.005)
    back = from_shape(wp.val())
    plane = cq.Workplane("XZ", origin=(0, 5, 0)).plane
    glob = np.array([plane.toWorldCoords((x, y, 0)).toTuple() for x, y in PTS[:, :2]])
    assert float(cagd.closest_point(back, glob).distances.max()) <= 0.005 + 1e-9
    stacked = cq.Workplane("XY").newObject([cq.Vertex.makeVertex(*p) for p in PTS[::10]])
    e = from_shape(stacked.fitCurve(tol=0.01).val())
    assert float(cagd.closest_point(e, PTS[::10]).distances.max()) <= 0.01 + 1e-9


def test_fit_curve_holds_end_tangents_and_refuses_an_unmet_tol():
    wp = cq.Workplane("XY").fitCurve(PTS, tol=0.01, start_tangent=(1, 0.5, 0), end_tangent=(1, -1, 0))
    c = from_shape(wp.val())
    d0, d1 = c.derivative(c.domain[0]), c.derivative(c.domain[1])
    for d, T in ((d0, np.array([1, 0.5, 0])), (d1, np.array([1, -1, 0]))):
        assert np.linalg.norm(np.cross(d / np.linalg.norm(d), T / np.linalg.norm(T))) <= 1e-9
    noisy = PTS + np.random.default_rng(0).normal(0, 0.05, PTS.shape)
    with pytest.raises(CagdError, match="tol"):
        cq.Workplane("XY").fitCurve(noisy, tol=1e-6, max_control_points=20)
    with pytest.raises(CagdError, match="points"):
        cq.Workplane("XY").fitCurve(tol=0.1)


def test_rebuild_and_remove_knots_on_the_stack():
    c = cagd.fit_curve(PTS, 0.01).curve
    wp = cq.Workplane("XY").cagdCurve(c).rebuild(20, 3)
    back = from_shape(wp.val())
    assert len(back.control_points) == 20 and back.degree == 3
    dense = c.refine(np.linspace(0.05, 0.95, 30))
    fewer = from_shape(cq.Workplane("XY").cagdCurve(dense).removeKnots(1e-9).val())
    assert len(fewer.control_points) == len(c.control_points)
    t = np.linspace(0, 1, 501)
    assert np.abs(fewer(t) - c(t)).max() <= 1e-8
    surf = cagd.BSplineSurface(np.random.default_rng(1).random((5, 5, 3)), 3, 3)
    face = from_shape(cq.Workplane("XY").cagdSurface(surf).rebuild((7, 6), (3, 2)).val())
    assert face.control_points.shape[:2] == (7, 6) and (face.degree_u, face.degree_v) == (3, 2)
    with pytest.raises(CagdError, match="no edges or faces"):
        cq.Workplane("XY").rebuild(5)


def test_periodic_fit_is_a_closed_wire_that_extrudes():
    phi = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = np.stack([10 * np.cos(phi), 6 * np.sin(phi)], axis=1)
    wp = cq.Workplane("XY").fitCurve(ring, tol=0.01, periodic=True)
    wire = wp.val()
    assert isinstance(wire, cq.Wire) and wire.IsClosed()
    solid = wp.extrude(2.0).val()
    assert solid.isValid()
    assert solid.Volume() == pytest.approx(np.pi * 10 * 6 * 2.0, rel=1e-3)


def _grid():
    x, y = np.meshgrid(np.linspace(0, 40, 30), np.linspace(0, 30, 25), indexing="ij")
    return np.stack([x, y, 3 * np.sin(x / 9) * np.cos(y / 7)], -1)


def test_fit_surface_auto_degree_is_the_engines_choice(caplog):
    """fitSurface(degree="auto"): the face read back through OCCT is fit_surface(...,
    degree="auto")'s surface (degree and poles), which is the degree of AUTO_DEGREES with
    the fewest control points (each fitted here), every grid point within tol of the face
    (certified closest points); the summary with the degree is logged. At tol 3e-4 (4 here:
    10 x 9 poles against 11 x 10 at degree 3; at 0.01 the tuned knots make 3 the fewest)."""
    import logging
    from cagd.fitting.fit_surface import AUTO_DEGREES
    Q = _grid()
    with caplog.at_level(logging.INFO, logger="cq_ext.workplane"):
        wp = cq.Workplane("XY").fitSurface(Q, tol=3e-4, degree="auto")
    face = wp.val()
    assert isinstance(face, cq.Face)
    back = from_shape(face)
    each = {p: cagd.fit_surface(Q, 3e-4, degree=p) for p in AUTO_DEGREES}
    fewest = min((f.surface.control_points[..., 0].size, p) for p, f in each.items() if f.converged)[1]
    assert fewest != 3                                 # the default degree would not pass
    assert (back.degree_u, back.degree_v) == (fewest, fewest)
    assert np.abs(np.asarray(back.control_points) - each[fewest].surface.control_points).max() <= 1e-9
    assert float(cagd.closest_point(back, Q.reshape(-1, 3)).distances.max()) <= 3e-4 + 1e-9
    assert f"degree {fewest} x {fewest}" in caplog.text


def test_fit_surface_placed_scattered_and_refusing_an_unmet_tol():
    """On an offset workplane the face is the local fit placed; scattered points fit too;
    a cap that cannot meet tol raises with the achieved error."""
    Q = _grid()
    wp = cq.Workplane("XZ", origin=(0, 5, 0)).fitSurface(Q, tol=0.01, degree=4)
    plane = cq.Workplane("XZ", origin=(0, 5, 0)).plane
    glob = np.array([plane.toWorldCoords(tuple(p)).toTuple() for p in Q.reshape(-1, 3)])
    assert float(cagd.closest_point(from_shape(wp.val()), glob).distances.max()) <= 0.01 + 1e-9
    rng = np.random.default_rng(1)
    X, Y = rng.random(500) * 40, rng.random(500) * 30
    P = np.stack([X, Y, 3 * np.sin(X / 9) * np.cos(Y / 7)], -1)
    face = from_shape(cq.Workplane("XY").fitSurface(P, tol=0.02, degree="auto").val())
    assert float(cagd.closest_point(face, P).distances.max()) <= 0.02 + 1e-9
    with pytest.raises(CagdError, match="tol.*not met"):
        cq.Workplane("XY").fitSurface(Q, tol=1e-6, max_control_points=(5, 5))
    with pytest.raises(CagdError, match="degree"):
        cq.Workplane("XY").fitSurface(Q, tol=0.01, degree="best")
