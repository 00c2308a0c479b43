"""Engine <-> FreeCAD Part conversion through OCCT's exact B-spline form, and FreeCAD's
own analytic surfaces for the engine's surfaces of revolution.

Engine -> Part: ``geometry.to_nurbs().occ_form()`` gives exactly the arguments of
``Part.BSplineCurve().buildFromPolesMultsKnots(poles, mults, knots, periodic,
degree, weights)`` and ``Part.BSplineSurface().buildFromPolesMultsKnots(poles,
umults, vmults, uknots, vknots, uperiodic, vperiodic, udegree, vdegree, weights)``
(rational and periodic included). Part -> engine: getPoles / getWeights / getKnots
/ getMultiplicities / Degree / isPeriodic into ``BSplineCurve.from_occ_form`` and
``BSplineSurface.from_occ_form``; Part Bezier geometry and any other edge or face
geometry first become B-splines (``toBSpline`` / ``toNurbs``).

A :class:`cagd.RevolvedSurface` (a Revolution object, cagd.sphere, torus, cylinder,
cone) becomes, unless ``nurbs=True``, a face on Part.Sphere, Part.Toroid,
Part.Cylinder, Part.Cone or Part.SurfaceOfRevolution of the profile's exact
B-spline (:func:`analytic_surface`): the same point set as the engine's NURBS form,
parametrised by the angle (the relation is :meth:`cagd.RevolvedSurface.analytic_parameters`,
the same as OCCT's in :mod:`cagd.occ.analytic`). Part's Offset and Thickness accept
those faces; they refuse the NURBS form, whose rational circles have double knots
that OCCT declares C0.
"""
from __future__ import annotations

from itertools import chain
from typing import Optional, Tuple, Union

import numpy as np

import FreeCAD as App
import Part

from . import ensure_engine

ensure_engine()
import cagd  # noqa: E402

EngineGeometry = Union["cagd.Curve", "cagd.Surface"]


def vectors(points) -> list:
    """An (n, 3) array (or nested (n, m, 3)) as a list of App.Vector (nested lists);
    one App.Vector(x, y, z) call per point from the columns' Python floats."""
    a = np.asarray(points, dtype=float)
    flat = list(map(App.Vector, *a.reshape(-1, 3).T.tolist()))
    if a.ndim == 3:
        n = a.shape[1]
        return [flat[i * n:(i + 1) * n] for i in range(a.shape[0])]
    return flat


def array(vecs) -> np.ndarray:
    """A list of App.Vector (or nested lists) as a float array (..., 3), read through
    the vectors' own iteration (numpy.fromiter over their coordinates)."""
    if len(vecs) and isinstance(vecs[0], (list, tuple)):
        rows = len(vecs)
        return array([v for row in vecs for v in row]).reshape(rows, -1, 3)
    return np.fromiter(chain.from_iterable(vecs), dtype=float, count=3 * len(vecs)).reshape(-1, 3)


def curve_to_part(curve: "cagd.Curve") -> "Part.BSplineCurve":
    """The engine curve as a Part.BSplineCurve (the same parametrisation)."""
    f = curve.to_nurbs().occ_form()
    bc = Part.BSplineCurve()
    weights = None if f.weights is None else [float(w) for w in f.weights]
    args = [vectors(f.poles), [int(m) for m in f.multiplicities], [float(k) for k in f.knots],
            bool(f.periodic), int(f.degree)]
    bc.buildFromPolesMultsKnots(*args, *([weights] if weights is not None else []))
    return bc


def surface_to_part(surface: "cagd.Surface") -> "Part.BSplineSurface":
    """The engine surface (any kind, triangles through their collapsed-edge NURBS
    form) as a Part.BSplineSurface with the same parametrisation."""
    f = surface.to_nurbs().occ_form()
    bs = Part.BSplineSurface()
    args = [vectors(f.poles), [int(m) for m in f.multiplicities_u], [int(m) for m in f.multiplicities_v],
            [float(k) for k in f.knots_u], [float(k) for k in f.knots_v],
            bool(f.periodic_u), bool(f.periodic_v), int(f.degree_u), int(f.degree_v)]
    if f.weights is not None:
        args.append([[float(w) for w in row] for row in f.weights])
    bs.buildFromPolesMultsKnots(*args)
    return bs


