"""Headless cases of the pole edit mode (issue 19): the pure drag geometry of
cagdwb/poledrag.py and the property updates of cagdwb/editpoles.py (a pole moved in
global coordinates, a linked Part Vertex moved instead, a vertex of a solid refused, a
pole's weight). The GUI drags themselves are in gui_edit_macro.py."""
import math

import numpy as np
import Part

import FreeCAD as App
from suite_support import V, cagd, case, check, conversion, curves, new_doc, recompute_ok, surfaces

from cagdwb import editpoles, poledrag


def _raises(fn, words):
    """fn() raises CagdError whose message contains ``words``."""
    try:
        fn()
    except cagd.CagdError as exc:
        check(words in str(exc), f"message {exc!s} lacks {words!r}")
        return
    raise AssertionError(f"no CagdError ({words})")


@case
def test_pole_drag_geometry():
    """pick_pole: the point nearest the ray (brute force over random clouds), the front
    one of two on the ray, none beyond tol; drag_in_plane: on the plane and on the ray;
    drag_along: on the axis, the segment to the ray normal to both (closest points);
    drag_in_depth: the travel up the screen along the axis; net_normals of a plane
    z = a x + b y: (-a, -b, 1) / norm."""
    rng = np.random.default_rng(19)
    for _ in range(20):
        P = rng.normal(size=(50, 3)) * 10
        o, d = rng.normal(size=3) * 20, rng.normal(size=3)
        u = d / np.linalg.norm(d)
        rel = P - o
        dist = np.linalg.norm(rel - np.outer(rel @ u, u), axis=1)
        check(poledrag.pick_pole(P, o, d, 1e9) == int(np.argmin(dist)), "pick_pole is not the nearest to the ray")
        check(poledrag.pick_pole(P, o, d, 0.999 * dist.min()) is None, "pick_pole beyond tol")
    two = np.array([[0, 0, 5.0], [0, 0, -5.0], [3, 0, 0]])
    check(poledrag.pick_pole(two, [0, 0, 10], [0, 0, -1], 0.5) == 0, "not the front pole")
    check(poledrag.pick_pole(two, [0, 0, -10], [0, 0, 1], 0.5) == 1, "not the front pole (from below)")
    for _ in range(20):
        a, n, o, d = (rng.normal(size=3) for _ in range(4))
        q = poledrag.drag_in_plane(a, n, o, d)
        check(abs((q - a) @ n) <= 1e-9 * np.linalg.norm(n) * (1 + np.abs(q).max()), "not on the plane")
        check(np.linalg.norm(np.cross(q - o, d)) <= 1e-9 * np.linalg.norm(d) * (1 + np.abs(q).max()),
              "not on the ray")
        q = poledrag.drag_along(a, n, o, d)
        check(np.linalg.norm(np.cross(q - a, n)) <= 1e-9 * np.linalg.norm(n) * (1 + np.abs(q).max()),
              "not on the axis")
        w = q - o
        foot = o + (w @ d) / (d @ d) * d                  # the ray's point nearest q
        gap = q - foot
        scale = 1e-9 * (1 + np.abs(q).max() + np.abs(foot).max())
        check(abs(gap @ n) <= scale * np.linalg.norm(n) and abs(gap @ d) <= scale * np.linalg.norm(d),
              "the segment between the lines is not normal to both")
    q = poledrag.drag_in_depth([1, 2, 3], [0, 0, -2], [0, 0, 0], [5, 7, 0], [0, 1, 0])
    check(np.allclose(q, [1, 2, -4], rtol=0, atol=1e-15), f"drag_in_depth {q}")
    a_, b_ = 0.3, -0.7
    x, y = np.meshgrid(np.linspace(0, 4, 5), np.linspace(0, 3, 4), indexing="ij")
    N = poledrag.net_normals(np.stack([x, y, a_ * x + b_ * y], -1))
    want = np.array([-a_, -b_, 1.0]) / math.sqrt(a_ * a_ + b_ * b_ + 1)
    check(np.abs(N - want).max() <= 1e-12, f"net normals {N[0, 0]} vs {want}")
    _raises(lambda: poledrag.drag_in_plane([0, 0, 0], [0, 0, 1], [0, 0, 1], [1, 0, 0]), "direction")
    _raises(lambda: poledrag.drag_along([0, 0, 0], [0, 0, 1], [1, 0, 0], [0, 0, -1]), "axis")
    _raises(lambda: poledrag.pick_pole(two, [0, 0, 1], [0, 0, 0], 1.0), "direction")
    _raises(lambda: poledrag.pick_pole(two, [0, 0, 1], [0, 0, 1], 0.0), "tol")


