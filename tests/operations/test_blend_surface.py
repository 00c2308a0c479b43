"""Blend surfaces and edge matching (cagd.blend_surface, cagd.match_surface; issue 18).

The oracle, independent of the module's own measurements: at 50 stations along each
edge, the position gap (<= 1e-12 size), the tangent-plane angle of
:func:`cagd.edge_continuity` (<= 1e-9 rad) and for G2 the normal curvature across the
edge, kappa(d) = II(w, w) / I(w, w) with d = n1 x T, w = J^+ d (J = [S_u S_v], the
pseudo-inverse), I and II from :meth:`Surface.fundamental_forms`, II's sign turned to
n1 (do Carmo 3.2-3.3), equal on both sides to 1e-9 relative to max(|k1|, |k2|, 1 / size);
two surfaces meeting G1 with one transversal normal curvature equal are G2 (Pegna and
Wolter's linkage curve theorem), so the Gaussian curvatures and the (orientation-signed)
mean curvatures must agree as well, which is checked too.
"""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import cagd
from cagd import BSplineSurface, CagdError, blend_surface, edge_continuity, match_surface
from cagd.surfaces.continuity import EDGES

TOL = 1e-9           # the bounds: G1 angle (rad), G2 relative curvature difference
GAP = 1e-12          # position gap relative to the size
STATIONS = 50


