"""Closest points do not depend on the parameter scale (issue 16's reparametrisation
oracle): the same bumpy bicubic with its knots scaled by 1e-3 and shifted by 1e4 gives
the same feet, distances and certified lower bounds, the parameters mapped alike.

What "the same" can mean in floating point: parameters near 1e4 are spaced
ulp(1e4) = 1.8e-12 apart, 1.8e-9 of a knot span of width 1e-4, so a point of the shifted
surface is only defined to about that fraction of a span's size (here 100/9 mm): about
2e-8 mm. Feet and distances agree to a few such units; the bounds stay non-zero."""
import numpy as np

import cagd

SHIFT, SCALE = 1e4, 1e-3
N = 12
SIZE = 100.0
SPAN = SIZE / (N - 3)                                          # a knot span's geometric size
PRECISION = 8 * np.spacing(SHIFT) / (SCALE / (N - 3)) * SPAN   # what the shifted parameters resolve


def _pair(n: int, scale: float, shift: float, rng: np.random.Generator):
    """A bumpy n x n bicubic over [0, SIZE]^2 on uniform clamped knots, the same net on
    its knots times ``scale`` plus ``shift``, and 800 points at 0.1 to 50 mm from it."""
    g = np.linspace(0.0, SIZE, n)
    P = np.zeros((n, n, 3))
    P[..., 0], P[..., 1] = np.meshgrid(g, g, indexing="ij")
    P[..., 2] = 8 * rng.standard_normal((n, n))
    S = cagd.BSplineSurface(P, 3, 3)
    T = cagd.BSplineSurface(P, 3, 3, S.knots_u * scale + shift, S.knots_v * scale + shift)
    near = S(rng.random(200), rng.random(200))
    return S, T, np.concatenate([near + rng.normal(size=near.shape) * s for s in (0.1, 1.0, 10.0, 50.0)])


def test_scaled_and_shifted_knots_give_the_same_answers():
    S, T, pts = _pair(N, SCALE, SHIFT, np.random.default_rng(7))
    a, b = cagd.closest_point(S, pts), cagd.closest_point(T, pts)
    assert a.converged and b.converged
    assert np.abs(a.feet - b.feet).max() <= PRECISION
    assert np.abs(a.distances - b.distances).max() <= PRECISION
    assert np.abs(a.lower_bounds - b.lower_bounds).max() <= PRECISION
    assert (b.lower_bounds > 0).all() and (b.lower_bounds <= b.distances).all()
    assert np.abs(a.params * SCALE + SHIFT - b.params).max() <= 8 * np.spacing(SHIFT) * N


def test_exactly_representable_reparametrisation_gives_the_same_answers_to_1e12():
    """With knots whose scaled and shifted values are exact in float64 (dyadic spans,
    scale 2^-10 ~ 1e-3, shift 2^13 ~ 1e4) both surfaces are the same geometry (equal at
    dyadic parameters to rounding), so the issue's 1e-12 of the size holds for the
    distances and the lower bounds. The feet hold to what parameters near 2^13 resolve:
    ulp(2^13) = 1.8e-12 is 1.5e-8 of a span of 2^-13, i.e. 2e-7 mm of a 12.5 mm span (a
    foot's distance is insensitive to that to first order)."""
    shift, scale, n = 2.0 ** 13, 2.0 ** -10, 11                  # 8 spans of 1/8
    rng = np.random.default_rng(11)
    S, T, pts = _pair(n, scale, shift, rng)
    assert np.array_equal((S.knots_u * scale + shift - shift) / scale, S.knots_u)    # exact
    uv = rng.integers(0, 2 ** 20, (200, 2)) / 2.0 ** 20                 # exact after the map
    assert np.abs(S(uv[:, 0], uv[:, 1]) - T(uv[:, 0] * scale + shift, uv[:, 1] * scale + shift)).max() <= 1e-12 * SIZE
    a, b = cagd.closest_point(S, pts), cagd.closest_point(T, pts)
    assert a.converged and b.converged
    for f in ("distances", "lower_bounds"):
        assert np.abs(getattr(a, f) - getattr(b, f)).max() <= 1e-12 * SIZE, f
    resolved = 8 * np.spacing(shift) / scale * SIZE                  # a span's speed times ulp(2^13)
    assert np.abs(a.feet - b.feet).max() <= resolved
    assert (b.lower_bounds > 0).all() and (b.lower_bounds <= b.distances).all()
    assert np.abs(a.params * scale + shift - b.params).max() <= 8 * np.spacing(shift)