def analytic_surface(surface: "cagd.Surface") -> Optional[Tuple[object, Tuple[float, float, float, float], bool]]:
    """(Part surface, (U0, U1, V0, V1), reversed) for a :class:`cagd.RevolvedSurface`,
    else None: Part.Sphere / Toroid / Cylinder / Cone of its primitive record, placed
    in the record's right-handed frame (x_direction, axis x x_direction, axis), or
    Part.SurfaceOfRevolution of the profile's exact B-spline; the bounds are the
    engine's range on it, and ``reversed`` says that the surface's own normal is the
    opposite of the engine's S_u x S_v (a face on it must be reversed)."""
    if not isinstance(surface, cagd.RevolvedSurface):
        return None
    p = surface.primitive
    if p is None:
        r = surface.revolution
        geom = Part.SurfaceOfRevolution(curve_to_part(r.profile), App.Vector(*map(float, r.axis_point)),
                                        App.Vector(*map(float, r.axis_direction)))
        return geom, surface.analytic_bounds, True
    if p.kind == "sphere":
        geom = Part.Sphere()
        geom.Radius = p.radius
    elif p.kind == "torus":
        geom = Part.Toroid()
        geom.MajorRadius, geom.MinorRadius = p.radius, p.minor_radius
    elif p.kind == "cylinder":
        geom = Part.Cylinder()
        geom.Radius = p.radius
    else:
        geom = Part.Cone()
        geom.Radius, geom.SemiAngle = p.radius, p.semi_angle
    frame = np.column_stack([p.x_direction, p.y_direction, p.axis, p.center])
    geom.transform(App.Matrix(*map(float, frame.ravel()), 0.0, 0.0, 0.0, 1.0))
    return geom, p.analytic_bounds, p.turn < 0


def curve2d_to_part(curve: "cagd.Curve") -> "Part.Geom2d.BSplineCurve2d":
    """A 2-D engine curve (a trimming curve in (u, v)) as a Part.Geom2d.BSplineCurve2d
    with the same parametrisation."""
    f = curve.to_nurbs().occ_form()
    bc = Part.Geom2d.BSplineCurve2d()
    weights = None if f.weights is None else [float(w) for w in f.weights]
    poles = [App.Base.Vector2d(float(p[0]), float(p[1])) for p in f.poles]
    args = [poles, [int(m) for m in f.multiplicities], [float(k) for k in f.knots], bool(f.periodic), int(f.degree)]
    bc.buildFromPolesMultsKnots(*args, *([weights] if weights is not None else []))
    return bc


def trimmed_face(ts: "cagd.TrimmedSurface") -> "Part.Face":
    """The face of a :class:`cagd.TrimmedSurface`: its surface's exact B-spline
    (:func:`surface_to_part`, the engine's parameters) bounded by one wire per loop, an
    edge per loop curve (the Geom2d curve on the surface; FreeCAD builds its 3-D curve),
    the holes cut by ``Face.cutHoles`` (``Part.Face(surface, [wires])`` gives an invalid
    face in FreeCAD 0.20), then ``validate()``. ``ts.edges`` (a file's 3-D curves) are
    not used: FreeCAD 0.20's Python cannot attach a given pcurve to an edge made from
    a 3-D curve, and the pcurves ``validate()`` then projects were 1e-3 off on an
    annulus (measured, issue 15).

    Raises:
        ValueError: FreeCAD's face is not valid (e.g. a loop along a collapsed edge).
    """
    surface = surface_to_part(ts.surface)
    wires = [Part.Wire([curve2d_to_part(c).toShape(surface, *map(float, c.domain)) for c in loop])
             for loop in ts.loops]
    face = Part.Face(surface, wires[0])
    if len(wires) > 1:
        face.cutHoles(wires[1:])
    face.validate()
    if not face.isValid():
        raise ValueError("surface: FreeCAD could not make a valid face of the trimmed surface's loops")
    return face


