"""The ellipsoid octant of seed 003, 2.4 (bicubic rational Bezier patch) and the whole
ellipsoid from eight reflected patches: the seed's table against the seed's own polar
form, the implicit equation, the trigonometric parametrisation, the area (elliptic
integrals), shared edges, octant signs, outward normals and the pole."""
import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import ellipeinc, ellipkinc

from cagd import BezierSurface, CagdError
from cagd.surfaces.ellipsoid import SEED_W, SEED_X, SEED_Y, SEED_Z, ellipsoid, ellipsoid_octant

SETTINGS = settings(max_examples=30, deadline=None)
U = np.linspace(0.0, 1.0, 101)
RNG = np.random.default_rng(7)
RU, RV = RNG.random(3000), RNG.random(3000)
axes = st.floats(0.05, 20.0)


def seed_polar_form(us, vs, a, b, c):
    """The seed's bicubic polar form (X, Y, Z, W) of the homogeneous ellipsoid
    X = a(1-u^2)(1-v^2), Y = 2b(1-u^2)v, Z = 2c(1+v^2)u, W = (1+u^2)(1+v^2),
    u = tan(phi/2), v = tan(theta/2), typed from the seed's formulas."""
    u1, u2, u3 = us
    v1, v2, v3 = vs
    su2 = (u1 * u2 + u2 * u3 + u1 * u3) / 3
    sv2 = (v1 * v2 + v2 * v3 + v1 * v3) / 3
    su1, sv1 = (u1 + u2 + u3) / 3, (v1 + v2 + v3) / 3
    return np.stack([a * (1 - su2) * (1 - sv2), 2 * b * (1 - su2) * sv1, 2 * c * (1 + sv2) * su1,
                     (1 + su2) * (1 + sv2)], axis=-1)


def implicit(P, a, b, c):
    return np.abs((P[..., 0] / a) ** 2 + (P[..., 1] / b) ** 2 + (P[..., 2] / c) ** 2 - 1)


# --- the seed's table ---------------------------------------------------------------------
def test_seed_table_is_the_transposed_homogeneous_polar_form():
    """Block i, column j of the seed's table = f(0^(3-j) 1^j; 0^(3-i) 1^i) (homogeneous):
    the block index counts the seed's v = tan(theta/2)."""
    a, b, c = 3.0, 2.0, 1.5
    table = np.stack([a * SEED_X, b * SEED_Y, c * SEED_Z, SEED_W], axis=-1)
    blossom = np.empty((4, 4, 4))
    for i in range(4):
        for j in range(4):
            blossom[i, j] = seed_polar_form([0.0] * (3 - j) + [1.0] * j, [0.0] * (3 - i) + [1.0] * i, a, b, c)
    assert np.abs(table - blossom).max() <= 1e-15 * 4
    # read literally (block i = u-index of the polar form) the table does not match
    assert np.abs(table - blossom.transpose(1, 0, 2)).max() > 0.5


def test_reading_the_table_as_cartesian_points_is_off_the_ellipsoid():
    """The columns labelled (p, w) are (w p, w): as Cartesian points with weights w the
    patch leaves the ellipsoid (while the homogeneous reading is exact)."""
    a, b, c = 3.0, 2.0, 1.5
    wrong = BezierSurface(np.stack([a * SEED_X, b * SEED_Y, c * SEED_Z], axis=-1), SEED_W)
    assert implicit(wrong.grid(U, U), a, b, c).max() > 0.1
    assert implicit(ellipsoid_octant(a, b, c).grid(U, U), a, b, c).max() <= 1e-14


def test_patch_shape_and_degenerate_pole_edge():
    S = ellipsoid_octant(3.0, 2.0, 1.5)
    assert isinstance(S, BezierSurface) and S.is_rational
    assert (S.degree_u, S.degree_v) == (3, 3)
    assert np.array_equal(S.control_points[:, 3], np.tile([0.0, 0.0, 1.5], (4, 1)))
    assert np.array_equal(S.control_points[0, 0], [3.0, 0.0, 0.0])
    assert np.array_equal(S.control_points[3, 0], [0.0, 2.0, 0.0])


# --- exactness ---------------------------------------------------------------------------------
@SETTINGS
@given(axes, axes, axes)
def test_octant_on_the_ellipsoid(a, b, c):
    S = ellipsoid_octant(a, b, c)
    assert implicit(S.grid(U, U), a, b, c).max() <= 1e-14
    assert implicit(S(RU, RV), a, b, c).max() <= 1e-14
    assert implicit(S.to_nurbs()(RU, RV), a, b, c).max() <= 1e-14


@SETTINGS
@given(axes, axes, axes)
def test_octant_parametrisation(a, b, c):
    """S(u, v) = (a cos(phi) cos(theta), b cos(phi) sin(theta), c sin(phi)) with
    theta = 2 atan(u), phi = 2 atan(v) (the seed's substitution, u and v exchanged)."""
    theta, phi = 2 * np.arctan(RU), 2 * np.arctan(RV)
    expected = np.stack([a * np.cos(phi) * np.cos(theta), b * np.cos(phi) * np.sin(theta), c * np.sin(phi)], -1)
    assert np.abs(ellipsoid_octant(a, b, c)(RU, RV) - expected).max() <= 1e-14 * max(a, b, c)


