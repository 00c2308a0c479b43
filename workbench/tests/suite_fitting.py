"""Headless cases of the fitting objects (see headless_suite.py): Fit curve / Fit surface
from a Points object, a mesh's vertices and linked vertices, and Rebuild / Remove knots
/ Reduce degree / Fair on a linked edge or face. The oracle is Part's own distToShape:
every input point within Tolerance of the fitted edge or face, the source within the
reported Deviation of the result; each object follows its moved or edited input, and
bad input is an error naming the property."""
import math
import os

import numpy as np

import FreeCAD as App
import Mesh
import Part
import Points

from suite_support import (OUT, V, cagd, case, check, compare, curves, expect_error, exported, new_doc,
                           recompute_ok, surfaces)
from cagdwb import conversion, fitting, inspection

MEASURED = {}                  # largest values measured, printed at the end of the suite
SLACK = 1e-8                   # Part's distToShape against the engine's certified distances (mm;
                               # measured: 1.3e-9 from an interpolating fit whose MaxError is 3e-14)


def _distances(shape, P):
    """Part's distToShape of every point (N, 3) from ``shape``."""
    return np.array([shape.distToShape(Part.Vertex(V(*map(float, p))))[0] for p in P])


def _cloud(doc, P, name="Scan"):
    obj = doc.addObject("Points::Feature", name)
    kernel = Points.Points()
    kernel.addPoints([V(*map(float, p)) for p in P])
    obj.Points = kernel
    doc.recompute()
    return obj


def _stored(cloud):
    return np.array([tuple(p) for p in cloud.Points.Points])


def _wave(n=300):
    """Points along a 3-D curve of varying curvature (100 mm long or so)."""
    t = np.linspace(0.0, 1.0, n)
    return np.c_[80.0 * t, 12.0 * np.sin(7.0 * t) * (1.0 + t), 6.0 * np.cos(4.0 * t)]


def _within(obj, P, what):
    """Every point within Tolerance of the shape (Part) and Part's largest distance
    equal to the engine's MaxError (certified closest points)."""
    d = _distances(obj.Shape, P)
    MEASURED[what] = (float(d.max()), float(obj.MaxError), float(obj.Tolerance))
    check(d.max() <= obj.Tolerance + SLACK, f"{what}: a point {d.max():.3g} from the fit (Tolerance "
          f"{obj.Tolerance:g})")
    check(abs(d.max() - obj.MaxError) <= SLACK + 1e-6 * obj.MaxError,
          f"{what}: Part's largest distance {d.max():.6g} != MaxError {obj.MaxError:.6g}")
    rms = math.sqrt(float(np.mean(d * d)))
    check(abs(rms - obj.RmsError) <= SLACK + 1e-6 * obj.RmsError, f"{what}: RMS {rms:.6g} != {obj.RmsError:.6g}")
    return d


def _reloaded(obj, filename):
    """(document, object) after saving obj's document in OUT as ``filename``, closing and
    opening it again."""
    path = os.path.join(OUT, filename)
    obj.Document.saveAs(path)
    name, doc_name = obj.Name, obj.Document.Name
    App.closeDocument(doc_name)
    doc = App.openDocument(path)
    return doc, doc.getObject(name)


def _readonly(obj, names):
    for name in names:
        check("ReadOnly" in obj.getEditorMode(name), f"{obj.Label}.{name} is editable")


