"""GUI commands of the CAGD workbench. Creation commands use the selection when it
fits (vertices or point objects -> curve poles/points; four edges -> Coons patch;
one edge -> revolution; two edges -> join) and otherwise make an editable example
object; the continuity check measures two selected edges or faces; the query
commands make the intersection curve of two selected faces and the deviation map of
a selected Points object (or a CSV file) against selected faces; the fitting commands
fit a curve or surface to a selected Points object, mesh or vertices, and rebuild,
remove knots from, reduce the degree of or fair one selected edge or face, refusing
a selection they cannot use before any object is made; the network commands make a
Gordon surface of selected edges (split into two families: the edges meeting the
first are the guides), sweeps (profile then path; two rails then profiles), a blend
curve between two edges' nearest ends, a blend surface and a match between two faces'
facing edges (or two selected face edges), refused likewise."""
from __future__ import annotations

from typing import Callable, List, Optional, Tuple

import FreeCAD as App
import FreeCADGui as Gui

from . import analysis, conversion, curves, features, fitting, icon, inspection, network, surface_analysis, surfaces
from .conversion import cagd

Link = Tuple[object, str]
LAST_CHECK: List[analysis.JointCheck] = []       # results of the continuity command (newest last)
LAST_PLOT: list = []                    # the curvature plot panel last opened by Curve quality
LAST_MARKER: list = []                  # (view, node) of the worst-station marker shown in the 3-D view
MARKER_FRACTION = 0.02                  # the marker's radius, this fraction of the checked shapes' size


# --- selection ------------------------------------------------------------------------------
def _selected(kind: str) -> List[Link]:
    """(object, 'KindN') of the selected sub-elements of one kind, in selection
    order; a whole selected object counts when its shape has exactly one of them."""
    out = []
    for sel in Gui.Selection.getSelectionEx():
        subs = [s for s in sel.SubElementNames if s.startswith(kind)]
        if subs:
            out.extend((sel.Object, s) for s in subs)
        elif not sel.SubElementNames and hasattr(sel.Object, "Shape"):
            elements = getattr(sel.Object.Shape, kind + "es" if kind == "Vertex" else kind + "s")
            if len(elements) == 1:
                out.append((sel.Object, kind + "1"))
    return out


def selected_vertices() -> List[Link]:
    return _selected("Vertex")


def selected_edges() -> List[Link]:
    return _selected("Edge")


def selected_faces() -> List[Link]:
    return _selected("Face")


def _finish(obj) -> None:
    """Recompute; report an error state; show a warning (a valid object whose Message
    is not "ok": no intersection, an unmet fitting tolerance) in the status bar; hide
    the inputs the new object wholly uses (point objects, single curves; as Part Loft
    hides its sections)."""
    doc = obj.Document
    doc.recompute()
    Gui.Selection.clearSelection()
    if not obj.isValid():
        App.Console.PrintError(f"{obj.Label}: {obj.Message}\n")
        return
    if obj.Message != "ok" and Gui.getMainWindow() is not None:
        Gui.getMainWindow().statusBar().showMessage(obj.Message, 8000)
    for o in obj.Proxy.consumed(obj):
        if getattr(o, "ViewObject", None) is not None:
            o.ViewObject.Visibility = False


def debug_tracebacks() -> bool:
    """The debug preference (BaseApp/Preferences/Mod/Cagd, DebugTracebacks): errors
    print their Python traceback as well as the message."""
    return features.debug_tracebacks()


def _error(message: str) -> None:
    App.Console.PrintError(f"CAGD: {message}\n")
    if Gui.getMainWindow() is not None:
        Gui.getMainWindow().statusBar().showMessage(message, 8000)


