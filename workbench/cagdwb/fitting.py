"""Fitting and fairing objects (issue 17): curves and surfaces fitted to points within a
tolerance, and operations on a linked edge or face (rebuild, knot removal, degree
reduction, fairing) that show the deviation they caused.

FitCurve / FitSurface: ``cagd.fit_curve`` / ``cagd.fit_surface`` of the points of a
linked Points object, a mesh's vertices, a shape's vertices, or linked vertices in
order; the achieved ``MaxError`` / ``RmsError`` (certified closest points, measured
by the engine) and ``Converged`` are read-only; FitSurface's ``AutoDegree`` (off by
default; added on restore to older documents) lets the engine choose the degree
(``degree="auto"``), shown in the read-only ``AchievedDegreeU/V``. A tolerance the engine cannot meet
(``converged`` False: the cap or its rounds reached) leaves the object valid with the
best fit and a warning in ``Message`` and the report view, as the intersection curve
does for its tolerance.

Rebuild / RemoveKnots / ReduceDegree / Fair: ``cagd.rebuild``,
``remove_knots`` (Tiller, Piegl & Tiller A5.8), ``reduce_degree`` (P&T A5.11),
``cagd.fair_curve`` / ``cagd.fair_surface`` of the linked edge's or face's exact
B-spline form (``conversion.edge_to_curve`` / ``face_to_surface``); ``Deviation`` is the
engine's measured deviation of the result from the source. Engine errors are renamed
to the property they came from (``tol`` -> ``Tolerance``, ``curve`` -> ``Source``, ...).

Tolerances and errors are ``App::PropertyPrecision`` (FreeCAD's property for
tolerances: the property editor shows 16 decimals, so 1e-7 neither shows as "0.00"
nor is written back as 0).
"""
from __future__ import annotations

import contextlib
from typing import Dict, Iterator, Optional, Tuple

import numpy as np


from . import conversion
from .conversion import cagd
from .features import Feature, _element, add, add_enum, link_target, linked_edge, linked_points, make, vector
from cagd.fitting.fit_surface import AUTO_DEGREES  # noqa: E402  (after .conversion: the engine on the path)

PARAMETERS = cagd.fitting.PARAMETERS
KEEP = ("G0", "G1", "G2")
DIRECTIONS = ("Both", "U", "V")
#: engine argument names -> the property (or link) they come from, per object kind
FIT_NAMES = {"tol": "Tolerance", "degree": "Degree", "points": "Source", "parameters": "Parametrization",
             "start_tangent": "StartTangent", "end_tangent": "EndTangent",
             "max_control_points": "MaxControlPoints", "periodic": "Periodic"}
OPERATION_NAMES = {"tol": "Tolerance", "degree": "Degree", "count": "Count", "curve": "Source",
                   "surface": "Source", "obj": "Source", "keep": "Keep", "direction": "Direction"}
ZERO = 0.0                       # a zero tangent vector means "free"
PRECISION = "Precision"          # App::PropertyPrecision: tolerances shown with 16 decimals


@contextlib.contextmanager
def renamed(names: Dict[str, str]) -> Iterator[None]:
    """Re-raise an engine CagdError 'arg: ...' as 'Property: ...' (the message otherwise kept)."""
    try:
        yield
    except cagd.CagdError as exc:
        text = str(exc)
        head, sep, rest = text.partition(":")
        if sep and head.strip() in names:
            raise cagd.CagdError(f"{names[head.strip()]}:{rest}") from None
        raise


def _tolerance(obj, name: str = "Tolerance") -> float:
    tol = float(getattr(obj, name))
    if not tol > 0.0:                               # also NaN; PropertyPrecision clamps negatives to 0
        raise cagd.CagdError(f"{name}: must be > 0, got {tol:g}")
    return tol


# --- points of a Points object, a mesh or a shape ----------------------------------------------
def source_points(obj, name: str = "Source") -> np.ndarray:
    """(N, 3) points (global, in their stored order) of a Points object (single
    precision, as FreeCAD stores them), a mesh (its vertices) or a shape (its vertices)."""
    if obj is None:
        raise cagd.CagdError(f"{name}: nothing linked")
    if obj.isDerivedFrom("Points::Feature"):
        pts = obj.Points.Points
    elif obj.isDerivedFrom("Mesh::Feature"):
        pts = obj.Mesh.Topology[0]
    elif getattr(obj, "Shape", None) is not None and not obj.Shape.isNull():
        pts = [v.Point for v in obj.Shape.Vertexes]
    else:
        raise cagd.CagdError(f"{name}: {obj.Label} is neither a Points object, a mesh nor a shape")
    if not pts:
        raise cagd.CagdError(f"{name}: {obj.Label} holds no points")
    return conversion.array(pts)


