"""The Workplane methods ``import cq_ext`` registers (CadQuery's plugin convention:
plain functions taking the Workplane as ``self``, attached to ``cq.Workplane``).

Engine geometry given by numbers is in the workplane's local coordinates (2-D or
3-D; tuples, arrays, CadQuery or build123d ``Vector``s), like the points of
CadQuery's own ``spline``; shapes of any library are taken as they are (global).

The stack, as CadQuery's own methods use it (:mod:`cq_ext.stack`):

- curves go on the stack as edges, replacing it, and are queued as pending edges
  (or a wire with ``makeWire``) for ``close``, ``extrude``, ``revolve``, ``sweep``
  and ``loft``, and for ``coonsPatch``, ``loftSurface`` and ``ruledSurface``, which
  consume them;
- surfaces are faces ADDED to the faces and shells already on the stack (like
  ``Workplane.add``): ``cagdSurface(a).cagdSurface(b)`` holds both, the new face
  last;
- network surfaces (``gordonSurface``, ``sweepSurface``, ``sweep2Surface``) take
  the curves given and fill the missing ones from the pending edges (consumed),
  else the pending wires (one curve each), else the edges on the stack;
  ``blendCurve`` queues its bridge like the curve methods (a curve given as None:
  the last or first pending edge); ``blendSurface`` and
  ``matchSurface`` add their face like the surface methods (``matchSurface``
  replacing the matched face when it is on the stack). Their achieved accuracy
  (``max_error``, angles) is logged on the ``cq_ext.workplane`` logger (INFO); an
  unmet tolerance raises CagdError with it, as ``fitCurve`` does;
- consumers (``sewSolid``, ``closeWithCaps``, ``thickenSurface``,
  ``projectPoints``, ``intersectFaces``) take the faces, shells, compounds and
  sketches on the stack and replace the stack with their result (the solid is not
  combined with solids earlier in the chain: use ``union``).
"""
from __future__ import annotations

import logging
import math
import warnings
from typing import Callable, List, Mapping, Optional, Sequence, Tuple, TypeVar, Union

import cadquery as cq
import numpy as np

import cagd
from cagd.curves.base import Curve
from cagd._deprecation import RELATIVE, renamed
from cagd.errors import CagdError
from cagd.occ import from_occ
from cagd.occ.wrapped import describe, occ_faces
from cagd.surfaces.base import Surface

from .convert import curve_list, from_shape, placed, plane_map, reported, to_cq, untrimmed_surface
from .cq_api import close_with_caps, sew_shell, sew_solid, thicken
from .solids import revolution_angle, revolution_face, revolution_input
from .stack import curve_of, faces_given_or_stacked, local_points, queued_curves, surface_objects, with_face
from .stack import points as as_points

LOG = logging.getLogger(__name__)                # achieved accuracy of the network, sweep and blend methods

# OCCT edges meet within its confusion tolerance (1e-7), so Coons corners of edges are
# checked that loosely (relative to the curves' size); engine curves use cagd's 1e-9
EDGE_CORNER_TOL = 1e-7

T = TypeVar("T", bound=cq.Workplane)
CurveLike = Union[Curve, cq.Edge, object]        # engine curves, edges of CadQuery, build123d or OCCT
FaceLike = Union[cq.Face, object]                # faces of CadQuery, build123d or OCCT
Points = Union[Sequence, np.ndarray]             # tuples, lists, arrays, CadQuery or build123d Vectors
Law = Union[float, Callable[[float], float], None]   # cagd.sweep's scale and twist laws of t in [0, 1]


def _push_curve(wp: T, curve: Curve, forConstruction: bool, makeWire: bool, name: str = "control_points") -> T:
    if curve.dim not in (2, 3):
        raise CagdError(f"{name}: a workplane curve needs 2-D or 3-D points, got {curve.dim}-D")
    return _push_edge(wp, to_cq(placed(curve, wp.plane)), forConstruction, makeWire)


def _push_edge(wp: T, edge: cq.Edge, forConstruction: bool, makeWire: bool) -> T:
    """The edge (global) on the stack, queued as a pending edge, or as a wire."""
    if makeWire:
        wire = cq.Wire.assembleEdges([edge])
        if not forConstruction:
            wp._addPendingWire(wire)
        return wp.newObject([wire])
    if not forConstruction:
        wp._addPendingEdge(edge)
    return wp.newObject([edge])


def cagdCurve(self: T, curve: Curve, forConstruction: bool = False, makeWire: bool = False) -> T:
    """Any engine curve (in local coordinates) as an edge on the stack."""
    if not isinstance(curve, Curve):
        raise CagdError(f"curve: expected a cagd Curve, got {describe(curve)}")
    return _push_curve(self, curve, forConstruction, makeWire, "curve")


