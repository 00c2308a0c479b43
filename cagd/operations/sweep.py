"""Sweep surfaces: a profile moved along a path (one rail) or placed between two rails.

One rail: with c(t) the path on its domain mapped to t in [0, 1], F(t) = [T r s] an
orthonormal frame (columns: unit tangent, normal, binormal), s(t) the scale law and
theta(t) the twist law (radians about T), the true sweep of the profile C(u) is

    S(u, t) = c(t) + M(t) (C(u) - c(0)),   M(t) = s(t) F(t) R_T(theta(t)) F(0)^T,

R_T(theta) the rotation by theta about the first axis. M(t) is a similarity, so it maps
the profile's control points exactly (weights unchanged): at every station t_k the moved
poles Q_i(t_k) = c(t_k) + M(t_k) (P_i - c(0)) with the profile's knots, degree and weights
are the swept profile. Along t the pole trajectories Q_i(t) are interpolated by cubic
B-splines (Piegl & Tiller 9.2.1) with the surface weights W_ij = w_i, so that
S(u, t) - S_true(u, t) is a convex combination of Q_i(t) - Q_i^true(t): the largest pole
miss at a check parameter bounds the surface's error there for every u. Stations are
bisected (a bounded loop) until that bound is within ``tol`` at the check parameters
(k/8, k = 1..7, of every station interval; the worst intervals at 63 points). When M(t)
is constant (the "fixed" frame, or a straight path, with constant laws) the sweep is the
translational surface with the path's own knots, exact: poles M (P_i - c(0)) + c_j, weights w_i v_j.
When the path is an arc of a circle (centre O, axis a; a rational curve on it, found by
:func:`_circle`), the laws are constant and the frame turns rigidly with the path ("rmf" and
"frenet": a planar path's rotation-minimising frame is its Frenet frame up to a constant
turn; an up vector along a), M(t) = Rot_a(phi(t)) M(0): the sweep is the surface of
revolution of the placed profile c(0) + M(0) (C(u) - c(0)) by the path's own rational
circle, built exactly (:func:`_revolution`; a torus for a circle profile about a circle).
Both exact cases report the measured distance to the true sweep (rounding).

Frames: "rmf", the rotation-minimising frame by double reflection (Wang, Juettler, Zheng,
Liu 2008, "Computation of rotation minimizing frames", ACM TOG 27(1), Algorithm 1) on a
reference grid of RMF_SAMPLES intervals, carried to any t by one more double-reflection
step; "frenet" (Frenet-Serret frame, CagdError where the curvature vanishes); "fixed"
(F = I: the profile translated); an up vector a: r = (a - (a.T) T) / |a - (a.T) T|.

Two rails: at each t the profile is mapped by the similarity taking its end points onto
rail1(t) and rail2(t): S(u, t) = a(t) + |b(t) - a(t)| G(t) L(u), a, b the rails, G(t) the
frame whose first axis is the chord direction d = (b - a)/|b - a|, transported along t by
minimal rotations (the rotation-minimising frame of the chord direction), L the profile in
its chord frame (scaled to unit chord); several profiles are blended by interpolating their
local control points L_k over their rail parameters (cubic where there are four or more).
"""
from __future__ import annotations

from dataclasses import dataclass
from numbers import Real
from typing import Callable, Optional, Sequence, Tuple, Union

import numpy as np

from .. import _checks
from .._results import ReadOnlyArrays
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..fitting.interpolation import collocate
from ..knots import vectors as kv
from ..surfaces.bspline import BSplineSurface

#: default distance tolerance of the sweeps (model units)
SWEEP_TOL = 1e-6
#: intervals of the reference grid on which the rotation-minimising frame is computed
RMF_SAMPLES = 4096
#: bound on the station-bisection passes
MAX_REFINEMENTS = 14
#: bound on the number of stations along the path
MAX_STATIONS = 4097
#: initial number of station intervals
INITIAL_INTERVALS = 8
#: degree of the interpolation along the path
PATH_DEGREE = 3
#: a path derivative below this times (path size / domain length) counts as vanishing
TANGENT_ZERO_TOL = 1e-12
#: a double-reflection step shorter than this share of its points' magnitude is a
#: coincident point (no reflection: the frame is carried over); a step at rounding level
#: has a direction of noise, and a reflection across its plane is no small change (at a
#: station 3e-17 past a grid point the frame turned by 0.3 rad)
RMF_STEP_RTOL = 1e-8
#: at a coincident point, a tangent change of less than this (unit tangents) is rounding
#: (the frame is carried over, projected normal to the new tangent); a larger one (a kink
#: of the path) is reflected once, tangent onto tangent
RMF_TURN_TOL = 1e-8
#: a curvature below this divided by the path size counts as zero (no Frenet normal)
CURVATURE_ZERO_TOL = 1e-9
#: an up vector whose component normal to the tangent is below this (relative) is parallel
UP_PARALLEL_TOL = 1e-9
#: control points within this times the path size of a line count as collinear
STRAIGHT_TOL = 1e-14
#: where in every station interval the error is measured (the checks)
CHECK_FRACTIONS = tuple(k / 8.0 for k in range(1, 8))

