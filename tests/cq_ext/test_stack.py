"""CadQuery's stack conventions (cq_ext.stack): surface methods add their face to the
faces on the stack (a chain keeps every surface: the chained thicken has the volume
of both patches, the chained ellipsoid patches sew into the ellipsoid); curve methods
queue pending edges that coonsPatch/loftSurface/ruledSurface consume; consumers say
what the stack holds when it does not fit. Points: CadQuery and build123d Vectors,
tuples and arrays give the same curves; includeCurrent with one point or many; bad
points are refused naming the argument."""
import math
import warnings

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402,F401  (registers the Workplane methods)
from cagd import CagdError  # noqa: E402
from cagd.occ import check_valid, volume  # noqa: E402

from cq_helpers import distance_to_shape, edge_points, edge_range, face_points  # noqa: E402


def flat_patch(x0, size=4.0):
    """A bicubic Bezier patch on the square [x0, x0 + size] x [0, size] of z = 0."""
    s = np.linspace(0, size, 4)
    return np.array([[(x0 + a, b, 0.0) for b in s] for a in s])


# --- surfaces add to the stack ----------------------------------------------------------------
def test_chained_surfaces_stay_on_the_stack_in_order():
    a, b = cagd.BezierSurface(flat_patch(0)), cagd.BezierSurface(flat_patch(4))
    wp = cq.Workplane().cagdSurface(a).cagdSurface(b)
    assert len(wp.vals()) == 2 and all(isinstance(f, cq.Face) for f in wp.vals())
    for face, s in zip(wp.vals(), (a, b)):                   # the new face last
        u = np.linspace(0, 1, 5)
        assert np.abs(face_points(face, u, u) - s(u, u)).max() <= 1e-12 * 8
    assert wp.parent.parent.parent is None and len(wp.parent.vals()) == 1    # each step a new Workplane


def test_chained_thicken_thickens_both_patches():
    """The issue: .bezierSurface(a).bezierSurface(b).thickenSurface(t) thickened b only
    (volume 16 x 0.5 / 2). Two coplanar 4 x 4 patches sharing an edge: the offset of a
    plane is exact, so OCCT's volume is 2 x 16 x t."""
    t = 0.5
    solid = cq.Workplane().bezierSurface(flat_patch(0)).bezierSurface(flat_patch(4)).thickenSurface(t).val()
    assert isinstance(solid, cq.Solid) and check_valid(solid)
    assert volume(solid) == pytest.approx(2 * 16 * t, rel=1e-9)


def test_chained_ellipsoid_patches_sew_into_the_ellipsoid():
    wp = cq.Workplane()
    for patch in cagd.ellipsoid(3.0, 2.0, 1.5):
        wp = wp.cagdSurface(patch)
    assert len(wp.vals()) == 8
    solid = wp.sewSolid().val()
    assert volume(solid) == pytest.approx(4 / 3 * math.pi * 3.0 * 2.0 * 1.5, rel=1e-9)


def test_surfaces_keep_faces_but_not_other_objects():
    box = cq.Workplane().box(2, 2, 2)
    wp = box.faces(">Z").bezierSurface(flat_patch(5))
    assert [type(o) for o in wp.vals()] == [cq.Face, cq.Face]
    wp = box.vertices().bezierSurface(flat_patch(5))          # vertices are not surfaces: replaced
    assert [type(o) for o in wp.vals()] == [cq.Face]


@pytest.mark.parametrize("method, args", [("thickenSurface", (1.0,)), ("sewSolid", ()), ("closeWithCaps", ())])
def test_consumers_say_what_the_stack_holds(method, args):
    wp = cq.Workplane().bezierCurve([(0, 0), (1, 1), (2, 0)])
    with pytest.raises(CagdError, match=rf"^{method}: no faces or shells on the stack \(it holds 1 Edge\)$"):
        getattr(wp, method)(*args)
    with pytest.raises(CagdError, match=rf"^{method}: no faces or shells on the stack \(it holds nothing\)$"):
        getattr(cq.Workplane(), method)(*args)