# --- commands -------------------------------------------------------------------------------
class Command:
    """Base: resources from NAME/MENU/TIP/ICON, active with an open document."""
    NAME = MENU = TIP = ICON = ""

    def GetResources(self) -> dict:
        return {"Pixmap": icon(self.ICON), "MenuText": self.MENU, "ToolTip": self.TIP}

    def IsActive(self) -> bool:
        return App.ActiveDocument is not None

    def Activated(self) -> None:
        """run() in one undo transaction; when it raises, the transaction is aborted
        (and any object it left behind removed) and the error goes to the report view."""
        doc = App.ActiveDocument
        before = {o.Name for o in doc.Objects}
        doc.openTransaction(self.MENU)
        try:
            self.run()
        except Exception as exc:
            doc.abortTransaction()
            for name in [o.Name for o in doc.Objects if o.Name not in before]:
                doc.removeObject(name)              # undo disabled: remove them ourselves
            doc.recompute()
            _error(f"{self.MENU} failed: {type(exc).__name__}: {exc}")
            if debug_tracebacks():
                import traceback
                App.Console.PrintLog("".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))
        else:
            doc.commitTransaction()

    def run(self) -> None:
        raise NotImplementedError


def _points_command(name, menu, tip, icon_name, make: Callable, min_points: int):
    """A curve command that links the selected vertices (when at least min_points)."""
    class PointsCommand(Command):
        NAME, MENU, TIP, ICON = name, menu, tip, icon_name

        def run(self) -> None:
            verts = selected_vertices()
            if 0 < len(verts) < min_points:
                return _error(f"{menu}: select {min_points} or more vertices in order, or nothing for an "
                              f"example curve (got {len(verts)} vertex)")
            _finish(make(verts or None))
    PointsCommand.__name__ = name
    return PointsCommand()


def _bezier(verts):
    return curves.make_bezier_curve(vertices=verts)


def _bspline(verts):
    return curves.make_bspline_curve(vertices=verts, degree=None if not verts else min(3, len(verts) - 1))


def _interpolation(verts):
    return curves.make_interpolation_curve(vertices=verts, degree=None if not verts else min(3, len(verts) - 1))


def _cubic(verts):
    return curves.make_cubic_spline(vertices=verts)


def _hermite(verts):
    if verts and len(verts) == 2:
        a, b = (o.Shape.getElement(s).Point for o, s in verts)
        t0, t1 = curves.example_tangents(a, b)
        return curves.make_hermite_curve(StartPoint=a, EndPoint=b, StartTangent=t0, EndTangent=t1)
    return curves.make_hermite_curve()


class CoonsCommand(Command):
    NAME, MENU, ICON = "Cagd_CoonsPatch", "Coons patch", "CoonsPatch"
    TIP = "Bilinearly blended Coons patch from four selected edges forming a closed loop"

    def run(self) -> None:
        edges = selected_edges()
        if len(edges) != 4:
            return _error(f"Coons patch: select exactly four edges (got {len(edges)})")
        try:                                   # an open loop is refused before any object is made
            surfaces.coons_from_edges([(f"{o.Label}.{sub}", o.Shape.getElement(sub)) for o, sub in edges])
        except cagd.CagdError as exc:
            return _error(f"Coons patch: {exc}")
        _finish(surfaces.make_coons(edges))


class RevolutionCommand(Command):
    NAME, MENU, ICON = "Cagd_Revolution", "Surface of revolution", "Revolution"
    TIP = "Revolve the selected edge about the z axis (edit AxisPoint, AxisDirection, Angle)"

    def run(self) -> None:
        edges = selected_edges()
        if len(edges) != 1:
            return _error(f"Revolution: select one profile edge (got {len(edges)})")
        _finish(surfaces.make_revolution(edges[0]))


class JoinCommand(Command):
    NAME, MENU, ICON = "Cagd_Join", "Join G1/G2", "Join"
    TIP = "Continue the first selected curve with the second, G2 (edit Continuity, Alpha, Beta)"

    def run(self) -> None:
        edges = selected_edges()
        if len(edges) != 2:
            return _error(f"Join: select two edges, the curve to continue first (got {len(edges)})")
        obj, sub = edges[1]
        try:                                   # a multi-span or rational Source is refused before any object
            curves.join_source(obj.Shape.getElement(sub))
        except cagd.CagdError as exc:
            return _error(f"Join: {obj.Label}.{sub}: {exc}")
        _finish(curves.make_join(edges[0], edges[1]))       # hides Source (when a single curve)


