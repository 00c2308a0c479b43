"""Total-degree Bezier triangles (seed 003, 3.1): input, evaluation, derivatives,
blossoms, subdivision, degree elevation, exact tensor-product (NURBS) form."""
import itertools
from math import factorial

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.polynomial import polynomial as npoly

from cagd import BezierSurface, BSplineSurface, CagdError, Surface
from cagd.triangles import BezierTriangle, index_triples, triangle_bernstein

from strategies import point_arrays, positive_weights

SETTINGS = settings(max_examples=50, deadline=None)


@st.composite
def triangles(draw, min_degree=1, max_degree=6, rational=None, dims=(1, 3)):
    n = draw(st.integers(min_degree, max_degree))
    N = (n + 1) * (n + 2) // 2
    P = draw(point_arrays(N, draw(st.integers(*dims))))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=N, max_size=N))) if is_rational else None
    return BezierTriangle(P, w)


@st.composite
def bary(draw, inside=True):
    """A barycentric triple; inside the triangle, or anywhere in [-2, 3]^2 (affine point)."""
    if inside:
        a, b = draw(st.floats(0, 1)), draw(st.floats(0, 1))
        if a + b > 1:
            a, b = 1 - a, 1 - b
    else:
        a, b = draw(st.floats(-2, 3)), draw(st.floats(-2, 3))
    return np.array([a, b, 1 - a - b])


def scale(t):
    return max(1.0, float(np.abs(t.control_points).max()))


def samples(count=40, seed=0):
    rng = np.random.default_rng(seed)
    u, v = rng.uniform(0, 1, count), rng.uniform(0, 1, count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    corners = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0.5], [0, 0.5], [0.5, 0]])
    return np.concatenate([u, corners[:, 0]]), np.concatenate([v, corners[:, 1]])


def oracle(t, u, v):
    """sum n!/(i!j!k!) u^i v^j w^k w_ijk P_ijk / sum (...) w_ijk, one triple at a time."""
    n = t.degree
    w = 1 - u - v
    num, den = 0.0, 0.0
    for (i, j, k), P in t.as_dict().items():
        wt = 1.0 if t.weights is None else t.weights[index_triples(n).index((i, j, k))]
        B = factorial(n) / (factorial(i) * factorial(j) * factorial(k)) * u ** i * v ** j * w ** k * wt
        num = num + B[..., None] * P
        den = den + B
    return num / np.asarray(den)[..., None]


def power_coefficients(t):
    """Coefficients C[a, b, d] of u^a v^b (numpy.polynomial 2-D) of a polynomial triangle,
    expanding (1 - u - v)^k by the multinomial theorem."""
    n = t.degree
    C = np.zeros((n + 1, n + 1, t.dim))
    for (i, j, k), P in t.as_dict().items():
        c0 = factorial(n) / (factorial(i) * factorial(j) * factorial(k))
        for p in range(k + 1):
            for q in range(k - p + 1):
                c = c0 * factorial(k) / (factorial(p) * factorial(q) * factorial(k - p - q)) * (-1) ** (p + q)
                C[i + p, j + q] += c * P
    return C


def power_partial(t, u, v, a, b):
    C = power_coefficients(t)
    out = []
    for d in range(t.dim):
        c = C[..., d]
        if a:
            c = npoly.polyder(c, a, axis=0)
        if b:
            c = npoly.polyder(c, b, axis=1)
        out.append(npoly.polyval2d(u, v, c))
    return np.stack(out, axis=-1)


def blossom_oracle(t, xs):
    """f(x_1..x_n) = sum over vertex choices c in {1,2,3}^n of prod_r x_r[c_r] P_count(c)
    (multilinearity with P_ijk = f(e1^i, e2^j, e3^k)); homogeneous values."""
    hom = t.homogeneous_control_points
    n = t.degree
    total = 0.0
    for c in itertools.product(range(3), repeat=n):
        coef = np.prod([x[ci] for x, ci in zip(xs, c)])
        counts = (c.count(0), c.count(1), c.count(2))
        total = total + coef * hom[index_triples(n).index(counts)]
    return total


