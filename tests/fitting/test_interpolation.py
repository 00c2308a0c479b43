"""Bezier through points (seed 000, 5.2.6), B-spline interpolation and least-squares
approximation (Piegl & Tiller 9.2.1, 9.4.1) against scipy and hand-written formulas."""
import numpy as np
import pytest
from hypothesis import given, settings, assume
from hypothesis import strategies as st
from scipy.interpolate import BSpline, make_interp_spline, make_lsq_spline

from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.fitting import approximate, approximation_knots, bezier_through_points, interpolate, parametrize
from strategies import point_arrays

SETTINGS = settings(max_examples=40, deadline=None)


def well_spread(Q, min_step=0.05):
    return np.all(np.linalg.norm(np.diff(Q, axis=0), axis=1) > min_step)


# --- parameters -------------------------------------------------------------------------
def test_parametrize_by_hand():
    Q = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]])          # chords 5 and 1
    assert np.allclose(parametrize(Q, "uniform"), [0.0, 0.5, 1.0], rtol=0, atol=1e-15)
    assert np.allclose(parametrize(Q, "chord"), [0.0, 5 / 6, 1.0], rtol=0, atol=1e-15)
    r5 = np.sqrt(5.0)
    assert np.allclose(parametrize(Q, "centripetal"), [0.0, r5 / (r5 + 1), 1.0], rtol=0, atol=1e-15)
    assert np.array_equal(parametrize(Q, [0.0, 0.2, 3.0]), [0.0, 0.2, 3.0])


@pytest.mark.parametrize("bad, word", [
    ("spline", "unknown parametrisation"),
    ([0.0, 1.0], "expected 3"),
    ([0.0, 0.5, 0.5], "strictly increasing"),
])
def test_parametrize_rejects(bad, word):
    with pytest.raises(CagdError, match="parameters") as e:
        parametrize([[0, 0], [1, 0], [2, 1]], bad)
    assert word in str(e.value)


def test_coincident_points_rejected_for_chord():
    with pytest.raises(CagdError, match=r"points: points\[1\] and points\[2\] coincide"):
        parametrize([[0, 0], [1, 0], [1, 0], [2, 1]], "chord")


# --- Bezier through points (seed 000, 5.2.6) --------------------------------------------
def test_seed_system_n3_by_hand():
    """The seed's system for n = 3, t_i = i/3: rows C(3,j) (i/3)^j (1-i/3)^(3-j)."""
    Q = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.5], [4.0, 0.0]])
    M = np.array([[1, 0, 0, 0],
                  [8 / 27, 12 / 27, 6 / 27, 1 / 27],
                  [1 / 27, 6 / 27, 12 / 27, 8 / 27],
                  [0, 0, 0, 1]])
    P = np.linalg.solve(M, Q)
    c = bezier_through_points(Q)
    assert isinstance(c, BezierCurve) and c.degree == 3
    assert np.allclose(c.control_points, P, rtol=0, atol=1e-14)
    # closed form of the inverse: P1 = (-5 Q0 + 18 Q1 - 9 Q2 + 2 Q3)/6, P2 symmetric
    assert np.allclose(c.control_points[1], (-5 * Q[0] + 18 * Q[1] - 9 * Q[2] + 2 * Q[3]) / 6, atol=1e-14)
    assert np.allclose(c.control_points[2], (2 * Q[0] - 9 * Q[1] + 18 * Q[2] - 5 * Q[3]) / 6, atol=1e-14)
    assert np.array_equal(c.control_points[[0, 3]], Q[[0, 3]])


@SETTINGS
@given(st.integers(1, 7), st.integers(1, 3), st.sampled_from(["uniform", "chord", "centripetal"]), st.data())
def test_bezier_passes_through_points(n, dim, method, data):
    Q = data.draw(point_arrays(n + 1, dim))
    assume(well_spread(Q, 0.5))
    c = bezier_through_points(Q, method)
    t = parametrize(Q, method)
    assert c.degree == n
    assert np.abs(c(t) - Q).max() <= 1e-9 * max(1.0, np.abs(Q).max())
    assert np.abs(c.de_casteljau(t) - Q).max() <= 1e-9 * max(1.0, np.abs(Q).max())


def test_bezier_explicit_parameters():
    Q = np.array([[0.0, 1.0], [1.0, 3.0], [2.0, 2.0], [5.0, 0.0]])
    t = [0.0, 0.1, 0.7, 1.0]
    c = bezier_through_points(Q, t)
    assert np.allclose(c(t), Q, rtol=0, atol=1e-13)
    with pytest.raises(CagdError, match="parameters: .*start at 0 and end at 1"):
        bezier_through_points(Q, [0.0, 0.1, 0.7, 2.0])


