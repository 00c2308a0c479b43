"""cq_ext takes the shapes of every library: the ellipsoid's eight patches as CadQuery
faces, shell, solid, compound or Workplane, build123d faces, shell, part, sketch or
BuildPart, bare TopoDS shapes, or mixed, sew into the solid of volume 4/3 pi a b c; a
frustum's lateral face in every wrapper closes with caps into the frustum (pi h/3
(R^2 + R r + r^2)); a 2 x 3 rectangle in every wrapper thickens into a box of volume
6 t (the offset of a plane is exact); edges and faces in every wrapper give the
engine curve or surface back (from_shape); the Workplane methods take build123d
edges and faces as arguments. Refusals name the argument, library and type."""
import math

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")
bd = pytest.importorskip("build123d")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cq_ext import b3d  # noqa: E402
from cagd import CagdError  # noqa: E402
from cagd.occ import check_valid, volume  # noqa: E402

from cq_helpers import face_points  # noqa: E402

A, B, C = 3.0, 2.0, 1.5
V_ELL = 4 / 3 * math.pi * A * B * C
PATCHES = cagd.ellipsoid(A, B, C)


def _build_part(solid):
    with bd.BuildPart() as p:
        bd.insert(solid)
    return p


def _bd_compound(shapes):
    return bd.Compound([bd.Shape.cast(getattr(s, "wrapped", s)) for s in shapes]).wrapped


ELLIPSOID = {
    "cq.Face list": lambda: [cq_ext.to_cq(s) for s in PATCHES],
    "cq.Shell": lambda: cq_ext.sew_shell(PATCHES),
    "cq.Solid": lambda: cq_ext.sew_solid(PATCHES),
    "cq.Compound": lambda: cq.Compound.makeCompound([cq_ext.to_cq(s) for s in PATCHES]),
    "cq.Workplane": lambda: cq.Workplane().add([cq_ext.to_cq(s) for s in PATCHES]),
    "bd.Face list": lambda: [cq_ext.to_b3d(s) for s in PATCHES],
    "bd.Shell": lambda: b3d.sew_shell(PATCHES),
    "bd.Part": lambda: bd.Part(_bd_compound([b3d.sew_solid(PATCHES)])),
    "bd.Sketch": lambda: bd.Sketch(_bd_compound([cq_ext.to_b3d(s) for s in PATCHES])),
    "bd.BuildPart": lambda: _build_part(b3d.sew_solid(PATCHES)),
    "TopoDS list": lambda: [cq_ext.to_cq(s).wrapped for s in PATCHES],
    "mixed list": lambda: [cq_ext.to_cq(PATCHES[0]), cq_ext.to_b3d(PATCHES[1]), cq_ext.to_cq(PATCHES[2]).wrapped,
                           cq.Workplane().add(cq_ext.to_cq(PATCHES[3]))] + list(PATCHES[4:]),
}


@pytest.mark.parametrize("name", list(ELLIPSOID))
def test_sew_solid_takes_every_wrapper(name):
    faces = ELLIPSOID[name]()
    solid = cq_ext.sew_solid(faces)
    assert isinstance(solid, cq.Solid) and check_valid(solid)
    assert volume(solid) == pytest.approx(V_ELL, rel=1e-9)
    other = b3d.sew_solid(faces)
    assert isinstance(other, bd.Solid) and volume(other) == pytest.approx(V_ELL, rel=1e-9)
    assert cq_ext.free_edges(faces) == [] and b3d.free_edges(faces) == []


R, RR, H = 2.0, 1.0, 3.0
FRUSTUM = math.pi * H / 3 * (R * R + R * RR + RR * RR)


def lateral():
    """The frustum's lateral face: the segment (2, 0) - (1, 3) about the y axis."""
    return cq.Workplane("XY").revolveSurface(cagd.BSplineCurve(np.array([[R, 0.0], [RR, H]]), 1)).val()


LATERAL = {
    "cq.Face": lateral,
    "cq.Shell": lambda: cq.Shell.makeShell([lateral()]),
    "cq.Compound": lambda: cq.Compound.makeCompound([lateral()]),
    "cq.Workplane": lambda: cq.Workplane().add(lateral()),
    "bd.Face": lambda: bd.Face(lateral().wrapped),
    "bd.Shell": lambda: bd.Shell(lateral().wrapped),
    "bd.Sketch": lambda: bd.Sketch(_bd_compound([lateral()])),
    "TopoDS_Face": lambda: lateral().wrapped,
}


