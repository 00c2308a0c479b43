"""Parametric curve objects: Bezier, B-spline/NURBS by poles, interpolating B-spline,
natural cubic spline, Hermite curve and the G1/G2 join of two curves.

Each proxy turns its properties into one engine call (cagd.BezierCurve,
cagd.BSplineCurve, cagd.interpolate, cagd.natural_cubic_spline, cagd.HermiteCurve,
cagd.join); the shape is the exact B-spline form of the result.
"""
from __future__ import annotations

import math

import numpy as np

import FreeCAD as App

from . import conversion
from .conversion import cagd
from .features import Feature, add, add_enum, linked_edge, make, points_from, vector, weights_or_none

V = App.Vector
PARAMETERS = cagd.fitting.PARAMETERS        # the engine's parameters= names (property "Parametrization")
END_CONDITIONS = ("natural", "clamped", "periodic", "virtual")
JOIN_CONTINUITIES = ("G1", "G2", "C1", "C2")
HERMITE_ANGLE = math.radians(30.0)     # example tangents: the chord turned by this angle


def _poles_and_vertices(obj, poles, doc_poles: str) -> None:
    add(obj, "VectorList", "Poles", "Curve", doc_poles, poles)
    add(obj, "LinkSubList", "Vertices", "Curve",
        "Vertices (or point objects) giving the poles; when set, Poles follow them")


class BezierCurve(Feature):
    """Bezier curve C(t) = sum B_i^n(t) w_i P_i / sum B_i^n(t) w_i on [0, 1] (Farin ch. 4)."""

    TYPE = "Cagd::BezierCurve"
    DEFAULT_LABEL = "BezierCurve"
    LINKS = ("Vertices",)

    def setup(self, obj) -> None:
        _poles_and_vertices(obj, [V(0, 0, 0), V(10, 20, 0), V(30, 20, 5), V(40, 0, 0)], "Control points P_0..P_n")
        add(obj, "FloatList", "Weights", "Curve", "One positive weight per pole; empty = polynomial")

    def build(self, obj):
        return cagd.BezierCurve(points_from(obj, "Poles"), weights_or_none(obj.Weights))


class BSplineCurve(Feature):
    """B-spline / NURBS curve from poles, degree, knots and weights (Piegl & Tiller ch. 2, 4)."""

    TYPE = "Cagd::BSplineCurve"
    DEFAULT_LABEL = "BSplineCurve"
    LINKS = ("Vertices",)

    def setup(self, obj) -> None:
        _poles_and_vertices(obj, [V(0, 0, 0), V(10, 15, 0), V(20, -5, 5), V(30, 15, 5), V(40, 0, 0),
                                  V(50, 10, 0)], "Control points")
        add(obj, "Integer", "Degree", "Curve", "Polynomial degree p >= 1", 3)
        add(obj, "FloatList", "Knots", "Curve",
            "Full knot vector (n+p+1 values; periodic: one period t_0..t_n); empty = clamped uniform on [0, 1]")
        add(obj, "FloatList", "Weights", "Curve", "One positive weight per pole; empty = polynomial")
        add(obj, "Bool", "Periodic", "Curve", "Closed periodic curve (poles wrap around)", False)

    def build(self, obj):
        poles = points_from(obj, "Poles")
        knots = np.array(obj.Knots, dtype=float) if len(obj.Knots) else None
        if knots is None and obj.Periodic:
            knots = np.linspace(0.0, 1.0, len(poles) + 1)
        return cagd.BSplineCurve(poles, obj.Degree, knots, weights_or_none(obj.Weights), obj.Periodic)


class InterpolationCurve(Feature):
    """The B-spline through points or vertices (global interpolation, Piegl & Tiller 9.2.1)."""

    TYPE = "Cagd::InterpolationCurve"
    DEFAULT_LABEL = "InterpolationCurve"
    LINKS = ("Vertices",)
    POINTS = "Points"

    def setup(self, obj) -> None:
        add(obj, "VectorList", "Points", "Curve", "Points the curve passes through",
            [V(0, 0, 0), V(10, 10, 0), V(20, 0, 5), V(30, 10, 5), V(40, 0, 0)])
        add(obj, "LinkSubList", "Vertices", "Curve", "Vertices giving the points; when set, Points follow them")
        add(obj, "Integer", "Degree", "Curve", "Degree p, 1 <= p < number of points", 3)
        add_enum(obj, "Parametrization", "Curve", "Parameters of the points", PARAMETERS, "chord")

    def build(self, obj):
        return cagd.interpolate(points_from(obj), obj.Degree, parameters=obj.Parametrization)


