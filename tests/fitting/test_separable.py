"""cagd.fitting.separable (issue 17): the ends-held operators against scipy's design matrix
with numpy's lstsq (the oracle), the separable poles against the tensor of 1-D oracle
fits, the misses against the surface's own evaluation."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BSpline

from cagd import BSplineSurface
from cagd.fitting.separable import (INTERLACE_SHARE, LEBESGUE_MAX, SeparableGrid, ends_held_operator, interlaced,
                                    site_breaks)


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


#: the v sites of the 8 x 30 bumpy grid of test_fit_surface's certified-max property (seed 1)
#: and the v breakpoints the growth chose there at the cap (30 poles, degree 2)
CAP_SITES = np.array([0.0, 0.03318028, 0.06699449, 0.10164729, 0.13711048, 0.17286346, 0.20853074, 0.24362384,
                      0.27786195, 0.31128447, 0.34437978, 0.37781169, 0.41208138, 0.44712232, 0.48279279, 0.51862908,
                      0.55404133, 0.58867635, 0.62244235, 0.65562501, 0.68882122, 0.72261677, 0.75736677, 0.79277809,
                      0.82859523, 0.86424591, 0.89929143, 0.93349432, 0.96690585, 1.0])
CAP_BREAKS = np.array([0.0, 0.10936417, 0.15719289, 0.19095558, 0.21975803, 0.24634065, 0.2776173, 0.31747192,
                       0.34952508, 0.37525662, 0.3975414, 0.42008325, 0.44860581, 0.48524183, 0.53216874, 0.5722807,
                       0.6029723, 0.62968607, 0.65470177, 0.68703036, 0.72561307, 0.76258151, 0.79390191, 0.82061276,
                       0.84539912, 0.86977805, 0.89939, 0.93749949, 1.0])


def test_rank_deficiency_the_qr_does_not_show():
    """The grid's cap case: the interior system's smallest singular value is ~1e-18 of the
    largest, the unpivoted QR's smallest |R_ii| 1.6e-7 of the largest (so the QR was
    trusted; its inverse made |F| ~ 1e15 and a net of 1e14). Now the Schoenberg-Whitney
    check sends it to the pseudo-inverse: the minimum-norm least squares (oracle: numpy's
    lstsq on scipy's design matrix, which drops that singular value too)."""
    U = clamped(CAP_BREAKS, 2)
    A = BSpline.design_matrix(CAP_SITES, U, 2).toarray()[1:-1, 1:-1]
    R = np.linalg.qr(A)[1]
    assert np.abs(np.diag(R)).min() > 1e-8 * np.abs(np.diag(R)).max()              # the QR looks fine
    assert np.linalg.matrix_rank(A) < A.shape[1]                                       # it is not
    Q = np.random.default_rng(1).normal(size=(len(CAP_SITES), 3))
    _, F = ends_held_operator(U, 2, CAP_SITES)
    assert np.abs(F).max() <= 1e3
    assert np.abs(F @ Q - lsq_ends_held(Q, CAP_SITES, U, 2)).max() <= 1e-8


def lebesgue(t, U, p):
    """Oracle: the ends-held least squares' Lebesgue constant (max row sum of |F|) from
    numpy's pseudo-inverse of scipy's design matrix; inf where it is rank deficient."""
    A = BSpline.design_matrix(t, U, p).toarray()
    inner = A[1:-1, 1:-1]
    if np.linalg.matrix_rank(inner) < inner.shape[1]:
        return np.inf
    X = np.linalg.pinv(inner)
    F = np.zeros((A.shape[1], len(t)))
    F[0, 0] = F[-1, -1] = 1.0
    F[1:-1, 1:-1], F[1:-1, 0], F[1:-1, -1] = X, -X @ A[1:-1, 0], -X @ A[1:-1, -1]
    return float(np.abs(F).sum(axis=1).max())


def test_interlaced_at_the_cap():
    """The cap case's breakpoints (rank deficient) moved towards the sites' own: full rank,
    a Lebesgue constant within LEBESGUE_MAX (oracle: lebesgue); the sites' own knots at
    n = m are the averaging knots (Piegl & Tiller eq. 9.8, computed here by hand)."""
    U0 = clamped(CAP_BREAKS, 2)
    assert lebesgue(CAP_SITES, U0, 2) == np.inf
    b = interlaced(CAP_BREAKS, CAP_SITES, 2)
    assert len(b) == len(CAP_BREAKS) and np.all(np.diff(b) > 0)
    assert lebesgue(CAP_SITES, clamped(b, 2), 2) <= LEBESGUE_MAX
    home = site_breaks(CAP_SITES, 2, len(CAP_BREAKS) - 1)
    assert np.abs(home[1:-1] - 0.5 * (CAP_SITES[1:-2] + CAP_SITES[2:-1])).max() <= 1e-15


def periodic_lebesgue(t, breaks, p):
    """Oracle: the periodic least squares' Lebesgue constant (max row sum of |pinv(N)|), N
    scipy's design matrix on the breakpoints extended by p spans either side (a period
    shifted), its columns wrapped modulo the count."""
    count = len(breaks) - 1
    T = np.concatenate([breaks[count - p:count] - 1.0, breaks, breaks[1:p + 1] + 1.0])
    A = BSpline.design_matrix(t, T, p).toarray()
    N = np.zeros((len(t), count))
    for j in range(A.shape[1]):
        N[:, j % count] += A[:, j]
    return float(np.abs(np.linalg.pinv(N)).sum(axis=1).max())


def test_interlaced_periodic_tube_rows():
    """The periodic tube's 20 rows (uniform sites in [0, 1)) and the 19 breakpoints the
    growth chased the misses to (test_fit_surface_conditions' periodic example): moved
    to a Lebesgue constant within LEBESGUE_MAX (oracle: periodic_lebesgue; the given
    breakpoints' is above it)."""
    t = np.arange(20) / 20.0
    chased = np.array([0.0, 0.05, 0.101, 0.155, 0.222, 0.318, 0.382, 0.424, 0.459, 0.49, 0.519, 0.546, 0.577,
                       0.612, 0.657, 0.722, 0.819, 0.889, 0.947, 1.0])
    assert periodic_lebesgue(t, chased, 2) > LEBESGUE_MAX
    b = interlaced(chased, t, 2, periodic=True)
    assert len(b) == len(chased) and b[0] == 0.0 and b[-1] == 1.0 and np.all(np.diff(b) > 0)
    assert periodic_lebesgue(t, b, 2) <= LEBESGUE_MAX


@settings(max_examples=60, deadline=None)
@given(m=st.integers(3, 40), p=st.integers(1, 4), share=st.floats(0.05, 1.0), power=st.floats(0.3, 3.0),
       seed=st.integers(0, 10**6), uniform=st.booleans())
def test_interlaced_property(m, p, share, power, seed, uniform):
    """On random sites and random breakpoints of up to as many poles as sites: the sites'
    own breakpoints always give a full-rank ends-held least squares; interlaced's give one
    (oracle: numpy's matrix_rank of scipy's design matrix), above INTERLACE_SHARE of the
    sites with a Lebesgue constant (oracle: numpy's pinv) within LEBESGUE_MAX or at most
    the given and the sites' own breakpoints'; the breakpoints are kept where they pass."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, m) if uniform else np.concatenate([[0.0], np.sort(rng.random(m - 2)), [1.0]])
    if m < p + 1 or len(np.unique(t)) < m:
        return
    count = max(1, int(round(share * (m - p))))
    breaks = np.unique(np.concatenate([[0.0, 1.0], np.sort(rng.random(count - 1)) ** power]))
    count = len(breaks) - 1
    home = site_breaks(t, p, count)
    assert lebesgue(t, clamped(home, p), p) < np.inf
    b = interlaced(breaks, t, p)
    assert len(b) == len(breaks) and np.all(np.diff(b) > 0) and b[0] == 0.0 and b[-1] == 1.0
    L = lebesgue(t, clamped(b, p), p)
    assert L < np.inf
    L0 = lebesgue(t, clamped(breaks, p), p)
    if count + p > INTERLACE_SHARE * m:
        assert L <= max(LEBESGUE_MAX, min(L0, lebesgue(t, clamped(home, p), p))) * (1 + 1e-9)
    if L0 < np.inf and (count + p <= INTERLACE_SHARE * m or L0 <= LEBESGUE_MAX * (1 - 1e-9)):
        assert np.array_equal(b, breaks)


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
