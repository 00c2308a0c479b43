"""PNG pictures of curves (the curve, its control polygon and a curvature comb) and
of surfaces (shaded 3-D views with optional control nets).

matplotlib is imported only inside these functions (the ``plot`` extra).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from .analysis.comb import COMB_SIZE, curvature_comb
from .curves.base import Curve
from .errors import CagdError
from .surfaces.base import Surface


def _combs(curves: Sequence[Curve], samples: int = 120) -> list:
    """The curvature combs (:func:`cagd.analysis.curvature_comb`) of all curves of a
    picture with one scale (COMB_SIZE of the picture's size over the largest
    curvature), so that combs of joined curves are comparable."""
    combs = [curvature_comb(c, samples=samples, scale=1.0) for c in curves]
    if not combs:
        return combs
    kmax = max(float(c.curvature.max()) for c in combs)
    size = float(np.ptp(np.vstack([c.base for c in combs]), axis=0).max())
    return [c.scaled(COMB_SIZE * size / kmax if kmax > 0 else 0.0) for c in combs]


def plot_curves(path: Path, title: str, curves: Sequence[Curve], control_polygons: Sequence[np.ndarray] = (),
                comb: bool = True, points: Optional[np.ndarray] = None, samples: int = 400) -> Path:
    """Write one PNG with the curves (xy projection), dashed control polygons, a
    curvature comb per curve and optional data points."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=110)
    colors = ["tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange"]
    combs = _combs(curves) if comb else [None] * len(curves)
    for i, (c, teeth) in enumerate(zip(curves, combs)):
        col = colors[i % len(colors)]
        if teeth is not None:
            base, tips = teeth.base[:, :2], teeth.tips[:, :2]
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


_SURFACE_COLORS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:cyan", "tab:olive",
                   "tab:pink"]


def _triangle_samples(surface: Surface, samples: int):
    """Points of a Bezier triangle on the triangular grid u = i/n, v = j/n, i + j <= n
    (n = samples - 1) and the index triangles of that grid: ((N, 3), (M, 3))."""
    n = max(int(samples) - 1, 1)
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    inside = i + j <= n
    index = np.full((n + 1, n + 1), -1)
    index[inside] = np.arange(int(inside.sum()))
    u, v = i[inside] / n, j[inside] / n
    pts = surface(u, np.minimum(v, 1.0 - u))
    a, b = i[:-1, :-1], j[:-1, :-1]
    low = (a + b + 1 <= n)                                     # (a,b), (a+1,b), (a,b+1)
    high = (a + b + 2 <= n)                                    # (a+1,b), (a+1,b+1), (a,b+1)
    tris = [np.stack([index[a, b][low], index[a + 1, b][low], index[a, b + 1][low]], axis=1),
            np.stack([index[a + 1, b][high], index[a + 1, b + 1][high], index[a, b + 1][high]], axis=1)]
    return pts, np.concatenate(tris)


def _net_lines(net: np.ndarray):
    """Polylines of a control net: the rows and columns of an (nu, nv, 3) grid, or the
    three families of lines of a triangular net (N, 3) in BezierTriangle order
    (i descending, then j descending).

    Raises:
        CagdError: a flat net whose point count is not triangular.
    """
    if net.ndim == 3:
        return list(net) + list(net.transpose(1, 0, 2))
    n = int(round((np.sqrt(8 * len(net) + 1) - 3) / 2))
    if (n + 1) * (n + 2) // 2 != len(net):
        raise CagdError(f"control_nets: a net of {len(net)} points is neither a grid nor a triangular net")
    pos = {}
    for r, (i, j) in enumerate((i, j) for i in range(n, -1, -1) for j in range(n - i, -1, -1)):
        pos[(i, j)] = r
    lines = []
    for c in range(n + 1):                     # i = c, j = c, k = c constant
        lines.append(net[[pos[(c, j)] for j in range(n - c + 1)]])
        lines.append(net[[pos[(i, c)] for i in range(n - c + 1)]])
        lines.append(net[[pos[(i, n - c - i)] for i in range(n - c + 1)]])
    return lines


def _shaded(color, normals: np.ndarray, light: np.ndarray, alpha: float) -> np.ndarray:
    """Two-sided Lambert shading: RGBA = color * (0.3 + 0.7 |n . light|) for unit face
    normals n (a degenerate face gets 0.65), so both sides of a patch are lit whatever
    the orientation of its parametrisation."""
    from matplotlib.colors import to_rgb
    length = np.linalg.norm(normals, axis=-1)
    cosine = np.full(length.shape, 0.5)
    ok = length > 0
    cosine[ok] = np.abs(normals[ok] @ light) / length[ok]
    rgb = np.asarray(to_rgb(color)) * (0.3 + 0.7 * cosine)[..., None]
    return np.concatenate([rgb, np.full(rgb.shape[:-1] + (1,), alpha)], axis=-1)


