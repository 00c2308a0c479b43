"""rebuild (issue 17): a curve or surface refitted to a chosen size, with the deviation
measured. Oracles: the original's own size gives it back (the least squares reproduces a
spline in its space), brute force (KD-tree on dense samples of the result) for the
reported deviation, the h^(p+1) convergence of a cubic rebuild of a circle."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import cagd
from cagd import BSplineCurve, BSplineSurface, CagdError, rebuild

W = np.sqrt(0.5)
ARC = BSplineCurve([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], 2, [0, 0, 0, .5, .5, 1, 1, 1], [1, W, 1, W, 1])


def test_rebuild_to_the_original_size_is_the_identity():
    rng = np.random.default_rng(2)
    c = BSplineCurve(rng.random((12, 3)), 3, [0, 0, 0, 0, .1, .15, .3, .5, .6, .7, .8, .95, 1, 1, 1, 1])
    r = rebuild(c, 12, 3)
    assert np.abs(r.result.control_points - c.control_points).max() <= 1e-12 and r.deviation <= 1e-12
    S = BSplineSurface(rng.random((6, 5, 3)), 3, 2)
    r = rebuild(S, (6, 5), (3, 2))
    assert np.abs(r.result.control_points - S.control_points).max() <= 1e-12 and r.deviation <= 1e-12


def test_deviation_is_what_brute_force_measures():
    r = rebuild(ARC, 8, 3)
    t = np.linspace(0, 1, 2001)
    dense = r.result(np.linspace(0, 1, 400_001))
    chord = float(np.sqrt((np.diff(dense, axis=0) ** 2).sum(-1)).max())
    brute, _ = cKDTree(dense).query(ARC(t))
    assert r.deviation <= float(brute.max()) + 1e-12           # samples: brute is an upper bound
    assert float(brute.max()) <= r.deviation * 1.05 + chord    # and the deviation is not far below it
    assert r.result.degree == 3 and len(r.result.control_points) == 8
    assert r.result.domain == ARC.domain and not r.result.is_rational


def test_cubic_rebuild_of_a_circle_converges_like_h4():
    devs = [rebuild(ARC, n, 3).deviation for n in (8, 16, 32)]
    assert devs[0] > devs[1] > devs[2]
    assert devs[1] / devs[2] > 10.0                 # about 2^4 per halving of the spans


def test_surface_rebuild_of_a_sphere():
    r = rebuild(cagd.sphere(2.0), (16, 16), (3, 3))
    u, v = np.linspace(0, 1, 60), np.linspace(0, 1, 60)
    radius = np.sqrt((r.result.grid(u, v) ** 2).sum(-1))
    assert np.abs(radius - 2.0).max() <= r.deviation * 1.5 + 1e-12
    assert r.deviation < 0.01
    assert r.result.control_points.shape == (16, 16, 3)


@pytest.mark.parametrize("args, word", [
    ((ARC, 2, 3), "count"),
    ((ARC, 5, 0), "degree"),
    ((ARC, 5.5, 3), "count"),
    ((cagd.sphere(1.0), (3, 8, 1), 3), "count"),
    (("curve", 5, 3), "obj"),
])
def test_bad_input(args, word):
    with pytest.raises(CagdError, match=word):
        rebuild(*args)


def test_high_degree_identity_and_count_cap():
    c = BSplineCurve(np.random.default_rng(1).random((21, 3)), 20)
    assert rebuild(c, 21, 20).deviation <= 1e-10
    with pytest.raises(CagdError, match="count"):
        rebuild(ARC, 10 ** 6, 3)
