"""Tensor-product Bezier patches (seed 000, 5.2.7; seed 003, 2.2-2.4): the direct
double sum of Bernstein products, de Casteljau, the seed's matrix forms, corners,
boundary curves and tangents, blossoms, subdivision, elevation, and the seed's
worked example of an ellipsoid as a bicubic rational Bezier patch."""
import itertools
from math import comb

import numpy as np
import pytest
from geomdl import BSpline as GeomdlBSpline
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BezierSurface, BSplineSurface, CagdError

from surface_strategies import bezier_surfaces, relative, weight_ratio

SETTINGS = settings(max_examples=40, deadline=None)
T = np.linspace(0.0, 1.0, 11)

# the seed's matrices for p(u, v) = [u^m .. u 1] M P M^T [v^n .. v 1]^T (seed 000, 5.2.7)
M1 = np.array([[-1, 1], [1, 0]], float)
M2 = np.array([[1, -2, 1], [-2, 2, 0], [1, 0, 0]], float)
M3 = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]], float)   # seed 000, 5.2.3


def size(s) -> float:
    return max(1.0, float(np.abs(s.control_points).max()))


def bernstein_sum(s, u, v) -> np.ndarray:
    """sum_i sum_j C(m,i) u^i (1-u)^(m-i) C(n,j) v^j (1-v)^(n-j) w_ij P_ij / (same without P),
    written out term by term (element-wise u, v of one shape)."""
    m, n = s.degree_u, s.degree_v
    w = np.ones((m + 1, n + 1)) if s.weights is None else s.weights
    u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
    num = np.zeros(u.shape + (s.dim,))
    den = np.zeros(u.shape)
    for i, j in itertools.product(range(m + 1), range(n + 1)):
        b = comb(m, i) * u ** i * (1 - u) ** (m - i) * comb(n, j) * v ** j * (1 - v) ** (n - j) * w[i, j]
        num += b[..., None] * s.control_points[i, j]
        den += b
    return num / den[..., None]


@SETTINGS
@given(s=bezier_surfaces(), data=st.data())
def test_every_evaluation_route_agrees_with_the_double_sum(s, data):
    """__call__ (B-spline route), grid, bernstein_evaluate, de_casteljau (seed 003, 2.2.1)
    against the written-out double sum of Bernstein products (seed 000, 5.2.7)."""
    u = np.array(data.draw(st.lists(st.floats(0, 1), min_size=1, max_size=12)) + [0.0, 1.0, 0.0, 1.0])
    v = np.array(data.draw(st.lists(st.floats(0, 1), min_size=len(u) - 4, max_size=len(u) - 4)) + [0.0, 0.0, 1.0, 1.0])
    ref = bernstein_sum(s, u, v)
    tol = 1e-13 * weight_ratio(s) * (s.degree_u + s.degree_v)
    for got in (s(u, v), s.bernstein_evaluate(u, v), s.de_casteljau(u, v)):
        assert got.shape == ref.shape
        assert relative(got, ref, size(s)) <= tol
    g = s.grid(T, T)
    assert relative(g, bernstein_sum(s, T[:, None], T[None, :]), size(s)) <= tol
    # broadcasting in the seed's algorithms as in __call__
    assert s.de_casteljau(T[:, None], T[None, :3]).shape == (11, 3, s.dim)
    assert s.bernstein_evaluate(T[:, None], 0.5).shape == (11, 1, s.dim)


@settings(max_examples=25, deadline=None)
@given(s=bezier_surfaces(rational=False, dims=(3, 3), max_degree=4))
def test_partials_vs_geomdl(s):
    m, n = s.degree_u, s.degree_v
    g = GeomdlBSpline.Surface(normalize_kv=False)
    g.degree_u, g.degree_v = m, n
    g.ctrlpts_size_u, g.ctrlpts_size_v = m + 1, n + 1
    g.ctrlpts = s.control_points.reshape(-1, 3).tolist()
    g.knotvector_u = [0.0] * (m + 1) + [1.0] * (m + 1)
    g.knotvector_v = [0.0] * (n + 1) + [1.0] * (n + 1)
    pts = [(0.13, 0.71), (0.5, 0.5), (0.91, 0.02), (0.0, 1.0)]
    mine = s.derivatives(np.array([p[0] for p in pts]), np.array([p[1] for p in pts]), 2, 2)
    for k, (u, v) in enumerate(pts):
        ref = np.array(g.derivatives(u, v, 2))
        for a, b in itertools.product(range(3), range(3)):
            if a + b <= 2:
                scale = size(s) * max(m, n) ** (a + b)
                assert np.abs(mine[a, b, k] - ref[a, b]).max() <= 1e-12 * scale, (a, b)


