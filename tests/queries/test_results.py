"""Query results are values: frozen dataclasses with ``converged`` and ``message``, their
arrays read-only; the reports of the continuity checks are frozen too. And the
vocabulary of their tolerances: ``tol`` a distance, ``param_tol`` in parameter space,
``angle_tol`` in radians; old forms still work for one release with a warning."""
import dataclasses
import warnings

import numpy as np
import pytest

import cagd
from cagd.analysis import CurvatureComb
from cagd.queries import (ClosestPoints, Deviation, IntersectionCurve, IntersectionPoint, IntersectionResult,
                          Overlap, Projector, SurfaceOverlap, closest_point, deviation, intersect, plane)
from cagd.queries.closest import CLOSEST_TOL

QUERY_RESULTS = (ClosestPoints, Deviation, IntersectionPoint, IntersectionResult, Overlap, SurfaceOverlap,
                 IntersectionCurve)
REPORTS = (cagd.ContinuityReport, cagd.EdgeContinuityReport, cagd.TriangleContinuity, CurvatureComb)


def _arrays(value):
    if isinstance(value, np.ndarray):
        yield value
    elif isinstance(value, tuple):
        for item in value:
            yield from _arrays(item)


def _samples():
    """One instance of every result class, from real queries."""
    s = cagd.sphere(2.0)
    X = np.random.default_rng(0).normal(size=(20, 3)) * 3
    out = [closest_point(s, X), closest_point(s, np.zeros(3) + [0, 0, 0.5], all_minima=True), deviation(s, X)]
    a = cagd.BezierCurve([[0, 0], [1, 2], [2, 0]])
    hits = intersect(a, cagd.BezierCurve([[0, 1], [2, 1]]))
    c = cagd.interpolate(np.random.default_rng(1).random((8, 2)))
    ov = intersect(c.segment(0.0, 0.6), c.segment(0.4, 1.0))
    sec = intersect(s, plane((0, 0, 1), (0, 0, 1)), tol=1e-7)
    net = np.random.default_rng(2).random((5, 6, 3)) + np.stack(np.meshgrid(np.arange(5), np.arange(6), [0],
                                                                             indexing="ij"), -1)[..., 0, :]
    S = cagd.BSplineSurface(net, 3, 3)
    sov = intersect(S.segment("u", 0.0, 0.6), S.segment("u", 0.4, 1.0), tol=1e-7)
    out += [hits, hits.points[0], ov.overlaps[0], sec, sec.curves[0], sov.overlaps[0]]
    return out


SAMPLES = _samples()


def test_every_query_result_class_is_sampled():
    assert {type(r) for r in SAMPLES} == set(QUERY_RESULTS)


@pytest.mark.parametrize("result", SAMPLES, ids=[type(r).__name__ for r in SAMPLES])
def test_query_results_are_frozen_with_converged_and_message(result):
    assert dataclasses.is_dataclass(result)
    assert isinstance(result.converged, bool) and isinstance(result.message, str)
    assert result.converged == (result.message == "") or not result.converged
    for f in dataclasses.fields(result):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(result, f.name, None)
        for arr in _arrays(getattr(result, f.name)):
            assert not arr.flags.writeable, f.name
            with pytest.raises(ValueError):
                arr[(0,) * arr.ndim] = 0
    copy = dataclasses.replace(result)                 # dataclasses.replace is the way to vary one
    assert type(copy) is type(result)


@pytest.mark.parametrize("result", SAMPLES, ids=[type(r).__name__ for r in SAMPLES])
def test_pickled_results_are_equal_and_still_read_only(result):
    """A result sent back from a worker process or a Dask task (issue 16) is pickled:
    pickle restored writable arrays; they are read-only again, with the same values."""
    import pickle
    back = pickle.loads(pickle.dumps(result))
    assert type(back) is type(result)
    for f in dataclasses.fields(result):
        got, want = list(_arrays(getattr(back, f.name))), list(_arrays(getattr(result, f.name)))
        assert len(got) == len(want)
        for a, b in zip(got, want):
            np.testing.assert_array_equal(a, b)
            assert not a.flags.writeable, f.name


def test_report_classes_are_frozen():
    A = cagd.BezierCurve([[0.0, 0.0], [1.0, 0.0]])
    reports = [cagd.continuity(A, A.translated([1.0, 0.0])),
               cagd.edge_continuity(cagd.BezierSurface(np.random.default_rng(0).random((3, 3, 3))),
                                    cagd.BezierSurface(np.random.default_rng(1).random((3, 3, 3))), "u1", "u0"),
               cagd.analysis.curvature_comb(A)]
    t = cagd.BezierTriangle({(2, 0, 0): [0, 0, 0], (1, 1, 0): [1, 0, 0], (1, 0, 1): [0, 1, 0],
                             (0, 2, 0): [2, 0, 0], (0, 1, 1): [1, 1, 0], (0, 0, 2): [0, 2, 0]})
    reports.append(cagd.triangle_continuity(t, cagd.c1_neighbor(t)))
    assert {type(r) for r in reports} == set(REPORTS)
    for r in reports:
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(r, dataclasses.fields(r)[0].name, None)


