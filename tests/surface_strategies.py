"""Hypothesis strategies and independent oracles for tensor-product surfaces.

Knot vectors per direction come from ``strategies`` (clamped, floating uniform,
non-uniform with repeated knots, periodic); control nets from bounded floats.
The oracles here use only scipy, the textbook Cox-de Boor recursion and plain
numpy, never the engine's evaluation code.
"""
from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from cagd import BezierSurface, BSplineSurface
from cagd.basis import cox_de_boor
from cagd.knots import periodic_extend

from strategies import (clamped_knots, coordinates, floating_knots, periodic_knots, positive_weights,
                        scipy_derivatives)

KINDS = ("clamped", "floating", "nonuniform", "periodic")
NONPERIODIC = ("clamped", "floating", "nonuniform")


@st.composite
def nets(draw, nu: int, nv: int, dim: int):
    """An (nu, nv, dim) control net of coordinates in [-10, 10]."""
    flat = draw(st.lists(coordinates, min_size=nu * nv * dim, max_size=nu * nv * dim))
    return np.array(flat, dtype=np.float64).reshape(nu, nv, dim)


@st.composite
def weight_nets(draw, nu: int, nv: int):
    """(nu, nv) weights in [0.2, 5]."""
    flat = draw(st.lists(positive_weights, min_size=nu * nv, max_size=nu * nv))
    return np.array(flat, dtype=np.float64).reshape(nu, nv)


@st.composite
def direction_knots(draw, kind: str, degree: int):
    """(knots as the surface takes them, number of control points, periodic) for one direction."""
    if kind == "clamped":
        knots = draw(clamped_knots(degree, max_interior=3))
        return knots, len(knots) - degree - 1, False
    if kind == "floating":
        knots = draw(floating_knots(degree, uniform=True))
        return knots, len(knots) - degree - 1, False
    if kind == "nonuniform":
        knots = draw(floating_knots(degree, max_distinct=6))
        return knots, len(knots) - degree - 1, False
    knots = draw(periodic_knots(degree, max_distinct=4))
    return knots, len(knots) - 1, True


@st.composite
def bspline_surfaces(draw, kinds=KINDS, kinds_v=None, min_degree: int = 1, max_degree: int = 4,
                     rational=None, dims=(1, 3)):
    """A random :class:`cagd.BSplineSurface`; ``kinds`` for u (and v unless
    ``kinds_v`` is given), degrees in [min_degree, max_degree] per direction,
    ``rational`` True/False/None (either)."""
    kind_u = draw(st.sampled_from(kinds))
    kind_v = draw(st.sampled_from(kinds if kinds_v is None else kinds_v))
    p = draw(st.integers(min_degree, max_degree))
    q = draw(st.integers(min_degree, max_degree))
    ku, nu, per_u = draw(direction_knots(kind_u, p))
    kv, nv, per_v = draw(direction_knots(kind_v, q))
    dim = draw(st.integers(*dims))
    P = draw(nets(nu, nv, dim))
    is_rational = draw(st.booleans()) if rational is None else rational
    W = draw(weight_nets(nu, nv)) if is_rational else None
    return BSplineSurface(P, p, q, ku, kv, W, per_u, per_v)


@st.composite
def bezier_surfaces(draw, min_degree: int = 1, max_degree: int = 5, rational=None, dims=(1, 3)):
    m = draw(st.integers(min_degree, max_degree))
    n = draw(st.integers(min_degree, max_degree))
    dim = draw(st.integers(*dims))
    P = draw(nets(m + 1, n + 1, dim))
    is_rational = draw(st.booleans()) if rational is None else rational
    return BezierSurface(P, draw(weight_nets(m + 1, n + 1)) if is_rational else None)


# --- helpers ----------------------------------------------------------------------------------

def full_knots(surface, direction: str) -> np.ndarray:
    """The full (unwrapped for a periodic direction) knot vector of one direction."""
    if direction == "u":
        k, p, per = surface.knots_u, surface.degree_u, surface.periodic_u
    else:
        k, p, per = surface.knots_v, surface.degree_v, surface.periodic_v
    return periodic_extend(np.asarray(k, float), p) if per else np.asarray(k, float)


def unwrapped(surface) -> BSplineSurface:
    """The same surface as a non-periodic B-spline on the full knot vectors (the
    periodic net P_0..P_{n-1}, P_0..P_{p-1} in each periodic direction)."""
    hom = surface.homogeneous_control_points
    ku, kv = full_knots(surface, "u"), full_knots(surface, "v")
    if surface.is_rational:
        return BSplineSurface(hom[..., :-1] / hom[..., -1:], surface.degree_u, surface.degree_v, ku, kv,
                              hom[..., -1])
    return BSplineSurface(hom, surface.degree_u, surface.degree_v, ku, kv)


def domain_parameters(surface, count: int = 9, include_knots: bool = True):
    """(us, vs): equally spaced parameters over each direction's domain plus the
    distinct knots inside it."""
    out = []
    for which, d in enumerate("uv"):
        a, b = surface.domain[which]
        t = np.linspace(a, b, count)
        if include_knots and isinstance(surface, BSplineSurface):
            k = np.unique(full_knots(surface, d))
            t = np.unique(np.concatenate([t, k[(k >= a) & (k <= b)]]))
        out.append(t)
    return out[0], out[1]


