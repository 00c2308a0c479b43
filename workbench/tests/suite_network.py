"""Headless cases of the curve-network and blending objects (issue 18, see
headless_suite.py): Gordon surface, Sweep (one and two rails), Blend curve, Blend
surface and Match surface. The oracles are Part's own: distToShape, Area, normalAt,
tangentAt, curvatureAt of the shapes FreeCAD holds; each object follows a moved or
edited link on recompute, and a wrong link is an error naming the property."""
import math
import os

import numpy as np

import FreeCAD as App
import Part

from suite_support import (OUT, V, case, check, compare, conversion, expect_error, exported, new_doc, recompute_ok,
                           surfaces)
from cagdwb import network

MEASURED = {}                  # largest values measured, printed at the end of the suite
STATIONS = 50                  # stations along an edge for the tangent-plane angles (the 50)


def _note(what, value):
    MEASURED[what] = max(MEASURED.get(what, 0.0), float(value))
    return value


def _readonly(obj, names):
    for name in names:
        check("ReadOnly" in obj.getEditorMode(name), f"{obj.Label}.{name} is editable")


def _angle(a, b):
    """The angle between two lines (unsigned directions), from the cross product:
    accurate near 0 (acos of the dot product resolves only ~1e-8 rad)."""
    s, c = a.cross(b).Length, abs(a.dot(b))
    return math.atan2(s, c)


def _dist(shape, p):
    return shape.distToShape(Part.Vertex(p))[0]


def _span_area(face):
    """Part's Area of a B-spline face summed over its knot spans in u (Part's Surface.segment
    of each span; FreeCAD's Area of the whole face uses one Gauss rule across the spans)."""
    u0, u1, v0, v1 = face.ParameterRange
    knots = [k for k in face.Surface.getUKnots() if u0 <= k <= u1]
    total = 0.0
    for a, b in zip(knots[:-1], knots[1:]):
        piece = face.Surface.copy()
        piece.segment(a, b, v0, v1)
        total += piece.toShape().Area
    return total


def _feature(doc, shape, name):
    obj = doc.addObject("Part::Feature", name)
    obj.Shape = shape
    return obj


# --- sweeps -------------------------------------------------------------------------------------
@case
def test_sweep_circle_along_line_is_cylinder():
    """A circle of radius r swept along a straight line of length h: every point at radius r
    between the ends is on the face (Part's distToShape ~0) and Part's Area is 2 pi r h."""
    doc = new_doc("sweep")
    r, h = 5.0, 20.0
    circle = doc.addObject("Part::Circle", "Circle")
    circle.Radius = r
    line = doc.addObject("Part::Line", "Path")
    line.X2, line.Y2, line.Z2 = 0.0, 0.0, h
    doc.recompute()
    obj = network.make_sweep((circle, "Edge1"), (line, "Edge1"), doc=doc)
    recompute_ok(obj)
    check(obj.getTypeIdOfProperty("Tolerance") == "App::PropertyPrecision", "Tolerance type")
    _readonly(obj, ("MaxError", "Converged"))
    check(obj.Converged and obj.MaxError <= obj.Tolerance, f"{obj.MaxError} {obj.Converged}")
    compare(obj)

    def cylinder(height):
        face = obj.Shape.Faces[0]
        worst = max(_dist(face, V(r * math.cos(a), r * math.sin(a), z))
                    for a in np.linspace(0.0, 2 * math.pi, 13) for z in np.linspace(0.0, height, 7))
        exact = 2 * math.pi * r * height
        area = abs(_span_area(face) - exact) / exact
        # Part's Area of the whole periodic rational face integrates across its double knots
        # (2.7e-3 off for Part's own makeCylinder().toNurbs() too): equal to that one's
        own = Part.makeCylinder(r, height).Faces[0].toNurbs().Faces[0].Area
        same = abs(face.Area - own) / own
        _note("sweep cylinder: distToShape of points at radius r (mm)", worst)
        _note("sweep cylinder: relative error of Part's Area summed over knot spans", area)
        _note("sweep cylinder: Area vs Part's own NURBS cylinder's Area (relative)", same)
        check(worst <= 1e-9 and area <= 1e-6 and same <= 1e-9,
              f"h {height}: points {worst:.3g} off, Area off {area:.3g}, vs Part's NURBS cylinder {same:.3g}")
    cylinder(h)
    line.Z2 = 35.0                                      # the linked path changes: the sweep follows
    doc.recompute()
    recompute_ok(obj)
    cylinder(35.0)
    line.X1, line.Y1, line.Z1, line.X2, line.Y2, line.Z2 = 0.0, 0.0, 35.0, 0.0, 0.0, 0.0   # path backwards
    doc.recompute()
    recompute_ok(obj)
    cylinder(35.0)
    exported(obj, compare(obj))
    obj.Frame = "frenet"                                # a straight path has no Frenet normal
    expect_error(obj, ["Frame", "frenet"])
    check(obj.MaxError == 0.0 and not obj.Converged, "results kept after an error")
    obj.Frame = "rmf"
    obj.Profile = (line, "Vertex1")
    expect_error(obj, ["Profile", "not an edge"])
    obj.Profile = (circle, "Edge1")
    obj.Tolerance = 0.0
    expect_error(obj, ["Tolerance", "> 0"])
    obj.Tolerance = 1e-4
    recompute_ok(obj)