@pytest.mark.parametrize("degree, M", [(1, M1), (2, M2), (3, M3)])
def test_matrix_forms_of_the_seed(degree, M):
    """Seed 000, 5.2.7: bilinear p = [u 1] M1 P M1^T [v 1]^T, biquadratic with M2,
    bicubic with the cubic Bezier matrix; matrix_form returns C = M P M^T."""
    rng = np.random.default_rng(degree)
    P = rng.uniform(-4, 4, (degree + 1, degree + 1, 3))
    s = BezierSurface(P)
    C = s.matrix_form()
    np.testing.assert_allclose(C, np.einsum("ai,ijd,bj->abd", M, P, M), rtol=0, atol=1e-13)
    U = T[:, None] ** np.arange(degree, -1, -1)
    np.testing.assert_allclose(np.einsum("ua,abd,vb->uvd", U, C, U), s.grid(T, T), rtol=0, atol=1e-13)


def test_mixed_degree_matrix_form():
    rng = np.random.default_rng(9)
    P = rng.uniform(-4, 4, (4, 3, 2))                  # cubic in u, quadratic in v
    s = BezierSurface(P)
    np.testing.assert_allclose(s.matrix_form(), np.einsum("ai,ijd,bj->abd", M3, P, M2), atol=1e-13)


def test_bilinear_formula_and_partials():
    """Seed 000, 5.2.7 and seed 003, 2.2.1: p = (1-u)(1-v)P00 + (1-u)v P01 + u(1-v)P10 + uv P11;
    x_u = (1-v)(b10-b00) + v(b11-b01), x_v = (1-u)(b01-b00) + u(b11-b10),
    x_uu = x_vv = 0, x_uv = b00 - b10 - b01 + b11."""
    P = np.array([[[0, 0, 1], [0, 1, -2]], [[1, 0, 3], [1.5, 2, 0.5]]], float)
    s = BezierSurface(P)
    U, V = T[:, None, None], T[None, :, None]
    b00, b01, b10, b11 = P[0, 0], P[0, 1], P[1, 0], P[1, 1]
    d = s.derivatives(T[:, None], T[None, :], 2, 2)
    bilinear = (1 - U) * (1 - V) * b00 + (1 - U) * V * b01 + U * (1 - V) * b10 + U * V * b11
    np.testing.assert_allclose(d[0, 0], bilinear, atol=1e-15)
    full = d[0, 0].shape
    np.testing.assert_allclose(d[1, 0], np.broadcast_to((1 - V) * (b10 - b00) + V * (b11 - b01), full), atol=1e-14)
    np.testing.assert_allclose(d[0, 1], np.broadcast_to((1 - U) * (b01 - b00) + U * (b11 - b10), full), atol=1e-14)
    np.testing.assert_array_equal(d[2, 0], 0.0)
    np.testing.assert_array_equal(d[0, 2], 0.0)
    np.testing.assert_allclose(d[1, 1], np.broadcast_to(b00 - b10 - b01 + b11, d[1, 1].shape), atol=1e-14)


@SETTINGS
@given(s=bezier_surfaces())
def test_corners_and_boundary_curves(s):
    """p(0,0) = P00, p(0,1) = P0n, p(1,0) = Pm0, p(1,1) = Pmn (seed 000, 5.2.7 property 1);
    the boundary curves are the Bezier curves of the boundary control points (seed 003, 2.2.2)."""
    P, W = s.control_points, s.weights
    got = s(np.array([0.0, 0.0, 1.0, 1.0]), np.array([0.0, 1.0, 0.0, 1.0]))
    np.testing.assert_allclose(got, [P[0, 0], P[0, -1], P[-1, 0], P[-1, -1]], rtol=1e-14, atol=1e-14 * size(s))
    take = lambda A, k: None if A is None else A[k]  # noqa: E731
    edges = [(s(T, 0.0), P[:, 0], take(W, (slice(None), 0))), (s(1.0, T), P[-1], take(W, -1)),
             (s(T, 1.0), P[:, -1], take(W, (slice(None), -1))), (s(0.0, T), P[0], take(W, 0))]
    for k, (pts, ctrl, w) in enumerate(edges):
        assert relative(pts, BezierCurve(ctrl, w)(T), size(s)) <= 1e-13 * weight_ratio(s), k
    for k, c in enumerate(s.boundaries()):
        assert relative(c(T), edges[k][0], size(s)) <= 1e-13 * weight_ratio(s), k


