"""Workplane.gordonSurface, sweepSurface, sweep2Surface, blendCurve, blendSurface and
matchSurface (issue 18), measured on what CadQuery holds: faces sampled through OCCT
(BRepAdaptor), distances by BRepExtrema, continuity by cagd.edge_continuity on the
engine forms read back from the resulting CadQuery faces (from_shape), tangents by
CadQuery's own Edge.tangentAt, areas and volumes by OCCT's integration against closed
forms."""
import logging
import math

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402,F401  (registers the Workplane methods)
from cagd import CagdError  # noqa: E402
from cagd.occ import area, volume  # noqa: E402
from cagd.operations.blend_surface import curvature_gap  # noqa: E402
from cq_ext import from_shape, to_cq  # noqa: E402

from cq_helpers import distance_to_shape, face_points, green_area  # noqa: E402

V = cq.Vector
ISO = (0.0, 0.3, 0.7, 1.0)
PATCH = cagd.BSplineSurface(np.array([[(i, j, 0.5 * math.sin(i + 2 * j)) for j in range(4)] for i in range(4)],
                                     dtype=float), 3, 3)          # a bicubic Bezier patch on [0, 1]^2


def grid(domain, n=7, m=None):
    (a, b), (c, d) = domain
    U, W = np.meshgrid(np.linspace(a, b, n), np.linspace(c, d, m or n), indexing="ij")
    return U.ravel(), W.ravel()


