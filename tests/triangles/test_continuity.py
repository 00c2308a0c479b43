"""Continuity of Bezier triangles across a shared edge (seed 003, 3.2)."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cagd import CagdError
from cagd.triangles import BezierTriangle, c1_neighbor, index_triples, neighbor_vertices, triangle_continuity

from strategies import point_arrays

SETTINGS = settings(max_examples=50, deadline=None)


@st.composite
def triangles(draw, min_degree=1, max_degree=5, rational=None):
    n = draw(st.integers(min_degree, max_degree))
    N = (n + 1) * (n + 2) // 2
    P = draw(point_arrays(N, 3))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = None
    if is_rational:     # weights near 1 so that the continuation stays positive
        w = np.array(draw(st.lists(st.floats(0.8, 1.25), min_size=N, max_size=N)))
    return BezierTriangle(P, w)


@st.composite
def apexes(draw, edge):
    """An apex across ``edge``: D_e in [-1.5, -0.2], the other two free in [-0.5, 1.5]."""
    D = np.zeros(3)
    D[edge] = draw(st.floats(-1.5, -0.2))
    D[(edge + 1) % 3] = draw(st.floats(-0.5, 1.5))
    D[(edge + 2) % 3] = 1.0 - D[edge] - D[(edge + 1) % 3]
    return D


def scale(*ts):
    return max(1.0, *(float(np.abs(t.control_points).max()) for t in ts))


def one_sided_slopes(t1, t2, M, s, h=1e-4):
    """phi(h) = surface at x + h (D - x), x on the edge: t1 for h <= 0, t2 for h >= 0.
    Second-order one-sided differences of each side at 0 (independent of the
    derivative code)."""
    x1 = np.outer(1 - s, M[1]) + np.outer(s, M[0])
    d1 = M[2] - x1
    Minv = np.linalg.inv(M)

    def phi(hh):
        p = x1 + hh * d1
        if hh <= 0:
            return t1(p[:, 0], p[:, 1])
        y = p @ Minv
        return t2(y[:, 0], y[:, 1])

    left = (3 * phi(0.0) - 4 * phi(-h) + phi(-2 * h)) / (2 * h)
    right = (-3 * phi(0.0) + 4 * phi(h) - phi(2 * h)) / (2 * h)
    x2 = x1 @ Minv
    value_gap = np.abs(t1(x1[:, 0], x1[:, 1]) - t2(x2[:, 0], x2[:, 1])).max()
    return left, right, value_gap


def test_neighbor_vertices_layout_and_default_apex():
    """Seed 003, 3.2: T1 = {a, b, c}, T2 = {c, b, d}; the default d = b + c - a."""
    M = neighbor_vertices(0)
    np.testing.assert_array_equal(M, [[0, 0, 1], [0, 1, 0], [-1, 1, 1]])
    np.testing.assert_array_equal(neighbor_vertices(1, (0.2, -0.5)), [[1, 0, 0], [0, 0, 1], [0.2, -0.5, 1.3]])
    np.testing.assert_array_equal(neighbor_vertices(2, (0.7, 0.8, -0.5))[:2], [[0, 1, 0], [1, 0, 0]])
    for bad, match in (((0.2, 0.2, 0.6), "apex: .* must lie across edge 0"), ((1, 1, 1), "apex: barycentric"),
                       ((1, 2, 3, 4), "apex: expected")):
        with pytest.raises(CagdError, match=match):
            neighbor_vertices(0, bad)
    with pytest.raises(CagdError, match="edge"):
        neighbor_vertices(3)


def test_seed_quadratic_conditions():
    """Seed 003, 3.2 for two quadratics: C0 is f(b,b) = g(b,b), f(b,c) = g(b,c), f(c,c) = g(c,c);
    C1 adds f(a,b) = g(a,b), f(b,d) = g(b,d), f(a,c) = g(a,c), f(c,d) = g(c,d). Each
    blossom is evaluated in its own triangle's barycentric coordinates."""
    rng = np.random.default_rng(11)
    t1 = BezierTriangle(rng.normal(size=(6, 3)))
    D = np.array([-0.6, 0.9, 0.7])
    t2 = c1_neighbor(t1, 0, D, free={(0, 0, 2): [7.0, 7.0, 7.0]})
    M = neighbor_vertices(0, D)
    to2 = np.linalg.inv(M)                                  # t1 coordinates -> t2 coordinates
    a, b, c = np.eye(3)
    pairs = [(b, b), (b, c), (c, c), (a, b), (b, D), (a, c), (c, D)]
    for x, y in pairs:
        np.testing.assert_allclose(t1.blossom(x, y), t2.blossom(x @ to2, y @ to2), atol=1e-12)
    # the free point g(d, d) breaks C2 only: f(d, d) != g(d, d)
    assert np.abs(t1.blossom(D, D) - t2.blossom(D @ to2, D @ to2)).max() > 1
    r = triangle_continuity(t1, t2, 0, D, order=2)
    assert r.continuity_order() == 1 and r.is_continuous(1) and not r.is_continuous(2)
    with pytest.warns(DeprecationWarning, match="rel_tol"):       # the old keyword, one release
        assert r.is_continuous(1, tol=1e-9) and r.continuity_order(tol=1e-9) == 1