def test_consumers_take_shells_and_compounds():
    shell = cq_ext.sew_shell(cagd.ellipsoid(3.0, 2.0, 1.5))
    V = 4 / 3 * math.pi * 3.0 * 2.0 * 1.5
    assert isinstance(shell, cq.Shell)
    assert volume(cq.Workplane().add(shell).sewSolid().val()) == pytest.approx(V, rel=1e-9)
    compound = cq.Compound.makeCompound([cq_ext.to_cq(s) for s in cagd.ellipsoid(3.0, 2.0, 1.5)])
    assert volume(cq.Workplane().add(compound).sewSolid().val()) == pytest.approx(V, rel=1e-9)


# --- pending edges feed the patches ---------------------------------------------------------
LOOP = [[(0, 0), (1, -0.5), (2, 0)], [(2, 0), (2.5, 1), (2, 2)], [(2, 2), (1, 2.5), (0, 2)],
        [(0, 2), (-0.5, 1), (0, 0)]]


def test_four_chained_interp_curves_make_the_coons_patch():
    """The issue: coonsPatch() after four interpCurve calls saw 1 curve (only the last
    edge is on the stack); the four are the pending edges, and the patch consumes them."""
    wp = cq.Workplane("XZ")
    for pts in LOOP:
        wp = wp.interpCurve(pts)
    assert len(wp.ctx.pendingEdges) == 4
    out = wp.coonsPatch()
    assert [type(o) for o in out.vals()] == [cq.Face] and check_valid(out.val())
    assert out.ctx.pendingEdges == [] and out.ctx.firstPoint is None
    curves = [cq_ext.placed(cagd.natural_cubic_spline(np.array(p, dtype=float)), wp.plane) for p in LOOP]
    ref = cagd.CoonsPatch.from_loop(curves, 1e-7)
    U, V = np.meshgrid(np.linspace(0, 1, 6), np.linspace(0, 1, 6), indexing="ij")
    assert np.abs(face_points(out.val(), U, V) - ref(U.ravel(), V.ravel())).max() <= 1e-12 * 3
    # and it is bounded by the four curves
    for c in curves:
        assert distance_to_shape(out.val(), c(np.linspace(*c.domain, 9))).max() <= 1e-9 * 3


def test_mixed_curve_methods_feed_the_patch():
    wp = cq.Workplane().bezierCurve([(0, 0), (1, -0.5), (2, 0)]).nurbsCurve([(2, 0), (2.5, 0.7), (2.5, 1.3), (2, 2)]) \
        .hermiteCurve((2, 2), (0, 2), (-1, 1), (-1, -1)).interpCurve([(0, 2), (-0.5, 1), (0, 0)])
    face = wp.coonsPatch().val()
    assert isinstance(face, cq.Face) and check_valid(face)


def test_coons_wrong_count_names_the_source():
    wp = cq.Workplane().interpCurve(LOOP[0]).interpCurve(LOOP[1]).interpCurve(LOOP[2])
    with pytest.raises(CagdError, match=r"4 boundary curves, got 3 \(pending edges\)"):
        wp.coonsPatch()
    assert len(wp.ctx.pendingEdges) == 3                     # a failed patch consumes nothing


def test_coons_from_a_pending_closed_wire():
    wp = cq.Workplane().polyline([(0, 0), (2, 0), (2, 1), (0, 1)]).close()
    assert wp.ctx.pendingWires and not wp.ctx.pendingEdges
    face = wp.coonsPatch().val()
    assert face.Area() == pytest.approx(2.0, rel=1e-12)


SECTIONS = [cagd.natural_cubic_spline(np.array([(0, 0, z), (1, 0.3 * z, z), (2, -0.2, z), (3, 0.1 * z * z, z)]))
            for z in (0.0, 1.0, 2.5, 3.0)]


def surface_points(face, surface, n=7):
    """The face's B-spline (from_shape) and the engine surface on the same grid."""
    back = cq_ext.from_shape(face)
    (a, b), (c, d) = surface.domain
    U, V = np.meshgrid(np.linspace(a, b, n), np.linspace(c, d, n), indexing="ij")
    return back(U.ravel(), V.ravel()), surface(U.ravel(), V.ravel())


