"""OCCT shapes from engine geometry: edges, wires, faces with natural bounds, sewn
shells, closed solids; validity (BRepCheck) and mass properties (BRepGProp). Every
function taking shapes takes CadQuery and build123d shapes too (:mod:`.wrapped`)."""
from __future__ import annotations

from typing import Iterable, List, Union

import numpy as np

from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeSolid,
                                BRepBuilderAPI_MakeWire, BRepBuilderAPI_NurbsConvert, BRepBuilderAPI_Sewing)
from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.BRepLib import BRepLib
from OCP.GeomAbs import GeomAbs_SurfaceOfExtrusion
from OCP.GProp import GProp_GProps
from OCP.Precision import Precision
from OCP.ShapeFix import ShapeFix_Shape
from OCP.TopAbs import (TopAbs_COMPOUND, TopAbs_COMPSOLID, TopAbs_EDGE, TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID,
                        TopAbs_VERTEX, TopAbs_WIRE, TopAbs_ShapeEnum)
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS_Edge, TopoDS_Face, TopoDS_Shape, TopoDS_Shell, TopoDS_Solid

from .compat import _cast, as_compound, as_edge, as_face, as_shell, as_solid, as_vertex, as_wire
from .._checks import positive
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from .analytic import analytic_form
from .convert import to_occ
from .trim import TrimmedSurface, make_trimmed_face
from .wrapped import describe, is_shape, occ_faces, occ_shape, occt_errors


# parameter ranges of an analytic face up to this are read by OCCT as closed (its
# Precision::PConfusion is 1e-9; measured: a revolution by 1.7e-10 rad became a whole
# turn, area 19.0 for 5.3e-10); such faces get the exact B-spline form instead
SLIVER_RANGE = 10 * Precision.PConfusion_s()




def _shape(shape, name: str = "shape") -> TopoDS_Shape:
    """A non-null OCCT shape (OCCT crashes on null shapes in many places): a
    TopoDS_Shape, or the one inside a CadQuery or build123d object (see
    :mod:`cagd.occ.wrapped`)."""
    return occ_shape(shape, name)


# the sub-shape types and their downcasts (TopAbs_SHAPE names no type: refused)
_CASTS = {TopAbs_COMPOUND: as_compound, TopAbs_COMPSOLID: _cast("CompSolid"), TopAbs_SOLID: as_solid,
          TopAbs_SHELL: as_shell, TopAbs_FACE: as_face, TopAbs_WIRE: as_wire, TopAbs_EDGE: as_edge,
          TopAbs_VERTEX: as_vertex}


def subshapes(shape: TopoDS_Shape, kind: TopAbs_ShapeEnum) -> list:
    """The sub-shapes of one type (TopAbs_FACE, TopAbs_EDGE, ...), downcast."""
    shape = _shape(shape)
    cast = _CASTS.get(kind) if isinstance(kind, TopAbs_ShapeEnum) else None
    if cast is None:
        raise CagdError(f"kind: expected one of {', '.join(k.name for k in _CASTS)}, got {kind!r}")
    out, ex = [], TopExp_Explorer(shape, kind)
    while ex.More():
        out.append(cast(ex.Current()))
        ex.Next()
    return out


def make_edge(curve: Curve) -> TopoDS_Edge:
    """The edge of an engine curve on its whole domain (its exact OCCT B-spline)."""
    if not isinstance(curve, Curve):
        raise CagdError(f"curve: expected a cagd Curve, got {type(curve).__name__}")
    maker = BRepBuilderAPI_MakeEdge(to_occ(curve))
    if not maker.IsDone():
        raise CagdError(f"curve: OCCT could not make an edge (error {maker.Error()})")
    return maker.Edge()


def make_wire(curves: Iterable[Union[Curve, TopoDS_Edge]]) -> TopoDS_Shape:
    """A wire of curves or edges (any iterable) joined end to end (in order, within
    their tolerances).

    Raises:
        CagdError: not an iterable, an empty one or pieces that do not connect.
    """
    try:
        curves = list(curves)
    except TypeError:
        raise CagdError(f"curves: expected a sequence of cagd curves or edges, got {type(curves).__name__}") from None
    if not curves:
        raise CagdError("curves: need at least one curve")
    maker = BRepBuilderAPI_MakeWire()
    for i, c in enumerate(curves):
        maker.Add(c if isinstance(c, TopoDS_Edge) else make_edge(c))
        if not maker.IsDone():
            raise CagdError(f"curves[{i}]: does not connect to the previous pieces (OCCT wire error {maker.Error()})")
    return maker.Wire()