def to_shape(geometry: EngineGeometry, nurbs: bool = False) -> "Part.Shape":
    """An edge for an engine curve, a face for an engine surface: the face of its
    exact B-spline, or for a surface of revolution with a construction record the
    face of FreeCAD's analytic surface (:func:`analytic_surface`), oriented so that
    its normal is the engine's, unless ``nurbs=True``; for a
    :class:`cagd.TrimmedSurface` the face bounded by its loops (:func:`trimmed_face`;
    before, the untrimmed surface was shown)."""
    if isinstance(geometry, cagd.Curve):
        return curve_to_part(geometry).toShape()
    if isinstance(geometry, cagd.TrimmedSurface):
        return trimmed_face(geometry)
    if isinstance(geometry, cagd.Surface):
        form = None if nurbs else analytic_surface(geometry)
        if form is None:
            return surface_to_part(geometry).toShape()
        geom, bounds, reversed_ = form
        face = geom.toShape(*bounds)
        return face.reversed() if reversed_ else face
    raise TypeError(f"geometry: expected a cagd Curve or Surface, got {type(geometry).__name__}")


def part_curve_to_engine(curve) -> "cagd.BSplineCurve":
    """A Part.BSplineCurve or Part.BezierCurve as an engine BSplineCurve (exact)."""
    if isinstance(curve, Part.BezierCurve):
        curve = curve.toBSpline()
    if not isinstance(curve, Part.BSplineCurve):
        raise TypeError(f"curve: expected a Part B-spline or Bezier curve, got {type(curve).__name__}")
    weights = curve.getWeights() if curve.isRational() else None
    return cagd.BSplineCurve.from_occ_form(array(curve.getPoles()), weights, curve.getKnots(),
                                           curve.getMultiplicities(), curve.Degree, curve.isPeriodic())


def part_surface_to_engine(surface) -> "cagd.BSplineSurface":
    """A Part.BSplineSurface or Part.BezierSurface as an engine BSplineSurface (exact)."""
    if isinstance(surface, Part.BezierSurface):
        surface = _bezier_surface_to_bspline(surface)
    if not isinstance(surface, Part.BSplineSurface):
        raise TypeError(f"surface: expected a Part B-spline or Bezier surface, got {type(surface).__name__}")
    weights = np.array(surface.getWeights()) if surface.isURational() or surface.isVRational() else None
    return cagd.BSplineSurface.from_occ_form(
        array(surface.getPoles()), weights, surface.getUKnots(), surface.getVKnots(),
        surface.getUMultiplicities(), surface.getVMultiplicities(), surface.UDegree, surface.VDegree,
        surface.isUPeriodic(), surface.isVPeriodic())


def _bezier_surface_to_bspline(surface) -> "Part.BSplineSurface":
    """A Part.BezierSurface as the single-patch clamped B-spline on [0, 1]^2."""
    poles = surface.getPoles()
    nu, nv = len(poles), len(poles[0])
    bs = Part.BSplineSurface()
    args = [poles, [nu, nu], [nv, nv], [0.0, 1.0], [0.0, 1.0], False, False, nu - 1, nv - 1]
    if surface.isURational() or surface.isVRational():
        args.append(surface.getWeights())
    bs.buildFromPolesMultsKnots(*args)
    return bs


def edge_to_curve(edge) -> "cagd.BSplineCurve":
    """The edge's geometry (placement applied, trimmed to the edge's parameter range)
    as an engine curve; lines, circles and other analytic curves through ``toNurbs``.

    An edge on a periodic curve may run across the curve's seam (e.g. the range
    (3.5, 4.5) of a curve periodic on [0, 4]): its range is taken as is and cut by
    OCCT's own ``Geom_BSplineCurve::Segment`` (on a copy), which wraps around the
    period exactly; non-periodic curves are cut by the engine (``segment``).
    """
    curve = edge.Curve
    first, last = edge.FirstParameter, edge.LastParameter
    if not isinstance(curve, (Part.BSplineCurve, Part.BezierCurve)):
        curve = edge.toNurbs().Edges[0].Curve
        first, last = curve.FirstParameter, curve.LastParameter
    a, b = curve.FirstParameter, curve.LastParameter
    eps = 1e-12 * max(1.0, abs(a), abs(b), abs(first), abs(last))
    whole = abs(first - a) <= eps and abs(last - b) <= eps
    if isinstance(curve, Part.BSplineCurve) and curve.isPeriodic() and not whole:
        curve = curve.copy()
        curve.segment(first, last)          # OCCT wraps the range around the period
        return part_curve_to_engine(curve)
    c = part_curve_to_engine(curve)
    a, b = c.domain
    if first > a + eps or last < b - eps:
        c = c.segment(max(first, a), min(last, b))
    return c


