"""The seam arithmetic of periodic directions (cagd._periodic) against a brute-force
oracle in exact rational arithmetic, and its users: evaluation of periodic curves and
surfaces across the seam."""
from fractions import Fraction

import numpy as np
from hypothesis import given, settings, strategies as st

import cagd
from cagd._periodic import wrap, wrapped_difference

# periods from tiny to large, starts anywhere, values up to a million periods away
periods = st.floats(1e-6, 1e6)
starts = st.floats(-1e6, 1e6)
offsets = st.one_of(st.floats(-1e6, 1e6), st.integers(-10**6, 10**6).map(float),
                    st.sampled_from([0.0, -0.0, 1.0, -1.0, 1.0 - 2 ** -53, -(2 ** -60), 2 ** -60]))


def exact_wrap(t: float, a: float, T: float) -> Fraction:
    """a + (t - a) - k T with k = floor((t - a) / T), in exact rationals."""
    t, a, T = Fraction(t), Fraction(a), Fraction(T)
    k = (t - a) // T
    return a + (t - a) - k * T


def circle_distance(x: float, y: float, T: float) -> float:
    """The distance of x and y on the circle of length T (exact, then rounded)."""
    d = (Fraction(x) - Fraction(y)) % Fraction(T)
    return float(min(d, Fraction(T) - d))


@settings(max_examples=400, deadline=None)
@given(starts, periods, offsets, st.sampled_from([0.0, 0.5, 1.0]))
def test_wrap_against_exact_arithmetic(a, T, k, frac):
    """t = a + k T (+ a fraction of T): the result lies in [a, a + T) and is t's point on
    the circle up to the rounding of the inputs' magnitude."""
    t = a + k * T + frac * T
    w = float(wrap(t, a, T))
    assert a <= w < a + T or (w == a)
    slack = 8 * np.finfo(float).eps * (abs(t) + abs(a) + T)
    assert circle_distance(w, float(exact_wrap(t, a, T)), T) <= slack


@settings(max_examples=300, deadline=None)
@given(starts, periods, st.floats(0.0, 1.0, exclude_max=True), st.integers(-1000, 1000))
def test_values_at_the_seam_and_many_periods_away(a, T, s, k):
    """a + s T shifted by k periods wraps back to a + s T (or to a, the same point, at the
    seam); both ends of the domain are one point."""
    base = a + s * T
    w = float(wrap(base + k * T, a, T))
    assert circle_distance(w, base, T) <= 8 * np.finfo(float).eps * (abs(a) + abs(k * T) + T)
    assert float(wrap(a + T, a, T)) == a or circle_distance(float(wrap(a + T, a, T)), a, T) <= 4e-16 * (abs(a) + T)
    assert float(wrap(a, a, T)) == a


def test_just_below_the_start_is_not_the_end():
    """mod(-tiny, T) rounds to T; the wrapped value must be a (the seam), never a + T."""
    for a, T in ((0.0, 1.0), (0.3, 0.7), (-2.0, 2 * np.pi), (1e6, 1.0)):
        w = wrap(np.array([a - 1e-300, a - 1e-17, np.nextafter(a, -np.inf)]), a, T)
        assert np.all(w >= a) and np.all(w < a + T)


@settings(max_examples=400, deadline=None)
@given(starts, periods, offsets, offsets)
def test_wrapped_difference_is_the_shortest_step(a, T, x, y):
    t1, t0 = a + x, a + y
    d = float(wrapped_difference(t1, t0, T))
    assert -T / 2 <= d <= T / 2
    slack = 8 * np.finfo(float).eps * (abs(t1) + abs(t0) + T)
    # the step lands on t1's point of the circle, and none is shorter
    assert circle_distance(t0 + d, t1, T) <= slack
    assert abs(abs(d) - circle_distance(t1, t0, T)) <= slack


def test_vectorized_with_per_direction_periods():
    t = np.array([[1.5, -0.25], [-3.0, 7.0]])
    np.testing.assert_allclose(wrap(t, np.array([0.0, -1.0]), np.array([1.0, 2.0])), [[0.5, -0.25], [0.0, -1.0]])
    np.testing.assert_allclose(wrapped_difference(np.array([0.95, 0.1]), np.array([0.05, 0.9]), 1.0),
                               [-0.1, 0.2], atol=1e-15)
    assert wrap(np.array([12, -3]), 0, 10).tolist() == [2, 7]        # integers stay integers


def test_periodic_curve_and_surface_evaluate_across_the_seam():
    """Users: parameters a period (or many) away, or just below the start, evaluate to the
    same points."""
    c = cagd.BSplineCurve([[0, 0], [2, 0], [2, 2], [0, 2]], 3, periodic=True)
    t = np.array([0.0, 0.25, 0.9])
    np.testing.assert_allclose(c(t + 7.0), c(t), atol=1e-13)
    np.testing.assert_allclose(c(-1e-17), c(0.0), atol=1e-15)
    s = cagd.BSplineSurface(np.random.default_rng(1).normal(size=(6, 4, 3)), 3, 2, periodic_u=True)
    (u0, u1), _ = s.domain
    u = np.array([u0, u0 + 0.3 * (u1 - u0)])
    np.testing.assert_allclose(s(u - 5 * (u1 - u0), 0.2), s(u, 0.2), atol=1e-13)
    np.testing.assert_allclose(s(u0 - 1e-17, 0.2), s(u0, 0.2), atol=1e-15)
    np.testing.assert_allclose(s.grid(u + (u1 - u0), [0.2]), s.grid(u, [0.2]), atol=1e-13)
