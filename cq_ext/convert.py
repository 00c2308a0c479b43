"""Engine objects <-> CadQuery and build123d shapes, through the exact OCCT bridge."""
from __future__ import annotations

from typing import Union

import cadquery as cq
import numpy as np

from cagd.curves.base import Curve
from cagd.errors import CagdError
from cagd.occ import from_occ, make_edge, make_face
from cagd.surfaces.base import Surface


def plane_map(plane: cq.Plane, dim: int):
    """(A, b) taking a workplane's local coordinates (2-D or 3-D) to global ones: the
    images of the unit vectors under ``plane.toWorldCoords``, as CadQuery maps the
    points of its own ``spline`` (which makes xDir perpendicular to the normal)."""
    b = np.array(plane.toWorldCoords((0.0, 0.0, 0.0)).toTuple())
    A = np.column_stack([np.array(plane.toWorldCoords(tuple(e)).toTuple()) - b for e in np.eye(3)])
    return A[:, :dim], b


def placed(obj: Union[Curve, Surface], plane: cq.Plane) -> Union[Curve, Surface]:
    """The engine object moved from the workplane's local coordinates to global ones
    (an affine map of its defining points: exact)."""
    A, b = plane_map(plane, obj.dim)
    return obj.transformed(A, b)


def to_cq(obj: Union[Curve, Surface], nurbs: bool = False) -> Union[cq.Edge, cq.Face]:
    """A CadQuery ``Edge`` (curves) or ``Face`` with natural bounds (surfaces) holding
    the object's exact OCCT B-spline; spheres, tori, cylinders, cones and other
    surfaces of revolution get OCCT's analytic surface (the same point set, by angle;
    what CadQuery's ``shell`` and :func:`cq_ext.thicken` need) unless ``nurbs=True``
    (see :func:`cagd.occ.make_face`).

    Raises:
        CagdError: not an engine curve or surface, or OCCT refuses it.
    """
    if isinstance(obj, Curve):
        return cq.Edge(make_edge(obj))
    if isinstance(obj, Surface):
        return cq.Face(make_face(obj, nurbs=nurbs))
    raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")


def to_b3d(obj: Union[Curve, Surface], nurbs: bool = False):
    """A build123d ``Edge`` or ``Face`` (see :func:`to_cq`)."""
    import build123d as bd
    if isinstance(obj, Curve):
        return bd.Edge(make_edge(obj))
    if isinstance(obj, Surface):
        return bd.Face(make_face(obj, nurbs=nurbs))
    raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")


def from_shape(shape, dim: int = 3):
    """The engine B-spline of a CadQuery or build123d edge or face (or a bare OCCT
    shape): any geometry OCCT converts to a B-spline, on the edge's range / the face's
    UV bounds (see :func:`cagd.occ.from_occ`).

    Raises:
        CagdError: not an edge or face, or geometry OCCT cannot convert.
    """
    wrapped = getattr(shape, "wrapped", shape)
    if isinstance(shape, cq.Workplane):
        objs = shape.vals()
        if len(objs) != 1:
            raise CagdError(f"shape: the workplane holds {len(objs)} objects, need exactly one edge or face")
        wrapped = objs[0].wrapped
    return from_occ(wrapped, dim)
