"""Solid modelling helpers: sew faces into a shell or solid (naming the gaps when it
fails), close a surface with planar caps (a surface of revolution whose profile
ends off the axis), thicken a surface into a solid. Every solid returned passes
CadQuery's ``isValid()`` (OCCT's BRepCheck)."""
from __future__ import annotations

import math
from typing import Iterable, List, Union

import cadquery as cq
import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.BRepOffset import BRepOffset_MakeOffset, BRepOffset_Skin
from OCP.GeomAbs import GeomAbs_Arc
from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
from OCP.TopAbs import TopAbs_FACE, TopAbs_WIRE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS_Shape

from cagd.errors import CagdError
from cagd.curves.base import Curve
from cagd.occ.compat import as_wire
from cagd.occ import make_face, make_solid, sewing, subshapes
from cagd.surfaces.base import Surface
from cagd.surfaces.revolution import revolve

FaceLike = Union[cq.Face, Surface, cq.Shape]


def _occ_faces(faces: Iterable[FaceLike]) -> list:
    out = []
    for i, f in enumerate(faces):
        if isinstance(f, Surface):
            out.append(make_face(f))
        elif isinstance(f, cq.Workplane):
            out += [v.wrapped for v in f.vals() if isinstance(v, cq.Shape)]
        elif isinstance(f, cq.Shape):
            out.append(f.wrapped)
        elif isinstance(f, TopoDS_Shape):
            out.append(f)
        else:
            raise CagdError(f"faces[{i}]: expected a CadQuery face/shape or a cagd Surface, got {type(f).__name__}")
    if not out:
        raise CagdError("faces: nothing to sew")
    return out


def _sewn(faces: Iterable[FaceLike], tol: float):
    """cagd.occ's sewing of the faces (CadQuery shapes and engine surfaces)."""
    return sewing(_occ_faces(faces), tol)


def free_edges(faces: Iterable[FaceLike], tol: float = 1e-6) -> List[cq.Edge]:
    """The edges left unpaired after sewing the faces with ``tol`` (empty for a closed
    shell): the gaps and open boundaries."""
    sewing = _sewn(faces, tol)
    return [cq.Edge(sewing.FreeEdge(i)) for i in range(1, sewing.NbFreeEdges() + 1)]


def gap_report(edges: List[cq.Edge], limit: int = 8) -> str:
    """One line per free edge: length, midpoint and the distance to the nearest other
    free edge (a gap narrower than that would have been sewn with a larger tol)."""
    lines = []
    for i, e in enumerate(edges[:limit]):
        mid = e.positionAt(0.5)
        others = [o for j, o in enumerate(edges) if j != i]
        near = min((e.distance(o) for o in others), default=float("nan"))
        lines.append(f"  free edge {i}: length {e.Length():.6g} at ({mid.x:.6g}, {mid.y:.6g}, {mid.z:.6g}), "
                     f"nearest other free edge {near:.3g} away")
    if len(edges) > limit:
        lines.append(f"  ... and {len(edges) - limit} more")
    return "\n".join(lines)


def sew_shell(faces: Iterable[FaceLike], tol: float = 1e-6) -> cq.Shape:
    """Sew faces (CadQuery faces or engine surfaces) whose edges meet within ``tol``:
    a ``cq.Shell`` when they form one piece, else a compound."""
    return cq.Shape.cast(_sewn(faces, tol).SewedShape())


def sew_solid(faces: Iterable[FaceLike], tol: float = 1e-6) -> cq.Solid:
    """Sew faces into a closed shell and make the solid.

    Raises:
        CagdError: the faces do not close within ``tol``; the message lists the free
            edges (length, position, nearest other free edge) to show the gaps.
    """
    faces = list(faces)
    sewing = _sewn(faces, tol)
    if sewing.NbFreeEdges():
        edges = [cq.Edge(sewing.FreeEdge(i)) for i in range(1, sewing.NbFreeEdges() + 1)]
        raise CagdError(f"faces: the shell is not closed with tol={tol:g}: {len(edges)} free edge(s)\n"
                        + gap_report(edges))
    return _checked(cq.Solid(make_solid(sewing.SewedShape(), tol)))


