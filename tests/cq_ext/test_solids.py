"""Solid helpers: sew_solid (the ellipsoid's eight rational patches: 4/3 pi a b c; the
gap report of an open set), booleans with ordinary CadQuery solids (inclusion-exclusion
of volumes, the half ellipsoid), close_with_caps, thicken (also of the engine's
spheres, tori, cylinders, cones and revolutions, through OCCT's analytic faces, and
CadQuery's shell of them: volumes against closed forms and Pappus); and the two
volume integrators (cagd.occ.volume's adaptive one vs CadQuery's fixed-order Volume())."""
import math
import re

import numpy as np
import pytest
from scipy.integrate import quad

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cagd import CagdError  # noqa: E402
from cagd.occ import area, volume  # noqa: E402
from OCP.BRep import BRep_Tool  # noqa: E402

from cq_helpers import nurbs_volume, revolution_wall_volume  # noqa: E402

A, B, C = 3.0, 2.0, 1.5
V_ELL = 4 / 3 * math.pi * A * B * C


@pytest.fixture(scope="module")
def ellipsoid():
    return cq_ext.sew_solid([cq_ext.to_cq(s) for s in cagd.ellipsoid(A, B, C)])


def test_sew_ellipsoid(ellipsoid):
    assert isinstance(ellipsoid, cq.Solid) and ellipsoid.isValid()
    assert len(ellipsoid.Faces()) == 8
    assert volume(ellipsoid.wrapped) == pytest.approx(V_ELL, rel=1e-9)          # measured 4e-15
    # engine surfaces are accepted directly, and so is the Workplane method
    assert volume(cq_ext.sew_solid(cagd.ellipsoid(A, B, C)).wrapped) == pytest.approx(V_ELL, rel=1e-9)
    wp = cq.Workplane().add([cq_ext.to_cq(s) for s in cagd.ellipsoid(A, B, C)]).sewSolid()
    assert volume(wp.val().wrapped) == pytest.approx(V_ELL, rel=1e-9)


def test_sew_shell_gives_a_closed_shell():
    shell = cq_ext.sew_shell([cq_ext.to_cq(s) for s in cagd.ellipsoid(A, B, C)])
    assert isinstance(shell, cq.Shell) and BRep_Tool.IsClosed_s(shell.wrapped)
    assert cq_ext.free_edges(cagd.ellipsoid(A, B, C)) == []


def quarter_ellipse(a, b):
    return quad(lambda t: math.hypot(a * math.sin(t), b * math.cos(t)), 0, math.pi / 2, epsabs=0, epsrel=1e-13)[0]


def test_sew_seven_of_eight_reports_the_gaps():
    faces = [cq_ext.to_cq(s) for s in cagd.ellipsoid(A, B, C)]
    with pytest.raises(CagdError, match="free edge") as info:
        cq_ext.sew_solid(faces[:7])
    msg = str(info.value)
    assert "3 free edge(s)" in msg and "faces" in msg
    # the missing octant's three quarter-ellipse arcs, by their lengths
    lengths = sorted(float(x) for x in re.findall(r"length ([0-9.]+)", msg))
    expected = sorted(quarter_ellipse(p, q) for p, q in ((A, B), (A, C), (B, C)))
    assert lengths == pytest.approx(expected, rel=1e-5)               # printed with 6 digits
    assert len(cq_ext.free_edges(faces[:7])) == 3


def test_sew_bad_arguments():
    with pytest.raises(CagdError, match="tol"):
        cq_ext.sew_solid(cagd.ellipsoid(A, B, C), tol=-1)
    with pytest.raises(CagdError, match=r"faces\[0\]"):
        cq_ext.sew_solid(["abc"])
    with pytest.raises(CagdError, match="faces"):
        cq.Workplane().sewSolid()


@pytest.fixture(scope="module")
def tilted_box():
    return cq.Workplane().box(3, 2.5, 2).rotate((0, 0, 0), (1, 1, 0), 25).translate((1.5, 0.7, 0.4)).val()


