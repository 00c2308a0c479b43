"""min_distance honours trims (issue 15, cagd.queries._distance_trimmed): a TrimmedSurface
is the face itself against a point set, a curve, a surface or another face. Oracles:
closed forms (a disk trimmed from a plane against spheres, a segment and a parallel
disk), brute force (dense samples of the trimmed domain and its loops against the other
object), OCCT's BRepExtrema_DistShapeShape on the faces written by cagd.occ, and the
certificate (lower_bound <= distance, both points on their faces)."""
import math

import numpy as np
import pytest

from cagd import BSplineCurve, BSplineSurface, CagdError, TrimmedSurface, closest_point, min_distance
from cagd.surfaces.revolution import sphere
from trim_shapes import circle, curved_patch

RNG = np.random.default_rng(151)


def disk(c=(0.5, 0.5), r=0.3, z=0.0):
    """The disk of centre (2 c, z) and radius 2 r in the plane at height z."""
    P = np.array([[[0, 0, z], [0, 2, z]], [[2, 0, z], [2, 2, z]]], float)
    return TrimmedSurface(BSplineSurface(P, 1, 1), [[circle(c, r)]])


def bumpy():
    return TrimmedSurface(curved_patch(), [[circle((0.5, 0.5), 0.4)], [circle((0.6, 0.45), 0.12, clockwise=True)]])


def on_face(obj, param, point):
    """The result's point is obj at param, inside its trim."""
    if isinstance(obj, TrimmedSurface):
        assert obj.contains(param[0], param[1])
        assert np.abs(obj.untrimmed(param[0], param[1]) - point).max() <= 1e-12
    elif isinstance(obj, BSplineCurve):
        assert np.abs(obj(param) - point).max() <= 1e-12


def check(r, a, b, tol=1e-9):
    assert r.converged, r.message
    assert r.lower_bound <= r.distance <= r.lower_bound + tol * 10
    assert abs(np.linalg.norm(r.points[0] - r.points[1]) - r.distance) <= 1e-14 * max(1.0, r.distance)
    on_face(a, r.params[0], r.points[0])
    on_face(b, r.params[1], r.points[1])


@pytest.mark.parametrize("centre, radius", [((2.5, 1.0, 0.8), 0.5), ((1.0, 2.4, -0.3), 0.2), ((0.1, 0.2, 0.5), 0.3)])
def test_disk_against_a_sphere_beside_it(centre, radius):
    """A sphere whose nearest point of the plane is off the disk: the minimum is on the
    disk's edge, sqrt((rho - 0.6)^2 + h^2) - R (rho the centre's distance from the disk's
    axis), farther than from the untrimmed square."""
    ts, S = disk(), sphere(radius, centre)
    rho = math.hypot(centre[0] - 1.0, centre[1] - 1.0)
    expect = math.hypot(rho - 0.6, centre[2]) - radius
    r = min_distance(ts, S)
    check(r, ts, S)
    assert r.distance == pytest.approx(expect, rel=1e-12, abs=1e-12)
    assert min_distance(S, ts).distance == pytest.approx(expect, rel=1e-12, abs=1e-12)   # either order
    assert min_distance(ts.untrimmed, S).distance < expect - 0.05       # the trim matters here


def test_disk_against_a_sphere_over_it():
    """Over the disk the minimum is inside the face: h - R (the edge is farther)."""
    ts, S = disk(), sphere(0.3, (1.1, 0.9, 0.8))
    r = min_distance(ts, S)
    check(r, ts, S)
    assert r.distance == pytest.approx(0.5, rel=1e-12)
    assert np.linalg.norm(r.points[0] - [1.1, 0.9, 0.0]) <= 1e-6


def test_point_set_against_a_face():
    """A point set: the nearest of its points' closest points on the face (closed form on
    the disk: the phantom corner's points are far from the face), params (uv, index)."""
    ts = disk()
    X = np.array([[0.0, 0.0, 0.0], [2.0, 2.0, 0.1], [1.0, 1.9, 0.4]])
    expect = [math.sqrt(2) - 0.6, math.hypot(math.sqrt(2) - 0.6, 0.1), math.hypot(0.3, 0.4)]
    r = min_distance(ts, X)
    assert r.distance == pytest.approx(min(expect), rel=1e-12)
    assert r.params[1] == int(np.argmin(expect))
    assert ts.contains(*r.params[0])
    assert r.lower_bound <= r.distance
    s = min_distance(X, ts)
    assert s.distance == r.distance and s.params[0] == r.params[1]


def test_segment_over_the_phantom_corner():
    """A segment across the square's corner, above the plane: 0.3 from the untrimmed
    square, from the disk the distance to its edge (closed form by dense sampling of the
    segment against the circle)."""
    ts = disk()
    seg = BSplineCurve(np.array([[-0.5, 0.5, 0.3], [0.5, -0.5, 0.3]]), 1)
    r = min_distance(ts, seg)
    check(r, ts, seg)
    t = np.linspace(0, 1, 200001)
    P = seg(t)
    expect = np.hypot(np.hypot(P[:, 0] - 1, P[:, 1] - 1) - 0.6, 0.3).min()
    assert r.distance == pytest.approx(expect, rel=1e-9)
    assert min_distance(ts.untrimmed, seg).distance == pytest.approx(0.3, rel=1e-12)


