"""Joining Bezier curves with G0, G1 or G2 continuity (seed 000, 5.2.5 "Bezier 曲线的拼接").

Given P (degree n, control points P_0..P_n) the next curve Q (degree m,
Q_0..Q_m) starts where P ends. With a_n = P_n - P_{n-1} (seed's notation):

* G0: Q_0 = P_n.
* G1: Q_1 - Q_0 = alpha a_n, alpha > 0 (seed: b_1 = alpha a_n), i.e.
  Q'(0) = gamma P'(1) with gamma = m alpha / n (so gamma = alpha when m = n).
* G2: additionally Q''(0) = gamma^2 P''(1) + beta P'(1) (the seed's condition
  with alpha^2 for m = n). Solving for Q_2 with Q''(0) = m(m-1)(Q_2 - 2Q_1 + Q_0),
  P'(1) = n a_n and P''(1) = n(n-1)(P_n - 2P_{n-1} + P_{n-2}):

      Q_2 = 2 Q_1 - Q_0 + alpha^2 m(n-1)/(n(m-1)) (P_n - 2P_{n-1} + P_{n-2})
                        + beta n/(m(m-1)) a_n,

  which for m = n is the seed's
  Q_2 = (alpha^2 + 2 alpha + beta/(n-1) + 1) P_n - (2 alpha^2 + 2 alpha + beta/(n-1)) P_{n-1}
        + alpha^2 P_{n-2}.

  Both conditions say Q is, to second order at the joint, P reparametrised by a
  map phi with phi' = gamma > 0, phi'' = beta (chain rule), so unit tangent,
  curvature and principal normal agree (Farin, Curves and Surfaces for CAGD, 14.1).

"C1"/"C2" are the special case gamma = 1 (alpha = n/m), beta = 0: equal first
(and second) derivatives (seed 000, 5.1.1). A rational P is handled through its
actual end derivatives P'(1), P''(1) (the same reparametrisation argument):
Q_1 - Q_0 = (alpha / n) P'(1) = alpha (w_{n-1}/w_n) a_n, and Q_2 as above with
P'(1), P''(1) in place of the polynomial expressions. Q is always polynomial.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._deprecation import deprecated
from ..curves.base import rational_derivatives
from ..curves.bezier import BezierCurve
from ..errors import CagdError

_LEVELS = {"G0": 0, "G1": 1, "G2": 2, "C0": 0, "C1": 1, "C2": 2}


def _level(continuity: object) -> Tuple[str, int]:
    key = str(continuity).upper() if isinstance(continuity, str) else None
    if key not in _LEVELS:
        raise CagdError(f"continuity: must be one of {sorted(_LEVELS)}, got {continuity!r}")
    return key, _LEVELS[key]


def _end_derivatives(P: BezierCurve) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """P(1), P'(1), P''(1) from the end differences of the (homogeneous) control
    points, H'(1) = n (H_n - H_{n-1}), H''(1) = n(n-1)(H_n - 2H_{n-1} + H_{n-2})
    (seed 000, 5.2.1 end derivatives); a rational curve then by
    C' = (A' - w' C)/w, C'' = (A'' - 2w' C' - w'' C)/w (Piegl & Tiller eq. 4.8)."""
    n, H = P.degree, P.homogeneous_control_points
    d1 = n * (H[-1] - H[-2])
    d2 = n * (n - 1) * (H[-1] - 2.0 * H[-2] + H[-3]) if n >= 2 else np.zeros_like(d1)
    hom = np.stack([H[-1], d1, d2])[:, None, :]
    d = rational_derivatives(hom)[:, 0] if P.is_rational else hom[:, 0]
    return P.control_points[-1].copy(), d[1], d[2]


