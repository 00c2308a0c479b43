"""Reusable hypothesis strategies: knot vectors and B-spline / NURBS curves.

Knot spacings are drawn from [0.05, 1] (times a scale) so the spans are never
degenerate; repeated knots come from explicit multiplicities, not from
coincident floats.
"""
from __future__ import annotations

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from cagd import BSplineCurve

KINDS = ("clamped", "floating", "nonuniform", "periodic")

# Periods on a dyadic grid (multiples of 1/64) when True, so that t_n - T == t_0
# exactly. False: arbitrary floats, which once exposed periodic_extend's inexact
# seam copies (pinned by test_periodic_extend_seam_is_exact and
# test_periodic_bezier_segments_with_inexact_seam).
EXACT_PERIODS = False

# CAD-like coordinates: magnitudes below 1e-9 snap to 0 (zero stays an edge case; tiny
# magnitudes would only test underflow of relative tolerances, not the geometry)
coordinates = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False, width=64).map(
    lambda x: 0.0 if abs(x) < 1e-9 else x)
positive_weights = st.floats(0.2, 5.0, allow_nan=False, allow_infinity=False)


@st.composite
def gaps(draw, count: int):
    """``count`` positive spacings in [0.05, 1]."""
    return np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=count, max_size=count)))


@st.composite
def point_arrays(draw, count: int, dim: int):
    flat = draw(st.lists(coordinates, min_size=count * dim, max_size=count * dim))
    return np.array(flat, dtype=np.float64).reshape(count, dim)


@st.composite
def clamped_knots(draw, degree: int, max_interior: int = 5, max_mult=None, start=None):
    """A clamped knot vector: degree+1 copies of both ends, interior knots with
    multiplicities 1..max_mult (default degree)."""
    p = degree
    max_mult = p if max_mult is None else max_mult
    k = draw(st.integers(0, max_interior))
    mults = draw(st.lists(st.integers(1, max_mult), min_size=k, max_size=k))
    a = draw(st.floats(-5.0, 5.0)) if start is None else start
    values = a + np.cumsum(np.concatenate([[0.0], draw(gaps(k + 1))]))
    return np.repeat(values, [p + 1] + mults + [p + 1])


@st.composite
def floating_knots(draw, degree: int, uniform: bool = False, max_distinct: int = 8):
    """An unclamped knot vector (no end multiplicity forced); with ``uniform``
    equally spaced simple knots, otherwise random spacing and multiplicities
    1..degree. The domain [u_p, u_n] is non-empty."""
    p = degree
    if uniform:
        n = draw(st.integers(p + 1, p + 6))
        h = draw(st.floats(0.1, 2.0))
        a = draw(st.floats(-5.0, 5.0))
        return a + h * np.arange(n + p + 1, dtype=np.float64)
    k = draw(st.integers(2, max_distinct))
    mults = np.array(draw(st.lists(st.integers(1, p), min_size=k, max_size=k)))
    values = draw(st.floats(-5.0, 5.0)) + np.concatenate([[0.0], np.cumsum(draw(gaps(k - 1)))])
    u = np.repeat(values, mults)
    n = len(u) - p - 1
    assume(n >= p + 1 and u[p] < u[n])
    return u


@st.composite
def periodic_knots(draw, degree: int, max_distinct: int = 7, repeated_seam: bool = None):
    """One period t_0..t_n with multiplicities <= degree, the seam counted once
    over both ends; optionally a repeated seam knot."""
    p = degree
    k = draw(st.integers(1, max_distinct))           # distinct knots in [t_0, t_n)
    mults = draw(st.lists(st.integers(1, p), min_size=k, max_size=k))
    if repeated_seam is False:
        mults[0] = 1
    elif repeated_seam is True:
        assume(p >= 2)
        mults[0] = draw(st.integers(2, p))
    a = draw(st.floats(-3.0, 3.0))
    steps = draw(gaps(k))
    if EXACT_PERIODS:
        a, steps = np.round(a * 64) / 64, np.round(steps * 64) / 64
    values = a + np.concatenate([[0.0], np.cumsum(steps)])
    # split the seam multiplicity between the two ends of the period
    m0 = mults[0]
    left = draw(st.integers(1, m0))
    right = m0 - left + 1
    inner = list(np.repeat(values[1:k], mults[1:]))
    period = np.array([values[0]] * left + inner + [values[k]] * right)
    n = len(period) - 1
    assume(n >= max(p, 2))
    return period


