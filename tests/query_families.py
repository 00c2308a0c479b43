"""Curves of every family for the OCCT family tests of the geometric queries."""
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
