"""cagd.gordon: surfaces through curve networks, against independent oracles: the
surface a network was cut from (spline interpolation reproduces it), cagd's Coons
patch (a 2 x 2 Gordon surface is the bilinear Coons patch), certified closest points
of the network curves, build123d's make_gordon_surface, and bad networks."""
import dataclasses

import numpy as np
import pytest

import cagd
from cagd.knots import vectors as kv

GRID = np.linspace(0.0, 1.0, 21)
SAMPLES = 200           # closest-point samples per network curve
ROUNDING = 1e-12 * 100  # closest-point distances of exact cases carry rounding of the 100 mm size
NET_TOL = 1e-4          # interpolants of 20-30 points of one surface miss each other by up to ~5e-6


def height(u, v):
    """A smooth 100 mm surface."""
    return np.stack([100 * u, 100 * v, 10 * np.sin(3 * u) * np.cos(2 * v) + 5 * u * v], axis=-1)


def interpolated_network(m, n, points=30):
    """m profiles (v = const) and n guides (u = const) of ``height``, each interpolated
    through ``points`` points (chord parameters: the curves meet at differing parameters)."""
    t = np.linspace(0.0, 1.0, points)
    profiles = [cagd.interpolate(height(t, np.full_like(t, v))) for v in np.linspace(0, 1, m)]
    guides = [cagd.interpolate(height(np.full_like(t, u), t)) for u in np.linspace(0, 1, n)]
    return profiles, guides


def off_surface(surface, curves):
    """Largest certified closest-point distance of samples of the curves from the surface."""
    pts = np.concatenate([c(np.linspace(*c.domain, SAMPLES)) for c in curves])
    res = cagd.closest_point(surface, pts)
    assert res.converged
    return float(res.distances.max())


def spread(a, b):
    """Largest distance of grid points of surface a from surface b (certified)."""
    return float(cagd.closest_point(b, a.grid(GRID, GRID).reshape(-1, 3)).distances.max())


@pytest.fixture(scope="module")
def bezier_patch():
    rng = np.random.default_rng(1)
    P = rng.random((4, 4, 3)) * 10
    P[..., 0] += np.arange(4)[:, None] * 10
    P[..., 1] += np.arange(4)[None, :] * 10
    return cagd.BezierSurface(P)


def iso_network(surface, us, vs):
    N = surface.to_nurbs()
    return [N.isocurve("u", v) for v in vs], [N.isocurve("v", u) for u in us]


def test_bicubic_bezier_patch_is_reproduced_from_its_4x4_iso_curves(bezier_patch):
    ts = np.array([0.0, 1 / 3, 2 / 3, 1.0])
    r = cagd.gordon(*iso_network(bezier_patch, ts, ts))
    assert r.converged and r.reparametrised == ()
    assert np.abs(r.surface.grid(GRID, GRID) - bezier_patch.grid(GRID, GRID)).max() <= 1e-10
    assert np.allclose(r.intersections[..., 0], ts[None, :], atol=1e-12)
    assert np.allclose(r.intersections[..., 1], ts[:, None], atol=1e-12)
    assert r.max_error <= 1e-10