def test_booleans_with_a_box(ellipsoid, tilted_box):
    VA, VB = volume(ellipsoid.wrapped), volume(tilted_box.wrapped)
    assert VB == pytest.approx(3 * 2.5 * 2, rel=1e-12)
    union, diff, inter = ellipsoid.fuse(tilted_box), ellipsoid.cut(tilted_box), ellipsoid.intersect(tilted_box)
    for s in (union, diff, inter):
        assert s.isValid() and s.Solids()
    VU, VD, VI = (volume(s.wrapped) for s in (union, diff, inter))
    assert 0 < VI < min(VA, VB)
    assert VU == pytest.approx(VA + VB - VI, rel=1e-6)
    assert VD == pytest.approx(VA - VI, rel=1e-6)


def test_cut_in_half_by_a_box(ellipsoid):
    """A box over x >= 0 (larger than the ellipsoid elsewhere) keeps exactly half."""
    box = cq.Workplane().box(5, 8, 8).translate((2.5, 0, 0)).val()
    half = ellipsoid.cut(box)
    assert half.isValid()
    assert volume(half.wrapped) == pytest.approx(V_ELL / 2, rel=1e-9)
    assert volume(ellipsoid.intersect(box).wrapped) == pytest.approx(V_ELL / 2, rel=1e-9)


def test_cadquery_volume_is_less_accurate(ellipsoid):
    """CadQuery's Solid.Volume() integrates with a fixed low order: ~2e-10 off on the
    ellipsoid, ~2e-3 off on the rational B-spline cylinder (pi r^2 h is the oracle);
    cagd.occ.volume is within 1e-12 on both."""
    assert abs(ellipsoid.Volume() / V_ELL - 1) > 1e-11                     # measured 2.0e-10
    r, h = 2.0, 3.0
    cyl = cq.Workplane("XY").revolveSurface(cagd.BSplineCurve(np.array([[r, 0.0], [r, h]]), 1), close=True,
                                            nurbs=True).val()
    exact = math.pi * r * r * h
    assert volume(cyl.wrapped) == pytest.approx(exact, rel=1e-12)
    assert abs(cyl.Volume() / exact - 1) > 1e-3                              # measured 2.4e-3
    assert abs(cyl.Volume() / exact - 1) < 1e-2


def test_occ_volume_of_an_extruded_spline():
    pts = [(3, 0), (2, 2), (0, 3), (-2, 1.5), (-3, -1), (0, -2.5), (2, -2)]
    solid = cq.Workplane("XY").interpCurve(pts, end_condition="periodic").extrude(2.5).val()
    cap = area(solid.faces("<Z").wrapped)                 # planar face: accurate
    assert nurbs_volume(solid) == pytest.approx(cap * 2.5, rel=1e-12)
    assert volume(solid.wrapped) == pytest.approx(cap * 2.5, rel=1e-6)


def test_close_with_caps():
    prof = cagd.natural_cubic_spline(np.array([[2.0, 0], [2.8, 1.5], [2.2, 4], [1.5, 6]]))
    face = cq.Workplane("XY").revolveSurface(prof).val()
    solid = cq_ext.close_with_caps([face])
    assert isinstance(solid, cq.Solid) and solid.isValid()
    assert sorted(f.geomType() for f in solid.Faces()) == ["PLANE", "PLANE", "REVOLUTION"]
    # caps are the disks of radius 2 (y = 0) and 1.5 (y = 6)
    caps = sorted(area(f.wrapped) for f in solid.Faces() if f.geomType() == "PLANE")
    assert caps == pytest.approx([math.pi * 1.5**2, math.pi * 4], rel=1e-12)
    same = cq.Workplane("XY").add(face).closeWithCaps().val()
    assert volume(same.wrapped) == pytest.approx(volume(solid.wrapped), rel=1e-12)
    with pytest.raises(CagdError, match="faces"):
        cq.Workplane().closeWithCaps()


