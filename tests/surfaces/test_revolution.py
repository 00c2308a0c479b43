"""Exact surfaces of revolution (seed 003, 2.4; Piegl & Tiller A8.1): points on the
implicit equations of sphere, torus, cylinder and cone, the profile reproduced, the
isocurves are circle arcs about the axis (checked with an independent Rodrigues
rotation), partial angles, arbitrary axes, radial sphere normals, errors; the
construction records (the rational circle's angle, the primitives' angle
parametrisations against their closed forms, records moved by similarities and
dropped by every other map or operation)."""
import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from cagd import BezierCurve, BSplineCurve, BSplineSurface, CagdError, RevolvedSurface
from cagd.surfaces.revolution import (SIMILARITY_TOL, arc_angle, arc_parameter, arc_parameters, cone, cylinder,
                                      revolve, sphere, torus)

from strategies import bspline_curves

SETTINGS = settings(max_examples=40, deadline=None)
U = np.linspace(0.0, 1.0, 101)
V = np.linspace(0.0, 1.0, 103)                     # 10403 samples per grid
RNG = np.random.default_rng(20240601)
RU, RV = RNG.random(2000), RNG.random(2000)

sizes = st.floats(0.05, 50.0)
centers = st.lists(st.floats(-20.0, 20.0), min_size=3, max_size=3).map(np.array)


def samples(surface):
    """Grid points and scattered points (both evaluation paths)."""
    return np.concatenate([surface.grid(U, V).reshape(-1, 3), surface(RU, RV)])


def rodrigues(p, a, d, theta):
    """p rotated by theta about the axis through a along the unit vector d."""
    x = p - a
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    return a + x * c + np.cross(d, x) * s + d * (x @ d)[..., None] * (1 - c)


def axial_frame(points, a, d):
    """(axial coordinate, distance from the axis) of points."""
    x = points - a
    h = x @ d
    return h, np.linalg.norm(x - h[..., None] * d, axis=-1)


# --- implicit equations -------------------------------------------------------------------------
@SETTINGS
@given(sizes, centers)
def test_sphere_on_implicit_equation(r, c):
    P = samples(sphere(r, c))
    size = r + np.abs(c).max()
    assert np.abs(np.linalg.norm(P - c, axis=1) - r).max() <= 1e-14 * size


@SETTINGS
@given(sizes, st.floats(0.05, 0.95), centers)
def test_torus_on_implicit_equation(R, ratio, c):
    r = ratio * R
    x, y, z = (samples(torus(R, r, c)) - c).T
    size = R + r + np.abs(c).max()
    # (sqrt(x^2 + y^2) - R)^2 + z^2 = r^2, compared as a distance
    assert np.abs(np.sqrt((np.hypot(x, y) - R) ** 2 + z ** 2) - r).max() <= 1e-14 * size
    assert np.abs((np.hypot(x, y) - R) ** 2 + z ** 2 - r * r).max() <= 1e-14 * size * size


@SETTINGS
@given(sizes, sizes, centers)
def test_cylinder_on_implicit_equation(r, h, c):
    x, y, z = (samples(cylinder(r, h, c)) - c).T
    size = r + h + np.abs(c).max()
    assert np.abs(np.hypot(x, y) - r).max() <= 1e-14 * size
    assert z.min() >= -1e-14 * size and z.max() <= h + 1e-14 * size


@SETTINGS
@given(sizes, sizes, centers)
def test_cone_on_implicit_equation(r, h, c):
    x, y, z = (samples(cone(r, h, c)) - c).T
    size = r + h + np.abs(c).max()
    # the distance from the line rho / r + z / h = 1 in the (rho, z) half plane
    dist = np.abs(np.hypot(x, y) * h + z * r - r * h) / math.hypot(r, h)
    assert dist.max() <= 1e-14 * size