class CubicSpline(Feature):
    """Interpolating C2 cubic spline with a choice of end conditions (seed 000, 5.1.2)."""

    TYPE = "Cagd::CubicSpline"
    DEFAULT_LABEL = "CubicSpline"
    LINKS = ("Vertices",)
    POINTS = "Points"

    def setup(self, obj) -> None:
        add(obj, "VectorList", "Points", "Curve", "Points the spline passes through",
            [V(0, 0, 0), V(10, 10, 0), V(20, 0, 5), V(30, 10, 5), V(40, 0, 0)])
        add(obj, "LinkSubList", "Vertices", "Curve", "Vertices giving the points; when set, Points follow them")
        add_enum(obj, "EndCondition", "Curve", "natural: S''=0 at the ends; clamped: end tangents; "
                 "periodic: closed C2 (the first point is appended when the list is open); "
                 "virtual: extra points beyond the ends", END_CONDITIONS, "natural")
        add_enum(obj, "Parametrization", "Curve", "Parameters of the points", PARAMETERS, "chord")
        add(obj, "Vector", "StartTangent", "Clamped", "S'(t_0) for EndCondition clamped", V(1, 1, 0))
        add(obj, "Vector", "EndTangent", "Clamped", "S'(t_n) for EndCondition clamped", V(1, -1, 0))
        add(obj, "Bool", "ReflectedVirtualPoints", "Virtual",
            "Use the reflections 2p_0-p_1, 2p_n-p_(n-1) as virtual points", True)
        add(obj, "Vector", "StartVirtualPoint", "Virtual", "p_(-1) when not reflected", V(-10, -10, 0))
        add(obj, "Vector", "EndVirtualPoint", "Virtual", "p_(n+1) when not reflected", V(50, -10, 0))

    def build(self, obj):
        P = points_from(obj)
        kind = obj.EndCondition
        kwargs = {}
        if kind == "periodic" and len(P) and np.any(P[-1] != P[0]):
            P = np.vstack([P, P[:1]])
        if kind == "clamped":
            kwargs["tangents"] = np.array([vector(obj.StartTangent), vector(obj.EndTangent)])
        if kind == "virtual" and not obj.ReflectedVirtualPoints:
            kwargs["virtual_points"] = np.array([vector(obj.StartVirtualPoint), vector(obj.EndVirtualPoint)])
        return cagd.natural_cubic_spline(P, kind, parameters=obj.Parametrization, **kwargs)


class HermiteCurve(Feature):
    """Cubic Hermite curve from end points and end tangents (seed 000, 5.1)."""

    TYPE = "Cagd::HermiteCurve"
    DEFAULT_LABEL = "HermiteCurve"
    POINTS = "StartPoint, EndPoint"

    def setup(self, obj) -> None:
        add(obj, "Vector", "StartPoint", "Curve", "p0 = C(0)", V(0, 0, 0))
        add(obj, "Vector", "EndPoint", "Curve", "p1 = C(1)", V(40, 0, 0))
        t0, t1 = example_tangents(V(0, 0, 0), V(40, 0, 0))
        add(obj, "Vector", "StartTangent", "Curve", "C'(0)", t0)
        add(obj, "Vector", "EndTangent", "Curve", "C'(1)", t1)

    def build(self, obj):
        return cagd.HermiteCurve(vector(obj.StartPoint), vector(obj.EndPoint),
                                 vector(obj.StartTangent), vector(obj.EndTangent))


