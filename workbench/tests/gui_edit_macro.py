"""GUI test macro of the pole edit mode (cagdwb/editpoles.py), run by the FreeCAD GUI
under Xvfb like gui_macro.py (tests/workbench/test_gui_edit.py):

    CAGD_WB_OUT=/tmp/out QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a freecad workbench/tests/gui_edit_macro.py

The drags are real Qt mouse events (press, moves, release) sent to the 3-D view's
viewport widget: they go through Quarter's translation to Coin events, the navigation
style and the scene graph to the editor's event callback, as a user's drag does. Each
step's checks are made here; the summary (with the measured redraw rates) goes to
``$CAGD_WB_OUT/result.json``, screenshots to ``$CAGD_WB_OUT``. ``os._exit`` ends FreeCAD.
"""
import os
import sys
import time

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_support import OUT, RESULT, QtCore, QtWidgets, check, log, run, settle, show_only, step  # noqa: E402
from cagdwb.qt import QtGui  # noqa: E402

RESULT["rates"] = {}
V = App.Vector
WIDTH, HEIGHT = 480, 360
MOVES = 30                     # mouse moves per measured drag
STATE = {}
CLICK_MARGIN = 0.05            # s beyond Qt's double-click interval between two presses
LAST_PRESS = [-1e9]            # time.monotonic() of the macro's last press


def vec(v):
    return np.array([v[0], v[1], v[2]], dtype=float)


class PaintCounter(QtCore.QObject):
    """Counts the viewport's paint events (one per redraw of the 3-D view)."""

    def __init__(self):
        super().__init__()
        self.count = 0

    def eventFilter(self, watched, event):
        if event.type() == QtCore.QEvent.Paint:
            self.count += 1
        return False


class Mouse:
    """Qt mouse events to the 3-D view's viewport at Coin pixel positions (origin at the
    bottom left, device pixels: the positions view.getPoint / getPointOnScreen use)."""

    def __init__(self, view):
        self.view = view
        self.widget = view.graphicsView().viewport()
        self.ratio = view.getSize()[0] / self.widget.width()

    def qt(self, x, y):
        height = self.view.getSize()[1]
        return QtCore.QPointF((x + 0.5) / self.ratio, (height - 1 - y + 0.5) / self.ratio)

    def send(self, kind, x, y, button, buttons, shift=False):
        mods = QtCore.Qt.ShiftModifier if shift else QtCore.Qt.NoModifier
        event = QtGui.QMouseEvent(kind, self.qt(x, y), button, buttons, mods)
        QtWidgets.QApplication.sendEvent(self.widget, event)

    def press(self, x, y, shift=False):
        """A press at least a double-click interval after the last one: FreeCAD's
        navigation style takes a press sooner than that for a double-click's second and
        hands it to the scene graph only with the release (NavigationStyle::
        processClickEvent), so a drag started then would not move (as for a user)."""
        wait = QtWidgets.QApplication.doubleClickInterval() / 1000.0 + CLICK_MARGIN - (time.monotonic() - LAST_PRESS[0])
        if wait > 0:
            time.sleep(wait)
        self.send(QtCore.QEvent.MouseButtonPress, x, y, QtCore.Qt.LeftButton, QtCore.Qt.LeftButton, shift)
        LAST_PRESS[0] = time.monotonic()

    def move(self, x, y, shift=False):
        self.send(QtCore.QEvent.MouseMove, x, y, QtCore.Qt.NoButton, QtCore.Qt.LeftButton, shift)

    def release(self, x, y, shift=False):
        self.send(QtCore.QEvent.MouseButtonRelease, x, y, QtCore.Qt.LeftButton, QtCore.Qt.NoButton, shift)

    def key(self, key):
        for kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease):
            QtWidgets.QApplication.sendEvent(self.widget, QtGui.QKeyEvent(kind, key, QtCore.Qt.NoModifier))