@case
def test_sweep_follows_a_sketch():
    """The profile is a sketch's circle: changing its radius constraint (setDatum) or moving
    the sketch recomputes the sweep: a cylinder of the new radius (Part distToShape of
    points at that radius, Area summed over knot spans = 2 pi r h to 1e-6)."""
    import Sketcher
    doc = new_doc("sweepsketch")
    sketch = doc.addObject("Sketcher::SketchObject", "ProfileSketch")
    sketch.addGeometry(Part.Circle(V(0, 0, 0), V(0, 0, 1), 5.0), False)
    radius = sketch.addConstraint(Sketcher.Constraint("Radius", 0, 5.0))
    sketch.addConstraint(Sketcher.Constraint("Coincident", 0, 3, -1, 1))
    line = doc.addObject("Part::Line", "Path")
    line.X2, line.Y2, line.Z2 = 0.0, 0.0, 30.0
    doc.recompute()
    obj = network.make_sweep((sketch, "Edge1"), (line, "Edge1"), doc=doc)
    recompute_ok(obj)

    def cylinder(r, z0, h):
        face = obj.Shape.Faces[0]
        worst = max(_dist(face, V(r * math.cos(a), r * math.sin(a), z0 + z))
                    for a in np.linspace(0.0, 2 * math.pi, 9) for z in np.linspace(0.0, h, 5))
        area = abs(_span_area(face) - 2 * math.pi * r * h) / (2 * math.pi * r * h)
        _note("sweep of a sketch's circle: distToShape at radius r (mm)", worst)
        _note("sweep of a sketch's circle: relative Area error (spans)", area)
        check(worst <= 1e-9 and area <= 1e-6, f"r {r}: points {worst:.3g} off, Area off {area:.3g}")
    cylinder(5.0, 0.0, 30.0)
    sketch.setDatum(radius, App.Units.Quantity("8 mm"))          # the linked sketch edge changes
    doc.recompute()
    recompute_ok(obj)
    cylinder(8.0, 0.0, 30.0)
    sketch.Placement = App.Placement(V(0, 0, 10), App.Rotation())  # the sketch moves up the path
    doc.recompute()
    recompute_ok(obj)
    cylinder(8.0, 10.0, 30.0)                                     # the profile swept from where it sits


@case
def test_sweep_along_arc_rmf():
    """A circle of radius 3 normal to an arc of radius 30 at its start, swept along it
    (rotation-minimising frame): every point of the face is 3 from the arc (Part's
    distToShape) within the reported MaxError <= Tolerance."""
    doc = new_doc("sweeparc")
    arc = _feature(doc, Part.makeCircle(30.0, V(0, 0, 0), V(0, 0, 1), 0, 120), "Arc")
    ring = _feature(doc, Part.makeCircle(3.0, V(30, 0, 0), V(0, 1, 0)), "Ring")
    doc.recompute()
    obj = network.make_sweep((ring, "Edge1"), (arc, "Edge1"), doc=doc, Tolerance=1e-5)
    recompute_ok(obj)
    compare(obj)
    face = obj.Shape.Faces[0]
    u0, u1, v0, v1 = face.ParameterRange
    worst = max(abs(_dist(arc.Shape, face.Surface.value(u, v)) - 3.0)
                for u in np.linspace(u0, u1, 11) for v in np.linspace(v0, v1, 15))
    _note("sweep along an arc: |distance to the arc - 3| (mm)", worst)
    _note("sweep along an arc: MaxError (mm)", obj.MaxError)
    check(obj.Converged and worst <= obj.MaxError + 1e-9 and obj.MaxError <= 1e-5,
          f"tube radius off by {worst:.3g}, MaxError {obj.MaxError:.3g}")