def test_close_with_caps_refuses_a_non_planar_loop():
    P = np.array([[(i, j, 0.5 * i * j) for j in range(3)] for i in range(3)], dtype=float)
    with pytest.raises(CagdError, match="planar|loop"):
        cq_ext.close_with_caps([cq_ext.to_cq(cagd.BezierSurface(P))])


PATCH = np.array([[(i * 10 / 3, j * 10 / 3, 0.5 * math.sin(i) * math.cos(j)) for j in range(4)] for i in range(4)])


@pytest.mark.parametrize("t", [0.5, -0.5])
def test_thicken_bicubic_patch(t):
    face = cq_ext.to_cq(cagd.BezierSurface(PATCH))
    solid = cq_ext.thicken(face, t)
    assert isinstance(solid, cq.Solid) and solid.isValid()
    # gently curved: volume = area x thickness up to the curvature terms and OCCT's offset
    # approximation (measured 4e-4)
    assert volume(solid.wrapped) == pytest.approx(area(face.wrapped) * abs(t), rel=0.02)
    cut = solid.cut(cq.Workplane().box(3, 3, 5).val())
    assert cut.isValid()
    assert volume(cut.wrapped) < volume(solid.wrapped)
    same = cq.Workplane().bezierSurface(PATCH).thickenSurface(t).val()
    assert volume(same.wrapped) == pytest.approx(volume(solid.wrapped), rel=1e-12)


def test_thicken_plane_is_exact():
    P = np.array([[(i, j, 0.0) for j in range(2)] for i in range(2)], dtype=float) * 4
    solid = cq_ext.thicken(cq_ext.to_cq(cagd.BezierSurface(P)), 0.25)
    assert volume(solid.wrapped) == pytest.approx(16 * 0.25, rel=1e-9)


# --- the engine's primitives: OCCT's analytic faces, which its offsets accept ----------------------
RP, HP, TORUS_R, T = 2.0, 3.0, 5.0, 0.3
SLANT = math.hypot(RP, HP)


def revolved_polygon_volume(poly) -> float:
    """Volume of a polygon in the (rho, z) half-plane turned about the z-axis (Pappus:
    2 pi x centroid radius x area, by the shoelace sums)."""
    a = c = 0.0
    for (x0, z0), (x1, z1) in zip(poly, poly[1:] + poly[:1]):
        cross = x0 * z1 - x1 * z0
        a, c = a + cross / 2, c + (x0 + x1) * cross / 6
    return abs(2 * math.pi * c)


def cone_wall(t: float) -> float:
    """The cone (base radius RP, height HP, apex up) thickened by t along its outward
    normal n = (HP, RP) / SLANT (meridian plane): the quadrilateral between the slant
    line and its offset; outwards the arc join rounds the apex (a spherical sector of
    radius t over the apex's normal cone, half-angle acos(RP / SLANT)), inwards the
    offset line meets the axis below the apex."""
    rim = (RP + t * HP / SLANT, t * RP / SLANT)
    if t > 0:
        tip = (t * HP / SLANT, HP + t * RP / SLANT)
        return revolved_polygon_volume([(0, HP), (RP, 0), rim, tip]) + 2 / 3 * math.pi * t ** 3 * (1 - RP / SLANT)
    return revolved_polygon_volume([(0, HP), (RP, 0), rim, (0, HP + t * SLANT / RP)])


PRIMITIVE_WALLS = {   # engine surface, volume of its thickening by t (closed forms)
    "sphere": (lambda: cagd.sphere(RP, (1.0, -2.0, 0.5)), lambda t: 4 / 3 * math.pi * abs((RP + t) ** 3 - RP ** 3)),
    "torus": (lambda: cagd.torus(TORUS_R, RP), lambda t: 2 * math.pi ** 2 * TORUS_R * abs((RP + t) ** 2 - RP ** 2)),
    "cylinder": (lambda: cagd.cylinder(RP, HP, (0.0, 1.0, 0.0)), lambda t: math.pi * abs((RP + t) ** 2 - RP ** 2) * HP),
    "cone": (lambda: cagd.cone(RP, HP), cone_wall),
}


