"""The broad phase of intersections (issue 14, memory): box_pairs by a sweep equals the
all-pairs test, and self_intersections of a long curve no longer forms every pair of its
pieces (a 1e4-pole curve needed over 23 GB and was killed; 1e5 poles asked for 37 GiB)."""
import tracemalloc

import numpy as np

import cagd
from cagd.queries import _subdivision as sd


def all_pairs(a, b, tol):
    lo_a, hi_a = sd.boxes(a.ctrl)
    lo_b, hi_b = sd.boxes(b.ctrl)
    gap = np.maximum(0.0, np.maximum(lo_a[:, None] - hi_b[None], lo_b[None] - hi_a[:, None]))
    return np.nonzero(np.einsum("ijd,ijd->ij", gap, gap) <= tol * tol)


def test_sweep_equals_all_pairs():
    rng = np.random.default_rng(3)
    for n, m, tol in [(1, 1, 0.0), (40, 70, 1e-3), (300, 200, 0.05), (500, 500, 0.0)]:
        a = sd.Geometry(cagd.BSplineCurve(np.cumsum(rng.normal(0, 1, (n + 3, 3)), axis=0), 3), "a").pieces
        b = sd.Geometry(cagd.BSplineCurve(np.cumsum(rng.normal(0, 1, (m + 3, 3)), axis=0), 3), "b").pieces
        i, j = sd.box_pairs(a, b, tol, chunk=997)
        I, J = all_pairs(a, b, tol)
        assert np.array_equal(i, I) and np.array_equal(j, J)


def test_self_intersections_of_a_long_curve_stay_small():
    rng = np.random.default_rng(0)
    c = cagd.BSplineCurve(np.cumsum(rng.normal(0, 1, (5000, 3)), axis=0), 3)
    tracemalloc.start()
    res = cagd.self_intersections(c)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 400e6, peak                     # all pairs of its 4997 pieces: about 2.4 GB
    assert res.converged or "open" in res.message
