"""Surfaces through a grid of points: global tensor-product B-spline interpolation
(Piegl & Tiller, The NURBS Book, 9.2.5, algorithm A9.4).
"""
from __future__ import annotations

from typing import Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError
from ..basis.banded import solve_banded_rows
from ..basis.bspline import basis_functions
from ..fitting.interpolation import FIT_RESIDUAL_TOL, _frame, _schoenberg_whitney, parametrize
from ..fitting.parameters import averaged_parameters, option
from ..knots import vectors as kv
from .bspline import BSplineSurface

SurfaceParameters = Union[str, Tuple[np.ndarray, np.ndarray]]

_RESIDUAL_ROWS = 256    # rows per block of the residual check (bounds its temporaries)


def surface_parameters(points: ArrayLike, parameters: SurfaceParameters = "chord", *,
                       method: Optional[SurfaceParameters] = None) -> Tuple[np.ndarray, np.ndarray]:
    """Parameters (ubar_0..ubar_n, vbar_0..vbar_m) for an (n+1, m+1, dim) grid Q_kl
    (Piegl & Tiller 9.2.5, eq. 9.8-9.10 averaged): for every column l the chord
    parameters of Q_0l..Q_nl as for curves (:func:`cagd.fitting.parametrize`, eq. 9.5;
    with ``"centripetal"`` the square roots of the chords, eq. 9.6), then
    ubar_k = mean over the columns of those; columns of zero total length (a
    collapsed row, e.g. a pole) are left out of the mean. Likewise vbar over the
    rows. ``"uniform"`` gives k/n and l/m (the names: :data:`cagd.fitting.PARAMETERS`);
    a pair of arrays is checked (strictly increasing, one value per row/column) and
    returned. ``method=`` is the deprecated name of ``parameters=`` (one release).

    Raises:
        CagdError: points not an (n+1 >= 2, m+1 >= 2, dim) finite array, an unknown
            name, every column (row) of zero length, averaged parameters not
            strictly increasing, explicit parameters of the wrong length or order.
    """
    parameters = option(parameters, {"method": method}, "surface_parameters", "chord")
    Q = _grid(points)
    if isinstance(parameters, str):
        return (averaged_parameters(Q, parameters, "points", "rows"),
                averaged_parameters(Q.transpose(1, 0, 2), parameters, "points", "columns"))
    if not isinstance(parameters, (tuple, list)) or len(parameters) != 2:
        raise CagdError("parameters: expected a parametrisation name or a pair (params_u, params_v)")
    pu = parametrize(Q[:, 0], parameters[0])           # checks length and strict increase
    pv = parametrize(Q[0], parameters[1])
    return pu, pv


def interpolate_surface(points: ArrayLike, degree_u: int = 3, degree_v: int = 3,
                        parameters: SurfaceParameters = "chord") -> BSplineSurface:
    """The B-spline surface S(u, v) = sum_i sum_j N_i,p(u) N_j,q(v) P_ij through the
    grid of points, S(ubar_k, vbar_l) = Q_kl (Piegl & Tiller 9.2.5, A9.4).

    Parameters by :func:`surface_parameters`; knots by averaging (eq. 9.8) in each
    direction. Then through the rows: R = A_u^-1 Q with all nv * dim columns as
    right-hand sides, and through the columns: P^T = A_v^-1 R^T, where A_u = [N_i,p(ubar_k)]
    is the banded collocation matrix (p + 1 non-zeros per row; block LU of
    :func:`cagd.basis.banded.solve_banded_rows`, as curve interpolation). Solved in
    the points' normalised frame; memory O(nu nv dim) (a few copies of the grid, no
    n x n matrix and no wide-curve evaluation), time O(nu nv dim (p + q)).

    The miss at the grid is bounded by |A_u R - Q| + |A_v P^T - R^T| (the rows of A_u
    are non-negative and sum to 1), both computed by banded products; beyond
    FIT_RESIDUAL_TOL of the points' spread the system is refused as ill-conditioned.

    Raises:
        CagdError: points not an (n+1 >= 2, m+1 >= 2, dim) finite array, degree_u
            outside 1..min(n, MAX_DEGREE), degree_v outside 1..min(m, MAX_DEGREE), bad
            parameters (see :func:`surface_parameters`), a Schoenberg-Whitney failure,
            an ill-conditioned system.
    """
    Q = _grid(points)
    nu, nv, dim = Q.shape
    p = _checks.degree(degree_u, "degree_u", 1, nu - 1)
    q = _checks.degree(degree_v, "degree_v", 1, nv - 1)
    pu, pv = surface_parameters(Q, parameters)
    ku, kvv = kv.averaged(pu, p), kv.averaged(pv, q)
    center, scale = _frame(Q.reshape(-1, dim))
    Qn = ((Q - center) / scale).reshape(nu, nv * dim)
    # through the rows: nu points, each a whole (nv * dim) row
    R, miss_u = _solve_direction(Qn, pu, ku, p, "degree_u")
    del Qn
    # through the columns: nv points, each a whole (nu * dim) column
    Rt = np.ascontiguousarray(R.reshape(nu, nv, dim).transpose(1, 0, 2)).reshape(nv, nu * dim)
    del R
    Pt, miss_v = _solve_direction(Rt, pv, kvv, q, "degree_v")
    del Rt
    miss = miss_u + miss_v
    if not miss <= FIT_RESIDUAL_TOL:
        raise CagdError(f"points: interpolate_surface (degrees ({p}, {q}), {nu} x {nv} points) is "
                        f"ill-conditioned: the solved surface misses its points by up to {miss:.3g} of their "
                        f"spread (more than FIT_RESIDUAL_TOL = {FIT_RESIDUAL_TOL}); use lower degrees")
    P = Pt.reshape(nv, nu, dim).transpose(1, 0, 2) * scale + center
    return BSplineSurface(P, p, q, ku, kvv)


def _solve_direction(Q: np.ndarray, u: np.ndarray, U: np.ndarray, p: int, name: str) -> Tuple[np.ndarray, float]:
    """Control rows X with sum_i N_i,p(u_k) X_i = Q_k for every k (the banded
    collocation system, clamped ends exactly Q_0 and Q_n) and the largest miss
    max |A X - Q| (Q normalised, so relative to the points' spread)."""
    count = Q.shape[0]
    span = kv.find_span(U, p, u, count)
    N = basis_functions(U, p, u, span)                      # (count, p + 1): the band of each row
    start = span - p
    _schoenberg_whitney(N, start, u)
    X = solve_banded_rows(start, N, Q, name)
    if N[0, 0] == 1.0:                                      # clamped ends interpolate exactly
        X[0] = Q[0]
    if N[-1, -1] == 1.0:
        X[-1] = Q[-1]
    with np.errstate(over="ignore", invalid="ignore"):
        miss = 0.0
        for c in range(0, count, _RESIDUAL_ROWS):          # A X - Q by bands, a block of rows at a time
            rows = slice(c, c + _RESIDUAL_ROWS)
            acc = -Q[rows]
            for w in range(p + 1):
                acc += N[rows, w, None] * X[start[rows] + w]
            miss = max(miss, float(np.max(np.abs(acc))))
    if not np.isfinite(miss):
        miss = np.inf
    return X, miss


def _grid(points: ArrayLike) -> np.ndarray:
    Q = _checks.finite_array(points, "points")
    if Q.ndim != 3 or Q.shape[0] < 2 or Q.shape[1] < 2 or Q.shape[2] < 1:
        raise CagdError(f"points: expected a grid of shape (nu >= 2, nv >= 2, dim), got {Q.shape}")
    return Q
