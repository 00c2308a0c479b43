"""Pole edit mode: shape a curve or surface by dragging its poles (or the points an
interpolating curve passes through) in the 3-D view.

Double-click a Bezier / B-spline curve or surface, a Bezier triangle, an interpolating
curve or a cubic spline (or run Cagd_EditPoles): the points are drawn as markers on
top of the scene; the left mouse drags the picked one in the view plane through it,
with Shift held along the net's normal at that pole (surfaces given by a grid) or in
depth along the view direction (the pointer's travel up the screen), or held to the
X, Y or Z axis chosen in the panel ("Drag along"), optionally snapped to a grid ("Snap",
poledrag.snapped); the object's
property changes and the shape, net and comb recompute while dragging; each drag is
one undo step; Esc cancels a drag, or leaves the mode. A point given by a linked
vertex moves that vertex when it is a point object (Part Vertex, Draft Point: X, Y, Z
properties); a vertex of another shape is refused with the reason in the status bar.
The task panel shows the picked pole and, for rational objects (or to make one), its
weight. On B-spline curve and surface objects the panel and the view's context menu
also insert a knot at the parameter nearest the picked pole, elevate the degree and
remove knots within a tolerance (the deviation reported in the status bar and report
view), each one undo step with the shape kept (knotedit.py, no GUI). The geometry is
in poledrag.py (no GUI); this module maps mouse events to it.
"""
from __future__ import annotations

import time
from typing import List, Optional, Tuple

import numpy as np

import FreeCAD as App

from . import conversion, knotedit, poledrag
from .conversion import cagd

EDIT_POLES = 10                  # the view providers' edit mode number of this mode (0: the property panel)
POINT_PROPERTIES = ("Poles", "Points")
PICK_PIXELS = 8.0                # pick radius around a marker, pixels
MARKER_PIXELS = 7.0              # markers are GL points, one draw call (an SoMarkerSet draws a bitmap per marker)
PICKED_PIXELS = 11.0
MARKER_COLOR = (0.1, 0.1, 0.1)
PICKED_COLOR = (1.0, 0.55, 0.0)
WEIGHT_RANGE = (1e-6, 1e6)
SNAP_MAX = 1e6                   # the largest snap grid the panel offers (mm)
DRAG_DEVIATION = 1.0             # display Deviation (%) of a face while dragging: 5x coarser than FreeCAD's 0.2,
                                 # a 30 x 30 net's face meshes in a quarter of the time; restored on release


# --- the object's points (no GUI) ---------------------------------------------------------------
def point_property(obj) -> Optional[str]:
    """The vector list property the editor drags (Poles, or Points of the interpolating
    curves), or None for an object that has none (Coons patch, fits, queries)."""
    for name in POINT_PROPERTIES:
        if name in obj.PropertiesList and obj.getTypeIdOfProperty(name) == "App::PropertyVectorList" \
                and obj.getGroupOfProperty(name) in ("Curve", "Surface"):
            return name
    return None


def _matrix(placement) -> np.ndarray:
    return np.array(placement.toMatrix().A, dtype=float).reshape(4, 4)


def placed_points(obj) -> np.ndarray:
    """The edited points in global coordinates (the object's Placement applied), (n, 3)."""
    P = conversion.array(getattr(obj, point_property(obj)))
    M = _matrix(obj.Placement)
    return P @ M[:3, :3].T + M[:3, 3]


def surface_normals(obj) -> Optional[np.ndarray]:
    """Unit normals of the pole grid at each point (global, flat like the property),
    for objects whose points form CountU rows; None otherwise (curves, triangles)."""
    count_u = int(getattr(obj, "CountU", 0) or 0)
    P = placed_points(obj)
    if count_u < 2 or len(P) % count_u or len(P) // count_u < 2:
        return None
    return poledrag.net_normals(P.reshape(count_u, -1, 3)).reshape(-1, 3)


def vertex_links(obj) -> List[Tuple[object, Optional[str]]]:
    """(object, sub-element or None) giving each point, in order, when the points come
    from linked Vertices; empty otherwise."""
    out = []
    for o, subs in getattr(obj, "Vertices", None) or []:
        subs = [s for s in (subs or []) if s]
        out.extend([(o, s) for s in subs] if subs else [(o, None)])
    return out