def test_quadrics_cover_their_angle_and_height():
    """Full turns: the seam is closed exactly, the angle covers [0, 2 pi) without jumps,
    the sphere reaches both poles."""
    for s in (sphere(1.5), torus(2.0, 0.5), cylinder(1.0, 2.0), cone(1.0, 2.0)):
        assert np.array_equal(s(U, 0.0), s(U, 1.0))
        P = s(0.5, np.linspace(0, 1, 4001))
        theta = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
        assert np.all(np.diff(theta) > 0)
        assert theta[-1] - theta[0] == pytest.approx(2 * np.pi, abs=1e-13)
    S = sphere(1.5)
    assert np.abs(S(0.0, V) - [0, 0, 1.5]).max() <= 1e-15
    assert np.abs(S(1.0, V) - [0, 0, -1.5]).max() <= 1e-15


def test_sphere_net_is_piegl_tiller():
    """Biquadratic, 5 x 9 control points, weights the products of 1, sqrt(2)/2."""
    S = sphere(2.0)
    assert isinstance(S, BSplineSurface) and S.to_nurbs() is S
    assert (S.degree_u, S.degree_v) == (2, 2) and S.control_points.shape == (5, 9, 3)
    w = np.array([1, math.sqrt(0.5)] * 4 + [1])
    assert np.allclose(S.weights, np.outer([1, math.sqrt(0.5), 1, math.sqrt(0.5), 1], w), rtol=1e-15)
    assert np.array_equal(S.knots_v, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1])


# --- normals ---------------------------------------------------------------------------------
@SETTINGS
@given(sizes, centers)
def test_sphere_normals_are_radial_and_outward(r, c):
    S = sphere(r, c)
    u, v = 0.01 + 0.98 * RU[:500], RV[:500]
    n = S.normal(u, v)
    # the oracle (S - c) / r carries the rounding of S amplified by |c| / r
    assert np.abs(n - (S(u, v) - c) / r).max() <= 1e-13 * (10 + np.abs(c).max() / r)


def test_outward_normals_of_the_quadrics():
    u, v = 0.05 + 0.9 * RU[:300], RV[:300]
    t = torus(3.0, 1.0)
    p = t(u, v)
    rho = np.hypot(p[:, 0], p[:, 1])
    tube = p - 3.0 * np.stack([p[:, 0] / rho, p[:, 1] / rho, 0 * rho], axis=1)
    assert np.abs(t.normal(u, v) - tube).max() <= 1e-12
    cy = cylinder(2.0, 3.0)
    q = cy(u, v)
    assert np.abs(cy.normal(u, v) - q * [0.5, 0.5, 0]).max() <= 1e-12
    co = cone(1.0, 2.0)            # outward normal of the cone is (2 x/rho, 2 y/rho, 1)/sqrt(5)
    q = co(u, v)
    rho = np.hypot(q[:, 0], q[:, 1])
    expected = np.stack([2 * q[:, 0] / rho, 2 * q[:, 1] / rho, np.ones_like(rho)], axis=1) / math.sqrt(5)
    assert np.abs(co.normal(u, v) - expected).max() <= 1e-12


# --- general profiles ---------------------------------------------------------------------------
def unit_vectors():
    return st.lists(st.floats(-1, 1), min_size=3, max_size=3).map(np.array).filter(
        lambda d: np.linalg.norm(d) > 0.1)


@SETTINGS
@given(bspline_curves(dims=(3, 3), max_degree=5), centers, unit_vectors(),
       st.floats(0.1, 2 * np.pi), st.floats(-7.0, 7.0))
