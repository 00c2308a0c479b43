"""Benchmark: intersections of neighbouring faces from real files (issue 16), the pairs
that raised, ran for minutes or ended far off: boxed_sphere.step Document[190] x [191]
(two hemispheres sharing a circle, parameters in the thousands), trj3_s1-al-214.stp
space_ship[82] x [85], occ22470.igs SOLID[2] x [3] (a fillet nearly tangent to its
neighbour). For each: the engine's time on the untrimmed surfaces, its branches, whether
it converged and the distance its worst branch reached, beside OCCT's GeomAPI_IntSS
(time and line count) on the same surfaces. Issue 16's targets: no pair over 2 s, every
pair converged or reported with a reason; in all, at most 2x OCCT's time.

Run: python -m benchmarks.real_pairs [--cad DIR] [--tol T]
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import List

import cagd

PAIRS = [("step/boxed_sphere.step", "Document[190]", "Document[191]"),
         ("step/trj3_s1-al-214.stp", "space_ship[82]", "space_ship[85]"),
         ("iges/occ22470.igs", "SOLID[2]", "SOLID[3]")]


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cad", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data" / "cad")
    ap.add_argument("--tol", type=float, default=1e-9)
    args = ap.parse_args(argv)
    if not args.cad.is_dir():
        print(f"{args.cad}: not there (the real files of ../shared/data/cad)")
        return 0
    from OCP.GeomAPI import GeomAPI_IntSS
    from cagd.occ import read_cad, to_occ
    print(f"{'pair':46s} {'engine s':>9s} {'branches':>9s} {'converged':>9s} {'worst':>9s} {'OCCT s':>8s} "
          f"{'lines':>6s}")
    total = total_occ = 0.0
    for name, a, b in PAIRS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            by = {it.name: it.object for it in read_cad(args.cad / name)}
        A, B = (getattr(by[k], "untrimmed", by[k]) for k in (a, b))
        t0 = time.perf_counter()
        res = cagd.intersect(A, B, tol=args.tol)
        sec = time.perf_counter() - t0
        worst = max((max(c.max_distance, c.params_max_distance) for c in res.curves), default=0.0)
        ga, gb = to_occ(A), to_occ(B)
        t0 = time.perf_counter()
        inter = GeomAPI_IntSS(ga, gb, args.tol)
        osec = time.perf_counter() - t0
        lines = inter.NbLines() if inter.IsDone() else -1
        total, total_occ = total + sec, total_occ + osec
        print(f"{Path(name).name + ' ' + a + ' x ' + b:46s} {sec:9.2f} {len(res.curves):9d} {str(res.converged):>9s} "
              f"{worst:9.2e} {osec:8.3f} {lines:6d}")
        if res.message:
            print(f"    {res.message[:150]}")
    ratio = total / max(total_occ, 1e-9)
    print(f"total: engine {total:.2f} s, OCCT {total_occ:.3f} s, ratio {ratio:.1f}x (target <= 2x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
