"""Knot tuning of the separable grid fit (cagd.fitting.grid_knots, issue 17)."""
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cagd import BSplineSurface, fit_surface
from cagd.fitting.grid_knots import _Tuner, tune_knots
from cagd.fitting.separable import SeparableGrid
from benchmarks.fitting import anchor_grid
from tests.fitting.test_fit_surface import brute_distances

FS = sys.modules["cagd.fitting.fit_surface"]


def sampled_spline(seed, ku, kv, m=50):
    """A bicubic height field over [0, 10]^2 with the interior knots ku, kv, sampled on an
    m x m grid of uniform parameters."""
    rng = np.random.default_rng(seed)
    nu, nv = len(ku) + 4, len(kv) + 4
    X, Y = np.meshgrid(np.linspace(0, 10, nu), np.linspace(0, 10, nv), indexing="ij")
    P = np.stack([X, Y, 3 * rng.standard_normal((nu, nv))], axis=-1)
    S = BSplineSurface(P, 3, 3, np.r_[[0.0] * 4, ku, [1.0] * 4], np.r_[[0.0] * 4, kv, [1.0] * 4])
    t = np.linspace(0, 1, m)
    return S, S.grid(t, t)


def poles(surface):
    return int(np.prod(surface.control_points.shape[:2]))


@pytest.mark.parametrize("seed, ku, kv", [(0, [0.3, 0.38], [0.55]), (1, [0.2, 0.7], [0.33, 0.4]),
                                          (2, [0.45], [0.15, 0.6, 0.66])])
def test_sampled_spline_comes_back_with_its_knot_count(seed, ku, kv, monkeypatch):
    """A grid sampled from a bicubic B-spline with k_u x k_v interior knots (uneven, some
    close together) at tol 1e-4 of its size (above the exactness path's SEARCH_TOL) comes
    back with k_u x k_v interior knots, its own control-point count; the equidistributed
    knots of the rounds alone (the stage switched off) took 15 x 7, 13 x 11 and 7 x 21
    poles for 6 x 5, 6 x 6 and 5 x 7. Oracle of the error: brute force (dense sampling of
    the fit plus Gauss-Newton, an upper bound of every distance) within tol."""
    S, Q = sampled_spline(seed, ku, kv)
    tol = 1e-3
    r = fit_surface(Q, tol, parameters="uniform")
    assert r.converged and r.max_error <= tol, r.message
    assert r.surface.control_points.shape[:2] == S.control_points.shape[:2]
    assert float(brute_distances(r.surface, Q.reshape(-1, 3)).max()) <= tol
    old = fit_surface(Q, tol, parameters="uniform", tune_knots=False)
    assert old.converged and poles(old.surface) >= 1.5 * poles(S)
    monkeypatch.setattr(FS, "fewer_spans", lambda grid, best, tol, fewer: (best, 0))
    assert fit_surface(Q, tol, parameters="uniform").surface.control_points.shape == old.surface.control_points.shape


def test_anchor_grid_within_the_issue_ratio():
    """The benchmark's 100 x 100 anchor at tol 0.01, degree 3: at most 0.6 of OCCT's
    GeomAPI_PointsToBSplineSurface's 15 x 15 = 225 poles (benchmarks/fitting.py; before
    the stage 12 x 12 = 144, 0.64); every point within tol by the brute-force oracle."""
    Q = anchor_grid()
    r = fit_surface(Q, 0.01)
    assert r.converged and r.max_error <= 0.01
    assert poles(r.surface) <= 0.6 * 225
    assert float(brute_distances(r.surface, Q.reshape(-1, 3)).max()) <= 0.01


def wave_grid(m, n, wave):
    """An m x n grid over [0, 40] x [0, 30] of a product wave (cq_ext's and the workbench's
    test grids)."""
    x, y = np.meshgrid(np.linspace(0, 40, m), np.linspace(0, 30, n), indexing="ij")
    z = 3 * np.sin(x / 9) * np.cos(y / 7) if wave == "cq" else 4 * np.sin(x / 9) * np.cos(y / 7) + 0.002 * x * y
    return np.stack([x, y, z], -1)