# --- global interpolation (Piegl & Tiller 9.2.1) ---------------------------------------------
def averaged_by_hand(u, p):
    """Piegl & Tiller eq. 9.8 written as the book's loop."""
    n = len(u) - 1
    U = [u[0]] * (p + 1)
    for j in range(1, n - p + 1):
        U.append(sum(u[j:j + p]) / p)
    return np.array(U + [u[-1]] * (p + 1))


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5])
@pytest.mark.parametrize("method", ["uniform", "chord", "centripetal"])
def test_interpolate_matches_scipy(degree, method):
    rng = np.random.default_rng(10 * degree + len(method))
    Q = rng.normal(size=(11, 3))
    c = interpolate(Q, degree, method)
    u = parametrize(Q, method)
    assert np.allclose(c.knots, averaged_by_hand(u, degree), rtol=0, atol=1e-15)
    s = make_interp_spline(u, Q, k=degree, t=c.knots)
    assert np.abs(s.c - c.control_points).max() <= 1e-10
    assert np.abs(c(u) - Q).max() <= 1e-12


@SETTINGS
@given(st.integers(1, 5), st.integers(1, 3), st.sampled_from(["uniform", "chord", "centripetal"]), st.data())
def test_interpolate_property(degree, dim, method, data):
    count = data.draw(st.integers(degree + 1, degree + 10))
    Q = data.draw(point_arrays(count, dim))
    assume(well_spread(Q, 0.5))
    c = interpolate(Q, degree, method)
    u = parametrize(Q, method)
    scale = max(1.0, np.abs(Q).max())
    assert np.abs(c(u) - Q).max() <= 1e-9 * scale
    s = make_interp_spline(u, Q, k=degree, t=c.knots)
    assert np.abs(s.c - c.control_points).max() <= 1e-9 * scale


def test_interpolate_given_knots():
    Q = np.array([[0, 0], [1, 1], [2, 0], [3, 2], [4, 1], [5, 3], [6, 0]], float)
    u = parametrize(Q, "chord")
    knots = np.concatenate([[0.0] * 4, [0.3, 0.45, 0.7], [1.0] * 4])
    c = interpolate(Q, 3, "chord", knots=knots)
    assert np.array_equal(c.knots, knots)
    s = make_interp_spline(u, Q, k=3, t=knots)
    assert np.abs(s.c - c.control_points).max() <= 1e-10
    assert np.abs(c(u) - Q).max() <= 1e-12


def test_interpolate_errors():
    Q = np.array([[0, 0], [1, 1], [2, 0], [3, 2], [4, 1]], float)
    with pytest.raises(CagdError, match="degree"):
        interpolate(Q, 5)
    with pytest.raises(CagdError, match="knots: expected 9"):
        interpolate(Q, 3, knots=[0, 0, 0, 0, 1, 1, 1, 1])
    with pytest.raises(CagdError, match="knots: the domain"):
        interpolate(Q, 3, "uniform", knots=[0, 0, 0, 0, 0.5, 0.9, 0.9, 0.9, 0.9])


def test_schoenberg_whitney_violation():
    Q = np.array([[0, 0], [1, 1], [2, 0], [3, 2], [4, 1], [5, 0]], float)
    # uniform parameters 0, .2, ..., 1; N_{1,3} has support [0, 0.02], so N_{1,3}(0.2) = 0
    knots = [0, 0, 0, 0, 0.01, 0.02, 1, 1, 1, 1]
    with pytest.raises(CagdError, match="Schoenberg-Whitney"):
        interpolate(Q, 3, "uniform", knots=knots)


# --- least-squares approximation (Piegl & Tiller 9.4.1) ----------------------------------
def knots_by_hand(ub, count, p):
    """Piegl & Tiller eq. 9.68-9.69 as the book's loop."""
    m, n = len(ub) - 1, count - 1
    d = (m + 1) / (n - p + 1)
    U = [ub[0]] * (p + 1)
    for j in range(1, n - p + 1):
        i = int(j * d)
        a = j * d - i
        U.append((1 - a) * ub[i - 1] + a * ub[i])
    return np.array(U + [ub[-1]] * (p + 1))


def constrained_lsq(Q, ub, U, p):
    """min |A x - Q|^2 subject to x_0 = Q_0, x_n = Q_m, with the basis from scipy's
    BSpline.design_matrix (independent of cagd): the constraints eliminated and the
    rest solved by SVD (np.linalg.lstsq), which loses cond(A) digits where the KKT
    normal equations lose cond(A)^2 (with count near len(points) their residual was
    3e-8 off, on 23 points)."""
    A = BSpline.design_matrix(ub, U, p).toarray()
    x = np.empty((A.shape[1], Q.shape[1]))
    x[0], x[-1] = Q[0], Q[-1]
    rhs = Q - np.outer(A[:, 0], Q[0]) - np.outer(A[:, -1], Q[-1])
    x[1:-1] = np.linalg.lstsq(A[:, 1:-1], rhs, rcond=None)[0]
    return x