# --- index triples, basis, input --------------------------------------------------------
def test_index_triples_canonical_order():
    assert index_triples(2) == [(2, 0, 0), (1, 1, 0), (1, 0, 1), (0, 2, 0), (0, 1, 1), (0, 0, 2)]
    for n in range(7):
        t = index_triples(n)
        assert len(t) == len(set(t)) == (n + 1) * (n + 2) // 2
        assert all(sum(x) == n and min(x) >= 0 for x in t)
        assert t == sorted(t, reverse=True)
    assert BezierTriangle.index_triples(3) == index_triples(3)


@SETTINGS
@given(n=st.integers(0, 7), x=bary())
def test_triangle_bernstein_formula_and_partition(n, x):
    B = triangle_bernstein(n, x[0], x[1])
    expected = [factorial(n) / (factorial(i) * factorial(j) * factorial(k)) * x[0] ** i * x[1] ** j * x[2] ** k
                for i, j, k in index_triples(n)]
    np.testing.assert_allclose(B, expected, rtol=1e-13, atol=1e-15)
    assert abs(B.sum() - 1) < 1e-13 and np.all(B >= -1e-15)


def test_dict_pairs_and_array_inputs_agree():
    rng = np.random.default_rng(3)
    P = rng.normal(size=(10, 3))
    W = rng.uniform(0.5, 2, 10)
    d = dict(zip(index_triples(3), P))
    a = BezierTriangle(P, W)
    b = BezierTriangle(d, dict(zip(index_triples(3), W)))
    c = BezierTriangle(list(reversed(list(d.items()))), W)
    for t in (b, c):
        np.testing.assert_array_equal(t.control_points, a.control_points)
        np.testing.assert_array_equal(t.weights, a.weights)
    assert a.degree == 3 and a.dim == 3 and a.is_rational
    np.testing.assert_array_equal(a.control_point(1, 0, 2), d[(1, 0, 2)])
    one_d = BezierTriangle(np.arange(6.0))
    assert one_d.dim == 1 and one_d.degree == 2


def _quad():
    return {t: [float(sum(t[:2])), float(t[0])] for t in index_triples(2)}


@pytest.mark.parametrize("build, match", [
    (lambda d: {k: v for k, v in d.items() if k != (1, 0, 1)}, r"control_points: missing triple \(1, 0, 1\)"),
    (lambda d: {**d, (3, 0, 0): [0, 0]}, r"control_points: extra triple \(3, 0, 0\)"),
    (lambda d: list(d.items()) + [((0, 2, 0), [1, 1])], r"control_points: triple \(0, 2, 0\) is given more than once"),
    (lambda d: {**d, (0, 1, 1): [1, 2, 3]}, r"control_points: point for triple \(0, 1, 1\) has 3 coordinates"),
    (lambda d: {**d, (1, 1, 0): [np.nan, 0]}, r"control_points: point for triple \(1, 1, 0\) contains NaN"),
    (lambda d: {**d, (1, -1, 2): [0, 0]}, r"control_points: key \(1, -1, 2\) is not a triple"),
    (lambda d: {(1, 1): [0, 0]}, r"control_points: key \(1, 1\) is not a triple"),
    (lambda d: {(0, 0, 0): [0, 0]}, r"control_points: the degree must be at least 1"),
    (lambda d: {**d, (0, 2, 0): "x"}, r"control_points: point for triple \(0, 2, 0\) is not numeric"),
])
def test_control_point_errors_name_the_triple(build, match):
    with pytest.raises(CagdError, match=match):
        BezierTriangle(build(_quad()))