def test_bspline_surface_in_the_interpolation_space_is_reproduced():
    """Iso-curves at us, vs of a bicubic B-spline surface whose knots are the averaged
    knots of us, vs (Piegl & Tiller eq. 9.8): skinning reproduces it in both directions."""
    us, vs = np.array([0.0, 0.2, 0.45, 0.7, 1.0]), np.array([0.0, 0.3, 0.5, 0.8, 1.0])
    rng = np.random.default_rng(7)
    P = np.stack(np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij"), axis=-1) * 20
    P = np.concatenate([P, rng.random((5, 5, 1)) * 15], axis=-1)
    S = cagd.BSplineSurface(P, 3, 3, kv.averaged(us, 3), kv.averaged(vs, 3))
    r = cagd.gordon(*iso_network(S, us, vs))
    assert r.converged and r.reparametrised == ()
    assert np.abs(r.surface.grid(GRID, GRID) - S.grid(GRID, GRID)).max() <= 1e-10


def test_coons_boundary_gives_the_coons_patch():
    c0 = cagd.BezierCurve([[0, 0, 0], [3, 1, 1], [7, -1, 0], [10, 0, 0]])
    c1 = cagd.BezierCurve([[0, 10, 0], [4, 11, 2], [10, 10, 1]])
    d0 = cagd.BezierCurve([[0, 0, 0], [-1, 5, 2], [0, 10, 0]])
    d1 = cagd.BSplineCurve([[10, 0, 0], [11, 3, 0], [12, 7, -1], [11, 9, 0], [10, 10, 1]], 3)
    coons = cagd.CoonsPatch(c0, c1, d0, d1)
    r = cagd.gordon([c0, c1], [d0, d1])
    assert r.converged
    assert np.abs(r.surface.grid(GRID, GRID) - coons.grid(GRID, GRID)).max() <= 1e-10
    assert r.surface.degree_u == 3 and r.surface.degree_v == 3


@pytest.mark.parametrize("m, n", [(3, 3), (4, 5)])
def test_network_curves_lie_on_the_surface_within_max_error(m, n):
    profiles, guides = interpolated_network(m, n)
    r = cagd.gordon(profiles, guides, NET_TOL, certify=True)
    assert r.converged, r.message
    assert r.certified_error <= r.max_error
    assert set(r.reparametrised) == {"profiles", "guides"}      # chord parameters differ per curve
    assert 0 < r.max_error <= NET_TOL
    off = off_surface(r.surface, profiles + guides)
    assert off <= r.max_error and 0.5 * off <= r.certified_error <= 2 * off
    assert r.max_miss <= NET_TOL
    # the intersection grid: every profile at v_i meets every guide at u_j
    uv = r.intersections.reshape(-1, 2)
    X = r.surface(uv[:, 0], uv[:, 1]).reshape(m, n, 3)
    for i, f in enumerate(profiles):
        assert cagd.closest_point(f, X[i]).distances.max() <= r.max_error
    # the surface stays close to the one the network was cut from (no wild interior; 3x3: 0.027)
    cut = cagd.fit_surface(height(*np.meshgrid(GRID, GRID, indexing="ij")), 1e-3).surface
    assert spread(r.surface, cut) < 0.1


@pytest.mark.parametrize("network", ["iso", "interpolated"])
def test_shuffled_and_reversed_curves_give_the_same_surface(bezier_patch, network):
    if network == "iso":
        ts = np.array([0.0, 1 / 3, 2 / 3, 1.0])
        profiles, guides = iso_network(bezier_patch, ts, ts)
        same = 1e-10
    else:
        profiles, guides = interpolated_network(4, 4, 20)
        same = NET_TOL
    a = cagd.gordon(profiles, guides, NET_TOL)
    P = [profiles[2], profiles[0].reversed(), profiles[3], profiles[1]]
    G = [guides[1].reversed(), guides[3], guides[0], guides[2].reversed()]
    b = cagd.gordon(P, G, NET_TOL)
    assert b.profile_order.tolist() == [1, 3, 0, 2] and b.guide_order.tolist() == [2, 0, 3, 1]
    assert b.reversed_profiles.tolist() == [False, True, False, False]
    assert b.reversed_guides.tolist() == [True, False, False, True]
    assert spread(a.surface, b.surface) <= same and spread(b.surface, a.surface) <= same


def test_profile_zero_reversed_flips_u():
    profiles, guides = interpolated_network(3, 3, 20)
    a = cagd.gordon(profiles, guides, NET_TOL)
    b = cagd.gordon([c.reversed() for c in profiles], guides, NET_TOL)
    assert b.reversed_profiles.tolist() == [False, False, False]        # profile 0 keeps its direction
    assert np.abs(b.surface.grid(1 - GRID, GRID) - a.surface.grid(GRID, GRID)).max() <= NET_TOL


def test_near_miss_within_tol_is_accepted_and_reported(bezier_patch):
    ts = np.array([0.0, 1 / 3, 2 / 3, 1.0])
    profiles, guides = iso_network(bezier_patch, ts, ts)
    shift = np.array([0.0, 0.0, 4e-7])
    moved = guides[:1] + [guides[1].translated(shift)] + guides[2:]
    r = cagd.gordon(profiles, moved, tol=1e-6)
    assert 3e-7 <= r.max_miss <= 5e-7
    assert off_surface(r.surface, profiles + moved) <= r.max_error <= 1e-6
    with pytest.raises(cagd.CagdError, match=r"profiles\[\d\], guides\[1\]: do not meet"):
        cagd.gordon(profiles, moved, tol=1e-8)


def test_build123d_agrees_with_fewer_poles():
    bd = pytest.importorskip("build123d")
    from OCP.BRep import BRep_Tool
    from cagd.occ import from_occ, make_edge
    profiles, guides = interpolated_network(4, 4)
    r = cagd.gordon(profiles, guides, NET_TOL)
    face = bd.Face.make_gordon_surface([bd.Edge(make_edge(c)) for c in profiles],
                                       [bd.Edge(make_edge(c)) for c in guides], NET_TOL)
    theirs = from_occ(BRep_Tool.Surface_s(face.wrapped))
    their_error = off_surface(theirs, profiles + guides)
    assert off_surface(r.surface, profiles + guides) <= r.max_error
    # the surfaces agree: on the network within their errors, and in between closely
    X = np.concatenate([c(np.linspace(*c.domain, 50)) for c in profiles + guides])
    feet = cagd.closest_point(r.surface, X).feet
    assert cagd.closest_point(theirs, feet).distances.max() <= r.max_error + their_error
    assert spread(r.surface, theirs) <= 1e-4       # measured 3.2e-6 (both about 5e-6 off the network)
    ours, their_poles = r.surface.control_points.shape[:2], theirs.control_points.shape[:2]
    assert ours[0] * ours[1] <= their_poles[0] * their_poles[1]


# --- bad input --------------------------------------------------------------------------
def test_fewer_than_two_curves_per_family():
    profiles, guides = interpolated_network(3, 3, 10)
    with pytest.raises(cagd.CagdError, match=r"^profiles: need 2"):
        cagd.gordon(profiles[:1], guides)
    with pytest.raises(cagd.CagdError, match=r"^guides: need 2"):
        cagd.gordon(profiles, guides[:1])
    with pytest.raises(cagd.CagdError, match=r"^profiles\[1\]: expected a cagd curve"):
        cagd.gordon([profiles[0], "x"], guides)
    with pytest.raises(cagd.CagdError, match="tol"):
        cagd.gordon(profiles, guides, tol=0)


def test_profile_missing_a_guide():
    profiles, guides = interpolated_network(3, 3)
    t = np.linspace(0.0, 0.4, 10)                 # ends before guides 1 and 2
    short = cagd.interpolate(height(t, np.full_like(t, 0.5)))
    with pytest.raises(cagd.CagdError, match=r"profiles\[1\], guides\[1\]: do not meet"):
        cagd.gordon([profiles[0], short, profiles[2]], guides, NET_TOL)


def test_two_intersections_per_pair():
    w = np.linspace(-1.0, 1.0, 41)                # a guide snaking across the middle profile 3 times
    snake = np.stack([50 + 10 * w, 50 + 50 * (2 * w ** 3 - w), np.zeros_like(w)], axis=1)
    flat = [cagd.BSplineCurve([[0, y, 0], [100, y, 0]], 1) for y in (0.0, 50.0, 100.0)]
    sides = [cagd.BSplineCurve([[x, 0, 0], [x, 100, 0]], 1) for x in (0.0, 100.0)]
    with pytest.raises(cagd.CagdError, match=r"profiles\[1\], guides\[1\]: meet 3 times"):
        cagd.gordon(flat, [sides[0], cagd.interpolate(snake), sides[1]])


S2 = np.sqrt(0.5)
CIRCLE_KNOTS = [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1]


def nurbs_circle(x, r):
    """The 9-pole quadratic NURBS circle of radius r about the x-axis in the plane at x."""
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float) * r
    return cagd.BSplineCurve(np.column_stack([np.full(9, x), P]), 2, CIRCLE_KNOTS, [1, S2, 1, S2, 1, S2, 1, S2, 1])


