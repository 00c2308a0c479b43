"""Benchmark: intersections of neighbouring B-spline faces of the real files (issue 16:
faces sharing an edge, the case CAD users meet most). Every pair of B-spline faces
(GeomAbs_BSplineSurface) that share an edge in each file given, up to ``--per-file``
pairs, is intersected by the engine (``cagd.intersect`` on the untrimmed surfaces) and
by OCCT's GeomAPI_IntSS, both at ``--tol``. Prints per pair the times, branch counts,
whether the engine converged and its worst branch distance, then the totals: pairs
converged or reported, the slowest pair, and the time ratio. The issue's targets: every
pair converged or reported with a reason, no pair over 2 s, in all at most 2x OCCT.

Run: python -m benchmarks.neighbour_pairs [--cad DIR] [--files a.stp,b.igs] [--per-file N] [--tol T]
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import List

import cagd

FILES = ("step/trj3_s1-al-214.stp,step/boxed_sphere.step,iges/occ22470.igs,step/bug28366_fuselage.stp,"
         "step/wing_fuselage.step,step/trj12_gd1-id-214.stp,step/periodic_u_cst.step,step/bug33398.step")


def pairs_of(path: Path, per_file: int):
    """(face index a, face index b, TopoDS_Face a, TopoDS_Face b) for B-spline faces sharing an edge."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_BSplineSurface
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.IGESControl import IGESControl_Reader
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from OCP.TopoDS import TopoDS
    from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape, TopTools_IndexedMapOfShape
    reader = IGESControl_Reader() if path.suffix.lower() in (".igs", ".iges") else STEPControl_Reader()
    if reader.ReadFile(str(path)) != IFSelect_RetDone:
        return []
    reader.TransferRoots()
    shape = reader.OneShape()
    faces = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(shape, TopAbs_FACE, faces)
    ancestors = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    out, seen = [], set()
    for i in range(1, ancestors.Extent() + 1):
        around = [TopoDS.Face_s(f) for f in ancestors.FindFromIndex(i)]
        for a in range(len(around)):
            for b in range(a + 1, len(around)):
                fa, fb = around[a], around[b]
                ia, ib = faces.FindIndex(fa), faces.FindIndex(fb)
                if ia == ib or (min(ia, ib), max(ia, ib)) in seen:
                    continue
                if all(BRepAdaptor_Surface(f).GetType() == GeomAbs_BSplineSurface for f in (fa, fb)):
                    seen.add((min(ia, ib), max(ia, ib)))
                    out.append((ia, ib, fa, fb))
                    if len(out) >= per_file:
                        return out
    return out


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cad", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data" / "cad")
    ap.add_argument("--files", default=FILES)
    ap.add_argument("--per-file", type=int, default=8)
    ap.add_argument("--tol", type=float, default=1e-9)
    args = ap.parse_args(argv)
    if not args.cad.is_dir():
        print(f"{args.cad}: not there (the real files of ../shared/data/cad)")
        return 0
    from OCP.BRep import BRep_Tool
    from OCP.GeomAPI import GeomAPI_IntSS
    from cagd.occ import from_occ
    rows = []
    print(f"{'file':24s} {'faces':>10s} {'engine s':>9s} {'curves':>6s} {'conv':>5s} {'worst':>9s} {'OCCT s':>8s} "
          f"{'lines':>5s}")
    for name in args.files.split(","):
        path = args.cad / name
        if not path.is_file():
            continue
        for ia, ib, fa, fb in pairs_of(path, args.per_file):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                A, B = (getattr(s, "untrimmed", s) for s in (from_occ(fa), from_occ(fb)))
            t0 = time.perf_counter()
            try:
                res = cagd.intersect(A, B, tol=args.tol)
                conv, n, why = res.converged, len(res.curves), res.message
                worst = max((max(c.max_distance, c.params_max_distance) for c in res.curves), default=0.0)
            except cagd.CagdError as exc:
                conv, n, worst, why = False, -1, float("nan"), f"raised: {exc}"
            sec = time.perf_counter() - t0
            t0 = time.perf_counter()
            inter = GeomAPI_IntSS(BRep_Tool.Surface_s(fa), BRep_Tool.Surface_s(fb), args.tol)
            osec = time.perf_counter() - t0
            lines = inter.NbLines() if inter.IsDone() else -1
            rows.append((sec, osec, conv, bool(why)))
            print(f"{path.name[:24]:24s} {f'{ia}x{ib}':>10s} {sec:9.2f} {n:6d} {str(conv):>5s} {worst:9.2e} "
                  f"{osec:8.3f} {lines:5d}")
            if why and not conv:
                print(f"    {why[:140]}")
    if not rows:
        print("no pairs")
        return 0
    total, total_occ = sum(r[0] for r in rows), sum(r[1] for r in rows)
    reported = sum(1 for r in rows if r[2] or r[3])
    print(f"{len(rows)} pairs: {sum(r[2] for r in rows)} converged, {reported} converged or reported with a reason; "
          f"slowest {max(r[0] for r in rows):.2f} s, {sum(r[0] > 2.0 for r in rows)} over 2 s")
    print(f"total: engine {total:.1f} s, OCCT {total_occ:.2f} s, ratio {total / max(total_occ, 1e-9):.1f}x "
          "(target <= 2x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
