"""Surfaces: tensor-product Bezier/B-spline/NURBS patches and their operations."""
from .base import Surface
from .bspline import BSplineSurface
from .bezier import BezierSurface

__all__ = ["Surface", "BSplineSurface", "BezierSurface"]