def test_array_and_weight_errors():
    P = np.zeros((6, 2))
    with pytest.raises(CagdError, match=r"control_points: 5 entries is not \(n\+1\)\(n\+2\)/2"):
        BezierTriangle(np.zeros((5, 2)))
    with pytest.raises(CagdError, match=r"control_points: 1 entries is not"):
        BezierTriangle(np.zeros((1, 2)))
    bad = P.copy()
    bad[4, 1] = np.inf
    with pytest.raises(CagdError, match=r"control_points: point for triple \(0, 1, 1\) \(row 4\)"):
        BezierTriangle(bad)
    with pytest.raises(CagdError, match=r"weights: must be finite and positive \(triple \(1, 0, 1\)"):
        BezierTriangle(P, [1, 1, -1, 1, 1, 1])
    with pytest.raises(CagdError, match=r"weights: expected 6 weights"):
        BezierTriangle(P, [1, 1, 1])
    with pytest.raises(CagdError, match=r"weights: missing triple \(0, 0, 2\)"):
        BezierTriangle(P, {t: 1.0 for t in index_triples(2)[:-1]})
    with pytest.raises(CagdError, match=r"weights: the triples have degree 3"):
        BezierTriangle(P, {t: 1.0 for t in index_triples(3)})
    with pytest.raises(CagdError, match=r"weights: must be finite and positive \(triple \(2, 0, 0\)"):
        BezierTriangle(P, {t: (0.0 if t == (2, 0, 0) else 1.0) for t in index_triples(2)})


def test_parameters_outside_the_triangle_are_rejected():
    t = BezierTriangle(np.random.default_rng(0).normal(size=(10, 3)))
    for u, v in ((-1e-9, 0.2), (0.2, -1e-9), (0.6, 0.4 + 1e-9), (1.5, 0.0)):
        for f in (t, t.de_casteljau, t.bernstein_evaluate):
            with pytest.raises(CagdError, match="u|v"):
                f(u, v)
        with pytest.raises(CagdError):
            t.directional_derivative(u, v, (1, -1, 0))
    t(0.6, 0.4 + 1e-13)                                     # within the 1e-12 tolerance
    with pytest.raises(CagdError, match="us, vs"):
        t.grid([0, 0.5], [0, 0.6])
    with pytest.raises(CagdError, match="direction: a direction must sum to 0"):
        t.directional_derivative(0.2, 0.2, (1, 0, 0))


# --- evaluation --------------------------------------------------------------------------------
@SETTINGS
@given(t=triangles())
def test_three_evaluators_agree_with_the_direct_sum(t):
    u, v = samples()
    expected = oracle(t, u, v)
    tol = 1e-12 * scale(t) * (1 if t.weights is None else t.weights.max() / t.weights.min())
    for f in (t, t.de_casteljau, t.bernstein_evaluate):
        assert np.abs(f(u, v) - expected).max() <= tol


def test_degree_one_is_the_flat_triangle_and_vertices_interpolate():
    P = np.array([[1.0, 2, 3], [4, -1, 0], [0, 0, 5]])    # P_100, P_010, P_001
    t = BezierTriangle(P)
    u, v = samples()
    np.testing.assert_allclose(t(u, v), u[:, None] * P[0] + v[:, None] * P[1] + (1 - u - v)[:, None] * P[2], atol=1e-14)
    q = BezierTriangle(np.random.default_rng(5).normal(size=(15, 2)))
    np.testing.assert_allclose(q([1, 0, 0], [0, 1, 0]), q.control_points[[0, 10, 14]], atol=1e-15)


def test_broadcasting_grid_and_surface_interface():
    t = BezierTriangle(np.random.default_rng(1).normal(size=(10, 3)), np.linspace(0.5, 2, 10))
    assert isinstance(t, Surface)
    u = np.array([[0.0], [0.1], [0.3]])
    v = np.array([[0.0, 0.2, 0.4, 0.7]])
    assert t(u, v).shape == (3, 4, 3)
    np.testing.assert_allclose(t(u, v), t.de_casteljau(u, v), atol=1e-14)
    g = t.grid([0.0, 0.1, 0.3], [0.0, 0.2, 0.4, 0.7], 1, 1)
    np.testing.assert_allclose(g, t.derivative(u, v, 1, 1), atol=1e-12)
    assert t.blossom(np.full((5, 1, 3), 1 / 3), np.full((4, 3), 1 / 3), (1, 0, 0)).shape == (5, 4, 3)


