"""Benchmark: bicubic B-spline surface with 20 x 20 control points on a 1000 x 1000 grid.

The engine's ``grid`` (per block of parameters, one matrix product of the small
dense local basis with the pole rows it touches) against, in the same run: the
engine's element-wise ``__call__`` on the same 10^6 (u, v) pairs, the NURBS grid,
scipy's BSpline applied per direction, splipy's Surface (if installed), geomdl (a
subsample, rate extrapolated) and OCCT's Geom_BSplineSurface through OCP (per-point
Value calls, a subsample). Prints throughput in million points per second, ratios
against the engine grid, and the maximum deviation from the engine relative to the
surface size (must be <= 1e-12).

Run: python -m benchmarks.surface_grid [--grid N] [--repeat R]
"""
from __future__ import annotations

import argparse
from typing import List

import numpy as np

import cagd

from .common import best, occ_knots, report


def _occ_surface(s: cagd.BSplineSurface):
    from OCP.Geom import Geom_BSplineSurface
    from cagd.occ.compat import Array2OfPnt
    from OCP.gp import gp_Pnt

    nu, nv, _ = s.control_points.shape
    poles = Array2OfPnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*map(float, s.control_points[i, j])))

    def knots(full):
        return occ_knots(*cagd.knots.distinct_with_multiplicities(full))

    ku, mu = knots(s.knots_u)
    kv, mv = knots(s.knots_v)
    return Geom_BSplineSurface(poles, ku, kv, mu, mv, s.degree_u, s.degree_v)


def main(argv: List[str] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, default=1000, help="points per direction")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--subsample", type=int, default=20000, help="points for the per-point peers")
    args = ap.parse_args(argv)

    rng = np.random.default_rng(42)
    P = rng.uniform(-1.0, 1.0, (20, 20, 3))
    W = rng.uniform(0.5, 2.0, (20, 20))
    surface = cagd.BSplineSurface(P, 3, 3)
    nurbs = cagd.BSplineSurface(P, 3, 3, weights=W)
    us = np.linspace(0.0, 1.0, args.grid)
    vs = np.linspace(0.0, 1.0, args.grid)
    npts = len(us) * len(vs)
    size = float(np.ptp(P.reshape(-1, 3), axis=0).max())
    step = max(1, int(round(np.sqrt(npts / args.subsample))))
    sub_u, sub_v = us[::step], vs[::step]
    U, V = (x.ravel() for x in np.meshgrid(sub_u, sub_v, indexing="ij"))

    rows = []  # (name, seconds, points, result, reference)
    sec, ref = best(lambda: surface.grid(us, vs), args.repeat)
    rows.append(("engine grid", sec, npts, ref, ref))
    ref_sub = ref[::step, ::step].reshape(-1, 3)
    sec, out = best(lambda: surface(us[:, None], vs[None, :]), max(1, args.repeat // 2))
    rows.append(("engine __call__ (element-wise, broadcast)", sec, npts, out, ref))
    sec, out_r = best(lambda: nurbs.grid(us, vs), args.repeat)
    rows.append(("engine grid, rational (NURBS)", sec, npts, None, None))

    from scipy.interpolate import BSpline

    def scipy_grid():
        rows_v = BSpline(surface.knots_v, P.transpose(1, 0, 2).reshape(20, 60), 3)(vs)        # (Mv, nu*3)
        cols = rows_v.reshape(len(vs), 20, 3).transpose(1, 0, 2).reshape(20, -1)
        return BSpline(surface.knots_u, cols, 3)(us).reshape(len(us), len(vs), 3)
    sec, out = best(scipy_grid, args.repeat)
    rows.append(("scipy BSpline per direction", sec, npts, out, ref))

    try:
        import splipy
        basis_u = splipy.BSplineBasis(order=4, knots=surface.knots_u)
        basis_v = splipy.BSplineBasis(order=4, knots=surface.knots_v)
        # splipy orders the control points with u running fastest
        sp = splipy.Surface(basis_u, basis_v, P.transpose(1, 0, 2).reshape(-1, 3))
        sec, out = best(lambda: sp(us, vs), args.repeat)
        rows.append(("splipy Surface(us, vs)", sec, npts, out, ref))
    except ImportError:
        print("splipy not installed: skipped")

    try:
        from geomdl import BSpline as GBSpline
        g = GBSpline.Surface(normalize_kv=False)
        g.degree_u = g.degree_v = 3
        g.ctrlpts_size_u = g.ctrlpts_size_v = 20
        g.ctrlpts = P.reshape(-1, 3).tolist()
        g.knotvector_u = surface.knots_u.tolist()
        g.knotvector_v = surface.knots_v.tolist()
        pairs = np.column_stack([U, V]).tolist()
        sec, out = best(lambda: np.array(g.evaluate_list(pairs)), 1)
        rows.append(("geomdl evaluate_list (subsample)", sec, len(U), out, ref_sub))
    except ImportError:
        print("geomdl not installed: skipped")

    try:
        occ = _occ_surface(surface)

        def occ_eval():
            out = np.empty((len(U), 3))
            for k, (a, b) in enumerate(zip(U.tolist(), V.tolist())):
                p = occ.Value(a, b)
                out[k] = (p.X(), p.Y(), p.Z())
            return out
        sec, out = best(occ_eval, 1)
        rows.append(("OCCT Geom_BSplineSurface.Value per point (subsample)", sec, len(U), out, ref_sub))
    except ImportError:
        print("OCP not installed: skipped")

    engine_rate = rows[0][2] / rows[0][1]
    print(f"bicubic B-spline surface, 20 x 20 control points, {len(us)} x {len(vs)} grid, best of {args.repeat}")
    ok = report(rows, size, width=54, engine_label="engine grid / peer")
    print(f"engine grid: {engine_rate / 1e6:.1f} M points/s (target >= 50); "
          f"rational / polynomial grid time {rows[2][1] / rows[0][1]:.2f} (target <= 1.5)")
    print("all results within 1e-12 of the engine" if ok else "DEVIATION ABOVE 1e-12")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
