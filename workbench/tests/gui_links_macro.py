"""GUI test macro of the task panel's link rows (cagdwb/linkedit.py), run by the FreeCAD
GUI under Xvfb like gui_edit_macro.py (tests/workbench/test_gui_links.py):

    CAGD_WB_OUT=/tmp/out QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a freecad workbench/tests/gui_links_macro.py

The selection is made through FreeCADGui.Selection and the buttons are pressed by real
Qt mouse events (press and release at the button's centre). The oracle of a changed
Gordon surface is the engine's cagd.gordon on the same edges (Part's Area and points
of both); Cancel must restore the links and the shape. The summary goes to
``$CAGD_WB_OUT/result.json``; ``os._exit`` ends FreeCAD.
"""
import os
import sys

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_support import QtCore, QtWidgets, check, log, run, settle, step  # noqa: E402
from cagdwb.qt import QtGui  # noqa: E402

V = App.Vector
STATE = {}
SAME = 1e-9                     # relative agreement of Part's Area / bounds with the engine's surface


def click(button):
    """A left click on ``button``: mouse press and release at its centre, sent through Qt."""
    check(button.isVisible() and button.isEnabled(), f"button {button.text()!r} not clickable")
    centre = QtCore.QPointF(button.rect().center())
    for kind, buttons in ((QtCore.QEvent.MouseButtonPress, QtCore.Qt.LeftButton),
                          (QtCore.QEvent.MouseButtonRelease, QtCore.Qt.NoButton)):
        event = QtGui.QMouseEvent(kind, centre, QtCore.Qt.LeftButton, buttons, QtCore.Qt.NoModifier)
        QtWidgets.QApplication.sendEvent(button, event)
    settle()


def select(*picks):
    Gui.Selection.clearSelection()
    for obj, sub in picks:
        Gui.Selection.addSelection(App.ActiveDocument.Name, obj.Name, sub)
    settle()


def open_panel(obj):
    Gui.ActiveDocument.setEdit(obj.Name, 0)
    settle()
    check(Gui.Control.activeDialog(), f"{obj.Label}: no task dialog")
    return obj.ViewObject.Proxy.panel


def cancel(panel):
    panel.reject()
    settle()
    check(not Gui.Control.activeDialog(), "task dialog still open after Cancel")


def listed(editor):
    return [editor.list.item(k).text() for k in range(editor.list.count())]


def engine_face(obj):
    """Part face of cagd.gordon on the object's linked edges (the oracle)."""
    from cagdwb import conversion
    from cagdwb.network import _curves
    profiles, _ = _curves(obj.Profiles, "Profiles")
    guides, _ = _curves(obj.Guides, "Guides")
    r = conversion.cagd.gordon(profiles, guides, float(obj.Tolerance))
    return conversion.surface_to_part(r.surface).toShape()


def agree(obj, what):
    """The object's face against the engine's Gordon surface of its links: relative
    difference of Part's Area, and the largest distance between Part's Surface.value of
    both at 21 x 21 parameters of the face's box (the same construction, the same
    parametrisation) relative to the face's size."""
    mine, engine = obj.Shape.Faces[0], engine_face(obj)
    area = abs(mine.Area - engine.Area) / engine.Area
    u0, u1, v0, v1 = mine.ParameterRange
    check(np.allclose(engine.ParameterRange, (u0, u1, v0, v1), rtol=0, atol=1e-12), "parameter boxes differ")
    gap = max((mine.Surface.value(u, v) - engine.Surface.value(u, v)).Length
              for u in np.linspace(u0, u1, 21) for v in np.linspace(v0, v1, 21)) / engine.BoundBox.DiagonalLength
    log(f"{what}: area {mine.Area:.9g} vs engine {engine.Area:.9g} ({area:.3g}), points {gap:.3g}")
    check(area <= SAME and gap <= SAME, f"{what}: area off {area:.3g}, points off {gap:.3g}")


