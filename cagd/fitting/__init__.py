"""Fitting: curves through points (interpolation) and near points (least squares)."""
from .interpolation import (
    approximate,
    approximation_knots,
    bezier_through_points,
    interpolate,
    parametrize,
)

__all__ = ["approximate", "approximation_knots", "bezier_through_points", "interpolate", "parametrize"]
