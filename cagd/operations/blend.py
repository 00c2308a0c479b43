"""Bridge (blend) curves between the ends of two curves, G1, G2 or G3 to both
(Farin, Curves and Surfaces for CAGD, 14.1 G1/G2 joins; seed 000, 5.2.5).

At c1's chosen end take the point P and the arc-length derivatives of c1 oriented
away from c1 into the gap: the unit tangent T = x', the curvature vector K = x'' =
kappa N and X = x''' = -kappa^2 T + kappa' N + kappa tau B (kappa' = d kappa / ds;
Frenet-Serret). From the curve's own derivatives c', c'', c''' (speed v = |c'|,
v' = c''.T): K = (c'' - v' T) / v^2 and, from c''' = v'' T + 3 v v' K + v^3 X,
X = perp_T(c''' - 3 v v' K) / v^3 - |K|^2 T (perp_T the part normal to T). Likewise
Q, U, L, Y at c2's end, oriented from the gap into c2. (Reversing a curve flips T and
X and keeps K.)

The bridge B is a Bezier curve of degree n = 2k + 1 (k = continuity: 3, 5 or 7) with
end speeds s0, s1 > 0 and no tangential acceleration: the chain rule for B(t) = x(s(t))
with s' = s0, s'' = s''' = 0 (the beta parameters of geometric continuity set to zero,
Farin 14.1 / seed 000, 5.2.5 with beta_2 = beta_3 = 0) gives the end derivatives

    B^(j)(0) = s0^j x^(j)(0)  (j = 1..k),   B^(j)(1) = s1^j y^(j),  y the c2 side,

and with Delta^j B_0 = B^(j)(0) (n - j)! / n! the first k + 1 control points are
B_j = sum_i C(j, i) Delta^i B_0; the last k + 1 likewise from the reversed bridge. So
B has T, K (G2: curvature and principal normal) and X (G3: also d kappa / ds and, in
3-D, the torsion) of both curves at its ends; the n + 1 = 2 k + 2 control points are
exactly these conditions.

Speeds s0 = a |Q - P|, s1 = b |Q - P|. With ``tangent_scales`` (a, b) given they are
used as they are ((1, 1): the first and last legs |Q - P| / n long, the chord-length
heuristic). By default (a, b) minimise the curvature-variation energy
E = L^3 int (d kappa / ds)^2 ds of the bridge (Moreton & Sequin's minimum-variation
functional, made scale-free by the cube of the bridge's length L, so that it does not
favour long detours; :func:`curvature_variation`) over the box SCALE_BOUNDS^2: the lowest
START_MINIMA local minima of a START_GRID x START_GRID log-spaced grid, each refined by a
bounded Nelder-Mead in (log a, log b) (at most MAX_ITERATIONS steps; the energy is not
convex in (a, b): several starts). (1, 1) is kept unless the energy drops
below its value there by more than ENERGY_TIE (two collinear tangents along the chord give
a straight bridge, energy 0, for every (a, b): the uniform segment is kept).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import comb, perm
from operator import index
from typing import Callable, Optional, Sequence, Tuple, Union

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..errors import CagdError
from .continuity import CONTINUITY_TOL, _angle, _curvature_vector, _norm, curve_size

#: an end derivative at most this times (curve size / domain length) counts as zero
#: (a degenerate end without a tangent), the threshold of :func:`continuity`'s G1 test
TANGENT_ZERO_TOL = 1e-12
#: end points closer than this times the size of both curves count as coincident
COINCIDENT_TOL = 1e-12
#: the box of the automatic tangent scales a, b (times the chord |Q - P|)
SCALE_BOUNDS = (0.1, 4.0)
#: points per axis of the log-spaced grid the automatic search starts from
START_GRID = 17
#: the search refines at most this many of the grid's local minima
START_MINIMA = 3
#: bound on the Nelder-Mead steps of the automatic search
MAX_ITERATIONS = 300
#: the search stops when the simplex is this small in (log a, log b)
SIMPLEX_TOL = 1e-10
#: the automatic scales leave (1, 1) only for an energy lower by more than this relative
#: to its value at (1, 1), plus ENERGY_FLOOR
ENERGY_TIE = 1e-12
#: energies below this are rounding (a straight bridge)
ENERGY_FLOOR = 1e-20
#: Gauss-Legendre panels and nodes per panel of the energy quadrature
ENERGY_PANELS = 32
ENERGY_NODES = 8
_ENDS = ("start", "end")


@dataclass(frozen=True)
class BlendCurve:
    """A bridge curve and what it achieves at both ends.

    curve: the Bezier bridge (degree 3 for G1, 5 for G2, 7 for G3), curve(0) = c1's end,
    curve(1) = c2's end; g1_angles: angles (radians) between the bridge's tangent and
    the oriented end tangent of c1 (at 0) and c2 (at 1); curvature_gaps: relative
    differences |K_bridge - K_curve| / max(|K_bridge|, |K_curve|, 1 / size) of the
    curvature vectors there (size: bounding-box diagonal of c1 and c2);
    curvature_derivative_gaps: |X_bridge - X_curve| / max(|X_bridge|, |X_curve|,
    1 / size^2) of the third arc-length derivatives X = x''' (the G3 measure: curvature,
    d kappa / ds and torsion), all measured for every continuity (guaranteed small only
    up to the requested one); tangent_scales: the (a, b) used (given or automatic);
    energy: the bridge's scale-free curvature variation L^3 int (d kappa / ds)^2 ds
    (:func:`curvature_variation`);
    converged: the requested measurements within CONTINUITY_TOL; message: a summary.
    """
    curve: BezierCurve
    g1_angles: Tuple[float, float]
    curvature_gaps: Tuple[float, float]
    continuity: int
    converged: bool
    message: str
    curvature_derivative_gaps: Tuple[float, float] = (float("nan"), float("nan"))
    tangent_scales: Tuple[float, float] = (1.0, 1.0)
    energy: float = float("nan")


def _arc_derivatives(D: np.ndarray) -> np.ndarray:
    """(T, K, X): the arc-length derivatives x', x'', x''' from the parametric c', c'', c'''
    = D[1], D[2], D[3] (module docstring)."""
    v = _norm(D[1])
    T = D[1] / v
    K = _curvature_vector(D[1], D[2])
    W = D[3] - (3.0 * v * float(D[2] @ T)) * K
    with np.errstate(over="ignore", under="ignore"):
        X = (W - (W @ T) * T) / v / v / v - float(K @ K) * T
    return np.stack([T, K, X])


def _end(c: Curve, end: object, name: str, end_name: str, sign: int) -> Tuple[np.ndarray, np.ndarray]:
    """(point, (T, K, X)) at an end, oriented along ``sign`` times c's own direction."""
    if not isinstance(end, str) or end not in _ENDS:
        raise CagdError(f"{end_name}: must be 'start' or 'end', got {end!r}")
    a, b = c.domain
    t = b if end == "end" else a
    D = c.derivatives(t, 3)
    if _norm(D[1]) <= TANGENT_ZERO_TOL * curve_size(c) / (b - a):
        raise CagdError(f"{name}: its first derivative vanishes at its {end} (t = {t!r}): a degenerate end "
                        f"has no tangent to match ({end_name} = {end!r})")
    D = D * np.array([1.0, sign, 1.0, sign])[:, None]
    return c(t), _arc_derivatives(D)   # c(t): the point as evaluated (D[0] may differ by an ulp)