@SETTINGS
@given(t1=triangles(), data=st.data())
def test_c1_neighbor_is_c1_and_free_rows_only_break_c2(t1, data):
    n = t1.degree
    edge = data.draw(st.integers(0, 2))
    D = data.draw(apexes(edge))
    free = {t: data.draw(point_arrays(1, 3))[0] for t in index_triples(n) if t[2] >= 2}
    try:
        t2 = c1_neighbor(t1, edge, D, free=free)
    except CagdError:
        assume(False)                         # rational continuation with non-positive weights
    M = neighbor_vertices(edge, D)
    s = np.linspace(0.1, 0.9, 7)
    left, right, gap = one_sided_slopes(t1, t2, M, s)
    ref = scale(t1, t2)
    assert gap <= 1e-11 * ref
    assert np.abs(left - right).max() <= 1e-5 * ref              # finite differences, h = 1e-4
    r = triangle_continuity(t1, t2, edge, D, order=n)
    assert max(r.control_deviations[:2]) <= 1e-11 * ref
    assert max(r.derivative_deviations[:2]) <= 1e-10 * ref * 10.0 ** (1 if t1.is_rational else 0)
    assert r.continuity_order() >= 1
    full = c1_neighbor(t1, edge, D)                               # default fill: the continuation
    assert triangle_continuity(t1, full, edge, D, order=n).continuity_order() == n


@SETTINGS
@given(t1=triangles(min_degree=2, rational=False), data=st.data())
def test_perturbing_the_c1_row_is_detected(t1, data):
    n = t1.degree
    edge = data.draw(st.integers(0, 2))
    D = data.draw(apexes(edge))
    t2 = c1_neighbor(t1, edge, D)
    P = t2.control_points.copy()
    row1 = [r for r, t in enumerate(index_triples(n)) if t[2] == 1]
    P[data.draw(st.sampled_from(row1))] += [0.5, -0.25, 1.0]
    bad = BezierTriangle(P)
    r = triangle_continuity(t1, bad, edge, D)
    assert r.control_deviations[0] <= 1e-12 * scale(t1) and r.control_deviations[1] > 0.5
    assert r.derivative_deviations[1] > 1e-3 and r.continuity_order() == 0
    left, right, _ = one_sided_slopes(t1, bad, neighbor_vertices(edge, D), np.linspace(0.1, 0.9, 9))
    assert np.abs(left - right).max() > 1e-3


