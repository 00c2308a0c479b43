"""``cagd fit points.csv --tol 0.01 -o fit.step``: a B-spline curve within a tolerance of
measured points (:func:`cagd.fit_curve`; with ``--surface`` a surface through scattered
points, :func:`cagd.fit_surface`), written as STEP, IGES or a JSON model file
(by the suffix of ``-o``), with a report of the errors (Markdown, on stdout and with
``--report``) and a picture (``--png``: the points coloured by their distance, the fit
and its control polygon). Exit codes: 0 every point within tol, 1 tol not met (the fit
is still written, the report says by how much), 2 bad input."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, List, Union

import numpy as np

from .errors import CagdError

#: the output types by suffix of -o
STEP_SUFFIXES = (".step", ".stp")
IGES_SUFFIXES = (".igs", ".iges")
JSON_SUFFIXES = (".json",)


def add_parser(sub: Any) -> None:
    """The ``fit`` sub-command on the ``cagd`` parser's sub-parsers."""
    fit = sub.add_parser("fit", help="a B-spline curve within a tolerance of points (CSV) to STEP, IGES or JSON")
    fit.add_argument("points", type=Path, help="CSV of points in order along the curve, one x,y[,z] per line")
    fit.add_argument("--tol", type=float, required=True, help="the largest distance of a point from the curve")
    fit.add_argument("-o", "--output", type=Path, required=True,
                     help="the fit: .step/.stp, .igs/.iges or .json (a cagd model file)")
    fit.add_argument("--degree", type=_degree, default=3,
                     help="degree of the fit (3); with --surface also 'auto': each of the degrees of "
                          "cagd.fitting.fit_surface.AUTO_DEGREES tried, the fewest control points kept")
    fit.add_argument("--parameters", default="centripetal", help="initial parameters of the points "
                                                                 "(uniform, chord, centripetal)")
    fit.add_argument("--max-poles", type=int, help="at most this many control points")
    fit.add_argument("--periodic", action="store_true", help="a closed curve, C^(degree-1) at its seam")
    fit.add_argument("--surface", action="store_true", help="a B-spline surface through scattered x,y,z "
                                                             "points (a scanned sheet, a graph over its plane)")
    fit.add_argument("--smoothing", type=float, default=0.0, help="weight of the bending energy (0)")
    fit.add_argument("--report", type=Path, help="also write the report (Markdown) here")
    fit.add_argument("--png", type=Path, help="also draw the points, coloured by distance, and the fit")


def _degree(text: str) -> Union[int, str]:
    """--degree: an integer (checked by the fit) or 'auto' (surfaces only: checked by run_fit)."""
    if text.strip().lower() == AUTO:
        return AUTO
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer or '{AUTO}', got {text!r}") from None


#: the --degree value that lets fit_surface choose the degree
AUTO = "auto"


def _picture(path: Path, pts: np.ndarray, fit) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curve = fit.curve
    xyz = curve(np.linspace(0.0, 1.0, 2000))
    P = curve.control_points
    d = np.asarray(fit.distances)
    fig = plt.figure(figsize=(7.0, 5.0), dpi=110)
    three = pts.shape[1] == 3
    ax: Any = fig.add_subplot(projection="3d") if three else fig.add_subplot()
    if three:
        ax.computed_zorder = False                     # the fit over the points, as listed
    cols = [pts[:, k] for k in range(pts.shape[1])]
    dots = ax.scatter(*cols, c=d, cmap="viridis", s=4, vmin=0.0, vmax=max(float(d.max()), fit.tol), zorder=1)
    ax.plot(*[P[:, k] for k in range(pts.shape[1])], color="0.5", lw=0.6, ls="--", marker="o", ms=2,
            label=f"control polygon ({len(P)} points)", zorder=2)
    ax.plot(*[xyz[:, k] for k in range(pts.shape[1])], color="red", lw=1.2, label="fit", zorder=3)
    fig.colorbar(dots, ax=ax, label="distance")
    ax.set_title(f"fit_curve: tol {fit.tol:g}, max {fit.max_error:.3g}")
    ax.legend(loc="best", fontsize=8)
    fig.savefig(path)
    plt.close(fig)


