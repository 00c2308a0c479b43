"""The Workplane methods ``import cq_ext`` registers (CadQuery's plugin convention:
plain functions taking the Workplane as ``self``, attached to ``cq.Workplane``).

Engine geometry given by numbers is in the workplane's local coordinates (2-D or
3-D), like the points of CadQuery's own ``spline``; CadQuery shapes are taken as
they are (global). Curves go on the stack as edges, queued as pending edges (or a
wire with ``makeWire``) for ``close``, ``extrude``, ``revolve``, ``sweep`` and
``loft``; surfaces as faces.
"""
from __future__ import annotations

import math
import warnings
from typing import Mapping, Optional, Sequence, Tuple, TypeVar, Union

import cadquery as cq
import numpy as np

import cagd
from cagd.curves.base import Curve
from cagd.errors import CagdError
from cagd.surfaces.base import Surface

from .convert import from_shape, placed, plane_map, to_cq
from .solids import close_with_caps, revolution_face, sew_solid, thicken

T = TypeVar("T", bound=cq.Workplane)
CurveLike = Union[Curve, cq.Edge]


def _local_points(wp: cq.Workplane, points, includeCurrent: bool) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    if includeCurrent:
        cur = wp._findFromPoint(True)
        first = np.array(cur.toTuple()[:pts.shape[-1]]) if pts.ndim == 2 else None
        pts = np.vstack([first, pts])
    return pts


def _push_curve(wp: T, curve: Curve, forConstruction: bool, makeWire: bool) -> T:
    if curve.dim not in (2, 3):
        raise CagdError(f"control_points: a workplane curve needs 2-D or 3-D points, got {curve.dim}-D")
    edge = to_cq(placed(curve, wp.plane))
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
        raise CagdError(f"curve: expected a cagd Curve, got {type(curve).__name__}")
    return _push_curve(self, curve, forConstruction, makeWire)


def bezierCurve(self: T, control_points: Sequence, weights: Optional[Sequence[float]] = None,
                includeCurrent: bool = False, forConstruction: bool = False, makeWire: bool = False) -> T:
    """A (rational) Bezier curve on its control points (seed 000, 5.2)."""
    pts = _local_points(self, control_points, includeCurrent)
    return _push_curve(self, cagd.BezierCurve(pts, weights), forConstruction, makeWire)


def nurbsCurve(self: T, control_points: Sequence, degree: int = 3, knots: Optional[Sequence[float]] = None,
               weights: Optional[Sequence[float]] = None, periodic: bool = False,
               forConstruction: bool = False, makeWire: bool = False) -> T:
    """A B-spline or NURBS curve (knots as :class:`cagd.BSplineCurve`: the full vector,
    or one period when periodic; default clamped uniform)."""
    curve = cagd.BSplineCurve(control_points, degree, knots, weights, periodic)
    return _push_curve(self, curve, forConstruction, makeWire)


def interpCurve(self: T, points: Sequence, end_condition: str = "natural", parametrization: str = "chord",
                tangents: Optional[Sequence] = None, includeCurrent: bool = False,
                forConstruction: bool = False, makeWire: bool = False) -> T:
    """The C2 cubic spline through the points (seed 000, 5.1.2): end conditions
    'natural', 'clamped' (with ``tangents`` = start and end tangent), 'periodic'
    (the first point need not be repeated at the end; the result is a closed wire);
    parameters 'chord', 'centripetal' or 'uniform'."""
    pts = _local_points(self, points, includeCurrent)
    if end_condition == "periodic" and len(pts) > 1 and not np.array_equal(pts[0], pts[-1]):
        pts = np.vstack([pts, pts[:1]])           # CadQuery's spline(periodic=True) convention
    curve = cagd.natural_cubic_spline(pts, end_condition, parametrization, tangents=tangents)
    return _push_curve(self, curve, forConstruction, makeWire or end_condition == "periodic")


def hermiteCurve(self: T, p0: Sequence[float], p1: Sequence[float], t0: Sequence[float], t1: Sequence[float],
                 forConstruction: bool = False, makeWire: bool = False) -> T:
    """The cubic Hermite curve from p0 to p1 with end derivatives t0, t1 (seed 004, 1.3)."""
    return _push_curve(self, cagd.HermiteCurve(p0, p1, t0, t1), forConstruction, makeWire)


