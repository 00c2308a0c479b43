"""Bezier/B-spline surfaces at extreme scales and orders (issue 14)."""
from __future__ import annotations

import numpy as np
import pytest

import cagd
from cagd import BezierSurface, CagdError


@pytest.mark.parametrize("scale", [1e-300, 1e-100, 1e100, 1e300])
def test_normal_scale_invariant(scale):
    # reported: OverflowError from normal at 1e300
    P = np.random.default_rng(0).random((3, 4, 3))
    u, v = np.linspace(0.1, 0.9, 5), np.linspace(0.2, 0.8, 5)
    ref = BezierSurface(P).normal(u, v)
    su, sv = BezierSurface(P).derivative(u, v, 1, 0), BezierSurface(P).derivative(u, v, 0, 1)
    direct = np.cross(su, sv)
    direct /= np.linalg.norm(direct, axis=-1, keepdims=True)
    assert np.allclose(ref, direct, atol=1e-15)
    assert np.allclose(BezierSurface(P * scale).normal(u, v), ref, atol=1e-14)


def test_orders_bounded():
    s = BezierSurface(np.random.default_rng(1).random((3, 3, 3)))
    for call in (lambda: s.grid([0.5], [0.5], du=10**18), lambda: s.derivatives(0.5, 0.5, 10**18, 0)):
        with pytest.raises(CagdError, match="MAX_ORDER"):
            call()
    assert np.all(s.derivatives(0.5, 0.5, cagd.MAX_ORDER, 0)[3:] == 0)


def sphere_octant(r):
    """The exact rational sphere of radius r (oracle: K = 1/r^2, |H| = 1/r)."""
    return cagd.sphere(r)


@pytest.mark.parametrize("r", [1e-150, 1e-100, 1.0, 1e100, 1e150])
def test_sphere_curvatures_scale_invariant(r):
    s = sphere_octant(r).to_nurbs()
    (u0, u1), (v0, v1) = s.domain
    u = np.linspace(u0, u1, 7)[1:-1]
    v = np.linspace(v0, v1, 7)[1:-1]
    uu, vv = np.meshgrid(u, v)
    assert np.allclose(s.gaussian_curvature(uu, vv) * r * r, 1.0, rtol=1e-10)
    assert np.allclose(np.abs(s.mean_curvature(uu, vv)) * r, 1.0, rtol=1e-10)
    (E, F, G), (L, M, N) = s.fundamental_forms(uu, vv)
    assert np.allclose(L / E * r, np.sign(L / E), rtol=1e-9)      # normal curvature along u: 1/r


def test_curvature_beyond_float_range_is_a_cagd_error():
    s = cagd.sphere(1e-200).to_nurbs()
    (u0, u1), (v0, v1) = s.domain
    with pytest.raises(CagdError, match="floating-point range"):
        s.gaussian_curvature(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    assert abs(s.mean_curvature(0.5 * (u0 + u1), 0.5 * (v0 + v1))) * 1e-200 == pytest.approx(1.0, rel=1e-10)


def test_grid_size_bounded():
    from cagd._checks import MAX_SAMPLES
    s = BezierSurface(np.random.default_rng(2).random((3, 3, 3)))
    n = int(np.sqrt(MAX_SAMPLES)) + 2
    with pytest.raises(CagdError, match="MAX_SAMPLES"):
        s.grid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    assert s.grid(np.linspace(0, 1, 30), np.linspace(0, 1, 20)).shape == (30, 20, 3)