@case
def test_sweep2_between_rails():
    """An arc between two rails: the sweep's side edges lie on the rails (Part's
    distToShape), its first iso-curve is the profile; a profile drawn from Rail2 to Rail1
    is turned round; a rail moved: the sweep follows."""
    doc = new_doc("sweep2")
    rail1 = _feature(doc, Part.makeLine(V(0, 0, 0), V(0, 40, 0)), "Rail1")
    rail2 = _feature(doc, Part.makeLine(V(20, 0, 0), V(30, 40, 5)), "Rail2")
    profile = _feature(doc, Part.Arc(V(20, 0, 0), V(10, 0, 6), V(0, 0, 0)).toShape(), "Profile")   # rail2 -> rail1
    doc.recompute()
    obj = network.make_sweep2([(profile, "Edge1")], (rail1, "Edge1"), (rail2, "Edge1"), doc=doc)
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("MaxError", "Converged"))

    def on_rails():
        face = obj.Shape.Faces[0]
        u0, u1, v0, v1 = face.ParameterRange
        gap = max(max(_dist(rail1.Shape, face.Surface.value(u0, v)), _dist(rail2.Shape, face.Surface.value(u1, v)))
                  for v in np.linspace(v0, v1, 21))
        first = max(_dist(profile.Shape, face.Surface.value(u, v0)) for u in np.linspace(u0, u1, 21))
        _note("sweep2: side edges off the rails (mm)", gap)
        _note("sweep2: first iso-curve off the profile (mm)", first)
        check(gap <= 1e-9 and first <= 1e-9, f"rails {gap:.3g}, profile {first:.3g}")
    on_rails()
    rail2.Shape = Part.makeLine(V(20, 0, 0), V(45, 40, -5))
    doc.recompute()
    recompute_ok(obj)
    on_rails()
    area = obj.Shape.Area
    rail2.Shape = Part.makeLine(V(45, 40, -5), V(20, 0, 0))       # drawn the other way: the same sweep
    doc.recompute()
    recompute_ok(obj)
    on_rails()
    check(abs(obj.Shape.Area - area) <= 1e-9 * area, f"reversed Rail2: area {obj.Shape.Area} != {area}")
    obj.Rail2 = (rail1, "Edge1")                         # both rails the same line: zero chords
    expect_error(obj, ["Rail2", "zero-length chord"])
    obj.Rail2 = (rail2, "Edge1")
    obj.Profiles = []
    expect_error(obj, ["Profiles", "no edges"])


# --- Gordon --------------------------------------------------------------------------------------
def _patch():
    """A wavy bicubic B-spline patch on [0, 1]^2 with one interior knot at 0.5 each way."""
    i, j = np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij")
    P = np.stack([10.0 * i + 1.5 * np.sin(j), 8.0 * j, 3.0 * np.sin(i + 0.7 * j) + 0.4 * i * j], -1)
    k = [0, 0, 0, 0, 0.5, 1, 1, 1, 1]
    return conversion.cagd.BSplineSurface(P, 3, 3, k, k)


@case
def test_gordon_reproduces_a_patch():
    """Iso-curves of a known bicubic patch at u, v = 0, 1/4, ..., 1 (Part's own uIso / vIso
    of the patch) are a network whose Gordon surface is the patch: Surface.value(u, v)
    equal to the patch at 21 x 21 parameters to 1e-9. A profile moved off the network is
    an error naming it; moved back, the surface is valid again."""
    doc = new_doc("gordon")
    patch = _patch()
    part = conversion.surface_to_part(patch)
    params = [0.0, 0.25, 0.5, 0.75, 1.0]
    profiles = [_feature(doc, part.vIso(v).toShape(), f"Profile{k}") for k, v in enumerate(params)]   # along u
    guides = [_feature(doc, part.uIso(u).toShape(), f"Guide{k}") for k, u in enumerate(params)]       # along v
    doc.recompute()
    obj = network.make_gordon([(o, "Edge1") for o in profiles[::-1]], [(o, "Edge1") for o in guides], doc=doc)
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("MaxError", "MaxMiss", "Converged"))
    check(obj.Converged and obj.MaxError <= 1e-9, f"MaxError {obj.MaxError}")
    s = obj.Shape.Faces[0].Surface
    size = float(np.ptp(patch.control_points.reshape(-1, 3), axis=0).max())

    def deviation():
        worst = 0.0
        for u in np.linspace(0.0, 1.0, 21):
            for v in np.linspace(0.0, 1.0, 21):
                q = np.array(tuple(s.value(float(u), float(v))))
                worst = max(worst, float(np.abs(q - patch(u, v)).max()))
        return worst
    # profiles were given in reverse order: the engine sorts them (u along the profiles, v along guide 0)
    worst = deviation()
    _note("gordon vs patch, same (u, v) (mm)", worst)
    check(worst <= 1e-9 * max(1.0, size), f"Gordon surface {worst:.3g} off the patch")
    exported(obj, compare(obj))
    profiles[2].Placement = App.Placement(V(0, 0, 2.0), App.Rotation())      # off the network
    doc.recompute()
    expect_error(obj, ["Profiles[2] (Profile2.Edge1)"])
    profiles[2].Placement = App.Placement()
    doc.recompute()
    recompute_ok(obj)
    obj.Guides = [(guides[0], "Edge1")]
    expect_error(obj, ["Guides", "need 2"])
    obj.Guides = [(o, "Edge1") for o in guides]
    obj.Tolerance = 0.0
    expect_error(obj, ["Tolerance"])


# --- blends ----------------------------------------------------------------------------------------
def _grid_surface(doc, x0, name, lift=0.0, tilt=0.0):
    """A B-spline surface object (6 x 5 poles, bicubic), x in [x0, x0 + 40] along u, y in [0, 30] along v."""
    i, j = np.meshgrid(np.arange(6.0), np.arange(5.0), indexing="ij")
    X, Y = x0 + 8.0 * i, 7.5 * j
    Z = 3.0 * np.sin(0.6 * i + 0.4 * j) + lift + tilt * i
    obj = surfaces.make_bspline_surface(np.stack([X, Y, Z], -1), 6, doc=doc)
    obj.Label = name
    doc.recompute()
    return obj


