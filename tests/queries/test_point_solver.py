"""The curve–surface subdivision of cagd.queries._point_solver on a curve running close
to a surface and nearly parallel to it (issue 16: a fillet's edge 1e-5 off its nearly
tangent neighbour, occ22470.igs SOLID[2] x [3], kept the boxes of its pairs overlapping
down to pieces 1e-5 long and ran into max_pairs)."""
import numpy as np
import pytest

import cagd
from cagd.queries import _subdivision as sd, closest_point, intersect

# a quarter-turned frame: the pieces' axis-aligned boxes are not tight
ROT = np.linalg.qr(np.array([[0.8, 0.3, 0.5], [-0.4, 0.9, 0.2], [0.1, -0.2, 0.97]]))[0]


def _surface():
    """z = 0.1 x^2 on [0, 1]^2 (quadratic in x, linear in y), turned by ROT."""
    net = np.array([[[x, y, z] for y in (0.0, 1.0)] for x, z in ((0.0, 0.0), (0.5, 0.0), (1.0, 0.1))])
    return cagd.BezierSurface(net @ ROT.T)


def _line(z0, z1):
    """The line x = 0.5 from y = -0.2 (height z0) to y = 1.2 (height z1), turned by ROT;
    the surface is at height 0.025 under it."""
    return cagd.BezierCurve(np.array([[0.5, -0.2, z0], [0.5, 1.2, z1]]) @ ROT.T)


@pytest.fixture
def pairs_split(monkeypatch):
    """The number of pairs made by every split_pairs call from now on."""
    made = []
    real = sd.split_pairs

    def spy(*a, **kw):
        out = real(*a, **kw)
        made.append(len(out[2]))
        return out

    monkeypatch.setattr(sd, "split_pairs", spy)
    return made


@pytest.mark.parametrize("gap", [1e-5, 1e-7])
def test_a_line_along_a_surface_is_parted_by_the_slab(gap, pairs_split):
    """A line parallel to the rulings, gap above the surface (closed form: no common
    point for gap > tol): converged with no point, after a few hundred pairs; the boxes
    alone kept 3,363 pairs open at max_pairs."""
    res = intersect(_line(0.025 + gap, 0.025 + gap), _surface(), tol=1e-9)
    assert res.converged and res.points == () and res.overlaps == ()
    assert sum(pairs_split) <= 2000


def test_a_line_crossing_a_surface_at_a_shallow_angle_keeps_its_point():
    """The line rises from 1e-3 under to 1e-3 over the surface: the slab parts no pair
    holding the crossing, found at its middle (y = 0.5, closed form), converged."""
    res = intersect(_line(0.025 - 1e-3, 0.025 + 1e-3), _surface(), tol=1e-9)
    assert res.converged and len(res.points) == 1
    expected = np.array([0.5, 0.5, 0.025]) @ ROT.T
    assert np.linalg.norm(res.points[0].point - expected) <= 1e-9


def test_no_seed_inside_an_overlap_is_solved(monkeypatch):
    """A curve lying in a plane on [0, 0.5]: seeds made there before the overlap was
    grown would only give roots dropped as inside it; none reaches the solver (issue 16:
    the curve runs within tol of the other object there, the slowest Newton solves)."""
    from cagd.queries import _point_solver as ps
    starts = []
    real = ps.refine

    def spy(A, B, x, y, *a, **kw):
        starts.append(np.array(x, float))
        return real(A, B, x, y, *a, **kw)

    monkeypatch.setattr(ps, "refine", spy)
    S = cagd.BezierSurface(np.array([[[-0.5, -0.5, 0], [-0.5, 0.5, 0]], [[1.5, -0.5, 0], [1.5, 0.5, 0]]]) @ ROT.T)
    x = np.linspace(0, 1, 8)
    C = cagd.BSplineCurve(np.stack([x, 0.1 * np.sin(3 * x), [0, 0, 0, 0, 0, 0.01, -0.05, 0.1]], 1) @ ROT.T, 2)
    res = intersect(C, S, tol=1e-9)
    assert res.converged and len(res.overlaps) == 1 and len(res.points) == 2       # down through it and up
    s0, s1 = res.overlaps[0].param_a
    assert s0 == 0.0 and 0.5 < s1 < 0.6 < min(p.param_a for p in res.points)
    at = C(np.array([p.param_a for p in res.points]))
    assert closest_point(S, at).distances.max() <= 1e-9
    solved = np.concatenate(starts)[:, 0]
    assert len(solved) and not np.any((solved > s0) & (solved < s1))


