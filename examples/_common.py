"""Shared by the CadQuery / build123d examples: the output folder, a table of checks
that ends in "checks passed" (exit code 1 otherwise), and the STEP round trip of
the engine objects through cagd.occ.verify."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import List, Sequence, Tuple

from OCP.TopAbs import TopAbs_SOLID

import cagd
from cagd.occ import check_valid, read_shapes, subshapes, verify


def output_folder(default: str) -> Path:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else default)
    out.mkdir(parents=True, exist_ok=True)
    return out


class Checks:
    """Rows of (what, measured, limit); ``finish`` prints them and exits 1 on a failure."""

    def __init__(self, title: str):
        self.title, self.rows = title, []

    def at_most(self, what: str, measured: float, limit: float) -> None:
        self.rows.append((what, float(measured), float(limit), float(measured) <= limit))

    def true(self, what: str, ok: bool) -> None:
        self.rows.append((what, float(bool(ok)), 1.0, bool(ok)))

    def verified(self, named: Sequence[Tuple[str, object]], file_tol: float = 1e-12) -> None:
        """cagd.occ.verify (OCCT, STEP, IGES) of every engine object."""
        worst, failed = {}, []
        for name, obj in named:
            report = verify(obj, name, file_tol=file_tol)
            for stage in report.stages:
                worst[stage.stage] = max(worst.get(stage.stage, 0.0), stage.max_deviation)
            if not report.passed:
                failed.append(name)
                print(report)
        self.true(f"cagd.occ.verify of {len(named)} objects: all stages within tolerance"
                  + (f" (failed: {', '.join(failed)})" if failed else ""), not failed)
        for stage, dev in worst.items():
            self.at_most(f"round trip, worst over {len(named)} objects: {stage}", dev,
                         1e-12 if stage in ("to_nurbs", "occt", "from_occ") else file_tol)

    def step_valid(self, path: Path, solids: int) -> None:
        """The STEP file read back by OCCT holds ``solids`` valid solids."""
        found = [so for _, s in read_shapes(path) for so in subshapes(s, TopAbs_SOLID)]
        self.true(f"{path.name} read back: {len(found)} solid(s), expected {solids}", len(found) == solids)
        self.true(f"{path.name} read back: every solid valid", all(check_valid(s) for s in found))

    def finish(self) -> None:
        w = max(len(r[0]) for r in self.rows)
        print(self.title)
        for what, measured, limit, ok in self.rows:
            print(f"  {what:{w}s}  {measured:12.4g}  <= {limit:<9.3g} {'ok' if ok else 'FAILED'}")
        bad = [r for r in self.rows if not r[3]]
        if bad:
            print(f"{len(bad)} check(s) FAILED")
            sys.exit(1)
        print("checks passed")


__all__: List[str] = ["output_folder", "Checks", "cagd"]