class IntersectionCommand(Command):
    NAME, MENU, ICON = "Cagd_IntersectionCurve", "Intersection curve", "IntersectionCurve"
    TIP = "Parametric intersection curve of two selected faces (updates when they change or move)"

    def run(self) -> None:
        faces = selected_faces()
        if len(faces) != 2:
            return _error(f"Intersection curve: select exactly two faces (got {len(faces)})")
        _finish(inspection.make_intersection(faces[0], faces[1]))      # no intersection: a warning


class SurfaceAnalysisCommand(Command):
    NAME, MENU, ICON = "Cagd_SurfaceAnalysis", "Surface analysis", "DeviationMap"
    TIP = ("Colour the selected face by its Gaussian, mean, max or min curvature, zebra stripes, isophotes or "
           "draft angle (edit Kind, Direction, Stripes, Range)")

    def run(self) -> None:
        faces = selected_faces()
        if len(faces) != 1:
            return _error(f"Surface analysis: select one face (got {len(faces)})")
        obj, sub = faces[0]
        try:                                   # a face Part cannot convert is refused before any object
            conversion.face_to_surface(obj.Shape.getElement(sub))
        except Exception as exc:
            return _error(f"Surface analysis: {obj.Label}.{sub} has no B-spline form ({exc})")
        _finish(surface_analysis.make_surface_analysis((obj, sub)))


def selected_clouds() -> list:
    """The selected Points objects (Points::Feature), in selection order."""
    return [s.Object for s in Gui.Selection.getSelectionEx() if s.Object.isDerivedFrom("Points::Feature")]


def ask_csv_file() -> str:
    """A CSV file of points picked in a file dialog ('' when cancelled)."""
    from .qt import QtWidgets
    path, _ = QtWidgets.QFileDialog.getOpenFileName(Gui.getMainWindow(), "Points for the deviation map", "",
                                                    "Point files (*.csv *.txt *.xyz);;All files (*)")
    return path or ""


class DeviationCommand(Command):
    NAME, MENU, ICON = "Cagd_DeviationMap", "Deviation map", "DeviationMap"
    TIP = ("Signed deviations of a point cloud from the selected faces, shown as coloured points: select "
           "faces and a Points object, or only faces and pick a CSV file")

    def run(self) -> None:
        faces, clouds = selected_faces(), selected_clouds()
        if not faces:
            return _error("Deviation map: select one or more faces (and a Points object, or pick a CSV file)")
        if len(clouds) > 1:
            return _error(f"Deviation map: select one Points object (got {len(clouds)})")
        csv = "" if clouds else ask_csv_file()
        if not clouds and not csv:
            return _error("Deviation map: no points (select a Points object or pick a CSV file)")
        _finish(inspection.make_deviation_map(faces, clouds[0] if clouds else None, csv))


def selected_point_objects() -> list:
    """The selected Points objects and meshes (whole objects), in selection order."""
    return [s.Object for s in Gui.Selection.getSelectionEx()
            if s.Object.isDerivedFrom("Points::Feature") or s.Object.isDerivedFrom("Mesh::Feature")]


class FitCommand(Command):
    """Fit a curve or surface: to one selected Points object or mesh (linked as Source),
    or to selected vertices in order (linked as Vertices)."""

    def __init__(self, name, menu, tip, icon_name, make, min_points: int):
        self.NAME, self.MENU, self.TIP, self.ICON, self.make, self.min_points = \
            name, menu, tip, icon_name, make, min_points

    def run(self) -> None:
        clouds, verts = selected_point_objects(), selected_vertices()
        if len(clouds) == 1 and not verts:
            count = len(fitting.source_points(clouds[0]))
            if count < self.min_points:
                return _error(f"{self.MENU}: {clouds[0].Label} holds {count} points; at least "
                              f"{self.min_points} are needed")
            return _finish(self.make(source=clouds[0]))
        if not clouds and len(verts) >= self.min_points:
            return _finish(self.make(vertices=verts))
        _error(f"{self.MENU}: select one Points object or mesh, or {self.min_points} or more vertices in order "
               f"(got {len(clouds)} point objects, {len(verts)} vertices)")