def join_control_points(P: BezierCurve, continuity: str = "G1", alpha: float = 1.0, beta: float = 0.0,
                        degree: Optional[int] = None) -> np.ndarray:
    """The leading control points Q_0..Q_c (c = 0, 1, 2 for G0/C0, G1/C1, G2/C2) of a
    degree-``degree`` (default: P's degree) Bezier curve Q that continues P with the
    requested continuity; see the module docstring for the formulas (seed 000, 5.2.5).

    Returns:
        array of shape (c + 1, dim).

    Raises:
        CagdError: P not a BezierCurve, unknown continuity, alpha <= 0, alpha/beta
            given with C1/C2 (they are fixed there), degree < c (Q would not have
            c + 1 control points) or < 1.
    """
    if not isinstance(P, BezierCurve):
        raise CagdError(f"P: must be a BezierCurve, got {type(P).__name__}")
    key, c = _level(continuity)
    n = P.degree
    m = n if degree is None else _checks.degree(degree, "degree", max(1, c))
    if m < c:
        raise CagdError(f"degree: {key} fixes {c + 1} control points of Q, so Q needs degree >= {c}, got {m}")
    alpha, beta = _checks.scalar(alpha, "alpha"), _checks.scalar(beta, "beta")
    if key in ("C1", "C2"):
        if alpha != 1.0:
            raise CagdError(f"alpha: {key} fixes Q'(0) = P'(1) (alpha = n/m); use G1/G2 to choose alpha")
        if beta != 0.0:
            raise CagdError(f"beta: {key} fixes beta = 0; use G2 to choose beta")
        alpha = n / m
    if alpha <= 0.0:
        raise CagdError(f"alpha: must be positive for a G1 join (Q_1 - Q_0 = alpha (P_n - P_(n-1))), got {alpha}")
    p1, d1, d2 = _end_derivatives(P)
    Q = [p1]
    if c >= 1:
        Q.append(p1 + (alpha / n) * d1)                     # Q'(0) = gamma P'(1), gamma = m alpha / n
    if c >= 2:
        gamma = m * alpha / n
        Q.append(2.0 * Q[1] - Q[0] + (gamma * gamma * d2 + beta * d1) / (m * (m - 1)))
    return np.array(Q)


def join_bezier(P: BezierCurve, continuity: str = "G1", alpha: float = 1.0, beta: float = 0.0,
                degree: Optional[int] = None) -> np.ndarray:
    """Deprecated (one release): the leading control points, now
    :func:`join_control_points`; the joined curve itself is :func:`join`."""
    deprecated("join_bezier", "join_bezier is deprecated: use join_control_points (the same leading control "
                              "points) or join (the joined BezierCurve, like every other constructor)")
    return join_control_points(P, continuity, alpha, beta, degree)


def join(P: BezierCurve, rest_points: Optional[ArrayLike] = None, continuity: str = "G1", alpha: float = 1.0,
         beta: float = 0.0) -> BezierCurve:
    """The Bezier curve Q continuing P: its leading control points from
    :func:`join_control_points`, followed by ``rest_points`` (the user's free points
    Q_{c+1}..Q_m); Q has degree m = c + len(rest_points).

    Raises:
        CagdError: as :func:`join_control_points`; ``rest_points`` of another dimension
            than P; too few points for Q (fewer than 2 in all, or m < 2 for G2).
    """
    if not isinstance(P, BezierCurve):
        raise CagdError(f"P: must be a BezierCurve, got {type(P).__name__}")
    key, c = _level(continuity)
    if rest_points is None or np.size(rest_points) == 0:
        rest = np.empty((0, P.dim))
    else:
        rest = _checks.points(rest_points, "rest_points")
        if rest.shape[1] != P.dim:
            raise CagdError(f"rest_points: P is {P.dim}-D, got points of dimension {rest.shape[1]}")
    m = c + rest.shape[0]
    if m < max(1, c):
        raise CagdError(f"rest_points: a {key} join needs at least {max(1, c) - c} further point(s) "
                        f"so that Q has degree >= {max(1, c)}, got {rest.shape[0]}")
    lead = join_control_points(P, key, alpha, beta, degree=m)
    return BezierCurve(np.vstack([lead, rest]))
