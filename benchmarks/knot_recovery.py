"""Benchmark: the exactness oracle of issue 17 for fit_curve's knot recovery
(cagd/fitting/free_knots.py). Random fair cubics and quartics (a random walk of control
points with a bounded turn per step; interior knots at least 0.4 / (q + 1) apart) with
5-12 control points, sampled at 300-1000 random parameters that are not given (centripetal
start), fitted at tol 1e-9: how many come back with their number of control points and
within 1e-10 both ways (certified closest points), and the time per fit.

``--uneven``: the interior knots uniformly random instead (two of them may be a
thousandth apart).

Run: python -m benchmarks.knot_recovery [--curves N] [--seed S] [--tol 1e-9] [--uneven]
"""
from __future__ import annotations

import argparse
import time
from typing import List, Optional, Tuple

import numpy as np

import cagd


def fair_poles(rng: np.random.Generator, n: int) -> np.ndarray:
    """n control points of a random walk that turns by a bounded random amount per step."""
    d, P = np.array([1.0, 0.0, 0.0]), [np.zeros(3)]
    for _ in range(n - 1):
        d = d + rng.normal(0.0, 0.5, 3)
        d /= np.linalg.norm(d)
        P.append(P[-1] + 3.0 * d * rng.uniform(0.7, 1.3))
    return np.array(P)


def sampled(curve: cagd.BSplineCurve, m: int, rng: np.random.Generator) -> np.ndarray:
    """m points at random parameters (the ends included), in order."""
    return curve(np.sort(np.r_[0.0, 1.0, rng.random(m - 2)]))


def random_curve(rng: np.random.Generator, degree: int, count: int, uneven: bool = False) -> cagd.BSplineCurve:
    """A fair random B-spline: ``count`` control points, interior knots at least
    0.4 / (q + 1) apart (q of them); ``uneven``: the q interior knots uniformly random in
    (0.02, 0.98), however close."""
    if uneven:
        inner = np.sort(rng.uniform(0.02, 0.98, count - degree - 1))
    else:
        gaps = rng.uniform(1.0, 2.5, count - degree)
        inner = np.cumsum(gaps)[:-1] / gaps.sum()
    return cagd.BSplineCurve(fair_poles(rng, count), degree,
                             np.r_[np.zeros(degree + 1), inner, np.ones(degree + 1)])


def both_ways(a: cagd.BSplineCurve, b: cagd.BSplineCurve, samples: int = 2000) -> float:
    """The largest distance of either curve's samples from the other (certified)."""
    s = np.linspace(0.0, 1.0, samples)
    return max(float(cagd.closest_point(a, b(s)).distances.max()),
               float(cagd.closest_point(b, a(s)).distances.max()))


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--curves", type=int, default=16)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tol", type=float, default=1e-9)
    ap.add_argument("--uneven", action="store_true", help="interior knots uniformly random, however close")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    print(f"{'degree':>6s} {'poles':>5s} {'points':>6s} {'fit poles':>9s} {'both ways':>10s} {'time s':>7s}")
    rows: List[Tuple[bool, float]] = []
    for _ in range(args.curves):
        p = int(rng.choice([3, 4]))
        n = int(rng.integers(5, 13))
        m = int(rng.integers(300, 1001))
        c = random_curve(rng, p, n, args.uneven)
        t0 = time.perf_counter()
        r = cagd.fit_curve(sampled(c, m, rng), args.tol, degree=p)
        dt = time.perf_counter() - t0
        k = len(r.curve.control_points)
        gap = both_ways(r.curve, c) if k == n else float("nan")
        rows.append((k == n and gap <= 1e-10, dt))
        print(f"{p:6d} {n:5d} {m:6d} {k:9d} {gap:10.2g} {dt:7.2f}")
    back = sum(ok for ok, _ in rows)
    print(f"{back} of {len(rows)} came back (same count, 1e-10 both ways); time per fit median "
          f"{np.median([dt for _, dt in rows]):.2f} s, max {max(dt for _, dt in rows):.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