class JoinCurve(Feature):
    """Continue the curve ``Base`` with the curve ``Source`` G1/G2 (or C1/C2) at Base's
    end (cagd.join, seed 000, 5.2.5): Source's leading control points are replaced by
    Q_0 = P_n, Q_1 - Q_0 = alpha (P_n - P_(n-1)) and the G2 point with beta; Base's
    last Bezier segment is used, Source must be one polynomial Bezier segment."""

    TYPE = "Cagd::JoinCurve"
    DEFAULT_LABEL = "JoinCurve"
    LINKS = ("Base", "Source")
    POINTS = "Base, Source"

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Base", "Join", "The curve P to continue (at its end)")
        add(obj, "LinkSub", "Source", "Join", "The curve Q whose free control points are kept")
        add_enum(obj, "Continuity", "Join", "G1/G2 with alpha, beta; C1/C2 fix alpha = n/m, beta = 0",
                 JOIN_CONTINUITIES, "G2")
        add(obj, "Float", "Alpha", "Join", "G1 scale: Q_1 - Q_0 = alpha (P_n - P_(n-1)), alpha > 0", 1.0)
        add(obj, "Float", "Beta", "Join", "G2 shape parameter beta", 0.0)

    def claimed(self, obj) -> list:
        """Only Source: the join replaces it, while Base stays a curve of its own."""
        source = obj.Source[0] if obj.Source else None
        return [source] if source is not None and source is not obj else []

    def build(self, obj):
        P = conversion.edge_to_curve(linked_edge(obj.Base, "Base")).to_bezier()[-1]
        Q = join_source(linked_edge(obj.Source, "Source"))
        c = {"G1": 1, "C1": 1, "G2": 2, "C2": 2}[obj.Continuity]
        rest = Q.control_points[c + 1:]
        alpha, beta = (obj.Alpha, obj.Beta) if obj.Continuity[0] == "G" else (1.0, 0.0)
        return cagd.join(P, rest, obj.Continuity, alpha, beta)


def join_source(edge):
    """The edge's curve as the one polynomial Bezier segment a join's Source must be;
    CagdError naming Source otherwise (several spans, rational). The command calls it
    before creating an object."""
    pieces = conversion.edge_to_curve(edge).to_bezier()
    if len(pieces) != 1:
        raise cagd.CagdError(f"Source: must be a single Bezier segment, this curve has {len(pieces)} spans")
    if pieces[0].is_rational:
        raise cagd.CagdError("Source: must be polynomial (the joined curve is a polynomial Bezier curve)")
    return pieces[0]


def example_tangents(start, end, angle: float = HERMITE_ANGLE):
    """End tangents of an example Hermite curve from ``start`` to ``end``: close to the
    circular arc through both that turns by 2 angle (radius R = |d| / (2 sin angle) for
    the chord d): the chord turned by +angle at the start and -angle at the end, in the
    plane of d and z (of d and x when d is near z), of length 4 R tan(angle / 2) (the
    cubic arc approximation, Farin 13.3: handles 4/3 tan(angle / 2) R; a Hermite tangent
    is 3 handles). Its curvature stays within 0.5 % of 1 / R: no hooks at the ends
    (tangents normal to the chord made the curvature peak there)."""
    d = end - start
    normal = V(0, 0, 1) if abs(d.z) < 0.9 * d.Length else V(1, 0, 0)
    side = normal.cross(d)
    side = side * (d.Length / side.Length) if side.Length > 0 else side
    length = 4.0 * math.tan(0.5 * angle) / (2.0 * math.sin(angle))      # |tangent| / |d|
    c, s = math.cos(angle), math.sin(angle)
    return (d * c + side * s) * length, (d * c - side * s) * length


# --- creation helpers (used by the commands and the tests) ----------------------------------
def make_bezier_curve(poles=None, weights=None, vertices=None, doc=None):
    return _make(BezierCurve, doc, Poles=poles, Weights=weights, Vertices=vertices)


def make_bspline_curve(poles=None, degree=None, knots=None, weights=None, periodic=None, vertices=None, doc=None):
    return _make(BSplineCurve, doc, Poles=poles, Degree=degree, Knots=knots, Weights=weights,
                 Periodic=periodic, Vertices=vertices)


def make_interpolation_curve(points=None, degree=None, vertices=None, doc=None):
    return _make(InterpolationCurve, doc, Points=points, Degree=degree, Vertices=vertices)


def make_cubic_spline(points=None, end_condition=None, vertices=None, doc=None):
    return _make(CubicSpline, doc, Points=points, EndCondition=end_condition, Vertices=vertices)


def make_hermite_curve(doc=None, **values):
    return _make(HermiteCurve, doc, **values)


def make_join(base, source, continuity="G2", alpha=1.0, beta=0.0, doc=None):
    """``base``/``source``: (object, 'EdgeN') pairs."""
    return _make(JoinCurve, doc, Base=base, Source=source, Continuity=continuity, Alpha=alpha, Beta=beta)


def _make(cls, doc, **values):
    return make(cls, doc=doc, **{k: (conversion.vectors(v) if k in ("Poles", "Points") and
                                     isinstance(v, np.ndarray) else v)
                                 for k, v in values.items() if v is not None})
