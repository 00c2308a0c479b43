"""View providers: the Part display plus an overlay with the control polygon / net
(toggle ``ShowControlNet``) and, for curves, the curvature comb (toggle
``ShowCurvatureComb``, ``CombScale`` 0 = automatic, ``CombSamples``).

The overlay lives under the view object's root node, after the placement
transform, so its points are given in the object's local coordinates.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui
from pivy import coin

from . import analysis, icon
from .features import Stateless

ICONS = {
    "Cagd::BezierCurve": "BezierCurve", "Cagd::BSplineCurve": "BSplineCurve",
    "Cagd::InterpolationCurve": "InterpolationCurve", "Cagd::CubicSpline": "CubicSpline",
    "Cagd::HermiteCurve": "HermiteCurve", "Cagd::JoinCurve": "Join", "Cagd::BezierSurface": "BezierSurface",
    "Cagd::BSplineSurface": "BSplineSurface", "Cagd::CoonsPatch": "CoonsPatch",
    "Cagd::BezierTriangle": "BezierTriangle", "Cagd::Revolution": "Revolution",
    "Cagd::Primitive": "Revolution",
    "Cagd::IntersectionCurve": "IntersectionCurve", "Cagd::DeviationMap": "DeviationMap",
    "Cagd::FitCurve": "FitCurve", "Cagd::FitSurface": "FitSurface", "Cagd::Rebuild": "Rebuild",
    "Cagd::RemoveKnots": "RemoveKnots", "Cagd::ReduceDegree": "ReduceDegree", "Cagd::Fair": "Fair",
    "Cagd::GordonSurface": "GordonSurface", "Cagd::Sweep": "Sweep", "Cagd::Sweep2": "Sweep2",
    "Cagd::BlendCurve": "BlendCurve", "Cagd::BlendSurface": "BlendSurface", "Cagd::MatchSurface": "MatchSurface",
}
COMB_SAMPLES = (64, 10, 5000, 1)     # default, minimum, maximum, step of CombSamples
COMB_PER_SPAN = 8                    # the engine comb's default teeth per knot span
NET_COLOR = (0.85, 0.2, 0.1)
COMB_COLOR = (0.1, 0.45, 0.9)


def _comb_lines(feet: np.ndarray, tips: np.ndarray) -> Tuple[np.ndarray, List[int]]:
    """The teeth (foot, tip) and the envelope through the tips, as points and polyline
    point counts (features.polylines_array's form)."""
    return np.concatenate([np.stack([feet, tips], axis=1).reshape(-1, 3), tips]), [2] * len(feet) + [len(tips)]


def _annotation(color) -> coin.SoAnnotation:
    """An SoAnnotation (drawn after the scene, no depth test), unpickable, in ``color``."""
    sep = coin.SoAnnotation()
    pick = coin.SoPickStyle()
    pick.style = coin.SoPickStyle.UNPICKABLE
    base = coin.SoBaseColor()
    base.rgb = color
    sep.addChild(pick)
    sep.addChild(base)
    return sep


PARTIAL_UPDATE = 16                  # Lines.set: at most this many changed points are set one by one


class Lines:
    """Polylines (and their vertices as dots) drawn as an SoAnnotation: after the scene
    without the depth test, so a net or comb is never hidden by its own surface. The
    nodes are made once; :meth:`set` replaces the coordinates and counts in place, only
    the points that changed when they are few (a dragged pole moves two points of a net)
    without rebuilding the scene graph."""

    def __init__(self, color, width: float, dots: bool):
        self.node = _annotation(color)
        style = coin.SoDrawStyle()
        style.lineWidth = width
        style.pointSize = 6.0
        self.coords, self.lines = coin.SoCoordinate3(), coin.SoLineSet()
        for node in (style, self.coords, self.lines):
            self.node.addChild(node)
        if dots:
            self.node.addChild(coin.SoPointSet())
        self.set(np.zeros((0, 3)), [])

    def set(self, points: np.ndarray, counts: Sequence[int]) -> None:
        """Draw ``counts`` consecutive ``points`` (n, 3) per polyline; nothing when empty.
        Counts equal to the drawn ones are not set again (a drag changes points only)."""
        counts = np.asarray(counts, dtype=np.int64).tolist()
        if counts != getattr(self, "counts", None):
            self.lines.numVertices.setNum(len(counts))
            if counts:
                self.lines.numVertices.setValues(0, len(counts), counts)
            self.counts = counts
        points = np.array(points, dtype=float).reshape(-1, 3)
        drawn = getattr(self, "points", None)
        if drawn is not None and drawn.shape == points.shape:
            changed = np.flatnonzero((drawn != points).any(axis=1))
            if len(changed) <= PARTIAL_UPDATE:          # a pole dragged: its two net points
                for i in changed.tolist():
                    self.coords.point.set1Value(i, points[i].tolist())
                self.points = points
                return
        self.coords.point.setNum(len(points))
        if len(points):
            self.coords.point.setValues(0, len(points), points.tolist())
        self.points = points


STATION_RED = (1.0, 0.0, 0.0)


def station_marker(point, radius: float, color=STATION_RED) -> coin.SoSeparator:
    """A sphere of ``radius`` at ``point`` (the worst station of a continuity check), as
    an SoAnnotation (drawn over the faces it sits on), unpickable."""
    sep = _annotation(color)
    move = coin.SoTranslation()
    move.translation = tuple(float(x) for x in point)
    sphere = coin.SoSphere()
    sphere.radius = float(radius)
    for node in (move, sphere):
        sep.addChild(node)
    return sep


class ViewProvider(Stateless):
    """Proxy of the workbench objects' view objects."""

    def __init__(self, vobj, curve: bool):
        vobj.Proxy = self
        vobj.addProperty("App::PropertyBool", "ShowControlNet", "CAGD", "Show the control polygon / net")
        vobj.ShowControlNet = True
        what = "curve" if curve else f"surface, on {analysis.ISO_COMBS} iso-curves in each direction"
        vobj.addProperty("App::PropertyBool", "ShowCurvatureComb", "CAGD", f"Show the curvature comb ({what})")
        vobj.addProperty("App::PropertyFloat", "CombScale", "CAGD",
                         "Tooth length = scale x curvature; 0 = longest tooth a fifth of the curve's length "
                         "(of the surface's size)")
        lo, hi = COMB_SAMPLES[1], COMB_SAMPLES[2]
        vobj.addProperty("App::PropertyIntegerConstraint", "CombSamples", "CAGD",
                         f"Least number of comb teeth per curve ({lo}..{hi}, clamped; at least "
                         f"{COMB_PER_SPAN} on each knot span, its ends included)")
        vobj.CombSamples = COMB_SAMPLES
        self.attach(vobj)

    def attach(self, vobj) -> None:
        self.vobj = vobj
        self.switch = coin.SoSwitch()
        self.switch.whichChild = coin.SO_SWITCH_ALL
        self.net, self.comb_lines = Lines(NET_COLOR, 1.0, True), Lines(COMB_COLOR, 1.0, False)
        self.switch.addChild(self.net.node)
        self.switch.addChild(self.comb_lines.node)
        vobj.RootNode.addChild(self.switch)
        self.refresh()

    # --- drawing ----------------------------------------------------------------------------
    def _local(self, points: np.ndarray) -> np.ndarray:
        """Placed points in the object's local coordinates (the overlay is placed)."""
        M = np.array(self.vobj.Object.Placement.inverse().toMatrix().A, dtype=float).reshape(4, 4)
        return points @ M[:3, :3].T + M[:3, 3]

    def refresh(self) -> None:
        """The overlay from the object's current shape and toggles (coordinates replaced
        in the existing nodes)."""
        if not getattr(self, "switch", None):
            return
        obj = self.vobj.Object
        self.drawn = obj.Placement.toMatrix().A
        empty: Tuple[np.ndarray, List[int]] = (np.zeros((0, 3)), [])
        shown = not obj.Shape.isNull() and self.vobj.Visibility
        net = comb = empty
        if shown and getattr(self.vobj, "ShowControlNet", False):
            net = obj.Proxy.net_arrays(obj)
        if shown and getattr(self.vobj, "ShowCurvatureComb", False) and obj.Shape.Edges:
            comb = self.comb(obj)
        for lines, (points, counts) in ((self.net, net), (self.comb_lines, comb)):
            lines.set(self._local(points) if len(points) else points, counts)

    def comb(self, obj) -> Tuple[np.ndarray, List[int]]:
        """Teeth and the envelope through their tips (placed coordinates, as
        features.polylines_array gives them): of the edge, or of iso-curves of the face
        (analysis.surface_combs)."""
        from .features import polylines_array
        samples = min(max(int(self.vobj.CombSamples), COMB_SAMPLES[1]), COMB_SAMPLES[2])
        scale = float(self.vobj.CombScale)
        if obj.Shape.Faces:
            return polylines_array(analysis.surface_combs(obj.Shape.Faces[0], samples=samples, scale=scale))
        return _comb_lines(*analysis.comb_arrays(obj.Shape.Edges[0], samples, scale))

    # --- FreeCAD protocol -------------------------------------------------------------------
    def updateData(self, obj, prop: str) -> None:
        if prop == "Placement" and getattr(self, "drawn", None) == obj.Placement.toMatrix().A:
            return                        # execute sets the same Placement again after the Shape
        if prop in ("Shape", "Placement"):
            self.refresh()
            if getattr(self, "editor", None) is not None:        # pole editing: markers follow (undo too)
                self.editor.refresh()

    def onChanged(self, vobj, prop: str) -> None:
        if prop == "CombSamples":               # bounds are not saved with a document: clamp here too
            lo, hi = COMB_SAMPLES[1], COMB_SAMPLES[2]
            value = int(vobj.CombSamples)
            if not lo <= value <= hi:
                vobj.CombSamples = min(max(value, lo), hi)
                return
        if prop in ("ShowControlNet", "ShowCurvatureComb", "CombScale", "CombSamples", "Visibility"):
            self.refresh()

    def getIcon(self) -> str:
        obj = getattr(self, "vobj", None) and self.vobj.Object
        name = ICONS.get(getattr(getattr(obj, "Proxy", None), "TYPE", ""), "CagdWorkbench")
        return icon(name)

    def claimChildren(self) -> list:
        """The linked input objects (vertices, edges' objects; a join's Source), so
        they nest under the new object in the tree like Part features' inputs."""
        obj = getattr(self, "vobj", None) and self.vobj.Object
        proxy = getattr(obj, "Proxy", None)
        return proxy.claimed(obj) if hasattr(proxy, "claimed") else []

    def setEdit(self, vobj, mode: int = 0) -> bool:
        """Mode 0: the property task panel; editpoles.EDIT_POLES: drag the poles."""
        from . import editpoles
        if mode == editpoles.EDIT_POLES and editpoles.point_property(vobj.Object):
            self.editor = editpoles.PoleEditor(vobj)
            return True
        if mode != 0:
            return False
        from .taskpanel import TaskPanel
        self.panel = TaskPanel(vobj.Object)
        Gui.Control.showDialog(self.panel)
        return True

    def unsetEdit(self, vobj, mode: int = 0) -> bool:
        from . import editpoles
        if mode == editpoles.EDIT_POLES and getattr(self, "editor", None) is not None:
            self.editor.close()
            if self.editor.shown:                 # not another command's dialog
                Gui.Control.closeDialog()
            self.editor = None
            return True
        if mode != 0:
            return False
        Gui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj) -> bool:
        """Objects with poles (or interpolated points) go into pole editing, the others
        open the property panel."""
        from . import editpoles
        Gui.ActiveDocument.setEdit(vobj.Object, editpoles.EDIT_POLES if editpoles.point_property(vobj.Object) else 0)
        return True

    def setupContextMenu(self, vobj, menu) -> None:
        """Edit poles (objects with poles) and Edit properties (the task panel); in pole
        editing, the knot and degree edits of a B-spline object."""
        from . import editpoles
        modes = [("Edit properties", 0)]
        if editpoles.point_property(vobj.Object):
            modes.insert(0, ("Edit poles", editpoles.EDIT_POLES))
        for text, mode in modes:
            action = menu.addAction(text)
            action.triggered.connect(lambda checked=False, m=mode: Gui.ActiveDocument.setEdit(vobj.Object, m))
        if getattr(self, "editor", None) is not None:          # pole editing: knot and degree edits
            menu.addSeparator()
            self.editor.context_actions(menu)



