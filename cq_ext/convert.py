"""Engine objects <-> CadQuery and build123d shapes, through the exact OCCT bridge.

Neither library is imported at module level: :func:`to_cq` imports CadQuery,
:func:`to_b3d` build123d, when called; :func:`from_shape` takes either library's
shapes (or bare OCCT shapes) by duck typing (:mod:`cagd.occ.wrapped`).
"""
from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, Callable, List, Union

import numpy as np
from OCP.TopAbs import TopAbs_COMPOUND, TopAbs_EDGE, TopAbs_FACE, TopAbs_SHELL, TopAbs_WIRE

from cagd.curves.base import Curve
from cagd.errors import CagdError
from cagd.occ import from_occ, make_edge, make_face, subshapes
from cagd.occ.wrapped import describe, is_shape, occ_shapes
from cagd.surfaces.base import Surface

if TYPE_CHECKING:                               # pragma: no cover
    import build123d as bd
    import cadquery as cq

_CONTAINERS = (TopAbs_COMPOUND, TopAbs_SHELL, TopAbs_WIRE)


def plane_map(plane: "cq.Plane", dim: int):
    """(A, b) taking a workplane's local coordinates (2-D or 3-D) to global ones: the
    images of the unit vectors under ``plane.toWorldCoords``, as CadQuery maps the
    points of its own ``spline`` (which makes xDir perpendicular to the normal)."""
    b = np.array(plane.toWorldCoords((0.0, 0.0, 0.0)).toTuple())
    A = np.column_stack([np.array(plane.toWorldCoords(tuple(e)).toTuple()) - b for e in np.eye(3)])
    return A[:, :dim], b


def placed(obj: Union[Curve, Surface], plane: "cq.Plane") -> Union[Curve, Surface]:
    """The engine object moved from the workplane's local coordinates to global ones
    (an affine map of its defining points: exact)."""
    A, b = plane_map(plane, obj.dim)
    return obj.transformed(A, b)


def _occ(obj: Union[Curve, Surface], nurbs: bool = False):
    if isinstance(obj, Curve):
        return make_edge(obj)
    if isinstance(obj, Surface):
        return make_face(obj, nurbs=nurbs)
    raise CagdError(f"obj: expected a cagd Curve or Surface, got {describe(obj)}")


def to_cq(obj: Union[Curve, Surface], nurbs: bool = False) -> Union["cq.Edge", "cq.Face"]:
    """A CadQuery ``Edge`` (curves) or ``Face`` with natural bounds (surfaces) holding
    the object's exact OCCT B-spline; spheres, tori, cylinders, cones and other
    surfaces of revolution get OCCT's analytic surface (the same point set, by angle;
    what CadQuery's ``shell`` and :func:`cq_ext.thicken` need) unless ``nurbs=True``
    (see :func:`cagd.occ.make_face`). A :class:`cagd.TrimmedSurface` gives the trimmed
    face: its surface's B-spline bounded by wires of its loops' pcurves, with 3-D edges
    (:func:`cagd.occ.make_trimmed_face`; ``nurbs`` does not apply). Measure it with
    :func:`cagd.occ.area`: CadQuery's ``Face.Area()`` integrates at OCCT's default
    precision (on a disk trimmed from a B-spline square: 1.8e-4 relative off).

    Raises:
        CagdError: not an engine curve or surface, or OCCT refuses it.
    """
    shape = _occ(obj, nurbs)
    import cadquery as cq
    return cq.Shape.cast(shape)


def to_b3d(obj: Union[Curve, Surface], nurbs: bool = False) -> Union["bd.Edge", "bd.Face"]:
    """A build123d ``Edge`` or ``Face`` (see :func:`to_cq`); needs build123d only."""
    shape = _occ(obj, nurbs)
    import build123d as bd
    return bd.Edge(shape) if isinstance(obj, Curve) else bd.Face(shape)


def _kinds(shapes) -> str:
    counts = Counter(s.ShapeType().name[len("TopAbs_"):].lower() for s in shapes)
    return ", ".join(f"{n} {k}{'s' if n != 1 else ''}" for k, n in sorted(counts.items()))