@pytest.mark.parametrize("plane", ["XY", "XZ"])
@pytest.mark.parametrize("source", ["pending", "engine", "edges"])
def test_loft_surface_is_cagd_loft(source, plane):
    wp = cq.Workplane(plane)
    placed = [cq_ext.placed(c, wp.plane) for c in SECTIONS]
    if source == "pending":
        for c in SECTIONS:
            wp = wp.cagdCurve(c)
        out = wp.loftSurface(parameters="centripetal")
        assert out.ctx.pendingEdges == []
    elif source == "engine":
        out = wp.loftSurface(*SECTIONS, parameters="centripetal")
    else:
        out = wp.loftSurface(*[cq_ext.to_cq(c) for c in placed], parameters="centripetal")
    ref = cagd.loft(placed, 3, "centripetal")
    got, expected = surface_points(out.val(), ref)
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    assert check_valid(out.val())


def test_ruled_surface_is_cagd_ruled():
    c0, c1 = SECTIONS[0], cagd.BezierCurve(np.array([(0, 1.0, 2), (1.5, 2, 2.5), (3, 1, 2)]), weights=[1, 2, 1])
    for out in (cq.Workplane().cagdCurve(c0).cagdCurve(c1).ruledSurface(),
                cq.Workplane().ruledSurface(c0, c1),
                cq.Workplane().ruledSurface(cq_ext.to_cq(c0), cq_ext.to_b3d(c1))):
        got, expected = surface_points(out.val(), cagd.ruled(c0, c1))
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
        assert check_valid(out.val()) and out.ctx.pendingEdges == []


def test_loft_and_ruled_errors():
    with pytest.raises(CagdError, match=r"c1: give both curves or neither"):
        cq.Workplane().ruledSurface(SECTIONS[0])
    with pytest.raises(CagdError, match=r"ruled surface needs 2 curves, got 3 \(pending edges\)"):
        cq.Workplane().cagdCurve(SECTIONS[0]).cagdCurve(SECTIONS[1]).cagdCurve(SECTIONS[2]).ruledSurface()
    with pytest.raises(CagdError, match=r"loft needs at least 2 section curves, got 0"):
        cq.Workplane().loftSurface()
    with pytest.raises(CagdError, match="degree_v"):
        cq.Workplane().loftSurface(*SECTIONS[:3], degree_v=0)
    assert cq.Workplane().loftSurface(*SECTIONS[:3]).val().isValid()   # degree 3 capped at 2 for 3 sections
    with pytest.raises(CagdError, match=r"curves\[1\]: expected a cagd Curve or an edge, got str"):
        cq.Workplane().loftSurface(SECTIONS[0], "x")
    with pytest.raises(CagdError, match=r"curves\[0\]: expected a cagd Curve or an edge, got a CadQuery Face"):
        cq.Workplane().loftSurface(cq_ext.to_cq(cagd.sphere(1.0)), SECTIONS[0])
    with pytest.raises(CagdError, match=r"^c1: expected a cagd Curve or an edge, got int"):
        cq.Workplane().ruledSurface(SECTIONS[0], 3)
    with pytest.raises(CagdError, match=r"a wire of 4 edges; give one curve per section"):
        cq.Workplane().rect(1, 1).loftSurface()


def test_loft_of_pending_closed_wires():
    blob = [(3, 0), (2, 2), (0, 3), (-2, 1.5), (-3, -1), (0, -2.5), (2, -2)]
    wp = cq.Workplane()
    for z, s in ((0, 1.0), (1, 0.8), (2, 0.9), (3, 0.6)):
        wp = wp.interpCurve([(s * x, s * y, z) for x, y in blob], "periodic")
    assert len(wp.ctx.pendingWires) == 4
    out = wp.loftSurface()
    assert out.ctx.pendingWires == [] and check_valid(out.val())
    back = cq_ext.from_shape(out.val())
    assert np.abs(back(np.array([0.0, 0.0]), np.array([0.0, 1.0])) - [(3, 0, 0), (1.8, 0, 3)]).max() <= 1e-9


# --- points ---------------------------------------------------------------------------------
PTS3 = [(0.0, 0.0, 0.0), (1.0, 2.0, 0.5), (3.0, 2.5, -1.0), (4.0, 0.0, 0.0), (6.0, 1.0, 2.0)]
PTS2 = [p[:2] for p in PTS3]


def as_cq(points):
    return [cq.Vector(*p) for p in points]


def as_b3d(points):
    bd = pytest.importorskip("build123d")
    return [bd.Vector(*p) for p in points]


