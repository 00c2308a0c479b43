"""Deviation analysis: signed distances against analytic ones (plane, sphere, circle),
statistics against numpy, the colour map is a PNG, bad input."""
import numpy as np
import pytest

import cagd
from cagd import CagdError
from cagd.queries.deviation import deviation, deviation_map


def plane():
    """z = 0 over [0, 2] x [0, 1]; S_u x S_v = +z."""
    P = np.array([[[0, 0, 0], [0, 1, 0]], [[2, 0, 0], [2, 1, 0]]], float)
    return cagd.BezierSurface(P)


def test_plane_signed_distances_and_statistics():
    rng = np.random.default_rng(1)
    X = np.column_stack([rng.uniform(0, 2, 500), rng.uniform(0, 1, 500), rng.normal(0, 0.01, 500)])
    d = deviation(plane(), X, percentiles=(5, 50, 95))
    np.testing.assert_allclose(d.distances, X[:, 2], atol=1e-15)
    assert d.signed
    z = X[:, 2]
    assert d.max == pytest.approx(z.max()) and d.min == pytest.approx(z.min())
    assert d.mean == pytest.approx(z.mean(), abs=1e-15) and d.rms == pytest.approx(np.sqrt(np.mean(z ** 2)))
    assert d.max_abs == pytest.approx(np.abs(z).max())
    np.testing.assert_allclose(list(d.percentiles.values()), np.percentile(z, [5, 50, 95]), atol=1e-15)
    assert "| rms |" in d.table()