def bezierCurve(self: T, control_points: Points, weights: Optional[Sequence[float]] = None,
                includeCurrent: bool = False, forConstruction: bool = False, makeWire: bool = False) -> T:
    """A (rational) Bezier curve on its control points (seed 000, 5.2)."""
    pts = local_points(self, control_points, includeCurrent, "control_points")
    return _push_curve(self, cagd.BezierCurve(pts, weights), forConstruction, makeWire)


def nurbsCurve(self: T, control_points: Points, degree: int = 3, knots: Optional[Sequence[float]] = None,
               weights: Optional[Sequence[float]] = None, periodic: bool = False, forConstruction: bool = False,
               makeWire: bool = False, includeCurrent: bool = False) -> T:
    """A B-spline or NURBS curve (knots as :class:`cagd.BSplineCurve`: the full vector,
    or one period when periodic; default clamped uniform)."""
    pts = local_points(self, control_points, includeCurrent, "control_points")
    curve = cagd.BSplineCurve(pts, degree, knots, weights, periodic)
    return _push_curve(self, curve, forConstruction, makeWire)


def interpCurve(self: T, points: Points, end_condition: str = "natural",
                parameters: Union[str, Sequence[float]] = "chord", tangents: Optional[Points] = None,
                includeCurrent: bool = False, forConstruction: bool = False, makeWire: bool = False,
                parametrization: Optional[str] = None) -> T:
    """The C2 cubic spline through the points (seed 000, 5.1.2): end conditions
    'natural', 'clamped' (with ``tangents`` = start and end tangent), 'periodic'
    (the first point need not be repeated at the end; the result is a closed wire);
    ``parameters`` 'chord', 'centripetal', 'uniform' or the values t_0 < ... < t_n
    (``parametrization=`` is its deprecated name)."""
    if parametrization is not None:
        parameters = renamed("interpCurve", "parametrization", "parameters", parametrization, parameters, "chord")
    pts = local_points(self, points, includeCurrent, "points")
    if end_condition == "periodic" and pts.ndim == 2 and len(pts) > 1 and not np.array_equal(pts[0], pts[-1]):
        pts = np.vstack([pts, pts[:1]])           # CadQuery's spline(periodic=True) convention
    tan = None if tangents is None else as_points(tangents, "tangents")
    curve = cagd.natural_cubic_spline(pts, end_condition, parameters, tangents=tan)
    return _push_curve(self, curve, forConstruction, makeWire or end_condition == "periodic", "points")


def hermiteCurve(self: T, p0: Points, p1: Points, t0: Points, t1: Points,
                 forConstruction: bool = False, makeWire: bool = False) -> T:
    """The cubic Hermite curve from p0 to p1 with end derivatives t0, t1 (seed 004, 1.3)."""
    ends = [as_points(v, n) for v, n in ((p0, "p0"), (p1, "p1"), (t0, "t0"), (t1, "t1"))]
    return _push_curve(self, cagd.HermiteCurve(*ends), forConstruction, makeWire)


def joinCurves(self: T, first: Union[Points, cagd.BezierCurve], continuity: str = "G2", alpha: float = 1.0,
               beta: float = 0.0, rest_points: Optional[Points] = None, forConstruction: bool = False) -> T:
    """A Bezier curve (control points or a BezierCurve) and the Bezier curve joined to
    its end with G1 or G2 continuity (seed 000, 5.2.5: alpha scales the end tangent,
    beta the curvature term); both go on the stack as edges, in order."""
    if not isinstance(first, cagd.BezierCurve):
        first = cagd.BezierCurve(as_points(first, "control_points"))
    rest = None if rest_points is None else as_points(rest_points, "rest_points")
    second = cagd.join(first, rest, continuity, alpha, beta)
    edges = [to_cq(placed(c, self.plane)) for c in (first, second)]
    if not forConstruction:
        for e in edges:
            self._addPendingEdge(e)
    return self.newObject(edges)


def cagdSurface(self: T, surface: Surface) -> T:
    """Any engine surface (local coordinates) as a face with natural bounds, added to
    the faces on the stack."""
    if not isinstance(surface, Surface):
        raise CagdError(f"surface: expected a cagd Surface, got {describe(surface)}")
    return with_face(self, to_cq(placed(surface, self.plane)))


def bezierSurface(self: T, points: Points, weights: Optional[Sequence] = None) -> T:
    """A (rational) tensor-product Bezier patch on an (m+1) x (n+1) grid of control points."""
    return cagdSurface(self, cagd.BezierSurface(as_points(points, "control_points"), weights))