def _relative_gap(a: np.ndarray, b: np.ndarray, floor: float) -> float:
    """|a - b| / max(|a|, |b|, floor) (the relative measure of :func:`continuity`'s G2 test)."""
    return _norm(a - b) / max(_norm(a), _norm(b), floor)


def _scales(tangent_scales: Optional[Sequence[float]]) -> Optional[Tuple[float, float]]:
    if tangent_scales is None:
        return None
    try:
        a, b = tangent_scales
    except (TypeError, ValueError):
        raise CagdError(f"tangent_scales: must be two positive numbers (a, b), got {tangent_scales!r}") from None
    return _checks.positive(a, "tangent_scales[0]"), _checks.positive(b, "tangent_scales[1]")


def _continuity(value: object, allowed: Tuple[int, ...] = (1, 2, 3),
                what: str = "1: G1, a cubic bridge; 2: G2, a quintic; 3: G3, degree 7") -> int:
    """``value`` as an int of ``allowed`` (not a bool), else CagdError naming continuity."""
    try:
        k = index(value)  # type: ignore[arg-type]
    except TypeError:
        k = -1
    if isinstance(value, (bool, np.bool_)) or k not in allowed:
        raise CagdError(f"continuity: must be one of {allowed} ({what}), got {value!r}")
    return k