@step
def setup():
    """A network of iso-curves of a wavy bicubic patch: three profiles, three guides; the
    Gordon surface links the three profiles and the outer two guides."""
    import Part
    from cagdwb import conversion, network
    Gui.activateWorkbench("CagdWorkbench")
    doc = App.newDocument("LinkPanel")
    settle()
    i, j = np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij")
    P = np.stack([12 * i, 12 * j, 6 * np.sin(1.3 * i + 0.9 * j) + 0.5 * i * j], -1)
    patch = conversion.surface_to_part(conversion.cagd.BezierSurface(P))

    def feature(shape, name):
        o = doc.addObject("Part::Feature", name)
        o.Shape = shape
        return o
    profiles = [feature(patch.vIso(t).toShape(), f"NetP{k}") for k, t in enumerate((0.0, 0.5, 1.0))]
    guides = [feature(patch.uIso(t).toShape(), f"NetG{k}") for k, t in enumerate((0.0, 0.4, 1.0))]
    gordon = network.make_gordon([(o, "Edge1") for o in profiles], [(guides[0], "Edge1"), (guides[2], "Edge1")],
                                 doc=doc)
    ring = feature(Part.makeCircle(3.0, V(80, 0, 0)), "Ring")
    short = feature(Part.makeLine(V(80, 0, 0), V(80, 0, 20)), "ShortPath")
    long = feature(Part.makeLine(V(80, 0, 0), V(80, 0, 35)), "LongPath")
    sweep = network.make_sweep((ring, "Edge1"), (short, "Edge1"), doc=doc)
    doc.recompute()
    for o in (gordon, sweep):
        check(o.isValid() and o.Message == "ok", f"{o.Label}: {o.Message}")
    STATE.update(doc=doc, profiles=profiles, guides=guides, gordon=gordon, ring=ring, short=short, long=long,
                 sweep=sweep)
    agree(gordon, "3 x 2 network")


@step
def every_link_property_has_a_row():
    """Each network object's panel lists each of its link properties with the buttons of
    its type (a list: Add selection, Remove, Up, Down; a single link: Set from selection)."""
    from cagdwb import features, linkedit, network
    doc = STATE["doc"]
    for cls in network.KINDS.values():
        obj = features.make(cls, doc=doc)
        links = {n: obj.getTypeIdOfProperty(n) for n in obj.PropertiesList
                 if obj.getTypeIdOfProperty(n) in linkedit.KINDS}
        check(set(links) >= set(cls.LINKS), f"{cls.__name__}: links {sorted(links)}")
        panel = open_panel(obj)
        for name, kind in links.items():
            editor = panel.widgets.get(name)
            check(isinstance(editor, linkedit.LinkEditor), f"{cls.__name__}.{name}: no link row")
            want = ["Add selection", "Remove", "Up", "Down"] if kind in linkedit.LIST_KINDS else ["Set from selection"]
            check(list(editor.buttons) == want, f"{cls.__name__}.{name}: buttons {list(editor.buttons)}")
        cancel(panel)
        doc.removeObject(obj.Name)
    doc.recompute()


