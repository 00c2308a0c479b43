"""Headless cases of the query objects (see headless_suite.py): the intersection curve
of two faces and the deviation map, against analytic oracles (a cylinder cut by a
tilted plane is an ellipse; points offset along a sphere's radius by known amounts)
and against OCCT's own section (Part ``section``)."""
import math
import os

import numpy as np

import FreeCAD as App
import Part
import Points

from suite_support import OUT, V, case, check, expect_error, new_doc, recompute_ok, surfaces
from cagdwb import inspection

MEASURED = {}                  # printed at the end of each case (largest values measured)


def _edge_points(shape, n=60):
    """Points along every edge of ``shape`` ((N, 3), n per edge)."""
    pts = []
    for e in shape.Edges:
        t0, t1 = e.ParameterRange
        pts += [tuple(e.valueAt(t)) for t in np.linspace(t0, t1, n)]
    return np.array(pts)


def _cylinder_and_plane(doc, angle=30.0, height=10.0):
    """A Part.makeCylinder (r 5, h 20) and a 40 x 40 plane face tilted by ``angle``
    about x through (0, 0, height); returns the objects, the cylinder face's name and
    the plane's (origin, unit normal) for the analytic oracle."""
    cyl = doc.addObject("Part::Feature", "Cylinder")
    cyl.Shape = Part.makeCylinder(5.0, 20.0)
    name = next(f"Face{k + 1}" for k, f in enumerate(cyl.Shape.Faces) if "Cylinder" in f.Surface.TypeId)
    plane = doc.addObject("Part::Feature", "TiltedPlane")
    shape = Part.makePlane(40.0, 40.0, V(-20, -20, 0))
    shape.rotate(V(0, 0, 0), V(1, 0, 0), angle)
    shape.translate(V(0, 0, height))
    plane.Shape = shape
    doc.recompute()
    a = math.radians(angle)
    return cyl, name, plane, np.array([0.0, 0.0, height]), np.array([0.0, -math.sin(a), math.cos(a)])


def _on_cylinder_and_plane(obj, origin, normal, tol, what):
    P = _edge_points(obj.Shape)
    on_cyl = np.abs(np.hypot(P[:, 0], P[:, 1]) - 5.0).max()
    on_plane = np.abs((P - origin) @ normal).max()
    MEASURED[what] = max(on_cyl, on_plane)
    check(on_cyl <= tol and on_plane <= tol, f"{what}: off the cylinder by {on_cyl:.3g}, off the plane by "
          f"{on_plane:.3g} (Tolerance {tol:g})")
    return P


@case
def test_intersection_cylinder_tilted_plane_is_an_ellipse():
    doc = new_doc("intersect")
    cyl, face, plane, origin, normal = _cylinder_and_plane(doc)
    obj = inspection.make_intersection((cyl, face), (plane, "Face1"), doc=doc)
    recompute_ok(obj)
    tol = obj.Tolerance
    check(tol == 1e-7, f"default Tolerance {tol}")
    check(obj.BranchCount == 1 and obj.ClosedBranches == 1 and len(obj.Shape.Edges) == 1,
          f"branches {obj.BranchCount}, closed {obj.ClosedBranches}, edges {len(obj.Shape.Edges)}")
    edge = obj.Shape.Edges[0]
    check(edge.isClosed() and isinstance(edge.Curve, Part.BSplineCurve), "branch not a closed B-spline edge")
    check(0.0 < obj.AchievedTolerance <= tol, f"AchievedTolerance {obj.AchievedTolerance}")
    check("ReadOnly" in obj.getEditorMode("AchievedTolerance"), "AchievedTolerance editable")
    _on_cylinder_and_plane(obj, origin, normal, tol, "ellipse")
    # the ellipse: semi-axes 5 and 5 / cos 30 deg; its perimeter by dense quadrature
    a, b = 5.0 / math.cos(math.radians(30.0)), 5.0
    t = np.linspace(0.0, 2 * math.pi, 200001)
    perimeter = np.trapz(np.hypot(a * np.sin(t), b * np.cos(t)), t)
    check(abs(edge.Length - perimeter) <= 1e-6 * perimeter, f"length {edge.Length} != ellipse {perimeter}")
    # OCCT's own section of the two faces lies on the curve
    section = cyl.Shape.getElement(face).section(plane.Shape.Faces[0])
    gap = max(edge.distToShape(Part.Vertex(V(*p)))[0] for p in _edge_points(section, 20))
    MEASURED["ellipse vs OCCT section"] = gap
    check(gap <= 1e-6, f"OCCT's section is {gap:.3g} away from the curve")
    check(obj.Proxy.claimed(obj) == [] and obj.Placement.isIdentity(), "claims or placement")


