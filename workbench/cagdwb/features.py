"""Base class of the workbench's FeaturePython objects and property helpers.

Every object is a ``Part::FeaturePython`` whose proxy builds an engine geometry from
the object's properties (:meth:`Feature.build`) and stores its exact B-spline form as
the object's Shape. Bad property values raise in ``execute``: the object goes into
FreeCAD's error state ("Invalid", message in the report view and in the object's
``Message`` property) and its Shape is emptied, so no stale shape survives.
"""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

import FreeCAD as App
import Part

from . import conversion
from .conversion import cagd

ROUND = 1e-12          # relative rounding noise when comparing points


PREFERENCES = "User parameter:BaseApp/Preferences/Mod/Cagd"


def debug_tracebacks() -> bool:
    """The debug preference DebugTracebacks (BaseApp/Preferences/Mod/Cagd, default off):
    an error then also prints the engine's traceback (Console log); without it only the
    message is reported (FreeCAD adds the one frame of ``execute`` it calls)."""
    return bool(App.ParamGet(PREFERENCES).GetBool("DebugTracebacks", False))


def report_traceback(exc: BaseException) -> None:
    """The full traceback of ``exc`` to the report view's log, with the debug preference."""
    if debug_tracebacks():
        import traceback
        App.Console.PrintLog("".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))


class Stateless:
    """A FreeCAD proxy that saves no state of its own: everything is in the object's
    properties, so the document reloads the proxy empty (FreeCAD 0.20 calls
    __getstate__/__setstate__, 0.21+ dumps/loads)."""

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


