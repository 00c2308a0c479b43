"""Shared by the tests of the geometric queries: curves of every family (the OCCT
family tests) and the check that a converged closest point is certified."""
import numpy as np

from cagd import BezierCurve, BSplineCurve, natural_cubic_spline


def curve_of(kind, rng, dim=3, shift=0.0):
    """A curve of one family ("bezier", "rational", "periodic", "spline") through the
    unit box moved by ``shift``."""
    P = rng.random((6, dim)) + shift
    if kind == "bezier":
        return BezierCurve(P[:4])
    if kind == "rational":
        return BSplineCurve(P, 3, weights=rng.uniform(0.5, 2.0, 6))
    if kind == "periodic":
        return BSplineCurve(P, 3, np.linspace(0, 1, 7), periodic=True)
    return natural_cubic_spline(P[:5])


def assert_converged_means_certified(r, obj):
    """A point of the closest_point result ``r`` on ``obj`` reported converged has its foot
    proven global: its lower bound meets its distance (to the search's win gap, 1e-9 of
    the distance, and rounding of the object's size, at most its control net's extent);
    ``converged`` is all of them."""
    P = np.asarray(obj.to_nurbs().control_points)
    size = float(np.ptp(P.reshape(-1, P.shape[-1]), axis=0).max())
    ok = r.point_converged
    assert np.all(r.lower_bounds[ok] >= r.distances[ok] * (1 - 2e-9) - 1e-12 * size)
    assert r.converged == bool(ok.all())