def patch(offset, knots_u, knots_v, seed, weights=None, wobble=0.2):
    """A bicubic patch over a jittered grid on [0, 1]^2 with a wavy height, moved by offset."""
    rng = np.random.default_rng(seed)
    nu, nv = len(knots_u) - 4, len(knots_v) - 4
    P = np.stack(np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij"), -1)
    P = P + 0.04 * rng.standard_normal(P.shape)
    Z = wobble * np.sin(3 * P[..., :1] + 2 * P[..., 1:]) + 0.05 * rng.standard_normal((nu, nv, 1))
    W = None if weights is None else rng.uniform(*weights, (nu, nv))
    return BSplineSurface(np.concatenate([P, Z], -1) + offset, 3, 3, knots_u, knots_v, W)


KU1, KV1 = [0, 0, 0, 0, 0.2, 0.4, 0.6, 0.8, 1, 1, 1, 1], [0, 0, 0, 0, 0.5, 1, 1, 1, 1]
KU2, KV2 = [0, 0, 0, 0, 0.4, 1, 1, 1, 1], [0, 0, 0, 0, 0.2, 0.5, 0.7, 1, 1, 1, 1]
S1 = patch([0.0, 0.0, 0.0], KU1, KV1, 1)
S2 = patch([1.6, 0.1, 0.3], KU2, KV2, 2).reversed("v")                     # its u0 edge runs against S1's u1
R2 = patch([1.6, 0.1, 0.3], KU2, KV2, 2, weights=(0.8, 1.25)).reversed("v")  # the same, rational


def views(s, edge):
    """The same surface with the same edge under the four names (u/v swapped, reversed)."""
    other = {"u0": "u1", "u1": "u0", "v0": "v1", "v1": "v0"}
    swap = {"u0": "v0", "u1": "v1", "v0": "u0", "v1": "u1"}
    flip = s.reversed(edge[0])
    return [(s, edge), (flip, other[edge]), (s.swapped(), swap[edge]), (flip.swapped(), swap[other[edge]])]


def edge_uv(s, edge, t):
    (u0, u1), (v0, v1) = s.domain
    if edge[0] == "u":
        return np.full_like(t, u0 if edge == "u0" else u1), v0 + t * (v1 - v0)
    return u0 + t * (u1 - u0), np.full_like(t, v0 if edge == "v0" else v1)


def normal_curvatures(s, edge, t, n_ref, T):
    """Normal curvature of s at its edge stations t in the direction n_ref x T (the oracle)."""
    u, v = edge_uv(s, edge, t)
    (E, F, G), (L, M, N) = s.fundamental_forms(u, v)
    sign = np.sign(np.einsum("ij,ij->i", s.normal(u, v), n_ref))
    D = s.derivatives(u, v, 1, 1)
    J = np.stack([D[1, 0], D[0, 1]], axis=-1)                   # (N, 3, 2)
    w = np.einsum("nij,nj->ni", np.linalg.pinv(J), np.cross(n_ref, T))
    a, b = w[:, 0], w[:, 1]
    return sign * (L * a * a + 2 * M * a * b + N * b * b) / (E * a * a + 2 * F * a * b + G * b * b)


def relative(x, y, floor):
    return float(np.max(np.abs(x - y) / np.maximum(np.maximum(np.abs(x), np.abs(y)), floor)))


def joint(a, edge_a, b, edge_b, reverse, k, size):
    """Measure a -> b across the shared edge at STATIONS stations; return the numbers."""
    t = np.linspace(0.0, 1.0, STATIONS)
    tb = t[::-1].copy() if reverse else t
    pa, pb = a(*edge_uv(a, edge_a, t)), b(*edge_uv(b, edge_b, tb))
    out = {"gap": float(np.linalg.norm(pa - pb, axis=-1).max()) / size}
    rep = edge_continuity(a, b, edge_a, edge_b, samples=STATIONS, reverse=reverse)
    out["angle"] = rep.normal_angle
    if k == 2:
        ua, va = edge_uv(a, edge_a, t)
        ub, vb = edge_uv(b, edge_b, tb)
        na = a.normal(ua, va)
        Da = a.derivatives(ua, va, 1, 1)
        T = Da[0, 1] if edge_a[0] == "u" else Da[1, 0]
        ka, kb = normal_curvatures(a, edge_a, t, na, T), normal_curvatures(b, edge_b, tb, na, T)
        out["kappa"] = relative(ka, kb, 1.0 / size)
        out["K"] = relative(a.gaussian_curvature(ua, va), b.gaussian_curvature(ub, vb), 1.0 / size ** 2)
        sign = np.sign(np.einsum("ij,ij->i", na, b.normal(ub, vb)))
        out["H"] = relative(a.mean_curvature(ua, va), sign * b.mean_curvature(ub, vb), 1.0 / size)
    return out


def size_of(*surfaces):
    P = np.concatenate([s.control_points.reshape(-1, 3) for s in surfaces])
    return float(np.linalg.norm(P.max(0) - P.min(0)))


def assert_joint(m, k):
    assert m["gap"] <= GAP, m
    assert m["angle"] <= TOL, m
    if k == 2:
        assert m["kappa"] <= TOL and m["K"] <= TOL and m["H"] <= TOL, m


def check_blend(s1, e1, s2, e2, k, scales=None):
    res = blend_surface(s1, e1, s2, e2, k, tangent_scales=scales)
    B, size = res.surface, size_of(s1, s2)
    assert isinstance(B, BSplineSurface) and B.degree_v == 2 * k + 1
    m1 = joint(B, "v0", s1, e1, False, k, size)
    m2 = joint(B, "v1", s2, e2, res.reversed, k, size)
    assert_joint(m1, k)
    assert_joint(m2, k)
    assert res.converged and res.continuity == k and res.max_angle <= TOL
    assert (res.max_curvature_gap is None) == (k == 1)
    return res, m1, m2


# --- blend ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k", [1, 2])
@pytest.mark.parametrize("second", ["polynomial", "rational"])
@pytest.mark.parametrize("view1", range(4))
def test_blend_bicubic_patches(k, second, view1):
    s1, e1 = views(S1, "u1")[view1]
    s2, e2 = views(R2 if second == "rational" else S2, "u0")[(view1 + 1) % 4]
    res, _, _ = check_blend(s1, e1, s2, e2, k)
    assert res.surface.is_rational == (second == "rational")


def test_blend_detects_the_reversed_edge():
    res, _, _ = check_blend(S1, "u1", S2, "u0", 2)
    assert res.reversed
    res, _, _ = check_blend(S1, "u1", S2.reversed("v"), "u0", 2)
    assert not res.reversed


@pytest.mark.parametrize("scales", [(0.3, 2.0), (2.5, 0.5)])
def test_blend_tangent_scales(scales):
    res, _, _ = check_blend(S1, "u1", S2, "u0", 2, scales)
    base = blend_surface(S1, "u1", S2, "u0", 2).surface.control_points
    P = res.surface.control_points
    ratio = np.linalg.norm(P[:, 1] - P[:, 0], axis=-1) / np.linalg.norm(base[:, 1] - base[:, 0], axis=-1)
    assert np.allclose(ratio, scales[0], rtol=1e-12)
    ratio = np.linalg.norm(P[:, -2] - P[:, -1], axis=-1) / np.linalg.norm(base[:, -2] - base[:, -1], axis=-1)
    assert np.allclose(ratio, scales[1], rtol=1e-12)


def test_blend_of_coplanar_planar_patches_is_planar():
    rng = np.random.default_rng(5)
    basis = np.linalg.qr(rng.standard_normal((3, 3)))[0]          # a tilted plane: e0, e1 span it
    normal, origin = basis[:, 2], np.array([0.3, -1.2, 0.7])

    def flat(offset, ku, kv):
        nu, nv = len(ku) - 4, len(kv) - 4
        P = np.stack(np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij"), -1)
        P = P + 0.05 * rng.standard_normal(P.shape) + offset
        return BSplineSurface(origin + P[..., :1] * basis[:, 0] + P[..., 1:] * basis[:, 1], 3, 3, ku, kv)

    a, b = flat([0.0, 0.0], KU1, KV1), flat([1.7, 0.4], KU2, KV2).reversed("v")
    for k in (1, 2):
        res, _, _ = check_blend(a, "u1", b, "u0", k)
        P = res.surface.control_points
        assert np.abs((P - origin) @ normal).max() <= 1e-12 * size_of(a, b)


@pytest.mark.parametrize("k", [1, 2])
def test_blend_of_coaxial_cylinders_is_a_surface_of_revolution(k):
    """Rational (NURBS circle) rims: by symmetry the blend's radius and height are
    constant along each rim-parallel isocurve."""
    a, b = cagd.cylinder(1.0, 2.0, [0.0, 0.0, 0.0]), cagd.cylinder(2.0, 1.5, [0.0, 0.0, 3.0])
    res, _, _ = check_blend(a.to_nurbs(), "u0", b.to_nurbs(), "u1", k)
    assert res.surface.is_rational and not res.reversed
    u, v = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 9), indexing="ij")
    P = res.surface(u, v)
    for x in (np.hypot(P[..., 0], P[..., 1]), P[..., 2]):
        assert np.ptp(x, axis=0).max() <= 1e-12 * 4.0
    assert np.all(np.diff(P[0, :, 2]) > 0)                   # it climbs from the top rim to the bottom rim
    flipped, _, _ = check_blend(a.to_nurbs(), "u0", b.to_nurbs().reversed("v"), "u1", k)
    assert flipped.reversed                                   # closed edges: no corners tell the direction
    assert np.abs(flipped.surface(u, v) - P).max() <= 1e-12 * 4.0


