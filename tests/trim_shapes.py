"""Trimmed-face test shapes shared by tests/surfaces, tests/queries and tests/mesh: exact
NURBS circles in (u, v), lines and rectangles, a flat square patch and a bicubic bump; and
check_triangulation, the exact-cover check of a trimmed tessellation."""
import math

import numpy as np

from cagd import BSplineCurve, BSplineSurface
from cagd.surfaces.trimmed import ON

W = math.sqrt(0.5)
CIRCLE_KNOTS = [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1]
CIRCLE_WEIGHTS = [1, W, 1, W, 1, W, 1, W, 1]
UNIT = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)


def circle(center, r, clockwise=False):
    c = BSplineCurve(UNIT * r + np.asarray(center, float), 2, CIRCLE_KNOTS, CIRCLE_WEIGHTS)
    return c.reversed() if clockwise else c


def circle3d(center, r):
    """The 3-D circle (x, y) = centre + r (cos, sin), z = centre's z, in the same rational
    quadratic form (and parameter) as trim_shapes.circle."""
    P = np.concatenate([UNIT * r, np.zeros((len(UNIT), 1))], axis=1) + np.asarray(center, float)
    return BSplineCurve(P, 2, CIRCLE_KNOTS, CIRCLE_WEIGHTS)


def line(a, b):
    return BSplineCurve(np.array([a, b], float), 1)


def square_patch(side=2.0):
    """S(u, v) = (side u, side v, 0): |S_u x S_v| = side^2."""
    P = np.array([[[0, 0, 0], [0, side, 0]], [[side, 0, 0], [side, side, 0]]], float)
    return BSplineSurface(P, 1, 1)


def curved_patch():
    """A bicubic bump over [0, 1]^2 (control net of a graph z = f(x, y))."""
    x = np.linspace(0, 1, 4)
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = 0.3 * np.sin(3 * X) * np.cos(2 * Y)
    return BSplineSurface(np.stack([X, Y, Z], axis=-1), 3, 3)


def rectangle(u0, u1, v0, v1):
    return [line((u0, v0), (u1, v0)), line((u1, v0), (u1, v1)), line((u1, v1), (u0, v1)), line((u0, v1), (u0, v0))]


def periodic_tube(n=8, height=1.0):
    """A periodic cubic tube in u (control points on a regular n-gon, two rings in v at
    z = 0 and z = height): shifting u by one span (1/n) is a rotation, so areas and trims
    move with it."""
    a = 2 * np.pi * np.arange(n) / n
    ring = np.stack([np.cos(a), np.sin(a)], axis=1)
    P = np.stack([np.concatenate([ring, np.full((n, 1), z)], 1) for z in (0.0, height)], axis=1)
    return BSplineSurface(P, 3, 1, np.linspace(0, 1, n + 1), None, periodic_u=True)


# --- checks of a tessellation (tests/surfaces/test_tessellate.py, tests/mesh) ---------------------
def _polygon_area(uv, ring):
    P = uv[ring]
    return 0.5 * float(np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]))


def signed_areas(uv, T):
    p = uv[T]
    return 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))


def mesh_area(ts, t):
    V = ts.surface(t.uv[:, 0], t.uv[:, 1])
    P = V[t.triangles]
    return 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1).sum()


def _loops_of(t):
    """The trim chords as rings (following boundary pairs)."""
    succ = dict(map(tuple, t.boundary))
    rings, seen = [], set()
    for a in succ:
        if a in seen:
            continue
        ring, x = [], a
        while x not in seen:
            seen.add(x)
            ring.append(x)
            x = succ[x]
        rings.append(np.array(ring))
    return rings


def check_triangulation(ts, count):
    t = ts.tessellation(count)
    assert t.fallbacks == 0
    s = signed_areas(t.uv, t.triangles)
    assert s.min() > 0
    # the sums about the vertices' centre: a shoelace of coordinates far from the origin (a
    # face 0.3 wide at (43, 50), SampleCrankshaft4A.stp[48]) cancels to 4e-11 relative
    uv = t.uv - t.uv.mean(axis=0)
    region = sum(_polygon_area(uv, r) for r in _loops_of(t))
    assert abs(signed_areas(uv, t.triangles).sum() - region) <= 1e-12 * abs(region) + 1e-15
    E = np.sort(np.concatenate([t.triangles[:, [0, 1]], t.triangles[:, [1, 2]], t.triangles[:, [2, 0]]]), axis=1)
    edges, uses = np.unique(E, axis=0, return_counts=True)
    assert uses.max() <= 2
    once = {tuple(e) for e in edges[uses == 1]}
    assert once == {tuple(sorted(b)) for b in t.boundary}
    on = np.unique(t.boundary.ravel())
    (u0, u1), (v0, v1) = ts.surface.domain
    uv = t.uv[on]
    clipped = np.minimum.reduce([uv[:, 0] - u0, u1 - uv[:, 0], uv[:, 1] - v0, v1 - uv[:, 1]]) <= ts.tol
    assert np.all((ts.classify(uv[:, 0], uv[:, 1]) == ON) | clipped)   # (loops may leave the domain by tol)
    return t