@case
def test_intersection_follows_moved_input_and_reports_empty():
    doc = new_doc("intersectmove")
    cyl, face, plane, origin, normal = _cylinder_and_plane(doc)
    obj = inspection.make_intersection((cyl, face), (plane, "Face1"), doc=doc)
    recompute_ok(obj)
    base = plane.Placement                        # the tilt (the shape's own placement)
    plane.Placement = App.Placement(V(0, 0, 4), App.Rotation()).multiply(base)
    doc.recompute()
    check(obj.isValid() and obj.Message == "ok", f"after the move: {obj.Message}")
    P = _on_cylinder_and_plane(obj, origin + np.array([0, 0, 4.0]), normal, obj.Tolerance, "moved ellipse")
    check(abs(P[:, 2].mean() - 14.0) < 0.5, f"curve did not follow the plane (mean z {P[:, 2].mean()})")
    cyl.Placement = App.Placement(V(0, 0, 0), App.Rotation(V(0, 0, 1), 40))   # about its axis: same ellipse
    doc.recompute()
    check(obj.isValid() and obj.BranchCount == 1, f"after rotating the cylinder: {obj.Message}")
    plane.Placement = App.Placement(V(0, 0, 100), App.Rotation()).multiply(base)
    doc.recompute()
    check(obj.isValid(), f"no intersection made an error: {obj.getStatusString()}")
    check(obj.Shape.isNull() and obj.BranchCount == 0 and obj.AchievedTolerance == 0.0, "stale shape")
    check(obj.Message.startswith("warning:") and "do not intersect" in obj.Message, obj.Message)
    plane.Placement = base
    doc.recompute()
    recompute_ok(obj)
    check(obj.BranchCount == 1, "not back after moving the plane back")


@case
def test_intersection_bad_links_and_tolerance():
    doc = new_doc("intersectbad")
    cyl, face, plane, _, _ = _cylinder_and_plane(doc)
    obj = inspection.make_intersection((cyl, face), (plane, "Face1"), doc=doc)
    recompute_ok(obj)
    obj.Tool = (cyl, "Edge1")
    expect_error(obj, ["Tool", "not a face"])
    obj.Tool = (plane, "Face7")
    expect_error(obj, ["Tool", "has no Face7"])
    obj.Tool = (plane, "Face1")
    obj.Base = None
    expect_error(obj, ["Base", "no face linked"])
    obj.Base = (cyl, face)
    obj.Tolerance = 0.0
    expect_error(obj, ["Tolerance", "> 0"])
    check(obj.BranchCount == 0, "BranchCount kept after an error")
    obj.Tolerance = 1e-6
    recompute_ok(obj)
    check(obj.AchievedTolerance <= 1e-6, f"AchievedTolerance {obj.AchievedTolerance}")


@case
def test_intersection_engine_face_with_native_sphere():
    """An engine B-spline surface object against a native Part sphere: one closed
    loop on both (the sphere analytically, the B-spline face by OCCT's projection),
    and OCCT's section of the same faces lies on it."""
    doc = new_doc("intersectnative")
    surf = surfaces.make_bspline_surface(doc=doc)
    sphere = doc.addObject("Part::Sphere", "Sphere")
    sphere.Radius = 12.0
    sphere.Placement = App.Placement(V(20, 20, 0), App.Rotation())
    doc.recompute()
    obj = inspection.make_intersection((surf, "Face1"), (sphere, "Face1"), doc=doc)
    recompute_ok(obj)
    check(obj.BranchCount >= 1 and obj.AchievedTolerance <= obj.Tolerance, f"{obj.BranchCount} branches")
    P = _edge_points(obj.Shape)
    on_sphere = np.abs(np.linalg.norm(P - np.array([20.0, 20.0, 0.0]), axis=1) - 12.0).max()
    s = surf.Shape.Faces[0].Surface
    on_surface = max((s.value(*s.parameter(V(*p))) - V(*p)).Length for p in P)
    MEASURED["B-spline x sphere"] = max(on_sphere, on_surface)
    check(on_sphere <= obj.Tolerance and on_surface <= obj.Tolerance,
          f"off the sphere by {on_sphere:.3g}, off the surface by {on_surface:.3g}")
    # OCCT's section of the same faces: approximated within its edges' tolerance
    # (measured ~3e-5: its points are that far off the sphere), so it must lie on our
    # curve within that tolerance, and have the same length
    section = surf.Shape.Faces[0].section(sphere.Shape.Faces[0])
    Q = _edge_points(section, 20)
    occt_tol = max(e.Tolerance for e in section.Edges)
    gap = max(obj.Shape.distToShape(Part.Vertex(V(*p)))[0] for p in Q)
    MEASURED["B-spline x sphere vs OCCT section"] = gap
    MEASURED["OCCT section off the sphere"] = np.abs(np.linalg.norm(Q - np.array([20.0, 20.0, 0.0]), axis=1)
                                                     - 12.0).max()
    check(gap <= occt_tol + obj.Tolerance, f"OCCT's section is {gap:.3g} away from the curve (its tolerance "
          f"{occt_tol:.3g})")
    length = sum(e.Length for e in section.Edges)
    check(abs(obj.Shape.Length - length) <= 1e-6 * length, f"length {obj.Shape.Length} != OCCT's {length}")