def test_sphere_sign_is_outside_positive():
    s = cagd.sphere(2.0)
    rng = np.random.default_rng(2)
    dirs = rng.normal(size=(200, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    radii = 2.0 + rng.uniform(-0.1, 0.1, 200)
    d = deviation(s, dirs * radii[:, None])
    np.testing.assert_allclose(d.distances, radii - 2.0, atol=1e-13)


def test_plane_curve_in_plane_sign_and_space_curve_unsigned():
    w = np.sqrt(0.5)
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    circle = cagd.BSplineCurve(P, 2, np.array([0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4]) / 4,
                               np.array([1, w, 1, w, 1, w, 1, w, 1]))      # counterclockwise
    ang = np.linspace(0.1, 6.2, 50)
    r = 1.0 + np.linspace(-0.2, 0.2, 50)
    X = np.stack([r * np.cos(ang), r * np.sin(ang)], 1)
    d = deviation(circle, X)
    np.testing.assert_allclose(d.distances, 1.0 - r, atol=1e-13)     # left of travel = inside
    c3 = cagd.BezierCurve([[0, 0, 0], [1, 1, 1], [2, 0, 0]])
    X3 = c3(np.linspace(0, 1, 20)) + [0, 0, 0.05]
    d3 = deviation(c3, X3)
    assert not d3.signed and np.all(d3.distances >= 0)
    with pytest.raises(CagdError, match="signed"):
        deviation(c3, X3, signed=True)


def test_colour_map_png(tmp_path):
    pytest.importorskip("matplotlib")
    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(0, 2, 100), rng.uniform(0, 1, 100), rng.normal(0, 0.01, 100)])
    out = deviation_map(plane(), X, tmp_path / "dev.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    w = np.sqrt(0.5)
    circle = cagd.BSplineCurve([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], 2, [0, 0, 0, .5, .5, 1, 1, 1],
                               [1, w, 1, w, 1])
    out = deviation_map(circle, rng.uniform(-1, 1, (30, 2)), tmp_path / "curve.png")
    assert out.stat().st_size > 1000


def test_bad_input():
    with pytest.raises(CagdError, match="points"):
        deviation(plane(), np.zeros((0, 3)))
    with pytest.raises(CagdError, match="percentiles"):
        deviation(plane(), [[0.0, 0.0, 0.1]], percentiles=(50, 101))
    with pytest.raises(CagdError, match="obj"):
        deviation("plane", [[0.0, 0.0, 0.1]])


@pytest.mark.parametrize("scale", [1e-300, 1.0, 1e200, 1e300])
def test_statistics_do_not_overflow_at_any_scale(scale):
    """The mean and RMS of distances near 1e300 were inf (d * d overflowed): a point
    cloud and a sphere scaled together give the same statistics, scaled."""
    pts = np.array([[2.0, 0, 0], [0, 3.0, 0], [0, 0, 0.5]])
    ref = deviation(cagd.sphere(1.0), pts)
    got = deviation(cagd.sphere(scale), pts * scale)
    for name in ("mean", "rms", "max_abs", "max", "min"):
        assert getattr(got, name) == pytest.approx(getattr(ref, name) * scale, rel=1e-12), name
    assert ref.rms == pytest.approx(np.sqrt((1 + 4 + 0.25) / 3), rel=1e-12)


def test_chunked_equals_unchunked(monkeypatch):
    """deviation measures DEVIATION_CHUNK points at a time (issue 14: 10^7 points in one
    query ran out of memory); chunks of 29 give the same answer as one chunk, for the
    nearest of several patches, signed (the distances bit for bit)."""
    import sys
    dev_module = sys.modules["cagd.queries.deviation"]
    patches = cagd.ellipsoid(3.0, 2.0, 1.5)
    rng = np.random.default_rng(8)
    X = rng.normal(size=(120, 3)) * 2.5
    monkeypatch.setattr(dev_module, "DEVIATION_CHUNK", 1 << 20)
    whole = dev_module.deviation(patches, X)
    monkeypatch.setattr(dev_module, "DEVIATION_CHUNK", 29)
    parts = dev_module.deviation(patches, X)
    for name in ("distances", "params", "feet", "owner"):
        assert np.array_equal(getattr(parts, name), getattr(whole, name)), name
    # the certificates come from each query's own branch and bound: valid and close
    assert np.all(parts.lower_bounds <= np.abs(parts.distances))
    np.testing.assert_allclose(parts.lower_bounds, whole.lower_bounds, rtol=1e-6)
    assert (parts.max, parts.min, parts.mean, parts.rms, parts.percentiles, parts.signed) == \
        (whole.max, whole.min, whole.mean, whole.rms, whole.percentiles, whole.signed)
    assert parts.owner is not None and len(set(parts.owner.tolist())) > 1     # several patches are nearest


def test_many_objects_far_ones_cost_their_box_test_only(monkeypatch):
    """Issue 16: points near one surface measured against it and three surfaces far away
    give the answer of that surface alone (same distances, feet, bounds; owner its index),
    and the far surfaces are never queried (their box bounds exceed the distances found);
    on equal distances the first object owns the point, whatever the order measured."""
    import sys
    dv = sys.modules["cagd.queries.deviation"]
    near = plane()
    far = [near.transformed(np.eye(3), [0.0, 0.0, z]) for z in (50.0, 80.0, -60.0)]
    rng = np.random.default_rng(8)
    X = np.column_stack([rng.uniform(0, 2, 300), rng.uniform(0, 1, 300), rng.normal(0, 0.01, 300)])
    asked = []
    real = dv._closest_point

    def spy(o, pts, **kw):
        asked.append((o, len(pts)))
        return real(o, pts, **kw)

    monkeypatch.setattr(dv, "_closest_point", spy)
    alone = deviation(near, X)
    asked.clear()
    many = deviation(far[:2] + [near] + far[2:], X)
    assert [n for o, n in asked] == [300] and asked[0][0] is near
    np.testing.assert_array_equal(many.distances, alone.distances)
    np.testing.assert_array_equal(many.feet, alone.feet)
    np.testing.assert_array_equal(many.lower_bounds, alone.lower_bounds)
    assert np.all(many.owner == 2)
    twice = deviation([far[0], near, near], X)
    assert np.all(twice.owner == 1)