@pytest.mark.parametrize("scale, offset", [(1e-300, 0.0), (1e-100, 0.0), (1e150, 1e12), (1e300, 0.0)])
def test_blend_and_match_at_extreme_scales(scale, offset):
    a, b = (s.transformed(np.eye(3) * scale, np.full(3, offset)) for s in (S1, R2))
    for k in (1, 2):
        r = blend_surface(a, "u1", b, "u0", k)
        assert r.converged and r.max_angle <= TOL
        assert r.max_curvature_gap is None if k == 1 else r.max_curvature_gap <= TOL
        assert r.max_gap <= GAP * scale
        m = match_surface(a, "u1", b, "u0", k)
        assert m.converged and m.max_angle <= TOL and m.max_gap <= GAP * scale


def test_the_oracle_catches_a_moved_second_row():
    """Moving the blend's second row across (the G2 row) by 1e-6 breaks the G2 test
    but not G1; moving the first row breaks G1."""
    res = blend_surface(S1, "u1", R2, "u0", 2)
    B, size = res.surface, size_of(S1, R2)
    P = B.control_points.copy()
    P[:, 2, 2] += 1e-6
    m = joint(B.with_control_points(P), "v0", S1, "u1", False, 2, size)
    assert m["angle"] <= TOL and m["gap"] <= GAP
    assert m["kappa"] > 100 * TOL and m["K"] > TOL
    P = B.control_points.copy()
    P[:, 1, 2] += 1e-6
    m = joint(B.with_control_points(P), "v0", S1, "u1", False, 1, size)
    assert m["angle"] > 100 * TOL


@st.composite
def random_patch(draw, offset):
    grid = np.stack(np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4), indexing="ij"), -1)
    jitter = np.array(draw(st.lists(st.floats(-0.15, 0.15), min_size=32, max_size=32))).reshape(4, 4, 2)
    z = np.array(draw(st.lists(st.floats(-0.5, 0.5), min_size=16, max_size=16))).reshape(4, 4, 1)
    w = draw(st.one_of(st.none(), st.lists(st.floats(0.7, 1.4), min_size=16, max_size=16)))
    P = np.concatenate([grid + jitter, z], -1) + offset
    return BSplineSurface(P, 3, 3, weights=None if w is None else np.reshape(w, (4, 4)))


