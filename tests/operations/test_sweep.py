"""Sweeps (cagd.sweep, cagd.sweep2): exact analytic cases (a plane, cylinders) to 1e-12,
the rotation-minimising frame on a helix against its closed form (normal turning by
-tau s relative to Frenet), the reported max_error checked against an independent true
sweep (the RMF integrated by scipy's solve_ivp from r' = -(r . T') T), two-rail edges on
the rails, and bad input."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd
from cagd import BSplineCurve, CagdError, sweep, sweep2

EXACT = 1e-12
R_HELIX, C_HELIX = 2.0, 0.5          # helix (R cos th, R sin th, c th)
HELIX_TURNS = 4.0 * math.pi


def circle(radius=1.0, center=(0.0, 0.0, 0.0)):
    """Exact full NURBS circle in the xy-plane (rational quadratic, four spans; P&T 7.3)."""
    w = math.sqrt(0.5)
    P = np.array([[1, 0, 0], [1, 1, 0], [0, 1, 0], [-1, 1, 0], [-1, 0, 0], [-1, -1, 0], [0, -1, 0], [1, -1, 0],
                  [1, 0, 0]], float) * radius + np.asarray(center, float)
    return BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, w, 1, w, 1, w, 1, w, 1])


def helix_path(samples=801):
    th = np.linspace(0.0, HELIX_TURNS, samples)
    pts = np.c_[R_HELIX * np.cos(th), R_HELIX * np.sin(th), C_HELIX * th]
    return cagd.interpolate(pts, 3)


HELIX = helix_path()


def grid(surface, n=101):
    (u0, u1), (v0, v1) = surface.domain
    u, v = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
    return u.ravel(), v.ravel(), surface(u.ravel(), v.ravel())


def path_param(path, t):
    a, b = path.domain
    return a + np.asarray(t) * (b - a)


# --- an independent true sweep ------------------------------------------------------------
def rmf_ode(path, t):
    """Rotation-minimising normals at t (normalised) by integrating r' = -(r . T') T
    (Bishop 1975) with scipy, from the start normal e normal to T(0)."""
    from scipy.integrate import solve_ivp

    def T_and_dT(tt):
        D = path.derivatives(path_param(path, tt), 2)
        d1, d2 = D[1], D[2]
        s = np.linalg.norm(d1)
        T = d1 / s
        return T, (d2 - (d2 @ T) * T) / s * (path.domain[1] - path.domain[0])

    T0, _ = T_and_dT(0.0)
    e = np.zeros(3)
    e[int(np.argmin(np.abs(T0)))] = 1.0
    r0 = e - (e @ T0) * T0
    r0 /= np.linalg.norm(r0)

    def rhs(tt, r):
        T, dT = T_and_dT(tt)
        return -(r @ dT) * T

    sol = solve_ivp(rhs, (0.0, 1.0), r0, t_eval=np.unique(np.concatenate([[0.0], t])), rtol=1e-12, atol=1e-13,
                    method="DOP853")
    out = sol.y.T
    idx = np.searchsorted(np.unique(np.concatenate([[0.0], t])), t)
    return out[idx]


def frames_true(path, t, frame):
    t = np.asarray(t, float)
    D = path.derivatives(path_param(path, t), 2)
    T = D[1] / np.linalg.norm(D[1], axis=-1, keepdims=True)
    if frame == "fixed":
        return np.broadcast_to(np.eye(3), (len(t), 3, 3))
    if frame == "rmf":
        r = rmf_ode(path, t)
        r = r - np.einsum("ki,ki->k", r, T)[:, None] * T
        r /= np.linalg.norm(r, axis=-1, keepdims=True)
    elif frame == "frenet":
        B = np.cross(D[1], D[2])
        B /= np.linalg.norm(B, axis=-1, keepdims=True)
        r = np.cross(B, T)
    else:
        up = np.asarray(frame, float)
        r = up - np.einsum("ki,i->k", T, up)[:, None] * T
        r /= np.linalg.norm(r, axis=-1, keepdims=True)
    return np.stack([T, r, np.cross(T, r)], axis=-1)


def true_sweep(profile, path, frame, u, t, scale=None, twist=None):
    """S(u, t) = c(t) + s(t) F(t) R_T(theta(t)) F(0)^T (C(u) - c(0)), pointwise."""
    t = np.asarray(t, float)
    F = frames_true(path, np.concatenate([[0.0], t]), frame)
    F0, F = F[0], F[1:]
    s = np.array([1.0 if scale is None else (scale(x) if callable(scale) else scale) for x in t])
    th = np.array([0.0 if twist is None else (twist(x) if callable(twist) else twist) for x in t])
    c, sn = np.cos(th), np.sin(th)
    Rx = np.zeros((len(t), 3, 3))
    Rx[:, 0, 0], Rx[:, 1, 1], Rx[:, 1, 2], Rx[:, 2, 1], Rx[:, 2, 2] = 1, c, -sn, sn, c
    M = s[:, None, None] * F @ Rx @ F0.T
    x0 = path(path_param(path, 0.0))
    rel = profile(u) - x0
    return path(path_param(path, t)) + np.einsum("kij,kj->ki", M, rel)


# --- exact cases ------------------------------------------------------------------------------
def test_line_along_line_is_the_bilinear_plane():
    prof = BSplineCurve([[0, 0, 0], [1, 0, 0]], 1)
    path = BSplineCurve([[0, 0, 0], [0, 1, 0], [0, 3, 0]], 2, [0, 0, 0, 1, 1, 1])   # a line, uneven speed
    for frame in ("rmf", "fixed", [0, 0, 1]):
        r = sweep(prof, path, frame=frame)
        assert r.converged and r.max_error <= EXACT
        S = r.surface
        assert (S.degree_u, S.degree_v) == (1, 2) and not S.is_rational
        u, v, X = grid(S)
        np.testing.assert_allclose(X[:, 2], 0.0, atol=EXACT)
        expected = np.c_[u, path(path_param(path, v))[:, 1], np.zeros_like(u)]
        np.testing.assert_allclose(X, expected, atol=EXACT)


@pytest.mark.parametrize("frame", ["rmf", "fixed", [1.0, 0.0, 0.0]])
def test_circle_along_line_is_a_cylinder(frame):
    R = 1.5
    prof = circle(R)
    path = BSplineCurve([[0, 0, 0], [0, 0, 1], [0, 0, 1.5], [0, 0, 3]], 3)   # the z axis, cubic parametrisation
    r = sweep(prof, path, frame=frame)
    assert r.converged and r.max_error <= EXACT
    S = r.surface
    assert S.is_rational and S.degree_u == 2
    np.testing.assert_array_equal(S.knots_u, prof.knots)
    u, v, X = grid(S, 201)
    np.testing.assert_allclose(np.hypot(X[:, 0], X[:, 1]), R, atol=EXACT, rtol=0)
    np.testing.assert_allclose(X[:, 2], path(path_param(path, v))[:, 2], atol=EXACT)
    assert X[:, 2].min() >= -EXACT and X[:, 2].max() <= 3 + EXACT


def test_circle_along_tilted_line_rmf_is_a_cylinder_about_that_line():
    R = 0.7
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    prof0 = circle(R)
    # the circle placed normal to the axis: rotate z onto axis
    z = np.array([0.0, 0.0, 1.0])
    k = np.cross(z, axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    Rot = np.eye(3) + K + K @ K / (1 + z @ axis)
    prof = prof0.transformed(Rot, [1.0, -1.0, 0.5])
    path = BSplineCurve([[1.0, -1.0, 0.5], [1.0, -1.0, 0.5] + 4 * axis], 1)
    r = sweep(prof, path)
    assert r.converged
    _, _, X = grid(r.surface, 201)
    rel = X - [1.0, -1.0, 0.5]
    radial = rel - np.outer(rel @ axis, axis)
    np.testing.assert_allclose(np.linalg.norm(radial, axis=-1), R, atol=EXACT, rtol=0)


def test_rational_path_translational_sweep_is_exact():
    prof = BSplineCurve([[0, 0, 0], [0, 0, 1]], 1)
    arc = BSplineCurve([[0, 0, 0], [1, 0, 0], [1, 1, 0]], 2, None, [1, math.sqrt(0.5), 1])  # quarter circle
    r = sweep(prof, arc, frame="fixed")
    assert r.converged and r.max_error <= EXACT
    _, _, X = grid(r.surface)
    np.testing.assert_allclose(np.hypot(X[:, 0], X[:, 1] - 1.0), 1.0, atol=EXACT, rtol=0)


# --- the rotation-minimising frame on a helix ---------------------------------------------------
def helix_closed_form(theta):
    L = math.hypot(R_HELIX, C_HELIX)
    T = np.c_[-R_HELIX * np.sin(theta), R_HELIX * np.cos(theta), np.full_like(theta, C_HELIX)] / L
    N = np.c_[-np.cos(theta), -np.sin(theta), np.zeros_like(theta)]
    B = np.cross(T, N)
    tau = C_HELIX / L ** 2
    s = L * theta
    return T, N, B, tau, s


@pytest.mark.parametrize("frame", ["rmf", "frenet"])
def test_helix_frame_against_closed_form(frame):
    """A short segment from c(0) along N(0): its far end traces c(t) + rho r(t) with, for
    the RMF, r = cos(tau s) N - sin(tau s) B (the normal turns by -tau s relative to
    Frenet), and r = N for the Frenet frame."""
    rho = 0.25
    x0 = HELIX(HELIX.domain[0])
    N0 = np.array([-1.0, 0.0, 0.0])
    prof = BSplineCurve([x0, x0 + rho * N0], 1)
    r = sweep(prof, HELIX, frame=frame, tol=1e-7)
    assert r.converged and r.max_error <= 1e-7
    v = np.linspace(0.0, 1.0, 401)
    X = r.surface(np.ones_like(v), v)
    c = HELIX(path_param(HELIX, v))
    theta = c[:, 2] / C_HELIX                    # the helix angle of the path point
    _, N, B, tau, s = helix_closed_form(theta)
    if frame == "rmf":
        expected = np.cos(tau * s)[:, None] * N - np.sin(tau * s)[:, None] * B
    else:
        expected = N
    # the interpolated path is a helix to about 1e-9 (801 points): frames agree to ~1e-6
    np.testing.assert_allclose((X - c) / rho, expected, atol=2e-6)
    # and the RMF really differs from Frenet: tau s reaches 4 pi c / L = 3.05 rad
    assert frame == "frenet" or np.linalg.norm(expected[-1] - N[-1]) > 1.5


# --- honesty of max_error --------------------------------------------------------------------------
PATHS = {
    "helix": helix_path(41),
    "space cubic": BSplineCurve([[0, 0, 0], [1, 2, 0.5], [2, 2.5, -0.5], [3, 1, 1.0], [4, 0, 0.3]], 3,
                                [0, 0, 0, 0, 0.4, 1, 1, 1, 1]),
}


@pytest.mark.parametrize("name", sorted(PATHS))
@pytest.mark.parametrize("frame", ["rmf", "frenet", "fixed", [0.0, 0.0, 1.0]])
@pytest.mark.parametrize("laws", [False, True])
def test_max_error_is_honest(name, frame, laws):
    path = PATHS[name]
    x0 = path(path_param(path, 0.0))
    prof = circle(0.3).transformed(np.eye(3), x0) if name == "helix" else \
        BSplineCurve(x0 + np.array([[0, 0, 0], [0, 0.3, 0.1], [0, 0.2, 0.5], [0.1, -0.2, 0.4]]), 3)
    scale = (lambda t: 1.0 + 0.5 * t) if laws else None
    twist = (lambda t: 2.0 * t * t) if laws else None
    tol = 1e-5
    r = sweep(prof, path, frame=frame, scale=scale, twist=twist, tol=tol)
    assert r.converged and r.max_error <= tol, r.message
    rng = np.random.default_rng(7)
    (u0, u1), _ = r.surface.domain
    u = rng.uniform(u0, u1, 400)
    t = np.sort(rng.uniform(0.0, 1.0, 400))
    X = r.surface(u, t)
    Y = true_sweep(prof, path, frame, u, t, scale, twist)
    miss = np.linalg.norm(X - Y, axis=-1)
    assert miss.max() <= r.max_error + 1e-9, (miss.max(), r.max_error)
    # the start edge is the placed profile itself (scale(0) = 1, twist(0) = 0)
    np.testing.assert_allclose(r.surface(u, np.zeros_like(u)), prof(u), atol=EXACT)


def test_rmf_frame_is_continuous_across_its_grid_points():
    """The rotation-minimising frame at a parameter a rounding step past one of its grid
    points equals the frame there (a step of 3e-17 had a direction of rounding noise, and
    the reflection across its plane turned the frame by 0.3 rad at t = 11/64 of the space
    cubic: its sweep at tol 1e-5 passed only where no station fell there)."""
    from cagd.operations.sweep import RMF_SAMPLES, _Path
    path = PATHS["space cubic"]
    P = _Path(path, "rmf")
    k = np.array([1, 704, 1472, 2048, RMF_SAMPLES - 1])
    t = k / RMF_SAMPLES
    _, at = P.frames(t)
    for nudge in (np.nextafter(t, 2.0), np.nextafter(np.nextafter(t, 2.0), 2.0), t + 1e-15):
        _, near = P.frames(nudge)
        assert np.abs(near - at).max() <= 1e-12
    # and densely: no jump larger than the frame's own turning between samples
    tt = np.linspace(0.0, 1.0, 200_001)
    _, F = P.frames(tt)
    jumps = np.linalg.norm(np.diff(F[:, :, 1], axis=0), axis=1)
    assert jumps.max() <= 4.0 * np.median(jumps) + 1e-9


def test_not_converged_is_reported():
    r = sweep(circle(0.3).transformed(np.eye(3), HELIX(HELIX.domain[0])), HELIX, tol=1e-14)
    assert not r.converged and r.max_error > r.tol
    assert "not converged" in r.message
    assert r.max_error < 1e-6          # still the measured value (of the best stations), not the tolerance


# --- sweep2 ---------------------------------------------------------------------------------------
def test_sweep2_straight_profile_between_parallel_lines_is_a_plane():
    r1 = BSplineCurve([[0, 0, 0], [0, 0.5, 0], [0, 3, 0]], 2)
    r2 = BSplineCurve([[2, 0, 0], [2, 2, 0], [2, 3, 0]], 2)
    prof = BSplineCurve([[5, 5, 5], [6, 5, 5]], 1)        # anywhere: the similarity places it
    r = sweep2(prof, r1, r2)
    assert r.converged and r.max_error <= 1e-12
    u, v, X = grid(r.surface)
    np.testing.assert_allclose(X[:, 2], 0.0, atol=EXACT)
    assert X[:, 0].min() >= -EXACT and X[:, 0].max() <= 2 + EXACT


RAIL1 = BSplineCurve([[0, 0, 0], [0.5, 1, 0.2], [0, 2, 0.5], [0.3, 3, 0]], 3)
RAIL2 = BSplineCurve([[2, 0, 0], [2.5, 1, 0.8], [3, 2, 0.1], [2.2, 3.2, 0.4]], 3)


def test_sweep2_edges_lie_on_the_rails():
    arc = BSplineCurve([[0, 0, 0], [1, 0, 1], [2, 0, 0]], 2, None, [1, math.sqrt(0.5), 1])
    r = sweep2(arc, RAIL1, RAIL2, tol=1e-6)
    assert r.converged and r.max_error <= 1e-6
    v = np.linspace(0, 1, 301)
    (u0, u1), _ = r.surface.domain
    e1 = r.surface(np.full_like(v, u0), v)
    e2 = r.surface(np.full_like(v, u1), v)
    assert np.max(np.linalg.norm(e1 - RAIL1(v), axis=-1)) <= r.max_error + EXACT
    assert np.max(np.linalg.norm(e2 - RAIL2(v), axis=-1)) <= r.max_error + EXACT
    # and the profile's shape is kept: the apex is at 1/2 of the chord length from it
    mid = r.surface(np.full_like(v, 0.5 * (u0 + u1)), v)
    a, b = RAIL1(v), RAIL2(v)
    h = np.linalg.norm(mid - 0.5 * (a + b), axis=-1) / np.linalg.norm(b - a, axis=-1)
    np.testing.assert_allclose(h, arc(0.5)[2] / 2.0, atol=1e-5)


def test_sweep2_several_profiles_pass_through_each():
    r1 = BSplineCurve([[0, 0, 0], [0, 1, 0], [0, 2, 0]], 2)
    r2 = BSplineCurve([[1, 0, 0], [1, 1, 0], [1, 2, 0]], 2)
    p0 = BSplineCurve([[0, 0, 0], [0.5, 0, 0.2], [1, 0, 0]], 2)
    p1 = BSplineCurve([[0, 1, 0], [0.5, 1, 0.6], [1, 1, 0]], 2)
    p2 = BSplineCurve([[0, 2, 0], [0.5, 2, 0.1], [1, 2, 0]], 2)
    r = sweep2([p2, p0, p1], r1, r2, tol=1e-7)           # any order
    assert r.converged
    u = np.linspace(0, 1, 51)
    for p, t in ((p0, 0.0), (p1, 0.5), (p2, 1.0)):
        np.testing.assert_allclose(r.surface(u, np.full_like(u, t)), p(u), atol=1e-7)


# --- bad input ------------------------------------------------------------------------------------
LINE = BSplineCurve([[0, 0, 0], [0, 0, 1]], 1)
PROF = BSplineCurve([[0, 0, 0], [1, 0, 0]], 1)


@pytest.mark.parametrize("kwargs, name", [
    (dict(profile="x", path=LINE), "profile"),
    (dict(profile=PROF, path=np.zeros((2, 3))), "path"),
    (dict(profile=BSplineCurve([[0, 0], [1, 0]], 1), path=LINE), "profile"),
    (dict(profile=PROF, path=BSplineCurve([[0, 0, 0], [0, 0, 0]], 1)), "path"),
    (dict(profile=PROF, path=LINE, frame="bishop"), "frame"),
    (dict(profile=PROF, path=LINE, frame=[0, 0]), "frame"),
    (dict(profile=PROF, path=LINE, frame=[0, 0, 0]), "frame"),
    (dict(profile=PROF, path=LINE, frame=[0, 0, np.nan]), "frame"),
    (dict(profile=PROF, path=LINE, frame=[0, 0, 1]), "frame"),      # parallel to the tangent
    (dict(profile=PROF, path=LINE, frame="frenet"), "frame"),       # no curvature
    (dict(profile=PROF, path=LINE, scale=0.0), "scale"),
    (dict(profile=PROF, path=LINE, scale=lambda t: -1.0), "scale"),
    (dict(profile=PROF, path=LINE, scale=lambda t: math.inf), "scale"),
    (dict(profile=PROF, path=LINE, twist=lambda t: math.nan), "twist"),
    (dict(profile=PROF, path=LINE, twist="a"), "twist"),
    (dict(profile=PROF, path=LINE, tol=0.0), "tol"),
    (dict(profile=PROF, path=LINE, tol=math.nan), "tol"),
])
def test_sweep_bad_input_names_the_argument(kwargs, name):
    with pytest.raises(CagdError, match=rf"^{name}"):
        sweep(**kwargs)


def test_sweep2_bad_input_names_the_argument():
    r1 = BSplineCurve([[0, 0, 0], [0, 1, 0]], 1)
    with pytest.raises(CagdError, match=r"^rail2.*zero-length chord"):
        sweep2(PROF, r1, BSplineCurve([[1, 0, 0], [0, 1, 0]], 1))    # meets rail1 at t = 1
    with pytest.raises(CagdError, match=r"^profiles\[0\]"):
        sweep2(BSplineCurve([[0, 0, 0], [1, 1, 0], [0, 0, 0]], 2), r1, BSplineCurve([[1, 0, 0], [1, 1, 0]], 1))
    with pytest.raises(CagdError, match=r"^profiles"):
        sweep2([], r1, BSplineCurve([[1, 0, 0], [1, 1, 0]], 1))
    with pytest.raises(CagdError, match=r"^rail1"):
        sweep2(PROF, "r", BSplineCurve([[1, 0, 0], [1, 1, 0]], 1))
    with pytest.raises(CagdError, match=r"^tol"):
        sweep2(PROF, r1, BSplineCurve([[1, 0, 0], [1, 1, 0]], 1), tol=-1.0)


# --- hypothesis -----------------------------------------------------------------------------------
coords = st.floats(-2.0, 2.0, allow_nan=False)


@settings(max_examples=12, deadline=None)
@given(prof=st.lists(st.tuples(coords, coords, coords), min_size=3, max_size=5),
       steps=st.lists(st.tuples(st.floats(0.3, 1.0), coords, coords), min_size=3, max_size=4),
       frame=st.sampled_from(["rmf", "fixed", "up"]), scale=st.floats(0.5, 2.0))
def test_random_sweeps_start_at_the_profile_and_report_honestly(prof, steps, frame, scale):
    """Random profiles and x-monotone paths (never degenerate; the up vector (0, 0, 1) is
    kept off the tangent by steps bounded in z): the start edge is the placed profile and
    every sampled point is within max_error of the true sweep."""
    P = np.array(prof)
    profile = BSplineCurve(P, min(3, len(P) - 1))
    Q = np.cumsum(np.vstack([[0.0, 0.0, 0.0], np.array(steps) * [1.0, 0.5, 0.3]]), axis=0)
    path = BSplineCurve(Q, min(3, len(Q) - 1))
    up = [0.0, 0.0, 1.0]
    fr = up if frame == "up" else frame

    def law(t):
        return 1.0 + (scale - 1.0) * t

    tol = 1e-4
    r = sweep(profile, path, frame=fr, scale=law, tol=tol)
    assert r.converged and r.max_error <= tol
    rng = np.random.default_rng(0)
    u = rng.uniform(0.0, 1.0, 100)
    np.testing.assert_allclose(r.surface(u, np.zeros_like(u)), profile(u) + (Q[0] - path(0.0)), atol=1e-10)
    t = rng.uniform(0.0, 1.0, 100)
    Y = true_sweep(profile, path, fr, u, t, scale=law)
    miss = np.linalg.norm(r.surface(u, t) - Y, axis=-1)
    assert miss.max() <= r.max_error + 1e-10


# --- a circular path: an exact surface of revolution ------------------------------------------------
R_MAJOR, R_MINOR = 3.0, 1.0
XZ = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])     # the xy-plane onto the xz-plane


def torus_residual(X, R=R_MAJOR, r=R_MINOR):
    """(sqrt(x^2 + y^2) - R)^2 + z^2 - r^2: zero on the torus about the z axis."""
    return (np.hypot(X[:, 0], X[:, 1]) - R) ** 2 + X[:, 2] ** 2 - r ** 2


def random_points(surface, count=2000, seed=3):
    rng = np.random.default_rng(seed)
    (u0, u1), (v0, v1) = surface.domain
    return surface(rng.uniform(u0, u1, count), rng.uniform(v0, v1, count))


@pytest.mark.parametrize("frame", ["rmf", "frenet", [0.0, 0.0, 1.0], [0.0, 0.0, -2.0]])
def test_circle_around_a_circle_is_an_exact_torus(frame):
    from cagd.surfaces.revolution import RevolvedSurface
    prof = circle(R_MINOR).transformed(XZ, [R_MAJOR, 0.0, 0.0])
    r = sweep(prof, circle(R_MAJOR), frame=frame)
    assert r.converged and r.max_error <= 1e-14 and "revolution" in r.message, r.message
    assert isinstance(r.surface, RevolvedSurface) and r.surface.revolution.angle == 2.0 * math.pi
    np.testing.assert_allclose(r.surface.revolution.axis_direction, [0.0, 0.0, 1.0], atol=1e-15)
    X = random_points(r.surface)
    assert np.abs(torus_residual(X)).max() <= 1e-12
    # the whole torus is covered: the angles about the axis and about the tube fill [-pi, pi]
    phi = np.arctan2(X[:, 1], X[:, 0])
    psi = np.arctan2(X[:, 2], np.hypot(X[:, 0], X[:, 1]) - R_MAJOR)
    for a in (phi, psi):
        assert np.histogram(a, bins=8, range=(-math.pi, math.pi))[0].min() > 0


def tilted_arc(angle, spans=None):
    """A circle arc of radius 2 about (1, -1, 0.5) in a tilted plane, from its standard
    rational quadratic form (the arc_parameters of cagd.surfaces.revolution), and its frame."""
    from cagd.surfaces.revolution import arc_parameters
    c, s, w, knots = arc_parameters(0.3, angle)
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    e1 = np.cross(axis, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    O = np.array([1.0, -1.0, 0.5])
    arc = BSplineCurve(O + 2.0 * (c[:, None] * e1 + s[:, None] * e2), 2, knots, w)
    return arc, O, axis


@pytest.mark.parametrize("angle", [1.2, 2.5, 2.0 * math.pi])
def test_profile_along_an_arc_is_exact_against_the_ode_frame(angle):
    """A space profile swept along a tilted arc, with constant scale and twist: the exact
    revolution agrees with the true sweep (RMF integrated by scipy) and lies on the surface of
    revolution (every point at the distance from the axis of its profile point)."""
    path, O, axis = tilted_arc(angle)
    x0 = path(0.0)
    prof = BSplineCurve(x0 + np.array([[0.0, 0.0, 0.0], [0.3, 0.2, 0.1], [0.1, 0.6, -0.2], [-0.2, 0.4, 0.5]]), 3,
                        None, [1.0, 0.7, 1.3, 1.0])
    r = sweep(prof, path, scale=1.3, twist=0.4)
    assert r.converged and r.max_error <= 1e-14 and "revolution" in r.message
    rng = np.random.default_rng(11)
    u, t = rng.uniform(0.0, 1.0, 300), np.sort(rng.uniform(0.0, 1.0, 300))
    X = r.surface(u, t)
    Y = true_sweep(prof, path, "rmf", u, t, scale=1.3, twist=0.4)
    assert np.abs(X - Y).max() <= 1e-9                    # the ODE's accuracy
    start = r.surface(u, np.zeros_like(u))                 # the placed profile, turned about the axis
    for Z in (X,):
        rel, rel0 = Z - O, start - O
        np.testing.assert_allclose(rel @ axis, rel0 @ axis, atol=1e-13)
        np.testing.assert_allclose(np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=-1),
                                   np.linalg.norm(rel0 - np.outer(rel0 @ axis, axis), axis=-1), atol=1e-13)


def test_other_rational_circles_give_the_exact_tensor_product():
    """Circles not in the standard form (a knot inserted, degree elevated, a 120 degree arc
    in one span): a plain NURBS tensor product of the profile and the path, still exact."""
    from cagd.surfaces.revolution import RevolvedSurface
    prof = circle(R_MINOR).transformed(XZ, [R_MAJOR, 0.0, 0.0])
    h = math.pi / 3.0
    one_span = BSplineCurve([[R_MAJOR, 0, 0], [R_MAJOR, R_MAJOR * math.tan(h), 0],
                             [R_MAJOR * math.cos(2 * h), R_MAJOR * math.sin(2 * h), 0]], 2, None,
                            [1.0, math.cos(h), 1.0])
    for path in (circle(R_MAJOR).insert_knot(0.1), circle(R_MAJOR).elevate(1), one_span):
        r = sweep(prof, path)
        assert r.converged and r.max_error <= 1e-14 and "revolution" in r.message
        assert not isinstance(r.surface, RevolvedSurface) and r.surface.is_rational
        assert np.abs(torus_residual(random_points(r.surface))).max() <= 1e-12


def test_not_a_revolution():
    """An up vector off the axis turns the frame non-rigidly, an interpolated circle is not a
    rational circle, a varying law breaks the rotation invariance: the station sweep, not exact."""
    prof = circle(R_MINOR).transformed(XZ, [R_MAJOR, 0.0, 0.0])
    th = np.linspace(0.0, 2.0 * math.pi, 33)
    approx = cagd.interpolate(np.c_[R_MAJOR * np.cos(th), R_MAJOR * np.sin(th), np.zeros_like(th)], 3)
    for kwargs in (dict(path=circle(R_MAJOR), frame=[0.0, 0.1, 1.0]), dict(path=approx),
                   dict(path=circle(R_MAJOR), scale=lambda t: 1.0)):
        r = sweep(prof, **kwargs)
        assert r.converged and "revolution" not in r.message and "stations" in r.message, r.message
