"""``cagd plot --analysis KIND MODEL -o out.png``: a surface-quality picture of a model's
surfaces (:mod:`cagd.analysis.surface_maps`): a curvature map (gaussian, mean, max,
min) or the draft angle with a colour bar (symmetric about 0 unless ``--range``), zebra
stripes or isophote bands. MODEL is a JSON model, a STEP/IGES file, or ``demo`` (the
built-in model). Each surface is sampled on a samples x samples grid of its domain;
points where the normal is undefined are grey. matplotlib is imported only here."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, List, Tuple

import numpy as np

from .errors import CagdError

ANALYSES = ("gaussian", "mean", "max", "min", "zebra", "isophotes", "draft")
ELEVATION, AZIMUTH = 30.0, -60.0          # the picture's view (degrees), as cagd.plotting
MAX_PICTURE_SAMPLES = 400                 # grid points per direction and surface, at most


def add_parser(sub: Any) -> None:
    """The ``plot`` sub-command on the ``cagd`` parser's sub-parsers."""
    p = sub.add_parser("plot", help="a PNG of a surface analysis (curvature map, zebra, isophotes, draft angle)")
    p.add_argument("model", help="a JSON model file, a STEP or IGES file, or 'demo' (the built-in model)")
    p.add_argument("--analysis", choices=ANALYSES, required=True, help="what to show")
    p.add_argument("-o", "--output", type=Path, required=True, help="the picture to write (.png)")
    p.add_argument("--object", action="append", help="only this entry (repeatable; default: every surface)")
    p.add_argument("--samples", type=int, default=80, help="grid points per direction and surface (80)")
    p.add_argument("--light", type=float, nargs=3, help="light bars (zebra) or light direction (isophotes); "
                                                        "default z, resp. towards the viewer")
    p.add_argument("--pull", type=float, nargs=3, default=(0.0, 0.0, 1.0), help="pull direction (draft; z)")
    p.add_argument("--stripes", type=int, default=8, help="light bars of the zebra (8)")
    p.add_argument("--levels", type=int, default=10, help="isophote bands (10)")
    p.add_argument("--range", type=float, nargs=2, metavar=("LO", "HI"), help="colour range (default symmetric)")


def _unit(values: Any) -> np.ndarray:
    v = np.asarray(values, dtype=np.float64)
    n = float(np.linalg.norm(v))
    if not np.isfinite(n) or n == 0.0:
        raise CagdError(f"direction {list(values)}: must be a finite non-zero vector")
    return v / n


def _surfaces(model: str, names: Any) -> List[Tuple[str, Any]]:
    from .surfaces.base import Surface
    if model == "demo":
        from .model import default_model
        m = default_model()
        entries = [m[n] for n in names] if names else m.exported()
        items = [(label, obj) for e in entries for label, obj in e.labels()]
    else:
        from .deviation_cli import model_objects
        items = model_objects(Path(model), names)[1]
    chosen = [(n, o) for n, o in items if isinstance(o, Surface) and o.rectangular and o.dim == 3]
    if not chosen:
        raise CagdError(f"model: {model} has no 3-D rectangular surface to analyse")
    return chosen


def _values(kind: str, s: Any, u: np.ndarray, v: np.ndarray, args: argparse.Namespace,
            eye: np.ndarray) -> np.ndarray:
    from .analysis import surface_maps as sm
    if kind == "zebra":
        light = _unit(args.light) if args.light else np.array([0.0, 0.0, 1.0])
        z = sm.zebra(s, u, v, light, -eye, stripes=args.stripes)
        return np.where(z.defined, z.lit.astype(float), np.nan)
    if kind == "isophotes":
        iso = sm.isophotes(s, u, v, _unit(args.light) if args.light else eye, levels=args.levels)
        return np.where(iso.defined, iso.band.astype(float), np.nan)
    if kind == "draft":
        return sm.draft_angle(s, u, v, _unit(args.pull), degrees=True)
    return sm.curvature_map(s, u, v, kind)


