"""Bezier joins (seed 000, 5.2.5): the seed's formulas, and the continuity they give,
measured independently on the resulting curves (tangent, curvature, Frenet frame)."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.operations import continuity, join, join_bezier, join_control_points
from strategies import point_arrays, positive_weights

SETTINGS = settings(max_examples=50, deadline=None)

P3 = BezierCurve([[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [3.0, 2.5, -0.5], [4.0, 0.0, 1.0]])


def seed_q2(P, alpha, beta):
    """Seed 000, 5.2.5: Q2 = (a^2 + 2a + b/(n-1) + 1) Pn - (2a^2 + 2a + b/(n-1)) Pn-1 + a^2 Pn-2."""
    n, C = P.degree, P.control_points
    a, b = alpha, beta / (n - 1)
    return (a * a + 2 * a + b + 1) * C[-1] - (2 * a * a + 2 * a + b) * C[-2] + a * a * C[-3]


def non_degenerate_end(P):
    d = P.derivatives(1.0, 2)
    c = np.linalg.norm(np.cross(d[1], d[2]))
    return c > 1e-2 * np.linalg.norm(d[1]) * max(np.linalg.norm(d[2]), 1e-300)


def test_g0_g1_by_the_seed():
    Q = join_control_points(P3, "G0")
    assert Q.shape == (1, 3) and np.array_equal(Q[0], P3.control_points[-1])
    Q = join_control_points(P3, "G1", alpha=0.6)
    a_n = P3.control_points[-1] - P3.control_points[-2]
    assert np.allclose(Q[1] - Q[0], 0.6 * a_n, rtol=0, atol=1e-15)     # b_1 = alpha a_n


@pytest.mark.parametrize("alpha, beta", [(1.0, 0.0), (0.5, 0.0), (2.0, -1.5), (0.3, 4.0)])
def test_g2_equals_seed_formula(alpha, beta):
    Q = join_control_points(P3, "G2", alpha, beta)
    assert Q.shape == (3, 3)
    assert np.allclose(Q[2], seed_q2(P3, alpha, beta), rtol=0, atol=1e-13)
    # the seed's rewritten form: Q2 - Pn = (a^2 + 2a + b/(n-1)) a_n - a^2 a_(n-1)
    C, n = P3.control_points, P3.degree
    rhs = (alpha ** 2 + 2 * alpha + beta / (n - 1)) * (C[-1] - C[-2]) - alpha ** 2 * (C[-2] - C[-3])
    assert np.allclose(Q[2] - C[-1], rhs, rtol=0, atol=1e-13)


def test_general_degree_reduces_to_seed():
    """For m = n the general formula is the seed's; for m != n it satisfies the
    defining derivative conditions Q'(0) = gamma P'(1), Q''(0) = gamma^2 P''(1) + beta P'(1)."""
    alpha, beta = 0.8, 0.7
    n = P3.degree
    for m in (2, 3, 4, 6):
        Q = join(P3, np.ones((m - 2, 3)) * [5.0, 1.0, 0.0] + np.arange(m - 2)[:, None], "G2", alpha, beta)
        assert Q.degree == m
        if m == n:
            assert np.allclose(Q.control_points[2], seed_q2(P3, alpha, beta), rtol=0, atol=1e-13)
        gamma = m * alpha / n
        dP, dQ = P3.derivatives(1.0, 2), Q.derivatives(0.0, 2)
        assert np.allclose(dQ[1], gamma * dP[1], rtol=0, atol=1e-12)
        assert np.allclose(dQ[2], gamma ** 2 * dP[2] + beta * dP[1], rtol=0, atol=1e-11)


def test_g1_join_measured():
    Q = join(P3, [[6.0, 1.0, 0.0], [7.0, 3.0, 1.0]], "G1", alpha=0.4)
    T1, T2 = P3.tangent(1.0), Q.tangent(0.0)
    assert np.allclose(T1, T2, rtol=0, atol=1e-14)          # parallel, same direction
    r = continuity(P3, Q)
    assert r.G1 and not r.C1 and r.level == "G1"
    assert Q.degree == 3 and r.derivative_ratio == pytest.approx(0.4, rel=1e-14)   # gamma = alpha for m = n
    Q5 = join(P3, [[6.0, 1.0, 0.0], [7.0, 3.0, 1.0], [8, 0, 0], [9, 1, 1]], "G1", alpha=0.4)
    assert continuity(P3, Q5).derivative_ratio == pytest.approx(5 * 0.4 / 3, rel=1e-14)   # gamma = m alpha / n


def test_g2_coplanar_and_same_side():
    """Seed 000, 5.2.5: P_{n-2}, P_{n-1}, P_n = Q_0, Q_1, Q_2 coplanar, and P_{n-2}
    and Q_2 on the same side of the line P_{n-1} Q_1."""
    Q = join_control_points(P3, "G2", alpha=1.3, beta=-0.4)
    C = P3.control_points
    five = np.vstack([C[-3:], Q[1:]])
    s = np.linalg.svd(five - five.mean(axis=0), compute_uv=False)
    assert s[2] <= 1e-13 * s[0]
    d = C[-1] - C[-2]
    d /= np.linalg.norm(d)

    def perp(x):
        v = x - C[-2]
        return v - (v @ d) * d
    assert perp(C[-3]) @ perp(Q[2]) > 0


