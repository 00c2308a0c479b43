"""The shared surface interface (seed 003, 2.1: partial derivatives, normal vector):
broadcasting, element-wise vs grid evaluation, rational partials by the quotient
rule, normals, fundamental forms and curvatures of a cylinder and a sphere built
by hand as NURBS (circle x line, circle x semicircle)."""
import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BezierSurface, BSplineCurve, BSplineSurface, CagdError, Surface
import cagd
from cagd.surfaces.base import NORMAL_TOL, rational_partials, unit_normals

from surface_strategies import (bezier_surfaces, bspline_surfaces, domain_parameters, interior_parameters,
                                min_span, net_size, regular, relative, scipy_homogeneous_grid,
                                weight_ratio)

SETTINGS = settings(max_examples=40, deadline=None)
S2 = np.sqrt(0.5)
# the 9-point quadratic NURBS circle (Piegl & Tiller 7.3), knots at quarter turns
CIRCLE = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
CIRCLE_W = np.array([1, S2, 1, S2, 1, S2, 1, S2, 1])
CIRCLE_KNOTS = [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1]


def cylinder(r=2.0, h=3.0):
    """Circle NURBS (u) times a line segment (v, degree 1): x^2 + y^2 = r^2, 0 <= z <= h."""
    P = np.empty((9, 2, 3))
    P[:, :, :2] = r * CIRCLE[:, None, :]
    P[:, 0, 2], P[:, 1, 2] = 0.0, h
    W = np.repeat(CIRCLE_W[:, None], 2, axis=1)
    return BSplineSurface(P, 2, 1, CIRCLE_KNOTS, [0, 0, 1, 1], W)


def sphere(r=1.5):
    """Circle (u, around z) times the meridian half circle (v, from the south to the
    north pole: the right half of the 9-point circle, rotated), w_ij = w_i w_j."""
    half = np.array([[0, -1], [1, -1], [1, 0], [1, 1], [0, 1]], float)     # (rho, z)
    hw = np.array([1, S2, 1, S2, 1])
    P = np.empty((9, 5, 3))
    P[..., 0] = r * CIRCLE[:, None, 0] * half[None, :, 0]
    P[..., 1] = r * CIRCLE[:, None, 1] * half[None, :, 0]
    P[..., 2] = r * np.broadcast_to(half[None, :, 1], (9, 5))
    return BSplineSurface(P, 2, 2, CIRCLE_KNOTS, [0, 0, 0, 0.5, 0.5, 1, 1, 1], CIRCLE_W[:, None] * hw[None, :])


# --- broadcasting and evaluation routes ---------------------------------------------------------

@SETTINGS
@given(s=st.one_of(bspline_surfaces(max_degree=3), bezier_surfaces(max_degree=3)))
def test_broadcasting_shapes(s):
    (a, b), (c, d) = s.domain
    u = np.linspace(a, b, 5)[:, None]
    v = np.linspace(c, d, 7)[None, :]
    assert s(u, v).shape == (5, 7, s.dim)
    assert s(float(u[1, 0]), float(v[0, 2])).shape == (s.dim,)
    assert s(u[:, 0], float(v[0, 3])).shape == (5, s.dim)
    assert s.derivatives(u, v, 2, 1).shape == (3, 2, 5, 7, s.dim)
    assert s.derivative(u, v, 1, 1).shape == (5, 7, s.dim)
    assert s.grid(u[:, 0], v[0], 1, 0).shape == (5, 7, s.dim)
    # an element-wise broadcast equals the explicit loop over the pairs
    full = s(u, v)
    for i, j in ((0, 0), (2, 5), (4, 6)):
        np.testing.assert_array_equal(full[i, j], s(u[i, 0], v[0, j]))
    u3 = np.linspace(a, b, 24).reshape(2, 3, 4)
    assert s(u3, c).shape == (2, 3, 4, s.dim)