def face_to_surface(face) -> "cagd.BSplineSurface":
    """The face's underlying surface as an engine B-spline surface, cut to the face's
    parameter box (trimming curves inside that box are ignored). In a periodic
    direction the box may run across the seam: the surface is then cut by OCCT's
    ``Geom_BSplineSurface::Segment`` on a copy (exact, wraps around the period)."""
    surface = face.Surface
    if not isinstance(surface, (Part.BSplineSurface, Part.BezierSurface)):
        # NURBS conversion restricts the surface to the face's box already; the new
        # face's ParameterRange is not cut by: on a closed surface it can start at
        # another seam (11752.stp's torus faces: u from 0.108, the surface's 0.091 ..
        # 6.375: a cut lost a strip of the face) or leave the bounds (Segment fails)
        return part_surface_to_engine(face.toNurbs().Faces[0].Surface)
    u0, u1, v0, v1 = face.ParameterRange
    cut_u = cut_v = False
    if isinstance(surface, Part.BSplineSurface) and (surface.isUPeriodic() or surface.isVPeriodic()):
        a, b, c, d = surface.bounds()
        eps = 1e-12 * max(1.0, *map(abs, (a, b, c, d, u0, u1, v0, v1)))
        cut_u = surface.isUPeriodic() and (abs(u0 - a) > eps or abs(u1 - b) > eps)
        cut_v = surface.isVPeriodic() and (abs(v0 - c) > eps or abs(v1 - d) > eps)
        if cut_u or cut_v:
            surface = surface.copy()
            surface.segment(u0 if cut_u else a, u1 if cut_u else b, v0 if cut_v else c, v1 if cut_v else d)
    s = part_surface_to_engine(surface)
    (a, b), (c, d) = s.domain
    eps = 1e-12 * max(1.0, abs(a), abs(b), abs(c), abs(d))
    # a direction Segment cut is the face's box already, its range possibly moved by whole
    # periods (trj3_s1-al-214.stp: [2, 6] of a period [2, 10] comes back as [10, 14])
    if not cut_u and (u0 > a + eps or u1 < b - eps):
        s = s.segment("u", max(u0, a), min(u1, b))
    if not cut_v and (v0 > c + eps or v1 < d - eps):
        s = s.segment("v", max(v0, c), min(v1, d))
    return s


def _pcurve(face, edge) -> "cagd.BSplineCurve":
    """The edge's pcurve on ``face`` (Part's ``curveOnSurface``) over the edge's range,
    as an engine 2-D B-spline (Part's exact ``toBSpline``: lines, circles, ellipses as
    rational B-splines), running along the edge as oriented in its wire."""
    found = face.curveOnSurface(edge)
    if not found:
        raise cagd.CagdError("an edge has no pcurve on the face")
    curve, first, last = found[0], float(found[1]), float(found[2])
    c = _exact_conic2d(curve, first, last)
    if c is not None:
        return c.reversed() if edge.Orientation == "Reversed" else c
    b = curve.toBSpline(first, last)          # exact for B-spline and Bezier pcurves
    poles = np.array([[p.x, p.y] for p in b.getPoles()], dtype=np.float64)
    weights = b.getWeights() if b.isRational() else None
    c = cagd.BSplineCurve.from_occ_form(poles, weights, b.getKnots(), b.getMultiplicities(), b.Degree,
                                        periodic=b.isPeriodic(), dim=2)
    return c.reversed() if edge.Orientation == "Reversed" else c


def _edge_curve(edge, pcurve: "cagd.BSplineCurve") -> Optional["cagd.BSplineCurve"]:
    """The edge's 3-D curve (:func:`edge_to_curve`) oriented like its pcurve, or None
    where it is degenerated or its range is not the pcurve's (e.g. a circle made a
    NURBS by ``toNurbs``, reparametrised)."""
    if edge.Degenerated:
        return None
    try:
        c = edge_to_curve(edge)
    except Exception:
        return None
    c = c.reversed() if edge.Orientation == "Reversed" else c
    (a, b), (p, q) = c.domain, pcurve.domain
    if max(abs(a - p), abs(b - q)) > EDGE_RANGE_TOL * max(abs(q - p), 1e-300):
        return None
    return c


