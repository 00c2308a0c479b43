"""The ``cagd`` command."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import List, Optional


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="cagd", description="CAGD toolkit")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="build the seeds' example curves, check them against oracles, plot them")
    demo.add_argument("-o", "--output", type=Path, default=Path("out/demo"), help="folder for the PNG plots")
    demo.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    args = parser.parse_args(argv)
    if args.command == "demo":
        from .demo import run_demo
        results = run_demo(args.output, plots=not args.no_plots)
        return 0 if all(r.passed for r in results) else 1
    return 2  # pragma: no cover - argparse rejects unknown commands


if __name__ == "__main__":
    raise SystemExit(main())