@case
def test_fit_curve_from_points_object():
    doc = new_doc("fitcurve")
    cloud = _cloud(doc, _wave())
    obj = fitting.make_fit_curve(cloud, doc=doc)
    recompute_ok(obj)
    check(obj.getTypeIdOfProperty("Tolerance") == "App::PropertyPrecision", "Tolerance type")
    _readonly(obj, ("MaxError", "RmsError", "Converged", "ControlPoints"))
    check(obj.Converged and 4 <= obj.ControlPoints < 300, f"converged {obj.Converged}, {obj.ControlPoints} poles")
    geom = compare(obj)
    check(len(geom.control_points) == obj.ControlPoints, "ControlPoints")
    _within(obj, _stored(cloud), "fit curve 0.01")
    few = obj.ControlPoints
    obj.Tolerance = 1e-4                                   # tighter: more control points, still within
    recompute_ok(obj)
    _within(obj, _stored(cloud), "fit curve 1e-4")
    check(obj.ControlPoints > few and abs(obj.Tolerance - 1e-4) < 1e-19, f"{obj.ControlPoints} vs {few} poles")
    # the Points object moves: the fit follows
    cloud.Placement = App.Placement(V(0, 0, 7), App.Rotation(V(0, 0, 1), 30))
    doc.recompute()
    recompute_ok(obj)
    _within(obj, _stored(cloud), "fit curve, moved points")
    check(obj.Placement.isIdentity() and obj.Proxy.claimed(obj) == [cloud], "placement or claims")
    # an unmet tolerance: the best fit, a warning, Converged False
    obj.Tolerance, obj.MaxControlPoints = 1e-6, 6
    doc.recompute()
    check(obj.isValid() and not obj.Shape.isNull(), f"unmet tolerance made an error: {obj.Message}")
    check(obj.Message.startswith("warning:") and "Tolerance" in obj.Message and "not met" in obj.Message,
          obj.Message)
    check(not obj.Converged and obj.MaxError > 1e-6 and obj.ControlPoints <= 6, f"{obj.MaxError} {obj.ControlPoints}")
    d = _distances(obj.Shape, _stored(cloud))
    check(abs(d.max() - obj.MaxError) <= 1e-6 * obj.MaxError, f"best fit MaxError {obj.MaxError} vs Part {d.max()}")
    obj.Tolerance, obj.MaxControlPoints = 0.0, 0
    expect_error(obj, ["Tolerance", "> 0"])
    check(obj.MaxError == 0.0 and not obj.Converged, "results kept after an error")
    obj.Tolerance, obj.Degree = 0.01, 0
    expect_error(obj, ["Degree"])
    obj.Degree, obj.Source = 3, None
    expect_error(obj, ["Source"])
    obj.Source = cloud
    recompute_ok(obj)
    exported(obj, compare(obj))


@case
def test_fit_curve_from_vertices_periodic_and_tangent():
    doc = new_doc("fitverts")
    angles = np.linspace(0.0, 2 * math.pi, 16, endpoint=False)
    verts = []
    for k, a in enumerate(angles):
        v = doc.addObject("Part::Vertex", f"P{k}")
        v.X, v.Y, v.Z = 20 * math.cos(a), 12 * math.sin(a), 3 * math.sin(3 * a)
        verts.append(v)
    doc.recompute()
    links = [(v, "Vertex1") for v in verts]
    obj = fitting.make_fit_curve(vertices=links, doc=doc, Tolerance=0.001, Periodic=True)
    recompute_ok(obj)
    edge = obj.Shape.Edges[0]
    check(edge.isClosed() and edge.Curve.isPeriodic(), "periodic fit not a closed periodic edge")
    P = np.array([tuple(v.Shape.Vertexes[0].Point) for v in verts])
    _within(obj, P, "periodic fit of vertices")
    verts[3].Z = 6.0                                    # a vertex moves: the fit follows
    doc.recompute()
    recompute_ok(obj)
    check(obj.Shape.Edges[0].distToShape(verts[3].Shape)[0] <= obj.Tolerance + SLACK, "fit does not follow the vertex")
    obj.StartTangent = V(0, 1, 0)
    expect_error(obj, ["StartTangent", "periodic"])
    # open, with the start tangent held
    obj.Periodic = False
    obj.StartTangent = V(0, 1, 0.2)
    recompute_ok(obj)
    edge = obj.Shape.Edges[0]
    tangent = edge.tangentAt(edge.FirstParameter)
    angle = tangent.getAngle(V(0, 1, 0.2))
    MEASURED["held start tangent angle (rad)"] = angle
    check(angle <= 1e-9, f"start tangent {tangent} not along (0, 1, 0.2): {angle:.3g} rad")
    check((edge.valueAt(edge.FirstParameter) - verts[0].Shape.Vertexes[0].Point).Length <= 1e-9, "start point")
    # the start tangent from a linked edge ending at (or near) the first point: G1 continuation
    first = verts[0].Shape.Vertexes[0].Point
    line = doc.addObject("Part::Line", "Lead")
    (line.X1, line.Y1, line.Z1), (line.X2, line.Y2, line.Z2) = (first.x - 10, first.y - 4, first.z + 2), tuple(first)
    doc.recompute()
    obj.StartEdge = (line, "Edge1")
    recompute_ok(obj)
    for what in ("line ending at the first point", "line starting there"):
        edge = obj.Shape.Edges[0]
        along = line.Shape.Edges[0].tangentAt(0.0)
        want = along if what.startswith("line ending") else -along
        angle = edge.tangentAt(edge.FirstParameter).getAngle(want)
        MEASURED[f"StartEdge tangent angle, {what} (rad)"] = angle
        check(angle <= 1e-9, f"StartEdge ({what}): the fit leaves at {angle:.3g} rad from the edge's direction")
        (line.X1, line.Y1, line.Z1), (line.X2, line.Y2, line.Z2) = tuple(first), (first.x - 10, first.y - 4,
                                                                              first.z + 2)
        doc.recompute()
        recompute_ok(obj)
    check(line not in obj.Proxy.claimed(obj), "the tangent edge is claimed")
    obj.EndEdge = (verts[1], "Vertex1")
    expect_error(obj, ["EndEdge", "not an edge"])
    obj.EndEdge = None
    obj.Periodic = True
    expect_error(obj, ["StartTangent", "periodic"])
    obj.Periodic = False
    obj.Vertices = links[:1]
    expect_error(obj, ["Vertices", "2 points"])


