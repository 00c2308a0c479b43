"""Benchmark: closest_point on the big and hard cases of issue 14.

Cases (sizes adjustable, the issue's in brackets):
  net     random bicubic B-spline net in [-1, 1]^3, n x n control points [300], points
          uniform in [-1, 1]^3 [1e3];
  curve   random cubic B-spline curve in [-1, 1]^3 with n poles [1e5], points uniform in
          [-1, 1]^3 [1e4];
  sphere  the engine's exact NURBS sphere of radius 1, points uniform in [-2, 2]^3 [1e6].
Prints wall and CPU time of preparation plus query (a fresh object: nothing cached), the peak
resident memory of the process, how tight the certificates are (median and maximum of
distances - lower_bounds) and, for the sphere, the largest error against the analytic
distance | |X| - 1 |.

Run: python -m benchmarks.closest_big [--case net|curve|sphere] [--n N] [--points M] [--seed S]
"""
from __future__ import annotations

import argparse
import resource
import time

import numpy as np

import cagd
from cagd.queries.closest import closest_point

SIZES = {"net": (300, 1000), "curve": (100_000, 10_000), "sphere": (0, 1_000_000)}


def make(case: str, n: int, points: int, seed: int = 0):
    """The object and the query points of one case."""
    rng = np.random.default_rng(seed)
    if case == "net":
        return cagd.BSplineSurface(rng.uniform(-1, 1, (n, n, 3)), 3, 3), rng.uniform(-1, 1, (points, 3))
    if case == "curve":
        return cagd.BSplineCurve(rng.uniform(-1, 1, (n, 3)), 3), rng.uniform(-1, 1, (points, 3))
    if case == "sphere":
        return cagd.sphere(1.0), rng.uniform(-2, 2, (points, 3))
    raise ValueError(case)


def run(case: str, n: int, points: int, seed: int = 0) -> dict:
    obj, X = make(case, n, points, seed)
    w0, c0 = time.perf_counter(), time.process_time()
    r = closest_point(obj, X)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    gap = r.distances - r.lower_bounds
    out = {"case": case, "n": n, "points": points, "wall_s": wall, "cpu_s": cpu,
           "peak_rss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2 ** 20,
           "gap_median": float(np.median(gap)), "gap_max": float(gap.max()), "converged": bool(r.converged),
           "bounds_hold": bool(np.all(r.lower_bounds <= r.distances))}
    if case == "sphere":
        out["max_error"] = float(np.abs(r.distances - np.abs(np.linalg.norm(X, axis=1) - 1.0)).max())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=sorted(SIZES), default="sphere")
    ap.add_argument("--n", type=int, default=None, help="control points per direction (net) or poles (curve)")
    ap.add_argument("--points", type=int, default=None)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    n, points = SIZES[a.case]
    res = run(a.case, a.n if a.n is not None else n, a.points if a.points is not None else points, a.seed)
    print("  ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in res.items()))


if __name__ == "__main__":
    main()