def _across(blend_face, side_face, v_edge, ends):
    """Largest tangent-plane angle (Part's normalAt, both faces) and position gap across
    the blend's v = v_edge boundary at STATIONS stations; the neighbour's parameters
    from Part's Surface.parameter."""
    u0, u1, _, _ = blend_face.ParameterRange
    angle = gap = 0.0
    for u in np.linspace(u0, u1, STATIONS):
        p = blend_face.Surface.value(float(u), v_edge)
        a, b = side_face.Surface.parameter(p)
        angle = max(angle, _angle(blend_face.normalAt(float(u), v_edge), side_face.normalAt(a, b)))
        gap = max(gap, _dist(ends, p))
    return angle, gap


def _edge_of(face, side):
    return next(e for e in face.Edges if network.edge_side(face, e) == side)


@case
def test_blend_surface_g1_g2():
    """A blend between the u1 edge of one face and the u0 edge of another across a gap:
    tangent planes (Part's normalAt of the blend and of each neighbour) agree to 1e-9 rad
    at 50 stations along both edges, G1 and G2; the blend follows a moved face; a wrong
    link is an error naming the property."""
    doc = new_doc("blendsrf")
    a = _grid_surface(doc, 0.0, "Left")
    b = _grid_surface(doc, 60.0, "Right", lift=6.0, tilt=-0.8)
    obj = network.make_blend_surface((a, "Face1"), "u1", (b, "Face1"), "u0", doc=doc)
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("MaxAngle", "MaxCurvatureGap", "MaxGap", "Converged"))

    def measured(what):
        fa, fb, fblend = a.Shape.Faces[0], b.Shape.Faces[0], obj.Shape.Faces[0]
        _, _, w0, w1 = fblend.ParameterRange
        ang1, gap1 = _across(fblend, fa, w0, _edge_of(fa, "u1"))
        ang2, gap2 = _across(fblend, fb, w1, _edge_of(fb, "u0"))
        _note(f"blend surface {what}: tangent-plane angle, Part normalAt (rad)", max(ang1, ang2))
        _note(f"blend surface {what}: gap to the edges (mm)", max(gap1, gap2))
        check(max(ang1, ang2) <= 1e-9 and max(gap1, gap2) <= 1e-9,
              f"{what}: angles {ang1:.3g}, {ang2:.3g} rad, gaps {gap1:.3g}, {gap2:.3g}")
        check(obj.Converged and obj.MaxAngle <= 1e-9, f"{what}: engine MaxAngle {obj.MaxAngle}")
    measured("G1")
    obj.Continuity = "G2"
    recompute_ok(obj)
    measured("G2")
    check(obj.MaxCurvatureGap <= 1e-9 and obj.Shape.Faces[0].Surface.VDegree == 5,
          f"G2: curvature gap {obj.MaxCurvatureGap}, degree {obj.Shape.Faces[0].Surface.VDegree}")
    _note("blend surface G2: engine MaxCurvatureGap", obj.MaxCurvatureGap)
    before = obj.Shape.copy()
    b.Placement = App.Placement(V(5, 0, 4), App.Rotation(V(0, 1, 0), 10))   # the linked face moves
    doc.recompute()
    recompute_ok(obj)
    check(not obj.Shape.isPartner(before) and abs(obj.Shape.Area - before.Area) > 1e-6, "the blend did not follow")
    measured("G2 after moving")
    exported(obj, compare(obj))
    obj.TangentScale1 = -1.0
    expect_error(obj, ["TangentScale1", "positive"])
    obj.TangentScale1 = 1.0
    obj.Face1 = (a, "Edge1")
    expect_error(obj, ["Face1", "not a face"])
    obj.Face1 = (b, "Face1")                                     # the same edge twice
    obj.Edge1 = "u0"
    expect_error(obj, ["Edge2", "coincides"])
    plate = _feature(doc, Part.makeBox(10, 10, 1).cut(Part.makeCylinder(3, 5, V(5, 5, -1))), "Holed")
    top = next(k for k, f in enumerate(plate.Shape.Faces) if abs(f.CenterOfMass.z - 1.0) < 1e-9)
    obj.Face1 = (plate, f"Face{top + 1}")
    expect_error(obj, ["Face1", "trimmed face"])


