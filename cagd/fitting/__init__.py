"""Fitting: curves through points (interpolation), near points (least squares with a
given count), within a tolerance of points (:func:`fit_curve`, :func:`fit_surface` for
grids, the counts chosen); curves and surfaces faired within a tolerance
(:func:`fair_curve`, :func:`fair_surface`) and rebuilt to a chosen size (:func:`rebuild`);
the parameters of the points (:data:`PARAMETERS`, the one list of rule names)."""
from .fair import Fairing, SurfaceFairing, fair_curve, fair_surface
from .fit import CurveFit, fit_curve
from .fit_surface import SurfaceFit, fit_surface
from .rebuild import Rebuild, rebuild
from .interpolation import (
    approximate,
    approximation_knots,
    bezier_through_points,
    interpolate,
    parametrize,
)
from .parameters import PARAMETERS, spline_parameters

__all__ = ["CurveFit", "Fairing", "PARAMETERS", "Rebuild", "SurfaceFairing", "SurfaceFit", "approximate",
           "approximation_knots", "bezier_through_points", "fair_curve", "fair_surface", "fit_curve", "fit_surface",
           "interpolate", "parametrize", "rebuild", "spline_parameters"]
