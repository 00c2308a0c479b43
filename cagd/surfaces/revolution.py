"""Exact surfaces of revolution as NURBS (seed 003, 2.4 "旋转曲面": rational patches
represent surfaces of revolution exactly, the profile's control points swept along
rational quadratic circles; Piegl & Tiller, The NURBS Book, 7.5 and A8.1).

Convention: u is the profile's parameter (its own domain, unchanged), v in [0, 1]
sweeps the angle from ``start_angle`` to ``start_angle + angle``, counter-clockwise
about ``axis_direction`` (right-hand rule). S(u, 0) is the profile rotated by
``start_angle``. The v parametrisation is rational (not proportional to the angle).
"""
from __future__ import annotations

from typing import Tuple

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from .bspline import BSplineSurface

_TWO_PI = 2.0 * np.pi
_ANGLE_TOL = 1e-14


def arc_parameters(start: float, angle: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The rational quadratic circle through ``angle`` from ``start`` (Piegl & Tiller
    A7.1): (cos-factors, sin-factors, weights, knots) of its 2 n + 1 control points,
    n = ceil(angle / 90 degrees) arcs of equal sweep d. The control point k of the
    unit circle is (c_k, s_k); the even ones lie on the circle at start + j d, the odd
    ones are the tangent intersections (cos(m) , sin(m)) / cos(d/2) at the arc
    midpoints m with weight cos(d/2). Knots 0, 0, 0, 1/n, 1/n, ..., 1, 1, 1."""
    n = int(np.ceil(angle / (np.pi / 2) - _ANGLE_TOL))
    n = max(n, 1)
    d = angle / n
    theta = start + d * np.arange(2 * n + 1) / 2.0
    factor = np.ones(2 * n + 1)
    factor[1::2] = 1.0 / np.cos(d / 2)
    w = np.ones(2 * n + 1)
    w[1::2] = np.cos(d / 2)
    c, s = factor * np.cos(theta), factor * np.sin(theta)
    if abs(angle - _TWO_PI) <= _ANGLE_TOL * _TWO_PI:     # closed: the seam is exact
        c[-1], s[-1] = c[0], s[0]
    knots = np.concatenate([[0.0, 0.0, 0.0], np.repeat(np.arange(1, n) / n, 2), [1.0, 1.0, 1.0]])
    return c, s, w, knots


def _axis(axis_point, axis_direction) -> Tuple[np.ndarray, np.ndarray]:
    a = _checks.finite_array(axis_point, "axis_point", ndim=1)
    d = _checks.finite_array(axis_direction, "axis_direction", ndim=1)
    if a.shape != (3,):
        raise CagdError(f"axis_point: expected 3 coordinates, got {a.shape[0]}")
    if d.shape != (3,):
        raise CagdError(f"axis_direction: expected 3 coordinates, got {d.shape[0]}")
    length = float(np.linalg.norm(d))
    if not length > 0.0:
        raise CagdError("axis_direction: zero-length axis direction")
    return a, d / length


def _angle(angle, name: str = "angle") -> float:
    angle = _checks.scalar(angle, name)
    if not 0.0 < angle <= _TWO_PI * (1.0 + _ANGLE_TOL):
        raise CagdError(f"{name}: must lie in (0, 2 pi], got {angle}")
    return min(angle, _TWO_PI)


def revolve(profile, axis_point=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0),
            angle: float = _TWO_PI, start_angle: float = 0.0) -> BSplineSurface:
    """The surface swept by the 3-D curve ``profile`` turning about the axis through
    ``axis_point`` along ``axis_direction`` (Piegl & Tiller A8.1; seed 003, 2.4).

    With the profile's NURBS form P_i, w_i (clamped), O_i the foot of P_i on the axis,
    X_i = P_i - O_i, Y_i = d x X_i and the unit arc (c_k, s_k, w'_k) of
    :func:`arc_parameters`: P_ik = O_i + c_k X_i + s_k Y_i, w_ik = w_i w'_k. Degree 2 in v
    (2 n + 1 columns, n <= 4 arcs of at most 90 degrees), the profile's degree and knots
    in u. Exact: every isocurve u = const is a rational quadratic circle. (The seed turns
    the profile about the y-axis with four quadratic arcs; any axis is accepted here.)
    Orientation: v turns counter-clockwise about ``axis_direction``, so the normal
    S_u x S_v points away from the axis when the profile runs against the axis
    direction (as in :func:`sphere`), towards it when the profile runs along it.

    Raises:
        CagdError: ``profile`` not a 3-D engine curve, a zero-length ``axis_direction``,
            ``angle`` not in (0, 2 pi], non-finite values.
    """
    if not isinstance(profile, Curve):
        raise CagdError(f"profile: expected a cagd curve, got {type(profile).__name__}")
    if profile.dim != 3:
        raise CagdError(f"profile: must be a 3-D curve, got {profile.dim}-D")
    a, d = _axis(axis_point, axis_direction)
    angle = _angle(angle)
    start = _checks.scalar(start_angle, "start_angle")
    C = profile.to_nurbs().clamped()
    P = C.control_points
    O = a + ((P - a) @ d)[:, None] * d
    X = P - O
    Y = np.cross(d, X)
    c, s, w, knots_v = arc_parameters(start, angle)
    net = O[:, None, :] + c[None, :, None] * X[:, None, :] + s[None, :, None] * Y[:, None, :]
    wp = np.ones(len(P)) if C.weights is None else C.weights
    return BSplineSurface(net, C.degree, 2, C.knots, knots_v, wp[:, None] * w[None, :])


def _positive(value, name: str) -> float:
    x = _checks.scalar(value, name)
    if not x > 0.0:
        raise CagdError(f"{name}: must be positive, got {x}")
    return x


def _center(center) -> np.ndarray:
    c = _checks.finite_array(center, "center", ndim=1)
    if c.shape != (3,):
        raise CagdError(f"center: expected 3 coordinates, got {c.shape[0]}")
    return c


def _circle_in_xz(center: np.ndarray, radius: float, start: float, angle: float) -> BSplineCurve:
    """The arc center + radius (cos t e_x - sin t e_z), t from start through angle."""
    c, s, w, knots = arc_parameters(start, angle)
    P = center + radius * np.stack([c, np.zeros_like(c), -s], axis=1)
    return BSplineCurve(P, 2, knots, w)


def sphere(radius: float = 1.0, center=(0.0, 0.0, 0.0)) -> BSplineSurface:
    """Sphere |p - center| = radius: the half circle from the north pole (u = 0) to the
    south pole (u = 1) in the xz-plane revolved about the z-axis through ``center``;
    biquadratic NURBS, 5 x 9 control points; S_u x S_v points outwards (undefined at the
    poles).

    Raises:
        CagdError: radius not positive, bad center.
    """
    r, c = _positive(radius, "radius"), _center(center)
    return revolve(_circle_in_xz(c, r, -np.pi / 2, np.pi), c)


def torus(R: float, r: float, center=(0.0, 0.0, 0.0)) -> BSplineSurface:
    """Torus (sqrt(x^2 + y^2) - R)^2 + z^2 = r^2 about the z-axis through ``center``:
    the circle of radius r about (R, 0, 0) in the xz-plane, starting at the outer
    equator and going down, revolved; 9 x 9 control points, outward S_u x S_v. R <= r
    gives the self-intersecting horn/spindle tori.

    Raises:
        CagdError: R or r not positive, bad center.
    """
    R, r, c = _positive(R, "R"), _positive(r, "r"), _center(center)
    return revolve(_circle_in_xz(c + [R, 0.0, 0.0], r, 0.0, _TWO_PI), c)


def cylinder(radius: float, height: float, center=(0.0, 0.0, 0.0)) -> BSplineSurface:
    """Cylinder x^2 + y^2 = radius^2, 0 <= z <= height (relative to ``center``, the
    centre of the bottom circle): the segment from the top rim (u = 0) down to the
    bottom rim (u = 1) revolved about z; degree (1, 2), outward S_u x S_v.

    Raises:
        CagdError: radius or height not positive, bad center.
    """
    r, h, c = _positive(radius, "radius"), _positive(height, "height"), _center(center)
    return revolve(BSplineCurve(c + [[r, 0.0, h], [r, 0.0, 0.0]], 1), c)


def cone(radius: float, height: float, center=(0.0, 0.0, 0.0)) -> BSplineSurface:
    """Cone sqrt(x^2 + y^2) = radius (1 - z / height), 0 <= z <= height (relative to
    ``center``, the centre of the base circle): the segment from the apex (u = 0) to
    the base rim (u = 1) revolved about z; degree (1, 2), outward S_u x S_v (undefined
    at the apex).

    Raises:
        CagdError: radius or height not positive, bad center.
    """
    r, h, c = _positive(radius, "radius"), _positive(height, "height"), _center(center)
    return revolve(BSplineCurve(c + [[0.0, 0.0, h], [r, 0.0, 0.0]], 1), c)
