"""Headless cases: every parametric object type (see headless_suite.py)."""
import math

import FreeCAD as App
import numpy as np
import Part

from suite_support import (TOL, V, analysis, case, check, compare, curves, exchange, expect_error, exported,
                           new_doc, note, recompute_ok, standard, surfaces)


# --- parametric objects ---------------------------------------------------------------------
@case
def test_bezier_curve():
    doc = new_doc("bezier")
    obj = curves.make_bezier_curve(doc=doc)

    def bad(o):
        o.Weights = [1.0, 2.0]

    def fix(o):
        o.Weights = [1.0, 2.0, 0.5, 1.0]
    standard(obj, lambda o: setattr(o, "Poles", o.Poles[:-1] + [V(50, 5, 0)]), bad, ["weights"], fix)


@case
def test_bspline_curve():
    doc = new_doc("bspline")
    obj = curves.make_bspline_curve(doc=doc)

    def edit(o):
        o.Knots = [0, 0, 0, 0, 0.2, 0.7, 1, 1, 1, 1]
        o.Weights = [1, 2, 1, 0.5, 1, 1]

    def bad(o):
        o.Knots = [0, 0, 0, 0, 0.7, 0.2, 1, 1, 1, 1]

    def fix(o):
        o.Knots = []
        o.Periodic = True
    standard(obj, edit, bad, ["knots"], fix)
    obj.Degree = 0
    expect_error(obj, ["degree"])
    obj.Degree = 2
    recompute_ok(obj)
    check(obj.Shape.Edges[0].Curve.isPeriodic() and obj.Shape.Edges[0].isClosed(), "periodic curve not closed")


@case
def test_interpolation_curve_follows_vertices():
    doc = new_doc("interp")
    pts = [V(0, 0, 0), V(10, 8, 0), V(20, -3, 4), V(30, 6, 0)]
    verts = [doc.addObject("Part::Vertex", f"P{i}") for i in range(4)]
    for v, p in zip(verts, pts):
        v.X, v.Y, v.Z = p.x, p.y, p.z
    doc.recompute()
    obj = curves.make_interpolation_curve(vertices=[(v, "Vertex1") for v in verts], doc=doc)

    def edit(o):
        verts[2].Z = 12.0

    def bad(o):
        o.Degree = 4

    def fix(o):
        o.Degree = 2
    standard(obj, edit, bad, ["degree"], fix)
    edge = obj.Shape.Edges[0]
    for v in verts:
        check(edge.distToShape(v.Shape)[0] < 1e-9, f"curve misses {v.Label}")
    check(abs(obj.Points[2].z - 12.0) < 1e-12, "Points did not follow the moved vertex")


@case
def test_cubic_spline_end_conditions():
    doc = new_doc("cubic")
    obj = curves.make_cubic_spline(doc=doc)
    recompute_ok(obj)
    shapes = {}
    for kind in curves.END_CONDITIONS:
        obj.EndCondition = kind
        recompute_ok(obj)
        compare(obj)
        edge = obj.Shape.Edges[0]
        shapes[kind] = edge.valueAt(edge.FirstParameter + 1.0)
        check(edge.isClosed() == (kind == "periodic"), f"{kind}: closed is {edge.isClosed()}")
        for p in obj.Points:
            check(edge.distToShape(Part.Vertex(p))[0] < 1e-9, f"{kind}: misses {p}")
    check(len({(round(p.x, 9), round(p.y, 9), round(p.z, 9)) for p in shapes.values()}) == 4,
          "end conditions do not change the spline")
    obj.EndCondition = "virtual"
    obj.ReflectedVirtualPoints = False
    recompute_ok(obj)
    obj.EndCondition = "natural"
    standard(obj, lambda o: setattr(o, "Parametrization", "centripetal"),
             lambda o: setattr(o, "Points", [V(0, 0, 0), V(0, 0, 0), V(1, 1, 1)]), ["points"],
             lambda o: setattr(o, "Points", [V(0, 0, 0), V(10, 0, 0), V(10, 10, 3)]))


@case
def test_hermite_curve():
    doc = new_doc("hermite")
    obj = curves.make_hermite_curve(doc=doc)
    recompute_ok(obj)
    edge = obj.Shape.Edges[0]
    check((edge.valueAt(0) - obj.StartPoint).Length < 1e-12, "start point")
    check((edge.derivative1At(1) - obj.EndTangent).Length < 1e-9, "end tangent")
    standard(obj, lambda o: setattr(o, "EndTangent", V(10, 10, 10)),
             lambda o: setattr(o, "StartPoint", V(float("nan"), 0, 0)), ["p0"],
             lambda o: setattr(o, "StartPoint", V(0, 0, 0)))