# --- derivatives --------------------------------------------------------------------------------
@SETTINGS
@given(t=triangles(rational=False, max_degree=5))
def test_partials_match_the_power_form(t):
    u, v = samples(20)
    n = t.degree
    D = t.derivatives(u, v, n + 1, n + 1)
    for a in range(n + 2):
        for b in range(n + 2):
            expected = power_partial(t, u, v, a, b)
            ref = max(1.0, np.abs(expected).max())
            assert np.abs(D[a, b] - expected).max() <= 1e-10 * ref * scale(t), (a, b)


@SETTINGS
@given(t=triangles(rational=True, max_degree=5, dims=(2, 3)))
def test_rational_first_partials_by_the_chain_rule_through_to_nurbs(t):
    """S(s, q) = T(s, (1 - s) q): T_v = S_q / (1 - s), T_u = S_s + q T_v."""
    u, v = samples(20)
    u, v = 0.9 * u, 0.9 * v                  # keep 1 - s away from 0
    S = t.to_nurbs()
    q = v / (1 - u)
    d = S.derivatives(u, q, 1, 1)
    Tv = d[0, 1] / (1 - u)[:, None]
    Tu = d[1, 0] + q[:, None] * Tv
    ref = scale(t) * (t.weights.max() / t.weights.min()) ** 2
    assert np.abs(t.derivative(u, v, 1, 0) - Tu).max() <= 1e-9 * ref
    assert np.abs(t.derivative(u, v, 0, 1) - Tv).max() <= 1e-9 * ref


@SETTINGS
@given(t=triangles(max_degree=5), x=bary(), c=st.tuples(st.floats(-2, 2), st.floats(-2, 2)))
def test_directional_derivatives_are_combinations_of_partials(t, x, c):
    """d = a (1,0,-1) + b (0,1,-1): D_d T = a T_u + b T_v, D_d^2 T = a^2 T_uu + 2ab T_uv + b^2 T_vv."""
    a, b = c
    d = (a, b, -a - b)
    P = t.derivatives(x[0], x[1], 2, 2)
    ref = scale(t) * (1 if t.weights is None else (t.weights.max() / t.weights.min()) ** 3) * max(1, a * a + b * b)
    assert np.abs(t.directional_derivative(x[0], x[1], d) - (a * P[1, 0] + b * P[0, 1])).max() <= 1e-10 * ref
    second = a * a * P[2, 0] + 2 * a * b * P[1, 1] + b * b * P[0, 2]
    assert np.abs(t.directional_derivative(x[0], x[1], d, 2) - second).max() <= 1e-9 * ref
    assert np.abs(t.directional_derivative(x[0], x[1], d, 0) - t(x[0], x[1])).max() <= 1e-12 * ref


def test_derivatives_by_central_differences_and_beyond_the_degree():
    rng = np.random.default_rng(7)
    t = BezierTriangle(rng.normal(size=(10, 3)), rng.uniform(0.5, 2, 10))
    u, v, h = 0.3, 0.25, 1e-5
    fd_u = (t(u + h, v) - t(u - h, v)) / (2 * h)
    fd_v = (t(u, v + h) - t(u, v - h)) / (2 * h)
    np.testing.assert_allclose(t.derivative(u, v, 1, 0), fd_u, atol=1e-8)
    np.testing.assert_allclose(t.derivative(u, v, 0, 1), fd_v, atol=1e-8)
    fd_uv = (t.derivative(u, v + h, 1, 0) - t.derivative(u, v - h, 1, 0)) / (2 * h)
    np.testing.assert_allclose(t.derivative(u, v, 1, 1), fd_uv, atol=1e-7)
    p = BezierTriangle(rng.normal(size=(6, 2)))
    assert np.all(p.derivative(u, v, 2, 1) == 0) and np.all(p.directional_derivative(u, v, (1, 1, -2), 3) == 0)