@pytest.mark.parametrize("name", list(LATERAL))
def test_close_with_caps_takes_every_wrapper(name):
    face = LATERAL[name]()
    for solid, kind in ((cq_ext.close_with_caps(face), cq.Solid), (b3d.close_with_caps([face]), bd.Solid)):
        assert isinstance(solid, kind) and check_valid(solid)
        assert volume(solid) == pytest.approx(FRUSTUM, rel=1e-9)
        assert len(solid.Faces() if kind is cq.Solid else solid.faces()) == 3


def _build_sketch():
    with bd.BuildSketch() as s:
        bd.Rectangle(2, 3)
    return s


RECTANGLE = {
    "cq.Face": lambda: cq.Face.makePlane(2, 3),
    "cq.Shell": lambda: cq.Shell.makeShell([cq.Face.makePlane(2, 3)]),
    "cq.Compound": lambda: cq.Compound.makeCompound([cq.Face.makePlane(2, 3)]),
    "cq.Workplane": lambda: cq.Workplane().add(cq.Face.makePlane(2, 3)),
    "cq.Sketch": lambda: cq.Sketch().rect(2, 3),
    "bd.Face": lambda: bd.Face.make_rect(2, 3),
    "bd.Sketch": lambda: _build_sketch().sketch,
    "bd.BuildSketch": _build_sketch,
    "TopoDS_Face": lambda: cq.Face.makePlane(2, 3).wrapped,
    "cagd surface": lambda: cagd.BezierSurface(np.array([[(0, 0, 0), (0, 3, 0)], [(2, 0, 0), (2, 3, 0)]], float)),
}


@pytest.mark.parametrize("t", [0.25, -0.5])
@pytest.mark.parametrize("name", list(RECTANGLE))
def test_thicken_takes_every_wrapper(name, t):
    rect = RECTANGLE[name]()
    for solid, kind in ((cq_ext.thicken(rect, t), cq.Solid), (b3d.thicken(rect, t), bd.Solid)):
        assert isinstance(solid, kind) and check_valid(solid)
        assert volume(solid) == pytest.approx(6 * abs(t), rel=1e-9)


CURVE = cagd.BSplineCurve(np.array([(0, 0, 0), (1, 2, 0.5), (3, 1, -1), (4, 3, 0)], float), 3)
PATCH = cagd.BezierSurface(np.array([[(i, j, 0.2 * i * j) for j in range(3)] for i in range(4)], float))


def _build_line():
    with bd.BuildLine() as line:
        bd.insert(cq_ext.to_b3d(CURVE))
    return line


EDGES = {
    "cq.Edge": lambda: cq_ext.to_cq(CURVE),
    "cq.Wire": lambda: cq.Wire.assembleEdges([cq_ext.to_cq(CURVE)]),
    "cq.Workplane": lambda: cq.Workplane().cagdCurve(CURVE),
    "bd.Edge": lambda: cq_ext.to_b3d(CURVE),
    "bd.Wire": lambda: bd.Wire([cq_ext.to_b3d(CURVE)]),
    "bd.Curve": lambda: bd.Curve(_bd_compound([cq_ext.to_b3d(CURVE)])),
    "bd.BuildLine": _build_line,
    "TopoDS_Edge": lambda: cq_ext.to_cq(CURVE).wrapped,
}
FACES = {
    "cq.Face": lambda: cq_ext.to_cq(PATCH),
    "cq.Shell": lambda: cq.Shell.makeShell([cq_ext.to_cq(PATCH)]),
    "cq.Compound": lambda: cq.Compound.makeCompound([cq_ext.to_cq(PATCH)]),
    "cq.Workplane": lambda: cq.Workplane().cagdSurface(PATCH),
    "bd.Face": lambda: cq_ext.to_b3d(PATCH),
    "bd.Sketch": lambda: bd.Sketch(_bd_compound([cq_ext.to_b3d(PATCH)])),
    "TopoDS_Face": lambda: cq_ext.to_cq(PATCH).wrapped,
}


@pytest.mark.parametrize("name", list(EDGES))
def test_from_shape_of_every_edge_wrapper(name):
    back = cq_ext.from_shape(EDGES[name]())
    t = np.linspace(0, 1, 11)
    assert np.abs(back(t) - CURVE(t)).max() <= 1e-15 * 8
    assert b3d.from_shape is cq_ext.from_shape