def fuselage(angles_deg=(20, 100, 200, 290)):
    """Circles of radius 20-25 at x = 0..100 (rational profiles, one construction) and
    cubic guides through them at fixed angles (polynomial)."""
    xs = np.array([0.0, 30.0, 60.0, 100.0])
    radii = 20 + 5 * np.sin(np.pi * xs / 100)
    th = np.radians(angles_deg)
    guides = [cagd.interpolate(np.column_stack([xs, radii * np.cos(t), radii * np.sin(t)])) for t in th]
    return [nurbs_circle(x, r) for x, r in zip(xs, radii)], guides, xs, radii


def test_fuselage_of_nurbs_circles_is_the_exact_rational_surface_smooth_across_the_seam():
    """Closed rational profiles: the surface contains every circle exactly (their implicit
    equation x = x_i, y^2 + z^2 = r_i^2 on S(u, v_i) to 1e-12 of the size), every curve
    within max_error by certified closest points, and the seam (guides[0], inside a
    circle's span) is C2: S_u and S_uu agree at u = 0 and u = 1."""
    rings, guides, xs, radii = fuselage()
    r = cagd.gordon(rings, guides, 1e-6)
    assert r.converged and r.reparametrised == () and r.message == ""
    S = r.surface
    assert S.is_rational and r.max_error <= 1e-9
    u = np.linspace(0.0, 1.0, 400)
    for i, v in enumerate(r.intersections[:, 0, 1]):
        p = S(u, np.full_like(u, v))
        assert np.abs(np.hypot(p[:, 1], p[:, 2]) - radii[i]).max() <= 1e-12 * 100
        assert np.abs(p[:, 0] - xs[i]).max() <= 1e-12 * 100
    assert off_surface(S, rings + guides) <= r.max_error + ROUNDING
    v = np.linspace(0.0, 1.0, 60)
    for k in (0, 1, 2):
        a, b = S.derivative(np.zeros_like(v), v, k, 0), S.derivative(np.ones_like(v), v, k, 0)
        assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max(), k


