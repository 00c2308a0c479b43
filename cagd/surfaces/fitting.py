"""Surfaces through a grid of points: global tensor-product B-spline interpolation
(Piegl & Tiller, The NURBS Book, 9.2.5, algorithm A9.4).
"""
from __future__ import annotations

from typing import Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError
from ..fitting.interpolation import interpolate, parametrize
from ..fitting.parameters import averaged_parameters, option
from ..knots import vectors as kv
from .bspline import BSplineSurface

SurfaceParameters = Union[str, Tuple[np.ndarray, np.ndarray]]


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
    direction. Then curve interpolation (:func:`cagd.fitting.interpolate`) through the
    rows: for every l, R_il interpolates Q_kl at ubar_k; and through the results: for
    every i, P_ij interpolates R_il at vbar_l. Each step solves one collocation system
    with all rows (columns) as right-hand sides.

    Raises:
        CagdError: points not an (n+1 >= 2, m+1 >= 2, dim) finite array, degree_u
            outside 1..n, degree_v outside 1..m, bad parameters
            (see :func:`surface_parameters`).
    """
    Q = _grid(points)
    nu, nv, dim = Q.shape
    p = _checks.integer(degree_u, "degree_u", 1, nu - 1)
    q = _checks.integer(degree_v, "degree_v", 1, nv - 1)
    pu, pv = surface_parameters(Q, parameters)
    ku, kvv = kv.averaged(pu, p), kv.averaged(pv, q)
    # through the rows: nu points, each a whole (nv * dim) row
    R = interpolate(Q.reshape(nu, nv * dim), p, pu, ku).control_points.reshape(nu, nv, dim)
    # through the columns: nv points, each a whole (nu * dim) column
    Rt = np.ascontiguousarray(R.transpose(1, 0, 2)).reshape(nv, nu * dim)
    P = interpolate(Rt, q, pv, kvv).control_points.reshape(nv, nu, dim).transpose(1, 0, 2)
    return BSplineSurface(P, p, q, ku, kvv)


def _grid(points: ArrayLike) -> np.ndarray:
    Q = _checks.finite_array(points, "points")
    if Q.ndim != 3 or Q.shape[0] < 2 or Q.shape[1] < 2 or Q.shape[2] < 1:
        raise CagdError(f"points: expected a grid of shape (nu >= 2, nv >= 2, dim), got {Q.shape}")
    return Q
