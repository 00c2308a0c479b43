"""The curve–surface subdivision of cagd.queries._point_solver on a curve running close
to a surface and nearly parallel to it (issue 16: a fillet's edge 1e-5 off its nearly
tangent neighbour, occ22470.igs SOLID[2] x [3], kept the boxes of its pairs overlapping
down to pieces 1e-5 long and ran into max_pairs)."""
import numpy as np
import pytest

import cagd
from cagd.queries import _subdivision as sd, intersect

# a quarter-turned frame: the pieces' axis-aligned boxes are not tight
ROT = np.linalg.qr(np.array([[0.8, 0.3, 0.5], [-0.4, 0.9, 0.2], [0.1, -0.2, 0.97]]))[0]


def _surface():
    """z = 0.1 x^2 on [0, 1]^2 (quadratic in x, linear in y), turned by ROT."""
    net = np.array([[[x, y, z] for y in (0.0, 1.0)] for x, z in ((0.0, 0.0), (0.5, 0.0), (1.0, 0.1))])
    return cagd.BezierSurface(net @ ROT.T)


def _line(z0, z1):
    """The line x = 0.5 from y = -0.2 (height z0) to y = 1.2 (height z1), turned by ROT;
    the surface is at height 0.025 under it."""
    return cagd.BezierCurve(np.array([[0.5, -0.2, z0], [0.5, 1.2, z1]]) @ ROT.T)


@pytest.fixture
def pairs_split(monkeypatch):
    """The number of pairs made by every split_pairs call from now on."""
    made = []
    real = sd.split_pairs

    def spy(*a, **kw):
        out = real(*a, **kw)
        made.append(len(out[2]))
        return out

    monkeypatch.setattr(sd, "split_pairs", spy)
    return made


@pytest.mark.parametrize("gap", [1e-5, 1e-7])
def test_a_line_along_a_surface_is_parted_by_the_slab(gap, pairs_split):
    """A line parallel to the rulings, gap above the surface (closed form: no common
    point for gap > tol): converged with no point, after a few hundred pairs; the boxes
    alone kept 3,363 pairs open at max_pairs."""
    res = intersect(_line(0.025 + gap, 0.025 + gap), _surface(), tol=1e-9)
    assert res.converged and res.points == () and res.overlaps == ()
    assert sum(pairs_split) <= 2000


def test_a_line_crossing_a_surface_at_a_shallow_angle_keeps_its_point():
    """The line rises from 1e-3 under to 1e-3 over the surface: the slab parts no pair
    holding the crossing, found at its middle (y = 0.5, closed form), converged."""
    res = intersect(_line(0.025 - 1e-3, 0.025 + 1e-3), _surface(), tol=1e-9)
    assert res.converged and len(res.points) == 1
    expected = np.array([0.5, 0.5, 0.025]) @ ROT.T
    assert np.linalg.norm(res.points[0].point - expected) <= 1e-9