def joinCurves(self: T, first: Union[Sequence, cagd.BezierCurve], continuity: str = "G2", alpha: float = 1.0,
               beta: float = 0.0, rest_points: Optional[Sequence] = None, forConstruction: bool = False) -> T:
    """A Bezier curve (control points or a BezierCurve) and the Bezier curve joined to
    its end with G1 or G2 continuity (seed 000, 5.2.5: alpha scales the end tangent,
    beta the curvature term); both go on the stack as edges, in order."""
    first = first if isinstance(first, cagd.BezierCurve) else cagd.BezierCurve(first)
    second = cagd.join(first, rest_points, continuity, alpha, beta)
    edges = [to_cq(placed(c, self.plane)) for c in (first, second)]
    if not forConstruction:
        for e in edges:
            self._addPendingEdge(e)
    return self.newObject(edges)


def cagdSurface(self: T, surface: Surface) -> T:
    """Any engine surface (local coordinates) as a face with natural bounds."""
    if not isinstance(surface, Surface):
        raise CagdError(f"surface: expected a cagd Surface, got {type(surface).__name__}")
    return self.newObject([to_cq(placed(surface, self.plane))])


def bezierSurface(self: T, points: Sequence, weights: Optional[Sequence] = None) -> T:
    """A (rational) tensor-product Bezier patch on an (m+1) x (n+1) grid of control points."""
    return cagdSurface(self, cagd.BezierSurface(points, weights))


def bsplineSurface(self: T, points: Sequence, degree_u: int = 3, degree_v: int = 3, interpolate: bool = False,
                   knots_u: Optional[Sequence[float]] = None, knots_v: Optional[Sequence[float]] = None,
                   weights: Optional[Sequence] = None, periodic_u: bool = False, periodic_v: bool = False) -> T:
    """A B-spline/NURBS surface from a grid of points: the control net, or with
    ``interpolate=True`` the surface through the points (averaged chord parameters)."""
    if interpolate:
        surface = cagd.interpolate_surface(points, degree_u, degree_v)
    else:
        surface = cagd.BSplineSurface(points, degree_u, degree_v, knots_u, knots_v, weights, periodic_u, periodic_v)
    return cagdSurface(self, surface)


def _curves(wp: cq.Workplane, curves) -> list:
    """Engine curves (local, placed here) and CadQuery edges (global), or the edges
    on the stack when none are given."""
    items = list(curves) if curves else [o for o in wp.objects if isinstance(o, cq.Edge)]
    out = []
    for i, c in enumerate(items):
        if isinstance(c, Curve):
            out.append(placed(c, wp.plane))
        elif isinstance(c, cq.Edge):
            out.append(from_shape(c))
        else:
            raise CagdError(f"curves[{i}]: expected a cagd Curve or a CadQuery Edge, got {type(c).__name__}")
    return out


def coonsPatch(self: T, *curves: CurveLike, tol: float = 1e-7) -> T:
    """The bilinearly blended Coons patch (Farin 22.2) bounded by four curves given in
    any order and direction that form a loop: CadQuery edges or engine curves, or,
    with no arguments, the four edges on the stack (e.g. ``.edges()`` of a face)."""
    found = _curves(self, curves)
    if len(found) != 4:
        raise CagdError(f"curves: a Coons patch needs 4 boundary curves, got {len(found)}")
    return self.newObject([to_cq(cagd.CoonsPatch.from_loop(found, tol))])


def bezierTriangle(self: T, control_points: Union[Mapping[Tuple[int, int, int], Sequence[float]], Sequence],
                   weights: Optional[Union[Mapping[Tuple[int, int, int], float], Sequence[float]]] = None) -> T:
    """A (rational) Bezier triangle (seed 003, 3): {(i, j, k): point} or the flat list
    in :meth:`cagd.BezierTriangle.index_triples` order; the face is its exact
    collapsed-edge NURBS form."""
    return cagdSurface(self, cagd.BezierTriangle(control_points, weights))


def revolveSurface(self: T, profile: CurveLike, angleDegrees: float = 360.0,
                   axisStart: Sequence[float] = (0.0, 0.0, 0.0), axisEnd: Sequence[float] = (0.0, 1.0, 0.0),
                   close: bool = False, nurbs: bool = False) -> T:
    """The surface of revolution of a profile (an engine curve in local coordinates, or
    a CadQuery edge) about the axis from ``axisStart`` to ``axisEnd`` (local; default
    the local y axis, as CadQuery's ``revolve``). ``close=True`` gives the solid,
    closed by planar caps where the profile ends off the axis.

    By default the face is OCCT's own surface of revolution of the profile's exact
    B-spline, the kind CadQuery's ``revolve`` makes, which OCCT's offsets
    (``shell``, ``thicken``) accept. ``nurbs=True`` puts the engine's rational NURBS
    form (:func:`cagd.revolve`) in the face instead: the same surface, parametrised
    by the rational circle; OCCT declares it C0 at the circle's double knots and its
    offset algorithm then fails, so keep it for export and exact NURBS exchange."""
    if isinstance(profile, cq.Edge):
        curve = from_shape(profile)
    elif isinstance(profile, Curve):
        curve = placed(profile, self.plane)
    else:
        raise CagdError(f"profile: expected a cagd Curve or a CadQuery Edge, got {type(profile).__name__}")
    if curve.dim == 2:
        curve = curve.transformed(np.eye(3)[:, :2])
    a = np.array(self.plane.toWorldCoords(tuple(axisStart)).toTuple())
    b = np.array(self.plane.toWorldCoords(tuple(axisEnd)).toTuple())
    if nurbs:
        face = to_cq(cagd.revolve(curve, a, b - a, math.radians(angleDegrees)), nurbs=True)
    else:
        face = revolution_face(curve, a, b - a, angleDegrees)
    return self.newObject([close_with_caps([face]) if close else face])


