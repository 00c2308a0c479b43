"""The curvature comb of a curve (Farin, Curves and Surfaces for CAGD, 23.2 "curvature
plots"; the curvature vector kappa N = (C'' - (C''.T) T) / |C'|^2, Farin 10.1).

A tooth stands on the curve at C(t) and has the length scale * kappa(t); it points
away from the centre of curvature (the comb is drawn on the convex side), so
tip = C(t) - scale * kappa N. Teeth are placed per knot span (Bezier piece of the
exact NURBS form), each span's closed interval sampled on its own and evaluated on
that piece: at an interior knot there are two teeth at the same parameter, the left
and the right limit, so a curvature jump (a G1 but not G2 joint) shows as a jump of
the comb instead of being smoothed over by a sample on either side.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from .. import _checks
from .._results import ReadOnlyArrays
from ..curves.base import Curve
from ..errors import CagdError

COMB_SIZE = 0.15          # default scale: the longest tooth is this fraction of the curve's size
_SINGULAR = 1e-12         # |C'| below this fraction of its largest sample: a singular point, no tooth


@dataclass(frozen=True)
class CurvatureComb(ReadOnlyArrays):
    """The teeth of a curvature comb, M of them (see the module doc).

    params: (M,) curve parameters (an interior knot twice: left, then right limit);
    span: (M,) index of the knot span (Bezier piece) each tooth was evaluated on;
    base: (M, dim) points C(t); curvature: (M,) kappa >= 0 (0 at singular points,
    where C' vanishes); normals: (M, dim) unit vectors from the base to the tip, -N for
    the principal normal N (towards the centre of curvature), zero where kappa = 0;
    tips: (M, dim) base + scale * curvature * normals; scale: the tooth length per unit
    curvature."""
    params: np.ndarray
    span: np.ndarray
    base: np.ndarray
    curvature: np.ndarray
    normals: np.ndarray
    tips: np.ndarray
    scale: float

    def scaled(self, scale: float) -> "CurvatureComb":
        """The same comb with tooth length ``scale`` * curvature."""
        s = _checks.scalar(scale, "scale")
        return replace(self, tips=self.base + s * self.curvature[:, None] * self.normals, scale=s)


def curvature_comb(curve: Curve, samples_per_span: int = 8, scale: Optional[float] = None,
                   samples: int = 0) -> CurvatureComb:
    """The curvature comb of ``curve`` (any engine curve, any dimension >= 2).

    Args:
        curve: the curve.
        samples_per_span: teeth per knot span, at least 2 (both ends of the span's
            closed interval included).
        scale: tooth length per unit curvature; default COMB_SIZE times the size of the
            sampled points (largest extent of their box) over the largest curvature (0
            for a straight curve).
        samples: at least this many teeth in all (spans get teeth in proportion to
            their parameter length, at least ``samples_per_span`` each).

    Returns:
        :class:`CurvatureComb`.

    Raises:
        CagdError: not a curve, samples_per_span < 2, samples < 0, more teeth than
            MAX_SAMPLES = 10^7, a scale that is not a finite number.
    """
    if not isinstance(curve, Curve):
        raise CagdError(f"curve: expected a cagd Curve, got {type(curve).__name__}")
    from ..queries.bounds import bezier_pieces
    per = _checks.integer(samples_per_span, "samples_per_span", 2, _checks.MAX_SAMPLES)
    total = _checks.integer(samples, "samples", 0, _checks.MAX_SAMPLES)
    pieces = bezier_pieces(curve)
    b = pieces.breaks[0]
    h = np.diff(b)
    if per * len(h) > _checks.MAX_SAMPLES:
        raise CagdError(f"samples_per_span: {per} teeth on each of {len(h)} spans exceed MAX_SAMPLES = "
                        f"{_checks.MAX_SAMPLES}")
    counts = np.maximum(per, np.ceil(total * h / (b[-1] - b[0])).astype(np.intp))
    span = np.repeat(np.arange(len(h)), counts)
    first = np.repeat(np.cumsum(counts) - counts, counts)
    frac = (np.arange(len(span)) - first) / np.repeat(counts - 1, counts)
    t = np.where(frac == 1.0, b[span + 1], b[span] + frac * h[span])
    p, d1, d2 = pieces.derivatives(span, t[:, None], 2)
    # kappa N = (C'' - (C''.T) T) / |C'|^2 in the normalised frame: C' = a u, C'' = b w with
    # a, b the largest coordinates (scale-invariant; no under/overflow at 1e-300 / 1e300)
    a = np.max(np.abs(d1), axis=1)
    b2 = np.max(np.abs(d2), axis=1)
    u = d1 / np.where(a > 0, a, 1.0)[:, None]
    w = d2 / np.where(b2 > 0, b2, 1.0)[:, None]
    uu = np.einsum("ij,ij->i", u, u)
    top = float(a.max()) if a.size else 0.0
    regular = (a > 0) & (a * np.sqrt(uu) > _SINGULAR * top)
    uu = np.where(regular, uu, 1.0)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        factor = np.where(regular, (b2 / np.where(regular, a, 1.0)) / np.where(regular, a, 1.0), 0.0)
        kdir = (w - (np.einsum("ij,ij->i", w, u) / uu)[:, None] * u) / uu[:, None]     # kappa N / factor
        length = np.linalg.norm(kdir, axis=1)
        kappa = length * factor
        normals = np.where((kappa > 0.0)[:, None], -kdir / np.where(length > 0, length, 1.0)[:, None], 0.0)
    if scale is None:
        kmax = float(kappa.max())
        size = float(np.ptp(p, axis=0).max())
        scale = COMB_SIZE * size / kmax if kmax > 0.0 else 0.0
        # tooth lengths as COMB_SIZE size (kappa / kmax): no underflow of the scale at 1e-300
        lengths = COMB_SIZE * size * (kappa / kmax) if kmax > 0.0 else np.zeros_like(kappa)
    else:
        scale = _checks.scalar(scale, "scale")
        lengths = scale * kappa
    return CurvatureComb(t, span, p, kappa, normals, p + lengths[:, None] * normals, scale)