def test_revolve_any_profile(C, a, d, angle, start):
    """S(u, 0) is the profile rotated by start_angle, S(u, 1) by start + angle, every point
    keeps the profile point's axial coordinate and distance from the axis, and the angle
    increases monotonically from start to start + angle (oracle: Rodrigues rotation)."""
    S = revolve(C, a, d, angle, start)
    dn = d / np.linalg.norm(d)
    lo, hi = C.domain
    u = np.linspace(lo, hi, 31)
    P = C(u)
    scale = float(np.abs(C.control_points).max() + np.abs(a).max())
    assert S.domain[0] == pytest.approx((lo, hi)) and S.domain[1] == (0.0, 1.0)
    assert np.abs(S(u, 0.0) - rodrigues(P, a, dn, np.full(len(u), start))).max() <= 1e-12 * scale
    assert np.abs(S(u, 1.0) - rodrigues(P, a, dn, np.full(len(u), start + angle))).max() <= 1e-12 * scale
    v = np.linspace(0.0, 1.0, 301)
    Q = S(u[:, None], v[None, :])                                   # (31, 301, 3)
    h0, r0 = axial_frame(P, a, dn)
    h, r = axial_frame(Q, a, dn)
    assert np.abs(h - h0[:, None]).max() <= 1e-12 * scale
    assert np.abs(r - r0[:, None]).max() <= 1e-12 * scale
    # the angle of each point about the axis, measured from the profile point (none to
    # measure where the whole profile lies on the axis)
    far = r0 > 1e-3 * scale
    if not far.any():
        return
    x0 = P[far] - a - h0[far, None] * dn
    e1 = x0 / np.linalg.norm(x0, axis=1, keepdims=True)
    e2 = np.cross(dn, e1)
    x = Q[far] - a
    theta = np.unwrap(np.arctan2(np.einsum("ijk,ik->ij", x, e2), np.einsum("ijk,ik->ij", x, e1)), axis=1)
    theta = theta - theta[:, :1] + start
    assert np.all(np.diff(theta, axis=1) > 0)
    assert np.abs(theta[:, -1] - (start + angle)).max() <= 1e-9


@SETTINGS
@given(bspline_curves(dims=(3, 3), max_degree=4), unit_vectors(), st.floats(0.3, 2 * np.pi))
def test_arbitrary_axis_is_a_rotated_frame(C, d, angle):
    """revolve(M C + t, M a + t, M d) = M revolve(C, a, d) + t for a rigid motion (M, t)."""
    M = Rotation.from_rotvec(d * 1.3).as_matrix()
    t = np.array([1.0, -2.0, 0.5])
    a = np.array([0.3, 0.1, -0.2])
    S1 = revolve(C.transformed(M, t), M @ a + t, M @ d, angle).grid(np.linspace(*C.domain, 23), V)
    S0 = revolve(C, a, d, angle).grid(np.linspace(*C.domain, 23), V) @ M.T + t
    assert np.abs(S1 - S0).max() <= 1e-12 * (np.abs(C.control_points).max() + 3)


@pytest.mark.parametrize("angle, arcs", [(np.pi / 6, 1), (np.pi / 2, 1), (2 * np.pi / 3, 2), (np.pi, 2),
                                         (3 * np.pi / 2, 3), (5.0, 4), (2 * np.pi, 4)])
def test_partial_angles_use_arcs_of_at_most_90_degrees(angle, arcs):
    """Piegl & Tiller A7.1: n = ceil(angle / 90 deg) arcs, weights cos(angle / (2 n))."""
    c, s, w, knots = arc_parameters(0.0, angle)
    assert len(c) == 2 * arcs + 1 and len(knots) == 2 * arcs + 4
    assert np.allclose(w[1::2], math.cos(angle / (2 * arcs)), rtol=1e-15)
    profile = BezierCurve([[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [1.5, 0.0, 2.0]])
    S = revolve(profile, angle=angle)
    P = S.grid(U, V)
    assert np.abs(np.hypot(P[..., 0], P[..., 1]) - np.hypot(*profile(U)[:, [0, 1]].T)[:, None]).max() <= 1e-14 * 3
    theta = np.arctan2(P[:, :, 1], P[:, :, 0])
    theta = np.where(theta < -1e-12, theta + 2 * np.pi, theta)
    assert theta.min() >= -1e-12 and theta.max() <= angle + 1e-12
    assert np.abs(S(U, 1.0) - rodrigues(profile(U), np.zeros(3), np.array([0, 0, 1.0]),
                                       np.full(len(U), angle))).max() <= 1e-14 * 3


def test_profile_touching_the_axis_and_rational_profile():
    """A profile through the axis (degenerate, collapsed control points) and a rational
    profile (quarter circle) revolve to the expected spherical cap exactly."""
    s = math.sqrt(0.5)
    quarter = BSplineCurve([[0.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, 0.0]], 2, None, [1.0, s, 1.0])
    S = revolve(quarter, (0, 0, 0), (0, 0, 3.0), angle=1.0, start_angle=0.25)
    P = samples(S)
    assert np.abs(np.linalg.norm(P, axis=1) - 2.0).max() <= 2e-14
    assert np.all(P[:, 2] >= -1e-15)


# --- errors ----------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, name", [
    (dict(axis_direction=(0, 0, 0)), "axis_direction"),
    (dict(axis_direction=(0, 1)), "axis_direction"),
    (dict(axis_point=(0, 0, np.nan)), "axis_point"),
    (dict(angle=0.0), "angle"),
    (dict(angle=-1.0), "angle"),
    (dict(angle=2 * np.pi + 1e-9), "angle"),
    (dict(angle=7.0), "angle"),
    (dict(start_angle=np.inf), "start_angle"),
])
def test_revolve_errors_name_the_argument(kwargs, name):
    profile = BezierCurve([[1.0, 0.0, 0.0], [1.0, 0.0, 1.0]])
    with pytest.raises(CagdError, match=name):
        revolve(profile, **kwargs)