def same_edge(a, b):
    ta, tb = np.linspace(*edge_range(a), 9), np.linspace(*edge_range(b), 9)
    return np.abs(edge_points(a, ta) - edge_points(b, tb)).max() <= 1e-15 * 8


@pytest.mark.parametrize("convert", [as_cq, as_b3d, np.array, lambda p: (tuple(q) for q in p)],
                         ids=["cq.Vector", "bd.Vector", "ndarray", "generator"])
@pytest.mark.parametrize("call", [lambda w, p: w.interpCurve(p), lambda w, p: w.bezierCurve(p),
                                  lambda w, p: w.nurbsCurve(p, 2)], ids=["interp", "bezier", "nurbs"])
def test_vectors_give_the_same_curve_as_tuples(convert, call):
    ref = call(cq.Workplane("XZ"), PTS3).val()
    assert same_edge(call(cq.Workplane("XZ"), convert(PTS3)).val(), ref)


def test_vector_arguments_elsewhere():
    bd = pytest.importorskip("build123d")
    ref = cq.Workplane().hermiteCurve((0, 0, 1), (3, 1, 0), (1, 2, 0), (2, -1, 1)).val()
    got = cq.Workplane().hermiteCurve(cq.Vector(0, 0, 1), bd.Vector(3, 1, 0), np.array([1, 2, 0]),
                                      cq.Vector(2, -1, 1)).val()
    assert same_edge(got, ref)
    grid = [[cq.Vector(i, j, 0.1 * i * j) for j in range(3)] for i in range(3)]
    face = cq.Workplane().bezierSurface(grid).val()
    assert np.allclose(face_points(face, [1.0], [1.0]), [[2, 2, 0.4]], atol=1e-15)
    sphere = cq.Workplane().sphere(2.0).faces()
    for pts in ([cq.Vector(3, 0, 0)], [bd.Vector(3, 0, 0)], (3, 0, 0), np.array([[3.0, 0, 0]])):
        (v,) = sphere.projectPoints(pts).vals()
        assert np.allclose(v.toTuple(), (2, 0, 0), atol=1e-12)


@pytest.mark.parametrize("points, end", [((2, 3), (2, 3, 0)), ([(2, 3)], (2, 3, 0)), ([(2, 3), (4, 0)], (4, 0, 0)),
                                         (cq.Vector(2, 3, 1), (2, 3, 1)), (np.array([2.0, 3.0]), (2, 3, 0))])
def test_include_current_with_one_point_or_many(points, end):
    e = cq.Workplane("XY").moveTo(1, 1).bezierCurve(points, includeCurrent=True).val()
    assert np.allclose(e.startPoint().toTuple(), (1, 1, 0), atol=1e-15)
    assert np.allclose(e.endPoint().toTuple(), end, atol=1e-15)


def test_include_current_interp_and_off_plane_current_point():
    wp = cq.Workplane("XY").moveTo(1, 1)
    e = wp.interpCurve([(2, 3), (4, 0)], includeCurrent=True).val()
    assert np.allclose(edge_points(e, [edge_range(e)[0]]), [(1, 1, 0)], atol=1e-15)
    start = cq.Workplane("XY").polyline([(0, 0, 0), (1, 1, 2)])      # current point (1, 1, 2): off the plane
    e = start.bezierCurve([(2, 3), (4, 0)], includeCurrent=True).val()
    assert np.allclose(e.startPoint().toTuple(), (1, 1, 2), atol=1e-15)
    assert np.allclose(e.endPoint().toTuple(), (4, 0, 0), atol=1e-15)


def sphere_faces():
    return cq.Workplane().sphere(1.0).faces()


