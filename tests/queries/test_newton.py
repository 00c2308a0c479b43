"""cagd.queries._newton.refine at a pole: the parameter along a collapsed edge is
arbitrary and moves the foot by rounding only; such a coordinate is settled (issue 16:
projections onto the nose of trj3_s1-al-214.stp space_ship[85] went on for all 30
iterations, steps along the pole leaving the distance unchanged)."""
import numpy as np
import pytest

import cagd
from cagd.queries import _subdivision as sd
from cagd.queries._newton import FixedPoints, refine


def _sphere_with_rounded_poles(R, c):
    """A sphere whose pole rows of control points differ by rounding (as read from a
    file): the partial along a pole is ~1e-15 instead of 0."""
    s = cagd.sphere(R, c).to_nurbs()
    P = np.array(s.control_points)
    rng = np.random.default_rng(1)
    for row in (0, -1):
        P[row] = P[row] * (1 + 4e-16 * rng.standard_normal(P[row].shape))
    return cagd.BSplineSurface(P, s.degree_u, s.degree_v, s.knots_u, s.knots_v, s.weights)


@pytest.fixture
def evaluations(monkeypatch):
    count = [0]
    real = sd.Geometry.derivatives

    def spy(self, *a, **kw):
        count[0] += 1
        return real(self, *a, **kw)

    monkeypatch.setattr(sd.Geometry, "derivatives", spy)
    return count


def test_projections_onto_a_pole_settle(evaluations):
    """Points on the axis beyond both poles, started 1e-3 off them: the distance is the
    closed form |P - c| - R, converged in a few iterations (74 evaluations and the south
    row unconverged before)."""
    R, c = 7.3, np.array([0.1, 0.2, 0.3])
    G = sd.Geometry(_sphere_with_rounded_poles(R, c), "b")
    P = c + np.array([[0.0, 0.0, 9.0], [0.0, 0.0, -9.5]])
    seed = np.array([[G.lo[0] + 1e-3, 0.3], [G.hi[0] - 1e-3, 0.7]])
    _, y, dist, conv = refine(FixedPoints(P), G, np.zeros((2, 0)), seed, True, 30)
    assert conv.all()
    assert dist == pytest.approx([9.0 - R, 9.5 - R], abs=1e-13)
    assert evaluations[0] <= 20
