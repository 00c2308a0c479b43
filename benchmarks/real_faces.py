"""Benchmark: closest points on the B-spline faces of real CAD files (issue 16: "at least
20x OCCT in total over every B-spline face of the real files at 1% and 10%"), the engine
beside OCCT's reused Extrema_ExtPS in one run.

For every untrimmed B-spline surface of the files (the first ``--faces`` per file),
``--points`` points at Gaussian distance ``spread`` x the face's size from random points
of it (``--spread``, shares of the face's size). Each face is a new object (its set-up
counted, as a user's first query on it); the points go in one call. OCCT answers a
subsample (``--subsample`` points per face; per-point Perform on an Extrema_ExtPS
initialised once per face). Prints per spread: the faces, the engine's points per CPU
second and per wall second, OCCT's per wall second, their ratio, the points not
converged, and whether every engine distance is at most OCCT's + 1e-9 of the face size;
with ``--slowest K`` the K slowest faces.

Run: python -m benchmarks.real_faces [--cad DIR] [--files F ...] [--faces N] [--points N]
[--spread S ...] [--subsample M] [--slowest K]
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import List

import numpy as np

import cagd

from .projection import _occ_extrema

FILES = ("step/bug33398.step", "step/trj3_s1-al-214.stp", "step/bug28366_fuselage.stp", "step/wing_fuselage.step",
         "iges/occ22470.igs", "step/11752.stp")


def faces_of(path: Path, most: int) -> List[cagd.BSplineSurface]:
    """The first ``most`` B-spline surfaces of a STEP or IGES file (trimmed faces untrimmed)."""
    from cagd.occ import read_cad
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        items = read_cad(path)
    faces = [getattr(it.object, "untrimmed", it.object) for it in items]
    return [s for s in faces if isinstance(s, cagd.BSplineSurface)][:most]


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cad", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data" / "cad")
    ap.add_argument("--files", nargs="+", default=list(FILES))
    ap.add_argument("--faces", type=int, default=12, help="B-spline faces per file")
    ap.add_argument("--points", type=int, default=500, help="points per face")
    ap.add_argument("--spread", type=float, nargs="+", default=[0.01, 0.1])
    ap.add_argument("--subsample", type=int, default=50, help="points per face for OCCT")
    ap.add_argument("--slowest", type=int, default=0)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    faces = [(f, i, s) for f in args.files if (args.cad / f).exists()
             for i, s in enumerate(faces_of(args.cad / f, args.faces))]
    if not faces:
        print(f"no corpus files under {args.cad}: nothing to measure")
        return 0
    try:
        from cagd.occ import to_occ
    except ImportError:
        to_occ = None
    ok = True
    print(f"{'spread':>7s} {'faces':>5s} {'rational':>8s} {'engine pts/CPU s':>16s} {'engine pts/s':>12s} "
          f"{'OCCT pts/s':>10s} {'engine/OCCT':>11s} {'not conv.':>9s} {'<= OCCT':>7s}")
    for spread in args.spread:
        cpu = wall = occ_wall = 0.0
        n = n_occ = unconverged = 0
        slow = []
        good = True
        for f, i, s in faces:
            (a, b), (c, d) = s.domain
            uv = np.c_[rng.uniform(a, b, args.points), rng.uniform(c, d, args.points)]
            G = s(uv[:, 0], uv[:, 1])
            size = float(np.ptp(G, axis=0).max())
            X = G + rng.normal(size=G.shape) * spread * size
            t0, c0 = time.perf_counter(), time.process_time()
            r = cagd.closest_point(s, X)
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            wall, cpu, n = wall + dt, cpu + dc, n + len(X)
            unconverged += int(np.count_nonzero(~r.point_converged))
            slow.append((dc, f, i))
            if to_occ is not None:
                sub = X[:args.subsample]
                geom = to_occ(s)
                t0 = time.perf_counter()
                occ = _occ_extrema(geom, sub)
                occ_wall += time.perf_counter() - t0
                n_occ += len(sub)
                good &= bool(np.all(r.distances[:len(sub)] <= occ + 1e-9 * size))
        ok &= good
        rational = sum(s.weights is not None for _, _, s in faces)
        occ_rate = n_occ / occ_wall if occ_wall else float("nan")
        print(f"{spread:7.1%} {len(faces):5d} {rational:8d} {n / cpu:16,.0f} {n / wall:12,.0f} {occ_rate:10,.0f} "
              f"{n / wall / occ_rate:10.1f}x {unconverged:9d} {'yes' if good else 'NO':>7s}")
        for dc, f, i in sorted(slow, reverse=True)[:args.slowest]:
            print(f"        slowest: {f} face {i}: {args.points / dc:,.0f} points per CPU s")
    print("target (issue 16): engine / OCCT >= 20 at 1% and 10%")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
