"""``BSplineCurve.occ_form()`` against OpenCascade's own evaluator (Geom_BSplineCurve)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import BSplineCurve, CagdError

from strategies import bspline_curves, periodic_knots, point_arrays, positive_weights

OCP = pytest.importorskip("OCP")
from OCP.Geom import Geom_BSplineCurve  # noqa: E402
from OCP.gp import gp_Pnt, gp_Vec  # noqa: E402
from cagd.occ.compat import Array1OfInteger, Array1OfPnt, Array1OfReal  # noqa: E402


def to_occ(form, roll: int = 0):
    """Geom_BSplineCurve(poles, [weights,] knots, mults, degree, periodic); OCCT
    arrays are 1-based. ``roll`` shifts the poles (and weights) for the negative test."""
    poles = np.roll(form.poles, roll, axis=0)
    P = Array1OfPnt(1, len(poles))
    for i, q in enumerate(poles):
        P.SetValue(i + 1, gp_Pnt(*(float(x) for x in q)))
    K = Array1OfReal(1, len(form.knots))
    for i, k in enumerate(form.knots):
        K.SetValue(i + 1, float(k))
    M = Array1OfInteger(1, len(form.multiplicities))
    for i, m in enumerate(form.multiplicities):
        M.SetValue(i + 1, int(m))
    if form.weights is None:
        return Geom_BSplineCurve(P, K, M, int(form.degree), bool(form.periodic))
    W = Array1OfReal(1, len(form.weights))
    for i, w in enumerate(np.roll(form.weights, roll)):
        W.SetValue(i + 1, float(w))
    return Geom_BSplineCurve(P, W, K, M, int(form.degree), bool(form.periodic))


def occ_derivatives(g, t):
    """D2 at each parameter: (3, len(t), 3) array of point, first, second derivative."""
    out = np.empty((3, len(t), 3))
    for j, x in enumerate(t):
        p, v1, v2 = gp_Pnt(), gp_Vec(), gp_Vec()
        g.D2(float(x), p, v1, v2)
        out[0, j] = p.X(), p.Y(), p.Z()
        out[1, j] = v1.X(), v1.Y(), v1.Z()
        out[2, j] = v2.X(), v2.Y(), v2.Z()
    return out


def engine_derivatives(curve, t, order=2):
    d = curve.derivatives(t, order)
    out = np.zeros(d.shape[:-1] + (3,))
    out[..., :curve.dim] = d
    return out


def parameters(curve, count=50):
    """~50 parameters: interior samples off the knots (derivatives are one-sided there)
    plus the domain start, where both take right limits."""
    a, b = curve.domain
    t = np.linspace(a, b, count + 1)[:-1] + 0.37 * (b - a) / count
    u = curve.full_knots
    t = t[np.abs(t[:, None] - u[None, :]).min(axis=1) > 1e-9 * (b - a)]
    return np.concatenate([[a], t])


def max_relative_error(curve, g, order=2):
    t = parameters(curve)
    mine = engine_derivatives(curve, t, order)
    ref = occ_derivatives(g, t)
    errs = []
    a, b = curve.domain
    for k in range(order + 1):
        # derivative scale floor: size / (domain length)^k (a constant rational curve has
        # zero derivatives that both sides compute only to rounding)
        scale = max(np.abs(ref[k]).max(), np.abs(curve.control_points).max() / (b - a) ** k, 1e-300)
        errs.append(float(np.abs(mine[k] - ref[k]).max() / scale))
    return max(errs)


def check(curve, tol=1e-12):
    form = curve.occ_form()
    g = to_occ(form)
    assert g.IsPeriodic() == curve.periodic
    assert g.Degree() == curve.degree
    # OCCT treats equal weights as a polynomial curve
    assert g.IsRational() == (curve.is_rational and np.ptp(curve.weights) > 0)
    a, b = curve.domain
    assert g.FirstParameter() == pytest.approx(a, abs=1e-14 * max(1, abs(a)))
    assert g.LastParameter() == pytest.approx(b, abs=1e-14 * max(1, abs(b)))
    err = max_relative_error(curve, g)
    assert err <= tol, f"occ_form disagrees with OCCT: {err:.3g}"
    return err


RNG = np.random.default_rng(2024)
P6 = RNG.normal(size=(6, 3))
P7 = RNG.normal(size=(7, 3))
W6 = RNG.uniform(0.3, 3.0, 6)
W7 = RNG.uniform(0.3, 3.0, 7)

CASES = {
    "clamped": BSplineCurve(P7, 3),
    "clamped-2d": BSplineCurve(P7[:, :2], 4),
    "nonuniform-repeated": BSplineCurve(P7, 3, [0, 0, 0, 0, 0.3, 0.3, 0.7, 1, 1, 1, 1]),
    "unclamped": BSplineCurve(P7, 2, [-1, -0.5, 0, 0.2, 0.2, 0.9, 1.4, 2.0, 2.5, 3.0]),
    "rational": BSplineCurve(P7, 3, [0, 0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1, 1], W7),
    "periodic-uniform": BSplineCurve(P6, 3, periodic=True),
    "periodic-nonuniform": BSplineCurve(P6, 3, [0, 0.1, 0.35, 0.4, 0.75, 0.9, 1.2], periodic=True),
    "periodic-nonuniform-repeated-inner": BSplineCurve(P6, 3, [0, 0.1, 0.4, 0.4, 0.75, 0.9, 1.2], periodic=True),
    "periodic-rational": BSplineCurve(P6, 3, [0, 0.1, 0.35, 0.4, 0.75, 0.9, 1.2], W6, periodic=True),
    "periodic-degree-eq-count": BSplineCurve(P6[:4], 4, [0, 0.3, 0.5, 0.8, 1.0], periodic=True),
    "periodic-quadratic": BSplineCurve(P6[:4], 2, [0, 1, 2, 3, 4], periodic=True),
}

SEAM_CASES = {  # periodic with a repeated seam knot, copies at the start, the end or both
    "seam-start-2": BSplineCurve(P6[:4], 3, [0, 0, 0.3, 0.6, 1], periodic=True),
    "seam-start-3": BSplineCurve(P6[:4], 3, [0, 0, 0, 0.5, 1], periodic=True),
    "seam-end-2": BSplineCurve(P6[:4], 3, [0, 0.2, 0.5, 1, 1], periodic=True),
    "seam-end-3": BSplineCurve(P6[:4], 3, [0, 0.5, 1, 1, 1], periodic=True),
    "seam-both": BSplineCurve(P6[:4], 3, [0, 0, 0.5, 1, 1], periodic=True),
    "seam-start-quadratic": BSplineCurve(P6[:3], 2, [0, 0, 0.4, 1], periodic=True),
    "seam-start-quartic": BSplineCurve(P6[:5], 4, [0, 0, 0.3, 0.3, 0.6, 1], periodic=True),
    "seam-start-rational": BSplineCurve(P6[:4], 3, [0, 0, 0.3, 0.6, 1], W6[:4], periodic=True),
    "seam-offset-period": BSplineCurve(P6[:5], 3, [0.5, 0.5, 0.75, 1.0, 1.25, 1.5], W6[:5], periodic=True),
}


@pytest.mark.parametrize("name", list(CASES))
def test_occ_form_matches_occt(name):
    check(CASES[name])


@pytest.mark.parametrize("name", list(SEAM_CASES))
def test_periodic_repeated_seam_knot(name):
    """The period [0, 0, 0.3, 0.6, 1] etc.: OCCT only sees distinct knots and
    multiplicities, so the poles must be associated with the knots the way OCCT
    does it (found with OCP: as if every extra seam copy sat at the end of the
    period, i.e. the poles rolled by (copies of t_0) - 1)."""
    check(SEAM_CASES[name])


def test_periodic_circle_with_double_seam():
    """The 9-point unit circle as a periodic NURBS with a double seam knot."""
    sq = math.sqrt(0.5)
    pts = np.array([[1, -1], [1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1]], float)
    w = np.array([sq, 1, sq, 1, sq, 1, sq, 1])
    c = BSplineCurve(pts, 2, [0, 0, .25, .25, .5, .5, .75, .75, 1], w, periodic=True)
    check(c)
    g = to_occ(c.occ_form())
    for x in np.linspace(0, 1, 37):
        p = g.Value(float(x))
        assert abs(math.hypot(p.X(), p.Y()) - 1.0) <= 1e-14


@pytest.mark.parametrize("name", ["periodic-uniform", "periodic-nonuniform", "periodic-rational",
                                  "seam-start-2", "seam-end-2", "seam-both"])
def test_rolled_poles_disagree(name):
    """Negative control: the same form with the periodic poles rolled by one is a
    different curve, far beyond the tolerance."""
    curve = {**CASES, **SEAM_CASES}[name]
    form = curve.occ_form()
    for roll in (1, -1):
        assert max_relative_error(curve, to_occ(form, roll)) > 1e-6


@settings(max_examples=30, deadline=None)
@given(curve=bspline_curves(max_degree=6, dims=(2, 3)))
def test_random_curves_match_occt(curve):
    check(curve, tol=1e-11)


@settings(max_examples=30, deadline=None)
@given(data=st.data(), degree=st.integers(2, 6))
def test_random_repeated_seam_match_occt(data, degree):
    period = data.draw(periodic_knots(degree, repeated_seam=True))
    n = len(period) - 1
    P = data.draw(point_arrays(n, 3))
    w = np.array(data.draw(st.lists(positive_weights, min_size=n, max_size=n))) if data.draw(st.booleans()) else None
    check(BSplineCurve(P, degree, period, w, periodic=True), tol=1e-11)


def test_occ_form_fields():
    c = CASES["nonuniform-repeated"]
    form = c.occ_form()
    np.testing.assert_allclose(form.knots, [0, 0.3, 0.7, 1])
    np.testing.assert_array_equal(form.multiplicities, [4, 2, 1, 4])
    assert form.poles.shape == (7, 3) and form.weights is None and not form.periodic
    f2 = CASES["clamped-2d"].occ_form()
    np.testing.assert_array_equal(f2.poles[:, 2], 0.0)
    fp = SEAM_CASES["seam-both"].occ_form()
    np.testing.assert_array_equal(fp.multiplicities, [3, 1, 3])      # seam counted once: 2 + 2 - 1
    assert sum(fp.multiplicities[:-1]) == len(fp.poles)              # OCCT's periodic pole count


def test_occ_form_rejects_4d():
    with pytest.raises(CagdError, match="^control_points"):
        BSplineCurve(np.zeros((4, 4)), 2).occ_form()
