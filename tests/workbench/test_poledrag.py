"""The pole editor's drag geometry (workbench/cagdwb/poledrag.py) without FreeCAD: it is
numpy only. Oracles: brute force for the pick, the defining properties of a ray-plane
intersection and of the closest points of two lines, the normal of an affine grid."""
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from wb_runner import ADDON

sys.path.insert(0, str(ADDON))
from cagdwb import poledrag  # noqa: E402

from cagd import CagdError  # noqa: E402

coords = st.floats(-100, 100, allow_nan=False, allow_infinity=False)
vec3 = arrays(np.float64, 3, elements=coords)
unitish = vec3.filter(lambda v: np.linalg.norm(v) > 1e-2)


@settings(deadline=None, max_examples=60)
@given(arrays(np.float64, st.tuples(st.integers(1, 30), st.just(3)), elements=coords), vec3, unitish,
       st.floats(1e-3, 50))
def test_pick_is_the_nearest_within_tol(points, origin, direction, tol):
    u = direction / np.linalg.norm(direction)
    brute = [(np.linalg.norm(p - origin - ((p - origin) @ u) * u), (p - origin) @ u, i) for i, p in enumerate(points)]
    inside = sorted(b for b in brute if b[0] <= tol)
    got = poledrag.pick_pole(points, origin, direction, tol)
    if not inside:
        assert got is None
    else:
        d = np.linalg.norm(points[got] - origin - ((points[got] - origin) @ u) * u)
        assert got is not None and d <= inside[0][0] + 1e-9 * (1 + np.abs(points).max())


@settings(deadline=None, max_examples=60)
@given(vec3, unitish, vec3, unitish)
def test_drag_in_plane_is_on_plane_and_ray(anchor, normal, origin, direction):
    n, d = normal / np.linalg.norm(normal), direction / np.linalg.norm(direction)
    if abs(n @ d) < 1e-3:
        return
    q = poledrag.drag_in_plane(anchor, normal, origin, direction)
    scale = 1e-9 * (1 + np.abs(q).max() + np.abs(anchor).max() + np.abs(origin).max())
    assert abs((q - anchor) @ n) <= scale
    assert np.linalg.norm(np.cross(q - origin, d)) <= scale


@settings(deadline=None, max_examples=60)
@given(vec3, unitish, vec3, unitish)
def test_drag_along_gives_the_closest_points(anchor, axis, origin, direction):
    u, d = axis / np.linalg.norm(axis), direction / np.linalg.norm(direction)
    if 1 - (u @ d) ** 2 < 1e-4:
        return
    q = poledrag.drag_along(anchor, axis, origin, direction)
    foot = origin + ((q - origin) @ d) * d
    scale = 1e-8 * (1 + np.abs(q).max() + np.abs(anchor).max() + np.abs(origin).max()) / (1 - (u @ d) ** 2)
    assert np.linalg.norm(np.cross(q - anchor, u)) <= scale
    assert abs((q - foot) @ u) <= scale and abs((q - foot) @ d) <= scale


def test_parallel_rays_are_refused():
    with pytest.raises(CagdError, match="axis"):
        poledrag.drag_along([0, 0, 0], [0, 0, 1], [3, 1, 0], [0, 0, -2])
    with pytest.raises(CagdError, match="direction"):
        poledrag.drag_in_plane([0, 0, 0], [0, 0, 1], [3, 1, 5], [1, 2, 0])


@settings(deadline=None, max_examples=40)
@given(arrays(np.float64, (3, 3), elements=st.floats(-5, 5)), vec3)
def test_net_normals_of_an_affine_grid(A, shift):
    i, j = np.meshgrid(np.arange(4.0), np.arange(5.0), indexing="ij")
    grid = np.stack([i, j, np.zeros_like(i)], -1) @ A.T + shift
    n = np.cross(A[:, 0], A[:, 1])
    if np.linalg.norm(n) < 1e-3:
        return
    N = poledrag.net_normals(grid)
    assert np.abs(N - n / np.linalg.norm(n)).max() <= 1e-9


def test_bad_input_names_the_argument():
    with pytest.raises(CagdError, match="tol"):
        poledrag.pick_pole([[0, 0, 0]], [0, 0, 1], [0, 0, -1], 0.0)
    with pytest.raises(CagdError, match="direction"):
        poledrag.pick_pole([[0, 0, 0]], [0, 0, 1], [0, 0, 0], 1.0)
    with pytest.raises(CagdError, match="origin"):
        poledrag.drag_in_plane([0, 0, 0], [0, 0, 1], [0, np.nan, 1], [0, 0, 1])
    with pytest.raises(CagdError, match="grid"):
        poledrag.net_normals(np.zeros((1, 4, 3)))



@settings(deadline=None, max_examples=60)
@given(vec3, st.floats(1e-3, 20), st.sampled_from([None, "X", "Y", "Z"]))
def test_snap_rounds_to_the_grid(p, step, name):
    """Every coordinate (no axis) or only the axis' coordinate lands on a multiple of
    step, within half a step of where it was; the others are untouched."""
    axis = poledrag.AXES["View plane" if name is None else name]
    q = poledrag.snapped(p, step, axis)
    moved = np.ones(3, bool) if axis is None else np.abs(np.array(axis)) == 1.0
    ratio = q[moved] / step
    assert np.abs(ratio - np.round(ratio)).max() <= 1e-9 * (1 + np.abs(ratio).max())
    assert np.abs(q - p)[moved].max() <= 0.5 * step * (1 + 1e-12)
    assert np.array_equal(q[~moved], p[~moved])


def test_snap_bad_input():
    assert np.array_equal(poledrag.snapped([1.2, 3.4, 5.6], 0.0), [1.2, 3.4, 5.6])
    with pytest.raises(CagdError, match="step"):
        poledrag.snapped([0, 0, 0], -1.0)
    with pytest.raises(CagdError, match="coordinate axis"):
        poledrag.snapped([0, 0, 0], 1.0, (1.0, 1.0, 0.0))