def _single_pole_curve(curve, k, delta):
    """OCCT's curve with pole k = delta and the others 0: N_k(t) delta (the oracle of a
    moved pole: C_new - C_old, the curve being linear in its poles)."""
    one = Part.BSplineCurve()
    poles = [V(*delta) if i == k else V(0, 0, 0) for i in range(curve.NbPoles)]
    one.buildFromPolesMultsKnots(poles, curve.getMultiplicities(), curve.getKnots(), curve.isPeriodic(),
                                 curve.Degree)
    return one


@case
def test_pole_set_point():
    """set_point moves a pole given in global coordinates: the property gets it in the
    placed object's local coordinates, the edge moves by N_k(t) delta (OCCT's one-pole
    curve, 41 parameters, 1e-9 of the size); on a surface S_new - S_old = N_i(u) N_j(v)
    delta (OCCT's one-pole surface); placed_points and net normals in global coordinates;
    an index out of range is an error naming Poles."""
    doc = new_doc("setpoint")
    obj = curves.make_bspline_curve(doc=doc)
    obj.Placement = App.Placement(V(5, -3, 2), App.Rotation(V(0, 0, 1), 30))
    recompute_ok(obj)
    edge = obj.Shape.Edges[0]
    ts = np.linspace(edge.FirstParameter, edge.LastParameter, 41)
    before = np.array([tuple(edge.valueAt(t)) for t in ts])
    P = editpoles.placed_points(obj)
    check(np.abs(P - np.array([tuple(p) for p in edge.Curve.getPoles()])).max() <= 1e-12 * 60,
          "placed_points are not the shape's poles")
    delta = np.array([1.5, -2.0, 4.0])
    editpoles.set_point(obj, 2, P[2] + delta)
    recompute_ok(obj)
    local = obj.Placement.inverse().multVec(V(*(P[2] + delta)))
    check((obj.Poles[2] - local).Length <= 1e-12 * 60, f"property pole {obj.Poles[2]} vs {local}")
    edge = obj.Shape.Edges[0]
    one = _single_pole_curve(edge.Curve, 2, delta)
    after = np.array([tuple(edge.valueAt(t)) for t in ts])
    dev = np.abs(after - before - np.array([tuple(one.value(t)) for t in ts])).max()
    check(dev <= 1e-9 * 60, f"edge moved {dev:.3g} off N_k(t) delta")
    _raises(lambda: editpoles.set_point(obj, 6, (0, 0, 0)), "Poles")
    i, j = np.meshgrid(np.arange(5.0), np.arange(6.0), indexing="ij")
    grid = np.stack([10 * i, 10 * j, 3 * np.sin(i + j)], -1)
    surf = surfaces.make_bspline_surface(grid, 5, doc=doc)
    recompute_ok(surf)
    face = surf.Shape.Faces[0]
    uv = [(u, v) for u in np.linspace(0, 1, 7) for v in np.linspace(0, 1, 7)]
    before = np.array([tuple(face.Surface.value(u, v)) for u, v in uv])
    k = 2 * 6 + 3
    editpoles.set_point(surf, k, grid[2, 3] + delta)
    recompute_ok(surf)
    s = surf.Shape.Faces[0].Surface
    one = Part.BSplineSurface()
    one.buildFromPolesMultsKnots([[V(*delta) if (a, b) == (2, 3) else V(0, 0, 0) for b in range(6)] for a in range(5)],
                                 s.getUMultiplicities(), s.getVMultiplicities(), s.getUKnots(), s.getVKnots(),
                                 False, False, s.UDegree, s.VDegree)
    after = np.array([tuple(s.value(u, v)) for u, v in uv])
    dev = np.abs(after - before - np.array([tuple(one.value(u, v)) for u, v in uv])).max()
    check(dev <= 1e-9 * 60, f"surface moved {dev:.3g} off N_i(u) N_j(v) delta")
    N = editpoles.surface_normals(surf)
    check(N is not None and N.shape == (30, 3) and np.allclose(np.linalg.norm(N, axis=1), 1.0),
          "surface_normals of a 5 x 6 grid")
    check(editpoles.surface_normals(obj) is None and editpoles.point_property(obj) == "Poles", "curve normals")
    spline = curves.make_cubic_spline(doc=doc)
    check(editpoles.point_property(spline) == "Points", "a cubic spline edits its Points")
    coons = doc.addObject("Part::Feature", "Plain")
    check(editpoles.point_property(coons) is None, "a Part feature has points to edit")


