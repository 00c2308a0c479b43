"""Interpolating C2 cubic splines (seed 000, 5.1.2 "natural cubic spline interpolation"),
with scipy.interpolate.CubicSpline as the oracle."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.interpolate import CubicSpline as ScipySpline

from cagd import BSplineCurve, CagdError
from cagd.curves.cubic_spline import (CubicSpline, natural_cubic_spline, solve_cyclic_tridiagonal,
                                      solve_tridiagonal, spline_parameters)
from cagd.curves.hermite import HermiteSpline
from cagd.knots import distinct_with_multiplicities
from strategies import point_arrays, relative_error

SETTINGS = settings(max_examples=40, deadline=None)
PARAMS = ("uniform", "chord", "centripetal")


def size_of(values):
    return max(float(np.abs(values).max()), 1.0)


@st.composite
def data_points(draw, closed=False, min_points=2, max_points=10):
    """Points with no chord shorter than 2% of the bounding box (closed: last = first)."""
    n = draw(st.integers(min_points, max_points))
    dim = draw(st.integers(1, 3))
    P = draw(point_arrays(n, dim))
    if closed:
        P = np.vstack([P, P[:1]])
    size = np.linalg.norm(P.max(0) - P.min(0))
    assume(size > 1e-3 and np.linalg.norm(np.diff(P, axis=0), axis=1).min() > 0.02 * size)
    return P


def scipy_oracle(s):
    if s.end_condition == "natural":
        bc = "natural"
    elif s.end_condition == "clamped":
        bc = ((1, s.end_tangents[0]), (1, s.end_tangents[1]))
    else:
        bc = "periodic"
    return ScipySpline(s.parameters, s.points, bc_type=bc, axis=0)


def check_against(s, oracle, t, tol=1e-12, ends3=True):
    """Values and derivatives 1..3 agree; ``ends3=False`` skips the third derivative
    at the two ends (where an oracle on a longer knot sequence jumps)."""
    got = s.derivatives(t, 3)
    # the third derivative jumps at the knots: compare it only away from them (the
    # engine's and the oracle's knots agree to rounding, so a sample on a knot may
    # take different sides)
    knots = np.asarray(s.parameters)[1:-1]
    width = s.domain[1] - s.domain[0]
    off_knots = np.abs(t[:, None] - knots[None, :]).min(axis=1, initial=np.inf) > 1e-9 * width
    for k in range(4):
        sel = np.ones(len(t), dtype=bool) if k < 3 else off_knots.copy()
        if k == 3 and not ends3:
            sel[[0, -1]] = False
        want = oracle(t[sel], k)
        # a k-th derivative is as exact as size / width^k (a line's third derivative from
        # scipy was 3.3e-12, not 0, on a domain 0.02 wide)
        scale = max(size_of(want), float(np.ptp(np.asarray(s.points), axis=0).max()) / width ** k)
        assert relative_error(got[k][sel], want, scale) < tol, k


# --- the scipy oracle ----------------------------------------------------------------------------
@SETTINGS
@given(data_points(), st.sampled_from(PARAMS))
def test_natural_matches_scipy(P, param):
    s = CubicSpline(P, "natural", param)
    check_against(s, scipy_oracle(s), np.linspace(*s.domain, 401))
    d2 = s.derivative(np.array(s.domain), 2)
    assert np.abs(d2).max() < 1e-12 * size_of(s.derivatives(np.linspace(*s.domain, 101), 2))


@SETTINGS
@given(data_points(), st.sampled_from(PARAMS), st.data())
def test_clamped_matches_scipy(P, param, data):
    ends = data.draw(point_arrays(2, P.shape[1]))
    s = CubicSpline(P, "clamped", param, tangents=ends)
    check_against(s, scipy_oracle(s), np.linspace(*s.domain, 401))
    np.testing.assert_allclose(s.derivative(np.array(s.domain), 1), ends, rtol=1e-13, atol=1e-13)


@SETTINGS
@given(data_points(closed=True, min_points=3), st.sampled_from(PARAMS))
def test_periodic_matches_scipy(P, param):
    s = CubicSpline(P, "periodic", param)
    assert s.periodic
    check_against(s, scipy_oracle(s), np.linspace(*s.domain, 401))
    # evaluation wraps around the period
    T = s.domain[1] - s.domain[0]
    t = np.linspace(*s.domain, 13)
    np.testing.assert_allclose(s(t + 2 * T), s(t), atol=1e-12 * size_of(P))


@SETTINGS
@given(data_points(), st.sampled_from(PARAMS), st.booleans(), st.data())
def test_virtual_points_is_the_extended_natural_spline(P, param, explicit, data):
    """Oracle: scipy's natural spline through p_-1, p_0..p_n, p_n+1, restricted to [t_0, t_n]."""
    V = data.draw(point_arrays(2, P.shape[1])) if explicit else np.stack([2 * P[0] - P[1], 2 * P[-1] - P[-2]])
    ext = np.vstack([V[:1], P, V[1:]])
    size = np.linalg.norm(ext.max(0) - ext.min(0))
    assume(np.linalg.norm(np.diff(ext, axis=0), axis=1).min() > 0.02 * size)
    s = CubicSpline(P, "virtual", param, virtual_points=V if explicit else None)
    np.testing.assert_array_equal(s.virtual_points, V)
    text = spline_parameters(ext, param) - spline_parameters(ext, param)[1]
    np.testing.assert_allclose(s.parameters, text[1:-1], rtol=1e-13, atol=1e-13)
    oracle = ScipySpline(text, ext, bc_type="natural", axis=0)
    check_against(s, oracle, np.linspace(*s.domain, 301), tol=1e-11, ends3=False)


