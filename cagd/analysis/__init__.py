"""Shape interrogation of curves: the curvature comb."""
from .comb import COMB_SIZE, CurvatureComb, curvature_comb

__all__ = ["COMB_SIZE", "CurvatureComb", "curvature_comb"]
