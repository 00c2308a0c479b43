"""Surfaces: tensor-product Bezier/B-spline/NURBS patches, surfaces of revolution,
the seed's rational ellipsoid, Coons patches, ruled surfaces, lofts and Gordon surfaces."""
from .base import Surface
from .bspline import BSplineSurface
from .bezier import BezierSurface
from .revolution import Primitive, Revolution, RevolvedSurface, cone, cylinder, revolve, sphere, torus
from .ellipsoid import ellipsoid, ellipsoid_octant
from .coons import CoonsPatch, HermiteCoonsPatch
from .loft import loft, loft_parameters, make_compatible, ruled
from .continuity import EdgeContinuityReport, edge_continuity
from .trim_continuity import TrimEdgeContinuityReport, trim_edge_continuity
from .fitting import interpolate_surface, surface_parameters
from .trimmed import AreaResult, TrimBoundary, TrimmedSurface
from .gordon import GordonSurface, gordon

__all__ = ["Surface", "BSplineSurface", "BezierSurface", "RevolvedSurface", "Revolution", "Primitive",
           "revolve", "sphere", "torus", "cylinder", "cone",
           "ellipsoid", "ellipsoid_octant", "CoonsPatch", "HermiteCoonsPatch", "ruled", "loft",
           "loft_parameters", "make_compatible", "EdgeContinuityReport", "edge_continuity",
           "TrimEdgeContinuityReport", "trim_edge_continuity",
           "interpolate_surface", "surface_parameters", "TrimmedSurface", "AreaResult", "TrimBoundary",
           "gordon", "GordonSurface"]
