"""Surface analysis overlay: a face (ours or any FreeCAD face Part can convert to a
B-spline) coloured by the engine's curvature map (Gaussian, mean, maximum or minimum
principal curvature), zebra stripes, isophotes or draft angle (cagd.analysis), all
computed at once (vectorized) on the vertices of a tessellation of the face
(:func:`face_mesh`): a parameter grid where the face is all of its surface over its
parameter box, else Part's own triangulation of the trimmed face with each vertex's
(u, v) found by the engine's certified closest point. The object stores the mesh and
the values; the view provider (viewproviders.AnalysisViewProvider) only draws them with
:func:`vertex_colors`.
"""
from __future__ import annotations

from typing import Tuple

import numpy as np

import FreeCAD as App

from . import conversion
from .conversion import cagd
from .features import Stateless, add, add_enum, report_traceback
from .inspection import colormap, linked_face

CURVATURES = ("gaussian", "mean", "max", "min")
KINDS = CURVATURES + ("zebra", "isophotes", "draft")
STRIPED = ("zebra", "isophotes")          # drawn as black and white bands
RESOLUTION = (48, 4, 1000, 1)             # grid points per direction: default, minimum, maximum, step
UNDEFINED_COLOR = (0.5, 0.5, 0.5)         # where the normal is undefined (NaN value)
DARK, LIGHT = (0.05, 0.05, 0.05), (1.0, 1.0, 1.0)
_ZERO_DIRECTION = 1e-12                   # a direction vector shorter than this is refused
WHOLE_BOX_RTOL = 1e-9                     # a face whose area is its parameter box's to this is untrimmed
DEFLECTION = 0.25                         # the mesh of a trimmed face: deflection = this x size / Resolution
ANGULAR_DEFLECTION = 0.1                  # ... and at most this angle (rad) between neighbouring normals
ON_SURFACE_RTOL = 1e-4                    # a vertex's foot farther than this x size: value undefined (a face
                                          # converted by toNurbs may lie 1e-6 x size off Part's: 11752.stp)
EDGE_TOLERANCE_FACTOR = 2.0               # ... or farther than this x the face's largest BRep tolerance (a
                                          # file's edge may leave its surface by its tolerance, 917_fusee.stp:
                                          # 0.022 mm, 8e-4 x size; the tolerance is sampled); and the least
                                          # deflection of Part's mesh, in the same multiples


def _unit(v, name: str) -> np.ndarray:
    d = np.array([v.x, v.y, v.z], dtype=float)
    length = float(np.linalg.norm(d))
    if not length > _ZERO_DIRECTION:
        raise cagd.CagdError(f"{name}: must be a non-zero vector, got {tuple(d)}")
    return d / length


