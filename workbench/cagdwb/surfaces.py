"""Parametric surface objects: Bezier and B-spline surfaces from a point grid, Coons
patch from four linked edges, Bezier triangle, surface of revolution and the
primitives (sphere, torus, cylinder, cone).

Each proxy makes one engine object (cagd.BezierSurface, cagd.BSplineSurface,
cagd.interpolate_surface, cagd.CoonsPatch, cagd.BezierTriangle, cagd.revolve,
cagd.sphere / torus / cylinder / cone); the shape is the face of its exact B-spline
form, except for the revolution and the primitives: FreeCAD's own analytic surface
(Part.SurfaceOfRevolution of the profile's exact B-spline, Part.Sphere, ...), the
same surface, which Part's Offset and Thickness accept; their ``Nurbs`` property
gives the exact NURBS face instead (see conversion.analytic_surface).
"""
from __future__ import annotations

import math
from typing import List

import numpy as np

import FreeCAD as App

from . import conversion
from .conversion import cagd
from .features import Feature, add, add_enum, grid, linked_edge, linked_edges, make, vector, weights_or_none

V = App.Vector


def sample_grid(count_u: int, count_v: int, size: float = 40.0) -> List[App.Vector]:
    """A wavy (count_u x count_v) grid of points, row-major (default geometry)."""
    pts = []
    for i in range(count_u):
        for j in range(count_v):
            x, y = size * i / (count_u - 1), size * j / (count_v - 1)
            pts.append(V(x, y, 6.0 * math.sin(math.pi * i / (count_u - 1)) * math.cos(math.pi * j / (count_v - 1))))
    return pts


class BezierSurface(Feature):
    """Tensor-product Bezier surface from a (m+1) x (n+1) grid of poles (Farin ch. 15)."""

    TYPE = "Cagd::BezierSurface"
    DEFAULT_LABEL = "BezierSurface"

    def setup(self, obj) -> None:
        add(obj, "VectorList", "Poles", "Surface", "Control points, row-major (CountU rows)", sample_grid(4, 4))
        add(obj, "Integer", "CountU", "Surface", "Number of rows (poles in u)", 4)
        add(obj, "FloatList", "Weights", "Surface", "Weights, row-major like Poles; empty = polynomial")

    def build(self, obj):
        W = weights_or_none(obj.Weights)
        return cagd.BezierSurface(grid(obj.Poles, obj.CountU),
                                  None if W is None else grid(W, obj.CountU, "Weights"))


class BSplineSurface(Feature):
    """B-spline / NURBS surface from a pole grid, or interpolating the grid
    (``Interpolate``: Piegl & Tiller 9.2.5 through cagd.interpolate_surface)."""

    TYPE = "Cagd::BSplineSurface"
    DEFAULT_LABEL = "BSplineSurface"

    def setup(self, obj) -> None:
        add(obj, "VectorList", "Poles", "Surface", "Control points (or points to interpolate), row-major",
            sample_grid(5, 5))
        add(obj, "Integer", "CountU", "Surface", "Number of rows (poles in u)", 5)
        add(obj, "Integer", "DegreeU", "Surface", "Degree in u", 3)
        add(obj, "Integer", "DegreeV", "Surface", "Degree in v", 3)
        add(obj, "FloatList", "KnotsU", "Surface", "Full knot vector in u; empty = clamped uniform")
        add(obj, "FloatList", "KnotsV", "Surface", "Full knot vector in v; empty = clamped uniform")
        add(obj, "FloatList", "Weights", "Surface", "Weights, row-major like Poles; empty = polynomial")
        add(obj, "Bool", "PeriodicU", "Surface", "Periodic in u (KnotsU: one period)", False)
        add(obj, "Bool", "PeriodicV", "Surface", "Periodic in v (KnotsV: one period)", False)
        add(obj, "Bool", "Interpolate", "Surface", "Poles are points the surface passes through", False)

    def build(self, obj):
        P = grid(obj.Poles, obj.CountU)
        if obj.Interpolate:
            return cagd.interpolate_surface(P, obj.DegreeU, obj.DegreeV)
        W = weights_or_none(obj.Weights)
        ku = np.array(obj.KnotsU) if len(obj.KnotsU) else None
        kv = np.array(obj.KnotsV) if len(obj.KnotsV) else None
        if ku is None and obj.PeriodicU:
            ku = np.linspace(0.0, 1.0, P.shape[0] + 1)
        if kv is None and obj.PeriodicV:
            kv = np.linspace(0.0, 1.0, P.shape[1] + 1)
        return cagd.BSplineSurface(P, obj.DegreeU, obj.DegreeV, ku, kv,
                                   None if W is None else grid(W, obj.CountU, "Weights"),
                                   obj.PeriodicU, obj.PeriodicV)