def test_normal_of_a_flat_and_of_a_curved_triangle():
    P = np.array([[1.0, 0, 0], [0, 1, 0], [0, 0, 1]])
    flat = BezierTriangle(P).degree_elevate(2)
    u, v = samples(10)
    expected = np.cross(P[0] - P[2], P[1] - P[2]) / np.sqrt(3)
    np.testing.assert_allclose(flat.normal(u, v), np.tile(expected, (len(u), 1)), atol=1e-14)
    t = BezierTriangle(np.random.default_rng(2).normal(size=(10, 3)))
    su, sv = power_partial(t, u, v, 1, 0), power_partial(t, u, v, 0, 1)
    n = np.cross(su, sv)
    np.testing.assert_allclose(t.normal(u, v), n / np.linalg.norm(n, axis=1, keepdims=True), atol=1e-10)


# --- blossom --------------------------------------------------------------------------------------
@SETTINGS
@given(t=triangles(max_degree=4), data=st.data())
def test_blossom_symmetric_multiaffine_diagonal_and_oracle(t, data):
    n = t.degree
    xs = [data.draw(bary(inside=False)) for _ in range(n)]
    ref = scale(t) * 5.0 ** n * (1 if t.weights is None else t.weights.max())
    f = t.blossom(*xs, homogeneous=True)
    assert np.abs(f - blossom_oracle(t, xs)).max() <= 1e-11 * ref
    perm = data.draw(st.permutations(range(n)))
    assert np.abs(t.blossom(*[xs[i] for i in perm], homogeneous=True) - f).max() <= 1e-11 * ref
    y, alpha = data.draw(bary(inside=False)), data.draw(st.floats(-2, 3))
    mixed = t.blossom(alpha * xs[0] + (1 - alpha) * y, *xs[1:], homogeneous=True)
    affine = alpha * f + (1 - alpha) * t.blossom(y, *xs[1:], homogeneous=True)
    assert np.abs(mixed - affine).max() <= 1e-10 * ref
    x = data.draw(bary())
    assert np.abs(t.blossom(*[x] * n) - t(x[0], x[1])).max() <= 1e-11 * ref


@SETTINGS
@given(t=triangles(max_degree=5))
def test_control_points_are_blossom_values_at_the_vertices(t):
    E = np.eye(3)
    for r, (i, j, k) in enumerate(index_triples(t.degree)):
        got = t.blossom(*([E[0]] * i + [E[1]] * j + [E[2]] * k))
        assert np.abs(got - t.control_points[r]).max() <= 1e-12 * scale(t)


def test_seed_monomial_polar_forms_and_the_seed_uv_misprint():
    """seed 003, 3.1: polar forms of 1, u, v, u^2, uv, v^2 as degree-2 triangles
    (P_ijk = f(e1^i e2^j e3^k) read off the polar form). The seed prints
    (u1 v1 + u1 v2 + u2 v1 + u2 v2)/4 for uv; that is not affine in one argument,
    the blossom is (u1 v2 + u2 v1)/2."""
    T = index_triples(2)
    mono = {
        "1": ({t: 1.0 for t in T}, lambda a, b: 1.0),
        "u": ({t: t[0] / 2 for t in T}, lambda a, b: (a[0] + b[0]) / 2),
        "v": ({t: t[1] / 2 for t in T}, lambda a, b: (a[1] + b[1]) / 2),
        "uu": ({t: float(t == (2, 0, 0)) for t in T}, lambda a, b: a[0] * b[0]),
        "uv": ({t: 0.5 * (t == (1, 1, 0)) for t in T}, lambda a, b: (a[0] * b[1] + b[0] * a[1]) / 2),
        "vv": ({t: float(t == (0, 2, 0)) for t in T}, lambda a, b: a[1] * b[1]),
    }
    rng = np.random.default_rng(4)
    a, b = rng.uniform(-1, 2, 2), rng.uniform(-1, 2, 2)
    A, B = np.append(a, 1 - a.sum()), np.append(b, 1 - b.sum())
    for name, (cp, polar) in mono.items():
        t = BezierTriangle(cp)
        assert abs(t.blossom(A, B)[0] - polar(a, b)) < 1e-14, name
        x = rng.uniform(0, 0.5, 2)
        assert abs(t(x[0], x[1])[0] - polar(x, x)) < 1e-14, name
    seed_uv = (a[0] * a[1] + a[0] * b[1] + b[0] * a[1] + b[0] * b[1]) / 4
    assert abs(BezierTriangle(mono["uv"][0]).blossom(A, B)[0] - seed_uv) > 1e-3