def interior_parameters(surface, direction: str, per_span: int = 3, margin: float = 0.0) -> np.ndarray:
    """Parameters strictly inside the non-empty spans of one direction."""
    which = 0 if direction == "u" else 1
    a, b = surface.domain[which]
    k = np.unique(full_knots(surface, direction)) if isinstance(surface, BSplineSurface) else np.array([a, b])
    k = k[(k >= a) & (k <= b)]
    s = np.linspace(0.0, 1.0, per_span + 2)[1:-1]
    lo, hi = k[:-1] + margin, k[1:] - margin
    ok = hi > lo
    return (lo[ok, None] + (hi - lo)[ok, None] * s).ravel()


def scipy_homogeneous_grid(surface, us, vs, du: int, dv: int) -> np.ndarray:
    """Homogeneous partials (du+1, dv+1, len(us), len(vs), D) of the tensor product
    sum_i sum_j N_i(u) N_j(v) H_ij by scipy.interpolate.BSpline one direction at a
    time: first the v-curves of every row i, then the u-curves through their values
    (right limits at knots, left limits at the domain end)."""
    H = surface.homogeneous_control_points                       # (nu', nv', D), unwrapped
    nu, nv, D = H.shape
    ku, kv = full_knots(surface, "u"), full_knots(surface, "v")
    us, vs = np.asarray(us, float), np.asarray(vs, float)
    # rows: coefficients (nv, nu*D) -> values (dv+1, Mv, nu*D)
    Cv = scipy_derivatives(kv, H.transpose(1, 0, 2).reshape(nv, nu * D), surface.degree_v, vs, dv)
    Cv = Cv.reshape(dv + 1, len(vs), nu, D).transpose(0, 2, 1, 3)        # (dv+1, nu, Mv, D)
    out = np.empty((du + 1, dv + 1, len(us), len(vs), D))
    for l in range(dv + 1):
        R = scipy_derivatives(ku, Cv[l].reshape(nu, len(vs) * D), surface.degree_u, us, du)
        out[:, l] = R.reshape(du + 1, len(us), len(vs), D)
    return out


def closed_cox_de_boor(knots, degree: int, t) -> np.ndarray:
    """The textbook Cox-de Boor basis (seed 000, 5.3.1), shape (len(t), n), with the
    left limit at the domain end u_n taken from the mirrored knots (the half-open
    recursion gives 0 there)."""
    knots = np.asarray(knots, float)
    t = np.asarray(t, float).ravel()
    n = len(knots) - degree - 1
    N = cox_de_boor(knots, degree, t)
    end = t >= knots[n]
    if end.any():
        N[end] = cox_de_boor(-knots[::-1], degree, -t[end])[:, ::-1]
    return N


def direct_surface(surface, u, v) -> np.ndarray:
    """S(u, v) = sum N_i(u) N_j(v) w_ij P_ij / sum N_i(u) N_j(v) w_ij by the direct
    double sum of textbook Cox-de Boor products (element-wise, flat u and v)."""
    H = surface.homogeneous_control_points
    Nu = closed_cox_de_boor(full_knots(surface, "u"), surface.degree_u, u)
    Nv = closed_cox_de_boor(full_knots(surface, "v"), surface.degree_v, v)
    h = np.einsum("ki,kj,ijd->kd", Nu, Nv, H)
    return h[:, :-1] / h[:, -1:] if surface.is_rational else h


def relative(got, expected, scale: float = 0.0) -> float:
    """max |got - expected| / max(max |expected|, scale)."""
    got, expected = np.asarray(got), np.asarray(expected)
    ref = max(float(np.abs(expected).max()) if expected.size else 0.0, scale)
    return float(np.abs(got - expected).max()) / max(ref, 1e-300)


def net_size(surface) -> float:
    """max |P| over the control net (a scale for absolute tolerances)."""
    return max(float(np.abs(surface.control_points).max()), 1e-300)


def weight_ratio(surface) -> float:
    return 1.0 if surface.weights is None else float(surface.weights.max() / surface.weights.min())


def min_span(surface, direction: str) -> float:
    which = 0 if direction == "u" else 1
    a, b = surface.domain[which]
    if not isinstance(surface, BSplineSurface):
        return b - a
    k = np.unique(full_knots(surface, direction))
    return float(np.diff(k).min())


def regular(s, d, offset: float = 0.0) -> bool:
    """Every sample of the partials d = s.derivatives(u, v, >=1, >=1) is safely a
    regular point: |S_u x S_v| > 1e-6 |S_u| |S_v|, neither partial is rounding noise
    (|S_u| h_u, |S_v| h_v > 1e-8 (|P| + offset) w_max / w_min, h the shortest span)
    and |S_u x S_v| > 1e-9 extent^2 / (L_u L_v) (1000 times the floor below which
    Surface.normal reports a degenerate point; extent of the net, L the domain spans)."""
    lift = lambda x: x if x.shape[-1] == 3 else np.concatenate(  # noqa: E731
        [x, np.zeros(x.shape[:-1] + (3 - x.shape[-1],))], axis=-1)
    su, sv = np.linalg.norm(d[1, 0], axis=-1), np.linalg.norm(d[0, 1], axis=-1)
    c = np.linalg.norm(np.cross(lift(d[1, 0]), lift(d[0, 1])), axis=-1)
    floor = 1e-8 * (net_size(s) + offset) * weight_ratio(s)
    (u0, u1), (v0, v1) = s.domain
    extent = float(np.ptp(s.control_points.reshape(-1, s.dim), axis=0).max())
    return bool(np.all(c > 1e-6 * su * sv) and np.min(su) * min_span(s, "u") > floor
                and np.min(sv) * min_span(s, "v") > floor
                and np.min(c) > 1e-9 * extent ** 2 / ((u1 - u0) * (v1 - v0)))