EDGE_RANGE_TOL = 1e-9       # relative (pcurve range): an edge curve kept must run over its pcurve's range


def _exact_conic2d(curve, first: float, last: float) -> Optional["cagd.BSplineCurve"]:
    """A line, circle or ellipse pcurve (Part's own ``toBSpline`` approximates 2-D
    conics: 2e-8 off a circle of radius 0.3) as the exact B-spline over [first, last]:
    the segment, or C + a cos(t) X + b sin(t) Y as the rational quadratic arc of
    ``cagd.surfaces.revolution.arc_parameters`` (Piegl & Tiller A7.1; same point set
    and direction, another parametrisation). None for other curve types."""
    from cagd.surfaces.revolution import arc_parameters
    kind = type(curve).__name__
    if kind.startswith("Line2d"):
        p, q = curve.value(first), curve.value(last)
        return cagd.BSplineCurve(np.array([[p.x, p.y], [q.x, q.y]]), 1, [first, first, last, last])
    if kind.startswith(("Circle2d", "ArcOfCircle2d")):
        a = b = float(curve.Radius)
    elif kind.startswith(("Ellipse2d", "ArcOfEllipse2d")):
        a, b = float(curve.MajorRadius), float(curve.MinorRadius)
    else:
        return None
    centre = np.array([curve.Location.x, curve.Location.y])
    x_axis = np.array([curve.XAxis.x, curve.XAxis.y])
    y_axis = np.array([curve.YAxis.x, curve.YAxis.y])
    x_axis, y_axis = x_axis / np.linalg.norm(x_axis), y_axis / np.linalg.norm(y_axis)
    cos_f, sin_f, w, knots = arc_parameters(first, last - first)
    P = centre + a * cos_f[:, None] * x_axis + b * sin_f[:, None] * y_axis
    return cagd.BSplineCurve(P, 2, first + (last - first) * knots, w)


def face_to_trimmed(face) -> Tuple["cagd.Surface", Optional[str]]:
    """The face as the engine sees it: ``(cagd.TrimmedSurface, None)`` on
    :func:`face_to_surface`'s surface bounded by the face's wires' pcurves (Part's
    ``curveOnSurface`` on the face's NURBS form, whose parameters are the engine
    surface's; loops oriented by the engine), or ``(untrimmed surface, None)`` when the
    boundary is the parameter box, or ``(untrimmed surface, reason)`` when the pcurves
    cannot make a valid trim (the caller reports the reason)."""
    from cagd.surfaces._trim_box import chained, into_window, is_box
    surface = face_to_surface(face)
    nf = face if isinstance(face.Surface, (Part.BSplineSurface, Part.BezierSurface)) else face.toNurbs().Faces[0]
    try:
        wires = [nf.OuterWire] + [w for w in nf.Wires if not w.isSame(nf.OuterWire)]
        loops = [[_pcurve(nf, e) for e in w.OrderedEdges] for w in wires]
        edges = [[_edge_curve(e, c) for e, c in zip(w.OrderedEdges, lp)] for w, lp in zip(wires, loops)]
        a, b, c, d = nf.Surface.bounds()        # a seam's two pcurves: chained by whole periods
        periods = (b - a if face.Surface.isUPeriodic() else float("inf"),
                   d - c if face.Surface.isVPeriodic() else float("inf"))
        loops = [into_window(chained(lp, periods), periods, surface.domain) for lp in loops if lp]
        if not loops or is_box(loops, surface.domain, periods=periods):
            return surface, None
        if len(edges) == len(loops):        # (no empty wire dropped: the rows match the loops)
            try:                            # the face's own 3-D edge curves, where they fit the constructor
                return cagd.TrimmedSurface(surface, loops, edges=edges), None
            except cagd.CagdError:
                pass
        return cagd.TrimmedSurface(surface, loops), None
    except Exception as exc:                # the untrimmed surface, with the reason reported
        return surface, f"trim not used ({type(exc).__name__}: {exc})"