class Spy:
    """Wraps the editor's event callback to record the Coin positions it is given."""

    def __init__(self, editor):
        self.editor, self.positions = editor, []
        coin = editor.coin
        editor.view.removeEventCallbackPivy(coin.SoEvent.getClassTypeId(), editor.callback)
        editor.callback = editor.view.addEventCallbackPivy(coin.SoEvent.getClassTypeId(), self)
        self.inner = editor.on_event

    def __call__(self, cb):
        self.positions.append(tuple(cb.getEvent().getPosition().getValue()))
        self.inner(cb)


def drag(view, start, travel, shift=False, measure=None):
    """Press at the Coin position ``start``, move by ``travel`` pixels in MOVES steps
    (processing events after each, so the view redraws), release. Returns
    (seconds, paints, updates made by the editor, seconds the editor spent on them,
    seconds of one redraw of the unchanged scene afterwards, CPU seconds of the drag's
    moves in this thread and in all of FreeCAD's threads: software OpenGL rasterises
    in its own threads)."""
    mouse = Mouse(view)
    counter = PaintCounter()
    mouse.widget.installEventFilter(counter)
    editor = measure
    made, busy = (editor.redraws, editor.busy) if editor is not None else (0, 0.0)
    x0, y0 = start
    mouse.press(x0, y0, shift)
    settle(2)
    counter.count = 0
    t0, c0, p0 = time.perf_counter(), time.thread_time(), time.process_time()
    for k in range(1, MOVES + 1):
        mouse.move(x0 + travel[0] * k / MOVES, y0 + travel[1] * k / MOVES, shift)
        QtWidgets.QApplication.processEvents()
    QtWidgets.QApplication.processEvents()
    seconds = time.perf_counter() - t0
    cpu = (time.thread_time() - c0, time.process_time() - p0)
    paints = counter.count
    mouse.release(x0 + travel[0], y0 + travel[1], shift)
    settle(2)
    counter.count = 0                     # the same scene redrawn unchanged: the cost of a frame alone
    t0 = time.perf_counter()
    for _ in range(10):
        view.redraw()
        QtWidgets.QApplication.processEvents()
    frame = (time.perf_counter() - t0) / max(counter.count, 1)
    mouse.widget.removeEventFilter(counter)
    if editor is None:
        return seconds, paints, 0, 0.0, frame, cpu
    return seconds, paints, editor.redraws - made, editor.busy - busy, frame, cpu


def edge_points(obj, n=61):
    e = obj.Shape.Edges[0]
    return np.array([vec(e.valueAt(t)) for t in np.linspace(e.FirstParameter, e.LastParameter, n)])


def rate(name, seconds, paints, updates, busy, frame, cpu):
    """Record a drag's rates: redraws (paint events of the viewport) and property
    updates per second of the drag, and the editor's own milliseconds per update (event
    to recomputed shape, net, comb and markers; the rest is Qt and rendering); the CPU
    milliseconds per update of the GUI thread and of the others (OpenGL's rasterisers),
    which a loaded machine does not stretch as it stretches the wall clock."""
    size = Gui.ActiveDocument.ActiveView.getSize()
    per_update = 1000 * busy / max(updates, 1)
    main_cpu, other_cpu = (1000 * c / max(updates, 1) for c in (cpu[0], cpu[1] - cpu[0]))
    RESULT["rates"][name] = {"redraws_per_s": paints / seconds, "updates_per_s": updates / seconds,
                             "paints": paints, "updates": updates, "seconds": round(seconds, 3),
                             "editor_ms_per_update": per_update, "frame_ms": 1000 * frame,
                             "viewport": list(size), "load": os.getloadavg()[0],
                             "gui_cpu_ms_per_update": main_cpu, "other_cpu_ms_per_update": other_cpu}
    log(f"{name}: {paints} redraws, {updates} property updates in {seconds:.3f} s = "
        f"{paints / seconds:.1f} redraws/s, {updates / seconds:.1f} updates/s; editor {per_update:.1f}"
        f" ms per update, a redraw of the unchanged scene {1000 * frame:.1f} ms; viewport {size[0]} x {size[1]}, "
        f"load average {os.getloadavg()[0]:.1f}; CPU per update: GUI thread {main_cpu:.1f} ms, "
        f"others {other_cpu:.1f} ms")


