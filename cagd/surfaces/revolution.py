"""Exact surfaces of revolution as NURBS (seed 003, 2.4 "旋转曲面": rational patches
represent surfaces of revolution exactly, the profile's control points swept along
rational quadratic circles; Piegl & Tiller, The NURBS Book, 7.5 and A8.1).

Convention: u is the profile's parameter (its own domain, unchanged), v in [0, 1]
sweeps the angle from ``start_angle`` to ``start_angle + angle``, counter-clockwise
about ``axis_direction`` (right-hand rule). S(u, 0) is the profile rotated by
``start_angle``. The v parametrisation is rational (not proportional to the angle):
the angle at v is :func:`arc_angle`.

The surfaces come back as :class:`RevolvedSurface`: a plain NURBS surface that also
remembers its construction (a :class:`Revolution` record and, for :func:`sphere`,
:func:`torus`, :func:`cylinder`, :func:`cone`, a :class:`Primitive` record), so that
the OCCT bridge and the FreeCAD workbench can hand over the analytic surface (the
same point set, parametrised by the angle) that OCCT's offsets accept.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from .bspline import BSplineSurface

_TWO_PI = 2.0 * np.pi
_ANGLE_TOL = 1e-14
_OCCT_PERIODIC_TOL = 1e-9       # OCCT's Precision::PConfusion(), as ElCLib::AdjustPeriodic uses it
SIMILARITY_TOL = 1e-12
"""Relative: a 3 x 3 matrix A with |A^T A - s^2 I| <= SIMILARITY_TOL s^2 counts as a
rigid motion times the uniform scaling s; the records survive only such maps."""


def arc_parameters(start: float, angle: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The rational quadratic circle through ``angle`` from ``start`` (Piegl & Tiller
    A7.1): (cos-factors, sin-factors, weights, knots) of its 2 n + 1 control points,
    n = ceil(angle / 90 degrees) arcs of equal sweep d. The control point k of the
    unit circle is (c_k, s_k); the even ones lie on the circle at start + j d, the odd
    ones are the tangent intersections (cos(m) , sin(m)) / cos(d/2) at the arc
    midpoints m with weight cos(d/2). Knots 0, 0, 0, 1/n, 1/n, ..., 1, 1, 1."""
    n = _arc_count(angle)
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


def _arc_count(angle: float) -> int:
    return max(int(np.ceil(angle / (np.pi / 2) - _ANGLE_TOL)), 1)


def arc_angle(t: ArrayLike, start: float, angle: float) -> np.ndarray:
    """The angle of the point at t in [0, 1] of the circle of :func:`arc_parameters`.
    On arc j (t in [j / n, (j + 1) / n], local s = n t - j in [0, 1]) the rational
    quadratic with end weights 1 and middle weight cos(d/2) (Piegl & Tiller 7.3) is the
    stereographic parametrisation: tan((theta - m_j) / 2) = (2 s - 1) tan(d / 4),
    m_j = start + (j + 1/2) d the arc's midpoint (checked against the NURBS circle in
    tests/surfaces/test_revolution.py)."""
    t = np.asarray(t, dtype=float)
    n = _arc_count(angle)
    d = angle / n
    j = np.clip(np.floor(t * n), 0, n - 1)
    return start + d * (j + 0.5) + 2.0 * np.arctan((2.0 * (t * n - j) - 1.0) * np.tan(d / 4))


def arc_parameter(theta: ArrayLike, start: float, angle: float) -> np.ndarray:
    """The inverse of :func:`arc_angle` on [start, start + angle]."""
    theta = np.asarray(theta, dtype=float)
    n = _arc_count(angle)
    d = angle / n
    j = np.clip(np.floor((theta - start) / d), 0, n - 1)
    s = (np.tan((theta - start - d * (j + 0.5)) / 2.0) / np.tan(d / 4) + 1.0) / 2.0
    return (j + s) / n


def _frozen_vector(x: ArrayLike) -> np.ndarray:
    a = np.array(x, dtype=float)
    a.setflags(write=False)
    return a


def _unit(x: ArrayLike) -> np.ndarray:
    return _frozen_vector(np.asarray(x, dtype=float) / np.linalg.norm(x))