@SETTINGS
@given(s=bspline_surfaces(max_degree=4), data=st.data())
def test_elementwise_equals_grid_with_partials(s, data):
    """__call__/derivatives on broadcast (u[:, None], v[None, :]) and the grid fast path
    (basis matrices and matrix products) agree for every partial, rational too."""
    us, vs = domain_parameters(s, 6)
    du, dv = data.draw(st.integers(0, 2)), data.draw(st.integers(0, 2))
    elem = s.derivatives(us[:, None], vs[None, :], du, dv)
    for k, l in itertools.product(range(du + 1), range(dv + 1)):
        g = s.grid(us, vs, k, l)
        pu = s.degree_u / min_span(s, "u")
        pv = s.degree_v / min_span(s, "v")
        rounding = net_size(s) * weight_ratio(s) ** (k + l + 1) * pu ** k * pv ** l
        tol = 1e-12 * np.abs(elem[k, l]).max() + 1e-13 * rounding
        assert np.abs(g - elem[k, l]).max() <= tol, (k, l)


@SETTINGS
@given(s=bspline_surfaces(rational=True, max_degree=3))
def test_rational_partials_by_the_quotient_rule(s):
    """With A = sum N N w P, w = sum N N w (homogeneous partials from scipy), S = A / w:
    S_u = (A_u - w_u S) / w, S_uu = (A_uu - 2 w_u S_u - w_uu S) / w,
    S_uv = (A_uv - w_uv S - w_u S_v - w_v S_u) / w (Piegl & Tiller eq. 4.20)."""
    us = interior_parameters(s, "u", 1)
    vs = interior_parameters(s, "v", 1)
    H = scipy_homogeneous_grid(s, us, vs, 2, 2)
    A, w = H[..., :-1], H[..., -1:]
    S = A[0, 0] / w[0, 0]
    Su = (A[1, 0] - w[1, 0] * S) / w[0, 0]
    Sv = (A[0, 1] - w[0, 1] * S) / w[0, 0]
    Suu = (A[2, 0] - 2 * w[1, 0] * Su - w[2, 0] * S) / w[0, 0]
    Suv = (A[1, 1] - w[1, 1] * S - w[1, 0] * Sv - w[0, 1] * Su) / w[0, 0]
    mine = s.derivatives(us[:, None], vs[None, :], 2, 2)
    pu, pv = s.degree_u / min_span(s, "u"), s.degree_v / min_span(s, "v")
    for (k, l), ref in {(0, 0): S, (1, 0): Su, (0, 1): Sv, (2, 0): Suu, (1, 1): Suv}.items():
        tol = 1e-11 * np.abs(ref).max() + 1e-12 * net_size(s) * weight_ratio(s) ** (k + l + 1) * pu ** k * pv ** l
        assert np.abs(mine[k, l] - ref).max() <= tol, (k, l)
    # and the engine's own helper on the same homogeneous partials
    np.testing.assert_allclose(rational_partials(H)[1, 1], Suv, rtol=1e-9, atol=1e-12 * net_size(s) * pu * pv)


# --- normals and fundamental forms ----------------------------------------------------------------

@SETTINGS
@given(s=bspline_surfaces(dims=(3, 3), max_degree=3))
def test_normal_is_a_unit_vector_perpendicular_to_both_partials(s):
    us = interior_parameters(s, "u", 1)
    vs = interior_parameters(s, "v", 1)
    U, V = us[:, None], vs[None, :]
    d = s.derivatives(U, V, 1, 1)
    su, sv = d[1, 0], d[0, 1]
    cross = np.linalg.norm(np.cross(su, sv), axis=-1)
    if (cross == 0).any():
        with pytest.raises(CagdError, match="normal"):
            s.normal(U, V)
        return
    if not regular(s, d):
        return                                          # nearly degenerate: no well-defined normal
    n = s.normal(U, V)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, rtol=1e-14)
    assert np.abs(np.einsum("...i,...i", n, su)).max() <= 1e-12 * np.abs(su).max()
    assert np.abs(np.einsum("...i,...i", n, sv)).max() <= 1e-12 * np.abs(sv).max()
    # orientation: n . (S_u x S_v) > 0
    assert np.all(np.einsum("...i,...i", n, np.cross(su, sv)) > 0)