def attach(obj) -> None:
    """Give a workbench object its view provider (GUI only)."""
    from . import curves, fitting, inspection, network
    is_curve = isinstance(obj.Proxy, (curves.BezierCurve, curves.BSplineCurve, curves.InterpolationCurve,
                                      curves.CubicSpline, curves.HermiteCurve, curves.JoinCurve,
                                      inspection.IntersectionCurve, fitting.FitCurve,
                                      network.BlendCurve)) or fitting.on_edge(obj)
    ViewProvider(obj.ViewObject, is_curve)
    if isinstance(obj.Proxy, inspection.IntersectionCurve):
        obj.ViewObject.ShowControlNet = False        # fitted branches: many poles, not a design net
        obj.ViewObject.LineWidth = 3.0
        obj.ViewObject.LineColor = (0.9, 0.1, 0.1)


# --- deviation map ------------------------------------------------------------------------------
LEGEND_STEPS = 32
FACE_TRANSPARENCY = 0.5          # the measured faces drawn behind the coloured points


class _OneMode(Stateless):
    """A view provider with one display mode, ``MODE``: its scene under ``root``,
    rebuilt by ``refresh()``."""
    MODE = ""

    def attach(self, vobj) -> None:
        if getattr(self, "root", None) is not None:
            return
        self.vobj = vobj
        self.root = coin.SoSeparator()
        vobj.addDisplayMode(self.root, self.MODE)
        self.refresh()

    def getDisplayModes(self, vobj) -> list:
        return [self.MODE]

    def getDefaultDisplayMode(self) -> str:
        return self.MODE

    def setDisplayMode(self, mode: str) -> str:
        return mode

    def refresh(self) -> None:
        raise NotImplementedError


