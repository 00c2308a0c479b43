"""cagd.surfaces._crossings (the fast path of gordon's network crossings) against the
general solver cagd.intersect, and the refit's deviation bound against brute force."""
import sys
from pathlib import Path

import numpy as np
import pytest

import cagd
from cagd.surfaces._crossings import network_crossings

sys.path.insert(0, str(Path(__file__).parent))
from test_gordon import CLOSED_TOL, NET_TOL, conic_arcs, interpolated_network, tube, tube_network  # noqa: E402

gordon_module = sys.modules["cagd.surfaces.gordon"]


def unit(curves):
    return [gordon_module.unit_nurbs(c) for c in curves]


def test_crossings_equal_the_general_solver():
    """Every pair of an interpolated 4 x 5 network is settled here, at the parameters
    cagd.intersect finds (subdivision + Newton), to 1e-9."""
    profiles, guides = interpolated_network(4, 5)
    F, G = unit(profiles), unit(guides)
    S, T, miss, proven = network_crossings(F, G, NET_TOL)
    assert proven.all()
    for i, f in enumerate(F):
        for j, g in enumerate(G):
            r = cagd.intersect(f, g, NET_TOL)
            (p,) = r.points
            assert abs(S[i, j] - p.param_a) <= 1e-9 and abs(T[i, j] - p.param_b) <= 1e-9
            assert miss[i, j] <= p.residual + 1e-12


def test_pairs_without_a_clear_angle_are_left_to_the_general_solver():
    """A guide crossing a profile three times (its hodograph turns back) and a closed
    ring against its seam guide (every direction) are not settled here."""
    flat = [cagd.BSplineCurve([[0, y, 0], [100, y, 0]], 1) for y in (0.0, 50.0, 100.0)]
    t = np.linspace(0, 1, 40)
    snake = cagd.interpolate(np.column_stack([30 + 40 * t, 100 * t - 20 * np.sin(4 * np.pi * t), 0 * t]))
    _, _, _, proven = network_crossings(unit(flat), unit([snake]), 1e-6)
    assert not proven[1, 0]
    rings, guides = tube_network()
    t = np.linspace(0.0, 1.0, 61)
    at_start = cagd.interpolate(tube(np.zeros_like(t), t))          # through rings[0]'s start and end
    _, _, _, proven = network_crossings(unit(rings), unit([at_start] + guides), CLOSED_TOL)
    assert not proven[0, 0] and proven[:, 1:].all()


def test_gordon_is_the_same_with_and_without_the_fast_path(monkeypatch):
    profiles, guides = interpolated_network(3, 4)
    fast = cagd.gordon(profiles, guides, NET_TOL)
    def nothing_proven(F, G, tol):
        return tuple(np.full((len(F), len(G)), np.nan) for _ in range(3)) + (np.zeros((len(F), len(G)), bool),)
    monkeypatch.setattr(gordon_module, "network_crossings", nothing_proven)
    slow = cagd.gordon(profiles, guides, NET_TOL)
    assert np.abs(fast.intersections - slow.intersections).max() <= 1e-9
    assert np.abs(fast.surface.control_points - slow.surface.control_points).max() <= 1e-6


def _sampled_deviation(fitted, curves, old, new):
    """max |c~(s) - c(r(s))| over the family on 2 x 10^5 samples (brute force)."""
    s = np.linspace(0.0, 1.0, 200001)
    return max(float(np.linalg.norm(f(s) - c(gordon_module._reparametrisation(new, o)(s)), axis=1).max())
               for f, c, o in zip(fitted, curves, old))


@pytest.mark.parametrize("rational", [False, True])
def test_refit_bound_holds_and_is_tight(rational):
    """The Bernstein bound of |c~(s) - c(r(s))| is at least the deviation on 2 x 10^5
    samples (brute force) and at most twice it."""
    if rational:
        curves, _ = conic_arcs([0.5, 0.9, 1.6])
        old = np.array([[0.0, 0.4, 1.0], [0.0, 0.5, 1.0], [0.0, 0.62, 1.0]])
    else:
        profiles, _ = interpolated_network(3, 3, 12)
        curves = unit(profiles)
        old = np.array([[0.0, 0.45, 1.0], [0.0, 0.5, 1.0], [0.0, 0.57, 1.0]])
    new = old.mean(axis=0)
    fitted, err, ok = gordon_module._refit(list(curves), old, new, 1e-3, "curves")
    true = _sampled_deviation(fitted, curves, old, new)
    assert ok and true <= err <= 2 * true, (true, err)


def test_inverse_of_a_reparametrisation():
    x, y = np.array([0, 0.1, 0.5, 0.9, 1.0]), np.array([0, 0.5, 0.55, 0.6, 1.0])
    q = np.concatenate([np.linspace(0, 1, 1001), [0.5, 0.55]])
    for r in (gordon_module._reparametrisation(x, y), gordon_module._pchip(x, y)):
        assert np.abs(r(gordon_module._inverse(r, q)) - q).max() <= 1e-14


def test_refit_out_of_rounds_still_reports_a_bound(monkeypatch):
    """A refit stopped after one round (its samples still failing) reports the bound of
    that fit, not the sampled value: at least the deviation on 2 x 10^5 samples."""
    monkeypatch.setattr(gordon_module, "REFIT_ROUNDS", 1)
    curves, _ = conic_arcs([0.5, 0.9, 1.6])
    old = np.array([[0.0, 0.4, 1.0], [0.0, 0.5, 1.0], [0.0, 0.62, 1.0]])
    new = old.mean(axis=0)
    fitted, err, ok = gordon_module._refit(list(curves), old, new, 1e-7, "curves")
    true = _sampled_deviation(fitted, curves, old, new)
    assert not ok and true <= err, (true, err)
