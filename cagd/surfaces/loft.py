"""Ruled and skinned (lofted) surfaces through section curves, and the compatibility
of curves they need (Piegl & Tiller, The NURBS Book, 8.4 ruled surfaces, 10.3
skinned surfaces; the seeds do not cover lofting).

Conventions: u runs along the sections (every section's own domain is mapped
linearly onto [0, 1]), v runs across them, also on [0, 1].
"""
from __future__ import annotations

from typing import Iterable, List, Sequence

import numpy as np

from .. import _checks
from ..basis.bspline import basis_matrix
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots import vectors as kv
from .bspline import BSplineSurface
from ..fitting.parameters import ParameterSpec, averaged_parameters, rule

_SNAP = 64 * np.finfo(float).eps     # knots this close (on [0, 1]) are the same knot


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
def _sections(sections: Iterable[Curve]) -> List[BSplineCurve]:
    sections = list(sections)
    if len(sections) < 2:
        raise CagdError(f"sections: need at least 2 section curves, got {len(sections)}")
    return make_compatible(sections)


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


def loft(sections: Iterable[Curve], degree_v: int = 3, parameters: ParameterSpec = "chord") -> BSplineSurface:
    """Skinned surface through the section curves (Piegl & Tiller 10.3): the sections
    are made compatible (:func:`make_compatible`), given parameters v_k
    (:func:`loft_parameters`) and averaged knots in v (eq. 9.8, as in
    :func:`cagd.interpolate`), and every column of control points is interpolated
    globally: [N_{j,q}(v_k)] X = Q_k. Rational sections are interpolated in
    homogeneous coordinates (w P, w), so the isocurve at v_k is the section exactly;
    between sections the interpolated weights must stay positive.

    S(u, v_k) = sections[k](a_k + u (b_k - a_k)) for the section's domain [a_k, b_k].

    Raises:
        CagdError: fewer than degree_v + 1 sections, bad parameters (see
            :func:`loft_parameters`), non-positive interpolated weights.
    """
    cs = _sections(sections)
    count = len(cs)
    q = _checks.integer(degree_v, "degree_v", 1)
    if q > count - 1:
        raise CagdError(f"degree_v: a degree-{q} loft needs at least {q + 1} sections, got {count}")
    v = loft_parameters(cs, parameters)
    V = kv.averaged(v, q)
    N = basis_matrix(V, q, v, count)
    H = np.stack([c.homogeneous_control_points for c in cs])    # (K+1, n, D)
    X = np.linalg.solve(N, H.reshape(count, -1)).reshape(H.shape).transpose(1, 0, 2)
    p, U = cs[0].degree, cs[0].knots
    if cs[0].is_rational:
        W = X[..., -1]
        if np.any(W <= 0):
            raise CagdError("sections: interpolating the weights in homogeneous space gives non-positive "
                            "weights; reweight the sections or add sections")
        return BSplineSurface(X[..., :-1] / W[..., None], p, q, U, V, W)
    return BSplineSurface(X, p, q, U, V)
