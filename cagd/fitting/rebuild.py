"""Rebuild a curve or surface to a chosen size: a B-spline of the given degree and
control-point count, fitted by least squares to dense samples of the original, with the
deviation measured (issue 17; Rhino's Rebuild; the seeds do not treat it).

The new knots are clamped uniform over the original's domain, or the original's own knots
when count and degree are the original's (the original then lies in the fitted space and
comes back: rebuilding to the same size is the identity). The samples are
REBUILD_SAMPLES per new knot span (and per original span where the original is a
B-spline) at the original's parameters, so the parametrisation is kept; the end points
(the boundary curves' corners of a surface) are held (Piegl & Tiller 9.4.1, eq. 9.63-9.67,
per direction for a surface: the tensor-product least squares separates). A rational or
periodic original is rebuilt polynomial and clamped.

The reported deviation is the largest certified closest-point distance from samples of
the original (DEVIATION_PER_SPAN per span of each) to the result.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple, Union

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from .interpolation import LSQ_DENSE_MAX, _frame, _least_squares
from .separable import ends_held_operator

#: fitting samples per knot span of the result (and of the original B-spline)
REBUILD_SAMPLES = 12
#: samples per span (of the original and of the result) at which the deviation is measured
DEVIATION_PER_SPAN = 16
#: the largest control-point count per direction rebuild accepts (the samples grow with it)
MAX_REBUILD_COUNT = 10_000


@dataclass(frozen=True)
class Rebuild:
    """The result of :func:`rebuild`: ``result`` (a BSplineCurve or BSplineSurface of the
    asked size) and ``deviation``, the largest certified distance of the original's
    samples from it; ``converged`` is True (the size is what was asked) and ``message``
    states the size and the deviation."""
    result: object
    deviation: float
    converged: bool
    message: str


def _samples(breaks_list, per: int) -> np.ndarray:
    """Parameters: ``per`` per span of every breakpoint vector given, merged."""
    f = np.linspace(0.0, 1.0, per + 1)
    out = [(b[:-1, None] + f[None] * np.diff(b)[:, None]).ravel() for b in breaks_list]
    return np.unique(np.concatenate(out))


def _breaks(obj, direction: int = 0) -> np.ndarray:
    if isinstance(obj, BSplineCurve):
        return np.unique(obj.full_knots[obj.degree:len(obj.full_knots) - obj.degree])
    if isinstance(obj, BSplineSurface):
        U, p = (obj._u, obj.degree_u) if direction == 0 else (obj._v, obj.degree_v)
        return np.unique(U[p:len(U) - p])
    return np.zeros(0)


def _knots(obj, direction: int, count: int, degree: int, a: float, b: float) -> np.ndarray:
    """The original's knots when count and degree are its own (clamped), else clamped
    uniform on [a, b]."""
    if isinstance(obj, BSplineCurve) and (len(obj.control_points), obj.degree) == (count, degree) \
            and not obj.periodic:
        return np.asarray(obj.knots, float)
    if isinstance(obj, BSplineSurface) and not (obj.periodic_u if direction == 0 else obj.periodic_v):
        own = (obj.control_points.shape[direction], obj.degree_u if direction == 0 else obj.degree_v)
        if own == (count, degree):
            return np.asarray(obj.knots_u if direction == 0 else obj.knots_v, float)
    return kv.clamped_uniform(count, degree, a, b)


def _fit_rows(U: np.ndarray, p: int, t: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Least squares along axis 0 of Q (m, F) at the parameters t on the clamped knots U
    with the ends held (Piegl & Tiller 9.4.1, eq. 9.63-9.67): the (len(U) - p - 1, F)
    control points, solved in Q's normalised frame, the ends Q[0] and Q[-1] bit for bit.
    Up to LSQ_DENSE_MAX matrix entries by the separable fit's operator
    (:func:`cagd.fitting.separable.ends_held_operator`: the minimum-norm least squares
    where a pole has no site, so it never raises); larger systems (rebuild's, whose
    samples fill every span) by the banded normal equations of
    :func:`cagd.fitting.interpolation._least_squares` (O(m p) memory).

    Raises:
        CagdError: a system above LSQ_DENSE_MAX entries with a span without a site."""
    count = len(U) - p - 1
    center, scale = _frame(Q)
    Qn = (Q - center) / scale
    if len(t) * count <= LSQ_DENSE_MAX:
        P = ends_held_operator(U, p, t)[1] @ Qn
    else:
        P = np.empty((count, Q.shape[1]))
        P[0], P[-1] = Qn[0], Qn[-1]
        try:
            P[1:-1] = _least_squares(U, p, t[1:-1], count, Qn)
        except CagdError as exc:
            raise CagdError(f"count: {count} control points of degree {p} cannot be fitted here "
                            f"({str(exc).split(': ', 1)[-1]})") from None
    P = P * scale + center
    P[0], P[-1] = Q[0], Q[-1]
    return P


