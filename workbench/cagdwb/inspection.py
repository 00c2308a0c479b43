"""Query objects: the intersection curve of two faces and the deviation map of a point
cloud against faces (seed 004, ch. 1 §4, positional relations between shapes).

IntersectionCurve (``Part::FeaturePython``): ``cagd.intersect`` of the two linked
faces as the engine's trimmed surfaces (``conversion.face_to_trimmed``: the B-spline
form bounded by the face's pcurves; branches clipped to both trims); each branch is the engine's fitted cubic B-spline,
converted exactly into a ``Part.BSplineCurve``; the shape is the compound of the
branch edges. ``AchievedTolerance`` is the largest distance of the fitted branches
from both surfaces that the engine measured (dense samples), ``BranchCount`` the
number of branches. No intersection is not an error: the object stays valid with an
empty shape and a warning (like an empty Part Section); bad links or a bad
``Tolerance`` are errors naming the property.

DeviationMap (``App::FeaturePython``): signed distances (along the surface normal,
positive on the side the face's normal points to: reversed faces flip the sign) of
the points of a linked Points object, or of a CSV file, from the nearest linked face
(``cagd.deviation``: the certified global closest point); statistics in read-only
properties, the table in the report view; the view provider colours the points.
"""
from __future__ import annotations

import dataclasses
from typing import List, Optional, Sequence, Tuple

import numpy as np

import FreeCAD as App
import Part

from . import conversion
from .conversion import cagd
from .features import Feature, Stateless, _element, add, link_target, report_traceback

STATS = ("Max", "Min", "Mean", "RMS", "MaxAbs")
# colour map stops (blue - cyan - green - yellow - red), from -range to +range
STOPS = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 0.85, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]])


def colormap(values, limit: float) -> np.ndarray:
    """(N, 3) RGB colours of ``values`` on the blue-cyan-green-yellow-red scale from
    -limit to +limit (clipped; zero is green)."""
    limit = max(float(limit), 1e-300)
    t = np.clip((np.asarray(values, dtype=float) / limit + 1.0) * 0.5, 0.0, 1.0) * (len(STOPS) - 1)
    k = np.minimum(t.astype(int), len(STOPS) - 2)
    f = (t - k)[:, None]
    return STOPS[k] * (1.0 - f) + STOPS[k + 1] * f


def linked_face(link, name: str):
    """The face of a LinkSub value ``(obj, ['Face2'])`` (or a whole object whose shape
    has exactly one face); errors name the property."""
    obj, subs, shape = link_target(link, name, "face")
    if not subs:
        if len(shape.Faces) != 1:
            raise cagd.CagdError(f"{name}: {obj.Label} has {len(shape.Faces)} faces; link one face")
        return shape.Faces[0]
    element = _element(obj, subs[0], name)
    if element.ShapeType != "Face":
        raise cagd.CagdError(f"{name}: {obj.Label}.{subs[0]} is a {element.ShapeType}, not a face")
    return element


def face_surface(face, where: str, notes: Optional[List[str]] = None):
    """The face as the engine measures it (``conversion.face_to_trimmed``: a
    cagd.TrimmedSurface bounded by its pcurves, or its surface when the boundary is the
    parameter box), with an error naming where the face came from. A trim that cannot
    be used leaves the untrimmed surface; its reason goes to ``notes`` (the object's
    warnings) or the report view."""
    try:
        surface, reason = conversion.face_to_trimmed(face)
    except Exception as exc:
        raise cagd.CagdError(f"{where}: the face cannot be converted to a B-spline surface ({exc})") from None
    if reason is not None:
        note = f"{where}: {reason}; measured over the untrimmed surface"
        if notes is None:
            App.Console.PrintWarning(note + "\n")
        else:
            notes.append(note)
    return surface


def _tolerance(obj) -> float:
    tol = float(obj.Tolerance)
    if not tol > 0.0:                              # also NaN
        raise cagd.CagdError(f"Tolerance: must be > 0, got {tol:g}")
    return tol