@case
def test_bezier_surface():
    doc = new_doc("bezsurf")
    obj = surfaces.make_bezier_surface(doc=doc)

    def edit(o):
        P = o.Poles
        P[5] = V(P[5].x, P[5].y, 25.0)
        o.Poles = P
        o.Weights = [1.0] * 5 + [3.0] + [1.0] * 10
    standard(obj, edit, lambda o: setattr(o, "CountU", 3), ["countu"], lambda o: setattr(o, "CountU", 4))


@case
def test_bspline_surface():
    doc = new_doc("bssurf")
    obj = surfaces.make_bspline_surface(doc=doc)

    def edit(o):
        o.DegreeV = 2
        o.KnotsU = [0, 0, 0, 0, 0.3, 1, 1, 1, 1]

    def fix(o):
        o.DegreeU = 3
        o.Interpolate = True
    standard(obj, edit, lambda o: setattr(o, "DegreeU", 7), ["degree"], fix)
    face = obj.Shape.Faces[0]
    for p in obj.Poles:
        check(face.distToShape(Part.Vertex(p))[0] < 1e-7, "interpolating surface misses a point")
    obj.Interpolate, obj.PeriodicV = False, True
    recompute_ok(obj)
    compare(obj)
    check(obj.Shape.Faces[0].Surface.isVPeriodic(), "not periodic in v")


def _boundary(doc):
    """Four curve objects forming a closed loop (given in scrambled order/direction)."""
    a = curves.make_bezier_curve([V(0, 0, 0), V(10, -5, 3), V(20, 5, 0), V(30, 0, 0)], doc=doc)
    b = curves.make_bspline_curve([V(30, 0, 0), V(35, 10, 5), V(28, 20, 0), V(32, 30, 2)], doc=doc)
    c = curves.make_bezier_curve([V(32, 30, 2), V(20, 35, 6), V(0, 30, 0)], doc=doc)   # runs backwards
    d = curves.make_hermite_curve(StartPoint=V(0, 0, 0), EndPoint=V(0, 30, 0), StartTangent=V(-20, 30, 0),
                                  EndTangent=V(20, 30, 0), doc=doc)
    doc.recompute()
    return a, b, c, d


@case
def test_coons_patch_follows_edges():
    doc = new_doc("coons")
    a, b, c, d = _boundary(doc)
    obj = surfaces.make_coons([(a, "Edge1"), (c, "Edge1"), (d, "Edge1"), (b, "Edge1")], doc=doc)
    recompute_ok(obj)
    compare(obj)
    face = obj.Shape.Faces[0]
    for e in (a, b, c, d):
        mid = e.Shape.Edges[0].valueAt(sum(e.Shape.Edges[0].ParameterRange) / 2)
        check(face.distToShape(Part.Vertex(mid))[0] < 1e-7, f"patch misses the middle of {e.Label}")
    # moving the boundary objects moves the patch
    for e in (a, b, c, d):
        e.Placement = App.Placement(V(0, 0, 7), App.Rotation())
    doc.recompute()
    recompute_ok(obj)
    moved = obj.Shape.Faces[0].Surface.value(0.4, 0.6) - face.Surface.value(0.4, 0.6)
    check((moved - V(0, 0, 7)).Length < 1e-9, f"patch did not follow the edges (moved by {moved})")
    compare(obj)
    # editing one boundary curve: the patch follows it
    P = c.Poles
    P[1] = V(20, 45, 6)
    c.Poles = P
    doc.recompute()
    dy = obj.Shape.Faces[0].Surface.value(0.5, 1.0).y - face.Surface.value(0.5, 1.0).y
    check(obj.isValid() and dy > 1.0, f"patch did not follow the edit (dy {dy})")
    # open loop -> error
    P = c.Poles
    P[0] = V(40, 40, 40)
    c.Poles = P
    expect_error(obj, ["edges"])
    P[0] = V(32, 30, 2)
    c.Poles = P
    doc.recompute()
    recompute_ok(obj)
    exported(obj, compare(obj))
    obj.Edges = [(a, "Edge1"), (b, "Edge1"), (c, "Edge1")]
    expect_error(obj, ["4 edges"])


