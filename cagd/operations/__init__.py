"""Operations on curves: Bezier joins and continuity analysis at joints."""
from .continuity import ContinuityReport, continuity, curve_size
from .blend import BlendCurve, blend_curve, curvature_variation
from .join import join, join_bezier, join_control_points

__all__ = ["ContinuityReport", "continuity", "curve_size", "join", "join_bezier", "join_control_points",
           "BlendCurve", "blend_curve", "curvature_variation"]
from .sweep import SweepResult, sweep, sweep2
from .blend_surface import BlendSurface, MatchSurface, blend_surface, match_surface

__all__ += ["SweepResult", "sweep", "sweep2", "BlendSurface", "MatchSurface", "blend_surface", "match_surface"]
