"""Composite curves (seed 004, "组合曲线"): evaluation against the pieces, the single
NURBS form against the composite, joints and their continuity."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.curves.composite import CompositeCurve
from cagd.knots import distinct_with_multiplicities
from cagd.operations import join
from strategies import bspline_curves

SETTINGS = settings(max_examples=30, deadline=None)


def chain(curves):
    """Translate each curve so that it starts where the previous one ends."""
    out = [curves[0]]
    for c in curves[1:]:
        out.append(c.translated(out[-1](out[-1].domain[1]) - c(c.domain[0])))
    return out


def mixed_pieces():
    bez = BezierCurve([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])                      # degree 3
    rat = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], [1.0, np.sqrt(0.5), 1.0])       # quarter circle
    bsp = BSplineCurve([[0, 0], [1, -1], [2, 0], [3, -2], [4, 1], [5, 0]], 4,
                       [2, 2, 2, 2, 2, 2.7, 3.5, 3.5, 3.5, 3.5, 3.5])                       # degree 4 on [2, 3.5]
    lin = BSplineCurve([[0, 0], [1, 1], [2, 0]], 1, [5, 5, 6, 7, 7])                          # degree 1 with a kink
    per = BSplineCurve([[0, 0], [1, 0], [1, 1], [0, 1]], 3, periodic=True)                   # closed piece
    return chain([bez, rat, bsp, lin, per])


def reference(curves, t, order=0):
    """Piece-by-piece evaluation with a Python loop over the parameters."""
    out = []
    s = curves[0].domain[0]
    starts = [s]
    for c in curves:
        s = s + (c.domain[1] - c.domain[0])
        starts.append(s)
    for x in t:
        i = min(np.searchsorted(starts[1:-1], x, side="right"), len(curves) - 1)
        c = curves[i]
        out.append(c.derivatives(min(c.domain[0] + (x - starts[i]), c.domain[1]), order))
    return np.array(out)


def test_parametrisation_and_evaluation():
    pieces = mixed_pieces()
    comp = CompositeCurve(pieces)
    lengths = [c.domain[1] - c.domain[0] for c in pieces]
    assert comp.domain == (0.0, sum(lengths))
    assert np.allclose(comp.breakpoints, np.concatenate([[0], np.cumsum(lengths)]), rtol=0, atol=1e-15)
    assert np.array_equal(comp.joints, comp.breakpoints[1:-1]) and len(comp) == 5
    t = np.random.default_rng(0).uniform(*comp.domain, 300)
    t = np.concatenate([t, comp.breakpoints])
    got = comp.derivatives(t, 2)
    ref = reference(pieces, t, 2)
    assert np.abs(np.moveaxis(got, 0, 1) - ref).max() <= 1e-13 * np.abs(ref).max()
    assert comp(t.reshape(2, -1)).shape == (2, len(t) // 2, 2)
    # at a joint the right piece is used, at the end the last
    assert np.array_equal(comp.piece_index(comp.breakpoints), [0, 1, 2, 3, 4, 4])


def test_to_nurbs_mixed_pieces():
    pieces = mixed_pieces()
    comp = CompositeCurve(pieces)
    nurbs = comp.to_nurbs()
    assert nurbs.is_rational and nurbs.degree == 4 and nurbs.domain == comp.domain
    vals, mults = distinct_with_multiplicities(nurbs.knots)
    inner = mults[np.isin(vals, comp.joints)]
    assert np.all(inner == 4)                              # multiplicity = degree at the joints
    t = np.concatenate([np.linspace(*comp.domain, 2001), comp.breakpoints])
    err = np.abs(nurbs(t) - comp(t)).max()
    assert err <= 1e-12 * np.abs(comp(t)).max()
    # one-sided derivatives agree inside the pieces
    inside = t[~np.isin(t, comp.breakpoints)]
    d_n, d_c = nurbs.derivatives(inside, 1), comp.derivatives(inside, 1)
    assert np.abs(d_n - d_c).max() <= 1e-10 * np.abs(d_c).max()


def test_to_nurbs_weights_scaled_per_piece():
    """Joint weights differ (2 vs 5): each piece's weights are scaled by one constant."""
    A = BezierCurve([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], [1.0, 3.0, 2.0])
    B = BezierCurve([[2.0, 0.0], [3.0, -1.0], [4.0, 1.0]], [5.0, 1.0, 4.0])
    comp = CompositeCurve([A, B])
    n = comp.to_nurbs()
    assert np.allclose(n.weights, [1.0, 3.0, 2.0, 2.0 / 5.0, 8.0 / 5.0], rtol=1e-15, atol=0)
    t = np.linspace(0, 2, 501)
    assert np.abs(n(t) - comp(t)).max() <= 1e-14