def colour_bar(flat, limit: float, unit: str) -> coin.SoSeparator:
    """A vertical colour bar (inspection.colormap, -limit at the bottom to +limit at the
    top) right of the points' bounding box (height: half its diagonal), labelled
    +limit, 0 and -limit in ``unit``; unlit colours come from the caller's light model."""
    from .inspection import colormap
    P = np.asarray(flat, dtype=float)
    lo, hi = P.min(axis=0), P.max(axis=0)
    size = max(float(np.linalg.norm(hi - lo)), 1e-9)
    x0, y0, z0 = hi[0] + 0.12 * size, 0.5 * (lo[1] + hi[1]), lo[2]
    width, height = 0.05 * size, 0.5 * size
    values = np.linspace(-limit, limit, LEGEND_STEPS + 1)
    zs = z0 + height * np.linspace(0.0, 1.0, LEGEND_STEPS + 1)
    sep = coin.SoSeparator()
    coords = coin.SoCoordinate3()
    corners = [(x0 + width * i, y0, float(z)) for z in zs for i in (0, 1)]
    coords.point.setValues(0, len(corners), corners)
    material = coin.SoMaterial()
    colors = [tuple(map(float, c)) for c in colormap(values, limit) for _ in (0, 1)]
    material.diffuseColor.setValues(0, len(colors), colors)
    binding = coin.SoMaterialBinding()
    binding.value = coin.SoMaterialBinding.PER_VERTEX
    mesh = coin.SoQuadMesh()
    mesh.verticesPerRow = 2
    mesh.verticesPerColumn = LEGEND_STEPS + 1
    for node in (coords, material, binding, mesh):
        sep.addChild(node)
    for value, z in ((limit, zs[-1]), (0.0, 0.5 * (zs[0] + zs[-1])), (-limit, zs[0])):
        label = coin.SoSeparator()
        move = coin.SoTranslation()
        move.translation = (x0 + 1.5 * width, y0, float(z))
        color = coin.SoBaseColor()
        color.rgb = (0.1, 0.1, 0.1)
        text = coin.SoText2()
        text.string = f"{value:+.3g} {unit}" if value else "0"
        for node in (move, color, text):
            label.addChild(node)
        sep.addChild(label)
    return sep


