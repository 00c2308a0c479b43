"""Shared table of valid model entries: (type, fields, the direct engine construction)."""
import math

import numpy as np

import cagd
from cagd.triangles.basis import index_triples

CUBIC = [[0.0, 0.0, 0.0], [10.0, 5.0, 2.0], [20.0, -3.0, 4.0], [30.0, 0.0, 1.0]]
CUBIC2 = [[0.0, 0.0, 10.0], [10.0, 4.0, 12.0], [20.0, -2.0, 15.0], [30.0, 1.0, 10.0]]
PROFILE = [[0.0, 0.0, 20.0], [8.0, 0.0, 16.0], [9.0, 0.0, 5.0], [0.0, 0.0, 0.0]]
NET = [[[10.0 * i, 10.0 * j, math.sin(i + 2 * j)] for j in range(4)] for i in range(5)]
W5x4 = [[1.0 + 0.1 * i + 0.05 * j for j in range(4)] for i in range(5)]
TRI = [[float(i), float(j), 0.3 * i * j + k] for i, j, k in index_triples(3)]
W = math.sqrt(0.5)
CIRCLE_UV = dict(degree=2, knots=[0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], weights=[1, W, 1, W, 1, W, 1, W, 1],
                 control_points=[[0.8, 0.5], [0.8, 0.8], [0.5, 0.8], [0.2, 0.8], [0.2, 0.5], [0.2, 0.2], [0.5, 0.2],
                                 [0.8, 0.2], [0.8, 0.5]])
SQUARE_UV = [[[0.05, 0.05], [0.95, 0.05]], [[0.95, 0.05], [0.95, 0.95]], [[0.95, 0.95], [0.05, 0.95]],
             [[0.05, 0.95], [0.05, 0.05]]]


def doc(*objects):
    return {"format": "cagd-model", "version": 1, "units": "mm", "objects": list(objects)}


def entry(name, type_, **fields):
    return {"name": name, "type": type_, **fields}


def sample(obj) -> np.ndarray:
    """Points and first derivatives on a fixed parameter set."""
    if isinstance(obj, cagd.Curve):
        t = np.linspace(*obj.domain, 23)
        return np.concatenate([obj(t), obj.derivative(t, 1)])
    (u0, u1), (v0, v1) = obj.domain
    if not obj.rectangular:
        g = np.linspace(0.0, 1.0, 7)
        u, v = np.meshgrid(g, g)
        keep = u + v <= 1.0
        return obj(u[keep], v[keep])
    u, v = np.meshgrid(np.linspace(u0, u1, 7), np.linspace(v0, v1, 6))
    return np.concatenate([obj(u, v), obj.derivative(u, v, 1, 0), obj.derivative(u, v, 0, 1)])


def same(a, b):
    sa, sb = sample(a), sample(b)
    assert sa.shape == sb.shape
    scale = max(1.0, float(np.abs(sb).max()))
    assert float(np.abs(sa - sb).max()) <= 1e-15 * scale


curve_a = cagd.BezierCurve(CUBIC)
curve_b = cagd.BezierCurve(CUBIC2)
REF_A = entry("A", "bezier_curve", control_points=CUBIC)
REF_B = entry("B", "bezier_curve", control_points=CUBIC2)