def fit_input(obj) -> np.ndarray:
    """The points to fit: the linked Vertices in order when any, else Source's points."""
    if obj.Vertices:
        return linked_points(obj.Vertices)
    if obj.Source is None:
        raise cagd.CagdError("Source: link a Points object, a mesh or a shape (or set Vertices)")
    return source_points(obj.Source)


def _readonly(obj, names) -> None:
    for name in names:
        obj.setEditorMode(name, 1)


class Measured(Feature):
    """A feature whose :meth:`compute` also gives read-only results (Feature.RESULTS)
    and may end valid with a warning (the engine's best result kept)."""

    def compute(self, obj) -> Tuple[object, Dict[str, object], Optional[str]]:
        raise NotImplementedError

    def build(self, obj):
        return self.compute(obj)[0]


FIT_RESULTS = (("MaxError", 0.0), ("RmsError", 0.0), ("Converged", False))


def _fit_properties(obj, what: str, tol: float) -> None:
    add(obj, "Link", "Source", "Fit", "A Points object, a mesh (its vertices) or a shape (its vertices)")
    add(obj, "LinkSubList", "Vertices", "Fit", "Vertices in order (used instead of Source when set)")
    add(obj, PRECISION, "Tolerance", "Fit", f"Largest allowed distance (mm, > 0) of a point from the {what}", tol)
    add(obj, PRECISION, "MaxError", "Status", "Largest distance of a point from the fit (mm, engine's certified "
        "closest points)", 0.0)
    add(obj, PRECISION, "RmsError", "Status", "Root-mean-square distance of the points (mm)", 0.0)
    add(obj, "Bool", "Converged", "Status", "Every point within Tolerance", False)


def _fit_warning(fit, tol: float) -> Optional[str]:
    if fit.converged and fit.max_error <= tol:
        return None
    return (f"Tolerance {tol:.3g} mm not met: largest distance {fit.max_error:.3g} mm, best fit kept "
            f"({fit.message}); raise Tolerance or MaxControlPoints")


def edge_tangent(link, name: str, point: np.ndarray, leaving: bool) -> np.ndarray:
    """The unit tangent of the linked edge at its end nearest ``point``, pointing away
    from the edge when ``leaving`` (the fit continues it) and into its end otherwise
    (the fit runs on into the edge)."""
    edge = linked_edge(link, name)
    ends = [(edge.FirstParameter, -1.0), (edge.LastParameter, 1.0)]
    t, outward = min(ends, key=lambda e: float(np.linalg.norm(vector(edge.valueAt(e[0])) - point)))
    d = vector(edge.tangentAt(t)) * outward
    return d if leaving else -d


def _fit_names(obj) -> Dict[str, str]:
    """FIT_NAMES with the points named after the link that gave them."""
    return dict(FIT_NAMES, points="Vertices" if obj.Vertices else "Source")


def _cap(obj) -> int:
    cap = int(obj.MaxControlPoints)
    if cap < 0:
        raise cagd.CagdError(f"MaxControlPoints: must be >= 0 (0 = automatic), got {cap}")
    return cap


