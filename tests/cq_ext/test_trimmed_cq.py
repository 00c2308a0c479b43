"""Trimmed faces through cq_ext (issue 15): ``to_cq`` / ``to_b3d`` of a TrimmedSurface
are trimmed faces (a disk cut from a square: pi r^2 by OCCT's BRepGProp to 1e-9, valid
for BRepCheck, usable by CadQuery: extruded, the volume is area x height), and
``from_shape`` of CadQuery's and build123d's trimmed faces keeps the trim (a square with
a hole: 16 - pi; contains = inside the square and outside the circle, checked at the
3-D points)."""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")
bd = pytest.importorskip("build123d")

import cq_ext  # noqa: E402
from cagd import BSplineSurface, TrimmedSurface  # noqa: E402
from cagd.occ import area, check_valid, volume  # noqa: E402

sys.path.insert(0, str(Path(__file__).parents[1] / "surfaces"))
from test_trimmed import circle, square_patch  # noqa: E402

R, SIDE = 0.3, 2.0
DISK_AREA = math.pi * (SIDE * R) ** 2        # the patch is S(u, v) = (2u, 2v, 0)
RNG = np.random.default_rng(1515)


def disk():
    return TrimmedSurface(square_patch(SIDE), [[circle((0.5, 0.5), R)]])


def plate_oracle(ts, half=2.0, hole=1.0, count=4000):
    """contains against the point set: |x|, |y| < half and x^2 + y^2 > hole^2 at S(u, v),
    for random (u, v) of the domain farther than 1e-6 from those boundaries."""
    (u0, u1), (v0, v1) = ts.domain
    u, v = u0 + (u1 - u0) * RNG.random(count), v0 + (v1 - v0) * RNG.random(count)
    x, y = ts(u, v)[:, 0], ts(u, v)[:, 1]
    margin = np.minimum(np.minimum(half - np.abs(x), half - np.abs(y)), np.abs(np.hypot(x, y) - hole))
    far = np.abs(margin) > 1e-6
    want = (np.abs(x) < half) & (np.abs(y) < half) & (np.hypot(x, y) > hole)
    assert np.array_equal(ts.contains(u, v)[far], want[far])
    return int(far.sum()), int(want[far].sum())


def test_to_cq_of_a_disk_is_a_trimmed_face_with_area_pi_r2():
    face = cq_ext.to_cq(disk())
    assert isinstance(face, cq.Face) and check_valid(face.wrapped)
    assert area(face.wrapped) == pytest.approx(DISK_AREA, rel=1e-9)
    back = cq_ext.from_shape(face)
    assert isinstance(back, TrimmedSurface)
    assert back.area() == pytest.approx(DISK_AREA, rel=1e-12)


def test_a_trimmed_cq_face_works_in_cadquery():
    """Extruded by CadQuery 0.5 along z: a cylinder of volume pi (2r)^2 x 0.5 (OCCT's
    BRepGProp volume, over the rational side face, measured 3.1e-9 off: bound 1e-8)."""
    face = cq_ext.to_cq(disk())
    solid = cq.Solid.extrudeLinear(face, cq.Vector(0, 0, 0.5))
    assert check_valid(solid.wrapped)
    assert volume(solid.wrapped) == pytest.approx(DISK_AREA * 0.5, rel=1e-8)
    wp = cq.Workplane("XY").cagdSurface(disk())
    (f,) = wp.faces().vals()
    assert area(f.wrapped) == pytest.approx(DISK_AREA, rel=1e-9)


def test_to_b3d_of_a_disk_is_a_trimmed_face_with_area_pi_r2():
    face = cq_ext.to_b3d(disk())
    assert isinstance(face, bd.Face) and check_valid(face.wrapped)
    assert area(face.wrapped) == pytest.approx(DISK_AREA, rel=1e-9)
    assert isinstance(cq_ext.from_shape(face), TrimmedSurface)


def test_from_shape_of_a_cadquery_face_with_a_hole_keeps_the_trim():
    top = cq.Workplane().rect(4, 4).circle(1).extrude(1).faces(">Z").val()
    ts = cq_ext.from_shape(top)
    assert isinstance(ts, TrimmedSurface) and len(ts.loops) == 2
    assert ts.area() == pytest.approx(16 - math.pi, rel=1e-12)
    assert ts.area() == pytest.approx(area(top.wrapped), rel=1e-12)
    n, inside = plate_oracle(ts)
    assert n > 3000 and 0 < inside < n


def test_from_shape_of_a_build123d_face_with_a_hole_keeps_the_trim():
    with bd.BuildSketch() as sk:
        bd.Rectangle(4, 4)
        bd.Circle(1, mode=bd.Mode.SUBTRACT)
    (face,) = sk.sketch.faces()
    ts = cq_ext.from_shape(face)
    assert isinstance(ts, TrimmedSurface) and len(ts.loops) == 2
    assert ts.area() == pytest.approx(16 - math.pi, rel=1e-12)
    plate_oracle(ts)


def test_from_shape_of_an_untrimmed_face_stays_a_surface():
    """A face whose boundary is its parameter box is the plain surface (no trim to keep)."""
    top = cq.Workplane().rect(4, 4).extrude(1).faces(">Z").val()
    s = cq_ext.from_shape(top)
    assert isinstance(s, BSplineSurface) and not isinstance(s, TrimmedSurface)
    assert cq_ext.from_shape(top).to_nurbs().control_points.shape[:2] == (2, 2)


def test_thicken_a_trimmed_annulus():
    """cq_ext.thicken of a planar annulus (holes kept): a valid solid of volume area x t
    (measured 4.4e-14 relative)."""
    ts = TrimmedSurface(square_patch(SIDE), [[circle((0.5, 0.5), R)], [circle((0.5, 0.5), 0.1, clockwise=True)]])
    solid = cq_ext.thicken(ts, 0.25)
    assert isinstance(solid, cq.Solid) and check_valid(solid.wrapped)
    want = math.pi * (SIDE ** 2) * (R ** 2 - 0.1 ** 2) * 0.25
    assert volume(solid.wrapped) == pytest.approx(want, rel=1e-9)
