"""Deviation analysis: signed distances against analytic ones (plane, sphere, circle),
statistics against numpy, the colour map is a PNG, bad input."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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


def test_many_objects_far_ones_are_never_set_up(projectors_built):
    """Issue 16, many objects: surfaces far from every point cost a pass over their
    control net only: no closest-point projector (no Bezier cells, bounds or hierarchy)
    is built for them, and the answer is the near surface's alone bit for bit."""
    rng = np.random.default_rng(3)
    P = np.stack([*np.meshgrid(np.linspace(0, 10, 6), np.linspace(0, 10, 6), indexing="ij"), np.zeros((6, 6))], -1)
    P[..., 2] = rng.normal(0, 1, (6, 6))
    near = cagd.BSplineSurface(P, 3, 3)
    far = [near.transformed(np.eye(3), off) for off in ([30.0, 0, 0], [0, -40.0, 0], [0, 0, 25.0])]
    X = near(rng.uniform(0, 1, 40), rng.uniform(0, 1, 40)) + rng.normal(0, 0.2, (40, 3))
    alone = deviation(near, X)
    built = projectors_built
    built.forget(near)                           # near is set up again (the spy sees it)
    built.clear()
    many = deviation([far[0], near, far[1], far[2]], X)
    assert built and all(o is near for o in built)
    for f in ("distances", "feet", "params", "lower_bounds"):
        np.testing.assert_array_equal(getattr(many, f), getattr(alone, f))
    assert np.all(many.owner == 1)


@pytest.mark.parametrize("first", [0, 1])
def test_a_point_equidistant_from_two_surfaces_belongs_to_the_first(first):
    """Two planes z = -1 and z = +1 (different objects, not copies) and points at z = 0:
    the distance 1 to both; the owner is the first in the list whichever plane it is,
    its foot, parameters, sign and lower bound those of that plane alone."""
    low, high = plane().transformed(np.eye(3), [0, 0, -1.0]), plane().transformed(np.eye(3), [0, 0, 1.0])
    pair = [low, high] if first == 0 else [high, low]
    rng = np.random.default_rng(4)
    X = np.column_stack([rng.uniform(0.1, 1.9, 50), rng.uniform(0.1, 0.9, 50), np.zeros(50)])
    both = deviation(pair, X)
    assert np.all(both.owner == 0)
    own = deviation(pair[0], X)
    np.testing.assert_allclose(np.abs(both.distances), 1.0, rtol=1e-15)
    for f in ("distances", "feet", "params", "lower_bounds"):
        np.testing.assert_array_equal(getattr(both, f), getattr(own, f))
    assert np.all(both.distances == (1.0 if pair[0] is low else -1.0))


@settings(max_examples=15, deadline=None)
@given(st.lists(st.tuples(st.floats(-30, 30), st.floats(-30, 30), st.floats(-5, 5)), min_size=1, max_size=4),
       st.integers(0, 2 ** 31))
def test_many_objects_give_the_nearest_of_each_alone(offsets, seed):
    """Copies of one bumpy patch placed anywhere (apart, overlapping, touching): every
    point's |distance| is the smallest over the objects measured alone (to 1e-12 of the
    size: the queries see other row sets), its owner one of those nearest, its foot on the
    owner at that distance, and the lower bound certified (<= the distance)."""
    rng = np.random.default_rng(seed)
    P = np.stack([*np.meshgrid(np.linspace(0, 10, 4), np.linspace(0, 10, 4), indexing="ij"), np.zeros((4, 4))], -1)
    P[..., 2] = rng.normal(0, 1, (4, 4))
    objs = [cagd.BSplineSurface(P, 2, 2).transformed(np.eye(3), off) for off in [(0, 0, 0)] + offsets]
    X = objs[0](rng.uniform(0, 1, 60), rng.uniform(0, 1, 60)) + rng.normal(0, 3.0, (60, 3))
    many = deviation(objs, X)
    each = np.array([np.abs(deviation(o, X).distances) for o in objs])
    size = 50.0
    assert np.all(np.abs(np.abs(many.distances) - each.min(axis=0)) <= 1e-12 * size)
    assert np.all(each[many.owner, np.arange(len(X))] <= each.min(axis=0) + 1e-12 * size)
    assert np.all(many.lower_bounds <= np.abs(many.distances))
    on = np.array([np.linalg.norm(objs[k](*p) - f) for k, p, f in zip(many.owner, many.params, many.feet)])
    assert on.max() <= 1e-12 * size


# --- issue 16, scan scale: worker processes and Dask tasks give the serial answer ---------------

def two_lids():
    """Two bumpy biquadratic Bezier patches side by side (x in [20, 40] and [40, 60])."""
    a = cagd.BezierSurface([[[20, 0, 0], [20, 10, 2], [20, 20, 0]], [[30, 0, 1], [30, 10, 4], [30, 20, 1]],
                            [[40, 0, 0], [40, 10, 2], [40, 20, 0]]])
    b = cagd.BezierSurface([[[40, 0, 0], [40, 10, 2], [40, 20, 0]], [[50, 0, -1], [50, 10, 0], [50, 20, -1]],
                            [[60, 0, 0], [60, 10, 3], [60, 20, 0]]])
    return [a, b]


