"""Parameters for points to be interpolated or approximated: the one list of rules and
the one implementation of them (Piegl & Tiller, The NURBS Book, 9.2.1 and 9.2.5; Lee,
"Choosing nodes in parametric curve interpolation", CAD 21, 1989).

Every function that parametrises points takes ``parameters=``: one of
:data:`PARAMETERS` or explicit values. With Q_0..Q_n the points and d_k = |Q_k - Q_{k-1}|
the interval lengths are h_k = 1 ("uniform", eq. 9.3), d_k ("chord", eq. 9.5) or
sqrt(d_k) ("centripetal", eq. 9.6).
"""
from __future__ import annotations

from typing import Any, Dict, Optional, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._deprecation import renamed
from ..errors import CagdError

PARAMETERS = ("uniform", "chord", "centripetal")

#: a ``parameters=`` argument: one of :data:`PARAMETERS` or explicit parameter values
ParameterSpec = Union[str, ArrayLike]


def rule(value: object, name: str = "parameters") -> str:
    """``value`` checked to be one of :data:`PARAMETERS` (the one place the names are
    validated).

    Raises:
        CagdError: naming ``name`` and listing the values."""
    if not isinstance(value, str) or value not in PARAMETERS:
        raise CagdError(f"{name}: unknown parametrisation {value!r}; expected one of {PARAMETERS} "
                        f"or explicit parameter values")
    return value


def option(parameters: Any, old: Dict[str, Any], func: str, default: Any) -> Any:
    """The ``parameters`` argument of ``func``, taking the deprecated keywords in ``old``
    ({"method": value or None, "parametrization": value or None}) for one release."""
    for key, value in old.items():
        if value is not None:
            parameters = renamed(func, key, "parameters", value, parameters, default)
    return parameters


def interval_lengths(chords: np.ndarray, kind: str) -> np.ndarray:
    """h_k from the chord lengths d_k: 1, d_k or sqrt(d_k) (see the module doc); ``kind``
    is validated."""
    kind = rule(kind)
    if kind == "uniform":
        return np.ones_like(chords)
    return chords.copy() if kind == "chord" else np.sqrt(chords)


def averaged_parameters(Q: np.ndarray, kind: str, name: str = "points", item: str = "points") -> np.ndarray:
    """Parameters 0 = t_0 < ... < t_n = 1 of the n+1 entries along axis 0 of Q (shape
    (n+1, columns, dim)): t_k = sum_{j<=k} h_j / sum h_j for every column, averaged over
    the columns (Piegl & Tiller eq. 9.9-9.10 for grids, 10.8 for loft sections; one
    column is the curve case, eq. 9.3-9.6); columns of zero total length (a pole, a
    common apex) are left out.

    Raises:
        CagdError: an unknown ``kind``; naming ``name`` when every column has zero length
            or two consecutive ``item`` coincide in every column.
    """
    kind = rule(kind)
    n = Q.shape[0] - 1
    if kind == "uniform":
        return np.arange(n + 1, dtype=np.float64) / n
    d = interval_lengths(np.linalg.norm(np.diff(normalised(Q), axis=0), axis=-1), kind)      # (n, columns)
    total = d.sum(axis=0)
    used = total > 0.0
    if not used.any():
        raise CagdError(f"{name}: all {item} coincide; no {kind} parameters")
    u = np.concatenate([np.zeros((1, int(used.sum()))), np.cumsum(d[:, used], axis=0)]) / total[used]
    u = u.mean(axis=1)
    u[0], u[-1] = 0.0, 1.0
    bad = np.flatnonzero(np.diff(u) <= 0.0)
    if bad.size:
        k = int(bad[0])
        raise CagdError(f"{name}: {item}[{k}] and {item}[{k + 1}] coincide; "
                        f"{kind} parameters need distinct consecutive {item}")
    return u


def normalised(Q: np.ndarray) -> np.ndarray:
    """``Q`` divided by its largest absolute coordinate (a power of two, so exactly), so
    that differences and their norms neither overflow (points at 1e300) nor underflow
    (at 1e-300); chord lengths scale uniformly, so every parametrisation is unchanged."""
    m = float(np.max(np.abs(Q))) if Q.size else 0.0
    if not m > 0.0:
        return Q
    return np.ldexp(Q, -int(np.frexp(m)[1]))


def spline_parameters(points: ArrayLike, parameters: str = "chord", *,
                      parametrization: Optional[str] = None) -> np.ndarray:
    """Parameters t_0 = 0, t_{k} = t_{k-1} + h_k, not normalised: h_k = 1 ("uniform"),
    |p_k - p_{k-1}| ("chord") or its square root ("centripetal") (see the module doc).

    Raises:
        CagdError: coincident consecutive points (a zero chord; "chord", "centripetal"),
            an unknown name.
    """
    kind = rule(option(parameters, {"parametrization": parametrization}, "spline_parameters", "chord"))
    P = _checks.points(points, "points", min_count=2)
    d = np.ones(len(P) - 1) if kind == "uniform" else chords(P, "points")
    return np.concatenate([[0.0], np.cumsum(interval_lengths(d, kind))])


def chords(P: np.ndarray, name: str) -> np.ndarray:
    """|p_k - p_{k-1}|, all non-zero.

    Raises:
        CagdError: two consecutive points coincide."""
    d = np.linalg.norm(np.diff(normalised(P), axis=0), axis=1) * _scale_of(P)
    if np.any(d == 0.0):
        i = int(np.argmax(d == 0.0))
        raise CagdError(f"{name}: consecutive points {i} and {i + 1} coincide (zero chord)")
    return d


def _scale_of(P: np.ndarray) -> float:
    """The factor :func:`normalised` divided by."""
    m = float(np.max(np.abs(P))) if P.size else 0.0
    return float(np.ldexp(1.0, int(np.frexp(m)[1]))) if m > 0.0 else 1.0
