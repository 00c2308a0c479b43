"""Benchmark: ``cagd.min_distance`` on cases with a closed-form minimum, among them
continua of minima (issue 13: the README's torus and sphere at its centre, concentric
spheres and arcs, coaxial cylinders, parallel patches, a circle about a sphere) and
isolated minima (two spheres, a sphere inside an ellipsoid: two equal minima). Prints
the best time of each, the distance's error, gap / tol, converged and isolated; every
case must converge to within 1e-9 of the exact distance with the exact value inside
[lower_bound, distance] and the expected ``isolated``.

Run: python -m benchmarks.distance [--repeat R]
"""
from __future__ import annotations

import argparse

import numpy as np

import cagd
from cagd.surfaces.revolution import arc_parameters

from .common import best


def _arc(center, r, start, angle, z=None):
    c, s, w, knots = arc_parameters(start, angle)
    P = np.c_[c, s] * r + center
    return cagd.BSplineCurve(P if z is None else np.c_[P, np.full(len(P), z)], 2, knots, w)


def _ellipsoid(a, b, c):
    s = cagd.sphere(1.0)
    return cagd.BSplineSurface(np.asarray(s.control_points) * [a, b, c], 2, 2, s.knots_u, s.knots_v, s.weights,
                               s.periodic_u, s.periodic_v)


def cases():
    """(name, a, b, exact distance, isolated)."""
    P = np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]], float)
    return [
        ("torus(10, 3) / sphere(2) at its centre", cagd.torus(10, 3), cagd.sphere(2.0), 5.0, False),
        ("concentric spheres 1 / 3", cagd.sphere(1.0), cagd.sphere(3.0), 2.0, False),
        ("coaxial cylinders 1 / 3", cagd.cylinder(1.0, 2.0), cagd.cylinder(3.0, 2.0, (0, 0, 0.5)), 2.0, False),
        ("concentric arcs 1 / 2.5", _arc((0.2, 0.1), 1.0, 0.0, 2.0), _arc((0.2, 0.1), 2.5, 0.5, 2.5), 1.5, False),
        ("parallel patches", cagd.BezierSurface(P), cagd.BezierSurface(P + [0.3, 0.2, 1.0]), 1.0, False),
        ("circle r 3 at z 1 / sphere(1)", _arc((0, 0), 3.0, 0.0, 2 * np.pi, 1.0), cagd.sphere(1.0),
         np.sqrt(10.0) - 1.0, False),
        ("two spheres apart", cagd.sphere(1.0), cagd.sphere(0.5, (3, 1, 0.5)), np.sqrt(10.25) - 1.5, True),
        ("sphere in ellipsoid 3, 2, 2.5", cagd.sphere(1.0), _ellipsoid(3.0, 2.0, 2.5), 1.0, True),
    ]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    ok = True
    print(f"{'case':40s} {'seconds':>8s} {'distance - exact':>17s} {'gap / tol':>10s} {'converged':>9s} "
          f"{'isolated':>8s}")
    for name, a, b, exact, isolated in cases():
        sec, res = best(lambda: cagd.min_distance(a, b), args.repeat)
        good = (res.converged and abs(res.distance - exact) <= 1e-9 and res.lower_bound <= exact
                and res.isolated == isolated)
        ok &= good
        print(f"{name:40s} {sec:8.3f} {res.distance - exact:17.1e} {res.gap / res.tol:10.1e} {res.converged!s:>9s} "
              f"{res.isolated!s:>8s}" + ("" if good else "   WRONG"))
    print("every case converged to its closed form" if ok else "SOME CASES WRONG")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