@SETTINGS
@given(s=bspline_surfaces(dims=(3, 3), max_degree=3, rational=False))
def test_fundamental_forms_and_curvatures_from_their_definitions(s):
    """E = S_u.S_u, F = S_u.S_v, G = S_v.S_v, L = S_uu.n, M = S_uv.n, N = S_vv.n,
    K = (LN - M^2)/(EG - F^2), H = (EN - 2FM + GL)/(2(EG - F^2)) (do Carmo 3.3)."""
    us = interior_parameters(s, "u", 1)[:4]
    vs = interior_parameters(s, "v", 1)[:4]
    U, V = us[:, None], vs[None, :]
    d = s.derivatives(U, V, 2, 2)
    c = np.cross(d[1, 0], d[0, 1])
    if not regular(s, d):
        return
    n = c / np.linalg.norm(c, axis=-1, keepdims=True)
    dot = lambda a, b: (a * b).sum(-1)  # noqa: E731
    E, F, G = dot(d[1, 0], d[1, 0]), dot(d[1, 0], d[0, 1]), dot(d[0, 1], d[0, 1])
    L, M, N = dot(d[2, 0], n), dot(d[1, 1], n), dot(d[0, 2], n)
    (e, f, g), (l_, m, n_) = s.fundamental_forms(U, V)
    for got, ref in ((e, E), (f, F), (g, G)):
        np.testing.assert_allclose(got, ref, rtol=1e-13, atol=1e-13 * np.abs(E).max())
    second = max(np.abs(d[2, 0]).max(), np.abs(d[1, 1]).max(), np.abs(d[0, 2]).max())
    for got, ref in ((l_, L), (m, M), (n_, N)):
        np.testing.assert_allclose(got, ref, rtol=1e-11, atol=1e-12 * second)
    det = E * G - F * F
    K = (L * N - M * M) / det
    H = (E * N - 2 * F * M + G * L) / (2 * det)
    # rounding of L, M, N (~1e-12 second) carried through the division by det
    assert np.all(np.abs(s.gaussian_curvature(U, V) - K) <= 1e-9 * np.abs(K) + 1e-11 * second ** 2 / det)
    assert np.all(np.abs(s.mean_curvature(U, V) - H) <= 1e-9 * np.abs(H) + 1e-11 * second * (E + G) / det)


def test_cylinder_curvatures():
    """Cylinder of radius r: K = 0, H = +-1/(2r), normal radial, E = |C'(u)|^2, G = h^2."""
    r, h = 2.0, 3.0
    s = cylinder(r, h)
    u, v = np.meshgrid(np.linspace(0, 1, 17), np.linspace(0, 1, 5), indexing="ij")
    p = s(u, v)
    np.testing.assert_allclose(np.hypot(p[..., 0], p[..., 1]), r, rtol=1e-14)
    np.testing.assert_allclose(p[..., 2], h * v, atol=1e-14)
    np.testing.assert_allclose(s.gaussian_curvature(u, v), 0.0, atol=1e-12)
    H = s.mean_curvature(u, v)
    np.testing.assert_allclose(np.abs(H), 1 / (2 * r), rtol=1e-12)
    assert np.all(np.sign(H) == np.sign(H.flat[0]))
    n = s.normal(u, v)
    radial = p.copy()
    radial[..., 2] = 0
    radial /= r
    np.testing.assert_allclose(np.abs(np.einsum("...i,...i", n, radial)), 1.0, rtol=1e-13)
    (E, F, G), _ = s.fundamental_forms(u, v)
    np.testing.assert_allclose(G, h * h, rtol=1e-14)
    np.testing.assert_allclose(F, 0.0, atol=1e-13)
    circle = BSplineCurve(r * CIRCLE, 2, CIRCLE_KNOTS, CIRCLE_W)
    np.testing.assert_allclose(E, (circle.derivative(u[:, 0], 1) ** 2).sum(-1)[:, None] * np.ones_like(v), rtol=1e-13)


