"""Fitting: curves through points (interpolation) and near points (least squares), and
the parameters of the points (:data:`PARAMETERS`, the one list of rule names)."""
from .interpolation import (
    approximate,
    approximation_knots,
    bezier_through_points,
    interpolate,
    parametrize,
)
from .parameters import PARAMETERS, spline_parameters

__all__ = ["PARAMETERS", "approximate", "approximation_knots", "bezier_through_points", "interpolate",
           "parametrize", "spline_parameters"]
