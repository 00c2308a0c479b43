"""closest_point when the branch-and-bound budget runs out (cagd.queries.closest,
"Bounded work"): a point whose boxes are still open when the budget is spent must not
keep its local foot. The case: the fit tests/fitting's
test_measured_max_is_certified_property made at seed 1 (m 8, n 15, tol 0.002, degree 2)
before issue 17's knot fixes, frozen in data/folded_fit.npz: its control net swings out
to 2.7e7 between the grid lines (a folded surface, every hull sphere huge); its grid
points queried together used to get local feet up to 0.68 away with the global foot
within 1e-9 (converged, lower bound 0)."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from cagd import BSplineSurface, closest_point
from cagd.queries.closest import CLOSEST_TOL
from query_families import assert_converged_means_certified


@pytest.fixture(scope="module")
def folded():
    """The folded fit, frozen (data/folded_fit.npz: fit_surface's result on that grid
    before issue 17's knot fixes; the fit is sane now, the surface stays a test case):
    degree 2 x 2, 8 x 15 control points swinging out to 2.7e7; the 120 grid points and
    their fitting parameters."""
    z = np.load(Path(__file__).parent / "data" / "folded_fit.npz")
    S = BSplineSurface(z["control_points"], 2, 2, z["knots_u"], z["knots_v"])
    fit = SimpleNamespace(surface=S, params=z["params"])
    P = np.asarray(S.control_points).reshape(-1, 3)
    # Newton's default stop, a distance: CLOSEST_TOL times the control net's extent
    slack = CLOSEST_TOL * float(np.ptp(P, axis=0).max())
    return fit, z["points"].reshape(-1, 3), slack


def test_points_queried_together_get_their_global_foot(folded):
    """Oracle (evaluation only): S at the fit's own parameters of each grid point is a
    point of S, so its distance bounds the closest distance from above; the 120 points
    queried at once (the budget is spent) must not be farther, and lower_bounds hold."""
    fit, Q, slack = folded
    S = fit.surface
    uv = fit.params.reshape(-1, 2)
    upper = np.linalg.norm(S(uv[:, 0], uv[:, 1]) - Q, axis=1)
    r = closest_point(S, Q)
    assert np.all(r.distances <= upper + slack), np.flatnonzero(r.distances > upper + slack)
    assert np.all(r.lower_bounds <= r.distances)
    # the same points queried one at a time (the budget not spent) agree
    for i in np.argsort(r.distances - upper)[-3:]:
        alone = closest_point(S, Q[i])
        assert abs(alone.distances[0] - r.distances[i]) <= slack


@pytest.mark.parametrize("copies", [12, 100])
def test_copies_of_a_point_get_its_global_foot(folded, copies):
    """Copies of one grid point (every copy shares the budget) get the foot of the point
    queried alone, to Newton's tolerance; the point lies on the surface (upper bound from
    the fit's parameters)."""
    fit, Q, slack = folded
    S = fit.surface
    i = 35
    u, v = fit.params.reshape(-1, 2)[i]
    upper = float(np.linalg.norm(S(u, v) - Q[i]))
    alone = closest_point(S, Q[i]).distances[0]
    r = closest_point(S, np.repeat(Q[i:i + 1], copies, axis=0))
    assert alone <= upper + slack
    assert np.all(np.abs(r.distances - alone) <= slack)
    assert np.all(r.lower_bounds <= r.distances)


def test_open_certificates_are_reported_not_converged(folded):
    """Where the work bound stops the search before the lower bound meets the distance,
    the point is reported not converged and the message says why: a converged point's
    lower bound meets its distance (the old code reported all 120 converged, 32 with
    lower bounds far below). The same points queried one at a time (the budget not
    shared) obey the same rule and get the same distances (most stay open: the fold
    makes every box's bound vacuous near them)."""
    fit, Q, slack = folded
    S = fit.surface
    r = closest_point(S, Q)
    assert_converged_means_certified(r, S)
    assert not r.converged and "work bound" in r.message
    for i in np.flatnonzero(~r.point_converged)[:8]:
        alone = closest_point(S, Q[i])
        assert_converged_means_certified(alone, S)
        assert abs(alone.distances[0] - r.distances[i]) <= slack
        assert alone.converged == (alone.message == "")
