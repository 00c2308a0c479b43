"""Intersections of trimmed faces (issue 15): branches cut where they leave a trim,
points outside a trim dropped. Oracles: a bump whose x is u exactly, cut by the plane
x = 0.5, trimmed by a disk (one branch, v from 0.1 to 0.9) and by an annulus (two
branches, the hole's chord taken out); two trimmed faces: every sample of every branch
lies in both trims and the cut ends lie on a loop."""
import numpy as np
import pytest

from cagd import BSplineSurface, TrimmedSurface, intersect
from cagd.queries.intersect import plane
from trim_shapes import circle, curved_patch, rectangle

PLANE = plane([0.5, 0.0, 0.0], [1.0, 0.0, 0.0])


def v_ranges(res):
    out = []
    for br in res.curves:
        uv, _ = br.surface_params(np.linspace(*br.curve.domain, 201))
        assert np.abs(uv[:, 0] - 0.5).max() <= 1e-8
        out.append((uv[:, 1].min(), uv[:, 1].max()))
    return sorted(out)


def test_disk_cuts_the_branch_to_its_chord():
    ts = TrimmedSurface(curved_patch(), [[circle((0.5, 0.5), 0.4)]])
    full = intersect(ts.untrimmed, PLANE)
    assert v_ranges(full) == [pytest.approx((0.0, 1.0), abs=1e-9)]
    res = intersect(ts, PLANE)
    assert v_ranges(res) == [pytest.approx((0.1, 0.9), abs=1e-9)]
    assert res.curves[0].ends == ("trim", "trim") and not res.curves[0].closed


def test_an_annulus_gives_two_branches():
    ts = TrimmedSurface(curved_patch(), [[circle((0.5, 0.5), 0.4)], [circle((0.5, 0.5), 0.15, clockwise=True)]])
    res = intersect(ts, PLANE)
    assert v_ranges(res) == [pytest.approx((0.1, 0.35), abs=1e-9), pytest.approx((0.65, 0.9), abs=1e-9)]


def test_two_trimmed_faces():
    """The bump against a flat sheet z = 0.05 trimmed to half its square: every point of
    every branch is on both faces, and every cut end is on one of the loops."""
    bump = TrimmedSurface(curved_patch(), [[circle((0.5, 0.5), 0.45)]])
    P = np.array([[[-0.2, -0.2, 0.05], [-0.2, 1.2, 0.05]], [[1.2, -0.2, 0.05], [1.2, 1.2, 0.05]]])
    sheet = TrimmedSurface(BSplineSurface(P, 1, 1), [rectangle(0.0, 0.5, 0.0, 1.0)])
    plain = intersect(bump.untrimmed, sheet.untrimmed)
    res = intersect(bump, sheet)
    assert res.curves and len(res.curves) >= len(plain.curves)
    trims = 0
    for br in res.curves:
        t = np.linspace(*br.curve.domain, 401)
        uva, uvb = br.surface_params(t)
        assert bump.contains(uva[:, 0], uva[:, 1]).all() and sheet.contains(uvb[:, 0], uvb[:, 1]).all()
        for end, te in zip(br.ends, br.curve.domain):
            if end == "trim":
                trims += 1
                a, b = br.surface_params([te])
                on_a = np.hypot(a[0, 0] - 0.5, a[0, 1] - 0.5) - 0.45
                on_b = min(abs(b[0, 0] - 0.5), abs(b[0, 0]), abs(b[0, 1]), abs(b[0, 1] - 1.0))
                assert min(abs(on_a), on_b) <= 1e-9
    assert trims >= 2
    length = sum(br.curve.arc_length() for br in res.curves)
    assert length < sum(br.curve.arc_length() for br in plain.curves)


def test_a_loop_cut_open_is_one_piece_through_its_seam():
    """A dome cut by z = 0.5 gives a closed loop; a trim v >= 0.55 that holds the loop's
    seam leaves one arc (the runs before and after the seam joined), both ends 'trim'
    on v = 0.55, every point on the plane (found in review: two pieces with 'closed' ends)."""
    x = np.linspace(0, 1, 3)
    X, Y = np.meshgrid(x, x, indexing="ij")
    S = BSplineSurface(np.stack([X, Y, np.array([[0, 0.5, 0], [0.5, 1.5, 0.5], [0, 0.5, 0]])], -1), 2, 2)
    level = plane([0, 0, 0.5], [0, 0, 1])
    assert intersect(S, level).curves[0].closed
    res = intersect(TrimmedSurface(S, [rectangle(0, 1, 0.55, 1)]), level)
    assert len(res.curves) == 1
    br = res.curves[0]
    assert br.ends == ("trim", "trim") and not br.closed
    uv, _ = br.surface_params(np.array(br.curve.domain))
    assert np.abs(uv[:, 1] - 0.55).max() <= 1e-9
    t = np.linspace(*br.curve.domain, 2001)
    assert np.abs(br.curve(t)[:, 2] - 0.5).max() <= 1e-8
    uv, _ = br.surface_params(t)
    assert uv[:, 1].min() >= 0.55 - 1e-9