@case
def test_match_surface():
    """A face's u1 edge matched to another face's u0 edge (which it does not touch): G0
    puts it on the edge (Part distToShape 1e-9), G1 and G2 also make the tangent planes
    agree at 50 stations to 1e-9 rad (Part normalAt); the opposite edge stays."""
    doc = new_doc("match")
    a = _grid_surface(doc, 0.0, "Moving")
    t = _grid_surface(doc, 45.0, "Target", lift=3.0, tilt=0.6)
    obj = network.make_match_surface((a, "Face1"), "u1", (t, "Face1"), "u0", doc=doc, Continuity="G0")
    recompute_ok(obj)
    compare(obj)
    check(obj.Proxy.claimed(obj) == [a], "claims")
    for level in ("G0", "G1", "G2"):
        obj.Continuity = level
        recompute_ok(obj)
        fm, ft = obj.Shape.Faces[0], t.Shape.Faces[0]
        u0, u1, v0, v1 = fm.ParameterRange
        target_edge = _edge_of(ft, "u0")
        gap = angle = 0.0
        for v in np.linspace(v0, v1, STATIONS):
            p = fm.Surface.value(u1, float(v))
            gap = max(gap, _dist(target_edge, p))
            pa, pb = ft.Surface.parameter(p)
            angle = max(angle, _angle(fm.normalAt(u1, float(v)), ft.normalAt(pa, pb)))
        still = max(_dist(a.Shape.Faces[0], fm.Surface.value(u0, float(v))) for v in np.linspace(v0, v1, 9))
        _note(f"match {level}: gap to the target edge (mm)", gap)
        _note(f"match {level}: opposite edge moved (mm)", still)
        if level != "G0":
            _note(f"match {level}: tangent-plane angle, Part normalAt (rad)", angle)
        check(gap <= 1e-9 and still <= 1e-9 and (level == "G0" or angle <= 1e-9),
              f"match {level}: gap {gap:.3g}, angle {angle:.3g}, opposite edge {still:.3g}")
    t.Placement = App.Placement(V(0, 0, 2), App.Rotation())    # the target moves: the match follows
    doc.recompute()
    recompute_ok(obj)
    fm = obj.Shape.Faces[0]
    u0, u1, v0, v1 = fm.ParameterRange
    gap = max(_dist(_edge_of(t.Shape.Faces[0], "u0"), fm.Surface.value(u1, float(v))) for v in np.linspace(v0, v1, 9))
    check(gap <= 1e-9, f"match after the target moved: gap {gap:.3g}")
    obj.Target = (t, "Vertex1")
    expect_error(obj, ["Target", "not an edge or a face"])