class FitCurve(Measured):
    """A B-spline within Tolerance of points, with few control points (cagd.fit_curve:
    least squares with parameter correction and adaptive knots, Piegl & Tiller 9.4)."""

    TYPE = "Cagd::FitCurve"
    DEFAULT_LABEL = "FitCurve"
    LINKS = ("Source", "Vertices", "StartEdge", "EndEdge")
    POINTS = "Source"
    RESULTS = FIT_RESULTS + (("ControlPoints", 0),)

    def setup(self, obj) -> None:
        _fit_properties(obj, "curve", 0.01)
        add(obj, "Integer", "Degree", "Fit", "Degree p >= 1", 3)
        add(obj, "Bool", "Periodic", "Fit", "Closed periodic curve, C^(p-1) at its seam (points in order round "
            "the loop)", False)
        add_enum(obj, "Parametrization", "Fit", "Initial parameters of the points", PARAMETERS, "centripetal")
        add(obj, "Integer", "MaxControlPoints", "Fit", "Cap on the control-point count; 0 = the number of points", 0)
        add(obj, "Vector", "StartTangent", "Tangents", "Direction held at the first point; zero = free")
        add(obj, "Vector", "EndTangent", "Tangents", "Direction held at the last point; zero = free")
        add(obj, "LinkSub", "StartEdge", "Tangents", "An edge the fit continues G1 at its first point (the "
            "edge's end nearest that point; overrides StartTangent)")
        add(obj, "LinkSub", "EndEdge", "Tangents", "An edge the fit runs into G1 at its last point (overrides "
            "EndTangent)")
        add(obj, "Integer", "ControlPoints", "Status", "Control points of the fit", 0)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def claimed(self, obj) -> list:
        """The points' objects; the tangent edges (neighbouring curves) stay where they are."""
        return [o for o in Feature.claimed(self, obj)
                if o not in [getattr(obj, n)[0] for n in ("StartEdge", "EndEdge") if getattr(obj, n)]]

    def compute(self, obj):
        tol = _tolerance(obj)
        P = fit_input(obj)
        tangents = [None if v.Length == ZERO else vector(v) for v in (obj.StartTangent, obj.EndTangent)]
        for k, name in enumerate(("StartEdge", "EndEdge")):
            if getattr(obj, name):
                tangents[k] = edge_tangent(getattr(obj, name), name, P[-k], leaving=k == 0)
        if obj.Periodic and any(t is not None for t in tangents):
            raise cagd.CagdError("StartTangent: a periodic fit has no end tangents; set StartTangent and "
                                 "EndTangent to zero and clear StartEdge and EndEdge")
        cap = _cap(obj)
        with renamed(_fit_names(obj)):
            fit = cagd.fit_curve(P, tol, int(obj.Degree), obj.Parametrization, start_tangent=tangents[0],
                                 end_tangent=tangents[1], max_control_points=cap or None,
                                 periodic=bool(obj.Periodic))
        values = {"MaxError": float(fit.max_error), "RmsError": float(fit.rms_error),
                  "Converged": bool(fit.converged), "ControlPoints": len(fit.curve.control_points)}
        return fit.curve, values, _fit_warning(fit, tol)


AUTO_DEGREE_DOC = ("On: the engine chooses the degree: it fits with each of the degrees "
                   f"{', '.join(map(str, AUTO_DEGREES))} (both directions; at most a "
                   "grid's rows - 1 and columns - 1) and keeps the fit with the fewest control points; DegreeU "
                   "and DegreeV are not used then (AchievedDegreeU/V show the choice). Off (default): DegreeU, "
                   "DegreeV")