def test_two_parallel_disks():
    """Disks in parallel planes whose projections do not overlap: the untrimmed planes are
    h apart everywhere (a continuum); the faces are sqrt(gap^2 + h^2) apart, edge to edge."""
    a = disk((0.3, 0.3), 0.2)                       # centre (0.6, 0.6), radius 0.4
    b = disk((0.7, 0.75), 0.15, z=0.25)             # centre (1.4, 1.5), radius 0.3
    gap = math.hypot(0.8, 0.9) - 0.7
    r = min_distance(a, b)
    check(r, a, b)
    assert r.distance == pytest.approx(math.hypot(gap, 0.25), rel=1e-12)
    assert min_distance(a.untrimmed, b.untrimmed).distance == pytest.approx(0.25, rel=1e-12)


def samples(ts, n=301, m=4001):
    """Dense points of a face: a grid of its domain kept inside the trim, and its loops."""
    s = ts.untrimmed
    (u0, u1), (v0, v1) = s.domain
    uu, vv = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
    k = ts.contains(uu.ravel(), vv.ravel())
    Q = [s(uu.ravel()[k], vv.ravel()[k])]
    for loop in ts.loops:
        for c in loop:
            q = c(np.linspace(*c.domain, m))
            Q.append(s(q[:, 0], q[:, 1]))
    return np.concatenate(Q)


@pytest.mark.parametrize("centre", [(0.5, 0.5, 0.75), (1.2, 0.4, 0.2), (0.6, 0.45, 0.45)])
def test_bumpy_face_against_a_sphere_by_brute_force(centre):
    """A bicubic bump trimmed to a disk with a hole: never farther than the best of dense
    samples of the face against the sphere (closed form per sample), and within the
    samples' reach of it."""
    ts, S = bumpy(), sphere(0.2, centre)
    r = min_distance(ts, S)
    check(r, ts, S)
    b = np.abs(np.linalg.norm(samples(ts) - centre, axis=1) - 0.2).min()     # to the sphere: | |q - c| - R |
    assert r.distance <= b + 1e-12
    assert b - r.distance <= 1e-4                          # the samples' spacing, squared
    assert r.distance >= min_distance(ts.untrimmed, S).distance - 1e-15


def test_face_against_a_face_by_brute_force():
    """The bump face against a disk face lifted over it: the samples of each face
    against the other face bound it from above."""
    a, b = bumpy(), disk((0.55, 0.5), 0.22, z=0.45)
    r = min_distance(a, b)
    check(r, a, b)
    best = min(closest_point(b, samples(a)).distances.min(), closest_point(a, samples(b)).distances.min())
    assert r.distance <= best + 1e-12
    assert best - r.distance <= 1e-4


def occt_shape(x):
    from cagd.occ import make_edge, make_face
    return make_edge(x) if isinstance(x, BSplineCurve) else make_face(x)


def occt_distance(x, y):
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    d = BRepExtrema_DistShapeShape(occt_shape(x), occt_shape(y))
    assert d.IsDone()
    return d.Value()


@pytest.mark.parametrize("case", ["sphere", "face", "curve"])
def test_against_occt(case):
    """BRepExtrema_DistShapeShape between the OCCT faces (cagd.occ.make_face): the engine's
    distance is never larger (+1e-9 relative) and agrees to OCCT's own tolerance."""
    pytest.importorskip("OCP")
    a = bumpy()
    b = {"sphere": sphere(0.2, (1.2, 0.4, 0.2)),
         "face": disk((0.55, 0.5), 0.22, z=0.45),
         "curve": BSplineCurve(np.array([[-0.2, 0.3, 0.3], [0.4, 0.55, 0.1], [1.3, 0.6, 0.35]]), 2)}[case]
    r = min_distance(a, b)
    check(r, a, b)
    occt = occt_distance(a, b)
    assert r.distance <= occt * (1 + 1e-9) + 1e-12
    assert abs(r.distance - occt) <= 1e-7


def test_intersecting_faces_are_zero_apart():
    """The bump face crosses the plane's disk (centre (0.6, 0.5), radius 0.2, at z = 0.1:
    the bump is 0.158 above its centre, 0.049 at (0.6, 0.7)): distance 0 (to rounding)."""
    a, b = bumpy(), disk((0.3, 0.25), 0.1, z=0.1)
    r = min_distance(a, b)
    check(r, a, b)
    assert r.distance <= r.tol


def test_bad_input():
    ts = disk()
    with pytest.raises(CagdError, match="b"):                  # point sets only against a face
        min_distance(ts.untrimmed, np.ones((3, 3)))
    with pytest.raises(CagdError, match="dimension"):
        min_distance(ts, np.zeros((2, 2)))
    with pytest.raises(CagdError, match="a"):
        min_distance(np.zeros((0, 3)), ts)