@step
def setup():
    Gui.activateWorkbench("CagdWorkbench")
    App.newDocument("EditTest")
    settle()
    check("Cagd_EditPoles" in Gui.listCommands(), "Cagd_EditPoles not registered")


@step
def drag_curve_pole():
    """A 200-pole cubic with its comb, seen from the top: a drag of pole 100 by
    (40, 25) pixels moves the pole by the focal-plane displacement of the pointer
    (orthographic view), the edge by N_100(t) times it (OCCT's curve of that one pole
    as the oracle); one undo step restores pole and shape."""
    from cagdwb import curves
    doc = App.ActiveDocument
    x = np.linspace(0.0, 400.0, 200)
    obj = curves.make_bspline_curve([V(float(a), 10.0 * np.sin(a / 7.0), 0.0) for a in x], 3)
    doc.recompute()
    obj.ViewObject.ShowCurvatureComb = True
    view = show_only([obj], "viewTop")
    obj.ViewObject.Proxy.doubleClicked(obj.ViewObject)          # what a double-click in the tree or view calls
    settle()
    editor = obj.ViewObject.Proxy.editor
    check(editor is not None and Gui.Control.activeDialog(), "double-click did not start pole editing")
    spy = Spy(editor)
    k = 100
    before, poles, undo = edge_points(obj), [vec(p) for p in obj.Poles], len(doc.UndoNames)
    start = view.getPointOnScreen(obj.Poles[k])
    rate("curve 200 poles + comb", *drag(view, start, (40, 25), measure=editor))
    check(editor.picked == k, f"picked pole {editor.picked}, expected {k}")
    press = next(p for p in spy.positions)
    end = spy.positions[-1]
    moved = vec(view.getPoint(*end)) - vec(view.getPoint(*press))
    delta = vec(obj.Poles[k]) - poles[k]
    check(np.linalg.norm(moved) > 5.0 and np.linalg.norm(delta - moved) <= 1e-9 * 400,
          f"pole moved by {delta}, pointer by {moved}")
    others = max(np.linalg.norm(vec(p) - q) for i, (p, q) in enumerate(zip(obj.Poles, poles)) if i != k)
    check(others == 0.0, f"other poles moved by {others}")
    import Part
    e = obj.Shape.Edges[0]
    one = Part.BSplineCurve()            # the curve of pole k alone: N_k(t) delta (OCCT's basis)
    c = e.Curve
    one.buildFromPolesMultsKnots([V(*delta) if i == k else V(0, 0, 0) for i in range(200)], c.getMultiplicities(),
                                 c.getKnots(), False, 3)
    ts = np.linspace(e.FirstParameter, e.LastParameter, 61)
    expected = before + np.array([vec(one.value(t)) for t in ts])
    dev = np.abs(edge_points(obj) - expected).max()
    check(dev <= 1e-9 * 400, f"edge moved {dev:.3g} off N_k(t) delta")
    check(len(doc.UndoNames) == undo + 1, f"undo steps {doc.UndoNames[:3]} (was {undo})")
    doc.undo()
    settle()
    check(all(np.array_equal(vec(p), q) for p, q in zip(obj.Poles, poles)), "undo did not restore the poles")
    dev = np.abs(edge_points(obj) - before).max()
    log(f"curve drag: pole {k} moved {np.linalg.norm(delta):.4g}, edge off N_k delta by <= 1e-9; after one undo "
        f"the edge is {dev:.3g} off the original")
    check(dev == 0.0, f"one undo left the edge {dev:.3g} off the original")
    STATE["curve"] = obj
    RESULT["curve_drag"] = {"pole": k, "moved": float(np.linalg.norm(delta)), "undo_deviation": float(dev)}