@case
def test_pole_linked_vertex():
    """A Bezier curve on Part Vertex objects (one placed): set_point moves that vertex
    object (X, Y, Z in its own coordinates) and the curve follows; a pole from a box's
    vertex is refused (CagdError naming Vertices and the box, refusal() says why) and
    nothing changes."""
    doc = new_doc("linkedpole")
    verts = []
    for n, p in enumerate([V(0, 0, 0), V(10, 20, 0), V(30, 20, 0)]):
        v = doc.addObject("Part::Vertex", f"P{n}")
        v.X, v.Y, v.Z = p.x, p.y, p.z
        verts.append(v)
    verts[1].Placement = App.Placement(V(1, 2, 3), App.Rotation(V(1, 0, 0), 90))
    box = doc.addObject("Part::Box", "Block")
    doc.recompute()
    obj = curves.make_bezier_curve(vertices=[(v, "") for v in verts] + [(box, "Vertex7")], doc=doc)
    recompute_ok(obj)
    target = np.array([12.0, 25.0, -4.0])
    check(editpoles.refusal(obj, 1) is None, "a Part Vertex refused")
    editpoles.set_point(obj, 1, target)
    recompute_ok(obj)
    moved = verts[1].Shape.Vertexes[0].Point
    check(np.abs(np.array(tuple(moved)) - target).max() <= 1e-12 * 30, f"vertex at {moved}, wanted {target}")
    check(np.abs(np.array(tuple(obj.Poles[1])) - target).max() <= 1e-12 * 30, "curve did not follow the vertex")
    poles = [tuple(p) for p in obj.Poles]
    reason = editpoles.refusal(obj, 3)
    check(reason is not None and "Vertices" in reason and "Block.Vertex7" in reason, f"refusal {reason!r}")
    _raises(lambda: editpoles.set_point(obj, 3, (1, 2, 3)), "Block.Vertex7")
    recompute_ok(obj)
    check([tuple(p) for p in obj.Poles] == poles, "a refused move changed the poles")


@case
def test_pole_weight():
    """set_weight on a polynomial curve makes it rational (all ones, the picked weight
    set; OCCT's curve carries it); a weight out of range is an error naming Weights; the
    points of a cubic spline or of an interpolating surface have no weights."""
    doc = new_doc("poleweight")
    obj = curves.make_bspline_curve(doc=doc)
    recompute_ok(obj)
    editpoles.set_weight(obj, 3, 2.5)
    recompute_ok(obj)
    check(list(obj.Weights) == [1.0, 1.0, 1.0, 2.5, 1.0, 1.0], f"weights {list(obj.Weights)}")
    c = obj.Shape.Edges[0].Curve
    check(c.isRational() and abs(c.getWeight(4) - 2.5) <= 1e-15, "OCCT's curve lacks the weight")
    _raises(lambda: editpoles.set_weight(obj, 3, 0.0), "Weights")
    _raises(lambda: editpoles.set_weight(obj, 9, 1.0), "Weights")
    spline = curves.make_cubic_spline(doc=doc)
    _raises(lambda: editpoles.set_weight(spline, 0, 2.0), "no pole weights")
    through = surfaces.make_bspline_surface(Interpolate=True, doc=doc)
    _raises(lambda: editpoles.set_weight(through, 0, 2.0), "no pole weights")
    check(conversion.array(obj.Poles).shape == (6, 3), "poles changed by a weight")


