"""Geometric queries (seed 004, ch. 1 §4, positional relations between shapes):
closest points, minimum distance, intersections, deviation analysis; global and
vectorized, with certified bounds where the issue asks for them. Surface-plane
sections and surface-surface intersections are marched branches fitted as B-splines
within a stated tolerance (:mod:`cagd.queries.intersect_surfaces`).
"""
from .bounds import BezierPieces, bezier_pieces
from .closest import ClosestPoints, Projector, closest_point
from .deviation import Deviation, deviation, deviation_map
from .distance import DistanceResult, min_distance
from .intersect import IntersectionPoint, IntersectionResult, Overlap, Plane, intersect, plane, self_intersections
from .intersect_surfaces import IntersectionCurve, SurfaceOverlap

__all__ = ["closest_point", "ClosestPoints", "Projector", "min_distance", "DistanceResult", "intersect",
           "self_intersections", "plane", "Plane", "IntersectionResult", "IntersectionPoint", "Overlap",
           "IntersectionCurve", "SurfaceOverlap",
           "deviation", "deviation_map", "Deviation", "bezier_pieces", "BezierPieces"]
