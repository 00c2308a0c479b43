"""``cagd demo``: the seeds' example curves, each checked against an independent oracle.

Every example builds a curve with the engine, measures the largest deviation from
an oracle that does not share the engine's evaluation path (the seed's matrix
form, a direct Bernstein or Cox-de Boor sum, a closed-form property), and draws
the curve with its control polygon and curvature comb.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np

from .basis.bernstein import bezier_matrix
from .basis.bspline import cox_de_boor
from .curves.base import Curve
from .curves.bezier import BezierCurve
from .curves.bspline import BSplineCurve

T = np.linspace(0.0, 1.0, 201)


@dataclass
class Example:
    name: str
    seed: str
    oracle: str
    tolerance: float
    build: Callable[[], Tuple[float, Sequence[Curve], Sequence[np.ndarray], Optional[np.ndarray]]]


@dataclass
class Result:
    example: Example
    deviation: float
    png: Optional[Path]

    @property
    def passed(self) -> bool:
        return self.deviation <= self.example.tolerance


EXAMPLES: List[Example] = []


def example(name: str, seed: str, oracle: str, tolerance: float = 1e-12):
    def register(fn):
        EXAMPLES.append(Example(name, seed, oracle, tolerance, fn))
        return fn
    return register


def _rel(a: np.ndarray, b: np.ndarray, size: float = None) -> float:
    size = size if size is not None else max(float(np.ptp(np.asarray(b).reshape(-1, np.shape(b)[-1]), axis=0).max()), 1.0)
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / size)


P4 = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.5], [4.0, 0.5]])


@example("cubic Bezier", "000 5.2.3", "matrix form [t^3 t^2 t 1] M P")
def _cubic_bezier():
    c = BezierCurve(P4)
    U = T[:, None] ** np.arange(3, -1, -1)
    return _rel(c(T), U @ bezier_matrix(3) @ P4), [c], [P4], None


@example("quadratic Bezier midpoint", "000 5.2.3", "p(1/2) = (P1 + (P0+P2)/2)/2")
def _quadratic():
    P = P4[:3]
    c = BezierCurve(P)
    return _rel(c(0.5), 0.5 * (P[1] + 0.5 * (P[0] + P[2])), 4.0), [c], [P], None


@example("de Casteljau vs Bernstein, degree 7", "000 5.2.1, 5.2.4", "direct Bernstein sum")
def _casteljau():
    P = np.array([[0, 0], [1, 3], [2, -1], [3, 3], [4, -1], [5, 3], [6, -1], [7, 1.0]])
    c = BezierCurve(P)
    return max(_rel(c.de_casteljau(T), c.bernstein_evaluate(T)), _rel(c(T), c.bernstein_evaluate(T))), [c], [P], None


@example("rational quadratic NURBS circle", "Piegl & Tiller 7.5", "|C(t)| = 1")
def _circle():
    s = np.sqrt(0.5)
    P = [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]]
    c = BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, s, 1, s, 1, s, 1, s, 1])
    t = np.linspace(0, 1, 10001)
    return float(np.abs(np.linalg.norm(c(t), axis=1) - 1).max()), [c], [np.array(P, float)], None


@example("uniform periodic cubic B-spline", "000 5.3.2", "matrix M_BEZ per segment; p(0) = (P0+4P1+P2)/6")
def _periodic_cubic():
    P = np.array([[0, 0], [2, 0], [3, 2], [2, 4], [0, 4], [-1, 2.0]])
    n = len(P)
    c = BSplineCurve(P, 3, np.arange(n + 1.0), periodic=True)
    M = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]]) / 6.0
    dev = 0.0
    for seg in range(n):
        G = P[[(seg + k) % n for k in range(4)]]
        U = T[:, None] ** np.arange(3, -1, -1)
        dev = max(dev, _rel(c(seg + T), U @ M @ G))
    dev = max(dev, _rel(c(0.0), (P[0] + 4 * P[1] + P[2]) / 6), _rel(c.derivative(0.0), (P[2] - P[0]) / 2))
    return dev, [c], [np.vstack([P, P[:1]])], None


@example("uniform quadratic B-spline, knots 0..6", "000 5.3.2", "p_start = (P0+P1)/2, p'_start = P1-P0; Cox-de Boor sum")
def _quadratic_bspline():
    P = np.array([[0, 0], [1, 2], [3, 2], [4, 0.0]])
    c = BSplineCurve(P, 2, np.arange(7.0))
    t = np.linspace(2, 4, 201)
    dev = max(_rel(c(2.0), (P[0] + P[1]) / 2), _rel(c(4.0), (P[2] + P[3]) / 2),
              _rel(c.derivative(2.0), P[1] - P[0]), _rel(c.derivative(4.0), P[3] - P[2]),
              _rel(c(t[:-1]), cox_de_boor(c.knots, 2, t[:-1]) @ P))
    return dev, [c], [P], None


@example("non-uniform NURBS: knot insertion and degree elevation", "Piegl & Tiller 5.2, 5.5", "same samples before/after")
def _refine():
    P = np.array([[0, 0], [1, 2], [2, -1], [3, 3], [5, 1], [6, 2.0]])
    c = BSplineCurve(P, 3, [0, 0, 0, 0, .3, .7, 1, 1, 1, 1], [1, 2, .5, 1, 3, 1])
    r = c.insert_knot(0.5, 2).elevate(1)
    return _rel(r(T), c(T)), [c], [P, r.control_points], None


def run_demo(out_dir: Path, stream=None, plots: bool = True) -> List[Result]:
    """Run every example, write its PNG, print the table; return the results."""
    stream = sys.stdout if stream is None else stream
    out_dir = Path(out_dir)
    results = []
    for i, ex in enumerate(EXAMPLES, 1):
        print(f"[{i}/{len(EXAMPLES)}] {ex.name}", file=sys.stderr, flush=True)
        dev, curves, polygons, pts = ex.build()
        png = None
        if plots:
            from .plotting import plot_curves
            slug = "".join(ch if ch.isalnum() else "_" for ch in ex.name.lower()).strip("_")
            png = plot_curves(out_dir / f"{i:02d}_{slug}.png", f"{ex.name} (seed {ex.seed})", curves, polygons, points=pts)
        results.append(Result(ex, dev, png))
    w = max(len(r.example.name) for r in results)
    print(f"{'example':{w}s}  {'seed':18s} {'max deviation':>13s} {'tolerance':>9s}  ok  oracle", file=stream)
    for r in results:
        e = r.example
        print(f"{e.name:{w}s}  {e.seed:18s} {r.deviation:13.2e} {e.tolerance:9.0e}  {'yes' if r.passed else 'NO ':3s} {e.oracle}",
              file=stream)
    if plots:
        print(f"PNG plots (curve, control polygon, curvature comb) in {out_dir}", file=stream)
    return results