def test_sphere_curvatures():
    """Sphere of radius r as circle x semicircle: |S| = r, K = 1/r^2, H = +-1/r, normal radial."""
    r = 1.5
    s = sphere(r)
    u, v = np.meshgrid(np.linspace(0, 1, 13), np.linspace(0.02, 0.98, 11), indexing="ij")
    p = s(u, v)
    np.testing.assert_allclose(np.linalg.norm(p, axis=-1), r, rtol=1e-14)
    np.testing.assert_allclose(s.gaussian_curvature(u, v), 1 / r ** 2, rtol=1e-11)
    np.testing.assert_allclose(np.abs(s.mean_curvature(u, v)), 1 / r, rtol=1e-11)
    np.testing.assert_allclose(np.abs(np.einsum("...i,...i", s.normal(u, v), p / r)), 1.0, rtol=1e-13)
    # the poles v = 0, 1 are the boundary rows collapsed to points
    np.testing.assert_allclose(s(np.linspace(0, 1, 5), 0.0), np.broadcast_to([0, 0, -r], (5, 3)), atol=1e-15)
    np.testing.assert_allclose(s(np.linspace(0, 1, 5), 1.0), np.broadcast_to([0, 0, r], (5, 3)), atol=1e-15)


def test_planar_surfaces_have_normal_z():
    """A 2-D surface is lifted to z = 0 for the cross product: n = (0, 0, +-1)."""
    P = np.array([[[0, 0], [0, 1], [0, 2]], [[1, 0], [1.2, 1], [1, 2.5]]], float)
    s = BezierSurface(P)
    n = s.normal(T2[:, None], T2[None, :])
    np.testing.assert_allclose(n, np.broadcast_to([0, 0, 1.0], n.shape), atol=1e-15)   # S_u ~ +x, S_v ~ +y
    np.testing.assert_allclose(s.gaussian_curvature(0.3, 0.6), 0.0, atol=1e-15)


T2 = np.linspace(0, 1, 5)


def test_normal_errors():
    one_d = BezierSurface(np.arange(4.0).reshape(2, 2, 1))
    with pytest.raises(CagdError, match="normal"):
        one_d.normal(0.5, 0.5)
    four_d = BezierSurface(np.random.default_rng(0).normal(size=(2, 2, 4)))
    with pytest.raises(CagdError, match="normal"):
        four_d.gaussian_curvature(0.5, 0.5)
    flat = BezierSurface(np.zeros((2, 2, 3)))              # collapsed to a point
    with pytest.raises(CagdError, match="normal"):
        flat.normal(0.5, 0.5)


# --- the normal where it is defined (unit_normals, NORMAL_TOL) --------------------------------------------------

def test_normal_cut_off_is_the_sine_between_the_partials():
    """Partials of unit length: defined iff sin(angle) > NORMAL_TOL (both sides of the cut)."""
    su = np.array([1.0, 0.0, 0.0])
    for theta, defined in ((2 * NORMAL_TOL, True), (0.5 * NORMAL_TOL, False), (np.pi / 2, True), (0.0, False)):
        n, ok = unit_normals(su, np.array([np.cos(theta), np.sin(theta), 0.0]))
        assert bool(ok) == defined
        np.testing.assert_array_equal(n, [0, 0, 1.0] if defined else [0, 0, 0])


def test_normal_cut_off_scales_the_partials_from_below():
    """A partial that is rounding noise against its scale (a pole) leaves the normal
    undefined even when it points somewhere: the test is relative to max(|S_u|, scale_u)."""
    noise, sv = np.array([1e-17, 3e-18, 0.0]), np.array([0.0, 2.0, 0.0])
    assert unit_normals(noise, sv)[1]                                # no scale: the sine alone
    assert not unit_normals(noise, sv, scale_u=1.0, scale_v=1.0)[1]


