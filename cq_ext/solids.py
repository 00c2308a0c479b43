"""Solid modelling helpers: sew faces into a shell or solid (naming the gaps when it
fails), close a surface with planar caps (a surface of revolution whose profile
ends off the axis), thicken a surface into a solid. Every solid returned passes
OCCT's BRepCheck.

This module imports neither CadQuery nor build123d: the faces may be engine
surfaces and the shapes of either library (or bare OCCT shapes, see
:mod:`cagd.occ.wrapped`), and its functions return OCCT shapes. The functions
users call, returning CadQuery shapes (``cq_ext.sew_solid``, ...) or build123d
shapes (``cq_ext.b3d.sew_solid``, ...), are made by :func:`front_end` from a
library's ``Shape.cast``.
"""
from __future__ import annotations

import math
from typing import Callable, Iterable, List, NamedTuple, Union

import numpy as np
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepOffset import BRepOffset_MakeOffset, BRepOffset_Skin
from OCP.GCPnts import GCPnts_AbscissaPoint
from OCP.GeomAbs import GeomAbs_Arc
from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL, TopAbs_WIRE
from OCP.TopoDS import TopoDS_Edge, TopoDS_Face, TopoDS_Shape, TopoDS_Solid

from cagd.curves.base import Curve
from cagd.errors import CagdError
from cagd.occ import check_valid, make_face, make_solid, sewing, subshapes, volume
from cagd.occ.convert import occt_coordinates
from cagd.occ.shapes import face_list
from cagd.occ.wrapped import occ_edges, occt_errors
from cagd.surfaces.base import Surface
from cagd.surfaces.revolution import revolve

Faces = Union[Surface, object, Iterable[object]]     # surfaces, shapes of any library, or a list of them
_SIGN_EPS = 1e-3                                     # relative precision enough for the sign of a volume


def free_edges_of(sewn: BRepBuilderAPI_Sewing) -> List[TopoDS_Edge]:
    """The edges a performed sewing left unpaired."""
    return [sewn.FreeEdge(i) for i in range(1, sewn.NbFreeEdges() + 1)]


def unpaired_edges(faces: Faces, tol: float = 1e-6) -> List[TopoDS_Edge]:
    """The edges left unpaired after sewing the faces with ``tol`` (empty for a closed
    shell): the gaps and open boundaries."""
    return free_edges_of(sewing(faces, tol))


def _length_and_middle(edge) -> tuple:
    """Arc length and the point at half the arc length (GCPnts_AbscissaPoint)."""
    curve = BRepAdaptor_Curve(edge)
    length = GCPnts_AbscissaPoint.Length_s(curve)
    t = GCPnts_AbscissaPoint(curve, length / 2, curve.FirstParameter()).Parameter()
    p = curve.Value(t)
    return length, (p.X(), p.Y(), p.Z())


def gap_report(edges: List, limit: int = 8) -> str:
    """One line per free edge (any library's edges): length, midpoint and the distance
    to the nearest other free edge (a gap narrower than that would have been sewn with
    a larger tol)."""
    occ = [e for i, edge in enumerate(edges) for e in occ_edges(edge, f"edges[{i}]")]
    lines = []
    for i, e in enumerate(occ[:limit]):
        length, (x, y, z) = _length_and_middle(e)
        near = min((BRepExtrema_DistShapeShape(e, o).Value() for j, o in enumerate(occ) if j != i),
                   default=float("nan"))
        lines.append(f"  free edge {i}: length {length:.6g} at ({x:.6g}, {y:.6g}, {z:.6g}), "
                     f"nearest other free edge {near:.3g} away")
    if len(occ) > limit:
        lines.append(f"  ... and {len(occ) - limit} more")
    return "\n".join(lines)


def shell_of(faces: Faces, tol: float = 1e-6) -> TopoDS_Shape:
    """The faces sewn where their edges meet within ``tol``: a shell when they form one
    piece, else a compound."""
    return sewing(faces, tol).SewedShape()