class OperationCommand(Command):
    """Rebuild / remove knots / reduce degree / fair one selected edge or face; the
    selection is checked (fitting.check_operation) before the object is made."""

    def __init__(self, kind, menu, tip):
        self.kind, self.NAME, self.MENU, self.TIP, self.ICON = kind, "Cagd_" + kind, menu, tip, kind

    def run(self) -> None:
        picks = selected_faces() + selected_edges()
        if len(picks) != 1:
            return _error(f"{self.MENU}: select one edge or one face (got {len(picks)})")
        obj, sub = picks[0]
        try:
            values = fitting.check_operation(self.kind, (obj, [sub]))
        except cagd.CagdError as exc:
            return _error(f"{self.MENU}: {obj.Label}.{sub}: {exc}")
        _finish(fitting.make_operation(self.kind, (obj, sub), **values))


class NetworkCommand(Command):
    """Base of the network commands: ``links()`` turns the selection into the new
    object's link values (or raises CagdError with the reason); the engine is tried on
    them (network.check) before the object is made."""
    KIND = ""

    def links(self) -> dict:
        raise NotImplementedError

    def run(self) -> None:
        try:
            values = self.links()
            network.check(self.KIND, **values)
        except cagd.CagdError as exc:
            return _error(f"{self.MENU}: {exc}")
        _finish(features.make(network.KINDS[self.KIND], **network.link_values(values)))


def _edge_picks(what: str, least: int, most: Optional[int] = None) -> list:
    """The selected edges, at least ``least`` and at most ``most`` of them, else CagdError
    saying what to select."""
    edges = selected_edges()
    if len(edges) < least or (most is not None and len(edges) > most):
        raise cagd.CagdError(f"select {what} (got {len(edges)} edges)")
    return edges