def test_sphere_pole_has_no_normal_and_the_rest_is_radial():
    s = cagd.sphere(2.0, center=(1.0, -1.0, 0.5))
    (u0, u1), (v0, v1) = s.domain
    v = np.linspace(v0, v1, 7)
    for pole in (u0, u1):                                 # each edge u = const collapses to a pole
        n, ok = s.normals(np.full_like(v, pole), v)
        assert not ok.any() and np.all(n == 0)
        with pytest.raises(CagdError, match="normal is undefined"):
            s.normal(pole, v[3])
    u, vv = np.meshgrid(np.linspace(u0, u1, 9)[1:-1], v, indexing="ij")
    n, ok = s.normals(u, vv)
    assert ok.all()
    radial = (s(u, vv) - [1.0, -1.0, 0.5]) / 2.0
    np.testing.assert_allclose(np.abs(np.einsum("...k,...k", n, radial)), 1.0, atol=1e-13)


def test_cone_apex_has_no_normal_and_the_side_is_perpendicular_to_its_generators():
    c = cagd.cone(1.0, 2.0)                               # apex (0, 0, 2) on the edge u = u0
    (u0, u1), (v0, v1) = c.domain
    v = np.linspace(v0, v1, 5)
    n, ok = c.normals(np.full_like(v, u0), v)
    assert not ok.any()
    u = np.linspace(u0, u1, 6)[1:]
    U, V = np.meshgrid(u, v, indexing="ij")
    n, ok = c.normals(U, V)
    assert ok.all()
    generator = c(U, V) - [0.0, 0.0, 2.0]
    np.testing.assert_allclose(np.einsum("...k,...k", n, generator), 0.0, atol=1e-13)
    # half-angle alpha = atan(r / h) at the apex: n makes the angle pi/2 - alpha with the axis
    np.testing.assert_allclose(np.abs(n[..., 2]), np.sin(np.arctan(0.5)), rtol=1e-13)


def test_degenerate_patches_have_no_normal():
    """A patch collapsed to a segment (S_u parallel to S_v everywhere) and a triangle-like
    patch whose edge v = 0 collapses to a corner point."""
    line = np.array([[[0, 0, 0], [1, 1, 1]], [[2, 2, 2], [3, 3, 3]]], float)
    n, ok = BezierSurface(line).normals(*np.meshgrid(T2, T2, indexing="ij"))
    assert not ok.any()
    P = np.array([[[0, 0, 0], [0, 1, 0], [0, 2, 0]], [[0, 0, 0], [1, 1, 0], [1, 2, 0]],
                  [[0, 0, 0], [2, 1, 0], [2, 2, 0]]], float)
    fan = BezierSurface(P)                                # S(u, 0) = (0, 0, 0) for every u
    _, ok = fan.normals(T2, np.zeros_like(T2))
    assert not ok.any()
    n, ok = fan.normals(T2[1:, None], T2[None, 1:])
    assert ok.all() and np.allclose(np.abs(n[..., 2]), 1.0)


# --- curves on the surface, transforms ------------------------------------------------------------

@SETTINGS
@given(s=st.one_of(bezier_surfaces(max_degree=3), bspline_surfaces(max_degree=3)))
def test_boundaries_follow_the_edges(s):
    """boundaries() = [S(u, v0), S(u1, v), S(u, v1), S(u0, v)], each in the increasing
    parameter of its edge, for every kind of surface (the base goes through to_nurbs)."""
    (a, b), (c, d) = s.domain
    us, vs = np.linspace(a, b, 9), np.linspace(c, d, 9)
    if s.periodic_u:
        us = us[:-1]
    if s.periodic_v:
        vs = vs[:-1]
    edges = [(us, lambda t: s(t, c)), (vs, lambda t: s(b, t)), (us, lambda t: s(t, d)), (vs, lambda t: s(a, t))]
    tol = 1e-12 * weight_ratio(s)
    for curve, (t, ref) in zip(s.boundaries(), edges):
        assert relative(curve(t), ref(t), net_size(s)) <= tol