@step
def weight_of_picked_pole():
    """The panel's weight box sets the picked pole's weight (OCCT's curve has it), one
    undo step; Esc leaves the edit mode."""
    obj = STATE["curve"]
    doc = App.ActiveDocument
    editor = obj.ViewObject.Proxy.editor
    undo = len(doc.UndoNames)
    box = editor.panel.weight
    check(box.isEnabled(), "weight box disabled with a picked pole")
    box.setValue(2.5)
    box.editingFinished.emit()
    settle()
    check(len(obj.Weights) == 200 and obj.Weights[100] == 2.5 and obj.isValid(), f"weights: {obj.Message}")
    check(abs(obj.Shape.Edges[0].Curve.getWeight(101) - 2.5) <= 1e-12, "OCCT's curve lacks the weight")
    check(len(doc.UndoNames) == undo + 1, "weight change is not one undo step")
    doc.undo()
    check(len(obj.Weights) == 0, "undo did not restore the polynomial curve")
    Mouse(Gui.ActiveDocument.ActiveView).key(QtCore.Qt.Key_Escape)
    settle()
    check(Gui.ActiveDocument.getInEdit() is None and obj.ViewObject.Proxy.editor is None, "Esc did not leave")
    check(not Gui.Control.activeDialog(), "panel still open after Esc")


@step
def knot_buttons():
    """Back in pole editing on the same curve, pole 100 picked: the panel's buttons,
    pressed through Qt, insert a knot (Knots one longer, OCCT's edge unchanged at 61
    parameters to 1e-9 of the size), elevate the degree (4, the edge unchanged) and
    remove knots within the panel's tolerance (the deviation in the status bar), each
    one undo step; three undos give back the properties; the context menu's Elevate
    degree does the same as the button; Esc leaves."""
    obj = STATE["curve"]
    doc = App.ActiveDocument
    obj.ViewObject.Proxy.doubleClicked(obj.ViewObject)
    settle()
    editor = obj.ViewObject.Proxy.editor
    check(editor is not None and set(editor.panel.buttons) == set(editor.KNOT_EDITS), "no knot buttons")
    editor.picked = 100
    editor.refresh()
    check(editor.panel.buttons["Insert knot"].isEnabled(), "Insert knot disabled with a picked pole")
    before, knots, undo = edge_points(obj), len(obj.Knots) or 204, len(doc.UndoNames)
    props = (list(obj.Poles), list(obj.Knots), obj.Degree)
    editor.panel.buttons["Insert knot"].click()
    settle()
    dev = np.abs(edge_points(obj) - before).max()
    check(len(obj.Knots) == knots + 1 and len(obj.Poles) == 201, f"knots {knots} -> {len(obj.Knots)}")
    check(dev <= 1e-9 * 400 and len(doc.UndoNames) == undo + 1, f"insert: edge {dev:.3g}, undo {doc.UndoNames[:2]}")
    editor.panel.buttons["Elevate degree"].click()
    settle()
    dev_elevate = np.abs(edge_points(obj) - before).max()
    check(obj.Degree == 4 and obj.Shape.Edges[0].Curve.Degree == 4, f"degree {obj.Degree}")
    check(dev_elevate <= 1e-9 * 400 and len(doc.UndoNames) == undo + 2, f"elevate: edge {dev_elevate:.3g}")
    editor.panel.tol.setValue(1e-7)
    editor.panel.buttons["Remove knots"].click()
    settle()
    text = Gui.getMainWindow().statusBar().currentMessage()
    dev_remove = np.abs(edge_points(obj) - before).max()
    check("deviation" in text and len(doc.UndoNames) == undo + 3, f"remove knots: status {text!r}")
    check(dev_remove <= 1e-7 + 1e-9 * 400, f"remove knots moved the edge {dev_remove:.3g} > 1e-7")
    for _ in range(3):
        doc.undo()
    settle()
    check((list(obj.Poles), list(obj.Knots), obj.Degree) == props, "three undos did not restore the curve")
    log(f"knot buttons: insert {dev:.3g}, elevate {dev_elevate:.3g}, remove {dev_remove:.3g} off the edge; {text}")
    RESULT["knot_buttons"] = {"insert": float(dev), "elevate": float(dev_elevate), "remove": float(dev_remove),
                              "status": text}
    menu = QtWidgets.QMenu()                 # the view's context menu in edit mode has the same edits
    obj.ViewObject.Proxy.setupContextMenu(obj.ViewObject, menu)
    actions = {a.text(): a for a in menu.actions()}
    check({"Insert knot at picked pole", "Elevate degree", "Remove knots..."} <= set(actions),
          f"context menu {sorted(actions)}")
    actions["Elevate degree"].trigger()
    settle()
    check(obj.Degree == 4 and len(doc.UndoNames) == undo + 1, f"context Elevate degree: degree {obj.Degree}")
    check(np.abs(edge_points(obj) - before).max() <= 1e-9 * 400, "context Elevate degree moved the edge")
    doc.undo()
    settle()
    Mouse(Gui.ActiveDocument.ActiveView).key(QtCore.Qt.Key_Escape)
    settle()
    check(Gui.ActiveDocument.getInEdit() is None, "Esc did not leave")


