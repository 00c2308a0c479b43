"""Distance bounds from a centre or an axis fitted to a continuum of minima (private;
used by :func:`cagd.queries.distance.min_distance`).

The distance to a flat, phi(x) = |Pi (x - c)| with Pi = I (a point c) or Pi = I - a a^T
(an axis through c along the unit a), is 1-Lipschitz, so two pieces P (of a) and Q
(of b) are at least max(min_Q phi - max_P phi, min_P phi - max_Q phi) apart, whatever
c and a are. The range of phi over a rational Bezier piece
x = sum B_i w_i P_i / sum B_i w_i: phi^2 = N / W with N = |sum B_i w_i Pi (P_i - c)|^2
and W = (sum B_i w_i)^2, polynomials of twice the degree whose Bernstein coefficients
N_k, W_k > 0 follow from the product rule (:func:`cagd.basis.product_matrix`). N / W is
a convex combination of the N_k / W_k (weights W_k B_k / W), so
min_k N_k / W_k <= phi^2 <= max_k N_k / W_k: exact, up to rounding, on a sphere about c
or a cylinder about the axis (N = r^2 W there) and at a piece's edge where phi is
extremal (a torus's equator at the knot of its circle).

Continua of minima in exact NURBS geometry come from symmetry: concentric spheres and
arcs, coaxial cylinders, tori and circles. There the common normals of the minima all
pass through one point (the centre) or all cross one line at right angles (the axis);
:func:`fit_flats` finds them from the normal lines of a few minima, and the bounds above
then hold every pair along the continuum at the minimum distance itself. Parallel
continua (planes) need no fit: a slab along the common normal is exact there.
"""
from __future__ import annotations

from functools import lru_cache
from typing import List, NamedTuple, Tuple

import numpy as np

from ..basis.bernstein import product_matrix
from ._subdivision import project

FIT_RTOL = 1e-10          # a centre / an axis fits when every normal line passes within FIT_RTOL * size
PARALLEL_TOL = 1e-10      # normals closer than this (unit vectors) are parallel: no centre, no axis
ROUNDING_SLACK = 8.0 * np.finfo(float).eps   # per product term, times |Y_i| (|Y_i| + |P_i| + |c|),
#                                             Y_i = Pi (P_i - c): rounding of the phi^2 bounds


class Flat(NamedTuple):
    """A point (``projector`` = I) or an axis (I - a a^T) through ``origin``."""
    origin: np.ndarray
    projector: np.ndarray


@lru_cache(maxsize=None)
def _square_weights(shape: Tuple[int, ...]) -> np.ndarray:
    """(K*K, K2) matrix taking the products (x_i y_j) of two Bezier nets of ``shape``
    (control points per direction, K in all) to the Bernstein coefficients of the
    product polynomial (K2 of them), tensor products for surfaces."""
    T = product_matrix(shape[0] - 1, shape[0] - 1)
    if len(shape) == 2:
        V = product_matrix(shape[1] - 1, shape[1] - 1)
        T = np.einsum("ijk,lqr->iljqkr", T, V)
    K = int(np.prod(shape))
    return T.reshape(K * K, -1)