def _from_derivatives(D: Sequence[np.ndarray], n: int) -> np.ndarray:
    """The first len(D) control points (axis -2) of degree-n Bezier curves with B^(j)(0) = D[j]
    (each (..., dim)): Delta^j B_0 = D[j] (n - j)! / n!, B_j = sum_i C(j, i) Delta^i B_0 (Farin 5.3)."""
    delta = [D[j] / perm(n, j) for j in range(len(D))]
    return np.stack([sum(comb(j, i) * delta[i] for i in range(j + 1)) for j in range(len(D))], axis=-2)


def _bridge(P: np.ndarray, A: np.ndarray, Q: np.ndarray, C: np.ndarray, s0: Union[float, np.ndarray],
            s1: Union[float, np.ndarray], k: int) -> np.ndarray:
    """Control points (..., 2k + 2, dim) of the degree 2k+1 bridges with end speeds s0, s1 (arrays
    of one shape; module docstring); A = (T, K, X) at P, C = (U, L, Y) at Q, oriented along the bridge."""
    n = 2 * k + 1
    s0, s1 = np.asarray(s0, dtype=float)[..., None], np.asarray(s1, dtype=float)[..., None]
    B = np.empty(s0.shape[:-1] + (n + 1, P.shape[0]))
    B[..., :k + 1, :] = _from_derivatives([P + 0.0 * s0] + [s0 ** j * A[j - 1] for j in range(1, k + 1)], n)
    B[..., n - k:, :] = _from_derivatives([Q + 0.0 * s1] + [(-s1) ** j * C[j - 1] for j in range(1, k + 1)],
                                          n)[..., ::-1, :]
    return B


_GL_X, _GL_W = np.polynomial.legendre.leggauss(ENERGY_NODES)
#: quadrature nodes and weights on [0, 1] (ENERGY_PANELS Gauss-Legendre panels)
_NODES = ((np.arange(ENERGY_PANELS)[:, None] + 0.5 * (_GL_X[None, :] + 1.0)) / ENERGY_PANELS).ravel()
_WEIGHTS = np.tile(_GL_W / (2.0 * ENERGY_PANELS), ENERGY_PANELS)


def _variation(D1: np.ndarray, D2: np.ndarray, D3: np.ndarray) -> np.ndarray:
    """L^3 int (d kappa / ds)^2 ds from c', c'', c''' at the nodes (shape (..., nodes, dim)),
    on a unit domain: v = |c'|, T = c' / v, w = c'' - (c''.T) T, kappa = |w| / v^2,
    d kappa / dt = (w^.c''') / v^2 - 3 |w| (T.c'') / v^3 (w^ = w / |w|, 0 where w = 0),
    ds = v dt, L = int v dt; inf where c' vanishes at a node (a cusp)."""
    v = np.linalg.norm(D1, axis=-1)
    bad = ~(v > 0.0)
    v = np.where(bad, 1.0, v)
    T = D1 / v[..., None]
    tan = np.einsum("...i,...i->...", D2, T)
    w = D2 - tan[..., None] * T
    wn = np.linalg.norm(w, axis=-1)
    what = w / np.where(wn > 0.0, wn, 1.0)[..., None]
    dk = np.einsum("...i,...i->...", what, D3) / v ** 2 - 3.0 * wn * tan / v ** 3
    with np.errstate(over="ignore"):
        E = np.sum(_WEIGHTS * dk * dk / v, axis=-1) * np.sum(_WEIGHTS * v, axis=-1) ** 3
    return np.where(np.any(bad, axis=-1), np.inf, E)


def curvature_variation(curve: Curve) -> float:
    """The scale-free curvature variation L^3 int (d kappa / ds)^2 ds of a curve over its
    domain (L its length; Moreton & Sequin 1992 times L^3), by Gauss-Legendre quadrature
    (ENERGY_PANELS panels of ENERGY_NODES nodes), the formula of the module's energy.

    Raises:
        CagdError: not a cagd Curve."""
    if not isinstance(curve, Curve):
        raise CagdError(f"curve: must be a cagd Curve, got {type(curve).__name__}")
    a, b = curve.domain
    D = curve.derivatives(a + (b - a) * _NODES, 3)
    return float(_variation(D[1], D[2], D[3]))            # invariant under the map to [0, 1]