@pytest.mark.parametrize("name", list(FACES))
def test_from_shape_of_every_face_wrapper(name):
    back = cq_ext.from_shape(FACES[name]())
    u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), indexing="ij")
    assert np.abs(back(u.ravel(), v.ravel()) - PATCH(u.ravel(), v.ravel())).max() <= 1e-15 * 8


def test_workplane_methods_take_build123d_shapes():
    box = bd.Solid.make_box(2, 3, 4)
    top = max(box.faces(), key=lambda f: f.center().Z)
    patch = cq.Workplane().coonsPatch(*top.edges()).val()                 # four build123d edges
    assert patch.Area() == pytest.approx(6.0, rel=1e-12)
    face = cq.Workplane("XY").revolveSurface(bd.Edge.make_line((3, 0, 0), (3, 2, 0))).val()
    assert face.Area() == pytest.approx(2 * math.pi * 3 * 2, rel=1e-9)
    sphere = bd.Solid.make_sphere(2.0).faces()[0]
    (v,) = cq.Workplane().projectPoints([(0, 0, 5)], face=sphere).vals()
    assert np.allclose(v.toTuple(), (0, 0, 2), atol=1e-9)
    plane = bd.Face.make_rect(10, 10)                                     # z = 0
    edges = cq.Workplane().add(cq.Face(sphere.wrapped)).intersectFaces(plane).vals()
    assert sum(e.Length() for e in edges) == pytest.approx(2 * math.pi * 2, rel=1e-6)
    lofted = cq.Workplane().loftSurface(cq_ext.to_b3d(CURVE), cq_ext.to_cq(CURVE.transformed(np.eye(3), (0, 0, 1))),
                                        degree_v=1).val()
    u = np.linspace(0, 1, 5)
    assert np.abs(face_points(lofted, u, 0.5 + 0 * u) - (CURVE(u) + (0, 0, 0.5))).max() <= 1e-12 * 4


@pytest.mark.parametrize("call, message", [
    (lambda: cq_ext.sew_solid([bd.Curve(_bd_compound([cq_ext.to_b3d(CURVE)]))]),
     r"faces\[0\]: expected a face, got a build123d Curve holding 0 faces"),
    (lambda: b3d.sew_solid([cq_ext.to_cq(PATCH), _build_line()]),
     r"faces\[1\]: expected a face, got a build123d BuildLine holding 0 faces"),
    (lambda: cq_ext.close_with_caps(cq.Workplane()),
     r"faces\[0\]: expected .* got a CadQuery Workplane holding no shapes"),
    (lambda: cq_ext.thicken(np.zeros((2, 2)), 1.0),
     r"faces\[0\]: expected a cagd Surface, a CadQuery or build123d shape or a TopoDS_Shape, got numpy ndarray"),
    (lambda: b3d.thicken(bd.BuildSketch(), 1.0),
     r"faces\[0\]: expected .* got a build123d BuildSketch holding no shapes"),
    (lambda: cq_ext.from_shape(bd.Solid.make_box(1, 1, 1)),
     r"shape: expected one edge or a face, got a build123d Solid$"),
    (lambda: cq_ext.from_shape(bd.Curve(_bd_compound([bd.Edge.make_line((0, 0), (1, 0)),
                                                      bd.Edge.make_line((1, 0), (1, 1))]))),
     r"shape: expected one edge or a face, got a build123d Curve holding 2 edges$"),
    (lambda: cq_ext.from_shape(cq.Workplane().box(1, 1, 1).faces()),
     r"shape: expected one edge or a face, got a CadQuery Workplane holding 6 faces$"),
    (lambda: cq.Workplane().coonsPatch(bd.Solid.make_box(1, 1, 1), CURVE, CURVE, CURVE),
     r"curves\[0\]: expected one edge or a face, got a build123d Solid$"),
    (lambda: cq.Workplane().projectPoints([(0, 0, 1)], face=bd.Edge.make_line((0, 0), (1, 0))),
     r"face\[0\]: expected a face, got a build123d Edge holding 0 faces"),
    (lambda: cq.Workplane().revolveSurface(cq_ext.to_b3d(PATCH)), r"profile: expected a cagd Curve or an edge, got a "
                                                                  r"build123d Face \(a face\)"),
    (lambda: cq_ext.gap_report(["x"]), r"edges\[0\]: expected .* got str"),
])
def test_refusals_name_argument_library_and_type(call, message):
    with pytest.raises(CagdError, match=f"^{message}"):
        call()
