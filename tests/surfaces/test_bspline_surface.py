"""B-spline and NURBS surfaces against scipy.interpolate (one direction at a time),
geomdl, the direct double sum of Cox-de Boor products, the seed's uniform bicubic
matrix form (seed 000, 5.3.3) and the invariance of the surface under every
per-direction operation."""
import itertools

import numpy as np
import pytest
from geomdl import BSpline as GeomdlBSpline
from geomdl import NURBS as GeomdlNURBS
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cagd import BezierCurve, BSplineCurve, BSplineSurface, CagdError
from cagd.knots import uniform

from surface_strategies import (KINDS, bspline_surfaces, direct_surface, domain_parameters,
                                full_knots, interior_parameters, min_span, net_size, regular, relative,
                                scipy_homogeneous_grid, unwrapped, weight_ratio)

SETTINGS = settings(max_examples=40, deadline=None)


def derivative_bound(surface, k: int, l: int, ref: np.ndarray) -> float:
    """Rounding allowance for the partial S_(u^k v^l): 1e-12 of its size plus
    1e-13 |P| (p/h_u)^k (q/h_v)^l, the size of the basis-derivative products
    (h = the shortest span of the direction)."""
    pu = surface.degree_u / min_span(surface, "u")
    pv = surface.degree_v / min_span(surface, "v")
    return 1e-12 * float(np.abs(ref).max()) + 1e-13 * net_size(surface) * pu ** k * pv ** l


def assert_same_surface(s1, s2, us, vs, rtol=1e-11, map_u=None, map_v=None):
    """s1 on the grid us x vs equals s2 at the mapped parameters (relative to s1's net)."""
    a = s1(us[:, None], vs[None, :])
    uu = us if map_u is None else map_u(us)
    vv = vs if map_v is None else map_v(vs)
    b = s2(uu[:, None], vv[None, :])
    assert a.shape == b.shape
    scale = max(net_size(s1), float(np.abs(a).max()))
    assert np.abs(a - b).max() <= rtol * scale, np.abs(a - b).max() / scale


# --- evaluation against independent oracles -------------------------------------------------

@SETTINGS
@given(surface=bspline_surfaces(rational=False))
def test_partials_vs_scipy_per_direction(surface):
    """All partials up to (min(p,3), min(q,3)) on a grid including the knots, against
    scipy.interpolate.BSpline applied to the rows and then to the columns."""
    us, vs = domain_parameters(surface, 7)
    if surface.periodic_u:
        us = us[us < surface.domain[0][1]]         # the periodic end is the start again
    if surface.periodic_v:
        vs = vs[vs < surface.domain[1][1]]
    du, dv = min(surface.degree_u, 3), min(surface.degree_v, 3)
    ref = scipy_homogeneous_grid(surface, us, vs, du, dv)
    mine = surface.derivatives(us[:, None], vs[None, :], du, dv)
    assert mine.shape == ref.shape
    for k, l in itertools.product(range(du + 1), range(dv + 1)):
        err = np.abs(mine[k, l] - ref[k, l]).max()
        assert err <= derivative_bound(surface, k, l, ref[k, l]), (k, l, err)


@st.composite
def grid_parameters(draw, surface, which: int) -> np.ndarray:
    """Up to 40 parameters of one direction: uniform draws, knots of the domain, repeats,
    sorted or in a drawn order (the grid sorts them and splits them into blocks)."""
    a, b = surface.domain[which]
    periodic = surface.periodic_u if which == 0 else surface.periodic_v
    knots = np.unique(full_knots(surface, "uv"[which]))
    knots = knots[(knots >= a) & (knots < b if periodic else knots <= b)]
    fractions = draw(st.lists(st.floats(0.0, 1.0, exclude_max=periodic), min_size=1, max_size=30))
    t = np.concatenate([a + (b - a) * np.array(fractions), draw(st.lists(st.sampled_from(list(knots)), max_size=6))])
    t = np.minimum(t, np.nextafter(b, a)) if periodic else np.clip(t, a, b)
    t = np.concatenate([t, t[:draw(st.integers(0, 3))]])                    # repeated parameters
    if draw(st.booleans()):
        return np.sort(t)
    return t[np.array(draw(st.permutations(range(len(t)))))]