def angle(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return math.atan2(np.linalg.norm(np.cross(a, b)), a @ b)


def world(wp, points):
    return np.array([wp.plane.toWorldCoords(tuple(map(float, q))).toTuple() for q in points])


# --- Gordon ----------------------------------------------------------------------------------
def test_gordon_of_the_iso_curves_of_a_bicubic_patch_is_the_patch():
    profiles = [PATCH.isocurve("u", v) for v in ISO]          # u -> S(u, v_i)
    guides = [PATCH.isocurve("v", u) for u in ISO]            # v -> S(u_j, v)
    wp = cq.Workplane("XY").gordonSurface(profiles, guides)
    face = wp.val()
    assert isinstance(face, cq.Face) and face.isValid()
    U, W = grid(((0, 1), (0, 1)))
    assert np.abs(face_points(face, U, W) - PATCH(U, W)).max() <= 1e-9          # measured 8.9e-16


def test_gordon_guides_given_profiles_pending_on_a_workplane():
    """Profiles queued by cagdCurve (local XZ coordinates) are consumed; guides given as
    CadQuery edges of the same (placed) curves."""
    wp = cq.Workplane("XZ")
    for v in ISO:
        wp = wp.cagdCurve(PATCH.isocurve("u", v))
    guides = [to_cq(cq_ext.placed(PATCH.isocurve("v", u), wp.plane)) for u in ISO]
    out = wp.gordonSurface(guides=guides)
    assert not out.ctx.pendingEdges
    U, W = grid(((0, 1), (0, 1)))
    assert np.abs(face_points(out.val(), U, W) - world(wp, PATCH(U, W))).max() <= 1e-9


def test_gordon_needs_a_family():
    with pytest.raises(CagdError, match="profiles, guides"):
        cq.Workplane().gordonSurface()
    with pytest.raises(CagdError, match="at least 2 profiles, got 0"):
        cq.Workplane().gordonSurface(guides=[PATCH.isocurve("v", u) for u in ISO])


def test_gordon_unmet_tol_is_an_error_with_max_error():
    """A profile that is a 7-point cubic through S(t^2, 0.3): the network misses by
    1.7e-3 and the surface's max_error is 2.36e-3 (a bound): accepted at tol 3e-3, an error at 2e-3."""
    profiles = [PATCH.isocurve("u", v) for v in ISO]
    profiles[1] = cagd.BSplineCurve(profiles[1](np.linspace(0, 1, 7) ** 2), 3)
    guides = [PATCH.isocurve("v", u) for u in ISO]
    assert cq.Workplane().gordonSurface(profiles, guides, tol=3e-3).val().isValid()
    with pytest.raises(CagdError, match=r"tol: gordonSurface: max_error 0\.0023\d > tol 0\.002"):
        cq.Workplane().gordonSurface(profiles, guides, tol=2e-3)


def test_gordon_engine_error_passes_through():
    far = [c.transformed(np.eye(3), (0, 0, 5.0)) for c in (PATCH.isocurve("v", u) for u in ISO)]
    with pytest.raises(CagdError, match=r"profiles\[0\], guides\[0\]: do not meet"):
        cq.Workplane().gordonSurface([PATCH.isocurve("u", v) for v in ISO], far)


def test_gordon_of_cadquery_circles_is_an_exact_fuselage():
    """CadQuery circles (rational edges) around splines through them: the exact rational
    Gordon surface, every circle on the face (BRepExtrema to 1e-9) and its iso-curves at
    the circles' heights of the circles' radii (BRepAdaptor points)."""
    zs, rs = (0.0, 30.0, 60.0, 100.0), (20.0, 24.0, 25.0, 20.0)
    circles = [cq.Edge.makeCircle(r, V(0, 0, z), V(0, 0, 1)) for r, z in zip(rs, zs)]
    guides = [cq.Edge.makeSpline([V(r * math.cos(a), r * math.sin(a), z) for r, z in zip(rs, zs)])
              for a in np.radians([10, 100, 190, 280])]
    face = cq.Workplane().gordonSurface(circles, guides, tol=1e-6).val()
    assert face.isValid()
    for c in circles:
        on = [c.positionAt(t).toTuple() for t in np.linspace(0.0, 1.0, 13)]
        assert distance_to_shape(face, on).max() <= 1e-9
    S = from_shape(face)
    assert S.is_rational
    (u0, u1), (v0, v1) = S.domain
    pts = S(np.linspace(u0, u1, 50), np.full(50, v0))
    assert np.abs(np.hypot(pts[:, 0], pts[:, 1]) - rs[0]).max() <= 1e-9


# --- sweeps ----------------------------------------------------------------------------------
R_TUBE, H = 1.5, 4.0


def test_circle_swept_along_a_line_is_a_cylinder_and_caps_to_its_solid():
    """CadQuery's circle (a pending wire) swept along a CadQuery line edge."""
    wp = cq.Workplane("XY").circle(R_TUBE).sweepSurface(path=cq.Edge.makeLine(V(0, 0, 0), V(0, 0, H)))
    assert not wp.ctx.pendingWires
    face = wp.val()
    assert face.isValid()
    Q = face_points(face, *grid(from_shape(face).domain, 17, 9))
    assert np.abs(np.hypot(Q[:, 0], Q[:, 1]) - R_TUBE).max() <= 1e-9             # measured 4.4e-16
    assert Q[:, 2].min() == pytest.approx(0.0, abs=1e-12) and Q[:, 2].max() == pytest.approx(H, abs=1e-12)
    # OCCT's adaptive area (CadQuery's Face.Area() integrates at a low fixed order: 2.7e-3 off here)
    assert area(face.wrapped) == pytest.approx(2 * math.pi * R_TUBE * H, rel=1e-6)   # measured 1.1e-9
    solid = wp.closeWithCaps().val()
    assert isinstance(solid, cq.Solid) and solid.isValid()
    assert volume(solid.wrapped) == pytest.approx(math.pi * R_TUBE ** 2 * H, rel=1e-6)   # measured 7.4e-10


def test_circle_swept_along_a_quarter_circle_is_a_torus_quarter():
    """Rotation-minimising frame along a CadQuery arc: a tube of radius 1 about the
    arc; closed with caps, Pappus' volume pi r^2 R pi / 2."""
    R = 10.0
    wp = cq.Workplane("XZ", origin=(R, 0, 0)).circle(1.0).sweepSurface(path=cq.Edge.makeCircle(R, angle1=0,
                                                                                               angle2=90))
    face = wp.val()
    assert face.isValid()
    Q = face_points(face, *grid(from_shape(face).domain, 17, 33))
    assert np.abs(np.hypot(np.hypot(Q[:, 0], Q[:, 1]) - R, Q[:, 2]) - 1.0).max() <= 1e-6   # measured 5.3e-15
    solid = wp.closeWithCaps().val()
    assert solid.isValid()
    assert volume(solid.wrapped) == pytest.approx(math.pi ** 2 * R / 2, rel=1e-6)    # measured 4.0e-8


def test_rectangle_wire_swept_edge_by_edge_into_a_shell():
    """CadQuery's rect (a pending wire of 4 edges) swept along a line: 4 planar faces
    sewn into one valid shell (OCCT: area 2 (w + h) H, 8 free edges), which caps to the
    box (volume w h H)."""
    w, h = 2.0, 1.0
    wp = cq.Workplane("XY").rect(w, h).sweepSurface(path=cq.Edge.makeLine(V(0, 0, 0), V(0, 0, H)))
    assert not wp.ctx.pendingWires
    shell = wp.val()
    assert isinstance(shell, cq.Shell) and shell.isValid() and len(shell.Faces()) == 4
    assert area(shell.wrapped) == pytest.approx(2 * (w + h) * H, rel=1e-12)
    assert len(cq_ext.free_edges(shell)) == 8
    solid = wp.closeWithCaps().val()
    assert solid.isValid() and volume(solid.wrapped) == pytest.approx(w * h * H, rel=1e-12)


def test_slot_wire_given_swept_along_a_curve_sews_its_faces():
    """A slot (two lines, two arcs) given as a wire and swept along a bent path: one
    face per edge, neighbours sewn within 2 tol into one shell with only the two end
    loops free; every face point within 1e-6 of the slot's tube of the path start's
    frame (checked at the start: the first section is the slot itself)."""
    slot = cq.Workplane("XY").slot2D(4.0, 1.0).val()          # a closed wire of 4 edges
    path = to_cq(cagd.BSplineCurve(np.array([[0, 0, 0], [0, 0, 3.0], [1.0, 0, 6.0], [3.0, 0, 8.0]]), 3))
    wp = cq.Workplane("XY").sweepSurface(slot, path)
    shell = wp.val()
    assert isinstance(shell, cq.Shell) and shell.isValid() and len(shell.Faces()) == 4
    assert len(cq_ext.free_edges(shell)) == 8                   # the two slot loops: 2 x 4 edges
    start = np.concatenate([face_points(f, *(lambda d: (np.linspace(*d[0], 9), np.full(9, d[1][0])))(
        from_shape(f).domain)) for f in shell.Faces()])
    assert np.abs(start[:, 2]).max() <= 1e-9                    # the sections start in the slot's plane


def test_sweep_both_curves_pending_scale_passed_through():
    """Profile then path as pending edges (local XY coordinates); a linear scale law:
    the end section is the profile scaled by 2 about the path's end."""
    prof = cagd.BezierCurve(np.array([[1.0, 0, 0], [1, 1, 0], [0, 1, 0]]))
    path = cagd.BSplineCurve(np.array([[0.0, 0, 0], [0, 0, 3]]), 1)
    wp = cq.Workplane("XY").cagdCurve(prof).cagdCurve(path).sweepSurface(scale=lambda t: 1 + t)
    assert not wp.ctx.pendingEdges
    face = wp.val()
    s = from_shape(face)
    (a, b), (c, d) = s.domain
    t = np.linspace(a, b, 9)
    end = face_points(face, t, np.full_like(t, d))
    expected = 2 * prof(np.linspace(0, 1, 9)) + [0, 0, 3]
    assert np.abs(end - expected).max() <= 1e-6


def test_sweep_up_vector_is_in_local_coordinates():
    """On the XZ workplane the local up vector (0, 1, 0) is the global z axis: the
    fixed-up frame keeps a flat profile's normal horizontal along a horizontal path."""
    prof = cagd.BSplineCurve(np.array([[0.0, 0, -1], [0, 0, 1]]), 1)      # local: across the path, along -y_g
    path = cagd.BezierCurve(np.array([[0.0, 0, 0], [3, 0, 2], [6, 0, 0]]))   # in the local xz-plane: global xy
    wp = cq.Workplane("XZ").sweepSurface(prof, path, frame=(0, 1, 0))
    face = wp.val()
    Q = face_points(face, *grid(from_shape(face).domain, 5, 9))
    assert np.abs(Q[:, 2]).max() <= 1e-6            # the ruling stays horizontal (global z = 0)


def test_sweep_unmet_tol_is_an_error_with_the_achieved_error():
    path = cagd.BezierCurve(np.array([[0, 0, 0], [3, 0, 2], [6, 3, 0], [9, 0, 1.0]]))
    prof = cagd.BezierCurve(np.array([[0, -1, 0], [0, 0, 1], [0, 1, 0.0]]))
    with pytest.raises(CagdError, match=r"tol: sweepSurface: .*max error .*not converged"):
        cq.Workplane().sweepSurface(prof, path, twist=lambda t: 3 * t, tol=1e-10)


def test_sweep_wrong_count_and_bad_frame():
    with pytest.raises(CagdError, match=r"profile, path: sweepSurface takes 2 curve\(s\).*found 0"):
        cq.Workplane().sweepSurface()
    line = cagd.BSplineCurve(np.array([[0.0, 0, 0], [0, 0, 3]]), 1)
    with pytest.raises(CagdError, match="frame"):
        cq.Workplane().sweepSurface(line, line, frame=(1, 2, 3, 4))


def _rails():
    rail1 = cq.Edge.makeSpline([V(0, 0, 0), V(3, 0.5, 0.3), V(6, 0, 0)])
    rail2 = cq.Edge.makeSpline([V(0, 4, 0), V(3, 4.5, -0.2), V(6, 5, 0.5)])
    arc = cq.Edge.makeThreePointArc(V(0, 0, 0), V(0, 2, 1.5), V(0, 4, 0))
    return rail1, rail2, arc


def test_sweep2_face_runs_along_both_rails():
    rail1, rail2, arc = _rails()
    face = cq.Workplane().sweep2Surface(arc, rail1, rail2, tol=1e-6).val()
    assert face.isValid()
    for edge in (rail1, rail2, arc):
        pts = np.array([edge.positionAt(x).toTuple() for x in np.linspace(0, 1, 11)])
        assert distance_to_shape(face, pts).max() <= 1e-6              # measured 7.1e-9 (rail1), 9e-16


def test_sweep2_profiles_pending_or_rails_pending():
    rail1, rail2, arc = _rails()
    ref = cq.Workplane().sweep2Surface(arc, rail1, rail2).val()
    U, W = grid(from_shape(ref).domain, 5)
    wp = cq.Workplane().add(arc)
    wp.ctx.pendingEdges = [arc]
    a = wp.sweep2Surface(rail1=rail1, rail2=rail2)
    assert not a.ctx.pendingEdges
    wp = cq.Workplane()
    wp.ctx.pendingEdges = [rail1, rail2]
    b = wp.sweep2Surface(arc)
    for out in (a, b):
        assert np.abs(face_points(out.val(), U, W) - face_points(ref, U, W)).max() <= 1e-12
    with pytest.raises(CagdError, match="rail2: give both rails or neither"):
        cq.Workplane().sweep2Surface(arc, rail1)
    with pytest.raises(CagdError, match="give the profiles or the rails"):
        cq.Workplane().sweep2Surface()


# --- blend curve ----------------------------------------------------------------------------
@pytest.mark.parametrize("continuity", [1, 2])
def test_blend_curve_between_a_cadquery_edge_and_an_engine_curve(continuity):
    c1 = cq.Edge.makeSpline([V(0, 0, 0), V(2, 1, 0), V(4, 0, 1)])
    c2 = cagd.BezierCurve(np.array([[8.0, 3, 2], [10, 4, 1], [12, 2, 0]]))
    wp = cq.Workplane().blendCurve(c1, "end", c2, "start", continuity=continuity)
    edge = wp.val()
    assert isinstance(edge, cq.Edge) and edge.isValid() and wp.ctx.pendingEdges == [edge]
    assert (edge.positionAt(0) - c1.endPoint()).Length <= 1e-12
    assert np.abs(np.array(edge.positionAt(1).toTuple()) - c2(0.0)).max() <= 1e-12
    assert angle(edge.tangentAt(0).toTuple(), c1.tangentAt(1).toTuple()) <= 1e-9           # measured 3e-16
    assert angle(edge.tangentAt(1).toTuple(), c2.derivative(np.array([0.0]), 1)[0]) <= 1e-9
    if continuity == 2:                                         # curvature, OCCT's, on both sides
        assert edge.curvatureAt(0) == pytest.approx(c1.curvatureAt(1), rel=1e-9)
        assert edge.curvatureAt(1) == pytest.approx(to_cq(c2).curvatureAt(0), rel=1e-9)


def test_blend_curve_closes_a_wire_with_cadquery():
    """Two arcs and the two bridges between them, the curves not given taken from the
    pending edges (c1 the last, c2 the first): CadQuery's own wire() and extrude take
    the four pending edges as one closed wire; its volume is the area Green's theorem
    gives over the four curves."""
    a = cagd.BezierCurve(np.array([[0.0, 0], [2, -2], [4, 0]]), weights=[1, 0.7, 1])
    b = cq.Edge.makeThreePointArc(V(4, 3, 0), V(2, 4, 0), V(0, 3, 0))
    wp = cq.Workplane().cagdCurve(a).blendCurve(None, "end", b, "start")
    wp.ctx.pendingEdges.append(b)
    wp = wp.blendCurve(None, "end", None, "start")
    loop = list(wp.ctx.pendingEdges)
    assert len(loop) == 4 and loop[2] is b
    solid = wp.wire().extrude(1.0).val()
    assert isinstance(solid, cq.Solid) and solid.isValid()
    enclosed = sum(green_area(from_shape(e)) for e in loop)       # Green's theorem over the loop's curves
    assert volume(solid.wrapped) == pytest.approx(abs(enclosed), rel=1e-9)
    with pytest.raises(CagdError, match="c1: not given and there are no pending edges"):
        cq.Workplane().blendCurve(None, "end", b, "start")


def test_blend_curve_bad_end():
    c = cagd.BezierCurve(np.array([[0.0, 0, 0], [1, 1, 0]]))
    with pytest.raises(CagdError, match="end1"):
        cq.Workplane().blendCurve(c, "middle", c.transformed(np.eye(3), (3, 0, 0)), "start")


# --- blend and match surfaces ----------------------------------------------------------------
def _faces():
    top = cq.Workplane().box(4, 4, 1).faces(">Z").val()              # z = 0.5; its u1 edge is x = 2
    wave = cq.Face.makeRuledSurface(cq.Edge.makeSpline([V(5, -2, 2), V(6, -1, 2.5), V(7, 0, 1.8), V(6.5, 2, 2.2)]),
                                    cq.Edge.makeSpline([V(8, -2, 3), V(9, 0, 3.5), V(8.5, 2, 3)]))  # v0 near x = 6
    return top, wave


@pytest.mark.parametrize("continuity", [1, 2])
def test_blend_surface_between_two_cadquery_faces(continuity):
    top, wave = _faces()
    wp = cq.Workplane().add(top).add(wave).blendSurface(top, "u1", wave, "v0", continuity=continuity)
    assert len(wp.vals()) == 3                          # added to the faces on the stack
    face = wp.vals()[-1]
    assert face.isValid()
    B, s1, s2 = from_shape(face), from_shape(top), from_shape(wave)
    r1, r2 = cagd.edge_continuity(s1, B, "u1", "v0"), cagd.edge_continuity(B, s2, "v1", "v0")
    for r in (r1, r2):
        assert r.G1 and r.normal_angle <= 1e-9 and r.gap <= 1e-12 * 10                 # measured 5.7e-16, 2e-15
    if continuity == 2:
        assert curvature_gap(s1, "u1", B, "v0") <= 1e-9 and curvature_gap(B, "v1", s2, "v0") <= 1e-9   # 4.4e-15
    # the three faces sew into one shell, open only along its outline
    shell = cq_ext.sew_shell([top, face, wave])
    assert isinstance(shell, cq.Shell) and len(cq_ext.free_edges([top, face, wave])) == 8


def test_blend_surface_engine_surfaces_in_local_coordinates():
    s1 = cagd.BSplineSurface(np.array([[(i, j, 0.0) for j in range(3)] for i in range(3)], dtype=float), 2, 2)
    s2 = s1.transformed(np.eye(3), (4.0, 0.5, 1.0))
    wp = cq.Workplane("XZ").blendSurface(s1, "u1", s2, "u0")
    B = from_shape(wp.val())
    g1, g2 = cq_ext.placed(s1, wp.plane), cq_ext.placed(s2, wp.plane)
    assert cagd.edge_continuity(g1, B, "u1", "v0").normal_angle <= 1e-9
    assert cagd.edge_continuity(B, g2, "v1", "u0").normal_angle <= 1e-9


def test_blend_surface_wrong_edge_and_trimmed_face():
    top, wave = _faces()
    with pytest.raises(CagdError, match="edge1: must be one of .*'w1'"):
        cq.Workplane().blendSurface(top, "w1", wave, "v0")
    with pytest.raises(CagdError, match="edge2: must be one of .*'u2'"):
        cq.Workplane().blendSurface(top, "u1", wave, "u2")
    holed = cq.Workplane().box(4, 4, 1).faces(">Z").workplane().hole(1).faces(">Z").val()
    with pytest.raises(CagdError, match="face1: a trimmed face.*untrimmed parameter box"):
        cq.Workplane().blendSurface(holed, "u1", wave, "v0")
    with pytest.raises(CagdError, match="face2: expected a cagd Surface or a face"):
        cq.Workplane().blendSurface(top, "u1", cq.Edge.makeLine(V(0, 0, 0), V(1, 0, 0)), "v0")
    with pytest.raises(CagdError, match="continuity"):
        cq.Workplane().blendSurface(top, "u1", wave, "v0", continuity=3)


@pytest.mark.parametrize("continuity", [0, 1, 2])
def test_match_surface_to_a_cadquery_face(continuity):
    top, _ = _faces()
    net = np.array([[(2.3 + i, -2 + j, 0.8 + 0.2 * math.sin(i + j)) for j in range(5)] for i in range(4)])
    wp0 = cq.Workplane().bsplineSurface(net, 3, 3)
    face = wp0.val()
    wp = wp0.matchSurface(face, "u0", top, "u1", continuity=continuity)
    assert len(wp.vals()) == 1                          # the matched face replaces the given one
    out = wp.val()
    assert out.isValid()
    M, T = from_shape(out), from_shape(top)
    r = cagd.edge_continuity(T, M, "u1", "u0")
    assert r.C0 and r.gap <= 1e-12 * 10                                                     # measured 2.2e-16
    if continuity >= 1:
        assert r.G1 and r.normal_angle <= 1e-9                                              # measured 0
    else:
        assert r.normal_angle > 0.1                     # G0 only moves the edge (measured 0.35 rad)
    if continuity == 2:
        assert curvature_gap(T, "u1", M, "u0") <= 1e-9
    # the far edge stays where it was
    t = np.linspace(0, 1, 9)
    assert np.abs(face_points(out, np.ones_like(t), t) - face_points(face, np.ones_like(t), t)).max() <= 1e-12


def test_match_surface_bad_edge():
    top, wave = _faces()
    with pytest.raises(CagdError, match="target_edge: must be one of .*'x'"):
        cq.Workplane().matchSurface(wave, "v0", top, "x")


# --- a solid from the network methods ----------------------------------------------------------
def test_blended_faces_thicken_and_log(caplog):
    """The achieved accuracy is logged (INFO, cq_ext.workplane); the blend with its two
    faces is a shell that thickenSurface makes a valid solid."""
    top, wave = _faces()
    with caplog.at_level(logging.INFO, logger="cq_ext.workplane"):
        wp = cq.Workplane().add(top).add(wave).blendSurface(top, "u1", wave, "v0")
    assert any("blendSurface: G1 blend" in r.getMessage() and "rad" in r.getMessage() for r in caplog.records)
    solid = wp.thickenSurface(0.2).val()
    assert isinstance(solid, cq.Solid) and solid.isValid() and volume(solid.wrapped) > 0


def test_sweep_twist_passed_through():
    """A radial segment along the z axis twisted by a quarter turn: a helicoid, whose
    end ruling points along y."""
    prof = cagd.BSplineCurve(np.array([[0.0, 0, 0], [1, 0, 0]]), 1)
    path = cagd.BSplineCurve(np.array([[0.0, 0, 0], [0, 0, 3]]), 1)
    face = cq.Workplane().sweepSurface(prof, path, twist=lambda t: 0.5 * math.pi * t).val()
    t = np.linspace(0, 1, 9)
    Q = face_points(face, np.ones_like(t), t)                       # the outer helix
    expected = np.column_stack([np.cos(0.5 * math.pi * t), np.sin(0.5 * math.pi * t), 3 * t])
    assert np.abs(Q - expected).max() <= 1e-6


# --- build123d shapes --------------------------------------------------------------------------
def test_build123d_edges_and_faces_are_taken():
    bd = pytest.importorskip("build123d")
    profiles = [cq_ext.to_b3d(PATCH.isocurve("u", v)) for v in ISO]
    guides = [cq_ext.to_b3d(PATCH.isocurve("v", u)) for u in ISO]
    U, W = grid(((0, 1), (0, 1)))
    face = cq.Workplane().gordonSurface(profiles, guides).val()
    assert np.abs(face_points(face, U, W) - PATCH(U, W)).max() <= 1e-9
    c1 = bd.Edge.make_spline([(0, 0, 0), (2, 1, 0), (4, 0, 1)])
    c2 = bd.Edge.make_circle(1.0).moved(bd.Location((8, 0, 0)))
    edge = cq.Workplane().blendCurve(c1, "end", c2, "start", continuity=2).val()
    assert angle(edge.tangentAt(0).toTuple(), tuple(c1.tangent_at(1))) <= 1e-9
    top, wave = _faces()
    b3d_top = bd.Face(top.wrapped)
    B = from_shape(cq.Workplane().blendSurface(b3d_top, "u1", bd.Face(wave.wrapped), "v0").val())
    assert cagd.edge_continuity(from_shape(top), B, "u1", "v0").normal_angle <= 1e-9