def conic_arcs(weights):
    """Rational quadratic arcs over [0, 100] in the planes y = 0, 40, 100 (middle weights
    ``weights``), a straight guide at each end and one through the arcs' midpoints."""
    ys = np.array([0.0, 40.0, 100.0])
    arcs = [cagd.BSplineCurve([[0, y, 0], [50, y, 20], [100, y, 0]], 2, weights=[1, w, 1])
            for y, w in zip(ys, weights)]
    mid = np.array([a(0.5) for a in arcs])
    guides = [cagd.BSplineCurve([[0, 0, 0], [0, 100, 0]], 1), cagd.interpolate(mid, 2),
              cagd.BSplineCurve([[100, 0, 0], [100, 100, 0]], 1)]
    return arcs, guides


def test_arcs_with_matching_weights_give_the_exact_rational_surface():
    arcs, guides = conic_arcs([0.7, 0.7, 0.7])
    r = cagd.gordon(arcs, guides)
    assert r.converged and r.reparametrised == () and r.surface.is_rational
    u = np.linspace(0.0, 1.0, 101)
    for arc, v in zip(arcs, r.intersections[:, 0, 1]):
        assert np.abs(r.surface(u, np.full_like(u, v)) - arc(u)).max() <= 1e-12 * 100
    assert off_surface(r.surface, arcs + guides) <= r.max_error + ROUNDING and r.max_error <= 1e-9


def test_arcs_with_other_weights_are_approximated_and_reported():
    """Weights 0.5 / 0.9 / 1.6 at the middle crossing are not one constant per curve:
    the arcs are fitted by polynomial B-splines within a share of tol, which the result
    says; the network still lies on the surface within max_error (certified)."""
    arcs, guides = conic_arcs([0.5, 0.9, 1.6])
    r = cagd.gordon(arcs, guides, 1e-5)
    assert r.converged, r.message
    assert "profiles" in r.reparametrised and not r.surface.is_rational
    assert "rational curves approximated by polynomial B-splines" in r.message
    assert off_surface(r.surface, arcs + guides) <= r.max_error <= 1e-5


def test_equal_weights_are_a_polynomial_curve():
    arcs, guides = conic_arcs([1.0, 1.0, 1.0])
    heavy = [a.with_weights([3.0, 3.0, 3.0]) for a in arcs]
    a, b = cagd.gordon(arcs, guides), cagd.gordon(heavy, guides)
    assert not b.surface.is_rational and b.reparametrised == ()
    assert np.array_equal(a.surface.control_points, b.surface.control_points)