@settings(max_examples=60, deadline=None)
@given(surface=bspline_surfaces(), data=st.data())
def test_grid_blocks_vs_scipy_per_direction(surface, data):
    """The grid's blocks (sorted parameters cut into chunks of pole rows and products
    of dense local bases, banded passes where sparse; the block sizes drawn down to one
    parameter) against scipy.interpolate.BSpline applied to the rows and then to the
    columns, all partials up to (2, 2): homogeneous values divided (rational points) or
    put through rational_partials (rational derivatives); ``grid``'s (du, dv) partial
    alone the same."""
    from unittest import mock

    from cagd.surfaces import bspline as sb
    from cagd.surfaces.base import rational_partials
    us, vs = data.draw(grid_parameters(surface, 0)), data.draw(grid_parameters(surface, 1))
    du, dv = data.draw(st.integers(0, 2)), data.draw(st.integers(0, 2))
    sizes = {name: data.draw(st.sampled_from(choices), label=name) for name, choices in (
        ("_GRID_VALUES", [1, 40, 300, 1 << 20]), ("_GRID_BLOCK", [1, 13, 200, 1 << 16]),
        ("_GRID_ROWS", [1, 6, 32]), ("_GRID_GEMM_MIN", [0, 50, 1 << 40]))}
    with mock.patch.multiple(sb, **sizes):
        got = surface._grid(us, vs, du, dv)
        last = surface.grid(us, vs, du, dv)          # the (du, dv) partial alone when polynomial
    hom = scipy_homogeneous_grid(surface, us, vs, du, dv)
    if not surface.is_rational:
        ref = hom
    elif du == dv == 0:
        ref = hom[..., :-1] / hom[..., -1:]
    else:
        ref = rational_partials(hom)
    assert got.shape == ref.shape
    ratio = weight_ratio(surface) ** (du + dv + 1)
    for k, l in itertools.product(range(du + 1), range(dv + 1)):
        err = np.abs(got[k, l] - ref[k, l]).max()
        assert err <= derivative_bound(surface, k, l, ref[k, l]) * ratio, (k, l, err)
    assert np.abs(last - ref[du, dv]).max() <= derivative_bound(surface, du, dv, ref[du, dv]) * ratio


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("sizes", [{"_GRID_VALUES": 1 << 20}, {"_GRID_VALUES": 500, "_GRID_BLOCK": 40, "_GRID_ROWS": 1},
                                   {"_GRID_VALUES": 5000, "_GRID_BLOCK": 700, "_GRID_GEMM_MIN": 1 << 40}])
def test_grid_of_sparse_parameters_on_a_large_net(rational, sizes):
    """A 70 x 60-pole net with knots of multiplicity up to the degree, parameters in
    clusters far apart (the pole rows of a chunk are then gathered, not a range) and in
    a drawn order, against scipy per direction (points and first partials)."""
    from unittest import mock

    from cagd.surfaces import bspline as sb
    from cagd.surfaces.base import rational_partials
    rng = np.random.default_rng(16)
    p, q, nu, nv = 3, 2, 70, 60

    def knots(n, deg):
        inner = np.sort(rng.random(n - deg - 1))
        inner[5:5 + deg] = inner[5]                      # multiplicity deg
        inner[20:22] = inner[20]
        return np.concatenate([np.zeros(deg + 1), inner, np.ones(deg + 1)])
    ku, kv = knots(nu, p), knots(nv, q)
    W = rng.uniform(0.5, 2.0, (nu, nv)) if rational else None
    s = BSplineSurface(rng.uniform(-1, 1, (nu, nv, 3)), p, q, ku, kv, W)
    us = rng.permutation(np.concatenate([rng.uniform(0.0, 0.05, 7), rng.uniform(0.5, 0.52, 9), [0.9, 1.0, ku[9]]]))
    vs = rng.permutation(np.concatenate([rng.uniform(0.1, 0.12, 5), rng.uniform(0.7, 1.0, 40), [0.0, kv[30]]]))
    with mock.patch.multiple(sb, **sizes):
        got = s._grid(us, vs, 1, 1)
        points = s.grid(us, vs)
    hom = scipy_homogeneous_grid(s, us, vs, 1, 1)
    ref = rational_partials(hom) if rational else hom
    scale = np.abs(ref).max(axis=(2, 3, 4))
    assert (np.abs(got - ref).max(axis=(2, 3, 4)) <= 1e-12 * scale).all()
    assert relative(points, hom[0, 0, ..., :-1] / hom[0, 0, ..., -1:] if rational else hom[0, 0]) <= 1e-14


@SETTINGS
@given(surface=bspline_surfaces(), data=st.data())
def test_points_vs_direct_cox_de_boor_double_sum(surface, data):
    """Element-wise S(u, v) against sum_i sum_j N_i(u) N_j(v) w_ij P_ij / sum N N w
    with the textbook recursion (seed 000, 5.3.3; seed 003, 2.4)."""
    (a, b), (c, d) = surface.domain
    u = np.array(data.draw(st.lists(st.floats(a, b), min_size=1, max_size=20)))
    v = np.array(data.draw(st.lists(st.floats(c, d), min_size=len(u), max_size=len(u))))
    # both ends and both corners too
    u = np.concatenate([u, [a, b, a, b]])
    v = np.concatenate([v, [c, c, d, d]])
    if surface.periodic_u:
        u = np.where(u >= b, a, u)
    if surface.periodic_v:
        v = np.where(v >= d, c, v)
    got = surface(u, v)
    ref = direct_surface(surface, u, v)
    assert relative(got, ref, net_size(surface)) <= 1e-12 * weight_ratio(surface)


