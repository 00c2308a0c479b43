"""The named tolerances shared by the queries (issue 16, layout: no bare ``1e-*``
literals in :mod:`cagd.queries`), and :func:`unit`. Relative tolerances (``*_RTOL``)
multiply the scale named beside them: the model size, a domain's width, a value
computed two ways. Tolerances that belong to one step are named in its module."""
from __future__ import annotations

import numpy as np

TINY = 1e-300               # floor of divisors, norms and eigenvalue scales (keeps 0/0 out; below every scale)
ULP_RTOL = 1e-15            # a few units in the last place of a double, relative
SLACK_RTOL = 1e-12          # slack of a value computed two ways (squared distances, radii, box edges), relative
SIZE_ROUNDING = 1e-13       # lengths below this share of the model size are rounding
BOUND_SHRINK_RTOL = 1e-13   # certified lower bounds are lowered by this share, for their own rounding
LEVENBERG_RTOL = 1e-12      # the tiny Levenberg shift of small Newton systems, relative to their diagonal
AT_END_RTOL = 1e-9          # a parameter within this share of the domain's width of an end is at it
END_MARGIN_RTOL = 1e-6      # overlap ends: margins and snapping to a domain end, share of the width
SAME_PARAM_RTOL = 1e-7      # curve parameters closer than this share of the width are one point
COLLAPSED_SPEED_RTOL = 1e-8      # a partial moving the point under this share of the size (or of the other
#                             partials) does not move it: a collapsed edge, a pole
DEFAULT_TOL = 1e-9          # intersect: the default distance tolerance (model units)
DEFAULT_ANGLE_TOL = 1e-6    # intersect: contacts within this angle (radians) are tangential
MIN_TOL_RTOL = 1e-13        # intersect: a tol below this share of the objects' size is refused
RESIDUAL_SHARE = 1e-3       # Newton correctors of the intersection system solve |F| to this share of tol ...
RESIDUAL_FLOOR = 1e-14      # ... but not below this share of the model size (rounding)


def residual_tol(tol: float, size: float) -> float:
    """The residual |F| the intersection correctors solve to: RESIDUAL_SHARE tol, at
    least RESIDUAL_FLOOR size."""
    return max(RESIDUAL_SHARE * tol, RESIDUAL_FLOOR * size)


def squared_norms(v: np.ndarray) -> np.ndarray:
    """|v|^2 along the last axis, summed component by component in order: what
    ``(v ** 2).sum(-1)`` gives for a few components, bit for bit, without numpy's slow
    reduction over a short last axis (issue 16, set-up: 6x faster on (m, 16, 3) nets)."""
    acc = v[..., 0] ** 2
    for a in range(1, v.shape[-1]):
        acc = acc + v[..., a] ** 2
    return acc


def lead_sum(a: np.ndarray) -> np.ndarray:
    """The sum over the first axis, row by row in order (the twin of :func:`squared_norms`
    for component-first arrays: a handful of long contiguous rows; numpy's reduction over
    a leading axis was 2.5x slower on 65,536 boxes of the closest-point bounds)."""
    out = a[0]
    for row in a[1:]:
        out = out + row
    return out


def eigenvalue_2x2(a: np.ndarray, b: np.ndarray, c: np.ndarray, sign: float) -> np.ndarray:
    """The larger (sign 1) or smaller (sign -1) eigenvalue of the symmetric [[a, b], [b, c]]:
    (a + c)/2 +- sqrt(((a - c)/2)^2 + b^2)."""
    return 0.5 * (a + c) + sign * np.sqrt(0.25 * (a - c) ** 2 + b * b)


def column_extremes(P: np.ndarray) -> "tuple[np.ndarray, np.ndarray]":
    """(min, max) per coordinate of points P (..., dim), through the transposed copy:
    numpy reduces (n, 3) arrays along axis 0 ten times slower (issue 16, set-up)."""
    Pt = np.ascontiguousarray(P.reshape(-1, P.shape[-1]).T)
    return Pt.min(axis=1), Pt.max(axis=1)


def row_max(v: np.ndarray) -> np.ndarray:
    """The largest entry of each row of v (n, ...), over all its other axes, through the
    transposed copy: numpy reduces (n, 12) arrays along axis 1 four to fifteen times
    slower (issue 16, set-up: the cells' hodograph and hull bounds)."""
    return np.ascontiguousarray(v.reshape(len(v), -1).T).max(axis=0)


def row_min(v: np.ndarray) -> np.ndarray:
    """The smallest entry of each row of v (n, ...) (see :func:`row_max`)."""
    return np.ascontiguousarray(v.reshape(len(v), -1).T).min(axis=0)


def unit(v: np.ndarray) -> np.ndarray:
    """v / |v| along the last axis (0 where v = 0)."""
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), TINY)


def smallest_per_group(group: np.ndarray, key: np.ndarray) -> np.ndarray:
    """The index of the row of smallest ``key`` in each group of equal ``group`` (the
    groups in increasing order; the first such row on a tie)."""
    order = np.lexsort((key, group))
    if not len(order):
        return order
    g = group[order]
    return order[np.r_[True, g[1:] != g[:-1]]]
