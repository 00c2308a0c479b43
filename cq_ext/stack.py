"""What the Workplane methods read from their arguments and from the CadQuery stack.

Points: sequences of CadQuery or build123d ``Vector``s (or ``Vertex``es), tuples,
lists or numpy arrays, 2-D or 3-D, in the workplane's local coordinates.

The stack, as CadQuery's own methods use it: curves are queued as pending edges
(``ctx.pendingEdges``, or wires in ``ctx.pendingWires``) that the next consumer
takes and clears (CadQuery's ``wire()``, ``close()``, here ``coonsPatch``,
``loftSurface``, ``ruledSurface``); surfaces are faces on the stack (``objects``).
"""
from __future__ import annotations

from collections import Counter
from typing import Callable, List, Optional, Sequence, Tuple

import cadquery as cq
import numpy as np

from cagd import _checks
from cagd.curves.base import Curve
from cagd.errors import CagdError
from cagd.occ.wrapped import describe, library

from .convert import from_shape, global_curve, placed

SURFACE_TYPES = (cq.Face, cq.Shell, cq.Compound, cq.Sketch)     # what surface consumers take from the stack


# --- points ----------------------------------------------------------------------------------
def _coords(value):
    """Nested sequences with every CadQuery/build123d Vector or Vertex as a tuple."""
    if isinstance(value, (np.ndarray, str, bytes)) or np.isscalar(value):
        return value
    as_tuple = getattr(value, "toTuple", None)                   # CadQuery Vector, Vertex
    if callable(as_tuple):
        return as_tuple()
    if library(value) == "build123d" and hasattr(value, "X"):    # build123d Vector, Vertex
        return (value.X, value.Y, value.Z)
    if hasattr(value, "__iter__"):
        return [_coords(v) for v in value]
    return value


def points(value, name: str) -> np.ndarray:
    """The coordinates of ``value`` as a float array (any shape; the caller checks it).

    Raises:
        CagdError: not numbers, vectors or sequences of them; NaN or inf.
    """
    if value is None:
        raise CagdError(f"{name}: expected points, got None")
    return _checks.finite_array(_coords(value), name)


def current_point(wp: cq.Workplane) -> np.ndarray:
    """The workplane's current point in local coordinates (CadQuery's
    ``_findFromPoint``: the end of the last edge, or the last vector or vertex)."""
    try:
        return np.array(wp._findFromPoint(True).toTuple(), dtype=float)
    except ValueError:
        raise CagdError(f"includeCurrent: there is no current point: the last object on the stack is "
                        f"{describe(wp.objects[-1])}") from None


def local_points(wp: cq.Workplane, value, include_current: bool, name: str) -> np.ndarray:
    """Points in local coordinates; with ``include_current`` the current point first
    (then one point may be given alone as a 1-D sequence; 2-D points are lifted to
    z = 0 when the current point is off the workplane)."""
    pts = points(value, name)
    if not include_current:
        return pts
    pts = pts[None, :] if pts.ndim == 1 else pts
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise CagdError(f"{name}: expected 2-D or 3-D points, got shape {pts.shape}")
    first = current_point(wp)
    if pts.shape[1] == 2 and first[2] == 0.0:
        first = first[:2]
    elif pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    return np.vstack([first, pts])


# --- the stack ---------------------------------------------------------------------------------
def contents(objects: Sequence) -> str:
    """What a list of stack objects holds, for messages: "2 Edge, 1 Vector" or "nothing"."""
    counts = Counter(type(o).__name__ for o in objects)
    return ", ".join(f"{n} {k}" for k, n in counts.items()) or "nothing"


def surface_objects(wp: cq.Workplane, what: str) -> list:
    """The faces, shells, compounds and sketches on the stack (CadQuery's
    ``_getFaces`` convention: other objects are left aside).

    Raises:
        CagdError: none on the stack; the message says what the stack holds.
    """
    found = [o for o in wp.objects if isinstance(o, SURFACE_TYPES)]
    if not found:
        raise CagdError(f"{what}: no faces or shells on the stack (it holds {contents(wp.objects)})")
    return found


def with_face(wp: cq.Workplane, face: cq.Shape) -> cq.Workplane:
    """A new workplane whose stack is the faces and shells already there plus ``face``
    (like ``Workplane.add``: a chain of surface methods keeps every surface)."""
    kept = [o for o in wp.objects if isinstance(o, (cq.Face, cq.Shell))]
    return wp.newObject(kept + [face])


def curve_of(item, plane: cq.Plane, name: str) -> Curve:
    """An engine curve (local coordinates, placed on the plane) or an edge of any
    library (global) as a global engine curve."""
    return placed(item, plane) if isinstance(item, Curve) else global_curve(item, name)


def _wire_curves(wire: cq.Wire, one_per_wire: bool, name: str) -> List[Curve]:
    edges = wire.Edges()
    if one_per_wire and len(edges) != 1:
        raise CagdError(f"{name}: a wire of {len(edges)} edges; give one curve per section")
    return [from_shape(e) for e in edges]


def queued_curves(wp: cq.Workplane, curves: Sequence, one_per_wire: bool, name: str = "curves"
                  ) -> Tuple[List[Curve], str, Callable[[], None]]:
    """The curves a surface is built from, the source's name and the function that
    consumes them: the given curves (engine curves in local coordinates, edges of
    any library), else the pending edges (CadQuery's queue of the curve methods), else
    the pending wires (each one curve if ``one_per_wire``, else all its edges), else
    the edges and wires on the stack. Pending ones are consumed (cleared, as
    CadQuery's ``wire()`` does) by calling the returned function once the surface is
    made."""
    ctx = wp.ctx
    if curves:
        return [curve_of(c, wp.plane, f"{name}[{i}]") for i, c in enumerate(curves)], "given", lambda: None
    if ctx.pendingEdges:
        def consume():
            ctx.pendingEdges, ctx.firstPoint = [], None
        return [from_shape(e) for e in ctx.pendingEdges], "pending edges", consume
    if ctx.pendingWires:
        def consume():
            ctx.pendingWires = []
        found = [c for i, w in enumerate(ctx.pendingWires) for c in _wire_curves(w, one_per_wire, f"{name}[{i}]")]
        return found, "pending wires", consume
    found = []
    for i, o in enumerate(wp.objects):
        if isinstance(o, cq.Edge):
            found.append(from_shape(o))
        elif isinstance(o, cq.Wire):
            found += _wire_curves(o, one_per_wire, f"{name}[{i}]")
    return found, f"edges on the stack, which holds {contents(wp.objects)}", lambda: None


def faces_given_or_stacked(wp: cq.Workplane, face: Optional[object], what: str) -> list:
    """``[face]`` when given, else the surface objects on the stack."""
    return [face] if face is not None else surface_objects(wp, what)
