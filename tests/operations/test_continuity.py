"""Continuity reports (seed 000, 5.1.1 C0/C1/C2, G1/G2) on joints whose continuity
is known by construction."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.knots import distinct_with_multiplicities
from cagd.operations import ContinuityReport, continuity, join
from strategies import bspline_curves

SETTINGS = settings(max_examples=40, deadline=None)

P = BezierCurve([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])


@SETTINGS
@given(bspline_curves(kinds=("clamped",), min_degree=3, max_degree=6, dims=(2, 3)), st.data())
def test_split_at_simple_knot_is_c2(curve, data):
    """A B-spline is C^(p-k) at a knot of multiplicity k (seed 000, 5.3.1)."""
    a, b = curve.domain
    vals, mults = distinct_with_multiplicities(curve.knots)
    inner = vals[(vals > a) & (vals < b) & (mults <= curve.degree - 2)]
    assume(inner.size > 0)
    t = data.draw(st.sampled_from(list(inner)))
    left, right = curve.split(t)
    r = continuity(left, right)
    assert r.C0 and r.C1 and r.C2 and r.level == "C2"
    assert r.derivative_ratio == pytest.approx(1.0, rel=1e-9) or not np.isfinite(r.derivative_ratio)


def test_split_reports_parameters_and_given_parameters():
    c = BSplineCurve(np.random.default_rng(2).normal(size=(8, 3)), 3, [0, 0, 0, 0, .2, .4, .6, .8, 1, 1, 1, 1])
    left, right = c.split(0.4)
    r = continuity(left, right)
    assert (r.t1, r.t2) == (0.4, 0.4) and r.level == "C2"
    # inside one curve at a given parameter: trivially C2, measured at that parameter
    r = continuity(c, c.segment(0.3, 1.0), t1=0.3, t2=0.3)
    assert r.level == "C2" and r.gap <= 1e-15


def test_g1_not_c1():
    Q = join(P, [[6.0, 1.0], [7.0, 3.0]], "G1", alpha=0.5)
    r = continuity(P, Q)
    assert r.G1 and not r.C1 and not r.G2 and r.level == "G1"
    assert r.tangent_angle <= 1e-15
    assert r.derivative_ratio == pytest.approx(0.5, rel=1e-14)


def test_g2_not_c2():
    Q = join(P, [[6.0, 1.0], [7.0, 3.0]], "G2", alpha=0.5, beta=2.0)
    r = continuity(P, Q)
    assert r.G2 and not r.C1 and r.level == "G2"
    assert r.curvature_difference <= 1e-14
    assert r.second_derivative_gap > 1.0


def test_c1_not_g2():
    Q = join(P, [[6.0, 1.0], [7.0, 3.0]], "C1")
    r = continuity(P, Q)
    assert r.C1 and r.G1 and not r.G2 and not r.C2 and r.level == "C1"
    assert r.curvature_difference == pytest.approx(abs(Q.curvature(0.0) - P.curvature(1.0)), rel=1e-12)


def test_kink_is_c0_only():
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    B = BezierCurve([[1.0, 0.0], [1.0, 0.5], [1.0, 2.0]])
    r = continuity(A, B)
    assert r.C0 and not (r.G1 or r.C1 or r.G2 or r.C2) and r.level == "C0"
    assert r.tangent_angle == pytest.approx(np.pi / 2, abs=1e-15)
    assert r.derivative_ratio == pytest.approx(1.0, rel=1e-15)        # |B'(0)| = 2 * 0.5 = 1 = |A'|
    r = continuity(A, A.reversed())                                   # turning back: angle pi
    assert r.tangent_angle == pytest.approx(np.pi, abs=1e-15) and r.level == "C0"


def test_gap_is_measured():
    A = BezierCurve([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    B = BezierCurve([[1.0, 3e-4, 4e-4], [1.0, 2.0, 0.0]])
    r = continuity(A, B)
    assert r.gap == pytest.approx(5e-4, rel=1e-12)
    assert not r.C0 and r.level == "none"
    loose = continuity(A, B, rel_tol=1e-3)                 # size ~2.2, so 5e-4 <= 1e-3 * 2.2
    assert loose.C0 and loose.rel_tol == 1e-3
    assert "rel_tol 0.001" in str(loose) and str(loose).startswith("C0")


def test_tolerance_is_relative_to_size():
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    B = BezierCurve([[1.0, 1e-10], [2.0, 0.0]])
    assert continuity(A, B).C0                             # 1e-10 <= 1e-9 * 2
    big = continuity(A.transformed(1e6 * np.eye(2)), B.transformed(1e6 * np.eye(2)))
    assert big.C0 and big.gap == pytest.approx(1e-4, rel=1e-6)
    small = continuity(A.transformed(1e-6 * np.eye(2)), B.transformed(1e-6 * np.eye(2)))
    assert small.C0 and small.level == continuity(A, B).level


def test_mixed_families_and_rational():
    """A rational arc joined to a B-spline with matching end derivatives."""
    arc = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], [1.0, np.sqrt(0.5), 1.0])
    d = arc.derivatives(1.0, 2)
    # a cubic whose first two derivatives at 0 equal the arc's at 1 (Bezier end formulas)
    Q0 = d[0]
    Q1 = Q0 + d[1] / 3
    Q2 = 2 * Q1 - Q0 + d[2] / 6
    nxt = BSplineCurve([Q0, Q1, Q2, [-2.0, 0.0]], 3)
    r = continuity(arc, nxt)
    assert r.level == "C2"
    assert r.curvature_difference <= 1e-12                      # unit circle: curvature 1 both sides
    assert nxt.curvature(0.0) == pytest.approx(1.0, rel=1e-12)


def test_zero_derivative_is_not_g1():
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]])      # A'(1) = 0
    B = BezierCurve([[1.0, 0.0], [1.0, 0.0], [1.0, 1.0]])      # B'(0) = 0
    r = continuity(A, B)
    assert np.isnan(r.tangent_angle) and not r.G1 and r.C1 and r.level == "C1"


def test_report_fields():
    r = continuity(P, P.translated([4.0, 0.0]))
    assert isinstance(r, ContinuityReport)
    assert set(["gap", "tangent_angle", "derivative_ratio", "curvature_difference", "second_derivative_gap",
                "C0", "C1", "C2", "G1", "G2", "rel_tol", "angle_tol"]) <= set(r.__dataclass_fields__)
    assert r.level in str(r)


def test_errors():
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(CagdError, match="c2: dimension 3 differs from c1's 2"):
        continuity(A, BezierCurve([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]))
    with pytest.raises(CagdError, match="c1: must be a cagd Curve"):
        continuity(np.zeros((2, 2)), A)
    with pytest.raises(CagdError, match="rel_tol: must be positive"):
        continuity(A, A, rel_tol=0.0)
    with pytest.raises(CagdError, match="angle_tol"):
        continuity(A, A, angle_tol=-1e-3)
    with pytest.raises(CagdError, match="outside the domain"):
        continuity(A, A, t1=2.0)


def test_angle_tol_is_an_angle_in_radians():
    """Two segments meeting at 1e-6 rad: G1 with angle_tol = 2e-6, not with 5e-7; the
    gap test keeps its own rel_tol."""
    A = BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    B = BezierCurve([[1.0, 0.0], [2.0, np.tan(1e-6)]])
    assert continuity(A, B, rel_tol=1e-12, angle_tol=2e-6).G1
    r = continuity(A, B, rel_tol=1e-12, angle_tol=5e-7)
    assert r.C0 and not r.G1 and r.angle_tol == 5e-7
    assert continuity(A, B).angle_tol == continuity(A, B).rel_tol == 1e-9      # default: rel_tol


def test_old_tol_keyword_warns_and_gives_the_same_report():
    A = BezierCurve([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    B = BezierCurve([[1.0, 3e-4, 4e-4], [1.0, 2.0, 0.0]])
    new = continuity(A, B, rel_tol=1e-3)
    with pytest.warns(DeprecationWarning, match="rel_tol") as rec:
        old = continuity(A, B, tol=1e-3)
    assert rec[0].filename == __file__
    assert old == new
    with pytest.warns(DeprecationWarning, match="rel_tol"):
        assert old.tol == old.rel_tol
    with pytest.raises(CagdError, match="both"):
        continuity(A, B, rel_tol=1e-3, tol=1e-3)
