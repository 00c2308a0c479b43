"""Trimmed faces through OCCT (issue 15): from_occ of CadQuery faces (a plate with a
hole, a cylinder cut by a cylinder: pcurves mapped from OCCT's angle to the rational
circle's parameter, a sphere cut by a box: a pole and a seam, REVERSED faces) against
OCCT's area (BRepGProp), classifier (BRepClass_FaceClassifier at the 3-D points) and
normals; make_face/to_occ of engine trimmed surfaces valid for BRepCheck with OCCT's
area; STEP round trips keeping the area to 1e-9."""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")
cq = pytest.importorskip("cadquery")

from OCP.BRepAdaptor import BRepAdaptor_Surface  # noqa: E402
from OCP.BRepClass import BRepClass_FaceClassifier  # noqa: E402
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf  # noqa: E402
from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.gp import gp_Pnt, gp_Vec  # noqa: E402
from OCP.TopAbs import TopAbs_FACE, TopAbs_IN, TopAbs_OUT, TopAbs_REVERSED  # noqa: E402
from OCP.TopoDS import TopoDS_Face  # noqa: E402

import cagd  # noqa: E402
from cagd import BSplineSurface, CagdError, TrimmedSurface  # noqa: E402
from cagd.occ import (area, check_valid, from_occ, make_face, read_iges, read_step, to_occ, write_iges,  # noqa: E402
                      write_step)
from cagd.occ.shapes import subshapes  # noqa: E402
from cagd.occ.trim import _ArcMap  # noqa: E402

sys.path.insert(0, str(Path(__file__).parents[1] / "surfaces"))
from test_trimmed import circle, curved_patch, periodic_tube, rectangle, square_patch  # noqa: E402

RNG = np.random.default_rng(1515)
AREA_TOL = 1e-9          # OCCT's BRepGProp on rational faces reaches about 1e-9 (measured 1.1e-9 on cylinders)


def faces_of(shape):
    return subshapes(shape.val().wrapped if hasattr(shape, "val") else shape, TopAbs_FACE)


def trimmed_faces(shape):
    out = [(f, from_occ(f)) for f in faces_of(shape)]
    return [(f, s) for f, s in out if isinstance(s, TrimmedSurface)]


def occt_state(face, points, tol=1e-9):
    """BRepClass_FaceClassifier at 3-D points (it projects them onto the face)."""
    out = []
    for p in points:
        c = BRepClass_FaceClassifier(face, gp_Pnt(*map(float, p)), tol)
        out.append(c.State())
    return out


def check_classification(face, ts, count=400, margin=1e-3):
    """contains vs OCCT's classifier at random (u, v) of the loops' box whose distance to
    the boundary polyline exceeds ``margin`` of the box (both are sure there)."""
    flat = ts._flattened()
    u = flat.lo[0] + (flat.hi[0] - flat.lo[0]) * RNG.random(count)
    v = flat.lo[1] + (flat.hi[1] - flat.lo[1]) * RNG.random(count)
    d = np.min(np.hypot(u[:, None] - flat.A[None, :, 0], v[:, None] - flat.A[None, :, 1]), axis=1)
    keep = d > margin * flat.scale
    u, v = u[keep], v[keep]
    ours = ts.contains(u, v)
    theirs = occt_state(face, ts(u, v))
    assert all(s in (TopAbs_IN, TopAbs_OUT) for s in theirs)
    assert np.array_equal(ours, np.array([s == TopAbs_IN for s in theirs]))
    return len(u)


# --- reading ------------------------------------------------------------------------------------------
def test_plate_with_a_hole():
    plate = cq.Workplane("XY").box(10, 8, 2).faces(">Z").workplane().hole(3)
    found = trimmed_faces(plate)
    assert len(found) == 2                       # top and bottom: an outer loop and a hole
    for f, ts in found:
        assert len(ts.loops) == 2 and ts.reoriented == ()
        assert ts.area() == pytest.approx(80 - math.pi * 1.5 ** 2, rel=1e-13)
        assert ts.area() == pytest.approx(area(f), rel=1e-12)
        assert check_classification(f, ts) > 200


def test_cylinder_cut_by_a_cylinder_maps_the_pcurves():
    """The B-spline pcurves of the intersection are in OCCT's angle: fitted onto the
    rational circle's parameter (quintic Hermite), area and classification as OCCT's."""
    shape = cq.Workplane("XY").cylinder(5, 2).cut(cq.Workplane("YZ").cylinder(10, 0.7))
    found = [(f, ts) for f, ts in trimmed_faces(shape) if BRepAdaptor_Surface(f).GetType().name.endswith("Cylinder")]
    assert len(found) == 2
    for f, ts in found:
        assert ts.area() == pytest.approx(area(f), rel=AREA_TOL)
        check_classification(f, ts, 120)


def test_sphere_cut_by_a_box_has_a_pole_and_a_seam():
    shape = cq.Workplane("XY").sphere(3).cut(cq.Workplane("XY").box(2, 2, 10).translate((2.5, 0, 0)))
    found = [(f, ts) for f, ts in trimmed_faces(shape) if BRepAdaptor_Surface(f).GetType().name.endswith("Sphere")]
    assert found
    for f, ts in found:
        assert ts.area() == pytest.approx(area(f), rel=AREA_TOL)
        check_classification(f, ts, 150)