@lru_cache(maxsize=8)
def _bernstein_derivatives(n: int) -> Tuple[np.ndarray, ...]:
    """M_j (j = 1, 2, 3): B^(j)(nodes) = M_j @ B for degree-n control points B
    (B^(j) = n! / (n-j)! sum_i Delta^j B_i b_i^(n-j); Farin 5.3)."""
    out = []
    for j in (1, 2, 3):
        m = n - j
        i = np.arange(m + 1)
        basis = np.array([comb(m, q) for q in i]) * _NODES[:, None] ** i * (1.0 - _NODES[:, None]) ** (m - i)
        diff = np.eye(n + 1)
        for _ in range(j):
            diff = np.diff(diff, axis=0)
        out.append(perm(n, j) * basis @ diff)
    return tuple(out)


def _bridge_variation(B: np.ndarray) -> np.ndarray:
    """:func:`curvature_variation` of the Bezier curves with control points B (..., n + 1, dim)."""
    M1, M2, M3 = _bernstein_derivatives(B.shape[-2] - 1)
    return _variation(M1 @ B, M2 @ B, M3 @ B)


def _nelder_mead(f: Callable[[np.ndarray], float], x0: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """A bounded Nelder-Mead (coefficients 1, 2, 1/2, 1/2; points clipped to [lo, hi]^2),
    at most MAX_ITERATIONS steps, stopping when the simplex is within SIMPLEX_TOL."""
    def clip(x: np.ndarray) -> np.ndarray:
        return np.clip(x, lo, hi)

    step = 0.05 * (hi - lo)
    S = [clip(x0), clip(x0 + [step, 0.0]), clip(x0 + [0.0, step])]
    if np.array_equal(S[1], S[0]):
        S[1] = clip(x0 - [step, 0.0])
    if np.array_equal(S[2], S[0]):
        S[2] = clip(x0 - [0.0, step])
    F = [f(x) for x in S]
    for _ in range(MAX_ITERATIONS):
        order = np.argsort(F, kind="stable")
        S, F = [S[i] for i in order], [F[i] for i in order]
        if max(np.max(np.abs(S[i] - S[0])) for i in (1, 2)) <= SIMPLEX_TOL:
            break
        centre = 0.5 * (S[0] + S[1])
        xr = clip(2.0 * centre - S[2])
        fr = f(xr)
        if fr < F[0]:
            xe = clip(3.0 * centre - 2.0 * S[2])
            fe = f(xe)
            S[2], F[2] = (xe, fe) if fe < fr else (xr, fr)
        elif fr < F[1]:
            S[2], F[2] = xr, fr
        else:
            xc = clip(0.5 * (centre + (xr if fr < F[2] else S[2])))
            fc = f(xc)
            if fc < min(fr, F[2]):
                S[2], F[2] = xc, fc
            else:
                for i in (1, 2):
                    S[i] = 0.5 * (S[0] + S[i])
                    F[i] = f(S[i])
    return S[int(np.argmin(F))]


def _automatic(energy: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> Tuple[float, float]:
    """The tangent scales of least ``energy`` (vectorized over scales a, b) in SCALE_BOUNDS^2:
    Nelder-Mead in logs from each of the START_MINIMA lowest local minima of a log-spaced
    START_GRID^2 grid; (1, 1) unless beaten by more than ENERGY_TIE (module docstring)."""
    lo, hi = np.log(SCALE_BOUNDS[0]), np.log(SCALE_BOUNDS[1])

    def f(x: np.ndarray) -> float:
        return float(energy(np.exp(x[0]), np.exp(x[1])))

    e1 = float(energy(np.ones(()), np.ones(())))
    g = np.linspace(lo, hi, START_GRID)
    E = energy(np.exp(g)[:, None], np.exp(g)[None, :])
    padded = np.pad(E, 1, constant_values=np.inf)
    neighbours = np.min([padded[1 + i:1 + i + START_GRID, 1 + j:1 + j + START_GRID]
                         for i in (-1, 0, 1) for j in (-1, 0, 1) if i or j], axis=0)
    minima = np.flatnonzero((E <= neighbours).ravel() & np.isfinite(E).ravel())
    minima = minima[np.argsort(E.ravel()[minima], kind="stable")][:START_MINIMA]
    best, x = e1, None
    for m in minima:
        y = _nelder_mead(f, np.array([g[m // START_GRID], g[m % START_GRID]]), lo, hi)
        fy = f(y)
        if fy < best:
            best, x = fy, y
    if x is not None and best < e1 * (1.0 - ENERGY_TIE) - ENERGY_FLOOR:
        return float(np.exp(x[0])), float(np.exp(x[1]))
    return 1.0, 1.0


def blend_curve(c1: Curve, end1: str, c2: Curve, end2: str, continuity: int = 1,
                tangent_scales: Optional[Sequence[float]] = None) -> BlendCurve:
    """A Bezier bridge from c1's ``end1`` to c2's ``end2`` ("start" or "end"), G1
    (``continuity=1``, cubic), G2 (``2``, quintic) or G3 (``3``, degree 7) to both;
    control points from the end derivatives with zero beta parameters (module docstring;
    Farin 14.1, seed 000, 5.2.5), speeds s0 = a |Q - P|, s1 = b |Q - P| with (a, b) =
    ``tangent_scales``, or by default those of least curvature variation
    (:func:`curvature_variation`, reported in the result).

    Raises:
        CagdError: c1/c2 not cagd curves, of different dimensions, end1/end2 not
            "start"/"end", continuity not 1, 2 or 3, a vanishing end derivative (naming the
            curve), tangent_scales not two positive finite numbers, coincident end points.
    """
    for name, c in (("c1", c1), ("c2", c2)):
        if not isinstance(c, Curve):
            raise CagdError(f"{name}: must be a cagd Curve, got {type(c).__name__}")
    if c1.dim != c2.dim:
        raise CagdError(f"c2: dimension {c2.dim} differs from c1's {c1.dim}")
    k = _continuity(continuity)
    given = _scales(tangent_scales)
    P, A = _end(c1, end1, "c1", "end1", 1 if end1 == "end" else -1)
    Q, C = _end(c2, end2, "c2", "end2", 1 if end2 == "start" else -1)
    size = curve_size(c1, c2)
    with np.errstate(over="ignore"):
        chord = _norm(0.5 * Q - 0.5 * P) * 2.0
    if not chord > COINCIDENT_TOL * size:
        raise CagdError(f"end2: c2's {end2} point coincides with c1's {end1} point (distance {chord:.3g}); "
                        f"a bridge needs two distinct end points")

    def energy(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        a, b = np.broadcast_arrays(a, b)
        return _bridge_variation(_bridge(P, A, Q, C, a * chord, b * chord, k))

    sa, sb = given if given is not None else _automatic(energy)
    bridge = BezierCurve(_bridge(P, A, Q, C, sa * chord, sb * chord, k))
    E0, E1 = (_arc_derivatives(bridge.derivatives(t, 3)) for t in (0.0, 1.0))
    angles = (_angle(E0[0], A[0]), _angle(E1[0], C[0]))
    gaps = (_relative_gap(E0[1], A[1], 1.0 / size), _relative_gap(E1[1], C[1], 1.0 / size))
    gaps3 = (_relative_gap(E0[2], A[2], size ** -2), _relative_gap(E1[2], C[2], size ** -2))
    measured = [max(angles), max(gaps), max(gaps3)][:k]
    converged = bool(max(measured) <= CONTINUITY_TOL)
    E = float(_bridge_variation(bridge.control_points))     # = curvature_variation(bridge), faster
    message = (f"G{k} bridge of degree {2 * k + 1}, tangent scales ({sa:.6g}, {sb:.6g})"
               f"{'' if given is not None else ' (least curvature variation)'}: tangent angles "
               f"{angles[0]:.3g}, {angles[1]:.3g} rad, relative curvature gaps {gaps[0]:.3g}, {gaps[1]:.3g}, "
               f"curvature-derivative gaps {gaps3[0]:.3g}, {gaps3[1]:.3g}, energy {E:.6g}"
               + ("" if converged else f" (above the tolerance {CONTINUITY_TOL:g})"))
    return BlendCurve(bridge, angles, gaps, k, converged, message, gaps3, (sa, sb), E)