def geomdl_surface(surface):
    """geomdl takes the unwrapped homogeneous net (w P, w) as ``ctrlptsw``, v fastest."""
    flat = unwrapped(surface)
    hom = flat.homogeneous_control_points
    g = (GeomdlNURBS if surface.is_rational else GeomdlBSpline).Surface(normalize_kv=False)
    g.degree_u, g.degree_v = surface.degree_u, surface.degree_v
    g.ctrlpts_size_u, g.ctrlpts_size_v = hom.shape[0], hom.shape[1]
    if surface.is_rational:
        g.ctrlptsw = hom.reshape(-1, hom.shape[2]).tolist()
    else:
        g.ctrlpts = hom.reshape(-1, hom.shape[2]).tolist()
    g.knotvector_u = flat.knots_u.tolist()
    g.knotvector_v = flat.knots_v.tolist()
    return g


@settings(max_examples=25, deadline=None)
@given(surface=bspline_surfaces(kinds=("clamped", "nonuniform", "periodic"), max_degree=4, dims=(2, 3)))
def test_partials_vs_geomdl(surface):
    """Polynomial and rational partials S_(k,l), k + l <= 2, against geomdl's
    BSpline.Surface / NURBS.Surface (its rational recursion loses a few digits)."""
    g = geomdl_surface(surface)
    us = interior_parameters(surface, "u", 1)
    vs = interior_parameters(surface, "v", 1)
    u, v = (x.ravel() for x in np.meshgrid(us, vs, indexing="ij"))
    mine = surface.derivatives(u, v, 2, 2)
    ref = np.array([g.derivatives(float(a), float(b), 2) for a, b in zip(u, v)])   # (N, 3, 3, dim)
    for k, l in itertools.product(range(3), range(3)):
        if k + l > 2:
            continue
        r = ref[:, k, l]
        tol = 1e-12 if k + l == 0 else 1e-9
        assert relative(mine[k, l], r, derivative_bound(surface, k, l, r) / 1e-12) <= tol, (k, l)


def test_nurbs_vs_geomdl_fixed_example():
    rng = np.random.default_rng(5)
    P = rng.uniform(-5, 5, (5, 4, 3))
    W = rng.uniform(0.5, 2.0, (5, 4))
    ku = [0, 0, 0, 0, 0.3, 1, 1, 1, 1]
    kv = [0, 0, 0, 0.5, 1, 1, 1]
    s = BSplineSurface(P, 3, 2, ku, kv, W)
    g = geomdl_surface(s)
    uv = rng.uniform(0, 1, (40, 2))
    ref = np.array(g.evaluate_list(uv.tolist()))
    assert relative(s(uv[:, 0], uv[:, 1]), ref) <= 1e-13


def test_uniform_bicubic_matrix_form():
    """Seed 000, 5.3.3: on a 4x4 net with uniform floating knots,
    p(u, v) = U M_BEZ P M_BEZ^T V^T, U = [u^3 u^2 u 1], V = [v^3 v^2 v 1],
    M_BEZ = 1/6 [[-1,3,-3,1],[3,-6,3,0],[-3,0,3,0],[1,4,1,0]], (u, v) in [0, 1]^2."""
    M = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]]) / 6.0
    rng = np.random.default_rng(0)
    P = rng.uniform(-3, 3, (4, 4, 3))
    knots = uniform(4, 3)                                    # [-3, -2, ..., 4], domain [0, 1]
    np.testing.assert_array_equal(knots, np.arange(-3.0, 5.0))
    s = BSplineSurface(P, 3, 3, knots, knots)
    assert s.domain == ((0.0, 1.0), (0.0, 1.0))
    t = np.linspace(0, 1, 11)
    U = t[:, None] ** np.arange(3, -1, -1)
    ref = np.einsum("ua,ai,ijd,bj,vb->uvd", U, M, P, M, U)
    assert relative(s.grid(t, t), ref) <= 1e-14
    # seed 000, 5.3.2: the corner p(0, 0) is the mean (1,4,1)/6 x (1,4,1)/6 of the first 3x3 net
    w = np.array([1, 4, 1]) / 6
    np.testing.assert_allclose(s(0.0, 0.0), np.einsum("i,j,ijd->d", w, w, P[:3, :3]), rtol=1e-14, atol=1e-14)