class FitSurface(Measured):
    """A B-spline surface within Tolerance of a grid of points (GridRows > 0: the points
    row-major, GridRows rows) or of scattered points (a sheet over its least-squares
    plane) (cagd.fit_surface); with AutoDegree the engine's degree="auto"."""

    TYPE = "Cagd::FitSurface"
    DEFAULT_LABEL = "FitSurface"
    LINKS = ("Source", "Vertices")
    POINTS = "Source"
    RESULTS = FIT_RESULTS + (("ControlPointsU", 0), ("ControlPointsV", 0), ("AchievedDegreeU", 0),
                             ("AchievedDegreeV", 0))

    def setup(self, obj) -> None:
        _fit_properties(obj, "surface", 0.01)
        add(obj, "Integer", "DegreeU", "Fit", "Degree in u", 3)
        add(obj, "Integer", "DegreeV", "Fit", "Degree in v", 3)
        add(obj, "Integer", "GridRows", "Fit", "0 = scattered points; n > 0: the points are a grid of n rows, "
            "row-major", 0)
        add(obj, "Integer", "MaxControlPoints", "Fit", "Cap on the control-point count in u and in v; 0 = the "
            "engine's default (the grid's size)", 0)
        add(obj, "Integer", "ControlPointsU", "Status", "Control points of the fit in u", 0)
        add(obj, "Integer", "ControlPointsV", "Status", "Control points of the fit in v", 0)
        self.add_auto_degree(obj)

    def add_auto_degree(self, obj) -> None:
        """AutoDegree (off) and the read-only achieved degrees, where missing (a document
        saved before them gets them on restore)."""
        if not hasattr(obj, "AutoDegree"):
            add(obj, "Bool", "AutoDegree", "Fit", AUTO_DEGREE_DOC, False)
        for name, axis in (("AchievedDegreeU", "u"), ("AchievedDegreeV", "v")):
            if not hasattr(obj, name):
                add(obj, "Integer", name, "Status", f"Degree of the fit in {axis} (DegreeU/V, or the engine's "
                    "choice with AutoDegree)", 0)
        _readonly(obj, [n for n, _ in self.RESULTS])
        self.degree_modes(obj)

    @staticmethod
    def degree_modes(obj) -> None:
        """DegreeU and DegreeV read-only while AutoDegree is on (they are not used then)."""
        if hasattr(obj, "AutoDegree"):
            for name in ("DegreeU", "DegreeV"):
                obj.setEditorMode(name, 1 if obj.AutoDegree else 0)

    def onChanged(self, obj, prop: str) -> None:
        super().onChanged(obj, prop)
        if prop == "AutoDegree":
            self.degree_modes(obj)

    def onDocumentRestored(self, obj) -> None:
        super().onDocumentRestored(obj)
        self.add_auto_degree(obj)

    def compute(self, obj):
        tol = _tolerance(obj)
        P = fit_input(obj)
        rows = int(obj.GridRows)
        if rows < 0 or (rows and len(P) % rows):
            raise cagd.CagdError(f"GridRows: {len(P)} points do not form {rows} rows of equal length "
                                 "(0 = scattered)")
        if rows:
            P = P.reshape(rows, len(P) // rows, 3)
        cap = _cap(obj)
        auto = bool(getattr(obj, "AutoDegree", False))
        with renamed(dict(_fit_names(obj), degree="AutoDegree" if auto else "DegreeU, DegreeV")):
            fit = cagd.fit_surface(P, tol, "auto" if auto else (int(obj.DegreeU), int(obj.DegreeV)),
                                   max_control_points=(cap, cap) if cap else None)
        nu, nv = np.asarray(fit.surface.control_points).shape[:2]
        values = {"MaxError": float(fit.max_error), "RmsError": float(fit.rms_error),
                  "Converged": bool(fit.converged), "ControlPointsU": int(nu), "ControlPointsV": int(nv),
                  "AchievedDegreeU": int(fit.surface.degree_u), "AchievedDegreeV": int(fit.surface.degree_v)}
        return fit.surface, values, _fit_warning(fit, tol)


# --- operations on a linked edge or face -----------------------------------------------------
def linked_element(link, name: str = "Source"):
    """The edge or face of a LinkSub value ``(obj, ['Edge1'])`` (or a whole object whose
    shape is one face, or else one edge); errors name the property."""
    obj, subs, shape = link_target(link, name, "edge or face")
    if not subs:
        if len(shape.Faces) == 1:
            return shape.Faces[0], f"{obj.Label}"
        if not shape.Faces and len(shape.Edges) == 1:
            return shape.Edges[0], f"{obj.Label}"
        raise cagd.CagdError(f"{name}: {obj.Label} has {len(shape.Faces)} faces and {len(shape.Edges)} edges; "
                             "link one edge or face")
    element = _element(obj, subs[0], name)
    if element.ShapeType not in ("Edge", "Face"):
        raise cagd.CagdError(f"{name}: {obj.Label}.{subs[0]} is a {element.ShapeType}, not an edge or a face")
    return element, f"{obj.Label}.{subs[0]}"


def source_geometry(link, name: str = "Source"):
    """The engine B-spline of the linked edge (its trimmed range) or face (its
    untrimmed surface when bounded by its parameter box; a trimmed face is refused)."""
    element, where = linked_element(link, name)
    if element.ShapeType == "Edge":
        return conversion.edge_to_curve(element)
    surface, reason = conversion.face_to_trimmed(element)
    if isinstance(surface, cagd.TrimmedSurface) or reason is not None:
        raise cagd.CagdError(f"{name}: {where} is a trimmed face (its boundary is not its parameter box"
                             + (f"; {reason}" if reason else "") + "); these operations take whole B-spline faces")
    return surface


def _surface(geometry) -> bool:
    return isinstance(geometry, cagd.Surface)


class Operation(Measured):
    """Base of the operations on a linked edge or face: ``Source`` and read-only ``Deviation``."""

    LINKS = ("Source",)
    POINTS = "Source"
    RESULTS: Tuple[Tuple[str, object], ...] = (("Deviation", 0.0),)

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Source", self.GROUP, "The edge or face to work on")
        add(obj, PRECISION, "Deviation", "Status", self.DEVIATION_DOC, 0.0)
        self.parameters(obj)
        _readonly(obj, [n for n, _ in self.RESULTS])

    GROUP = "Operation"
    DEVIATION_DOC = "Largest deviation of the result from the source (mm, measured by the engine)"

    def parameters(self, obj) -> None:
        """Add the operation's own properties."""

    NAMES = OPERATION_NAMES          # engine argument -> property, for the error messages

    def compute(self, obj):
        source = source_geometry(obj.Source)
        with renamed(self.NAMES):
            return self.operate(obj, source)

    def operate(self, obj, source):
        raise NotImplementedError


def _pair(obj, name: str, v_name: str) -> Tuple[int, int]:
    """(value, value in v) of two integer properties; the v one 0 = the same."""
    a, b = int(getattr(obj, name)), int(getattr(obj, v_name))
    return a, (b or a)


class Rebuild(Operation):
    """The source as a B-spline of Count control points of Degree (cagd.rebuild:
    least squares on dense samples, ends held); a face per direction."""

    TYPE = "Cagd::Rebuild"
    DEFAULT_LABEL = "Rebuild"
    GROUP = "Rebuild"
    DEVIATION_DOC = "Largest distance of the source from the rebuilt geometry (mm, certified closest points)"

    def parameters(self, obj) -> None:
        add(obj, "Integer", "Count", "Rebuild", "Control points (a face: in u); 0 = the source's own count", 0)
        add(obj, "Integer", "CountV", "Rebuild", "A face's control points in v; 0 = as Count (or the source's)", 0)
        add(obj, "Integer", "Degree", "Rebuild", "Degree (a face: in u)", 3)
        add(obj, "Integer", "DegreeV", "Rebuild", "A face's degree in v; 0 = as Degree", 0)

    def operate(self, obj, source):
        n = np.asarray(source.to_nurbs().control_points).shape
        if _surface(source):
            pu, pv = _pair(obj, "Degree", "DegreeV")
            cu, cv = int(obj.Count), int(obj.CountV) or int(obj.Count)
            count = (cu or max(n[0], pu + 1), cv or max(n[1], pv + 1))
            r = cagd.rebuild(source, count, (pu, pv))
        else:
            p = int(obj.Degree)
            r = cagd.rebuild(source, int(obj.Count) or max(n[0], p + 1), p)
        return r.result, {"Deviation": float(r.deviation)}, None if r.converged else r.message


def _direction_steps(direction: str, source, tol: float):
    """[(direction or None, tol share)]: a curve one step; a face in U, V or Both
    (U with half of Tolerance, then V with what its bound left, as cq_ext's removeKnots)."""
    if not _surface(source):
        return [(None, tol)]
    if direction == "Both":
        return [("u", 0.5 * tol), ("v", None)]
    return [(direction.lower(), tol)]


def remove_knots_within(source, tol: float, direction: str = "Both") -> Tuple[object, int, float, float]:
    """(geometry, knots removed, summed error bound, summed deviation) of the engine
    curve or surface ``source`` with as many knots removed as keep it within ``tol``
    (a surface in ``direction``: U, V or Both, see :func:`_direction_steps`; Tiller's
    removal, Piegl & Tiller A5.8). The RemoveKnots object and the pole editor use it."""
    removed, bound, dev, geometry = 0, 0.0, 0.0, source
    for step, share in _direction_steps(direction, source, tol):
        share = tol - bound if share is None else share
        r = geometry.remove_knots(share) if step is None else geometry.remove_knots(share, step)
        geometry, removed, bound, dev = r.result, removed + r.removed, bound + r.error_bound, dev + r.deviation
    return geometry, removed, bound, dev


def _direction_property(obj, group: str, what: str) -> None:
    add_enum(obj, "Direction", group, f"A face's direction(s) to {what} (Both: u with half of Tolerance, then v)",
             DIRECTIONS, "Both")


class RemoveKnots(Operation):
    """As many interior knots removed as keep the source within Tolerance of itself at
    equal parameters (Tiller's knot removal with its error bound, Piegl & Tiller A5.8)."""

    TYPE = "Cagd::RemoveKnots"
    DEFAULT_LABEL = "RemoveKnots"
    GROUP = "RemoveKnots"
    RESULTS = Operation.RESULTS + (("KnotsRemoved", 0), ("ErrorBound", 0.0))
    DEVIATION_DOC = "Largest deviation from the source at equal parameters (mm, sampled per knot span)"

    def parameters(self, obj) -> None:
        add(obj, PRECISION, "Tolerance", "RemoveKnots", "Largest allowed deviation (mm, > 0)", 1e-3)
        _direction_property(obj, "RemoveKnots", "remove knots in")
        add(obj, "Integer", "KnotsRemoved", "Status", "Knots removed", 0)
        add(obj, PRECISION, "ErrorBound", "Status", "Tiller's certified bound of the deviation (mm, <= Tolerance)", 0.0)

    def operate(self, obj, source):
        geometry, removed, bound, dev = remove_knots_within(source, _tolerance(obj), obj.Direction)
        return geometry, {"Deviation": float(dev), "KnotsRemoved": int(removed), "ErrorBound": float(bound)}, None


class ReduceDegree(Operation):
    """The source one degree lower (a face: in Direction), within Tolerance at equal
    parameters if the shape allows (Piegl & Tiller 5.6, A5.11, then knot removal); an
    unmet Tolerance keeps the reduced geometry with a warning and Converged False."""

    TYPE = "Cagd::ReduceDegree"
    DEFAULT_LABEL = "ReduceDegree"
    GROUP = "ReduceDegree"
    RESULTS = Operation.RESULTS + (("ErrorBound", 0.0), ("Converged", False))
    DEVIATION_DOC = "Largest deviation from the source at equal parameters (mm, sampled per knot span)"
    NAMES = dict(OPERATION_NAMES, degree="Source")        # no Degree property: the source's degree

    def parameters(self, obj) -> None:
        add(obj, PRECISION, "Tolerance", "ReduceDegree", "Largest allowed deviation (mm, > 0)", 0.01)
        _direction_property(obj, "ReduceDegree", "reduce")
        add(obj, PRECISION, "ErrorBound", "Status", "Certified bound of the deviation (mm)", 0.0)
        add(obj, "Bool", "Converged", "Status", "ErrorBound within Tolerance", False)

    def operate(self, obj, source):
        tol = _tolerance(obj)
        bound, dev, geometry, ok, notes = 0.0, 0.0, source, True, []
        for direction, share in _direction_steps(obj.Direction, source, tol):
            share = max(tol - bound, 0.0) if share is None else share
            r = geometry.reduce_degree(share) if direction is None else geometry.reduce_degree(share, direction)
            geometry, bound, dev = r.result, bound + r.error_bound, dev + r.deviation
            ok = ok and bool(r.converged)
            if not r.converged:
                notes.append(r.message)
        ok = ok and bound <= tol
        warning = None if ok else (f"Tolerance {tol:.3g} mm not met: bound {bound:.3g} mm, measured {dev:.3g} mm; "
                                   f"the reduced geometry is kept ({'; '.join(notes) or 'bound over Tolerance'})")
        return geometry, {"Deviation": float(dev), "ErrorBound": float(bound), "Converged": ok}, warning


class Fair(Operation):
    """The source with its fairness energy lowered while it stays within Tolerance of
    itself, Keep held exactly at the ends (curve: curvature variation, G0/G1/G2) or
    along the four edges (face: thin-plate energy, G0/G1/G2) (cagd.fair_curve, fair_surface)."""

    TYPE = "Cagd::Fair"
    DEFAULT_LABEL = "Fair"
    GROUP = "Fair"
    RESULTS = Operation.RESULTS + (("EnergyBefore", 0.0), ("EnergyAfter", 0.0), ("InflectionsBefore", 0),
                                   ("InflectionsAfter", 0), ("Converged", False))
    DEVIATION_DOC = "Certified largest distance of the result from the source (mm, <= Tolerance)"

    def parameters(self, obj) -> None:
        add(obj, PRECISION, "Tolerance", "Fair", "Largest allowed distance from the source (mm, > 0)", 0.01)
        add_enum(obj, "Keep", "Fair", "Continuity held at the ends (a face: along its four edges)", KEEP, "G2")
        add(obj, PRECISION, "EnergyBefore", "Status", "Fairness energy of the source", 0.0)
        add(obj, PRECISION, "EnergyAfter", "Status", "Fairness energy of the result", 0.0)
        add(obj, "Integer", "InflectionsBefore", "Status", "Curvature sign changes of the source (curves)", 0)
        add(obj, "Integer", "InflectionsAfter", "Status", "Curvature sign changes of the result (curves)", 0)
        add(obj, "Bool", "Converged", "Status", "The engine's fairing converged", False)

    def operate(self, obj, source):
        tol = _tolerance(obj)
        if _surface(source):
            r = cagd.fair_surface(source, tol, obj.Keep)
            geometry, values = r.surface, {}
        else:
            r = cagd.fair_curve(source, tol, obj.Keep)
            geometry = r.curve
            values = {"InflectionsBefore": int(r.inflections_before), "InflectionsAfter": int(r.inflections_after)}
        values.update(Deviation=float(r.max_deviation), EnergyBefore=float(r.energy_before),
                      EnergyAfter=float(r.energy_after), Converged=bool(r.converged))
        return geometry, values, None if r.converged else r.message


OPERATIONS = {"Rebuild": Rebuild, "RemoveKnots": RemoveKnots, "ReduceDegree": ReduceDegree, "Fair": Fair}


# --- creation helpers (used by the commands and the tests) ----------------------------------
def make_fit_curve(source=None, vertices=None, doc=None, **values):
    """``source``: a Points, mesh or shape object; ``vertices``: [(obj, 'VertexN'), ...]."""
    return _make(FitCurve, doc, source, vertices, values)


def make_fit_surface(source=None, vertices=None, doc=None, **values):
    return _make(FitSurface, doc, source, vertices, values)


def _make(cls, doc, source, vertices, values):
    links = {k: v for k, v in (("Source", source), ("Vertices", vertices)) if v is not None}
    return make(cls, doc=doc, **links, **values)


def make_operation(kind: str, source, doc=None, **values):
    """``kind``: one of OPERATIONS; ``source``: (object, 'EdgeN' or 'FaceN')."""
    return make(OPERATIONS[kind], doc=doc, Source=source, **values)


def check_operation(kind: str, source) -> dict:
    """The property values the command gives a new ``kind`` object on ``source`` (Fair:
    the strongest Keep that leaves control points to move; ReduceDegree: the directions
    above degree 1), or raise the error the object would be in, before any object is
    made (the commands refuse a wrong selection)."""
    geometry = source_geometry(source)
    surface = _surface(geometry)
    with renamed(OPERATION_NAMES):
        if kind == "ReduceDegree":
            if not surface:
                if geometry.degree < 2:
                    raise cagd.CagdError("Source: a degree-1 edge cannot be reduced further")
                return {}
            free = [d for d, p in (("U", geometry.degree_u), ("V", geometry.degree_v)) if p >= 2]
            if not free:
                raise cagd.CagdError("Source: degree 1 in u and v; the face cannot be reduced further")
            return {"Direction": "Both" if len(free) == 2 else free[0]}
        if kind == "Fair":
            fair = cagd.fair_surface if surface else cagd.fair_curve
            error = None
            for keep in reversed(KEEP):
                try:
                    fair(geometry, FAIR_PROBE * _size(geometry), keep)
                except cagd.CagdError as exc:
                    error = exc
                    if "keep=" not in str(exc):
                        raise
                else:
                    return {"Keep": keep}
            raise error
    return {}


#: the tolerance of the command's trial fairing, relative to the source's size
FAIR_PROBE = 1e-3


def _size(geometry) -> float:
    P = np.asarray(geometry.to_nurbs().control_points, float).reshape(-1, 3)
    return max(float(np.ptp(P, axis=0).max()), 1.0)


def on_edge(obj) -> bool:
    """True for an operation whose Source is an edge (its view gets the curvature comb)."""
    if not isinstance(getattr(obj, "Proxy", None), Operation) or not obj.Source:
        return False
    try:
        return linked_element(obj.Source)[0].ShapeType == "Edge"
    except cagd.CagdError:
        return False
