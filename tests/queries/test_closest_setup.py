"""Closest-point set-up (issue 16): the light projector for a few points, projectors cached
by content, partial bounds computed once."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st, HealthCheck

import cagd
import cagd.queries.closest as cl
from cagd.queries.bounds import bezier_pieces


def _bumpy(n: int = 30, noise: float = 0.5, seed: int = 0) -> cagd.BSplineSurface:
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 100.0, n)
    U, V = np.meshgrid(u, u, indexing="ij")
    Z = 10.0 * np.sin(0.07 * U) * np.cos(0.05 * V) + noise * rng.standard_normal(U.shape)
    return cagd.BSplineSurface(np.stack([U, V, Z], -1), 3, 3)


@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.integers(0, 10_000), st.sampled_from([0.0, 0.5, 3.0]), st.sampled_from([0.01, 0.1, 1.0]))
def test_light_projector_gives_the_default_answer(seed, noise, spread):
    """The light projector (pieces as cells, no voxel grid: every point descends the
    hierarchy) finds the same distances as the default one, with valid bounds, for points
    near and far (spread: the points' offset in model sizes)."""
    s = _bumpy(12, noise, seed)
    rng = np.random.default_rng(seed)
    X = s(rng.uniform(0, 1, 20), rng.uniform(0, 1, 20)) + spread * 100.0 * rng.standard_normal((20, 3))
    light, full = cl.Projector(s, light=True), cl.Projector(s)
    assert light._origin is None and full._origin is not None
    a, b = light.closest(X), full.closest(X)
    np.testing.assert_allclose(a.distances, b.distances, rtol=1e-10, atol=1e-10)
    assert np.all(a.lower_bounds <= a.distances)
    np.testing.assert_allclose(a.lower_bounds, a.distances, rtol=1e-6)


def test_light_projector_against_brute_force():
    """One point at a time on a bumpy 50 x 50 net: the light answer is no farther than a
    dense sampling (the sampling's nearest point, refined nowhere) and its bound holds."""
    s = _bumpy(50, 2.0, 3)
    G = s.grid(np.linspace(0, 1, 400), np.linspace(0, 1, 400)).reshape(-1, 3)
    rng = np.random.default_rng(5)
    for X in rng.uniform([-20, -20, -30], [120, 120, 30], (6, 3)):
        r = cagd.closest_point(s, X)
        brute = np.sqrt(((G - X) ** 2).sum(1)).min()
        assert r.distances[0] <= brute + 1e-9
        assert brute - r.distances[0] < 0.05          # the sampling's step is 0.25
        assert r.lower_bounds[0] <= r.distances[0]


def test_tiers_and_reuse(monkeypatch):
    """Fewer than LIGHT_POINTS points build the light projector; a larger query the
    default one; each is built once and a query always gets its own tier's (issue 16:
    a small query after a large one took the default projector, and its answer depended
    on the calls made before: 5e-15 apart, so no worker process could reproduce it)."""
    monkeypatch.setattr(cl, "_CACHE", type(cl._CACHE)())
    monkeypatch.setattr(cl, "_BY_CONTENT", type(cl._BY_CONTENT)())
    monkeypatch.setattr(cl, "LIGHT_POINTS", 64)
    s = _bumpy(20)
    X = s(np.full(200, 0.3), np.linspace(0, 1, 200)) + 1.0
    first = cagd.closest_point(s, X[:5])
    assert set(cl._CACHE[s]) == {0} and cl._CACHE[s][0].light
    light = cl._CACHE[s][0]
    cagd.closest_point(s, X)
    assert set(cl._CACHE[s]) == {0, 1}
    assert cl.projector(s, 1) is light and cl.projector(s, 64) is cl._CACHE[s][1]
    again = cagd.closest_point(s, X[:5])
    for name in ("params", "feet", "distances", "lower_bounds"):
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name))