@SETTINGS
@given(st.integers(1, 4), st.integers(1, 3), st.sampled_from(["uniform", "chord", "centripetal"]), st.data())
def test_approximate_against_kkt_oracle(degree, dim, method, data):
    total = data.draw(st.integers(degree + 3, 25))
    count = data.draw(st.integers(degree + 1, total))
    Q = data.draw(point_arrays(total, dim))
    assume(well_spread(Q, 0.3))
    c = approximate(Q, count, degree, method)
    ub = parametrize(Q, method)
    if count < total:
        assert np.allclose(c.knots, knots_by_hand(ub, count, degree), rtol=0, atol=1e-14)
    else:
        assert np.allclose(c.knots, averaged_by_hand(ub, degree), rtol=0, atol=1e-14)
    P = constrained_lsq(Q, ub, c.knots, degree)
    scale = max(1.0, np.abs(Q).max())
    # the normal-equation oracle loses cond(A)^2 digits; with count near len(points)
    # the eq. 9.69 knots give cond(A) up to ~1e5 (and control points far outside the data)
    A = BSpline.design_matrix(ub, c.knots, degree).toarray()[:, 1:-1]
    kappa = np.linalg.cond(A) if A.size else 1.0
    assert np.abs(P - c.control_points).max() <= 1e-14 * max(kappa ** 2, 1e4) * max(scale, np.abs(P).max())
    ours = np.sum((c(ub) - Q) ** 2)
    oracle = np.sum((BSpline(c.knots, P, degree)(ub) - Q) ** 2)
    assert abs(ours - oracle) <= 1e-9 * max(oracle, scale ** 2)
    assert ours <= oracle + 1e-12 * scale ** 2            # ours is the optimum
    # the unconstrained optimum on the same knots can only be better
    free = make_lsq_spline(ub, Q, c.knots, k=degree)
    assert np.sum((free(ub) - Q) ** 2) <= ours + 1e-9 * scale ** 2
    assert np.array_equal(c.control_points[[0, -1]], Q[[0, -1]])


def test_approximate_is_optimal():
    """The residual is orthogonal to every interior basis function (normal equations)."""
    rng = np.random.default_rng(3)
    t = np.linspace(0, 2 * np.pi, 40)
    Q = np.c_[np.cos(t), np.sin(2 * t)] + 0.01 * rng.normal(size=(40, 2))
    c = approximate(Q, 9, 3)
    ub = parametrize(Q)
    A = BSpline.design_matrix(ub, c.knots, 3).toarray()
    r = c(ub) - Q
    assert np.abs(A[:, 1:-1].T @ r).max() <= 1e-12
    # moving an interior control point only increases the residual
    base = np.sum(r ** 2)
    for k in (1, 4, 7):
        P = c.control_points.copy()
        P[k] += [1e-3, -1e-3]
        assert np.sum((BSplineCurve(P, 3, c.knots)(ub) - Q) ** 2) > base


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_approximate_with_all_points_interpolates(degree):
    rng = np.random.default_rng(degree)
    Q = rng.normal(size=(12, 3))
    c = approximate(Q, 12, degree)
    ub = parametrize(Q)
    assert np.abs(c(ub) - Q).max() <= 1e-12
    ref = interpolate(Q, degree)
    assert np.array_equal(ref.knots, c.knots)
    assert np.abs(ref.control_points - c.control_points).max() <= 1e-12
    # one control point fewer: the eq. 9.69 knots, a genuine fit (end points kept)
    d = approximate(Q, 11, degree)
    assert np.array_equal(d.control_points[[0, -1]], Q[[0, -1]])
    assert np.abs(d(ub) - Q).max() > 1e-6


def test_approximate_minimal_counts():
    Q = np.array([[0, 0], [1, 2], [2, 3], [3, 3], [4, 1]], float)
    line = approximate(Q, 2, 1)
    assert np.array_equal(line.control_points, Q[[0, -1]])
    bez = approximate(Q, 4, 3)           # one Bezier span, interior points fitted
    ub = parametrize(Q)
    P = constrained_lsq(Q, ub, bez.knots, 3)
    assert np.allclose(bez.control_points, P, rtol=0, atol=1e-12)


@pytest.mark.parametrize("count, word", [(3, "at least degree \\+ 1 = 4"), (6, "at most len\\(points\\) = 5"),
                                         (2.5, "integer")])
def test_approximate_count_errors(count, word):
    Q = np.array([[0, 0], [1, 2], [2, 3], [3, 3], [4, 1]], float)
    with pytest.raises(CagdError, match="count: .*" + word):
        approximate(Q, count, 3)


def test_approximation_knots_spans_hold_parameters():
    ub = parametrize(np.random.default_rng(5).normal(size=(30, 2)))
    for count in range(4, 31):
        U = approximation_knots(ub, count, 3)
        inner = np.unique(U)
        hits = np.histogram(ub, bins=inner)[0]
        assert np.all(hits >= 1)