def rebuild(obj: Union[Curve, Surface], count: Union[int, Tuple[int, int]],
            degree: Union[int, Tuple[int, int]] = 3) -> Rebuild:
    """A B-spline with ``count`` control points of ``degree`` (per direction for a
    surface: (count_u, count_v), (degree_u, degree_v)) fitted to the curve or rectangular
    surface ``obj``; see the module docstring.

    Raises:
        CagdError: obj not a cagd Curve or rectangular Surface, count < degree + 1,
            degree out of range."""
    from ..queries.closest import closest_point
    out: Union[BSplineCurve, BSplineSurface]
    if isinstance(obj, Curve):
        p = _checks.degree(degree, "degree", 1)
        n = _checks.integer(count, "count", p + 1, MAX_REBUILD_COUNT)
        a, b = obj.domain
        U = _knots(obj, 0, n, p, a, b)
        t = _samples([np.unique(U[p:len(U) - p]), _breaks(obj)], max(REBUILD_SAMPLES, p + 2))
        out = BSplineCurve(_fit_rows(U, p, t, obj(t)), p, U)
        check = _samples([np.unique(U[p:len(U) - p]), _breaks(obj)], DEVIATION_PER_SPAN)
        dev = float(closest_point(out, obj(check)).distances.max())
        return Rebuild(out, dev, True, f"{n} control points of degree {p}, within {dev:.3g} of the original")
    if isinstance(obj, Surface) and obj.rectangular:
        pu, pv = _pair(degree, "degree")
        nu, nv = _pair(count, "count")
        pu, pv = _checks.degree(pu, "degree", 1), _checks.degree(pv, "degree", 1)
        nu, nv = _checks.integer(nu, "count", pu + 1, MAX_REBUILD_COUNT), _checks.integer(nv, "count", pv + 1,
                                                                                           MAX_REBUILD_COUNT)
        (a, b), (c, d) = obj.domain
        U, V = _knots(obj, 0, nu, pu, a, b), _knots(obj, 1, nv, pv, c, d)
        su = _samples([np.unique(U[pu:len(U) - pu]), _breaks(obj, 0)], max(REBUILD_SAMPLES, pu + 2))
        sv = _samples([np.unique(V[pv:len(V) - pv]), _breaks(obj, 1)], max(REBUILD_SAMPLES, pv + 2))
        G = obj.grid(su, sv)                                         # (mu, mv, dim)
        dim = G.shape[2]
        rows = _fit_rows(U, pu, su, G.reshape(len(su), -1)).reshape(nu, len(sv), dim)
        P = _fit_rows(V, pv, sv, rows.transpose(1, 0, 2).reshape(len(sv), -1)).reshape(nv, nu, dim)
        out = BSplineSurface(P.transpose(1, 0, 2), pu, pv, U, V)
        cu = _samples([np.unique(U[pu:len(U) - pu]), _breaks(obj, 0)], DEVIATION_PER_SPAN // 2)
        cv = _samples([np.unique(V[pv:len(V) - pv]), _breaks(obj, 1)], DEVIATION_PER_SPAN // 2)
        dev = float(closest_point(out, obj.grid(cu, cv).reshape(-1, dim)).distances.max())
        return Rebuild(out, dev, True, f"{nu} x {nv} control points of degree {pu} x {pv}, within {dev:.3g} "
                                       f"of the original")
    raise CagdError(f"obj: expected a cagd Curve or a rectangular Surface, got {type(obj).__name__}")


def _pair(value, name: str) -> Tuple[int, int]:
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return value[0], value[1]
    if isinstance(value, (tuple, list)):
        raise CagdError(f"{name}: expected one value or a pair (u, v), got {value!r}")
    return value, value
