"""The coincidence test of the surface–surface seed subdivision
(cagd.queries._surface_overlaps.lying_on): a piece lies on the other surface when all
5 x 5 of its samples project within tol. The centres are projected first and the other
samples only where the centre is on the surface (issue 16: nearly parallel neighbours
are tested at every level and almost never lie on each other)."""
import warnings
from pathlib import Path

import numpy as np
import pytest

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
    assert np.array_equal(mid, ref_mid)


CAD = Path(__file__).parents[2] / ".." / "shared" / "data" / "cad"
if not CAD.is_dir():
    CAD = Path("/work/shared/data/cad")


@pytest.mark.skipif(not CAD.is_dir(), reason="../shared/data/cad is not there")
def test_neighbours_sharing_an_edge_project_their_centres_only(projected, monkeypatch):
    """trj3_s1-al-214.stp space_ship[82] x [85] (two patches of one surface of revolution
    meeting in two edges): nearly parallel pieces along the edges were tested at each of
    ~30 levels, 25 samples each (5.6 s of the 5.8 s); no piece lies on the other patch,
    so one projection per tested piece, and the same two exact boundary branches."""
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
    assert sum(projected) == sum(tested)                # ... one projection a piece