@settings(max_examples=15, deadline=None)
@given(random_patch([0.0, 0.0, 0.0]), random_patch([2.5, 0.3, 0.4]), st.sampled_from(EDGES),
       st.sampled_from(EDGES), st.sampled_from([1, 2]),
       st.one_of(st.none(), st.tuples(st.floats(0.3, 3.0), st.floats(0.3, 3.0))))
def test_random_blends_are_tangent(s1, s2, e1, e2, k, scales):
    try:
        res = blend_surface(s1, e1, s2, e2, k, tangent_scales=scales)
    except CagdError as exc:          # rational rows whose weights would turn negative at given scales
        if scales is None or "turn non-positive" not in str(exc):
            raise
        assume(False)
    size = size_of(s1, s2)
    for m in (joint(res.surface, "v0", s1, e1, False, 1, size),
              joint(res.surface, "v1", s2, e2, res.reversed, 1, size)):
        assert m["gap"] <= GAP and m["angle"] <= TOL, m
    assert res.converged


# --- match ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k", [0, 1, 2])
@pytest.mark.parametrize("target", ["polynomial", "rational"])
@pytest.mark.parametrize("view", range(4))
def test_match_bicubic_patches(k, target, view):
    s, e = views(S1, "u1")[view]
    t, te = (R2 if target == "rational" else S2), "u0"
    res = match_surface(s, e, t, te, k)
    size = size_of(s, t)
    m = joint(res.surface, e, t, te, res.reversed, k, size)
    assert m["gap"] <= GAP, m
    if k >= 1:
        assert_joint(m, k)
    assert res.converged and res.moved_rows == k + 1 and res.reversed
    assert res.poles_along == (5, 7)           # KV1's knot 0.5 and KV2's reversed 0.3, 0.5, 0.8
    # away from the moved rows the shape is s's: u below the support of rows nu-1-k.. (edge u1 of S1)
    U = S1.knots_u
    cut = U[S1.control_points.shape[0] - 1 - k]
    u, v = np.meshgrid(np.linspace(0.0, cut, 23), np.linspace(0.0, 1.0, 19), indexing="ij")
    back = _back_to_s1(res.surface, view)
    assert np.abs(back(u, v) - S1(u, v)).max() <= 1e-13 * size
    # and the moved rows do change it next to the edge
    assert np.abs(back(np.full(5, 1.0), np.linspace(0, 1, 5)) - S1(np.full(5, 1.0), np.linspace(0, 1, 5))).max() > 0.1


def _back_to_s1(s, view):
    """Undo the view's swap/reversal (views(S1, 'u1')[view])."""
    if view in (2, 3):
        s = s.swapped()
    if view in (1, 3):
        s = s.reversed("u")
    return s


@pytest.mark.parametrize("k", [0, 1, 2])
def test_match_keeps_the_rows_beyond_the_moved_ones(k):
    """With the target's edge knots already in s no refinement happens: every row but
    the moved ones is s's, bit for bit."""
    t = patch([1.0, 0.0, 0.1], KU2, KV1, 3)
    res = match_surface(S1, "u1", t, "u0", k)
    assert res.poles_along == (5, 5) and not res.reversed
    P, Q = res.surface.control_points, S1.control_points
    assert np.array_equal(P[:-(k + 1)], Q[:-(k + 1)])
    assert not np.array_equal(P[-(k + 1):], Q[-(k + 1):])
    assert_joint(joint(res.surface, "u1", t, "u0", False, k, size_of(S1, t)), k) if k else None


def split_pair(rational):
    """A bicubic surface split at u = 0.45: two halves meeting C2."""
    s = patch([0.0, 0.0, 0.0], [0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1], KV2, 7,
              weights=(0.8, 1.25) if rational else None, wobble=0.5)
    return s.split("u", 0.45)


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("k", [0, 1, 2])
def test_match_of_an_already_smooth_pair_changes_nothing(rational, k):
    left, right = split_pair(rational)
    u, v = np.meshgrid(np.linspace(0, 0.45, 17), np.linspace(0, 1, 21), indexing="ij")
    size = size_of(left, right)
    targets = [right,
               right.reparametrized(domain_u=(-3.0, 2.0)),             # another cross speed (G1, not C1)
               right.reversed("v"),                                    # the edge runs the other way
               right.swapped()]                                        # the edge is v0
    if rational:
        targets.append(right.with_weights(3.0 * right.weights))       # the same surface, other weights
    for target in targets:
        te = "v0" if target is targets[3] else "u0"
        res = match_surface(left, "u1", target, te, k)
        assert np.abs(res.surface(u, v) - left(u, v)).max() <= 1e-12 * size, (target, res.message)
        assert res.converged


