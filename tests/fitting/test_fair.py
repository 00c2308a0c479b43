"""fair_curve (issue 17): the curvature-variation energy goes down, the curve stays within
tol of the original (dense evaluation and certified closest points: oracles that do not
use the convex-hull bound the method holds), the ends keep G0/G1/G2 exactly (the end
derivatives measured), wiggles go (fewer inflections), bad input names the argument."""
import numpy as np
import pytest

import cagd
from cagd import BSplineCurve, CagdError, fair_curve
from cagd.fitting.fair import energy, inflections


def wiggly(seed=0, noise=0.05):
    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, 40)
    P = np.stack([100 * s, 10 * np.sin(3 * s)], axis=1)
    P[2:-2] += rng.normal(0, noise, (36, 2))
    return BSplineCurve(P, 3)


@pytest.mark.parametrize("tol", [0.01, 0.05, 0.2])
def test_energy_down_within_tol(tol):
    c = wiggly()
    r = fair_curve(c, tol)
    assert r.energy_after < r.energy_before
    assert r.energy_before == pytest.approx(energy(c)) and r.energy_after == pytest.approx(energy(r.curve))
    t = np.linspace(0, 1, 20001)
    assert float(np.sqrt(((r.curve(t) - c(t)) ** 2).sum(-1)).max()) <= tol * (1 + 1e-12)
    assert float(cagd.closest_point(c, r.curve(t)).distances.max()) <= tol * (1 + 1e-12)
    assert r.max_deviation <= tol * (1 + 1e-12) and r.converged
    assert np.array_equal(r.curve.knots, c.knots) and r.curve.degree == 3


def test_wiggles_go():
    c = wiggly()
    r = fair_curve(c, 0.2)
    assert r.inflections_before == inflections(c) > 4
    assert r.inflections_after < r.inflections_before


@pytest.mark.parametrize("keep, order", [("G0", 0), ("G1", 1), ("G2", 2)])
def test_ends_keep_their_continuity(keep, order):
    c = wiggly(1)
    r = fair_curve(c, 0.1, keep=keep)
    for t in (0.0, 1.0):
        a, b = c.derivatives(t, order), r.curve.derivatives(t, order)
        scale = np.abs(a).max(axis=-1, keepdims=True)
        assert np.all(np.abs(a - b) <= 1e-12 * np.maximum(scale, 1.0))
    assert np.array_equal(r.curve.control_points[0], c.control_points[0])
    if order < 2:        # a free next control point: the derivative one order up moves
        d_a, d_b = c.derivatives(0.0, order + 1)[-1], r.curve.derivatives(0.0, order + 1)[-1]
        assert np.abs(d_a - d_b).max() > 1e-9


def test_zero_tolerance_is_the_original():
    c = wiggly(2)
    r = fair_curve(c, 0.0)
    assert np.array_equal(r.curve.control_points, c.control_points) or \
        np.abs(r.curve.control_points - c.control_points).max() <= 1e-12 * 100


def test_three_dimensional_curves():
    rng = np.random.default_rng(3)
    s = np.linspace(0, 1, 30)
    P = np.stack([np.cos(4 * s), np.sin(4 * s), s], axis=1) + rng.normal(0, 0.01, (30, 3))
    c = BSplineCurve(P, 3)
    r = fair_curve(c, 0.02)
    assert r.energy_after < 0.8 * r.energy_before and r.inflections_after < r.inflections_before
    t = np.linspace(0, 1, 5001)
    assert float(np.sqrt(((r.curve(t) - c(t)) ** 2).sum(-1)).max()) <= 0.02 * (1 + 1e-12)


@pytest.mark.parametrize("args, kwargs, word", [
    (("curve", 0.1), {}, "curve"),
    ((BSplineCurve([[0, 0], [1, 1], [2, 0]], 2, None, [1, 2, 1]), 0.1), {}, "rational"),
    ((BSplineCurve(np.random.default_rng(0).random((8, 2)), 3), -1.0), {}, "tol"),
    ((BSplineCurve(np.random.default_rng(0).random((8, 2)), 3), 0.1), {"keep": "G3"}, "keep"),
    ((BSplineCurve(np.random.default_rng(0).random((6, 2)), 3), 0.1), {"keep": "G2"}, "nothing can move"),
])
def test_bad_input(args, kwargs, word):
    with pytest.raises(CagdError, match=word):
        fair_curve(*args, **kwargs)


# --- surfaces -----------------------------------------------------------------------------
def bumpy_net(seed=0, n=14, noise=0.05):
    rng = np.random.default_rng(seed)
    x = np.linspace(0, 10, n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    return cagd.BSplineSurface(np.stack([X, Y, np.sin(X / 3) + rng.normal(0, noise, X.shape)], -1), 3, 3)


@pytest.mark.parametrize("tol", [0.01, 0.2])
def test_surface_energy_down_within_tol(tol):
    S = bumpy_net()
    r = cagd.fair_surface(S, tol)
    assert r.energy_after < r.energy_before and r.max_deviation <= tol * (1 + 1e-12)
    u = np.linspace(0, 1, 151)
    assert float(np.sqrt(((r.surface.grid(u, u) - S.grid(u, u)) ** 2).sum(-1)).max()) <= tol * (1 + 1e-12)


@pytest.mark.parametrize("keep, order", [("G0", 0), ("G1", 1), ("G2", 2)])
def test_surface_edges_keep_their_continuity(keep, order):
    S = bumpy_net(1)
    r = cagd.fair_surface(S, 0.1, keep=keep)
    t = np.linspace(0, 1, 61)
    for k in range(order + 1):          # cross-boundary derivatives up to the kept order, all 4 edges
        for a, b in (((0.0,), t), ((1.0,), t), (t, (0.0,)), (t, (1.0,))):
            du, dv = (k, 0) if len(a) == 1 else (0, k)
            assert np.abs(r.surface.grid(a, b, du, dv) - S.grid(a, b, du, dv)).max() <= 1e-9 * max(1.0, 10.0 ** k)
    du = (order + 1, 0)                 # one order up moves (something was faired near the edge)
    assert np.abs(r.surface.grid((0.0,), t, *du) - S.grid((0.0,), t, *du)).max() > 1e-6


def test_surface_bad_input():
    with pytest.raises(CagdError, match="surface"):
        cagd.fair_surface(cagd.sphere(1.0), 0.1)
    with pytest.raises(CagdError, match="no control point free"):
        cagd.fair_surface(cagd.BSplineSurface(np.random.default_rng(0).random((4, 4, 3)), 3, 3), 0.1)
    with pytest.raises(CagdError, match="keep"):
        cagd.fair_surface(bumpy_net(), 0.1, keep="C1")
    with pytest.raises(CagdError, match="tol"):
        cagd.fair_surface(bumpy_net(), -0.1)


def test_keep_of_the_wrong_type():
    with pytest.raises(CagdError, match="keep"):
        fair_curve(wiggly(), 0.1, keep=["G1"])
    with pytest.raises(CagdError, match="keep"):
        cagd.fair_surface(bumpy_net(), 0.1, keep=["G1"])