def refusal(obj, index: int) -> Optional[str]:
    """Why point ``index`` cannot be dragged (a linked vertex of a shape that has no
    X, Y, Z of its own), or None when it can."""
    links = vertex_links(obj)
    if not links:
        return None
    if not 0 <= index < len(links):
        return f"Vertices: no linked vertex for point {index} ({len(links)} linked)"
    o, sub = links[index]
    movable = all(n in o.PropertiesList for n in ("X", "Y", "Z")) and len(o.Shape.Vertexes) == 1
    if movable:
        return None
    name = f"{o.Label}.{sub}" if sub else o.Label
    return (f"Vertices: point {index} is the linked vertex {name}, which cannot be moved from here "
            f"(move {o.Label} itself, or unlink the vertices)")


def set_point(obj, index: int, point) -> "App.Vector":
    """Move point ``index`` to ``point`` (global coordinates): the property entry (in
    the object's local coordinates), or the linked point object's X, Y, Z (in its own);
    returns the point in the object's local coordinates (the markers' frame).
    CagdError naming the property for an index out of range or a vertex that cannot move."""
    name = point_property(obj)
    if name is None:
        raise cagd.CagdError(f"{obj.Label}: has no poles or points to edit")
    values = list(getattr(obj, name))
    if not 0 <= index < len(values):
        raise cagd.CagdError(f"{name}: index {index} out of range (0..{len(values) - 1})")
    p = App.Vector(*map(float, point))
    if vertex_links(obj):
        reason = refusal(obj, index)
        if reason:
            raise cagd.CagdError(reason)
        target = vertex_links(obj)[index][0]
        local = target.Placement.inverse().multVec(p)
        target.X, target.Y, target.Z = local.x, local.y, local.z
        return obj.Placement.inverse().multVec(p)
    values[index] = obj.Placement.inverse().multVec(p)
    setattr(obj, name, values)
    return values[index]


def has_weights(obj) -> bool:
    """True when the edited points are poles with a Weights list (not the points an
    interpolating object passes through)."""
    return point_property(obj) == "Poles" and "Weights" in obj.PropertiesList and \
        not getattr(obj, "Interpolate", False)


def set_weight(obj, index: int, weight: float) -> None:
    """Weight of pole ``index``; an empty Weights list (polynomial) becomes all ones first."""
    if not has_weights(obj):
        raise cagd.CagdError(f"{obj.Label}: has no pole weights")
    if not WEIGHT_RANGE[0] <= weight <= WEIGHT_RANGE[1]:
        raise cagd.CagdError(f"Weights: weight {weight!r} outside {WEIGHT_RANGE[0]:g}..{WEIGHT_RANGE[1]:g}")
    count = len(obj.Poles)
    W = list(obj.Weights) if len(obj.Weights) == count else [1.0] * count
    if not 0 <= index < count:
        raise cagd.CagdError(f"Weights: index {index} out of range (0..{count - 1})")
    W[index] = float(weight)
    obj.Weights = W


# --- the edit mode (GUI) ------------------------------------------------------------------------
def _vec(v) -> np.ndarray:
    return np.array([v[0], v[1], v[2]], dtype=float)


