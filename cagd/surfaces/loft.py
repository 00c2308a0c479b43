"""Ruled and skinned (lofted) surfaces through section curves, and the compatibility
of curves they need (Piegl & Tiller, The NURBS Book, 8.4 ruled surfaces, 10.3
skinned surfaces; the seeds do not cover lofting).

Conventions: u runs along the sections (every section's own domain is mapped
linearly onto [0, 1]), v runs across them, also on [0, 1]. Closed (and periodic)
sections are aligned before skinning (:func:`aligned_sections`): one direction of
travel, seams started where each section comes nearest the previous one's seam, so the
skin does not twist; the result is clamped in u and closed (C^(p-1) across the seam
where every section is). With guide curves the skin is the Gordon surface
(:func:`cagd.gordon`).
"""
from __future__ import annotations

from typing import Iterable, List, Optional, Sequence, Tuple

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from .bspline import BSplineSurface
from ..fitting.interpolation import collocate
from ..fitting.parameters import ParameterSpec, averaged_parameters, rule

_SNAP = 64 * np.finfo(float).eps     # knots this close (on [0, 1]) are the same knot
CLOSED_RTOL = 1e-9                    # a section whose ends meet within this share of the sections' size is closed
ORIENTATION_SAMPLES = 64              # points per closed section for its area vector (Newell)
#: a closed section's seam is moved only when its point nearest the previous section's
#: start lies farther than this share of its parameter range from its own start: sections
#: drawn alike (scaled copies, whose nearest points are near but not at each other's
#: starts) keep their own correspondence
SEAM_SHIFT = 0.01


# --- compatibility ----------------------------------------------------------------------
def unit_nurbs(curve: Curve, name: str = "curve") -> BSplineCurve:
    """``curve.to_nurbs()``, clamped and mapped linearly onto [0, 1] (same points:
    C_unit(s) = C(a + s (b - a)) on the curve's domain [a, b]).

    Raises:
        CagdError: ``curve`` is not an engine curve.
    """
    if not isinstance(curve, Curve):
        raise CagdError(f"{name}: expected a cagd curve, got {type(curve).__name__}")
    c = curve.to_nurbs().clamped()
    p, k = c.degree, c.knots
    a, b = k[p], k[-p - 1]
    s = (k - a) / (b - a)
    s[:p + 1], s[-p - 1:] = 0.0, 1.0
    return BSplineCurve(c.control_points, p, s, c.weights)


def plain(c: BSplineCurve) -> BSplineCurve:
    """The homogeneous (w P, w) curve of a clamped NURBS as a polynomial B-spline."""
    return BSplineCurve(c.homogeneous_control_points, c.degree, c.knots)


def rotated_start(c: BSplineCurve, a: float) -> Tuple[BSplineCurve, float]:
    """A closed curve (clamped on [0, 1], c(0) ~ c(1)) started at parameter a: w = u - a
    on [a, 1], u + 1 - a on [0, a], exact (the two pieces of c.split(a), joined at the old
    start with a knot of multiplicity p, the joint pole the midpoint of c(1) and c(0); a
    rational curve is joined in homogeneous space, the second piece's weights scaled to
    meet the first's at the joint, which leaves it unchanged).
    Returns the curve and how far the joint moved (half the closing gap)."""
    p = c.degree
    near = np.abs(c.knots - a) <= _SNAP
    a = float(c.knots[near][0]) if near.any() else a        # split at a knot a few ulps off: at the knot
    left, right = c.split(a)
    L, R = left.homogeneous_control_points, right.homogeneous_control_points
    if c.is_rational:
        L = L * (R[-1, -1] / L[0, -1])
    joint = 0.5 * (R[-1] + L[0])
    H = np.concatenate([R[:-1], joint[None], L[1:]])
    knots = np.concatenate([right.knots[:-1] - a, left.knots[p + 1:] + (1.0 - a)])
    knots[:p + 1], knots[-p - 1:] = 0.0, 1.0
    if c.is_rational:
        out = BSplineCurve(H[:, :-1] / H[:, -1:], p, knots, H[:, -1])
        moved = float(np.linalg.norm(right.control_points[-1] - out.control_points[len(R) - 1]))
        return out, moved
    return BSplineCurve(H, p, knots), float(np.linalg.norm(R[-1] - joint))


