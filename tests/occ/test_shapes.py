"""OCCT shapes from engine geometry: validity (BRepCheck), sewing, solids, and mass
properties from OCCT against closed forms, scipy and the engine's own quadrature."""
import math

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE  # noqa: E402

from cagd import (BezierCurve, BezierTriangle, BSplineCurve, CagdError, ellipsoid, natural_cubic_spline,  # noqa: E402
                  revolve, sphere, torus)
from cagd.occ import (area, check_valid, free_edge_count, make_edge, make_face, make_solid, make_wire, sew,  # noqa: E402
                      solid_from_surfaces, subshapes, volume)
from cagd.surfaces import properties  # noqa: E402


def test_edges_and_wires():
    a = BezierCurve([[0, 0, 0], [1, 1, 0], [2, 0, 0]])
    b = BSplineCurve([[2, 0, 0], [3, -1, 1], [4, 0, 0], [5, 1, 0]], 2)
    e = make_edge(a)
    assert check_valid(e)
    w = make_wire([a, b])
    assert check_valid(w) and len(subshapes(w, TopAbs_EDGE)) == 2
    far = BezierCurve([[9, 9, 9], [10, 9, 9]])
    with pytest.raises(CagdError, match=r"curves\[2\]: does not connect"):
        make_wire([a, b, far])
    with pytest.raises(CagdError, match="at least one"):
        make_wire([])


@pytest.mark.parametrize("s", [sphere(1.0), torus(2.0, 0.5), ellipsoid(1, 2, 3)[5],
                               BezierTriangle(np.random.default_rng(2).normal(size=(10, 3)))],
                         ids=["sphere", "torus", "ellipsoid-patch", "triangle"])
def test_faces_with_natural_bounds_are_valid(s):
    f = make_face(s)
    assert check_valid(f)


def test_ellipsoid_solid():
    a, b, c = 1.0, 2.0, 3.0
    patches = ellipsoid(a, b, c)
    solid = solid_from_surfaces(patches)
    assert check_valid(solid)
    assert len(subshapes(solid, TopAbs_FACE)) == 8
    exact = 4 / 3 * math.pi * a * b * c
    assert volume(solid) == pytest.approx(exact, rel=1e-9)
    assert properties.enclosed_volume(patches).value == pytest.approx(exact, rel=1e-12)


def test_open_shell_is_refused():
    shell = sew(ellipsoid(1, 2, 3)[:7])
    assert free_edge_count(shell) > 0
    with pytest.raises(CagdError, match="free edge"):
        make_solid(shell)


def test_sphere_and_torus_solids_against_closed_forms():
    r = 1.7
    s = make_solid(make_face(sphere(r)))
    assert check_valid(s)
    assert volume(s) == pytest.approx(4 / 3 * math.pi * r ** 3, rel=1e-9)
    assert area(s) == pytest.approx(4 * math.pi * r ** 2, rel=1e-9)
    R, q = 3.0, 0.8
    t = make_solid(make_face(torus(R, q)))
    assert check_valid(t)
    assert volume(t) == pytest.approx(2 * math.pi ** 2 * R * q ** 2, rel=1e-9)
    assert area(t) == pytest.approx(4 * math.pi ** 2 * R * q, rel=1e-9)


def test_revolved_natural_spline_profile_solid():
    from scipy.integrate import quad
    pts = np.array([[0, 0, 0], [1.0, 0, 0.3], [1.4, 0, 1.2], [0.8, 0, 2.0], [0, 0, 2.4]])
    prof = natural_cubic_spline(pts)
    surf = revolve(prof.to_nurbs())
    solid = make_solid(make_face(surf))
    assert check_valid(solid)
    a, b = prof.domain
    knots = prof.parameters
    f = lambda t: float(prof(np.array([t]))[0, 0] ** 2 * prof.derivative(np.array([t]), 1)[0, 2])  # noqa: E731
    oracle = math.pi * sum(quad(f, lo, hi, epsabs=1e-15, epsrel=1e-14)[0] for lo, hi in zip(knots, knots[1:]))
    engine = properties.enclosed_volume(surf)
    assert abs(engine.value) == pytest.approx(abs(oracle), rel=1e-12)
    assert volume(solid) == pytest.approx(abs(oracle), rel=1e-9)


def triangle_area_oracle(tri, pieces: int = 40, order: int = 20) -> float:
    """∫∫_{s+t<=1} |T_s x T_t| ds dt with the triangle's own partials (not its NURBS form), by
    Gauss-Legendre on pieces x pieces cells of the square, mapped by (s, t) = (x, y (1 - x))."""
    x, w = np.polynomial.legendre.leggauss(order)
    e = np.linspace(0.0, 1.0, pieces + 1)
    nodes = ((e[:-1, None] + e[1:, None]) / 2 + np.diff(e)[:, None] / 2 * x).ravel()
    weights = (np.diff(e)[:, None] / 2 * w).ravel()
    U, V = np.meshgrid(nodes, nodes, indexing="ij")
    D = tri.derivatives(U.ravel(), (V * (1 - U)).ravel(), 1, 1)
    f = np.linalg.norm(np.cross(D[1, 0], D[0, 1]), axis=-1).reshape(U.shape) * (1 - U)
    return float(weights @ f @ weights)


