"""Edge cases of the bridge: orientation of reversed shapes, offsets (no exact
B-spline form), null and unbounded shapes, bad arguments, OCCT's global settings,
non-ASCII names."""
import math

import numpy as np
import pytest

import cagd
from cagd import CagdError

OCP = pytest.importorskip("OCP")
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge  # noqa: E402
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox  # noqa: E402
from OCP.Geom import Geom_Line, Geom_OffsetCurve, Geom_OffsetSurface, Geom_TrimmedCurve  # noqa: E402
from OCP.Geom2d import Geom2d_Line  # noqa: E402
from OCP.gp import gp_Dir, gp_Dir2d, gp_Pnt, gp_Pnt2d  # noqa: E402
from OCP.Interface import Interface_Static  # noqa: E402
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED  # noqa: E402
from OCP.TopoDS import TopoDS_Edge, TopoDS_Shape  # noqa: E402

from cagd.occ import (check_valid, from_occ, make_edge, make_face, make_solid, read_iges, read_step,  # noqa: E402
                      sew, subshapes, to_occ, verify, volume, write_iges, write_step)
from cagd.surfaces.properties import enclosed_volume  # noqa: E402


def test_faces_of_a_box_read_back_bound_its_volume(tmp_path):
    """Reversed faces come back with u reversed, so that S_u x S_v is the face's
    outward normal: the engine's flux integral over them is the box's volume."""
    box = BRepPrimAPI_MakeBox(gp_Pnt(-5.0, -10.0, -15.0), 10.0, 20.0, 30.0).Shape()   # centred: every face counts
    assert any(f.Orientation() == TopAbs_REVERSED for f in subshapes(box, TopAbs_FACE))
    write_step([("box", box)], tmp_path / "box.step")
    faces = [i.object for i in read_step(tmp_path / "box.step")]
    assert len(faces) == 6
    assert enclosed_volume(faces).value == pytest.approx(6000.0, rel=1e-13)
    raw = [from_occ(f, oriented=False) for f in subshapes(box, TopAbs_FACE)]
    assert abs(enclosed_volume(raw).value - 6000.0) > 1.0          # OCCT's parametrisation ignores orientation


def test_reversed_edge_runs_along_the_edge():
    c = cagd.BSplineCurve([[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 0]], 3)
    edge = make_edge(c).Reversed()
    back = from_occ(edge)
    assert np.allclose(back(np.array(back.domain)), c(np.array(c.domain))[::-1], atol=1e-15)
    same = from_occ(edge, oriented=False)
    assert np.allclose(same(np.linspace(0, 1, 9)), c(np.linspace(0, 1, 9)), atol=1e-15)


def test_offset_curve_needs_a_tolerance_and_meets_it():
    c = to_occ(cagd.BSplineCurve([[0, 0, 0], [10, 10, 0], [20, -5, 0], [30, 0, 0]], 3))
    offset = Geom_OffsetCurve(c, 2.0, gp_Dir(0, 0, 1))
    with pytest.raises(CagdError, match="approximate"):
        from_occ(offset)
    approx = from_occ(offset, approximate=1e-6)
    t = np.linspace(0, 1, 201)
    occ = np.array([[p.X(), p.Y(), p.Z()] for p in (offset.Value(x) for x in t)])
    # the approximation may be parametrised differently: distance to the dense OCCT polyline
    pts = approx(np.linspace(*approx.domain, 101))
    d = np.sqrt(((pts[:, None] - occ[None]) ** 2).sum(-1)).min(axis=1)
    assert d.max() < 0.2                                      # polyline spacing bound
    with pytest.raises(CagdError, match="approximate: the tolerance"):
        from_occ(offset, approximate=-1.0)


def test_offset_surface_needs_a_tolerance():
    s = to_occ(cagd.sphere(5.0))
    with pytest.raises(CagdError, match="offset surface has no exact"):
        from_occ(Geom_OffsetSurface(s, 1.0))


@pytest.mark.parametrize("tol", [1e-300, 0.0, -1.0, float("nan"), "abc", 10 ** 400])
def test_an_approximation_tolerance_below_occts_resolution_is_refused(tol):
    """approximate=1e-300 ran OCCT's approximation for over 60 s (issue 14); the bound is
    Precision::Confusion (1e-7)."""
    offset = Geom_OffsetSurface(to_occ(cagd.sphere(5.0)), 1.0)
    with pytest.raises(CagdError, match="approximate"):
        from_occ(offset, approximate=tol)