def test_blossom_argument_errors():
    t = BezierTriangle(np.zeros((6, 2)))
    with pytest.raises(CagdError, match="args: .* takes 2"):
        t.blossom((1, 0, 0))
    with pytest.raises(CagdError, match=r"x2: barycentric coordinates must sum to 1"):
        t.blossom((1, 0, 0), (0.5, 0.5, 0.5))
    with pytest.raises(CagdError, match=r"x1: expected barycentric triples"):
        t.blossom((1, 0), (1, 0, 0))


# --- operations ---------------------------------------------------------------------------------------
def _check_piece(t, piece, V, tol):
    u, v = samples(15, seed=9)
    y = np.stack([u, v, 1 - u - v], axis=1)
    x = y @ np.asarray(V, dtype=float)
    assert np.abs(piece(u, v) - t(x[:, 0], x[:, 1])).max() <= tol


@SETTINGS
@given(t=triangles(), p=bary())
def test_subdivide_at_a_point(t, p):
    p = 0.02 + 0.94 * p                          # strictly inside
    pieces = t.subdivide(p)
    E = np.eye(3)
    tol = 1e-11 * scale(t) * (1 if t.weights is None else t.weights.max() / t.weights.min())
    for r, piece in enumerate(pieces):
        V = [p if s == r else E[s] for s in range(3)]
        _check_piece(t, piece, V, tol)
        assert piece.degree == t.degree and piece.is_rational == t.is_rational


@SETTINGS
@given(t=triangles())
def test_subdivide_at_edge_midpoints(t):
    e1, e2, e3 = np.eye(3)
    m12, m23, m31 = (e1 + e2) / 2, (e2 + e3) / 2, (e3 + e1) / 2
    tol = 1e-11 * scale(t) * (1 if t.weights is None else t.weights.max() / t.weights.min())
    for piece, V in zip(t.subdivide_midpoints(), [(e1, m12, m31), (m12, e2, m23), (m31, m23, e3), (m23, m31, m12)]):
        _check_piece(t, piece, V, tol)


def test_subdivide_errors_and_continuation_outside():
    t = BezierTriangle(np.random.default_rng(6).normal(size=(10, 3)))
    for bad in ((0.5, 0.5, 0.0), (1.2, -0.1, -0.1), (0.3, 0.3, 0.3)):
        with pytest.raises(CagdError, match="point"):
            t.subdivide(bad)
    V = np.array([[1.5, -0.5, 0.0], [-0.5, 1.0, 0.5], [0.2, -0.6, 1.4]])
    big = t.subtriangle(*V)
    u, v = samples(15)
    x = np.stack([u, v, 1 - u - v], axis=1) @ V
    np.testing.assert_allclose(big(u, v), power_partial(t, x[:, 0], x[:, 1], 0, 0), atol=1e-11)


@SETTINGS
@given(t=triangles(max_degree=5), times=st.integers(0, 3))
def test_degree_elevation(t, times):
    e = t.degree_elevate(times)
    assert e.degree == t.degree + times
    u, v = samples(20)
    tol = 1e-12 * scale(t) * (1 if t.weights is None else t.weights.max() / t.weights.min())
    assert np.abs(e(u, v) - t(u, v)).max() <= tol