def bsplineSurface(self: T, points: Points, degree_u: int = 3, degree_v: int = 3, interpolate: bool = False,
                   knots_u: Optional[Sequence[float]] = None, knots_v: Optional[Sequence[float]] = None,
                   weights: Optional[Sequence] = None, periodic_u: bool = False, periodic_v: bool = False) -> T:
    """A B-spline/NURBS surface from a grid of points: the control net, or with
    ``interpolate=True`` the surface through the points (averaged chord parameters)."""
    grid = as_points(points, "control_points")
    if interpolate:
        surface = cagd.interpolate_surface(grid, degree_u, degree_v)
    else:
        surface = cagd.BSplineSurface(grid, degree_u, degree_v, knots_u, knots_v, weights, periodic_u, periodic_v)
    return cagdSurface(self, surface)


def coonsPatch(self: T, *curves: CurveLike, rel_tol: float = EDGE_CORNER_TOL, tol: Optional[float] = None) -> T:
    """The bilinearly blended Coons patch (Farin 22.2) bounded by four curves given in
    any order and direction that form a loop: edges of any library or engine curves
    (local coordinates), or, with no arguments, the four pending edges of the curve
    methods before it (consumed), else the pending wires' edges, else the edges on
    the stack (e.g. ``.edges()`` of a face). The corners must meet within ``rel_tol``
    of the curves' size (:meth:`cagd.CoonsPatch.from_loop`; ``tol=`` is the
    deprecated name of this relative tolerance)."""
    if tol is not None:
        rel_tol = renamed("coonsPatch", "tol", "rel_tol", tol, rel_tol, EDGE_CORNER_TOL, RELATIVE)
    found, source, consume = queued_curves(self, curves, one_per_wire=False)
    if len(found) != 4:
        raise CagdError(f"curves: a Coons patch needs 4 boundary curves, got {len(found)} ({source})")
    face = to_cq(cagd.CoonsPatch.from_loop(found, rel_tol))
    consume()
    return with_face(self, face)


def loftSurface(self: T, *curves: CurveLike, degree_v: int = 3,
                parameters: Union[str, Sequence[float]] = "chord") -> T:
    """The skinned surface through section curves (Piegl & Tiller 10.3,
    :func:`cagd.loft`: S(u, v_k) is section k): the given curves (engine curves in
    local coordinates, edges of any library), or the pending edges (consumed), else
    one curve per pending wire, else the edges on the stack. ``degree_v`` needs at
    least degree_v + 1 sections; ``parameters`` 'chord', 'centripetal', 'uniform' or
    the values v_k."""
    found, source, consume = queued_curves(self, curves, one_per_wire=True)
    if len(found) < 2:
        raise CagdError(f"curves: a loft needs at least 2 section curves, got {len(found)} ({source})")
    face = to_cq(cagd.loft(found, degree_v, parameters))
    consume()
    return with_face(self, face)


def ruledSurface(self: T, c0: Optional[CurveLike] = None, c1: Optional[CurveLike] = None) -> T:
    """The ruled surface between two curves (Piegl & Tiller 8.4, :func:`cagd.ruled`:
    S(u, 0) = c0, S(u, 1) = c1): both given (engine curves in local coordinates, edges
    of any library), or neither: then the two pending edges (consumed), else the two
    pending wires, else the two edges on the stack."""
    if (c0 is None) != (c1 is None):
        raise CagdError(f"{'c1' if c1 is None else 'c0'}: give both curves or neither")
    if c0 is not None:
        found, consume = [curve_of(c, self.plane, n) for c, n in ((c0, "c0"), (c1, "c1"))], (lambda: None)
    else:
        found, source, consume = queued_curves(self, (), one_per_wire=True)
        if len(found) != 2:
            raise CagdError(f"curves: a ruled surface needs 2 curves, got {len(found)} ({source})")
    face = to_cq(cagd.ruled(*found))
    consume()
    return with_face(self, face)


def bezierTriangle(self: T, control_points: Union[Mapping[Tuple[int, int, int], Sequence[float]], Points],
                   weights: Optional[Union[Mapping[Tuple[int, int, int], float], Sequence[float]]] = None) -> T:
    """A (rational) Bezier triangle (seed 003, 3): {(i, j, k): point} or the flat list
    in :meth:`cagd.BezierTriangle.index_triples` order; the face is its exact
    collapsed-edge NURBS form."""
    if not isinstance(control_points, Mapping):
        control_points = as_points(control_points, "control_points")
    return cagdSurface(self, cagd.BezierTriangle(control_points, weights))