@step
def gordon_guide_added_moved_removed_and_cancelled():
    """Add selection puts the middle guide into Guides: the surface changes and equals
    the engine's Gordon surface of the new network; Up reorders (same surface: the engine
    sorts the curves); Remove of a boundary guide is an error naming the profile that no
    longer ends on a guide, down to one guide one saying Guides needs two; an empty
    selection is refused; Cancel restores the two links and the shape."""
    doc, gordon, guides = STATE["doc"], STATE["gordon"], STATE["guides"]
    original = [(o.Name, s) for o, s in gordon.Guides]
    area0 = gordon.Shape.Area
    panel = open_panel(gordon)
    editor = panel.widgets["Guides"]
    check(listed(editor) == ["NetG0.Edge1", "NetG2.Edge1"], f"listed {listed(editor)}")
    check(listed(panel.widgets["Profiles"]) == ["NetP0.Edge1", "NetP1.Edge1", "NetP2.Edge1"], "profiles listed")
    select()
    click(editor.buttons["Add selection"])
    check("nothing selected" in panel.message.text() and len(gordon.Guides) == 2, panel.message.text())
    select((guides[1], "Edge1"))
    click(editor.buttons["Add selection"])
    check(listed(editor) == ["NetG0.Edge1", "NetG2.Edge1", "NetG1.Edge1"], f"after Add: {listed(editor)}")
    check(gordon.isValid() and panel.message.text() == "ok", panel.message.text())
    area3 = gordon.Shape.Area
    check(abs(area3 - area0) > 1e-6 * area0, f"shape unchanged by the third guide: {area3} vs {area0}")
    agree(gordon, "3 x 3 network after Add selection")
    check(editor.list.currentRow() == 2, f"current row {editor.list.currentRow()}")
    click(editor.buttons["Up"])
    check(listed(editor) == ["NetG0.Edge1", "NetG1.Edge1", "NetG2.Edge1"], f"after Up: {listed(editor)}")
    check(gordon.isValid() and abs(gordon.Shape.Area - area3) <= SAME * area3, "reordered guides changed the shape")
    agree(gordon, "3 x 3 network after Up")
    editor.list.setCurrentRow(0)
    click(editor.buttons["Down"])
    check(listed(editor) == ["NetG1.Edge1", "NetG0.Edge1", "NetG2.Edge1"], f"after Down: {listed(editor)}")
    click(editor.buttons["Remove"])                  # row 1 (NetG0, a boundary guide) is current after Down
    message = panel.message.text()
    log(f"boundary guide removed: {message}")
    check(listed(editor) == ["NetG1.Edge1", "NetG2.Edge1"], f"after Remove: {listed(editor)}")
    check(not gordon.isValid() and gordon.Shape.isNull(), "a network without its boundary guide accepted")
    check(message.startswith("error:") and "Profiles[0] (NetP0.Edge1)" in message and
          "meets Guides[0] (NetG1.Edge1)" in message and "first and last curve" in message, message)
    check(editor.list.currentRow() == 1, f"current row {editor.list.currentRow()}")
    click(editor.buttons["Remove"])                  # one guide left: not a network
    message = panel.message.text()
    log(f"one guide left: {message}")
    check(listed(editor) == ["NetG1.Edge1"] and not gordon.isValid(), f"after Remove: {listed(editor)}")
    check(message.startswith("error:") and "Guides" in message and "need 2" in message, message)
    cancel(panel)
    check([(o.Name, s) for o, s in gordon.Guides] == original, f"Cancel: guides {gordon.Guides}")
    check(gordon.isValid() and gordon.Message == "ok", gordon.Message)
    check(abs(gordon.Shape.Area - area0) <= 1e-12 * area0, f"Cancel: area {gordon.Shape.Area} vs {area0}")
    doc.recompute()


@step
def sweep_path_set_from_selection():
    """Set from selection replaces the sweep's Path: the cylinder grows to the new path's
    length (its vertices); two selected elements are refused; Cancel restores it."""
    sweep, short, long, ring = STATE["sweep"], STATE["short"], STATE["long"], STATE["ring"]
    panel = open_panel(sweep)
    editor = panel.widgets["Path"]
    check(listed(editor) == ["ShortPath.Edge1"], f"listed {listed(editor)}")
    select((long, "Edge1"), (ring, "Edge1"))
    click(editor.buttons["Set from selection"])
    check("select one element" in panel.message.text() and sweep.Path[0] is short, panel.message.text())
    select((long, "Edge1"))
    click(editor.buttons["Set from selection"])
    heights = sorted(v.Point.z for v in sweep.Shape.Vertexes)
    check(listed(editor) == ["LongPath.Edge1"] and sweep.isValid() and panel.message.text() == "ok",
          f"{listed(editor)}: {panel.message.text()}")
    check(abs(heights[-1] - 35.0) <= 1e-9 and abs(heights[0]) <= 1e-9, f"sweep vertices at z {heights}")
    select((short, "Vertex1"))
    click(editor.buttons["Set from selection"])
    check(panel.message.text().startswith("error:") and "Path" in panel.message.text(), panel.message.text())
    cancel(panel)
    check(sweep.Path[0] is short and sweep.isValid(), f"Cancel: path {sweep.Path}")
    check(abs(max(v.Point.z for v in sweep.Shape.Vertexes) - 20.0) <= 1e-9, "Cancel: height")