def test_profile_and_helper_errors():
    with pytest.raises(CagdError, match="profile"):
        revolve(np.zeros((3, 3)))
    with pytest.raises(CagdError, match="profile"):
        revolve(BezierCurve([[1.0, 0.0], [1.0, 1.0]]))
    for call, name in [(lambda: sphere(0.0), "radius"), (lambda: sphere(1.0, (0, 0)), "center"),
                       (lambda: torus(-1.0, 0.5), "R"), (lambda: torus(2.0, 0.0), "r"),
                       (lambda: cylinder(1.0, -2.0), "height"), (lambda: cone(0.0, 1.0), "radius")]:
        with pytest.raises(CagdError, match=name):
            call()


def test_full_turn_accepts_exactly_two_pi():
    S = revolve(BezierCurve([[1.0, 0.0, 0.0], [1.0, 0.0, 1.0]]), angle=2 * np.pi)
    assert S.control_points.shape[1] == 9


# --- construction records -------------------------------------------------------------------
@SETTINGS
@given(st.floats(-7.0, 7.0), st.floats(0.1, 2 * np.pi))
def test_arc_angle_is_the_angle_of_the_rational_circle(start, angle):
    """arc_angle(t) is the polar angle of the circle of arc_parameters at t (oracle: the
    NURBS circle evaluated, atan2), and arc_parameter inverts it."""
    c, s, w, knots = arc_parameters(start, angle)
    t = np.linspace(0.0, 1.0, 401)
    P = BSplineCurve(np.stack([c, s], axis=1), 2, knots, w)(t)
    polar = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    polar += 2 * np.pi * np.round((start - polar[0]) / (2 * np.pi))
    theta = arc_angle(t, start, angle)
    assert np.abs(theta - polar).max() <= 1e-13 * max(1.0, abs(start) + angle)
    assert np.all(np.diff(theta) > 0) and theta[0] == pytest.approx(start, abs=1e-14 * (1 + abs(start)))
    assert np.abs(arc_parameter(theta, start, angle) - t).max() <= 1e-13 * max(1.0, abs(start) + angle)


def primitive_point(p, U, V):
    """The closed-form angle parametrisation of a primitive record (OCCT's gp_Sphere,
    gp_Torus, gp_Cylinder, gp_Cone formulas) in its right-handed frame."""
    x, z = p.x_direction, p.axis
    assert np.array_equal(p.y_direction, np.cross(z, x))
    radial = np.cos(U)[..., None] * x + np.sin(U)[..., None] * np.cross(z, x)
    if p.kind == "sphere":
        return p.center + p.radius * (np.cos(V)[..., None] * radial + np.sin(V)[..., None] * z)
    if p.kind == "torus":
        return (p.center + (p.radius + p.minor_radius * np.cos(V))[..., None] * radial
                + p.minor_radius * np.sin(V)[..., None] * z)
    if p.kind == "cylinder":
        return p.center + p.radius * radial + V[..., None] * z
    slant = math.hypot(p.radius, p.height)                    # the cone: V along the slant from the base rim
    assert p.semi_angle == pytest.approx(-math.atan(p.radius / p.height), abs=1e-15)
    return p.center + (p.radius * (1 - V / slant))[..., None] * radial + (p.height * V / slant)[..., None] * z