def solid_of(faces: Faces, tol: float = 1e-6) -> TopoDS_Solid:
    """The solid bounded by the faces sewn into a closed shell.

    Raises:
        CagdError: the faces do not close within ``tol``; the message lists the free
            edges (length, position, nearest other free edge) to show the gaps.
    """
    sewn = sewing(faces, tol)
    if sewn.NbFreeEdges():
        edges = free_edges_of(sewn)
        raise CagdError(f"faces: the shell is not closed with tol={tol:g}: {len(edges)} free edge(s)\n"
                        + gap_report(edges))
    return _checked(make_solid(sewn.SewedShape(), tol))


def capped_solid(faces: Faces, tol: float = 1e-6) -> TopoDS_Solid:
    """The faces sewn, a planar face on each open boundary loop, and the solid.

    Raises:
        CagdError: an open boundary that is not a closed planar loop.
    """
    sewn = shell_of(faces, tol)
    bounds = ShapeAnalysis_FreeBounds(sewn, False, False)      # free bounds of the sewn (shared-edge) shell
    if _wires(bounds.GetOpenWires()):
        raise CagdError("faces: an open boundary does not form a closed loop")
    caps = []
    for wire in _wires(bounds.GetClosedWires()):
        maker = BRepBuilderAPI_MakeFace(wire, True)
        if not maker.IsDone():
            raise CagdError("faces: an open boundary loop is not planar; cannot cap it with a plane")
        caps.append(maker.Face())
    return solid_of([sewn] + caps, tol)


def _wires(compound) -> list:
    """The wires of a free-bounds compound (a null shape when there are none)."""
    return [] if compound.IsNull() else subshapes(compound, TopAbs_WIRE)


def _thickness(thickness) -> float:
    if isinstance(thickness, bool) or not isinstance(thickness, (int, float, np.floating, np.integer)) \
            or not thickness or not np.isfinite(thickness):
        raise CagdError(f"thickness: must be a finite non-zero number, got {thickness!r}")
    return float(thickness)


def thickened(faces: Faces, thickness: float, tol: float = 1e-6) -> TopoDS_Shape:
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
    thickness = _thickness(thickness)
    occ = face_list(faces, tol)
    shape = occ[0] if len(occ) == 1 else shell_of(occ, tol)
    if shape.ShapeType() not in (TopAbs_FACE, TopAbs_SHELL):
        raise CagdError(f"faces: they do not sew into one shell with tol={tol:g} ({shape.ShapeType().name}, "
                        f"{len(subshapes(shape, TopAbs_SHELL))} shells)")
    maker = BRepOffset_MakeOffset()
    with occt_errors("thickness", f"thicken the surface by {thickness}"):
        maker.Initialize(shape, thickness, tol, BRepOffset_Skin, False, False, GeomAbs_Arc, True)
        maker.MakeOffsetShape()
        if not maker.IsDone():
            raise CagdError(f"thickness: OCCT could not thicken the surface by {thickness} (offset error "
                            f"{maker.Error().name})")
        lost = [i for i, f in enumerate(subshapes(shape, TopAbs_FACE)) if maker.Generated(f).Size() == 0]
        if lost:
            raise CagdError(f"thickness: {thickness} collapses the offset of face(s) {lost}: OCCT left them out "
                            "(the thickness reaches a radius of curvature)")
        return _checked(maker.Shape())


def revolution_face(profile: Curve, axis_point, axis_direction, angle_degrees: float = 360.0) -> TopoDS_Face:
    """The face of :func:`cagd.revolve` as :func:`cagd.occ.make_face` makes it: OCCT's
    surface of revolution of the profile's exact B-spline (Geom_SurfaceOfRevolution),
    the same surface as the engine's NURBS form, parametrised by the angle; its normal
    is the engine's. A negative angle sweeps from ``angle_degrees`` up to 0.

    Raises:
        CagdError: a zero axis direction, an angle of 0 or beyond a full turn, or OCCT fails.
    """
    angle = math.radians(revolution_angle(angle_degrees))
    return make_face(revolve(profile, axis_point, axis_direction, abs(angle), min(angle, 0.0)))