@pytest.mark.parametrize("start, call, word", [
    (cq.Workplane, lambda w: w.interpCurve([cq.Vector(0, 0, 0), "x", (1, 1, 1)]), "points"),
    (cq.Workplane, lambda w: w.interpCurve([(0, 0), (1, np.nan), (2, 0)]), "points"),
    (cq.Workplane, lambda w: w.bezierCurve(None), "control_points"),
    (cq.Workplane, lambda w: w.nurbsCurve([(0, 0), (1, "a"), (2, 0), (3, 1)]), "control_points"),
    (cq.Workplane, lambda w: w.interpCurve([(0, 0), (1, 1)], "clamped", tangents="ab"), "tangents"),
    (cq.Workplane, lambda w: w.bezierCurve([[(0, 0)]], includeCurrent=True), "control_points"),
    (cq.Workplane, lambda w: w.box(1, 1, 1).faces(">Z").bezierCurve([(1, 1)], includeCurrent=True),
     "includeCurrent"),
    (cq.Workplane, lambda w: w.revolveSurface(SECTIONS[0], axisEnd="ab"), "axisEnd"),
    (cq.Workplane, lambda w: w.revolveSurface(SECTIONS[0], axisEnd=(1, 2, 3, 4)), "axisEnd"),
    (sphere_faces, lambda w: w.projectPoints("abc"), "points"),
    (sphere_faces, lambda w: w.projectPoints([(1, 2, 3, 4)]), "points"),
])
def test_bad_points_name_the_argument(start, call, word):
    with pytest.raises(CagdError, match=f"^{word}"):
        call(start())


# --- the interpCurve keyword ------------------------------------------------------------------
def test_parametrization_keyword_is_deprecated_but_works():
    pts = [(0, 0), (1, 2), (3, 2.5), (4, 0)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        new = cq.Workplane().interpCurve(pts, parameters="centripetal").val()
    with pytest.warns(DeprecationWarning, match="parameters="):
        old = cq.Workplane().interpCurve(pts, parametrization="centripetal").val()
    assert same_edge(old, new)
    uniform = cq.Workplane().interpCurve(pts, parameters="uniform").val()
    assert not same_edge(uniform, new)
    with pytest.raises(CagdError, match="both parametrization= .deprecated. and parameters="):
        cq.Workplane().interpCurve(pts, parameters="uniform", parametrization="chord")


def test_explicit_parameter_values():
    pts = np.array([(0, 0), (1, 2), (3, 2.5), (4, 0)], dtype=float)
    t = [0.0, 1.0, 1.5, 4.0]
    e = cq.Workplane().interpCurve(pts, parameters=t).val()
    assert edge_range(e) == pytest.approx((0.0, 4.0), abs=1e-15)
    assert np.abs(edge_points(e, t)[:, :2] - pts).max() <= 1e-12 * 4


# --- consumers of several faces --------------------------------------------------------------
def test_project_points_onto_the_nearest_face_on_the_stack():
    box = cq.Workplane().box(2, 3, 4)
    rng = np.random.default_rng(3)
    pts = rng.uniform(-4, 4, size=(30, 3))
    feet = np.array([v.toTuple() for v in box.faces().projectPoints(pts).vals()])
    # each foot is on the box's boundary, at the point's distance from the box (BRepExtrema)
    assert distance_to_shape(box.val(), feet).max() <= 1e-12 * 4
    d = np.linalg.norm(feet - pts, axis=1)
    inside = np.all(np.abs(pts) <= (1, 1.5, 2), axis=1)
    outside = ~inside
    assert np.abs(d[outside] - distance_to_shape(box.val(), pts[outside])).max() <= 1e-12 * 4
    # inside: the nearest face's distance, min over the six planes
    assert np.abs(d[inside] - np.min((1, 1.5, 2) - np.abs(pts[inside]), axis=1)).max() <= 1e-12 * 4


def test_intersect_two_chained_surfaces():
    """The plane z = 0 (a flat patch) and the plane y = 2 (a vertical one): the line
    y = 2, z = 0 across the first patch."""
    a = cagd.BezierSurface(flat_patch(0))
    b = cagd.BezierSurface(np.array([[(x, 2.0, z) for z in np.linspace(-2, 2, 3)] for x in np.linspace(-1, 5, 3)]))
    edges = cq.Workplane().cagdSurface(a).cagdSurface(b).intersectFaces().vals()
    assert len(edges) == 1 and edges[0].Length() == pytest.approx(4.0, rel=1e-9)
    P = edge_points(edges[0], np.linspace(*edge_range(edges[0]), 9))
    assert np.abs(P[:, 1:] - (2.0, 0.0)).max() <= 1e-9
    with pytest.raises(CagdError, match=r"need exactly two faces .*got 3"):
        cq.Workplane().cagdSurface(a).cagdSurface(b).intersectFaces(cq_ext.to_cq(a))
