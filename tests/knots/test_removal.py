"""Knot removal (cagd.knots.removal; Tiller, Piegl & Tiller 5.4 and 9.4.4, issue 17):
inserted knots come back out exactly; the certified bound holds against dense
evaluation (an independent oracle: the two curves at equal parameters); what a tight
tolerance cannot remove stays; OCCT's own RemoveKnot agrees on what is removable."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd import BSplineCurve, BSplineSurface, CagdError

from ..strategies import bspline_curves

EXACT = 1e-12
REMOVABLE = 1e-9          # removal tolerance (relative to the net) for inserted knots of random nets


def _dense(c, n=4001):
    a, b = c.domain
    return np.linspace(a, b, n)


@settings(max_examples=60, deadline=None)
@given(bspline_curves(kinds=("clamped",), max_degree=6), st.lists(st.floats(0.02, 0.98), min_size=1, max_size=4),
       st.integers(1, 3))
def test_inserted_knots_come_back_out(c, where, times):
    """Knots inserted (each up to `times`, at most the degree) and removed give the
    original curve back (dense evaluation, within REMOVABLE of the net), with at most its
    control points."""
    a, b = c.domain
    p = c.degree
    d = c
    for f in where:
        t = a + f * (b - a)
        have = int(np.count_nonzero(d.knots == t))
        k = min(times, p - have)
        if k > 0:
            d = d.insert_knot(t, k)
    scale = max(1.0, float(np.abs(c.control_points).max()))
    # the removal solves back through the alphas, which amplify rounding where inserted
    # knots crowd (triple knots 0.06 apart on a degree-4 NURBS: 1e-12 was not reachable)
    r = d.remove_knots(REMOVABLE * scale)
    out = r.result
    # at most the original count (a knot of the original may go too where the drawn net
    # makes it removable); with the original knots, the original control points
    assert len(out.control_points) <= len(c.control_points)
    if len(out.knots) == len(c.knots) and np.array_equal(out.knots, c.knots):
        assert np.abs(out.control_points - c.control_points).max() <= REMOVABLE * scale
    t = _dense(c)
    assert np.abs(out(t) - c(t)).max() <= REMOVABLE * scale
    assert r.removed == len(d.control_points) - len(out.control_points)


@settings(max_examples=60, deadline=None)
@given(bspline_curves(kinds=("clamped", "nonuniform", "periodic"), max_degree=5), st.floats(1e-4, 1.0))
def test_bound_holds_against_dense_evaluation(c, rel):
    """deviation (sampled) <= error_bound <= tol, and the dense oracle <= bound."""
    scale = max(float(np.ptp(c.control_points, axis=0).max()), 1e-3)
    tol = rel * scale
    r = c.remove_knots(tol)
    t = _dense(c)
    dense = float(np.linalg.norm(r.result(t) - c(t), axis=-1).max())
    slack = 1e-12 * max(1.0, float(np.abs(c.control_points).max()))
    assert r.error_bound <= tol
    assert dense <= r.error_bound + slack
    assert r.deviation <= r.error_bound + slack
    assert r.converged and r.message


def test_rational_circle_keeps_its_shape():
    """A NURBS circle with knots inserted: removal at 1e-12 gives the 9-point circle back;
    at 1e-3 it removes nothing more (the quarter joints are not removable)."""
    w = np.sqrt(0.5)
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    c = BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, w, 1, w, 1, w, 1, w, 1])
    d = c.insert_knot(0.1).insert_knot(0.6)
    r = d.remove_knots(1e-12)
    assert r.removed == 2 and len(r.result.control_points) == 9
    t = _dense(c)
    assert np.abs(np.linalg.norm(r.result(t), axis=1) - 1).max() <= 1e-14
    r2 = c.remove_knots(1e-3)
    assert np.abs(np.linalg.norm(r2.result(t), axis=1) - 1).max() <= r2.error_bound + 1e-15
    assert r2.error_bound <= 1e-3


def test_fewer_control_points_for_a_dense_interpolant():
    """400 samples of a helix interpolated (400 control points): at 1e-5 far fewer remain,
    and the dense deviation is within the bound."""
    t = np.linspace(0, 1, 400)
    c = cagd.interpolate(np.c_[np.cos(3 * t), np.sin(3 * t), t], 3)
    r = c.remove_knots(1e-5)
    assert len(r.result.control_points) < 40
    s = _dense(c, 20001)
    assert np.linalg.norm(r.result(s) - c(s), axis=1).max() <= r.error_bound <= 1e-5


def test_tight_tolerance_removes_nothing_from_a_random_curve():
    rng = np.random.default_rng(5)
    c = BSplineCurve(rng.random((20, 3)), 3)
    r = c.remove_knots(1e-9)
    assert r.removed == 0 and r.error_bound == 0 and r.result == c or \
        np.array_equal(r.result.control_points, c.control_points)


def test_periodic_curve_comes_back_clamped():
    rng = np.random.default_rng(2)
    c = BSplineCurve(rng.random((8, 2)), 3, np.linspace(0, 1, 9), periodic=True)
    r = c.refine([0.33, 0.71]).remove_knots(1e-12)
    assert not r.result.periodic and "clamped" in r.message
    t = _dense(c)
    assert np.abs(r.result(t) - c(t)).max() <= 1e-12


@pytest.mark.parametrize("direction", ["u", "v"])
def test_surface_rows_removed_together(direction):
    rng = np.random.default_rng(3)
    W = rng.uniform(0.5, 2.0, (7, 6))
    S = BSplineSurface(rng.random((7, 6, 3)), 3, 2, weights=W)
    S2 = S.insert_knot(direction, 0.37).insert_knot(direction, 0.61, 2)
    r = S2.remove_knots(1e-12, direction)
    assert r.removed == 3
    assert np.abs(r.result.control_points - S.control_points).max() <= 1e-12
    assert np.abs(r.result.weights - W).max() <= 1e-12
    # a loose tolerance: the bound holds on a dense grid
    r = S.remove_knots(0.05, direction)
    g = np.linspace(0, 1, 81)
    assert np.linalg.norm(r.result.grid(g, g) - S.grid(g, g), axis=-1).max() <= r.error_bound + 1e-14


@pytest.mark.parametrize("tol", [-1.0, float("nan"), "x", float("inf")])
def test_bad_tolerance(tol):
    c = BSplineCurve(np.random.default_rng(0).random((6, 2)), 3)
    with pytest.raises(CagdError, match="tol"):
        c.remove_knots(tol)


def test_bad_direction():
    S = BSplineSurface(np.random.default_rng(0).random((4, 4, 3)), 3, 3)
    with pytest.raises(CagdError, match="direction"):
        S.remove_knots(1e-3, "w")


def test_occt_agrees_on_what_is_removable():
    """OCCT's Geom_BSplineCurve::RemoveKnot(index, 0, tol) on the same curve: a knot
    inserted into a random cubic is removable for both at 1e-9; an original knot of the
    random cubic for neither."""
    pytest.importorskip("OCP")
    from cagd.occ import from_occ, to_occ
    rng = np.random.default_rng(7)
    c = BSplineCurve(rng.random((9, 3)), 3)
    d = c.insert_knot(0.45)
    g = to_occ(d)
    idx = [i for i in range(2, g.NbKnots()) if abs(g.Knot(i) - 0.45) < 1e-15][0]
    assert g.RemoveKnot(idx, 0, 1e-9)
    ours = d.remove_knots(1e-9)
    assert ours.removed == 1
    t = _dense(c)
    assert np.abs(from_occ(g)(t) - ours.result(t)).max() <= 1e-12
    g2 = to_occ(c)
    assert not g2.RemoveKnot(3, 0, 1e-9)
    assert c.remove_knots(1e-9).removed == 0