def test_refined_starts_at_one_root_go_on_once():
    """After the first refinement the starts that share a parameter cell (a tenth of
    SAME_PARAM_RTOL of each width) are one root: the nearest goes on to the tangential
    refinement and polish (issue 16: bug33398.step's faces 247 x 359, 1,054 starts at
    228 roots); starts one cell apart in any parameter are kept."""
    from cagd.queries import _point_solver as ps
    A, B = sd.Geometry(_line(0.0, 0.05), "a"), sd.Geometry(_surface(), "b")
    c = 0.3 + 0.5e-8                                        # the middle of a cell
    x = np.array([[c], [c + 1e-10], [c], [c], [0.6]])
    y = np.array([[0.2, 0.4], [0.2, 0.4], [0.2, 0.4 + 1e-8], [0.2 + 1e-8, 0.4], [0.2, 0.4]])
    d = np.array([3e-10, 1e-10, 2e-10, 4e-10, 5e-10])
    xs, ys, ds = ps._one_per_cell(A, B, x, y, d)
    assert sorted(ds) == [1e-10, 2e-10, 4e-10, 5e-10]
    i = int(np.argmin(ds))
    assert xs[i, 0] == c + 1e-10 and np.array_equal(ys[i], [0.2, 0.4])


def _same(r, s):
    """Two IntersectionResults equal to the bit: points, overlaps, convergence, message."""
    assert (r.converged, r.message, len(r.points), len(r.overlaps)) == (s.converged, s.message, len(s.points),
                                                                        len(s.overlaps))
    for p, q in zip(r.points, s.points):
        assert np.array_equal(p.param_a, q.param_a) and np.array_equal(p.param_b, q.param_b)
        assert np.array_equal(p.point, q.point) and p.tangential == q.tangential
    for p, q in zip(r.overlaps, s.overlaps):
        assert np.array_equal(p.param_a, q.param_a) and np.array_equal(p.param_b, q.param_b)


def test_jobs_in_lock_step_answer_as_alone(monkeypatch):
    """run_many subdivides jobs of equal piece shapes together (issue 16: the boundary
    curves of a face against its neighbour): every job's answer is the one it gets
    alone, to the bit, through crossings, a tangential corner, an overlap, a miss, a
    job stopped at its own max_pairs while the others go on, and jobs of another shape
    (another group)."""
    from cagd.queries import _point_solver as ps
    from cagd.queries._point_solver import run, run_many
    S = _surface()
    G = sd.Geometry(S, "b")
    # along the surface at height 0.025 (an overlap at gap 0), across it, a miss, a cubic
    # touching it at its start (z = 0.1 x^2 + 0.2 (x - 0.1)^2 from x = 0.1: tangential),
    # and a wiggle crossing it several times
    lines = [_line(0.025, 0.025), _line(-0.3, 0.4), _line(0.5, 0.6)]
    z = [0.001, 0.001 + 0.008, 0.209]               # the quadratic's Bezier ordinates in t = (x - 0.1) / 0.8
    touch = cagd.BezierCurve(np.array([[0.1 + 0.8 * t, 0.3, zt] for t, zt in
                                       zip((0, 1 / 3, 2 / 3, 1), (z[0], (z[0] + 2 * z[1]) / 3,
                                                                  (2 * z[1] + z[2]) / 3, z[2]))]) @ ROT.T)
    wiggle = cagd.BezierCurve(np.array([[0.1, 0.1, 0.1], [0.4, 0.3, -0.2], [0.6, 0.6, 0.3], [0.9, 0.8, -0.1]])
                              @ ROT.T)
    curves = [sd.Geometry(c, "a") for c in lines + [touch, wiggle]]
    for pairs in (20000, 40):                      # at 40 pairs some jobs stop early
        jobs = [(c, G) for c in curves]
        alone = [run(c, G, 1e-9, 1e-6, 64, pairs) for c in curves]
        together = run_many(jobs, 1e-9, 1e-6, 64, pairs)
        monkeypatch.setattr(ps, "LOCKSTEP_PAIRS", 2 * pairs)         # lock steps of 2 jobs at most
        twos = run_many(jobs, 1e-9, 1e-6, 64, pairs)
        monkeypatch.undo()
        assert len(together) == len(twos) == len(jobs)
        for r, s, t in zip(alone, together, twos):
            _same(r, s)
            _same(r, t)
        if pairs == 20000:
            assert [len(r.points) for r in alone[1:]] == [1, 0, 1, 3] and len(alone[0].overlaps) == 1
            assert all(r.converged for r in alone) and alone[3].points[0].tangential
        else:
            assert not all(r.converged for r in alone) and any(r.converged for r in alone)