@st.composite
def bspline_curves(draw, kinds=KINDS, min_degree: int = 1, max_degree: int = 10,
                   rational=None, dims=(1, 3), uniform=None):
    """A random :class:`cagd.BSplineCurve`.

    kinds: subset of ("clamped", "floating", "nonuniform", "periodic");
    "floating" is floating uniform, "nonuniform" unclamped with repeated knots.
    rational: True, False or None (either).
    """
    kind = draw(st.sampled_from(kinds))
    p = draw(st.integers(min_degree, max_degree))
    if kind == "clamped":
        knots = draw(clamped_knots(p))
        n = len(knots) - p - 1
    elif kind == "floating":
        knots = draw(floating_knots(p, uniform=True))
        n = len(knots) - p - 1
    elif kind == "nonuniform":
        knots = draw(floating_knots(p))
        n = len(knots) - p - 1
    else:
        knots = draw(periodic_knots(p))
        n = len(knots) - 1
    dim = draw(st.integers(*dims))
    P = draw(point_arrays(n, dim))
    is_rational = draw(st.booleans()) if rational is None else rational
    w = np.array(draw(st.lists(positive_weights, min_size=n, max_size=n))) if is_rational else None
    return BSplineCurve(P, p, knots, w, periodic=(kind == "periodic"))


def sample_parameters(curve, count: int = 41, include_knots: bool = True) -> np.ndarray:
    """Equally spaced parameters over the domain, plus the knots inside it."""
    a, b = curve.domain
    t = np.linspace(a, b, count)
    if include_knots:
        u = np.unique(curve.full_knots)
        t = np.unique(np.concatenate([t, u[(u >= a) & (u <= b)]]))
    return t


def relative_error(got: np.ndarray, expected: np.ndarray, scale: float = None) -> float:
    """max |got - expected| / max(max |expected|, scale)."""
    got, expected = np.asarray(got), np.asarray(expected)
    ref = float(np.abs(expected).max()) if expected.size else 0.0
    if scale is not None:
        ref = max(ref, scale)
    return float(np.abs(got - expected).max()) / max(ref, 1e-300)


def scipy_derivatives(knots, coefficients, degree: int, t, order: int) -> np.ndarray:
    """Derivatives 0..order of the spline sum_i c_i N_{i,p}(t) by scipy.interpolate
    (an independent oracle), shape (order+1, len(t), dim).

    scipy takes right limits, and at the right domain end u_n it uses the span
    ending there, which is empty (so it returns 0) when u_{n-1} = u_n. The left
    limit at u_n is taken from the mirrored spline instead:
    s(t; u, c) = s(-t; -u reversed, c reversed), derivatives times (-1)^k."""
    from scipy.interpolate import BSpline as SciBSpline
    knots = np.asarray(knots, float)
    c = np.asarray(coefficients, float)
    t = np.asarray(t, float).ravel()
    n = len(knots) - degree - 1
    spl = SciBSpline(knots, c, degree, extrapolate=False)
    mirror = SciBSpline(-knots[::-1], c[::-1], degree, extrapolate=False)
    end = t == knots[n]
    out = np.empty((order + 1, t.size, c.shape[1]))
    for k in range(order + 1):
        out[k] = spl(t, nu=k)
        if end.any():
            out[k][end] = (-1) ** k * mirror(-t[end], nu=k)
    return out
