"""Benchmark: fitting a curve to points within a tolerance (issue 17), the engine beside
OCCT's GeomAPI_PointsToBSpline (degree 3..8, C2) and scipy's make_splprep in one run.

The anchor data: ``--points`` points (default 2,000) on a 100 mm 3-D curve of varying
curvature. Every fit's largest distance from the points is measured the same way, by the
engine's certified closest points on the fitted curve (OCCT's and scipy's curves are
converted exactly). scipy's smoothing factor is chosen per tolerance as
s = m (tol / 2)^2 (a smoothing spline is fitted to a residual sum, not to a tolerance),
and the engine is then asked for scipy's achieved deviation too, so the counts compare at
equal error.

The surface anchor: a 100 x 100 grid of a 100 mm bumpy height field, fitted by
``cagd.fit_surface`` and OCCT's GeomAPI_PointsToBSplineSurface (degree 3..8, C2) at
tol 0.01 and 0.001, and with noise (sigma 0.005) at tol 0.02 beside the noise-free fit
at the same tol, plain, with ``minimax=True`` and with the thin-plate smoothing
(``smoothing=1e-9``), the ratios of the poles printed (the issue's target: 1.2); then
10,000 scattered points of the same field (base plane and quadric); last, tol below the
noise (a 1,341-point cloud of pure noise, the anchor curve with noise 10 tol), where the
fits stop early and say so.

Every engine row is timed after a warm-up fit, the curve rows as the best of
CURVE_REPEAT runs; OCCT's rows print the ratios engine /
OCCT of poles and time (wall clock, and process CPU time: less sensitive to a shared
machine). The time of the numpy parts depends on the BLAS threads: on a loaded machine
run with OPENBLAS_NUM_THREADS=1 (multithreaded OpenBLAS made a 133 x 133 solve 10x
slower with 2 cores shared).

Run: python -m benchmarks.fitting [--points N] [--tols 0.1,0.01,0.001] [--no-curve] [--no-surface]
[--no-scattered] [--quick]
"""
from __future__ import annotations

import argparse
import time
from typing import List, Optional, Tuple

import numpy as np

import cagd
from cagd.fitting.fit import fit_curve


def anchor_curve(m: int = 2000) -> np.ndarray:
    """m points on a 100 mm long-ish 3-D curve whose curvature varies along it."""
    s = np.linspace(0.0, 1.0, m)
    return np.stack([100.0 * s, 20.0 * np.sin(2 * np.pi * s * (1 + 2 * s)),
                     10.0 * np.cos(3 * np.pi * s ** 2)], axis=1)


def max_distance(curve: cagd.BSplineCurve, Q: np.ndarray) -> float:
    return float(cagd.closest_point(curve, Q).distances.max())


def occt_fit(Q: np.ndarray, tol: float) -> Optional[Tuple[cagd.BSplineCurve, float, float]]:
    try:
        from OCP.GeomAbs import GeomAbs_C2
        from OCP.GeomAPI import GeomAPI_PointsToBSpline
        from OCP.gp import gp_Pnt
        from OCP.TColgp import TColgp_Array1OfPnt
        from cagd.occ import from_occ
    except ImportError:
        return None
    arr = TColgp_Array1OfPnt(1, len(Q))
    for i, q in enumerate(Q, 1):
        arr.SetValue(i, gp_Pnt(*map(float, q)))
    t0, c0 = time.perf_counter(), time.process_time()
    fit = GeomAPI_PointsToBSpline(arr, 3, 8, GeomAbs_C2, tol)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    return from_occ(fit.Curve()), dt, cpu


def scipy_fit(Q: np.ndarray, tol: float) -> Optional[Tuple[cagd.BSplineCurve, float]]:
    try:
        from scipy.interpolate import make_splprep
    except ImportError:
        return None
    t0 = time.perf_counter()
    spl, _ = make_splprep(Q.T, k=3, s=len(Q) * (tol / 2) ** 2)
    dt = time.perf_counter() - t0
    c = np.asarray(spl.c)
    c = c if c.shape[0] == len(spl.t) - 4 else c.T
    return cagd.BSplineCurve(c, 3, spl.t), dt


