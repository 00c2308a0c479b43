"""Continuity across a shared edge of two patches (seed 003, 2.2.3): the halves of a
split surface are C1, the seed's Bezier construction with a scaled difference vector
is G1 but not C1, a kinked pair is only C0, and a gap is not even C0."""
import numpy as np
import pytest

import cagd
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BezierSurface, BSplineSurface, CagdError
from cagd.surfaces.continuity import EdgeContinuityReport, edge_continuity

from surface_strategies import NONPERIODIC, bspline_surfaces

SETTINGS = settings(max_examples=40, deadline=None)
T = np.linspace(0.0, 1.0, 33)


def plane_angle_conditioning(s, edge, count=33):
    """min over the edge of |T x D| / (|T| |D|) for s's own along/cross derivatives."""
    (u0, u1), (v0, v1) = s.domain
    t = np.linspace(0, 1, count)
    if edge[0] == "u":
        d = s.derivatives(np.full(count, u0 if edge == "u0" else u1), v0 + t * (v1 - v0), 1, 1)
        a, c = d[0, 1], d[1, 0]
    else:
        d = s.derivatives(u0 + t * (u1 - u0), np.full(count, v0 if edge == "v0" else v1), 1, 1)
        a, c = d[1, 0], d[0, 1]
    lift = lambda x: np.concatenate([x, np.zeros(x.shape[:-1] + (3 - x.shape[-1],))], axis=-1)  # noqa: E731
    n = np.linalg.norm(np.cross(lift(a), lift(c)), axis=-1)
    return float((n / (np.linalg.norm(a, axis=-1) * np.linalg.norm(c, axis=-1) + 1e-300)).min())


def off_knots(s, direction, t):
    """t is not a knot: at a knot of multiplicity m the surface is only C^(p-m) (a
    degree-1 surface has a kink at every knot), and its halves need not be C1."""
    k = s.knots_u if direction == "u" else s.knots_v
    return bool(np.abs(np.asarray(k) - t).min() > 1e-9)


@SETTINGS
@given(s=bspline_surfaces(kinds=NONPERIODIC, dims=(2, 3), max_degree=3), data=st.data())
def test_halves_of_a_split_surface_are_c1(s, data):
    d = data.draw(st.sampled_from("uv"))
    which = 0 if d == "u" else 1
    a, b = s.domain[which]
    t = data.draw(st.floats(a + 0.1 * (b - a), b - 0.1 * (b - a)))
    assume(off_knots(s, d, t))
    left, right = s.split(d, t)
    e1, e2 = ("u1", "u0") if d == "u" else ("v1", "v0")
    r = edge_continuity(left, right, e1, e2)
    assert isinstance(r, EdgeContinuityReport)
    assert r.C0 and r.C1 and not r.reversed, str(r)
    assert r.gap <= 1e-12 * r.size * 10
    if plane_angle_conditioning(left, e1) > 1e-3:
        assert r.G1 and r.normal_angle <= 1e-9, str(r)
        assert r.level == "C1"


@SETTINGS
@given(s=bspline_surfaces(kinds=NONPERIODIC, dims=(3, 3), max_degree=3), t=st.floats(0.2, 0.8))
def test_other_edge_pairings_and_reversal(s, t):
    """Split in u; the right half swapped (the edge becomes its "v0") or reversed along
    the edge (detected as the opposite direction) is still C1 with the first half."""
    (a, b), (c, d) = s.domain
    assume(off_knots(s, "u", a + t * (b - a)))
    left, right = s.split("u", a + t * (b - a))
    r = edge_continuity(left, right.swapped(), "u1", "v0")
    assert r.C0 and r.C1 and not r.reversed, str(r)
    flipped = right.reversed("v")
    r2 = edge_continuity(left, flipped, "u1", "u0")
    r3 = edge_continuity(left, flipped, "u1", "u0", reverse=False)
    forced = edge_continuity(left, flipped, "u1", "u0", reverse=True)
    assert forced.reversed and forced.C0 and forced.C1, str(forced)
    assert r3.gap >= r2.gap
    if r3.gap > 1e-9 * r3.size:                     # the edge is not symmetric: detected
        assert r2.reversed and r2.C0 and r2.C1, str(r2)
    else:
        assert not r2.reversed                      # C0 in the same direction: kept
    # the pair the other way round: right's u0 left, left's u1 entering
    r4 = edge_continuity(right, left, "u0", "u1")
    assert r4.C0 and r4.C1