def test_virtual_with_explicit_parameters_copies_end_intervals():
    P = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 4.0]])
    t = np.array([0.0, 0.5, 2.0, 2.25])
    V = np.array([[-1.0, 1.0], [5.0, 3.0]])
    s = CubicSpline(P, "virtual", tangents=None, virtual_points=V, parameters=t)
    oracle = ScipySpline(np.concatenate([[-0.5], t, [2.5]]), np.vstack([V[:1], P, V[1:]]), bc_type="natural")
    check_against(s, oracle, np.linspace(0, 2.25, 101), ends3=False)


def test_explicit_parameters_and_alias():
    P = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 4.0], [6.0, 0.0]])
    t = np.array([-1.0, 0.0, 0.5, 2.0, 7.0])
    s = natural_cubic_spline(P, parameters=t)
    assert isinstance(s, CubicSpline) and isinstance(s, HermiteSpline)
    assert s.parametrization is None and s.domain == (-1.0, 7.0)
    check_against(s, ScipySpline(t, P, bc_type="natural"), np.linspace(-1, 7, 201))


def test_spline_parameters():
    P = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 13.0]])
    np.testing.assert_array_equal(spline_parameters(P, "uniform"), [0, 1, 2])
    np.testing.assert_array_equal(spline_parameters(P, "chord"), [0, 5, 14])
    np.testing.assert_allclose(spline_parameters(P, "centripetal"), [0, np.sqrt(5), np.sqrt(5) + 3])
    assert CubicSpline(P).parameters.tolist() == [0, 5, 14]     # chord is the default


def test_natural_spline_through_collinear_points_is_the_line():
    P = np.outer(np.arange(6.0), [1.0, 2.0, -2.0])
    s = CubicSpline(P, parameters="uniform")
    t = np.linspace(0, 5, 41)
    np.testing.assert_allclose(s(t), np.outer(t, [1.0, 2.0, -2.0]), atol=1e-14)
    assert s.arc_length() == pytest.approx(15.0, rel=1e-12)


# --- the NURBS form ----------------------------------------------------------------------------------
END = st.sampled_from(["natural", "clamped", "periodic", "virtual"])