def flat_range(ctrl: np.ndarray, flat: Flat) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Certified (lower, upper) bounds (M,) of the distance from ``flat`` over each
    homogeneous Bezier piece (M, n+1[, m+1], D+1), and the variation (M, k) of the
    coefficients N_k / W_k along each parameter (the largest range along one row of
    the coefficient grid): where it is zero along v (a parallel of a surface of
    revolution about the axis), halving across u alone tightens the bounds."""
    M = ctrl.shape[0]
    w = ctrl[..., -1].reshape(M, -1)
    Y = ((project(ctrl) - flat.origin) @ flat.projector).reshape(M, w.shape[1], -1)
    Yw = Y * w[..., None]
    T = _square_weights(ctrl.shape[1:-1])
    N = np.matmul(Yw, Yw.transpose(0, 2, 1)).reshape(M, -1) @ T
    W = (w[:, :, None] * w[:, None, :]).reshape(M, -1) @ T
    ratio = N / W
    size = np.linalg.norm(Y, axis=2)
    reach = np.linalg.norm(flat.origin) + np.linalg.norm(project(ctrl), axis=-1).reshape(M, -1)
    slack = ROUNDING_SLACK * w.shape[1] * (size * (size + reach)).max(axis=1)
    grid = ratio.reshape((M,) + tuple(2 * (n - 1) + 1 for n in ctrl.shape[1:-1]))
    variation = np.stack([np.ptp(grid, axis=ax).reshape(M, -1).max(axis=1) for ax in range(1, grid.ndim)], 1)
    return (np.sqrt(np.maximum(ratio.min(axis=1) - slack, 0.0)),
            np.sqrt(ratio.max(axis=1) + slack), variation)


class FlatGap(NamedTuple):
    """Per pair: the lower bound ``gap`` from one flat, the widths of the two pieces'
    ranges of phi and their coefficient variations (see :func:`flat_range`)."""
    gap: np.ndarray
    width_a: np.ndarray
    width_b: np.ndarray
    variation_a: np.ndarray
    variation_b: np.ndarray


def flat_gap(ctrl_a: np.ndarray, ctrl_b: np.ndarray, flat: Flat) -> FlatGap:
    """Lower bound (M,) of the distance between the pieces of each pair from the
    1-Lipschitz distance to ``flat``: max(min_b - max_a, min_a - max_b, 0)."""
    lo_a, hi_a, var_a = flat_range(ctrl_a, flat)
    lo_b, hi_b, var_b = flat_range(ctrl_b, flat)
    return FlatGap(np.maximum(0.0, np.maximum(lo_b - hi_a, lo_a - hi_b)), hi_a - lo_a, hi_b - lo_b, var_a, var_b)


def _common_point(p: np.ndarray, n: np.ndarray, size: float):
    """The point nearest (least squares) to the lines p_i + s n_i (unit n_i), or None
    when the lines are (nearly) parallel or miss it by more than FIT_RTOL * size."""
    D = p.shape[1]
    E = np.eye(D) - n[:, :, None] * n[:, None, :]          # projectors across each line
    A, rhs = E.sum(axis=0), np.einsum("mij,mj->i", E, p)
    lam = np.linalg.eigvalsh(A)
    if lam[0] <= PARALLEL_TOL * lam[-1]:
        return None
    c = np.linalg.solve(A, rhs)
    miss = np.linalg.norm(np.einsum("mij,mj->mi", E, c - p), axis=1).max()
    return c if miss <= FIT_RTOL * size else None


def fit_flats(p: np.ndarray, n: np.ndarray, size: float) -> List[Flat]:
    """Centres and axes that every normal line p_i + s n_i (points (m, D) on a, unit
    normals (m, D)) passes through: the 3-D (2-D) least-squares point of the lines if
    all pass within FIT_RTOL * size of it; in 3-D also, when all normals are
    perpendicular to one direction a, the axis along a through the common point of the
    lines projected across a (cylinders, tori, circles about one axis). Empty when the
    normals are parallel (a slab along them is exact) or fit nothing."""
    if len(p) < 2 or np.abs(n - n[0]).max() <= PARALLEL_TOL:
        return []
    out = []
    c = _common_point(p, n, size)
    if c is not None:
        out.append(Flat(c, np.eye(p.shape[1])))
    if p.shape[1] == 3:
        lam, V = np.linalg.eigh(n.T @ n)
        a = V[:, 0]
        if np.abs(n @ a).max() <= PARALLEL_TOL:
            across = np.eye(3) - np.outer(a, a)
            basis = V[:, 1:]                               # the plane across a
            c2 = _common_point(p @ basis, (n @ basis) / np.linalg.norm(n @ basis, axis=1, keepdims=True), size)
            if c2 is not None:
                out.append(Flat(basis @ c2, across))
    return out