# --- deviation map --------------------------------------------------------------------------
def _sphere_cloud(n=240, seed=11):
    """Directions and known signed offsets (a few exactly 0)."""
    rng = np.random.default_rng(seed)
    dirs = rng.normal(size=(n, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    d = rng.uniform(-0.4, 0.6, n)
    d[:5] = 0.0
    return dirs, d


def _stats_match(obj, d, what):
    """The object's statistics and distances against the known offsets d."""
    expected = {"Max": d.max(), "Min": d.min(), "Mean": d.mean(), "RMS": math.sqrt(np.mean(d * d)),
                "MaxAbs": np.abs(d).max()}
    err = max(abs(getattr(obj, k) - v) for k, v in expected.items())
    err = max(err, float(np.abs(np.array(obj.Distances) - d).max()))
    MEASURED[what] = err
    check(obj.Count == len(d) and len(obj.Coordinates) == len(d), f"{what}: Count {obj.Count}")
    check(err <= 1e-9, f"{what}: statistics deviate by {err:.3g} from the known offsets")


@case
def test_deviation_map_sphere_csv_and_points():
    doc = new_doc("deviation")
    center, R = np.array([3.0, -4.0, 5.0]), 10.0
    sphere = doc.addObject("Part::Sphere", "Sphere")
    sphere.Radius = R
    sphere.Placement = App.Placement(V(*center), App.Rotation(V(1, 1, 0), 25))
    doc.recompute()
    dirs, d = _sphere_cloud()
    X = center + dirs * (R + d)[:, None]
    path = os.path.join(OUT, "sphere_points.csv")
    with open(path, "w", encoding="utf-8") as f:
        f.write("x,y,z\n" + "".join(f"{x:.17g},{y:.17g},{z:.17g}\n" for x, y, z in X))
    obj = inspection.make_deviation_map([(sphere, "Face1")], csv_file=path, doc=doc)
    doc.recompute()
    check(obj.isValid() and obj.Message == "ok", f"CSV deviation map: {obj.Message}")
    _stats_match(obj, d, "deviation, CSV")
    check(obj.Max > 0.5 and obj.Min < -0.3, "signs: outward offsets must be positive")
    # the same points as a Points object (FreeCAD stores single precision: the oracle
    # is the stored points' own distance from the sphere)
    cloud = doc.addObject("Points::Feature", "Cloud")
    kernel = Points.Points()
    kernel.addPoints([V(*p) for p in X])
    cloud.Points = kernel
    doc.recompute()
    obj.Points = cloud
    doc.recompute()
    check(obj.isValid(), f"Points deviation map: {obj.Message}")
    stored = np.array([tuple(p) for p in cloud.Points.Points])
    _stats_match(obj, np.linalg.norm(stored - center, axis=1) - R, "deviation, Points object")
    check(obj.Proxy.claimed(obj) == [cloud], "the points object is not claimed")
    # the points object moves: the map follows
    cloud.Placement = App.Placement(V(0, 0, 0.25), App.Rotation())
    doc.recompute()
    moved = np.array([tuple(p) for p in cloud.Points.Points])
    check(abs(moved[:, 2].mean() - stored[:, 2].mean() - 0.25) < 1e-5, "Points placement not applied")
    _stats_match(obj, np.linalg.norm(moved - center, axis=1) - R, "deviation, moved Points")


@case
def test_deviation_map_reversed_face_and_errors():
    doc = new_doc("deviationbad")
    R = 6.0
    dirs, d = _sphere_cloud(60, 3)
    X = dirs * (R + d)[:, None]
    path = os.path.join(OUT, "small_sphere.csv")
    np.savetxt(path, X, delimiter=",", fmt="%.17g")
    inside_out = doc.addObject("Part::Feature", "Reversed")
    inside_out.Shape = Part.makeSphere(R).Faces[0].reversed()
    doc.recompute()
    obj = inspection.make_deviation_map([(inside_out, "Face1")], csv_file=path, doc=doc)
    doc.recompute()
    check(obj.isValid(), obj.Message)
    _stats_match(obj, -d, "deviation, reversed face")
    obj.CsvFile = os.path.join(OUT, "no_such_file.csv")
    doc.recompute()
    check(not obj.isValid() and "csvfile" in obj.Message.lower() and obj.Count == 0, obj.Message)
    obj.CsvFile = ""
    doc.recompute()
    check(not obj.isValid() and "Points: link" in obj.Message, obj.Message)
    obj.CsvFile = path
    obj.Faces = []
    doc.recompute()
    check(not obj.isValid() and "Faces: no face" in obj.Message and obj.Distances == [], obj.Message)
    obj.Faces = [(inside_out, "Face1")]
    doc.recompute()
    check(obj.isValid() and obj.Message == "ok", obj.Message)
    saved = os.path.join(OUT, "deviation.FCStd")             # saved and reloaded: recomputes the same
    doc.saveAs(saved)
    name = obj.Name
    App.closeDocument(doc.Name)
    doc = App.openDocument(saved)
    obj = doc.getObject(name)
    obj.touch()
    doc.recompute()
    check(obj.isValid() and type(obj.Proxy).__name__ == "DeviationMap", f"reloaded: {obj.Message}")
    _stats_match(obj, -d, "deviation, reloaded")
    colors = inspection.colormap([-2.0, -1.0, 0.0, 1.0, 5.0], 1.0)
    check(np.allclose(colors, [[0, 0, 1], [0, 0, 1], [0, 0.85, 0], [1, 0, 0], [1, 0, 0]]), f"colours {colors}")


# --- trimmed faces (issue 15) -----------------------------------------------------------
def _holed_plate(doc, r=2.0):
    """A 10 x 10 x 1 plate with a hole of radius r through (5, 5); its top face (z = 1)."""
    plate = doc.addObject("Part::Feature", "HoledPlate")
    plate.Shape = Part.makeBox(10, 10, 1).cut(Part.makeCylinder(r, 5, V(5, 5, -1)))
    doc.recompute()
    k = next(i for i, f in enumerate(plate.Shape.Faces)
             if len(f.Wires) == 2 and abs(f.CenterOfMass.z - 1.0) < 1e-9)
    return plate, f"Face{k + 1}"


@case
def test_face_to_trimmed_keeps_the_faces_trim():
    """conversion.face_to_trimmed: a holed plate's face is a TrimmedSurface of the
    face's area (Part's Area), not its 10 x 10 box; the hole's centre is outside; a
    face bounded by its parameter box stays the untrimmed surface; a disk cut from a
    B-spline plane by a circle has area pi r^2."""
    from cagdwb import conversion
    doc = new_doc("trimmed")
    plate, name = _holed_plate(doc)
    face = plate.Shape.getElement(name)
    ts, why = conversion.face_to_trimmed(face)
    check(why is None and type(ts).__name__ == "TrimmedSurface", f"holed plate: {type(ts).__name__}, {why}")
    rel = abs(ts.area() - face.Area) / face.Area
    MEASURED["trimmed plate area"] = rel
    check(rel <= 1e-9, f"holed plate: area {ts.area():.15g} against Part's {face.Area:.15g}")
    centre = face.Surface.parameter(V(5, 5, 1))
    corner = face.Surface.parameter(V(0.5, 0.5, 1))
    inside = ts.contains(np.array([centre[0], corner[0]]), np.array([centre[1], corner[1]]))
    check(list(np.asarray(inside, dtype=bool)) == [False, True], f"contains: hole, corner -> {inside}")
    side, why = conversion.face_to_trimmed(Part.makeCylinder(3, 4).Faces[0])
    check(why is None and type(side).__name__ != "TrimmedSurface", f"cylinder side: {type(side).__name__}")
    # a periodic face whose boundary runs along its seam (the bore of a cross hole):
    # the seam's two pcurves are chained by whole periods; OCCT's boolean gives
    # approximated pcurves there, so the area agrees to their accuracy only
    bored = Part.makeCylinder(5, 20).cut(Part.makeCylinder(1, 20, V(0, -10, 10), V(0, 1, 0)))
    bore = next(f for f in bored.Faces if isinstance(f.Surface, Part.Cylinder) and abs(f.Surface.Radius - 1) < 1e-9)
    bt, why = conversion.face_to_trimmed(bore)
    rel = abs(bt.area() - bore.Area) / bore.Area if why is None else float("inf")
    MEASURED["trimmed bore area"] = rel
    check(type(bt).__name__ == "TrimmedSurface" and rel <= 1e-5, f"bore across its seam: {why}, area {rel:.3g}")
    bs = Part.BSplineSurface()
    bs.buildFromPolesMultsKnots([[V(-5, -5, 0), V(-5, 5, 0)], [V(5, -5, 0), V(5, 5, 0)]],
                                [2, 2], [2, 2], [0, 1], [0, 1], False, False, 1, 1)
    circle = Part.Geom2d.Circle2d(App.Base.Vector2d(0.5, 0.5), 0.3)
    disk = Part.Face(bs, Part.Wire([circle.toShape(bs)]))
    disk.validate()
    dt, why = conversion.face_to_trimmed(disk)
    expected = math.pi * 3.0 ** 2                              # 0.3 of a 10-wide parameter square
    rel = abs(dt.area() - expected) / expected
    MEASURED["trimmed disk area"] = rel
    check(why is None and rel <= 1e-9, f"disk: area {dt.area():.15g}, pi r^2 {expected:.15g} ({why})")


@case
def test_deviation_map_and_intersection_use_the_trim():
    """A point above the hole's centre is as far as the hole's rim (hypot(r, h)), not
    h; a plane through the hole cuts the face in two branches of total length 10 - 2r."""
    doc = new_doc("trimmedqueries")
    r, h = 2.0, 0.5
    plate, name = _holed_plate(doc, r)
    X = np.array([[5.0, 5.0, 1 + h], [1.0, 1.0, 1 + h], [9.0, 2.0, 1 - h / 2]])
    path = os.path.join(OUT, "holed_points.csv")
    with open(path, "w", encoding="utf-8") as f:
        f.write("".join(f"{x:.17g},{y:.17g},{z:.17g}\n" for x, y, z in X))
    obj = inspection.make_deviation_map([(plate, name)], csv_file=path, doc=doc)
    doc.recompute()
    check(obj.isValid(), f"holed deviation map: {obj.Message}")
    got = np.abs(np.array(obj.Distances))
    want = np.array([math.hypot(r, h), h, h / 2])
    MEASURED["trimmed deviation"] = float(np.abs(got - want).max())
    check(np.abs(got - want).max() <= 1e-9, f"holed plate distances {got} against {want}")
    (verts, tris, values), = inspection.face_meshes(obj)           # drawn: the trimmed triangulation
    face = plate.Shape.getElement(name)
    drawn = inspection.mesh_area(verts, tris)
    MEASURED["trimmed drawn area"] = abs(drawn - face.Area) / face.Area
    check(abs(drawn - face.Area) <= 0.01 * face.Area, f"drawn area {drawn:.6g}, face {face.Area:.6g}")
    r_v = np.hypot(verts[:, 0] - 5, verts[:, 1] - 5)
    check(r_v.min() >= r * (1 - 1e-6) and np.all(np.isin(values, np.array(obj.Distances))),
          f"drawn vertices inside the hole (min radius {r_v.min():.6g}) or values not the points' distances")
    cutter = doc.addObject("Part::Feature", "Cutter")
    cutter.Shape = Part.makePlane(20, 20, V(5, 15, -5), V(1, 0, 0))      # x = 5, y in [-5, 15]
    doc.recompute()
    cut = inspection.make_intersection((plate, name), (cutter, "Face1"), doc=doc)
    doc.recompute()
    length = sum(e.Length for e in cut.Shape.Edges)
    MEASURED["trimmed intersection length"] = abs(length - (10 - 2 * r))
    check(cut.BranchCount == 2 and abs(length - (10 - 2 * r)) <= 1e-6,
          f"plane through the hole: {cut.BranchCount} branches, length {length:.12g} (want {10 - 2 * r})")


@case
def test_query_measurements():
    """Prints the largest values measured by the cases above."""
    print("  query cases measured: " + ", ".join(f"{k} {v:.3g}" for k, v in MEASURED.items()))
    check(len(MEASURED) >= 8, f"measurements missing: {sorted(MEASURED)}")