@st.composite
def splines(draw):
    end = draw(END)
    P = draw(data_points(closed=end == "periodic", min_points=3 if end == "periodic" else 2))
    param = draw(st.sampled_from(PARAMS))
    tangents = draw(point_arrays(2, P.shape[1])) if end == "clamped" else None
    return CubicSpline(P, end, param, tangents=tangents)


@SETTINGS
@given(splines())
def test_to_nurbs_is_the_C2_bspline(s):
    nurbs = s.to_nurbs()
    assert isinstance(nurbs, BSplineCurve) and nurbs.degree == 3
    t = np.linspace(*s.domain, 401)
    ref = s.derivatives(t, 2)
    for k in range(3):
        got = nurbs.derivative(t, k) if k else nurbs(t)
        assert relative_error(got, ref[k], size_of(ref[k])) < 1e-12
    if s.periodic:
        assert nurbs.periodic
        np.testing.assert_array_equal(nurbs.knots, s.parameters)
        assert len(nurbs.control_points) == len(s.points) - 1
    else:
        values, mults = distinct_with_multiplicities(nurbs.knots)
        np.testing.assert_array_equal(values, s.parameters)
        assert mults.tolist() == [4] + [1] * (len(values) - 2) + [4]


@pytest.mark.parametrize("end", ["natural", "clamped", "periodic", "virtual"])
def test_to_nurbs_with_very_uneven_intervals(end):
    """Two chords 1e-3 long next to chords of length ~3: the control points are blossoms
    of the longest span in each support, so there is no extrapolation over 3000 span
    lengths (blossoms of the span starting at t_{j+3} gave errors of 1e-10 here)."""
    P = np.array([[0.0, 0.0], [3.0, 1.0], [3.001, 1.0], [3.002, 1.001], [6.0, 0.0], [5.0, 3.0], [0.0, 0.0]])
    kw = dict(tangents=[[1.0, 0.0], [0.0, -1.0]]) if end == "clamped" else {}
    s = CubicSpline(P if end == "periodic" else P[:-1], end, "chord", **kw)
    t = np.unique(np.concatenate([np.linspace(*s.domain, 2001), s.parameters]))
    assert relative_error(s.to_nurbs()(t), s(t), size_of(P)) < 1e-13


@SETTINGS
@given(data_points(closed=True, min_points=3), st.sampled_from(PARAMS))
def test_periodic_nurbs_is_C2_at_the_seam(P, param):
    s = CubicSpline(P, "periodic", param)
    nurbs = s.to_nurbs()
    a, b = s.domain
    pp = nurbs.ppform                     # last span is closed at b: left limits there
    left = np.stack([pp(np.array([b]), k)[0] for k in range(3)])
    right = np.stack([pp(np.array([a]), k)[0] for k in range(3)])
    scale = size_of(s.derivatives(np.linspace(a, b, 101), 2))
    assert relative_error(left, right, scale) < 1e-12
    # and the spline's own spans meet with C2 at the seam
    segs = s.segments()
    h = np.diff(s.parameters)
    end, start = segs[-1].derivatives(1.0, 2), segs[0].derivatives(0.0, 2)
    for k in range(3):
        assert relative_error(end[k] / h[-1] ** k, start[k] / h[0] ** k, scale) < 1e-12


# --- properties --------------------------------------------------------------------------------------------
@SETTINGS
@given(splines())
def test_interpolates_and_is_C2_at_interior_knots(s):
    t = s.parameters
    assert relative_error(s(t[:-1]), s.points[:-1], size_of(s.points)) < 1e-13
    assert relative_error(s(np.array([t[-1]]))[0] if not s.periodic else s.points[-1],
                          s.points[-1], size_of(s.points)) < 1e-13
    h = np.diff(t)
    scale = size_of(s.derivatives(np.linspace(*s.domain, 101), 2))
    segs = s.segments()
    for j in range(1, len(segs)):       # exact left/right limits at t_j
        left, right = segs[j - 1].derivatives(1.0, 2), segs[j].derivatives(0.0, 2)
        for k in range(3):
            assert relative_error(left[k] / h[j - 1] ** k, right[k] / h[j] ** k, scale) < 1e-12
    # the same through the evaluator: one ulp to the left of each knot vs at the knot
    inner = t[1:-1]
    if inner.size:
        lft = s.derivatives(np.nextafter(inner, -np.inf), 2)
        rgt = s.derivatives(inner, 2)
        assert relative_error(lft, rgt, scale) < 1e-11