def run_plot(args: argparse.Namespace) -> int:
    """The command: checks the output first, computes every map, writes the PNG atomically."""
    from . import _checks
    from ._atomic import check_target, write_file
    from ._optional import require
    out = check_target(args.output, "--output")
    require("matplotlib", "--output")
    n = _checks.integer(args.samples, "--samples", 2, MAX_PICTURE_SAMPLES)
    try:
        items = _surfaces(args.model, args.object)
    except KeyError as exc:
        raise CagdError(f"--object {exc.args[0]}: no such entry in {args.model}") from None
    el, az = np.radians(ELEVATION), np.radians(AZIMUTH)
    eye = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    maps = []
    for _, s in items:
        (u0, u1), (v0, v1) = s.domain
        u, v = np.linspace(u0, u1, n)[:, None], np.linspace(v0, v1, n)[None, :]
        maps.append((s(u, v), _values(args.analysis, s, u, v, args, eye)))
    finite = np.concatenate([m[np.isfinite(m)] for _, m in maps])
    if args.range:
        lo, hi = float(args.range[0]), float(args.range[1])
        if not lo < hi:
            raise CagdError(f"--range: LO must be below HI, got {lo} {hi}")
    elif args.analysis in ("zebra", "isophotes"):
        lo, hi = 0.0, float(max(finite.max(), 1.0)) if finite.size else 1.0
    else:
        top = float(np.max(np.abs(finite))) if finite.size else 0.0
        lo, hi = (-top, top) if top > 0 else (-1.0, 1.0)
    names = list(dict.fromkeys(name.split(".")[0].split("[")[0] for name, _ in items))   # ellipsoid.3 -> ellipsoid
    title = f"{args.analysis}: {', '.join(names)}"
    write_file(out, lambda path: _picture(path, title, maps, args.analysis, lo, hi), "--output")
    print(f"picture: {out}")
    return 0


def _picture(path: Path, title: str, maps: list, kind: str, lo: float, hi: float) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import cm, colors

    cmap = {"zebra": "gray", "isophotes": "tab20"}.get(kind, "coolwarm")
    norm = colors.Normalize(lo, hi)
    mapper = cm.ScalarMappable(norm=norm, cmap=cmap)
    fig = plt.figure(figsize=(6.4, 5.6), dpi=110)
    ax: Any = fig.add_subplot(projection="3d")
    ax.view_init(elev=ELEVATION, azim=AZIMUTH)
    for P, m in maps:
        # a cell's colour: its corner mean (maps), its first corner (stripes and bands)
        cell = m[:-1, :-1] if kind in ("zebra", "isophotes") else \
            0.25 * (m[1:, 1:] + m[:-1, :-1] + m[1:, :-1] + m[:-1, 1:])
        rgba = mapper.to_rgba(np.nan_to_num(cell))
        rgba[~np.isfinite(cell)] = (0.6, 0.6, 0.6, 1.0)          # normal undefined: grey
        ax.plot_surface(P[..., 0], P[..., 1], P[..., 2], facecolors=np.pad(rgba, ((0, 1), (0, 1), (0, 0)),
                        mode="edge"), shade=False, rstride=1, cstride=1, linewidth=0.0, antialiased=False)
    pts = np.vstack([P.reshape(-1, 3) for P, _ in maps])
    lo3, hi3 = pts.min(axis=0), pts.max(axis=0)
    ax.set_box_aspect(tuple(np.maximum(hi3 - lo3, 0.02 * float((hi3 - lo3).max()) + 1e-300)))
    if kind != "zebra":
        label = {"draft": "draft angle (degrees)", "isophotes": "isophote band"}.get(kind, f"{kind} curvature")
        fig.colorbar(mapper, ax=ax, label=label, shrink=0.7)
    ax.set_title(title, fontsize=10)
    fig.savefig(path, format="png")
    plt.close(fig)
