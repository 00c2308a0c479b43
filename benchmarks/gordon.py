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

The issue's second anchor, the sparse networks (``--sparse``, on by default): curves
through 8 points each, the crossings among the points, the guides moved by up to a
micrometre so that the curves cross within about a micrometre, not exactly, at tol 1e-3.

OCCT 8.0's GeomFill_Gordon runs beside them where a Python with cadquery-ocp 8 is given
(``--occt8-python``, default the CI's ``.venv-b3d`` when present): in a child process
(benchmarks/occt8_gordon.py) with a time limit and a memory limit, since on the 60-point
4x5 network it ran over 10 minutes and 3.2 GB.

Run: python -m benchmarks.gordon [--sizes 3x3,4x5,7x7] [--points 60] [--tol 1e-6]
         [--sparse-tol 1e-3] [--occt8-python PATH] [--occt8-timeout 60]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
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


SPARSE_POINTS = 8        # points per curve of the sparse networks
SPARSE_MISS = 1e-6       # ... whose guides are moved by up to this (mm)
OCCT8_MEMORY = 4 << 30   # bytes the OCCT 8 child may allocate
VENV_B3D = Path(__file__).resolve().parent.parent / ".venv-b3d" / "bin" / "python"


def sparse_network(m: int, n: int) -> Tuple[List[cagd.BSplineCurve], List[cagd.BSplineCurve]]:
    """m profiles and n guides through SPARSE_POINTS points each, the crossings among
    them (the rest evenly between), each guide point moved by a fixed random vector of
    length up to SPARSE_MISS: the curves cross within about a micrometre."""
    rng = np.random.default_rng(18)

    def params(crossings: np.ndarray) -> np.ndarray:
        fill = np.linspace(0.0, 1.0, SPARSE_POINTS + len(crossings))
        fill = fill[np.abs(fill[:, None] - crossings[None, :]).min(axis=1) > 0.5 / SPARSE_POINTS]
        return np.sort(np.concatenate([crossings, fill[:SPARSE_POINTS - len(crossings)]]))
    us, vs = np.linspace(0, 1, n), np.linspace(0, 1, m)
    tu, tv = params(us), params(vs)
    profiles = [cagd.interpolate(anchor(tu, np.full_like(tu, v))) for v in vs]
    guides = []
    for u in us:
        shift = rng.normal(size=(len(tv), 3))
        shift *= SPARSE_MISS * rng.random((len(tv), 1)) / np.linalg.norm(shift, axis=1, keepdims=True)
        guides.append(cagd.interpolate(anchor(np.full_like(tv, u), tv) + shift))
    return profiles, guides


def occt8_gordon(python: Path, profiles, guides, tol: float, timeout: float) -> str:
    """OCCT 8.0's GeomFill_Gordon in a child process (benchmarks/occt8_gordon.py): a
    table cell, the time and pole counts or why there are none."""
    def spec(c: cagd.BSplineCurve) -> dict:
        f = c.occ_form()
        return {"poles": f.poles.tolist(), "knots": f.knots.tolist(), "mults": f.multiplicities.tolist(),
                "degree": f.degree}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "network.json"
        path.write_text(json.dumps({"profiles": [spec(c) for c in profiles], "guides": [spec(c) for c in guides]}))
        limit = f"import resource; resource.setrlimit(resource.RLIMIT_AS, ({OCCT8_MEMORY}, {OCCT8_MEMORY}))"
        script = Path(__file__).with_name("occt8_gordon.py")
        cmd = [str(python), "-c", f"{limit}; import runpy, sys; sys.argv = {[str(script), str(path), repr(tol)]!r}; "
               f"runpy.run_path({str(script)!r}, run_name='__main__')"]
        try:
            run = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return f"stopped after {timeout:g} s"
    lines = run.stdout.strip().splitlines()
    if run.returncode != 0 or not lines:
        return f"failed (exit {run.returncode}{', out of memory' if 'MemoryError' in run.stderr else ''})"
    out = json.loads(lines[-1])
    if "error" in out:
        return out["error"][:60]
    if out["status"] != "Done":
        return f"{out['status']} after {out['seconds']:.3f} s"
    return f"{out['poles'][0]}x{out['poles'][1]} poles in {out['seconds']:.3f} s"


def fresh(curves: Sequence[cagd.BSplineCurve]) -> List[cagd.BSplineCurve]:
    """Equal new curve objects: no cached Bezier decomposition or pp form carries over
    between timed calls."""
    return [cagd.BSplineCurve(c.control_points, c.degree, c.knots) for c in curves]


def distance(surface: cagd.BSplineSurface, curves: Sequence[cagd.BSplineCurve], samples: int) -> float:
    pts = np.concatenate([c(np.linspace(*c.domain, samples)) for c in curves])
    return float(cagd.closest_point(surface, pts).distances.max())


def build123d_gordon(profiles, guides, tol: float, repeat: int):
    """(time, surface) of build123d's make_gordon_surface, None without build123d, or
    the message where it fails."""
    try:
        import build123d as bd
        from OCP.BRep import BRep_Tool
        from cagd.occ import from_occ, make_edge
    except ImportError:
        return None
    P = [bd.Edge(make_edge(c)) for c in profiles]
    G = [bd.Edge(make_edge(c)) for c in guides]
    try:
        dt, face = best(lambda: bd.Face.make_gordon_surface(P, G, tol), repeat)
    except Exception as exc:             # the peer's failure is a result to print
        return f"{type(exc).__name__}: {exc}"[:90]
    return dt, from_occ(BRep_Tool.Surface_s(face.wrapped))


def run_network(label: str, profiles, guides, tol: float, args, occt8: Optional[Path]) -> bool:
    """One network's rows: cagd.gordon, build123d, OCCT 8. Returns whether cagd converged
    with every sampled curve point within max_error."""
    dt, r = best(lambda: cagd.gordon(fresh(profiles), fresh(guides), tol), args.repeat)
    nu, nv = r.surface.control_points.shape[:2]
    off = distance(r.surface, profiles + guides, args.samples)
    ok = r.converged and off <= r.max_error
    print(f"{label:12s} {'cagd.gordon':26s} {nu:4d}x{nv:<4d} {dt:8.3f} {off:12.3g} {r.max_error:10.3g}"
          f"   max miss {r.max_miss:.2g}")
    peer = build123d_gordon(profiles, guides, tol, args.repeat)
    if isinstance(peer, str):
        print(f"{'':12s} {'build123d make_gordon':26s} fails: {peer}")
    elif peer is not None:
        t_b, S = peer
        bu, bv = S.control_points.shape[:2]
        off_b = distance(S, profiles + guides, args.samples)
        print(f"{'':12s} {'build123d make_gordon':26s} {bu:4d}x{bv:<4d} {t_b:8.3f} {off_b:12.3g} {'-':>10s}"
              f"   cagd/build123d: time {dt / t_b:.2f}, poles {nu * nv / (bu * bv):.2f}")
    if occt8 is not None:
        cell = occt8_gordon(occt8, profiles, guides, tol, args.occt8_timeout)
        print(f"{'':12s} {'OCCT 8.0 GeomFill_Gordon':26s} {cell}")
    return ok


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="3x3,4x5,7x7")
    ap.add_argument("--points", type=int, default=60)
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--sparse-tol", type=float, default=1e-3)
    ap.add_argument("--no-sparse", action="store_true", help="skip the 8-point networks")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--occt8-python", default=os.environ.get("CAGD_OCCT8_PYTHON", str(VENV_B3D)),
                    help="a Python with cadquery-ocp 8 (skipped when absent)")
    ap.add_argument("--occt8-timeout", type=float, default=60.0)
    args = ap.parse_args(argv)
    occt8 = Path(args.occt8_python) if Path(args.occt8_python).is_file() else None
    print(f"gordon: networks of iso-curves of a 100 mm surface; {args.points} points per curve at tol {args.tol:g}"
          + ("" if args.no_sparse else f", {SPARSE_POINTS} points at tol {args.sparse_tol:g}")
          + (f"; OCCT 8 from {occt8}" if occt8 else "; no OCCT 8 Python (--occt8-python)"))
    print(f"{'network':12s} {'method':26s} {'poles':>9s} {'time s':>8s} {'off network':>12s} {'max_error':>10s}")
    ok = True
    for size in args.sizes.split(","):
        m, n = map(int, size.lower().split("x"))
        ok &= run_network(f"{size} x{args.points}", *network(m, n, args.points), args.tol, args, occt8)
    if not args.no_sparse:
        for size in args.sizes.split(","):
            m, n = map(int, size.lower().split("x"))
            ok &= run_network(f"{size} x{SPARSE_POINTS}", *sparse_network(m, n), args.sparse_tol, args, occt8)
    sys.stdout.flush()
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