def make_face(surface: Surface, tol: float = 1e-7, *, nurbs: bool = False) -> TopoDS_Face:
    """The face of an engine surface bounded by its natural (parameter-domain) boundary.
    Collapsed boundaries (poles of a revolution, the apex of a cone or of a triangle's
    NURBS form) become degenerated edges, closed directions a seam edge; ``tol`` is
    OCCT's tolerance for detecting them.

    A surface of revolution that remembers its construction (:func:`cagd.sphere`,
    :func:`cagd.torus`, :func:`cagd.cylinder`, :func:`cagd.cone`, :func:`cagd.revolve`)
    gets OCCT's own analytic surface (:mod:`cagd.occ.analytic`: the same point set,
    parametrised by the angle), bounded to the engine's range, the face oriented so
    that its normal is the engine's S_u x S_v: OCCT's offsets (thickening, shelling)
    work on it. ``nurbs=True`` gives the face of the exact B-spline instead (the same
    parametrisation as the engine: the exchange form STEP and IGES files get); so does
    a revolution through an angle of at most SLIVER_RANGE radians, which OCCT would
    read as a whole turn."""
    if not isinstance(surface, Surface):
        raise CagdError(f"surface: expected a cagd Surface, got {type(surface).__name__}")
    tol = positive(tol, "tol")
    if isinstance(surface, TrimmedSurface):                  # its own wires (cagd.occ.trim)
        return make_trimmed_face(surface, tol)
    form = None if nurbs else analytic_form(surface)
    if form is not None and min(form.bounds[1] - form.bounds[0], form.bounds[3] - form.bounds[2]) <= SLIVER_RANGE:
        form = None                 # OCCT would close a periodic direction: a full turn
    if form is None:
        maker = BRepBuilderAPI_MakeFace(to_occ(surface), tol)
    else:
        maker = BRepBuilderAPI_MakeFace(form.surface, *form.bounds, tol)
    if not maker.IsDone():
        raise CagdError(f"surface: OCCT could not make a face (error {maker.Error()})")
    face = maker.Face()
    return as_face(face.Reversed()) if form is not None and form.reversed else face


def face_list(items: Iterable, tol: float = 1e-6, *, nurbs: bool = False) -> List[TopoDS_Shape]:
    """The OCCT faces of engine surfaces (:func:`make_face`, ``nurbs`` as there; OCCT
    tolerance min(tol, 1e-7)) and of shapes of any library (their faces; see
    :mod:`.wrapped`).

    Raises:
        CagdError: an item that is neither, an item holding no face, nothing at all.
    """
    if isinstance(items, (Surface, str, bytes, np.ndarray)) or is_shape(items) or not hasattr(items, "__iter__"):
        items = [items]                                      # one item
    out = []
    for i, item in enumerate(items):
        if isinstance(item, Surface):
            out.append(make_face(item, min(tol, 1e-7), nurbs=nurbs))
        elif is_shape(item):
            out.extend(occ_faces(item, f"faces[{i}]"))
        else:
            raise CagdError(f"faces[{i}]: expected a cagd Surface, a CadQuery or build123d shape or a "
                            f"TopoDS_Shape, got {describe(item)}")
    if not out:
        raise CagdError("faces: nothing to sew")
    return out


def sewing(faces: Iterable[Union[Surface, TopoDS_Shape]], tol: float = 1e-6, *,
           nurbs: bool = False) -> BRepBuilderAPI_Sewing:
    """OCCT's sewing of faces (or engine surfaces, or the faces of shapes) whose edges
    meet within ``tol``, performed: ``SewedShape()``, ``NbFreeEdges()``, ``FreeEdge(i)``.
    Engine surfaces become faces by :func:`make_face` (``nurbs`` as there)."""
    tol = positive(tol, "tol")
    result = BRepBuilderAPI_Sewing(tol)
    for f in face_list(faces, tol, nurbs=nurbs):
        result.Add(f)
    result.Perform()
    return result


def sew(faces: Iterable[Union[Surface, TopoDS_Shape]], tol: float = 1e-6, *, nurbs: bool = False) -> TopoDS_Shape:
    """Sew faces (or engine surfaces) whose edges meet within ``tol`` into a shell
    (BRepBuilderAPI_Sewing); returns a shell, or a compound when they form several."""
    return sewing(faces, tol, nurbs=nurbs).SewedShape()


