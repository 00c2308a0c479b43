"""Fitting: curves through points (interpolation), near points (least squares with a
given count), within a tolerance of points (:func:`fit_curve`, the count chosen), curves
and surfaces rebuilt to a chosen size (:func:`rebuild`), and the parameters of the
points (:data:`PARAMETERS`, the one list of rule names)."""
from .fit import CurveFit, fit_curve
from .rebuild import Rebuild, rebuild
from .interpolation import (
    approximate,
    approximation_knots,
    bezier_through_points,
    interpolate,
    parametrize,
)
from .parameters import PARAMETERS, spline_parameters

__all__ = ["CurveFit", "PARAMETERS", "Rebuild", "rebuild", "approximate", "approximation_knots",
           "bezier_through_points", "fit_curve", "interpolate", "parametrize", "spline_parameters"]
