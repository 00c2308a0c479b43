"""Intersections of curves with curves, surfaces and planes; self-intersections of a
curve (seed 004, ch. 1 §4, positional relations between shapes): the public entry
:func:`intersect`, which sends curve requests to :mod:`cagd.queries._point_solver`
(subdivision and Newton, points and overlaps) and surface–plane and surface–surface
requests to :mod:`cagd.queries.intersect_surfaces` (marched branches).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Union

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from . import _subdivision as sd
from .results import IntersectionResult

from ._point_solver import Plane, plane, plane_geometry, run
from .intersect_surfaces import surface_plane, surface_surface
from ._numerics import DEFAULT_ANGLE_TOL, DEFAULT_TOL, MIN_TOL_RTOL

__all__ = ["intersect", "self_intersections", "plane", "Plane"]


def intersect(a: Union[Curve, Surface, Plane], b: Union[Curve, Surface, Plane, None] = None,
              tol: float = DEFAULT_TOL, *,
              angle_tol: float = DEFAULT_ANGLE_TOL, max_depth: int = 64, max_pairs: int = 20000) -> IntersectionResult:
    """All intersections of ``a`` and ``b`` (curve–curve in any dimension, curve–surface,
    curve–plane); ``b`` omitted: the self-intersections of the curve ``a``.

    ``tol`` is a distance in model units: points are solved to a residual
    |a(x) - b(y)| <= ``tol``, pieces closer than ``tol`` are candidates, and an overlap
    is where one object stays within ``tol`` of the other; surface branches are fitted
    within ``tol`` of both surfaces. A contact is tangential when the angle between the
    tangents (curve–curve), between the curve and the tangent plane (curve–surface) or
    between the tangent planes (surface–surface) is at most ``angle_tol`` radians.
    Coincident pieces are returned as :class:`Overlap` intervals. Bounded: at most
    ``max_depth`` halvings and ``max_pairs`` live pairs; hitting a bound sets
    ``converged`` False.

    Surface–plane and surface–surface requests go to
    :mod:`cagd.queries.intersect_surfaces` (branches in ``curves``). A
    :class:`cagd.TrimmedSurface` is intersected as its face: the untrimmed answer with
    points outside the trim dropped, branches cut where they leave it (those ends
    'trim') and overlaps restricted to their cells on both faces, with their area
    (:func:`cagd.queries.trimmed.clip_to_trims`).

    Raises:
        CagdError: not curves/surfaces/planes, two planes, different dimensions,
            tol <= 0 or NaN, or tol below 1e-13 of the objects' size (beyond what
            doubles resolve there: the fitted branches would need ever more points),
            angle_tol < 0.
    """
    tol = _checks.positive(tol, "tol")
    from ..surfaces.trimmed import TrimmedSurface
    if isinstance(a, Plane) and not isinstance(b, Plane) and b is not None:     # as intersect(b, a), swapped
        return _swapped(intersect(b, a, tol, angle_tol=angle_tol, max_depth=max_depth, max_pairs=max_pairs))
    if isinstance(a, TrimmedSurface) or isinstance(b, TrimmedSurface):     # the faces: clipped to their trims
        from .trimmed import clip_to_trims
        res = intersect(a.untrimmed if isinstance(a, TrimmedSurface) else a,
                        b.untrimmed if isinstance(b, TrimmedSurface) else b, tol, angle_tol=angle_tol,
                        max_depth=max_depth, max_pairs=max_pairs)
        return clip_to_trims(res, a, b)
    if isinstance(a, Plane) and isinstance(b, Plane):
        raise CagdError("a, b: two planes: intersect them with their normals (a line or nothing), "
                        "not with this curve and surface query")
    sizes = [_extent(o, name) for o, name in ((a, "a"), (b, "b")) if o is not None and not isinstance(o, Plane)]
    if sizes and tol < MIN_TOL_RTOL * max(sizes):
        raise CagdError(f"tol: {tol:g} is below 1e-13 of the objects' size {max(sizes):.6g}, beyond the "
                        "precision of doubles there; pass a larger tol")
    angle_tol = _checks.angle(angle_tol)
    max_depth = _checks.integer(max_depth, "max_depth", 1, 200)
    max_pairs = _checks.integer(max_pairs, "max_pairs", 16)
    if b is None:
        if not isinstance(a, Curve):
            raise CagdError(f"a: self-intersection needs a cagd curve, got {type(a).__name__}")
        return run(sd.Geometry(a, "a"), None, tol, angle_tol, max_depth, max_pairs)
    assert not isinstance(a, Plane)         # plane first: answered above as intersect(b, a)
    if isinstance(b, Plane):
        if isinstance(a, Surface):
            return surface_plane(a, b, tol, angle_tol=angle_tol, max_pairs=max_pairs)
        A = sd.Geometry(a, "a")
        if A.dim != 3:
            raise CagdError(f"a: a plane lives in 3-D, the curve is {A.dim}-D")
        return run(A, plane_geometry(b, A), tol, angle_tol, max_depth, max_pairs)
    A, B = sd.Geometry(a, "a"), sd.Geometry(b, "b")
    if A.dim != B.dim:
        raise CagdError(f"a, b: objects of different dimension ({A.dim}-D and {B.dim}-D)")
    if A.k == 2 and B.k == 1:
        return _swapped(run(B, A, tol, angle_tol, max_depth, max_pairs))
    if A.k == 2:
        return surface_surface(A, B, tol, angle_tol=angle_tol, max_pairs=max_pairs)
    return run(A, B, tol, angle_tol, max_depth, max_pairs)


def _extent(obj: object, name: str) -> float:
    """The largest extent of the control net's box (>= the object's own; cheap: no
    Bezier decomposition, which the query then does once)."""
    if not isinstance(obj, (Curve, Surface)):
        raise CagdError(f"{name}: expected a cagd curve or surface, got {type(obj).__name__}")
    nurbs = obj.to_nurbs()
    return float(np.ptp(np.asarray(nurbs.control_points).reshape(-1, nurbs.dim), axis=0).max())


def self_intersections(curve: Curve, tol: float = DEFAULT_TOL, **kwargs: Any) -> IntersectionResult:
    """Points where a curve meets itself (pairs s < t with curve(s) = curve(t)), and
    pieces where it runs over itself as overlaps; ``tol`` a distance in model units, as
    for :func:`intersect`. The closing point of a closed curve (start = end) and cusps
    are not reported."""
    return intersect(curve, None, tol, **kwargs)


def _swapped(res: IntersectionResult) -> IntersectionResult:
    """The result of intersect(b, a) as that of intersect(a, b): every pair of a- and
    b-fields exchanged (points' parameters, curve overlaps' intervals, surface overlaps'
    boxes, branches' parameter curves and domains)."""
    def swap(x, pairs):
        fields = {f for f in getattr(x, "__dataclass_fields__", {})}
        change = {}
        for fa, fb in pairs:
            if fa in fields and fb in fields:
                change[fa], change[fb] = getattr(x, fb), getattr(x, fa)
        if "domains" in fields:
            change["domains"] = tuple(reversed(x.domains))
        return replace(x, **change)

    pairs = (("param_a", "param_b"), ("box_a", "box_b"), ("params_a", "params_b"))
    return replace(res, points=tuple(swap(p, pairs) for p in res.points),
                   overlaps=tuple(swap(o, pairs) for o in res.overlaps),
                   curves=tuple(swap(c, pairs) for c in res.curves))