@case
def test_blend_curve():
    """A G2 bridge between the ends of two B-spline edges: its end points are the edges'
    vertices, its tangents (Part's tangentAt) along theirs and its curvature (curvatureAt)
    theirs, to 1e-9; G1 too; moving a linked edge moves the bridge; wrong links are errors."""
    doc = new_doc("blendcurve")
    from cagdwb import curves
    c1 = curves.make_bspline_curve(conversion.vectors(np.array([[0, 0, 0], [10, 8, 0], [20, 2, 3], [30, 10, 0]],
                                                               float)), 3, doc=doc)
    c2 = curves.make_bspline_curve(conversion.vectors(np.array([[50, 20, 5], [60, 12, 0], [70, 25, -2], [80, 18, 0]],
                                                               float)), 3, doc=doc)
    doc.recompute()
    obj = network.make_blend_curve((c1, "Edge1"), (c2, "Edge1"), doc=doc)
    check((obj.End1, obj.End2) == ("end", "start"), f"nearest ends {obj.End1}, {obj.End2}")
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("MaxAngle", "MaxCurvatureGap", "Converged"))

    def joints(level):
        e1, e2, br = c1.Shape.Edges[0], c2.Shape.Edges[0], obj.Shape.Edges[0]
        gap = angle = dk = 0.0
        for e, t, tb in ((e1, e1.LastParameter, br.FirstParameter), (e2, e2.FirstParameter, br.LastParameter)):
            gap = max(gap, (e.valueAt(t) - br.valueAt(tb)).Length)
            angle = max(angle, _angle(e.tangentAt(t), br.tangentAt(tb)))
            k = e.curvatureAt(t)
            dk = max(dk, abs(k - br.curvatureAt(tb)) / max(k, 1e-3))
        _note(f"blend curve {level}: end gap (mm)", gap)
        _note(f"blend curve {level}: tangent angle, Part tangentAt (rad)", angle)
        if level == "G2":
            _note("blend curve G2: relative curvature difference, Part curvatureAt", dk)
        check(gap <= 1e-9 and angle <= 1e-9 and (level == "G1" or dk <= 1e-9),
              f"{level}: gap {gap:.3g}, angle {angle:.3g}, curvature {dk:.3g}")
        for e, t, tb in ((e1, e1.LastParameter, br.FirstParameter), (e2, e2.FirstParameter, br.LastParameter)):
            check(e.tangentAt(t).dot(br.tangentAt(tb)) > 0, f"{level}: the bridge turns back at a joint")
    joints("G2")
    obj.Continuity = "G1"
    recompute_ok(obj)
    joints("G1")
    check(obj.Shape.Edges[0].Curve.Degree == 3, "G1 bridge not cubic")
    obj.Continuity = "G2"
    start = obj.Shape.Edges[0].valueAt(obj.Shape.Edges[0].FirstParameter)
    c1.Poles = c1.Poles[:-1] + [V(30, 10, 8)]                # the linked edge changes: the bridge follows
    doc.recompute()
    recompute_ok(obj)
    joints("G2")
    check((obj.Shape.Edges[0].valueAt(obj.Shape.Edges[0].FirstParameter) - start).Length > 1.0, "not followed")
    exported(obj, compare(obj))
    obj.Edge2, obj.End2 = (c1, "Edge1"), "end"               # both ends the same point
    expect_error(obj, ["End2", "coincides"])
    obj.Edge2 = (c2, "Vertex1")
    expect_error(obj, ["Edge2", "not an edge"])
    obj.Edge2, obj.End2 = (c2, "Edge1"), "start"
    recompute_ok(obj)
    automatic = (obj.UsedScale1, obj.UsedScale2)
    check(automatic != (1.0, 1.0), f"automatic scales {automatic}: the explicit (1, 1) below would test nothing")
    auto_shape = obj.Shape.copy()
    check(all("ReadOnly" in obj.getEditorMode(f"TangentScale{k}") for k in (1, 2)), "scales editable while unused")
    obj.TangentScale2 = 0.0                                  # not used while AutomaticScales is on
    recompute_ok(obj)
    obj.AutomaticScales = False
    check(not any("ReadOnly" in obj.getEditorMode(f"TangentScale{k}") for k in (1, 2)), "scales read-only")
    expect_error(obj, ["TangentScale2"])
    obj.TangentScale2 = 1.0                                  # explicit (1, 1): the chord-length legs
    recompute_ok(obj)
    e = obj.Shape.Edges[0]
    leg = (e.Curve.getPole(2) - e.Curve.getPole(1)).Length
    chord = (e.valueAt(e.LastParameter) - e.valueAt(e.FirstParameter)).Length
    check((obj.UsedScale1, obj.UsedScale2) == (1.0, 1.0) and abs(leg - chord / 5) <= 1e-9 * chord,
          f"explicit (1, 1): used {obj.UsedScale1}, {obj.UsedScale2}, first leg {leg} vs chord / 5 {chord / 5}")
    check(not obj.Shape.isPartner(auto_shape) and abs(e.Length - auto_shape.Edges[0].Length) > 1e-6,
          "explicit (1, 1) gave the automatic bridge")
    joints("G2")
    obj.AutomaticScales = True
    recompute_ok(obj)
    path = os.path.join(OUT, "blendcurve.FCStd")               # saved and reloaded: recomputes, links kept
    doc.saveAs(path)
    name, shape = obj.Name, obj.Shape.copy()
    App.closeDocument(doc.Name)
    doc = App.openDocument(path)
    obj = doc.getObject(name)
    obj.touch()
    doc.recompute()
    check(obj.isValid() and obj.Message == "ok" and obj.Proxy.__class__.__name__ == "BlendCurve", obj.Message)
    check(obj.Edge1[0].Label == "BSplineCurve" and obj.Continuity == "G2", "reloaded links or Continuity")
    e, f = obj.Shape.Edges[0], shape.Edges[0]
    check(max((e.valueAt(t) - f.valueAt(t)).Length for t in np.linspace(0, 1, 11)) <= 1e-12, "reloaded shape")


def _curvature_and_derivatives(d1, d2, d3):
    """(kappa, d kappa / ds, kappa tau) from the first three derivatives of a curve in any
    parameter (closed forms: kappa = |w| / |d1|^3 with w = d1 x d2, w' = d1 x d3,
    d kappa / dt = w.w' / (|w| |d1|^3) - 3 |w| (d1.d2) / |d1|^5, tau = w.d3 / |w|^2)."""
    d1, d2, d3 = (np.array(tuple(d), dtype=float) for d in (d1, d2, d3))
    w, v = np.cross(d1, d2), float(np.linalg.norm(d1))
    nw = float(np.linalg.norm(w))
    kappa = nw / v ** 3
    dk = (w @ np.cross(d1, d3)) / (nw * v ** 3) - 3.0 * nw * (d1 @ d2) / v ** 5
    return kappa, dk / v, kappa * float(w @ d3) / nw ** 2


def _g3_gaps(pairs, size):
    """Largest relative differences of (kappa, d kappa / ds, kappa tau) over the joints
    ``pairs`` of (derivatives of a curve, derivatives of the bridge) at the shared point,
    relative to max(|a|, |b|, floor) with floors 1 / size and 1 / size^2."""
    out = np.zeros(3)
    for da, db in pairs:
        a, b = _curvature_and_derivatives(*da), _curvature_and_derivatives(*db)
        floors = (1.0 / size, size ** -2, size ** -2)
        out = np.maximum(out, [abs(x - y) / max(abs(x), abs(y), f) for x, y, f in zip(a, b, floors)])
    return out