def test_elevating_a_flat_triangle_gives_the_linear_net():
    P = np.array([[1.0, 2, 3], [4, -1, 0], [0, 0, 5]])
    e = BezierTriangle(P).degree_elevate(3)
    expected = [(i * P[0] + j * P[1] + k * P[2]) / 4 for i, j, k in index_triples(4)]
    np.testing.assert_allclose(e.control_points, expected, atol=1e-14)


@pytest.mark.parametrize("order", list(itertools.permutations(range(3))))
def test_relabeled(order):
    t = BezierTriangle(np.random.default_rng(8).normal(size=(10, 2)), np.linspace(1, 2, 10))
    r = t.relabeled(order)
    u, v = samples(10)
    y = np.stack([u, v, 1 - u - v], axis=1)
    x = np.empty_like(y)
    x[:, list(order)] = y
    np.testing.assert_allclose(r(u, v), t(x[:, 0], x[:, 1]), atol=1e-13)


def test_transformed_isocurves_and_boundaries():
    rng = np.random.default_rng(10)
    t = BezierTriangle(rng.normal(size=(10, 3)), rng.uniform(0.5, 2, 10))
    A, b = rng.normal(size=(3, 3)), rng.normal(size=3)
    u, v = samples(10)
    np.testing.assert_allclose(t.transformed(A, b)(u, v), t(u, v) @ A.T + b, atol=1e-12)
    for c in (0.0, 0.3, 0.9):
        s = np.linspace(0, 1 - c, 9)
        np.testing.assert_allclose(t.isocurve("u", c)(s), t(s, c + 0 * s), atol=1e-13)
        np.testing.assert_allclose(t.isocurve("v", c)(s), t(c + 0 * s, s), atol=1e-13)
    with pytest.raises(CagdError, match="value"):
        t.isocurve("u", 1.0)
    s = np.linspace(0, 1, 9)
    e12, e23, e31 = t.boundaries()
    np.testing.assert_allclose(e12(s), t(1 - s, s), atol=1e-13)
    np.testing.assert_allclose(e23(s), t(0 * s, 1 - s), atol=1e-13)
    np.testing.assert_allclose(e31(s), t(s, 0 * s), atol=1e-13)


# --- exact tensor-product form -------------------------------------------------------------------
@SETTINGS
@given(t=triangles(min_degree=1, max_degree=6, dims=(2, 3)))
def test_to_nurbs_is_the_duffy_reparametrisation(t):
    S = t.to_nurbs()
    assert isinstance(S, BSplineSurface) and (S.degree_u, S.degree_v) == (t.degree, t.degree)
    assert S.is_rational == t.is_rational
    s, q = np.meshgrid(np.linspace(0, 1, 13), np.linspace(0, 1, 11), indexing="ij")
    s, q = s.ravel(), q.ravel()
    err = np.abs(S(s, q) - t(s, (1 - s) * q)).max()
    assert err <= 1e-12 * scale(t)
    B = t.to_bezier_surface()
    assert isinstance(B, BezierSurface)
    collapsed = np.tile(t.control_points[0], (t.degree + 1, 1))        # row s = 1: P_n00
    np.testing.assert_allclose(B.control_points[-1], collapsed, atol=1e-12 * scale(t))
    np.testing.assert_allclose(B.control_points[0, 0], t.control_point(0, 0, t.degree))
    np.testing.assert_allclose(B.control_points[0, -1], t.control_point(0, t.degree, 0))


def test_to_nurbs_degree_one_by_hand():
    """n = 1: Q_00 = P_001, Q_01 = P_010, Q_10 = Q_11 = P_100 (bilinear, collapsed edge s = 1)."""
    P = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    B = BezierTriangle(P).to_bezier_surface()
    np.testing.assert_array_equal(B.control_points, [[P[2], P[1]], [P[0], P[0]]])


