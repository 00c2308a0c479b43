"""B-spline surfaces at high degree and big sizes (issue 14): elevation keeps the
continuity, interpolation is banded, grids use the local basis. Oracles: scipy's
de Boor evaluation (scipy.interpolate.BSpline, make_interp_spline) direction by
direction, and point-by-point evaluation."""
from __future__ import annotations

import numpy as np
import pytest

from cagd import BSplineSurface

scipy_interpolate = pytest.importorskip("scipy.interpolate")


def tensor_values(ku, kv, p, q, P, u, v):
    """S(u_i, v_j) by scipy: the v-direction spline of every row, then u."""
    rows = scipy_interpolate.BSpline(kv, P.transpose(1, 0, 2), q)(v)          # (len(v), nu, D)
    return scipy_interpolate.BSpline(ku, rows.transpose(1, 0, 2), p)(u)       # (len(u), len(v), D)


def continuity_knots(n, p, rng):
    inner = np.sort(rng.random(n - p - 1))
    inner[2] = inner[1]
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


@pytest.mark.parametrize("p,times", [(3, 2), (21, 1), (40, 2)])
def test_surface_elevation_keeps_continuity_at_high_degree(p, times):
    rng = np.random.default_rng(p)
    nu, nv, q = p + 7, 6, 2
    ku, kv = continuity_knots(nu, p, rng), continuity_knots(nv, q, rng)
    P = rng.random((nu, nv, 3)) - 0.5
    s = BSplineSurface(P, p, q, ku, kv)
    e = s.elevate("u", times)
    vals, mults = np.unique(ku, return_counts=True)
    new_vals, new_mults = np.unique(e.knots_u, return_counts=True)
    assert np.array_equal(new_vals, vals) and np.array_equal(new_mults, mults + times)
    assert np.array_equal(e.knots_v, kv)
    u, v = np.linspace(0, 1, 97), np.linspace(0, 1, 31)
    ref = tensor_values(ku, kv, p, q, P, u, v)
    got = tensor_values(e.knots_u, e.knots_v, p + times, q, e.control_points, u, v)
    assert np.abs(got - ref).max() <= 1e-12 * np.abs(P).max()
    # the same in v, by symmetry of the implementation through swapped()
    ev = s.swapped().elevate("v", times)
    assert np.array_equal(np.unique(ev.knots_v, return_counts=True)[1], mults + times)


@pytest.mark.parametrize("p,q,rational,du,dv", [(3, 3, False, 0, 0), (2, 4, True, 0, 0), (3, 2, False, 2, 1),
                                                 (2, 3, True, 1, 1), (23, 5, False, 1, 0)])
def test_grid_equals_point_by_point(p, q, rational, du, dv):
    """The local-basis grid against point-by-point derivatives (another path: the
    patch table or the basis per point), including unsorted, repeated and end
    parameters and knots of multiplicity > 1."""
    rng = np.random.default_rng(p * 7 + q)
    nu, nv = p + 9, q + 12
    ku, kv = continuity_knots(nu, p, rng), continuity_knots(nv, q, rng)
    W = rng.uniform(0.5, 2.0, (nu, nv)) if rational else None
    s = BSplineSurface(rng.random((nu, nv, 3)), p, q, ku, kv, W)
    us = np.concatenate([[1.0, 0.0, ku[p + 3]], rng.random(60), [0.5, 0.5]])
    vs = np.concatenate([rng.random(45), [kv[q + 2], 0.0, 1.0]])
    g = s._grid(us, vs, du, dv)
    U, V = np.meshgrid(us, vs, indexing="ij")
    ref = s.derivatives(U, V, du, dv)
    assert g.shape == ref.shape
    assert np.abs(g - ref).max() <= 1e-12 * max(1.0, np.abs(ref).max())
    assert np.abs(s.grid(us, vs) - s(U, V)).max() <= 1e-14


@pytest.mark.parametrize("rational", [False, True])
def test_grid_of_a_large_net_uses_no_dense_basis(rational):
    """A 1500 x 1500 grid of a 3000 x 2000-pole net: the dense basis matrices were
    1500 x 3000 + 1500 x 2000 values (60 MB) plus an (nu, Mv, D) intermediate of 108 MB
    and 27 GFlop of products; the local path needs the output (54 MB) and bounded
    blocks (60 MB measured with whole-row passes, 17-18 MB with the block products,
    NURBS too: the division runs per block, no homogeneous grid)."""
    import tracemalloc
    rng = np.random.default_rng(5)
    W = rng.uniform(0.5, 2.0, (3000, 2000)) if rational else None
    s = BSplineSurface(rng.random((3000, 2000, 3)), 3, 3, weights=W)
    us, vs = np.linspace(0, 1, 1500), rng.random(1500)
    tracemalloc.start()
    try:
        g = s.grid(us, vs)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < g.nbytes + 40e6
    i, j = rng.integers(0, 1500, 200), rng.integers(0, 1500, 200)
    assert np.abs(g[i, j] - s(us[i], vs[j])).max() <= 1e-14
