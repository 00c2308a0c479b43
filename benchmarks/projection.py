"""Benchmark: projection of 10^5 points onto 20 x 20 bicubic B-spline surfaces.

Three surfaces: control points over the Greville abscissae (x = u, y = v), evenly
spaced control points on clamped knots (the parametrisation bends near the edges), and
a rational one (smooth weights in [0.7, 1.3]). The points are scattered within +-1% of the
model size around each surface (``--spread``: other distances, issue 16 asks 0.1%, 1%, 10%
and 50%). Peers
measured in the same run, per point on a subsample: OCCT's reused Extrema_ExtPS (its
faster path) and GeomAPI_ProjectPointOnSurf. Prints throughput and ratios against the
engine per surface (targets: >= 100,000 points/s, >= 30x the faster OCCT path) and checks that
every engine distance is <= OCCT's + 1e-9 relative to the model size; cases where the
engine is smaller (OCCT missed the global minimum) are counted.

Run: python -m benchmarks.projection [--points N] [--repeat R] [--subsample M] [--spread S ...]
"""
from __future__ import annotations

import argparse
import time
from typing import List, Tuple

import numpy as np

import cagd
from cagd.queries.closest import Projector, closest_point

from .common import best, report


def model_surface(seed: int = 7) -> cagd.BSplineSurface:
    """20 x 20 bicubic height field on [0, 1]^2: control points over the Greville
    abscissae (so x = u, y = v), z = 0.05 sin(2 pi x) cos(3 pi y) + N(0, 0.002)."""
    rng = np.random.default_rng(seed)
    n, p = 20, 3
    knots = np.r_[[0.0] * p, np.linspace(0.0, 1.0, n - p + 1), [1.0] * p]
    g = np.array([knots[i + 1:i + p + 1].mean() for i in range(n)])
    P = np.zeros((n, n, 3))
    P[..., 0], P[..., 1] = np.meshgrid(g, g, indexing="ij")
    P[..., 2] = 0.05 * np.sin(2 * np.pi * P[..., 0]) * np.cos(3 * np.pi * P[..., 1]) \
        + 0.002 * rng.standard_normal((n, n))
    return cagd.BSplineSurface(P, p, p, knots, knots)


def _knots(n: int = 20, p: int = 3) -> np.ndarray:
    return np.r_[[0.0] * p, np.linspace(0.0, 1.0, n - p + 1), [1.0] * p]


def bent_surface(seed: int = 7) -> cagd.BSplineSurface:
    """As :func:`model_surface` but with evenly spaced control points x = i/19, y = j/19
    on the clamped uniform knots: x(u) is not u, the spans near the edges are squeezed."""
    P = np.array(model_surface(seed).control_points)
    g = np.linspace(0.0, 1.0, P.shape[0])
    P[..., 0], P[..., 1] = np.meshgrid(g, g, indexing="ij")
    return cagd.BSplineSurface(P, 3, 3, _knots(), _knots())


def rational_surface(seed: int = 7) -> cagd.BSplineSurface:
    """:func:`model_surface` with smoothly varying weights
    w_ij = 1 + 0.3 sin(2 pi x_i) sin(2 pi y_j) in [0.7, 1.3] (a rational bicubic)."""
    P = np.array(model_surface(seed).control_points)
    W = 1.0 + 0.3 * np.sin(2 * np.pi * P[..., 0]) * np.sin(2 * np.pi * P[..., 1])
    return cagd.BSplineSurface(P, 3, 3, _knots(), _knots(), weights=W)


SURFACES = (("Greville control points (x = u, y = v)", model_surface),
            ("evenly spaced control points, clamped knots", bent_surface),
            ("rational (weights 0.7..1.3)", rational_surface))


def scattered_points(surface, count: int, spread: float = 0.01, seed: int = 1) -> np.ndarray:
    """Points S(u, v) + uniform noise within +-spread of the model size per coordinate."""
    rng = np.random.default_rng(seed)
    u, v = rng.uniform(0, 1, count), rng.uniform(0, 1, count)
    return surface(u, v) + rng.uniform(-spread, spread, (count, 3)) * surface.size


def _occ_extrema(geom, X: np.ndarray) -> np.ndarray:
    """Reused Extrema_ExtPS: the smallest extremum distance per point (inf if none)."""
    from OCP.Extrema import Extrema_ExtPS
    from OCP.GeomAdaptor import GeomAdaptor_Surface
    from OCP.gp import gp_Pnt

    u0, u1, v0, v1 = geom.Bounds()
    adaptor = GeomAdaptor_Surface(geom)        # kept alive: Extrema_ExtPS holds a reference
    ext = Extrema_ExtPS()
    ext.Initialize(adaptor, u0, u1, v0, v1, 1e-9, 1e-9)
    out = np.full(len(X), np.inf)
    for i, x in enumerate(X):
        ext.Perform(gp_Pnt(*map(float, x)))
        if ext.IsDone() and ext.NbExt() > 0:
            out[i] = np.sqrt(min(ext.SquareDistance(j) for j in range(1, ext.NbExt() + 1)))
    return out


