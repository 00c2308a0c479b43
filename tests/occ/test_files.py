"""STEP and IGES files: names, millimetres, 17 significant digits (bit-exact round
trips), free curves, solids, errors."""
import re

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRepAdaptor import BRepAdaptor_Surface  # noqa: E402
from OCP.GeomAbs import GeomAbs_BSplineSurface  # noqa: E402
from OCP.TopAbs import TopAbs_FACE  # noqa: E402

from cagd import BezierCurve, BSplineCurve, BSplineSurface, CagdError, ellipsoid, sphere  # noqa: E402
from cagd.occ import (read_iges, read_shapes, read_step, solid_from_surfaces, subshapes, write_iges,  # noqa: E402
                      write_step)

RNG = np.random.default_rng(11)
SURFACE = BSplineSurface(RNG.normal(size=(5, 4, 3)) * np.pi, 3, 2, None, None, RNG.uniform(0.3, 3, (5, 4)))
CURVE = BSplineCurve(RNG.normal(size=(7, 3)) / 3, 3, np.repeat(np.cumsum(RNG.uniform(0.1, 1, 5)), [4, 1, 1, 1, 4]),
                     RNG.uniform(0.3, 3, 7))
PERIODIC = BSplineCurve(RNG.normal(size=(7, 3)) / 3, 3, np.cumsum(RNG.uniform(0.1, 1, 8)), periodic=True)


def _same(a, b):
    fa, fb = a.occ_form(), b.occ_form()
    assert np.array_equal(fa.poles, fb.poles)
    assert (fa.weights is None) == (fb.weights is None)
    if fa.weights is not None:
        assert np.array_equal(fa.weights, fb.weights)
    for x, y in zip(fa[2:], fb[2:]):
        assert np.array_equal(np.asarray(x), np.asarray(y))


@pytest.mark.parametrize("kind", ["step", "iges"])
def test_round_trip_is_bit_exact_with_names(kind, tmp_path):
    path = tmp_path / f"model.{'step' if kind == 'step' else 'igs'}"
    write, read = (write_step, read_step) if kind == "step" else (write_iges, read_iges)
    out = write({"wing": SURFACE, "rail": CURVE}, path)
    assert out == path and path.is_file()
    back = read(path)
    names = {i.name: i.object for i in back}
    assert set(names) == {"wing", "rail"}
    _same(names["wing"], SURFACE)
    _same(names["rail"], CURVE)


@pytest.mark.parametrize("kind", ["step", "iges"])
def test_periodic_curve_round_trip(kind, tmp_path):
    # files hold the clamped exchange form (knot insertion: the same curve, same parameters)
    path = tmp_path / f"p.{'step' if kind == 'step' else 'igs'}"
    (write_step if kind == "step" else write_iges)([PERIODIC], path)
    (back,) = (read_step if kind == "step" else read_iges)(path)
    c = back.object
    assert c.domain == PERIODIC.domain
    t = np.linspace(*PERIODIC.domain, 57)
    assert np.abs(c(t) - PERIODIC(t)).max() <= 4e-16 * np.abs(PERIODIC.control_points).max() * 4
    _same(c, PERIODIC.clamped())


def test_step_text_names_units_and_digits(tmp_path):
    path = write_step([("wing", SURFACE), ("rail", CURVE)], tmp_path / "m.step")
    text = path.read_text()
    assert "PRODUCT('wing'" in text and "PRODUCT('rail'" in text
    assert "SI_UNIT(.MILLI.,.METRE.)" in text
    reals = re.findall(r"-?\d\.\d+E[+-]\d+", text)
    assert reals and all(len(r.lstrip("-").split("E")[0]) == 18 for r in reals)      # d.dddddddddddddddd
    # every control point coordinate appears with all its digits
    x = float(SURFACE.control_points[1, 2, 0])
    assert f"{x:.16E}" in text


def test_iges_text_names_and_units(tmp_path):
    path = write_iges([("wing", SURFACE)], tmp_path / "m.igs")
    text = path.read_text()
    assert "wing" in text
    assert "2HMM" in text.replace(" ", "") or "MM" in text.splitlines()[1]