def revolveSurface(self: T, profile: CurveLike, angleDegrees: float = 360.0,
                   axisStart: Points = (0.0, 0.0, 0.0), axisEnd: Points = (0.0, 1.0, 0.0),
                   close: bool = False, nurbs: bool = False) -> T:
    """The surface of revolution of a profile (an engine curve in local coordinates, or
    an edge of any library) about the axis from ``axisStart`` to ``axisEnd`` (local;
    default the local y axis, as CadQuery's ``revolve``), added to the faces on the
    stack. ``close=True`` gives the solid instead, closed by planar caps where the
    profile ends off the axis.

    By default the face is OCCT's own surface of revolution of the profile's exact
    B-spline, the kind CadQuery's ``revolve`` makes, which OCCT's offsets
    (``shell``, ``thicken``) accept. ``nurbs=True`` puts the engine's rational NURBS
    form (:func:`cagd.revolve`) in the face instead: the same surface, parametrised
    by the rational circle; OCCT declares it C0 at the circle's double knots and its
    offset algorithm then fails, so keep it for export and exact NURBS exchange."""
    curve = curve_of(profile, self.plane, "profile")
    if curve.dim == 2:
        curve = curve.transformed(np.eye(3)[:, :2])
    a, b = (_global_point(self.plane, p, n) for p, n in ((axisStart, "axisStart"), (axisEnd, "axisEnd")))
    angleDegrees = revolution_angle(angleDegrees)
    revolution_input(curve, a, b)                   # before OCCT: it fails or loops on 1e300
    if nurbs:
        face = to_cq(cagd.revolve(curve, a, b - a, math.radians(angleDegrees)), nurbs=True)
    else:
        face = cq.Face(revolution_face(curve, a, b - a, angleDegrees))
    return self.newObject([close_with_caps([face])]) if close else with_face(self, face)


def _global_point(plane: cq.Plane, value, name: str) -> np.ndarray:
    p = as_points(value, name)
    if p.shape not in ((2,), (3,)):
        raise CagdError(f"{name}: expected a 2-D or 3-D point, got shape {p.shape}")
    A, b = plane_map(plane, p.shape[0])
    return A @ p + b


def sewSolid(self: T, tol: float = 1e-6) -> T:
    """Sew the faces and shells on the stack into a closed solid (the error lists the
    gaps)."""
    return self.newObject([sew_solid(surface_objects(self, "sewSolid"), tol)])


def closeWithCaps(self: T, tol: float = 1e-6) -> T:
    """Close the faces and shells on the stack with planar caps on their open loops: a
    solid."""
    return self.newObject([close_with_caps(surface_objects(self, "closeWithCaps"), tol)])


def thickenSurface(self: T, thickness: float, tol: float = 1e-6) -> T:
    """Thicken the faces and shells on the stack, sewn into one shell, into a solid
    (see :func:`cq_ext.thicken`)."""
    return self.newObject([thicken(surface_objects(self, "thickenSurface"), thickness, tol)])


def _engine_faces(objects, name: str) -> list:
    return [from_occ(f) for i, o in enumerate(objects) for f in occ_faces(o, f"{name}[{i}]")]


def projectPoints(self: T, points: Points, face: Optional[FaceLike] = None) -> T:
    """The closest points to the given points (local coordinates) on a face (``face``,
    of any library, or the faces on the stack: each point's nearest), as vertices on
    the stack: global, certified minima (:func:`cagd.closest_point` on the faces'
    exact B-splines, any OCCT B-spline-convertible face; their UV bounds, not their
    trimming)."""
    surfaces = _engine_faces(faces_given_or_stacked(self, face, "projectPoints"), "face")
    pts = np.atleast_2d(as_points(points, "points"))
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise CagdError(f"points: expected (N, 2) or (N, 3) local coordinates, got shape {pts.shape}")
    A, b = plane_map(self.plane, pts.shape[1])
    query = pts @ A.T + b
    results = [cagd.closest_point(s, query) for s in surfaces]
    best = np.argmin(np.stack([r.distances for r in results]), axis=0)
    feet = np.stack([r.feet for r in results])[best, np.arange(len(query))]
    return self.newObject([cq.Vertex.makeVertex(*map(float, f)) for f in feet])


def intersectFaces(self: T, other: Optional[FaceLike] = None, tol: float = 1e-7) -> T:
    """The intersection curves of two faces (the two faces on the stack, or the face on
    the stack and ``other``, of any library) as edges on the stack: each branch
    marched and fitted as a B-spline within ``tol`` of both surfaces
    (:func:`cagd.intersect`; any OCCT B-spline-convertible faces, over their UV
    bounds, not their trimming). Isolated touching points are not edges and are left
    out; coincident faces raise CagdError, and an intersection that did not converge
    warns (RuntimeWarning)."""
    on_stack = [o for o in self.objects if isinstance(o, (cq.Face, cq.Shell, cq.Compound))]
    faces = _engine_faces(on_stack, "stack") + (_engine_faces([other], "other") if other is not None else [])
    if len(faces) != 2:
        raise CagdError(f"intersectFaces: need exactly two faces (on the stack and other), got {len(faces)} "
                        f"(the stack holds {', '.join(describe(o) for o in self.objects) or 'nothing'})")
    result = cagd.intersect(faces[0], faces[1], tol=tol)
    if result.overlaps:
        raise CagdError(f"faces: they coincide over {len(result.overlaps)} region(s); there is no curve "
                        "of intersection there")
    unsure = [k for k, branch in enumerate(result.curves) if not branch.converged]
    if not result.converged or unsure:
        warnings.warn(f"intersectFaces: the intersection is not certain: {result.message or ''} "
                      f"{'branches ' + str(unsure) + ' did not meet tol' if unsure else ''}".strip(),
                      RuntimeWarning, stacklevel=2)
    return self.newObject([to_cq(branch.curve) for branch in result.curves])