@SETTINGS
@given(surface=bspline_surfaces(), data=st.data())
def test_partition_of_unity(surface, data):
    """sum_i sum_j N_i(u) N_j(v) = 1: a net of equal points is that point, whatever
    the weights, and every derivative vanishes."""
    c = np.array(data.draw(st.lists(st.floats(-5, 5), min_size=surface.dim, max_size=surface.dim)))
    flat = BSplineSurface(np.broadcast_to(c, surface.control_points.shape), surface.degree_u,
                          surface.degree_v, surface.knots_u, surface.knots_v, surface.weights,
                          surface.periodic_u, surface.periodic_v)
    us, vs = domain_parameters(surface, 5)
    d = flat.derivatives(us[:, None], vs[None, :], 1, 1)
    scale = max(1.0, float(np.abs(c).max()))
    assert np.abs(d[0, 0] - c).max() <= 1e-13 * scale
    tol = 1e-12 * scale * weight_ratio(surface) * (max(surface.degree_u / min_span(surface, "u"),
                                                      surface.degree_v / min_span(surface, "v")) + 1) ** 2
    assert np.abs(d[1:, :]).max(initial=0.0) <= tol and np.abs(d[:, 1:]).max() <= tol


@SETTINGS
@given(surface=bspline_surfaces(kinds=("clamped",)))
def test_clamped_corners_and_boundaries(surface):
    """Clamped in both directions: the corners are P_00, P_0n, P_m0, P_mn and the
    boundary curves are the B-spline curves of the boundary rows and columns
    (seed 000, 5.2.7 property 1, for B-splines with clamped knots)."""
    P, W = surface.control_points, surface.weights
    (a, b), (c, d) = surface.domain
    got = surface(np.array([a, a, b, b]), np.array([c, d, c, d]))
    ref = np.array([P[0, 0], P[0, -1], P[-1, 0], P[-1, -1]])
    assert relative(got, ref, net_size(surface)) <= 1e-14
    curves = [(0, lambda M: M[:, 0], "u"), (1, lambda M: M[-1], "v"),
              (2, lambda M: M[:, -1], "u"), (3, lambda M: M[0], "v")]
    bounds = surface.boundaries()
    for k, take, along in curves:
        knots = surface.knots_u if along == "u" else surface.knots_v
        deg = surface.degree_u if along == "u" else surface.degree_v
        ref_curve = BSplineCurve(take(P), deg, knots, None if W is None else take(W))
        t = np.linspace(*(surface.domain[0] if along == "u" else surface.domain[1]), 13)
        assert relative(bounds[k](t), ref_curve(t), net_size(surface)) <= 1e-13, k


@SETTINGS
@given(surface=bspline_surfaces(), data=st.data())
def test_isocurves_are_the_surface(surface, data):
    """isocurve("u", v0)(u) = S(u, v0) and isocurve("v", u0)(v) = S(u0, v), periodic and rational too."""
    (a, b), (c, d) = surface.domain
    u0, v0 = data.draw(st.floats(a, b)), data.draw(st.floats(c, d))
    us, vs = domain_parameters(surface, 9, include_knots=False)
    cu, cv = surface.isocurve("u", v0), surface.isocurve("v", u0)
    assert cu.periodic == surface.periodic_u and cv.periodic == surface.periodic_v
    tol = 1e-12 * weight_ratio(surface)
    assert relative(cu(us), surface(us, v0), net_size(surface)) <= tol
    assert relative(cv(vs), surface(u0, vs), net_size(surface)) <= tol


@SETTINGS
@given(surface=bspline_surfaces(max_degree=5))
def test_partials_vs_central_differences(surface):
    """S_u, S_v, S_uv against central differences of the engine's own lower partials,
    away from knots: error ~ h^2/6 |third partial| + rounding eps |S| / h."""
    hu, hv = 1e-4 * min_span(surface, "u"), 1e-4 * min_span(surface, "v")
    us = interior_parameters(surface, "u", 2, margin=2 * hu)
    vs = interior_parameters(surface, "v", 2, margin=2 * hv)
    U, V = us[:, None], vs[None, :]
    d = surface.derivatives(U, V, 3, 3)
    fu = (surface(U + hu, V) - surface(U - hu, V)) / (2 * hu)
    fv = (surface(U, V + hv) - surface(U, V - hv)) / (2 * hv)
    fuv = (surface.derivative(U, V + hv, 1, 0) - surface.derivative(U, V - hv, 1, 0)) / (2 * hv)
    big = lambda k, l: np.abs(d[k, l]).max()  # noqa: E731
    # rounding of S and S_u: ~eps |P| and ~eps |P| p / h_min (w ratio for NURBS)
    r0 = max(big(0, 0), net_size(surface)) * weight_ratio(surface)
    r1 = max(big(1, 0), r0 * surface.degree_u / min_span(surface, "u")) * weight_ratio(surface)
    # truncation h^2/6 |third| (x4 margin) + rounding 1e-13 |lower| / h + 1e-9 |result|
    assert np.abs(fu - d[1, 0]).max() <= hu ** 2 / 6 * big(3, 0) * 4 + 1e-13 * r0 / hu + 1e-9 * big(1, 0)
    assert np.abs(fv - d[0, 1]).max() <= hv ** 2 / 6 * big(0, 3) * 4 + 1e-13 * r0 / hv + 1e-9 * big(0, 1)
    assert np.abs(fuv - d[1, 1]).max() <= hv ** 2 / 6 * big(1, 3) * 4 + 1e-13 * r1 / hv + 1e-9 * big(1, 1)


