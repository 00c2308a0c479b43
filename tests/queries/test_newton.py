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


@pytest.mark.parametrize("angle", [1e-2, 1e-5, 1e-6])
def test_the_corrector_stops_at_rounding_near_a_tangency(angle, monkeypatch):
    """A bumpy bicubic and its copy turned by ``angle`` about a line on it meet in a
    curve at that angle; the marching's corrector (a plane constraint row) from a
    predictor 1e-3 along the tangent converges to |F| ~ 1e-16 in 3-4 evaluations. At
    angle 1e-5 its steps stall at the rounding of J's condition number (~1e-11 of the
    width, above STEP_RTOL) and it ran all 12 iterations."""
    from cagd.queries._surface_system import System, cofactors
    from cagd.queries._newton import newton
    rng = np.random.default_rng(7)
    net = np.stack(np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4), indexing="ij"), -1)
    net = np.concatenate([net, 0.1 * rng.standard_normal((4, 4, 1))], -1)
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    p0 = net[1, 2]
    turned = cagd.BezierSurface((net - p0) @ turn.T + p0)
    S = System(sd.Geometry(cagd.BezierSurface(net), "a"), sd.Geometry(turned, "b"))
    x0 = np.array([[0.3 + 0.1 * k, 0.66, 0.3 + 0.1 * k, 0.66] for k in range(5)])
    x, ok = newton(S, x0, None, None, 1e-12, iters=30)
    assert ok.all()
    F, J, P, na, nb, _ = S.eval(x)
    assert np.linalg.norm(np.cross(na, nb), axis=1) == pytest.approx(angle, rel=1e-2)
    t = cofactors(J)
    t /= np.linalg.norm(t, axis=1)[:, None]
    xp = x + 1e-3 * t + 1e-6 * rng.standard_normal(x.shape)
    calls = [0]
    real = S.eval

    def spy(z):
        calls[0] += 1
        return real(z)

    monkeypatch.setattr(S, "eval", spy)
    y, ok, ev = newton(S, xp, t, np.einsum("nk,nk->n", t, xp), 1e-12, full=True)
    assert ok.all() and np.linalg.norm(ev[0], axis=1).max() <= 1e-14
    assert np.einsum("nk,nk->n", t, y - xp) == pytest.approx(0.0, abs=1e-15)
    assert calls[0] <= 5
