"""closest_point on hard inputs with bounded work (issue 14, big queries): the hierarchy of
cells against an all-pairs search, the caps on candidates and on branch-and-bound pairs
keep the certificate (lower_bounds <= the true distance, checked against brute force:
dense sampling + scipy refinement), random nets with points near and 10-100x the size
away, and the fine projector of large surface queries against the default one."""
import numpy as np
import pytest

import cagd
import cagd.queries.closest as cl
from cagd.queries.closest import Projector, closest_point
from cagd.surfaces.base import Surface

REL = 1e-9          # distances within REL * size of brute force (and never below it beyond it)


def brute_surface(s, X, n=160):
    """Dense sampling on an n x n grid, then L-BFGS-B from the 4 nearest samples."""
    from scipy.optimize import minimize
    (u0, u1), (v0, v1) = s.domain
    us, vs = np.linspace(u0, u1, n), np.linspace(v0, v1, n)
    G = s.grid(us, vs).reshape(-1, 3)
    out = []
    for x in X:
        d = np.linalg.norm(G - x, axis=1)
        best = d.min()
        for i in np.argsort(d)[:4]:
            res = minimize(lambda p: np.sum((s(p[0], p[1]) - x) ** 2), [us[i // n], vs[i % n]], method="L-BFGS-B",
                           bounds=[(u0, u1), (v0, v1)], options={"ftol": 1e-15, "gtol": 1e-12})
            best = min(best, float(np.sqrt(res.fun)))
        out.append(best)
    return np.array(out)


def brute_curve(c, X, samples=20000):
    """Dense sampling, then bounded Brent from the 4 nearest samples."""
    from scipy.optimize import minimize_scalar
    a, b = c.domain
    t = np.linspace(a, b, samples)
    P = c(t)
    out = []
    for x in X:
        d = np.linalg.norm(P - x, axis=1)
        best = d.min()
        for i in np.argsort(d)[:4]:
            lo, hi = t[max(i - 1, 0)], t[min(i + 1, samples - 1)]
            res = minimize_scalar(lambda s: np.linalg.norm(c(s) - x), bounds=(lo, hi), method="bounded",
                                  options={"xatol": 1e-13})
            best = min(best, float(res.fun))
        out.append(best)
    return np.array(out)


def random_net(n, seed):
    return cagd.BSplineSurface(np.random.default_rng(seed).uniform(-1, 1, (n, n, 3)), 3, 3)


def _points(obj, rng, count, far):
    """Points near the object (on it plus noise of 1% of its size) and, with ``far``, as many
    at 10 to 100 times its size in random directions."""
    if isinstance(obj, Surface):
        uv = rng.uniform(0, 1, (count, 2))
        (u0, u1), (v0, v1) = obj.domain
        base = obj(u0 + uv[:, 0] * (u1 - u0), v0 + uv[:, 1] * (v1 - v0))
    else:
        a, b = obj.domain
        base = obj(rng.uniform(a, b, count))
    size = float(np.ptp(base, axis=0).max())
    X = base + rng.uniform(-0.01, 0.01, base.shape) * size
    if far:
        u = rng.normal(size=base.shape)
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        X = np.vstack([X, u * size * rng.uniform(10, 100, (count, 1))])
    return X, size


# --- the hierarchy against all pairs ----------------------------------------------------------------
@pytest.mark.parametrize("direct", [0, 10 ** 9])
@pytest.mark.parametrize("which", ["net", "curve", "sphere"])
def test_tree_candidates_are_every_cell_below_the_threshold(which, direct, monkeypatch):
    """_tree_pairs returns exactly the cells whose bound (both hull spheres, the hull box) is
    below the threshold, found by an all-pairs search, and their bounds; the bound of the
    cells left out is the threshold. nearest=True gives a midpoint at the least distance.
    Both ways: down the hierarchy, and every pair formed directly (few points and cells)."""
    monkeypatch.setattr(cl, "DIRECT_PAIRS", direct)
    rng = np.random.default_rng(1)
    obj = {"net": random_net(9, 2), "curve": cagd.BSplineCurve(rng.uniform(-1, 1, (60, 3)), 3),
           "sphere": cagd.sphere(1.0)}[which]
    p = Projector(obj)
    X = rng.uniform(-3, 3, (40, 3))
    m = len(p.cells)
    cells = np.arange(m)
    allb = np.stack([p._cell_bounds(X, np.full(m, i), cells) for i in range(len(X))])   # (N, m)
    t = np.quantile(allb, 0.1, axis=1) + 1e-3       # about a tenth of the cells per point
    pid, cell, lb, rest = p._tree_pairs(X, t, False)
    got = np.zeros((len(X), m), dtype=bool)
    got[pid, cell] = True
    assert np.array_equal(got, allb < t[:, None])
    np.testing.assert_allclose(lb, allb[pid, cell], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(rest, t)
    seed = p._tree_pairs(X, np.full(len(X), np.inf), True)[1]
    dm = np.linalg.norm(X[:, None, :] - p.mid_points[None], axis=2)
    np.testing.assert_allclose(dm[np.arange(len(X)), seed], dm.min(axis=1), rtol=0, atol=1e-15)


def test_tree_cap_bounds_the_cells_left_out(monkeypatch):
    """With at most K nodes per point, the cells not returned are still bounded by rest: rest
    is at most the smallest all-pairs bound of any cell left out."""
    monkeypatch.setattr(cl, "CANDIDATES", 8)
    monkeypatch.setattr(cl, "PAIR_BUDGET", 8.0)
    rng = np.random.default_rng(3)
    p = Projector(random_net(12, 4))
    X = rng.uniform(-1, 1, (30, 3))
    m = len(p.cells)
    cells = np.arange(m)
    allb = np.stack([p._cell_bounds(X, np.full(m, i), cells) for i in range(len(X))])
    t = np.full(len(X), 10.0)                        # every cell qualifies: the cap binds
    pid, cell, lb, rest = p._tree_pairs(X, t, False)
    assert np.bincount(pid, minlength=len(X)).max() <= 8
    got = np.zeros((len(X), m), dtype=bool)
    got[pid, cell] = True
    left = np.where(got, np.inf, allb).min(axis=1)
    assert np.all(rest <= left + 1e-15)
    away = left > 0
    assert np.median(rest[away] / left[away]) > 0.5    # not vacuous: near the bound of what was left out


# --- certificates against brute force ------------------------------------------------------------
@pytest.mark.parametrize("n, seed", [(6, 0), (10, 1), (16, 2)])
def test_random_nets_near_and_far(n, seed):
    """Random bicubic nets (crumpled surfaces: every cell's hull overlaps many others), points
    near the surface and 10-100x its size away: distances <= brute force + 1e-9 relative,
    lower_bounds <= distances and <= brute force."""
    s = random_net(n, seed)
    rng = np.random.default_rng(10 + seed)
    X, size = _points(s, rng, 15, far=True)
    r = closest_point(s, X)
    brute = brute_surface(s, X)
    scale = np.maximum(size, brute)                 # far points: relative to their distance
    assert np.all(r.distances <= brute + REL * scale)
    assert np.all(r.lower_bounds <= r.distances)
    assert np.all(r.lower_bounds <= brute + REL * scale)
    # the feet are points of the surface at the reported distances
    np.testing.assert_allclose(np.linalg.norm(r.feet - X, axis=1), r.distances, rtol=1e-12, atol=1e-12 * size)
    near = slice(0, 15)
    assert np.median(r.lower_bounds[near] / np.maximum(r.distances[near], 1e-300)) > 0.5   # not vacuous


@pytest.mark.parametrize("seed", [0, 1])
def test_random_curves_near_and_far(seed):
    rng = np.random.default_rng(seed)
    c = cagd.BSplineCurve(rng.uniform(-1, 1, (200, 3)), 3)
    X, size = _points(c, rng, 20, far=True)
    r = closest_point(c, X)
    brute = brute_curve(c, X)
    scale = np.maximum(size, brute)
    assert np.all(r.distances <= brute + REL * scale)
    assert np.all(r.lower_bounds <= r.distances) and np.all(r.lower_bounds <= brute + REL * scale)


def test_caps_keep_the_certificate(monkeypatch):
    """Tiny caps (4 candidates per point, a branch budget of 2 pairs per point) make the search
    give up early: the distances are still distances to points of the object (>= the true
    minimum) and lower_bounds still hold (<= the true minimum); with the default caps the
    same points are solved."""
    s = random_net(12, 5)
    rng = np.random.default_rng(6)
    X, size = _points(s, rng, 12, far=False)
    X = np.vstack([X, rng.uniform(-1, 1, (12, 3))])
    brute = brute_surface(s, X)
    full = Projector(s).closest(X)
    assert np.all(full.distances <= brute + REL * size)
    monkeypatch.setattr(cl, "CANDIDATES", 4)
    monkeypatch.setattr(cl, "PAIR_BUDGET", 4.0)
    monkeypatch.setattr(cl, "BRANCH_PER_POINT", 2)
    monkeypatch.setattr(cl, "BRANCH_PER_CELL", 0)
    capped = Projector(s).closest(X)
    assert np.all(capped.distances >= brute - REL * size)
    assert np.all(capped.lower_bounds <= brute + REL * size)
    assert np.all(capped.lower_bounds <= capped.distances)
    assert np.any(capped.distances - capped.lower_bounds > full.distances - full.lower_bounds + 1e-6)  # caps bound


def test_large_query_uses_the_fine_projector(monkeypatch):
    """From FINE_POINTS points a surface query runs on a Projector with >= FINE_CELLS cells
    (cached apart): the sphere's distances are the analytic ones and the bounds hold, as with
    the default projector."""
    monkeypatch.setattr(cl, "FINE_POINTS", 100)
    S = cagd.sphere(1.0)
    X = np.random.default_rng(7).uniform(-2, 2, (300, 3))
    small = closest_point(S, X[:50])
    big = closest_point(S, X)
    assert len(cl._CACHE[S][2].cells) >= cl.FINE_CELLS > len(cl._CACHE[S][min(cl._CACHE[S])].cells)
    exact = np.abs(np.linalg.norm(X, axis=1) - 1.0)
    np.testing.assert_allclose(big.distances, exact, atol=1e-12)
    np.testing.assert_allclose(small.distances, exact[:50], atol=1e-12)
    assert np.all(big.lower_bounds <= big.distances)
    np.testing.assert_allclose(big.lower_bounds, big.distances, atol=1e-9)


def test_sphere_far_points_through_the_hierarchy():
    """Points 10 to 1e4 radii away (none served by the voxel grid): analytic distances,
    tight bounds."""
    rng = np.random.default_rng(8)
    u = rng.normal(size=(200, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    X = u * rng.uniform(10, 1e4, (200, 1))
    p = Projector(cagd.sphere(1.0))
    assert not np.any((p._voxels(X).length > 0))
    r = p.closest(X)
    exact = np.linalg.norm(X, axis=1) - 1.0
    np.testing.assert_allclose(r.distances, exact, rtol=1e-13)
    assert np.all(r.lower_bounds <= r.distances) and np.all(r.distances - r.lower_bounds <= 1e-9 * exact)


def test_points_whose_candidates_were_cut_are_solved_again(monkeypatch):
    """A point near the centre of a sphere meets most of its cells; when its candidate list is cut (here
    at 32 cells of 288), the point is solved again in a small group that keeps every cell,
    so its certificate is as tight as without caps (without that second pass, its lower
    bound stays loose); the points outside (about 8 candidates each) are not cut."""
    monkeypatch.setattr(cl, "CANDIDATES", 32)
    monkeypatch.setattr(cl, "PAIR_BUDGET", 32.0 * 40)
    rng = np.random.default_rng(9)
    u = rng.normal(size=(40, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    X = u * np.r_[rng.uniform(0.1, 0.15, 2), rng.uniform(1.3, 1.6, 38)][:, None]
    exact = np.abs(np.linalg.norm(X, axis=1) - 1.0)
    r = Projector(cagd.sphere(1.0)).closest(X)
    np.testing.assert_allclose(r.distances, exact, atol=1e-12)
    assert np.all(r.lower_bounds <= r.distances) and np.all(r.distances - r.lower_bounds <= 1e-9)
    monkeypatch.setattr(cl, "_merge", lambda res, rows, sub: res)
    loose = Projector(cagd.sphere(1.0)).closest(X)
    assert np.all(loose.lower_bounds <= loose.distances)
    assert (loose.distances - loose.lower_bounds)[:2].min() > 1e-6          # the cut did bind