def test_derivatives_beyond_the_degree_vanish():
    rng = np.random.default_rng(1)
    s = BSplineSurface(rng.normal(size=(6, 5, 3)), 2, 3)
    t = np.linspace(0, 1, 9)
    d = s.derivatives(t[:, None], t[None, :], 3, 4)
    np.testing.assert_array_equal(d[3], 0.0)
    np.testing.assert_array_equal(d[:, 4], 0.0)
    assert np.abs(d[2, 3]).max() > 0


# --- periodic directions --------------------------------------------------------------------

@SETTINGS
@given(data=st.data())
@pytest.mark.parametrize("direction", ["u", "v"])
def test_periodic_wrap_and_seam(direction, data):
    """Periodic in ``direction`` (the other any kind): S(u + kT, v) = S(u, v) (or in v),
    and at the seam the left limits (the unwrapped surface at its domain end) equal
    the right limits up to order p - m (m the seam multiplicity; C^(p-m), as for curves)."""
    if direction == "u":
        surface = data.draw(bspline_surfaces(kinds=("periodic",), kinds_v=KINDS))
    else:
        surface = data.draw(bspline_surfaces(kinds=KINDS, kinds_v=("periodic",)))
    which = 0 if direction == "u" else 1
    a, b = surface.domain[which]
    T = b - a
    us, vs = domain_parameters(surface, 7, include_knots=False)
    k = data.draw(st.sampled_from([-2, -1, 1, 3]))
    scale = net_size(surface)
    shifted = surface(us[:, None] + k * T, vs[None, :]) if which == 0 else surface(us[:, None], vs[None, :] + k * T)
    assert relative(shifted, surface(us[:, None], vs[None, :]), scale) <= 1e-11
    t = surface.knots_u if which == 0 else surface.knots_v
    m = int(np.count_nonzero(t == t[0]) + np.count_nonzero(t == t[-1]) - 1)
    p = surface.degree_u if which == 0 else surface.degree_v
    if which == 0:
        left = unwrapped(surface).derivatives(b, vs, p - m, 0)[:, 0]
        right = surface.derivatives(a, vs, p - m, 0)[:, 0]
    else:
        left = unwrapped(surface).derivatives(us, b, 0, p - m)[0]
        right = surface.derivatives(us, a, 0, p - m)[0]
    for r in range(p - m + 1):
        tol = 1e-12 * max(np.abs(left[r]).max(), scale) \
            + 1e-14 * scale * (p / min_span(surface, direction)) ** r * weight_ratio(surface) ** (r + 1)
        assert np.abs(left[r] - right[r]).max() <= tol, r


def test_periodic_in_both_directions_is_a_torus():
    """A torus: the periodic quadratic circle (8 points, double seam knot) of the tube
    swept by the same circle around the axis; |(rho - R, z)| = r everywhere, both
    directions wrap, and the seam is continuous."""
    s2 = np.sqrt(0.5)
    circle = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)
    cw = np.array([1, s2, 1, s2, 1, s2, 1, s2])
    period = [0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1]
    R, r = 3.0, 1.0
    # u: around the axis (x, y); v: around the tube (rho, z)
    rho = R + r * circle[:, 0]
    z = r * circle[:, 1]
    P = np.empty((8, 8, 3))
    P[..., 0] = circle[:, None, 0] * rho[None, :]
    P[..., 1] = circle[:, None, 1] * rho[None, :]
    P[..., 2] = np.broadcast_to(z, (8, 8))
    W = cw[:, None] * cw[None, :]
    torus = BSplineSurface(P, 2, 2, period, period, W, periodic_u=True, periodic_v=True)
    u = np.linspace(-1, 2, 31)
    pts = torus(u[:, None], u[None, :])
    dist = np.hypot(np.hypot(pts[..., 0], pts[..., 1]) - R, pts[..., 2])
    np.testing.assert_allclose(dist, r, rtol=1e-14)
    np.testing.assert_allclose(torus(u[:, None] + 1, u[None, :] - 2), pts, atol=1e-14)
    # C^0 at both seams (the double seam knot of a quadratic); derivative directions agree (G1)
    flat = unwrapped(torus)
    for du, dv in ((1, 0), (0, 1)):
        pa = torus.derivative(0.0 if du else 0.37, 0.37 if du else 0.0, du, dv)
        pb = flat.derivative(1.0 if du else 0.37, 0.37 if du else 1.0, du, dv)
        np.testing.assert_allclose(pa, pb, atol=1e-13)
    # Gaussian curvature of the torus: cos(phi) / (r (R + r cos(phi))), phi the tube angle
    v = np.linspace(0.01, 0.99, 7)
    q = torus(0.3, v)
    cos_phi = (np.hypot(q[:, 0], q[:, 1]) - R) / r
    K = cos_phi / (r * (R + r * cos_phi))
    np.testing.assert_allclose(torus.gaussian_curvature(0.3, v), K, rtol=1e-11, atol=1e-12)