def test_curves_are_free_edges_and_solids_give_eight_faces(tmp_path):
    solid = solid_from_surfaces(ellipsoid(1, 2, 3))
    write_step([("egg", solid), ("arc", BezierCurve([[0, 0, 0], [1, 1, 0], [2, 0, 0]]))], tmp_path / "s.step")
    back = read_step(tmp_path / "s.step")
    faces = [i for i in back if i.name.startswith("egg")]
    curves = [i for i in back if i.name == "arc"]
    assert len(faces) == 8 and all(isinstance(i.object, BSplineSurface) for i in faces)
    assert len(curves) == 1 and isinstance(curves[0].object, BSplineCurve)
    assert len(read_shapes(tmp_path / "s.step")) == 2


def test_default_names(tmp_path):
    """The engine class names the item (a sphere is a RevolvedSurface); the file gets its NURBS face."""
    write_step([sphere(1.0)], tmp_path / "a.step")
    back = read_step(tmp_path / "a.step")
    assert [i.name for i in back] == ["RevolvedSurface_1"]
    assert BRepAdaptor_Surface(subshapes(back[0].shape, TopAbs_FACE)[0]).GetType() == GeomAbs_BSplineSurface


def test_errors(tmp_path):
    with pytest.raises(CagdError, match="does not exist"):
        write_step([SURFACE], tmp_path / "nowhere" / "x.step")
    with pytest.raises(CagdError, match="does not exist"):
        write_iges([SURFACE], tmp_path / "nowhere" / "x.igs")
    with pytest.raises(CagdError, match="no such file"):
        read_step(tmp_path / "missing.step")
    with pytest.raises(CagdError, match="no such file"):
        read_iges(tmp_path / "missing.igs")
    with pytest.raises(CagdError, match=r"objects\[1\]"):
        write_step([SURFACE, "text"], tmp_path / "x.step")
    with pytest.raises(CagdError, match="nothing to write"):
        write_step([], tmp_path / "x.step")
    with pytest.raises(CagdError, match="kind"):
        read_shapes(tmp_path / "x.step", kind="stl")
    bad = tmp_path / "junk.step"
    bad.write_text("not a step file")
    with pytest.raises(CagdError, match="not a STEP file"):
        read_step(bad)


def test_a_face_that_does_not_convert_is_reported_and_the_rest_comes_back(tmp_path):
    """An offset surface has no exact B-spline form: without approximate= its face is
    listed in `skipped` (name, index, reason) with a RuntimeWarning, and the other face
    of the same item comes back; with approximate= both do."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_OffsetSurface
    from cagd import BezierSurface
    from cagd.occ import make_face, sew, to_occ
    x, y = np.meshgrid(np.linspace(0, 10, 4), np.linspace(0, 10, 4), indexing="ij")
    base = BezierSurface(np.stack([x, y, 0.3 * np.sin(x / 4) * np.cos(y / 5)], axis=-1))
    offset = BRepBuilderAPI_MakeFace(Geom_OffsetSurface(to_occ(base), 0.5), 1e-7).Face()
    write_step([("pair", sew([make_face(base), offset], 1e-6))], tmp_path / "o.step")
    with pytest.warns(RuntimeWarning, match="1 of 2 faces/edges not converted"):
        back = read_step(tmp_path / "o.step")
    assert not back.complete and len(back) == 1 and isinstance(back[0].object, BSplineSurface)
    (skip,) = back.skipped
    assert (skip.name, skip.kind) == ("pair", "face") and skip.index in (0, 1) and "offset" in skip.reason
    assert skip.shape.ShapeType() == TopAbs_FACE
    full = read_step(tmp_path / "o.step", approximate=1e-6)
    assert full.complete and len(full) == 2 and full.message == ""


def test_read_cad_dispatches_by_the_ending(tmp_path):
    """read_cad reads .step/.stp/.iges/.igs (any case) as read_step/read_iges do, and
    refuses other endings naming the path."""
    from cagd import BSplineCurve, CagdError
    from cagd.occ import read_cad, read_iges, read_step, write_iges, write_step
    c = BSplineCurve(np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 1.0, 1.0]]), 2)
    write_step({"c": c}, tmp_path / "a.STP")
    write_iges({"c": c}, tmp_path / "a.Igs")
    for name, reader in (("a.STP", read_step), ("a.Igs", read_iges)):
        ours, theirs = read_cad(tmp_path / name), reader(tmp_path / name)
        assert len(ours) == len(theirs) == 1
        assert np.array_equal(ours[0].object.control_points, theirs[0].object.control_points)
    (tmp_path / "a.obj").write_text("v 0 0 0\n")
    with pytest.raises(CagdError, match="path: .*a.obj.* is not a .step"):
        read_cad(tmp_path / "a.obj")