@SETTINGS
@given(t=triangles(max_degree=4), p=st.tuples(st.floats(0.05, 0.9), st.floats(0.05, 0.9)))
def test_pieces_of_a_subdivision_join_with_full_continuity(t, p):
    """T0 = (p, e2, e3) and T1 = (e1, p, e3) share the edge p-e3; T0's edge 1 runs
    V2 = e3 -> V0 = p, so the neighbour layout (V0, V2, D) is T1 relabeled to (p, e3, e1)."""
    assume(p[0] + p[1] < 0.95)
    p = np.array([p[0], p[1], 1 - p[0] - p[1]])
    T0, T1, _ = t.subdivide(p)
    E = np.eye(3)
    apex = np.linalg.solve(np.array([p, E[1], E[2]]).T, E[0])   # e1 in T0's coordinates
    r = triangle_continuity(T0, T1.relabeled((1, 2, 0)), edge=1, apex=apex, order=t.degree)
    ref = scale(t) * (1 if t.weights is None else 4.0)
    assert max(r.control_deviations) <= 1e-9 * ref * 10 ** t.degree
    assert r.continuity_order(rel_tol=1e-9 * 10 ** t.degree) == t.degree


def test_rational_neighbor_and_free_weights():
    rng = np.random.default_rng(12)
    t1 = BezierTriangle(rng.normal(size=(10, 3)), rng.uniform(0.9, 1.1, 10))
    D = np.array([0.6, -0.4, 0.8])
    t2 = c1_neighbor(t1, 1, D, free={(0, 0, 3): [1.0, 2.0, 3.0]}, free_weights={(1, 0, 2): 3.0})
    assert t2.is_rational
    left, right, gap = one_sided_slopes(t1, t2, neighbor_vertices(1, D), np.linspace(0.1, 0.9, 9))
    assert gap < 1e-13 and np.abs(left - right).max() < 1e-5
    poly = BezierTriangle(rng.normal(size=(10, 3)))
    t3 = c1_neighbor(poly, 2, None, free_weights={(0, 1, 2): 2.0})
    assert t3.is_rational and t3.weights[index_triples(3).index((0, 1, 2))] == 2.0
    r = triangle_continuity(poly, t3, 2, order=2)
    assert r.continuity_order() == 1 and r.derivative_deviations[1] < 1e-12


def test_continuity_errors():
    rng = np.random.default_rng(13)
    t1, t2 = BezierTriangle(rng.normal(size=(6, 3))), BezierTriangle(rng.normal(size=(10, 3)))
    with pytest.raises(CagdError, match="t2: degree 3 differs"):
        triangle_continuity(t1, t2)
    with pytest.raises(CagdError, match="t2: dimension"):
        triangle_continuity(t1, BezierTriangle(rng.normal(size=(6, 2))))
    with pytest.raises(CagdError, match="t1: expected a BezierTriangle"):
        triangle_continuity("x", t1)
    with pytest.raises(CagdError, match="order"):
        triangle_continuity(t1, t1.relabeled((1, 0, 2)), order=3)
    with pytest.raises(CagdError, match=r"free: triple \(1, 0, 1\) is fixed by C1"):
        c1_neighbor(t1, 0, free={(1, 0, 1): [0, 0, 0]})
    with pytest.raises(CagdError, match=r"free: triple \(1, 0, 3\) does not sum"):
        c1_neighbor(t1, 0, free={(1, 0, 3): [0, 0, 0]})
    with pytest.raises(CagdError, match=r"free: point for triple \(0, 0, 2\) has 2 coordinates"):
        c1_neighbor(t1, 0, free={(0, 0, 2): [0, 0]})
    with pytest.raises(CagdError, match=r"free_weights: the weight of the free triple \(0, 0, 2\)"):
        c1_neighbor(t1, 0, free_weights={(0, 0, 2): -1.0})
    with pytest.raises(CagdError, match="apex: the continuation of the rational t1"):
        c1_neighbor(BezierTriangle(rng.normal(size=(6, 3)), [1, 50.0, 1, 1, 1, 1]), 0, (-1, 1, 1))