# --- bad input --------------------------------------------------------------------------------------
_NET = patch([0.5, 0.2, 0.0], [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1], 9).control_points.copy()
_NET[0] = _NET[0, 0]
COLLAPSED = BSplineSurface(_NET, 3, 3)                 # its u0 edge is a point
FLAT = BSplineSurface(np.zeros((4, 4, 2)) + np.arange(4)[:, None, None], 3, 3)   # a 2-D surface

BAD_BLEND = [
    (dict(s1=np.zeros((4, 4, 3))), "s1"),
    (dict(s2="surface"), "s2"),
    (dict(s2=FLAT), "s2: blends and matches are built for 3-D"),
    (dict(edge1="u2"), "edge1"),
    (dict(edge2=0), "edge2"),
    (dict(continuity=0), "continuity"),
    (dict(continuity=3), "continuity"),
    (dict(continuity=True), "continuity"),
    (dict(continuity="G1"), "continuity"),
    (dict(tangent_scales=(0.0, 1.0)), r"tangent_scales\[0\]"),
    (dict(tangent_scales=(1.0, float("nan"))), r"tangent_scales\[1\]"),
    (dict(tangent_scales=2.0), "tangent_scales"),
    (dict(s1=COLLAPSED, edge1="u0"), "edge1"),
    (dict(s2=COLLAPSED, edge2="u0"), "edge2"),
    (dict(s2=S1, edge2="u1"), "edge2"),
]


@pytest.mark.parametrize("kwargs, match", BAD_BLEND)
def test_blend_bad_input(kwargs, match):
    args = dict(s1=S1, edge1="u1", s2=S2, edge2="u0", continuity=2, tangent_scales=None)
    args.update(kwargs)
    with pytest.raises(CagdError, match=match):
        blend_surface(**args)


BAD_MATCH = [
    (dict(s=[[0.0]]), "s"),
    (dict(target=None), "target"),
    (dict(edge="w0"), "edge"),
    (dict(target_edge="v2"), "target_edge"),
    (dict(continuity=3), "continuity"),
    (dict(continuity=-1), "continuity"),
    (dict(continuity=1.5), "continuity"),
    (dict(s=BSplineSurface(S1.control_points[:3, :4], 2, 3), continuity=2), "s: 3 control rows"),
    (dict(s=BSplineSurface(S1.control_points[:, :4], 1, 3), continuity=2), "s: its degree"),
    (dict(target=COLLAPSED, target_edge="u0"), "target_edge"),
]


@pytest.mark.parametrize("kwargs, match", BAD_MATCH)
def test_match_bad_input(kwargs, match):
    args = dict(s=S1, edge="u1", target=S2, target_edge="u0", continuity=2)
    args.update(kwargs)
    with pytest.raises(CagdError, match=match):
        match_surface(**args)


def test_exports_and_values():
    for name in ("blend_surface", "match_surface", "BlendSurface", "MatchSurface"):
        assert name in cagd.__all__ and getattr(cagd, name) is getattr(cagd.operations, name)
    res = blend_surface(S1, "u1", S2, "u0")
    with pytest.raises(AttributeError):
        res.converged = False                                     # frozen


def test_rational_weights_limit_the_tangent_scales():
    """Weights varying fast across a NURBS edge turn the blend's inner weights negative
    for long tangents: explicit scales are refused, naming the scale and its limit,
    below which they work; the default is shortened (and says so)."""
    heavy = patch([1.6, 0.1, 0.3], KU2, KV2, 2, weights=(0.5, 2.0)).reversed("v")
    with pytest.raises(CagdError, match=r"tangent_scales\[1\]: .* below about") as info:
        blend_surface(S1, "u1", heavy, "u0", 2, tangent_scales=(1.0, 1.0))
    limit = float(str(info.value).rsplit(" ", 1)[1])
    assert 0.0 < limit < 1.0
    check_blend(S1, "u1", heavy, "u0", 2, scales=(1.0, 0.95 * limit))
    with pytest.raises(CagdError, match=r"tangent_scales\[1\]"):
        blend_surface(S1, "u1", heavy, "u0", 2, tangent_scales=(1.0, 1.05 * limit))
    res, _, _ = check_blend(S1, "u1", heavy, "u0", 2)
    assert "shortened to (1, " in res.message
    assert np.all(res.surface.weights > 0.0)
