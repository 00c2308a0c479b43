"""Independent oracles for the cq_ext tests: OCCT evaluation of shapes (BRepAdaptor),
areas by Green's theorem with scipy's quad over the engine curve's spans, volumes
(the wall of a thickened surface of revolution by Pappus over its meridian strip).

Volumes: ``cagd.occ.volume`` (BRepGProp adaptive integration) is accurate on B-spline
faces (~1e-15 on the ellipsoid) but converges falsely on OCCT's extrusion faces
(Geom_SurfaceOfLinearExtrusion of a B-spline: ~2e-3 off, see
test_solids.test_occ_volume_of_an_extruded_spline); ``nurbs_volume`` converts every face
to its exact B-spline form first (BRepBuilderAPI_NurbsConvert), which makes the same
integration accurate.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad


def edge_points(edge, ts) -> np.ndarray:
    """Points of a CadQuery/build123d edge (or bare TopoDS_Edge) at raw OCCT parameters."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    a = BRepAdaptor_Curve(getattr(edge, "wrapped", edge))
    return np.array([[p.X(), p.Y(), p.Z()] for p in (a.Value(float(t)) for t in ts)])


def edge_derivatives(edge, t: float):
    """(point, first, second derivative) of an edge's curve at a raw parameter."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.gp import gp_Pnt, gp_Vec
    a = BRepAdaptor_Curve(getattr(edge, "wrapped", edge))
    p, d1, d2 = gp_Pnt(), gp_Vec(), gp_Vec()
    a.D2(float(t), p, d1, d2)
    return tuple(np.array([v.X(), v.Y(), v.Z()]) for v in (p, d1, d2))


def edge_range(edge):
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    a = BRepAdaptor_Curve(getattr(edge, "wrapped", edge))
    return a.FirstParameter(), a.LastParameter()


def face_points(face, us, vs) -> np.ndarray:
    """Points of a face's surface at raw (u, v) pairs."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    a = BRepAdaptor_Surface(getattr(face, "wrapped", face), False)
    out = []
    for u, v in zip(np.ravel(us), np.ravel(vs)):
        p = a.Value(float(u), float(v))
        out.append([p.X(), p.Y(), p.Z()])
    return np.array(out)


def distance_to_shape(shape, points) -> np.ndarray:
    """Distances of points to an OCCT shape (BRepExtrema, exact projection)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    s = getattr(shape, "wrapped", shape)
    out = []
    for p in np.asarray(points, dtype=float):
        v = BRepBuilderAPI_MakeVertex(gp_Pnt(*p.tolist())).Vertex()
        d = BRepExtrema_DistShapeShape(v, s)
        assert d.IsDone()
        out.append(d.Value())
    return np.array(out)


def nurbs_volume(shape) -> float:
    """cagd.occ.volume of the shape with every face converted to its exact B-spline form."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from cagd.occ import volume
    return volume(BRepBuilderAPI_NurbsConvert(getattr(shape, "wrapped", shape), True).Shape())


def _breaks(curve):
    a, b = curve.domain
    knots = np.unique(curve.to_nurbs().knots)
    return [a] + [k for k in knots if a < k < b] + [b]


def span_quad(f, curve) -> float:
    """int f(t) dt over the curve's domain, span by span (the integrand is smooth in each)."""
    br = _breaks(curve)
    return sum(quad(f, lo, hi, epsabs=0.0, epsrel=1e-13, limit=200)[0] for lo, hi in zip(br[:-1], br[1:]))


def green_area(curve) -> float:
    """1/2 int (x y' - y x') dt along the curve (Green's theorem): the signed area it
    encloses when closed; for an open curve add the closing segment's term
    1/2 (x_end y_start - x_start y_end)."""
    def f(t):
        tt = np.array([t])
        p, d = curve(tt)[0], curve.derivative(tt, 1)[0]
        return 0.5 * (p[0] * d[1] - p[1] * d[0])
    return span_quad(f, curve)


def size(points) -> float:
    P = np.asarray(points, dtype=float).reshape(-1, np.shape(points)[-1])
    return max(float(np.abs(P).max()), 1.0)


def revolution_wall_volume(profile, t: float, angle: float = 2 * np.pi) -> float:
    """Volume of {p + s n : p on the revolution of ``profile`` (a curve in the xz-plane,
    turned about the z-axis through ``angle``), 0 <= s <= t}, n the unit normal
    S_u x S_v (in the meridian plane: (-z', x') / |p'|): Pappus on the strip
    (u, s) -> q = p(u) + s n(u), angle * int int rho(q) |det dq/d(u, s)| ds du, with
    det = |p'| + s det(n', n) linear in s (no focal point within t), so the s-integral
    is closed form and the u-integral scipy's quad span by span."""
    def f(u):
        uu = np.array([u])
        d = profile.derivatives(uu, 2)
        (x, _, _), (dx, _, dz), (ddx, _, ddz) = d[0][0], d[1][0], d[2][0]
        L = math.hypot(dx, dz)
        nx, nz = -dz / L, dx / L
        dnx = -ddz / L - nx * (dx * ddx + dz * ddz) / L ** 2
        dnz = ddx / L - nz * (dx * ddx + dz * ddz) / L ** 2
        j1 = dnx * nz - dnz * nx
        return x * L * t + (x * j1 + nx * L) * t ** 2 / 2 + nx * j1 * t ** 3 / 3
    return abs(angle * span_quad(f, profile))