@SETTINGS
@given(splines(), st.data())
def test_affine_invariance_with_fixed_parameters(s, data):
    """The spline of the mapped points (same parameters; clamped tangents through A,
    virtual points through the affine map) is the mapped spline."""
    dim = s.dim
    A = data.draw(point_arrays(dim, dim))
    b = data.draw(point_arrays(1, dim))[0]
    kw = dict(parameters=s.parameters)
    if s.end_condition == "clamped":
        kw["tangents"] = s.end_tangents @ A.T
    if s.end_condition == "virtual":
        kw["virtual_points"] = s.virtual_points @ A.T + b
    Q = s.points @ A.T + b
    assume(np.linalg.norm(np.diff(Q, axis=0), axis=1).min() > 0)
    if s.end_condition == "virtual":
        assume(np.linalg.norm(kw["virtual_points"] - Q[[0, -1]], axis=1).min() > 0)
    direct = CubicSpline(Q, s.end_condition, **kw)
    moved = s.transformed(A, b)
    t = np.linspace(*s.domain, 101)
    d = s.derivatives(t, 2)
    scale = size_of(d) * size_of(A) + size_of(b)
    for curve in (direct, moved):
        got = curve.derivatives(t, 2)
        assert relative_error(got[0], d[0] @ A.T + b, scale) < 1e-11
        assert relative_error(got[1:], d[1:] @ A.T, scale) < 1e-11


@SETTINGS
@given(data_points(min_points=3), st.floats(0, 2 * np.pi), st.floats(0.1, 10), st.sampled_from(PARAMS[1:]))
def test_chord_parametrisation_is_invariant_under_similarities(P, angle, scale, param):
    assume(P.shape[1] == 2)
    c, s_ = np.cos(angle), np.sin(angle)
    R = scale * np.array([[c, -s_], [s_, c]])
    a = CubicSpline(P, "natural", param)
    b = CubicSpline(P @ R.T + [1.0, -2.0], "natural", param)
    # same curve at corresponding parameters t_b = t_a * scale (chord) or * sqrt(scale)
    f = scale if param == "chord" else np.sqrt(scale)
    np.testing.assert_allclose(b.parameters, a.parameters * f, rtol=1e-12)
    t = np.linspace(*a.domain, 51)
    assert relative_error(b(t * f), a(t) @ R.T + [1.0, -2.0], size_of(P) * scale + 2) < 1e-12


# --- the solvers ------------------------------------------------------------------------------------------------
def dense(lower, diag, upper, cyclic=False):
    n = len(diag)
    M = np.diag(diag) + np.diag(lower[1:], -1) + np.diag(upper[:-1], 1)
    if cyclic:
        M[0, n - 1] += lower[0]
        M[n - 1, 0] += upper[-1]
    return M


@SETTINGS
@given(st.integers(1, 12), st.integers(1, 3), st.data())
def test_thomas_matches_dense_solve(n, k, data):
    rng = np.random.default_rng(data.draw(st.integers(0, 2 ** 32 - 1)))
    lower, upper = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    diag = (np.abs(lower) + np.abs(upper) + 0.5) * rng.choice([-1, 1], n)
    rhs = rng.normal(size=(n, k))
    x = solve_tridiagonal(lower, diag, upper, rhs)
    np.testing.assert_allclose(dense(lower, diag, upper) @ x, rhs, atol=1e-13)
    np.testing.assert_allclose(solve_tridiagonal(lower, diag, upper, rhs[:, 0]), x[:, 0], rtol=1e-15)