def test_a_query_answers_the_same_whatever_was_cached_before(monkeypatch):
    """closest_point is a function of its arguments (issue 16: worker processes and Dask
    tasks start with an empty cache): the same answers, bit for bit, with a fresh cache
    and after queries of every tier on the same object."""
    monkeypatch.setattr(cl, "FINE_POINTS", 300)
    monkeypatch.setattr(cl, "LIGHT_POINTS", 64)
    s = _bumpy(12, 0.5, 1)
    rng = np.random.default_rng(3)
    X = s(rng.uniform(0, 1, 400), rng.uniform(0, 1, 400)) + rng.normal(0, 2.0, (400, 3))
    sizes = (5, 100, 400)

    def answers(order):
        got = {n: cagd.closest_point(s, X[:n]) for n in order}
        return [got[n] for n in sizes]

    monkeypatch.setattr(cl, "_CACHE", type(cl._CACHE)())
    monkeypatch.setattr(cl, "_BY_CONTENT", type(cl._BY_CONTENT)())
    fresh = []
    for n in sizes:                             # each with an empty cache
        cl._CACHE.clear()
        cl._BY_CONTENT.clear()
        fresh.append(cagd.closest_point(s, X[:n]))
    assert set(cl._CACHE[s]) == {2}
    for warm in (answers(sizes), answers(sizes[::-1])):     # every tier cached, the fullest last or first
        for a, b in zip(fresh, warm):
            for name in ("params", "feet", "distances", "lower_bounds"):
                np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_projectors_are_cached_by_content(monkeypatch):
    """An equal object built again (cq_ext.from_shape makes a new one on every call) finds
    the same projector; a different one (one pole moved by 1e-12) does not; classes that do
    not name their content (a Coons patch keeps its curves private) are cached by identity
    only."""
    monkeypatch.setattr(cl, "_BY_CONTENT", type(cl._BY_CONTENT)())
    s = _bumpy(20)
    again = cagd.BSplineSurface(np.array(s.control_points), 3, 3, np.array(s.knots_u), np.array(s.knots_v))
    assert again is not s
    assert cl.content_key(again) == cl.content_key(s)
    assert cl.projector(again, 1) is cl.projector(s, 1)
    P = np.array(s.control_points)
    P[3, 4, 2] += 1e-12
    moved = s.with_control_points(P)
    assert cl.content_key(moved) != cl.content_key(s)
    assert cl.projector(moved, 1) is not cl.projector(s, 1)
    c = cagd.BSplineCurve(np.random.default_rng(1).uniform(-1, 1, (9, 3)), 3)
    c2 = cagd.BSplineCurve(np.array(c.control_points), 3, np.array(c.knots))
    assert cl.projector(c2, 1) is cl.projector(c, 1)
    assert cl.content_key(c.with_weights(np.full(9, 2.0))) != cl.content_key(c)
    coons = cagd.CoonsPatch if hasattr(cagd, "CoonsPatch") else None
    if coons is not None:
        assert "_content_fields" not in vars(coons)
    rev = [t for t in vars(cagd).values() if isinstance(t, type) and issubclass(t, cagd.BSplineSurface)
           and t is not cagd.BSplineSurface]
    for t in rev:                                   # a subclass does not inherit the key
        assert "_content_fields" not in vars(t)


def test_content_cache_is_bounded(monkeypatch):
    monkeypatch.setattr(cl, "_BY_CONTENT", type(cl._BY_CONTENT)())
    monkeypatch.setattr(cl, "CACHE_OBJECTS", 3)
    curves = [cagd.BSplineCurve(np.random.default_rng(i).uniform(-1, 1, (6, 2)), 3) for i in range(5)]
    for c in curves:
        cl.projector(c, 1)
    assert len(cl._BY_CONTENT) == 3
    assert cl.content_key(curves[-1]) in cl._BY_CONTENT
    assert cl.content_key(curves[0]) not in cl._BY_CONTENT


def test_partial_bounds_computed_once_and_equal():
    """The bounds of the highest order asked are kept; lower orders are their subset, equal
    to a fresh computation of that order (rational pieces included)."""
    rng = np.random.default_rng(4)
    s = cagd.BSplineSurface(rng.uniform(-1, 1, (6, 5, 3)), 3, 2).with_weights(rng.uniform(0.5, 2.0, (6, 5)))
    for obj in (s, _bumpy(8)):
        fresh2 = bezier_pieces(obj).partial_bounds(2)
        pieces = bezier_pieces(obj)
        third = pieces.partial_bounds(3)
        again = pieces.partial_bounds(2)
        assert set(again) == set(fresh2)
        for al in fresh2:
            np.testing.assert_array_equal(again[al], fresh2[al])
            np.testing.assert_array_equal(third[al], fresh2[al])
        assert pieces.partial_bounds(3) is not third          # a copy: the cache cannot be edited
        with pytest.raises(ValueError):
            pieces.hull_boxes()[0][0, 0] = 1.0


def test_content_cache_is_bounded_by_bytes(monkeypatch):
    """Projectors kept by content hold at most CACHE_BYTES of arrays (the newest always)."""
    monkeypatch.setattr(cl, "_BY_CONTENT", type(cl._BY_CONTENT)())
    curves = [cagd.BSplineCurve(np.random.default_rng(i).uniform(-1, 1, (40, 3)), 3) for i in range(4)]
    one = cl._footprint(cl.Projector(curves[0], light=True))
    monkeypatch.setattr(cl, "CACHE_BYTES", int(2.5 * one))
    for c in curves:
        cl.projector(c, 1)
    assert len(cl._BY_CONTENT) == 2
    assert cl.content_key(curves[-1]) in cl._BY_CONTENT


def test_footprint_counts_the_half_hessian_hull_as_it_grows():
    """The hull's coefficients fill lazily, one row per cell asked for: the cache's byte
    count takes the rows held at the time (else projectors held by content could outgrow
    CACHE_BYTES), and a few points touch a small share of a large net's cells."""
    rng = np.random.default_rng(3)
    g = np.linspace(0.0, 100.0, 40)
    U, V = np.meshgrid(g, g, indexing="ij")
    P = np.stack([U, V, 10 * np.sin(0.07 * U) * np.cos(0.05 * V)], -1)
    for W in (None, rng.uniform(0.8, 1.25, (40, 40))):
        s = cagd.BSplineSurface(P, 3, 3, weights=W)
        with_hull, without = cl.Projector(s, light=True), cl.Projector(s, light=True)
        without._hessian = None
        assert cl._footprint(with_hull) == cl._footprint(without)
        uv = rng.uniform(0, 1, (5, 2))
        with_hull.closest(s(uv[:, 0], uv[:, 1]) + [0, 0, 1.0])
        held = with_hull._hessian.nbytes
        assert cl._footprint(with_hull) - cl._footprint(without) == held > 0
        rows = (with_hull._hessian._rows._slot >= 0).sum()
        assert 0 < rows <= 10 * len(uv), rows
