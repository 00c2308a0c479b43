"""Degree elevation and Bezier decomposition are local (issue 14): O(n) memory, exact,
at any accepted degree. Oracle: scipy.interpolate.BSpline of the original curve."""
from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from cagd import BSplineCurve, BezierCurve

scipy_interpolate = pytest.importorskip("scipy.interpolate")


def random_curve(n, p, seed, mult=1):
    rng = np.random.default_rng(seed)
    inner = np.repeat(np.sort(rng.random((n - p - 1) // mult)), mult)
    P = rng.random((len(inner) + p + 1, 3))
    knots = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    return BSplineCurve(P, p, knots), knots, P


@pytest.mark.parametrize("n,p,times,mult", [(10, 3, 1, 1), (20, 2, 3, 1), (30, 4, 2, 2), (16, 3, 1, 3),
                                            (40, 30, 2, 1), (90, 60, 5, 1)])
def test_elevated_curve_is_the_same_curve(n, p, times, mult):
    c, knots, P = random_curve(n, p, n + p, mult)
    e = c.elevate(times)
    assert e.degree == p + times
    t = np.linspace(0, 1, 301)
    ref = scipy_interpolate.BSpline(knots, P, p)(t)
    assert np.abs(e(t) - ref).max() <= 1e-12 * np.abs(P).max()


def test_elevation_keeps_continuity_at_low_degree():
    c, knots, _ = random_curve(12, 3, 7)
    e = c.elevate(2)
    vals, counts = np.unique(e.knots, return_counts=True)
    assert np.all(counts[1:-1] == 3)            # simple knots of a cubic -> multiplicity 1 + 2


def test_elevate_on_knots_one_ulp_apart():
    # reported: numpy LinAlgError
    x = 0.5
    k = [0, 0, 0, 0, x, np.nextafter(x, 1), 1, 1, 1, 1]
    P = np.random.default_rng(2).random((6, 2))
    c = BSplineCurve(P, 3, k)
    e = c.elevate()
    t = np.linspace(0, 1, 201)
    assert np.abs(e(t) - c(t)).max() <= 1e-12


def test_rational_elevation():
    c = BSplineCurve([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], 2, [0, 0, 0, .5, .5, 1, 1, 1],
                     [1, 2 ** -.5, 1, 2 ** -.5, 1])
    e = c.elevate(3)
    t = np.linspace(0, 1, 101)
    assert np.abs(np.linalg.norm(e(t), axis=1) - 1).max() <= 1e-14


def test_1e5_poles_elevate_and_to_bezier_are_linear():
    """Reported: elevate asked for 298 GiB; to_bezier took 84 s."""
    rng = np.random.default_rng(0)
    c = BSplineCurve(np.cumsum(rng.random((100_000, 3)) - 0.5, axis=0), 3)
    tracemalloc.start()
    try:
        e = c.elevate()
        peak_e = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        pieces = c.to_bezier()
        peak_b = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak_e < 1e9 and peak_b < 1e9
    assert len(pieces) == 100_000 - 3
    t = rng.random(300)
    assert np.abs(e(t) - c(t)).max() <= 1e-12 * np.abs(c.control_points).max()
    i = 4321
    lo, hi = c.knots[3 + i], c.knots[4 + i]
    s = np.linspace(0, 1, 5)
    assert np.abs(pieces[i](s) - c(lo + s * (hi - lo))).max() <= 1e-12 * np.abs(c.control_points).max()


def test_high_degree_bezier_elevation_is_exact():
    P = np.random.default_rng(3).random((81, 2))
    c = BezierCurve(P)
    e = c.elevate(40)
    t = np.linspace(0, 1, 51)
    assert np.abs(e(t) - c(t)).max() <= 1e-12


@pytest.mark.parametrize("p", [1, 2, 3, 5, 8])
def test_refine_equals_repeated_insertion_and_scipy(p):
    rng = np.random.default_rng(p)
    c, knots, P = random_curve(p + 8, p, 10 + p)
    new = np.concatenate([rng.random(25), np.repeat(knots[p + 2], p - 1)])
    r = c.refine(new)
    one_by_one = c
    for k in np.sort(new):
        one_by_one = one_by_one.insert_knot(k)
    assert np.array_equal(r.knots, one_by_one.knots)
    assert np.abs(r.control_points - one_by_one.control_points).max() <= 1e-13
    t = np.linspace(0, 1, 301)
    ref = scipy_interpolate.BSpline(knots, P, p)(t)
    assert np.abs(scipy_interpolate.BSpline(r.knots, r.control_points, p)(t) - ref).max() <= 1e-14


def test_refine_many_knots_is_linear():
    """1e5 new knots on a 1,000-pole curve: was 1e5 Boehm insertions of O(n) each."""
    rng = np.random.default_rng(1)
    c = BSplineCurve(rng.random((1000, 3)), 3)
    r = c.refine(rng.random(100_000))
    assert len(r.control_points) == 101_000
    t = rng.random(500)
    assert np.abs(r(t) - c(t)).max() <= 1e-13


def test_refine_rejects_bad_knots():
    from cagd import CagdError
    c = BSplineCurve(np.random.default_rng(2).random((6, 2)), 3)
    for bad in ([1.5], [np.nan], [0.5, 0.5, 0.5, 0.5], [0.0]):
        with pytest.raises(CagdError, match="new_knots"):
            c.refine(bad)
    rat = BSplineCurve([[1, 0], [1, 1], [0, 1]], 2, None, [1, 2 ** -.5, 1])
    t = np.linspace(0, 1, 51)
    assert np.abs(rat.refine([0.3, 0.3, 0.7])(t) - rat(t)).max() <= 1e-15


def test_refine_floating_end_with_repeated_knots():
    """The support of the first new basis function misses the domain (found by the
    surface refine property test): the same result as one-by-one insertion."""
    knots = [3.8769593, 3.8769593, 4.24847413, 4.24847413, 4.24847413, 4.85124851, 4.85124851, 4.99930966,
             4.99930966]
    c = BSplineCurve(np.random.default_rng(3).random((5, 2)), 3, knots)
    r = c.refine([4.560275312249374])
    ref = c.insert_knot(4.560275312249374)
    assert np.array_equal(r.knots, ref.knots)
    assert np.abs(r.control_points - ref.control_points).max() <= 1e-14


def _continuity_curve(p, seed, rational=False):
    """Degree p, p + 8 poles, interior knots simple except one double knot."""
    rng = np.random.default_rng(seed)
    n = p + 8
    inner = np.sort(rng.random(n - p - 1))
    inner[2] = inner[1]
    knots = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    P = rng.random((n, 3)) - 0.5
    w = rng.uniform(0.5, 2.0, n) if rational else None
    return BSplineCurve(P, p, knots, w), knots, P, w


@pytest.mark.parametrize("p", [3, 20, 21, 40, 100])
@pytest.mark.parametrize("times", [1, 2])
def test_elevation_keeps_continuity_at_every_degree(p, times):
    """Issue 14: above degree 20 elevate fell back to C^0 knots (a collocation solve
    whose condition grows like 2^q). Oracle: scipy's de Boor evaluation of the
    original curve; every distinct knot keeps its value and gains ``times``."""
    c, knots, P, _ = _continuity_curve(p, p + times)
    e = c.elevate(times)
    assert e.degree == p + times
    vals, mults = np.unique(knots, return_counts=True)
    new_vals, new_mults = np.unique(e.knots, return_counts=True)
    assert np.array_equal(new_vals, vals)
    assert np.array_equal(new_mults, mults + times)
    t = np.linspace(0, 1, 2001)
    ref = scipy_interpolate.BSpline(knots, P, p)(t)
    size = np.abs(P).max()
    assert np.abs(scipy_interpolate.BSpline(e.knots, e.control_points, p + times)(t) - ref).max() <= 1e-12 * size
    assert np.abs(e(t) - ref).max() <= 1e-12 * size


@pytest.mark.parametrize("p", [21, 40])
def test_rational_elevation_keeps_continuity_at_high_degree(p):
    c, knots, P, w = _continuity_curve(p, 5, rational=True)
    e = c.elevate(1)
    assert np.array_equal(np.unique(e.knots, return_counts=True)[1], np.unique(knots, return_counts=True)[1] + 1)
    t = np.linspace(0, 1, 1001)
    hom = scipy_interpolate.BSpline(knots, np.hstack([P * w[:, None], w[:, None]]), p)(t)
    assert np.abs(e(t) - hom[:, :3] / hom[:, 3:]).max() <= 1e-12 * np.abs(P).max()


@pytest.mark.parametrize("p", [20, 40, 100])
def test_high_degree_refine_is_stable(p):
    """refine by one knot at degree 20 was off by 1e-3 (a de Boor triangle over all p
    arguments on one span extrapolates); oracle: one-by-one Boehm insertion and scipy."""
    c, knots, P, _ = _continuity_curve(p, 11)
    new = [0.5, 0.25, 0.25]
    r = c.refine(new)
    one_by_one = c.insert_knot(0.25).insert_knot(0.25).insert_knot(0.5)
    assert np.array_equal(r.knots, one_by_one.knots)
    assert np.abs(r.control_points - one_by_one.control_points).max() <= 1e-13
    t = np.linspace(0, 1, 1001)
    ref = scipy_interpolate.BSpline(knots, P, p)(t)
    assert np.abs(scipy_interpolate.BSpline(r.knots, r.control_points, p)(t) - ref).max() <= 1e-13


def test_high_degree_many_poles_elevate_is_linear():
    """Degree 25 (beyond the old collocation's reach) on 5,000 poles: O(n) memory
    (the blossom arguments are made per chunk: all at once they were (m, q, p)
    indices, 208 MB at 20,000 poles) and exact against scipy."""
    rng = np.random.default_rng(4)
    P = np.cumsum(rng.random((5000, 3)) - 0.5, axis=0)
    c = BSplineCurve(P, 25)
    tracemalloc.start()
    try:
        e = c.elevate()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 100e6
    assert np.all(np.unique(e.knots, return_counts=True)[1][1:-1] == 2)
    t = rng.random(400)
    ref = scipy_interpolate.BSpline(c.knots, P, 25)(t)
    assert np.abs(e(t) - ref).max() <= 1e-12 * np.abs(P).max()


def test_refine_unclamped_end_with_a_discontinuity():
    """Found by a randomized check against one-by-one insertion: the domain end 0.472
    has multiplicity p + 1 with a knot beyond it, so the rows f(0.472, 0.472) are the
    control points of the pieces on both sides (the values alone do not tell which);
    such curves are refined one knot at a time."""
    k = [0.064, 0.064, 0.095, 0.195, 0.427, 0.472, 0.472, 0.472, 0.717]
    c = BSplineCurve(np.random.default_rng(0).random((6, 2)), 2, k)
    r = c.refine([0.13549092, 0.195])
    ref = c.insert_knot(0.13549092).insert_knot(0.195)
    assert np.array_equal(r.knots, ref.knots)
    assert np.abs(r.control_points - ref.control_points).max() <= 1e-15