class _Drawn:
    """What the picture needs: the fit, its tolerance and every point's distance."""

    def __init__(self, fit, tol: float, distances: np.ndarray):
        self.curve, self.max_error, self.tol, self.distances = fit.curve, fit.max_error, tol, distances


def run_fit(args: argparse.Namespace) -> int:
    """The command: checks every output path first, fits, writes all outputs or none."""
    from ._atomic import check_target, write_files
    from .deviation_cli import read_points
    from .fitting import fit_curve
    from .queries.closest import closest_point

    suffix = args.output.suffix.lower()
    if suffix not in STEP_SUFFIXES + IGES_SUFFIXES + JSON_SUFFIXES:
        raise CagdError(f"--output {args.output}: unknown type {suffix!r} (.step, .stp, .igs, .iges or .json)")
    check_target(args.output, "--output")
    for option, path in (("--report", args.report), ("--png", args.png)):
        if path is not None:
            check_target(path, option)
    if args.png is not None and args.png.suffix.lower() != ".png":
        raise CagdError(f"--png {args.png}: the picture is a .png file")
    if args.png is not None:
        from ._optional import require
        require("matplotlib", "--png")
    if args.surface and args.periodic:
        raise CagdError("--periodic: a periodic fit is a curve's; leave it out with --surface")
    if not args.surface and args.degree == AUTO:
        raise CagdError(f"--degree: '{AUTO}' chooses a surface's degree (with --surface); give the curve's degree")
    pts = read_points(args.points)
    fit: Any
    curve: Any                                          # what is written: the fitted curve or surface
    if args.surface:
        from .fitting import fit_surface
        fit = fit_surface(pts, args.tol, args.degree,
                          max_control_points=None if args.max_poles is None else (args.max_poles, args.max_poles))
        curve = fit.surface
        nu, nv = curve.control_points.shape[:2]
        what = f"- surface: degree {curve.degree_u} x {curve.degree_v}, {nu} x {nv} control points, on [0, 1]^2"
    else:
        fit = fit_curve(pts, args.tol, args.degree, args.parameters, smoothing=args.smoothing,
                        max_control_points=args.max_poles, periodic=args.periodic)
        curve = fit.curve
        what = (f"- curve: degree {curve.degree}, {len(curve.control_points)} control points, "
                f"{len(np.unique(curve.knots)) - 1} knot spans, parameters on [0, 1]"
                + (", periodic (closed)" if curve.periodic else ""))
    distances = np.asarray(closest_point(curve, pts).distances)
    lines: List[str] = [
        f"# Fit of {args.points.name}", "",
        f"- points: {len(pts)} ({pts.shape[1]}-D); tolerance {args.tol:g}",
        what,
        f"- largest distance {fit.max_error:.6g}, root mean square {fit.rms_error:.6g}; points over tol: "
        f"{int(np.count_nonzero(distances > args.tol))} (certified closest points)",
        f"- {'every point within tol' if fit.converged else 'TOL NOT MET'}: {fit.message}",
        f"- written: `{args.output}`", ""]
    outputs: list = []
    if suffix in JSON_SUFFIXES:
        from .model.writer import dumps, objects_to_dict
        outputs.append((args.output, dumps(objects_to_dict({"fit": curve}, name=args.points.stem,
                                                           description=fit.message)), "--output"))
    else:
        from .occ.files import iges_bytes, step_bytes
        data = step_bytes([("fit", curve)]) if suffix in STEP_SUFFIXES else iges_bytes([("fit", curve)])
        outputs.append((args.output, data, "--output"))
    if args.report is not None:
        outputs.append((args.report, "\n".join(lines), "--report"))
    if args.png is not None and args.surface:
        from .plotting import plot_surfaces
        surface = curve
        outputs.append((args.png, lambda temp: plot_surfaces(temp, f"fit_surface: tol {args.tol:g}, max "
                                                             f"{fit.max_error:.3g}", [surface]), "--png"))
    elif args.png is not None:
        drawn = _Drawn(fit, args.tol, distances)
        outputs.append((args.png, lambda temp: _picture(temp, pts, drawn), "--png"))
    write_files(outputs)
    print("\n".join(lines))
    return 0 if fit.converged else 1
