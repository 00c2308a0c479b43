"""Benchmark: closest_point on sliver faces, points slightly off them (issue 16).

A bicubic strip [0, w] x [0, 10] mm (aspect w : 10 of 1:100 and 1:1000), mildly curved
along (z = 0.3 sin(pi y / 10): radius ~34 mm) and across (a bow of 2% of the width:
radius ~6 w); query points on the strip moved along its normal by 1e-7, 1e-5 and 1e-3
of its size. Face 16 of bug24595_281390.stp (a 0.1 x 10 mm rational fillet strip) with
the single-precision vertices of its mesh, 1e-7..1e-5 off, took 70x the time of the same
vertices in double precision: the certificate's boxes near the foot must close to 1e-10
of the distance, and the box bounds treated the short direction as degenerate. Prints
CPU time (the best of ``--repeat``), points per second and how tight the certificates
are (largest (d - lower bound) / d).

Run: python -m benchmarks.closest_sliver [--points N] [--repeat R]
"""
from __future__ import annotations

import argparse
import time
from typing import List, Optional, Tuple

import numpy as np

import cagd

LENGTH = 10.0                   # mm, the strip's long side
ASPECTS = (1e-2, 1e-3)          # width / length
OFFSETS = (1e-7, 1e-5, 1e-3)    # distances off the strip, share of its size
BOW = 0.02                      # the cross section bows by this share of the width
WAVE = 0.3                      # mm, amplitude of the long direction's sine


def strip(width: float, length: float = LENGTH) -> cagd.BSplineSurface:
    """Bicubic B-spline strip, 4 x 8 control points (one Bezier piece across, five
    along) over the Greville abscissae of [0, width] x [0, length]: x = u width,
    y = v length (exact), z the samples of WAVE sin(pi y / length) + 4 BOW width
    (x / width)(1 - x / width) there."""
    p = 3
    ku = np.r_[[0.0] * (p + 1), [1.0] * (p + 1)]
    kv = np.r_[[0.0] * p, np.linspace(0.0, 1.0, 6), [1.0] * p]
    gu = np.array([ku[i + 1:i + p + 1].mean() for i in range(4)])
    gv = np.array([kv[i + 1:i + p + 1].mean() for i in range(8)])
    U, V = np.meshgrid(gu, gv, indexing="ij")
    Z = WAVE * np.sin(np.pi * V) + 4.0 * BOW * width * U * (1.0 - U)     # (the net's samples: about that shape)
    P = np.stack([U * width, V * length, Z], axis=-1)
    return cagd.BSplineSurface(P, p, p, ku, kv)


def near_points(S: cagd.BSplineSurface, count: int, offset: float, seed: int = 0
                ) -> Tuple[np.ndarray, np.ndarray]:
    """``count`` points moved off S along its unit normal by ``offset`` times S's size
    (either side), from feet at random parameters: (points, parameters of the feet)."""
    rng = np.random.default_rng(seed)
    (a, b), (c, d) = S.domain
    uv = np.stack([rng.uniform(a, b, count), rng.uniform(c, d, count)], axis=1)
    feet = S(uv[:, 0], uv[:, 1])
    n = S.normal(uv[:, 0], uv[:, 1])
    side = rng.choice([-1.0, 1.0], (count, 1))
    return feet + side * offset * S.size * n, uv


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--points", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    for aspect in ASPECTS:
        S = strip(aspect * LENGTH)
        for rel in OFFSETS:
            X, _ = near_points(S, args.points, rel)
            cagd.closest_point(S, X)                         # the projector, cached
            times = []
            for _ in range(args.repeat):
                t = time.process_time()
                r = cagd.closest_point(S, X)
                times.append(time.process_time() - t)
            gap = float(np.max((r.distances - r.lower_bounds) / r.distances))
            print(f"strip 1:{1 / aspect:,.0f}, points {rel:g} of the size off: {min(times):.3f} s CPU, "
                  f"{len(X) / min(times):,.0f} points/s, largest (d - lower bound) / d {gap:.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