@step
def drag_surface_pole_along_normal():
    """A 30 x 30 B-spline surface with its net, isometric view, entered by Cagd_EditPoles:
    a drag with Shift moves pole (15, 15) along the net's normal there; the on-screen
    part of its move is the pointer's travel along the normal's on-screen direction
    (closest points of the normal line and the pointer's ray). Then a plain drag
    measures the redraw rate."""
    from cagdwb import editpoles, poledrag, surfaces
    doc = App.ActiveDocument
    i, j = np.meshgrid(np.arange(30.0), np.arange(30.0), indexing="ij")
    P = np.stack([5 * i, 5 * j, 8 * np.sin(i / 5.0) * np.cos(j / 6.0)], -1)
    obj = surfaces.make_bspline_surface(P, 30, doc=doc)
    doc.recompute()
    view = show_only([obj])
    Gui.Selection.addSelection(obj)
    Gui.runCommand("Cagd_EditPoles", 0)
    settle()
    editor = obj.ViewObject.Proxy.editor
    check(editor is not None, "Cagd_EditPoles did not start pole editing")
    spy = Spy(editor)
    k = 15 * 30 + 15
    normal = poledrag.net_normals(P)[15, 15]
    anchor = vec(obj.Poles[k])
    start = view.getPointOnScreen(obj.Poles[k])
    undo = len(doc.UndoNames)
    drag(view, start, (0, 30), shift=True)
    check(editor.picked == k, f"picked {editor.picked}, expected {k}")
    delta = vec(obj.Poles[k]) - anchor
    along = float(delta @ normal)
    check(abs(along) > 1.0 and np.linalg.norm(delta - along * normal) <= 1e-9 * 150,
          f"shift-drag moved the pole by {delta}, not along the normal {normal}")
    d = vec(view.getViewDirection())
    seen = delta - (delta @ d) * d                       # the move's on-screen part
    pointer = vec(view.getPoint(*spy.positions[-1])) - vec(view.getPoint(*spy.positions[0]))
    check(abs(np.linalg.norm(seen) - pointer @ seen / np.linalg.norm(seen)) <= 1e-6 * 150,
          f"on-screen move {seen}, pointer travel {pointer}")
    check(len(doc.UndoNames) == undo + 1, "shift drag is not one undo step")
    check(editpoles.surface_normals(obj) is not None, "no net normals for a grid")
    rate("surface 30x30 + net", *drag(view, view.getPointOnScreen(obj.Poles[k]), (30, -20), measure=editor))
    for _ in range(2):
        doc.undo()
    check(np.array_equal(vec(obj.Poles[k]), anchor), "two undos did not restore the pole")
    Gui.ActiveDocument.resetEdit()
    settle()
    obj.ViewObject.Visibility = False


