"""cagd.trim_edge_continuity: continuity along the boundary curve two faces share
(issue 15, faces_continuity on trims), against closed forms."""
import math

import numpy as np
import pytest

import cagd
from cagd import BSplineCurve, BSplineSurface, TrimmedSurface

W = math.sqrt(0.5)
UNIT = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
KNOTS = [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1]


def circle(centre, r, clockwise=False):
    c = BSplineCurve(UNIT * r + np.asarray(centre, float), 2, KNOTS, [1, W, 1, W, 1, W, 1, W, 1])
    return c.reversed() if clockwise else c


def square(x0, x1, y0, y1, z=0.0):
    return BSplineSurface(np.array([[[x0, y0, z], [x0, y1, z]], [[x1, y0, z], [x1, y1, z]]], float), 1, 1,
                          [x0, x0, x1, x1], [y0, y0, y1, y1])


def box_sides(x0, x1, y0, y1):
    corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]], float)
    return [BSplineCurve(corners[k:k + 2], 1, [0, 0, 1, 1]) for k in range(4)]


def test_disk_and_its_complement_are_g1_along_the_circle():
    plane = square(-2.0, 2.0, -2.0, 2.0)
    disk = TrimmedSurface(plane, [[circle((0.3, -0.2), 1.1)]])
    rest = TrimmedSurface(plane, [box_sides(-2.0, 2.0, -2.0, 2.0), [circle((0.3, -0.2), 1.1, clockwise=True)]])
    r = cagd.trim_edge_continuity(disk, rest)
    assert (r.curve1, r.curve2) == (0, 4)           # the disk's circle = the hole, after the 4 box sides
    assert r.gap <= 1e-12 and r.normal_angle <= 1e-12 and r.G1 and r.converged
    assert r.curvature_difference <= 1e-12 and r.G2 and r.level == "G2"
    assert r.samples == 33 and "curve 0 of face 1" in str(r)


def test_disk_on_a_cylinder_is_a_right_angle_crease():
    radius, height = 1.5, 2.0
    cyl = cagd.cylinder(radius, height)             # bottom rim at z = 0 (u = 1)
    plane = square(-3.0, 3.0, -3.0, 3.0)
    cap = TrimmedSurface(plane, [[circle((0.0, 0.0), radius)]])
    r = cagd.trim_edge_continuity(cap, cyl, samples=21)
    assert r.gap <= 1e-12 * radius and r.C0
    assert abs(r.normal_angle - math.pi / 2) <= 1e-9 and not r.G1 and r.level == "C0"
    assert r.curve2 == 1                             # the cylinder's bottom rim u = u1: box side 1


@pytest.mark.parametrize("theta", [0.3, 1.0, 2.5])
def test_two_planes_meet_at_their_dihedral_angle(theta):
    a = square(-1.0, 1.0, -1.0, 1.0)
    # the plane through the edge x = 1 of a, tilted up by theta: (1 + s cos(theta), y, s sin(theta))
    ct, st = math.cos(theta), math.sin(theta)
    P = np.array([[[1.0, -1.0, 0.0], [1.0, 1.0, 0.0]], [[1.0 + ct, -1.0, st], [1.0 + ct, 1.0, st]]])
    b = BSplineSurface(P, 1, 1)
    r = cagd.trim_edge_continuity(a, b)
    assert r.curve1 == 1 and r.curve2 == 3           # a's side x = 1 (u = u1), b's side u = 0
    assert r.gap <= 1e-14
    assert abs(r.normal_angle - min(theta, math.pi - theta)) <= 1e-12
    assert not r.G1


def _cylinder_strip(radius):
    """(R sin t, y, R - R cos t), t in [0, pi/2] (exact rational quadratic), y in [0, 1]:
    tangent to the plane z = 0 along its side u = 0 (the line x = z = 0); the normal
    curvature across that line is 1 / R."""
    P = np.array([[[0, y, 0], [radius, y, 0], [radius, y, radius]] for y in (0.0, 1.0)], float).transpose(1, 0, 2)
    return BSplineSurface(P, 2, 1, None, None, np.array([[1, 1], [W, W], [1, 1]]))


def test_a_plane_tangent_to_a_cylinder_is_g1_not_g2():
    radius = 0.7
    r = cagd.trim_edge_continuity(square(-1.0, 0.0, 0.0, 1.0), _cylinder_strip(radius))
    assert r.curve1 == 1 and r.curve2 == 3           # the plane's side x = 0, the strip's side u = 0
    assert r.gap <= 1e-14 and r.normal_angle <= 1e-12 and r.G1
    assert abs(r.curvature_difference - 1 / radius) <= 1e-9 and not r.G2 and r.level == "G1"


