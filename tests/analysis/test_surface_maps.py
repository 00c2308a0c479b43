"""Surface quality maps (cagd.analysis.surface_maps) against closed forms: sphere,
cylinder and torus curvatures, reflection lines of a plane and a cylinder, the draft
angle of a tilted plane; invariance under rigid motion and the scaling law; bad input."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd.analysis import curvature_map, draft_angle, isophotes, zebra

U = np.linspace(0.05, 0.95, 9)[:, None]
V = np.linspace(0.0, 1.0, 13)[None, :]
Z = np.array([0.0, 0.0, 1.0])


def plane(e1, e2, origin=(0.0, 0.0, 0.0)):
    """The bilinear patch origin + u e1 + v e2, u, v in [0, 1]: normal e1 x e2."""
    o, a, b = (np.asarray(x, dtype=float) for x in (origin, e1, e2))
    return cagd.BezierSurface(np.array([[o, o + b], [o + a, o + a + b]]))


@pytest.mark.parametrize("R", [0.5, 2.0, 300.0])
def test_sphere_curvatures_outward_normal(R):
    s = cagd.sphere(R, (1.0, -2.0, 3.0))
    np.testing.assert_allclose(curvature_map(s, U, V, "gaussian"), 1 / R ** 2, rtol=1e-12)
    # S_u x S_v points outwards: the normal curvature is -1/R in every direction
    for kind in ("mean", "max", "min"):
        np.testing.assert_allclose(curvature_map(s, U, V, kind), -1 / R, rtol=1e-12)


def test_sphere_poles_are_nan_by_the_documented_rule():
    s = cagd.sphere(1.0)
    k = curvature_map(s, np.array([0.0, 0.5, 1.0]), 0.3, "gaussian")
    assert np.isnan(k[0]) and np.isnan(k[2]) and abs(k[1] - 1.0) < 1e-12
    assert np.isnan(draft_angle(s, 0.0, 0.3, Z))
    zb = zebra(s, 0.0, 0.3, Z, [1.0, 0.0, 0.0])
    assert not zb.defined and zb.index == -1 and np.isnan(zb.phase)


@pytest.mark.parametrize("R", [0.25, 3.0])
def test_cylinder_curvatures(R):
    c = cagd.cylinder(R, 5.0)
    np.testing.assert_allclose(curvature_map(c, U, V, "gaussian"), 0.0, atol=1e-14 / R ** 2)
    np.testing.assert_allclose(curvature_map(c, U, V, "mean"), -1 / (2 * R), rtol=1e-12)
    np.testing.assert_allclose(curvature_map(c, U, V, "max"), 0.0, atol=1e-12 / R)
    np.testing.assert_allclose(curvature_map(c, U, V, "min"), -1 / R, rtol=1e-12)


@pytest.mark.parametrize("R, r", [(3.0, 1.0), (10.0, 0.5)])
def test_torus_gaussian_curvature_at_the_equators(R, r):
    t = cagd.torus(R, r)
    v = np.linspace(0, 1, 7)
    # u = 0 the outer equator, u = 1/2 the inner one (the profile circle starts outside, going down)
    np.testing.assert_allclose(curvature_map(t, 0.0, v, "gaussian"), 1 / (r * (R + r)), rtol=1e-12)
    np.testing.assert_allclose(curvature_map(t, 0.5, v, "gaussian"), -1 / (r * (R - r)), rtol=1e-12)
    # principal curvatures there: -1/r (the tube) and -1/(R + r), +1/(R - r) (the ring)
    np.testing.assert_allclose(curvature_map(t, 0.0, v, "min"), -1 / r, rtol=1e-12)
    np.testing.assert_allclose(curvature_map(t, 0.0, v, "max"), -1 / (R + r), rtol=1e-12)
    np.testing.assert_allclose(curvature_map(t, 0.5, v, "max"), 1 / (R - r), rtol=1e-12)


def test_mean_and_gaussian_maps_agree_with_the_surface_methods():
    s = cagd.BezierSurface(np.random.default_rng(1).normal(size=(4, 4, 3)) + np.arange(4)[:, None, None]
                           * [1.0, 0, 0] + np.arange(4)[None, :, None] * [0, 1.0, 0])
    np.testing.assert_array_equal(curvature_map(s, U, V, "gaussian"), s.gaussian_curvature(U, V))
    np.testing.assert_array_equal(curvature_map(s, U, V, "mean"), s.mean_curvature(U, V))
    kmax, kmin = curvature_map(s, U, V, "max"), curvature_map(s, U, V, "min")
    K, H = s.gaussian_curvature(U, V), s.mean_curvature(U, V)
    scale = np.abs(kmax) + np.abs(kmin)
    np.testing.assert_allclose(kmax * kmin, K, atol=1e-12 * np.max(scale) ** 2)
    np.testing.assert_allclose((kmax + kmin) / 2, H, atol=1e-12 * np.max(scale))
    assert np.all(kmax >= kmin)


def rotation(a, b, c):
    def axis(i, t):
        m = np.eye(3)
        j, k = [x for x in range(3) if x != i]
        m[j, j] = m[k, k] = np.cos(t)
        m[j, k], m[k, j] = -np.sin(t), np.sin(t)
        return m
    return axis(0, a) @ axis(1, b) @ axis(2, c)


angles = st.floats(-np.pi, np.pi)


@settings(max_examples=25, deadline=None)
@given(angles, angles, angles, st.floats(0.01, 100.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_rigid_motion_invariance_and_scaling_law(a, b, c, scale, u, v):
    t = cagd.torus(3.0, 1.0)
    moved = t.transformed(scale * rotation(a, b, c), [1.0, -5.0, 2.0])
    for kind, power in (("gaussian", 2), ("mean", 1), ("max", 1), ("min", 1)):
        before, after = curvature_map(t, u, v, kind), curvature_map(moved, u, v, kind)
        np.testing.assert_allclose(after * scale ** power, before, rtol=1e-9, atol=1e-11)


def test_zebra_of_a_plane_is_the_closed_form_constant():
    p = plane([2.0, 0, 0], [0, 3.0, 0])          # z = 0, normal +z
    view = np.array([0.3, -0.4, -1.0])
    view /= np.linalg.norm(view)
    a = np.array([1.0, 0, 0])
    zb = zebra(p, U, V, a, view, stripes=6)
    # r = (vx, vy, -vz); e1 = (0, vy, vz) / |.|, e2 = a x e1 = (0, -vz, vy) / |.|
    r = view * [1, 1, -1]
    q = np.hypot(view[1], view[2])
    x, y = (r[1] * view[1] + r[2] * view[2]) / q, (-r[1] * view[2] + r[2] * view[1]) / q
    expected = 6 * (np.arctan2(y, x) + np.pi) / (2 * np.pi) % 6
    assert zb.phase.shape == (9, 13) and np.all(zb.defined)
    np.testing.assert_allclose(zb.phase, expected, atol=1e-12)
    assert np.all(zb.index == int(np.floor(expected)))


@pytest.mark.parametrize("stripes", [1, 4, 9])
def test_zebra_of_a_cylinder_is_straight_parallel_stripes(stripes):
    c = cagd.cylinder(2.0, 5.0)
    u = np.linspace(0.0, 1.0, 11)[:, None]                 # along the rulings
    v = ((np.arange(3600) + 0.37) / 3600.0)[None, :]       # around, off the stripe edges
    zb = zebra(c, u, v, Z, [-1.0, 0.0, 0.0], stripes=stripes, width=0.5)
    assert np.all(zb.index == zb.index[:1]) and np.all(zb.lit == zb.lit[:1])   # constant along rulings
    p = c(u[:1], v)[0]
    theta = np.mod(np.arctan2(p[:, 1], p[:, 0]), 2 * np.pi)
    # closed form: n = (cos t, sin t, 0) reflects v = -x into (cos 2t, sin 2t, 0): phase = stripes t / pi
    np.testing.assert_allclose(zb.phase[0], np.mod(stripes * theta / np.pi, stripes), atol=1e-9)
    transitions = np.count_nonzero(np.diff(zb.lit[0].astype(int)))
    assert transitions in (4 * stripes - 1, 4 * stripes)   # 2 stripes bar periods around, on/off each


def test_isophotes_of_a_sphere_are_latitude_bands():
    s = cagd.sphere(1.0)
    iso = isophotes(s, U, V, Z, levels=4)
    p = s(U, V)
    np.testing.assert_allclose(iso.value, p[..., 2], atol=1e-12)      # n = p on the unit sphere
    np.testing.assert_array_equal(iso.band, np.minimum(np.floor(4 * (p[..., 2] + 1) / 2), 3).astype(int))
    custom = isophotes(s, U, V, Z, levels=[-0.5, 0.0, 0.5])
    np.testing.assert_array_equal(custom.band, np.searchsorted([-0.5, 0.0, 0.5], iso.value, side="right"))


@pytest.mark.parametrize("alpha_deg", [0.0, 3.0, 30.0, 89.0])
def test_draft_angle_of_a_tilted_plane(alpha_deg):
    a = np.radians(alpha_deg)
    # spanned by (sin a, 0, cos a) and y: normal (-cos a, 0, sin a), a wall tilted by a from vertical
    p = plane([np.sin(a), 0, np.cos(a)], [0, 1.0, 0])
    np.testing.assert_allclose(draft_angle(p, U, V, Z), a, atol=1e-14)
    np.testing.assert_allclose(draft_angle(p, U, V, Z, degrees=True), alpha_deg, atol=1e-12)
    np.testing.assert_allclose(draft_angle(p, U, V, -Z), -a, atol=1e-14)


@pytest.mark.parametrize("call, name", [
    (lambda s: curvature_map(s, 0.5, 0.5, "gauss"), "kind"),
    (lambda s: curvature_map(s, np.nan, 0.5), "u"),
    (lambda s: curvature_map(s, 0.5, [np.inf]), "v"),
    (lambda s: curvature_map("sphere", 0.5, 0.5), "surface"),
    (lambda s: zebra(s, 0.5, 0.5, [0, 0, 2.0], [1.0, 0, 0]), "light_dir"),
    (lambda s: zebra(s, 0.5, 0.5, [0, 0, 0.0], [1.0, 0, 0]), "light_dir"),
    (lambda s: zebra(s, 0.5, 0.5, Z, [1.0, 0]), "view_dir"),
    (lambda s: zebra(s, 0.5, 0.5, Z, [np.nan, 0, 0]), "view_dir"),
    (lambda s: zebra(s, 0.5, 0.5, Z, [1.0, 0, 0], stripes=0), "stripes"),
    (lambda s: zebra(s, 0.5, 0.5, Z, [1.0, 0, 0], width=1.0), "width"),
    (lambda s: isophotes(s, 0.5, 0.5, Z, levels=0), "levels"),
    (lambda s: isophotes(s, 0.5, 0.5, Z, levels=[0.5, 0.0]), "levels"),
    (lambda s: isophotes(s, 0.5, 0.5, [0.1, 0, 0]), "light_dir"),
    (lambda s: draft_angle(s, 0.5, 0.5, [0, 0, 1.001]), "pull_dir"),
])
def test_bad_input_is_a_cagd_error_naming_the_argument(call, name):
    with pytest.raises(cagd.CagdError, match=f"^{name}"):
        call(cagd.sphere(1.0))


@settings(max_examples=25, deadline=None)
@given(angles, angles, angles, st.floats(0.01, 100.0), st.floats(0.02, 0.98), st.floats(0.0, 1.0))
def test_zebra_isophotes_draft_move_with_the_scene(a, b, c, scale, u, v):
    # rotating (and scaling) the surface with its lights, view and pull leaves every map unchanged
    t = cagd.torus(3.0, 1.0)
    Q = rotation(a, b, c)
    moved = t.transformed(scale * Q, [4.0, 0.5, -1.0])
    light, view = np.array([0.0, 0.6, 0.8]), np.array([-1.0, 0.0, 0.0])
    z0, z1 = zebra(t, u, v, light, view, 7), zebra(moved, u, v, Q @ light, Q @ view, 7)
    phase_gap = abs(float(z0.phase) - float(z1.phase))
    assert min(phase_gap, 7 - phase_gap) < 1e-9
    np.testing.assert_allclose(isophotes(moved, u, v, Q @ light).value, isophotes(t, u, v, light).value, atol=1e-12)
    np.testing.assert_allclose(draft_angle(moved, u, v, Q @ Z), draft_angle(t, u, v, Z), atol=1e-9)