@step
def perspective_drag_follows_the_pointer():
    """Perspective camera, isometric view: a plain drag keeps the pole under the pointer
    (its projection is the release position, to a pixel) and in the plane through it
    normal to the view direction; the camera type is restored after."""
    from cagdwb import curves, editpoles
    doc = App.ActiveDocument
    obj = curves.make_bspline_curve([V(0, 0, 0), V(10, 15, 5), V(20, -5, 10), V(30, 15, 0), V(40, 0, 5)], 3,
                                    doc=doc)
    doc.recompute()
    view = Gui.ActiveDocument.ActiveView
    kind = view.getCameraType()
    view.setCameraType("Perspective")
    try:
        view = show_only([obj])
        Gui.ActiveDocument.setEdit(obj, editpoles.EDIT_POLES)
        settle()
        spy = Spy(obj.ViewObject.Proxy.editor)
        anchor = vec(obj.Poles[2])
        drag(view, view.getPointOnScreen(obj.Poles[2]), (35, -25))
        check(obj.ViewObject.Proxy.editor.picked == 2, "pole 2 not picked")
        end = np.array(spy.positions[-1], float)
        seen = np.array(view.getPointOnScreen(obj.Poles[2]), float)
        d = vec(view.getViewDirection())
        moved = vec(obj.Poles[2]) - anchor
        check(np.linalg.norm(moved) > 1.0 and abs(moved @ d) <= 1e-9 * 40, f"moved {moved}, view {d}")
        check(np.abs(seen - end).max() <= 1.5, f"pole drawn at {seen}, pointer at {end}")
        log(f"perspective drag: pole at {seen}, pointer at {end}")
        Gui.ActiveDocument.resetEdit()
        settle()
    finally:
        view.setCameraType(kind)
    obj.ViewObject.Visibility = False


@step
def linked_vertices():
    """A curve on four Part Vertex objects: dragging pole 1 moves that vertex object (its
    X, Y, Z); a pole from a box's vertex is refused, the reason in the status bar."""
    from cagdwb import curves, editpoles
    doc = App.ActiveDocument
    points = []
    for n, p in enumerate([V(0, 0, 50), V(10, 20, 50), V(30, 20, 50), V(40, 0, 50)]):
        v = doc.addObject("Part::Vertex", f"Pole{n}")
        v.X, v.Y, v.Z = p.x, p.y, p.z
        points.append(v)
    box = doc.addObject("Part::Box", "Corner")
    box.Placement = App.Placement(V(50, -10, 40), App.Rotation())
    doc.recompute()
    obj = curves.make_bezier_curve(vertices=[(v, "") for v in points] + [(box, "Vertex2")], doc=doc)
    doc.recompute()
    check(obj.isValid(), obj.Message)
    view = show_only([obj], "viewTop")
    Gui.ActiveDocument.setEdit(obj, editpoles.EDIT_POLES)
    settle()
    editor = obj.ViewObject.Proxy.editor
    spy = Spy(editor)
    start = view.getPointOnScreen(obj.Poles[1])
    drag(view, start, (20, 0))
    moved = vec(view.getPoint(*spy.positions[-1])) - vec(view.getPoint(*spy.positions[0]))
    now = np.array([points[1].X.Value if hasattr(points[1].X, "Value") else points[1].X,
                    points[1].Y.Value if hasattr(points[1].Y, "Value") else points[1].Y,
                    points[1].Z.Value if hasattr(points[1].Z, "Value") else points[1].Z], float)
    check(np.linalg.norm(now - [10, 20, 50] - moved) <= 1e-9 * 50, f"vertex at {now}, pointer moved {moved}")
    check(np.linalg.norm(vec(obj.Poles[1]) - now) <= 1e-9 * 50, "the curve did not follow its vertex")
    poles, undo = [vec(p) for p in obj.Poles], len(doc.UndoNames)
    drag(view, view.getPointOnScreen(obj.Poles[4]), (20, 20))
    status = Gui.getMainWindow().statusBar().currentMessage()
    check(editor.picked == 4 and "cannot be moved" in status and "Corner" in status, f"status bar {status!r}")
    check(all(np.array_equal(vec(p), q) for p, q in zip(obj.Poles, poles)) and len(doc.UndoNames) == undo,
          "a refused drag changed something")
    log(f"linked vertex moved; refused: {status}")
    Gui.ActiveDocument.resetEdit()
    settle()


