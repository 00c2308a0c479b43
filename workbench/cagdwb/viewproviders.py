"""View providers: the Part display plus an overlay with the control polygon / net
(toggle ``ShowControlNet``) and, for curves, the curvature comb (toggle
``ShowCurvatureComb``, ``CombScale`` 0 = automatic, ``CombSamples``).

The overlay lives under the view object's root node, after the placement
transform, so its points are given in the object's local coordinates.
"""
from __future__ import annotations

from typing import List, Sequence

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
}
COMB_SAMPLES = (64, 10, 5000, 1)     # default, minimum, maximum, step of CombSamples
NET_COLOR = (0.85, 0.2, 0.1)
COMB_COLOR = (0.1, 0.45, 0.9)


def _lines_node(polylines: Sequence[Sequence[App.Vector]], color, width: float, points: bool) -> coin.SoSeparator:
    """A separator drawing the polylines (and their vertices as dots)."""
    sep = coin.SoSeparator()
    pick = coin.SoPickStyle()
    pick.style = coin.SoPickStyle.UNPICKABLE
    base = coin.SoBaseColor()
    base.rgb = color
    style = coin.SoDrawStyle()
    style.lineWidth = width
    style.pointSize = 6.0
    coords = coin.SoCoordinate3()
    flat = [(p.x, p.y, p.z) for line in polylines for p in line]
    coords.point.setValues(0, len(flat), flat)
    lines = coin.SoLineSet()
    lines.numVertices.setValues(0, len(polylines), [len(line) for line in polylines])
    for node in (pick, base, style, coords, lines):
        sep.addChild(node)
    if points:
        sep.addChild(coin.SoPointSet())
    return sep


class ViewProvider(Stateless):
    """Proxy of the workbench objects' view objects."""

    def __init__(self, vobj, curve: bool):
        vobj.Proxy = self
        vobj.addProperty("App::PropertyBool", "ShowControlNet", "CAGD", "Show the control polygon / net")
        vobj.ShowControlNet = True
        if curve:
            vobj.addProperty("App::PropertyBool", "ShowCurvatureComb", "CAGD", "Show the curvature comb")
            vobj.addProperty("App::PropertyFloat", "CombScale", "CAGD",
                             "Tooth length = scale x curvature; 0 = longest tooth a fifth of the curve")
            lo, hi = COMB_SAMPLES[1], COMB_SAMPLES[2]
            vobj.addProperty("App::PropertyIntegerConstraint", "CombSamples", "CAGD",
                             f"Number of comb teeth ({lo}..{hi}; values out of range are clamped)")
            vobj.CombSamples = COMB_SAMPLES
        self.attach(vobj)

    def attach(self, vobj) -> None:
        self.vobj = vobj
        self.switch = coin.SoSwitch()
        self.switch.whichChild = coin.SO_SWITCH_ALL
        vobj.RootNode.addChild(self.switch)
        self.refresh()

    # --- drawing ----------------------------------------------------------------------------
    def _local(self, polylines: List[List[App.Vector]]) -> List[List[App.Vector]]:
        inverse = self.vobj.Object.Placement.inverse()
        return [[inverse.multVec(p) for p in line] for line in polylines]

    def refresh(self) -> None:
        """Rebuild the overlay from the object's current shape and toggles."""
        if not getattr(self, "switch", None):
            return
        self.switch.removeAllChildren()
        obj = self.vobj.Object
        if obj.Shape.isNull() or not self.vobj.Visibility:
            return
        if getattr(self.vobj, "ShowControlNet", False):
            net = obj.Proxy.control_net(obj)
            if net:
                self.switch.addChild(_lines_node(self._local(net), NET_COLOR, 1.0, True))
        if getattr(self.vobj, "ShowCurvatureComb", False) and obj.Shape.Edges:
            self.switch.addChild(_lines_node(self._local(self.comb(obj)), COMB_COLOR, 1.0, False))

    def comb(self, obj) -> List[List[App.Vector]]:
        """Teeth and the envelope through their tips (placed coordinates)."""
        edge = obj.Shape.Edges[0]
        samples = min(max(int(self.vobj.CombSamples), COMB_SAMPLES[1]), COMB_SAMPLES[2])
        scale = float(self.vobj.CombScale) or analysis.auto_comb_scale(edge, samples)
        teeth = analysis.curvature_comb(edge, samples, scale)
        return [[a, b] for a, b in teeth] + [[b for _, b in teeth]]

    # --- FreeCAD protocol -------------------------------------------------------------------
    def updateData(self, obj, prop: str) -> None:
        if prop in ("Shape", "Placement"):
            self.refresh()

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
        if mode != 0:
            return False
        from .taskpanel import TaskPanel
        self.panel = TaskPanel(vobj.Object)
        Gui.Control.showDialog(self.panel)
        return True

    def unsetEdit(self, vobj, mode: int = 0) -> bool:
        if mode != 0:
            return False
        Gui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj) -> bool:
        Gui.ActiveDocument.setEdit(vobj.Object, 0)
        return True



def attach(obj) -> None:
    """Give a workbench object its view provider (GUI only)."""
    from . import curves
    is_curve = isinstance(obj.Proxy, (curves.BezierCurve, curves.BSplineCurve, curves.InterpolationCurve,
                                      curves.CubicSpline, curves.HermiteCurve, curves.JoinCurve))
    ViewProvider(obj.ViewObject, is_curve)