def fitCurve(self: T, points: Optional[Points] = None, tol: float = 1e-3, degree: int = 3,
             parameters: Union[str, Sequence[float]] = "centripetal", start_tangent: Optional[Points] = None,
             end_tangent: Optional[Points] = None, max_control_points: Optional[int] = None,
             periodic: bool = False, forConstruction: bool = False, makeWire: bool = False) -> T:
    """A B-spline edge within ``tol`` of the points (:func:`cagd.fit_curve`, the fewest
    control points it finds; the error measured by certified closest points): the points
    given (local coordinates), or else the vertices on the stack in order (global).
    End tangent directions are held exactly when given; ``max_control_points`` caps the
    count; ``periodic`` fits a closed curve (C^(degree-1) at its seam; a closed wire).

    Raises:
        CagdError: no points, bad arguments, or ``tol`` not met (the message gives the
            achieved error; raise ``tol`` or give more control points' worth of data)."""
    if points is None:
        verts = [o for o in self.objects if isinstance(o, cq.Vertex)]
        if not verts:
            raise CagdError("points: none given and no vertices on the stack")
        P = np.array([v.toTuple() for v in verts], dtype=float)
        tangents = [None if t is None else np.array(as_points(t, n), float)
                    for t, n in ((start_tangent, "start_tangent"), (end_tangent, "end_tangent"))]
        fit = cagd.fit_curve(P, tol, degree, parameters, start_tangent=tangents[0], end_tangent=tangents[1],
                             max_control_points=max_control_points, periodic=periodic)
        curve = fit.curve
    else:
        P = local_points(self, points, False, "points")
        tangents = [None if t is None else as_points(t, n)
                    for t, n in ((start_tangent, "start_tangent"), (end_tangent, "end_tangent"))]
        fit = cagd.fit_curve(P, tol, degree, parameters, start_tangent=tangents[0], end_tangent=tangents[1],
                             max_control_points=max_control_points, periodic=periodic)
        curve = placed(fit.curve, self.plane)
    if not fit.converged:
        raise CagdError(f"tol: {fit.message}")
    edge = to_cq(curve)                                 # global already: not _push_curve (it places)
    if makeWire or periodic:
        wire = cq.Wire.assembleEdges([edge])
        if not forConstruction:
            self._addPendingWire(wire)
        return self.newObject([wire])
    if not forConstruction:
        self._addPendingEdge(edge)
    return self.newObject([edge])


def fitSurface(self: T, points: Points, tol: float = 1e-3, degree: Union[int, Tuple[int, int], str] = 3,
               parameters: str = "centripetal", max_control_points: Optional[Tuple[int, int]] = None,
               boundary: Optional[str] = None) -> T:
    """A B-spline face within ``tol`` of the points (:func:`cagd.fit_surface`: a grid
    (m, n, 3), or scattered points (N, 3) parametrised on their plane; local coordinates),
    added to the faces on the stack. ``degree``: per direction, a pair, or "auto" (each
    degree of ``cagd.fitting.fit_surface.AUTO_DEGREES`` tried, the fewest control points
    kept: the face's degree, named in the logged summary); ``max_control_points`` caps the
    counts (count_u, count_v); ``boundary="G0"`` holds a grid's boundary curves.

    Raises:
        CagdError: bad arguments, or ``tol`` not met (the message gives the achieved
            error, as ``fitCurve``'s)."""
    fit = _reported("fitSurface", cagd.fit_surface(as_points(points, "points"), tol, degree, parameters,
                                                   max_control_points, boundary=boundary), "tol")
    return cagdSurface(self, fit.surface)


def _stacked_geometry(wp: cq.Workplane, what: str) -> list:
    """The engine curve or surface of every edge and face on the stack (global)."""
    from .convert import from_shape
    items = [o for o in wp.objects if isinstance(o, (cq.Edge, cq.Face))]
    if not items:
        raise CagdError(f"{what}: no edges or faces on the stack")
    return [from_shape(o) for o in items]