def grid_mesh(surface, count: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(u, v, points, triangles) of a count x count parameter grid over the surface's
    domain: u, v (N,) row-major, points (N, 3) = S(u, v), triangles (2 (count-1)^2, 3)."""
    (u0, u1), (v0, v1) = surface.domain
    U, W = np.meshgrid(np.linspace(u0, u1, count), np.linspace(v0, v1, count), indexing="ij")
    u, v = U.ravel(), W.ravel()
    i, j = np.meshgrid(np.arange(count - 1), np.arange(count - 1), indexing="ij")
    a = (i * count + j).ravel()
    b, c, d = a + count, a + count + 1, a + 1
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return u, v, np.asarray(surface(u, v), dtype=float), triangles


def whole_box(face) -> bool:
    """True when the face is all of its surface over its parameter box: its area equals
    (to WHOLE_BOX_RTOL) that of Part's face of ``face.Surface`` on ``face.ParameterRange``
    (a hole, or an outer boundary other than the box, makes it smaller). Then the grid
    of :func:`grid_mesh` over the engine surface (conversion.face_to_surface, cut to that
    box) is the face exactly."""
    try:
        box = face.Surface.toShape(*face.ParameterRange).Area
    except Exception:             # a surface Part cannot bound by the box: treated as trimmed
        return False
    return abs(box - face.Area) <= WHOLE_BOX_RTOL * max(abs(box), abs(face.Area))


def face_mesh(face, surface, count: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(u, v, points, triangles) of the face as :func:`grid_mesh` gives them: the
    count x count grid of ``surface`` (the face's, conversion.face_to_surface) when the
    face is its whole parameter box (:func:`whole_box`), else Part's triangulation of the
    face itself (OCCT's mesher through FreeCAD's MeshPart, deflection DEFLECTION x size /
    count, size the face's bounding-box diagonal, but not below EDGE_TOLERANCE_FACTOR x
    the face's largest BRep tolerance, and ANGULAR_DEFLECTION; it respects the trims.
    Part's ``face.tessellate`` alone made 38,000 vertices of a 0.03 mm face of bearing.iges
    and ran for minutes at a finer deflection, MeshPart 1,221 in 0.03 s; MeshPart's
    vertices are single precision, so they are read back by ``face.tessellate``, which
    finds the face meshed to its deflection and returns the same mesh in double
    precision: 1e-5 off the surface, the sliver faces of bug24595_281390.stp took 70x
    longer to project) with each vertex's (u, v) on
    ``surface`` from the engine's vectorized, certified ``cagd.closest_point``; points
    are the feet S(u, v). Where a foot is farther from its vertex than both
    ON_SURFACE_RTOL x size and EDGE_TOLERANCE_FACTOR x the largest tolerance of the
    face's edges and vertices, (u, v) are NaN (the caller's values there are undefined)."""
    if whole_box(face):
        return grid_mesh(surface, count)
    size = float(face.BoundBox.DiagonalLength)
    tolerance = max([face.Tolerance] + [e.Tolerance for e in face.Edges] + [v.Tolerance for v in face.Vertexes])
    import MeshPart
    deflection = max(DEFLECTION * size / count, EDGE_TOLERANCE_FACTOR * tolerance)
    MeshPart.meshFromShape(Shape=face, LinearDeflection=deflection, AngularDeflection=ANGULAR_DEFLECTION,
                           Relative=False)
    vertices, facets = face.tessellate(deflection)
    P = conversion.array(vertices)
    triangles = np.asarray(facets, dtype=np.int64).reshape(-1, 3)
    if not len(P) or not len(triangles):
        raise cagd.CagdError("Face: the mesh of the face is empty (OCCT's mesher made no triangle)")
    feet = cagd.closest_point(surface, P)
    uv = np.array(feet.params, dtype=float)
    off = ~(np.asarray(feet.distances) <= max(ON_SURFACE_RTOL * size, EDGE_TOLERANCE_FACTOR * tolerance))
    uv[off] = np.nan
    points = np.where(off[:, None], P, np.asarray(feet.feet, dtype=float))
    return uv[:, 0], uv[:, 1], points, triangles


def analyse(surface, kind: str, u, v, direction=(0.0, 0.0, 1.0), view=(0.0, -1.0, 0.0),
            stripes: int = 8) -> Tuple[np.ndarray, np.ndarray]:
    """(values, bands) of ``kind`` at S(u, v), one engine call: a curvature (1/mm, signs
    as cagd.analysis.curvature_map), zebra phase with bands = lit (1/0), isophote value
    n.L with bands = the engine's band, or draft angle in degrees (``direction``: the
    light bars' direction, the light or the pull direction; ``view``: the view ray for
    zebra). NaN values (band -1) where the normal is undefined or (u, v) is NaN."""
    u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
    known = np.isfinite(u) & np.isfinite(v)
    if not known.all():                      # evaluated where known, NaN / band -1 elsewhere
        values, bands = np.full(len(u), np.nan), np.full(len(u), -1.0)
        if known.any():
            values[known], bands[known] = analyse(surface, kind, u[known], v[known], direction, view, stripes)
        return values, bands
    if kind in CURVATURES:
        values = np.asarray(cagd.analysis.curvature_map(surface, u, v, kind), dtype=float)
        return values, np.zeros_like(values)
    if kind == "zebra":
        z = cagd.analysis.zebra(surface, u, v, direction, view, stripes)
        return np.asarray(z.phase, dtype=float), np.where(z.defined, z.lit.astype(float), -1.0)
    if kind == "isophotes":
        iso = cagd.analysis.isophotes(surface, u, v, direction, stripes)
        return np.asarray(iso.value, dtype=float), np.asarray(iso.band, dtype=float)
    if kind == "draft":
        values = np.asarray(cagd.analysis.draft_angle(surface, u, v, direction, degrees=True), dtype=float)
        return values, np.zeros_like(values)
    raise cagd.CagdError(f"Kind: must be one of {', '.join(KINDS)}, got {kind!r}")


def symmetric_limit(values) -> float:
    """The symmetric colour range: the largest |value| (NaN ignored); 1 if none."""
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite)]
    return float(finite.max()) if finite.size and finite.max() > 0 else 1.0


def unit(kind: str) -> str:
    """The unit of ``kind``'s values: 1/mm for curvatures, deg for the draft angle."""
    return "deg" if kind == "draft" else "1/mm" if kind in CURVATURES else ""


def vertex_colors(kind: str, values, bands, limit: float) -> np.ndarray:
    """(N, 3) RGB per vertex: striped kinds black/white (zebra: lit white; isophotes:
    alternate bands), the others on the blue-green-red scale from -limit to +limit
    (inspection.colormap); grey where undefined."""
    values, bands = np.asarray(values, dtype=float), np.asarray(bands, dtype=float)
    if kind in STRIPED:
        on = bands > 0.5 if kind == "zebra" else np.mod(bands, 2) == 1
        rgb = np.where(on[:, None], LIGHT, DARK)
    else:
        rgb = colormap(np.nan_to_num(values), limit)
    return np.where((bands < 0)[:, None] | ~np.isfinite(values)[:, None], UNDEFINED_COLOR, rgb)


