"""The coincidence test of the surface–surface seed subdivision
(cagd.queries._surface_overlaps.lying_on): a piece lies on the other surface when all
5 x 5 of its samples project within tol. The centres are projected first and the other
samples only where the centre is on the surface (issue 16: nearly parallel neighbours
are tested at every level and almost never lie on each other)."""
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd.queries import _subdivision as sd, _surface_overlaps as so


def _reference(G, H, lo, hi, lo_h, hi_h, tol):
    """The test on all 25 samples at once (the formula before issue 16)."""
    M, n2 = len(lo), so._N * so._N
    x = so._grid(lo, hi).reshape(-1, 2)
    seed = so.grid_seeds(H, G.points(x), np.repeat(lo_h, n2, axis=0), np.repeat(hi_h, n2, axis=0))
    d, y = so.distances(G, H, None, x, seed)
    return np.all(d.reshape(M, -1) <= tol, axis=1), y.reshape(M, n2, 2)[:, n2 // 2]


@pytest.fixture
def projected(monkeypatch):
    """The number of points projected by every so.distances call from now on."""
    rows = []
    real = so.distances

    def spy(G, H, pl, x, seed):
        rows.append(len(x))
        return real(G, H, pl, x, seed)

    monkeypatch.setattr(so, "distances", spy)
    return rows


def _pieces(gap):
    """Pieces of a bumpy bicubic and of the same surface shifted by ``gap`` along z
    (gap 0: the surface itself), paired piece by piece."""
    rng = np.random.default_rng(7)
    net = np.stack(np.meshgrid(np.linspace(0, 1, 7), np.linspace(0, 1, 7), indexing="ij"), -1)
    net = np.concatenate([net, 0.1 * rng.standard_normal((7, 7, 1))], -1)
    a = cagd.BSplineSurface(net, 3, 3)
    b = cagd.BSplineSurface(net + [0, 0, gap], 3, 3)
    G, H = sd.Geometry(a, "a"), sd.Geometry(b, "b")
    pa = sd.split(G.pieces)[0]
    pb = sd.split(H.pieces)[0]
    return G, H, pa, pb


@pytest.mark.parametrize("gap", [0.0, 5e-10, 1e-6, 1e-3])
def test_lying_on_is_the_all_samples_test(gap, projected):
    """The same mask and centre feet as the 25-sample test; pieces off the surface cost
    one projection (their centre), pieces on it 25."""
    G, H, pa, pb = _pieces(gap)
    tol = 1e-9
    ok, mid = so.lying_on(G, H, None, pa.lo, pa.hi, pb.lo, pb.hi, tol)
    assert sum(projected) == len(pa.lo) + 24 * int(ok.sum())
    ref_ok, ref_mid = _reference(G, H, pa.lo, pa.hi, pb.lo, pb.hi, tol)
    assert np.array_equal(ok, ref_ok) and ok.all() == (gap <= tol)
    # the same feet, up to rounding: projected in other batches (1.5e-12 seen)
    assert np.allclose(mid, ref_mid, rtol=0.0, atol=1e-10)


@pytest.mark.parametrize("gap", [0.0, 5e-10, 1e-6, 1e-3, 1e-2])
def test_lying_on_with_the_hulls_is_the_same_test(gap, projected):
    """Given the other pieces' control nets, a centre farther than tol from its piece's
    hull is off without a projection: the same mask, the same centre feet where on,
    one projection fewer per rejected centre, and at a gap of 1e-2 (nearly) every
    centre rejected."""
    G, H, pa, pb = _pieces(gap)
    pa, pb = sd.split(pa)[0], sd.split(pb)[0]
    tol = 1e-9
    ok, mid = so.lying_on(G, H, None, pa.lo, pa.hi, pb.lo, pb.hi, tol, pb.ctrl)
    with_hulls = sum(projected)
    ref_ok, ref_mid = so.lying_on(G, H, None, pa.lo, pa.hi, pb.lo, pb.hi, tol)
    assert np.array_equal(ok, ref_ok) and ok.all() == (gap <= tol)
    assert np.allclose(mid[ok], ref_mid[ok], rtol=0.0, atol=1e-10)
    rejected = int(np.sum(sd.hull_gap(G.points(0.5 * (pa.lo + pa.hi)), pb.ctrl) > tol))
    assert with_hulls == len(pa.lo) - rejected + 24 * int(ok.sum())
    assert rejected >= (0.9 * len(pa.lo) if gap >= 1e-2 else 0)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.integers(1, 3), st.floats(1e-3, 10.0))
def test_the_hull_gap_is_a_lower_bound_of_the_distance(seed, p, q, reach):
    """hull_gap never exceeds the distance from a point to its rational Bezier piece
    (positive weights), measured by a 61 x 61 sample of the piece (no nearer than the
    true distance), and it is the height above a flat piece."""
    rng = np.random.default_rng(seed)
    P = rng.standard_normal((4, p + 1, q + 1, 3))
    w = rng.uniform(0.2, 3.0, (4, p + 1, q + 1, 1))
    ctrl = np.concatenate([P * w, w], axis=-1)
    pts = rng.standard_normal((4, 3)) * reach
    s = np.linspace(0.0, 1.0, 61)
    from math import comb
    Bu = np.array([[comb(p, i) * t ** i * (1 - t) ** (p - i) for i in range(p + 1)] for t in s])
    Bv = np.array([[comb(q, j) * t ** j * (1 - t) ** (q - j) for j in range(q + 1)] for t in s])
    H = np.einsum("ai,bj,mijd->mabd", Bu, Bv, ctrl)
    S = (H[..., :3] / H[..., 3:]).reshape(4, -1, 3)
    sampled = np.linalg.norm(S - pts[:, None], axis=-1).min(axis=1)
    gap = sd.hull_gap(pts, ctrl)
    assert np.all(gap >= 0) and np.all(gap <= sampled * (1 + 1e-12) + 1e-12)
    flat = ctrl.copy()
    flat[..., 2] = 0.0
    up = (flat[0, ..., :3] / flat[0, ..., 3:]).reshape(-1, 3).mean(axis=0)[None] + [0.0, 0.0, reach]
    assert sd.hull_gap(up, flat[:1])[0] == pytest.approx(reach, rel=1e-12)


from corpus import CAD  # noqa: E402


@pytest.mark.skipif(not CAD.is_dir(), reason="../shared/data/cad is not there")
def test_neighbours_sharing_an_edge_project_their_centres_only(projected, monkeypatch):
    """trj3_s1-al-214.stp space_ship[82] x [85] (two patches of one surface of revolution
    meeting in two edges): nearly parallel pieces along the edges were tested at each of
    ~30 levels, 25 samples each (5.6 s of the 5.8 s); no piece lies on the other patch,
    so at most one projection per tested piece (none where the centre is farther than
    tol from the other piece's control hull), and the same two exact boundary branches."""
    pytest.importorskip("OCP")
    from cagd.occ import read_step
    tested = []
    real = so.lying_on

    def spy(G, H, pl, lo, *a):
        tested.append(len(lo))
        return real(G, H, pl, lo, *a)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                 # the file has 295 unreadable entities
        by = {it.name: it.object for it in read_step(CAD / "step" / "trj3_s1-al-214.stp")}
    monkeypatch.setattr(so, "lying_on", spy)
    res = cagd.intersect(by["space_ship[82]"].untrimmed, by["space_ship[85]"].untrimmed)
    assert res.converged and len(res.curves) == 2 and res.overlaps == ()
    assert sum(tested) >= 1000                          # the test runs at many levels ...
    assert sum(projected) <= sum(tested)                # ... at most one projection a piece
