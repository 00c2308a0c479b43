"""The distance bounds from a centre or an axis (cagd.queries._symmetry, issue 13): the
range of phi = |Pi (x - c)| over a rational Bezier piece from the Bernstein ratios
N_k / W_k contains every sampled value (any piece, any flat) and is exact on a sphere
about c and a cylinder about the axis; the fit recovers a centre and an axis from
normal lines and rejects lines that miss them."""
import numpy as np
from hypothesis import given, settings, strategies as st

from cagd import BezierCurve, BezierSurface, cylinder, sphere
from cagd.queries import _subdivision as sd
from cagd.queries._symmetry import Flat, fit_flats, flat_gap, flat_range


def pieces(obj):
    return sd.Geometry(obj, "obj").pieces


def random_flat(rng, dim):
    c = rng.uniform(-2, 2, dim)
    if dim == 3 and rng.random() < 0.5:
        a = rng.normal(size=3)
        a /= np.linalg.norm(a)
        return Flat(c, np.eye(3) - np.outer(a, a))
    return Flat(c, np.eye(dim))


def phi(flat, X):
    return np.linalg.norm((X - flat.origin) @ flat.projector, axis=-1)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10 ** 6), st.integers(1, 4), st.integers(1, 3), st.sampled_from([2, 3]), st.booleans())
def test_range_contains_every_sample(seed, n, m, dim, surface):
    rng = np.random.default_rng(seed)
    flat = random_flat(rng, dim)
    if surface:
        obj = BezierSurface(rng.uniform(-1, 1, (n + 1, m + 1, dim)), rng.uniform(0.2, 5.0, (n + 1, m + 1)))
        t = np.linspace(0, 1, 31)
        X = obj.grid(t, t).reshape(-1, dim)
    else:
        obj = BezierCurve(rng.uniform(-1, 1, (n + 1, dim)), rng.uniform(0.2, 5.0, n + 1))
        X = obj(np.linspace(0, 1, 401))
    lo, hi, variation = flat_range(pieces(obj).ctrl, flat)
    values = phi(flat, X)
    assert lo[0] <= values.min() and values.max() <= hi[0]
    assert variation.shape == (1, 2 if surface else 1) and np.all(variation >= 0)


def test_range_is_exact_on_a_sphere_and_a_cylinder():
    c = np.array([0.3, -0.2, 1.1])
    lo, hi, _ = flat_range(pieces(sphere(2.5, c)).ctrl, Flat(c, np.eye(3)))
    np.testing.assert_allclose(lo, 2.5, atol=1e-13)
    np.testing.assert_allclose(hi, 2.5, atol=1e-13)
    axis = Flat(np.zeros(3), np.diag([1.0, 1.0, 0.0]))
    lo, hi, variation = flat_range(pieces(cylinder(1.5, 2.0)).ctrl, axis)
    np.testing.assert_allclose(lo, 1.5, atol=1e-13)
    np.testing.assert_allclose(hi, 1.5, atol=1e-13)


def test_gap_of_concentric_spheres_is_their_distance():
    a, b = pieces(sphere(1.0)), pieces(sphere(3.0))
    gap = flat_gap(np.repeat(a.ctrl, len(b.ctrl), 0), np.tile(b.ctrl, (len(a.ctrl), 1, 1, 1)),
                   Flat(np.zeros(3), np.eye(3))).gap
    np.testing.assert_allclose(gap, 2.0, atol=1e-12)
    assert np.all(gap <= 2.0 + 1e-15)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_fit_recovers_centres_and_axes(seed):
    rng = np.random.default_rng(seed)
    c, a = rng.uniform(-3, 3, 3), rng.normal(size=3)
    a /= np.linalg.norm(a)
    # lines through the centre c
    n = rng.normal(size=(6, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    p = c - rng.uniform(1, 4, (6, 1)) * n
    (point,) = fit_flats(p, n, 10.0)
    np.testing.assert_allclose(point.origin, c, atol=1e-10)
    # lines crossing the axis (c, a) at right angles, at different heights
    e = np.cross(a, rng.normal(size=(6, 3)))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    p = c + rng.uniform(-2, 2, (6, 1)) * a - rng.uniform(1, 4, (6, 1)) * e
    (axis,) = fit_flats(p, e, 10.0)
    np.testing.assert_allclose(axis.projector, np.eye(3) - np.outer(a, a), atol=1e-10)
    assert np.linalg.norm((axis.origin - c) @ axis.projector) <= 1e-9
    # lines missing any common point or axis by 1e-6: nothing; parallel lines: nothing
    assert fit_flats(p + 1e-6 * rng.normal(size=p.shape), e, 10.0) == []
    assert fit_flats(p, np.tile(e[0], (6, 1)), 10.0) == []
