"""Benchmark: intersection curves of two 10 x 10 bicubic B-spline patches, engine
(``cagd.intersect``: subdivision seeds, marching, fitted B-splines) against OCCT's
GeomAPI_IntSS. Prints the time of each, the time ratio, and the largest distance of
the returned curves from both surfaces (dense samples projected with the engine's
certified ``closest_point``, the same measure for both), with the ratio.

Run: python -m benchmarks.surface_intersection [--size N] [--repeat R] [--tol T]
"""
from __future__ import annotations

import argparse
from typing import List

import numpy as np

import cagd
from cagd.queries import closest_point, intersect

from .common import best


def model_patches(n: int = 10, seed: int = 3):
    """Two crossing n x n bicubic height fields over [0, 1]^2: z = f(x, y) and
    x = g(y, z), f and g = 0.5 + 0.15 sin(...) + N(0, 0.05) on the control points."""
    rng = np.random.default_rng(seed)
    g = np.linspace(0.0, 1.0, n)
    P = np.zeros((n, n, 3))
    P[..., 0], P[..., 1] = np.meshgrid(g, g, indexing="ij")
    P[..., 2] = 0.5 + 0.15 * np.sin(3 * P[..., 0]) * np.cos(4 * P[..., 1]) + 0.05 * rng.standard_normal((n, n))
    Q = np.zeros((n, n, 3))
    Q[..., 1], Q[..., 2] = np.meshgrid(g, g, indexing="ij")
    Q[..., 0] = 0.5 + 0.15 * np.cos(5 * Q[..., 1]) * np.sin(2 * Q[..., 2]) + 0.05 * rng.standard_normal((n, n))
    return cagd.BSplineSurface(P, 3, 3), cagd.BSplineSurface(Q, 3, 3)


def max_distance(curve_points: List[np.ndarray], a, b) -> float:
    """Largest distance of the sample points from either surface."""
    if not curve_points:
        return float("nan")
    X = np.concatenate(curve_points)
    return float(np.maximum(closest_point(a, X).distances, closest_point(b, X).distances).max())


def _occ_curves(ga, gb, tol: float):
    from OCP.GeomAPI import GeomAPI_IntSS
    inter = GeomAPI_IntSS(ga, gb, tol)
    return [inter.Line(i) for i in range(1, inter.NbLines() + 1)] if inter.IsDone() else []


def _occ_samples(curves, count: int = 400) -> List[np.ndarray]:
    out = []
    for c in curves:
        pts = [c.Value(t) for t in np.linspace(c.FirstParameter(), c.LastParameter(), count)]
        out.append(np.array([[p.X(), p.Y(), p.Z()] for p in pts]))
    return out


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=10, help="control points per direction")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tol", type=float, default=1e-7)
    args = ap.parse_args(argv)

    a, b = model_patches(args.size)
    sec, res = best(lambda: intersect(a, b, tol=args.tol), args.repeat)
    mine = [br.curve(np.linspace(*br.curve.domain, 400)) for br in res.curves]
    dev = max_distance(mine, a, b)
    reported = max((br.max_distance for br in res.curves), default=float("nan"))
    print(f"two {args.size} x {args.size} bicubic patches, tol {args.tol:g}, best of {args.repeat}")
    print(f"{'implementation':34s} {'seconds':>9s} {'branches':>9s} {'max distance':>13s}")
    print(f"{'engine intersect':34s} {sec:9.4f} {len(res.curves):9d} {dev:13.2e}   (reported {reported:.2e})")
    ok = bool(res.converged and res.curves and dev <= args.tol * 1.01)
    try:
        from cagd.occ import to_occ
        ga, gb = to_occ(a), to_occ(b)
        osec, curves = best(lambda: _occ_curves(ga, gb, args.tol), args.repeat)
        odev = max_distance(_occ_samples(curves), a, b)
        print(f"{'OCCT GeomAPI_IntSS':34s} {osec:9.4f} {len(curves):9d} {odev:13.2e}")
        print(f"time engine / OCCT: {sec / osec:.2f}; max distance engine / OCCT: {dev / odev:.2e}")
    except ImportError:
        print("OCP not installed: OCCT peer skipped")
    print("engine curves within tol of both surfaces" if ok else "ENGINE CURVES NOT WITHIN TOL OR NOT CONVERGED")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
