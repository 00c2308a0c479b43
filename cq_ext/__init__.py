"""CadQuery plugin and build123d helpers on the cagd engine.

``import cq_ext`` registers on ``cadquery.Workplane``: ``bezierCurve``,
``nurbsCurve``, ``interpCurve``, ``hermiteCurve``, ``joinCurves``, ``cagdCurve``,
``cagdSurface``, ``bezierSurface``, ``bsplineSurface``, ``coonsPatch``,
``bezierTriangle``, ``revolveSurface``, ``sewSolid``, ``closeWithCaps``,
``thickenSurface``, ``projectPoints``, ``intersectFaces`` (chainable, like the
built-in methods). Conversions:
:func:`to_cq`, :func:`to_b3d`, :func:`from_shape`; solids: :func:`sew_solid`,
:func:`sew_shell`, :func:`close_with_caps`, :func:`thicken`, :func:`free_edges`.
Geometry reaches OCCT through :mod:`cagd.occ` (exact B-spline form).
"""
import cadquery as cq

from .convert import from_shape, placed, to_b3d, to_cq
from .solids import close_with_caps, free_edges, gap_report, sew_shell, sew_solid, thicken
from .workplane import (METHODS, bezierCurve, bezierSurface, bezierTriangle, bsplineSurface, cagdCurve, cagdSurface,
                        closeWithCaps, coonsPatch, hermiteCurve, interpCurve, intersectFaces, joinCurves, nurbsCurve,
                        projectPoints, revolveSurface, sewSolid, thickenSurface)

for _method in METHODS:
    setattr(cq.Workplane, _method.__name__, _method)

__all__ = ["to_cq", "to_b3d", "from_shape", "placed", "sew_shell", "sew_solid", "close_with_caps", "thicken",
           "free_edges", "gap_report"] + [m.__name__ for m in METHODS]
