"""CadQuery plugin and build123d helpers on the cagd engine.

With CadQuery installed, ``import cq_ext`` registers on ``cadquery.Workplane``:
``bezierCurve``, ``nurbsCurve``, ``interpCurve``, ``hermiteCurve``,
``joinCurves``, ``cagdCurve``, ``cagdSurface``, ``bezierSurface``,
``bsplineSurface``, ``coonsPatch``, ``loftSurface``, ``ruledSurface``,
``bezierTriangle``, ``revolveSurface``, ``sewSolid``, ``closeWithCaps``,
``thickenSurface``, ``projectPoints``, ``intersectFaces``, ``fitCurve``, ``fitSurface``, ``rebuild``,
``removeKnots``, ``gordonSurface``, ``sweepSurface``, ``sweep2Surface``,
``blendCurve``, ``blendSurface``, ``matchSurface`` (chainable, following
CadQuery's stack conventions: curves are pending edges that ``coonsPatch``,
``loftSurface``, ``ruledSurface`` and CadQuery's own ``close``/``extrude``/...
consume, and the network and sweep methods fill their missing curves from;
surfaces are added to the faces on the stack; see
:mod:`cq_ext.workplane`).

Conversions: :func:`to_cq`, :func:`to_b3d`, :func:`from_shape`; solids, returning
CadQuery shapes: :func:`sew_solid`, :func:`sew_shell`, :func:`close_with_caps`,
:func:`thicken`, :func:`free_edges`. :mod:`cq_ext.b3d` has the same solid helpers
returning build123d shapes, and with :func:`to_b3d` and :func:`from_shape` works
without CadQuery (build123d 0.13 on OCCT 8 cannot share a venv with CadQuery
2.8): there ``import cq_ext`` registers nothing and the CadQuery-only names raise
an AttributeError saying so. Every function taking shapes takes those of both
libraries (faces, shells, solids, compounds, Workplanes, parts, sketches, curves,
BuildPart/BuildSketch/BuildLine contexts) and bare OCCT shapes
(:mod:`cagd.occ.wrapped`). Geometry reaches OCCT through :mod:`cagd.occ` (exact
B-spline form).
"""
import importlib

from .convert import from_shape, placed, to_b3d, to_cq  # noqa: F401  (the public names: __all__ below)
from .solids import gap_report  # noqa: F401

_CADQUERY_ONLY = ["sew_shell", "sew_solid", "close_with_caps", "thicken", "free_edges"]
_NEUTRAL = ["to_b3d", "from_shape", "gap_report"]

try:
    import cadquery as _cq
except ImportError as exc:          # build123d 0.13 (OCCT 8) venvs: no CadQuery
    _cq, CADQUERY_MISSING = None, f"{type(exc).__name__}: {exc}"
else:
    CADQUERY_MISSING = ""

if _cq is not None:
    from .cq_api import close_with_caps, free_edges, sew_shell, sew_solid, thicken  # noqa: F401
    from .workplane import (METHODS, bezierCurve, bezierSurface, bezierTriangle, blendCurve,  # noqa: F401
                            blendSurface, bsplineSurface, cagdCurve, cagdSurface, closeWithCaps, coonsPatch,
                            fitCurve, fitSurface, gordonSurface, hermiteCurve, interpCurve, intersectFaces, joinCurves,
                            loftSurface, matchSurface, nurbsCurve, projectPoints, rebuild, removeKnots,
                            revolveSurface, ruledSurface, sewSolid, sweep2Surface, sweepSurface, thickenSurface)

    for _method in METHODS:
        setattr(_cq.Workplane, _method.__name__, _method)
    __all__ = _NEUTRAL + ["to_cq", "placed"] + _CADQUERY_ONLY + [m.__name__ for m in METHODS]
else:
    __all__ = list(_NEUTRAL)


def __getattr__(name: str):
    """``cq_ext.b3d`` on first use (it imports build123d); a clear error for the
    CadQuery parts when CadQuery did not import."""
    if name == "b3d":
        return importlib.import_module(".b3d", __name__)
    if name in _CADQUERY_ONLY or name == "METHODS":
        raise AttributeError(f"cq_ext.{name} needs CadQuery, which did not import ({CADQUERY_MISSING}); "
                             f"build123d users: cq_ext.b3d.{name}")
    raise AttributeError(f"module 'cq_ext' has no attribute {name!r}")