def test_rational_triangle_overflowing_homogeneous_net_is_an_error():
    with pytest.raises(CagdError, match="overflow"):
        BezierTriangle([[-1e300, 0, 0]] + [[1, 1, 1]] * 9, [1e12] + [1] * 9)


# --- limits (issue 14) ---------------------------------------------------------------------
def _exact_triangle_value(P, n, u, v):
    """sum n!/(i! j! k!) u^i v^j w^k P_ijk in exact integer arithmetic (u, v and the
    points are dyadic rationals), rounded once to float."""
    from fractions import Fraction
    (nu, du), (nv, dv) = Fraction(u).as_integer_ratio(), Fraction(v).as_integer_ratio()
    den = max(du, dv)
    nu, nv = nu * (den // du), nv * (den // dv)
    nw = den - nu - nv
    ratios = [[Fraction(float(x)).as_integer_ratio() for x in p] for p in P]
    L = max(d for row in ratios for _, d in row)
    total = [0] * P.shape[1]
    for (i, j, k), row in zip(index_triples(n), ratios):
        b = factorial(n) // (factorial(i) * factorial(j) * factorial(k)) * nu ** i * nv ** j * nw ** k
        for d, (num, dd) in enumerate(row):
            total[d] += b * num * (L // dd)
    return np.array([float(Fraction(t, den ** n * L)) for t in total])


def test_degree_above_max_degree_is_refused():
    """BezierTriangle had no MAX_DEGREE check (the multinomials overflow above 170)."""
    from cagd import MAX_DEGREE
    n = MAX_DEGREE + 1
    N = (n + 1) * (n + 2) // 2
    with pytest.raises(CagdError, match=r"control_points: .*degree 129.*MAX_DEGREE = 128"):
        BezierTriangle(np.zeros((N, 3)))
    with pytest.raises(CagdError, match="control_points: .*MAX_DEGREE"):
        BezierTriangle({t: (0.0, 0.0) for t in index_triples(n)})
    ok = BezierTriangle(np.zeros((3, 2)))
    with pytest.raises(CagdError, match="weights: .*MAX_DEGREE"):
        ok.with_weights({t: 1.0 for t in index_triples(n)})
    with pytest.raises(CagdError, match="times: raising degree 1 by 128"):
        ok.degree_elevate(MAX_DEGREE)
    with pytest.raises(CagdError, match="times"):
        ok.degree_elevate(10 ** 18)
    with pytest.raises(CagdError, match="order"):
        ok.directional_derivative(0.2, 0.3, (1, 0, -1), 10 ** 18)


def test_max_degree_triangle_evaluates_exactly_in_bounded_memory():
    """Degree 128 against exact rational arithmetic; the Bernstein matrix is built
    per chunk (it was (points, 8385) at once: 2,000 points held ~0.5 GB)."""
    import tracemalloc
    from cagd import MAX_DEGREE
    n = MAX_DEGREE
    rng = np.random.default_rng(7)
    P = rng.random(((n + 1) * (n + 2) // 2, 3))
    T = BezierTriangle(P)
    u, v = rng.random(2000) * 0.6, rng.random(2000) * 0.4
    tracemalloc.start()
    try:
        got = T(u, v)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200e6
    for r in (0, 1234):
        assert np.abs(got[r] - _exact_triangle_value(P, n, u[r], v[r])).max() <= 1e-12
    assert np.abs(T.de_casteljau(u[:20], v[:20]) - got[:20]).max() <= 1e-12


@pytest.mark.parametrize("n,times", [(3, 5), (40, 60)])
def test_high_degree_elevation_is_the_same_triangle(n, times):
    rng = np.random.default_rng(n)
    N = (n + 1) * (n + 2) // 2
    T = BezierTriangle(rng.random((N, 3)), rng.uniform(0.5, 2.0, N))
    E = T.degree_elevate(times)
    assert E.degree == n + times
    u, v = rng.random(200) * 0.5, rng.random(200) * 0.5
    assert np.abs(E(u, v) - T.de_casteljau(u, v)).max() <= 1e-12
