"""The bad-input contract of the queries (issue 14), property-based: closest_point,
deviation, min_distance and intersect on objects moved far from the origin, scaled from
1e-300 to 1e300, with hostile points and tolerances, answer correctly or raise CagdError.

"Correctly": a foot point is the object's point at the returned parameters, its
distance is no larger than the distance to any of a grid of the object's points (the
brute-force oracle) and no smaller than the certified lower bound; min_distance is no
larger than the closest pair of two sample grids."""
from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cagd
from contract import call
from hostile import OFFSETS, SCALES, point_arrays, tolerances

QUERIES = settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
#: slack of a comparison with the brute-force grid, relative to the object's size
GRID_SLACK = 1e-9
#: and in units of the coordinates' rounding (an object 0.8 across at 1e12 has points only to 1.2e-4)
ULPS = 8

OBJECTS = {
    "sphere": lambda: cagd.sphere(1.0),
    "bezier patch": lambda: cagd.BezierSurface(np.random.default_rng(3).random((4, 4, 3))),
    "rational patch": lambda: cagd.BSplineSurface(np.random.default_rng(4).random((3, 3, 3)), 2, 2,
                                                  weights=[[1, 1e-9, 1], [1, 1, 1], [1, 1, 1]]),
    "curve": lambda: cagd.BSplineCurve(np.random.default_rng(5).random((7, 3)), 3),
    "tiny spans": lambda: cagd.BSplineCurve(np.random.default_rng(6).random((5, 3)), 3,
                                            knots=[0, 0, 0, 0, 1e-300, 1, 1, 1, 1]),
}


def _moved(obj, scale: float, offset: float):
    dim = obj.dim
    return obj.transformed(np.eye(dim) * scale, np.full(dim, offset))


def _grid(obj, count: int = 41) -> np.ndarray:
    if isinstance(obj, cagd.Curve):
        a, b = obj.domain
        return obj(np.linspace(a, b, count * 4))
    (a, b), (c, d) = obj.domain
    return obj(np.linspace(a, b, count)[:, None], np.linspace(c, d, count)[None, :]).reshape(-1, obj.dim)


def _distances(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a_i - b_j| for all pairs, each in a unit of its own difference's size (a plain
    norm underflows at 1e-300 and overflows at 1e155; one unit for all pairs underflowed
    a point at 1e123 beside one at 1e300)."""
    d = a[:, None, :] - b[None, :, :]
    unit = np.maximum(np.abs(d).max(axis=-1, initial=0.0), 1e-300)
    return np.linalg.norm(d / unit[..., None], axis=-1) * unit


def _size(obj) -> float:
    pts = _grid(obj, 9)
    return float(np.ptp(pts, axis=0).max())


@QUERIES
@given(name=st.sampled_from(sorted(OBJECTS)), scale=SCALES, offset=OFFSETS, seed=st.integers(0, 2 ** 16),
       spread=st.sampled_from([1e-6, 0.01, 1.0, 100.0, 1e155]), tol=tolerances)
def test_closest_point(name, scale, offset, seed, spread, tol):
    made = call(_moved, OBJECTS[name](), scale, offset)
    if not made.ok:
        return
    obj = made.value
    grid = _grid(obj)
    if not np.all(np.isfinite(grid)):
        return
    size = _size(obj)
    slack = GRID_SLACK * size + ULPS * np.finfo(float).eps * float(np.abs(grid).max())
    rng = np.random.default_rng(seed)
    points = grid[rng.integers(0, len(grid), 20)] + rng.normal(size=(20, 3)) * spread * max(size, 1e-300)
    out = call(cagd.closest_point, obj, points, tol=tol) if tol is not None else call(cagd.closest_point, obj, points)
    if not out.ok:
        return
    r = out.value
    brute = _distances(points, grid).min(axis=1)
    assert np.all(np.isfinite(r.distances)), "a finite point got a non-finite distance"
    assert np.all(r.distances <= brute + slack + GRID_SLACK * brute), "farther than a grid point"
    assert np.all(r.lower_bounds <= r.distances * (1 + 1e-12) + 1e-300)
    on = obj(*np.moveaxis(r.params, -1, 0)) if not isinstance(obj, cagd.Curve) else obj(r.params)
    assert np.allclose(on, r.feet, rtol=0, atol=slack)


@QUERIES
@given(points=point_arrays(min_count=0, max_count=6, dims=(0, 1, 2, 3, 4)), tol=tolerances)
def test_closest_point_and_deviation_with_hostile_points(points, tol):
    for fn in (cagd.closest_point, cagd.deviation):
        out = call(fn, cagd.sphere(1.0), points, tol=tol) if tol is not None else call(fn, cagd.sphere(1.0), points)
        if out.ok and fn is cagd.closest_point:
            P = np.asarray(points, dtype=float).reshape(-1, 3)
            expected = np.abs(_distances(P, np.zeros((1, 3)))[:, 0] - 1.0)   # the sphere's closed form
            assert np.allclose(out.value.distances, expected, rtol=1e-9, atol=1e-9)


@QUERIES
@given(scale=SCALES, offset=OFFSETS, gap=st.sampled_from([0.0, 1e-9, 0.5, 3.0, 1e155]),
       pair=st.sampled_from([("sphere", "sphere"), ("sphere", "bezier patch"), ("curve", "sphere"),
                             ("curve", "curve")]))
def test_min_distance(scale, offset, gap, pair):
    a = call(_moved, OBJECTS[pair[0]](), scale, offset)
    b = call(_moved, OBJECTS[pair[1]](), scale, offset + gap * scale)
    if not (a.ok and b.ok):
        return
    ga, gb = _grid(a.value, 21), _grid(b.value, 21)
    if not (np.all(np.isfinite(ga)) and np.all(np.isfinite(gb))):
        return
    out = call(cagd.min_distance, a.value, b.value)
    if out.ok:
        r = out.value
        brute = float(_distances(ga, gb).min())
        size = max(_size(a.value), _size(b.value))
        rounding = ULPS * np.finfo(float).eps * max(float(np.abs(ga).max()), float(np.abs(gb).max()))
        assert np.isfinite(r.distance)
        assert r.distance <= brute + GRID_SLACK * max(size, brute) + rounding
        assert r.lower_bound <= r.distance * (1 + 1e-12) + 1e-300


@QUERIES
@given(tol=tolerances, scale=SCALES, kind=st.sampled_from(["sphere-plane", "sphere-sphere", "flat-flat"]))
def test_intersect(tol, scale, kind):
    """A sphere cut through its centre gives one circle of radius r; a surface against
    itself is one overlap, at any tol small against the objects (a tol larger than the
    sphere makes all of it one contact)."""
    s = cagd.sphere(scale)
    flat = cagd.BezierSurface(np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]], float) * scale)
    a, b = {"sphere-plane": (s, cagd.plane((0, 0, 0), (0, 0, 1))), "sphere-sphere": (s, s),
            "flat-flat": (flat, flat)}[kind]
    out = call(cagd.intersect, a, b, tol=tol) if tol is not None else call(cagd.intersect, a, b)
    if not out.ok:
        return
    r = out.value
    if (1e-9 if tol is None else float(tol)) > 1e-3 * scale:
        return
    if kind == "sphere-plane" and r.converged:
        assert len(r.curves) == 1 and not r.overlaps
    elif kind != "sphere-plane" and r.converged:
        assert len(r.overlaps) >= 1 and len(r.points) == 0, (len(r.points), len(r.overlaps))