def test_closed_network_of_iso_curves_is_c2_across_the_seam():
    """Iso-curves of a bicubic closed (periodic) in u meet at common parameters, so the
    rings are used exactly; the skin across the guides is periodic, so the seam is C2
    (a clamped skin leaves a crease: S_u differs by ~20% across it)."""
    rng = np.random.default_rng(5)
    ang = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
    P = np.stack([np.stack([(20 + 3 * rng.random(8)) * np.cos(ang), (20 + 3 * rng.random(8)) * np.sin(ang),
                            np.full(8, z)], axis=-1) for z in (0, 25, 50, 75, 100)], axis=1)   # (8, 5, 3)
    T = cagd.BSplineSurface(P, 3, 3, np.linspace(0, 1, 9), None, periodic_u=True)
    rings = [T.isocurve("u", v) for v in (0.0, 0.3, 0.6, 1.0)]
    guides = [T.isocurve("v", u) for u in (0.05, 0.3, 0.55, 0.8)]
    r = cagd.gordon(rings, guides, 1e-6)
    assert r.converged and r.reparametrised == ()
    S, v = r.surface, np.linspace(0.0, 1.0, 60)
    for k in (0, 1, 2):
        a, b = S.derivative(np.zeros_like(v), v, k, 0), S.derivative(np.ones_like(v), v, k, 0)
        assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max(), k
    assert off_surface(S, rings + guides) <= r.max_error + ROUNDING and r.max_error <= 1e-9


def tube(u, v):
    """A closed tube of radius 18-27 mm, 100 mm long (u around, v along)."""
    r = 20 + 5 * np.sin(np.pi * v) + 2 * np.cos(4 * np.pi * u) * v
    return np.stack([r * np.cos(2 * np.pi * u), r * np.sin(2 * np.pi * u), 100 * v], axis=-1)


def tube_network():
    """Closed rings (each starting at another angle) and open guides along the tube."""
    t = np.linspace(0.0, 1.0, 61)
    rings = [cagd.interpolate(tube(np.mod(t + 0.13 * k, 1.0), np.full_like(t, v)))
             for k, v in enumerate((0.0, 0.3, 0.7, 1.0))]
    guides = [cagd.interpolate(tube(np.full_like(t, u), t)) for u in (0.1, 0.35, 0.6, 0.85)]
    return rings, guides


CLOSED_TOL = 1e-3      # 61-point interpolants of the tube miss each other by up to ~1.4e-4


def test_closed_profiles_give_a_closed_surface_through_the_network():
    rings, guides = tube_network()
    r = cagd.gordon(rings, guides, CLOSED_TOL)
    assert r.converged, r.message
    assert r.guide_order.tolist() == [0, 1, 2, 3, 0]            # the seam guide repeated at u = 1
    assert r.intersections.shape == (4, 5, 2) and r.intersections[0, -1, 0] == 1.0
    v = np.linspace(0.0, 1.0, 50)
    S = r.surface
    assert np.abs(S(np.zeros_like(v), v) - S(np.ones_like(v), v)).max() <= 1e-9      # closed along the seam
    seam = cagd.closest_point(guides[0], S(np.zeros_like(v), v)).distances         # ... which is guides[0]
    assert seam.max() <= r.max_error
    assert off_surface(S, rings + guides) <= r.max_error <= CLOSED_TOL


def test_closed_network_reversed_and_shuffled_with_the_same_seam_guide():
    rings, guides = tube_network()
    a = cagd.gordon(rings, guides, CLOSED_TOL)
    b = cagd.gordon([rings[2].reversed(), rings[0], rings[3], rings[1].reversed()],
                    [guides[0], guides[3], guides[1].reversed(), guides[2]], CLOSED_TOL)
    assert b.converged and b.reversed_profiles.tolist() == [False, True, True, False]
    assert b.guide_order.tolist() == [0, 1, 3, 2, 0]             # around the other way, as profile 0 runs
    assert spread(a.surface, b.surface) <= CLOSED_TOL and spread(b.surface, a.surface) <= CLOSED_TOL


def test_closed_guides_and_mixed_profiles_are_rejected():
    rings, guides = tube_network()
    with pytest.raises(cagd.CagdError, match=r"^guides\[0\]: closed guides are not supported"):
        cagd.gordon(guides, rings, CLOSED_TOL)
    t = np.linspace(0.0, 0.9, 50)
    arc = cagd.interpolate(tube(t, np.full_like(t, 0.3)))
    with pytest.raises(cagd.CagdError, match=r"^profiles\[1\]: is open while profiles\[0\] is not"):
        cagd.gordon([rings[0], arc] + rings[2:], guides, CLOSED_TOL)