def revolution_angle(angle_degrees) -> float:
    """A sweep angle in degrees: a finite non-zero number within a full turn.

    Raises:
        CagdError: naming ``angleDegrees``.
    """
    if isinstance(angle_degrees, bool) or not isinstance(angle_degrees, (int, float, np.integer, np.floating)) \
            or not angle_degrees or not np.isfinite(angle_degrees) or abs(angle_degrees) > 360.0:
        raise CagdError(f"angleDegrees: must be a finite non-zero number of degrees within a full turn "
                        f"(|angle| <= 360), got {angle_degrees!r}")
    return float(angle_degrees)


def revolution_input(profile: Curve, axis_point: np.ndarray, axis_end: np.ndarray) -> None:
    """The profile and the axis within OCCT's coordinate range (before OCCT sees them;
    :data:`cagd.occ.convert.MAX_COORDINATE`), the axis points distinct.

    Raises:
        CagdError: naming ``profile``, ``axisStart`` or ``axisEnd``.
    """
    occt_coordinates(profile.to_nurbs().control_points, "profile")
    occt_coordinates(axis_point, "axisStart")
    occt_coordinates(axis_end, "axisEnd")
    if not np.any(axis_end != axis_point):
        raise CagdError(f"axisStart, axisEnd: the same point {tuple(axis_point.tolist())}, no axis")


def _checked(solid: TopoDS_Shape) -> TopoDS_Shape:
    if not check_valid(solid):
        raise CagdError("the resulting solid is not valid (BRepCheck)")
    if volume(solid, _SIGN_EPS) < 0:
        raise CagdError("the resulting solid has negative volume (inside out)")
    return solid


class FrontEnd(NamedTuple):
    """The solid helpers returning one library's shapes."""
    sew_shell: Callable
    sew_solid: Callable
    close_with_caps: Callable
    thicken: Callable
    free_edges: Callable


def front_end(cast: Callable[[TopoDS_Shape], object], library: str, module: str) -> FrontEnd:
    """The user-facing solid helpers for one library: the functions above with their
    results passed through ``cast`` (the library's ``Shape.cast``), documented as
    returning that library's shapes and listed under ``module``."""
    def sew_shell(faces: Faces, tol: float = 1e-6):
        """Sew faces (engine surfaces, CadQuery or build123d faces, shells, solids,
        compounds, Workplanes, sketches, parts, or OCCT shapes) whose edges meet within
        ``tol``: a {lib} Shell when they form one piece, else a Compound."""
        return cast(shell_of(faces, tol))

    def sew_solid(faces: Faces, tol: float = 1e-6):
        """Sew faces (as :func:`sew_shell` takes them) into a closed shell and make the
        {lib} Solid.

        Raises:
            CagdError: the faces do not close within ``tol``; the message lists the
                free edges (length, position, nearest other free edge) to show the gaps.
        """
        return cast(solid_of(faces, tol))

    def close_with_caps(faces: Faces, tol: float = 1e-6):
        """Close an open shell by a planar face on each open boundary loop, then make
        the {lib} Solid: a surface of revolution whose profile ends off the axis gets
        two disks.

        Raises:
            CagdError: an open boundary that is not a closed planar loop.
        """
        return cast(capped_solid(faces, tol))

    def thicken(faces: Faces, thickness: float, tol: float = 1e-6):
        """The {lib} Solid of the given thickness grown from a face, or from faces
        sewn into one shell, along the normal (negative: the other side); see
        :func:`cq_ext.solids.thickened` (OCCT's offset, its limits).

        Raises:
            CagdError: a zero or non-finite thickness, faces that do not sew into one
                shell, or OCCT cannot build a valid solid.
        """
        return cast(thickened(faces, thickness, tol))

    def free_edges(faces: Faces, tol: float = 1e-6) -> list:
        """The {lib} Edges left unpaired after sewing the faces with ``tol`` (empty
        for a closed shell): the gaps and open boundaries."""
        return [cast(e) for e in unpaired_edges(faces, tol)]

    made = FrontEnd(sew_shell, sew_solid, close_with_caps, thicken, free_edges)
    for fn in made:
        fn.__doc__ = fn.__doc__.format(lib=library)
        fn.__module__, fn.__qualname__ = module, fn.__name__
    return made


__all__ = ["Faces", "FrontEnd", "front_end", "unpaired_edges", "gap_report", "shell_of", "solid_of",
           "capped_solid", "thickened", "revolution_face"]