# --- knot and degree edits (cagdwb/knotedit.py) --------------------------------------------------
def _edge_points(obj, n=61):
    """Part's own points of the object's edge at n parameters of its domain."""
    edge = obj.Shape.Edges[0]
    ts = np.linspace(edge.FirstParameter, edge.LastParameter, n)
    return np.array([tuple(edge.valueAt(t)) for t in ts])


def _face_points(obj, n=13):
    """Part's own points of the object's face on an n x n grid of its parameter box."""
    s = obj.Shape.Faces[0].Surface
    u0, u1, v0, v1 = s.bounds()
    return np.array([tuple(s.value(u, v)) for u in np.linspace(u0, u1, n) for v in np.linspace(v0, v1, n)])


KNOT_PROPERTIES = ("Poles", "Degree", "Knots", "Weights", "Periodic", "CountU", "DegreeU", "DegreeV", "KnotsU",
                   "KnotsV", "PeriodicU", "PeriodicV")


def _snapshot(obj):
    return {n: [tuple(v) if hasattr(v, "x") else v for v in getattr(obj, n)] if isinstance(getattr(obj, n), list)
            else getattr(obj, n) for n in KNOT_PROPERTIES if n in obj.PropertiesList}


def _undo_restores(obj, before, undo_count):
    """One more undo step than ``undo_count``; undoing it gives back ``before``."""
    doc = obj.Document
    check(doc.UndoCount == undo_count + 1, f"undo stack {undo_count} -> {doc.UndoCount}, not one step")
    doc.undo()
    doc.recompute()
    check(_snapshot(obj) == before, "undo did not restore the properties")


@case
def test_knot_insert_elevate_curve():
    """Insert knot at the pole nearest parameter and elevate degree on a placed rational
    B-spline curve and a periodic one: Part's edge points (61 parameters) unchanged to
    1e-9 of the size; Knots one longer, Part's curve has one more knot (or multiplicity)
    at OCCT's own projection of the pole (Curve.parameter, 1e-6); Degree + 1; each edit
    one undo step restoring every property; an end pole and a linked-vertex curve are
    refused (CagdError naming Poles / Vertices) without a transaction."""
    from cagdwb import knotedit
    doc = new_doc("knotedit")
    doc.UndoMode = 1
    obj = curves.make_bspline_curve(weights=[1, 2, 0.5, 1, 3, 1], knots=[0, 0, 0, 0, 0.3, 0.55, 1, 1, 1, 1],
                                    doc=doc)
    obj.Placement = App.Placement(V(5, -3, 2), App.Rotation(V(1, 1, 0), 40))
    periodic = curves.make_bspline_curve(periodic=True, knots=[0, 0.1, 0.3, 0.5, 0.6, 0.8, 1], doc=doc)
    doc.recompute()
    for o in (obj, periodic):
        points, before, undo = _edge_points(o), _snapshot(o), doc.UndoCount
        pole = o.Placement.multVec(o.Poles[2])
        occ_t = o.Shape.Edges[0].Curve.parameter(pole)
        mults = sum(o.Shape.Edges[0].Curve.getMultiplicities())
        knotedit.run(o, "Insert knot", lambda g: knotedit.insert_knot(g, 2))
        check(len(o.Knots) == len(before["Knots"]) + 1 and len(o.Poles) == len(before["Poles"]) + 1,
              f"{o.Label}: knots {len(before['Knots'])} -> {len(o.Knots)}")
        new = sorted(set(o.Knots) - set(before["Knots"]))
        check(len(new) == 1 and abs(new[0] - occ_t) <= 1e-6, f"{o.Label}: knot {new} vs OCCT's parameter {occ_t}")
        c = o.Shape.Edges[0].Curve
        check(sum(c.getMultiplicities()) == mults + 1, "OCCT's curve has no new knot")
        dev = np.abs(_edge_points(o) - points).max()
        check(dev <= 1e-9 * 60, f"{o.Label}: insert moved the edge by {dev:.3g}")
        _undo_restores(o, before, undo)
        check(np.abs(_edge_points(o) - points).max() <= 1e-12 * 60, "undo did not restore the edge")
        knotedit.run(o, "Elevate degree", lambda g: knotedit.elevate(g))
        check(o.Degree == before["Degree"] + 1 and o.Shape.Edges[0].Curve.Degree == before["Degree"] + 1,
              f"{o.Label}: degree {before['Degree']} -> {o.Degree}")
        dev = np.abs(_edge_points(o) - points).max()
        check(dev <= 1e-9 * 60, f"{o.Label}: elevate moved the edge by {dev:.3g}")
        _undo_restores(o, before, undo)
    verts = []
    for n, p in enumerate([V(0, 0, 0), V(10, 20, 0), V(30, 20, 0), V(40, 0, 0)]):
        v = doc.addObject("Part::Vertex", f"K{n}")
        v.X, v.Y, v.Z = p.x, p.y, p.z
        verts.append(v)
    linked = curves.make_bspline_curve(vertices=[(v, "") for v in verts], doc=doc)
    doc.recompute()
    undo, before = doc.UndoCount, _snapshot(obj)
    _raises(lambda: knotedit.run(obj, "Insert knot", lambda g: knotedit.insert_knot(g, 0)), "Poles")
    _raises(lambda: knotedit.run(linked, "Elevate degree", knotedit.elevate), "Vertices")
    check(doc.UndoCount == undo and _snapshot(obj) == before, "a refused edit changed the document")