def edge_or_face(shape, name: str = "shape"):
    """The one OCCT edge or face of a shape of any library: an edge or face itself, or
    the only face (else the only edge) of a compound, shell, wire, build123d
    ``Sketch``/``Curve`` or Workplane stack.

    Raises:
        CagdError: not a shape, or not exactly one edge or face in it.
    """
    shapes, found = occ_shapes(shape, name), []
    for s in shapes:
        if s.ShapeType() in _CONTAINERS:
            found += subshapes(s, TopAbs_FACE) or subshapes(s, TopAbs_EDGE)
        else:
            found.append(s)
    if len(found) == 1 and found[0].ShapeType() in (TopAbs_EDGE, TopAbs_FACE):
        return found[0]
    plain = len(found) == 1 and found[0] is getattr(shape, "wrapped", shape)     # a solid, a vertex, ...
    held = "" if plain else f" holding {_kinds(found) or 'no edge or face'}"
    raise CagdError(f"{name}: expected one edge or a face, got {describe(shape)}{held}")


def from_shape(shape, dim: int = 3):
    """The engine B-spline of an edge or face of CadQuery, build123d or OCCT (also a
    Workplane, compound, wire, build123d ``Sketch``/``Curve`` holding exactly one):
    any geometry OCCT converts to a B-spline, on the edge's range / the face's UV
    bounds (see :func:`cagd.occ.from_occ`). A face whose boundary is not its UV box
    keeps its trim: a :class:`cagd.TrimmedSurface` of its wires' pcurves (a plate with
    a hole: the outer loop and the hole).

    Raises:
        CagdError: not one edge or face, or geometry OCCT cannot convert.
    """
    return from_occ(edge_or_face(shape), dim)


def global_curve(item, name: str) -> Curve:
    """An engine curve (as it is) or an edge of any library as an engine curve.

    Raises:
        CagdError: naming ``name``: neither, or a face."""
    return item if isinstance(item, Curve) else _converted(item, name, Curve, "Curve or an edge", "a face")


def _converted(item, name: str, kind: type, wanted: str, other: str):
    """The engine object of an edge or face of any library, of type ``kind``."""
    if not is_shape(item):
        raise CagdError(f"{name}: expected a cagd {wanted}, got {describe(item)}")
    obj = from_occ(edge_or_face(item, name))
    if not isinstance(obj, kind):
        raise CagdError(f"{name}: expected a cagd {wanted}, got {describe(item)} ({other})")
    return obj


def untrimmed_surface(item, name: str) -> Surface:
    """An untrimmed engine surface (as it is) or an untrimmed face of any library as an
    engine surface, whose edges "u0", "u1", "v0", "v1" are those of its parameter box
    (a face's: OCCT's UV bounds), for the blends and matches.

    Raises:
        CagdError: naming ``name``: not a surface or face, or trimmed (a hole or a cut
            outline: its boundary is not its parameter box)."""
    from cagd.surfaces.trimmed import TrimmedSurface
    if isinstance(item, TrimmedSurface):
        raise CagdError(f"{name}: a TrimmedSurface; the edges u0, u1, v0, v1 exist only on the untrimmed "
                        "parameter box: pass its untrimmed surface")
    if isinstance(item, Surface):
        return item
    surface = _converted(item, name, Surface, "Surface or a face", "an edge")
    if isinstance(surface, TrimmedSurface):
        raise CagdError(f"{name}: a trimmed face (its boundary is not its UV box: a hole or a cut outline); the "
                        "edges u0, u1, v0, v1 exist only on the untrimmed parameter box, which is not this face's "
                        "boundary: blend or match an untrimmed face")
    return surface


def reported(method: str, result, what: str, log=None):
    """The engine result when it met its tolerance (its summary logged on ``log``); else
    CagdError naming ``what`` with the achieved accuracy (``fitCurve``'s convention)."""
    if not result.converged:
        raise CagdError(f"{what}: {method}: {result.message}")
    if log is not None:
        log.info("%s: %s", method, result.message)
    return result


def curve_list(items, name: str, convert: Callable[[object, str], Curve] = global_curve) -> List[Curve]:
    """One curve or edge, or a sequence of them, as engine curves, each converted by
    ``convert(item, name[i])`` (default :func:`global_curve`).

    Raises:
        CagdError: naming ``name``: not a sequence, or an item ``convert`` refuses."""
    if isinstance(items, Curve) or is_shape(items):
        items = [items]
    try:
        items = list(items)
    except TypeError:
        raise CagdError(f"{name}: expected a sequence of curves or edges, got {describe(items)}") from None
    return [convert(c, f"{name}[{i}]") for i, c in enumerate(items)]