def union_breaks(knot_vectors: Iterable[np.ndarray]) -> np.ndarray:
    """Distinct interior knot values (strictly inside (0, 1)) of several knot vectors,
    values within a few ulps merged into the first."""
    inner = np.sort(np.concatenate([k[(k > 0.0) & (k < 1.0)] for k in knot_vectors]))
    if inner.size == 0:
        return inner
    return inner[np.concatenate([[True], np.diff(inner) > _SNAP])]


def snapped(c: BSplineCurve, reps: np.ndarray) -> BSplineCurve:
    """``c`` (polynomial, clamped on [0, 1]) with its interior knots replaced by the
    nearest of ``reps`` (they differ by a few ulps at most)."""
    k = c.knots.copy()
    inner = (k > 0.0) & (k < 1.0)
    if inner.any() and reps.size:
        j = np.clip(np.searchsorted(reps, k[inner] + _SNAP, side="right") - 1, 0, len(reps) - 1)
        k[inner] = reps[j]
    return BSplineCurve(c.control_points, c.degree, k)


def multiplicities(knots: np.ndarray, reps: np.ndarray) -> np.ndarray:
    """How often each of ``reps`` occurs in ``knots``."""
    return np.array([np.count_nonzero(knots == r) for r in reps], dtype=int)


def compatible_plain(curves: Sequence[BSplineCurve]) -> List[BSplineCurve]:
    """Polynomial B-splines on [0, 1] (any dims) raised to the highest degree
    (Piegl & Tiller 5.5) and refined to the union of their knots, each interior knot
    at its highest multiplicity (Piegl & Tiller 5.3; knots within a few ulps are
    snapped together first). Every curve is unchanged; all share degree and knots."""
    p = max(c.degree for c in curves)
    curves = [c.elevate(p - c.degree) for c in curves]
    reps = union_breaks([c.knots for c in curves])
    if reps.size == 0:
        return curves
    curves = [snapped(c, reps) for c in curves]
    have = np.stack([multiplicities(c.knots, reps) for c in curves])
    mult = have.max(axis=0)
    full = np.concatenate([np.zeros(p + 1), np.repeat(reps, mult), np.ones(p + 1)])
    out = []
    for c, h in zip(curves, have):
        new = np.repeat(reps, mult - h)
        r = c.refine(new) if new.size else c
        out.append(BSplineCurve(r.control_points, p, full))
    return out


def make_compatible(curves: Iterable[Curve]) -> List[BSplineCurve]:
    """The curves as B-splines/NURBS with one degree and one knot vector on [0, 1],
    each describing the same point set with its own parametrisation mapped linearly
    onto [0, 1] (degree elevation and knot refinement in homogeneous coordinates;
    Piegl & Tiller 10.3). If any curve is rational all come back rational (weights 1
    for the polynomial ones).

    Raises:
        CagdError: fewer than one curve, a non-curve, curves of different dimensions.
    """
    curves = list(curves)
    if len(curves) < 1:
        raise CagdError("curves: need at least one curve")
    units = [unit_nurbs(c, f"curves[{i}]") for i, c in enumerate(curves)]
    dims = {c.dim for c in units}
    if len(dims) > 1:
        raise CagdError(f"curves: all curves must have the same dimension, got {sorted(dims)}")
    rational = any(c.is_rational for c in units)
    hom = []
    for c in units:
        if rational and not c.is_rational:
            c = BSplineCurve(c.control_points, c.degree, c.knots, np.ones(len(c.control_points)))
        hom.append(plain(c))
    out = []
    for h in compatible_plain(hom):
        H = h.control_points
        if rational:
            out.append(BSplineCurve(H[:, :-1] / H[:, -1:], h.degree, h.knots, H[:, -1]))
        else:
            out.append(h)
    return out