# --- operations leave the surface unchanged ---------------------------------------------------

def draw_parameter(data, surface, direction, existing=True):
    """An existing knot of the domain or any float in it that is not within a
    subnormal distance (< 1e-300) of a knot (such spans evaluate, see
    test_subnormal_span_evaluates, but their derivatives exceed the float range)."""
    which = 0 if direction == "u" else 1
    a, b = surface.domain[which]
    k = np.unique(full_knots(surface, direction))
    inside = [float(x) for x in k if a <= x <= b]
    if existing and data.draw(st.booleans()):
        return data.draw(st.sampled_from(inside))
    t = data.draw(st.floats(a, b))
    if 0 < np.abs(k - t).min() < 1e-300:
        return data.draw(st.sampled_from(inside))
    return t


@SETTINGS
@given(surface=bspline_surfaces(), data=st.data())
def test_insert_knot_and_refine(surface, data):
    d = data.draw(st.sampled_from("uv"))
    p = surface.degree_u if d == "u" else surface.degree_v
    t = draw_parameter(data, surface, d)
    have = int(np.count_nonzero(full_knots(surface, d) == t))
    times = data.draw(st.integers(1, p - have)) if have < p else 0    # up to multiplicity p
    us, vs = domain_parameters(surface, 9)
    if times:
        s2 = surface.insert_knot(d, t, times)
        n_before = surface.control_points.shape[0 if d == "u" else 1]
        n_after = s2.control_points.shape[0 if d == "u" else 1]
        assert n_after >= n_before
        assert_same_surface(surface, s2, us, vs, rtol=1e-11 * weight_ratio(surface))
    which = 0 if d == "u" else 1
    a, b = surface.domain[which]
    new = np.array(data.draw(st.lists(st.floats(a, b, exclude_min=True, exclude_max=True), max_size=4,
                                      unique=True)))
    new = new[~np.isin(new, full_knots(surface, d))]          # existing knots: test the insertion above
    every = np.concatenate([full_knots(surface, d), new])
    gap = np.abs(new[:, None] - every[None, :])
    new = np.sort(new[np.all((gap == 0) | (gap >= 1e-300), axis=1)])
    s3 = surface.refine(d, new)
    assert s3.control_points.shape[which] <= surface.control_points.shape[which] + len(new)
    assert_same_surface(surface, s3, us, vs, rtol=1e-11 * weight_ratio(surface))


def test_subnormal_span_evaluates():
    """Was a strict xfail (NaN): basis_derivatives works in units of the span width and
    the pp form clips local knots beyond the float range (issue 14)."""
    s = BSplineSurface(np.arange(12.0).reshape(2, 2, 3), 1, 1)
    r = s.insert_knot("u", 1e-310)
    u, v = np.array([0.0, 5e-311, 1e-310, 2e-310, 0.5, 1.0]), np.full(6, 0.5)
    np.testing.assert_allclose(r(u, v), s(u, v), atol=1e-14)
    c = BSplineCurve([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 0.0]], 3).insert_knot(1e-310)
    ref = BSplineCurve([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 0.0]], 3)
    np.testing.assert_allclose(c(u), ref(u), atol=1e-14)


@settings(max_examples=30, deadline=None)
@given(surface=bspline_surfaces(max_degree=3), times=st.integers(1, 2), d=st.sampled_from("uv"))
def test_elevate(surface, times, d):
    s2 = surface.elevate(d, times)
    assert (s2.degree_u, s2.degree_v) == ((surface.degree_u + times, surface.degree_v) if d == "u"
                                          else (surface.degree_u, surface.degree_v + times))
    us, vs = domain_parameters(surface, 9)
    assert_same_surface(surface, s2, us, vs, rtol=1e-10 * weight_ratio(surface))


@SETTINGS
@given(surface=bspline_surfaces(), data=st.data())
def test_split_segment_and_clamped(surface, data):
    d = data.draw(st.sampled_from("uv"))
    which = 0 if d == "u" else 1
    a, b = surface.domain[which]
    t = data.draw(st.floats(a + 0.05 * (b - a), b - 0.05 * (b - a)))
    assume(not 0 < np.abs(full_knots(surface, d) - t).min() < 1e-300)     # test_subnormal_span_evaluates
    left, right = surface.split(d, t)
    assert left.domain[which] == (a, t) and right.domain[which] == (t, b)
    us, vs = domain_parameters(surface, 9, include_knots=False)
    tol = 1e-11 * weight_ratio(surface)
    if d == "u":
        assert_same_surface(left, surface, np.linspace(a, t, 7), vs, tol)
        assert_same_surface(right, surface, np.linspace(t, b, 7), vs, tol)
    else:
        assert_same_surface(left, surface, us, np.linspace(a, t, 7), tol)
        assert_same_surface(right, surface, us, np.linspace(t, b, 7), tol)
    lo = data.draw(st.floats(a, t))
    if t - lo >= 1e-300 and not 0 < np.abs(full_knots(surface, d) - lo).min() < 1e-300:
        seg = surface.segment(d, lo, t)
        assert seg.domain[which] == (lo, t)
        sub = np.linspace(lo, t, 7)
        assert_same_surface(seg, surface, sub if d == "u" else us, vs if d == "u" else sub, tol)
    cl = surface.clamped()
    assert not cl.periodic_u and not cl.periodic_v
    assert cl.domain == surface.domain
    for k in (cl.knots_u, cl.knots_v):
        assert np.count_nonzero(k == k[0]) >= 2 and np.count_nonzero(k == k[-1]) >= 2
    assert_same_surface(surface, cl, *domain_parameters(surface, 9), rtol=tol)