@pytest.mark.parametrize("t", [T, -T])
@pytest.mark.parametrize("name", list(PRIMITIVE_WALLS))
def test_thicken_primitives(name, t):
    """thicken / thickenSurface of cagd.sphere, torus, cylinder, cone: a valid solid of
    the closed-form volume (measured 1e-14); the NURBS face of the same surface is
    refused by OCCT's offset (the rational circle's double knots: C0 to OCCT)."""
    make, wall = PRIMITIVE_WALLS[name]
    solid = cq_ext.thicken(make(), t)
    assert isinstance(solid, cq.Solid) and solid.isValid()
    assert volume(solid.wrapped) == pytest.approx(wall(t), rel=1e-6)
    face = cq_ext.to_cq(make())
    assert face.geomType() == name.upper()
    same = cq.Workplane().add(face).thickenSurface(t).val()
    assert volume(same.wrapped) == pytest.approx(volume(solid.wrapped), rel=1e-12)
    with pytest.raises(CagdError, match="thickness"):
        cq_ext.thicken(cq_ext.to_cq(make(), nurbs=True), t)


VASE = cagd.natural_cubic_spline(np.array([[2.0, 0, 0], [2.8, 0, 1.5], [2.2, 0, 4], [1.5, 0, 6], [1.8, 0, 8]]))


@pytest.mark.parametrize("t", [0.2, -0.2])
@pytest.mark.parametrize("angle, start", [(2 * math.pi, 0.0), (2.0, 0.5)])
def test_thicken_general_revolution(angle, start, t):
    """cagd.revolve of a B-spline profile (OCCT's surface of revolution of it): the wall
    against Pappus over the meridian strip (measured 3e-9 full, 4e-8 partial)."""
    solid = cq_ext.thicken(cagd.revolve(VASE, angle=angle, start_angle=start), t)
    assert solid.isValid()
    assert volume(solid.wrapped) == pytest.approx(revolution_wall_volume(VASE, t, angle), rel=1e-6)


def test_cadquery_shell_of_primitives():
    """CadQuery's shell (BRepOffsetAPI_MakeThickSolid) of solids bounded by engine
    surfaces: the hollow sphere and torus, the cylinder and cone opened at one end."""
    for surface, hollow in ((cagd.sphere(RP), 4 / 3 * math.pi * (RP ** 3 - (RP - T) ** 3)),
                            (cagd.torus(TORUS_R, RP), 2 * math.pi ** 2 * TORUS_R * (RP ** 2 - (RP - T) ** 2))):
        shelled = cq.Workplane().add(cq_ext.sew_solid([surface])).shell(-T).val()
        assert shelled.isValid() and len(shelled.Faces()) == 2
        assert volume(shelled.wrapped) == pytest.approx(hollow, rel=1e-6)
    cup = cq.Workplane().add(cq_ext.close_with_caps([cagd.cylinder(RP, HP)])).faces(">Z").shell(-T).val()
    assert cup.isValid()
    assert volume(cup.wrapped) == pytest.approx(math.pi * (RP ** 2 * HP - (RP - T) ** 2 * (HP - T)), rel=1e-6)
    # the cone without its base: the inner cone is similar, k = 1 - T SLANT / (RP HP)
    cap = cq.Workplane().add(cq_ext.close_with_caps([cagd.cone(RP, HP)])).faces("<Z").shell(-T).val()
    assert cap.isValid()
    k = 1 - T * SLANT / (RP * HP)
    assert volume(cap.wrapped) == pytest.approx(math.pi * RP ** 2 * HP / 3 * (1 - k ** 3), rel=1e-6)


@pytest.mark.parametrize("t", [0, 0.0, float("nan"), float("inf")])
def test_thicken_bad_thickness(t):
    with pytest.raises(CagdError, match="thickness"):
        cq_ext.thicken(cq_ext.to_cq(cagd.BezierSurface(PATCH)), t)


