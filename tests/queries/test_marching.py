"""The marching of surface intersection branches (cagd.queries._marching, issue 16):
lanes in lock step chained through the starts they meet give the branch the one-by-one
march gives; the nearest-segment distance against brute force."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from benchmarks.surface_intersection import model_patches
from cagd.queries import _subdivision as sd
from cagd.queries._marching import Marcher, segments_distance
from cagd.queries._newton import newton
from cagd.queries._surface_system import System

TOL = 1e-7


def _brute(Q, P):
    """Distance to every segment (points projected and clamped), the nearest's length."""
    a, ab = P[:-1], np.diff(P, axis=0)
    L2 = (ab * ab).sum(1)
    tau = np.clip(np.einsum("skd,kd->sk", Q[:, None] - a[None], ab) / L2, 0.0, 1.0)
    d = np.linalg.norm(Q[:, None] - (a[None] + tau[..., None] * ab[None]), axis=2)
    k = d.argmin(1)
    return d[np.arange(len(Q)), k], np.sqrt(L2[k])


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 31), st.floats(-14, 0), st.floats(-3, 4))
def test_segments_distance_matches_brute_force(seed, log_off, log_scale):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.random(150))
    P = 10.0 ** log_scale * (np.stack([np.cos(5 * t), np.sin(5 * t), t], 1) + 3.0)
    Q = np.concatenate([P[rng.integers(0, len(P), 60)] + 10.0 ** (log_off + log_scale) * rng.normal(size=(60, 3)),
                        10.0 ** log_scale * (rng.random((20, 3)) * 4.0 + 1.0)])
    d0, L0 = _brute(Q, P)
    d1, L1 = segments_distance(Q, P, chunk=17)
    assert np.allclose(d1, d0, rtol=1e-9, atol=1e-12 * 10.0 ** log_scale)
    assert np.all(np.isclose(L1, L0) | np.isclose(d1, d0, rtol=0, atol=1e-12 * 10.0 ** log_scale))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 31), st.floats(-14, 0), st.floats(-3, 4), st.floats(-6, 0.5), st.integers(2, 200))
def test_segments_distance_within_matches_brute_force(seed, log_off, log_scale, log_within, n):
    """Up to ``within`` the distance and nearest length are the brute force's; beyond it
    inf (runs of SEGMENT_GROUP segments boxed: polylines shorter and longer than a run)."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.random(n))
    P = 10.0 ** log_scale * (np.stack([np.cos(5 * t), np.sin(5 * t), t], 1) + 3.0)
    Q = np.concatenate([P[rng.integers(0, len(P), 60)] + 10.0 ** (log_off + log_scale) * rng.normal(size=(60, 3)),
                        10.0 ** log_scale * (rng.random((20, 3)) * 4.0 + 1.0)])
    within = 10.0 ** (log_within + log_scale)
    d0, L0 = _brute(Q, P)
    d1, L1 = segments_distance(Q, P, within=within)
    near = d0 <= within * (1 - 1e-9)
    assert np.allclose(d1[near], d0[near], rtol=1e-12, atol=1e-13 * 10.0 ** log_scale)
    assert np.all(np.isclose(L1[near], L0[near]) | np.isclose(d1[near], d0[near], rtol=0,
                                                            atol=1e-12 * 10.0 ** log_scale))
    far = d0 > within * (1 + 1e-9)
    assert np.all(np.isinf(d1[far]))


@pytest.fixture(scope="module")
def system():
    a, b = model_patches(8)
    return System(sd.Geometry(a, "a"), sd.Geometry(b, "b"))


def _roots(S, M, k):
    """k roots along the branch of the pair: a grid of starts solved by Newton."""
    g = np.linspace(0.05, 0.95, 7)
    U, V = np.meshgrid(g, g, indexing="ij")
    x0 = np.stack([U.ravel(), V.ravel(), np.full(U.size, 0.5), U.ravel()], 1)
    x, ok = newton(S, x0, None, None, M.ftol, iters=30)
    x = x[ok]
    P = S.eval(x)[2]
    keep = [0]                                      # well apart in 3-D
    for i in range(1, len(x)):
        if np.linalg.norm(P[keep] - P[i], axis=1).min() > 0.05 * S.size:
            keep.append(i)
    return x[keep[:k]]


def test_lanes_chained_through_starts_give_the_one_by_one_branch(system):
    S = system
    M = Marcher(S, TOL)
    x = _roots(S, M, 6)
    assert len(x) >= 3
    chains, used, queue = M.march_seeds(x)
    assert len(chains) == 1 and used.all() and not queue
    xs, ends = chains[0]
    assert ends == ("boundary", "boundary")
    F = S.eval(xs)[0]
    assert np.linalg.norm(F, axis=1).max() <= M.ftol
    (fw, end_f, _), back = M.march_both(x[0])
    ref = np.array(back[0][::-1] + fw[1:])
    P, R = S.eval(xs)[2], S.eval(ref)[2]
    # the same curve, end to end: every point of one polyline near the other, within the
    # chord error of the longer steps (sagitta h^2 kappa / 8, h <= size / 8, kappa ~ 1 here)
    sag = 0.02 * S.size
    assert segments_distance(P, R)[0].max() <= sag
    assert segments_distance(R, P)[0].max() <= sag
    assert abs(np.linalg.norm(np.diff(P, axis=0), axis=1).sum()
               - np.linalg.norm(np.diff(R, axis=0), axis=1).sum()) <= 1e-3 * S.size
    assert np.linalg.norm(P[0] - R[0]) <= 1e-9 * S.size or np.linalg.norm(P[0] - R[-1]) <= 1e-9 * S.size
    # parameters continuous along the chain (no jump between lanes)
    steps = np.linalg.norm(np.diff(P, axis=0), axis=1)
    assert steps.max() <= M.hmax * 1.01 and steps.min() > 0.0