def test_a_cylinder_trimmed_in_two_is_g2_across_the_cut():
    S = _cylinder_strip(0.7)
    a = TrimmedSurface(S, [box_sides(0.0, 0.4, 0.0, 1.0)])
    b = TrimmedSurface(S, [box_sides(0.4, 1.0, 0.0, 1.0)])
    r = cagd.trim_edge_continuity(a, b)
    assert r.gap <= 1e-14 and r.G1
    assert r.curvature_difference <= 1e-12 and r.G2 and r.level == "G2"


def test_a_gap_is_measured():
    a = square(0.0, 1.0, 0.0, 1.0)
    b = square(1.0, 2.0, 0.0, 1.0, z=1e-3)           # parallel, lifted by 1e-3
    r = cagd.trim_edge_continuity(a, b, rel_tol=1e-6)
    assert abs(r.gap - 1e-3) <= 1e-12 and not r.C0 and r.level == "none"
    assert r.normal_angle <= 1e-12


@pytest.mark.parametrize("args, match", [
    ((square(0, 1, 0, 1), "x"), "s2"),
    ((square(0, 1, 0, 1), square(0, 1, 0, 1)), None),
])
def test_bad_input(args, match):
    if match is None:
        with pytest.raises(cagd.CagdError, match="samples"):
            cagd.trim_edge_continuity(*args, samples=1)
        with pytest.raises(cagd.CagdError, match="rel_tol"):
            cagd.trim_edge_continuity(*args, rel_tol=-1.0)
    else:
        with pytest.raises(cagd.CagdError, match=match):
            cagd.trim_edge_continuity(*args)
    flat = BSplineSurface(np.array([[[0, 0], [0, 1]], [[1, 0], [1, 1]]], float), 1, 1)
    with pytest.raises(cagd.CagdError, match="3-D"):
        cagd.trim_edge_continuity(flat, square(0, 1, 0, 1))


def test_per_station_read_out_along_a_plane_tangent_to_a_cylinder():
    """Every station along the shared line: gap 0, angle 0, curvature difference 1 / R
    (closed form); the stations lie on the line x = z = 0, y from 0 to 1."""
    radius = 0.7
    r = cagd.trim_edge_continuity(square(-1.0, 0.0, 0.0, 1.0), _cylinder_strip(radius), samples=17)
    assert r.points.shape == (17, 3) and not r.points.flags.writeable
    assert np.abs(r.points[:, [0, 2]]).max() <= 1e-14
    assert np.allclose(np.sort(r.points[:, 1]), np.linspace(0.0, 1.0, 17), atol=1e-14)
    assert r.gaps.max() <= 1e-14 and np.nanmax(r.angles) <= 1e-12
    assert np.abs(r.curvature_differences - 1 / radius).max() <= 1e-9
    measure, i, value, point = r.worst()             # G1 holds: the worst is the curvature difference
    assert measure == "curvature" and abs(value - 1 / radius) <= 1e-9 and np.array_equal(point, r.points[i])


def test_worst_station_of_a_growing_kink_is_at_the_far_end():
    """A plane z = 0 (x <= 0) against the saddle z = c x y (x >= 0, y in [0, L]): along
    x = 0 the saddle's normal is (-c y, 0, 1), the kink angle atan(c y) grows with y,
    worst at the end (0, L, 0), atan(c L) exactly."""
    c, length = 0.8, 2.0
    plane = square(-1.0, 0.0, 0.0, length)
    P = np.array([[[0.0, 0.0, 0.0], [0.0, length, 0.0]], [[1.0, 0.0, 0.0], [1.0, length, c * length]]])
    r = cagd.trim_edge_continuity(plane, BSplineSurface(P, 1, 1), samples=21)
    assert r.C0 and not r.G1
    y = r.points[:, 1]
    assert np.abs(r.angles - np.arctan(c * y)).max() <= 1e-12
    measure, i, value, point = r.worst()
    assert measure == "angle" and abs(value - math.atan(c * length)) <= 1e-12
    assert np.abs(point - [0.0, length, 0.0]).max() <= 1e-14 and value == r.normal_angle
    assert r.worst("gap")[2] <= 1e-14
    with pytest.raises(cagd.CagdError, match="measure"):
        r.worst("twist")