def _height(x, y):
    return 4.0 * np.sin(x / 9.0) * np.cos(y / 7.0) + 0.02 * x * y / 10.0


def _height_mesh(doc, n=18, size=40.0):
    """A Mesh::Feature triangulating z = _height on an n x n grid; its (n*n, 3) vertices."""
    x = np.linspace(0.0, size, n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    P = np.stack([X, Y, _height(X, Y)], -1)
    facets = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = P[i, j], P[i + 1, j], P[i + 1, j + 1], P[i, j + 1]
            facets += [[tuple(a), tuple(b), tuple(c)], [tuple(a), tuple(c), tuple(d)]]
    obj = doc.addObject("Mesh::Feature", "HeightMesh")
    obj.Mesh = Mesh.Mesh(facets)
    doc.recompute()
    return obj


@case
def test_fit_surface_from_mesh_and_grid():
    doc = new_doc("fitsurface")
    mesh = _height_mesh(doc)
    obj = fitting.make_fit_surface(mesh, doc=doc)
    recompute_ok(obj)
    _readonly(obj, ("MaxError", "RmsError", "Converged", "ControlPointsU", "ControlPointsV"))
    compare(obj)
    V_mesh = np.array([tuple(p) for p in mesh.Mesh.Topology[0]])
    check(len(V_mesh) == 18 * 18, f"{len(V_mesh)} mesh vertices")
    _within(obj, V_mesh, "fit surface, mesh (scattered)")
    check(obj.Converged and obj.ControlPointsU >= 4 and obj.ControlPointsV >= 4, f"{obj.ControlPointsU}")
    # a grid of points in a Points object, row-major: GridRows
    x, y = np.linspace(0, 40, 20), np.linspace(0, 30, 15)
    X, Y = np.meshgrid(x, y, indexing="ij")
    G = np.stack([X, Y, _height(X, Y)], -1).reshape(-1, 3)
    cloud = _cloud(doc, G, "Grid")
    obj.Source, obj.GridRows, obj.Tolerance = cloud, 20, 0.001
    recompute_ok(obj)
    _within(obj, _stored(cloud), "fit surface, 20 x 15 grid at 0.001")
    exported(obj, compare(obj))
    # the deviation map of the fit's face and its points: the same largest error
    dmap = inspection.make_deviation_map([(obj, "Face1")], cloud, doc=doc)
    doc.recompute()
    check(dmap.isValid() and dmap.Count == 300, dmap.Message)
    MEASURED["deviation map of the fit: MaxAbs vs MaxError"] = (dmap.MaxAbs, obj.MaxError)
    check(abs(dmap.MaxAbs - obj.MaxError) <= 1e-9, f"deviation map MaxAbs {dmap.MaxAbs} != MaxError {obj.MaxError}")
    doc.removeObject(dmap.Name)
    obj.MaxControlPoints = 5                              # capped: the best 5 x 5 fit and a warning
    doc.recompute()
    check(obj.isValid() and not obj.Converged and obj.Message.startswith("warning:") and
          "Tolerance" in obj.Message, obj.Message)
    check((obj.ControlPointsU, obj.ControlPointsV) == (5, 5) and obj.MaxError > obj.Tolerance,
          f"{obj.ControlPointsU} x {obj.ControlPointsV}, {obj.MaxError}")
    d = _distances(obj.Shape, _stored(cloud))
    MEASURED["fit surface capped 5 x 5 (Part, MaxError)"] = (float(d.max()), obj.MaxError)
    check(abs(d.max() - obj.MaxError) <= SLACK + 1e-6 * obj.MaxError, f"capped: Part {d.max()} vs {obj.MaxError}")
    obj.MaxControlPoints = 2
    expect_error(obj, ["MaxControlPoints"])
    obj.MaxControlPoints = 0
    obj.GridRows = 7
    expect_error(obj, ["GridRows", "300 points"])
    obj.GridRows, obj.DegreeU = 20, 0
    expect_error(obj, ["Degree"])
    obj.DegreeU = 3
    recompute_ok(obj)


@case
def test_fit_surface_auto_degree_and_an_old_document():
    """AutoDegree on a 20 x 15 grid at 9e-5: the face's degree (Part's UDegree / VDegree)
    and the read-only AchievedDegreeU/V are the engine's degree="auto" choice, 5 here
    (11 x 11 poles against 12 x 11 at degree 3; at 0.0001 the tuned cubic took 12 x 10),
    the degree of 3, 4, 5 with the fewest control points (each fitted by the engine), every
    point within Tolerance (Part's distToShape); DegreeU/V read-only while it is on and
    used again when it is off. A document saved before AutoDegree loads with it added
    (off) and the achieved degrees shown after a recompute."""
    doc = new_doc("fitsurface_auto")
    x, y = np.linspace(0, 40, 20), np.linspace(0, 30, 15)
    X, Y = np.meshgrid(x, y, indexing="ij")
    cloud = _cloud(doc, np.stack([X, Y, _height(X, Y)], -1).reshape(-1, 3), "Grid")
    P = _stored(cloud)
    obj = fitting.make_fit_surface(cloud, doc=doc, GridRows=20, Tolerance=9e-5)
    check(obj.AutoDegree is False, "AutoDegree on by default")
    obj.AutoDegree = True
    recompute_ok(obj)
    _readonly(obj, ("DegreeU", "DegreeV", "AchievedDegreeU", "AchievedDegreeV"))
    G = P.reshape(20, 15, 3)
    each = {p: cagd.fit_surface(G, 9e-5, degree=p) for p in (3, 4, 5)}
    fewest = min((f.surface.control_points[..., 0].size, p) for p, f in each.items() if f.converged)[1]
    face = obj.Shape.Faces[0].Surface
    MEASURED["fit surface AutoDegree: achieved, fewest, Part's degrees"] = (
        obj.AchievedDegreeU, fewest, face.UDegree, face.VDegree)
    check(fewest == 5 and (obj.AchievedDegreeU, obj.AchievedDegreeV) == (fewest, fewest) and
          (face.UDegree, face.VDegree) == (fewest, fewest), f"AutoDegree chose {obj.AchievedDegreeU} x "
          f"{obj.AchievedDegreeV} (Part {face.UDegree} x {face.VDegree}), the fewest poles at {fewest}")
    check((obj.ControlPointsU, obj.ControlPointsV) == each[fewest].surface.control_points.shape[:2],
          f"{obj.ControlPointsU} x {obj.ControlPointsV}")
    _within(obj, P, "fit surface, AutoDegree, 20 x 15 grid at 9e-5")
    compare(obj)
    obj.AutoDegree = False
    check("ReadOnly" not in obj.getEditorMode("DegreeU"), "DegreeU read-only with AutoDegree off")
    obj.DegreeU = obj.DegreeV = 5
    recompute_ok(obj)
    check((obj.AchievedDegreeU, obj.AchievedDegreeV) == (5, 5), f"{obj.AchievedDegreeU}")
    # an old document: no AutoDegree, no achieved degrees
    for name in ("AutoDegree", "AchievedDegreeU", "AchievedDegreeV"):
        obj.removeProperty(name)
    doc, obj = _reloaded(obj, "fitsurface_old.FCStd")
    check(hasattr(obj, "AutoDegree") and obj.AutoDegree is False and hasattr(obj, "AchievedDegreeV"),
          "old document: AutoDegree or the achieved degrees not added")
    _readonly(obj, ("AchievedDegreeU", "AchievedDegreeV"))
    obj.touch()
    recompute_ok(obj)
    check((obj.AchievedDegreeU, obj.AchievedDegreeV) == (5, 5) and obj.Converged, f"{obj.AchievedDegreeU}")
    obj.AutoDegree = True
    recompute_ok(obj)
    check(obj.AchievedDegreeU == fewest and "ReadOnly" in obj.getEditorMode("DegreeV"), "reloaded AutoDegree")
    App.closeDocument(doc.Name)


def _bspline_edge(doc, P, degree=3, knots=None, name="Source"):
    c = cagd.BSplineCurve(np.asarray(P, float), degree, knots)
    obj = curves.make_bspline_curve(conversion.vectors(c.control_points), degree,
                                    list(map(float, c.knots)), doc=doc)
    doc.recompute()
    obj.Label = name
    return obj, c


def _source_within(result, source_shape, deviation, what, samples=120):
    """Part's distance from samples of the source edge/face to the result <= Deviation."""
    if source_shape.Faces:
        f = source_shape.Faces[0]
        u0, u1, v0, v1 = f.ParameterRange
        pts = [tuple(f.Surface.value(u, v)) for u in np.linspace(u0, u1, 11) for v in np.linspace(v0, v1, 11)]
        d = _distances(result.Faces[0], np.array(pts))
    else:
        e = source_shape.Edges[0]
        pts = [tuple(e.valueAt(t)) for t in np.linspace(e.FirstParameter, e.LastParameter, samples)]
        d = _distances(result.Edges[0], np.array(pts))
    MEASURED[what] = (float(d.max()), float(deviation))
    check(d.max() <= deviation * (1 + 1e-6) + SLACK, f"{what}: the source is {d.max():.3g} from the result, "
          f"Deviation says {deviation:.3g}")
    return float(d.max())


@case
def test_rebuild_edge_and_face_follow_their_source():
    doc = new_doc("rebuild")
    circle = doc.addObject("Part::Circle", "Circle")
    circle.Radius = 10.0
    circle.Angle1, circle.Angle2 = 0.0, 270.0
    doc.recompute()
    obj = fitting.make_operation("Rebuild", (circle, "Edge1"), doc=doc, Count=8, Degree=3)
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("Deviation",))
    edge = obj.Shape.Edges[0]
    check(len(edge.Curve.getPoles()) == 8 and edge.Curve.Degree == 3 and not edge.Curve.isRational(),
          "not 8 polynomial cubic poles")
    got = _source_within(obj.Shape, circle.Shape, obj.Deviation, "rebuild circle arc, 8 poles")
    check(0 < obj.Deviation < 0.5 and got >= 0.5 * obj.Deviation, f"Deviation {obj.Deviation}, Part {got}")
    circle.Radius = 20.0                                  # the source changes: the rebuild follows
    doc.recompute()
    recompute_ok(obj)
    _source_within(obj.Shape, circle.Shape, obj.Deviation, "rebuild, radius 20")
    check(abs(obj.Shape.Edges[0].valueAt(obj.Shape.Edges[0].FirstParameter).Length - 20.0) < 1e-9, "not followed")
    obj.Count = 2
    expect_error(obj, ["Count"])
    obj.Count = 0                                         # 0: the source's own count
    recompute_ok(obj)
    # a face: a B-spline surface object's face to 6 x 5 poles
    surf = surfaces.make_bspline_surface(doc=doc)
    doc.recompute()
    obj.Source = (surf, "Face1")
    obj.Count, obj.CountV = 6, 5
    recompute_ok(obj)
    compare(obj)
    check(len(obj.Shape.Faces[0].Surface.getPoles()) == 6 and len(obj.Shape.Faces[0].Surface.getPoles()[0]) == 5,
          "not 6 x 5 poles")
    _source_within(obj.Shape, surf.Shape, obj.Deviation, "rebuild face 6 x 5")
    exported(obj, compare(obj))
    obj.Source = (surf, "Vertex1")
    expect_error(obj, ["Source", "not an edge or a face"])
    box = doc.addObject("Part::Box", "Box")
    doc.recompute()
    obj.Source = (box, "")
    expect_error(obj, ["Source", "6 faces"])
    plate = doc.addObject("Part::Feature", "Holed")
    plate.Shape = Part.makeBox(10, 10, 1).cut(Part.makeCylinder(3, 5, V(5, 5, -1)))
    doc.recompute()
    top = next(k for k, f in enumerate(plate.Shape.Faces) if abs(f.CenterOfMass.z - 1.0) < 1e-9)
    obj.Source = (plate, f"Face{top + 1}")
    expect_error(obj, ["Source", "is a trimmed face"])
    obj.Source = (box, "Face1")                          # a box's face: bounded by its parameter box
    recompute_ok(obj)
    _source_within(obj.Shape, box.Shape.Faces[0], obj.Deviation, "rebuild a box face")
    with_error = None
    try:
        fitting.check_operation("Rebuild", (plate, [f"Face{top + 1}"]))
    except cagd.CagdError as exc:
        with_error = str(exc)
    check(with_error and "trimmed face" in with_error, f"the command's check accepted a trimmed face: {with_error}")


