"""cagd: classical computer-aided geometric design in numpy.

Surfaces: tensor-product Bezier, B-spline and NURBS patches, revolution, Coons,
ruled and lofted surfaces, Bezier triangles; all exactly convertible to NURBS.
Curves: polynomial (algebraic form), Hermite, four-point, natural cubic splines,
Bezier, B-spline and NURBS, composite curves; each with vectorized evaluation,
derivatives of any order and an exact ``to_nurbs()``. Invalid input raises
:class:`CagdError` (a ValueError) naming the argument and the problem.
"""
from .errors import CagdError
from ._checks import MAX_DEGREE, MAX_ORDER
from .curves.base import Curve
from .curves.bspline import BSplineCurve, OccForm
from .curves.bezier import BezierCurve
from .curves.polynomial import HERMITE_M, HERMITE_M_INV, PolynomialCurve, four_point_cubic
from .curves.hermite import HermiteCurve, HermiteSpline, hermite_basis
from .curves.cubic_spline import CubicSpline, natural_cubic_spline
from .curves.composite import CompositeCurve
from .fitting import (CurveFit, Fairing, Rebuild, SurfaceFairing, SurfaceFit, approximate, bezier_through_points,
                      fair_curve, fair_surface, fit_curve, fit_surface, interpolate, parametrize, rebuild)
from .operations import ContinuityReport, continuity, join, join_bezier, join_control_points
from .surfaces.bspline import SurfaceOccForm
from .surfaces import (BezierSurface, BSplineSurface, CoonsPatch, HermiteCoonsPatch, Primitive, Revolution,
                       RevolvedSurface, Surface, cone, cylinder, ellipsoid, ellipsoid_octant, loft, make_compatible,
                       revolve, ruled, sphere, torus, EdgeContinuityReport, edge_continuity, interpolate_surface,
                       TrimEdgeContinuityReport, trim_edge_continuity,
                       TrimmedSurface, GordonSurface, gordon)
from .triangles import BezierTriangle, TriangleContinuity, c1_neighbor, triangle_continuity
from .queries import closest_point, deviation, intersect, min_distance, plane, self_intersections
from .analysis import CurvatureComb, curvature_comb
from .analysis import Fairness, Isophotes, Zebra, curvature_map, draft_angle, fairness, isophotes, zebra
from .operations import BlendCurve, blend_curve
from .operations import SweepResult, sweep, sweep2
from .operations import BlendSurface, MatchSurface, blend_surface, match_surface
from .mesh import MeshResult, write_obj, write_stl

__version__ = "0.1.0"
__all__ = [
    "CagdError", "MAX_DEGREE", "MAX_ORDER", "Curve", "BSplineCurve", "OccForm", "SurfaceOccForm", "BezierCurve",
    "PolynomialCurve", "four_point_cubic", "HERMITE_M", "HERMITE_M_INV",
    "HermiteCurve", "HermiteSpline", "hermite_basis", "CubicSpline", "natural_cubic_spline",
    "CompositeCurve", "approximate", "bezier_through_points", "interpolate", "parametrize", "fit_curve", "CurveFit",
    "rebuild", "Rebuild", "fit_surface", "SurfaceFit", "fair_curve", "Fairing", "fair_surface", "SurfaceFairing",
    "ContinuityReport", "continuity", "join", "join_bezier", "join_control_points",
    "Surface", "BezierSurface", "BSplineSurface", "CoonsPatch", "HermiteCoonsPatch", "RevolvedSurface",
    "Revolution", "Primitive", "revolve", "sphere", "torus", "cylinder", "cone", "ellipsoid", "ellipsoid_octant",
    "ruled", "loft", "make_compatible",
    "BezierTriangle", "TriangleContinuity", "triangle_continuity", "c1_neighbor",
    "EdgeContinuityReport", "edge_continuity", "interpolate_surface", "TrimmedSurface",
    "TrimEdgeContinuityReport", "trim_edge_continuity",
    "gordon", "GordonSurface",
    "closest_point", "min_distance", "intersect", "self_intersections", "plane", "deviation",
    "CurvatureComb", "curvature_comb",
    "Fairness", "Isophotes", "Zebra", "curvature_map", "draft_angle", "fairness", "isophotes", "zebra",
    "BlendCurve", "blend_curve",
    "SweepResult", "sweep", "sweep2",
    "BlendSurface", "MatchSurface", "blend_surface", "match_surface",
    "MeshResult", "write_stl", "write_obj",
]