@case
def test_bezier_triangle():
    doc = new_doc("triangle")
    obj = surfaces.make_bezier_triangle(doc=doc)

    def edit(o):
        o.Weights = [1.0] * 4 + [2.0] + [1.0] * 5
    standard(obj, edit, lambda o: setattr(o, "Poles", o.Poles[:-1]), ["control_points"],
             lambda o: setattr(o, "Poles", surfaces.triangle_sample(3)))
    tri = obj.Proxy.triangle(obj)
    face = obj.Shape.Faces[0]
    for u, v in [(0.2, 0.3), (0.6, 0.1), (0.1, 0.8)]:
        p = V(*map(float, tri(u, v)))
        check(face.distToShape(Part.Vertex(p))[0] < 1e-7, "face misses a triangle point")
    check(len(obj.Proxy.control_net(obj)) == 9, "triangular net lines")


@case
def test_revolution():
    doc = new_doc("revolve")
    profile = curves.make_bspline_curve([V(5, 0, 0), V(12, 0, 5), V(4, 0, 10), V(8, 0, 15)], doc=doc)
    doc.recompute()
    obj = surfaces.make_revolution((profile, "Edge1"), doc=doc)
    recompute_ok(obj)
    face = obj.Shape.Faces[0]
    check(any(e.isSeam(face) for e in face.Edges), "a full turn has no seam edge")

    def edit(o):
        o.Angle = 120.0
        o.StartAngle = 30.0
    standard(obj, edit, lambda o: setattr(o, "AxisDirection", V(0, 0, 0)), ["axis_direction"],
             lambda o: setattr(o, "AxisDirection", V(0, 0, 1)))
    profile.Placement = App.Placement(V(3, 0, 0), App.Rotation())
    doc.recompute()
    recompute_ok(obj)
    compare(obj)


@case
def test_join_g1_g2():
    doc = new_doc("join")
    base = curves.make_bezier_curve([V(0, 0, 0), V(10, 10, 0), V(20, 10, 3), V(30, 0, 0)], doc=doc)
    src = curves.make_bezier_curve([V(35, -5, 0), V(40, -10, 0), V(50, -5, 2), V(60, 0, 0)], doc=doc)
    doc.recompute()
    obj = curves.make_join((base, "Edge1"), (src, "Edge1"), "G2", 1.5, 2.0, doc=doc)
    recompute_ok(obj)
    compare(obj)
    r = analysis.edges_continuity(base.Shape.Edges[0], obj.Shape.Edges[0], rel_tol=1e-7)
    check(r.report.G2 and not r.report.C1, f"G2 join measured {r.level}: {r.report}")
    obj.Continuity = "C2"
    recompute_ok(obj)
    r = analysis.edges_continuity(base.Shape.Edges[0], obj.Shape.Edges[0], rel_tol=1e-7)
    check(r.report.C2, f"C2 join measured {r.level}")
    obj.Continuity = "G1"
    standard(obj, lambda o: setattr(o, "Alpha", 0.5), lambda o: setattr(o, "Alpha", -1.0), ["alpha"],
             lambda o: setattr(o, "Alpha", 2.0))
    r = analysis.edges_continuity(base.Shape.Edges[0], obj.Shape.Edges[0], rel_tol=1e-7)
    check(r.report.G1 and abs(r.report.derivative_ratio - 2.0) < 1e-9, f"G1 alpha=2: {r.report}")
    base.Poles = base.Poles[:-1] + [V(30, 5, 0)]
    doc.recompute()
    r = analysis.edges_continuity(base.Shape.Edges[0], obj.Shape.Edges[0], rel_tol=1e-7)
    check(r.report.G1, "join did not follow the moved base curve")


