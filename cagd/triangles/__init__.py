"""Total-degree (triangular) Bezier patches (seed 003, 3): evaluation, blossoms,
subdivision, degree elevation, continuity across a shared edge, exact NURBS form."""
from .basis import index_triples, triangle_bernstein
from .bezier_triangle import BezierTriangle
from .continuity import TriangleContinuity, c1_neighbor, neighbor_vertices, triangle_continuity

__all__ = ["BezierTriangle", "index_triples", "triangle_bernstein", "TriangleContinuity",
           "triangle_continuity", "c1_neighbor", "neighbor_vertices"]