class GordonCommand(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_GordonSurface", "Gordon surface", "GordonSurface", "GordonSurface"
    TIP = ("Surface through a network of selected edges: two families, every edge of one crossing every edge "
           "of the other (edit Profiles, Guides, Tolerance)")

    def links(self) -> dict:
        edges = _edge_picks("a network of 4 or more edges, two families crossing each other", 4)
        profiles, guides = network.split_network(edges)
        if len(profiles) < 2 or len(guides) < 2:
            raise cagd.CagdError(f"the edges make {len(profiles)} profiles and {len(guides)} guides (the edges "
                                 "meeting the first selected one); a network needs 2 or more of each")
        return {"Profiles": profiles, "Guides": guides}


class SweepCommand(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_Sweep", "Sweep", "Sweep", "Sweep"
    TIP = "Sweep the first selected edge (profile) along the second (path); edit Frame, Tolerance"

    def links(self) -> dict:
        edges = _edge_picks("two edges, the profile then the path", 2, 2)
        return {"Profile": edges[0], "Path": edges[1]}


class Sweep2Command(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_Sweep2", "Sweep along two rails", "Sweep2", "Sweep2"
    TIP = "Sweep profiles between two rails: select the two rail edges, then one or more profile edges"

    def links(self) -> dict:
        edges = _edge_picks("two rail edges, then one or more profile edges", 3)
        return {"Rail1": edges[0], "Rail2": edges[1], "Profiles": edges[2:]}


class BlendCurveCommand(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_BlendCurve", "Blend curve", "BlendCurve", "BlendCurve"
    TIP = ("G2 bridge between the nearest ends of two selected edges (edit End1, End2, Continuity G1/G2/G3, "
           "AutomaticScales)")

    def links(self) -> dict:
        edges = _edge_picks("two edges", 2, 2)
        shapes = [o.Shape.getElement(s) for o, s in edges]
        end1, end2 = network.nearest_ends(*shapes)
        return {"Edge1": edges[0], "Edge2": edges[1], "End1": end1, "End2": end2}


def _two_face_edges(menu: str, names) -> dict:
    """Links of two faces and their facing edges from two selected faces (the facing
    parameter-box edges) or two selected face edges."""
    faces, edges = selected_faces(), selected_edges()
    f1, e1, f2, e2 = names
    if len(faces) == 2 and not edges:
        shapes = [o.Shape.getElement(s) for o, s in faces]
        side1, side2 = network.facing_sides(*shapes)
        return {f1: faces[0], e1: side1, f2: faces[1], e2: side2}
    if len(edges) == 2 and not faces:
        (a, side1), (b, side2) = (network.face_and_side(o, s) for o, s in edges)
        return {f1: a, e1: side1, f2: b, e2: side2}
    raise cagd.CagdError(f"select two faces or two face edges (got {len(faces)} faces, {len(edges)} edges)")


class BlendSurfaceCommand(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_BlendSurface", "Blend surface", "BlendSurface", "BlendSurface"
    TIP = "G1/G2 surface bridging two selected face edges (or the facing edges of two selected faces)"

    def links(self) -> dict:
        return _two_face_edges(self.MENU, ("Face1", "Edge1", "Face2", "Edge2"))


class MatchSurfaceCommand(NetworkCommand):
    NAME, MENU, ICON, KIND = "Cagd_MatchSurface", "Match surface", "MatchSurface", "MatchSurface"
    TIP = "Move the first selected face's edge onto the second's, G0/G1/G2 (select two faces or two face edges)"

    def links(self) -> dict:
        return _two_face_edges(self.MENU, ("Face", "Edge", "Target", "TargetEdge"))


class ContinuityCommand(Command):
    NAME, MENU, ICON = "Cagd_ContinuityCheck", "Check continuity", "Continuity"
    TIP = ("Measure C0/C1/C2/G1/G2 where two selected edges meet, or G0/G1/G2 at every station along the boundary "
           "two faces share (select the faces, or the shared edge on each); the worst station is marked red")

    def run(self) -> None:
        faces, edges = selected_faces(), selected_edges()
        pick = faces if len(faces) == 2 else edges
        if len(pick) != 2:
            return _error("Continuity: select two edges or two faces")
        shapes = [o.Shape.getElement(s) for o, s in pick]
        try:
            result = analysis.check_selection(*pick, rel_tol=1e-7)
        except cagd.CagdError as exc:
            return _error(f"Continuity: {exc}")
        LAST_CHECK.append(result)
        names = " and ".join(f"{o.Label}.{s}" for o, s in pick)
        text = f"Continuity of {names}: {result.level}\n{result.text()}\n"
        App.Console.PrintMessage(text)
        mark_worst_station(result, shapes)
        show_message("Continuity check", text)

    def Activated(self) -> None:           # no document change: no transaction
        self.run()


class FairnessCommand(Command):
    NAME, MENU, ICON = "Cagd_Fairness", "Curve quality", "Comb"
    TIP = ("Curvature plot (curvature against arc length) and fairness of the selected edge: curvature range, "
           "energy, inflections, largest curvature jump at a knot")

    def run(self) -> None:
        edges = selected_edges()
        if len(edges) != 1:
            return _error(f"Curve quality: select one edge (got {len(edges)})")
        obj, sub = edges[0]
        from . import plotpanel
        try:
            panel = plotpanel.show(obj.Shape.getElement(sub), f"Curvature of {obj.Label}.{sub}")
        except cagd.CagdError as exc:
            return _error(f"Curve quality: {obj.Label}.{sub}: {exc}")
        LAST_PLOT[:] = [panel]
        App.Console.PrintMessage(f"Curve quality of {obj.Label}.{sub}:\n{panel.text}\n")

    def Activated(self) -> None:           # no document change: no transaction
        self.run()


class EditPolesCommand(Command):
    """Pole edit mode (editpoles.py) of the one selected curve or surface with poles."""
    NAME, MENU, ICON = "Cagd_EditPoles", "Edit poles", "EditPoles"
    TIP = ("Drag the poles of the selected Bezier / B-spline curve or surface, Bezier triangle (or the points of an "
           "interpolating curve or cubic spline) in the 3-D view; Shift: along the normal / in depth; Esc leaves")

    def run(self) -> None:
        from . import editpoles
        objs = [s.Object for s in Gui.Selection.getSelectionEx()]
        if len(objs) != 1 or getattr(objs[0], "ViewObject", None) is None or \
                not hasattr(objs[0].ViewObject, "ShowControlNet") or not editpoles.point_property(objs[0]):
            return _error(f"{self.MENU}: select one CAGD curve or surface with poles (Bezier, B-spline, Bezier "
                          "triangle, interpolating curve, cubic spline)")
        Gui.Selection.clearSelection()
        Gui.ActiveDocument.setEdit(objs[0], editpoles.EDIT_POLES)

    def Activated(self) -> None:           # each drag is its own transaction
        self.run()


def clear_station_marker() -> None:
    """Remove the continuity check's worst-station marker from its view."""
    while LAST_MARKER:
        view, node = LAST_MARKER.pop()
        try:
            view.getSceneGraph().removeChild(node)
        except Exception:                  # the view was closed
            pass


def mark_worst_station(result: analysis.JointCheck, shapes) -> None:
    """Replace the previous marker by a red sphere at the check's worst station (two faces;
    none for two edges) in the active 3-D view."""
    from .viewproviders import station_marker
    clear_station_marker()
    worst = result.worst()
    view = getattr(Gui.ActiveDocument, "ActiveView", None) if Gui.ActiveDocument else None
    if worst is None or worst[1] < 0 or view is None or not hasattr(view, "getSceneGraph"):
        return
    size = max(s.BoundBox.DiagonalLength for s in shapes)
    node = station_marker(worst[3], MARKER_FRACTION * size)
    view.getSceneGraph().addChild(node)
    LAST_MARKER.append((view, node))


def show_message(title: str, text: str) -> None:
    """A non-modal message box (does not block scripts driving the GUI)."""
    from .qt import QtCore, QtWidgets
    box = QtWidgets.QMessageBox(Gui.getMainWindow())
    box.setWindowTitle(title)
    box.setText(text)
    box.setModal(False)
    box.setAttribute(QtCore.Qt.WA_DeleteOnClose)
    box.show()


class ToggleCommand(Command):
    """Toggle a view property on the selected workbench objects (all of them when
    nothing is selected)."""
    PROPERTY = ""

    def run(self) -> None:
        objs = [s.Object for s in Gui.Selection.getSelectionEx()] or App.ActiveDocument.Objects
        vobjs = [o.ViewObject for o in objs if hasattr(o.ViewObject, self.PROPERTY)]
        if not vobjs:
            return _error(f"{self.MENU}: no CAGD object to toggle")
        value = not all(getattr(v, self.PROPERTY) for v in vobjs)
        for v in vobjs:
            setattr(v, self.PROPERTY, value)

    def Activated(self) -> None:
        self.run()


class ToggleNetCommand(ToggleCommand):
    NAME, MENU, ICON, PROPERTY = "Cagd_ToggleControlNet", "Toggle control net", "ControlNet", "ShowControlNet"
    TIP = "Show or hide the control polygon / net of the selected CAGD objects"


class ToggleCombCommand(ToggleCommand):
    NAME, MENU, ICON, PROPERTY = "Cagd_ToggleComb", "Toggle curvature comb", "Comb", "ShowCurvatureComb"
    TIP = "Show or hide the curvature comb of the selected CAGD curves (surfaces: combs of iso-curves)"


class SimpleCommand(Command):
    def __init__(self, name, menu, tip, icon_name, make):
        self.NAME, self.MENU, self.TIP, self.ICON, self.make = name, menu, tip, icon_name, make

    def run(self) -> None:
        _finish(self.make())


CURVES = [
    _points_command("Cagd_BezierCurve", "Bezier curve", "Bezier curve; poles from the selected vertices",
                    "BezierCurve", _bezier, 2),
    _points_command("Cagd_BSplineCurve", "B-spline curve", "B-spline/NURBS curve; poles from the selected vertices",
                    "BSplineCurve", _bspline, 2),
    _points_command("Cagd_InterpolationCurve", "Interpolating B-spline",
                    "B-spline through the selected vertices", "InterpolationCurve", _interpolation, 2),
    _points_command("Cagd_CubicSpline", "Cubic spline", "Natural cubic spline through the selected vertices "
                    "(EndCondition: natural, clamped, periodic, virtual)", "CubicSpline", _cubic, 2),
    _points_command("Cagd_HermiteCurve", "Hermite curve", "Cubic Hermite curve (between two selected vertices)",
                    "HermiteCurve", _hermite, 2),
    JoinCommand(),
]
SURFACES = [
    SimpleCommand("Cagd_BezierSurface", "Bezier surface", "Bezier surface from a grid of poles",
                  "BezierSurface", surfaces.make_bezier_surface),
    SimpleCommand("Cagd_BSplineSurface", "B-spline surface", "B-spline/NURBS surface from a grid of poles",
                  "BSplineSurface", surfaces.make_bspline_surface),
    CoonsCommand(), SimpleCommand("Cagd_BezierTriangle", "Bezier triangle", "Cubic Bezier triangle",
                                  "BezierTriangle", surfaces.make_bezier_triangle),
    RevolutionCommand(),
]
FITTING = [
    FitCommand("Cagd_FitCurve", "Fit curve", "B-spline within Tolerance of a selected Points object, mesh or "
               "vertices (in order); MaxError / RmsError show the achieved error", "FitCurve",
               fitting.make_fit_curve, 2),
    FitCommand("Cagd_FitSurface", "Fit surface", "B-spline surface within Tolerance of a selected Points object, "
               "mesh or vertices (scattered, or a grid: GridRows)", "FitSurface", fitting.make_fit_surface, 4),
    OperationCommand("Rebuild", "Rebuild", "Rebuild the selected edge or face with Count control points of Degree; "
                     "Deviation shows how far it moved"),
    OperationCommand("RemoveKnots", "Remove knots", "Remove as many knots of the selected edge or face as "
                     "Tolerance allows (Tiller's bound)"),
    OperationCommand("ReduceDegree", "Reduce degree", "The selected edge or face one degree lower, within "
                     "Tolerance if its shape allows"),
    OperationCommand("Fair", "Fair", "Lower the fairness energy of the selected edge or face within Tolerance, "
                     "Keep (G0/G1/G2) held at its ends or edges"),
]
NETWORK = [GordonCommand(), SweepCommand(), Sweep2Command(), BlendCurveCommand(), BlendSurfaceCommand(),
           MatchSurfaceCommand()]
TOOLS = [IntersectionCommand(), DeviationCommand(), ContinuityCommand(), ToggleNetCommand(), ToggleCombCommand(),
         SurfaceAnalysisCommand(), FairnessCommand(), EditPolesCommand()]


def register() -> List[List[str]]:
    """Add all commands to FreeCAD; returns the names per group (curves, surfaces,
    fitting, network, tools)."""
    groups = []
    for group in (CURVES, SURFACES, FITTING, NETWORK, TOOLS):
        for cmd in group:
            Gui.addCommand(cmd.NAME, cmd)
        groups.append([cmd.NAME for cmd in group])
    return groups