@SETTINGS
@given(surface=bspline_surfaces(), d=st.sampled_from("uv"))
def test_reversed_and_swapped(surface, d):
    (a, b), (c, e) = surface.domain
    us, vs = domain_parameters(surface, 9)
    r = surface.reversed(d)
    np.testing.assert_allclose(r.domain, surface.domain, rtol=1e-15, atol=1e-15)   # (a + b) - b rounds
    tol = 1e-11 * weight_ratio(surface)
    if d == "u":
        assert_same_surface(surface, r, us, vs, tol, map_u=lambda x: a + b - x)
    else:
        assert_same_surface(surface, r, us, vs, tol, map_v=lambda x: c + e - x)
    sw = surface.swapped()
    assert sw.domain == (surface.domain[1], surface.domain[0])
    got = sw(vs[:, None], us[None, :]).transpose(1, 0, 2)
    assert relative(got, surface(us[:, None], vs[None, :]), net_size(surface)) <= 1e-14
    u0, v0 = us[len(us) // 2], vs[len(vs) // 2]
    if surface.dim == 3 and regular(surface, surface.derivatives(u0, v0, 1, 1)):
        np.testing.assert_allclose(sw.normal(v0, u0), -surface.normal(u0, v0), atol=1e-9)


@settings(max_examples=30, deadline=None)
@given(surface=bspline_surfaces(max_degree=3), data=st.data())
def test_reparametrized(surface, data):
    a, b = data.draw(st.floats(-10, 10)), data.draw(st.floats(0.1, 10))
    c, e = data.draw(st.floats(-10, 10)), data.draw(st.floats(0.1, 10))
    r = surface.reparametrized((a, a + b), (c, c + e))
    np.testing.assert_allclose(r.domain, ((a, a + b), (c, c + e)), rtol=1e-15, atol=1e-15)
    (u0, u1), (v0, v1) = surface.domain
    us, vs = np.linspace(a, a + b, 7), np.linspace(c, c + e, 7)
    assert_same_surface(r, surface, us, vs, 1e-10 * weight_ratio(surface),
                        map_u=lambda x: np.clip(u0 + (x - a) / b * (u1 - u0), u0, u1),
                        map_v=lambda x: np.clip(v0 + (x - c) / e * (v1 - v0), v0, v1))


@settings(max_examples=30, deadline=None)
@given(surface=bspline_surfaces(max_degree=3))
def test_bezier_patches(surface):
    """Every patch is a single-span clamped patch on its knot rectangle, equal to the
    surface there; the breaks are the distinct knots of the domain."""
    bu, bv, patches = surface.bezier_patches()
    (a, b), (c, d) = surface.domain
    for br, (lo, hi), direction in ((bu, (a, b), "u"), (bv, (c, d), "v")):
        k = np.unique(full_knots(surface, direction))
        np.testing.assert_allclose(br, k[(k >= lo) & (k <= hi)], rtol=0, atol=1e-12 * max(1, abs(lo), abs(hi)))
    assert len(patches) == len(bu) - 1 and all(len(row) == len(bv) - 1 for row in patches)
    tol = 1e-11 * weight_ratio(surface)
    for i, j in itertools.product(range(len(bu) - 1), range(len(bv) - 1)):
        pt = patches[i][j]
        assert pt.control_points.shape[:2] == (surface.degree_u + 1, surface.degree_v + 1)
        np.testing.assert_allclose(pt.domain, ((bu[i], bu[i + 1]), (bv[j], bv[j + 1])), rtol=0, atol=1e-12 * 20)
        us, vs = np.linspace(bu[i], bu[i + 1], 4), np.linspace(bv[j], bv[j + 1], 4)
        assert relative(pt(us[:, None], vs[None, :]), surface(us[:, None], vs[None, :]), net_size(surface)) <= tol


@SETTINGS
@given(surface=bspline_surfaces(dims=(2, 3)), data=st.data())
def test_affine_invariance(surface, data):
    dim = surface.dim
    A = np.array(data.draw(st.lists(st.floats(-3, 3), min_size=dim * dim, max_size=dim * dim))).reshape(dim, dim)
    b = np.array(data.draw(st.lists(st.floats(-3, 3), min_size=dim, max_size=dim)))
    moved = surface.transformed(A, b)
    us, vs = domain_parameters(surface, 7)
    expected = surface(us[:, None], vs[None, :]) @ A.T + b
    scale = max(1.0, np.abs(A).max() * net_size(surface))
    assert np.abs(moved(us[:, None], vs[None, :]) - expected).max() <= 1e-12 * scale * dim


# --- errors ---------------------------------------------------------------------------------

P33 = np.zeros((4, 4, 3))


@pytest.mark.parametrize("kwargs, name", [
    (dict(control_points=np.zeros((4, 3))), "control_points"),
    (dict(control_points=np.zeros((1, 4, 3))), "control_points"),
    (dict(control_points=[[["a"]]]), "control_points"),
    (dict(control_points=np.full((4, 4, 3), np.nan)), "control_points"),
    (dict(degree_u=0), "degree_u"),
    (dict(degree_v=4), "degree_v"),
    (dict(degree_u=1.5), "degree_u"),
    (dict(knots_u=[0, 0, 0, 0, 1, 1, 1]), "knots_u"),
    (dict(knots_v=[0, 0, 0, 0, 1, 1, 0.5, 1]), "knots_v"),
    (dict(knots_u=[0, 0, 0, 0, 0, 1, 1, 1]), "knots_u"),
    (dict(knots_v=[0, 0, 0, np.inf, 1, 1, 1, 1]), "knots_v"),
    (dict(weights=np.ones((4, 3))), "weights"),
    (dict(weights=-np.ones((4, 4))), "weights"),
    (dict(weights=np.where(np.eye(4) > 0, 0.0, 1.0)), "weights"),
    (dict(weights=np.full((4, 4), np.nan)), "weights"),
    (dict(knots_u=[0, 1, 2], periodic_u=True), "knots_u"),
    (dict(knots_v=[0, 0, 0, 1, 1], periodic_v=True), "knots_v"),        # seam multiplicity 4 > 3
])
def test_constructor_errors(kwargs, name):
    args = dict(control_points=P33, degree_u=3, degree_v=3)
    args.update(kwargs)
    with pytest.raises(CagdError, match=name):
        BSplineSurface(**args)


@pytest.mark.parametrize("u, v, name", [(1.5, 0.5, "u"), (0.5, -0.1, "v"), (np.nan, 0.5, "u"),
                                        ([0.1, 0.2], [0.1, 0.2, 0.3], "u, v")])
def test_parameters_outside_the_domain(u, v, name):
    s = BSplineSurface(np.random.default_rng(0).normal(size=(4, 4, 3)), 3, 3)
    with pytest.raises(CagdError, match=name):
        s(u, v)
    with pytest.raises(CagdError, match=name.split(",")[0]):
        s.derivatives(u, v, 1, 1)


def test_grid_errors():
    s = BSplineSurface(np.random.default_rng(0).normal(size=(4, 4, 3)), 3, 3)
    with pytest.raises(CagdError, match="us"):
        s.grid([0.0, 1.5], [0.5])
    with pytest.raises(CagdError, match="vs"):
        s.grid([0.5], [[0.5]])
    with pytest.raises(CagdError, match="du"):
        s.grid([0.5], [0.5], du=-1)
    with pytest.raises(CagdError, match="dv"):
        s.derivatives(0.5, 0.5, 0, 1.5)


def test_operation_errors():
    rng = np.random.default_rng(0)
    s = BSplineSurface(rng.normal(size=(5, 4, 3)), 3, 2)
    with pytest.raises(CagdError, match="direction"):
        s.insert_knot("w", 0.5)
    with pytest.raises(CagdError, match="direction"):
        s.isocurve("x", 0.5)
    with pytest.raises(CagdError, match="value"):
        s.isocurve("u", 1.5)
    with pytest.raises(CagdError):
        s.split("u", 1.0)
    with pytest.raises(CagdError, match="times"):
        s.elevate("v", -1)
    with pytest.raises(CagdError, match="matrix"):
        s.transformed(np.eye(2))
    with pytest.raises(CagdError, match="offset"):
        s.transformed(np.eye(3), [1.0, 2.0])


def test_repr_and_bezier_conversion():
    rng = np.random.default_rng(2)
    s = BSplineSurface(rng.normal(size=(4, 3, 3)), 3, 2, weights=rng.uniform(1, 2, (4, 3)))
    assert "NURBS" in repr(s) and "(3, 2)" in repr(s)
    assert s.to_nurbs() is s
    # a single-span clamped B-spline curve of a boundary row is the Bezier curve of that row
    c = s.isocurve("u", 0.0)
    bz = BezierCurve(s.control_points[:, 0], s.weights[:, 0])
    t = np.linspace(0, 1, 9)
    np.testing.assert_allclose(c(t), bz(t), atol=1e-14)