class DeviationViewProvider(_OneMode):
    """The deviation map's points coloured by signed distance (blue - green - red from
    -range to +range, ``ColorRange`` 0 = the largest |distance|), per-vertex colours
    (SoMaterial + SoMaterialBinding PER_VERTEX on an SoPointSet, unlit), and a legend
    beside the cloud: a colour bar with the range and zero labelled."""
    MODE = "Deviation"

    def __init__(self, vobj):
        vobj.addProperty("App::PropertyFloat", "PointSize", "CAGD", "Point size in pixels")
        vobj.addProperty("App::PropertyFloat", "ColorRange", "CAGD",
                         "Distances mapped to the ends of the colour scale (mm); 0 = largest |distance|")
        vobj.addProperty("App::PropertyBool", "ShowLegend", "CAGD", "Show the colour bar")
        vobj.PointSize, vobj.ShowLegend = 5.0, True
        vobj.Proxy = self
        if getattr(self, "root", None) is None:
            self.attach(vobj)

    def limit(self) -> float:
        obj = self.vobj.Object
        value = float(getattr(self.vobj, "ColorRange", 0.0) or 0.0)
        return value if value > 0.0 else max(float(obj.MaxAbs), 1e-12)

    def refresh(self) -> None:
        """Rebuild the points and the legend from the object's Coordinates and Distances."""
        root = getattr(self, "root", None)
        if root is None:
            return
        root.removeAllChildren()
        obj = self.vobj.Object
        pts, dist = obj.Coordinates, obj.Distances
        if not pts or len(pts) != len(dist):
            return
        from .inspection import colormap
        limit = self.limit()
        flat = [(p.x, p.y, p.z) for p in pts]
        colors = [tuple(map(float, c)) for c in colormap(dist, limit)]
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        style = coin.SoDrawStyle()
        style.pointSize = float(getattr(self.vobj, "PointSize", 5.0) or 5.0)
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(flat), flat)
        material = coin.SoMaterial()
        material.diffuseColor.setValues(0, len(colors), colors)
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX
        cloud = coin.SoPointSet()
        cloud.numPoints = len(flat)
        for node in (pick, light, style, coords, material, binding, cloud):
            root.addChild(node)
        root.addChild(self.faces(obj, limit))
        if getattr(self.vobj, "ShowLegend", True):
            root.addChild(colour_bar(flat, limit, "mm"))

    @staticmethod
    def faces(obj, limit: float) -> coin.SoSeparator:
        """The linked faces, translucent, coloured by the distance of the nearest point:
        a trimmed face as its trimmed triangulation (``inspection.face_meshes``)."""
        from .inspection import colormap, face_meshes
        sep = coin.SoSeparator()
        try:
            meshes = face_meshes(obj)
        except Exception as exc:             # the points are still drawn; the faces' error is the object's
            App.Console.PrintWarning(f"{obj.Label}: faces not drawn ({exc})\n")
            return sep
        for V, T, values in meshes:
            part = coin.SoSeparator()
            coords = coin.SoCoordinate3()
            coords.point.setValues(0, len(V), [tuple(map(float, p)) for p in V])
            material = coin.SoMaterial()
            colors = [tuple(map(float, c)) for c in colormap(values, limit)]
            material.diffuseColor.setValues(0, len(colors), colors)
            material.transparency = FACE_TRANSPARENCY
            binding = coin.SoMaterialBinding()
            binding.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
            mesh = coin.SoIndexedFaceSet()
            index = [int(i) for t in T for i in (*t, -1)]
            mesh.coordIndex.setValues(0, len(index), index)
            for node in (coords, material, binding, mesh):
                part.addChild(node)
            sep.addChild(part)
        return sep

    def updateData(self, obj, prop: str) -> None:
        if prop in ("Coordinates", "Distances", "MaxAbs"):
            self.refresh()

    def onChanged(self, vobj, prop: str) -> None:
        if prop in ("PointSize", "ColorRange", "ShowLegend"):
            self.refresh()

    def getIcon(self) -> str:
        return icon("DeviationMap")

    def claimChildren(self) -> list:
        obj = getattr(self, "vobj", None) and self.vobj.Object
        proxy = getattr(obj, "Proxy", None)
        return proxy.claimed(obj) if hasattr(proxy, "claimed") else []