# --- ruled surface ------------------------------------------------------------------------
def ruled(c0: Curve, c1: Curve) -> BSplineSurface:
    """The ruled surface S(u, v) between S(u, 0) = c0(u) and S(u, 1) = c1(u), degree 1 in
    v (Piegl & Tiller 8.4): the two curves made compatible (:func:`make_compatible`), the
    control net is their two control polygons. Polynomial curves give exactly the linear
    blend S = (1 - v) c0(u) + v c1(u). Rational curves are blended in homogeneous space:
    the rulings are the same segments [c0(u), c1(u)], but the point at v is
    c0 + lam (c1 - c0) with lam = v w1(u) / ((1 - v) w0(u) + v w1(u)), w0, w1 the curves'
    weight functions (the linear blend itself needs degree 2 weights; see CoonsPatch).

    Raises:
        CagdError: non-curves or curves of different dimensions.
    """
    a, b = make_compatible([c0, c1])
    P = np.stack([a.control_points, b.control_points], axis=1)
    W = None if a.weights is None or b.weights is None else np.stack([a.weights, b.weights], axis=1)
    return BSplineSurface(P, a.degree, 1, a.knots, [0.0, 0.0, 1.0, 1.0], W)


# --- skinning -------------------------------------------------------------------------------
def _size(curves: Sequence[BSplineCurve]) -> float:
    P = np.concatenate([c.control_points for c in curves])
    return max(float(np.ptp(P, axis=0).max()), float(np.abs(P).max()) * np.finfo(float).eps)


def _area_vector(c: BSplineCurve) -> np.ndarray:
    """Newell's area vector sum P_i x P_i+1 / 2 of a closed curve's samples (3-D: normal
    times enclosed area of a planar loop; 2-D: the signed area as a 1-vector)."""
    P = c(np.linspace(0.0, 1.0, ORIENTATION_SAMPLES + 1)[:-1])
    Q = np.roll(P, -1, axis=0)
    if P.shape[1] == 2:
        return np.array([0.5 * np.sum(P[:, 0] * Q[:, 1] - P[:, 1] * Q[:, 0])])
    if P.shape[1] != 3:
        return np.zeros(1)
    return 0.5 * np.cross(P, Q).sum(axis=0)


def aligned_sections(sections: Sequence[Curve]) -> List[BSplineCurve]:
    """The sections as NURBS clamped on [0, 1] (:func:`unit_nurbs`); closed ones (periodic,
    or ends within CLOSED_RTOL of the sections' size), when all are closed, aligned for
    skinning: each runs the way of the one before (a section whose area vector (Newell)
    points against the previous one's is reversed) and starts where it comes nearest the
    previous section's start (its certified closest point; the seam moved exactly by
    :func:`rotated_start`) unless that point is within SEAM_SHIFT of its parameter range
    of its own start. Open sections are returned as they are, in their own direction.

    Raises:
        CagdError: a non-curve among the sections.
    """
    from ..queries.closest import closest_point
    units = [unit_nurbs(c, f"sections[{i}]") for i, c in enumerate(sections)]
    if not units:
        return units
    size = _size(units)
    if not all(np.linalg.norm(c(0.0) - c(1.0)) <= CLOSED_RTOL * size for c in units):
        return units
    out: List[BSplineCurve] = []
    prev: Optional[BSplineCurve] = None        # the last section with an extent (a point has no seam)
    for c in units:
        if np.ptp(c.control_points, axis=0).max() <= CLOSED_RTOL * size:
            out.append(c)
            continue
        if prev is not None:
            if float(np.dot(_area_vector(prev), _area_vector(c))) < 0.0:
                c = unit_nurbs(c.reversed())
            t = float(closest_point(c, prev(0.0)[None]).params[0])
            if SEAM_SHIFT < t < 1.0 - SEAM_SHIFT:
                c = rotated_start(c, t)[0]
        out.append(c)
        prev = c
    return out


def _sections(sections: Iterable[Curve], align: bool = False) -> List[BSplineCurve]:
    try:
        sections = list(sections)
    except TypeError:
        raise CagdError(f"sections: expected a sequence of cagd curves, got {type(sections).__name__}") from None
    if len(sections) < 2:
        raise CagdError(f"sections: need at least 2 section curves, got {len(sections)}")
    return make_compatible(aligned_sections(sections) if align else sections)