def test_thicken_errors():
    with pytest.raises(CagdError, match="no face"):
        cq.Workplane().thickenSurface(1.0)
    with pytest.raises(CagdError, match=r"faces\[0\]"):
        cq_ext.thicken("abc", 1.0)
    for t in (-2.0, -1.0):               # thicker than the radius inward: OCCT drops the collapsed face
        with pytest.raises(CagdError, match="thickness"):
            cq_ext.thicken(cq_ext.to_cq(cagd.sphere(1.0, (0, 0, 0))), t)
    with pytest.raises(CagdError, match="thickness"):
        cq_ext.thicken(cagd.cylinder(1.0, 2.0), -1.5)


# --- issue 14: extreme sweeps, far axes and thicknesses ---
_PROFILE = cagd.BezierCurve([[1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0]])


def _pappus_area_per_radian(curve) -> float:
    """Area of the revolution about the y axis per radian of sweep: int x(t) |c'(t)| dt
    (Pappus-Guldinus, the x coordinate is the distance from the axis)."""
    def f(t):
        d = curve.derivatives(np.array([t]), 1)
        return float(d[0, 0, 0] * np.linalg.norm(d[1, 0]))
    return quad(f, 0.0, 1.0, epsabs=1e-14)[0]


@pytest.mark.parametrize("degrees", [1e-12, 1e-8, 1e-7, 1e-3])
@pytest.mark.parametrize("nurbs", [False, True])
def test_revolve_surface_by_tiny_angles(degrees, nurbs):
    """A sweep OCCT reads as a whole turn (parameter range below its PConfusion, 1e-9:
    1e-8 degrees gave area 19.0 for the true 5.3e-10 before): the face has the area of
    Pappus' theorem (within 1e-6 relative)."""
    face = cq.Workplane("XY").revolveSurface(_PROFILE, degrees, nurbs=nurbs).val().wrapped
    expected = _pappus_area_per_radian(_PROFILE) * math.radians(degrees)
    assert area(face) == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("args, match", [
    ((1e300,), "angleDegrees: must be a finite non-zero"),           # > 60 s in OCCT before
    ((720.0,), "angleDegrees: must be a finite non-zero"),
    ((0.0,), "angleDegrees: must be a finite non-zero"),
    (("90",), "angleDegrees: must be a finite non-zero"),
    ((90.0, (1e300, 0, 0), (1e300, 1, 0)), "axisStart: coordinates up to 1e\\+300 exceed"),  # ConstructionError
    ((90.0, (0, 0, 0), (0, 1e300, 0)), "axisEnd: coordinates up to 1e\\+300 exceed"),
    ((90.0, (1, 2, 3), (1, 2, 3)), "axisStart, axisEnd: the same point"),
    ((90.0, "abc", (0, 1, 0)), "axisStart: not a numeric array"),    # UnboundLocalError once
])
@pytest.mark.parametrize("nurbs", [False, True])
def test_revolve_surface_bad_input(args, match, nurbs):
    with pytest.raises(CagdError, match=match):
        cq.Workplane("XY").revolveSurface(_PROFILE, *args, nurbs=nurbs)


def test_revolve_surface_far_profile_is_refused():
    far = cagd.BezierCurve([[1e200, 0.0, 0.0], [1e200, 1.0, 0.0]])
    with pytest.raises(CagdError, match="^profile: coordinates up to 1e\\+200 exceed"):
        cq.Workplane("XY").revolveSurface(far, 90.0)


@pytest.mark.parametrize("t", [1e300, -1e300, 1e-300])
def test_thicken_extreme_thickness(t):
    """OCCT's StdFail_NotDone (thickness 1e300) leaves as a CagdError naming thickness."""
    face = cq.Workplane().bezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]])
    with pytest.raises(CagdError, match="^thickness: OCCT"):
        face.thickenSurface(t)