def test_intersection_lists_are_tuples_and_swapping_keeps_the_class():
    a, b = cagd.BezierCurve([[0, 0], [1, 2], [2, 0]]), cagd.BezierCurve([[0, 1], [2, 1]])
    ab, ba = intersect(a, b), intersect(b, a)
    assert isinstance(ab.points, tuple) and isinstance(ab.overlaps, tuple) and isinstance(ab.curves, tuple)
    assert [p.param_a for p in ab.points] == pytest.approx([p.param_b for p in sorted(ba.points,
                                                                                     key=lambda p: p.param_b)])


def test_closest_points_converged_overall_and_per_point():
    c = cagd.BSplineCurve(np.random.default_rng(11).uniform(-1, 1, (12, 3)), 3)
    X = np.random.default_rng(12).uniform(-1, 1, (50, 3))
    one = closest_point(c, X, max_iterations=1, param_tol=1e-15)
    assert one.converged is False and not one.point_converged.all()
    bad = np.flatnonzero(~one.point_converged)
    assert f"{bad.size} of 50 points" in one.message and f"index {bad[0]}" in one.message
    full = closest_point(c, X)
    assert full.converged is True and full.point_converged.all() and full.message == ""


def test_curve_of_tangency_points_are_not_converged():
    """A sphere inside a cylinder of its radius touches it along a circle: the contact
    points come back with converged False and the result's message on each."""
    res = intersect(cagd.sphere(1.0), cagd.cylinder(1.0, 4.0, (0, 0, -2)), tol=1e-7)
    assert not res.converged and "curve of tangency" in res.message
    assert res.points and all(not p.converged and "curve of tangency" in p.message for p in res.points)


# --- tolerances ---------------------------------------------------------------------------------------------------
def test_closest_point_tol_is_a_distance_and_param_tol_the_old_step():
    """The old call closest_point(obj, X, tol=t) meant a step below t times the parameter
    range: that is param_tol=t now and gives the same answer; tol=t now is a distance
    (the foot moves by less), announced by a FutureWarning for one release."""
    s = cagd.torus(10.0, 3.0)
    X = np.random.default_rng(5).uniform(-14, 14, (200, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        default = closest_point(s, X)
        old_meaning = closest_point(s, X, param_tol=1e-12)
    with pytest.warns(FutureWarning, match="param_tol") as rec:
        distance_tol = closest_point(s, X, tol=1e-12)
    assert rec[0].filename == __file__
    for r in (old_meaning, distance_tol):
        assert r.converged
        np.testing.assert_allclose(r.distances, default.distances, rtol=0, atol=1e-12 * s.size)
        np.testing.assert_allclose(r.feet, default.feet, rtol=0, atol=1e-6 * s.size)
    # a loose distance tolerance: the feet are still within it of the exact ones
    with pytest.warns(FutureWarning):
        loose = closest_point(s, X, tol=1e-3)
    assert np.abs(loose.distances - default.distances).max() <= 1e-3
    assert CLOSEST_TOL == 1e-12


@pytest.mark.parametrize("kwargs, name", [({"tol": 0.0}, "tol"), ({"param_tol": -1.0}, "param_tol"),
                                          ({"param_tol": np.nan}, "param_tol")])
def test_bad_tolerances(kwargs, name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        with pytest.raises(cagd.CagdError, match=name):
            closest_point(cagd.sphere(1.0), np.ones(3), **kwargs)
        with pytest.raises(cagd.CagdError, match=name):
            deviation(cagd.sphere(1.0), np.ones((2, 3)), **kwargs)


def test_projector_methods_take_the_same_tolerances():
    p = Projector(cagd.sphere(1.0))
    X = np.array([[0.3, 0.2, 2.0]])
    with pytest.warns(FutureWarning):
        a = p.closest(X, tol=1e-12)
    b = p.closest(X, param_tol=1e-12)
    np.testing.assert_allclose(a.distances, b.distances, atol=1e-14)
    with pytest.warns(FutureWarning):
        p.local_minima(X, tol=1e-12)
    assert p.local_minima(X).converged


def test_intersect_angle_tol_is_in_radians():
    """A line through a parabola's vertex at the angle theta to its tangent is a
    tangential contact exactly when theta <= angle_tol (radians). At theta = 1.2 the sine
    (0.93), which was compared before, is below angle_tol = 1.0 while the angle is not;
    and a small angle, 1e-3, on both sides."""
    parabola = cagd.BezierCurve([[-1, 1], [0, -1], [1, 1]])          # y = x^2, tangent y = 0 at x = 0
    for theta, angle_tol, tangential in ((1.2, 1.0, False), (1.2, 1.3, True), (1e-3, 2e-3, True),
                                         (1e-3, 0.5e-3, False)):
        line = cagd.BezierCurve([[-1, -np.tan(theta)], [1, np.tan(theta)]])
        res = intersect(parabola, line, angle_tol=angle_tol)
        at_vertex = [p for p in res.points if abs(p.point[0]) < 1e-6]
        assert len(at_vertex) == 1 and at_vertex[0].tangential == tangential, (theta, angle_tol)
    with pytest.raises(cagd.CagdError, match="angle_tol"):
        intersect(parabola, line, angle_tol=-1e-3)


def test_intersection_curve_distances_and_their_old_names():
    br = next(r for r in SAMPLES if isinstance(r, IntersectionCurve))
    assert 0 < br.max_distance <= 1e-7 and 0 <= br.params_max_distance <= 1e-7
    with pytest.warns(DeprecationWarning, match="max_distance"):
        assert br.tolerance == br.max_distance
    with pytest.warns(DeprecationWarning, match="params_max_distance"):
        assert br.params_tolerance == br.params_max_distance
