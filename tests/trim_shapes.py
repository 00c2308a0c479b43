"""Trimmed-face test shapes shared by tests/surfaces and tests/queries: exact NURBS
circles in (u, v), lines and rectangles, a flat square patch and a bicubic bump."""
import math

import numpy as np

from cagd import BSplineCurve, BSplineSurface

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