def rebuild(self: T, count: Union[int, Tuple[int, int]], degree: Union[int, Tuple[int, int]] = 3) -> T:
    """Every edge and face on the stack rebuilt to ``count`` control points of ``degree``
    (a pair (u, v) for faces) by :func:`cagd.rebuild`; the stack becomes the new edges and
    faces. A trimmed face is refused (rebuild its untrimmed surface and trim again).

    Raises:
        CagdError: nothing on the stack, a trimmed face, bad count or degree."""
    out = []
    for obj in _stacked_geometry(self, "rebuild"):
        if isinstance(obj, cagd.TrimmedSurface):
            raise CagdError("rebuild: a trimmed face on the stack; rebuild its untrimmed surface "
                            "(cagd.rebuild(face.untrimmed, ...)) and trim it again")
        out.append(to_cq(cagd.rebuild(obj, count, degree).result))
    return self.newObject(out)


def removeKnots(self: T, tol: float) -> T:
    """Every edge and face on the stack with as many knots removed as keep it within
    ``tol`` of itself (Tiller's knot removal with its bound; faces in u, then in v); the
    stack becomes the new edges and faces.

    Raises:
        CagdError: nothing on the stack, a trimmed face, a bad tol."""
    out = []
    for obj in _stacked_geometry(self, "removeKnots"):
        if isinstance(obj, cagd.TrimmedSurface):
            raise CagdError("removeKnots: a trimmed face on the stack; remove knots from its untrimmed surface")
        if isinstance(obj, Surface):
            first = obj.remove_knots(0.5 * tol, "u")
            obj = first.result.remove_knots(tol - first.error_bound, "v").result
        else:
            obj = obj.remove_knots(tol).result
        out.append(to_cq(obj))
    return self.newObject(out)


# --- curve networks, sweeps and blends (issue 18) ---------------------------------------------
def _reported(method: str, result, what: str):
    """:func:`cq_ext.convert.reported` on this module's log."""
    return reported(method, result, what, LOG)


def _filled(wp: cq.Workplane, given: Sequence[Tuple[str, Optional[object]]], method: str
            ) -> Tuple[List[Curve], Callable[[], None]]:
    """The curves of ``given`` (name, curve or None): the given ones (engine curves in
    local coordinates, edges of any library), the missing ones taken in order from the
    pending edges, else the pending wires (one curve each), else the edges on the stack,
    which must hold exactly as many; and the function consuming the pending ones."""
    missing = [n for n, c in given if c is None]
    queued: List[Curve] = []
    consume: Callable[[], None] = lambda: None       # noqa: E731
    if missing:
        queued, source, consume = queued_curves(wp, (), one_per_wire=True)
        if len(queued) != len(missing):
            raise CagdError(f"{', '.join(missing)}: {method} takes {len(missing)} curve(s) from the pending edges "
                            f"or the stack, found {len(queued)} ({source})")
    it = iter(queued)
    return [curve_of(c, wp.plane, n) if c is not None else next(it) for n, c in given], consume


def _curve_list(wp: cq.Workplane, curves, name: str) -> List[Curve]:
    return curve_list(curves, name, lambda c, n: curve_of(c, wp.plane, n))


def gordonSurface(self: T, profiles: Optional[Sequence[CurveLike]] = None,
                  guides: Optional[Sequence[CurveLike]] = None, tol: float = 1e-6) -> T:
    """The Gordon surface through a network of curves (:func:`cagd.gordon`: every
    profile crosses every guide once, within ``tol``; u along the profiles, v along the
    guides): the curves of both families given (engine curves in local coordinates,
    edges of any library), or one family given and the other the pending edges
    (consumed), else one curve per pending wire, else the edges on the stack.

    Raises:
        CagdError: neither family given, the engine's refusals, or ``max_error`` above
            ``tol`` (the message gives it)."""
    if profiles is None and guides is None:
        raise CagdError("profiles, guides: give at least one family of curves; the other may be the pending edges")
    consume: Callable[[], None] = lambda: None       # noqa: E731
    families = []
    for name, given in (("profiles", profiles), ("guides", guides)):
        if given is None:
            found, source, consume = queued_curves(self, (), one_per_wire=True, name=name)
            if len(found) < 2:
                raise CagdError(f"{name}: a Gordon network needs at least 2 {name}, got {len(found)} ({source})")
            families.append(found)
        else:
            families.append(_curve_list(self, given, name))
    result = _reported("gordonSurface", cagd.gordon(families[0], families[1], tol=tol), "tol")
    face = to_cq(result.surface)
    consume()
    return with_face(self, face)


def _frame(wp: cq.Workplane, frame: Union[str, Points]) -> Union[str, np.ndarray]:
    if isinstance(frame, str):
        return frame
    up = as_points(frame, "frame")
    if up.shape not in ((2,), (3,)):
        raise CagdError(f"frame: expected 'rmf', 'frenet', 'fixed' or an up vector (2 or 3 numbers, local "
                        f"coordinates), got shape {up.shape}")
    A, _ = plane_map(wp.plane, len(up))
    return A @ up


