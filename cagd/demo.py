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
from typing import Callable, List, Optional, Sequence, TextIO, Tuple

import numpy as np

from ._atomic import write_file
from .errors import CagdError
from .basis.bernstein import bezier_matrix
from .basis.bspline import cox_de_boor
from .curves.base import Curve
from .curves.bezier import BezierCurve
from .curves.bspline import BSplineCurve
from .curves.composite import CompositeCurve
from .curves.cubic_spline import natural_cubic_spline
from .curves.hermite import HermiteCurve, hermite_basis
from .curves.polynomial import HERMITE_M, PolynomialCurve, four_point_cubic
from .fitting import bezier_through_points
from .operations import continuity, join

T = np.linspace(0.0, 1.0, 201)


Builder = Callable[[], Tuple[float, Sequence[Curve], Sequence[np.ndarray], Optional[np.ndarray]]]


@dataclass
class Example:
    name: str
    seed: str
    oracle: str
    tolerance: float
    build: Builder


@dataclass
class Result:
    example: Example
    deviation: float
    png: Optional[Path]

    @property
    def passed(self) -> bool:
        return self.deviation <= self.example.tolerance


EXAMPLES: List[Example] = []


def example(name: str, seed: str, oracle: str, tolerance: float = 1e-12) -> Callable[[Builder], Builder]:
    def register(fn: Builder) -> Builder:
        EXAMPLES.append(Example(name, seed, oracle, tolerance, fn))
        return fn
    return register


def _rel(a: np.ndarray, b: np.ndarray, size: Optional[float] = None) -> float:
    if size is None:
        size = max(float(np.ptp(np.asarray(b).reshape(-1, np.shape(b)[-1]), axis=0).max()), 1.0)
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


@example("uniform quadratic B-spline, knots 0..6", "000 5.3.2",
         "p_start = (P0+P1)/2, p'_start = P1-P0; Cox-de Boor sum")
def _quadratic_bspline():
    P = np.array([[0, 0], [1, 2], [3, 2], [4, 0.0]])
    c = BSplineCurve(P, 2, np.arange(7.0))
    t = np.linspace(2, 4, 201)
    dev = max(_rel(c(2.0), (P[0] + P[1]) / 2), _rel(c(4.0), (P[2] + P[3]) / 2),
              _rel(c.derivative(2.0), P[1] - P[0]), _rel(c.derivative(4.0), P[3] - P[2]),
              _rel(c(t[:-1]), cox_de_boor(c.knots, 2, t[:-1]) @ P))
    return dev, [c], [P], None


@example("non-uniform NURBS: knot insertion and degree elevation", "Piegl & Tiller 5.2, 5.5",
         "same samples before/after")
def _refine():
    P = np.array([[0, 0], [1, 2], [2, -1], [3, 3], [5, 1], [6, 2.0]])
    c = BSplineCurve(P, 3, [0, 0, 0, 0, .3, .7, 1, 1, 1, 1], [1, 2, .5, 1, 3, 1])
    r = c.insert_knot(0.5, 2).elevate(1)
    return _rel(r(T), c(T)), [c], [P, r.control_points], None


@example("Hermite segment, k0 = k1 = 20 and 80 (loop)", "004 1.3; 000 5.1.2", "p = P0 H0 + P1 H1 + R0 H2 + R1 H3")
def _hermite():
    p0, p1 = np.array([4.0, 4.0, 0.0]), np.array([24.0, 4.0, 0.0])
    d0, d1 = np.array([0.832, 0.5547, 0.0]), np.array([0.832, -0.5547, 0.0])
    curves, dev = [], 0.0
    for k in (20.0, 80.0):
        c = HermiteCurve.from_directions(p0, p1, d0, d1, k, k)
        H = hermite_basis(T)
        r0, r1 = k * d0 / np.linalg.norm(d0), k * d1 / np.linalg.norm(d1)
        dev = max(dev, _rel(c(T), H @ np.array([p0, p1, r0, r1])), _rel(c.to_nurbs()(T), c(T)))
        curves.append(c)
    return dev, curves, [], np.array([p0, p1])


@example("algebraic <-> geometric form of a cubic", "004 1.3 (A = M B, B = M^-1 A)",
         "Hermite matrix M_h applied by hand")
def _algebraic():
    A = np.array([[1.0, 0.0], [2.0, 3.0], [-1.0, 2.0], [0.5, -4.0]])      # a0..a3
    c = PolynomialCurve(A)
    B = c.to_hermite()                                                   # P0, P1, P0', P1'
    U = T[:, None] ** np.arange(3, -1, -1)
    return max(_rel(c(T), U @ HERMITE_M @ B), _rel(PolynomialCurve.from_hermite(B)(T), c(T))), [c], [], None


@example("four-point cubic", "004 contents (four-point curves)", "passes the points at u = 0, 1/3, 2/3, 1")
def _four_point():
    Q = np.array([[0.0, 0.0], [1.0, 1.5], [2.5, 1.0], [3.0, -0.5]])
    c = four_point_cubic(Q)
    return _rel(c(np.array([0, 1 / 3, 2 / 3, 1])), Q), [c], [], Q


