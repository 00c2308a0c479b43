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


# --- overlaps clipped to the trims ----------------------------------------------------------------------
def sheet(x0, x1, y0=0.0, y1=2.0):
    """The plane z = 0 over [x0, x1] x [y0, y1]: S(u, v) = (x0 + (x1 - x0) u, y0 + (y1 - y0) v, 0)."""
    P = np.array([[[x0, y0, 0], [x0, y1, 0]], [[x1, y0, 0], [x1, y1, 0]]], float)
    return BSplineSurface(P, 1, 1)


def disk_on(s, x0, x1, centre, r, y0=0.0, y1=2.0):
    """The disk of the given 3-D centre (x, y) and radius on sheet(x0, x1, y0, y1)."""
    cu, cv = (centre[0] - x0) / (x1 - x0), (centre[1] - y0) / (y1 - y0)
    assert x1 - x0 == y1 - y0                      # a circle in (u, v) too
    return TrimmedSurface(s, [[circle((cu, cv), r / (x1 - x0))]])


def lens(R, d):
    """The area of two disks of radius R whose centres are d apart (closed form)."""
    return 2 * R * R * np.arccos(d / (2 * R)) - 0.5 * d * np.sqrt(4 * R * R - d * d)


def test_coplanar_disks_overlap_in_their_lens():
    """Two coplanar trimmed disks (radius 0.5, centres 0.7 apart) on different patches of
    the plane z = 0: the untrimmed overlap (the patches' common strip) is clipped to the
    lens, its area the closed form within the reported error (measured 1.1e-5 within
    8.2e-4), every cell inside both disks and every edge cell within its diagonal of both
    circles, the boxes the lens's."""
    a = disk_on(sheet(0.0, 2.0), 0.0, 2.0, (0.8, 1.0), 0.5)
    b = disk_on(sheet(0.5, 2.5), 0.5, 2.5, (1.5, 1.0), 0.5)
    full = intersect(a.untrimmed, b.untrimmed)
    assert len(full.overlaps) == 1 and full.overlaps[0].area is None
    res = intersect(a, b)
    assert len(res.overlaps) == 1
    ov = res.overlaps[0]
    want = lens(0.5, 0.7)
    assert ov.area_error < 1e-2 * want
    assert abs(ov.area - want) <= ov.area_error
    S = a.untrimmed
    centres = 0.5 * (ov.cells_a[:, :2] + ov.cells_a[:, 2:])
    P = S(centres[:, 0], centres[:, 1])
    assert np.all(np.hypot(P[:, 0] - 0.8, P[:, 1] - 1.0) < 0.5) and np.all(np.hypot(P[:, 0] - 1.5, P[:, 1] - 1.0) < 0.5)
    E = 0.5 * (ov.edge_cells_a[:, :2] + ov.edge_cells_a[:, 2:])
    Q = S(E[:, 0], E[:, 1])
    diag = 2.0 * np.hypot(*(ov.edge_cells_a[0, 2:] - ov.edge_cells_a[0, :2]))
    near = np.minimum(np.abs(np.hypot(Q[:, 0] - 0.8, Q[:, 1] - 1.0) - 0.5),
                      np.abs(np.hypot(Q[:, 0] - 1.5, Q[:, 1] - 1.0) - 0.5))
    assert near.max() <= diag
    h = 0.5 * np.sqrt(4 * 0.25 - 0.49)              # the lens's half height; it spans x in [1.0, 1.3]
    (u0, u1), (v0, v1) = ov.box_a
    assert 2 * u0 == pytest.approx(1.0, abs=2 * diag) and 2 * u1 == pytest.approx(1.3, abs=2 * diag)
    assert 2 * v0 == pytest.approx(1.0 - h, abs=2 * diag) and 2 * v1 == pytest.approx(1.0 + h, abs=2 * diag)
    (bu0, bu1), _ = ov.box_b
    assert 0.5 + 2 * bu0 == pytest.approx(1.0, abs=2 * diag) and 0.5 + 2 * bu1 == pytest.approx(1.3, abs=2 * diag)
    assert "clipped to the trims" in ov.message


def test_disjoint_trims_on_one_plane_do_not_overlap():
    a = disk_on(sheet(0.0, 2.0), 0.0, 2.0, (0.6, 1.0), 0.3)
    b = disk_on(sheet(0.5, 2.5), 0.5, 2.5, (1.7, 1.0), 0.3)
    assert len(intersect(a.untrimmed, b.untrimmed).overlaps) == 1
    res = intersect(a, b)
    assert res.overlaps == () and res.curves == () and res.points == ()


def test_one_trimmed_face_clips_to_its_trim_only():
    """A disk (centre (0.8, 1), radius 0.5) on a plane patch against an untrimmed coplanar
    patch x >= 0.5: the overlap is the disk's part x >= 0.5, R^2 acos(d/R) - d sqrt(R^2 - d^2)
    short of the disk (d = 0.3), within the reported error."""
    a = disk_on(sheet(0.0, 2.0), 0.0, 2.0, (0.8, 1.0), 0.5)
    (ov,) = intersect(a, sheet(0.5, 2.5)).overlaps
    R, d = 0.5, 0.3
    want = np.pi * R * R - (R * R * np.arccos(d / R) - d * np.sqrt(R * R - d * d))
    assert abs(ov.area - want) <= ov.area_error < 1e-2 * want


def test_an_untrimmed_pair_keeps_its_overlap():
    """Untrimmed surfaces: the overlap as intersect_surfaces finds it, no cells, no area."""
    res = intersect(sheet(0.0, 2.0), sheet(0.5, 2.5))
    (ov,) = res.overlaps
    assert ov.cells_a is None and ov.edge_cells_a is None and ov.area is None and ov.area_error == 0.0
    (u0, u1), (v0, v1) = ov.box_a
    assert (u0, u1, v0, v1) == pytest.approx((0.25, 1.0, 0.0, 1.0), abs=1e-8)
    assert "clipped" not in ov.message


def test_the_cell_bound_stops_the_refinement_with_an_honest_error(monkeypatch):
    """With MAX_OVERLAP_CELLS = 64 the quadtree stops early: fewer, larger edge cells, a
    larger reported error that still holds the lens area."""
    import cagd.queries.trimmed as qt
    monkeypatch.setattr(qt, "MAX_OVERLAP_CELLS", 64)
    a = disk_on(sheet(0.0, 2.0), 0.0, 2.0, (0.8, 1.0), 0.5)
    b = disk_on(sheet(0.5, 2.5), 0.5, 2.5, (1.5, 1.0), 0.5)
    (ov,) = intersect(a, b).overlaps
    assert len(ov.edge_cells_a) <= 4 * 64 and "2^-" in ov.message and "2^-7" not in ov.message
    assert abs(ov.area - lens(0.5, 0.7)) <= ov.area_error