def loft_parameters(sections: Iterable[Curve], parameters: ParameterSpec = "chord") -> np.ndarray:
    """Parameters v_0 = 0 < ... < v_K = 1 of the sections (Piegl & Tiller eq. 10.8):
    for "chord" ("centripetal") the chord-length (square-root chord) parameters of
    every column of the compatible control nets, averaged over the columns (columns
    whose points all coincide, e.g. a common apex, are skipped); "uniform" k/K (the
    names: :data:`cagd.fitting.PARAMETERS`); an array is checked and returned.

    Raises:
        CagdError: fewer than 2 sections, an unknown name, coincident consecutive
            sections, explicit parameters of the wrong length, not increasing, or not
            from 0 to 1.
    """
    cs = _sections(sections)
    K = len(cs) - 1
    if not isinstance(parameters, str):
        v = _checks.finite_array(parameters, "parameters", ndim=1)
        if v.shape[0] != K + 1:
            raise CagdError(f"parameters: expected {K + 1} values (one per section), got {v.shape[0]}")
        if np.any(np.diff(v) <= 0) or v[0] != 0.0 or v[-1] != 1.0:
            raise CagdError(f"parameters: must increase strictly from 0 to 1, got {v.tolist()}")
        return v
    if rule(parameters) == "uniform":
        return np.arange(K + 1) / K
    Q = np.stack([c.control_points for c in cs])                 # (K+1, n, dim)
    return averaged_parameters(Q, parameters, "sections", "sections")


def loft(sections: Iterable[Curve], degree_v: int = 3, parameters: ParameterSpec = "chord", *,
         guides: Optional[Sequence[Curve]] = None, tol: float = 1e-6, align: bool = True) -> BSplineSurface:
    """Skinned surface through the section curves (Piegl & Tiller 10.3): the sections
    are aligned when closed (``align``: :func:`aligned_sections`, one direction, seams
    lined up; open sections keep their own direction), made compatible
    (:func:`make_compatible`: any degrees, knots and weights), given parameters v_k
    (:func:`loft_parameters`) and averaged knots in v (eq. 9.8, as in
    :func:`cagd.interpolate`), and every column of control points is interpolated
    globally, [N_{j,q}(v_k)] X = Q_k (a banded solve). The degree in v is ``degree_v``
    capped at len(sections) - 1: two sections give the ruled surface. Rational sections
    are interpolated in homogeneous coordinates (w P, w), so the isocurve at v_k is the
    section exactly; between sections the interpolated weights must stay positive.

    S(u, v_k) = sections[k](a_k + u (b_k - a_k)) for the section's domain [a_k, b_k]
    (the aligned section where ``align`` changed it).

    With ``guides`` (curves crossing every section once) the surface is the Gordon
    surface of the sections (as profiles) and the guides, :func:`cagd.gordon` with
    ``tol`` (a distance): it interpolates both families; ``degree_v``, ``parameters``
    and ``align`` are then not used.

    Raises:
        CagdError: fewer than 2 sections, degree_v < 1, bad parameters (see
            :func:`loft_parameters`), non-positive interpolated weights; with guides,
            what :func:`cagd.gordon` raises, and a network it could not fit within tol.
    """
    if guides is not None:
        from .gordon import gordon
        if degree_v != 3 or not isinstance(parameters, str) or parameters != "chord":
            raise CagdError("degree_v, parameters: the Gordon surface sets them when guides are given "
                            "(degree min(3, count - 1), parameters from the intersections); leave the defaults")
        res = gordon(list(sections), guides, tol)
        if not res.converged:
            raise CagdError(f"guides: the Gordon surface of the sections and guides is not within tol: {res.message}")
        return res.surface
    q = _checks.integer(degree_v, "degree_v", 1)
    cs = _sections(sections, align)
    count = len(cs)
    q = min(q, count - 1)
    v = loft_parameters(cs, parameters)
    V = kv.averaged(v, q)
    H = np.stack([c.homogeneous_control_points for c in cs])    # (K+1, n, D)
    X = collocate(H.reshape(count, -1), q, v, V).control_points.reshape(H.shape).transpose(1, 0, 2)
    p, U = cs[0].degree, cs[0].knots
    if cs[0].is_rational:
        W = X[..., -1]
        if np.any(W <= 0):
            raise CagdError("sections: interpolating the weights in homogeneous space gives non-positive "
                            "weights; reweight the sections or add sections")
        return BSplineSurface(X[..., :-1] / W[..., None], p, q, U, V, W)
    return BSplineSurface(X, p, q, U, V)