def outward(p, points):
    """The outward unit normal of the primitive at points on it (closed forms)."""
    x = points - p.center
    h = x @ p.axis
    radial = x - h[..., None] * p.axis
    radial /= np.linalg.norm(radial, axis=-1, keepdims=True)
    if p.kind == "sphere":
        return x / p.radius
    if p.kind == "torus":
        y = x - p.radius * radial
        return y / np.linalg.norm(y, axis=-1, keepdims=True)
    if p.kind == "cylinder":
        return radial
    n = p.height * radial + p.radius * p.axis
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


PRIMITIVES = {"sphere": lambda: sphere(2.0, (1.0, -2.0, 0.5)), "torus": lambda: torus(3.0, 1.2, (0.0, 1.0, -1.0)),
              "cylinder": lambda: cylinder(1.5, 4.0, (2.0, 0.0, 1.0)), "cone": lambda: cone(1.5, 2.5, (0.0, 0.0, 3.0))}
KIND_DATA = {"sphere": (2.0, None, None), "torus": (3.0, 1.2, None), "cylinder": (1.5, None, 4.0),
             "cone": (1.5, None, 2.5)}


def similarity(seed: int, scale: float, reflect: bool) -> np.ndarray:
    M = scale * Rotation.random(random_state=seed).as_matrix()
    return M @ np.diag([1.0, 1.0, -1.0]) if reflect else M


@pytest.mark.parametrize("kind", list(PRIMITIVES))
def test_primitive_records(kind):
    s = PRIMITIVES[kind]()
    p = s.primitive
    assert isinstance(s, RevolvedSurface) and type(s).__mro__[1] is BSplineSurface
    assert p.kind == kind and (p.radius, p.minor_radius, p.height) == KIND_DATA[kind] and p.turn == 1
    assert np.array_equal(p.axis, [0, 0, 1]) and np.array_equal(p.x_direction, [1, 0, 0])
    r = s.revolution
    assert r.full_turn and r.start_angle == 0.0 and np.array_equal(r.axis_direction, [0, 0, 1])
    assert np.array_equal(r.axis_point, p.center)
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.radius = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.angle = 1.0
    for a in (p.center, p.axis, p.x_direction, r.axis_point, r.axis_direction):
        with pytest.raises(ValueError):
            a[0] = 1.0


@SETTINGS
@given(st.sampled_from(list(PRIMITIVES)), st.integers(0, 10 ** 6), st.floats(0.1, 10.0), st.booleans(), centers)
def test_primitive_records_follow_a_similarity(kind, seed, scale, reflect, offset):
    """After x -> M x + t (M a rotation times a scale, possibly reflecting) the moved
    record's closed-form parametrisation at analytic_parameters(u, v) is S(u, v), and
    ``turn`` says whether S_u x S_v is the outward normal."""
    M = similarity(seed, scale, reflect)
    s = PRIMITIVES[kind]().transformed(M, offset)
    assert isinstance(s, RevolvedSurface)
    p = s.primitive
    assert p.turn == (-1 if reflect else 1)
    assert p.radius == pytest.approx(scale * KIND_DATA[kind][0], rel=1e-14)
    assert abs(p.axis @ p.x_direction) <= 1e-15
    u, v = RU[:300], RV[:300]
    U, V = s.analytic_parameters(u, v)
    bounds = p.analytic_bounds
    assert U.min() >= bounds[0] and U.max() <= bounds[1] and V.min() >= bounds[2] - 1e-15 and V.max() <= bounds[3]
    P = s(u, v)
    size = s.size
    assert np.abs(primitive_point(p, U, V) - P).max() <= 1e-13 * size
    keep = np.linalg.norm(np.cross(*s.derivatives(u, v, 1, 1)[[1, 0], [0, 1]]), axis=-1) > 1e-6 * size ** 2
    n = s.normal(u[keep], v[keep])
    assert np.abs(np.einsum("ij,ij->i", n, outward(p, P[keep])) - p.turn).max() <= 1e-12