@SETTINGS
@given(s=bezier_surfaces(rational=False))
def test_boundary_tangents(s):
    """Seed 003, 2.2.2: S_u(0, v) = m sum_j B_j(v) (P_1j - P_0j), S_u(1, v) with
    m (P_mj - P_{m-1,j}), and likewise S_v(u, 0), S_v(u, 1) with n (P_i1 - P_i0), n (P_in - P_i,n-1)."""
    nets_ = s.boundary_tangents()
    m, n, P = s.degree_u, s.degree_v, s.control_points
    np.testing.assert_allclose(nets_["u0"], m * (P[1] - P[0]))
    np.testing.assert_allclose(nets_["v1"], n * (P[:, -1] - P[:, -2]))
    expected = {"u0": s.derivative(0.0, T, 1, 0), "u1": s.derivative(1.0, T, 1, 0),
                "v0": s.derivative(T, 0.0, 0, 1), "v1": s.derivative(T, 1.0, 0, 1)}
    for edge, net in nets_.items():
        got = BezierCurve(net)(T)
        assert relative(got, expected[edge], size(s) * max(m, n)) <= 1e-13, edge


@SETTINGS
@given(s=bezier_surfaces(max_degree=4), data=st.data())
def test_blossom(s, data):
    """Seed 003, 2.2.4: the polar form is symmetric in the u's and in the v's, its
    diagonal is the surface, the control points are f(0^(m-i) 1^i; 0^(n-j) 1^j), and
    (polynomial patches) it is affine in each argument."""
    m, n = s.degree_u, s.degree_v
    us = data.draw(st.lists(st.floats(-1, 2), min_size=m, max_size=m))
    vs = data.draw(st.lists(st.floats(-1, 2), min_size=n, max_size=n))
    f = s.blossom(us, vs)
    perm_u = data.draw(st.permutations(us))
    perm_v = data.draw(st.permutations(vs))
    big = max(1.0, float(np.abs(f).max()), size(s) * 3.0 ** (m + n))   # |basis| <= 3^(m+n) on [-1, 2]
    tol = 1e-13 * weight_ratio(s) ** 2
    if s.is_rational:
        if np.abs(f).max() > 1e6 * size(s):
            return                                           # near a zero of the weight polar form
    assert np.abs(s.blossom(perm_u, perm_v) - f).max() <= tol * big
    # diagonal
    u0, v0 = data.draw(st.floats(0, 1)), data.draw(st.floats(0, 1))
    assert relative(s.blossom([u0] * m, [v0] * n), s(u0, v0), size(s)) <= 1e-13 * weight_ratio(s)
    # control points
    for i, j in itertools.product(range(m + 1), range(n + 1)):
        got = s.blossom([0.0] * (m - i) + [1.0] * i, [0.0] * (n - j) + [1.0] * j)
        np.testing.assert_allclose(got, s.control_points[i, j], rtol=1e-13, atol=1e-13 * size(s))
    if s.is_rational:
        return
    # multi-affine: f(.., a x + (1-a) y, ..) = a f(.., x, ..) + (1-a) f(.., y, ..), in one u and one v slot
    a = data.draw(st.floats(-2, 3))
    x, y = data.draw(st.floats(-1, 2)), data.draw(st.floats(-1, 2))
    k = data.draw(st.integers(0, m - 1))
    ua, ux, uy = list(us), list(us), list(us)
    ua[k], ux[k], uy[k] = a * x + (1 - a) * y, x, y
    lhs = s.blossom(ua, vs)
    rhs = a * s.blossom(ux, vs) + (1 - a) * s.blossom(uy, vs)
    assert np.abs(lhs - rhs).max() <= 1e-12 * big * (1 + abs(a))
    k = data.draw(st.integers(0, n - 1))
    va, vx, vy = list(vs), list(vs), list(vs)
    va[k], vx[k], vy[k] = a * x + (1 - a) * y, x, y
    lhs = s.blossom(us, va)
    rhs = a * s.blossom(us, vx) + (1 - a) * s.blossom(us, vy)
    assert np.abs(lhs - rhs).max() <= 1e-12 * big * (1 + abs(a))