def bezier_pair(alpha, rng, m=3, n=3, dim=3):
    """Seed 003, 2.2.3: the second patch starts on the first's last row (C0) and its
    first difference vectors are alpha times the first's last ones:
    Q_0j = P_mj, Q_1j - Q_0j = alpha (P_mj - P_(m-1)j)."""
    P = rng.uniform(-1, 1, (m + 1, n + 1, dim))
    P[:, :, 0] += np.arange(m + 1)[:, None] * 2.0               # a tame, regular patch
    P[:, :, 1] += np.arange(n + 1)[None, :] * 2.0
    Q = rng.uniform(-1, 1, (m + 1, n + 1, dim))
    Q[:, :, 0] += (np.arange(m + 1)[:, None] + m) * 2.0
    Q[:, :, 1] += np.arange(n + 1)[None, :] * 2.0
    Q[0] = P[m]
    Q[1] = P[m] + alpha * (P[m] - P[m - 1])
    return BezierSurface(P), BezierSurface(Q)


@pytest.mark.parametrize("alpha", [1.0, 0.5, 2.0, 3.7])
def test_seed_construction_g1_and_c1(alpha):
    """alpha = 1 is the seed's C1 ("difference vectors match"); alpha != 1 keeps the
    tangent planes (G1) but the cross-boundary derivative jumps by (alpha - 1) D1."""
    s1, s2 = bezier_pair(alpha, np.random.default_rng(7))
    r = edge_continuity(s1, s2, "u1", "u0")
    assert r.C0 and r.G1 and not r.reversed
    assert r.gap <= 1e-15 * r.size * 10
    assert r.normal_angle <= 1e-12
    D1 = BezierCurve(s1.boundary_tangents()["u1"])(T)          # m (P_mj - P_(m-1)j) in Bezier form
    expected = abs(alpha - 1) * np.linalg.norm(D1, axis=-1).max()
    np.testing.assert_allclose(r.cross_derivative_mismatch, expected, rtol=1e-12, atol=1e-13)
    assert r.C1 == (alpha == 1.0)
    assert r.level == ("C1" if alpha == 1.0 else "G1")


def test_seed_construction_in_v_and_2d():
    rng = np.random.default_rng(8)
    s1, s2 = bezier_pair(1.0, rng, m=2, n=4, dim=2)
    a, b = BezierSurface(s1.control_points.transpose(1, 0, 2)), BezierSurface(s2.control_points.transpose(1, 0, 2))
    r = edge_continuity(a, b, "v1", "v0")
    assert r.C1 and r.G1, str(r)
    s1, s2 = bezier_pair(0.25, rng, m=2, n=4, dim=2)
    r = edge_continuity(s1, s2, "u1", "u0")
    assert r.G1 and not r.C1


@pytest.mark.parametrize("theta", [0.3, 1.2, np.pi / 2, 2.5])
def test_kinked_pair_is_c0_only(theta):
    """Two planar cubic patches meeting at the line x = 3 at the angle theta between
    their planes: C0, the normal angle is theta, no G1 or C1."""
    i, j = np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij")
    P = np.stack([i, j, 0 * i], axis=-1)
    Q = np.stack([3 + i * np.cos(theta), j, i * np.sin(theta)], axis=-1)
    r = edge_continuity(BezierSurface(P), BezierSurface(Q), "u1", "u0")
    assert r.C0 and not r.G1 and not r.C1
    np.testing.assert_allclose(r.normal_angle, theta, rtol=1e-13)
    assert r.level == "C0"
    # cross derivatives (3, 0, 0) and 3 (cos, 0, sin): |D2 - D1| = 3 |2 sin(theta / 2)|
    np.testing.assert_allclose(r.cross_derivative_mismatch, 6 * np.sin(theta / 2), rtol=1e-13)


def test_fold_back_is_pi():
    """The second patch folded back onto the first shares the tangent plane but not
    its side: the oriented angle is pi."""
    i, j = np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij")
    P = np.stack([i, j, 0 * i], axis=-1)
    Q = np.stack([3 - i, j, 0.1 * i * (i - 1)], axis=-1)        # Q_1 - Q_0 = (-1, 0, 0)
    r = edge_continuity(BezierSurface(P), BezierSurface(Q), "u1", "u0")
    assert r.C0 and not r.G1
    np.testing.assert_allclose(r.normal_angle, np.pi, rtol=1e-12)


@pytest.mark.parametrize("delta", [1e-3, 0.5])
def test_gap(delta):
    s1, s2 = bezier_pair(1.0, np.random.default_rng(3))
    moved = s2.transformed(np.eye(3), [0.0, 0.0, delta])
    r = edge_continuity(s1, moved, "u1", "u0")
    np.testing.assert_allclose(r.gap, delta, rtol=1e-12)
    assert not r.C0 and not r.G1 and not r.C1 and r.level == "none"
    # a gap below the tolerance counts as C0
    r2 = edge_continuity(s1, moved, "u1", "u0", rel_tol=2 * delta / r.size)
    assert r2.C0 and r2.rel_tol == 2 * delta / r.size
    with pytest.warns(DeprecationWarning, match="rel_tol"):          # the old name, one release
        assert edge_continuity(s1, moved, "u1", "u0", tol=2 * delta / r.size) == r2
    assert "gap" in str(r)