def scan(n, seed=0):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(18, 62, n), rng.uniform(-2, 22, n), rng.normal(1, 1, n)])


def assert_same(a, b):
    """Two results equal bit for bit: every array, statistic and flag."""
    import dataclasses
    assert type(a) is type(b)
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), f.name
            assert not y.flags.writeable, f.name
        else:
            assert x == y, f.name


def test_workers_give_the_serial_answer_bit_for_bit(monkeypatch):
    """deviation(..., workers=2): the chunks measured in two spawned processes (each with
    an empty projector cache), the results equal to the serial run's bit for bit, the
    progress reported chunk by chunk in order."""
    import sys
    dv = sys.modules["cagd.queries.deviation"]
    monkeypatch.setattr(dv, "DEVIATION_CHUNK", 300)        # 5 chunks (the parent does the chunking)
    objs, X = two_lids(), scan(1300)
    for o in objs:                  # fuller projectors cached here than a worker builds for its chunks
        cagd.closest_point(o, scan(1500, seed=1))
    serial = deviation(objs, X)
    seen = []
    pooled = deviation(objs, X, workers=2, progress=lambda done, total: seen.append((done, total)))
    assert_same(serial, pooled)
    assert seen == [(min(s + 300, 1300), 1300) for s in range(0, 1300, 300)]
    assert set(pooled.owner.tolist()) == {0, 1} and pooled.signed
    assert np.all(pooled.lower_bounds <= np.abs(pooled.distances))


class Unsendable(cagd.BezierSurface):
    """A patch that pickles here and fails to unpickle in a worker (divides by zero)."""

    def __reduce__(self):
        import operator
        return operator.truediv, (1, 0)


def test_a_failure_in_a_worker_is_a_cagd_error_naming_the_chunk(monkeypatch):
    import multiprocessing
    import sys
    dv = sys.modules["cagd.queries.deviation"]
    monkeypatch.setattr(dv, "DEVIATION_CHUNK", 300)
    a, b = two_lids()
    bad = Unsendable(np.array(b.control_points))
    assert np.array_equal(deviation([a, bad], scan(50)).distances, deviation([a, b], scan(50)).distances)
    with pytest.raises(CagdError, match=r"^workers: chunk 0 \(points 0 to 299\) failed: .*ZeroDivisionError"):
        deviation([a, bad], scan(1300), workers=2)
    assert not multiprocessing.active_children()


@pytest.mark.parametrize("bad", [0, -1, True, 2.5, "2", None])
def test_bad_workers(bad):
    with pytest.raises(CagdError, match="^workers: "):
        deviation(two_lids(), scan(10), workers=bad)


def test_queries_run_unchanged_as_dask_tasks(monkeypatch):
    """closest_point and deviation submitted as they are to a local Dask cluster of two
    worker processes (the objects pickled to them, each worker with an empty projector
    cache) give the serial answers bit for bit, also after this process cached fuller
    projectors of the same objects; a scan split into chunks mapped over the cluster gives
    the serial run's distances."""
    distributed = pytest.importorskip("dask.distributed")
    import logging
    import sys
    dv = sys.modules["cagd.queries.deviation"]
    objs, X = two_lids(), scan(3000, seed=5)
    ball = cagd.sphere(10.0)
    Y = ball(*np.random.default_rng(6).uniform(0, 1, (2, 1500))) * 1.01
    cagd.closest_point(ball, Y)                 # a default projector cached here (a worker has none)
    cagd.closest_point(objs[0], X)
    tasks = [(cagd.closest_point, ball, Y[:200]), (cagd.closest_point, objs[1], X[:1500]),
             (deviation, objs, X[:700]), (deviation, objs + [ball], X[700:1000])]
    serial = [f(o, pts) for f, o, pts in tasks]
    monkeypatch.setattr(dv, "DEVIATION_CHUNK", 1000)
    whole = deviation(objs, X)                  # in chunks of 1000, here
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster, distributed.Client(cluster) as client:
        got = client.gather([client.submit(f, o, pts) for f, o, pts in tasks])
        parts = client.gather(client.map(deviation, [objs] * 3, [X[s:s + 1000] for s in range(0, 3000, 1000)]))
        assert len(client.scheduler_info()["workers"]) == 2
    for a, b in zip(serial, got):
        assert_same(a, b)
    np.testing.assert_array_equal(np.concatenate([p.distances for p in parts]), whole.distances)
    np.testing.assert_array_equal(np.concatenate([p.feet for p in parts]), whole.feet)
    np.testing.assert_array_equal(np.concatenate([p.owner for p in parts]), whole.owner)