class PoleEditor:
    """The edit mode of one object: markers under its view provider's root, an event
    callback on the 3-D view, a task panel. ``close()`` removes them all."""

    def __init__(self, vobj):
        import FreeCADGui as Gui
        from pivy import coin
        self.coin, self.vobj, self.obj = coin, vobj, vobj.Object
        self.doc = self.obj.Document
        self.view = Gui.getDocument(self.doc.Name).ActiveView
        self.picked: Optional[int] = None
        self.drag: Optional[dict] = None
        self.redraws, self.busy = 0, 0.0          # property updates made by drags and their seconds (for tests)
        self.axis: Optional[np.ndarray] = None     # a drag held to X, Y or Z (the panel's Drag along)
        self.snap = 0.0                            # the grid the dragged point snaps to (0: none)
        self.root = coin.SoAnnotation()
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        self.root.addChild(pick)
        self.coords, self.picked_coords = coin.SoCoordinate3(), coin.SoCoordinate3()
        for coords, color, size in ((self.coords, MARKER_COLOR, MARKER_PIXELS),
                                    (self.picked_coords, PICKED_COLOR, PICKED_PIXELS)):
            sep = coin.SoSeparator()
            base = coin.SoBaseColor()
            base.rgb = color
            style = coin.SoDrawStyle()
            style.pointSize = size
            for node in (base, style, coords, coin.SoPointSet()):
                sep.addChild(node)
            self.root.addChild(sep)
        vobj.RootNode.addChild(self.root)
        self.refresh()
        self.callback = self.view.addEventCallbackPivy(coin.SoEvent.getClassTypeId(), self.on_event)
        self.panel = PolePanel(self)
        self.shown = not Gui.Control.activeDialog()       # another task dialog open: editing without the panel
        if self.shown:
            Gui.Control.showDialog(self.panel)

    # --- drawing -------------------------------------------------------------------------------
    def refresh(self) -> None:
        """Markers at the property's points (local coordinates: the root is placed);
        during a drag only the dragged point's two markers move (its other points are
        unchanged), in place."""
        local = self.drag.get("local") if self.drag is not None else None
        if local is not None:
            p = [float(local.x), float(local.y), float(local.z)]
            self.coords.point.set1Value(self.drag["index"], p)
            self.picked_coords.point.setValues(0, 1, [p])
            self.panel.show_point(self.drag["index"], local)
            return
        name = point_property(self.obj)
        P = conversion.array(getattr(self.obj, name)) if name else np.zeros((0, 3))
        self.coords.point.setNum(len(P))
        self.coords.point.setValues(0, len(P), P.tolist())
        chosen = P[self.picked:self.picked + 1] if self.picked is not None and self.picked < len(P) else P[:0]
        self.picked_coords.point.setNum(len(chosen))
        self.picked_coords.point.setValues(0, len(chosen), chosen.tolist())
        if hasattr(self, "panel"):
            self.panel.show_pick()

    def close(self) -> None:
        if self.drag is not None:
            self.doc.commitTransaction()
            self.end_drag()
        self.view.removeEventCallbackPivy(self.coin.SoEvent.getClassTypeId(), self.callback)
        self.vobj.RootNode.removeChild(self.root)

    # --- mouse and keys --------------------------------------------------------------------------
    def ray(self, x: float, y: float) -> Tuple[np.ndarray, np.ndarray]:
        """(point on the focal plane under the pixel, direction into the scene)."""
        p = _vec(self.view.getPoint(int(x), int(y)))
        cam = self.view.getCameraNode()
        if cam.isOfType(self.coin.SoPerspectiveCamera.getClassTypeId()):
            return p, p - _vec(cam.position.getValue())
        return p, _vec(self.view.getViewDirection())

    def pixel(self, x: float, y: float) -> float:
        """Size of a pixel on the focal plane (model units)."""
        a, b = (_vec(self.view.getPoint(int(x) + k, int(y))) for k in (0, 1))
        return float(np.linalg.norm(b - a))

    def on_event(self, cb) -> None:
        coin = self.coin
        ev = cb.getEvent()
        x, y = ev.getPosition().getValue()
        if ev.isOfType(coin.SoKeyboardEvent.getClassTypeId()):
            if ev.getKey() == coin.SoKeyboardEvent.ESCAPE and ev.getState() == coin.SoButtonEvent.DOWN:
                cb.setHandled()
                self.escape()
            return
        if ev.isOfType(coin.SoMouseButtonEvent.getClassTypeId()):
            if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
                return
            if ev.getState() == coin.SoButtonEvent.DOWN and self.press(x, y):
                cb.setHandled()
            elif ev.getState() == coin.SoButtonEvent.UP and self.drag is not None:
                self.release()
                cb.setHandled()
            return
        if ev.isOfType(coin.SoLocation2Event.getClassTypeId()) and self.drag is not None:
            self.move(x, y, ev.wasShiftDown())
            cb.setHandled()

    def press(self, x: float, y: float) -> bool:
        """Pick the point under the pointer and open the drag's transaction; False when
        nothing is picked (the event goes on to navigation and selection)."""
        origin, direction = self.ray(x, y)
        P = placed_points(self.obj)
        index = poledrag.pick_pole(P, origin, direction, PICK_PIXELS * max(self.pixel(x, y), 1e-300))
        if index is None:
            return False
        self.picked = index
        reason = refusal(self.obj, index)
        if reason:
            _status(f"Edit poles: {reason}")
            self.refresh()
            return True
        view_dir = _vec(self.view.getViewDirection())
        normals = surface_normals(self.obj)
        normal = None if normals is None or not normals[index].any() else normals[index]
        up = _vec(self.view.getCameraOrientation().multVec(App.Vector(0, 1, 0)))
        self.drag = {"index": index, "anchor": P[index], "view": view_dir, "normal": normal, "up": up,
                     "start": origin, "grab": poledrag.drag_in_plane(P[index], view_dir, origin, direction)}
        if normal is not None:
            try:
                self.drag["grab_along"] = poledrag.drag_along(P[index], normal, origin, direction)
            except cagd.CagdError:
                self.drag["normal"] = None
        self.drag["axis"] = None
        if self.axis is not None:           # held to X, Y or Z (unless it points at the viewer)
            try:
                self.drag["grab_axis"] = poledrag.drag_along(P[index], self.axis, origin, direction)
                self.drag["axis"] = self.axis
            except cagd.CagdError as exc:
                _status(f"Edit poles: {exc}; dragging in the view plane")
        self.doc.openTransaction(f"Drag {point_property(self.obj)[:-1].lower()} {index} of {self.obj.Label}")
        self.coarse(True)
        viewer = self.view.getViewer()
        self.drag["navicube"] = viewer.isEnabledNaviCube()
        viewer.setEnabledNaviCube(False)
        self.refresh()
        return True

    def set_axis(self, name: str) -> None:
        """Hold the next drags to the axis ``name`` of poledrag.AXES (None: the view plane)."""
        axis = poledrag.AXES[str(name)]
        self.axis = None if axis is None else np.array(axis)

    def set_snap(self, step: float) -> None:
        self.snap = float(step)

    def end_drag(self) -> None:
        """The drag is over: the face's own Deviation and the navigation cube back. The
        cube is off while dragging: FreeCAD 0.20 draws it in pick mode and waits for the
        GL pipeline (glFinish, glReadPixels) on every mouse move over the view, 10-13 ms
        a move with software OpenGL, and it cannot be used during a drag anyway."""
        drag, self.drag = self.drag, None
        self.coarse(False)
        if drag is not None and drag.get("navicube"):
            self.view.getViewer().setEnabledNaviCube(True)

    def coarse(self, on: bool) -> None:
        """A face drawn with DRAG_DEVIATION while dragging, its own Deviation again after."""
        vobj = self.vobj
        if not self.obj.Shape.Faces or "Deviation" not in vobj.PropertiesList:
            return
        if on and vobj.Deviation < DRAG_DEVIATION:
            self.deviation = vobj.Deviation
            vobj.Deviation = DRAG_DEVIATION
        elif not on and getattr(self, "deviation", None) is not None:
            vobj.Deviation, self.deviation = self.deviation, None

    def target(self, x: float, y: float, shift: bool) -> np.ndarray:
        """Where the dragged point goes for the pointer at (x, y)."""
        d = self.drag
        origin, direction = self.ray(x, y)
        if d["axis"] is not None and not shift:
            return d["anchor"] + poledrag.drag_along(d["anchor"], d["axis"], origin, direction) - d["grab_axis"]
        if not shift:
            return d["anchor"] + poledrag.drag_in_plane(d["anchor"], d["view"], origin, direction) - d["grab"]
        if d["normal"] is not None:
            try:
                return d["anchor"] + poledrag.drag_along(d["anchor"], d["normal"], origin, direction) - d["grab_along"]
            except cagd.CagdError:
                pass
        return poledrag.drag_in_depth(d["anchor"], d["view"], d["start"], origin, d["up"])

    def move(self, x: float, y: float, shift: bool = False) -> None:
        started = time.perf_counter()
        try:
            point = poledrag.snapped(self.target(x, y, shift), self.snap, None if shift else self.drag["axis"])
        except cagd.CagdError as exc:
            _status(f"Edit poles: {exc}")
            return
        self.drag["local"] = set_point(self.obj, self.drag["index"], point)
        self.doc.recompute()                 # the view provider's updateData redraws net, comb and markers
        self.view.redraw()                   # one paint per move, now (not when Coin's delay queue fires)
        self.redraws += 1
        self.busy += time.perf_counter() - started

    def release(self) -> None:
        self.doc.commitTransaction()
        self.end_drag()
        self.refresh()

    def escape(self) -> None:
        """Esc: cancel the drag in progress (its changes undone), else leave the mode."""
        if self.drag is not None:
            self.end_drag()
            self.doc.abortTransaction()
            self.doc.recompute()
            self.refresh()
            return
        from .qt import QtCore
        QtCore.QTimer.singleShot(0, _leave)

    def change_weight(self, weight: float) -> None:
        """The picked pole's weight, one undo step."""
        if self.picked is None:
            return
        self.doc.openTransaction(f"Weight of pole {self.picked} of {self.obj.Label}")
        try:
            set_weight(self.obj, self.picked, weight)
        except cagd.CagdError as exc:
            self.doc.abortTransaction()
            _status(f"Edit poles: {exc}")
            return
        self.doc.recompute()
        self.doc.commitTransaction()
        self.refresh()

    KNOT_EDITS = ("Insert knot", "Elevate degree", "Remove knots")

    def knot_edit(self, title: str, direction: str = "Both", tol: float = knotedit.REMOVE_TOL) -> Optional[str]:
        """One of KNOT_EDITS on the object (Insert knot: at the parameter nearest the
        picked pole; a surface in ``direction``), one undo step; its message (None on a
        refusal) goes to the status bar and the report view."""
        if title == "Insert knot" and self.picked is None:
            _status("Edit poles: pick a pole first (the knot goes at the curve's or surface's point nearest it)")
            return None
        edit = {"Insert knot": lambda g: knotedit.insert_knot(g, self.picked, direction),
                "Elevate degree": lambda g: knotedit.elevate(g, direction),
                "Remove knots": lambda g: knotedit.remove_knots(g, tol, direction)}[title]
        try:
            message = knotedit.run(self.obj, title, edit)[1]
        except cagd.CagdError as exc:
            _status(f"Edit poles: {exc}")
            return None
        self.picked = None                      # the pole indices changed
        _status(f"{title} ({self.obj.Label}): {message}", warning=False)
        self.refresh()
        return message

    def context_actions(self, menu) -> None:
        """The knot and degree edits in the view's context menu (B-spline objects);
        Remove knots asks for the tolerance (a surface: the panel's direction)."""
        if knotedit.refusal(self.obj):
            return
        from .qt import QtWidgets
        panel = self.panel
        menu.addAction("Insert knot at picked pole").triggered.connect(
            lambda checked=False: self.knot_edit("Insert knot", panel.direction()))
        menu.addAction("Elevate degree").triggered.connect(
            lambda checked=False: self.knot_edit("Elevate degree", panel.direction()))

        def remove(checked=False):
            tol, ok = QtWidgets.QInputDialog.getDouble(None, "Remove knots", "Tolerance (mm)",
                                                       float(panel.tol.value()), 1e-9, 1e3, 9)
            if ok:
                self.knot_edit("Remove knots", panel.direction(), float(tol))
        menu.addAction("Remove knots...").triggered.connect(remove)