def test_reversed_faces_keep_the_face_normal():
    shape = cq.Workplane("XY").box(10, 8, 2).faces(">Z").workplane().hole(3).faces("<Z").workplane().hole(1)
    reversed_seen = 0
    for f, ts in trimmed_faces(shape):
        reversed_seen += f.Orientation() == TopAbs_REVERSED
        u, v = _inside_point(ts)
        p = ts(u, v)
        n = ts.normal(u, v)
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, p)), BRep_Tool.Surface_s(f))
        U, V = proj.LowerDistanceParameters()
        P, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
        BRepAdaptor_Surface(f).D1(U, V, P, du, dv)
        m = np.cross([du.X(), du.Y(), du.Z()], [dv.X(), dv.Y(), dv.Z()])
        m = (-m if f.Orientation() == TopAbs_REVERSED else m) / np.linalg.norm(m)
        assert np.dot(n, m) == pytest.approx(1.0, abs=1e-12)
    assert reversed_seen >= 1


def _inside_point(ts):
    flat = ts._flattened()
    for _ in range(1000):
        u = flat.lo[0] + (flat.hi[0] - flat.lo[0]) * RNG.random()
        v = flat.lo[1] + (flat.hi[1] - flat.lo[1]) * RNG.random()
        if ts.classify(u, v) == 1:
            return u, v
    raise AssertionError("no inside point found")


def test_box_faces_stay_plain_surfaces():
    """A face whose boundary is its parameter box comes back as the plain surface."""
    for f in faces_of(cq.Workplane("XY").box(3, 2, 1)):
        assert isinstance(from_occ(f), BSplineSurface)
    kinds = {}
    for f in faces_of(cq.Workplane("XY").cylinder(2, 1)):      # the side is plain, the caps disks
        kinds[BRepAdaptor_Surface(f).GetType().name.split("_")[-1]] = type(from_occ(f))
    assert kinds == {"Cylinder": BSplineSurface, "Plane": TrimmedSurface}


def test_arc_map_is_the_rational_circle():
    """OCCT's angle -> the rational quadratic's parameter, against cagd's own circle:
    S(t) on the NURBS circle of the span is at the angle theta."""
    from cagd.surfaces.revolution import arc_angle
    a, b = 0.3, 1.8                   # one arc (at most 90 degrees, as cagd's circle has)
    m = _ArcMap(np.array([a, b]), float("inf"))
    theta = np.linspace(a, b, 41)
    t = m(theta)
    assert np.allclose(arc_angle((t - a) / (b - a), a, b - a), theta, rtol=0, atol=1e-14)
    h = 1e-6
    assert np.allclose(m.derivative(theta[1:-1]), (m(theta[1:-1] + h) - m(theta[1:-1] - h)) / (2 * h), atol=1e-8)
    assert np.allclose(m.second_derivative(theta[1:-1]),
                       (m.derivative(theta[1:-1] + h) - m.derivative(theta[1:-1] - h)) / (2 * h), atol=1e-7)


# --- writing --------------------------------------------------------------------------------------------
ENGINE_CASES = {
    "disk on a plane": lambda: TrimmedSurface(square_patch(2.0), [[circle((0.5, 0.5), 0.3)]]),
    "annulus on a bump": lambda: TrimmedSurface(curved_patch(), [[circle((0.5, 0.5), 0.4)],
                                                                 [circle((0.5, 0.5), 0.15, clockwise=True)]]),
    "hemisphere (pole, closed edges)": lambda: TrimmedSurface(cagd.sphere(1.5), [rectangle(0.0, 0.5, 0.0, 1.0)]),
    "disk across a seam": lambda: TrimmedSurface(periodic_tube(), [[circle((0.0, 0.5), 0.1)]]),
}


@pytest.mark.parametrize("name", list(ENGINE_CASES))
def test_make_face_is_valid_with_the_engine_area(name):
    ts = ENGINE_CASES[name]()
    face = make_face(ts)
    assert isinstance(face, TopoDS_Face) and check_valid(face)
    assert area(face) == pytest.approx(ts.area(), rel=AREA_TOL)
    assert isinstance(to_occ(ts), TopoDS_Face)
    check_classification(face, ts, 200)


@pytest.mark.parametrize("name", list(ENGINE_CASES))
@pytest.mark.parametrize("kind", ["step", "iges"])
def test_file_round_trip_keeps_the_area(name, kind, tmp_path):
    """write_step/write_iges of the engine object itself write the trimmed face (they
    wrote the untrimmed surface before)."""
    ts = ENGINE_CASES[name]()
    write, read = (write_step, read_step) if kind == "step" else (write_iges, read_iges)
    path = write([("trimmed", ts)], tmp_path / f"t.{kind}")
    (item,) = read(path)
    back = item.object
    if not isinstance(back, TrimmedSurface):         # the trim was the (new) face's parameter box
        (u0, u1), (v0, v1) = back.domain
        back = TrimmedSurface(back, [rectangle(u0, u1, v0, v1)])
    assert back.area() == pytest.approx(ts.area(), rel=1e-9)


def test_step_round_trip_of_read_faces(tmp_path):
    shape = cq.Workplane("XY").box(4, 4, 1).faces(">Z").workplane().hole(1.0).edges("|Z").fillet(0.5)
    found = trimmed_faces(shape)
    assert len(found) == 2
    path = write_step([(f"f{i}", make_face(ts)) for i, (_, ts) in enumerate(found)], tmp_path / "r.step")
    back = [i.object for i in read_step(path)]
    assert len(back) == len(found)
    for (_, ts), b in zip(found, back):
        assert isinstance(b, TrimmedSurface)
        assert b.area() == pytest.approx(ts.area(), rel=1e-9)


def test_make_face_refuses_other_input():
    with pytest.raises(CagdError, match="surface: expected a cagd Surface"):
        make_face("nope")