def anchor_grid(n: int = 100) -> np.ndarray:
    """An n x n grid of a 100 mm bumpy height field."""
    x = np.linspace(0.0, 100.0, n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = 5 * np.sin(X / 15) * np.cos(Y / 20) + 3 * np.exp(-((X - 60) ** 2 + (Y - 40) ** 2) / 200)
    return np.stack([X, Y, Z], axis=-1)


def occt_surface_fit(Q: np.ndarray, tol: float):
    try:
        from OCP.GeomAbs import GeomAbs_C2
        from OCP.GeomAPI import GeomAPI_PointsToBSplineSurface
        from OCP.gp import gp_Pnt
        from OCP.TColgp import TColgp_Array2OfPnt
        from cagd.occ import from_occ
    except ImportError:
        return None
    m, n, _ = Q.shape
    arr = TColgp_Array2OfPnt(1, m, 1, n)
    for i in range(m):
        for j in range(n):
            arr.SetValue(i + 1, j + 1, gp_Pnt(*map(float, Q[i, j])))
    t0, c0 = time.perf_counter(), time.process_time()
    fit = GeomAPI_PointsToBSplineSurface(arr, 3, 8, GeomAbs_C2, tol)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    return from_occ(fit.Surface()), dt, cpu


def _poles(S) -> int:
    return int(np.prod(S.control_points.shape[:2]))


def surfaces(quick: bool = False, scattered: bool = True) -> bool:
    """The grid rows (each timed once, after one warm-up fit), OCCT beside the plain
    rows, the ratios engine / OCCT of poles and time (issue 17 asks <= 0.6 and <= 0.1)."""
    from cagd.fitting.fit_surface import fit_surface
    Q = anchor_grid()
    rng = np.random.default_rng(0)
    noisy = Q.copy()
    noisy[..., 2] += rng.normal(0.0, 0.005, Q.shape[:2])
    print(f"\nfit_surface: {Q.shape[0]} x {Q.shape[1]} grid of a 100 mm height field")
    print(f"{'tol':>7s} {'method':30s} {'poles':>9s} {'max distance':>13s} {'time s':>8s} {'CPU s':>7s}")
    fit_surface(Q, 0.01)                                 # warm-up (imports, first calls)
    ok = True
    counts = {}
    rows = [("", Q, 0.01, {}), ("degree=auto", Q, 0.01, {"degree": "auto"}), ("", Q, 0.001, {}),
            ("degree=auto", Q, 0.001, {"degree": "auto"}), ("noisy", noisy, 0.02, {}), ("clean", Q, 0.02, {}),
            ("noisy minimax", noisy, 0.02, {"minimax": True})]
    if not quick:
        rows += [("noisy smoothing=1e-9", noisy, 0.02, {"smoothing": 1e-9}),
                 ("clean smoothing=1e-9", Q, 0.02, {"smoothing": 1e-9})]
    occ_cache = {}
    for label, data, tol, options in rows:
        t0, c0 = time.perf_counter(), time.process_time()
        r = fit_surface(data, tol, **options)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        ok &= r.converged and r.max_error <= tol
        nu, nv = r.surface.control_points.shape[:2]
        counts[label] = nu * nv
        deg = f"deg {r.surface.degree_u}x{r.surface.degree_v}"
        print(f"{tol:7g} {('cagd.fit_surface ' + label).strip():30s} {nu:4d}x{nv:<4d} {r.max_error:13.3g} {dt:8.3f}"
              f" {cpu:7.3f}   {deg}")
        if label in ("", "noisy", "degree=auto"):
            key = (label == "noisy", tol)
            if key not in occ_cache:
                occ_cache[key] = occt_surface_fit(data, tol)
            occ = occ_cache[key]
            if occ is not None:
                S, t_occ, cpu_occ = occ
                ou, ov = S.control_points.shape[:2]
                dev = float(cagd.closest_point(S, data.reshape(-1, 3)).distances.max())
                if label != "degree=auto":
                    print(f"{'':7s} {'OCCT PointsToBSplineSurface':30s} {ou:4d}x{ov:<4d} {dev:13.3g} {t_occ:8.3f}"
                          f" {cpu_occ:7.3f}   deg {S.degree_u}x{S.degree_v}")
                print(f"{'':7s} {'  engine / OCCT':30s} poles {nu * nv / (ou * ov):.2f}, time {dt / t_occ:.3f}"
                      f" (CPU {cpu / cpu_occ:.3f})  (issue 17: <= 0.6, <= 0.1)")
    line = (f"noisy / clean poles at tol 0.02 (issue 17 asks <= 1.2): {counts['noisy'] / counts['clean']:.2f}; "
            f"minimax=True {counts['noisy minimax'] / counts['clean']:.2f}")
    if not quick:
        line += (f"; smoothing=1e-9 over the plain clean fit {counts['noisy smoothing=1e-9'] / counts['clean']:.2f},"
                 f" over the smoothed clean fit "
                 f"{counts['noisy smoothing=1e-9'] / counts['clean smoothing=1e-9']:.2f}")
    print(line)
    if scattered:
        ok &= scattered_surfaces(quick)
    return ok


def anchor_scattered(n: int = 10000, seed: int = 1) -> np.ndarray:
    """n random points of the anchor height field (:func:`anchor_grid`'s function)."""
    rng = np.random.default_rng(seed)
    X, Y = rng.random(n) * 100.0, rng.random(n) * 100.0
    Z = 5 * np.sin(X / 15) * np.cos(Y / 20) + 3 * np.exp(-((X - 60) ** 2 + (Y - 40) ** 2) / 200)
    return np.stack([X, Y, Z], axis=1)


def scattered_surfaces(quick: bool = False) -> bool:
    """fit_surface on scattered points of the anchor field, per base (OCCT has no
    scattered-point fit to compare with; the grid fit's poles at the same tol are)."""
    from cagd.fitting.fit_surface import fit_surface
    Q = anchor_scattered()
    print(f"\nfit_surface: {len(Q)} scattered points of the same height field")
    print(f"{'tol':>7s} {'method':28s} {'poles':>9s} {'max distance':>13s} {'time s':>8s}")
    ok = True
    for tol in (0.01,) if quick else (0.01, 0.001):
        for base in ("plane",) if quick else ("plane", "quadric"):
            t0 = time.perf_counter()
            r = fit_surface(Q, tol, base=base)
            dt = time.perf_counter() - t0
            ok &= r.converged
            nu, nv = r.surface.control_points.shape[:2]
            print(f"{tol:7g} {'cagd.fit_surface ' + base:28s} {nu:4d}x{nv:<4d} {r.max_error:13.3g} {dt:8.3f}")
    return ok


def noise_cloud(n: int = 1341, seed: int = 0) -> np.ndarray:
    """Pure noise: n points uniform over [0, 100]^2 with heights N(0, 1)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0.0, 100.0, (n, 2)), rng.normal(size=n)])


def unattainable() -> None:
    """tol below the noise: the fits stop early and say so (converged False; before the
    stall rule the 1,341-point cloud ran to its 36 x 36 cap in ~11 s per degree)."""
    from cagd.fitting.fit_surface import fit_surface
    print("\ntol below the noise (converged False expected)")
    print(f"{'tol':>7s} {'data':42s} {'poles':>9s} {'max distance':>13s} {'time s':>8s}")
    Q = noise_cloud()
    for degree in (3, "auto"):
        t0 = time.perf_counter()
        r = fit_surface(Q, 0.01, degree=degree)
        nu, nv = r.surface.control_points.shape[:2]
        print(f"{0.01:7g} {f'{len(Q)}-point noise cloud, degree {degree}':42s} {nu:4d}x{nv:<4d} {r.max_error:13.3g} "
              f"{time.perf_counter() - t0:8.3f}  converged {r.converged}")
    C = anchor_curve(2000) + np.random.default_rng(0).normal(scale=0.1, size=(2000, 3))
    t0 = time.perf_counter()
    c = fit_curve(C, 0.01)
    print(f"{0.01:7g} {'anchor curve + noise sigma 0.1':42s} {len(c.curve.control_points):9d} {c.max_error:13.3g} "
          f"{time.perf_counter() - t0:8.3f}  converged {c.converged}")


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=2000)
    ap.add_argument("--tols", default="0.1,0.01,0.001")
    ap.add_argument("--no-surface", action="store_true")
    ap.add_argument("--no-curve", action="store_true")
    ap.add_argument("--no-scattered", action="store_true")
    ap.add_argument("--quick", action="store_true", help="the grid rows without smoothing, one scattered row")
    args = ap.parse_args(argv)
    ok = True
    if not args.no_curve:
        ok &= curves(args)
    if not args.no_surface:
        ok &= surfaces(args.quick, not args.no_scattered)
    if not (args.quick or args.no_surface or args.no_scattered):
        unattainable()
    return 0 if ok else 1


#: the engine's curve fits are timed as the best of this many runs (a fit takes tenths of
#: a second: one run varies by a third on a shared machine)
CURVE_REPEAT = 3


def curves(args: argparse.Namespace) -> bool:
    Q = anchor_curve(args.points)
    print(f"fit_curve: {len(Q)} points on a 100 mm 3-D curve; max distance by certified closest points")
    print(f"{'tol':>7s} {'method':28s} {'poles':>6s} {'max distance':>13s} {'time s':>8s} {'CPU s':>7s}")
    ok = True
    fit_curve(Q, 0.1)                                    # warm-up (imports, first calls)
    for tol in map(float, args.tols.split(",")):
        dt = cpu = np.inf
        for _ in range(CURVE_REPEAT):
            t0, c0 = time.perf_counter(), time.process_time()
            r = fit_curve(Q, tol)
            dt, cpu = min(dt, time.perf_counter() - t0), min(cpu, time.process_time() - c0)
        ok &= r.converged and r.max_error <= tol
        n_engine = len(r.curve.control_points)
        print(f"{tol:7g} {'cagd.fit_curve':28s} {n_engine:6d} {r.max_error:13.3g} {dt:8.3f} {cpu:7.3f}")
        occ = occt_fit(Q, tol)
        if occ is not None:
            c, t_occ, cpu_occ = occ
            n = len(c.control_points)
            print(f"{'':7s} {'OCCT PointsToBSpline':28s} {n:6d} {max_distance(c, Q):13.3g} {t_occ:8.3f} {cpu_occ:7.3f}"
                  f"   engine/OCCT: poles {n_engine / n:.2f}, time {dt / t_occ:.2f} (CPU {cpu / cpu_occ:.2f})")
        sp = scipy_fit(Q, tol)
        if sp is not None:
            c, t_sp = sp
            dev = max_distance(c, Q)
            r2 = fit_curve(Q, dev)
            n, n2 = len(c.control_points), len(r2.curve.control_points)
            print(f"{'':7s} {'scipy make_splprep':28s} {n:6d} {dev:13.3g} {t_sp:8.3f}"
                  f"   engine at scipy's deviation: {n2} poles ({n2 / n:.2f}x), {r2.max_error:.3g}")
    return ok


if __name__ == "__main__":
    raise SystemExit(main())
