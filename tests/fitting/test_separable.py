"""cagd.fitting.separable (issue 17): the ends-held operators against scipy's design matrix
with numpy's lstsq (the oracle), the separable poles against the tensor of 1-D oracle
fits, the misses against the surface's own evaluation."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BSpline

from cagd import BSplineSurface
from cagd.fitting.separable import SeparableGrid, ends_held_operator


def clamped(breaks, p):
    return np.concatenate([np.zeros(p), breaks, np.ones(p)])


def lsq_ends_held(Q, t, U, p):
    """Oracle: least squares with the ends held, scipy's basis, numpy's lstsq (minimum
    norm where rank deficient)."""
    A = BSpline.design_matrix(t, U, p).toarray()
    P = np.zeros((A.shape[1], Q.shape[1]))
    P[0], P[-1] = Q[0], Q[-1]
    R = Q[1:-1] - A[1:-1, :1] * P[0] - A[1:-1, -1:] * P[-1]
    P[1:-1] = np.linalg.lstsq(A[1:-1, 1:-1], R, rcond=None)[0]
    return P


@settings(max_examples=40, deadline=None)
@given(m=st.integers(8, 60), spans=st.integers(1, 6), p=st.integers(1, 4), seed=st.integers(0, 10**6))
def test_operator_is_the_ends_held_least_squares(m, spans, p, seed):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.sort(rng.random(m - 2)), [1.0]])
    breaks = np.unique(np.concatenate([[0.0, 1.0], np.quantile(t, np.linspace(0, 1, spans + 1)[1:-1])]))
    U = clamped(breaks, p)
    if len(U) - p - 1 > m:
        return
    Q = rng.normal(size=(m, 3))
    N, F = ends_held_operator(U, p, t)
    assert np.abs(N - BSpline.design_matrix(t, U, p).toarray()).max() <= 1e-14
    assert np.abs(F @ Q - lsq_ends_held(Q, t, U, p)).max() <= 1e-8


def test_rank_deficient_gets_the_minimum_norm_solution():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 1.0])         # no site in (0.25, 0.9): a span without one
    U = clamped(np.array([0.0, 0.25, 0.5, 0.9, 1.0]), 3)
    Q = np.random.default_rng(0).normal(size=(len(t), 2))
    _, F = ends_held_operator(U, 3, t)
    assert np.all(np.isfinite(F))
    assert np.abs(F @ Q - lsq_ends_held(Q, t, U, 3)).max() <= 1e-9


@pytest.mark.parametrize("degrees", [(3, 3), (2, 4)])
def test_grid_poles_are_the_tensor_of_one_direction_fits(degrees):
    rng = np.random.default_rng(7)
    m, n = 23, 31
    u = np.concatenate([[0.0], np.sort(rng.random(m - 2)), [1.0]])
    v = np.linspace(0.0, 1.0, n)
    Q = rng.normal(size=(m, n, 3))
    bu, bv = np.array([0.0, 0.3, 0.55, 1.0]), np.array([0.0, 0.2, 0.5, 0.7, 1.0])
    pu, pv = degrees
    g = SeparableGrid(Q, u, v, pu, pv)
    P, miss = g.fit(bu, bv)
    U, V = clamped(bu, pu), clamped(bv, pv)
    rows = lsq_ends_held(Q.reshape(m, -1), u, U, pu).reshape(-1, n, 3)           # along u per column
    oracle = lsq_ends_held(rows.transpose(1, 0, 2).reshape(n, -1), v, V, pv).reshape(-1, rows.shape[0], 3)
    assert np.abs(P - oracle.transpose(1, 0, 2)).max() <= 1e-9
    S = BSplineSurface(P, pu, pv, U, V)
    assert np.abs(miss - np.sqrt(((S.grid(u, v) - Q) ** 2).sum(-1))).max() <= 1e-12
    ru, rv = g.residuals(bu, bv)
    along_u = BSpline(U, rows.reshape(rows.shape[0], -1), pu)(u).reshape(m, n, 3)
    assert np.abs(ru - np.sqrt(((along_u - Q) ** 2).sum(-1))).max() <= 1e-9
    cols = lsq_ends_held(Q.transpose(1, 0, 2).reshape(n, -1), v, V, pv)
    along_v = BSpline(V, cols, pv)(v).reshape(n, m, 3).transpose(1, 0, 2)
    assert np.abs(rv - np.sqrt(((along_v - Q) ** 2).sum(-1))).max() <= 1e-9


@pytest.mark.parametrize("crowded", [False, True])
def test_cell_normal_band_is_the_normal_matrix(crowded):
    """Oracle: the dense normal matrix sum_k w_k B_k B_k^T of the scattered tensor basis
    (built by numpy outer products), read through the band layout; crowded: most points
    in one cell (split into several bins)."""
    from cagd.basis.bspline import basis_matrix
    from cagd.fitting.separable import cell_normal_band
    from cagd.fitting.fit_surface import _chunk_basis
    rng = np.random.default_rng(2)
    uv = rng.random((3000, 2))
    if crowded:
        uv[:2900] = 0.01 + 0.02 * rng.random((2900, 2))
    bu, bv = np.array([0.0, 0.3, 0.5, 1.0]), np.array([0.0, 0.25, 0.6, 0.8, 1.0])
    U, V = clamped(bu, 3), clamped(bv, 2)
    nu, nv = len(U) - 4, len(V) - 3
    w = rng.random(3000)
    size = nu * nv
    reach = 3 * nv + 2
    width = 2 * reach + 1
    start = np.clip(np.arange(size) - reach, 0, size - width)
    band = np.zeros((size, width))
    for c0, B, cols in _chunk_basis(uv, U, V, 3, 2):
        cell_normal_band(band, start, cols, B, w[c0:c0 + len(B)])
    K = np.einsum("ki,kj->kij", basis_matrix(U, 3, uv[:, 0], nu), basis_matrix(V, 2, uv[:, 1], nv)).reshape(3000, -1)
    dense = (K * w[:, None]).T @ K
    got = np.zeros((size, size))
    rows = np.arange(size)[:, None]
    got[rows, start[:, None] + np.arange(width)] = band
    assert np.abs(got - dense).max() <= 1e-12 * np.abs(dense).max()