@case
def test_remove_knots_keeps_small_tolerance():
    doc = new_doc("removeknots")
    base = cagd.BSplineCurve(np.array([[0, 0, 0], [10, 15, 2], [25, -5, 0], [40, 12, 4], [55, 0, 0], [70, 8, 1]],
                                      float), 3)
    dense = base.insert_knot(0.2).insert_knot(0.45).insert_knot(0.8, 2)
    src = curves.make_bspline_curve(conversion.vectors(dense.control_points), 3,
                                    list(map(float, dense.knots)), doc=doc)
    doc.recompute()
    obj = fitting.make_operation("RemoveKnots", (src, "Edge1"), doc=doc, Tolerance=1e-7)
    recompute_ok(obj)
    compare(obj)
    check(obj.Tolerance == 1e-7 and obj.getTypeIdOfProperty("Tolerance") == "App::PropertyPrecision",
          f"Tolerance {obj.Tolerance!r}")
    _readonly(obj, ("Deviation", "KnotsRemoved", "ErrorBound"))
    poles = len(obj.Shape.Edges[0].Curve.getPoles())
    check(obj.KnotsRemoved == 4 and poles == 6, f"{obj.KnotsRemoved} knots removed, {poles} poles (the base has 6)")
    check(obj.ErrorBound <= 1e-7 and obj.Deviation <= 1e-7, f"bound {obj.ErrorBound}, deviation {obj.Deviation}")
    _source_within(obj.Shape, src.Shape, max(obj.Deviation, 1e-12), "remove knots, exact")
    # the source is edited (a pole moved): the removal follows, inserted knots no longer all removable
    P = dense.control_points.copy()
    P[4] += [0, 0, 3.0]
    src.Poles = conversion.vectors(P)
    doc.recompute()
    recompute_ok(obj)
    check(obj.KnotsRemoved < 4, f"{obj.KnotsRemoved} knots removed after a pole moved")
    _source_within(obj.Shape, src.Shape, obj.Deviation, "remove knots after the edit")
    # saved and reloaded: Tolerance 1e-7 kept
    doc, obj = _reloaded(obj, "removeknots.FCStd")
    check(obj.Tolerance == 1e-7, f"reloaded Tolerance {obj.Tolerance!r}")
    obj.touch()
    doc.recompute()
    check(obj.isValid() and obj.Message == "ok", obj.Message)
    obj.Tolerance = -1.0                                  # PropertyPrecision clamps to 0
    expect_error(obj, ["Tolerance", "> 0"])
    obj.Tolerance = 1e-7
    # a face: a knot inserted in u comes out again
    S = cagd.BSplineSurface(np.stack(np.meshgrid(np.arange(5.0) * 10, np.arange(4.0) * 10, indexing="ij")
                                     + [np.sin(np.add.outer(np.arange(5.0), np.arange(4.0)))], -1), 3, 2)
    Sd = S.insert_knot("u", 0.3).insert_knot("v", 0.6)
    face_src = surfaces.make_bspline_surface(doc=doc)
    nu = Sd.control_points.shape[0]
    face_src.Poles = conversion.vectors(Sd.control_points.reshape(-1, 3))
    face_src.CountU, face_src.DegreeU, face_src.DegreeV = nu, 3, 2
    face_src.KnotsU, face_src.KnotsV = list(map(float, Sd.knots_u)), list(map(float, Sd.knots_v))
    doc.recompute()
    check(face_src.isValid(), face_src.Message)
    obj.Source = (face_src, "Face1")
    recompute_ok(obj)
    check(obj.KnotsRemoved == 2, f"{obj.KnotsRemoved} knots removed from the face")
    poles = obj.Shape.Faces[0].Surface.getPoles()
    check((len(poles), len(poles[0])) == (5, 4), f"face poles {len(poles)} x {len(poles[0])}")
    _source_within(obj.Shape, face_src.Shape, max(obj.Deviation, 1e-12), "remove knots, face")
    obj.Direction = "V"
    recompute_ok(obj)
    check(obj.KnotsRemoved == 1, f"V only: {obj.KnotsRemoved} knots removed")


