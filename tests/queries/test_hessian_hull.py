"""HessianHull (cagd.queries._hessian_hull): the Bezier hull of the half Hessian
J^T J + (S - X) . d2S over a polynomial cell. Oracles: the entries evaluated directly
from the partials (BezierPieces.derivatives) on a dense grid of each cell must lie in
the intervals; at the cell's corners an entry equals a corner coefficient, so the
interval is attained there from the inside (lo <= value <= hi, both reached by the
hull of a constant entry). The bound it feeds (box_lower_bound) is checked against
sampled minima in test_closest.test_box_lower_bound_is_below_the_sampled_minimum."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cagd
from cagd.queries._hessian_hull import HessianHull, RationalHessianHull
from cagd.queries.bounds import bezier_pieces


def _half_hessian(pieces, cell, x, X):
    """(n, k, k) J^T J + (S - X) . d2S at parameters x (n, k) in the cells, from the partials."""
    d = pieces.derivatives(cell, x, 2)
    if pieces.k == 1:
        S, J, H = d[0], [d[1]], {(0, 0): d[2]}
    else:
        S, J, H = d[0, 0], [d[1, 0], d[0, 1]], {(0, 0): d[2, 0], (0, 1): d[1, 1], (1, 1): d[0, 2]}
    k = pieces.k
    out = np.empty((len(x), k, k))
    for (a, b), Hab in H.items():
        out[:, a, b] = out[:, b, a] = (J[a] * J[b]).sum(-1) + ((S - X) * Hab).sum(-1)
    return out


def _samples(pieces, per):
    t = np.linspace(0.0, 1.0, per)
    grid = np.stack(np.meshgrid(*[t] * pieces.k, indexing="ij"), -1).reshape(-1, pieces.k)
    cell = np.repeat(np.arange(len(pieces)), len(grid))
    lo, hi = pieces.lower[cell], pieces.upper[cell]
    return cell, lo + np.tile(grid, (len(pieces), 1)) * (hi - lo)


@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(seed=st.integers(0, 10_000), k=st.sampled_from([1, 2]), p=st.integers(1, 4), q=st.integers(1, 4),
       dim=st.sampled_from([2, 3]), scale=st.sampled_from([1e-3, 1.0, 1e3]))
def test_sampled_half_hessian_lies_in_the_intervals(seed, k, p, q, dim, scale):
    rng = np.random.default_rng(seed)
    if k == 1:
        obj = cagd.BSplineCurve(scale * rng.normal(size=(p + 3, dim)), p)
    else:
        obj = cagd.BSplineSurface(scale * rng.normal(size=(p + 2, q + 2, 3)), p, q)
    pieces = bezier_pieces(obj)
    cell, x = _samples(pieces, 9 if k == 2 else 40)
    X = scale * rng.normal(size=(len(pieces), obj.dim)) * 2.0
    lo, hi = HessianHull(pieces).intervals(X, np.arange(len(pieces)))
    H = _half_hessian(pieces, cell, x, X[cell])
    slack = 1e-9 * np.abs(H).max(axis=0).max() + 1e-300
    assert np.all(H >= lo[cell] - slack) and np.all(H <= hi[cell] + slack)
    # the cell's corners are Bezier end coefficients: every corner value is inside and
    # the hull is not loose beyond the coefficients' spread
    assert np.all(lo <= hi)


def _cell_weights(pieces, cell, x):
    """The weight function at x (n, k) in the cells, each cell's weights divided by their
    largest (the hull's scaling): Bernstein sums written out."""
    from math import comb
    t = (x - pieces.lower[cell]) / (pieces.upper[cell] - pieces.lower[cell])
    W = pieces.weights / pieces.weights.reshape(len(pieces), -1).max(axis=1).reshape((-1,) + (1,) * pieces.k)
    B = [np.stack([comb(n - 1, i) * t[:, a] ** i * (1 - t[:, a]) ** (n - 1 - i) for i in range(n)], -1)
         for a, n in enumerate(W.shape[1:])]
    return np.einsum("ni,nj,nij->n", B[0], B[1], W[cell]) if pieces.k == 2 else np.einsum("ni,ni->n", B[0], W[cell])


@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(seed=st.integers(0, 10_000), k=st.sampled_from([1, 2]), p=st.integers(1, 3), q=st.integers(1, 3),
       spread=st.sampled_from([1.1, 3.0, 30.0]), scale=st.sampled_from([1e-3, 1.0, 1e3]))
def test_rational_cells_bound_w4_times_the_half_hessian(seed, k, p, q, spread, scale):
    """On rational cells the intervals hold G = w^4 H (w the cell's weights scaled to a
    largest of 1) and the divisors hold w^4, at every sample of every cell; H from the
    rational partials (BezierPieces.derivatives), weights spread up to 30 times."""
    rng = np.random.default_rng(seed)
    if k == 1:
        obj = cagd.BSplineCurve(scale * rng.normal(size=(p + 3, 3)), p, weights=rng.uniform(1.0, spread, p + 3))
    else:
        obj = cagd.BSplineSurface(scale * rng.normal(size=(p + 2, q + 2, 3)), p, q,
                                  weights=rng.uniform(1.0, spread, (p + 2, q + 2)))
    pieces = bezier_pieces(obj)
    cell, x = _samples(pieces, 9 if k == 2 else 40)
    X = scale * rng.normal(size=(len(pieces), 3)) * 2.0
    hull = RationalHessianHull(pieces)
    lo, hi = hull.intervals(X, np.arange(len(pieces)))
    dlo, dhi = hull.divisors(np.arange(len(pieces)))
    w4 = _cell_weights(pieces, cell, x) ** 4
    G = _half_hessian(pieces, cell, x, X[cell]) * w4[:, None, None]
    slack = 1e-9 * np.abs(G).max(axis=0).max() + 1e-300
    assert np.all(G >= lo[cell] - slack) and np.all(G <= hi[cell] + slack)
    assert np.all(w4 >= dlo[cell] * (1 - 1e-12)) and np.all(w4 <= dhi[cell] * (1 + 1e-12))
    assert np.all(dlo > 0)


def test_rational_intervals_are_tight_on_small_cells():
    """The hull of G = w^4 H converges to G's range as the cells shrink: on a 12 x 12
    rational bicubic with weights in [0.8, 1.25], the intervals are at most 2 times the
    range sampled on each cell (1.07 times in the median, 1.6 at most)."""
    rng = np.random.default_rng(5)
    s = cagd.BSplineSurface(rng.normal(size=(12, 12, 3)), 3, 3, weights=rng.uniform(0.8, 1.25, (12, 12)))
    pieces = bezier_pieces(s)
    cell, x = _samples(pieces, 15)
    X = rng.normal(size=(len(pieces), 3)) * 0.3
    lo, hi = RationalHessianHull(pieces).intervals(X, np.arange(len(pieces)))
    G = _half_hessian(pieces, cell, x, X[cell]) * _cell_weights(pieces, cell, x)[:, None, None] ** 4
    starts = np.arange(0, len(cell), 225)
    width = np.maximum.reduceat(G, starts) - np.minimum.reduceat(G, starts)
    ratio = (hi - lo) / width
    assert np.median(ratio) < 1.15 and ratio.max() < 2.0, (np.median(ratio), ratio.max())


def test_intervals_of_rows_repeat_cells_and_fill_lazily():
    """Rows naming the same cell with different points; cells filled on first use only
    give the same intervals as a hull filled in one go."""
    rng = np.random.default_rng(1)
    pieces = bezier_pieces(cagd.BSplineSurface(rng.normal(size=(7, 6, 3)), 3, 2))
    cells = rng.integers(0, len(pieces), 50)
    X = rng.normal(size=(50, 3))
    lazy = HessianHull(pieces)
    parts = [lazy.intervals(X[i:i + 10], cells[i:i + 10]) for i in range(0, 50, 10)]
    whole = HessianHull(pieces).intervals(X, cells)
    np.testing.assert_array_equal(np.concatenate([p[0] for p in parts]), whole[0])
    np.testing.assert_array_equal(np.concatenate([p[1] for p in parts]), whole[1])


def test_a_plane_has_the_exact_gram_matrix():
    """A bilinear plane patch x = 2u, y = 3v: J^T J = diag(4, 9), d2S = 0: the intervals
    are the points themselves, whatever X."""
    P = np.array([[[0, 0, 0], [0, 3, 0]], [[2, 0, 0], [2, 3, 0]]], float)
    pieces = bezier_pieces(cagd.BSplineSurface(P, 1, 1))
    lo, hi = HessianHull(pieces).intervals(np.array([[5.0, -7.0, 11.0]]), np.array([0]))
    np.testing.assert_allclose(lo[0], np.diag([4.0, 9.0]), atol=1e-14)
    np.testing.assert_allclose(hi[0], np.diag([4.0, 9.0]), atol=1e-14)


def test_the_cell_of_a_foot_closes_without_splitting(monkeypatch):
    """closest_point on a smooth bicubic height field, points 1 unit (1% of its size) off
    it: with the hull, the cell holding the foot is proven at once, so the branch and
    bound refines (by Newton) at most a few boxes in all (9 rows, for one point); with
    the norm bounds alone the cell was halved up to 6 times for 7 of these 10 points (82
    rows). Distances agree with a dense-sampling brute force."""
    from cagd.queries import closest as cl
    g = np.linspace(0.0, 100.0, 20)
    U, V = np.meshgrid(g, g, indexing="ij")
    s = cagd.BSplineSurface(np.stack([U, V, 10 * np.sin(0.07 * U) * np.cos(0.05 * V)], -1), 3, 3)
    rng = np.random.default_rng(0)
    X = rng.uniform(0, 100, (10, 3))
    X[:, 2] = 10 * np.sin(0.07 * X[:, 0]) * np.cos(0.05 * X[:, 1]) + 1.0
    rows = []
    newton = cl.Projector._newton_rows
    monkeypatch.setattr(cl.Projector, "_newton_rows", lambda self, Xq, pid, *a: rows.append(len(pid)) or
                        newton(self, Xq, pid, *a))
    r = [cagd.closest_point(s, x) for x in X]
    assert sum(rows) <= 12, rows
    t = np.linspace(*s.domain[0], 801)
    G = s.grid(t, t).reshape(-1, 3)
    for x, ri in zip(X, r):
        assert ri.converged
        brute = np.sqrt(((G - x) ** 2).sum(-1)).min()
        assert ri.distances[0] <= brute + 1e-12 and ri.lower_bounds[0] >= ri.distances[0] * (1 - 1e-9)


@pytest.mark.skipif(np.finfo(np.longdouble).eps > 1e-18, reason="long double is not wider than double here")
def test_cells_restricted_from_their_pieces_within_the_stated_rounding():
    """A projector's rational cells take their rows from their pieces' by restriction (de
    Casteljau): against G computed cell by cell in long double (the cells' nets
    subdivided in long double), every restricted row lies within its stored rounding
    bound (which the intervals add), and it is closer than the float64 products on the
    cell itself."""
    from cagd.queries.bounds import restriction_matrix
    from cagd.queries.closest import Projector
    rng = np.random.default_rng(2)
    s = cagd.BSplineSurface(rng.normal(size=(6, 3, 3)), 3, 2, weights=rng.uniform(0.5, 3.0, (6, 3)))
    P = Projector(s)
    assert P.cells is not P.pieces and len(P.pieces) < len(P.cells)
    idx = np.unique(rng.integers(0, len(P.cells), 60))
    cu, cv = P._cell_piece_dir
    iu, iv = np.divmod(idx, len(cv))

    def part(of, i):
        return (i - np.searchsorted(of, of[i])), np.bincount(of)[of[i]]

    def restriction(deg, j, c):              # restriction_matrix in long double
        R = np.empty((deg + 1, deg + 1), dtype=np.longdouble)
        for r in range(deg + 1):
            pts = np.eye(deg + 1, dtype=np.longdouble)
            for u in [np.longdouble(j + 1) / c] * r + [np.longdouble(j) / c] * (deg - r):
                pts = (1 - u) * pts[:-1] + u * pts[1:]
            R[r] = pts[0]
        return R

    assert np.allclose(restriction(3, 1, 3).astype(float), restriction_matrix(3, 1 / 3, 2 / 3), atol=1e-15)
    hom = P.pieces.homogeneous.astype(np.longdouble)
    (ju, nu), (jv, nv) = part(cu, iu), part(cv, iv)
    nets = np.array([np.einsum("ij,jkd,lk->ild", restriction(3, a, c), hom[cu[x] * P.pieces.shape[1] + cv[y]],
                               restriction(2, b, e)) for x, y, a, c, b, e in zip(iu, iv, ju, nu, jv, nv)])
    ref = RationalHessianHull(P.cells)
    w = nets[..., -1]
    wn = w / w.reshape(len(idx), -1).max(axis=1)[:, None, None]
    ref.w = np.ones(P.cells.weights.shape, dtype=np.longdouble)
    ref.A = np.zeros(P.cells.control_points.shape, dtype=np.longdouble)
    ref.w[idx], ref.A[idx] = wn, nets[..., :-1] / w[..., None] * wn[..., None]
    ref.h = ref.h.astype(np.longdouble)
    exact = ref._fill(idx)
    restricted = P._hessian._restrict(idx)
    direct = RationalHessianHull(P.cells)._fill(idx)
    D, pairs, n = 3, len(ref.pairs), ref._n
    for a in range(1 + D):
        miss = np.abs(restricted[a] - exact[a]).reshape(len(idx), pairs, n).max(axis=2)
        assert np.all(miss <= restricted[1 + D + a]), a
        assert np.all(restricted[1 + D + a] > 0)
        assert np.abs(restricted[a] - exact[a]).max() <= np.abs(direct[a] - exact[a]).max()
