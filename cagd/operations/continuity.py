"""Measured continuity at the joint of two curves (seed 000, 5.1.1 "连续性条件").

Parametric: C0 the points agree, C1 also the first derivatives, C2 also the
second derivatives. Geometric: G1 the first derivatives are parallel and point
the same way (seed: "proportional"), G2 in addition equal curvature vectors
kappa N = (C'' - (C''.T) T) / |C'|^2, i.e. equal curvature and principal normal
(seed: "the curvatures are equal"; Farin, Curves and Surfaces for CAGD, 14.1).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from .. import _checks
from .._deprecation import RELATIVE, deprecated, renamed
from ..curves.base import Curve
from ..errors import CagdError


CONTINUITY_TOL = 1e-9      # default relative tolerance of the continuity tests


@dataclass(frozen=True)
class ContinuityReport:
    """Measurements at c1(t1) -> c2(t2) and the continuity they satisfy.

    gap: |c2(t2) - c1(t1)|; tangent_angle: angle between c1'(t1) and c2'(t2) in
    radians (nan if either vanishes); derivative_ratio: |c2'| / |c1'|;
    curvature_difference: |kappa2 - kappa1|; second_derivative_gap: |c2'' - c1''|;
    rel_tol: the relative tolerance used; size: the length scale (bounding-box
    diagonal of both curves) that makes it relative; angle_tol: the G1 angle bound
    (radians). ``tol`` is the deprecated name of ``rel_tol`` (one release).
    """
    t1: float
    t2: float
    gap: float
    tangent_angle: float
    derivative_ratio: float
    curvature_difference: float
    second_derivative_gap: float
    C0: bool
    C1: bool
    C2: bool
    G1: bool
    G2: bool
    rel_tol: float
    size: float
    angle_tol: float = CONTINUITY_TOL

    @property
    def tol(self) -> float:
        """Deprecated name of :attr:`rel_tol`."""
        deprecated("ContinuityReport.tol", "use rel_tol (the same relative tolerance)")
        return self.rel_tol

    @property
    def level(self) -> str:
        """The strongest property that holds: "C2" > "G2" > "C1" > "G1" > "C0" > "none"."""
        for name in ("C2", "G2", "C1", "G1", "C0"):
            if getattr(self, name):
                return name
        return "none"

    def __str__(self) -> str:
        return (f"{self.level}: gap {self.gap:.3g}, tangent angle {self.tangent_angle:.3g} rad, "
                f"|c2'|/|c1'| {self.derivative_ratio:.6g}, curvature difference "
                f"{self.curvature_difference:.3g}, |c2''-c1''| {self.second_derivative_gap:.3g} "
                f"(rel_tol {self.rel_tol:g} x size {self.size:.3g}, angle_tol {self.angle_tol:g} rad)")


def tolerances(func: str, rel_tol: float, angle_tol: Optional[float],
               tol: Optional[float]) -> Tuple[float, float]:
    """(rel_tol, angle_tol) of a continuity test ``func``, validated: ``angle_tol``
    defaults to ``rel_tol`` (radians); ``tol`` is the deprecated name of ``rel_tol``."""
    if tol is not None:
        rel_tol = renamed(func, "tol", "rel_tol", tol, rel_tol, CONTINUITY_TOL, RELATIVE)
    rel_tol = _checks.positive(rel_tol, "rel_tol")
    return rel_tol, (rel_tol if angle_tol is None else _checks.angle(angle_tol))


def _norm(x: np.ndarray) -> float:
    """|x| without over/underflow of the squares (x divided by its largest coordinate)."""
    m = float(np.max(np.abs(x))) if x.size else 0.0
    return m * float(np.linalg.norm(x / m)) if m > 0.0 else 0.0


def curve_size(*curves: Curve, samples: int = 33) -> float:
    """Diagonal of the bounding box of ``samples`` points on each curve (a length
    scale for relative tolerances; 1 for curves collapsed to a point).

    Raises:
        CagdError: samples not an integer in [2, MAX_SAMPLES], a curve that is not a Curve."""
    samples = _checks.integer(samples, "samples", 2, _checks.MAX_SAMPLES)
    for i, c in enumerate(curves):
        if not isinstance(c, Curve):
            raise CagdError(f"curves[{i}]: must be a cagd Curve, got {type(c).__name__}")
    pts: List[np.ndarray] = []
    for c in curves:
        a, b = c.domain
        pts.append(c._evaluate(np.linspace(a, b, samples), 0)[0])
    every = np.concatenate(pts)
    with np.errstate(over="ignore"):
        size = _norm(0.5 * every.max(axis=0) - 0.5 * every.min(axis=0)) * 2.0
    return size if size > 0.0 else 1.0


def _curvature_vector(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """kappa N = (d2 - (d2.T) T) / |d1|^2, T = d1 / |d1|, without squaring |d1|."""
    n1 = _norm(d1)
    if n1 == 0.0:
        return np.full_like(d1, np.nan)
    T = d1 / n1
    with np.errstate(over="ignore", under="ignore"):
        return (d2 - (d2 @ T) * T) / n1 / n1


def curvature_scale(k1: np.ndarray, k2: np.ndarray, size: float) -> float:
    """What a difference of curvature vectors k1, k2 is relative to in the G2 test:
    max(|k1|, |k2|, 1 / size) (a flat pair is compared with the curvature of the size)."""
    return max(_norm(k1), _norm(k2), 1.0 / size)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two vectors, 2 atan2(|a^ - b^|, |a^ + b^|) (accurate near 0 and pi)."""
    na, nb = _norm(a), _norm(b)
    if na == 0.0 or nb == 0.0:
        return float("nan")
    ua, ub = a / na, b / nb
    return float(2.0 * np.arctan2(np.linalg.norm(ua - ub), np.linalg.norm(ua + ub)))


