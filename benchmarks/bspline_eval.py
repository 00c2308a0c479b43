"""Benchmark: cubic B-spline with 100 control points evaluated at 10^6 parameters.

Peers measured in the same run: scipy's BSpline, geomdl (on a subsample), and
OCCT's Geom_BSplineCurve through OCP (per-point calls, on a subsample). Prints
throughput in million points per second and ratios against the engine; checks
that every result equals the engine's within 1e-12 (relative to the curve size).

Run: python -m benchmarks.bspline_eval [--points N] [--repeat R]
"""
from __future__ import annotations

import argparse
from typing import List

import numpy as np

import cagd

from .common import best, occ_knots, report


def _occ_curve(curve: cagd.BSplineCurve):
    from OCP.Geom import Geom_BSplineCurve
    from cagd.occ.compat import Array1OfPnt, Array1OfReal
    from OCP.gp import gp_Pnt

    f = curve.occ_form()
    poles = Array1OfPnt(1, len(f.poles))
    for i, p in enumerate(f.poles, 1):
        poles.SetValue(i, gp_Pnt(*map(float, p)))
    knots, mults = occ_knots(f.knots, f.multiplicities)
    if f.weights is None:
        return Geom_BSplineCurve(poles, knots, mults, f.degree, f.periodic)
    weights = Array1OfReal(1, len(f.weights))
    for i, w in enumerate(f.weights, 1):
        weights.SetValue(i, float(w))
    return Geom_BSplineCurve(poles, weights, knots, mults, f.degree, f.periodic)


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=10**6)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--subsample", type=int, default=20000, help="points for the per-point peers")
    args = ap.parse_args(argv)

    rng = np.random.default_rng(42)
    control_points = rng.uniform(-1.0, 1.0, (100, 3))
    weights = rng.uniform(0.5, 2.0, 100)
    curve = cagd.BSplineCurve(control_points, 3)
    nurbs = cagd.BSplineCurve(control_points, 3, weights=weights)
    nonuniform_knots = np.concatenate([[0.0] * 4, np.sort(rng.uniform(0, 1, 96)), [1.0] * 4])
    curve_nu = cagd.BSplineCurve(control_points, 3, nonuniform_knots)
    t = np.linspace(0.0, 1.0, args.points)
    t_random = rng.uniform(0.0, 1.0, args.points)
    sub = t[:: max(1, args.points // args.subsample)]
    size = np.ptp(control_points, axis=0).max()

    rows = []  # (name, seconds, points, result, reference)
    sec, ref = best(lambda: curve(t), args.repeat)
    rows.append(("engine, clamped uniform knots", sec, len(t), ref, ref))
    sec, out = best(lambda: curve(t_random), args.repeat)
    rows.append(("engine, unsorted parameters", sec, len(t), None, None))
    sec, out = best(lambda: curve_nu(t), args.repeat)
    rows.append(("engine, non-uniform knots", sec, len(t), None, None))
    sec, out_r = best(lambda: nurbs(t), args.repeat)
    rows.append(("engine, rational (NURBS)", sec, len(t), None, None))

    from scipy.interpolate import BSpline
    sp = BSpline(curve.knots, control_points, 3)
    sec, out = best(lambda: sp(t), args.repeat)
    rows.append(("scipy BSpline", sec, len(t), out, ref))
    scipy_row = len(rows) - 1
    sec, out = best(lambda: sp(t_random), args.repeat)
    rows.append(("scipy BSpline, unsorted parameters", sec, len(t), out, curve(t_random)))
    scipy_unsorted = len(rows) - 1
    sp_w = BSpline(curve.knots, np.hstack([control_points * weights[:, None], weights[:, None]]), 3)
    sec, hom = best(lambda: sp_w(t), args.repeat)
    rows.append(("scipy BSpline, homogeneous + division (NURBS)", sec, len(t), hom[:, :3] / hom[:, 3:], out_r))
    sp_nu = BSpline(curve_nu.knots, control_points, 3)
    sec, out_nu = best(lambda: sp_nu(t), args.repeat)
    rows.append(("scipy BSpline, non-uniform knots", sec, len(t), out_nu, curve_nu(t)))

    try:
        from geomdl import BSpline as GBSpline
        g = GBSpline.Curve()
        g.degree = 3
        g.ctrlpts = control_points.tolist()
        g.knotvector = curve.knots.tolist()
        sec, out = best(lambda: np.array(g.evaluate_list(sub.tolist())), 1)
        rows.append(("geomdl (subsample)", sec, len(sub), out, curve(sub)))
    except ImportError:
        print("geomdl not installed: skipped")

    try:
        occ = _occ_curve(curve)

        def occ_eval():
            pts = [occ.Value(float(x)) for x in sub]
            return np.array([[p.X(), p.Y(), p.Z()] for p in pts])
        sec, out = best(occ_eval, 1)
        rows.append(("OCCT Geom_BSplineCurve per point (subsample)", sec, len(sub), out, curve(sub)))
    except ImportError:
        print("OCP not installed: skipped")

    print(f"cubic B-spline, 100 control points, {args.points} parameters, best of {args.repeat}")
    ok = report(rows, size)
    rational_ratio = rows[3][1] / rows[0][1]
    print(f"rational / polynomial time: {rational_ratio:.2f} (target <= 1.5)")
    for name, mine, theirs in (("sorted", 0, scipy_row), ("unsorted", 1, scipy_unsorted)):
        ratio = rows[theirs][1] / rows[mine][1]
        print(f"engine / scipy throughput, {name} parameters: {ratio:.2f} (target >= 4, issue 16)")
    print("all results within 1e-12 of the engine" if ok else "DEVIATION ABOVE 1e-12")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