def test_polynomial_pieces_stay_polynomial():
    comp = CompositeCurve(chain([BezierCurve([[0, 0], [1, 1]]), BezierCurve([[0, 0], [1, 2], [2, 0]])]))
    n = comp.to_nurbs()
    assert not n.is_rational and n.degree == 2 and len(n.control_points) == 5
    t = np.linspace(0, 2, 301)
    assert np.abs(n(t) - comp(t)).max() <= 1e-14


@SETTINGS
@given(st.lists(bspline_curves(max_degree=6, dims=(3, 3)), min_size=1, max_size=4))
def test_to_nurbs_property(curves):
    comp = CompositeCurve(chain(curves))
    n = comp.to_nurbs()
    t = np.concatenate([np.linspace(*comp.domain, 400), comp.breakpoints])
    ref = comp(t)
    assert np.abs(n(t) - ref).max() <= 1e-12 * max(1.0, np.abs(ref).max())


def test_bezier_pieces_of_a_bspline():
    """The Bezier decomposition of a cubic B-spline, recomposed: the same curve, C2 joints."""
    c = BSplineCurve(np.random.default_rng(4).normal(size=(7, 3)), 3, [0, 0, 0, 0, 1, 2, 3.5, 4, 4, 4, 4])
    _, segs = c.bezier_segments()
    comp = CompositeCurve(segs)
    assert np.allclose(comp.joints, [1, 2, 3.5], rtol=0, atol=0)
    t = np.linspace(0, 4, 401)
    assert np.abs(comp(t) - c(t)).max() <= 1e-13
    reports = comp.continuity_at_joints()
    assert [r.level for r in reports] == ["C2"] * 3
    assert np.abs(comp.to_nurbs()(t) - c(t)).max() <= 1e-13
    assert comp.arc_length() == pytest.approx(c.arc_length(), rel=1e-10)


def test_continuity_at_joints_levels():
    P = BezierCurve([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])
    Q = join(P, [[6.0, 1.0], [7.0, 3.0]], "G2", alpha=0.5, beta=1.0)
    R = BezierCurve([Q.control_points[-1], Q.control_points[-1] + [1.0, -3.0]])
    comp = CompositeCurve([P, Q, R])
    levels = [r.level for r in comp.continuity_at_joints()]
    assert levels == ["G2", "C0"]
    assert comp.continuity_at_joints()[0].rel_tol == comp.rel_tol


def test_arc_length_and_transform():
    pieces = mixed_pieces()
    comp = CompositeCurve(pieces)
    assert comp.arc_length() == pytest.approx(sum(c.arc_length() for c in pieces), rel=1e-10)
    assert comp.arc_length(0.0, 1.0) == pytest.approx(pieces[0].arc_length(), rel=1e-10)
    A = np.array([[0.0, -2.0], [1.0, 0.5]])
    moved = comp.transformed(A, [1.0, 2.0])
    t = np.linspace(*comp.domain, 201)
    assert isinstance(moved, CompositeCurve)
    assert np.abs(moved(t) - (comp(t) @ A.T + [1.0, 2.0])).max() <= 1e-13


def test_gap_rejected():
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    B = BezierCurve([[1.0, 0.0], [2.0, 1.0]])
    C = BezierCurve([[2.0, 1.001], [3.0, 1.0]])
    with pytest.raises(CagdError,
                       match=r"curves: gap of 0.001 between the end of curves\[1\] and the start of curves\[2\]"):
        CompositeCurve([A, B, C])
    comp = CompositeCurve([A, B, C], rel_tol=1e-3)           # size ~3.2: accepted
    n = comp.to_nurbs()                                      # the joint point is the mean of the two ends
    assert np.allclose(n(2.0), [2.0, 1.0005], rtol=0, atol=1e-15)
    with pytest.warns(DeprecationWarning, match="rel_tol") as rec:   # the old keyword, one release
        old = CompositeCurve([A, B, C], tol=1e-3)
    assert rec[0].filename == __file__ and old.rel_tol == comp.rel_tol
    with pytest.warns(DeprecationWarning, match="rel_tol"):
        assert old.tol == 1e-3
    np.testing.assert_array_equal(old(np.linspace(0, 3, 7)), comp(np.linspace(0, 3, 7)))


@pytest.mark.parametrize("curves, match", [
    ([], "curves: need at least one curve"),
    ([np.zeros((2, 2))], r"curves: curves\[0\] is a ndarray"),
    ([BezierCurve([[0, 0], [1, 0]]), BezierCurve([[1, 0, 0], [2, 0, 0]])], r"curves: curves\[1\] is 3-D"),
    (5, "curves: must be a sequence"),
])
def test_errors(curves, match):
    with pytest.raises(CagdError, match=match):
        CompositeCurve(curves)
    with pytest.raises(CagdError, match="rel_tol: must be positive"):
        CompositeCurve([BezierCurve([[0, 0], [1, 0]])], rel_tol=-1)
    with pytest.raises(CagdError, match="outside the domain"):
        CompositeCurve([BezierCurve([[0, 0], [1, 0]])])(1.5)