@step
def blend_curve_panel():
    """The Blend curve's panel offers G3 (the combo box makes a degree-7 bridge meeting
    both edges G3 by the engine's measure), its tangent-scale rows are disabled while
    AutomaticScales is on and enabled when the check box is cleared (the typed scales
    then used); its Edge1/Edge2 rows set from the selection; Cancel undoes it all."""
    import Part
    from cagdwb import network
    doc = STATE["doc"]
    a = doc.addObject("Part::Feature", "BridgeA")
    a.Shape = Part.BSplineCurve([V(0, 60, 0), V(10, 68, 0), V(20, 62, 3), V(30, 70, 0)]).toShape()
    b = doc.addObject("Part::Feature", "BridgeB")
    b.Shape = Part.ArcOfEllipse(Part.Ellipse(V(60, 80, 5), 12.0, 5.0), 2.5, 4.0).toShape()
    c = doc.addObject("Part::Feature", "BridgeC")
    c.Shape = Part.makeLine(V(55, 60, 0), V(75, 50, 5))
    obj = network.make_blend_curve((a, "Edge1"), (b, "Edge1"), doc=doc, End1="end", End2="start")
    doc.recompute()
    check(obj.isValid() and obj.Shape.Edges[0].Curve.Degree == 5, obj.Message)
    before = (obj.UsedScale1, obj.UsedScale2)
    panel = open_panel(obj)
    w = panel.widgets
    combo = w["Continuity"]
    check([combo.itemText(k) for k in range(combo.count())] == ["G1", "G2", "G3"], "Continuity choices")
    check(w["AutomaticScales"].isChecked() and not w["TangentScale1"].isEnabled() and
          not w["TangentScale2"].isEnabled(), "scale rows enabled while automatic")
    combo.setCurrentText("G3")
    settle()
    check(obj.Continuity == "G3" and obj.isValid() and obj.Shape.Edges[0].Curve.Degree == 7 and
          obj.MaxCurvatureDerivativeGap <= 1e-9 and panel.message.text() == "ok",
          f"G3: {obj.Message}, gap {obj.MaxCurvatureDerivativeGap}")
    auto = (obj.UsedScale1, obj.UsedScale2)
    w["AutomaticScales"].setChecked(False)
    settle()
    check(w["TangentScale1"].isEnabled() and w["TangentScale2"].isEnabled(), "scale rows disabled when explicit")
    w["TangentScale1"].setValue(1.7)
    settle()
    check((obj.UsedScale1, obj.UsedScale2) == (1.7, 1.0) and obj.isValid(),
          f"explicit scales used {obj.UsedScale1}, {obj.UsedScale2} (automatic were {auto})")
    select((c, "Edge1"))
    click(w["Edge2"].buttons["Set from selection"])
    check(listed(w["Edge2"]) == ["BridgeC.Edge1"] and obj.isValid(), f"Edge2: {obj.Message}")
    e = obj.Shape.Edges[0]
    check((e.valueAt(e.LastParameter) - V(55, 60, 0)).Length <= 1e-9, "bridge does not end at BridgeC's start")
    cancel(panel)
    check(obj.Continuity == "G2" and obj.AutomaticScales and obj.Edge2[0] is b and
          (obj.UsedScale1, obj.UsedScale2) == before and obj.Shape.Edges[0].Curve.Degree == 5,
          f"Cancel: {obj.Continuity}, {obj.AutomaticScales}, {obj.Edge2}, {obj.UsedScale1}, {obj.UsedScale2}")


def leave_edit_mode():
    if Gui.Control.activeDialog():
        Gui.Control.closeDialog()


QtCore.QTimer.singleShot(500, lambda: run(leave_edit_mode))