class Feature(Stateless):
    """Proxy base: subclasses set TYPE and DEFAULT_LABEL, add properties in
    :meth:`setup` and return an engine curve or surface from :meth:`build`."""

    TYPE = "Cagd::Feature"
    DEFAULT_LABEL = "Cagd"
    LINKS: Tuple[str, ...] = ()      # link properties giving the geometry (global coordinates)
    POINTS = "Poles"                 # the property named when all control points coincide

    def __init__(self, obj):
        obj.Proxy = self
        obj.addProperty("App::PropertyString", "Message", "Status", "Result of the last recompute")
        obj.setEditorMode("Message", 1)
        self.setup(obj)

    # --- to override ------------------------------------------------------------------------
    def setup(self, obj) -> None:
        """Add the object's properties with valid default values."""

    def build(self, obj):
        """The engine geometry described by the properties (raise on bad values)."""
        raise NotImplementedError

    # --- links --------------------------------------------------------------------------------
    def linked(self, obj) -> bool:
        """True when the geometry comes from linked vertices or edges: those are in
        global coordinates, so the object's Placement is kept at the identity (and
        read-only in the property editor), like Part Loft or Ruled surface follow their
        inputs; an object without links has an editable Placement."""
        return any(getattr(obj, name, None) for name in self.LINKS)

    def claimed(self, obj) -> list:
        """The linked objects (each once, in link order): the view provider claims
        them as children in the tree."""
        out = []
        for name in self.LINKS:
            value = getattr(obj, name, None)
            if not value:
                continue
            items = value if isinstance(value, list) else [value]
            for item in items:
                o = item[0] if isinstance(item, tuple) else item
                if o is not None and o is not obj and o not in out:
                    out.append(o)
        return out

    def consumed(self, obj) -> list:
        """The claimed objects wholly used as input: their shape is just the linked
        vertex or edge (a point object, a single curve), so the creating command hides
        them; a solid whose edges or vertices are linked stays visible."""
        out = []
        for o in self.claimed(obj):
            shape = getattr(o, "Shape", None)
            if shape is None or shape.isNull():
                continue
            if (len(shape.Vertexes) == 1 and not shape.Edges) or \
                    (len(shape.Edges) == 1 and not shape.Faces):
                out.append(o)
        return out

    def sync_placement(self, obj) -> None:
        """Identity and read-only Placement while linked; editable otherwise."""
        if "Restore" in obj.State:
            return
        linked = self.linked(obj)
        if linked and not obj.Placement.isIdentity():
            obj.Placement = App.Placement()
        obj.setEditorMode("Placement", 1 if linked else 0)

    def onDocumentRestored(self, obj) -> None:
        obj.setEditorMode("Placement", 1 if self.linked(obj) else 0)

    def onChanged(self, obj, prop: str) -> None:
        if prop == "Placement" or prop in self.LINKS:
            if hasattr(obj, "Proxy") and all(hasattr(obj, n) for n in self.LINKS):
                self.sync_placement(obj)

    RESULTS: Tuple[Tuple[str, object], ...] = ()    # read-only result properties, (name, value after an error)

    def compute(self, obj) -> Tuple[object, dict, Optional[str]]:
        """(engine geometry, {result property: value}, warning or None): :meth:`build`,
        no results, no warning, unless overridden (the fitting objects)."""
        return self.build(obj), {}, None

    # --- FreeCAD protocol -------------------------------------------------------------------
    def execute(self, obj) -> None:
        """Shape and results from :meth:`compute`; a warning leaves the object valid
        with ``Message`` "warning: ..." (also in the report view)."""
        try:
            geometry, values, warning = self.compute(obj)
            self.check_not_a_point(geometry)
            shape = conversion.to_shape(geometry, nurbs=bool(getattr(obj, "Nurbs", False)))
            if shape.isNull() or not shape.isValid():
                raise cagd.CagdError("the engine's result does not make a valid OpenCascade shape "
                                     "(check for coincident poles or a degenerate net)")
        except Exception as exc:
            obj.Shape = Part.Shape()
            for name, empty in self.RESULTS:
                setattr(obj, name, empty)
            message = f"{obj.Label}: {exc}"
            obj.Message = "error: " + message
            report_traceback(exc)
            raise cagd.CagdError(message) from None
        self.sync_placement(obj)
        placement = obj.Placement
        obj.Shape = shape
        obj.Placement = placement
        for name, value in values.items():
            setattr(obj, name, value)
        if warning:
            obj.Message = f"warning: {obj.Label}: {warning}"
            App.Console.PrintWarning(obj.Message + "\n")
        else:
            obj.Message = "ok"

    def check_not_a_point(self, geometry) -> None:
        """Raise when all control points of the geometry's NURBS form coincide (the
        curve or surface is a single point, which OCCT accepts as a valid shape)."""
        P = np.asarray(geometry.to_nurbs().control_points, dtype=float)
        P = P.reshape(-1, P.shape[-1])
        scale = max(1.0, float(np.abs(P).max()))
        if float(np.ptp(P, axis=0).max()) <= 1e-12 * scale:
            kind = "curve" if isinstance(geometry, cagd.Curve) else "surface"
            what = "poles" if self.POINTS == "Poles" else "points"
            raise cagd.CagdError(f"{self.POINTS}: all {what} coincide: the {kind} is a point")

    # --- helpers for the view provider ------------------------------------------------------
    def net_arrays(self, obj) -> Tuple[np.ndarray, List[int]]:
        """The control polygon / net as one (n, 3) array of placed points and the
        polylines' point counts: each B-spline or Bezier edge's poles (a periodic one
        closed), each face's pole rows then columns (an analytic face: the engine's exact
        NURBS form of :meth:`build`). A subclass with its own :meth:`control_net` (lists
        of vectors) is read through it."""
        if type(self).control_net is not Feature.control_net:
            return polylines_array(self.control_net(obj))
        parts: List[np.ndarray] = []
        counts: List[int] = []
        for edge in obj.Shape.Edges if not obj.Shape.Faces else []:
            curve = edge.Curve
            if isinstance(curve, (Part.BSplineCurve, Part.BezierCurve)):
                P = conversion.array(curve.getPoles())
                if isinstance(curve, Part.BSplineCurve) and curve.isPeriodic():
                    P = np.concatenate([P, P[:1]])
                parts.append(P)
                counts.append(len(P))
        for face in obj.Shape.Faces:
            surface = face.Surface
            if isinstance(surface, (Part.BSplineSurface, Part.BezierSurface)):
                net = conversion.array(surface.getPoles())
            else:                         # an analytic face: the net of the engine's exact NURBS form
                net = np.asarray(self.build(obj).to_nurbs().control_points, dtype=float)
                M = np.array(obj.Placement.toMatrix().A, dtype=float).reshape(4, 4)
                net = net @ M[:3, :3].T + M[:3, 3]
            m, n = net.shape[:2]
            parts += [net.reshape(-1, 3), net.transpose(1, 0, 2).reshape(-1, 3)]
            counts += [n] * m + [m] * n
        return (np.concatenate(parts) if parts else np.zeros((0, 3))), counts

    def control_net(self, obj) -> List[List[App.Vector]]:
        """Polylines of the control polygon / net of the object's shape (placed), as
        lists of vectors (:meth:`net_arrays`)."""
        points, counts = self.net_arrays(obj)
        flat = conversion.vectors(points)
        ends = np.cumsum([0] + list(counts))
        return [flat[a:b] for a, b in zip(ends[:-1], ends[1:])]


def polylines_array(polylines: Sequence[Sequence[App.Vector]]) -> Tuple[np.ndarray, List[int]]:
    """Points of the polylines as one (n, 3) array and the polylines' point counts."""
    flat = [p for line in polylines for p in line]
    return (conversion.array(flat) if flat else np.zeros((0, 3))), [len(line) for line in polylines]


def make(feature_class, name: Optional[str] = None, doc=None, **values):
    """Create a Part::FeaturePython with the given proxy class in ``doc`` (default:
    the active document, or a new one), set property ``values``, attach the view
    provider when the GUI is up, and return the object (not yet recomputed)."""
    doc = doc or App.ActiveDocument or App.newDocument()
    obj = doc.addObject("Part::FeaturePython", name or feature_class.DEFAULT_LABEL)
    feature_class(obj)
    for key, value in values.items():
        setattr(obj, key, value)
    obj.Proxy.sync_placement(obj)
    if App.GuiUp:
        from . import viewproviders
        viewproviders.attach(obj)
    return obj