@case
def test_reduce_degree_and_unmet_tolerance():
    doc = new_doc("reducedegree")
    quadratic = cagd.BSplineCurve(np.array([[0, 0, 0], [10, 20, 0], [30, -10, 5], [45, 10, 0], [60, 0, 3]], float), 2)
    cubic = quadratic.elevate()
    src = curves.make_bspline_curve(conversion.vectors(cubic.control_points), 3, list(map(float, cubic.knots)),
                                    doc=doc)
    doc.recompute()
    obj = fitting.make_operation("ReduceDegree", (src, "Edge1"), doc=doc, Tolerance=1e-6)
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("Deviation", "ErrorBound", "Converged"))
    check(obj.Converged and obj.Shape.Edges[0].Curve.Degree == 2, f"degree {obj.Shape.Edges[0].Curve.Degree}")
    _source_within(obj.Shape, src.Shape, max(obj.Deviation, 1e-12), "reduce elevated quadratic")
    # a real cubic: the tolerance cannot be met; the reduced curve is kept with a warning
    src.Poles = conversion.vectors(np.array([[0, 0, 0], [10, 25, 0], [20, -20, 5], [35, 20, 0], [50, -15, 2],
                                             [60, 0, 0]], float))
    src.Knots = []
    doc.recompute()
    check(obj.isValid() and not obj.Shape.isNull() and not obj.Converged, f"unmet: {obj.Message}")
    check(obj.Message.startswith("warning:") and "Tolerance" in obj.Message, obj.Message)
    check(obj.Shape.Edges[0].Curve.Degree == 2 and obj.Deviation > 1e-6, f"deviation {obj.Deviation}")
    _source_within(obj.Shape, src.Shape, obj.Deviation, "reduce real cubic (unmet)")
    line = doc.addObject("Part::Line", "Line")
    doc.recompute()
    obj.Source = (line, "Edge1")
    expect_error(obj, ["Source", "degree-1"])
    # a face: a B-spline surface elevated in v, reduced back in V
    surf = surfaces.make_bspline_surface(doc=doc)
    surf.DegreeV = 2
    doc.recompute()
    s2 = conversion.face_to_surface(surf.Shape.Faces[0]).elevate("v")
    surf.Poles = conversion.vectors(np.asarray(s2.control_points).reshape(-1, 3))
    surf.CountU, surf.DegreeV = s2.control_points.shape[0], 3
    surf.KnotsU, surf.KnotsV = list(map(float, s2.knots_u)), list(map(float, s2.knots_v))
    doc.recompute()
    check(surf.isValid(), surf.Message)
    obj.Source, obj.Direction = (surf, "Face1"), "V"
    recompute_ok(obj)
    check(obj.Converged and obj.Shape.Faces[0].Surface.VDegree == 2, "face not reduced in v")
    _source_within(obj.Shape, surf.Shape, max(obj.Deviation, 1e-12), "reduce face in v")