class IntersectionCurve(Feature):
    """Intersection curves of two linked faces (cagd.intersect: subdivision seeds,
    marching, each branch fitted as a cubic B-spline within Tolerance)."""

    TYPE = "Cagd::IntersectionCurve"
    DEFAULT_LABEL = "IntersectionCurve"
    LINKS = ("Base", "Tool")

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Base", "Intersection", "The first face")
        add(obj, "LinkSub", "Tool", "Intersection", "The second face")
        add(obj, "Precision", "Tolerance", "Intersection",
            "Largest distance (mm, > 0) of the fitted branches from both faces", 1e-7)
        add(obj, "Precision", "AchievedTolerance", "Status",
            "Largest distance (mm) of the branches from both faces, measured by the engine", 0.0)
        add(obj, "Integer", "BranchCount", "Status", "Number of intersection branches", 0)
        add(obj, "Integer", "ClosedBranches", "Status", "How many branches are closed loops", 0)
        for name in ("AchievedTolerance", "BranchCount", "ClosedBranches"):
            obj.setEditorMode(name, 1)

    def claimed(self, obj) -> list:
        """The faces' objects stay where they are in the tree (the curve is drawn on them)."""
        return []

    def branches(self, obj):
        """The engine's intersection result of the linked faces (raises on bad values)."""
        tol = _tolerance(obj)
        fa, fb = linked_face(obj.Base, "Base"), linked_face(obj.Tool, "Tool")
        a, b = face_surface(fa, "Base"), face_surface(fb, "Tool")
        return cagd.intersect(a, b, tol), tol

    def execute(self, obj) -> None:
        try:
            result, tol = self.branches(obj)
            edges = [conversion.curve_to_part(c.curve).toShape() for c in result.curves]
            shape = Part.makeCompound(edges) if edges else Part.Shape()
            if edges and not shape.isValid():
                raise cagd.CagdError("the fitted branches do not make a valid OpenCascade shape")
        except Exception as exc:
            obj.Shape = Part.Shape()
            obj.AchievedTolerance, obj.BranchCount, obj.ClosedBranches = 0.0, 0, 0
            message = f"{obj.Label}: {exc}"
            obj.Message = "error: " + message
            report_traceback(exc)
            raise cagd.CagdError(message) from None
        self.sync_placement(obj)
        curves = result.curves
        achieved = max((float(c.max_distance) for c in curves), default=0.0)
        obj.Shape = shape
        obj.AchievedTolerance = achieved
        obj.BranchCount = len(curves)
        obj.ClosedBranches = sum(bool(c.closed) for c in curves)
        warnings = []
        if not curves:
            warnings.append("Base and Tool do not intersect (empty shape)")
        if not result.converged or any(not c.converged for c in curves) or achieved > tol:
            warnings.append(f"achieved tolerance {achieved:.3g} mm, asked {tol:.3g} mm"
                            + (f" ({result.message})" if result.message else ""))
        if warnings:
            obj.Message = f"warning: {obj.Label}: " + "; ".join(warnings)
            App.Console.PrintWarning(obj.Message + "\n")
        else:
            obj.Message = "ok"

    def control_net(self, obj):
        return []


def make_intersection(base, tool, doc=None, **values):
    """``base``, ``tool``: (object, 'FaceN')."""
    from .features import make
    return make(IntersectionCurve, doc=doc, Base=base, Tool=tool, **values)


# --- deviation map --------------------------------------------------------------------------
def cloud_points(obj, name: str = "Points") -> np.ndarray:
    """(N, 3) points of a Points object (placed; single precision, as FreeCAD stores
    them), or the vertices of a shape."""
    kernel = getattr(obj, "Points", None)
    if kernel is not None and hasattr(kernel, "Points"):
        pts = conversion.array(kernel.Points) if kernel.Points else np.zeros((0, 3))
    elif getattr(obj, "Shape", None) is not None and not obj.Shape.isNull():
        pts = conversion.array([v.Point for v in obj.Shape.Vertexes]) if obj.Shape.Vertexes else np.zeros((0, 3))
    else:
        raise cagd.CagdError(f"{name}: {obj.Label} is neither a Points object nor a shape with vertices")
    if len(pts) == 0:
        raise cagd.CagdError(f"{name}: {obj.Label} holds no points")
    return pts