# --- property helpers -----------------------------------------------------------------------
def add(obj, kind: str, name: str, group: str, doc: str, value=None) -> None:
    """obj.addProperty(App::Property<kind>, ...) and set its value."""
    obj.addProperty("App::Property" + kind, name, group, doc)
    if value is not None:
        setattr(obj, name, value)


def add_enum(obj, name: str, group: str, doc: str, choices: Sequence[str], value: str) -> None:
    obj.addProperty("App::PropertyEnumeration", name, group, doc)
    setattr(obj, name, list(choices))
    setattr(obj, name, value)


def weights_or_none(values: Sequence[float]) -> Optional[np.ndarray]:
    """An empty weight list means polynomial (None)."""
    return np.array(values, dtype=float) if len(values) else None


def grid(values, count_u: int, name: str = "Poles") -> np.ndarray:
    """A flat row-major list of vectors (or floats) as an (count_u, n_v, ...) grid."""
    a = conversion.array(values) if len(values) and isinstance(values[0], App.Vector) else \
        np.array(values, dtype=float)
    if count_u < 1 or len(a) % count_u:
        raise cagd.CagdError(f"CountU: {len(a)} {name} do not form rows of equal length "
                             f"with {count_u} rows")
    return a.reshape(count_u, len(a) // count_u, *a.shape[1:])


def linked_points(links) -> np.ndarray:
    """Points of a LinkSubList of vertices (``[(obj, ('Vertex1', ...)), ...]``) in
    order; whole objects without sub-elements count when their shape is one vertex."""
    pts = []
    for obj, subs in links:
        subs = [s for s in subs if s] if subs else []
        if not subs:
            vertexes = obj.Shape.Vertexes
            if len(vertexes) != 1:
                raise cagd.CagdError(f"Vertices: {obj.Label} is not a single point; select its vertices")
            pts.append(vertexes[0].Point)
            continue
        for sub in subs:
            element = _element(obj, sub, "Vertices")
            if element.ShapeType != "Vertex":
                raise cagd.CagdError(f"Vertices: {obj.Label}.{sub} is a {element.ShapeType}, not a vertex")
            pts.append(element.Point)
    return conversion.array(pts)


def points_from(obj, points_property: str = "Points") -> np.ndarray:
    """The points of ``obj``: from its linked Vertices when any (then written back to
    the points property for display), else the points property itself."""
    if obj.Vertices:
        pts = linked_points(obj.Vertices)
        current = getattr(obj, points_property)
        if len(current) != len(pts) or np.any(conversion.array(current) != pts):
            setattr(obj, points_property, conversion.vectors(pts))
        return pts
    return conversion.array(getattr(obj, points_property))


def _element(obj, sub: str, name: str):
    """obj.Shape.getElement(sub), with an error naming the property when the
    sub-element does not exist (e.g. 'Edge5' of a shape with one edge)."""
    try:
        return obj.Shape.getElement(sub)
    except Exception as exc:
        shape = obj.Shape
        counts = f"{len(shape.Vertexes)} vertices, {len(shape.Edges)} edges, {len(shape.Faces)} faces"
        raise cagd.CagdError(f"{name}: {obj.Label} has no {sub} ({counts}; {exc})") from None


def link_target(link, name: str, what: str):
    """(object, sub-element names, shape) of a LinkSub value ``(obj, ['Face2'])``;
    errors name the property (nothing linked, an object without a shape)."""
    if not link or link[0] is None:
        raise cagd.CagdError(f"{name}: no {what} linked")
    obj, subs = link
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull():
        raise cagd.CagdError(f"{name}: {obj.Label} has no shape")
    return obj, [s for s in (subs or []) if s], shape


def linked_edge(link, name: str):
    """The edge of a LinkSub property value ``(obj, ['Edge2'])`` (or a whole object
    whose shape has exactly one edge)."""
    if not link:
        raise cagd.CagdError(f"{name}: no edge linked")
    obj, subs = link
    subs = [s for s in (subs or []) if s]
    if not subs:
        edges = obj.Shape.Edges
        if len(edges) != 1:
            raise cagd.CagdError(f"{name}: {obj.Label} has {len(edges)} edges; link one edge")
        return edges[0]
    element = _element(obj, subs[0], name)
    if element.ShapeType != "Edge":
        raise cagd.CagdError(f"{name}: {obj.Label}.{subs[0]} is a {element.ShapeType}, not an edge")
    return element


def linked_edges(links, name: str) -> List[Tuple[str, object]]:
    """(label, edge) of every edge in a LinkSubList value, in order."""
    out = []
    for obj, subs in links:
        subs = [s for s in (subs or []) if s]
        if not subs:
            out.append((obj.Label, linked_edge((obj, []), name)))
        for sub in subs:
            out.append((f"{obj.Label}.{sub}", linked_edge((obj, [sub]), name)))
    return out


def vector(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z], dtype=float)
