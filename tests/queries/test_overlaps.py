"""Curve overlaps (cagd.queries._overlaps) found during the curve–surface subdivision:
each overlap's ends are searched once, however many levels find fragments of it, and
end where the distance passes (1 - END_TOL_SHARE) tol (issue 16)."""
import numpy as np
import pytest

import cagd
from cagd.queries import _overlaps as ov, closest_point, intersect

ROT = np.linalg.qr(np.array([[0.8, 0.3, 0.5], [-0.4, 0.9, 0.2], [0.1, -0.2, 0.97]]))[0]


def _case():
    """A plane patch (turned off the axes) and a quadratic B-spline curve lying in it on
    [0, 0.5] (its first control points are in the plane), rising from it after."""
    S = cagd.BezierSurface(np.array([[[-0.5, -0.5, 0], [-0.5, 0.5, 0]], [[1.5, -0.5, 0], [1.5, 0.5, 0]]]) @ ROT.T)
    x = np.linspace(0, 1, 8)
    net = np.stack([x, 0.1 * np.sin(3 * x), [0, 0, 0, 0, 0, 0.01, 0.05, 0.1]], 1)
    return cagd.BSplineCurve(net @ ROT.T, 2), S


def test_an_overlap_is_grown_once(monkeypatch):
    """Fragments of the overlap come at several levels; its two ends are searched once
    (4 searches before, and the subdivision ran into max_pairs where the curve leaves
    the plane tangentially)."""
    searched = []
    real = ov._edges

    def spy(A, B, starts, *a, **kw):
        searched.extend(st[2] for st in starts)         # the directions
        return real(A, B, starts, *a, **kw)

    monkeypatch.setattr(ov, "_edges", spy)
    C, S = _case()
    res = intersect(C, S, tol=1e-9)
    assert res.converged and res.points == () and len(res.overlaps) == 1
    assert sorted(searched) == [-1.0, 1.0]


def test_an_overlap_ends_within_tol():
    """The end lies within (1 - END_TOL_SHARE) tol of the plane by closest_point (an
    independent projection) and is not short of it: the distance there is that bound
    to 1e-6, rising beyond (the curve leaves the plane)."""
    C, S = _case()
    tol = 1e-9
    (o,) = intersect(C, S, tol=tol).overlaps
    s0, s1 = o.param_a
    assert s0 == 0.0 and 0.5 < s1 < 0.51
    d = closest_point(S, C(np.array([s1, s1 + 1e-4]))).distances
    assert d[0] == pytest.approx((1 - ov.END_TOL_SHARE) * tol, rel=1e-6)
    assert d[1] > tol


@pytest.mark.parametrize("bump", [5, 12, 27, 33])
def test_an_overlap_does_not_step_over_a_gap(bump):
    """A quadratic B-spline lying in the plane but for a bump of 1e-3 (one control point
    lifted: the curve is off the plane on two spans): two overlaps, each within tol by
    closest_point. Growing an overlap by steps h, 2h, 4h, ... tested the step ends only,
    stepped over the bump and gave one overlap [0, 1], 7.5e-4 off in the middle (the edge
    of trj3_s1-al-214.stp face 8 touching face 12 at 7 places, issue 16)."""
    _, S = _case()
    x = np.linspace(0, 1, 40)
    z = np.zeros(40)
    z[bump] = 1e-3
    C = cagd.BSplineCurve(np.stack([x, 0.1 * np.sin(3 * x), z], 1) @ ROT.T, 2)
    res = intersect(C, S, tol=1e-9)
    assert res.converged and len(res.overlaps) == 2
    knots = np.unique(C.knots)
    off = (knots[bump - 2], knots[bump + 1])            # the support of the lifted point
    (a0, a1), (b0, b1) = (o.param_a for o in res.overlaps)
    assert a0 == 0.0 and b1 == 1.0 and off[0] <= a1 < b0 <= off[1]
    for o in res.overlaps:
        s = np.linspace(*o.param_a, 2001)
        assert closest_point(S, C(s)).distances.max() <= 1e-9


def test_the_ends_of_several_overlaps_are_searched_together(monkeypatch):
    """A curve lying in the plane on three stretches: the six ends are searched in one
    batch, one projection call a round for all of them (issue 16: trj3_s1-al-214.stp
    faces 4 x 6, 14 ends, 127 calls one end at a time; here 16 calls, 56 before, the
    same overlaps bit for bit), and each end lies within tol of the plane by
    closest_point while the curve beyond it leaves tol."""
    _, S = _case()
    x = np.linspace(0, 1, 40)
    z = np.zeros(40)
    z[[12, 26]] = 1e-3
    C = cagd.BSplineCurve(np.stack([x, 0.2 + 0.1 * x, z], 1) @ ROT.T, 2)
    batches = []
    real = ov._edges

    def spy(A, B, starts, *a, **kw):
        batches.append(len(starts))
        return real(A, B, starts, *a, **kw)

    monkeypatch.setattr(ov, "_edges", spy)
    calls = []
    real_project = ov.project_onto

    def count(*a, **kw):
        calls.append(1)
        return real_project(*a, **kw)

    monkeypatch.setattr(ov, "project_onto", count)
    res = intersect(C, S, tol=1e-9)
    assert res.converged and len(res.overlaps) == 3
    assert max(batches) == 6 and len(calls) <= 20              # 56 calls one end at a time
    for o in res.overlaps:
        s = np.array(o.param_a)
        inside = closest_point(S, C(s)).distances
        assert inside.max() <= 1e-9
        beyond = s + np.array([-1e-4, 1e-4])
        beyond = beyond[(beyond > 0) & (beyond < 1)]
        assert np.all(closest_point(S, C(beyond)).distances > 1e-9)