def plot_surfaces(path: Path, title: str, surfaces: Sequence[Surface], control_nets: Sequence[np.ndarray] = (),
                  samples: int = 40) -> Path:
    """Write one PNG with a shaded 3-D view of the surfaces (each on a samples x samples
    grid of its domain; a Bezier triangle on the triangular grid u + v <= 1) and the
    optional control nets as lines with markers ((nu, nv, 3) grids or (N, 3) triangular
    nets), with equal scales on the three axes. View: elevation 30, azimuth -60; faces
    lit two-sided from the viewer's upper left; surfaces drawn back to front (by their
    centroids), the control nets on top.

    Raises:
        CagdError: nothing to draw, a surface that is not a 3-D cagd Surface, a control
            net that is not an (nu, nv, 3) grid or a triangular (N, 3) net.
    """
    for k, s in enumerate(surfaces):
        if not isinstance(s, Surface) or s.dim != 3:
            raise CagdError(f"surfaces: item {k} is not a 3-D cagd Surface ({s!r})")
    nets = [np.asarray(net, dtype=float) for net in control_nets]
    for k, net in enumerate(nets):
        if net.ndim not in (2, 3) or net.shape[-1] != 3:
            raise CagdError(f"control_nets: item {k} has shape {net.shape}, expected (nu, nv, 3) or (N, 3)")
    if not len(surfaces) and not nets:
        raise CagdError("surfaces, control_nets: nothing to draw")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .triangles.bezier_triangle import BezierTriangle

    sampled = []                                   # (points (.., 3), triangles or None)
    for s in surfaces:
        if isinstance(s, BezierTriangle):
            sampled.append(_triangle_samples(s, samples))
        else:
            (u0, u1), (v0, v1) = s.domain
            sampled.append((s.grid(np.linspace(u0, u1, samples), np.linspace(v0, v1, samples)), None))
    pts = np.vstack([p.reshape(-1, 3) for p, _ in sampled] + [n.reshape(-1, 3) for n in nets])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 0.02 * (hi - lo).max() + 1e-300)
    mid = 0.5 * (lo + hi)

    elev, azim = np.radians(30.0), np.radians(-60.0)
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    depth = [float(((p.reshape(-1, 3).mean(axis=0) - mid) / span) @ eye) for p, _ in sampled]
    rank = np.argsort(np.argsort(depth))           # farthest first: lowest zorder
    light = np.array([-0.45, -0.75, 0.85])
    light /= np.linalg.norm(light)

    fig = plt.figure(figsize=(6.4, 5.6), dpi=110)
    ax = fig.add_subplot(projection="3d", computed_zorder=False)
    ax.view_init(elev=30.0, azim=-60.0)
    for k, (P, tris) in enumerate(sampled):
        col = _SURFACE_COLORS[k % len(_SURFACE_COLORS)]
        z = 1.0 + rank[k]
        if tris is not None:
            corner = P[tris]
            normals = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])
            faces = ax.plot_trisurf(P[:, 0], P[:, 1], P[:, 2], triangles=tris, shade=False, linewidth=0.0,
                                    antialiased=False, zorder=z)
            faces.set_facecolor(_shaded(col, normals, light, 1.0))
        else:
            normals = np.cross(P[1:, 1:] - P[:-1, :-1], P[:-1, 1:] - P[1:, :-1])
            colors = np.pad(_shaded(col, normals, light, 1.0), ((0, 1), (0, 1), (0, 0)), mode="edge")
            ax.plot_surface(P[..., 0], P[..., 1], P[..., 2], facecolors=colors, shade=False, rstride=1, cstride=1,
                            linewidth=0.0, antialiased=False, zorder=z)
    for net in nets:
        for line in _net_lines(net):
            ax.plot(line[:, 0], line[:, 1], line[:, 2], "-o", color="0.15", lw=0.8, ms=3.0,
                    zorder=len(sampled) + 2)
    ax.set_xlim(mid[0] - span[0] / 2, mid[0] + span[0] / 2)
    ax.set_ylim(mid[1] - span[1] / 2, mid[1] + span[1] / 2)
    ax.set_zlim(mid[2] - span[2] / 2, mid[2] + span[2] / 2)
    ax.set_box_aspect(tuple(span))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(title, fontsize=10)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path