def continuity(c1: Curve, c2: Curve, t1: Optional[float] = None, t2: Optional[float] = None,
               rel_tol: float = CONTINUITY_TOL, *, angle_tol: Optional[float] = None,
               tol: Optional[float] = None) -> ContinuityReport:
    """Continuity of the joint c1(t1) -> c2(t2) (default: end of c1, start of c2).

    With size the bounding-box diagonal of both curves and L1, L2 their domain
    lengths, the tests (``rel_tol`` relative, ``angle_tol`` in radians, default
    ``rel_tol``) are
    C0: gap <= rel_tol size;
    C1: C0 and |c2' - c1'| <= rel_tol max(|c1'|, |c2'|, size / L);
    C2: C1 and |c2'' - c1''| <= rel_tol max(|c1''|, |c2''|, v^2 / size, size / L^2), v = max(|c1'|, |c2'|);
    G1: C0, both derivatives non-zero (above 1e-12 size / L) and tangent_angle <= angle_tol;
    G2: G1 and |k2 - k1| <= rel_tol max(|k1|, |k2|, 1 / size) for the curvature vectors k.
    The derivatives are taken in each curve's own parameter (one-sided at the ends).
    ``tol`` is the deprecated name of ``rel_tol`` (one release; ``tol`` is a distance in
    cagd).

    Raises:
        CagdError: c1 or c2 not a Curve, different dimensions, rel_tol not positive,
            angle_tol negative, t1/t2 outside the domains.
    """
    for name, c in (("c1", c1), ("c2", c2)):
        if not isinstance(c, Curve):
            raise CagdError(f"{name}: must be a cagd Curve, got {type(c).__name__}")
    if c1.dim != c2.dim:
        raise CagdError(f"c2: dimension {c2.dim} differs from c1's {c1.dim}")
    rel_tol, angle_tol = tolerances("continuity", rel_tol, angle_tol, tol)
    t1 = c1.domain[1] if t1 is None else _checks.scalar(t1, "t1")
    t2 = c2.domain[0] if t2 is None else _checks.scalar(t2, "t2")
    D1, D2 = c1.derivatives(t1, 2), c2.derivatives(t2, 2)
    size = curve_size(c1, c2)
    span = max(c1.domain[1] - c1.domain[0], c2.domain[1] - c2.domain[0])

    with np.errstate(over="ignore"):
        gap = _norm(0.5 * D2[0] - 0.5 * D1[0]) * 2.0
        n1, n2 = _norm(D1[1]), _norm(D2[1])
        v = max(n1, n2)
        dgap1 = _norm(0.5 * D2[1] - 0.5 * D1[1]) * 2.0
        dgap2 = _norm(0.5 * D2[2] - 0.5 * D1[2]) * 2.0
    angle = _angle(D1[1], D2[1])
    k1, k2 = _curvature_vector(D1[1], D1[2]), _curvature_vector(D2[1], D2[2])
    kn1, kn2 = _norm(k1), _norm(k2)

    C0 = gap <= rel_tol * size
    C1 = C0 and dgap1 <= rel_tol * max(v, size / span)
    with np.errstate(over="ignore", under="ignore"):
        C2 = C1 and dgap2 <= rel_tol * max(_norm(D1[2]), _norm(D2[2]), v * (v / size), size / span / span)
    tiny = 1e-12 * size / span           # a first derivative below this is rounding noise
    G1 = bool(C0 and n1 > tiny and n2 > tiny and angle <= angle_tol)
    G2 = bool(G1 and _norm(k2 - k1) <= rel_tol * curvature_scale(k1, k2, size))
    ratio = n2 / n1 if n1 > tiny else (float("inf") if n2 > tiny else float("nan"))
    if n2 <= tiny and n1 > tiny:
        ratio = 0.0
    return ContinuityReport(float(t1), float(t2), gap, angle, ratio, abs(kn2 - kn1), dgap2,
                            bool(C0), bool(C1), bool(C2), G1, G2, rel_tol, size, float(angle_tol))