def test_blossom_is_the_seeds_polar_form():
    """BezierSurface.blossom of the patch = the seed's polar form (u and v exchanged),
    projected: an independent check of all 16 weights and points at random arguments."""
    a, b, c = 2.5, 1.25, 4.0
    S = ellipsoid_octant(a, b, c)
    us = [RNG.random(200) for _ in range(3)]
    vs = [RNG.random(200) for _ in range(3)]
    H = seed_polar_form(vs, us, a, b, c)
    assert np.abs(S.blossom(us, vs) - H[:, :3] / H[:, 3:]).max() <= 1e-14 * 4


# --- eight patches ---------------------------------------------------------------------------
SIGNS = [np.array([sx, sy, sz]) for sz, sy, sx in itertools.product((1, -1), repeat=3)]


@SETTINGS
@given(axes, axes, axes)
def test_eight_patches_on_the_ellipsoid_and_in_their_octants(a, b, c):
    patches = ellipsoid(a, b, c)
    assert len(patches) == 8
    inner = np.linspace(0.01, 0.99, 41)
    for S, sign in zip(patches, SIGNS):
        P = S.grid(U, U)
        assert implicit(P, a, b, c).max() <= 1e-14
        assert np.all(P * sign >= 0.0)
        assert np.all(S.grid(inner, inner) * sign > 0.0)


def test_the_eight_areas_add_up_to_the_ellipsoid():
    """Surface area by Gauss-Legendre quadrature of |S_u x S_v| over the eight patches
    against the closed form with incomplete elliptic integrals (a > b > c)."""
    a, b, c = 3.0, 2.0, 1.0
    x, w = np.polynomial.legendre.leggauss(60)
    t, w = 0.5 * (x + 1), 0.5 * w
    area = 0.0
    for S in ellipsoid(a, b, c):
        su, sv = S.grid(t, t, 1, 0), S.grid(t, t, 0, 1)
        area += w @ np.linalg.norm(np.cross(su, sv), axis=-1) @ w
    phi = math.acos(c / a)
    k2 = a * a * (b * b - c * c) / (b * b * (a * a - c * c))
    exact = 2 * math.pi * c * c + 2 * math.pi * a * b / math.sin(phi) * (
        math.cos(phi) ** 2 * ellipkinc(phi, k2) + math.sin(phi) ** 2 * ellipeinc(phi, k2))
    assert area == pytest.approx(exact, rel=1e-10)


def edges(S):
    """The three non-degenerate edges as homogeneous control rows: u = 0, u = 1, v = 0."""
    H = S.homogeneous_control_points
    return {"u0": H[0], "u1": H[-1], "v0": H[:, 0]}


def test_neighbouring_patches_share_edges():
    """Every non-degenerate edge of every patch is the edge of exactly one other patch,
    with the same homogeneous control points (possibly reversed), hence C0; that patch
    lies in the octant across one coordinate plane; sampled edges coincide."""
    patches = ellipsoid(3.0, 2.0, 1.5)
    matches = 0
    for k, S in enumerate(patches):
        for name, row in edges(S).items():
            found = [(m, other) for m, T in enumerate(patches) if m != k
                     for other, r in edges(T).items()
                     if np.array_equal(r, row) or np.array_equal(r[::-1], row)]
            assert len(found) == 1, (k, name, found)
            m, other = found[0]
            assert np.count_nonzero(SIGNS[k] != SIGNS[m]) == 1
            t = np.linspace(0, 1, 57)
            e1 = S.isocurve("u" if name == "v0" else "v", 0.0 if name != "u1" else 1.0)(t)
            e2 = patches[m].isocurve("u" if other == "v0" else "v", 0.0 if other != "u1" else 1.0)(t)
            assert (np.abs(e1 - e2).max() <= 1e-15 * 3 or np.abs(e1 - e2[::-1]).max() <= 1e-15 * 3)
            matches += 1
    assert matches == 24                     # 12 shared edges, each seen from both sides
    poles = [S(RU[:50], 1.0) for S in patches]
    for P, sign in zip(poles, SIGNS):
        assert np.abs(P - [0.0, 0.0, 1.5 * sign[2]]).max() <= 1e-15


# --- normals ----------------------------------------------------------------------------------
def test_normals_outward_and_pole_limit():
    """n = S_u x S_v / |...| equals the normalised gradient (x/a^2, y/b^2, z/c^2) on every
    patch; at the pole edge S_u = 0 (CagdError), but the normal tends to (0, 0, +-1)."""
    a, b, c = 3.0, 2.0, 1.5
    u, v = RU[:400], 0.98 * RV[:400]
    for S, sign in zip(ellipsoid(a, b, c), SIGNS):
        P = S(u, v)
        g = P / np.array([a, b, c]) ** 2
        assert np.abs(S.normal(u, v) - g / np.linalg.norm(g, axis=1, keepdims=True)).max() <= 1e-12
        assert np.abs(S.derivative(u, 1.0, 1, 0)).max() <= 1e-14
        with pytest.raises(CagdError, match="normal"):
            S.normal(0.5, 1.0)
        n = S.normal(np.linspace(0, 1, 11), 1.0 - 1e-7)
        assert np.abs(n - [0.0, 0.0, sign[2]]).max() <= 1e-6


@pytest.mark.parametrize("args, name", [((0.0, 1.0, 1.0), "a"), ((1.0, -2.0, 1.0), "b"),
                                        ((1.0, 1.0, np.nan), "c"), ((1.0, "x", 1.0), "b")])
def test_bad_semi_axes(args, name):
    with pytest.raises(CagdError, match=f"^{name}:"):
        ellipsoid_octant(*args)
    with pytest.raises(CagdError, match=f"^{name}:"):
        ellipsoid(*args)