def csv_points(path: str) -> np.ndarray:
    """(N, 3) points of a CSV file (cagd.deviation_cli.read_points)."""
    import os
    from cagd.deviation_cli import read_points
    if not os.path.isfile(path):
        raise cagd.CagdError(f"CsvFile: no such file {path!r}")
    try:
        pts = read_points(path)
    except cagd.CagdError as exc:
        raise cagd.CagdError(f"CsvFile: {path}: {exc}") from None
    if pts.shape[1] != 3:
        raise cagd.CagdError(f"CsvFile: {path}: needs x, y, z per line, got {pts.shape[1]} coordinates")
    return pts


def linked_faces(links, name: str = "Faces") -> List[Tuple[str, object]]:
    """(label, face) of every face of a LinkSubList value, in order; a whole object
    counts with all its faces."""
    out = []
    for obj, subs in links or []:
        subs = [s for s in (subs or []) if s]
        if not subs:
            shape = getattr(obj, "Shape", None)
            faces = shape.Faces if shape is not None and not shape.isNull() else []
            if not faces:
                raise cagd.CagdError(f"{name}: {obj.Label} has no faces")
            out.extend((f"{obj.Label}.Face{k + 1}", f) for k, f in enumerate(faces))
        for sub in subs:
            out.append((f"{obj.Label}.{sub}", linked_face((obj, [sub]), name)))
    if not out:
        raise cagd.CagdError(f"{name}: no face linked")
    return out


def signed_deviation(faces: Sequence[Tuple[str, object]], points: np.ndarray):
    """cagd.deviation of the points from the nearest face, the sign following each
    face's orientation (a reversed face flips its surface normal), statistics
    recomputed from the signed distances."""
    surfaces = [face_surface(f, label) for label, f in faces]
    dev = cagd.deviation(surfaces, points)
    flip = np.array([-1.0 if f.Orientation == "Reversed" else 1.0 for _, f in faces])
    if np.all(flip == 1.0):
        return dev
    d = dev.distances * flip[dev.owner]
    pct = list(dev.percentiles)
    return dataclasses.replace(dev, distances=d, max=float(d.max()), min=float(d.min()), mean=float(d.mean()),
                               rms=float(np.sqrt(np.mean(d * d))), max_abs=float(np.abs(d).max()),
                               percentiles={p: float(v) for p, v in zip(pct, np.percentile(d, pct))})


#: grid of the drawn triangulation of a face bounded by its parameter box (per direction)
FACE_GRID = 24
#: points compared with the drawn face's vertices at once (nearest-point colouring)
NEAREST_CHUNK = 256          # (vertices x 256 x 3 doubles at once: 12 MB for 2,000 vertices)


def _nearest_values(vertices: np.ndarray, pts: np.ndarray, values: np.ndarray) -> np.ndarray:
    """values[k] of the point nearest each vertex (brute force, NEAREST_CHUNK points at once)."""
    best = np.full(len(vertices), np.inf)
    out = np.zeros(len(vertices))
    for s in range(0, len(pts), NEAREST_CHUNK):
        d2 = ((vertices[:, None, :] - pts[None, s:s + NEAREST_CHUNK, :]) ** 2).sum(axis=2)
        k = np.argmin(d2, axis=1)
        d = d2[np.arange(len(vertices)), k]
        closer = d < best
        best[closer], out[closer] = d[closer], values[s + k[closer]]
    return out


def face_meshes(obj) -> List[Tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The deviation map's faces as drawn: per linked face (vertices (n, 3), triangles
    (m, 3), value per vertex = the signed distance of the nearest measured point); a
    trimmed face is its trimmed triangulation (``TrimmedSurface.tessellate``), not its
    parameter box; a face bounded by its box a FACE_GRID x FACE_GRID grid."""
    pts = np.array([(p.x, p.y, p.z) for p in obj.Coordinates], dtype=np.float64).reshape(-1, 3)
    dist = np.asarray(obj.Distances, dtype=np.float64)
    out = []
    for label, face in linked_faces(obj.Faces):
        s = face_surface(face, label)
        if isinstance(s, cagd.TrimmedSurface):
            V, T = s.tessellate()
        else:
            (u0, u1), (v0, v1) = s.domain
            u, v = np.meshgrid(np.linspace(u0, u1, FACE_GRID + 1), np.linspace(v0, v1, FACE_GRID + 1), indexing="ij")
            V = s(u.ravel(), v.ravel())
            k = (np.arange(FACE_GRID)[:, None] * (FACE_GRID + 1) + np.arange(FACE_GRID)[None, :]).ravel()
            T = np.concatenate([np.stack([k, k + FACE_GRID + 1, k + FACE_GRID + 2], 1),
                                np.stack([k, k + FACE_GRID + 2, k + 1], 1)])
        values = _nearest_values(V, pts, dist) if len(pts) == len(dist) and len(pts) else np.zeros(len(V))
        out.append((np.asarray(V, dtype=np.float64), np.asarray(T, dtype=np.int64), values))
    return out


def mesh_area(V: np.ndarray, T: np.ndarray) -> float:
    """Sum of the triangles' areas |(b - a) x (c - a)| / 2."""
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


