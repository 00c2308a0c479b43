"""Bridge (blend) curves between the ends of two curves, G1 or G2 to both
(Farin, Curves and Surfaces for CAGD, 14.1 G1/G2 joins; seed 000, 5.2.5).

At c1's chosen end take the point P, the unit tangent T oriented away from c1
into the gap (c1'/|c1'| at its end, -c1'/|c1'| at its start) and the curvature
vector K = (c'' - (c''.T) T) / |c'|^2 (orientation-free); likewise Q, U, L at
c2's end, U oriented from the gap into c2. The bridge is a Bezier curve B of
degree n (3 for G1, 5 for G2) with speeds s0, s1 > 0 at its ends:

    B_0 = P,  B_1 = P + (s0 / n) T,  B_2 = 2 B_1 - B_0 + s0^2 K / (n (n-1)),
    B_n = Q,  B_(n-1) = Q - (s1 / n) U,  B_(n-2) = 2 B_(n-1) - B_n + s1^2 L / (n (n-1)),

from B'(0) = n (B_1 - B_0) = s0 T and B''(0) = n (n-1) (B_2 - 2 B_1 + B_0) = s0^2 K,
so the curvature vector of B at 0, (B'' - (B''.T) T) / s0^2, is K (the G2 condition
with no tangential acceleration, beta = 0 of seed 000, 5.2.5); the same at 1.
Speeds (a chord-length heuristic, Farin's choice for Hermite-type bridges):
s0 = a |Q - P|, s1 = b |Q - P| with (a, b) = ``tangent_scales`` (default (1, 1)),
i.e. the first and last control legs are |Q - P| / n long; two collinear
tangents along the chord then give the straight segment with uniform speed.
"""
from __future__ import annotations

from dataclasses import dataclass
from operator import index
from typing import Optional, Sequence, Tuple

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..errors import CagdError
from .continuity import CONTINUITY_TOL, _angle, _curvature_vector, _norm, curvature_scale, curve_size

#: an end derivative at most this times (curve size / domain length) counts as zero
#: (a degenerate end without a tangent), the threshold of :func:`continuity`'s G1 test
TANGENT_ZERO_TOL = 1e-12
#: end points closer than this times the size of both curves count as coincident
COINCIDENT_TOL = 1e-12
_ENDS = ("start", "end")


@dataclass(frozen=True)
class BlendCurve:
    """A bridge curve and what it achieves at both ends.

    curve: the Bezier bridge (degree 3 for G1, 5 for G2), curve(0) = c1's end,
    curve(1) = c2's end; g1_angles: angles (radians) between the bridge's tangent and
    the oriented end tangent of c1 (at 0) and c2 (at 1); curvature_gaps: relative
    differences |K_bridge - K_curve| / max(|K_bridge|, |K_curve|, 1 / size) of the
    curvature vectors there (size: bounding-box diagonal of c1 and c2), measured for
    both continuities (guaranteed small only for continuity 2); converged: all the
    requested measurements within CONTINUITY_TOL; message: a summary.
    """
    curve: BezierCurve
    g1_angles: Tuple[float, float]
    curvature_gaps: Tuple[float, float]
    continuity: int
    converged: bool
    message: str