def test_blossom_broadcasts():
    s = BezierSurface(np.random.default_rng(0).normal(size=(3, 4, 3)))
    f = s.blossom([T[:, None], 0.3], [T[None, :], 0.2, T[None, :]])
    assert f.shape == (11, 11, 3)
    np.testing.assert_allclose(f[4, 7], s.blossom([T[4], 0.3], [T[7], 0.2, T[7]]), atol=1e-15)


@SETTINGS
@given(s=bezier_surfaces(), t=st.floats(0.01, 0.99), direction=st.sampled_from("uv"))
def test_subdivide(s, t, direction):
    """The two halves are the surface on [0, t] and [t, 1] in the chosen direction,
    each reparametrised onto [0, 1] (de Casteljau in one direction)."""
    a, b = s.subdivide(direction, t)
    assert isinstance(a, BezierSurface) and (a.degree_u, a.degree_v) == (s.degree_u, s.degree_v)
    assert a.is_rational == s.is_rational
    U, V = T[:, None], T[None, :]
    tol = 1e-12 * weight_ratio(s)
    if direction == "u":
        assert relative(a(U, V), s(t * U, V), size(s)) <= tol
        assert relative(b(U, V), s(t + (1 - t) * U, V), size(s)) <= tol
    else:
        assert relative(a(U, V), s(U, t * V), size(s)) <= tol
        assert relative(b(U, V), s(U, t + (1 - t) * V), size(s)) <= tol


@SETTINGS
@given(s=bezier_surfaces(max_degree=4), tu=st.integers(0, 3), tv=st.integers(0, 3))
def test_elevate(s, tu, tv):
    e = s.elevate(tu, tv)
    assert (e.degree_u, e.degree_v) == (s.degree_u + tu, s.degree_v + tv)
    assert e.control_points.shape == (s.degree_u + tu + 1, s.degree_v + tv + 1, s.dim)
    assert relative(e.grid(T, T), s.grid(T, T), size(s)) <= 1e-12 * weight_ratio(s)
    # the corners stay where they were
    np.testing.assert_allclose(e.control_points[[0, 0, -1, -1], [0, -1, 0, -1]],
                               s.control_points[[0, 0, -1, -1], [0, -1, 0, -1]], atol=1e-13 * size(s))


@SETTINGS
@given(s=bezier_surfaces(rational=False, dims=(2, 3)))
def test_convex_hull(s):
    """Non-negative Bernstein products summing to 1: every point lies in the box of the net."""
    g = s.grid(T, T)
    lo = s.control_points.min(axis=(0, 1)) - 1e-12 * size(s)
    hi = s.control_points.max(axis=(0, 1)) + 1e-12 * size(s)
    assert np.all(g >= lo) and np.all(g <= hi)


@SETTINGS
@given(s=bezier_surfaces(), data=st.data())
def test_to_nurbs_and_affine_invariance(s, data):
    n = s.to_nurbs()
    assert isinstance(n, BSplineSurface) and n.domain == ((0.0, 1.0), (0.0, 1.0))
    np.testing.assert_array_equal(n.grid(T, T), s.grid(T, T))
    dim = s.dim
    A = np.array(data.draw(st.lists(st.floats(-2, 2), min_size=dim * dim, max_size=dim * dim))).reshape(dim, dim)
    b = np.array(data.draw(st.lists(st.floats(-2, 2), min_size=dim, max_size=dim)))
    moved = s.transformed(A, b)
    assert isinstance(moved, BezierSurface)
    np.testing.assert_allclose(moved.grid(T, T), s.grid(T, T) @ A.T + b, atol=1e-12 * size(s) * dim * 3)


# --- the seed's ellipsoid (seed 003, 2.4) ----------------------------------------------------

