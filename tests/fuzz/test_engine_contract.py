"""The bad-input contract of the engine (issue 14), property-based: every constructor,
fitting function and curve/surface method, driven with hostile input (tests/hostile.py),
answers correctly or raises CagdError, within the case bounds of tests/contract.py.

"Correctly" is checked where an answer comes back: finite points inside the convex
hull of the control points (non-rational and positive-weight forms), Bezier points
equal to de Casteljau's, interpolants through their points, copies that keep the
shape (elevate, insert_knot, split)."""
from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cagd
from contract import call
from hostile import SCALES, counts, finite, knot_vectors, non_numbers, point_arrays, tolerances
from strategies import bspline_curves

FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
#: agreement asked of an answer, relative to the size of its control net
HULL_TOL = 1e-9
CASTELJAU_TOL = 1e-12


def _size(points: np.ndarray) -> float:
    return float(np.ptp(points, axis=0).max()) if len(points) > 1 else float(np.abs(points).max())


def _in_hull_box(values: np.ndarray, points: np.ndarray) -> bool:
    """Points of a B-spline with non-negative weights lie in the box of its control
    points (the convex hull property, Piegl & Tiller P4.4), up to HULL_TOL x size."""
    slack = HULL_TOL * _size(points) + 8 * np.finfo(float).eps * float(np.abs(points).max()) + 1e-300
    lo, hi = points.min(axis=0) - slack, points.max(axis=0) + slack
    return bool(np.all((values >= lo) & (values <= hi)))


