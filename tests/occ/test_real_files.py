"""Real STEP/IGES files written by other CAD systems (../shared/data/cad, see its
README): what OCCT reads (counts, degrees, weights) and that every engine object
evaluates as OCCT's evaluation of the face's surface; a write_step/read_step round
trip of what was read is exact. Skipped when the folder is absent."""
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface  # noqa: E402
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED  # noqa: E402

from cagd import BSplineCurve, BSplineSurface  # noqa: E402
from cagd.occ import read_iges, read_step, write_step  # noqa: E402

CAD = Path(__file__).parents[2] / ".." / "shared" / "data" / "cad"
pytestmark = pytest.mark.skipif(not CAD.is_dir(), reason="../shared/data/cad is not there")

STEP_FILES = ["bug28366_fuselage.stp", "trj7_c2-al-214.stp", "xr1-tu-rod.stp", "bug29478.stp",
              "trj12_gd1-id-214.stp", "trj1_t4m-pe.stp", "xr1-db-214_7.stp"]
# faces as the README table says OCCT reads them
FACES = {"bug28366_fuselage.stp": 8, "trj7_c2-al-214.stp": 1, "xr1-tu-rod.stp": 4, "bug29478.stp": 1,
         "trj12_gd1-id-214.stp": 7, "trj1_t4m-pe.stp": 11, "xr1-db-214_7.stp": 4,
         "OCC8842_cylinder_Ideas.igs": 3}
_CACHE = {}


def imported(name):
    if name not in _CACHE:
        path = CAD / ("iges" if name.endswith(".igs") else "step") / name
        _CACHE[name] = (read_iges if name.endswith(".igs") else read_step)(path)
    return _CACHE[name]


def surfaces(name):
    return [i for i in imported(name) if isinstance(i.object, BSplineSurface)]


def curves(name):
    return [i for i in imported(name) if isinstance(i.object, BSplineCurve)]


@pytest.mark.parametrize("name", list(FACES))
def test_face_counts(name):
    assert len(surfaces(name)) == FACES[name]


def test_fuselage_bicubic_patches():
    ss = [i.object for i in surfaces("bug28366_fuselage.stp")]
    assert all((s.degree_u, s.degree_v) == (3, 3) and s.control_points.shape == (10, 4, 3) and s.weights is None
               and not (s.periodic_u or s.periodic_v) for s in ss)
    assert curves("bug28366_fuselage.stp") == []


def test_trj7_surface_and_free_curve():
    (c,) = curves("trj7_c2-al-214.stp")
    assert c.object.degree == 3 and len(c.object.control_points) == 7 and c.object.weights is None
    (s,) = surfaces("trj7_c2-al-214.stp")
    assert s.object.control_points.shape == (4, 4, 3) and s.object.weights is None


def test_rod_rational_half_cylinders():
    rational = [i.object for i in surfaces("xr1-tu-rod.stp") if i.object.weights is not None]
    assert len(rational) == 2
    for s in rational:
        assert {s.degree_u, s.degree_v} == {1, 3}
        # the file writes 1/3 with 11 digits (0.33333333333)
        assert np.allclose(s.weights, [[1, 1 / 3, 1 / 3, 1]] * 2, rtol=0, atol=1e-11) or \
            np.allclose(s.weights.T, [[1, 1 / 3, 1 / 3, 1]] * 2, rtol=0, atol=1e-11)


def test_periodic_imports():
    per = [i.object for i in surfaces("trj12_gd1-id-214.stp") if i.object.periodic_u]
    assert len(per) == 1 and per[0].control_points.shape[:2] == (6, 2) and per[0].weights is not None
    # the README: one V-periodic 2x16 surface of degree 1x8 shared by 2 faces; read_step gives each
    # face's own piece of it (trimmed to the face), a non-periodic 2x9 B-spline of the same degree
    deg8 = [i.object for i in surfaces("xr1-db-214_7.stp") if i.object.degree_v == 8]
    assert len(deg8) == 2 and all(s.degree_u == 1 and s.control_points.shape[:2] == (2, 9) for s in deg8)
    per = [i.object for i in surfaces("OCC8842_cylinder_Ideas.igs") if i.object.periodic_u]
    assert len(per) == 1 and per[0].control_points.shape[:2] == (8, 2)


@pytest.mark.parametrize("name", list(FACES))
def test_engine_objects_evaluate_as_occt(name):
    for item in surfaces(name):
        s = item.object
        g = BRep_Tool.Surface_s(item.shape) if item.shape.ShapeType() == TopAbs_FACE else None
        assert g is not None
        (a, b), (c, d) = s.domain
        u, v = np.meshgrid(np.linspace(a, b, 6), np.linspace(c, d, 6), indexing="ij")
        # a REVERSED face comes back with u reversed (its normal is the face's)
        flip = item.shape.Orientation() == TopAbs_REVERSED
        mine = s((a + b - u.ravel()) if flip else u.ravel(), v.ravel())
        theirs = []
        for x, y in zip(u.ravel().tolist(), v.ravel().tolist()):
            p = gp_Pnt()
            g.D0(x, y, p)
            theirs.append((p.X(), p.Y(), p.Z()))
        size = np.abs(s.control_points).max()
        if isinstance(g, (Geom_BSplineSurface, Geom_BezierSurface)):
            # the same parameter: the face's piece of OCCT's surface
            assert np.abs(mine - np.array(theirs)).max() <= 1e-12 * size, (name, item.name)
        else:
            # planes, cylinders, cones, spheres, tori: the rational form has its own parameter;
            # every engine point lies on OCCT's surface (distance by OCCT's projection)
            for q in mine:
                proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*q.tolist()), g)
                assert proj.NbPoints() >= 1 and proj.LowerDistance() <= 1e-12 * size, (name, item.name)


@pytest.mark.parametrize("name", list(FACES))
def test_write_read_round_trip_is_exact(name, tmp_path):
    items = imported(name)
    write_step([(f"o{k}", i.object) for k, i in enumerate(items)], tmp_path / "again.step")
    back = {i.name: i.object for i in read_step(tmp_path / "again.step")}
    assert len(back) == len(items)
    for k, i in enumerate(items):
        a, b = i.object.occ_form(), back[f"o{k}"].occ_form()
        assert np.array_equal(a.poles, b.poles), (name, k)
        assert (a.weights is None) == (b.weights is None)
        if a.weights is not None:
            assert np.array_equal(a.weights, b.weights)
        for x, y in zip(a[2:], b[2:]):
            assert np.array_equal(np.asarray(x), np.asarray(y))