def _profile_pieces(wp: cq.Workplane, profile, path) -> Optional[Tuple[List[Curve], Callable[[], None]]]:
    """The edges of a profile wire of several edges (given, or the one pending wire when
    only the path is given) as engine curves, with the function consuming the pending
    wire; None for a profile of one curve (:func:`_filled` takes it)."""
    if path is None:
        return None
    if profile is None:
        ctx = wp.ctx
        if ctx.pendingEdges or len(ctx.pendingWires) != 1 or len(ctx.pendingWires[0].Edges()) < 2:
            return None

        def consume():
            ctx.pendingWires = []
        return [from_shape(e) for e in ctx.pendingWires[0].Edges()], consume
    if isinstance(profile, cq.Shape) and not isinstance(profile, cq.Edge) and len(profile.Edges()) > 1:
        return [from_shape(e) for e in profile.Edges()], lambda: None
    return None


def sweepSurface(self: T, profile: Optional[CurveLike] = None, path: Optional[CurveLike] = None,
                 frame: Union[str, Points] = "rmf", scale: Law = None, twist: Law = None, tol: float = 1e-6) -> T:
    """The profile swept along the path (:func:`cagd.sweep`: frame "rmf"
    (rotation-minimising), "frenet", "fixed" or an up vector in local coordinates;
    ``scale`` and ``twist`` laws, constants or callables of t in [0, 1]; stations
    refined to ``tol``): the curves given (engine curves in local coordinates, edges of
    any library; the profile where it sits at the path's start), the missing ones the
    pending edges in order (consumed), else the pending wires (CadQuery's ``circle``),
    else the edges on the stack: ``circle(r).sweepSurface(path=edge)``. A profile wire
    of several edges (``rect(w, h).sweepSurface(path=edge)``, or a wire given) is swept
    edge by edge along the same path and frame, and the faces are sewn within 2 ``tol``
    into one shell on the stack.

    Raises:
        CagdError: the engine's refusals, missing curves, or ``max_error`` above ``tol``."""
    pieces = _profile_pieces(self, profile, path)
    if pieces is None:
        (prof, pth), consume = _filled(self, (("profile", profile), ("path", path)), "sweepSurface")
        profiles = [prof]
    else:
        profiles, consume = pieces
        pth = curve_of(path, self.plane, "path")
    faces = [to_cq(_reported("sweepSurface", cagd.sweep(prof, pth, frame=_frame(self, frame), scale=scale,
                                                        twist=twist, tol=tol), "tol").surface) for prof in profiles]
    consume()
    if len(faces) == 1:
        return with_face(self, faces[0])
    kept = [o for o in self.objects if isinstance(o, (cq.Face, cq.Shell))]
    return self.newObject(kept + [sew_shell(faces, 2.0 * tol)])     # each edge within tol: neighbours within 2 tol


def sweep2Surface(self: T, profiles: Union[CurveLike, Sequence[CurveLike], None] = None,
                  rail1: Optional[CurveLike] = None, rail2: Optional[CurveLike] = None, tol: float = 1e-6) -> T:
    """Profiles swept between two rails (:func:`cagd.sweep2`: each profile runs from
    rail1 to rail2, scaled to the chord between them): the curves given (engine curves
    in local coordinates, edges of any library); with the rails given and no profiles,
    the profiles are the pending edges (consumed), else the pending wires, else the
    edges on the stack; with profiles and no rails, those hold rail1 and rail2.

    Raises:
        CagdError: only one rail given, nothing given, the engine's refusals, or
            ``max_error`` above ``tol``."""
    if (rail1 is None) != (rail2 is None):
        raise CagdError(f"{'rail2' if rail2 is None else 'rail1'}: give both rails or neither")
    consume: Callable[[], None] = lambda: None       # noqa: E731
    if rail1 is None:
        if profiles is None:
            raise CagdError("profiles, rail1, rail2: give the profiles or the rails; the others may be the pending "
                            "edges")
        (r1, r2), consume = _filled(self, (("rail1", None), ("rail2", None)), "sweep2Surface")
        profs = _curve_list(self, profiles, "profiles")
    else:
        r1, r2 = curve_of(rail1, self.plane, "rail1"), curve_of(rail2, self.plane, "rail2")
        if profiles is None:
            profs, source, consume = queued_curves(self, (), one_per_wire=True, name="profiles")
            if not profs:
                raise CagdError(f"profiles: none given and none pending ({source})")
        else:
            profs = _curve_list(self, profiles, "profiles")
    result = _reported("sweep2Surface", cagd.sweep2(profs, r1, r2, tol=tol), "tol")
    face = to_cq(result.surface)
    consume()
    return with_face(self, face)


def _pending_end(wp: cq.Workplane, item: Optional[CurveLike], index: int, name: str) -> Curve:
    if item is not None:
        return curve_of(item, wp.plane, name)
    if not wp.ctx.pendingEdges:
        raise CagdError(f"{name}: not given and there are no pending edges to take it from")
    return from_shape(wp.ctx.pendingEdges[index])