@pytest.mark.parametrize("grid, tol, most", [((30, 25, "cq"), 3e-4, 110), ((20, 15, "wb"), 1.5e-4, 120),
                                             ((20, 15, "wb"), 1e-4, 120)])
def test_small_grids_keep_their_counts(grid, tol, most):
    """Degree 3 on small grids (no coarse level): at most the poles the forward-difference
    stage took (110, 120, 132), every point within tol by the brute-force oracle. The first
    case lost 110 -> 121 to a start ending at 1.002 tol until runs within TUNE_NEAR tol
    went on with the L_16 norm; the second 120 -> 130 to a stretched step that gained 1 %
    where the Newton step gained 13 % until stretched steps had to gain TUNE_RATIO of their
    prediction."""
    Q = wave_grid(*grid)
    r = fit_surface(Q, tol)
    assert r.converged and r.max_error <= tol
    assert poles(r.surface) <= most
    assert float(brute_distances(r.surface, Q.reshape(-1, 3)).max()) <= tol


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10 ** 6), st.integers(2, 5), st.integers(2, 5))
def test_tuned_knots_never_worse_and_stay_ordered(seed, su, sv):
    """tune_knots returns strictly increasing breakpoints on [0, 1] whose separable fit
    misses no more than the start's, and the miss it reports is the fit's (oracle: the
    surface of the separable poles evaluated by BSplineSurface, not the tuner's
    smoothing operators)."""
    rng = np.random.default_rng(seed)
    m, n = 24, 20
    u, v = np.linspace(0, 1, m), np.linspace(0, 1, n)
    X, Y = np.meshgrid(u, v, indexing="ij")
    a = rng.uniform(1, 4, 2)
    Q = np.stack([X, Y, 0.2 * np.sin(a[0] * X + 1) * np.exp(a[1] * Y - 2)], axis=-1)
    bu = np.r_[0.0, np.sort(rng.uniform(0.05, 0.95, su - 1)), 1.0]
    bv = np.r_[0.0, np.sort(rng.uniform(0.05, 0.95, sv - 1)), 1.0]
    if np.diff(bu).min() < 0.02 or np.diff(bv).min() < 0.02:
        return
    grid = SeparableGrid(Q, u, v, 3, 3)
    start = float(grid.fit(bu, bv)[1].max())
    tu, tv, miss = tune_knots(_Tuner(grid), bu, bv, 1e-9)
    assert miss <= start
    assert tu[0] == 0.0 and tu[-1] == 1.0 and np.all(np.diff(tu) > 0) and len(tu) == len(bu)
    assert tv[0] == 0.0 and tv[-1] == 1.0 and np.all(np.diff(tv) > 0) and len(tv) == len(bv)
    P = grid.poles(tu, tv)
    S = BSplineSurface(P, 3, 3, np.r_[[0.0] * 3, tu, [1.0] * 3], np.r_[[0.0] * 3, tv, [1.0] * 3])
    assert float(np.sqrt(((S.grid(u, v) - Q) ** 2).sum(-1)).max()) == pytest.approx(miss, rel=1e-9, abs=1e-14)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10 ** 6), st.integers(1, 5), st.integers(2, 5), st.sampled_from([(3, 3), (2, 4), (1, 5)]))
