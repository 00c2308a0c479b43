"""The ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 as bicubic rational Bezier patches:
the worked example of seed 003, 2.4 ("双三次有理Bézier曲面表示椭球面").

The seed starts from x = a cos(phi) cos(theta), y = b cos(phi) sin(theta),
z = c sin(phi), substitutes u = tan(phi/2), v = tan(theta/2), writes the
homogeneous form X = a(1-u^2)(1-v^2), Y = 2b(1-u^2)v, Z = 2c(1+v^2)u,
W = (1+u^2)(1+v^2) (biquadratic), takes its bicubic polar form and reads the 4 x 4
control points off it as f(0..0 1..1; 0..0 1..1). Its table is correct, read as
follows (checked against the polar form in the tests):

* the columns listed as (p_ij, w_ij) are the homogeneous points (w_ij p_ij, w_ij),
  not the Cartesian p_ij: e.g. (0, 0, 2c, 2) is the pole (0, 0, c) with weight 2;
* the table is the transpose of the polar-form formula: block i (p_i0..p_i3) holds
  f(0^(3-j) 1^j; 0^(3-i) 1^i), i.e. i counts the seed's v = tan(theta/2).

Used as printed, with the seed's surface formula sum_ij B_i(u) B_j(v) w_ij p_ij
(block index i paired with u), the patch is therefore S(u, v) with
u = tan(theta/2), v = tan(phi/2): the octant x, y, z >= 0, from the equator
(v = 0) to the pole (v = 1), from the xz-plane (u = 0) to the yz-plane (u = 1).
The edge v = 1 collapses to the pole (0, 0, c): S_u = 0 there, so the normal
S_u x S_v is undefined on that edge (its limit is (0, 0, 1)); the implicit
equation holds everywhere, the edge included.
"""
from __future__ import annotations

import itertools
from typing import List, Tuple

import numpy as np

from .. import _checks
from ..errors import CagdError
from .bezier import BezierSurface

_T = 1.0 / 3.0
# The seed's table, block i = row of the net, entry j = column: coefficients of a, b,
# c and the weights in the homogeneous coordinates (w x, w y, w z, w).
_SEED_TABLES: Tuple[List[List[float]], ...] = (
    [[1, 1, 2 * _T, 0], [1, 1, 2 * _T, 0], [2 * _T, 2 * _T, 4 / 9, 0], [0, 0, 0, 0]],
    [[0, 0, 0, 0], [2 * _T, 2 * _T, 4 / 9, 0], [4 * _T, 4 * _T, 8 / 9, 0], [2, 2, 4 * _T, 0]],
    [[0, 2 * _T, 4 * _T, 2], [0, 2 * _T, 4 * _T, 2], [0, 8 / 9, 16 / 9, 8 * _T], [0, 4 * _T, 8 * _T, 4]],
    [[1, 1, 4 * _T, 2], [1, 1, 4 * _T, 2], [4 * _T, 4 * _T, 16 / 9, 8 * _T], [2, 2, 8 * _T, 4]])
SEED_X, SEED_Y, SEED_Z, SEED_W = (_checks.frozen(table, np.float64) for table in _SEED_TABLES)


def _semi_axes(a: float, b: float, c: float) -> np.ndarray:
    out = []
    for value, name in ((a, "a"), (b, "b"), (c, "c")):
        x = _checks.scalar(value, name)
        if not x > 0.0:
            raise CagdError(f"{name}: semi-axis must be positive, got {x}")
        out.append(x)
    return np.array(out)


def ellipsoid_octant(a: float, b: float, c: float) -> BezierSurface:
    """The bicubic rational Bezier patch of seed 003, 2.4 on the octant x, y, z >= 0:
    control points p_ij = (a X_ij, b Y_ij, c Z_ij) / W_ij and weights W_ij from the
    seed's table (SEED_X, SEED_Y, SEED_Z, SEED_W, read as homogeneous coordinates).
    S(u, v) = (a cos(phi) cos(theta), b cos(phi) sin(theta), c sin(phi)) with
    theta = 2 atan(u), phi = 2 atan(v) (see the module docstring for the reading of
    the table). Exact: x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 for all (u, v) in [0, 1]^2.

    Raises:
        CagdError: a semi-axis not positive or not finite.
    """
    s = _semi_axes(a, b, c)
    hom = np.stack([s[0] * SEED_X, s[1] * SEED_Y, s[2] * SEED_Z], axis=-1)
    return BezierSurface(hom / SEED_W[..., None], SEED_W)


def ellipsoid(a: float, b: float, c: float) -> List[BezierSurface]:
    """The whole ellipsoid as eight octant patches: the patch of
    :func:`ellipsoid_octant` reflected by diag(sx, sy, sz) for every sign triple,
    in the order k = 4 [sz < 0] + 2 [sy < 0] + [sx < 0] (k = 0 is the seed's octant).
    Where an odd number of signs is negative the u direction is reversed, so that
    S_u x S_v points outwards on every patch. Neighbouring patches share their edge
    control points (with weights) exactly, hence the same edge curve: C0.

    Raises:
        CagdError: a semi-axis not positive or not finite.
    """
    base = ellipsoid_octant(a, b, c)
    P, W = base.control_points, base.weights
    assert W is not None       # the octant is a rational patch
    patches = []
    for sz, sy, sx in itertools.product((1.0, -1.0), repeat=3):
        Q = P * np.array([sx, sy, sz])
        w = W
        if sx * sy * sz < 0:
            Q, w = Q[::-1], w[::-1]
        patches.append(BezierSurface(Q, w))
    return patches