def de_casteljau(points: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The oracle: repeated linear interpolation of the control points (seed 000, 5.2.3),
    stable at every degree."""
    b = np.repeat(points[None], len(t), axis=0)
    for _ in range(len(points) - 1):
        b = (1.0 - t)[:, None, None] * b[:, :-1] + t[:, None, None] * b[:, 1:]
    return b[:, 0]


def _samples(curve, count: int = 17) -> np.ndarray:
    a, b = curve.domain
    return np.linspace(a, b, count)


# --- constructors -----------------------------------------------------------------------
@FUZZ
@given(points=point_arrays(max_count=10), degree=counts, data=st.data())
def test_bspline_curve_constructor(points, degree, data):
    n = len(points) if hasattr(points, "__len__") else 0
    knots = data.draw(st.one_of(st.none(), knot_vectors(n + (degree if isinstance(degree, int)
                                                                and 0 <= degree < 50 else 3) + 1)))
    weights = data.draw(st.one_of(st.none(), point_arrays(min_count=n, max_count=n, dims=(1,)).map(
        lambda w: np.abs(np.ravel(w)) if isinstance(w, np.ndarray) and w.dtype.kind == "f" else w)))
    out = call(cagd.BSplineCurve, points, degree, knots, weights)
    if out.ok:
        curve = out.value
        values = call(curve, _samples(curve))
        if values.ok:
            assert np.all(np.isfinite(values.value))
            assert _in_hull_box(values.value, np.asarray(curve.control_points))


@FUZZ
@given(degree=st.one_of(st.integers(0, 40), st.sampled_from([55, 60, 70, 80, 100, 170, 171, 200, 1000])),
       scale=SCALES, seed=st.integers(0, 2 ** 32 - 1))
def test_bezier_curve_of_any_degree_is_de_casteljaus(degree, scale, seed):
    """The issue's high-degree case: every accepted degree evaluates within 1e-12
    (relative to the net) of de Casteljau; a degree above the maximum is refused."""
    points = np.random.default_rng(seed).random((degree + 1, 3)) * scale
    out = call(cagd.BezierCurve, points)
    if not out.ok:
        return
    t = np.array([0.0, 1e-3, 0.25, 0.5, 0.999, 1.0])
    values = call(out.value, t)
    assert values.ok, values.error
    expected = de_casteljau(points, t)
    assert np.abs(values.value - expected).max() <= CASTELJAU_TOL * _size(points), degree


@FUZZ
@given(points=point_arrays(min_count=0, max_count=12), degree=counts,
       parameters=st.sampled_from(["chord", "centripetal", "uniform", "nope", None, 3]))
def test_interpolate(points, degree, parameters):
    """Interpolation hits its points (relative to their spread) or refuses."""
    out = call(cagd.interpolate, points, degree, parameters)
    if out.ok:
        P = np.asarray(points, dtype=float)
        P = P[:, None] if P.ndim == 1 else P                    # 1-D: n points of dim 1
        params = cagd.parametrize(P, parameters)
        got = out.value(params)
        assert np.abs(got - P).max() <= 1e-9 * max(_size(P), 1e-300)


@FUZZ
@given(points=point_arrays(min_count=0, max_count=12), count=counts, degree=counts)
def test_approximate(points, count, degree):
    out = call(cagd.approximate, points, count, degree)
    if out.ok:
        values = out.value(_samples(out.value))
        assert np.all(np.isfinite(values))


@FUZZ
@given(points=point_arrays(min_count=0, max_count=12))
def test_bezier_through_points_and_parametrize(points):
    for fn in (cagd.bezier_through_points, cagd.parametrize):
        out = call(fn, points)
        if out.ok and fn is cagd.parametrize:
            t = np.asarray(out.value)
            assert np.all(np.isfinite(t)) and np.all(np.diff(t) >= 0)
        elif out.ok:
            assert np.all(np.isfinite(out.value(_samples(out.value))))


@FUZZ
@given(args=st.tuples(st.one_of(finite, non_numbers, SCALES), st.one_of(finite, non_numbers, SCALES)),
       kind=st.sampled_from(["sphere", "torus", "cylinder", "cone"]))
def test_primitives(args, kind):
    fn = getattr(cagd, kind)
    out = call(fn, *args) if kind != "sphere" else call(fn, args[0])
    if out.ok:
        s = out.value
        (a, b), (c, d) = s.domain
        values = s(np.linspace(a, b, 5)[:, None], np.linspace(c, d, 5)[None, :])
        assert np.all(np.isfinite(values))


@FUZZ
@given(points=point_arrays(min_count=0, max_count=30, dims=(3,)), nu=st.integers(0, 6), degree=counts)
def test_bspline_surface_constructor(points, nu, degree):
    P = np.asarray(points) if isinstance(points, np.ndarray) else points
    if isinstance(P, np.ndarray) and P.ndim == 2 and nu and len(P) % nu == 0:
        P = P.reshape(nu, len(P) // nu, P.shape[1])
    out = call(cagd.BSplineSurface, P, degree, degree)
    if out.ok:
        s = out.value
        (a, b), (c, d) = s.domain
        values = call(s, np.linspace(a, b, 5)[:, None], np.linspace(c, d, 5)[None, :])
        if values.ok:
            assert _in_hull_box(values.value.reshape(-1, s.dim), np.asarray(s.control_points).reshape(-1, s.dim))


# --- methods of well-formed curves ------------------------------------------------------
@FUZZ
@given(curve=bspline_curves(max_degree=6), order=counts, t=st.one_of(finite, st.just(np.nan), non_numbers))
def test_derivatives_and_geometry(curve, order, t):
    call(curve.derivatives, t, order)
    for name in ("tangent", "curvature", "torsion", "normal", "binormal"):
        if hasattr(curve, name):
            out = call(getattr(curve, name), t)
            if out.ok and name == "curvature":
                assert np.all(np.asarray(out.value) >= 0) or np.all(np.isnan(out.value))


@FUZZ
@given(curve=bspline_curves(max_degree=6, dims=(2, 3)), tol=tolerances, scale=SCALES)
def test_arc_length(curve, tol, scale):
    """arc_length validates tol (a length) and ends: a finite length no shorter than the
    chord polygon through samples (a lower bound) less tol, scaled with the curve."""
    scaled = curve.transformed(np.eye(curve.dim) * scale)
    out = call(scaled.arc_length, tol=tol) if tol is not None else call(scaled.arc_length)
    if out.ok:
        pts = curve(_samples(curve, 257))              # the chord polygon of the unscaled curve, scaled
        chord = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()) * scale
        assert np.isfinite(out.value)
        assert out.value >= chord * (1 - 1e-9) - (0.0 if tol is None else float(tol))   # within tol of it


@FUZZ
@given(curve=bspline_curves(max_degree=6), times=counts, t=st.one_of(finite, non_numbers))
def test_modified_copies_keep_the_shape(curve, times, t):
    samples = _samples(curve)
    before = curve(samples)
    P = np.asarray(curve.control_points)
    slack = HULL_TOL * _size(P) + 8 * np.finfo(float).eps * float(np.abs(P).max()) + 1e-300
    out = call(curve.elevate, times)
    if out.ok:
        assert np.abs(out.value(samples) - before).max() <= slack
    out = call(curve.insert_knot, t, times)
    if out.ok:
        assert np.abs(out.value(samples) - before).max() <= slack
    call(curve.split, t)
    call(curve.to_bezier)