@case
def test_analytic_and_trimmed_edges():
    """Lines of a box and a circular arc (not B-splines, trimmed) as Coons edges and
    revolution profile: the patch is the box's planar face, the revolved half circle
    a sphere (every point at the radius from the centre)."""
    doc = new_doc("analytic")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30.0, 20.0, 10.0
    arc = doc.addObject("Part::Circle", "Arc")
    arc.Radius, arc.Angle1, arc.Angle2 = 8.0, -90.0, 90.0
    arc.Placement = App.Placement(V(0, 0, 0), App.Rotation(V(1, 0, 0), 90))     # in the x-z plane
    doc.recompute()
    top = next(i for i, f in enumerate(box.Shape.Faces, 1) if abs(f.CenterOfMass.z - 10.0) < 1e-9)
    edges = [box.Shape.getElement(f"Edge{k}") for k in range(1, len(box.Shape.Edges) + 1)]
    top_edges = [f"Edge{k}" for k, e in enumerate(edges, 1)
                 if any(e.isSame(f) for f in box.Shape.Faces[top - 1].Edges)]
    coons = surfaces.make_coons([(box, s) for s in top_edges], doc=doc)
    recompute_ok(coons)
    compare(coons)
    face = coons.Shape.Faces[0]
    for u in (0.0, 0.3, 0.8):
        for v in (0.1, 0.5, 1.0):
            p = face.Surface.value(u, v)
            check(abs(p.z - 10.0) < 1e-9 and -1e-9 <= p.x <= 30 + 1e-9 and -1e-9 <= p.y <= 20 + 1e-9,
                  f"Coons of the box top leaves the face: {p}")
    check(abs(face.Area - 600.0) < 1e-6, f"area {face.Area}")
    sphere = surfaces.make_revolution((arc, "Edge1"), doc=doc)
    recompute_ok(sphere)
    compare(sphere)
    s = sphere.Shape.Faces[0].Surface
    for u in (0.05, 0.4, 0.9):
        for v in (0.0, 0.3, 0.77):
            uu = s.bounds()[0] + u * (s.bounds()[1] - s.bounds()[0])
            vv = s.bounds()[2] + v * (s.bounds()[3] - s.bounds()[2])
            check(abs(s.value(uu, vv).Length - 8.0) < 1e-9, "revolved half circle is not a sphere")
    exported(sphere, compare(sphere))


# --- analytic faces of the engine's surfaces of revolution: Part's offsets accept them ------
def _refused_as_nurbs(obj):
    """With Nurbs the face is the exact B-spline (the engine's parametrisation), which
    Part's offset refuses (the rational circle's double knots: C0 to OCCT)."""
    obj.Nurbs = True
    recompute_ok(obj)
    compare(obj)
    face = obj.Shape.Faces[0]
    check(isinstance(face.Surface, Part.BSplineSurface), f"{obj.Label}: Nurbs face is {type(face.Surface).__name__}")
    try:
        face.makeOffsetShape(0.5, 1e-7)
    except Part.OCCError:
        pass
    else:
        raise AssertionError(f"{obj.Label}: OCCT offset the NURBS form (expected it to refuse the C0 knots)")
    obj.Nurbs = False
    recompute_ok(obj)


def _angle_relation(obj):
    """The face's surface at analytic_parameters(u, v) is the engine's S(u, v)."""
    geom = obj.Proxy.build(obj)
    (u0, u1), (v0, v1) = geom.domain
    u, v = np.meshgrid(np.linspace(u0, u1, 7), np.linspace(v0, v1, 9), indexing="ij")
    U, W = geom.analytic_parameters(u.ravel(), v.ravel())
    surface = obj.Shape.Faces[0].Surface
    got = np.array([tuple(surface.value(float(a), float(b))) for a, b in zip(U, W)])
    dev = note("freecad", exchange.relative_deviation(geom(u.ravel(), v.ravel()), got), obj.Label)
    check(dev <= TOL, f"{obj.Label}: the angle relation is off by {dev:.3g}")