def close_with_caps(faces: Iterable[FaceLike], tol: float = 1e-6) -> cq.Solid:
    """Close an open shell by a planar face on each open boundary loop, then make the
    solid: a surface of revolution whose profile ends off the axis gets two disks.

    Raises:
        CagdError: an open boundary that is not a closed planar loop.
    """
    faces = _occ_faces(faces)
    sewn = _sewn(faces, tol).SewedShape()
    bounds = ShapeAnalysis_FreeBounds(sewn, False, False)      # free bounds of the sewn (shared-edge) shell
    caps = []
    for wire in _wires(bounds.GetClosedWires()):
        maker = BRepBuilderAPI_MakeFace(wire, True)
        if not maker.IsDone():
            raise CagdError("faces: an open boundary loop is not planar; cannot cap it with a plane")
        caps.append(maker.Face())
    if _wires(bounds.GetOpenWires()):
        raise CagdError("faces: an open boundary does not form a closed loop")
    return sew_solid([cq.Shape.cast(f) for f in faces + caps], tol)


def _wires(compound) -> list:
    out, ex = [], TopExp_Explorer(compound, TopAbs_WIRE)
    while ex.More():
        out.append(as_wire(ex.Current()))
        ex.Next()
    return out


def thicken(faces: Union[FaceLike, Iterable[FaceLike]], thickness: float, tol: float = 1e-6) -> cq.Solid:
    """A solid of the given thickness grown from a face, or from faces sewn into one
    shell (e.g. two patches joined with G1), along the normal (negative: the other
    side), by OCCT's offset algorithm (BRepOffset_MakeOffset in skin mode with
    thickening, arc joins). The offset is exact only for planes, spheres and the
    like; OCCT approximates the offset of a free-form B-spline within its tolerance
    (the result is checked valid; the tests compare its volume with area x thickness).
    OCCT's offset needs C1 surfaces as OCCT declares them: a knot of multiplicity =
    degree (e.g. the rational circle's double knots) makes it fail. Engine spheres,
    tori, cylinders, cones and revolutions become OCCT's analytic faces
    (:func:`cagd.occ.make_face`), which it offsets exactly.

    Raises:
        CagdError: a zero or non-finite thickness, faces that do not sew into one
            shell, or OCCT cannot build a valid solid (e.g. the thickness exceeds a
            radius of curvature: OCCT then leaves out the collapsed offset face and
            returns a valid solid without it, which is refused).
    """
    if isinstance(thickness, bool) or not isinstance(thickness, (int, float, np.floating, np.integer)) \
            or not thickness or not np.isfinite(thickness):
        raise CagdError(f"thickness: must be a finite non-zero number, got {thickness!r}")
    single = isinstance(faces, (cq.Shape, Surface, TopoDS_Shape, cq.Workplane))
    items = [faces] if single else list(faces)
    occ = _occ_faces(items)
    shape = occ[0] if len(occ) == 1 and occ[0].ShapeType().name == "TopAbs_FACE" else _sewn(occ, tol).SewedShape()
    if shape.ShapeType().name not in ("TopAbs_FACE", "TopAbs_SHELL"):
        raise CagdError(f"faces: they do not sew into one shell with tol={tol:g} ({shape.ShapeType().name})")
    maker = BRepOffset_MakeOffset()
    maker.Initialize(shape, float(thickness), tol, BRepOffset_Skin, False, False, GeomAbs_Arc, True)
    maker.MakeOffsetShape()
    if not maker.IsDone():
        raise CagdError(f"thickness: OCCT could not thicken the surface by {thickness} (offset error "
                        f"{maker.Error().name})")
    lost = [i for i, f in enumerate(subshapes(shape, TopAbs_FACE)) if maker.Generated(f).Size() == 0]
    if lost:
        raise CagdError(f"thickness: {thickness} collapses the offset of face(s) {lost}: OCCT left them out "
                        "(the thickness reaches a radius of curvature)")
    return _checked(cq.Shape.cast(maker.Shape()))


def revolution_face(profile: Curve, axis_point, axis_direction, angle_degrees: float = 360.0) -> cq.Face:
    """The face of :func:`cagd.revolve` as :func:`cagd.occ.make_face` makes it: OCCT's
    surface of revolution of the profile's exact B-spline (Geom_SurfaceOfRevolution),
    the same surface as the engine's NURBS form, parametrised by the angle; its normal
    is the engine's. A negative angle sweeps from ``angle_degrees`` up to 0.

    Raises:
        CagdError: a zero axis direction, an angle of 0 or beyond a full turn, or OCCT fails.
    """
    if not angle_degrees or not np.isfinite(angle_degrees):
        raise CagdError(f"angle: must be finite and non-zero, got {angle_degrees!r}")
    angle = math.radians(angle_degrees)
    return cq.Face(make_face(revolve(profile, axis_point, axis_direction, abs(angle), min(angle, 0.0))))


def _checked(solid: cq.Shape) -> cq.Solid:
    if not solid.isValid():
        raise CagdError("the resulting solid is not valid (BRepCheck)")
    if solid.Volume() < 0:
        raise CagdError("the resulting solid has negative volume (inside out)")
    return solid
