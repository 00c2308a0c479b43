"""Surface analysis overlay: a face (ours or any FreeCAD face Part can convert to a
B-spline) coloured by the engine's curvature map (Gaussian, mean, maximum or minimum
principal curvature), zebra stripes, isophotes or draft angle (cagd.analysis), all
computed at once (vectorized) on the vertices of a parameter-grid tessellation of the
face's surface. The object stores the mesh and the values; the view provider
(viewproviders.AnalysisViewProvider) only draws them with :func:`vertex_colors`.
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


def analyse(surface, kind: str, u, v, direction=(0.0, 0.0, 1.0), view=(0.0, -1.0, 0.0),
            stripes: int = 8) -> Tuple[np.ndarray, np.ndarray]:
    """(values, bands) of ``kind`` at S(u, v), one engine call: a curvature (1/mm, signs
    as cagd.analysis.curvature_map), zebra phase with bands = lit (1/0), isophote value
    n.L with bands = the engine's band, or draft angle in degrees (``direction``: the
    light bars' direction, the light or the pull direction; ``view``: the view ray for
    zebra). NaN values (band -1) where the normal is undefined."""
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
                        "Grid points per parameter direction of the tessellation")
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
            surface = conversion.face_to_surface(linked_face(obj.Face, "Face"))
            count = min(max(int(obj.Resolution), RESOLUTION[1]), RESOLUTION[2])
            u, v, points, triangles = grid_mesh(surface, count)
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
