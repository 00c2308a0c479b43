"""cagd.occ takes the shapes of every library (cagd.occ.wrapped): the same 2 x 3 x 4 box
as a bare TopoDS_Shape, a CadQuery Solid, Compound or Workplane, a build123d Solid,
Box, Part or BuildPart context has OCCT's volume 24 and area 52, is valid, has no free
edges, six faces, sews into a closed shell, and reads back from STEP with the same
volume; the 2 x 3 rectangle as a face, sketch or context of either library has area 6.
Refusals name the argument, the library and the type. Each library's cases are skipped
where it is not installed (build123d 0.13 venvs have no CadQuery)."""
import importlib.util

import pytest

from cagd import CagdError
from cagd.occ import (area, check_valid, free_edge_count, make_solid, read_shapes, sew, subshapes, volume,
                      write_iges, write_step)
from OCP.BRep import BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
from OCP.gp import gp_Pln
from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL

NEEDS_CQ = pytest.mark.skipif(importlib.util.find_spec("cadquery") is None, reason="needs CadQuery")
NEEDS_B3D = pytest.mark.skipif(importlib.util.find_spec("build123d") is None, reason="needs build123d")


def cq_case(make, name):
    return pytest.param(make, id=name, marks=NEEDS_CQ)


def b3d_case(make, name):
    return pytest.param(make, id=name, marks=NEEDS_B3D)


def _cq():
    import cadquery
    return cadquery


def _bd():
    import build123d
    return build123d


def _build_part():
    bd = _bd()
    with bd.BuildPart() as p:
        bd.Box(2, 3, 4)
    return p


def _build_sketch():
    bd = _bd()
    with bd.BuildSketch() as s:
        bd.Rectangle(2, 3)
    return s


BOXES = [
    pytest.param(lambda: BRepPrimAPI_MakeBox(2.0, 3.0, 4.0).Shape(), id="TopoDS_Solid"),
    cq_case(lambda: _cq().Solid.makeBox(2, 3, 4), "cq.Solid"),
    cq_case(lambda: _cq().Compound.makeCompound([_cq().Solid.makeBox(2, 3, 4)]), "cq.Compound"),
    cq_case(lambda: _cq().Workplane().box(2, 3, 4), "cq.Workplane"),
    b3d_case(lambda: _bd().Solid.make_box(2, 3, 4), "bd.Solid"),
    b3d_case(lambda: _bd().Box(2, 3, 4), "bd.Box"),
    b3d_case(lambda: _build_part().part, "bd.Part"),
    b3d_case(_build_part, "bd.BuildPart"),
]

RECTANGLES = [
    pytest.param(lambda: BRepBuilderAPI_MakeFace(gp_Pln(), 0.0, 2.0, 0.0, 3.0).Face(), id="TopoDS_Face"),
    cq_case(lambda: _cq().Face.makePlane(2, 3), "cq.Face"),
    cq_case(lambda: _cq().Workplane().rect(2, 3).extrude(1).faces("<Z"), "cq.Workplane"),
    cq_case(lambda: _cq().Sketch().rect(2, 3), "cq.Sketch"),
    b3d_case(lambda: _bd().Face.make_rect(2, 3), "bd.Face"),
    b3d_case(lambda: _build_sketch().sketch, "bd.Sketch"),
    b3d_case(_build_sketch, "bd.BuildSketch"),
]


@pytest.mark.parametrize("make", BOXES)
def test_every_wrapper_of_a_box(make, tmp_path):
    box = make()
    assert volume(box) == pytest.approx(24.0, rel=1e-12)
    assert area(box) == pytest.approx(52.0, rel=1e-12)
    assert check_valid(box)
    assert free_edge_count(box) == 0
    assert len(subshapes(box, TopAbs_FACE)) == 6
    assert volume(make_solid(box)) == pytest.approx(24.0, rel=1e-12)
    shell = sew(box)
    assert shell.ShapeType() == TopAbs_SHELL and BRep_Tool.IsClosed_s(shell)
    for write, name in ((write_step, "box.step"), (write_iges, "box.igs")):
        write([("box", box)], tmp_path / name)
        shapes = [s for _, s in read_shapes(tmp_path / name)]
        assert sum(len(subshapes(s, TopAbs_FACE)) for s in shapes) == 6
    assert volume(read_shapes(tmp_path / "box.step")[0][1]) == pytest.approx(24.0, rel=1e-12)