def ellipsoid_patch(a, b, c):
    """The bicubic rational Bezier patch of seed 003, 2.4: the table lists the
    homogeneous points (w x, w y, w z, w) as p_{ji}, j the v index and i the u index
    (its p_01 = f(0,0,1; 0,0,0) has z = 2c/3, from u)."""
    table = np.array([
        [[a, 0, 0, 1], [a, 0, 2 * c / 3, 1], [2 * a / 3, 0, 4 * c / 3, 4 / 3], [0, 0, 2 * c, 2]],
        [[a, 2 * b / 3, 0, 1], [a, 2 * b / 3, 2 * c / 3, 1], [2 * a / 3, 4 * b / 9, 4 * c / 3, 4 / 3],
         [0, 0, 2 * c, 2]],
        [[2 * a / 3, 4 * b / 3, 0, 4 / 3], [2 * a / 3, 4 * b / 3, 8 * c / 9, 4 / 3],
         [4 * a / 9, 8 * b / 9, 16 * c / 9, 16 / 9], [0, 0, 8 * c / 3, 8 / 3]],
        [[0, 2 * b, 0, 2], [0, 2 * b, 4 * c / 3, 2], [0, 4 * b / 3, 8 * c / 3, 8 / 3], [0, 0, 4 * c, 4]],
    ])
    hom = table.transpose(1, 0, 2)                  # [i_u, j_v]
    return BezierSurface(hom[..., :3] / hom[..., 3:], hom[..., 3]), hom


def test_ellipsoid_worked_example():
    """x = a(1-u^2)(1-v^2)/((1+u^2)(1+v^2)), y = 2b(1-u^2)v/(...), z = 2cu/(1+u^2):
    the octant of x^2/a^2 + y^2/b^2 + z^2/c^2 = 1, with u = tan(phi/2), v = tan(theta/2)."""
    a, b, c = 3.0, 2.0, 1.5
    s, hom = ellipsoid_patch(a, b, c)
    U, V = T[:, None], T[None, :]
    ref = np.stack(np.broadcast_arrays(a * (1 - U ** 2) * (1 - V ** 2) / ((1 + U ** 2) * (1 + V ** 2)),
                                       2 * b * (1 - U ** 2) * V / ((1 + U ** 2) * (1 + V ** 2)),
                                       2 * c * U / (1 + U ** 2) + 0 * V), axis=-1)
    pts = s.grid(T, T)
    np.testing.assert_allclose(pts, ref, rtol=0, atol=1e-14 * a)
    q = (pts ** 2 / np.array([a, b, c]) ** 2).sum(axis=-1)
    np.testing.assert_allclose(q, 1.0, rtol=1e-14)
    # the table is the polar form at 0/1 arguments (seed 003: "f(0,..,1; 0,..,1)")
    def polar(us, vs):
        su2 = (us[0] * us[1] + us[1] * us[2] + us[0] * us[2]) / 3
        sv2 = (vs[0] * vs[1] + vs[1] * vs[2] + vs[0] * vs[2]) / 3
        su1, sv1 = sum(us) / 3, sum(vs) / 3
        return np.array([a * (1 - su2) * (1 - sv2), 2 * b * (1 - su2) * sv1, 2 * c * (1 + sv2) * su1,
                         (1 + su2) * (1 + sv2)])
    for i, j in itertools.product(range(4), range(4)):
        np.testing.assert_allclose(polar([0] * (3 - i) + [1] * i, [0] * (3 - j) + [1] * j), hom[i, j], atol=1e-15)
    # the engine's blossom is the projected homogeneous polar form, at any arguments
    rng = np.random.default_rng(4)
    for _ in range(20):
        us, vs = rng.uniform(0, 1, 3), rng.uniform(0, 1, 3)
        X = polar(us, vs)
        np.testing.assert_allclose(s.blossom(list(us), list(vs)), X[:3] / X[3], rtol=1e-13, atol=1e-14)
    # Gaussian curvature of the ellipsoid: 1 / (a^2 b^2 c^2 (x^2/a^4 + y^2/b^2^2 + z^2/c^4)^2),
    # mean curvature |H| = |x^2 + y^2 + z^2 - a^2 - b^2 - c^2| / (2 (abc)^2 (...)^(3/2))
    t = np.linspace(0.05, 0.9, 9)
    u, v = np.meshgrid(t, t, indexing="ij")
    p = s(u, v)
    g = (p ** 2 / np.array([a, b, c]) ** 4).sum(axis=-1)
    K = 1.0 / ((a * b * c) ** 2 * g ** 2)
    H = np.abs((p ** 2).sum(axis=-1) - a * a - b * b - c * c) / (2 * (a * b * c) ** 2 * g ** 1.5)
    np.testing.assert_allclose(s.gaussian_curvature(u, v), K, rtol=1e-10)
    np.testing.assert_allclose(np.abs(s.mean_curvature(u, v)), H, rtol=1e-10)