SMOOTH_TRIANGLE = BezierTriangle([[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0.5, 1, 0.4], [1.5, 1, 0.5], [1, 2, 0.1]],
                                 [1, 1.5, 1, 1, 0.8, 1])


def test_bezier_triangle_area_engine_vs_oracle_and_occt():
    from scipy.integrate import dblquad
    tri = SMOOTH_TRIANGLE
    oracle = triangle_area_oracle(tri)

    def density(t, s):
        d = tri.derivatives(np.array([s]), np.array([t]), 1, 1)
        return float(np.linalg.norm(np.cross(d[1, 0][0], d[0, 1][0])))
    assert dblquad(density, 0, 1, 0, lambda s: 1 - s, epsabs=1e-13, epsrel=1e-12)[0] == pytest.approx(oracle,
                                                                                                      rel=1e-11)
    engine = properties.area(tri)
    assert engine.value == pytest.approx(oracle, rel=1e-12)
    occt = area(make_face(tri))
    # OCCT integrates the face with a degenerate (collapsed) edge less accurately; measured below
    assert occt == pytest.approx(oracle, rel=1e-4)


FOLDED_TRIANGLE = BezierTriangle(np.random.default_rng(5).normal(size=(10, 3)))


@pytest.mark.parametrize("nodes", [8, 16, pytest.param(32, marks=pytest.mark.xfail(
    strict=True, reason="documented limitation: the error estimate |I(nodes+8) - I(nodes)| is not a bound; on "
    "a folded triangle |S_u x S_v| has a kink and at 32 nodes it reports 2.2e-6 for a true 6.9e-6"))])
def test_triangle_with_a_fold_engine_error_estimate_is_honest(nodes):
    # a random net folds (S_u x S_v = 0 on a curve): Gauss converges slowly; the estimate must cover it
    tri = FOLDED_TRIANGLE
    oracle = triangle_area_oracle(tri)
    r = properties.area(tri, nodes=nodes)
    assert abs(r.value - oracle) <= r.error, (nodes, r, oracle)


# --- issue 14: bad input is a CagdError naming the argument ---
def test_subshapes_of_every_type():
    """subshapes with TopAbs_COMPOUND (KeyError before), VERTEX and WIRE: the counts of
    a box from OCCT's own explorer (6 faces, 12 edges, 8 vertices, 6 wires, 1 shell)."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.TopAbs import TopAbs_COMPOUND, TopAbs_COMPSOLID, TopAbs_SHAPE, TopAbs_SHELL, TopAbs_SOLID, \
        TopAbs_VERTEX, TopAbs_WIRE
    from OCP.TopoDS import TopoDS_Vertex, TopoDS_Wire
    box = BRepPrimAPI_MakeBox(1.0, 2.0, 3.0).Shape()
    counts = {TopAbs_FACE: 6, TopAbs_EDGE: 24, TopAbs_VERTEX: 48, TopAbs_WIRE: 6, TopAbs_SHELL: 1,
              TopAbs_SOLID: 1, TopAbs_COMPOUND: 0, TopAbs_COMPSOLID: 0}
    for kind, n in counts.items():      # the explorer visits shared edges and vertices per face
        assert len(subshapes(box, kind)) == n, kind
    assert all(isinstance(v, TopoDS_Vertex) for v in subshapes(box, TopAbs_VERTEX))
    assert all(isinstance(w, TopoDS_Wire) for w in subshapes(box, TopAbs_WIRE))
    wire = make_wire([BezierCurve([[0, 0, 0], [1, 0, 0]]), BezierCurve([[1, 0, 0], [1, 1, 0]])])
    assert len(subshapes(wire, TopAbs_WIRE)) == 1 and len(subshapes(wire, TopAbs_EDGE)) == 2
    for bad in (TopAbs_SHAPE, "FACE", 3):
        with pytest.raises(CagdError, match="^kind: expected one of"):
            subshapes(box, bad)


def test_make_wire_takes_any_iterable():
    """A generator (TypeError: no len() before) gives the same wire as the list."""
    parts = [BezierCurve([[0, 0, 0], [1, 0, 0]]), BezierCurve([[1, 0, 0], [1, 1, 0]])]
    wire = make_wire(c for c in parts)
    assert len(subshapes(wire, TopAbs_EDGE)) == 2
    with pytest.raises(CagdError, match="^curves: expected a sequence"):
        make_wire(3)
    with pytest.raises(CagdError, match="^curves: need at least one"):
        make_wire(iter([]))


def test_occt_exceptions_become_cagd_errors():
    """OCCT's exceptions (raw Standard_NoSuchObject from free_edge_count before) leave
    the bridge as CagdError naming the argument; other exceptions pass through."""
    from OCP.Standard import Standard_NoSuchObject
    from cagd.occ.wrapped import occt_errors
    with pytest.raises(CagdError, match=r"^shape: OCCT failed to count \(Standard_NoSuchObject"):
        with occt_errors("shape", "count"):
            raise Standard_NoSuchObject("no such object")
    with pytest.raises(KeyError):
        with occt_errors("shape", "count"):
            raise KeyError("x")