# (type, entry fields, direct engine construction)
CASES = [
    ("bezier_curve", dict(control_points=CUBIC), lambda: cagd.BezierCurve(CUBIC)),
    ("bezier_curve", dict(control_points=CUBIC, weights=[1, 2, 0.5, 1]),
     lambda: cagd.BezierCurve(CUBIC, [1, 2, 0.5, 1])),
    ("bezier_curve", dict(control_points=[[0, 0], [1, 2], [3, 1]]), lambda: cagd.BezierCurve([[0, 0], [1, 2], [3, 1]])),
    ("bspline_curve", dict(control_points=CUBIC, degree=2), lambda: cagd.BSplineCurve(CUBIC, 2)),
    ("bspline_curve", dict(control_points=CUBIC, degree=2, knots=[0, 0, 0, 0.3, 1, 1, 1], weights=[1, 3, 1, 2]),
     lambda: cagd.BSplineCurve(CUBIC, 2, [0, 0, 0, 0.3, 1, 1, 1], [1, 3, 1, 2])),
    ("bspline_curve", dict(control_points=CUBIC, degree=3, periodic=True, knots=[0, 1, 2, 4, 5]),
     lambda: cagd.BSplineCurve(CUBIC, 3, [0, 1, 2, 4, 5], periodic=True)),
    ("polynomial_curve", dict(coefficients=CUBIC, domain=[1, 3]), lambda: cagd.PolynomialCurve(CUBIC, (1, 3))),
    ("polynomial_curve", dict(coefficients=CUBIC), lambda: cagd.PolynomialCurve(CUBIC)),
    ("hermite_curve", dict(p0=[0, 0, 0], p1=[10, 0, 0], t0=[0, 10, 0], t1=[0, -10, 5]),
     lambda: cagd.HermiteCurve([0, 0, 0], [10, 0, 0], [0, 10, 0], [0, -10, 5])),
    ("cubic_spline", dict(points=CUBIC), lambda: cagd.natural_cubic_spline(CUBIC)),
    ("cubic_spline", dict(points=CUBIC, end_condition="clamped", parameters="centripetal",
                          tangents=[[1, 0, 0], [0, 1, 0]]),
     lambda: cagd.natural_cubic_spline(CUBIC, "clamped", "centripetal", [[1, 0, 0], [0, 1, 0]])),
    ("cubic_spline", dict(points=CUBIC, end_condition="virtual", virtual_points=[[-5, 0, 0], [40, 0, 0]]),
     lambda: cagd.natural_cubic_spline(CUBIC, "virtual", virtual_points=[[-5, 0, 0], [40, 0, 0]])),
    ("cubic_spline", dict(points=CUBIC, parameters=[0, 1, 3, 4]),
     lambda: cagd.natural_cubic_spline(CUBIC, parameters=[0, 1, 3, 4])),
    ("cubic_spline", dict(points=CUBIC + [CUBIC[0]], end_condition="periodic", parameters="uniform"),
     lambda: cagd.natural_cubic_spline(CUBIC + [CUBIC[0]], "periodic", "uniform")),
    ("interpolate", dict(points=CUBIC + CUBIC2), lambda: cagd.interpolate(CUBIC + CUBIC2)),
    ("interpolate", dict(points=CUBIC, degree=2, parameters="centripetal"),
     lambda: cagd.interpolate(CUBIC, 2, "centripetal")),
    ("interpolate", dict(points=CUBIC, degree=2, parameters=[0, 0.2, 0.7, 1], knots=[0, 0, 0, 0.5, 1, 1, 1]),
     lambda: cagd.interpolate(CUBIC, 2, [0, 0.2, 0.7, 1], [0, 0, 0, 0.5, 1, 1, 1])),
    ("join", dict(curve={"ref": "A"}), lambda: cagd.join(curve_a)),
    ("join", dict(curve={"type": "bezier_curve", "control_points": CUBIC}, continuity="G2", alpha=0.7, beta=2.0,
                  rest_points=[[50, 5, 0], [60, 0, 0]]),
     lambda: cagd.join(curve_a, [[50, 5, 0], [60, 0, 0]], "G2", 0.7, 2.0)),
    ("composite", dict(curves=[{"ref": "A"}, {"type": "bezier_curve", "control_points": [CUBIC[-1], [40, 0, 0]]}]),
     lambda: cagd.CompositeCurve([curve_a, cagd.BezierCurve([CUBIC[-1], [40, 0, 0]])])),
    ("bezier_surface", dict(control_points=NET), lambda: cagd.BezierSurface(NET)),
    ("bezier_surface", dict(control_points=NET, weights=W5x4), lambda: cagd.BezierSurface(NET, W5x4)),
    ("bspline_surface", dict(control_points=NET, degree_u=2, degree_v=3),
     lambda: cagd.BSplineSurface(NET, 2, 3)),
    ("bspline_surface", dict(control_points=NET, degree_u=2, degree_v=1, knots_u=[0, 1, 2, 3, 4, 5],
                             knots_v=[0, 0, 1, 2, 3, 3], weights=W5x4, periodic_u=True),
     lambda: cagd.BSplineSurface(NET, 2, 1, [0, 1, 2, 3, 4, 5], [0, 0, 1, 2, 3, 3], W5x4, periodic_u=True)),
    ("interpolate_surface", dict(points=NET), lambda: cagd.interpolate_surface(NET)),
    ("interpolate_surface", dict(points=NET, degree_u=2, degree_v=2, parameters="uniform"),
     lambda: cagd.interpolate_surface(NET, 2, 2, "uniform")),
    ("interpolate_surface", dict(points=NET, degree_u=1, degree_v=1,
                                 parameters=[[0, 0.1, 0.5, 0.6, 1], [0, 0.3, 0.4, 1]]),
     lambda: cagd.interpolate_surface(NET, 1, 1, ([0, 0.1, 0.5, 0.6, 1], [0, 0.3, 0.4, 1]))),
    ("revolve", dict(profile={"type": "bezier_curve", "control_points": PROFILE}),
     lambda: cagd.revolve(cagd.BezierCurve(PROFILE))),
    ("revolve", dict(profile={"ref": "A"}, axis_point=[1, 2, 3], axis_direction=[0, 1, 1], angle=1.5,
                     start_angle=0.25),
     lambda: cagd.revolve(curve_a, [1, 2, 3], [0, 1, 1], 1.5, 0.25)),
    ("sphere", dict(radius=12.5, center=[1, 2, 3]), lambda: cagd.sphere(12.5, [1, 2, 3])),
    ("torus", dict(R=20, r=4), lambda: cagd.torus(20, 4)),
    ("cylinder", dict(radius=5, height=30, center=[0, 0, -3]), lambda: cagd.cylinder(5, 30, [0, 0, -3])),
    ("cone", dict(radius=5, height=30), lambda: cagd.cone(5, 30)),
    ("ellipsoid", dict(a=30, b=20, c=15), lambda: cagd.ellipsoid(30, 20, 15)),
    ("coons", dict(c0={"ref": "A"}, c1={"ref": "B"},
                   d0={"type": "bezier_curve", "control_points": [CUBIC[0], CUBIC2[0]]},
                   d1={"type": "bezier_curve", "control_points": [CUBIC[-1], CUBIC2[-1]]}),
     lambda: cagd.CoonsPatch(curve_a, curve_b, cagd.BezierCurve([CUBIC[0], CUBIC2[0]]),
                             cagd.BezierCurve([CUBIC[-1], CUBIC2[-1]]))),
    ("ruled", dict(c0={"ref": "A"}, c1={"ref": "B"}), lambda: cagd.ruled(curve_a, curve_b)),
    ("loft", dict(sections=[{"ref": "A"}, {"ref": "B"}, {"type": "bspline_curve", "control_points": PROFILE,
                                                          "degree": 2}], degree_v=2),
     lambda: cagd.loft([curve_a, curve_b, cagd.BSplineCurve(PROFILE, 2)], 2)),
    ("loft", dict(sections=[{"ref": "A"}, {"ref": "B"}], degree_v=1, parameters=[0, 1]),
     lambda: cagd.loft([curve_a, curve_b], 1, [0, 1])),
    ("bezier_triangle", dict(control_points=TRI), lambda: cagd.BezierTriangle(TRI)),
    ("bezier_triangle", dict(control_points=TRI, weights=[1, 2, 1, 1, 3, 1, 1, 1, 0.5, 1]),
     lambda: cagd.BezierTriangle(TRI, [1, 2, 1, 1, 3, 1, 1, 1, 0.5, 1])),
    ("trimmed_surface", dict(surface={"type": "bspline_surface", "control_points": NET, "degree_u": 2, "degree_v": 3},
                             loops=[[{"type": "bspline_curve", **CIRCLE_UV}]]),
     lambda: cagd.TrimmedSurface(cagd.BSplineSurface(NET, 2, 3),
                                 [[cagd.BSplineCurve(CIRCLE_UV["control_points"], 2, CIRCLE_UV["knots"],
                                                     CIRCLE_UV["weights"])]])),
    ("trimmed_surface", dict(surface={"type": "sphere", "radius": 12.5},
                             loops=[[{"type": "bezier_curve", "control_points": ab} for ab in SQUARE_UV]], tol=1e-6),
     lambda: cagd.TrimmedSurface(cagd.sphere(12.5), [[cagd.BezierCurve(ab) for ab in SQUARE_UV]], tol=1e-6)),
]
