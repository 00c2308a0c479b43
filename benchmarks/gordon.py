"""Benchmark: Gordon surfaces through curve networks (issue 18), ``cagd.gordon`` beside
build123d's ``Face.make_gordon_surface`` (ocp_gordon) on the same networks.

The networks: m profiles (v = const) and n guides (u = const) of a smooth 100 mm
surface, each curve interpolated through ``--points`` points by ``cagd.interpolate``
(chord parameters, so the curves meet at differing parameters and both methods
reparametrise). Both are asked for the same tolerance. Times are the best of
``--repeat`` calls on new but equal curve objects (nothing cached carries over;
build123d's edges are made beforehand, outside the timing). Every
surface's distance from the network is measured the same way, by the engine's certified
closest points at ``--samples`` points per curve; the engine's own ``max_error`` (an
upper bound) is printed beside it. The issue's target: at most 0.5x build123d's time.

Run: python -m benchmarks.gordon [--sizes 3x3,4x5,7x7] [--points 60] [--tol 1e-6]
"""
from __future__ import annotations

import argparse
from typing import List, Optional, Sequence, Tuple

import numpy as np

import cagd

from .common import best


def anchor(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A smooth 100 mm x 100 mm surface, heights within 15 mm."""
    return np.stack([100 * u, 100 * v, 10 * np.sin(3 * u) * np.cos(2 * v) + 5 * u * v], axis=-1)


def network(m: int, n: int, points: int) -> Tuple[List[cagd.BSplineCurve], List[cagd.BSplineCurve]]:
    """m profiles at v = i / (m - 1) and n guides at u = j / (n - 1), interpolated."""
    t = np.linspace(0.0, 1.0, points)
    profiles = [cagd.interpolate(anchor(t, np.full_like(t, v))) for v in np.linspace(0, 1, m)]
    guides = [cagd.interpolate(anchor(np.full_like(t, u), t)) for u in np.linspace(0, 1, n)]
    return profiles, guides


def fresh(curves: Sequence[cagd.BSplineCurve]) -> List[cagd.BSplineCurve]:
    """Equal new curve objects: no cached Bezier decomposition or pp form carries over
    between timed calls."""
    return [cagd.BSplineCurve(c.control_points, c.degree, c.knots) for c in curves]


def distance(surface: cagd.BSplineSurface, curves: Sequence[cagd.BSplineCurve], samples: int) -> float:
    pts = np.concatenate([c(np.linspace(*c.domain, samples)) for c in curves])
    return float(cagd.closest_point(surface, pts).distances.max())


def build123d_gordon(profiles, guides, tol: float, repeat: int):
    """(time, surface) of build123d's make_gordon_surface, or None without build123d."""
    try:
        import build123d as bd
        from OCP.BRep import BRep_Tool
        from cagd.occ import from_occ, make_edge
    except ImportError:
        return None
    P = [bd.Edge(make_edge(c)) for c in profiles]
    G = [bd.Edge(make_edge(c)) for c in guides]
    dt, face = best(lambda: bd.Face.make_gordon_surface(P, G, tol), repeat)
    return dt, from_occ(BRep_Tool.Surface_s(face.wrapped))


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="3x3,4x5,7x7")
    ap.add_argument("--points", type=int, default=60)
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--samples", type=int, default=200)
    args = ap.parse_args(argv)
    print(f"gordon: networks of iso-curves of a 100 mm surface, {args.points} points per curve, tol {args.tol:g}")
    print(f"{'network':8s} {'method':26s} {'poles':>9s} {'time s':>8s} {'off network':>12s} {'max_error':>10s}")
    ok = True
    for size in args.sizes.split(","):
        m, n = map(int, size.lower().split("x"))
        profiles, guides = network(m, n, args.points)
        dt, r = best(lambda: cagd.gordon(fresh(profiles), fresh(guides), args.tol), args.repeat)
        nu, nv = r.surface.control_points.shape[:2]
        off = distance(r.surface, profiles + guides, args.samples)
        ok &= r.converged and off <= r.max_error
        print(f"{size:8s} {'cagd.gordon':26s} {nu:4d}x{nv:<4d} {dt:8.3f} {off:12.3g} {r.max_error:10.3g}")
        peer = build123d_gordon(profiles, guides, args.tol, args.repeat)
        if peer is not None:
            t_b, S = peer
            bu, bv = S.control_points.shape[:2]
            off_b = distance(S, profiles + guides, args.samples)
            print(f"{'':8s} {'build123d make_gordon':26s} {bu:4d}x{bv:<4d} {t_b:8.3f} {off_b:12.3g} {'-':>10s}"
                  f"   cagd/build123d: time {dt / t_b:.2f}, poles {nu * nv / (bu * bv):.2f}")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
