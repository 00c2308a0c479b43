"""Fitting: curves through points (interpolation), near points (least squares with a
given count) and within a tolerance of points (:func:`fit_curve`, the count chosen), and
the parameters of the points (:data:`PARAMETERS`, the one list of rule names)."""
from .fit import CurveFit, fit_curve
from .interpolation import (
    approximate,
    approximation_knots,
    bezier_through_points,
    interpolate,
    parametrize,
)
from .parameters import PARAMETERS, spline_parameters

__all__ = ["CurveFit", "PARAMETERS", "approximate", "approximation_knots", "bezier_through_points", "fit_curve",
           "interpolate", "parametrize", "spline_parameters"]