def _end(c: Curve, end: object, name: str, end_name: str) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(point, derivative oriented outwards from the curve, curvature vector) at an end."""
    if not isinstance(end, str) or end not in _ENDS:
        raise CagdError(f"{end_name}: must be 'start' or 'end', got {end!r}")
    a, b = c.domain
    t = b if end == "end" else a
    D = c.derivatives(t, 2)
    if _norm(D[1]) <= TANGENT_ZERO_TOL * curve_size(c) / (b - a):
        raise CagdError(f"{name}: its first derivative vanishes at its {end} (t = {t!r}): a degenerate end "
                        f"has no tangent to match ({end_name} = {end!r})")
    d1 = D[1] if end == "end" else -D[1]
    return c(t), d1, _curvature_vector(D[1], D[2])   # c(t): the point as evaluated (D[0] may differ by an ulp)


def _relative_gap(D: np.ndarray, K: np.ndarray, size: float) -> float:
    """|k - K| / max(|k|, |K|, 1 / size) for k the curvature vector from derivatives D
    (the relative measure of :func:`continuity`'s G2 test)."""
    kb = _curvature_vector(D[1], D[2])
    return _norm(kb - K) / curvature_scale(kb, K, size)


def _scales(tangent_scales: Optional[Sequence[float]]) -> Tuple[float, float]:
    if tangent_scales is None:
        return 1.0, 1.0
    try:
        a, b = tangent_scales
    except (TypeError, ValueError):
        raise CagdError(f"tangent_scales: must be two positive numbers (a, b), got {tangent_scales!r}") from None
    return _checks.positive(a, "tangent_scales[0]"), _checks.positive(b, "tangent_scales[1]")


def _continuity(value: object, allowed: Tuple[int, ...] = (1, 2),
                what: str = "1: G1, a cubic bridge; 2: G2, a quintic") -> int:
    """``value`` as an int of ``allowed`` (not a bool), else CagdError naming continuity."""
    try:
        k = index(value)  # type: ignore[arg-type]
    except TypeError:
        k = -1
    if isinstance(value, (bool, np.bool_)) or k not in allowed:
        raise CagdError(f"continuity: must be one of {allowed} ({what}), got {value!r}")
    return k


def blend_curve(c1: Curve, end1: str, c2: Curve, end2: str, continuity: int = 1,
                tangent_scales: Optional[Sequence[float]] = None) -> BlendCurve:
    """A Bezier bridge from c1's ``end1`` to c2's ``end2`` ("start" or "end"), G1
    (``continuity=1``, cubic) or G2 (``continuity=2``, quintic) to both; control
    points and the automatic speeds s0 = a |Q - P|, s1 = b |Q - P| in the module
    docstring (Farin 14.1; seed 000, 5.2.5), (a, b) = ``tangent_scales``.

    Raises:
        CagdError: c1/c2 not cagd curves, of different dimensions, end1/end2 not
            "start"/"end", continuity not 1 or 2, a vanishing end derivative (naming the
            curve), tangent_scales not two positive finite numbers, coincident end points.
    """
    for name, c in (("c1", c1), ("c2", c2)):
        if not isinstance(c, Curve):
            raise CagdError(f"{name}: must be a cagd Curve, got {type(c).__name__}")
    if c1.dim != c2.dim:
        raise CagdError(f"c2: dimension {c2.dim} differs from c1's {c1.dim}")
    k = _continuity(continuity)
    sa, sb = _scales(tangent_scales)
    P, d0, K0 = _end(c1, end1, "c1", "end1")
    Q, e1, L1 = _end(c2, end2, "c2", "end2")
    e1 = -e1                                        # into c2: c2'(start) or -c2'(end)
    size = curve_size(c1, c2)
    with np.errstate(over="ignore"):
        chord = _norm(0.5 * Q - 0.5 * P) * 2.0
    if not chord > COINCIDENT_TOL * size:
        raise CagdError(f"end2: c2's {end2} point coincides with c1's {end1} point (distance {chord:.3g}); "
                        f"a bridge needs two distinct end points")
    n = 2 * k + 1
    s0, s1 = sa * chord, sb * chord
    T, U = d0 / _norm(d0), e1 / _norm(e1)
    B = np.empty((n + 1, P.shape[0]))
    B[0], B[1], B[-1], B[-2] = P, P + (s0 / n) * T, Q, Q - (s1 / n) * U
    if k == 2:
        B[2] = 2.0 * B[1] - B[0] + (s0 * s0 / (n * (n - 1))) * K0
        B[-3] = 2.0 * B[-2] - B[-1] + (s1 * s1 / (n * (n - 1))) * L1
    bridge = BezierCurve(B)
    D0, D1 = bridge.derivatives(0.0, 2), bridge.derivatives(1.0, 2)
    angles = (_angle(D0[1], T), _angle(D1[1], U))
    gaps = (_relative_gap(D0, K0, size), _relative_gap(D1, L1, size))
    g1 = max(angles) <= CONTINUITY_TOL
    g2 = max(gaps) <= CONTINUITY_TOL
    converged = bool(g1 and (g2 or k == 1))
    message = (f"G{k} bridge of degree {n}: tangent angles {angles[0]:.3g}, {angles[1]:.3g} rad, relative "
               f"curvature gaps {gaps[0]:.3g}, {gaps[1]:.3g}"
               + ("" if converged else f" (above the tolerance {CONTINUITY_TOL:g})"))
    return BlendCurve(bridge, angles, gaps, k, converged, message)