def test_collapsed_edge_is_skipped_for_the_angle():
    """A patch whose edge u = 0 is collapsed to a point (a triangle-like patch): the
    tangent along the edge vanishes, no tangent plane can be compared there."""
    i, j = np.meshgrid(np.arange(3.0), np.arange(3.0), indexing="ij")
    P = np.stack([i, j * i / 2, 0 * i], axis=-1)                 # row i = 0 collapses to the origin
    s = BezierSurface(P)
    r = edge_continuity(s, s, "u0", "u0")
    assert np.isnan(r.normal_angle) and not r.G1 and r.C0


def test_rational_halves():
    """A NURBS cylinder split at a quarter turn: the halves are C1."""
    s2 = np.sqrt(0.5)
    circle = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    w = np.array([1, s2, 1, s2, 1, s2, 1, s2, 1])
    P = np.empty((9, 2, 3))
    P[:, :, :2] = circle[:, None, :]
    P[:, 0, 2], P[:, 1, 2] = 0.0, 2.0
    cyl = BSplineSurface(P, 2, 1, [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1], [0, 0, 1, 1],
                         np.repeat(w[:, None], 2, axis=1))
    a, b = cyl.split("u", 0.25)
    r = edge_continuity(a, b, "u1", "u0")
    assert r.C1 and r.G1, str(r)
    # the closing seam u = 1 -> u = 0 of the full cylinder: G1 (the circle is smooth) but the
    # parametric speed differs only if the arcs differ; the 9-point circle is C1 there too
    r = edge_continuity(cyl, cyl, "u1", "u0")
    assert r.C0 and r.G1


def test_errors():
    s = BezierSurface(np.random.default_rng(0).normal(size=(3, 3, 3)))
    flat = BezierSurface(np.random.default_rng(0).normal(size=(3, 3, 2)))
    line = BezierSurface(np.random.default_rng(0).normal(size=(3, 3, 1)))
    with pytest.raises(CagdError, match="s1"):
        edge_continuity("x", s, "u1", "u0")
    with pytest.raises(CagdError, match="s2"):
        edge_continuity(s, None, "u1", "u0")
    with pytest.raises(CagdError, match="s2"):
        edge_continuity(s, flat, "u1", "u0")
    with pytest.raises(CagdError, match="edge1"):
        edge_continuity(s, s, "u2", "u0")
    with pytest.raises(CagdError, match="edge2"):
        edge_continuity(s, s, "u1", "left")
    with pytest.raises(CagdError, match="samples"):
        edge_continuity(s, s, "u1", "u0", samples=1)
    with pytest.raises(CagdError, match="rel_tol"):
        edge_continuity(s, s, "u1", "u0", rel_tol=0.0)
    with pytest.raises(CagdError, match="rel_tol"):
        edge_continuity(s, s, "u1", "u0", rel_tol=np.nan)
    with pytest.raises(CagdError, match="angle_tol"):
        edge_continuity(s, s, "u1", "u0", angle_tol=-1.0)
    with pytest.raises(CagdError, match="reverse"):
        edge_continuity(s, s, "u1", "u0", reverse="yes")
    with pytest.raises(CagdError, match="s1"):
        edge_continuity(line, line, "u1", "u0")


def test_triangles_are_sent_to_triangle_continuity():
    tri = cagd.BezierTriangle(np.arange(30.0).reshape(10, 3) % 7)
    with pytest.raises(cagd.CagdError, match="triangle_continuity"):
        cagd.edge_continuity(tri, tri, "u0", "u0")


def test_cross_derivative_collapsing_at_a_corner_is_not_a_flipped_normal():
    # found by hypothesis (numpy 1.24 run): the net's last column collapses to one point, so at
    # v = 1 the cross-boundary derivative is 0 and T x D is rounding noise of either sign
    P = np.array([[[1.0, 0.0], [0.0, 1.0], [0.6875, 0.3125]], [[0.9, 0.0], [0.0, 0.9], [0.6875, 0.3125]]])
    s = BSplineSurface(P, 1, 2, [1.0, 1.0, 2.0, 2.0], None)
    left, right = s.split("u", 1.06875)
    r = edge_continuity(left, right, "u1", "u0")
    assert r.C1 and r.G1 and r.normal_angle <= 1e-9, str(r)