class CoonsPatch(Feature):
    """Bilinearly blended Coons patch from four linked edges (Farin ch. 22.2); it
    follows the edges when their objects change or move."""

    TYPE = "Cagd::CoonsPatch"
    DEFAULT_LABEL = "CoonsPatch"
    LINKS = ("Edges",)
    POINTS = "Edges"

    def setup(self, obj) -> None:
        add(obj, "LinkSubList", "Edges", "Surface", "Four edges forming a closed loop, any order and direction")
        add(obj, "Precision", "Tolerance", "Surface",
            "Relative corner tolerance (> 0): loop gaps up to Tolerance x the loop's size, corner "
            "mismatches up to Tolerance x max(1, |coordinates|) (cagd.CoonsPatch.from_loop)", 1e-7)

    def build(self, obj):
        return coons_from_edges(linked_edges(obj.Edges, "Edges"), float(obj.Tolerance))


def coons_from_edges(edges, tol: float = 1e-7):
    """The Coons patch of four (label, edge) pairs (cagd.CoonsPatch.from_loop orders and
    orients the loop); raises CagdError naming Edges or Tolerance (a loop that does not
    close, a count other than four). The command calls it before creating an object."""
    if not tol > 0.0:                          # also NaN
        raise cagd.CagdError(f"Tolerance: must be > 0, got {tol:g}")
    if len(edges) != 4:
        raise cagd.CagdError(f"Edges: a Coons patch needs exactly 4 edges, got {len(edges)}")
    curves = [conversion.edge_to_curve(e) for _, e in edges]
    try:                                       # order and orient the loop: the engine's from_loop
        return cagd.CoonsPatch.from_loop(curves, rel_tol=tol)
    except cagd.CagdError as exc:
        message = str(exc)
        message = message[len("curves: "):] if message.startswith("curves: ") else message
        labels = ", ".join(label for label, _ in edges)
        raise cagd.CagdError(f"Edges: {message} (the loop starts with {edges[0][0]} as curve 0; "
                             f"edges: {labels})") from None


def triangle_sample(n: int = 3, size: float = 40.0) -> List[App.Vector]:
    """Control points of a domed degree-n triangle in index_triples order."""
    pts = []
    for i in range(n, -1, -1):
        for j in range(n - i, -1, -1):
            k = n - i - j
            x, y = size * (i + 0.5 * j) / n, size * 0.866 * j / n
            pts.append(V(x, y, 12.0 * (1.0 if min(i, j, k) > 0 else 0.0)))
    return pts


class BezierTriangle(Feature):
    """Degree-n Bezier triangle (seed 003, 3.1); the shape is its collapsed-edge
    B-spline form (one degenerate edge)."""

    TYPE = "Cagd::BezierTriangle"
    DEFAULT_LABEL = "BezierTriangle"

    def setup(self, obj) -> None:
        add(obj, "VectorList", "Poles", "Surface",
            "(n+1)(n+2)/2 control points P_ijk, i descending then j descending", triangle_sample())
        add(obj, "FloatList", "Weights", "Surface", "One positive weight per pole; empty = polynomial")

    def build(self, obj):
        return self.triangle(obj)

    @staticmethod
    def triangle(obj) -> "cagd.BezierTriangle":
        return cagd.BezierTriangle(conversion.array(obj.Poles), weights_or_none(obj.Weights))

    def control_net(self, obj):
        """The triangular net: rows of constant i, j and k."""
        tri = self.triangle(obj)
        n = tri.degree
        index = {t: k for k, t in enumerate(cagd.triangles.basis.index_triples(n))}
        P = conversion.vectors(tri.control_points)
        place = obj.Placement
        lines = []
        for fixed in range(3):
            for value in range(n):
                row = [t for t in index if t[fixed] == value]
                lines.append([place.multVec(P[index[t]]) for t in sorted(row)])
        return lines


NURBS_DOC = ("The face holds the engine's exact NURBS form (the engine's parametrisation) instead of "
             "FreeCAD's analytic surface (the same surface, by angle), which Part Offset / Thickness need")