@case
def test_primitives_are_analytic_and_thicken():
    """Sphere, torus, cylinder and cone objects hold Part.Sphere / Toroid / Cylinder /
    Cone faces equal to the engine surface (compare: the angle relation), through the
    edit / bad value / STEP and IGES cycle; Part's offset thickens them: the sphere's
    and torus's walls (offset face, the solid between) 4/3 pi ((r+t)^3 - r^3) and
    2 pi^2 R ((r+t)^2 - r^2), the cylinder's tube (Offset with fill) and cup (Part
    Thickness of the capped cylinder, top removed), 1e-6 relative."""
    doc = new_doc("primitives")
    r, t, R, h = 8.0, 0.5, 20.0, 30.0
    kinds = {"Sphere": Part.Sphere, "Torus": Part.Toroid, "Cylinder": Part.Cylinder, "Cone": Part.Cone}
    objs = {}
    for kind, part_type in kinds.items():
        obj = surfaces.make_primitive(kind, doc=doc, Radius=R if kind == "Torus" else r, MinorRadius=r, Height=h)
        standard(obj, lambda o: setattr(o, "Radius", o.Radius * 1.5), lambda o: setattr(o, "Radius", 0.0),
                 ["radius"], lambda o: setattr(o, "Radius", R if kind == "Torus" else r))
        face = obj.Shape.Faces[0]
        check(isinstance(face.Surface, part_type), f"{kind}: face on {type(face.Surface).__name__}")
        check(len(obj.Proxy.control_net(obj)) > 0, f"{kind}: no control net (the engine's NURBS net)")
        _angle_relation(obj)
        objs[kind] = obj
    _refused_as_nurbs(objs["Sphere"])
    for kind, closed_form in (("Sphere", 4 / 3 * math.pi * ((r + t) ** 3 - r ** 3)),
                              ("Torus", 2 * math.pi ** 2 * R * ((r + t) ** 2 - r ** 2))):
        face = objs[kind].Shape.Faces[0]
        outer = face.makeOffsetShape(t, 1e-7)
        check(isinstance(outer.Faces[0].Surface, kinds[kind]), f"{kind}: offset is {outer.Faces[0].Surface}")
        wall = Part.Solid(Part.Shell(outer.Faces)).cut(Part.Solid(Part.Shell([face])))
        check(wall.isValid() and len(wall.Solids) == 1, f"{kind}: wall not a valid solid")
        check(abs(wall.Volume - closed_form) <= 1e-6 * closed_form, f"{kind} wall: {wall.Volume} != {closed_form}")
    side = objs["Cylinder"].Shape.Faces[0]
    tube = side.makeOffsetShape(t, 1e-7, fill=True)
    exact = math.pi * ((r + t) ** 2 - r ** 2) * h
    check(tube.isValid() and abs(tube.Volume - exact) <= 1e-6 * exact, f"tube: {tube.Volume} != {exact}")
    caps = [Part.Face(Part.Wire([e])) for e in side.Edges if isinstance(e.Curve, Part.Circle)]
    closed = Part.Solid(Part.Shell([side] + caps))
    closed.fix(1e-7, 1e-7, 1e-7)                         # the caps' orientation
    check(closed.isValid() and abs(closed.Volume - math.pi * r * r * h) <= 1e-9 * closed.Volume, "capped cylinder")
    holder = doc.addObject("Part::Feature", "Capped")
    holder.Shape = closed
    top = next(f"Face{i}" for i, f in enumerate(closed.Faces, 1)
               if isinstance(f.Surface, Part.Plane) and abs(f.CenterOfMass.z - h) < 1e-9)
    cup = doc.addObject("Part::Thickness", "Cup")
    cup.Faces, cup.Value = (holder, [top]), -t
    doc.recompute()
    exact = math.pi * (r * r * h - (r - t) ** 2 * (h - t))
    check(cup.isValid() and cup.Shape.isValid(), f"Part Thickness failed: {cup.getStatusString()}")
    check(abs(cup.Shape.Volume - exact) <= 1e-6 * exact, f"cup: {cup.Shape.Volume} != {exact}")


@case
def test_revolution_face_thickens():
    """A Revolution holds Part.SurfaceOfRevolution of the profile's exact B-spline;
    the revolved segment parallel to the axis (a cylinder wall, its normal towards the
    axis: the profile runs along it) thickens by Part's Offset with fill into the tube
    pi (r^2 - (r - t)^2) h; the NURBS form is refused."""
    doc = new_doc("revolution_offset")
    r, h, t = 5.0, 10.0, 0.5
    profile = curves.make_bspline_curve([V(r, 0, 0), V(r, 0, h)], degree=1, doc=doc)
    doc.recompute()
    obj = surfaces.make_revolution((profile, "Edge1"), doc=doc)
    recompute_ok(obj)
    compare(obj)
    _angle_relation(obj)
    face = obj.Shape.Faces[0]
    check(isinstance(face.Surface, Part.SurfaceOfRevolution), f"revolution face on {type(face.Surface).__name__}")
    tube = face.makeOffsetShape(t, 1e-7, fill=True)
    exact = math.pi * (r ** 2 - (r - t) ** 2) * h
    check(tube.isValid() and abs(tube.Volume - exact) <= 1e-6 * exact, f"tube: {tube.Volume} != {exact}")
    _refused_as_nurbs(obj)