def _second_derivative_jump(spline, periodic: bool = False) -> float:
    """Largest jump of p'' at the joints, from each span's own cubic in u = (t - t_j)/h_j:
    left limit (2 a2 + 6 a3)/h_j^2, right limit 2 a2/h_{j+1}^2 (relative to max |p''|)."""
    a = spline.unit_coefficients()
    h = np.diff(spline.parameters)[:, None]
    left = (2 * a[2] + 6 * a[3]) / h ** 2
    right = 2 * a[2] / h ** 2
    jump = right[1:] - left[:-1]
    if periodic:
        jump = np.vstack([jump, right[:1] - left[-1:]])
    return float(np.abs(jump).max() / np.abs(np.vstack([left, right])).max())


_DATA = np.array([[0.0, 0.0], [1.0, 1.2], [2.2, 1.4], [3.1, 0.3], [4.0, -0.4], [5.2, 0.6]])


@example("natural cubic spline, chord length", "000 5.1.2", "interpolation, C2 joints, p'' = 0 at both ends")
def _natural():
    c = natural_cubic_spline(_DATA, "natural", "chord")
    t = c.parameters
    d2 = c.derivative(np.array([t[0], t[-1]]), 2)
    dev = max(_rel(c(t), _DATA), float(np.abs(d2).max()), _second_derivative_jump(c),
              _rel(c.to_nurbs()(np.linspace(t[0], t[-1], 201)), c(np.linspace(t[0], t[-1], 201))))
    return dev, [c], [], _DATA


@example("cubic spline end conditions: clamped, virtual points, periodic", "000 5.1.2",
         "interpolation and the end condition")
def _end_conditions():
    clamped = natural_cubic_spline(_DATA, "clamped", "centripetal", tangents=([1.0, 2.0], [1.0, 1.0]))
    virtual = natural_cubic_spline(_DATA, "virtual", "uniform")
    closed = natural_cubic_spline(np.vstack([_DATA, _DATA[:1]]), "periodic", "chord")
    a, b = clamped.domain
    dev = max(_rel(clamped(clamped.parameters), _DATA), _rel(virtual(virtual.parameters), _DATA),
              _rel(clamped.derivative(np.array([a, b])), np.array([[1.0, 2.0], [1.0, 1.0]]), 1.0),
              _second_derivative_jump(closed, periodic=True),
              _rel(closed(closed.parameters[:-1]), _DATA))
    return dev, [clamped, virtual, closed], [], _DATA


@example("Bezier through points at t = i/n", "000 5.2.6", "the curve passes every given point")
def _inverse_bezier():
    c = bezier_through_points(_DATA[:5])
    return _rel(c(np.linspace(0, 1, 5)), _DATA[:5]), [c], [c.control_points], _DATA[:5]


@example("G2 join of two Bezier curves (alpha = 0.6, beta = 0.5)", "000 5.2.5", "measured curvature jump at the joint")
def _g2_join():
    P = BezierCurve(P4)
    Q = join(P, [[6.5, -2.0]], "G2", alpha=0.6, beta=0.5)
    rep = continuity(P, Q)
    dev = max(rep.gap, rep.tangent_angle, rep.curvature_difference / max(abs(P.curvature(1.0)), 1e-300))
    assert rep.G2, rep
    return dev, [P, Q], [P.control_points, Q.control_points], None


@example("composite curve -> one NURBS", "004 1.11 (composite curves)", "samples of the pieces")
def _composite():
    s = np.sqrt(0.5)
    arc = BezierCurve([[4.0, 0.5], [5.0, 1.5], [6.0, 0.5]], [1.0, s, 1.0])
    line = BezierCurve([[6.0, 0.5], [7.0, -0.5]])
    comp = CompositeCurve([BezierCurve(P4), arc, line])
    t = np.linspace(*comp.domain, 301)
    return _rel(comp.to_nurbs()(t), comp(t)), [comp], [], None


def run_demo(out_dir: Path, stream: Optional[TextIO] = None, plots: bool = True) -> List[Result]:
    """Run every example, write its PNG, print the table; return the results."""
    stream = sys.stdout if stream is None else stream
    out_dir = Path(out_dir)
    if plots:
        try:
            out_dir.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise CagdError(f"out_dir: cannot make the folder {str(out_dir)!r}: {exc.strerror or exc}") from None
    results = []
    for i, ex in enumerate(EXAMPLES, 1):
        print(f"[{i}/{len(EXAMPLES)}] {ex.name}", file=sys.stderr, flush=True)
        dev, curves, polygons, pts = ex.build()
        png = None
        if plots:
            from .plotting import plot_curves
            slug = "".join(ch if ch.isalnum() else "_" for ch in ex.name.lower()).strip("_")
            title = f"{ex.name} (seed {ex.seed})"
            png = write_file(out_dir / f"{i:02d}_{slug}.png",        # atomic: a picture is whole or absent
                             lambda temp: plot_curves(temp, title, curves, polygons, points=pts), "--output")
        results.append(Result(ex, dev, png))
    w = max(len(r.example.name) for r in results)
    print(f"{'example':{w}s}  {'seed':32s} {'max deviation':>13s} {'tolerance':>9s}  ok  oracle", file=stream)
    for r in results:
        e = r.example
        ok = "yes" if r.passed else "NO "
        print(f"{e.name:{w}s}  {e.seed:32s} {r.deviation:13.2e} {e.tolerance:9.0e}  {ok:3s} {e.oracle}", file=stream)
    if plots:
        print(f"PNG plots (curve, control polygon, curvature comb) in {out_dir}", file=stream)
    return results
