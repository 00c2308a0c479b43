"""The ``cagd`` command: ``cagd demo`` (the main job on the built-in model),
``cagd export MODEL.json`` (a model file to STEP/IGES with the round-trip report),
``cagd deviation MODEL points.csv`` (a point cloud against the model),
``cagd fit points.csv --tol T -o fit.step`` (a curve within tol of the points) and
``cagd plot --analysis KIND MODEL -o out.png`` (a surface-quality picture).

Exit codes: 0 success; 1 a check failed (an oracle, the round trip, a solid);
2 bad input or an output that cannot be written (an invalid model file: the message
names the JSON path). Every failure is one line on stderr, no traceback (set
CAGD_DEBUG=1 to get the traceback of an unexpected error).
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import List, Optional


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="cagd", description="CAGD toolkit")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="the seeds' examples against oracles, then the built-in model to "
                                       "STEP/IGES with pictures and the round-trip report")
    demo.add_argument("-o", "--output", type=Path, default=Path("out/demo"), help="output folder (out/demo)")
    demo.add_argument("--no-plots", action="store_true", help="skip the PNG pictures")
    demo.add_argument("--no-model", action="store_true", help="only the seed examples (no OCCT needed)")
    export = sub.add_parser("export", help="a JSON model file (docs/model-format.md) to STEP and IGES")
    export.add_argument("model", type=Path, help="the model file (JSON, format cagd-model)")
    export.add_argument("-o", "--output", type=Path, required=True, help="the STEP file to write")
    export.add_argument("--iges", type=Path, help="also write this IGES file")
    export.add_argument("--report", type=Path, help="write the round-trip report (Markdown) here")
    export.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    dev = sub.add_parser("deviation", help="signed distances of a point cloud (CSV) from a model's surfaces")
    dev.add_argument("model", type=Path, help="the model: a JSON model file, or a STEP or IGES file")
    dev.add_argument("points", type=Path, help="CSV of points, one x,y[,z] per line (a header line is allowed)")
    dev.add_argument("-o", "--output", type=Path, required=True, help="the report to write (Markdown)")
    dev.add_argument("--png", type=Path, help="the colour map (default: next to the report, .png)")
    dev.add_argument("--no-png", action="store_true", help="no colour map (then matplotlib is not needed)")
    dev.add_argument("--csv", type=Path, help="per-point results: point, face, distance, lower bound, foot "
                                              "(always written here; default: next to the report, .points.csv, "
                                              "for up to 100,000 points)")
    dev.add_argument("--no-csv", action="store_true", help="no per-point results")
    dev.add_argument("--object", action="append", help="measure to this entry only (repeatable; default: "
                                                       "every exported surface, or every curve if none)")
    dev.add_argument("--workers", type=int, default=1, metavar="N",
                     help="processes measuring the points, 65,536 at a time (default 1; the results are the "
                          "same for any N)")
    dev.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="a progress bar on stderr (default: when stderr is a terminal)")
    from .fit_cli import add_parser
    add_parser(sub)
    from .analysis_cli import add_parser as add_plot
    add_plot(sub)
    from .mesh_cli import add_parser as add_mesh
    add_mesh(sub)
    return parser


DEBUG_VARIABLE = "CAGD_DEBUG"      # set to 1: unexpected errors raise (with their traceback)


def main(argv: Optional[List[str]] = None) -> int:
    args = _parser().parse_args(argv)
    from .errors import CagdError
    try:
        return _run(args)
    except CagdError as exc:
        problem = str(exc)
    except OSError as exc:
        problem = f"{exc.filename + ': ' if exc.filename else ''}{exc.strerror or exc}"
    except Exception as exc:        # the contract: one line and exit 2, never a traceback
        if os.environ.get(DEBUG_VARIABLE):
            raise
        problem = f"cannot be computed ({type(exc).__name__}: {exc}); set {DEBUG_VARIABLE}=1 for the traceback"
    print(f"cagd {args.command}: {_one_line(problem)}", file=sys.stderr)
    return 2


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _run(args) -> int:
    if args.command == "demo":
        from .errors import CagdError
        out = args.output
        if out.exists() and not out.is_dir():
            raise CagdError(f"--output: {str(out)!r} is a file; the demo writes into a folder")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise CagdError(f"--output: cannot make the folder {str(out)!r}: {exc.strerror or exc}") from None
        from .demo import run_demo
        results = run_demo(args.output, plots=not args.no_plots)
        ok = all(r.passed for r in results)
        if not args.no_model:
            from .demo_model import run_model_demo
            ok &= run_model_demo(args.output, plots=not args.no_plots).passed
        return 0 if ok else 1
    if args.command == "deviation":
        from .deviation_cli import run_deviation
        return run_deviation(args)
    if args.command == "fit":
        from .fit_cli import run_fit
        return run_fit(args)
    if args.command == "mesh":
        from .mesh_cli import run_mesh
        return run_mesh(args)
    if args.command == "plot":
        from .analysis_cli import run_plot
        return run_plot(args)
    return _export(args)


def _export(args) -> int:
    from ._atomic import check_target
    from .errors import CagdError
    from .model import load_model
    for option, path in (("--output", args.output), ("--iges", args.iges), ("--report", args.report)):
        if path is not None:
            check_target(path, option)
    from .occ.export import export_model
    try:
        model = load_model(args.model)
        result = export_model(model, args.output, args.iges, progress=not args.no_progress, report=args.report)
    except CagdError as exc:
        raise CagdError(f"{args.model}: {exc}") from None
    if not args.report:
        print(result.to_markdown())
    else:
        print(f"report: {args.report}")
    print("all checks passed" if result.passed else "SOME CHECKS FAILED", file=sys.stderr)
    return 0 if result.passed else 1


if __name__ == "__main__":
    raise SystemExit(main())
