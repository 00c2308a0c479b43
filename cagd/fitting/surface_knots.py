"""Knot recovery for the grid path of :func:`cagd.fit_surface` (issue 17): a grid sampled
from a B-spline surface comes back as that surface, per direction through the curve stage
(:mod:`cagd.fitting.free_knots`).

The rows of a grid sampled from S(u, v) at (u_i, v_j) are, stacked, the points of one
curve R(u) = (S(u, v_1), ..., S(u, v_n)) in R^(n d), a B-spline on the surface's u-knots
with the rows' shared parameters u_i (the same for the columns and v). So the u-knots and
the u_i are those of :func:`cagd.fit_curve` on the stacked rows (their distance in R^(n d)
bounds every point's: sqrt(sum_j |.|^2) >= max_j |.|), after an orthogonal projection onto
the rows' principal subspace (exact: the rows of a surface with n_u control rows lie in
an affine subspace of dimension < n_u; a grid whose rows need more than MAX_RANK dimensions
is not tried). The control points are then the separable least squares on both knot
vectors at (u_i, v_j) (Piegl & Tiller, The NURBS Book, 9.4.3 for the separable grid fit).
The stacking is this project's own.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from ..basis.bspline import basis_matrix
from ..surfaces.bspline import BSplineSurface

#: the stacked rows are projected onto at most this many principal directions
MAX_RANK = 40
#: singular values below this fraction of the largest are rounding (dropped)
RANK_RTOL = 1e-13


def _stacked_fit(rows: np.ndarray, tol: float, degree: int) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(knots, parameters) of fit_curve on the rows (m, k) projected onto their principal
    subspace, or None (too many dimensions, or tol not met)."""
    from .fit import fit_curve
    centred = rows - rows.mean(axis=0)
    _, s, Vt = np.linalg.svd(centred, full_matrices=False)
    if not s.size or s[0] == 0.0:
        return None
    rank = int(np.count_nonzero(s > RANK_RTOL * s[0]))
    if rank > MAX_RANK:
        return None
    fit = fit_curve(centred @ Vt[:rank].T, tol, degree)
    if not fit.converged:
        return None
    return np.asarray(fit.curve.knots), np.asarray(fit.params)


def recovered_surface(Q: np.ndarray, tol: float, degrees: Tuple[int, int], poles: int
                      ) -> Optional[Tuple[BSplineSurface, np.ndarray, np.ndarray]]:
    """A surface with fewer than ``poles`` control points whose every grid point (m, n, d)
    is within tol at its parameters (u_i, v_j) (an upper bound of the certified distance),
    with knots and parameters recovered per direction (module docstring); the corner
    points held bit for bit. Returns (surface, u, v) or None."""
    m, n, d = Q.shape
    pu, pv = degrees
    along_u = _stacked_fit(Q.reshape(m, n * d), tol, pu)
    along_v = _stacked_fit(Q.transpose(1, 0, 2).reshape(n, m * d), tol, pv)
    if along_u is None or along_v is None:
        return None
    (U, u), (V, v) = along_u, along_v
    nu, nv = len(U) - pu - 1, len(V) - pv - 1
    if nu * nv >= poles:
        return None
    Bu, Bv = basis_matrix(U, pu, u, nu), basis_matrix(V, pv, v, nv)
    X = np.linalg.lstsq(Bu, Q.reshape(m, n * d), rcond=None)[0].reshape(nu, n, d)
    P = np.linalg.lstsq(Bv, X.transpose(1, 0, 2).reshape(n, nu * d), rcond=None)[0]
    P = P.reshape(nv, nu, d).transpose(1, 0, 2)
    P[0, 0], P[0, -1], P[-1, 0], P[-1, -1] = Q[0, 0], Q[0, -1], Q[-1, 0], Q[-1, -1]
    S = BSplineSurface(P, pu, pv, U, V)
    if not float(np.sqrt(((S.grid(u, v) - Q) ** 2).sum(-1)).max()) <= tol:
        return None
    return S, u, v