Law = Union[float, Callable[[float], float], None]
#: intervals within this factor of the largest check error are measured densely
DENSE_NEAR = 0.5
#: at most this many intervals are measured densely per pass
DENSE_INTERVALS = 32
#: samples in each densely measured interval
DENSE_SAMPLES = 63

_FRAMES = ("rmf", "frenet", "fixed")


@dataclass(frozen=True)
class SweepResult(ReadOnlyArrays):
    """A swept surface and its measured accuracy.

    surface: the B-spline/NURBS surface, u along the profile (its knots, degree and
    weights), v in [0, 1] along the path (rails); max_error: the largest distance bound
    between the surface and the true sweep at the check parameters (module docstring), plus
    the estimated error of the sampled rotation-minimising frame; tol: the requested
    distance; converged: max_error <= tol; message: a summary.
    """
    surface: BSplineSurface
    max_error: float
    tol: float
    converged: bool
    message: str


# --- argument checks ---------------------------------------------------------------------
def _curve3(c: object, name: str) -> BSplineCurve:
    if not isinstance(c, Curve):
        raise CagdError(f"{name}: must be a cagd Curve, got {type(c).__name__}")
    if c.dim != 3:
        raise CagdError(f"{name}: must be a 3-D curve, got dimension {c.dim}")
    return c.to_nurbs()


def _tol(tol: object) -> float:
    return _checks.positive(tol, "tol")


def _size(points: np.ndarray) -> float:
    span = np.ptp(points.reshape(-1, points.shape[-1]), axis=0)
    return float(max(np.linalg.norm(span), np.finfo(float).tiny))


def _law(law: Law, name: str, t: np.ndarray, positive: bool) -> np.ndarray:
    """Values of a law (None, a constant or a callable of t in [0, 1]) at the parameters t."""
    default = 1.0 if positive else 0.0
    if law is None:
        return np.full(t.shape, default)
    if callable(law):
        out = np.empty(t.shape)
        for k, tk in enumerate(t):
            try:
                out[k] = float(law(float(tk)))
            except (TypeError, ValueError) as exc:
                raise CagdError(f"{name}: the law must return a number at t = {tk!r} ({exc})") from None
        bad = ~np.isfinite(out) | ((out <= 0.0) if positive else False)
        if np.any(bad):
            k = int(np.argmax(bad))
            what = "a positive finite number" if positive else "a finite number"
            raise CagdError(f"{name}: the law must return {what}, got {out[k]!r} at t = {t[k]!r}")
        return out
    if isinstance(law, bool) or not isinstance(law, Real):
        raise CagdError(f"{name}: must be None, a number or a callable of t in [0, 1], got {type(law).__name__}")
    v = _checks.positive(law, name) if positive else _checks.scalar(law, name)
    return np.full(t.shape, v)