def blendCurve(self: T, c1: Optional[CurveLike], end1: str, c2: Optional[CurveLike], end2: str,
               continuity: int = 1, tangent_scales: Optional[Sequence[float]] = None, forConstruction: bool = False,
               makeWire: bool = False) -> T:
    """The Bezier bridge from c1's ``end1`` to c2's ``end2`` ("start" or "end"), G1
    (cubic), G2 (quintic) or G3 (degree 7) to both (:func:`cagd.blend_curve`; tangent
    lengths automatic unless ``tangent_scales``), as an edge on the
    stack and queued as a pending edge like the curve methods. The curves are engine
    curves (local coordinates) or edges of any library; ``None`` takes c1 from the last
    pending edge and c2 from the first (left queued: with both ``None`` the bridge
    closes the pending chain, ready for ``wire()``).

    Raises:
        CagdError: the engine's refusals (naming c1, c2, end1, end2, continuity), a
            curve not given with no pending edges, or continuity not met within cagd's
            tolerance (the message gives the angles)."""
    a, b = _pending_end(self, c1, -1, "c1"), _pending_end(self, c2, 0, "c2")
    result = _reported("blendCurve", cagd.blend_curve(a, end1, b, end2, continuity, tangent_scales), "continuity")
    return _push_edge(self, to_cq(result.curve), forConstruction, makeWire)     # global already: not placed


def _surface_of(wp: cq.Workplane, item, name: str) -> Surface:
    """An engine surface (local coordinates) or a face of any library (global) as a
    global untrimmed engine surface (:func:`cq_ext.convert.untrimmed_surface`)."""
    if isinstance(item, Surface) and not isinstance(item, cagd.TrimmedSurface):
        return placed(item, wp.plane)
    return untrimmed_surface(item, name)


def blendSurface(self: T, face1: Union[Surface, FaceLike], edge1: str, face2: Union[Surface, FaceLike], edge2: str,
                 continuity: int = 1, tangent_scales: Optional[Sequence[float]] = None) -> T:
    """The surface bridging ``edge1`` of face1 and ``edge2`` of face2 ("u0", "u1",
    "v0", "v1" of their parameter boxes; a face's are OCCT's UV bounds, as
    :func:`cq_ext.from_shape` gives it), G1 (cubic across) or G2 (quintic) to both
    (:func:`cagd.blend_surface`): engine surfaces (local coordinates) or untrimmed
    faces of any library; the blend (v = 0 on edge1, v = 1 on edge2) is added to the
    faces on the stack.

    Raises:
        CagdError: a trimmed face, the engine's refusals (naming edge1, edge2,
            continuity, ...), or continuity not met within cagd's tolerance."""
    s1, s2 = _surface_of(self, face1, "face1"), _surface_of(self, face2, "face2")
    result = _reported("blendSurface", cagd.blend_surface(s1, edge1, s2, edge2, continuity, tangent_scales),
                       "continuity")
    return with_face(self, to_cq(result.surface))


def matchSurface(self: T, face: Union[Surface, FaceLike], edge: str, target: Union[Surface, FaceLike],
                 target_edge: str, continuity: int = 1) -> T:
    """``face`` modified next to its ``edge`` to meet ``target`` at ``target_edge``
    G0, G1 or G2 (:func:`cagd.match_surface`; edges "u0", "u1", "v0", "v1" of the
    parameter boxes, a face's as :func:`cq_ext.from_shape` gives it): engine surfaces
    (local coordinates) or untrimmed faces of any library. The matched face is added
    to the faces on the stack, replacing ``face`` there when it is on it.

    Raises:
        CagdError: a trimmed face, the engine's refusals (naming edge, target_edge,
            continuity, ...), or continuity not met within cagd's tolerance."""
    s, t = _surface_of(self, face, "face"), _surface_of(self, target, "target")
    result = _reported("matchSurface", cagd.match_surface(s, edge, t, target_edge, continuity), "continuity")
    matched = to_cq(result.surface)
    stacked = [o for o in self.objects if isinstance(o, (cq.Face, cq.Shell))]
    if isinstance(face, cq.Shape):
        stacked = [o for o in stacked if not o.isSame(face)]
    return self.newObject(stacked + [matched])


METHODS = [cagdCurve, bezierCurve, nurbsCurve, interpCurve, hermiteCurve, joinCurves, cagdSurface, bezierSurface,
           bsplineSurface, coonsPatch, loftSurface, ruledSurface, bezierTriangle, revolveSurface, sewSolid,
           closeWithCaps, thickenSurface, projectPoints, intersectFaces, fitCurve, fitSurface, rebuild, removeKnots,
           gordonSurface, sweepSurface, sweep2Surface, blendCurve, blendSurface, matchSurface]