@step
def drag_along_an_axis_with_snap():
    """The panel's Drag along Z and Snap 2.5, seen from the front (Z up the screen): a
    drag of pole 2 moves it along Z only (x and y bit for bit) to a multiple of 2.5,
    about as far as the pointer went; one undo step."""
    from cagdwb import curves
    doc = App.ActiveDocument
    obj = curves.make_bspline_curve([V(float(x), 5.0 * (x % 2), 0.0) for x in (0, 20, 40, 60, 80, 100)], 3, doc=doc)
    doc.recompute()
    view = show_only([obj], "viewFront")
    obj.ViewObject.Proxy.doubleClicked(obj.ViewObject)
    settle()
    editor = obj.ViewObject.Proxy.editor
    check(editor is not None and editor.panel is not None, "no pole editor")
    editor.panel.along.setCurrentText("Z")
    editor.panel.snap.setValue(2.5)
    k, step = 2, 2.5
    poles, undo = [vec(p) for p in obj.Poles], len(doc.UndoNames)
    start, made = view.getPointOnScreen(obj.Poles[k]), editor.redraws
    drag(view, start, (15, 150))
    check(editor.picked == k and editor.redraws > made, f"picked {editor.picked} (expected {k}), "
          f"{editor.redraws - made} moves reached the editor")
    p = vec(obj.Poles[k])
    pointer = vec(view.getPoint(start[0] + 15, start[1] + 150)) - vec(view.getPoint(*start))
    check(p[0] == poles[k][0] and p[1] == poles[k][1], f"pole left its Z line: {p} from {poles[k]}")
    check(abs(p[2] / step - round(p[2] / step)) <= 1e-9 and abs(p[2] - poles[k][2]) >= step,
          f"z = {p[2]} is not a moved multiple of {step}")
    check(abs(p[2] - poles[k][2] - pointer[2]) <= step / 2 + 1e-9, f"z moved {p[2] - poles[k][2]}, pointer {pointer}")
    check(len(doc.UndoNames) == undo + 1, f"undo steps {doc.UndoNames[:3]} (was {undo})")
    log(f"axis drag: pole {k} z {poles[k][2]:.4g} -> {p[2]:.4g} (pointer {pointer[2]:.4g}), x, y unchanged")
    Gui.ActiveDocument.resetEdit()
    settle()
    RESULT["axis_drag"] = {"z": float(p[2]), "pointer_z": float(pointer[2])}


@step
def screenshot_with_poles():
    """The default B-spline curve (6 poles, net off) in pole editing (entered by its
    context menu's Edit poles) with pole 2 picked:
    the model's pixels (against the view without it) and the markers' own (against the
    curve out of edit mode), with the picked marker orange."""
    from cagdwb import curves
    doc = App.ActiveDocument
    obj = curves.make_bspline_curve(doc=doc)
    doc.recompute()
    obj.ViewObject.ShowControlNet = False
    view = show_only([obj], "viewTop")
    view.saveImage(os.path.join(OUT, "EditPoles-plain.png"), WIDTH, HEIGHT, "White")
    menu = QtWidgets.QMenu()                          # right-click: the view provider's context menu entries
    obj.ViewObject.Proxy.setupContextMenu(obj.ViewObject, menu)
    actions = {a.text(): a for a in menu.actions()}
    check(set(actions) == {"Edit poles", "Edit properties"}, f"context menu {sorted(actions)}")
    actions["Edit poles"].trigger()
    settle()
    editor = obj.ViewObject.Proxy.editor
    check(editor is not None and Gui.ActiveDocument.getInEdit() is not None, "Edit poles did not start editing")
    editor.picked = 2
    editor.refresh()
    settle()
    view.saveImage(os.path.join(OUT, "EditPoles.png"), WIDTH, HEIGHT, "White")
    obj.ViewObject.Visibility = False
    settle()
    view.saveImage(os.path.join(OUT, "EditPoles-hidden.png"), WIDTH, HEIGHT, "White")
    obj.ViewObject.Visibility = True
    Gui.ActiveDocument.resetEdit()
    settle()
    RESULT["screenshot"] = {"poles": len(obj.Poles), "picked": 2}


def leave_edit_mode():
    """After a failed step: out of any edit mode, so the next step starts clean."""
    if Gui.ActiveDocument is not None and Gui.ActiveDocument.getInEdit() is not None:
        Gui.ActiveDocument.resetEdit()


QtCore.QTimer.singleShot(500, lambda: run(leave_edit_mode))