class Revolution(Feature):
    """Surface of revolution of a linked profile edge about an axis (Piegl & Tiller A8.1);
    the face is Part.SurfaceOfRevolution of the profile's exact B-spline unless Nurbs."""

    TYPE = "Cagd::Revolution"
    DEFAULT_LABEL = "Revolution"
    LINKS = ("Profile",)
    POINTS = "Profile"

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Profile", "Revolution", "The profile edge")
        add(obj, "Vector", "AxisPoint", "Revolution", "A point on the axis", V(0, 0, 0))
        add(obj, "Vector", "AxisDirection", "Revolution", "Axis direction", V(0, 0, 1))
        add(obj, "Angle", "Angle", "Revolution", "Sweep angle, (0, 360] degrees", 360.0)
        add(obj, "Angle", "StartAngle", "Revolution", "Start angle in degrees", 0.0)
        add(obj, "Bool", "Nurbs", "Revolution", NURBS_DOC, False)

    def build(self, obj):
        profile = conversion.edge_to_curve(linked_edge(obj.Profile, "Profile"))
        return cagd.revolve(profile, vector(obj.AxisPoint), vector(obj.AxisDirection),
                            math.radians(float(obj.Angle)), math.radians(float(obj.StartAngle)))


PRIMITIVE_KINDS = ("Sphere", "Torus", "Cylinder", "Cone")


class Primitive(Feature):
    """Sphere, torus, cylinder or cone of the engine (cagd.sphere, torus, cylinder,
    cone: exact NURBS surfaces of revolution about the local z axis, placed by the
    Placement); the face is Part.Sphere / Toroid / Cylinder / Cone unless Nurbs."""

    TYPE = "Cagd::Primitive"
    DEFAULT_LABEL = "Primitive"
    POINTS = "Radius"

    def setup(self, obj) -> None:
        add_enum(obj, "Kind", "Primitive", "Sphere, Torus, Cylinder or Cone", PRIMITIVE_KINDS, "Sphere")
        add(obj, "Length", "Radius", "Primitive",
            "Radius (sphere, cylinder; base radius of the cone; major radius of the torus)", 10.0)
        add(obj, "Length", "MinorRadius", "Primitive", "Tube radius of the torus", 3.0)
        add(obj, "Length", "Height", "Primitive", "Height of the cylinder or cone (apex up)", 20.0)
        add(obj, "Bool", "Nurbs", "Primitive", NURBS_DOC, False)

    def build(self, obj):
        kind = str(obj.Kind)
        used = ("Radius",) + {"Sphere": (), "Torus": ("MinorRadius",)}.get(kind, ("Height",))
        for name in used:                      # named by property (the engine says radius, R, r, height)
            if not float(getattr(obj, name)) > 0.0:
                raise cagd.CagdError(f"{name}: must be positive, got {float(getattr(obj, name)):g}")
        r = float(obj.Radius)
        if kind == "Sphere":
            return cagd.sphere(r)
        if kind == "Torus":
            return cagd.torus(r, float(obj.MinorRadius))
        return (cagd.cylinder if kind == "Cylinder" else cagd.cone)(r, float(obj.Height))


# --- creation helpers -----------------------------------------------------------------------
def make_bezier_surface(poles=None, count_u=None, weights=None, doc=None):
    return _make(BezierSurface, doc, Poles=poles, CountU=count_u, Weights=weights)


def make_bspline_surface(poles=None, count_u=None, doc=None, **values):
    return _make(BSplineSurface, doc, Poles=poles, CountU=count_u, **values)


def make_coons(edges, doc=None):
    """``edges``: a LinkSubList value, e.g. [(obj, 'Edge1'), (obj2, 'Edge1'), ...]."""
    return _make(CoonsPatch, doc, Edges=edges)


def make_bezier_triangle(poles=None, weights=None, doc=None):
    return _make(BezierTriangle, doc, Poles=poles, Weights=weights)


def make_revolution(profile, doc=None, **values):
    """``profile``: (object, 'EdgeN')."""
    return _make(Revolution, doc, Profile=profile, **values)


def make_primitive(kind: str = "Sphere", doc=None, **values):
    """``kind``: Sphere, Torus, Cylinder or Cone; ``values``: Radius, MinorRadius, Height, Nurbs."""
    return _make(Primitive, doc, Kind=kind, **values)


def _make(cls, doc, **values):
    def fix(key, v):
        if key == "Poles" and isinstance(v, np.ndarray):
            return conversion.vectors(v.reshape(-1, 3))
        if key == "Weights" and isinstance(v, np.ndarray):
            return [float(w) for w in v.ravel()]
        return v
    return make(cls, doc=doc, **{k: fix(k, v) for k, v in values.items() if v is not None})