# --- review fixes: links and placement, error messages, Coons loop --------------------------
def _points_objects(doc, pts):
    verts = [doc.addObject("Part::Vertex", f"P{i}") for i in range(len(pts))]
    for v, p in zip(verts, pts):
        v.X, v.Y, v.Z = p.x, p.y, p.z
    doc.recompute()
    return verts


def _on_vertices(obj, verts):
    edge = obj.Shape.Edges[0]
    for v in verts:
        d = edge.distToShape(v.Shape)[0]
        check(d < 1e-9, f"{obj.Label} misses {v.Label} by {d:.3g} (placement {obj.Placement})")


@case
def test_linked_objects_lie_on_their_links_whatever_the_placement():
    """Objects fed by links (vertices, edges) keep an identity, read-only Placement:
    their shape lies on the linked geometry (like Part Loft); unlinked objects keep
    an editable Placement that moves them."""
    doc = new_doc("placement")
    pts = [V(0, 0, 0), V(10, 8, 0), V(20, -3, 4), V(30, 6, 0)]
    verts = _points_objects(doc, pts)
    obj = curves.make_interpolation_curve(vertices=[(v, "Vertex1") for v in verts], doc=doc)
    recompute_ok(obj)
    check("ReadOnly" in obj.getEditorMode("Placement"), f"Placement editor mode {obj.getEditorMode('Placement')}")
    obj.Placement = App.Placement(V(0, 0, 50), App.Rotation(V(1, 0, 0), 30))
    doc.recompute()
    recompute_ok(obj)
    check(obj.Placement.isIdentity(), f"linked curve kept Placement {obj.Placement}")
    check((obj.Shape.Edges[0].Vertexes[0].Point - pts[0]).Length < 1e-9, "curve does not start at P0")
    _on_vertices(obj, verts)
    check(obj.Proxy.claimed(obj) == verts and obj.Proxy.consumed(obj) == verts, "claimed/consumed vertices")
    # unlinked: the Placement is the object's own again and moves it
    obj.Vertices = []
    check("ReadOnly" not in obj.getEditorMode("Placement"), "unlinked Placement still read-only")
    obj.Placement = App.Placement(V(0, 0, 50), App.Rotation())
    doc.recompute()
    recompute_ok(obj)
    start = obj.Shape.Edges[0].Vertexes[0].Point
    check((start - (pts[0] + V(0, 0, 50))).Length < 1e-9, f"unlinked curve not placed: starts at {start}")
    check(obj.Proxy.claimed(obj) == [], "unlinked curve claims objects")
    # a Coons patch on a box's top edges: on the box whatever its Placement; the box is
    # claimed but not consumed (it is more than the edges)
    box = doc.addObject("Part::Box", "Box")
    doc.recompute()
    top = [f"Edge{k}" for k, e in enumerate(box.Shape.Edges, 1)
           if abs(e.Vertexes[0].Point.z - 10) < 1e-9 and abs(e.Vertexes[-1].Point.z - 10) < 1e-9]
    coons = surfaces.make_coons([(box, s) for s in top], doc=doc)
    coons.Placement = App.Placement(V(0, 0, 50), App.Rotation())
    recompute_ok(coons)
    bb = coons.Shape.BoundBox
    check(abs(bb.ZMin - 10) < 1e-9 and abs(bb.ZMax - 10) < 1e-9, f"Coons patch left the box top: {bb}")
    check(coons.Proxy.claimed(coons) == [box] and coons.Proxy.consumed(coons) == [], "Coons claims")
    # revolution and join follow their links too; the join claims only Source
    profile = curves.make_bspline_curve([V(5, 0, 0), V(12, 0, 5), V(4, 0, 10), V(8, 0, 15)], doc=doc)
    src = curves.make_bezier_curve([V(35, -5, 0), V(40, -10, 0), V(50, -5, 2), V(60, 0, 0)], doc=doc)
    doc.recompute()
    rev = surfaces.make_revolution((profile, "Edge1"), doc=doc)
    join = curves.make_join((profile, "Edge1"), (src, "Edge1"), doc=doc)
    for o in (rev, join):
        o.Placement = App.Placement(V(0, 0, 50), App.Rotation())
        recompute_ok(o)
        check(o.Placement.isIdentity() and "ReadOnly" in o.getEditorMode("Placement"), f"{o.Label} Placement")
    check(rev.Shape.distToShape(Part.Vertex(V(5, 0, 0)))[0] < 1e-9, "revolution left its profile")
    end = profile.Shape.Edges[0].Vertexes[-1].Point
    check(join.Shape.distToShape(Part.Vertex(end))[0] < 1e-9, "join left the end of Base")
    check(rev.Proxy.claimed(rev) == [profile] and join.Proxy.claimed(join) == [src], "revolution/join claims")