def _occ_project(geom, X: np.ndarray) -> np.ndarray:
    """GeomAPI_ProjectPointOnSurf per point: LowerDistance (inf if no projection)."""
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt

    out = np.full(len(X), np.inf)
    for i, x in enumerate(X):
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, x)), geom)
        if proj.NbPoints() > 0:
            out[i] = proj.LowerDistance()
    return out


def run_surface(title: str, s, args, spread: float = 0.01) -> Tuple[float, float, bool]:
    """One surface, points within +-``spread`` of the model size: prints its table;
    returns (engine points/s, faster OCCT points/s (nan without OCP), every engine
    distance <= OCCT's + 1e-9 and converged)."""
    X = scattered_points(s, args.points, spread)
    size = s.size
    t0 = time.perf_counter()
    Projector(s)
    prep = time.perf_counter() - t0
    sec, res = best(lambda: closest_point(s, X), args.repeat)
    rows = [("engine closest_point (prepared object)", sec, len(X), None, None)]
    print(f"\n== {title}: 20 x 20 bicubic, {len(X)} points within +-{spread:.1%} of the model size, best of "
          f"{args.repeat}; preparation (Bezier cells, bounds, voxel grid) {prep * 1e3:.0f} ms once per object")
    gap = res.distances - res.lower_bounds
    print(f"engine: converged {res.point_converged.mean() * 100:.2f}%, certified gap distance - lower_bound: "
          f"max {gap.max() / size:.1e}, median {np.median(gap) / size:.1e} (relative to the model size)")
    ok = bool(res.converged and np.all(res.lower_bounds <= res.distances))
    sub = np.arange(0, len(X), max(1, len(X) // args.subsample))[:args.subsample]
    try:
        from cagd.occ import to_occ
        geom = to_occ(s)
        for name, fn in (("OCCT Extrema_ExtPS reused (subsample)", _occ_extrema),
                         ("OCCT GeomAPI_ProjectPointOnSurf (subsample)", _occ_project)):
            sec, occ = best(lambda: fn(geom, X[sub]), 1)
            rows.append((name, sec, len(sub), None, None))
            mine = res.distances[sub]
            worse = mine > occ + 1e-9 * size
            missed = occ > mine + 1e-9 * size
            ok &= not worse.any()
            print(f"{name}: engine distance <= OCCT + 1e-9 on {np.count_nonzero(~worse)}/{len(sub)}; "
                  f"OCCT larger (missed the minimum) on {np.count_nonzero(missed)}; "
                  f"max |engine - OCCT| {np.abs(mine - occ)[np.isfinite(occ)].max() / size:.1e}")
    except ImportError:
        print("OCP not installed: OCCT peers skipped")
    report(rows, size, engine_label="engine / peer")
    rate = rows[0][2] / rows[0][1]
    faster = max((r[2] / r[1] for r in rows[1:]), default=float("nan"))
    return rate, faster, ok


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=10**5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--subsample", type=int, default=2000, help="points for the per-point OCCT peers")
    ap.add_argument("--spread", type=float, nargs="+", default=[0.01],
                    help="the points' distance from the surface, share of the model size (issue 16: 0.001 .. 0.5)")
    args = ap.parse_args(argv)

    ok, summary = True, []
    for spread in args.spread:
        for title, make in SURFACES:
            rate, faster, good = run_surface(title, make(), args, spread)
            ok &= good
            summary.append((f"{title}, +-{spread:.1%}", rate, faster))
    print(f"\n{'surface, spread':58s} {'points/s':>10s} {'OCCT ExtPS/s':>13s} {'engine / faster OCCT path':>26s}")
    for title, rate, faster in summary:
        print(f"{title:58s} {rate:10,.0f} {faster:13,.0f} {rate / faster:25.1f}x")
    rate = min(r for _, r, _ in summary)
    print(f"engine throughput: {rate:,.0f} points/s, slowest case (target >= 100,000 at +-1%)")
    if not np.isnan(summary[0][2]):
        print(f"engine / faster OCCT path: {min(r / f for _, r, f in summary):.1f}x, slowest case (target >= 30)")
    print("every engine distance <= OCCT's + 1e-9" if ok else "ENGINE DISTANCE ABOVE OCCT's + 1e-9 OR NOT CONVERGED")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
