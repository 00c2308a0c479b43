"""The CadQuery side of cq_ext: the solid helpers returning CadQuery shapes
(``cq.Solid``, ``cq.Shell``, ``cq.Edge``). Imported by ``import cq_ext`` only when
CadQuery imports; see :mod:`cq_ext.b3d` for the same helpers returning build123d
shapes."""
from __future__ import annotations

import cadquery as cq

from .convert import from_shape, placed, plane_map, to_cq
from .solids import front_end

sew_shell, sew_solid, close_with_caps, thicken, free_edges = front_end(cq.Shape.cast, "CadQuery", __name__)

__all__ = ["to_cq", "from_shape", "placed", "plane_map", "sew_shell", "sew_solid", "close_with_caps", "thicken",
           "free_edges"]