def _removal_samples(knots, p):
    """The parameters at which the engine measures a removal's deviation (its
    definition, cagd.knots.removal): DEVIATION_SAMPLES per span of the original knots."""
    brk = np.unique(np.asarray(knots)[p:len(knots) - p])
    f = np.linspace(0.0, 1.0, cagd.knots.removal.DEVIATION_SAMPLES)
    return np.unique((brk[:-1, None] + f[None] * np.diff(brk)[:, None]).ravel())


@case
def test_knot_remove_curve():
    """Remove knots on a curve made by OCCT with a redundant knot (Part's insertKnot at
    0.37): that knot goes, the others stay, the reported deviation <= 1e-9 and Part's
    edge is unchanged (1e-9); on a smooth curve with tolerance 0.5 (size 60) a knot goes
    and the reported deviation (> 1e-6, <= tolerance) equals Part's largest distance of
    the old and new edges at the engine's sample parameters (to 1e-9 of the size), and
    bounds the distance of each old point from the new edge (Part's distToShape); one
    undo step each."""
    from cagdwb import knotedit
    doc = new_doc("knotremove")
    doc.UndoMode = 1
    poles = [V(0, 0, 0), V(10, 15, 0), V(20, -5, 5), V(30, 15, 5), V(40, 0, 0), V(50, 10, 0)]
    knots = [0, 0, 0, 0, 0.3, 0.55, 1, 1, 1, 1]
    part = Part.BSplineCurve()
    part.buildFromPolesMultsKnots(poles, [4, 1, 1, 4], [0, 0.3, 0.55, 1], False, 3)
    part.insertKnot(0.37, 1)
    full = [k for k, m in zip(part.getKnots(), part.getMultiplicities()) for _ in range(m)]
    obj = curves.make_bspline_curve(poles=part.getPoles(), knots=full, doc=doc)
    doc.recompute()
    points, before, undo = _edge_points(obj), _snapshot(obj), doc.UndoCount
    _, message, removed, dev = knotedit.run(obj, "Remove knots", lambda g: knotedit.remove_knots(g, 1e-6))
    check(removed == 1 and list(obj.Knots) == knots, f"knots after removal {list(obj.Knots)} ({message})")
    check(dev <= 1e-9, f"redundant knot removal deviation {dev:.3g}")
    check(np.abs(_edge_points(obj) - points).max() <= 1e-9 * 60, "removing a redundant knot moved the edge")
    _undo_restores(obj, before, undo)
    knots = [0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1]
    poles = [V(0, 0, 0), V(10, 3, 0), V(20, 5, 1), V(30, 6, 1), V(40, 5, 0), V(50, 2, 0), V(60, 0, 0)]
    generic = curves.make_bspline_curve(poles=poles, knots=knots, doc=doc)
    doc.recompute()
    old_edge, before, undo = generic.Shape.Edges[0], _snapshot(generic), doc.UndoCount
    tol = 0.5
    _, message, removed, dev = knotedit.run(generic, "Remove knots", lambda g: knotedit.remove_knots(g, tol))
    new_edge = generic.Shape.Edges[0]
    check(removed >= 1 and len(generic.Knots) == len(knots) - removed, f"no knot removed: {message}")
    check(1e-6 < dev <= tol, f"deviation {dev:.3g} of a removal that is not free")
    ts = _removal_samples(knots, 3)
    old = np.array([tuple(old_edge.valueAt(t)) for t in ts])
    new = np.array([tuple(new_edge.valueAt(t)) for t in ts])
    measured = float(np.linalg.norm(old - new, axis=1).max())
    check(abs(measured - dev) <= 1e-9 * 60, f"reported deviation {dev:.12g}, Part measures {measured:.12g}")
    gaps = [Part.Vertex(V(*p)).distToShape(new_edge)[0] for p in old]
    check(max(gaps) <= dev + 1e-9 and max(gaps) > 0.0, f"distToShape {max(gaps):.3g} vs deviation {dev:.3g}")
    check(f"{dev:.3g}" in message, f"message {message!r} lacks the deviation")
    _undo_restores(generic, before, undo)