def test_curve_not_ending_on_the_outer_curves():
    flat = [cagd.BSplineCurve([[0, y, 0], [100, y, 0]], 1) for y in (0.0, 100.0)]
    sides = [cagd.BSplineCurve([[x, 0, 0], [x, 100, 0]], 1) for x in (0.0, 100.0)]
    long = cagd.BSplineCurve([[0, 100, 0], [130, 100, 0]], 1)      # runs past guide 1
    with pytest.raises(cagd.CagdError, match=r"profiles\[1\]: its end is .* from where it meets guides\[1\]"):
        cagd.gordon([flat[0], long], sides)


def test_result_is_a_frozen_value(bezier_patch):
    ts = np.array([0.0, 0.5, 1.0])
    r = cagd.gordon(*iso_network(bezier_patch, ts, ts))
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.max_error = 0.0
    with pytest.raises(ValueError):
        r.intersections[0, 0, 0] = 1.0
    assert isinstance(r, cagd.GordonSurface) and isinstance(r.surface, cagd.BSplineSurface)


def test_unevenly_parametrised_profiles_are_refitted_onto_common_parameters():
    """Profiles of one surface traversed at increasingly uneven speeds (u = t^1 .. t^2.5):
    they meet guide j at very different parameters; the refit puts them on common ones and
    the curves still lie on the surface within max_error (certified closest points)."""
    t = np.linspace(0.0, 1.0, 40)
    profiles = [cagd.interpolate(height(t ** (1 + 0.5 * k), np.full_like(t, v)), parameters=t)
                for k, v in enumerate((0.0, 0.3, 0.6, 1.0))]
    guides = [cagd.interpolate(height(np.full_like(t, u), t), parameters=t) for u in (0, 0.25, 0.5, 0.75, 1)]
    r = cagd.gordon(profiles, guides, NET_TOL)
    assert r.converged, r.message
    assert r.reparametrised == ("profiles",)          # the guides meet the profiles at equal parameters
    assert off_surface(r.surface, profiles + guides) <= r.max_error <= NET_TOL


def test_polyline_profiles_keep_their_corners_in_the_refit():
    """Polylines (degree 1, a corner at every point) meeting the guides at differing
    parameters: the refit keeps each corner as a knot of full multiplicity at its exact
    preimage, so it converges with few poles (averaging the corners away left 1,082 poles
    and max_error 8e-4 at tol 1e-6); the network lies on the surface within max_error."""
    t = np.array([0, 0.2, 0.45, 0.6, 0.8, 1.0])
    profiles = [cagd.interpolate(height(t, np.full_like(t, v)), 1) for v in (0.0, 0.35, 0.7, 1.0)]
    guides = [cagd.interpolate(np.array([p(min(1.0, s + 0.04 * i * (0 < s < 1))) for i, p in enumerate(profiles)]), 3)
              for s in (0.0, 0.3, 0.62, 1.0)]
    r = cagd.gordon(profiles, guides, 1e-6)
    assert r.converged and "profiles" in r.reparametrised
    assert r.surface.control_points.shape[0] <= 60
    assert off_surface(r.surface, profiles + guides) <= r.max_error <= 1e-6


def test_reparametrisation_functions_are_monotone_and_interpolate():
    """Brute force on 10^4 samples: the C2 spline when its coefficients increase, else the
    Fritsch-Carlson cubic; both hit the data and never decrease."""
    from cagd.surfaces.gordon import _pchip, _reparametrisation
    s = np.linspace(0.0, 1.0, 10001)
    for x, y in ((np.array([0, 0.3, 0.7, 1.0]), np.array([0, 0.25, 0.72, 1.0])),
                 (np.array([0, 0.1, 0.5, 0.9, 1.0]), np.array([0, 0.5, 0.55, 0.6, 1.0]))):
        for make in (_reparametrisation, _pchip):
            r = make(x, y)
            assert np.abs(r(x) - y).max() <= 1e-14
            assert np.diff(r(s)).min() >= 0