class SurfaceAnalysis(Stateless):
    """The analysis of one linked face (see the module doc)."""

    TYPE = "Cagd::SurfaceAnalysis"
    DEFAULT_LABEL = "SurfaceAnalysis"

    def __init__(self, obj):
        obj.Proxy = self
        add(obj, "LinkSub", "Face", "Analysis", "The face analysed (any face Part converts to a B-spline)")
        add_enum(obj, "Kind", "Analysis", "gaussian/mean/max/min curvature (1/mm), zebra stripes, isophotes, "
                 "draft angle (degrees)", KINDS, "gaussian")
        add(obj, "Vector", "Direction", "Analysis",
            "Zebra: the light bars' direction; isophotes: towards the light; draft: the pull direction",
            App.Vector(0, 0, 1))
        add(obj, "Vector", "ViewDirection", "Analysis", "Zebra: the view ray (eye to surface)", App.Vector(0, -1, 0))
        add(obj, "Integer", "Stripes", "Analysis", "Zebra: bars around the direction; isophotes: bands of n.L", 8)
        obj.addProperty("App::PropertyIntegerConstraint", "Resolution", "Analysis",
                        "Grid points per parameter direction of the tessellation (a trimmed face: Part's "
                        "mesh with deflection size / (4 Resolution))")
        obj.Resolution = RESOLUTION
        add(obj, "Float", "Range", "Analysis", "Values at the ends of the colour scale; 0 = symmetric, "
            "the largest |value|", 0.0)
        add(obj, "VectorList", "Coordinates", "Result", "Tessellation vertices")
        add(obj, "IntegerList", "Facets", "Result", "Triangles, three vertex indices each")
        add(obj, "FloatList", "Values", "Result", "The analysed quantity per vertex (NaN: normal undefined)")
        add(obj, "FloatList", "Bands", "Result", "Zebra: lit 1 / 0; isophotes: band; -1 undefined")
        add(obj, "Float", "Minimum", "Result", "Smallest value")
        add(obj, "Float", "Maximum", "Result", "Largest value")
        add(obj, "String", "Message", "Status", "Result of the last recompute")
        for name in ("Minimum", "Maximum", "Message"):
            obj.setEditorMode(name, 1)
        for name in ("Coordinates", "Facets", "Values", "Bands"):
            obj.setEditorMode(name, 2)

    def claimed(self, obj) -> list:
        return []

    def consumed(self, obj) -> list:
        """The analysed object is drawn over by the coloured mesh: the command hides it."""
        return [obj.Face[0]] if obj.Face else []

    def limit(self, obj) -> float:
        return float(obj.Range) if obj.Range > 0 else symmetric_limit(obj.Values)

    def execute(self, obj) -> None:
        try:
            face = linked_face(obj.Face, "Face")
            surface = conversion.face_to_surface(face)
            count = min(max(int(obj.Resolution), RESOLUTION[1]), RESOLUTION[2])
            u, v, points, triangles = face_mesh(face, surface, count)
            values, bands = analyse(surface, obj.Kind, u, v, _unit(obj.Direction, "Direction"),
                                    _unit(obj.ViewDirection, "ViewDirection"), int(obj.Stripes))
        except Exception as exc:
            obj.Coordinates, obj.Facets, obj.Values, obj.Bands = [], [], [], []
            message = f"{obj.Label}: {exc}"
            obj.Message = "error: " + message
            report_traceback(exc)
            raise cagd.CagdError(message) from None
        obj.Coordinates = conversion.vectors(points)
        obj.Facets = [int(i) for i in triangles.ravel()]
        obj.Values = [float(x) for x in values]
        obj.Bands = [float(x) for x in bands]
        finite = values[np.isfinite(values)]
        obj.Minimum, obj.Maximum = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
        obj.Message = "ok"

    def onDocumentRestored(self, obj) -> None:
        pass


def make_surface_analysis(face, kind: str = "gaussian", doc=None, **values):
    """``face``: a LinkSub value (obj, 'FaceN')."""
    doc = doc or App.ActiveDocument or App.newDocument()
    obj = doc.addObject("App::FeaturePython", SurfaceAnalysis.DEFAULT_LABEL)
    SurfaceAnalysis(obj)
    obj.Face = face
    obj.Kind = kind
    for key, value in values.items():
        setattr(obj, key, value)
    if App.GuiUp:
        from . import viewproviders
        viewproviders.AnalysisViewProvider(obj.ViewObject)
    return obj