def _similarity(A: np.ndarray) -> Optional[Tuple[float, int]]:
    """(s, sign of det A) when the 3 x 3 matrix A is s times an orthogonal matrix
    (within :data:`SIMILARITY_TOL`), else None."""
    if A.shape != (3, 3):
        return None
    G = A.T @ A
    s2 = float(np.trace(G)) / 3.0
    if not s2 > 0.0 or np.abs(G - s2 * np.eye(3)).max() > SIMILARITY_TOL * s2:
        return None
    return float(np.sqrt(s2)), 1 if np.linalg.det(A) > 0 else -1


@dataclass(frozen=True, eq=False)
class Revolution:
    """How a :class:`RevolvedSurface` was made: S(u, v) is ``profile(u)`` turned about
    the axis through ``axis_point`` along the unit ``axis_direction`` by the angle
    theta(v) = :func:`arc_angle` (v, ``start_angle``, ``angle``), counter-clockwise
    about ``axis_direction`` (after a reflection the direction is the one about which
    v still turns counter-clockwise). ``profile`` is the clamped NURBS form of the
    curve given to :func:`revolve` (the same curve and parameter)."""
    profile: BSplineCurve
    axis_point: np.ndarray
    axis_direction: np.ndarray
    angle: float
    start_angle: float

    @property
    def full_turn(self) -> bool:
        return self.angle == _TWO_PI

    def angle_at(self, v: ArrayLike) -> np.ndarray:
        """theta(v): the angle about the axis of the isocurve v (rational, not linear)."""
        return arc_angle(v, self.start_angle, self.angle)

    def parameter_at(self, theta: ArrayLike) -> np.ndarray:
        """v(theta) on [start_angle, start_angle + angle] (the inverse of :meth:`angle_at`)."""
        return arc_parameter(theta, self.start_angle, self.angle)

    def _moved(self, A: np.ndarray, b: np.ndarray, sign: int) -> "Revolution":
        return Revolution(self.profile._affine(A, b), _frozen_vector(A @ self.axis_point + b),
                          _unit(sign * (A @ self.axis_direction)), self.angle, self.start_angle)


