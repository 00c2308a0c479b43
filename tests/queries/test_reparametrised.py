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


def test_scaled_and_shifted_knots_give_the_same_answers():
    rng = np.random.default_rng(7)
    g = np.linspace(0.0, SIZE, N)
    P = np.zeros((N, N, 3))
    P[..., 0], P[..., 1] = np.meshgrid(g, g, indexing="ij")
    P[..., 2] = 8 * rng.standard_normal((N, N))
    S = cagd.BSplineSurface(P, 3, 3)
    T = cagd.BSplineSurface(P, 3, 3, S.knots_u * SCALE + SHIFT, S.knots_v * SCALE + SHIFT)
    near = S(rng.random(200), rng.random(200))
    pts = np.concatenate([near + rng.normal(size=near.shape) * s for s in (0.1, 1.0, 10.0, 50.0)])
    a, b = cagd.closest_point(S, pts), cagd.closest_point(T, pts)
    assert a.converged and b.converged
    assert np.abs(a.feet - b.feet).max() <= PRECISION
    assert np.abs(a.distances - b.distances).max() <= PRECISION
    assert np.abs(a.lower_bounds - b.lower_bounds).max() <= PRECISION
    assert (b.lower_bounds > 0).all() and (b.lower_bounds <= b.distances).all()
    assert np.abs(a.params * SCALE + SHIFT - b.params).max() <= 8 * np.spacing(SHIFT) * N