@case
def test_error_messages_name_the_property():
    doc = new_doc("errors")
    profile = curves.make_bspline_curve([V(5, 0, 0), V(12, 0, 5), V(4, 0, 10), V(8, 0, 15)], doc=doc)
    doc.recompute()
    rev = surfaces.make_revolution((profile, "Edge1"), doc=doc)
    recompute_ok(rev)
    rev.Profile = (profile, ["Edge5"])
    expect_error(rev, ["Profile:", "Edge5"])
    rev.Profile = (profile, ["Edge1"])
    recompute_ok(rev)
    verts = _points_objects(doc, [V(0, 0, 0), V(10, 8, 0), V(20, -3, 4)])
    interp = curves.make_interpolation_curve(vertices=[(v, "Vertex1") for v in verts], degree=2, doc=doc)
    recompute_ok(interp)
    interp.Vertices = [(verts[0], "Vertex1"), (verts[1], "Vertex3"), (verts[2], "Vertex1")]
    expect_error(interp, ["Vertices:", "Vertex3"])
    # Coons tolerance must be positive
    a = curves.make_bezier_curve([V(0, 0, 0), V(10, 0, 0)], doc=doc)
    b = curves.make_bezier_curve([V(10, 0, 0), V(10, 10, 0)], doc=doc)
    c = curves.make_bezier_curve([V(10, 10, 0), V(0, 10, 0)], doc=doc)
    d = curves.make_bezier_curve([V(0, 10, 0), V(0, 0, 0)], doc=doc)
    doc.recompute()
    coons = surfaces.make_coons([(o, "Edge1") for o in (a, b, c, d)], doc=doc)
    recompute_ok(coons)
    for bad in (-1e-7, 0.0, float("nan")):
        coons.Tolerance = bad
        expect_error(coons, ["Tolerance: must be > 0"])
    coons.Tolerance = 1e-7
    recompute_ok(coons)
    # all poles in one point: an error, for curves and surfaces
    p = V(1, 2, 3)
    for obj, kind in ((curves.make_bezier_curve([p] * 4, doc=doc), "curve"),
                      (curves.make_bspline_curve([p] * 6, doc=doc), "curve"),
                      (surfaces.make_bezier_surface([p] * 16, 4, doc=doc), "surface"),
                      (surfaces.make_bspline_surface([p] * 25, 5, doc=doc), "surface"),
                      (surfaces.make_bezier_triangle([p] * 10, doc=doc), "surface")):
        expect_error(obj, ["Poles: all poles coincide", f"the {kind} is a point"])
    weighted = curves.make_bezier_curve([p] * 3, [1.0, 3.0, 1.0], doc=doc)
    expect_error(weighted, ["Poles: all poles coincide"])
    nearly = curves.make_bezier_curve([p, p + V(1e-6, 0, 0), p], doc=doc)
    recompute_ok(nearly)                      # a tiny curve is still a curve


@case
def test_coons_loop_any_order_and_direction():
    """The engine's CoonsPatch.from_loop orders the edges: every order and direction
    of the same loop gives a patch through all four edges, equal to the engine's."""
    doc = new_doc("coonsloop")
    edges = list(_boundary(doc))
    import itertools
    for order in itertools.permutations(range(4)):
        if order[0] != 0 and order not in ((2, 1, 3, 0), (3, 2, 0, 1)):
            continue                         # every order with edge a first, and two others
        obj = surfaces.make_coons([(edges[k], "Edge1") for k in order], doc=doc)
        recompute_ok(obj)
        compare(obj)
        face = obj.Shape.Faces[0]
        for e in edges:
            ed = e.Shape.Edges[0]
            for t in (0.25, 0.5, 0.75):
                q = ed.valueAt(ed.FirstParameter + t * (ed.LastParameter - ed.FirstParameter))
                check(face.distToShape(Part.Vertex(q))[0] < 1e-7, f"order {order}: patch misses {e.Label}")
        doc.removeObject(obj.Name)
