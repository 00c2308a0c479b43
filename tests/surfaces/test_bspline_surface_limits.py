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
