"""The polynomial pieces of sampled B-spline points (issue 17, exactness;
cagd/fitting/pieces.py): Bezier values anywhere on the line and speeds at the ends,
joins that give the knots between two pieces and the right piece's affine map exactly,
and cubics with uneven knots sampled at random places that come back only through this
stage."""
from __future__ import annotations

from math import comb

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd.fitting.free_knots as free_knots
from benchmarks.knot_recovery import both_ways, fair_poles
from cagd import BSplineCurve, fit_curve
import cagd.fitting.pieces as pieces
from cagd.fitting.pieces import Piece, _at, _join, _power, _speed

EXACT = 1e-10


@given(st.integers(1, 6), st.lists(st.floats(-2.0, 3.0), min_size=1, max_size=5), st.integers(0, 2 ** 31))
def test_bezier_values_and_end_speeds_anywhere(p, s, seed):
    """Against the Bernstein form expanded by numpy's polynomial module (an independent
    power basis): the values at s inside and outside [0, 1], and the speeds |B'| at the
    ends by its polyder."""
    P = np.random.default_rng(seed).normal(size=(p + 1, 3))
    poly = np.polynomial.polynomial
    coef = sum(comb(p, i) * np.outer(poly.polymul(poly.polypow([0.0, 1.0], i), poly.polypow([1.0, -1.0], p - i)),
                                     P[i]) for i in range(p + 1))
    x = np.array(s)
    np.testing.assert_allclose(_at(_power(P), x), poly.polyval(x, coef).T, rtol=1e-10,
                               atol=1e-10 * (1 + np.abs(x).max()) ** p)
    for end in (0, 1):
        want = np.linalg.norm(poly.polyval(float(end), poly.polyder(coef)))
        assert _speed(P, end) == pytest.approx(want, rel=1e-12, abs=1e-12)


def _piece(curve: BSplineCurve, a: float, b: float) -> Piece:
    """The curve on [a, b] (inside one knot span) as a piece: its Bezier poles."""
    seg = curve.segment(a, b)
    assert seg.control_points.shape[0] == curve.degree + 1
    return Piece(0, 0, seg.control_points, np.linspace(0.0, 1.0, 5))


@settings(max_examples=20, deadline=None)
@given(st.integers(1, 2), st.integers(0, 2 ** 31))
def test_join_gives_the_knots_and_the_map(count, seed):
    """A cubic with ``count`` knots between two windows, one in the span before them and
    one in the span after: the knots (in the left window's variable), the right window's
    offset and scale come back to 1e-8 (the join's tolerance is on its residual)."""
    rng = np.random.default_rng(seed)
    inner = np.sort(rng.uniform(0.3, 0.7, count))
    while np.diff(inner).size and np.diff(inner).min() < 0.02:
        inner = np.sort(rng.uniform(0.3, 0.7, count))
    c = BSplineCurve(fair_poles(rng, 4 + count), 3, np.r_[[0.0] * 4, inner, [1.0] * 4])
    a0, a1 = rng.uniform(0.05, 0.15), inner[0] - rng.uniform(0.0, 0.02)
    b0, b1 = inner[-1] + rng.uniform(0.0, 0.02), rng.uniform(0.85, 0.95)
    joint = _join(_piece(c, a0, a1), _piece(c, b0, b1), 3, count)
    assert joint is not None
    alpha, beta, knots = joint
    h = a1 - a0
    np.testing.assert_allclose(knots, (inner - a0) / h, rtol=0, atol=1e-8)
    np.testing.assert_allclose([alpha, beta], [(b0 - a0) / h, (b1 - b0) / h], rtol=1e-8, atol=1e-8)


