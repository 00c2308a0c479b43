"""cq_ext for build123d users, with or without CadQuery: engine objects to build123d
edges and faces (:func:`to_b3d`), any library's edges and faces back to engine
B-splines (:func:`from_shape`), and the solid helpers returning build123d shapes
(``Solid``, ``Shell``, ``Edge``): :func:`sew_solid`, :func:`sew_shell`,
:func:`close_with_caps`, :func:`thicken`, :func:`free_edges`. They take engine
surfaces and the shapes of build123d (``Face``, ``Shell``, ``Solid``, ``Part``,
``Sketch``, ``Curve``; ``BuildPart``/``BuildSketch``/``BuildLine`` contexts), of
CadQuery, and bare OCCT shapes. Works with build123d 0.12 (OCCT 7.9) and 0.13
(OCCT 8.0, where CadQuery cannot be installed alongside)::

    import cagd
    from cq_ext import b3d
    solid = b3d.sew_solid(cagd.ellipsoid(3, 2, 1.5))      # a build123d Solid
"""
from __future__ import annotations

import build123d as bd

from .convert import from_shape, to_b3d
from .solids import front_end, gap_report

sew_shell, sew_solid, close_with_caps, thicken, free_edges = front_end(bd.Shape.cast, "build123d", __name__)

__all__ = ["to_b3d", "from_shape", "sew_shell", "sew_solid", "close_with_caps", "thicken", "free_edges",
           "gap_report"]