@SETTINGS
@given(bspline_curves(dims=(3, 3), max_degree=4), centers, unit_vectors(), st.floats(0.3, 2 * np.pi),
       st.floats(-4.0, 4.0), st.integers(0, 10 ** 6), st.floats(0.1, 10.0), st.booleans())
def test_revolution_record_describes_the_surface_after_a_similarity(C, a, d, angle, start, seed, scale, reflect):
    """S(u, v) is the record's profile(u) turned by angle_at(v) about its axis (oracle:
    Rodrigues), before and after a similarity; analytic_parameters is (angle_at(v), u)."""
    M = similarity(seed, scale, reflect)
    t = np.array([0.5, -1.0, 2.0])
    for s in (revolve(C, a, d, angle, start), revolve(C, a, d, angle, start).transformed(M, t)):
        r = s.revolution
        assert isinstance(s, RevolvedSurface) and s.primitive is None
        lo, hi = C.domain
        u, v = lo + (hi - lo) * RU[:200], RV[:200]
        expected = rodrigues(r.profile(u), r.axis_point, r.axis_direction, r.angle_at(v))
        assert np.abs(s(u, v) - expected).max() <= 1e-12 * (s.size + np.abs(r.axis_point).max())
        U, V = s.analytic_parameters(u, v)
        turns = 2 * np.pi * math.floor(start / (2 * np.pi) + 1e-9 / (2 * np.pi))   # as OCCT: U0 in [0, 2 pi)
        assert np.array_equal(U, r.angle_at(v) - turns) and np.array_equal(V, u)
        assert s.analytic_bounds == (start - turns, start - turns + angle, lo, hi)
        assert -1e-9 < s.analytic_bounds[0] < 2 * np.pi - 1e-9
        assert np.abs(r.parameter_at(U + turns) - v).max() <= 1e-12


SHEAR = np.array([[1.0, 0.3, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("matrix", [SHEAR, np.diag([1.0, 1.0, 2.0]), np.eye(3)[:2],
                                    np.eye(3) + 100 * SIMILARITY_TOL * np.outer([1, 0, 0], [0, 1, 0])],
                         ids=["shear", "stretch", "projection", "nearly-rigid"])
def test_other_affine_maps_drop_the_records(matrix):
    for s in [sphere(1.0), revolve(BezierCurve([[1.0, 0, 0], [2.0, 0, 1.0]]))]:
        moved = s.transformed(matrix)
        assert type(moved) is BSplineSurface
        assert np.array_equal(moved.control_points, s.control_points @ matrix.T)


def test_new_surfaces_are_plain_bspline_surfaces():
    """Every operation that makes a new net gives a plain BSplineSurface (the record
    would be false or would not match the parametrisation); to_nurbs keeps the object."""
    s = torus(3.0, 1.0)
    assert s.to_nurbs() is s
    made = [s.insert_knot("u", 0.3), s.refine("v", [0.1, 0.2]), s.elevate("u"), s.segment("v", 0.0, 0.5),
            *s.split("u", 0.5), s.clamped(), s.reversed("u"), s.reversed("v"), s.reparametrized((0, 2), None),
            s.swapped(), s.bezier_patches()[2][0][0],
            RevolvedSurface.from_occ_form(*s.occ_form()),
            s.with_control_points(s.control_points * 1.5), s.moved_pole((0, 0), np.ones(3)),
            s.with_control_points(s.control_points), s.with_weights(s.weights * 2.0)]
    assert all(type(m) is BSplineSurface for m in made), [type(m).__name__ for m in made]


def test_revolved_surface_errors():
    s = sphere(1.0)
    with pytest.raises(CagdError, match="revolution"):
        RevolvedSurface(s.control_points, 2, 2, s.knots_u, s.knots_v, s.weights, revolution=None)
    with pytest.raises(CagdError, match="primitive"):
        RevolvedSurface(s.control_points, 2, 2, s.knots_u, s.knots_v, s.weights, revolution=s.revolution,
                        primitive="sphere")