def test_null_and_unbounded_shapes_are_errors():
    for bad in (TopoDS_Shape(), TopoDS_Edge()):
        with pytest.raises(CagdError, match="null shape"):
            from_occ(bad)
    with pytest.raises(CagdError, match="null shape"):
        make_solid(TopoDS_Shape())
    with pytest.raises(CagdError, match="null shape"):
        check_valid(TopoDS_Shape())
    infinite = BRepBuilderAPI_MakeEdge(Geom_Line(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0))).Edge()
    with pytest.raises(CagdError, match="unbounded"):
        from_occ(infinite)
    with pytest.raises(CagdError, match="unbounded"):
        from_occ(Geom2d_Line(gp_Pnt2d(0, 0), gp_Dir2d(1, 0)))
    line = from_occ(Geom_TrimmedCurve(Geom_Line(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), 0.0, 5.0))
    assert np.allclose(line(np.array(line.domain)), [[0, 0, 0], [5, 0, 0]])


@pytest.mark.parametrize("call, word", [
    (lambda: make_face(cagd.BSplineCurve([[0, 0], [1, 1]], 1)), "surface"),
    (lambda: make_edge(cagd.sphere(1.0)), "curve"),
    (lambda: sew(None), "faces"),
    (lambda: write_step(None, "/tmp/x.step"), "objects"),
    (lambda: write_step([cagd.sphere(1.0)], "/tmp"), "path"),
    (lambda: verify(cagd.sphere(1.0), samples=0), "samples"),
    (lambda: volume(make_face(cagd.sphere(1.0)), eps=math.nan), "eps"),
    (lambda: cagd.BSplineSurface.from_occ_form(np.zeros((3, 3, 3)), np.ones((2, 5)), [0, 1], [0, 1], [3, 3],
                                               [3, 3], 2, 2), "weights"),
    (lambda: cagd.BSplineCurve.from_occ_form(np.zeros((4, 3)), None, [0, 1], [4, 5], 3), "multiplicities"),
])
def test_bad_arguments_name_the_argument(call, word):
    with pytest.raises(CagdError, match=word):
        call()


def test_global_settings_are_restored(tmp_path):
    c = cagd.BSplineCurve([[0, 0, 0], [1, 1, 0], [2, 0, 0]], 2)
    write_iges([c], tmp_path / "warm.igs")          # OCCT registers the IGES parameters on first use
    read_iges(tmp_path / "warm.igs")
    before = (Interface_Static.CVal_s("write.step.schema"), Interface_Static.IVal_s("read.iges.bspline.continuity"),
              Interface_Static.CVal_s("xstep.cascade.unit"))
    c = cagd.BSplineCurve([[0, 0, 0], [1, 1, 0], [2, 0, 0]], 2)
    write_step([c], tmp_path / "c.step", schema="AP203")
    write_iges([c], tmp_path / "c.igs")
    read_step(tmp_path / "c.step")
    read_iges(tmp_path / "c.igs")
    verify(c)
    after = (Interface_Static.CVal_s("write.step.schema"), Interface_Static.IVal_s("read.iges.bspline.continuity"),
             Interface_Static.CVal_s("xstep.cascade.unit"))
    assert after == before


def test_non_ascii_names(tmp_path):
    c = cagd.BSplineCurve([[0, 0, 0], [1, 1, 0], [2, 0, 0]], 2)
    write_step({"Träger_ä": c}, tmp_path / "n.step")
    assert [i.name for i in read_step(tmp_path / "n.step")] == ["Träger_ä"]
    write_iges({"Träger_ä": c}, tmp_path / "n.igs")
    assert [i.name for i in read_iges(tmp_path / "n.igs")] == ["Trager_a"]         # IGES labels are ASCII


def test_default_tolerance_grows_with_degree_and_weights():
    from cagd.occ.verify import default_tolerance
    rng = np.random.default_rng(3)
    cubic = cagd.BSplineCurve(rng.normal(size=(8, 3)), 3)
    high = cagd.BSplineCurve(rng.normal(size=(14, 3)), 10, weights=rng.uniform(0.5, 2.0, 14))
    assert default_tolerance(cubic) == 1e-12
    w = high.weights
    assert default_tolerance(high) == pytest.approx(1e-12 * (10 / 3) ** 2 * w.max() / w.min())
    report = verify(high)
    assert report.passed, str(report)
    assert report.stage("occt").tolerance == default_tolerance(high)


def test_coordinates_beyond_occts_range_are_refused_before_occt():
    """OCCT reads coordinates beyond Precision::Infinite (2e100) as infinite: to_occ, and
    so every path to OCCT (faces, edges, files), refuses poles beyond MAX_COORDINATE."""
    from cagd.occ.convert import MAX_COORDINATE
    far = cagd.BSplineCurve([[0, 0, 0], [1, 1, 0], [3 * MAX_COORDINATE, 0, 0]], 2)
    with pytest.raises(CagdError, match="exceed OCCT's range"):
        to_occ(far)
    with pytest.raises(CagdError, match="exceed OCCT's range"):
        to_occ(cagd.sphere(1e200))
    to_occ(cagd.sphere(0.1 * MAX_COORDINATE))             # within the range: converts
