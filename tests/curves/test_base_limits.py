"""The shared curve interface at extreme scales and bad input (issue 14): curvature and
torsion are scale-invariant, undefined values raise CagdError (never NaN), arc_length
validates its bound and bounds its work."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve, CagdError
from cagd.curves.base import ARC_LENGTH_MAX_INTERVALS, ARC_LENGTH_MAX_LEVELS

HELIX_LIKE = np.array([[0, 0, 0], [1, 2, 0], [3, 1, 1], [4, 3, 2]], dtype=float)
T = np.linspace(0, 1, 9)


def direct_curvature_torsion(P, t):
    """Oracle: the cubic's derivatives from its power form, kappa and tau by the textbook
    formulas (exact inputs at unit scale)."""
    c = BezierCurve(P)
    d1, d2, d3 = (c.derivative(t, k) for k in (1, 2, 3))
    cr = np.cross(d1, d2)
    k = np.linalg.norm(cr, axis=-1) / np.linalg.norm(d1, axis=-1) ** 3
    tau = np.einsum("ij,ij->i", cr, d3) / np.einsum("ij,ij->i", cr, cr)
    return k, tau


def test_curvature_at_1e_minus_100_and_1e100_the_reported_case():
    # reported: 0 at x1e-100 and NaN at x1e100
    k, tau = direct_curvature_torsion(HELIX_LIKE, T)
    for s in (1e-100, 1e100):
        c = BezierCurve(HELIX_LIKE * s)
        assert np.allclose(c.curvature(T) * s, k, rtol=1e-13, atol=0)
        assert np.allclose(c.torsion(T) * s, tau, rtol=1e-13, atol=0)


@settings(max_examples=40, deadline=None)
@given(e=st.integers(-300, 300), seed=st.integers(0, 1000))
def test_property_curvature_and_torsion_scale_invariant(e, seed):
    P = np.random.default_rng(seed).random((5, 3))
    c, cs = BezierCurve(P), BezierCurve(P * 10.0 ** e)
    t = np.linspace(0.05, 0.95, 7)
    s = 10.0 ** e
    k = c.curvature(t)
    assert np.allclose(cs.curvature(t) * s, k, rtol=1e-12, atol=0)
    try:
        tau = c.torsion(t)
    except CagdError:
        return
    assert np.allclose(cs.torsion(t) * s, tau, rtol=1e-10, atol=1e-12 * np.abs(tau).max())
    T1, N1, B1 = c.frenet(t)
    T2, N2, B2 = cs.frenet(t)
    assert np.allclose(T1, T2, atol=1e-13) and np.allclose(N1, N2, atol=1e-12) and np.allclose(B1, B2, atol=1e-12)


def test_circle_curvature_exact_oracle():
    w = 2 ** -0.5
    r = 1e200
    c = BSplineCurve(np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]]) * r, 2, [0, 0, 0, .5, .5, 1, 1, 1],
                     [1, w, 1, w, 1])
    assert np.allclose(c.curvature(T) * r, 1.0, rtol=1e-13)


def test_undefined_values_raise_never_nan():
    line = BezierCurve([[0, 0, 0], [1, 1, 1], [3, 3, 3]])
    cusp = BezierCurve([[0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 1, 0]])
    # a straight line: curvature 0, torsion / normal / binormal undefined
    assert np.all(line.curvature(T) <= 1e-15)
    for f in (line.torsion, line.normal, line.binormal, line.frenet):
        with pytest.raises(CagdError, match="curvature vanishes"):
            f(0.5)
    # a stationary point: every quantity that needs the tangent raises, like tangent
    for f in (cusp.tangent, cusp.curvature, cusp.torsion, cusp.frenet, cusp.normal):
        with pytest.raises(CagdError, match="first derivative vanishes.*t = 0.0"):
            f([0.5, 0.0])
    # but regular points of the same curve answer
    assert np.isfinite(cusp.curvature([0.3, 0.7])).all()


def test_normal_binormal_are_the_frenet_frame():
    c = BezierCurve(HELIX_LIKE)
    Tt, N, B = c.frenet(T)
    assert np.allclose(c.normal(T), N) and np.allclose(c.binormal(T), B)
    assert np.allclose(np.cross(Tt, N), B, atol=1e-14)


@pytest.mark.parametrize("tol", [1e-17, 0, -1.0, float("nan"), float("inf"), "abc", None])
def test_arc_length_tol_validated(tol):
    c = BSplineCurve(np.random.default_rng(1).random((6, 2)), 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        if tol is None:
            assert c.arc_length() > 0
            return
        with pytest.raises(CagdError, match="tol"):
            c.arc_length(tol=tol)
    with pytest.raises(CagdError, match="rel_tol"):
        c.arc_length(rel_tol=1e-17)


def test_arc_length_work_is_bounded_and_reported():
    """A bound the quadrature cannot reach comes back not converged after bounded work
    (it used to double its intervals 40 times: a hang or a 3 GiB MemoryError)."""
    wiggle = BSplineCurve(np.random.default_rng(2).random((4000, 2)), 3)
    r = wiggle.arc_length_report(rel_tol=1e-15)
    assert r.intervals <= ARC_LENGTH_MAX_LEVELS * 2 * ARC_LENGTH_MAX_INTERVALS + 4000
    assert not r.converged and "not within" in r.message
    assert abs(r.length - wiggle.arc_length()) <= 10 * r.error + 1e-9 * r.length
    with pytest.warns(RuntimeWarning, match="arc_length"):
        wiggle.arc_length(rel_tol=1e-15)


def test_arc_length_of_rational_curve_offset_by_1e15():
    # reported: a hang at the default tol; the floor from the curve's size bounds it
    w = 2 ** -0.5
    c = BSplineCurve([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], 2, [0, 0, 0, .5, .5, 1, 1, 1], [1, w, 1, w, 1])
    far = c.translated([1e15, 1e15])
    r = far.arc_length_report()
    assert r.converged
    assert abs(r.length - math.pi) <= 1e-15 * 1.5e15 * 100       # rounding of C' at 1e15
    assert abs(c.arc_length() - math.pi) <= 1e-12 * math.pi


def test_derivative_order_and_integer_overflow():
    c = BezierCurve([[0, 0], [1, 1], [2, 0]])
    with pytest.raises(CagdError, match="order"):
        c.derivatives(0.5, 10**18)
    with pytest.raises(CagdError, match="floating-point range"):
        BezierCurve([[10**400, 0], [1, 1]])
    with pytest.raises(CagdError, match="t"):
        c(10**400)
    assert c.derivatives(0.5, cagd.MAX_ORDER).shape == (cagd.MAX_ORDER + 1, 2)


@pytest.mark.parametrize("s", [1e-300, 1e-200, 1e-100, 1e100, 1e200, 5e299])
def test_parameter_scale_does_not_matter(s):
    """Knots 1e-300 apart or 1e300 wide: the same geometry as on [0, 3] (the derivatives
    alone over/underflow; curvature, torsion, arc length must not)."""
    P = np.random.default_rng(0).random((6, 3))
    base = np.array([0, 0, 0, 0, 1, 2, 3, 3, 3, 3.0])
    ref = BSplineCurve(P, 3, base)
    c = BSplineCurve(P, 3, base * s)
    t = np.linspace(0, 3, 13)
    assert np.abs(c(t * s) - ref(t)).max() <= 1e-15
    assert np.allclose(c.curvature(t * s), ref.curvature(t), rtol=1e-13, atol=0)
    assert np.allclose(c.torsion(t * s), ref.torsion(t), rtol=1e-12, atol=0)
    assert np.allclose(c.tangent(t * s), ref.tangent(t), atol=1e-15)
    assert c.arc_length() == pytest.approx(ref.arc_length(), rel=1e-14)


@pytest.mark.parametrize("s", [1e-300, 1e300])
def test_arc_length_at_extreme_coordinates(s):
    P = np.random.default_rng(1).random((6, 3))
    ref = BSplineCurve(P, 3).arc_length()
    assert BSplineCurve(P * s, 3).arc_length() == pytest.approx(ref * s, rel=1e-13)


def test_arc_length_tiny_curve_meets_its_relative_bound():
    """At 1e-300 the default bound is relative (no absolute 1e-300 floor): a wiggly curve
    still gets 1e-12 relative, like at unit scale."""
    P = np.random.default_rng(7).random((30, 2))
    ref = BSplineCurve(P, 5).arc_length()
    tiny = BSplineCurve(P * 1e-300, 5).arc_length_report()
    assert tiny.converged
    assert tiny.length == pytest.approx(ref * 1e-300, rel=1e-12)
    assert BezierCurve([[0.0, 0.0], [0.0, 0.0]]).arc_length() == 0.0


def test_overflowing_geometry_is_a_cagd_error_not_nan():
    """One span 1e-300 wide among unit ones: the derivatives there exceed the float range;
    curvature raises there (and answers elsewhere)."""
    P = np.random.default_rng(4).random((6, 3))
    s = cagd.CubicSpline(P, "natural", [0, 1e-300, 2e-300, 3, 4, 5])
    with pytest.raises(CagdError, match="overflow"):
        s.curvature(1e-300)
    assert np.isfinite(s.curvature(4.5))


def test_hermite_tangents_overflowing_is_a_cagd_error():
    P = np.random.default_rng(5).random((4, 2)) * 1e300
    with pytest.raises(CagdError, match="overflow"):
        cagd.HermiteSpline(P, P, "chord")


def test_tridiagonal_solvers_validate():
    from cagd.curves.cubic_spline import solve_cyclic_tridiagonal, solve_tridiagonal
    for f in (solve_tridiagonal, solve_cyclic_tridiagonal):
        for args in (("a", [1], [1], [1]), ([10**400], [1, 1], [1], [1, 1]), (None, None, None, None),
                     ([1, 1], [2, np.nan], [1, 1], [1, 1]), ([1, 1], [2, 2], [1, 1], np.ones((2, 2, 2)))):
            with pytest.raises(CagdError):
                f(*args)
    x = solve_tridiagonal([0, 1, 1], [2, 2, 2], [1, 1, 0], [1, 2, 3])
    assert np.allclose([2 * x[0] + x[1], x[0] + 2 * x[1] + x[2], x[1] + 2 * x[2]], [1, 2, 3])


@pytest.mark.parametrize("degree", [3, 13, 20])
def test_nets_near_the_float_limit_evaluate_like_de_casteljau(degree):
    """The power coefficients are binomial multiples of the net: at 1e300 they left the
    float range from degree 13 and the points came back NaN. Such nets evaluate by the
    Bernstein sums (curves) or the basis (surfaces) instead."""
    rng = np.random.default_rng(degree)
    P = rng.random((degree + 1, 3)) * 1e300
    t = np.array([0.0, 0.1, 0.5, 0.999, 1.0])
    b = np.repeat(P[None], len(t), axis=0)
    for _ in range(degree):                          # de Casteljau, the oracle
        b = (1.0 - t)[:, None, None] * b[:, :-1] + t[:, None, None] * b[:, 1:]
    assert np.abs(cagd.BezierCurve(P)(t) - b[:, 0]).max() <= 1e-13 * 1e300
    net = rng.random((degree + 1, 4, 3)) * 1e300
    s = cagd.BezierSurface(net)
    u, v = 0.3, 0.6
    rows = [cagd.BezierCurve(net[:, j])(u) for j in range(4)]
    assert np.abs(s(u, v) - cagd.BezierCurve(np.array(rows))(v)).max() <= 1e-13 * 1e300


def test_steep_curve_is_measured_on_its_unit_copy():
    """Coordinates 1e300 over a domain 1e-10 long: |C'| = 1e310 overflows, yet the length
    (1e300) and the tangent do not depend on the parametrisation (found in review:
    arc_length returned 0.0, then raised naming t)."""
    c = cagd.BSplineCurve(np.array([[0.0, 0.0], [1e300, 0.0]]), 1, [0, 0, 1e-10, 1e-10])
    assert c.arc_length() == pytest.approx(1e300, rel=1e-12)
    assert c.arc_length(2.5e-11, 5e-11) == pytest.approx(2.5e299, rel=1e-12)
    assert np.allclose(c.tangent(5e-11), [1.0, 0.0])