@case
def test_blend_curve_g3():
    """A G3 bridge (degree 7) between a B-spline object's edge and an ellipse arc (a Part
    feature turned out of its plane): at both joints the engine's continuity (G2 at
    rel_tol 1e-9) of the edges and the bridge as FreeCAD holds them, and the curvature,
    its arc-length derivative and kappa tau (closed forms from the derivatives) equal to
    1e-9 relative, from the engine's curves and from Part's own derivative1At/2At/3At
    and curvatureAt; a G2 bridge between the same ends misses d kappa / ds. An old
    document (Continuity G1/G2 only, no AutomaticScales) reloads with G3 offered and its
    scales' meaning kept."""
    from cagdwb import curves
    cagd = conversion.cagd
    doc = new_doc("blendg3")
    c1 = curves.make_bspline_curve(conversion.vectors(np.array([[0, 0, 0], [10, 8, 0], [20, 2, 3], [30, 10, 0]],
                                                               float)), 3, doc=doc)
    arc = _feature(doc, Part.ArcOfEllipse(Part.Ellipse(V(60, 20, 5), 12.0, 5.0), 2.5, 4.0).toShape(), "EllipseArc")
    arc.Placement = App.Placement(V(0, 0, 0), App.Rotation(V(1, 0.3, 0), 25), V(55, 20, 5))
    doc.recompute()
    obj = network.make_blend_curve((c1, "Edge1"), (arc, "Edge1"), doc=doc, End1="end", End2="start",
                                   Continuity="G3")
    check(obj.getEnumerationsOfProperty("Continuity") == ["G1", "G2", "G3"], "Continuity choices")
    check("G3" in obj.getDocumentationOfProperty("Continuity"), "Continuity tooltip")
    check("automatic" in obj.getDocumentationOfProperty("AutomaticScales") and
          "AutomaticScales" in obj.getDocumentationOfProperty("TangentScale1"), "scale tooltips")
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("MaxCurvatureDerivativeGap", "UsedScale1", "UsedScale2"))
    check(obj.Shape.Edges[0].Curve.Degree == 7 and obj.Converged, f"G3 bridge: {obj.Message}")

    def measure():
        e1, e2, br = c1.Shape.Edges[0], arc.Shape.Edges[0], obj.Shape.Edges[0]
        E1, E2, B = (conversion.edge_to_curve(e) for e in (e1, e2, br))
        size = max(e.BoundBox.DiagonalLength for e in (e1, e2, br))
        joints = [cagd.continuity(E1, B, rel_tol=1e-9), cagd.continuity(B, E2, rel_tol=1e-9)]
        a1, b1 = E1.domain[1], B.domain[0]
        b2, a2 = B.domain[1], E2.domain[0]
        engine = _g3_gaps([(E1.derivatives(a1, 3)[1:], B.derivatives(b1, 3)[1:]),
                           (E2.derivatives(a2, 3)[1:], B.derivatives(b2, 3)[1:])], size)

        def part(e, t):
            return e.derivative1At(t), e.derivative2At(t), e.derivative3At(t)
        ends = ((e1, e1.LastParameter, br.FirstParameter), (e2, e2.FirstParameter, br.LastParameter))
        freecad = _g3_gaps([(part(e, t), part(br, tb)) for e, t, tb in ends], size)
        kappa = max(abs(e.curvatureAt(t) - br.curvatureAt(tb)) / max(e.curvatureAt(t), 1.0 / size)
                    for e, t, tb in ends)
        return joints, engine, freecad, kappa
    joints, engine, freecad, kappa = measure()
    for what, value in (("engine continuity: tangent angle (rad)", max(j.tangent_angle for j in joints)),
                        ("engine curves: relative curvature difference", engine[0]),
                        ("engine curves: relative d kappa / ds difference", engine[1]),
                        ("engine curves: relative kappa tau difference", engine[2]),
                        ("Part derivatives: relative d kappa / ds difference", freecad[1]),
                        ("Part derivatives: relative kappa tau difference", freecad[2]),
                        ("Part curvatureAt: relative difference", kappa)):
        _note(f"blend curve G3: {what}", value)
    check(all(j.G2 for j in joints), f"engine continuity: {joints}")
    check(engine.max() <= 1e-9 and freecad.max() <= 1e-9 and kappa <= 1e-9,
          f"G3 gaps: engine {engine}, Part {freecad}, Part curvatureAt {kappa:.3g}")
    check(obj.MaxCurvatureDerivativeGap <= 1e-9, f"engine result {obj.MaxCurvatureDerivativeGap}")
    obj.Continuity = "G2"                                    # the measure separates G2 from G3
    recompute_ok(obj)
    joints, engine, freecad, kappa = measure()
    _note("blend curve G2 (for contrast): relative d kappa / ds difference, Part derivatives", freecad[1])
    check(all(j.G2 for j in joints) and kappa <= 1e-9 and min(engine[1], freecad[1]) > 1e-6,
          f"G2 bridge: d kappa / ds gaps engine {engine[1]:.3g}, Part {freecad[1]:.3g}")
    obj.Continuity = "G3"
    recompute_ok(obj)
    # an old document: Continuity G1/G2 only, no AutomaticScales nor the new results
    explicit = network.make_blend_curve((c1, "Edge1"), (arc, "Edge1"), doc=doc, End1="end", End2="start",
                                        TangentScale1=1.5, TangentScale2=0.8)
    olds = [network.make_blend_curve((c1, "Edge1"), (arc, "Edge1"), doc=doc, End1="end", End2="start"), explicit]
    for o in olds:
        for name in ("AutomaticScales", "MaxCurvatureDerivativeGap", "UsedScale1", "UsedScale2"):
            o.removeProperty(name)
        o.Continuity = ["G1", "G2"]
        o.Continuity = "G1" if o is explicit else "G2"
    path = os.path.join(OUT, "blendcurve_old.FCStd")
    doc.saveAs(path)
    names = [o.Name for o in olds]
    App.closeDocument(doc.Name)
    doc = App.openDocument(path)
    auto, explicit = (doc.getObject(n) for n in names)
    for o, level, automatic in ((auto, "G2", True), (explicit, "G1", False)):
        check(o.getEnumerationsOfProperty("Continuity") == ["G1", "G2", "G3"] and o.Continuity == level,
              f"{o.Label}: Continuity {o.Continuity} of {o.getEnumerationsOfProperty('Continuity')}")
        check(o.AutomaticScales is automatic, f"{o.Label}: AutomaticScales {o.AutomaticScales}")
        check(("ReadOnly" in o.getEditorMode("TangentScale1")) is automatic, f"{o.Label}: TangentScale1 mode")
        o.touch()
    doc.recompute()
    for o in (auto, explicit):
        recompute_ok(o)
    check((explicit.UsedScale1, explicit.UsedScale2) == (1.5, 0.8), f"explicit scales {explicit.UsedScale1}")
    check((auto.UsedScale1, auto.UsedScale2) != (1.0, 1.0), f"automatic scales {auto.UsedScale1}")
    auto.Continuity = "G3"
    recompute_ok(auto)
    check(auto.Shape.Edges[0].Curve.Degree == 7 and auto.MaxCurvatureDerivativeGap <= 1e-9, auto.Message)