def test_jacobian_vs_finite_differences(seed, su, sv, degrees):
    """The analytic Jacobian of the grid's residuals S_u Q S_v^T - Q in the interior
    breakpoints (variable projection, the derivative of the ends-held projector) against
    central differences with one Richardson step (error O(h^4)) of the residuals
    themselves (built from the least-squares operators, no derivative formula); 1 to 5
    spans along u (one: no interior breakpoint, no row), 2 to 5 along v, degrees 1-5."""
    rng = np.random.default_rng(seed)
    m, n = 23, 19
    u, v = np.linspace(0, 1, m), np.linspace(0, 1, n)
    X, Y = np.meshgrid(u, v, indexing="ij")
    a = rng.uniform(1, 4, 3)
    Q = np.stack([X + 0.1 * np.sin(a[2] * Y), Y, 0.2 * np.sin(a[0] * X + 1) * np.exp(a[1] * Y - 2)], axis=-1)

    def breaks(spans, t):                     # interior breakpoints >= 0.1 apart, off the sites
        while True:
            b = np.r_[0.0, np.sort(rng.uniform(0.1, 0.9, spans - 1)), 1.0]
            if np.diff(b).min() >= 0.1 and np.abs(b[1:-1, None] - t).min(initial=1.0) > 2e-3:
                return b
    bu, bv = breaks(su, u), breaks(sv, v)
    tuner = _Tuner(SeparableGrid(Q, u, v, *degrees))
    R, du, dv = tuner.residuals(bu, bv)
    J = tuner.jacobian(R, du, dv, np.empty((su + sv - 2, m * n * 3)))
    assert J.shape == (su + sv - 2, m * n * 3)

    def central(j, h):
        b = [bu.copy(), bv.copy()]
        axis, i = (0, j + 1) if j < su - 1 else (1, j - su + 2)
        b[axis][i] += h
        plus = tuner.residuals(*b)[0]
        b[axis][i] -= 2 * h
        return (plus - tuner.residuals(*b)[0]).ravel() / (2 * h)
    h = 1e-4
    fd = np.array([(4 * central(j, h / 2) - central(j, h)) / 3 for j in range(len(J))]).reshape(J.shape)
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-9 * max(1.0, np.abs(fd).max()))


def test_stage_skipped_beyond_its_memory_bound(monkeypatch):
    """Where the Jacobian would hold more than TUNE_MAX_ENTRIES values the stage returns
    the fit it was given, untried (the fit of the rounds alone)."""
    import cagd.fitting.grid_knots as gk
    S, Q = sampled_spline(0, [0.3, 0.38], [0.55])
    monkeypatch.setattr(gk, "TUNE_MAX_ENTRIES", 50 * 50 * 3 * 3)
    r = fit_surface(Q, 1e-3, parameters="uniform")
    monkeypatch.setattr(FS, "fewer_spans", lambda grid, best, tol, fewer: (best, 0))
    old = fit_surface(Q, 1e-3, parameters="uniform")
    assert r.surface.control_points.shape == old.surface.control_points.shape
    assert poles(r.surface) > poles(S)


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 10 ** 6), st.sampled_from([3e-3, 1e-2, 3e-2]))
def test_tuning_never_adds_poles_and_keeps_tol(seed, tol):
    """Random smooth height fields (two Gaussian bumps and a wave over [0, 10]^2, 30 x 30
    grids): the tuned fit has at most the control points of the rounds' fit (the stage
    switched off) and every point within tol by the brute-force oracle."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0, 10, 30)
    X, Y = np.meshgrid(x, x, indexing="ij")
    c, s = rng.uniform(2, 8, (2, 2)), rng.uniform(1, 3, 2)
    Z = (np.exp(-((X - c[0, 0]) ** 2 + (Y - c[0, 1]) ** 2) / s[0] ** 2)
         - 0.7 * np.exp(-((X - c[1, 0]) ** 2 + (Y - c[1, 1]) ** 2) / s[1] ** 2) + 0.3 * np.sin(X / 2 + Y / 3))
    Q = np.stack([X, Y, Z], axis=-1)
    r = fit_surface(Q, tol)
    assert r.converged and r.max_error <= tol
    assert float(brute_distances(r.surface, Q.reshape(-1, 3)).max()) <= tol
    original = FS.fewer_spans
    try:
        FS.fewer_spans = lambda grid, best, tol, fewer: (best, 0)
        old = fit_surface(Q, tol)
    finally:
        FS.fewer_spans = original
    assert poles(r.surface) <= poles(old.surface)