def sewSolid(self: T, tol: float = 1e-6) -> T:
    """Sew the faces on the stack into a closed solid (the error lists the gaps)."""
    faces = [o for o in self.objects if isinstance(o, cq.Face)]
    return self.newObject([sew_solid(faces, tol)])


def closeWithCaps(self: T, tol: float = 1e-6) -> T:
    """Close the faces on the stack with planar caps on their open loops: a solid."""
    faces = [o for o in self.objects if isinstance(o, cq.Face)]
    return self.newObject([close_with_caps(faces, tol)])


def thickenSurface(self: T, thickness: float, tol: float = 1e-6) -> T:
    """Thicken the faces on the stack, sewn into one shell, into a solid (see
    :func:`cq_ext.thicken`)."""
    faces = [o for o in self.objects if isinstance(o, (cq.Face, cq.Shell))]
    if not faces:
        raise CagdError("thickenSurface: no face on the stack")
    return self.newObject([thicken(faces, thickness, tol)])


def _stack_faces(wp: cq.Workplane, faces) -> list:
    found = [f for f in (faces if faces else wp.objects) if isinstance(f, cq.Face)]
    if faces and len(found) != len(faces):
        raise CagdError("faces: expected CadQuery faces")
    return found


def projectPoints(self: T, points: Sequence[Sequence[float]], face: Optional[cq.Face] = None) -> T:
    """The closest points on a face (``face``, or the first face on the stack) to the
    given points (local coordinates), as vertices on the stack: global, certified
    minima (:func:`cagd.closest_point` on the face's exact B-spline, any OCCT
    B-spline-convertible face; the face's UV bounds, not its trimming)."""
    faces = _stack_faces(self, [face] if face is not None else None)
    if not faces:
        raise CagdError("projectPoints: no face given or on the stack")
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise CagdError(f"points: expected (N, 2) or (N, 3) local coordinates, got shape {pts.shape}")
    A, b = plane_map(self.plane, pts.shape[1])
    feet = cagd.closest_point(from_shape(faces[0]), pts @ A.T + b).feet
    return self.newObject([cq.Vertex.makeVertex(*map(float, f)) for f in feet])


def intersectFaces(self: T, other: Optional[cq.Face] = None, tol: float = 1e-7) -> T:
    """The intersection curves of two faces (the two faces on the stack, or the first
    face on the stack and ``other``) as edges on the stack: each branch marched and
    fitted as a B-spline within ``tol`` of both surfaces (:func:`cagd.intersect`; any
    OCCT B-spline-convertible faces, over their UV bounds, not their trimming).
    Isolated touching points are not edges and are left out; coincident faces raise
    CagdError, and an intersection that did not converge warns (RuntimeWarning)."""
    faces = _stack_faces(self, None) + ([other] if other is not None else [])
    if len(faces) != 2:
        raise CagdError(f"intersectFaces: need exactly two faces (stack + other), got {len(faces)}")
    result = cagd.intersect(from_shape(faces[0]), from_shape(faces[1]), tol=tol)
    if result.overlaps:
        raise CagdError(f"faces: they coincide over {len(result.overlaps)} region(s); there is no curve "
                        "of intersection there")
    unsure = [k for k, branch in enumerate(result.curves) if not branch.converged]
    if not result.converged or unsure:
        warnings.warn(f"intersectFaces: the intersection is not certain: {result.message or ''} "
                      f"{'branches ' + str(unsure) + ' did not meet tol' if unsure else ''}".strip(),
                      RuntimeWarning, stacklevel=2)
    return self.newObject([to_cq(branch.curve) for branch in result.curves])


METHODS = [cagdCurve, bezierCurve, nurbsCurve, interpCurve, hermiteCurve, joinCurves, cagdSurface, bezierSurface,
           bsplineSurface, coonsPatch, bezierTriangle, revolveSurface, sewSolid, closeWithCaps, thickenSurface,
           projectPoints, intersectFaces]