def test_isocurve_through_the_base_class():
    """Surface.isocurve (not overridden by BezierSurface) converts through to_nurbs."""
    rng = np.random.default_rng(3)
    s = BezierSurface(rng.normal(size=(4, 3, 3)), rng.uniform(0.5, 2, (4, 3)))
    assert type(s).isocurve is Surface.isocurve
    c = s.isocurve("v", 0.3)
    np.testing.assert_allclose(c(T2), s(0.3, T2), atol=1e-14)
    with pytest.raises(CagdError, match="direction"):
        s.isocurve("z", 0.3)


@SETTINGS
@given(s=st.one_of(bezier_surfaces(dims=(3, 3)), bspline_surfaces(dims=(3, 3))), data=st.data())
def test_rigid_motion_moves_normals_and_keeps_curvature(s, data):
    """Under a rotation R and translation b: points map, normals rotate, K and H stay."""
    angles = data.draw(st.lists(st.floats(-np.pi, np.pi), min_size=3, max_size=3))
    R = np.eye(3)
    for axis, t in enumerate(angles):
        c, sn = np.cos(t), np.sin(t)
        i, j = [k for k in range(3) if k != axis]
        G = np.eye(3)
        G[i, i] = G[j, j] = c
        G[i, j], G[j, i] = -sn, sn
        R = G @ R
    b = np.array(data.draw(st.lists(st.floats(-5, 5), min_size=3, max_size=3)))
    m = s.transformed(R, b)
    assert type(m) is type(s)
    us = interior_parameters(s, "u", 1)[:3]
    vs = interior_parameters(s, "v", 1)[:3]
    U, V = us[:, None], vs[None, :]
    np.testing.assert_allclose(m(U, V), s(U, V) @ R.T + b, atol=1e-12 * (net_size(s) + 5))
    d = s.derivatives(U, V, 2, 2)
    c = np.linalg.norm(np.cross(d[1, 0], d[0, 1]), axis=-1)
    if not regular(s, d, offset=5.0):
        return            # (near) degenerate points; a vanishing partial is test_normal_at_a_pole_...
    np.testing.assert_allclose(m.normal(U, V), s.normal(U, V) @ R.T, atol=1e-9)
    # K (EG - F^2) = LN - M^2 is of the size of the second partials squared
    (E, F, G), _ = s.fundamental_forms(U, V)
    det = E * G - F * F
    if np.any(det <= 1e-6 * E * G):
        return            # S_u, S_v within 1e-3 rad of parallel: EG - F^2 cancels, K is ill-conditioned
    second = max(np.abs(d[2, 0]).max(), np.abs(d[1, 1]).max(), np.abs(d[0, 2]).max())
    np.testing.assert_allclose(m.gaussian_curvature(U, V) * det, s.gaussian_curvature(U, V) * det,
                               rtol=1e-6, atol=1e-10 * second ** 2)


def test_transformed_errors():
    s = BezierSurface(np.zeros((2, 2, 3)))
    with pytest.raises(CagdError, match="matrix"):
        s.transformed(np.eye(2))
    with pytest.raises(CagdError, match="matrix"):
        s.transformed([1.0, 2.0, 3.0])
    with pytest.raises(CagdError, match="offset"):
        s.transformed(np.eye(3), [1.0])
    with pytest.raises(CagdError, match="offset"):
        s.transformed(np.eye(3), [np.nan, 0, 0])
    # a projection to the plane is allowed (fewer output rows)
    assert s.transformed(np.eye(3)[:2]).dim == 2


def test_base_class_is_abstract():
    base = Surface()
    with pytest.raises(NotImplementedError):
        base.domain
    with pytest.raises(NotImplementedError):
        base.to_nurbs()
