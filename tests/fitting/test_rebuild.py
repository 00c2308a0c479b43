"""rebuild (issue 17): a curve or surface refitted to a chosen size, with the deviation
measured. Oracles: the original's own size gives it back (the least squares reproduces a
spline in its space), brute force (KD-tree on dense samples of the result) for the
reported deviation, the h^(p+1) convergence of a cubic rebuild of a circle."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import cagd
from cagd import BSplineCurve, BSplineSurface, CagdError, rebuild

W = np.sqrt(0.5)
ARC = BSplineCurve([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], 2, [0, 0, 0, .5, .5, 1, 1, 1], [1, W, 1, W, 1])


def test_rebuild_to_the_original_size_is_the_identity():
    rng = np.random.default_rng(2)
    c = BSplineCurve(rng.random((12, 3)), 3, [0, 0, 0, 0, .1, .15, .3, .5, .6, .7, .8, .95, 1, 1, 1, 1])
    r = rebuild(c, 12, 3)
    assert np.abs(r.result.control_points - c.control_points).max() <= 1e-12 and r.deviation <= 1e-12
    S = BSplineSurface(rng.random((6, 5, 3)), 3, 2)
    r = rebuild(S, (6, 5), (3, 2))
    assert np.abs(r.result.control_points - S.control_points).max() <= 1e-12 and r.deviation <= 1e-12


def test_deviation_is_what_brute_force_measures():
    r = rebuild(ARC, 8, 3)
    t = np.linspace(0, 1, 2001)
    dense = r.result(np.linspace(0, 1, 400_001))
    chord = float(np.sqrt((np.diff(dense, axis=0) ** 2).sum(-1)).max())
    brute, _ = cKDTree(dense).query(ARC(t))
    assert r.deviation <= float(brute.max()) + 1e-12           # samples: brute is an upper bound
    assert float(brute.max()) <= r.deviation * 1.05 + chord    # and the deviation is not far below it
    assert r.result.degree == 3 and len(r.result.control_points) == 8
    assert r.result.domain == ARC.domain and not r.result.is_rational


def test_cubic_rebuild_of_a_circle_converges_like_h4():
    devs = [rebuild(ARC, n, 3).deviation for n in (8, 16, 32)]
    assert devs[0] > devs[1] > devs[2]
    assert devs[1] / devs[2] > 10.0                 # about 2^4 per halving of the spans


def test_surface_rebuild_of_a_sphere():
    r = rebuild(cagd.sphere(2.0), (16, 16), (3, 3))
    u, v = np.linspace(0, 1, 60), np.linspace(0, 1, 60)
    radius = np.sqrt((r.result.grid(u, v) ** 2).sum(-1))
    assert np.abs(radius - 2.0).max() <= r.deviation * 1.5 + 1e-12
    assert r.deviation < 0.01
    assert r.result.control_points.shape == (16, 16, 3)


@pytest.mark.parametrize("args, word", [
    ((ARC, 2, 3), "count"),
    ((ARC, 5, 0), "degree"),
    ((ARC, 5.5, 3), "count"),
    ((cagd.sphere(1.0), (3, 8, 1), 3), "count"),
    (("curve", 5, 3), "obj"),
])
def test_bad_input(args, word):
    with pytest.raises(CagdError, match=word):
        rebuild(*args)


def test_high_degree_identity_and_count_cap():
    c = BSplineCurve(np.random.default_rng(1).random((21, 3)), 20)
    assert rebuild(c, 21, 20).deviation <= 1e-10
    with pytest.raises(CagdError, match="count"):
        rebuild(ARC, 10 ** 6, 3)


def ends_held_oracle(U, p, t, Q):
    """Oracle: the least squares with the end rows held, by scipy's basis (dense design
    matrix) and numpy's lstsq (minimum norm where rank deficient), in the points'
    normalised frame (bounding-box centre, half diagonal), as _fit_rows documents."""
    from scipy.interpolate import BSpline
    lo, hi = Q.min(axis=0), Q.max(axis=0)
    center, scale = 0.5 * (lo + hi), float(np.abs(0.5 * (hi - lo)).max()) * np.sqrt(Q.shape[1])
    Qn = (Q - center) / scale
    A = BSpline.design_matrix(t, U, p).toarray()
    P = np.zeros((A.shape[1], Q.shape[1]))
    P[0], P[-1] = Qn[0], Qn[-1]
    R = Qn[1:-1] - A[1:-1, :1] * P[0] - A[1:-1, -1:] * P[-1]
    P[1:-1] = np.linalg.lstsq(A[1:-1, 1:-1], R, rcond=None)[0]
    P = P * scale + center
    P[0], P[-1] = Q[0], Q[-1]
    return P, A


@pytest.mark.parametrize("p, count, m, seed", [(1, 5, 12, 0), (2, 8, 40, 1), (3, 12, 200, 2), (3, 30, 61, 3),
                                               (5, 9, 25, 4)])
def test_fit_rows_is_the_ends_held_least_squares(p, count, m, seed):
    """_fit_rows (now the separable fit's operator, ends_held_operator) on full-rank
    systems: the old dense lstsq with the end rows held to 1e-12 (oracle above)."""
    from cagd.fitting.rebuild import _fit_rows
    rng = np.random.default_rng(seed)
    U = np.r_[np.zeros(p + 1), np.sort(rng.uniform(0.1, 0.9, count - p - 1)), np.ones(p + 1)]
    t = np.r_[0.0, np.sort(rng.random(m - 2)), 1.0]
    Q = rng.normal(size=(m, 3)) * 50.0 + 7.0
    expected, A = ends_held_oracle(U, p, t, Q)
    assert np.linalg.matrix_rank(A[1:-1, 1:-1]) == count - 2                   # full rank
    P = _fit_rows(U, p, t, Q)
    assert P.shape == (count, 3)
    assert np.abs(P - expected).max() <= 1e-12 * np.abs(Q).max()
    assert np.array_equal(P[0], Q[0]) and np.array_equal(P[-1], Q[-1])


def test_fit_rows_rank_deficient_returns_the_minimum_norm_fit():
    """Fewer distinct parameters (4 interior) than interior poles (8): the old _fit_rows
    raised ('count: ... cannot be fitted here (... rank deficient ...)'); now the
    minimum-norm least squares in the normalised frame (oracle: numpy's lstsq), the ends
    exact, every site's residual the least-squares minimum."""
    from cagd.fitting.rebuild import _fit_rows
    rng = np.random.default_rng(5)
    p, count = 3, 10
    U = np.r_[np.zeros(p + 1), np.linspace(0.0, 1.0, count - p + 1)[1:-1], np.ones(p + 1)]
    t = np.r_[0.0, np.repeat([0.2, 0.4, 0.6, 0.8], 5), 1.0]
    Q = rng.normal(size=(len(t), 2)) * 10.0
    expected, A = ends_held_oracle(U, p, t, Q)
    assert np.linalg.matrix_rank(A[1:-1, 1:-1]) < count - 2                    # rank deficient
    P = _fit_rows(U, p, t, Q)
    assert np.all(np.isfinite(P)) and P.shape == (count, 2)
    assert np.abs(P - expected).max() <= 1e-9 * np.abs(Q).max()
    assert np.array_equal(P[0], Q[0]) and np.array_equal(P[-1], Q[-1])
    assert np.linalg.norm(A @ P - Q) == pytest.approx(np.linalg.norm(A @ expected - Q), rel=1e-10)