class DeviationMap(Stateless):
    """Proxy of the deviation map (an App::FeaturePython: the result is data, drawn
    by :class:`cagdwb.viewproviders.DeviationViewProvider`)."""

    TYPE = "Cagd::DeviationMap"
    DEFAULT_LABEL = "DeviationMap"

    def __init__(self, obj):
        obj.Proxy = self
        add(obj, "LinkSubList", "Faces", "Deviation", "The model's faces (each point is measured to the nearest)")
        add(obj, "Link", "Points", "Deviation", "A Points object (or a shape's vertices); empty: use CsvFile")
        add(obj, "File", "CsvFile", "Deviation", "CSV file of x, y, z points, used when Points is empty")
        add(obj, "Integer", "Count", "Result", "Number of points", 0)
        for name in STATS:
            add(obj, "Float", name, "Result", f"{name} of the signed distances (mm)", 0.0)
        add(obj, "VectorList", "Coordinates", "Result", "The points measured")
        add(obj, "FloatList", "Distances", "Result", "Signed distance of each point (mm), + on the normal's side")
        add(obj, "String", "Message", "Status", "Result of the last recompute")
        for name in ("Count", "Message") + STATS:
            obj.setEditorMode(name, 1)
        for name in ("Coordinates", "Distances"):
            obj.setEditorMode(name, 2)

    def claimed(self, obj) -> list:
        return [obj.Points] if obj.Points is not None else []

    def consumed(self, obj) -> list:
        """The points object is drawn again, coloured: the command hides it."""
        return self.claimed(obj)

    def points(self, obj) -> np.ndarray:
        if obj.Points is not None:
            return cloud_points(obj.Points)
        if obj.CsvFile:
            return csv_points(obj.CsvFile)
        raise cagd.CagdError("Points: link a Points object or set CsvFile")

    def execute(self, obj) -> None:
        try:
            faces = linked_faces(obj.Faces)
            pts = self.points(obj)
            dev = signed_deviation(faces, pts)
        except Exception as exc:
            obj.Count, obj.Coordinates, obj.Distances = 0, [], []
            for name in STATS:
                setattr(obj, name, 0.0)
            message = f"{obj.Label}: {exc}"
            obj.Message = "error: " + message
            report_traceback(exc)
            raise cagd.CagdError(message) from None
        obj.Coordinates = conversion.vectors(pts)
        obj.Distances = [float(d) for d in dev.distances]
        obj.Count = len(pts)
        for name, key in zip(STATS, ("max", "min", "mean", "rms", "max_abs")):
            setattr(obj, name, float(getattr(dev, key)))
        source = obj.Points.Label if obj.Points is not None else obj.CsvFile
        App.Console.PrintMessage(f"{obj.Label}: signed deviation of {len(pts)} points ({source}) from "
                                 f"{', '.join(label for label, _ in faces)} (mm, + on the normal's side)\n"
                                 f"{dev.table()}\n")
        obj.Message = "ok"

    def onDocumentRestored(self, obj) -> None:
        pass


def make_deviation_map(faces, points=None, csv_file: str = "", doc=None):
    """``faces``: a LinkSubList value [(obj, 'FaceN'), ...]; ``points``: a Points
    object, or ``csv_file``: a CSV path (used when ``points`` is None)."""
    doc = doc or App.ActiveDocument or App.newDocument()
    obj = doc.addObject("App::FeaturePython", DeviationMap.DEFAULT_LABEL)
    DeviationMap(obj)
    obj.Faces = list(faces)
    if points is not None:
        obj.Points = points
    if csv_file:
        obj.CsvFile = csv_file
    if App.GuiUp:
        from . import viewproviders
        viewproviders.DeviationViewProvider(obj.ViewObject)
    return obj