@settings(max_examples=20, deadline=None, derandomize=True)
@given(st.integers(2, 3), st.integers(0, 2 ** 31))
def test_join_gives_a_multiple_knot(r, seed):
    """A cubic with one knot of multiplicity r (C^1, or C^0 with a kink) between two
    windows: the knot comes back r times to 1e-8 and the right window's map takes the
    knot to its own place there (at r = 3 the scale is free: a C^0 join fixes only where
    the pieces meet); a simple knot does not join it. (The same examples every run: the
    join is a local solver, and 1 of 1,500 random double knots ends in a local minimum
    with no join; 1 of 1,500 triple knots did too until the free scale was held.)"""
    rng = np.random.default_rng(seed)
    u = rng.uniform(0.35, 0.65)
    c = BSplineCurve(fair_poles(rng, 4 + r), 3, np.r_[[0.0] * 4, [u] * r, [1.0] * 4])
    a0, a1 = rng.uniform(0.05, 0.15), u - rng.uniform(0.0, 0.02)
    b0, b1 = u + rng.uniform(0.0, 0.02), rng.uniform(0.85, 0.95)
    left, right = _piece(c, a0, a1), _piece(c, b0, b1)
    joint = _join(left, right, 3, 1, r)
    assert joint is not None
    alpha, beta, knots = joint
    h = a1 - a0
    np.testing.assert_allclose(knots, [(u - a0) / h] * r, rtol=0, atol=1e-8)
    assert (knots[0] - alpha) / beta == pytest.approx((u - b0) / (b1 - b0), abs=1e-8)
    if r == 2:
        np.testing.assert_allclose([alpha, beta], [(b0 - a0) / h, (b1 - b0) / h], rtol=1e-8, atol=1e-8)
    assert _join(left, right, 3, 1) is None


def test_no_knot_between_runs_of_one_polynomial():
    """Two windows of one span: no knot, and the map between them."""
    c = BSplineCurve(fair_poles(np.random.default_rng(4), 5), 3, [0, 0, 0, 0, 0.8, 1, 1, 1, 1])
    joint = _join(_piece(c, 0.1, 0.3), _piece(c, 0.35, 0.7), 3, 1)
    assert joint is not None and len(joint[2]) == 0
    np.testing.assert_allclose(joint[:2], [1.25, 1.75], rtol=1e-8)


def test_two_knots_as_one_do_not_join():
    """Two knots between the windows, tried as one: no join (the residual stays ~1e-2)."""
    c = BSplineCurve(fair_poles(np.random.default_rng(5), 6), 3, [0, 0, 0, 0, 0.45, 0.55, 1, 1, 1, 1])
    assert _join(_piece(c, 0.1, 0.44), _piece(c, 0.56, 0.9), 3, 1) is None


@pytest.mark.parametrize("inner, m, seed", [((0.039, 0.0677), 566, 11), ((0.1333, 0.1612, 0.5492, 0.7726, 0.7774,
                                                                          0.8254, 0.9222), 630, 12)])
def test_uneven_cubics_come_back(monkeypatch, inner, m, seed):
    """Cubics whose knots are 0.03 and 0.005 apart, sampled at random places (parameters
    not given): the same count back, within 1e-10 both ways, at tol 1e-9; without the
    pieces they end at hundreds of control points (the adaptive fit's)."""
    rng = np.random.default_rng(seed)
    n = len(inner) + 4
    c = BSplineCurve(fair_poles(rng, n), 3, np.r_[[0.0] * 4, inner, [1.0] * 4])
    Q = c(np.sort(np.r_[0.0, 1.0, rng.random(m - 2)]))
    r = fit_curve(Q, 1e-9)
    assert r.converged and r.max_error <= 1e-9
    assert len(r.curve.control_points) == n
    np.testing.assert_allclose(np.asarray(r.curve.knots)[4:-4], inner, rtol=0, atol=1e-8)
    assert both_ways(r.curve, c) <= EXACT
    monkeypatch.setattr(free_knots, "_segmented", lambda *a, **k: None)
    assert len(fit_curve(Q, 1e-9).curve.control_points) > n