def free_edge_count(shape: TopoDS_Shape, tol: float = 1e-6) -> int:
    """Edges of ``shape`` that bound only one face (0 for a closed shell)."""
    result = BRepBuilderAPI_Sewing(positive(tol, "tol"))
    with occt_errors("shape", "sew the faces and count the free edges"):
        result.Load(_shape(shape))
        result.Perform()
        return result.NbFreeEdges()


def make_solid(shape: TopoDS_Shape, tol: float = 1e-6) -> TopoDS_Solid:
    """A solid from a closed shell, oriented so that its volume is positive.

    Raises:
        CagdError: not exactly one shell, the shell is open (the count of free edges
            is given), or the result is not a valid solid.
    """
    shape = _shape(shape)
    shells = subshapes(shape, TopAbs_SHELL)
    if not shells and shape.ShapeType() == TopAbs_FACE:      # one face closed on itself
        shell = TopoDS_Shell()
        builder = BRep_Builder()
        builder.MakeShell(shell)
        builder.Add(shell, shape)
        shell.Closed(BRep_Tool.IsClosed_s(shell))
        shells = [shell]
    if len(shells) != 1:
        raise CagdError(f"shape: need exactly one shell to make a solid, got {len(shells)} "
                        "(faces that did not sew within tol?)")
    free = free_edge_count(shells[0], tol)
    if free or not BRep_Tool.IsClosed_s(shells[0]):
        raise CagdError(f"shape: the shell is not closed: {free} free edge(s) after sewing with tol={tol:g}")
    solid = BRepBuilderAPI_MakeSolid(shells[0]).Solid()
    BRepLib.OrientClosedSolid_s(solid)
    if not check_valid(solid):
        fixer = ShapeFix_Shape(solid)
        fixer.Perform()
        solid = as_solid(subshapes(fixer.Shape(), TopAbs_SOLID)[0])
        if not check_valid(solid):
            raise CagdError("shape: OCCT reports the solid as invalid (BRepCheck), also after ShapeFix")
    return solid


def solid_from_surfaces(surfaces: Iterable[Union[Surface, TopoDS_Shape]], tol: float = 1e-6, *,
                        nurbs: bool = False) -> TopoDS_Solid:
    """Sew surfaces that bound a volume (the eight ellipsoid patches, a closed
    revolution, ...) and make the solid (see :func:`sew`, :func:`make_solid`)."""
    return make_solid(sew(surfaces, tol, nurbs=nurbs), tol)


def check_valid(shape: TopoDS_Shape) -> bool:
    """OCCT's BRepCheck_Analyzer verdict."""
    return bool(BRepCheck_Analyzer(_shape(shape)).IsValid())


_CONVERT = (GeomAbs_SurfaceOfExtrusion,)        # their NURBS form is exact (offsets' would not be)


def _integrated(shape: TopoDS_Shape, eps: float, volume: bool) -> float:
    """OCCT's adaptive integration (BRepGProp with relative precision ``eps``). Its
    error estimate is not to be trusted on every surface type: on the extrusion of a
    B-spline it reports 1e-16 and is off by 2e-3. A shape with such faces is
    integrated on its exact NURBS form (BRepBuilderAPI_NurbsConvert);
    others as they are (converting an analytic surface of revolution costs accuracy:
    5e-11 -> 1e-9 on a cylinder)."""
    eps, shape = positive(eps, "eps"), _shape(shape)
    if any(BRepAdaptor_Surface(f).GetType() in _CONVERT for f in subshapes(shape, TopAbs_FACE)):
        shape = BRepBuilderAPI_NurbsConvert(shape, True).Shape()
    props = GProp_GProps()
    if volume:
        BRepGProp.VolumeProperties_s(shape, props, eps)
    else:
        BRepGProp.SurfaceProperties_s(shape, props, eps)
    return props.Mass()


def area(shape: TopoDS_Shape, eps: float = 1e-13) -> float:
    """Surface area by OCCT's adaptive integration (see :func:`_integrated`)."""
    return _integrated(shape, eps, volume=False)


def volume(shape: TopoDS_Shape, eps: float = 1e-13) -> float:
    """Volume of a solid by OCCT's adaptive integration (see :func:`_integrated`)."""
    return _integrated(shape, eps, volume=True)