@SETTINGS
@given(st.integers(2, 6), st.integers(2, 7), st.floats(0.2, 5.0), st.floats(-3.0, 3.0), st.data())
def test_g2_join_property(n, m, alpha, beta, data):
    P = BezierCurve(data.draw(point_arrays(n + 1, 3)))
    assume(np.linalg.norm(P.derivative(1.0)) > 1e-1 and non_degenerate_end(P))
    rest = data.draw(point_arrays(m - 2, 3)) if m > 2 else None
    Q = join(P, rest, "G2", alpha, beta)
    assert Q.degree == m
    kP, kQ = P.curvature(1.0), Q.curvature(0.0)
    assert kQ == pytest.approx(kP, rel=1e-8)
    TP, NP, BP = P.frenet(1.0)
    TQ, NQ, BQ = Q.frenet(0.0)
    for u, v in ((TP, TQ), (NP, NQ), (BP, BQ)):
        assert np.abs(u - v).max() <= 1e-8
    r = continuity(P, Q, rel_tol=1e-8)
    assert r.G2 and r.derivative_ratio == pytest.approx(m * alpha / n, rel=1e-12)
    if m == n:
        assert np.allclose(Q.control_points[2], seed_q2(P, alpha, beta), rtol=0,
                           atol=1e-12 * max(1.0, np.abs(P.control_points).max()) * (alpha + 1) ** 2 * (1 + abs(beta)))
    five = np.vstack([P.control_points[-3:], Q.control_points[1:3]]) if m == n else None
    if five is not None:
        s = np.linalg.svd(five - five.mean(axis=0), compute_uv=False)
        assert s[2] <= 1e-10 * s[0]


@SETTINGS
@given(st.integers(2, 5), st.floats(0.2, 5.0), st.floats(-3.0, 3.0), st.data())
def test_rational_g2_join(n, alpha, beta, data):
    P = BezierCurve(data.draw(point_arrays(n + 1, 3)),
                    data.draw(st.lists(positive_weights, min_size=n + 1, max_size=n + 1)))
    assume(np.linalg.norm(P.derivative(1.0)) > 1e-1 and non_degenerate_end(P))
    Q = join(P, data.draw(point_arrays(2, 3)), "G2", alpha, beta)
    w = P.weights
    a_n = P.control_points[-1] - P.control_points[-2]
    assert np.allclose(Q.control_points[1] - Q.control_points[0], alpha * w[-2] / w[-1] * a_n,
                       rtol=1e-12, atol=1e-12)
    assert Q.curvature(0.0) == pytest.approx(P.curvature(1.0), rel=1e-8)
    assert continuity(P, Q, rel_tol=1e-8).G2


def test_c1_c2_joins():
    Q = join(P3, [[6.0, 1.0, 0.0], [7.0, 3.0, 1.0], [8.0, 0.0, 0.0]], "C2")     # m = 5 != n = 3
    dP, dQ = P3.derivatives(1.0, 2), Q.derivatives(0.0, 2)
    assert np.allclose(dP, dQ, rtol=0, atol=1e-12)
    assert continuity(P3, Q).level == "C2"
    Q = join(P3, [[6.0, 1.0, 0.0]], "C1")                                        # m = 2
    r = continuity(P3, Q)
    assert r.C1 and not r.G2 and r.level == "C1"


def test_planar_join():
    P = BezierCurve([[0, 0], [1, 1], [2, 1], [3, 0]])
    Q = join(P, [[5, -1], [6, 0]], "G2", alpha=2.0, beta=1.0)
    assert Q.curvature(0.0) == pytest.approx(P.curvature(1.0), rel=1e-12)
    assert continuity(P, Q).level == "G2"


@pytest.mark.parametrize("kwargs, match", [
    (dict(continuity="G1", alpha=0.0), "alpha: must be positive"),
    (dict(continuity="G2", alpha=-1.0), "alpha: must be positive"),
    (dict(continuity="G3"), "continuity: must be one of"),
    (dict(continuity="C1", alpha=2.0), "alpha: C1 fixes"),
    (dict(continuity="C2", beta=1.0), "beta: C2 fixes"),
    (dict(continuity="G2", degree=1), "degree"),
    (dict(continuity="G1", alpha=float("nan")), "alpha: must be finite"),
])
def test_join_control_points_errors(kwargs, match):
    with pytest.raises(CagdError, match=match):
        join_control_points(P3, **kwargs)


def test_join_errors():
    with pytest.raises(CagdError, match="P: must be a BezierCurve"):
        join(BSplineCurve([[0, 0], [1, 1], [2, 0]], 2), [[3, 3]])
    with pytest.raises(CagdError, match="rest_points: P is 3-D"):
        join(P3, [[1.0, 2.0]])
    with pytest.raises(CagdError, match="rest_points: a G0 join needs at least 1"):
        join(P3, None, "G0")
    line = join(P3, None, "G1", alpha=2.0)            # Q fully determined: a line segment
    assert line.degree == 1 and continuity(P3, line).G1


def test_join_bezier_is_the_deprecated_join_control_points():
    """join_bezier keeps returning the leading control points for one release, warning
    that they are join_control_points (and the curve is join)."""
    with pytest.warns(DeprecationWarning, match="join_control_points") as rec:
        old = join_bezier(P3, "G2", 1.3, -0.4)
    assert rec[0].filename == __file__
    np.testing.assert_array_equal(old, join_control_points(P3, "G2", 1.3, -0.4))
    curve = join(P3, [P3.control_points[-1] + 1.0], "G2", 1.3, -0.4)
    assert isinstance(curve, cagd.BezierCurve)
    np.testing.assert_array_equal(curve.control_points[:3], old)