@case
def test_knot_edit_surface():
    """A 5 x 6 B-spline surface: insert knot (Both) at the parameters nearest pole (2, 3)
    adds one knot in u and one in v (Part's multiplicity sums + 1 each) and leaves Part's
    face points (13 x 13) unchanged to 1e-9; elevate U raises DegreeU (Part's UDegree)
    with the same face; remove knots (Both, 1e-7) then takes the two inserted knots
    away with deviation <= 1e-9; each one undo step."""
    from cagdwb import knotedit
    doc = new_doc("knotsurface")
    doc.UndoMode = 1
    i, j = np.meshgrid(np.arange(5.0), np.arange(6.0), indexing="ij")
    grid = np.stack([10 * i, 10 * j, 3 * np.sin(i + 0.7 * j)], -1)
    obj = surfaces.make_bspline_surface(grid, 5, doc=doc)
    doc.recompute()
    points, start = _face_points(obj), _snapshot(obj)
    s = obj.Shape.Faces[0].Surface
    mults = (sum(s.getUMultiplicities()), sum(s.getVMultiplicities()))
    undo = doc.UndoCount
    knotedit.run(obj, "Insert knot", lambda g: knotedit.insert_knot(g, 2 * 6 + 3, "Both"))
    check(doc.UndoCount == undo + 1, "insert knot is not one undo step")
    s = obj.Shape.Faces[0].Surface
    check((sum(s.getUMultiplicities()), sum(s.getVMultiplicities())) == (mults[0] + 1, mults[1] + 1),
          f"multiplicities {mults} -> {sum(s.getUMultiplicities())}, {sum(s.getVMultiplicities())}")
    check(obj.CountU == 6 and len(obj.Poles) == 6 * 7, f"pole grid {obj.CountU} x {len(obj.Poles) // obj.CountU}")
    dev = np.abs(_face_points(obj) - points).max()
    check(dev <= 1e-9 * 40, f"insert moved the face by {dev:.3g}")
    inserted, undo = _snapshot(obj), doc.UndoCount
    knotedit.run(obj, "Elevate degree", lambda g: knotedit.elevate(g, "U"))
    check(obj.DegreeU == 4 and obj.DegreeV == 3 and obj.Shape.Faces[0].Surface.UDegree == 4, "elevate U")
    dev = np.abs(_face_points(obj) - points).max()
    check(dev <= 1e-9 * 40, f"elevate moved the face by {dev:.3g}")
    _undo_restores(obj, inserted, undo)
    _, message, removed, dev = knotedit.run(obj, "Remove knots", lambda g: knotedit.remove_knots(g, 1e-7, "Both"))
    check(removed == 2 and dev <= 1e-9, f"remove knots: {message}")
    s = obj.Shape.Faces[0].Surface
    check((sum(s.getUMultiplicities()), sum(s.getVMultiplicities())) == mults, "the inserted knots stayed")
    check(np.abs(_face_points(obj) - points).max() <= 1e-9 * 40, "remove knots moved the face")
    doc.undo()
    doc.undo()
    doc.recompute()
    check(_snapshot(obj) == start, "two undos do not give back the surface")