def test_sphere_from_the_ellipsoid_patch():
    r = 2.5
    s, _ = ellipsoid_patch(r, r, r)
    t = np.linspace(0.0, 0.95, 8)
    u, v = np.meshgrid(t, t, indexing="ij")
    np.testing.assert_allclose(np.linalg.norm(s(u, v), axis=-1), r, rtol=1e-14)
    np.testing.assert_allclose(s.gaussian_curvature(u, v), 1 / r ** 2, rtol=1e-10)
    np.testing.assert_allclose(np.abs(s.mean_curvature(u, v)), 1 / r, rtol=1e-10)
    # the unit normal is the radial direction up to sign
    n = s.normal(u, v)
    np.testing.assert_allclose(np.abs(np.einsum("...i,...i", n, s(u, v) / r)), 1.0, rtol=1e-12)
    # the row u = 1 collapses to the pole: S_v(1, v) = 0 (up to rounding)
    assert np.abs(s.derivative(1.0, T, 0, 1)).max() <= 1e-14 * r


def test_normal_at_a_pole_is_reported_undefined():
    """The row u = 1 of the seed's sphere patch collapses to the pole (0, 0, r):
    the normal there must raise CagdError (or be the limit (0, 0, +-1)), never an
    arbitrary vector such as the tangent-plane direction (-0.3846, 0.9231, 0) that the
    old test relative to |S_u| |S_v| let through."""
    s, _ = ellipsoid_patch(2.5, 2.5, 2.5)
    try:
        n = s.normal(1.0, 0.2)
    except CagdError:
        return
    np.testing.assert_allclose(np.abs(n), [0.0, 0.0, 1.0], atol=1e-6)


# --- errors ------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [
    (dict(control_points=np.zeros((3, 3))), "control_points"),
    (dict(control_points=np.zeros((1, 3, 2))), "control_points"),
    (dict(control_points=np.full((2, 2, 3), np.inf)), "control_points"),
    (dict(control_points=np.zeros((2, 2, 3)), weights=np.ones(4)), "weights"),
    (dict(control_points=np.zeros((2, 2, 3)), weights=[[1, 1], [1, 0]]), "weights"),
    (dict(control_points=np.zeros((2, 2, 3)), weights=[[1, 1], [1, np.nan]]), "weights"),
])
def test_constructor_errors(kwargs, name):
    with pytest.raises(CagdError, match=name):
        BezierSurface(**kwargs)


def test_operation_errors():
    P = np.random.default_rng(0).normal(size=(3, 4, 3))
    s = BezierSurface(P)
    r = BezierSurface(P, np.ones((3, 4)))
    with pytest.raises(CagdError, match="us, vs"):
        s.blossom([0.5], [0.5, 0.5, 0.5])
    with pytest.raises(CagdError, match="t"):
        s.subdivide("u", 1.0)
    with pytest.raises(CagdError, match="t"):
        s.subdivide("v", np.nan)
    with pytest.raises(CagdError, match="direction"):
        s.subdivide("w", 0.5)
    with pytest.raises(CagdError, match="times_u"):
        s.elevate(-1, 0)
    with pytest.raises(CagdError, match="times_v"):
        s.elevate(0, 1.5)
    with pytest.raises(CagdError, match="weights"):
        r.matrix_form()
    with pytest.raises(CagdError, match="weights"):
        r.boundary_tangents()
    with pytest.raises(CagdError, match="u"):
        s(1.2, 0.5)
    with pytest.raises(CagdError, match="v"):
        s.de_casteljau(0.5, np.nan)
    assert "rational" in repr(r) and "(2, 3)" in repr(s)