@dataclass(frozen=True, eq=False)
class Primitive:
    """What a primitive surface is, in the frame (``center``; ``x_direction``,
    ``axis`` x ``x_direction``, ``axis``), all unit and orthogonal:

    - sphere: |p - center| = ``radius``; u = 0 at center + radius axis (north pole);
    - torus: major radius ``radius`` about ``axis``, tube radius ``minor_radius``;
    - cylinder: radius ``radius``, from the base circle about ``center`` up to
      ``height`` along ``axis`` (u = 0 at the top rim);
    - cone: base circle of ``radius`` about ``center``, apex at center + height axis
      (u = 0 at the apex).

    v = 0 lies on the half-plane of ``x_direction``; v turns about ``axis``
    counter-clockwise when ``turn`` = +1 (then S_u x S_v points outwards), clockwise
    when -1 (after a reflection; S_u x S_v points inwards).
    """
    kind: str
    center: np.ndarray
    axis: np.ndarray
    x_direction: np.ndarray
    turn: int
    radius: float
    minor_radius: Optional[float] = None
    height: Optional[float] = None

    @property
    def analytic_bounds(self) -> Tuple[float, float, float, float]:
        """(U0, U1, V0, V1) of the analytic parametrisation (:meth:`analytic_parameters`)."""
        if self.kind == "sphere":
            V = (-np.pi / 2, np.pi / 2)
        elif self.kind == "torus":
            V = (0.0, _TWO_PI)
        else:
            V = (0.0, self._height if self.kind == "cylinder" else self._slant)
        return (0.0, _TWO_PI) + V

    @property
    def _height(self) -> float:
        """``height`` of a cylinder or cone (the kinds that have one)."""
        assert self.height is not None, f"a {self.kind} primitive has no height"
        return self.height

    @property
    def _slant(self) -> float:
        return float(np.hypot(self.radius, self._height)) if self.kind == "cone" else 0.0

    @property
    def y_direction(self) -> np.ndarray:
        """axis x x_direction: the frame's third direction (right-handed)."""
        return _frozen_vector(np.cross(self.axis, self.x_direction))

    @property
    def semi_angle(self) -> Optional[float]:
        """The cone's signed semi-angle as OCCT's gp_Cone (and Part.Cone) take it:
        -atan(radius / height), negative as the radius shrinks along ``axis``."""
        return -float(np.arctan2(self.radius, self._height)) if self.kind == "cone" else None

    def analytic_parameters(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
        """(U, V) of the point S(u, v) in the angle parametrisation of OCCT's
        Geom_SphericalSurface / ToroidalSurface / CylindricalSurface / ConicalSurface
        (and FreeCAD's Part.Sphere, Toroid, Cylinder, Cone) in the right-handed frame
        above: U the angle about ``axis`` from ``x_direction``; V the latitude (sphere),
        the tube angle from the outer equator towards ``axis`` (torus), the height
        (cylinder), the slant distance from the base rim (cone). The engine's v gives
        theta(v) = :func:`arc_angle` (v, 0, 2 pi), U = theta or 2 pi - theta (``turn``);
        its u gives the profile's own angle t(u) (the half circle and the tube circle
        are rational arcs too) or the linear height."""
        u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
        theta = arc_angle(v, 0.0, _TWO_PI)
        U = theta if self.turn > 0 else _TWO_PI - theta
        if self.kind == "sphere":
            V = -arc_angle(u, -np.pi / 2, np.pi)
        elif self.kind == "torus":
            V = _TWO_PI - arc_angle(u, 0.0, _TWO_PI)
        else:
            V = (self._height if self.kind == "cylinder" else self._slant) * (1.0 - u)
        return U, V

    def _moved(self, A: np.ndarray, b: np.ndarray, scale: float, sign: int) -> "Primitive":
        axis = _unit(A @ self.axis)
        x = A @ self.x_direction
        x = _unit(x - (x @ axis) * axis)
        scaled = lambda r: None if r is None else scale * r  # noqa: E731
        return Primitive(self.kind, _frozen_vector(A @ self.center + b), axis, x, sign * self.turn,
                         scale * self.radius, scaled(self.minor_radius), scaled(self.height))


class RevolvedSurface(BSplineSurface):
    """The NURBS surface of revolution made by :func:`revolve` (and :func:`sphere`,
    :func:`torus`, :func:`cylinder`, :func:`cone`): a plain :class:`BSplineSurface`
    (evaluation, poles, knots, weights are those of the NURBS form) that also carries
    ``revolution`` (a :class:`Revolution`) and ``primitive`` (a :class:`Primitive`, or
    None for a general revolution). A similarity (rigid motion, uniform scaling,
    reflections included: :data:`SIMILARITY_TOL`) moves the records with the poles;
    any other map and every operation that makes a new surface (knot insertion,
    reversal, segments, elevation, ...) gives a plain BSplineSurface."""

    def __init__(self, control_points: ArrayLike, degree_u: int, degree_v: int, knots_u: Optional[ArrayLike],
                 knots_v: Optional[ArrayLike], weights: Optional[ArrayLike], *, revolution: Revolution,
                 primitive: Optional[Primitive] = None):
        if not isinstance(revolution, Revolution):
            raise CagdError(f"revolution: expected a Revolution record, got {type(revolution).__name__}")
        if primitive is not None and not isinstance(primitive, Primitive):
            raise CagdError(f"primitive: expected a Primitive record or None, got {type(primitive).__name__}")
        self.revolution, self.primitive = revolution, primitive      # before the base freezes the object
        super().__init__(control_points, degree_u, degree_v, knots_u, knots_v, weights)

    def __repr__(self) -> str:
        kind = self.primitive.kind if self.primitive is not None else "revolution"
        return super().__repr__()[:-1] + f" ({kind})>"

    @classmethod
    def _of(cls, s: BSplineSurface, revolution: Revolution, primitive: Optional[Primitive]) -> "RevolvedSurface":
        return cls(s.control_points, s.degree_u, s.degree_v, s.knots_u, s.knots_v, s.weights,
                   revolution=revolution, primitive=primitive)

    def _affine(self, A: np.ndarray, b: np.ndarray) -> BSplineSurface:
        plain = super()._affine(A, b)
        similar = _similarity(A)
        if similar is None:
            return plain
        scale, sign = similar
        primitive = None if self.primitive is None else self.primitive._moved(A, b, scale, sign)
        return RevolvedSurface._of(plain, self.revolution._moved(A, b, sign), primitive)

    @classmethod
    def from_occ_form(cls, *args: Any, **kwargs: Any) -> BSplineSurface:
        """A plain BSplineSurface (OCCT's data carries no construction record)."""
        return BSplineSurface.from_occ_form(*args, **kwargs)

    def analytic_parameters(self, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
        """(U, V) of S(u, v) in the analytic surface's angle parametrisation: the
        primitive's (:meth:`Primitive.analytic_parameters`), else that of a surface of
        revolution of the profile (OCCT's Geom_SurfaceOfRevolution, FreeCAD's
        Part.SurfaceOfRevolution): U = theta(v) - 2 pi k, V = u, k the whole turns
        in ``start_angle`` (U starts in [0, 2 pi) as in OCCT's periodic ranges)."""
        if self.primitive is not None:
            return self.primitive.analytic_parameters(u, v)
        U, V = np.broadcast_arrays(self.revolution.angle_at(v) - self._whole_turns, np.asarray(u, dtype=float))
        return U.copy(), V.copy()

    @property
    def _whole_turns(self) -> float:
        """2 pi k for the whole turns k in ``start_angle``, as OCCT takes a periodic
        range to start in [0, 2 pi) (ElCLib::AdjustPeriodic: within its
        Precision::PConfusion() below 2 pi counts as 0)."""
        start = self.revolution.start_angle
        k = np.floor(start / _TWO_PI)
        if _TWO_PI - (start - _TWO_PI * k) < _OCCT_PERIODIC_TOL:
            k += 1
        return _TWO_PI * k

    @property
    def analytic_bounds(self) -> Tuple[float, float, float, float]:
        """(U0, U1, V0, V1): the range of :meth:`analytic_parameters` over the domain."""
        if self.primitive is not None:
            return self.primitive.analytic_bounds
        r = self.revolution
        (u0, u1), _ = self.domain
        U0 = r.start_angle - self._whole_turns
        return U0, U0 + r.angle, u0, u1


def _axis(axis_point: ArrayLike, axis_direction: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
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


def _angle(angle: float, name: str = "angle") -> float:
    angle = _checks.scalar(angle, name)
    if not 0.0 < angle <= _TWO_PI * (1.0 + _ANGLE_TOL):
        raise CagdError(f"{name}: must lie in (0, 2 pi], got {angle}")
    return min(angle, _TWO_PI)


def revolve(profile: Curve, axis_point: ArrayLike = (0.0, 0.0, 0.0), axis_direction: ArrayLike = (0.0, 0.0, 1.0),
            angle: float = _TWO_PI, start_angle: float = 0.0) -> RevolvedSurface:
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
    The result is a :class:`RevolvedSurface` carrying its :class:`Revolution` record.

    Raises:
        CagdError: ``profile`` not a 3-D engine curve, a zero-length ``axis_direction``,
            ``angle`` not in (0, 2 pi], non-finite values.
    """
    if not isinstance(profile, Curve):
        raise CagdError(f"profile: expected a cagd curve, got {type(profile).__name__}")
    if profile.dim != 3:
        raise CagdError(f"profile: must be a 3-D curve, got {profile.dim}-D")
    a, d = _axis(axis_point, axis_direction)
    return _revolved(profile.to_nurbs().clamped(), a, d, _angle(angle), _checks.scalar(start_angle, "start_angle"))


def _revolved(C: BSplineCurve, a: np.ndarray, d: np.ndarray, angle: float, start: float,
              primitive: Optional[Primitive] = None) -> RevolvedSurface:
    """The net of :func:`revolve` for the clamped NURBS profile C, with its records."""
    c, s, w, knots_v = arc_parameters(start, angle)
    net = turned_net(C.control_points, a, d, c, s)
    wp = np.ones(len(net)) if C.weights is None else C.weights
    record = Revolution(C, _frozen_vector(a), _frozen_vector(d), angle, start)
    return RevolvedSurface(net, C.degree, 2, C.knots, knots_v, wp[:, None] * w[None, :], revolution=record,
                           primitive=primitive)


def turned_net(P: np.ndarray, a: np.ndarray, d: np.ndarray, c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The control net P_ik = O_i + c_k X_i + s_k Y_i of the points P_i (n, 3) turned about
    the axis through a along the unit d (O_i the foot of P_i on the axis, X_i = P_i - O_i,
    Y_i = d x X_i) by the rational circle whose control points in the frame (X, Y) are
    (c_k, s_k): with that circle's weights w_k (times the profile's), every isocurve is the
    curve of P turned by the circle's angle (Piegl & Tiller A8.1)."""
    O = a + ((P - a) @ d)[:, None] * d
    X = P - O
    Y = np.cross(d, X)
    return O[:, None, :] + c[None, :, None] * X[:, None, :] + s[None, :, None] * Y[:, None, :]


def _positive(value: float, name: str) -> float:
    x = _checks.scalar(value, name)
    if not x > 0.0:
        raise CagdError(f"{name}: must be positive, got {x}")
    return x


def _center(center: ArrayLike) -> np.ndarray:
    c = _checks.finite_array(center, "center", ndim=1)
    if c.shape != (3,):
        raise CagdError(f"center: expected 3 coordinates, got {c.shape[0]}")
    return c


def _circle_in_xz(center: np.ndarray, radius: float, start: float, angle: float) -> BSplineCurve:
    """The arc center + radius (cos t e_x - sin t e_z), t from start through angle."""
    c, s, w, knots = arc_parameters(start, angle)
    P = center + radius * np.stack([c, np.zeros_like(c), -s], axis=1)
    return BSplineCurve(P, 2, knots, w)


def _primitive(kind: str, profile: BSplineCurve, c: np.ndarray, radius: float, minor_radius: Optional[float] = None,
               height: Optional[float] = None) -> RevolvedSurface:
    """The full turn of ``profile`` about the z-axis through c, with its primitive record."""
    e = np.eye(3)
    record = Primitive(kind, _frozen_vector(c), _frozen_vector(e[2]), _frozen_vector(e[0]), 1, radius,
                       minor_radius, height)
    return _revolved(profile.clamped(), c, e[2], _TWO_PI, 0.0, record)


def sphere(radius: float = 1.0, center: ArrayLike = (0.0, 0.0, 0.0)) -> RevolvedSurface:
    """Sphere |p - center| = radius: the half circle from the north pole (u = 0) to the
    south pole (u = 1) in the xz-plane revolved about the z-axis through ``center``;
    biquadratic NURBS, 5 x 9 control points; S_u x S_v points outwards (undefined at the
    poles). Carries its :class:`Primitive` record (kind "sphere").

    Raises:
        CagdError: radius not positive, bad center.
    """
    r, c = _positive(radius, "radius"), _center(center)
    return _primitive("sphere", _circle_in_xz(c, r, -np.pi / 2, np.pi), c, r)


def torus(R: float, r: float, center: ArrayLike = (0.0, 0.0, 0.0)) -> RevolvedSurface:
    """Torus (sqrt(x^2 + y^2) - R)^2 + z^2 = r^2 about the z-axis through ``center``:
    the circle of radius r about (R, 0, 0) in the xz-plane, starting at the outer
    equator and going down, revolved; 9 x 9 control points, outward S_u x S_v. R <= r
    gives the self-intersecting horn/spindle tori. Primitive record "torus"
    (``radius`` R, ``minor_radius`` r).

    Raises:
        CagdError: R or r not positive, bad center.
    """
    R, r, c = _positive(R, "R"), _positive(r, "r"), _center(center)
    return _primitive("torus", _circle_in_xz(c + [R, 0.0, 0.0], r, 0.0, _TWO_PI), c, R, minor_radius=r)


def cylinder(radius: float, height: float, center: ArrayLike = (0.0, 0.0, 0.0)) -> RevolvedSurface:
    """Cylinder x^2 + y^2 = radius^2, 0 <= z <= height (relative to ``center``, the
    centre of the bottom circle): the segment from the top rim (u = 0) down to the
    bottom rim (u = 1) revolved about z; degree (1, 2), outward S_u x S_v. Primitive
    record "cylinder".

    Raises:
        CagdError: radius or height not positive, bad center.
    """
    r, h, c = _positive(radius, "radius"), _positive(height, "height"), _center(center)
    return _primitive("cylinder", BSplineCurve(c + [[r, 0.0, h], [r, 0.0, 0.0]], 1), c, r, height=h)


def cone(radius: float, height: float, center: ArrayLike = (0.0, 0.0, 0.0)) -> RevolvedSurface:
    """Cone sqrt(x^2 + y^2) = radius (1 - z / height), 0 <= z <= height (relative to
    ``center``, the centre of the base circle): the segment from the apex (u = 0) to
    the base rim (u = 1) revolved about z; degree (1, 2), outward S_u x S_v (undefined
    at the apex). Primitive record "cone".

    Raises:
        CagdError: radius or height not positive, bad center.
    """
    r, h, c = _positive(radius, "radius"), _positive(height, "height"), _center(center)
    return _primitive("cone", BSplineCurve(c + [[0.0, 0.0, h], [r, 0.0, 0.0]], 1), c, r, height=h)