@pytest.mark.parametrize("make", RECTANGLES)
def test_every_wrapper_of_a_rectangle(make, tmp_path):
    rect = make()
    assert area(rect) == pytest.approx(6.0, rel=1e-12)
    assert check_valid(rect) and free_edge_count(rect) == 4
    assert len(subshapes(sew([rect]), TopAbs_FACE)) == 1
    write_step(rect, tmp_path / "rect.step")                 # one item given alone
    assert len(read_shapes(tmp_path / "rect.step")) == 1


def test_a_workplane_stack_is_all_its_shapes():
    cq = pytest.importorskip("cadquery")
    faces = cq.Workplane().box(2, 3, 4).faces()               # six faces: their compound
    assert area(faces) == pytest.approx(52.0, rel=1e-12)
    assert len(subshapes(faces, TopAbs_FACE)) == 6
    assert free_edge_count(faces) == 0


def _refusals():
    """(call, message) pairs; a library's rows only where it is installed."""
    import numpy as np
    rows = [
        (lambda: volume(np.zeros(3)),
         "shape: expected a CadQuery or build123d shape or a TopoDS_Shape, got numpy ndarray"),
        (lambda: check_valid("box"), "shape: expected a CadQuery or build123d shape or a TopoDS_Shape, got str"),
        (lambda: sew([BRepPrimAPI_MakeBox(1.0, 1.0, 1.0).Shape(), 3]),
         r"faces\[1\]: expected a cagd Surface, a CadQuery or build123d shape or a TopoDS_Shape, got int"),
        (lambda: write_step([("a", 1.5)], "/tmp/never.step"),
         r"objects\[0\]: expected a cagd Curve or Surface, a CadQuery or build123d shape or a TopoDS_Shape, "
         "got float"),
    ]
    if importlib.util.find_spec("cadquery"):
        cq = _cq()
        rows += [
            (lambda: volume(cq.Workplane()), "shape: expected .* got a CadQuery Workplane holding no shapes"),
            (lambda: area(cq.Workplane().pushPoints([(0, 0)])),
             "shape: expected .* got a CadQuery Workplane holding no shapes"),
            (lambda: volume(cq.Vector(1, 2, 3)), "shape: expected .* got a CadQuery Vector"),
            (lambda: check_valid(cq.Location()), "shape: expected .* got a CadQuery Location"),
            (lambda: sew([cq.Face.makePlane(1, 1), cq.Edge.makeLine(cq.Vector(), cq.Vector(1, 0, 0))]),
             r"faces\[1\]: expected a face, got a CadQuery Edge holding 0 faces"),
            (lambda: write_step([cq.Vector()], "/tmp/never.step"), r"objects\[0\]: expected .* got a CadQuery Vector"),
        ]
    if importlib.util.find_spec("build123d"):
        bd = _bd()
        rows += [
            (lambda: volume(bd.BuildPart()), "shape: expected .* got a build123d BuildPart holding no shapes"),
            (lambda: volume(bd.Part()), "shape: expected .* got a build123d Part holding no shapes"),
            (lambda: area(bd.Vector(1, 2, 3)), "shape: expected .* got a build123d Vector"),
            (lambda: sew([bd.Face.make_rect(1, 1), bd.Face.make_rect(1, 1),
                          bd.Sketch(bd.Compound([bd.Edge.make_line((0, 0), (1, 0))]).wrapped)]),
             r"faces\[2\]: expected a face, got a build123d Sketch holding 0 faces"),
            (lambda: make_solid(bd.Curve(bd.Edge.make_line((0, 0), (1, 0)).wrapped)),
             "shape: need exactly one shell"),
        ]
    return rows


@pytest.mark.parametrize("call, message", _refusals())
def test_refusals_name_argument_library_and_type(call, message):
    with pytest.raises(CagdError, match=f"^{message}"):
        call()