def test_a_join_stays_finite(recwarn):
    """Four knots 1e-5 apart between two quadratic-looking cubic pieces, tried as one: the
    knot without a jump used to run away (steps of 1e76 .. 1e103) until (s - t)^3
    overflowed and the least squares raised LinAlgError; now the unknowns stay in their
    box: no join, no warning (a fuzz of 6,000 joins: no exception, no warning)."""
    PL = np.array([[-1.4428435432074744, -0.19671277742948456], [-1.3011455404712489, -0.2802050181087551],
                   [-0.9293125464013963, -1.3275079754825645], [0.6327381926293112, -0.3859434668948057]])
    PR = np.array([[-0.9739417495356387, -0.6819175813909255], [-0.5031581743892228, -0.38247810501099205],
                   [-0.41538406420915425, -1.217176789737684], [-0.5354815216156142, -1.5850444311802803]])
    with np.errstate(all="raise"):
        for count in (1, 2):
            _join(Piece(0, 16, PL, np.linspace(0, 1, 16)), Piece(20, 36, PR, np.linspace(0, 1, 16)), 3, count)
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


@pytest.mark.parametrize("r, seed", [(2, 21), (3, 22)])
def test_multiple_knots_come_back(monkeypatch, r, seed):
    """Cubics with a double knot (C^1) and with a triple one and a kink (C^0, Bezier
    pieces joined at a corner), sampled at 600 random places (parameters not given): the
    same count back, within 1e-10 both ways, at tol 1e-9, the knot's multiplicity too
    (the knots themselves at r = 2; at a C^0 knot the speed ratio is free, so the knot
    values are one parametrisation of the same curve); with simple knots only the fit
    ends at hundreds of control points."""
    rng = np.random.default_rng(seed)
    n = 5 + r
    inner = [0.3] + [0.62] * r
    c = BSplineCurve(fair_poles(rng, n), 3, np.r_[[0.0] * 4, inner, [1.0] * 4])
    if r == 3:
        P = np.array(c.control_points)
        P[5:] += 0.3 * np.linalg.norm(P[4] - P[3]) * np.array([0.0, 0.0, 1.0])   # a kink at the knot
        c = BSplineCurve(P, 3, c.knots)
    Q = c(np.sort(np.r_[0.0, 1.0, rng.random(598)]))
    r_fit = fit_curve(Q, 1e-9)
    assert r_fit.converged and r_fit.max_error <= 1e-9
    assert len(r_fit.curve.control_points) == n
    found = np.asarray(r_fit.curve.knots)[4:-4]
    assert np.unique(found, return_counts=True)[1].tolist() == [1, r]
    if r == 2:
        np.testing.assert_allclose(found, inner, rtol=0, atol=1e-8)
    assert both_ways(r_fit.curve, c) <= EXACT
    monkeypatch.setattr(pieces, "_join_kinds", lambda p, most: [(1, 1), (2, 1)])
    assert len(fit_curve(Q, 1e-9).curve.control_points) > n


def test_rows_between_pieces_take_their_feet():
    """A planar cubic with a triple knot (fuzz case): the join finds the knot, but the
    four rows between the pieces got their parameters by chord length, one on the wrong
    side of the knot, and the fit stopped 1.2e-3 off with one control point per point;
    their feet on the nearer piece's polynomial give the curve back."""
    P = [[0.0, 0.0], [2.290441099426166, 0.46557528229307993], [2.21864338545876, 0.22259906198908713],
         [3.162674745226261, -0.25964390266074394], [2.2591562167467103, 0.7774118621440114],
         [2.1126141772733673, 1.6769187230464877], [3.318670026685851, 3.3912600514525724]]
    u = 0.5248582573641618
    c = BSplineCurve(np.array(P), 3, [0, 0, 0, 0, u, u, u, 1, 1, 1, 1])
    Q = c(np.sort(np.r_[0.0, 1.0, np.random.default_rng(0).random(818)]))
    r = fit_curve(Q, 4.93321342684764e-09)
    assert r.converged and len(r.curve.control_points) == 7
    assert both_ways(r.curve, c) <= EXACT
