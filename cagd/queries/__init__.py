"""Geometric queries (seed 004, ch. 1 §4, positional relations between shapes):
closest points, minimum distance, intersections, deviation analysis; global and
vectorized, with certified bounds where the issue asks for them. Surface-plane
sections and surface-surface intersections are marched branches fitted as B-splines
within a stated tolerance (:mod:`cagd.queries.intersect_surfaces`).

Where each step lives:

- public entries: :mod:`.closest` (``closest_point``, ``Projector``), :mod:`.distance`
  (``min_distance``), :mod:`.intersect` (``intersect``, ``self_intersections``,
  ``plane``), :mod:`.deviation` (``deviation``, ``deviation_map``); their result types
  all in :mod:`.results`.
- decomposition and bounds: :mod:`.bounds` (Bezier pieces, the normalised ``Frame``,
  hull, derivative and second-order box bounds), :mod:`._hessian_hull` (the half
  Hessian's Bezier hull over a cell, polynomial and rational), :mod:`._subdivision` (homogeneous
  pieces, boxes, halving, for intersections and distances), :mod:`._symmetry` (bounds
  from a centre or axis of a continuum of minima), :mod:`._cells` (the closest-point
  cells in power form).
- local solvers: :mod:`._newton` (the three Newton iterations: closest points,
  two-object refinement, the intersection system; shared bound handling and step
  halving).
- intersections: :mod:`._point_solver` (curve requests: subdivision, roots,
  contacts), :mod:`._overlaps` / :mod:`._surface_overlaps` (coincident pieces),
  :mod:`.intersect_surfaces` with :mod:`._surface_system` (F = A - B and its
  Jacobian), :mod:`._marching` (predictor-corrector along a branch) and
  :mod:`._branch_fit` (branches as B-splines within tol).
- many objects: :mod:`._many` (closest points and deviations over a list: the nearest
  object per point, far objects dismissed by the box of their control net).
- trimmed faces: :mod:`.trimmed` (closest points, clipping of intersections),
  :mod:`._distance_trimmed` (minimum distance).
- :mod:`._numerics`: the named tolerances shared by all of these.
"""
from .bounds import BezierPieces, bezier_pieces
from .closest import Projector, closest_point
from .deviation import deviation, deviation_map
from .distance import min_distance
from .intersect import Plane, intersect, plane, self_intersections
from .results import (ClosestPoints, Deviation, DistanceResult, IntersectionCurve, IntersectionPoint,
                      IntersectionResult, Overlap, SurfaceOverlap)

__all__ = ["closest_point", "ClosestPoints", "Projector", "min_distance", "DistanceResult", "intersect",
           "self_intersections", "plane", "Plane", "IntersectionResult", "IntersectionPoint", "Overlap",
           "IntersectionCurve", "SurfaceOverlap",
           "deviation", "deviation_map", "Deviation", "bezier_pieces", "BezierPieces"]