def _status(message: str, warning: bool = True) -> None:
    import FreeCADGui as Gui
    (App.Console.PrintWarning if warning else App.Console.PrintMessage)(message + "\n")
    if Gui.getMainWindow() is not None:
        Gui.getMainWindow().statusBar().showMessage(message, 8000)


def _leave() -> None:
    import FreeCADGui as Gui
    if Gui.ActiveDocument is not None:
        Gui.ActiveDocument.resetEdit()


class PolePanel:
    """Task panel of the edit mode: the picked point and its weight; Close leaves."""

    def __init__(self, editor: PoleEditor):
        from .qt import QtWidgets
        self.editor = editor
        obj = editor.obj
        self.form = QtWidgets.QWidget()
        self.form.setWindowTitle(f"Edit poles of {obj.Label}")
        layout = QtWidgets.QFormLayout(self.form)
        layout.addRow(QtWidgets.QLabel("Drag a marker with the left mouse (Shift: along the normal / in depth); "
                                       "each drag is one undo step; Esc leaves."))
        self.along = QtWidgets.QComboBox()
        self.along.addItems(list(poledrag.AXES))
        self.along.currentTextChanged.connect(editor.set_axis)
        layout.addRow("Drag along", self.along)
        self.snap = QtWidgets.QDoubleSpinBox()
        self.snap.setDecimals(4)
        self.snap.setRange(0.0, SNAP_MAX)
        self.snap.setToolTip("Grid spacing the dragged point snaps to (mm; 0: no snap)")
        self.snap.valueChanged.connect(editor.set_snap)
        layout.addRow("Snap (mm)", self.snap)
        self.label = QtWidgets.QLabel("none")
        layout.addRow("Picked", self.label)
        self.weight = QtWidgets.QDoubleSpinBox()
        self.weight.setRange(*WEIGHT_RANGE)
        self.weight.setDecimals(4)
        self.weight.setSingleStep(0.1)
        self.weight.setEnabled(False)
        self.weight.editingFinished.connect(lambda: editor.change_weight(float(self.weight.value())))
        if has_weights(obj):
            layout.addRow("Weight", self.weight)
        self.directions = QtWidgets.QComboBox()
        self.directions.addItems(list(knotedit.DIRECTIONS))
        self.tol = QtWidgets.QDoubleSpinBox()
        self.tol.setDecimals(9)
        self.tol.setRange(1e-9, 1e3)
        self.tol.setValue(knotedit.REMOVE_TOL)
        self.buttons = {}
        if not knotedit.refusal(obj):
            if obj.Shape.Faces:
                layout.addRow("Direction", self.directions)
            for title in editor.KNOT_EDITS:
                button = QtWidgets.QPushButton({"Insert knot": "Insert knot here"}.get(title, title))
                button.clicked.connect(lambda checked=False, t=title: editor.knot_edit(
                    t, self.direction(), float(self.tol.value())))
                self.buttons[title] = button
            layout.addRow(self.buttons["Insert knot"], self.buttons["Elevate degree"])
            layout.addRow("Tolerance (mm)", self.tol)
            layout.addRow(self.buttons["Remove knots"])
        self.show_pick()

    def direction(self) -> str:
        """A surface's direction of the knot and degree edits (Both, U, V)."""
        return str(self.directions.currentText())

    def show_point(self, i: int, p) -> None:
        """The picked point's index and coordinates (local)."""
        name = point_property(self.editor.obj) or "Points"
        self.label.setText(f"{name[:-1].lower()} {i}: ({p.x:.4g}, {p.y:.4g}, {p.z:.4g})")

    def show_pick(self) -> None:
        editor, obj = self.editor, self.editor.obj
        i = editor.picked
        name = point_property(obj)
        if "Insert knot" in self.buttons:
            self.buttons["Insert knot"].setEnabled(i is not None)
        if i is None or name is None or i >= len(getattr(obj, name)):
            self.label.setText("none")
            self.weight.setEnabled(False)
            return
        self.show_point(i, getattr(obj, name)[i])
        W = list(getattr(obj, "Weights", []) or [])
        self.weight.blockSignals(True)
        self.weight.setValue(W[i] if len(W) == len(getattr(obj, name)) else 1.0)
        self.weight.blockSignals(False)
        self.weight.setEnabled(True)

    def accept(self) -> bool:
        _leave()
        return True

    def reject(self) -> bool:
        _leave()
        return True

    def getStandardButtons(self) -> int:
        from .qt import QtWidgets
        return int(QtWidgets.QDialogButtonBox.Close)