@case
def test_network_selection_helpers():
    """What the commands use before making an object: a network's edges split into the
    two families; the facing box edges of two faces; a selected face edge's face and
    box edge; network.check raising the error the new object would be in."""
    doc = new_doc("netselect")
    part = conversion.surface_to_part(_patch())
    params = [0.0, 0.5, 1.0]
    profiles = [_feature(doc, part.vIso(v).toShape(), f"P{k}") for k, v in enumerate(params)]
    guides = [_feature(doc, part.uIso(u).toShape(), f"G{k}") for k, u in enumerate(params)]
    doc.recompute()
    mixed = [(guides[1], "Edge1"), (profiles[0], "Edge1"), (guides[0], "Edge1"), (profiles[2], "Edge1"),
             (guides[2], "Edge1"), (profiles[1], "Edge1")]
    first, second = network.split_network(mixed)
    check([o for o, _ in first] == [guides[1], guides[0], guides[2]] and
          [o for o, _ in second] == [profiles[0], profiles[2], profiles[1]], "network families")
    network.check("GordonSurface", Profiles=first, Guides=second)
    try:
        network.check("GordonSurface", Profiles=first[:1], Guides=second)
        raised = ""
    except conversion.cagd.CagdError as exc:
        raised = str(exc)
    check(raised.startswith("Profiles: need 2"), f"check: {raised!r}")
    try:                                             # P0, a boundary of the other family, left out
        network.check("GordonSurface", Profiles=first, Guides=second[1:])
        raised = ""
    except conversion.cagd.CagdError as exc:
        raised = str(exc)
    check(raised.startswith("Profiles[") and "(G" in raised.split(":")[0] and
          "meets Guides[1] (P1.Edge1)" in raised, f"check: {raised!r}")     # the body renamed too: P1 is now first
    a = _grid_surface(doc, 0.0, "A")
    b = _grid_surface(doc, 60.0, "B", lift=6.0)
    check(network.facing_sides(a.Shape.Faces[0], b.Shape.Faces[0]) == ("u1", "u0"), "facing sides")
    for side in network.EDGES:
        k = next(k for k, e in enumerate(a.Shape.Edges) if network.edge_side(a.Shape.Faces[0], e) == side)
        link, found = network.face_and_side(a, f"Edge{k + 1}")
        check(link == (a, "Face1") and found == side, f"face_and_side of {side}: {link}, {found}")
    line = _feature(doc, Part.makeLine(V(0, 0, 0), V(0, 0, 10)), "L")
    doc.recompute()
    try:
        network.check("Sweep", Profile=(line, "Vertex1"), Path=(line, "Edge1"))
        raised = ""
    except conversion.cagd.CagdError as exc:
        raised = str(exc)
    check(raised.startswith("Profile:") and "not an edge" in raised, f"check: {raised!r}")


def report():
    for what, value in MEASURED.items():
        print(f"     {what}: {value:.3g}")
