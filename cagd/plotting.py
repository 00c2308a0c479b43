"""PNG pictures of curves: the curve, its control polygon and a curvature comb.

matplotlib is imported only inside these functions (the ``plot`` extra).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from .curves.base import Curve


def curvature_comb(curve: Curve, samples: int = 200, scale: Optional[float] = None):
    """Base points and tooth tips of a curvature comb of a curve, in the xy plane:
    tip = C(t) - s * kappa_signed(t) * n(t), n the left normal, so the teeth point
    away from the centre of curvature. ``scale`` defaults to 15% of the curve's
    size over the largest curvature. Returns (points, tips), each (samples, 2)."""
    a, b = curve.domain
    t = np.linspace(a, b, samples)
    d = curve.derivatives(t, 2)
    p, d1, d2 = d[0][:, :2], d[1][:, :2], d[2][:, :2]
    speed = np.linalg.norm(d1, axis=1)
    ok = speed > 1e-12 * max(speed.max(), 1e-300)
    kappa = np.zeros(samples)
    kappa[ok] = (d1[ok, 0] * d2[ok, 1] - d1[ok, 1] * d2[ok, 0]) / speed[ok] ** 3
    normal = np.zeros_like(d1)
    normal[ok] = np.stack([-d1[ok, 1], d1[ok, 0]], axis=1) / speed[ok, None]
    if scale is None:
        size = np.ptp(p, axis=0).max()
        kmax = np.abs(kappa).max()
        scale = 0.15 * size / kmax if kmax > 0 else 0.0
    return p, p - scale * kappa[:, None] * normal


def _shared_comb_scale(curves: Sequence[Curve], samples: int = 200) -> float:
    """One comb scale for all curves of a picture (15% of the picture's size over
    the largest curvature), so that combs of joined curves are comparable."""
    pts, kmax = [], 0.0
    for c in curves:
        t = np.linspace(*c.domain, samples)
        pts.append(c(t)[:, :2])
        k = c.curvature(t)
        kmax = max(kmax, float(np.nanmax(k)) if np.isfinite(k).any() else 0.0)
    size = float(np.ptp(np.vstack(pts), axis=0).max())
    return 0.15 * size / kmax if kmax > 0 else 0.0


def plot_curves(path: Path, title: str, curves: Sequence[Curve], control_polygons: Sequence[np.ndarray] = (),
                comb: bool = True, points: Optional[np.ndarray] = None, samples: int = 400) -> Path:
    """Write one PNG with the curves (xy projection), dashed control polygons, a
    curvature comb per curve and optional data points."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=110)
    colors = ["tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange"]
    scale = _shared_comb_scale(curves) if comb else 0.0
    for i, c in enumerate(curves):
        col = colors[i % len(colors)]
        if comb:
            base, tips = curvature_comb(c, samples=120, scale=scale)
            for (x0, y0), (x1, y1) in zip(base, tips):
                ax.plot([x0, x1], [y0, y1], color="0.7", lw=0.6, zorder=1)
            ax.plot(tips[:, 0], tips[:, 1], color="0.55", lw=0.8, zorder=1)
        a, b = c.domain
        xy = c(np.linspace(a, b, samples))
        ax.plot(xy[:, 0], xy[:, 1], color=col, lw=2.0, zorder=3)
    for poly in control_polygons:
        poly = np.asarray(poly)
        ax.plot(poly[:, 0], poly[:, 1], "--o", color="0.25", lw=0.8, ms=4, zorder=2)
    if points is not None:
        ax.plot(points[:, 0], points[:, 1], "s", color="black", ms=5, zorder=4)
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.3)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
