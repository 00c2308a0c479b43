"""Shape interrogation: the curvature comb, curve fairness, surface quality maps."""
from .comb import COMB_SIZE, CurvatureComb, curvature_comb
from .fairness import Fairness, fairness
from .surface_maps import Isophotes, Zebra, curvature_map, draft_angle, isophotes, zebra

__all__ = ["COMB_SIZE", "CurvatureComb", "curvature_comb", "Fairness", "fairness", "Isophotes", "Zebra",
           "curvature_map", "draft_angle", "isophotes", "zebra"]