@case
def test_fair_curve_and_face():
    doc = new_doc("fair")
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1.0, 14)
    P = np.c_[80 * t, 10 * np.sin(3 * t), np.zeros_like(t)] + rng.normal(scale=0.4, size=(14, 3)) * [0, 1, 1]
    src, c = _bspline_edge(doc, P)
    obj = fitting.make_operation("Fair", (src, "Edge1"), doc=doc, Tolerance=0.5, Keep="G2")
    recompute_ok(obj)
    compare(obj)
    _readonly(obj, ("Deviation", "EnergyBefore", "EnergyAfter", "InflectionsBefore", "InflectionsAfter", "Converged"))
    check(obj.EnergyAfter < obj.EnergyBefore and obj.Deviation <= 0.5, f"energy {obj.EnergyBefore} -> "
          f"{obj.EnergyAfter}, deviation {obj.Deviation}")
    check(obj.InflectionsAfter <= obj.InflectionsBefore, f"inflections {obj.InflectionsBefore} -> "
          f"{obj.InflectionsAfter}")
    _source_within(obj.Shape, src.Shape, obj.Deviation, "fair curve G2")
    a, b = src.Shape.Edges[0], obj.Shape.Edges[0]
    for ta, tb in ((a.FirstParameter, b.FirstParameter), (a.LastParameter, b.LastParameter)):
        gap = (a.valueAt(ta) - b.valueAt(tb)).Length
        angle = a.tangentAt(ta).getAngle(b.tangentAt(tb))
        dk = abs(a.curvatureAt(ta) - b.curvatureAt(tb))
        MEASURED["fair G2 ends: gap, angle, curvature difference"] = (gap, angle, dk)
        check(gap <= 1e-9 and angle <= 1e-9 and dk <= 1e-9 * max(1.0, a.curvatureAt(ta)),
              f"ends not held G2: gap {gap:.3g}, angle {angle:.3g}, curvature {dk:.3g}")
    moved = c.control_points.copy()                     # the source is edited: the fairing follows
    moved[6] += [0, 3.0, 0]
    src.Poles = conversion.vectors(moved)
    energy = obj.EnergyBefore
    doc.recompute()
    recompute_ok(obj)
    check(obj.EnergyBefore != energy and obj.EnergyAfter < obj.EnergyBefore, f"energy {energy} -> {obj.EnergyBefore}")
    _source_within(obj.Shape, src.Shape, obj.Deviation, "fair curve after the source was edited")
    before = obj.EnergyAfter
    obj.Tolerance = 2.0                                   # more room: lower energy
    recompute_ok(obj)
    check(obj.EnergyAfter < before, f"energy {before} -> {obj.EnergyAfter} at a larger Tolerance")
    arc = doc.addObject("Part::Circle", "Arc")
    arc.Angle2 = 120.0
    doc.recompute()
    obj.Source = (arc, "Edge1")
    expect_error(obj, ["Source", "polynomial"])
    # a face, G1 along its four edges
    P = np.stack(np.meshgrid(np.arange(7.0) * 8, np.arange(6.0) * 8, indexing="ij") + [np.zeros((7, 6))], -1)
    P[1:-1, 1:-1, 2] += rng.normal(scale=1.0, size=(5, 4))
    surf = surfaces.make_bspline_surface(doc=doc)
    surf.Poles, surf.CountU = conversion.vectors(P.reshape(-1, 3)), 7
    doc.recompute()
    obj.Source, obj.Keep, obj.Tolerance = (surf, "Face1"), "G1", 1.0
    recompute_ok(obj)
    compare(obj)
    check(obj.EnergyAfter < obj.EnergyBefore and obj.Deviation <= 1.0, f"face energy {obj.EnergyBefore} -> "
          f"{obj.EnergyAfter}")
    _source_within(obj.Shape, surf.Shape, obj.Deviation, "fair face G1")
    fa, fb = surf.Shape.Faces[0], obj.Shape.Faces[0]
    boundary = Part.Compound(fb.Edges)
    gap = max(boundary.distToShape(Part.Vertex(ea.valueAt(ea.FirstParameter + k * (ea.LastParameter -
                                                                                 ea.FirstParameter) / 10)))[0]
              for ea in fa.Edges for k in range(11))
    MEASURED["fair face boundary gap"] = gap
    check(gap <= 1e-9, f"the faired face's boundary moved by {gap:.3g}")


def report():
    for what, value in MEASURED.items():
        print(f"     {what}: {value}")
