"""The curvature plot of a curve, free of GUI code (numpy only): curvature against arc
length (Farin, Curves and Surfaces for CAGD, 23.1: "curvature plots"), from the
engine's fairness read-out (cagd.analysis.fairness: arc_length, curvature per sample,
the samples per knot span with both limits at a knot, so a curvature jump is drawn as
a vertical step), mapped into a widget's pixel rectangle. The panel (plotpanel.py)
draws :attr:`CurvaturePlot.pixels` as a polyline; a test can map pixel rows back to
curvature with :meth:`CurvaturePlot.curvature_at_row`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from . import ensure_engine

ensure_engine()
from cagd import CagdError  # noqa: E402

MARGIN = 24              # pixels between the plot and the widget's border (axis labels)
HEADROOM = 0.1           # the curvature axis reaches this fraction above the largest curvature


@dataclass(frozen=True)
class CurvaturePlot:
    """Pixels of the curvature plot in a width x height widget (x right, y down) and
    the axis ranges: s from 0 to length, kappa from k_low (0, or the least signed
    curvature) to k_high = k_max + HEADROOM (k_max - k_low) (k_max > 0; 1 if kappa = 0)."""
    pixels: np.ndarray           # (n, 2) float pixel coordinates (x, y)
    length: float
    k_low: float
    k_high: float
    width: int
    height: int
    margin: int

    def row_of(self, kappa: float) -> float:
        """The pixel row (y) of the curvature value ``kappa``."""
        return self.margin + (self.k_high - kappa) / (self.k_high - self.k_low) * (self.height - 2 * self.margin)

    def curvature_at_row(self, row: float) -> float:
        """The curvature value drawn at pixel row ``row`` (the inverse of :meth:`row_of`)."""
        return self.k_high - (row - self.margin) / (self.height - 2 * self.margin) * (self.k_high - self.k_low)

    @property
    def axis_rows(self) -> Tuple[float, float]:
        """Rows of k_high (top) and k_low (bottom)."""
        return float(self.margin), float(self.height - self.margin)


def curvature_plot(arc_length: np.ndarray, curvature: np.ndarray, width: int, height: int,
                   margin: int = MARGIN) -> CurvaturePlot:
    """Map samples (s_i, kappa_i) into the widget: x = margin + s / L (width - 2 margin),
    y = margin + (k_high - kappa) / (k_high - k_low) (height - 2 margin), L = s_n - s_0.

    Raises:
        CagdError: arrays not 1-D of equal length >= 2, not finite, s decreasing or of
            zero total length, width/height not leaving room inside the margins.
    """
    s = np.asarray(arc_length, dtype=np.float64)
    k = np.asarray(curvature, dtype=np.float64)
    if s.ndim != 1 or k.shape != s.shape or len(s) < 2:
        raise CagdError(f"curvature: need 1-D arc_length and curvature of one length >= 2, got {s.shape}, {k.shape}")
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(k))):
        raise CagdError("curvature: arc_length and curvature must be finite")
    if np.any(np.diff(s) < 0) or s[-1] <= s[0]:
        raise CagdError("arc_length: must increase from the first sample to the last")
    if int(width) <= 2 * margin or int(height) <= 2 * margin:
        raise CagdError(f"width/height: {width} x {height} leaves no room inside the margin {margin}")
    length = float(s[-1] - s[0])
    k_low = min(0.0, float(k.min()))
    k_max = float(k.max())
    k_high = k_max + HEADROOM * (k_max - k_low) if k_max > k_low else k_low + 1.0
    x = margin + (s - s[0]) / length * (int(width) - 2 * margin)
    y = margin + (k_high - k) / (k_high - k_low) * (int(height) - 2 * margin)
    pixels = np.stack([x, y], axis=1)
    pixels.flags.writeable = False
    return CurvaturePlot(pixels, length, k_low, k_high, int(width), int(height), int(margin))