# --- frames ------------------------------------------------------------------------------
def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def _unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _reflect_step(x0: np.ndarray, t0: np.ndarray, r0: np.ndarray, x1: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """One double-reflection step (Wang et al. 2008, Algorithm 1): the normal at x1 from
    (x0, t0, r0); vectorized over leading axes. Points coincident to RMF_STEP_RTOL skip
    the first reflection, and the second one too where the tangents agree to RMF_TURN_TOL."""
    v1 = x1 - x0
    c1 = _dot(v1, v1)[..., None]
    step = c1 > RMF_STEP_RTOL ** 2 * (_dot(x0, x0) + _dot(x1, x1))[..., None]
    safe1 = np.where(step, c1, 1.0)
    rL = np.where(step, r0 - (2.0 / safe1) * _dot(v1, r0)[..., None] * v1, r0)
    tL = np.where(step, t0 - (2.0 / safe1) * _dot(v1, t0)[..., None] * v1, t0)
    v2 = t1 - tL
    c2 = _dot(v2, v2)[..., None]
    turn = step | (c2 > RMF_TURN_TOL ** 2)
    safe2 = np.where(turn & (c2 > 0.0), c2, 1.0)
    r1 = np.where(turn & (c2 > 0.0), rL - (2.0 / safe2) * _dot(v2, rL)[..., None] * v2, rL)
    r1 = r1 - _dot(r1, t1)[..., None] * t1                  # re-orthogonalise (rounding only)
    return _unit(r1)


def _any_normal(T: np.ndarray) -> np.ndarray:
    """A unit vector normal to the unit vector T."""
    e = np.zeros(3)
    e[int(np.argmin(np.abs(T)))] = 1.0
    return _unit(e - _dot(e, T) * T)


class _Path:
    """The path on t in [0, 1]: points, unit tangents, frames."""

    def __init__(self, path: BSplineCurve, frame: object):
        self.curve = path
        self.a, self.b = path.domain
        self.size = _size(path.control_points)
        self.frame = self._frame_kind(frame)
        self.grid = np.linspace(0.0, 1.0, RMF_SAMPLES + 1)
        self.gx, self.gT = self.points_tangents(self.grid)
        self.rmf_error = 0.0
        if self.frame == "rmf":
            self.gr = self._rmf(self.gx, self.gT)
            coarse = self._rmf(self.gx[::2], self.gT[::2])
            cosines = np.clip(_dot(coarse, self.gr[::2]), -1.0, 1.0)
            self.rmf_error = float(np.max(np.arccos(cosines)))   # radians, Richardson-type estimate

    def _frame_kind(self, frame: object):
        if isinstance(frame, str):
            if frame not in _FRAMES:
                raise CagdError(f"frame: must be 'rmf', 'frenet', 'fixed' or an up vector (3 numbers), got {frame!r}")
            return frame
        try:
            up = np.asarray(frame, dtype=float)
        except (TypeError, ValueError):
            raise CagdError(f"frame: must be 'rmf', 'frenet', 'fixed' or an up vector (3 numbers), "
                            f"got {type(frame).__name__}") from None
        if up.shape != (3,) or not np.all(np.isfinite(up)) or not np.linalg.norm(up) > 0.0:
            raise CagdError(f"frame: an up vector must be 3 finite numbers, not all zero, got {frame!r}")
        self.up = up / np.linalg.norm(up)
        return "up"

    def param(self, t: np.ndarray) -> np.ndarray:
        return np.clip(self.a + t * (self.b - self.a), self.a, self.b)

    def points_tangents(self, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        D = self.curve.derivatives(self.param(t), 1)
        speed = np.linalg.norm(D[1], axis=-1)
        small = speed <= TANGENT_ZERO_TOL * self.size / (self.b - self.a)
        if np.any(small):
            k = int(np.argmax(small))
            raise CagdError(f"path: degenerate, its first derivative vanishes at t = {float(t[k])!r} "
                            f"(normalised to [0, 1]): no tangent to sweep along")
        return D[0], D[1] / speed[:, None]

    def _rmf(self, x: np.ndarray, T: np.ndarray) -> np.ndarray:
        r = np.empty_like(x)
        r[0] = _any_normal(T[0])
        for k in range(len(x) - 1):
            r[k + 1] = _reflect_step(x[k], T[k], r[k], x[k + 1], T[k + 1])
        return r

    def frames(self, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(points (m, 3), frames (m, 3, 3) with columns T, r, s) at t in [0, 1]."""
        x, T = self.points_tangents(t)
        if self.frame == "fixed":
            return x, np.broadcast_to(np.eye(3), (len(t), 3, 3)).copy()
        if self.frame == "rmf":
            k = np.clip(np.searchsorted(self.grid, t, side="right") - 1, 0, RMF_SAMPLES)
            r = _reflect_step(self.gx[k], self.gT[k], self.gr[k], x, T)
        elif self.frame == "frenet":
            D = self.curve.derivatives(self.param(t), 2)
            c = np.cross(D[1], D[2])
            kappa = np.linalg.norm(c, axis=-1) / np.linalg.norm(D[1], axis=-1) ** 3
            flat = kappa * self.size <= CURVATURE_ZERO_TOL
            if np.any(flat):
                k0 = int(np.argmax(flat))
                raise CagdError(f"frame: 'frenet' needs a curved path, the path's curvature vanishes at "
                                f"t = {float(t[k0])!r} (normalised to [0, 1]); use 'rmf' or an up vector")
            B = _unit(c)
            r = np.cross(B, T)
        else:
            n = self.up - _dot(T, self.up)[:, None] * T
            length = np.linalg.norm(n, axis=-1)
            par = length <= UP_PARALLEL_TOL
            if np.any(par):
                k0 = int(np.argmax(par))
                raise CagdError(f"frame: the up vector {self.up.tolist()} is parallel to the path tangent at "
                                f"t = {float(t[k0])!r} (normalised to [0, 1])")
            r = n / length[:, None]
        return x, np.stack([T, r, np.cross(T, r)], axis=-1)

    def straight(self) -> bool:
        """All control points on one line and the tangent never reversing."""
        P = self.curve.control_points
        d = P[-1] - P[0]
        if not np.linalg.norm(d) > 0.0:
            return False
        e = d / np.linalg.norm(d)
        off = (P - P[0]) - np.outer((P - P[0]) @ e, e)
        if np.max(np.linalg.norm(off, axis=-1)) > STRAIGHT_TOL * self.size:
            return False
        return bool(np.all(self.gT @ e > 0.0))


def _rot_x(theta: np.ndarray) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    R = np.zeros(theta.shape + (3, 3))
    R[..., 0, 0] = 1.0
    R[..., 1, 1], R[..., 1, 2], R[..., 2, 1], R[..., 2, 2] = c, -s, s, c
    return R


# --- the interpolation along the path -----------------------------------------------------
def _fit_stations(t: np.ndarray, Q: np.ndarray) -> BSplineCurve:
    """The cubic (or lower) interpolant of the flattened poles Q (m, n*3) at stations t."""
    p = min(PATH_DEGREE, len(t) - 1)
    return collocate(Q, p, t, kv.averaged(t, p))


def _checks_between(t: np.ndarray) -> np.ndarray:
    f = np.asarray(CHECK_FRACTIONS)
    return (t[:-1, None] + f[None, :] * np.diff(t)[:, None]).ravel()


def _refine(moved: Callable[[np.ndarray], np.ndarray], start: np.ndarray, tol: float
            ) -> Tuple[BSplineCurve, float, bool, int]:
    """Bisect stations until the interpolated pole trajectories are within tol of the true
    ones at the check parameters; (curve, largest miss, hit the cap, station count)."""
    t = start
    best: Optional[Tuple[float, BSplineCurve, int]] = None
    for _ in range(MAX_REFINEMENTS + 1):
        curve = _fit_stations(t, moved(t).reshape(len(t), -1))
        tc = _checks_between(t)
        miss = np.linalg.norm((curve(tc) - moved(tc).reshape(len(tc), -1)).reshape(len(tc), -1, 3), axis=-1)
        per = miss.max(axis=1).reshape(len(t) - 1, len(CHECK_FRACTIONS)).max(axis=1)
        per = _densely(curve, moved, t, per)
        err = float(per.max())
        if best is None or err < best[0]:
            best = (err, curve, len(t))
        bad = per > tol
        if not np.any(bad):
            return curve, err, False, len(t)
        if len(t) + int(bad.sum()) > MAX_STATIONS:
            break
        t = np.sort(np.concatenate([t, 0.5 * (t[:-1][bad] + t[1:][bad])]))
    assert best is not None
    return best[1], best[0], True, best[2]


def _densely(curve: BSplineCurve, moved: Callable[[np.ndarray], np.ndarray], t: np.ndarray,
             per: np.ndarray) -> np.ndarray:
    """The per-interval errors with the worst intervals (within a factor DENSE_NEAR of the
    largest, at most DENSE_INTERVALS of them) measured at DENSE_SAMPLES points each, so
    that the maximum is not missed between the check fractions."""
    worst = np.argsort(per)[::-1][:DENSE_INTERVALS]
    worst = worst[per[worst] >= DENSE_NEAR * per.max()]
    f = np.linspace(0.0, 1.0, DENSE_SAMPLES + 2)[1:-1]
    tc = (t[worst, None] + f[None, :] * (t[worst + 1] - t[worst])[:, None]).ravel()
    miss = np.linalg.norm((curve(tc) - moved(tc).reshape(len(tc), -1)).reshape(len(tc), -1, 3), axis=-1)
    out = per.copy()
    out[worst] = np.maximum(per[worst], miss.max(axis=1).reshape(len(worst), DENSE_SAMPLES).max(axis=1))
    return out


def _surface(profile: BSplineCurve, curve: BSplineCurve) -> BSplineSurface:
    """The surface whose v-direction is the interpolant of the flattened poles."""
    n = len(profile.control_points)
    P = curve.control_points.reshape(len(curve.control_points), n, 3).transpose(1, 0, 2)
    W = None if profile.weights is None else np.repeat(profile.weights[:, None], P.shape[1], axis=1)
    return BSplineSurface(P, profile.degree, curve.degree, profile.knots, curve.knots, W, profile.periodic, False)


def _start_stations(*curves: BSplineCurve) -> np.ndarray:
    """The curves' breaks (normalised to [0, 1]) with each span split into enough pieces
    for INITIAL_INTERVALS in all, stations closer than MERGE_GAP times the mean spacing merged."""
    t = [np.linspace(0.0, 1.0, INITIAL_INTERVALS + 1)]
    for c in curves:
        a, b = c.domain
        breaks = np.unique(np.clip((np.unique(c.full_knots) - a) / (b - a), 0.0, 1.0))
        pieces = max(1, -(-INITIAL_INTERVALS // (len(breaks) - 1)))
        f = np.linspace(0.0, 1.0, pieces + 1)[:-1]
        t.append((breaks[:-1, None] + f[None, :] * np.diff(breaks)[:, None]).ravel())
    return _merged(np.concatenate(t + [np.ones(1)]))


#: stations closer than this times the mean station spacing are merged
MERGE_GAP = 0.1


def _merged(t: np.ndarray) -> np.ndarray:
    t = np.unique(t)
    gap = MERGE_GAP / (len(t) - 1)
    keep = [0.0]
    for x in t[1:-1]:
        if x - keep[-1] >= gap and 1.0 - x >= gap:
            keep.append(float(x))
    keep.append(1.0)
    return np.asarray(keep)


def _finish(surface: BSplineSurface, err: float, tol: float, capped: bool, what: str) -> SweepResult:
    converged = bool(err <= tol and not capped)
    message = (f"{what}: max error {err:.3g} (tol {tol:.3g})"
               + ("" if converged else f"; not converged: the station cap ({MAX_STATIONS}) or the refinement "
                  f"bound ({MAX_REFINEMENTS} passes) was reached above the tolerance"))
    return SweepResult(surface, float(err), tol, converged, message)


# --- a circular path: the sweep is a surface of revolution -----------------------------------
#: a path whose samples lie within this times its radius of one circle counts as that circle
CIRCLE_TOL = 1e-12
#: an up vector within this (sine of the angle) of the circle's axis keeps the frame rigid
AXIS_TOL = 1e-12
#: two arc control nets (cosine, sine factors) agreeing within this are the same
ARC_MATCH_TOL = 1e-13


def _circle(path: BSplineCurve) -> Optional[Tuple[np.ndarray, np.ndarray, float]]:
    """(centre O, unit axis a, radius R) when the path lies on one circle, a oriented so
    that the path turns counter-clockwise about it, else None. The circle is the one
    through c(0), c(1/3), c(2/3) (normalised parameters); the test samples 2 p + 3 points in
    every knot span: a rational curve of degree p meets a circle (a conic in its plane) in at
    most 2 p points of a span unless it lies on it, so the samples decide it."""
    a, b = path.domain
    breaks = np.unique(np.clip(np.asarray(path.full_knots, dtype=float), a, b))
    f = np.linspace(0.0, 1.0, 2 * path.degree + 3)
    t = (breaks[:-1, None] + f[None, :] * np.diff(breaks)[:, None]).ravel()
    p0, p1, p2 = path(np.array([a, a + (b - a) / 3.0, a + 2.0 * (b - a) / 3.0]))
    u, v = p1 - p0, p2 - p0
    w = np.cross(u, v)
    ww = float(w @ w)
    if not ww > (STRAIGHT_TOL * max(float(u @ u), float(v @ v))) ** 2:
        return None
    O = p0 + (float(v @ v) * np.cross(w, u) + float(u @ u) * np.cross(v, w)) / (2.0 * ww)
    n = w / np.sqrt(ww)
    R = float(np.linalg.norm(p0 - O))
    rel = path(t) - O
    if np.max(np.abs(np.linalg.norm(rel, axis=-1) - R)) > CIRCLE_TOL * R or np.max(np.abs(rel @ n)) > CIRCLE_TOL * R:
        return None
    T0 = path.derivatives(a, 1)[1]
    return O, (n if float(np.cross(p0 - O, T0) @ n) > 0.0 else -n), R


def _revolution(prof: BSplineCurve, path: BSplineCurve, O: np.ndarray, axis: np.ndarray, R: float
                ) -> BSplineSurface:
    """The profile (placed: M(0) applied) turned about the axis by the path's own rational
    circle: S(u, v) = O + Rot(phi(v)) (C(u) - O), phi the path's angle. With e1 = (c(0) - O) / R,
    e2 = axis x e1 and the path's poles c_j, weights v_j: cos phi = sum N_j v_j alpha_j / sum N_j v_j,
    sin phi likewise with alpha_j = (c_j - O).e1 / R, beta_j = (c_j - O).e2 / R, so the net
    :func:`~cagd.surfaces.revolution.turned_net` of the profile's poles by (alpha_j, beta_j),
    weights w_i v_j, is exact (Piegl & Tiller A8.1 with the path's circle). When the path is
    the standard arc of :func:`~cagd.surfaces.revolution.arc_parameters` the result is
    :func:`~cagd.surfaces.revolution.revolve`'s RevolvedSurface (its records kept)."""
    from ..surfaces.revolution import _arc_count, _revolved, arc_parameters, turned_net

    a, b = path.domain
    x0 = path(a)
    e1 = (x0 - O) / R
    e2 = np.cross(axis, e1)
    rel = path.control_points - O
    alpha, beta = rel @ e1 / R, rel @ e2 / R
    wv = np.ones(len(rel)) if path.weights is None else path.weights
    kv_ = (np.asarray(path.knots, dtype=float) - a) / (b - a)
    if path.degree == 2 and not path.periodic and not prof.periodic and len(rel) % 2 == 1 and wv[0] > 0.0:
        spans = len(rel) // 2
        half = float(np.arccos(np.clip(wv[1] / wv[0], -1.0, 1.0)))
        angle = 2.0 * half * spans
        if abs(angle - 2.0 * np.pi) <= ARC_MATCH_TOL * 2.0 * np.pi:
            angle = 2.0 * np.pi
        if 0.0 < angle <= 2.0 * np.pi and _arc_count(angle) == spans:
            c, s, w, knots = arc_parameters(0.0, angle)
            if (len(knots) == len(kv_) and np.allclose(knots, kv_, rtol=0, atol=ARC_MATCH_TOL)
                    and np.allclose(w, wv / wv[0], rtol=0, atol=ARC_MATCH_TOL)
                    and np.allclose(c, alpha, rtol=0, atol=ARC_MATCH_TOL)
                    and np.allclose(s, beta, rtol=0, atol=ARC_MATCH_TOL)):
                return _revolved(prof.clamped(), O, axis, angle, 0.0)
    P = turned_net(prof.control_points, O, axis, alpha, beta)
    wu = np.ones(len(P)) if prof.weights is None else prof.weights
    W = None if prof.weights is None and path.weights is None else np.outer(wu, wv)
    return BSplineSurface(P, prof.degree, path.degree, prof.knots, kv_, W, prof.periodic, path.periodic)


# --- sweep ---------------------------------------------------------------------------------
def sweep(profile: Curve, path: Curve, frame: Union[str, Sequence[float]] = "rmf", scale: Law = None,
          twist: Law = None, tol: float = SWEEP_TOL) -> SweepResult:
    """Sweep ``profile`` along ``path``: S(u, t) = c(t) + s(t) F(t) R_T(theta(t)) F(0)^T (C(u) - c(0))
    (module docstring; rotation-minimising frame by double reflection, Wang et al. 2008),
    the profile's poles moved exactly at stations and interpolated along t (Piegl & Tiller
    9.2.1), stations refined until the measured error is within ``tol``.

    Args:
        profile, path: 3-D cagd curves (the profile is given where it sits at the path's start).
        frame: "rmf", "frenet", "fixed" or an up vector (3 numbers).
        scale: uniform scale law s(t) > 0 about the path point (constant or callable of t in [0, 1]).
        twist: rotation law theta(t) in radians about the path tangent.
        tol: distance tolerance.

    Raises:
        CagdError: non-curves or not 3-D (naming profile/path), a degenerate path, a bad
            frame, a Frenet frame where the curvature vanishes, an up vector parallel to the
            tangent, laws that are not numbers or return non-finite (or non-positive scale)
            values, tol not positive.
    """
    prof = _curve3(profile, "profile")
    pth = _curve3(path, "path")
    tol = _tol(tol)
    P = _Path(pth, frame)
    x0, F0 = P.frames(np.zeros(1))
    rel = prof.control_points - x0[0]                        # profile poles relative to c(0)
    radius = float(np.max(np.linalg.norm(rel, axis=-1)))

    def motion(t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        x, F = P.frames(t)
        s = _law(scale, "scale", t, True)
        th = _law(twist, "twist", t, False)
        M = s[:, None, None] * np.einsum("kij,kjl,ml->kim", F, _rot_x(th), F0[0])
        return x, M

    def moved(t: np.ndarray) -> np.ndarray:
        x, M = motion(t)
        return x[:, None, :] + np.einsum("kij,nj->kni", M, rel)

    constant_laws = not callable(scale) and not callable(twist)
    if constant_laws and (P.frame == "fixed" or (P.frame in ("rmf", "up") and P.straight())):
        _, M = motion(np.zeros(1))
        surface = _translational(prof, pth, M[0], x0[0])
        tc = np.linspace(0.0, 1.0, 4 * INITIAL_INTERVALS + 1)
        err = _measured_exact(surface, moved, tc, len(prof.control_points))
        return _finish(surface, err, tol, False, "translational sweep (exact)")
    circle = _circle(pth) if constant_laws else None
    if circle is not None and (P.frame != "up" or np.linalg.norm(np.cross(P.up, circle[1])) <= AXIS_TOL):
        _, M = motion(np.zeros(1))                            # the placed profile, then turned rigidly
        placed = prof.with_control_points(x0[0] + rel @ M[0].T)
        surface = _revolution(placed, pth, *circle)
        tc = np.linspace(0.0, 1.0, 4 * INITIAL_INTERVALS + 1)
        err = _measured_exact(surface, moved, tc, len(prof.control_points))
        return _finish(surface, err, tol, False, f"surface of revolution ({P.frame} frame on a circular path, exact)")
    curve, err, capped, count = _refine(moved, _start_stations(pth), tol)
    err += P.rmf_error * radius * float(np.max(np.abs(_law(scale, "scale", P.grid[::64], True))))
    return _finish(_surface(prof, curve), err, tol, capped, f"sweep ({P.frame} frame), {count} stations")


def _translational(prof: BSplineCurve, path: BSplineCurve, M: np.ndarray, x0: np.ndarray) -> BSplineSurface:
    """S(u, v) = M (C(u) - c(0)) + c(v): poles M (P_i - c(0)) + c_j, weights w_i v_j, v on [0, 1]."""
    a, b = path.domain
    Pi = (prof.control_points - x0) @ M.T
    P = Pi[:, None, :] + path.control_points[None, :, :]
    wu = np.ones(len(Pi)) if prof.weights is None else prof.weights
    wv = np.ones(len(path.control_points)) if path.weights is None else path.weights
    W = None if prof.weights is None and path.weights is None else np.outer(wu, wv)
    kv_ = (np.asarray(path.knots) - a) / (b - a)
    return BSplineSurface(P, prof.degree, path.degree, prof.knots, kv_, W, prof.periodic, path.periodic)


def _measured_exact(surface: BSplineSurface, moved: Callable[[np.ndarray], np.ndarray], tc: np.ndarray,
                            n: int) -> float:
    """Largest distance between an exact sweep surface and the true sweep on a grid (u at
    the profile evaluated through the moved curves; v at ``tc``)."""
    (u0, u1), _ = surface.domain
    us = np.linspace(u0, u1, 33)
    iso = [surface.isocurve("u", float(v)) for v in tc]
    Q = moved(tc)
    err = 0.0
    for k, c in enumerate(iso):
        true = c.with_control_points(Q[k]) if len(c.control_points) == n else None
        if true is None:
            continue
        err = max(err, float(np.max(np.linalg.norm(c(us) - true(us), axis=-1))))
    return err


# --- sweep2 --------------------------------------------------------------------------------
def _minimal_rotation(d0: np.ndarray, d1: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The rotation taking the unit vector d0 to d1 about d0 x d1 (Rodrigues), applied to v
    (vectorized over leading axes; d0 = -d1 is rejected by the caller)."""
    k = np.cross(d0, d1)
    c = _dot(d0, d1)[..., None]
    kv1 = np.cross(k, v)
    return v + kv1 + np.cross(k, kv1) / (1.0 + c)


def sweep2(profiles: Union[Curve, Sequence[Curve]], rail1: Curve, rail2: Curve,
           tol: float = SWEEP_TOL) -> SweepResult:
    """Sweep profiles between two rails: S(u, t) = a(t) + |b(t) - a(t)| G(t) L(t; u) (module
    docstring), G(t) the minimal-rotation transport of the chord frame, L the profiles' poles
    in their chord frames, interpolated over the profiles' rail parameters; stations refined
    as in :func:`sweep` (Piegl & Tiller 9.2.1 for the interpolation).

    Args:
        profiles: one curve or a sequence; each runs from (near) rail1 to (near) rail2 and is
            placed at the rail1 parameter closest to its start point.
        rail1, rail2: 3-D curves, both on [0, 1] after normalising their domains.

    Raises:
        CagdError: non-curves, not 3-D, a profile with coincident end points, a zero-length
            chord between the rails, chords turning by 180 degrees, rational profiles of
            different weights, two profiles at one rail parameter, tol not positive.
    """
    from ..queries import closest_point
    from ..surfaces.loft import make_compatible

    if isinstance(profiles, Curve):
        profiles = [profiles]
    try:
        plist = list(profiles)
    except TypeError:
        raise CagdError(f"profiles: must be a curve or a sequence of curves, got {type(profiles).__name__}") from None
    if not plist:
        raise CagdError("profiles: need at least one profile")
    profs = [_curve3(c, f"profiles[{k}]") for k, c in enumerate(plist)]
    r1, r2 = _curve3(rail1, "rail1"), _curve3(rail2, "rail2")
    tol = _tol(tol)
    size = _size(np.concatenate([r1.control_points, r2.control_points]))
    (a1, b1), (a2, b2) = r1.domain, r2.domain

    def rails(t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        return r1(np.clip(a1 + t * (b1 - a1), a1, b1)), r2(np.clip(a2 + t * (b2 - a2), a2, b2))

    grid = np.linspace(0.0, 1.0, RMF_SAMPLES + 1)
    A, B = rails(grid)
    chord = np.linalg.norm(B - A, axis=-1)
    short = chord <= TANGENT_ZERO_TOL * size
    if np.any(short):
        k = int(np.argmax(short))
        raise CagdError(f"rail2: zero-length chord, rail2 meets rail1 at t = {float(grid[k])!r} "
                        f"(normalised to [0, 1]); the profile cannot be scaled to span it")
    D = (B - A) / chord[:, None]
    if np.any(_dot(D[:-1], D[1:]) <= -1.0 + 1e-12):
        raise CagdError("rail2: the chord between the rails turns by 180 degrees between two samples")
    R0 = np.empty_like(D)                                   # chord-frame normal, minimal rotations
    R0[0] = _any_normal(D[0])
    for k in range(len(D) - 1):
        r = _minimal_rotation(D[k], D[k + 1], R0[k])
        r = r - _dot(r, D[k + 1]) * D[k + 1]
        R0[k + 1] = r / np.linalg.norm(r)

    def chord_frames(t: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, b = rails(t)
        c = np.linalg.norm(b - a, axis=-1)
        if np.any(c <= TANGENT_ZERO_TOL * size):
            j = int(np.argmax(c <= TANGENT_ZERO_TOL * size))
            raise CagdError(f"rail2: zero-length chord at t = {float(t[j])!r} (normalised to [0, 1])")
        d = (b - a) / c[:, None]
        k = np.clip(np.searchsorted(grid, t, side="right") - 1, 0, RMF_SAMPLES)
        r = _minimal_rotation(D[k], d, R0[k])
        r = _unit(r - _dot(r, d)[:, None] * d)
        return a, c, np.stack([d, r, np.cross(d, r)], axis=-1)

    # the profiles in their chord frames
    if len(profs) > 1:
        profs = make_compatible(profs)
        ws = [p.weights for p in profs]
        w0 = ws[0]
        if any(w is not None for w in ws) and not (w0 is not None and all(
                w is not None and np.allclose(w, w0, rtol=0, atol=1e-15) for w in ws)):
            raise CagdError("profiles: rational profiles must share their weights (after make_compatible)")
        starts = np.array([p(p.domain[0]) for p in profs])
        tk = (closest_point(r1, starts).params.reshape(-1) - a1) / (b1 - a1)
    else:
        tk = np.zeros(1)
    order = np.argsort(tk)
    profs, tk = [profs[i] for i in order], tk[order]
    if len(tk) > 1 and np.any(np.diff(tk) <= 1e-9):
        raise CagdError("profiles: two profiles start at the same rail1 parameter")
    locals_ = []
    for k, p in enumerate(profs):
        p0, p1 = p(p.domain[0]), p(p.domain[1])
        e = p1 - p0
        length = float(np.linalg.norm(e))
        if not length > TANGENT_ZERO_TOL * _size(p.control_points):
            raise CagdError(f"profiles[{int(order[k])}]: its end points coincide; it has no chord to span the rails")
        e = e / length
        _, _, G = chord_frames(tk[k:k + 1])
        d = G[0][:, 0]
        if _dot(e, d) <= -1.0 + 1e-12:
            raise CagdError(f"profiles[{int(order[k])}]: runs from rail2 to rail1 (reverse it)")
        rel = _minimal_rotation(np.broadcast_to(e, p.control_points.shape), np.broadcast_to(d, p.control_points.shape),
                                p.control_points - p0) / length
        locals_.append(rel @ G[0])                          # coordinates in the chord frame
    Lk = np.array(locals_)                                  # (K, n, 3)
    n = Lk.shape[1]
    if len(tk) > 1:
        q = min(3, len(tk) - 1)
        blend = collocate(Lk.reshape(len(tk), -1), q, tk, kv.averaged(tk, q))

    def local(t: np.ndarray) -> np.ndarray:
        if len(tk) == 1:
            return np.broadcast_to(Lk[0], (len(t), n, 3))
        return blend(np.clip(t, tk[0], tk[-1])).reshape(len(t), n, 3)

    def moved(t: np.ndarray) -> np.ndarray:
        a, c, G = chord_frames(t)
        return a[:, None, :] + c[:, None, None] * np.einsum("kij,knj->kni", G, local(t))

    start = _start_stations(r1, r2)
    curve, err, capped, count = _refine(moved, start, tol)
    return _finish(_surface(profs[0], curve), err, tol, capped, f"two-rail sweep, {len(profs)} profile(s), "
                   f"{count} stations")