@SETTINGS
@given(st.integers(2, 12), st.integers(1, 3), st.data())
def test_cyclic_solver_matches_dense_solve(n, k, data):
    rng = np.random.default_rng(data.draw(st.integers(0, 2 ** 32 - 1)))
    lower, upper = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    diag = (np.abs(lower) + np.abs(upper) + 0.5) * rng.choice([-1, 1], n)
    rhs = rng.normal(size=(n, k))
    x = solve_cyclic_tridiagonal(lower, diag, upper, rhs)
    want = np.linalg.solve(dense(lower, diag, upper, cyclic=True), rhs)
    np.testing.assert_allclose(x, want, rtol=1e-10, atol=1e-12)
    assert solve_cyclic_tridiagonal(lower, diag, upper, rhs[:, 0]).shape == (n,)


def test_solver_errors():
    with pytest.raises(CagdError, match="zero pivot"):
        solve_tridiagonal([0, 1], [0, 1], [1, 0], [1, 1])
    with pytest.raises(CagdError, match="rhs"):
        solve_tridiagonal([0, 1], [1, 1], [1, 0], [1, 1, 1])
    with pytest.raises(CagdError, match="at least 2"):
        solve_cyclic_tridiagonal([0], [1], [0], [1])


# --- errors --------------------------------------------------------------------------------------------------------
P4 = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
SQUARE = np.vstack([P4, P4[:1]])


@pytest.mark.parametrize("kwargs, pattern", [
    (dict(points=P4, end_condition="free"), "end_condition.*'free'"),
    (dict(points=P4, parameters="arc"), "parameters.*'arc'"),
    (dict(points=P4[:1]), "points.*at least 2"),
    (dict(points=[[0, 0], [np.nan, 1]]), "points.*NaN"),
    (dict(points=np.vstack([P4[:2], P4[1:]])), "points.*1 and 2 coincide"),
    (dict(points=P4, parameters=[0, 1, 2]), "parameters.*expected 4"),
    (dict(points=P4, parameters=[0, 1, 1, 2]), "parameters.*strictly increasing"),
    (dict(points=P4, parameters=[0, 1, np.nan, 2]), "parameters.*NaN"),
    (dict(points=P4, end_condition="clamped"), "tangents.*needs"),
    (dict(points=P4, end_condition="clamped", tangents=np.zeros((3, 2))), "tangents.*shape"),
    (dict(points=P4, end_condition="clamped", tangents=np.zeros((2, 3))), "tangents.*shape"),
    (dict(points=P4, tangents=np.zeros((2, 2))), "tangents.*clamped"),
    (dict(points=P4, virtual_points=np.zeros((2, 2))), "virtual_points.*virtual"),
    (dict(points=P4, end_condition="virtual", virtual_points=np.zeros((1, 2))), "virtual_points.*shape"),
    (dict(points=P4, end_condition="virtual", virtual_points=[[0.0, 0.0], [5.0, 5.0]]), "virtual_points.*coincides"),
    (dict(points=P4, end_condition="periodic"), "points.*closed"),
    (dict(points=SQUARE[[0, 1, 0]], end_condition="periodic"), "points.*3 distinct"),
])
def test_errors_name_the_argument(kwargs, pattern):
    with pytest.raises(CagdError, match=pattern):
        CubicSpline(**kwargs)


def test_periodic_closure_tolerance():
    near = SQUARE.copy()
    near[-1, 0] += 1e-14                       # within 1e-12 of the size: accepted, snapped
    s = CubicSpline(near, "periodic")
    np.testing.assert_array_equal(s.points[-1], s.points[0])
    near[-1, 0] += 1e-9
    with pytest.raises(CagdError, match="points"):
        CubicSpline(near, "periodic")


def test_subnormal_parameter_step_is_reported_at_the_parameters():
    with pytest.raises(CagdError, match="^parameters:"):
        natural_cubic_spline([[0, 0], [1, 1], [2, 0], [3, 1]], parameters=[0, 5e-324, 3, 4])