# --- surface analysis ---------------------------------------------------------------------------
class AnalysisViewProvider(_OneMode):
    """The surface analysis' mesh with per-vertex colours (surface_analysis.vertex_colors),
    unlit (SoLightModel BASE_COLOR) so the colours are the values' own; for the colour
    scale kinds (curvatures, draft) a colour bar beside it (``ShowLegend``) labelled with
    the range: the object's ``Range``, or symmetric (the largest |value|) when 0."""
    MODE = "Analysis"

    def __init__(self, vobj):
        vobj.addProperty("App::PropertyBool", "ShowLegend", "CAGD",
                         "Show the colour bar (curvatures, draft angle): -Range blue .. +Range red")
        vobj.ShowLegend = True
        vobj.Proxy = self
        if getattr(self, "root", None) is None:
            self.attach(vobj)

    def refresh(self) -> None:
        root = getattr(self, "root", None)
        if root is None:
            return
        root.removeAllChildren()
        obj = self.vobj.Object
        pts, facets = obj.Coordinates, obj.Facets
        if not pts or len(obj.Values) != len(pts) or len(obj.Bands) != len(pts):   # mid-update: wait
            return
        from .surface_analysis import vertex_colors
        colors = vertex_colors(obj.Kind, obj.Values, obj.Bands, obj.Proxy.limit(obj))
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        coords = coin.SoCoordinate3()
        flat = [(p.x, p.y, p.z) for p in pts]
        coords.point.setValues(0, len(flat), flat)
        material = coin.SoMaterial()
        material.diffuseColor.setValues(0, len(colors), [tuple(map(float, c)) for c in colors])
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.UNKNOWN_ORDERING     # both sides shown
        mesh = coin.SoIndexedFaceSet()
        index = [int(i) for k in range(0, len(facets), 3) for i in (*facets[k:k + 3], -1)]
        mesh.coordIndex.setValues(0, len(index), index)
        for node in (light, hints, coords, material, binding, mesh):
            root.addChild(node)
        from .surface_analysis import STRIPED, unit
        if obj.Kind not in STRIPED and getattr(self.vobj, "ShowLegend", True):
            root.addChild(colour_bar(flat, obj.Proxy.limit(obj), unit(obj.Kind)))

    def updateData(self, obj, prop: str) -> None:
        if prop in ("Coordinates", "Values", "Bands", "Range"):
            self.refresh()

    def onChanged(self, vobj, prop: str) -> None:
        if prop == "ShowLegend":
            self.refresh()

    def getIcon(self) -> str:
        return icon("DeviationMap")
