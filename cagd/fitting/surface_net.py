"""The full-net least squares of a grid fit (issue 17): periodic directions, tangent planes
held along chosen edges (G1) and a thin-plate smoothing energy, for :func:`cagd.fit_surface`.

The separable fit of :mod:`cagd.fitting.fit_surface` cannot carry these (the thin-plate
energy couples the directions, a held cross-boundary tangent couples two rows), so the
control points P (nu x nv, the distinct ones of a periodic direction) minimise

    (1 / (m n)) sum_kl |S(u_k, v_l) - Q_kl|^2
        + smoothing int int |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2 du dv

in the grid's normalised frame (unit ball) over [0, 1]^2: the data term plus the
thin-plate (bending) energy, the standard regulariser of surface approximation
(Dierckx, Curve and Surface Fitting with Splines, 10.2 - his smoothing norm; the same
functional as :func:`cagd.fair_surface`; Piegl & Tiller 9.4.3 for the data term). Its
normal matrix is a sum of Kronecker products of one-direction matrices,
Nu^T Nu (x) Nv^T Nv + smoothing (G2u (x) G0v + 2 G1u (x) G1v + G0u (x) G2v), G_r the Gram
matrix of the r-th basis derivatives (:func:`_kron_band`): banded over the net, the band
pu nv + pv (periodic: the poles of that direction in the folded order of
:func:`cagd.fitting.fit._fold`, 2 pu + 1 rows either side), solved by the block-banded
solver (:func:`cagd.basis.banded.solve_banded_rows`) with held poles moved to the
right-hand side (:func:`cagd.fitting.fit.solve_fixed`); no n x n matrix over the net.

Periodic direction: the knots are :func:`cagd.knots.periodic_extend` of the breakpoints,
the basis wraps (pole i mod n), so the surface is C^(p-1) across its seam by construction.

Tangent edges: row 0 of control points along the edge is held (the neighbour's edge
curve, or the 1-D fit of the grid's boundary row), row 1 is row 0 + alpha D, D the
cross-boundary difference row (the neighbour's last two rows, or the 1-D fit of the grid's
one-sided cross derivatives) and alpha > 0 one scalar per edge chosen by the least squares
(the minimiser is linear in alpha: one extra right-hand side per edge and a k x k solve,
k <= 2). S's cross derivative along the edge is then a constant multiple of D(t): the
tangent plane is the neighbour's exactly (G1), the edge is the neighbour's edge (G0).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..basis.banded import banded_product
from ..basis.bspline import basis_derivatives
from ..errors import CagdError
from ..knots import vectors as kv
from .fit import _fold, _gauss, _knots, solve_fixed

if TYPE_CHECKING:
    from ..surfaces.bspline import BSplineSurface

#: the thin-plate weight below which no smoothing is asked, relative to the data term
#: (as the scattered fit's SCATTER_REGULARISATION: moves an exact fit by ~1e-9 of its size)
NET_REGULARISATION = 1e-9
#: the smallest alpha (cross tangent length factor) of a held tangent edge: keeps the
#: tangent plane's orientation where the least squares would fold the surface back
MIN_ALPHA = 1e-6


class Direction:
    """One direction of the net on the full knots U (unwrapped when periodic): the n poles'
    collocation matrix N (m, n) at the parameters t when given (dense per direction:
    m x n, not the net's square), the Gram matrices G_r = int N^(r) N^(r) (r = 0, 1, 2)
    and the poles' positions in the unknowns (folded when periodic)."""

    def __init__(self, U: np.ndarray, p: int, t: Optional[np.ndarray] = None, periodic: bool = False):
        self.p, self.periodic = p, periodic
        n = len(U) - p - 1 - (p if periodic else 0)
        self.U, self.n = U, n
        self.N = self._matrix(t, 0) if t is not None else np.zeros((0, n))
        x, w = _gauss(U, p)
        self.grams = []
        for r in range(3):
            B = self._matrix(x, r) if r <= p else np.zeros((len(x), n))
            self.grams.append((B * w[:, None]).T @ B)
        self.pos = _fold(np.arange(n), n) if periodic else np.arange(n)
        self.reach = 2 * p + 1 if periodic else p

    def _matrix(self, t: np.ndarray, r: int) -> np.ndarray:
        """[N_j^(r)(t_k)] (len(t), n), the basis wrapped modulo n when periodic."""
        p, U = self.p, self.U
        span = kv.find_span(U, p, t, len(U) - p - 1)
        D = basis_derivatives(U, p, t, span, r)[r]
        cols = span[:, None] - p + np.arange(p + 1)
        if self.periodic:
            cols = cols % self.n
        M = np.zeros((len(t), self.n))
        np.add.at(M, (np.repeat(np.arange(len(t)), p + 1), cols.ravel()), D.ravel())
        return M


def direction(breaks: np.ndarray, p: int, t: np.ndarray, periodic: bool,
              required: Optional[np.ndarray] = None) -> Direction:
    """The Direction on the breakpoints: periodic knots (:func:`cagd.knots.periodic_extend`),
    or clamped ones with a neighbour's ``required`` interior knots in."""
    if periodic:
        return Direction(kv.periodic_extend(breaks, p), p, t, True)
    return Direction(_knots(breaks, p) if required is None else _with_knots(breaks, p, required), p, t)


def _with_knots(breaks: np.ndarray, p: int, required: np.ndarray) -> np.ndarray:
    """The clamped knots of ``breaks`` with the interior knots ``required`` (with their
    multiplicities) in: a neighbour's edge knots, so that its edge curve is in the space.
    Breakpoints closer than a quarter of their smallest gap to a required knot go."""
    inner = breaks[1:-1]
    if len(required):
        gap = float(np.diff(breaks).min())
        near = np.abs(inner[:, None] - required[None]).min(axis=1) < 0.25 * gap
        inner = inner[~near]
    values = np.unique(np.concatenate([inner, required]))
    counts = np.array([max(int(np.count_nonzero(required == x)), 1) for x in values], dtype=int)
    return np.concatenate([np.zeros(p + 1), np.repeat(values, counts), np.ones(p + 1)])


def _kron_band(terms: Sequence[Tuple[np.ndarray, np.ndarray]], du: Direction, dv: Direction
               ) -> Tuple[np.ndarray, np.ndarray]:
    """(start, band) of sum_t A_t (x) B_t over the net, row i of the net's pole (i, j) at
    the unknown pos_u(i) nv + pos_v(j) (:func:`cagd.basis.banded.solve_banded_rows`' rows):
    the poles within p of each other per direction (cyclically when periodic)."""
    nu, nv = du.n, dv.n
    size = nu * nv
    reach = du.reach * nv + dv.reach
    width = min(2 * reach + 1, size)
    index = du.pos[:, None] * nv + dv.pos[None, :]
    start = np.clip(np.arange(size) - reach, 0, size - width)
    band = np.zeros((size, width))
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    for di in range(-du.p, du.p + 1):
        i2 = (i + di) % nu if du.periodic else i + di
        for dj in range(-dv.p, dv.p + 1):
            j2 = (j + dj) % nv if dv.periodic else j + dj
            ok = (i2 >= 0) & (i2 < nu) & (j2 >= 0) & (j2 < nv)
            a, b, a2, b2 = i[ok], j[ok], i2[ok], j2[ok]
            value = sum(A[a, a2] * B[b, b2] for A, B in terms)
            I, J = index[a, b], index[a2, b2]
            band[I, J - start[I]] += value
    return start, band


def thin_plate_terms(du: Direction, dv: Direction) -> List[Tuple[np.ndarray, np.ndarray]]:
    """G2u (x) G0v + 2 G1u (x) G1v + G0u (x) G2v: int |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2."""
    gu, gv = du.grams, dv.grams
    return [(gu[2], gv[0]), (2.0 * gu[1], gv[1]), (gu[0], gv[2])]


class HeldRows:
    """Rows of control points held by a solve: ``fixed`` {(i, j): point} (normalised), and
    the tangent edges, each (row-1 pole indices (k, 2), row-0 values E (k, d), cross
    difference poles D (k, d)): row 1 = row 0 + alpha D."""

    def __init__(self) -> None:
        self.fixed: Dict[Tuple[int, int], np.ndarray] = {}
        self.tangents: List[Tuple[np.ndarray, np.ndarray, np.ndarray]] = []


def solve_net(Q: np.ndarray, du: Direction, dv: Direction, smoothing: float, held: HeldRows
              ) -> Tuple[np.ndarray, np.ndarray]:
    """The control points (nu, nv, d) minimising the module docstring's functional with
    the held rows, and the alphas of the tangent edges."""
    m, n, d = Q.shape
    nu, nv = du.n, dv.n
    data = (du.N.T @ du.N / m, dv.N.T @ dv.N / n)
    bend = thin_plate_terms(du, dv)
    # the weight: smoothing, and at least NET_REGULARISATION of the data term's scale
    # (knot spans the grow / shrink leave without a parameter stay defined)
    unit = float(np.abs(data[0]).max() * np.abs(data[1]).max()) / max(
        sum(float(np.abs(A).max() * np.abs(B).max()) for A, B in bend), 1e-300)
    weight = max(smoothing, NET_REGULARISATION * unit)
    start, A = _kron_band([data] + [(weight * A, B) for A, B in bend], du, dv)
    index = du.pos[:, None] * nv + dv.pos[None, :]
    rhs = np.zeros((nu * nv, d))
    rhs[index.ravel()] = _both(du.N.T, Q, dv.N.T).reshape(-1, d) / (m * n)
    k = len(held.tangents)
    keys = list(held.fixed)
    for rows, E, _ in held.tangents:
        keys += [tuple(ij) for ij in rows]
    scalars = np.array([index[i, j] for i, j in keys], dtype=int)
    values = np.zeros((len(keys), d * (k + 1)))
    if held.fixed:
        values[:len(held.fixed), :d] = np.array(list(held.fixed.values()))
    at = len(held.fixed)
    for e, (rows, E, D) in enumerate(held.tangents):
        values[at:at + len(rows), :d] = E
        values[at:at + len(rows), d * (e + 1):d * (e + 2)] = D
        at += len(rows)
    B = np.zeros((nu * nv, d * (k + 1)))
    B[:, :d] = rhs
    X = solve_fixed(start, A.copy(), B, scalars, values)
    X0, alphas = X[:, :d], np.zeros(k)
    if k:
        Xe = [X[:, d * (e + 1):d * (e + 2)] for e in range(k)]
        AXe = [banded_product(start, A, x) for x in Xe]
        G = np.array([[float((Xe[a] * AXe[b]).sum()) for b in range(k)] for a in range(k)])
        g = np.array([float((Xe[a] * (banded_product(start, A, X0) - rhs)).sum()) for a in range(k)])
        try:
            alphas = np.maximum(np.linalg.solve(G, -g), MIN_ALPHA)
        except np.linalg.LinAlgError:
            raise CagdError("tangent_edges: the held tangent edges leave the fit undetermined") from None
        X0 = X0 + sum(a * x for a, x in zip(alphas, Xe))
    return X0[index.ravel()].reshape(nu, nv, d), alphas


def net_misses(Q: np.ndarray, du: Direction, dv: Direction, P: np.ndarray) -> np.ndarray:
    """|S(u_k, v_l) - Q_kl| (m, n) from the collocation matrices."""
    return np.sqrt(((_both(du.N, P, dv.N) - Q) ** 2).sum(-1))


def _both(A: np.ndarray, X: np.ndarray, B: np.ndarray) -> np.ndarray:
    """sum_ij A_ki X_ij B_lj (k, l, d) as two matrix products (the dense per-direction
    matrices: O(k i j d + k j l d), not the four-fold loop)."""
    k, (i, j, d) = A.shape[0], X.shape
    Y = (A @ X.reshape(i, j * d)).reshape(k, j, d)                       # (k, j, d)
    return np.einsum("lj,kjd->kld", B, Y, optimize=True)



#: the edges of a rectangular net (as :data:`cagd.surfaces.continuity.EDGES`): the
#: direction whose parameter is constant along it, and its end
EDGE_NAMES = ("u0", "u1", "v0", "v1")
#: the opposite edge, the default edge of a neighbour given without one
OPPOSITE = {"u0": "u1", "u1": "u0", "v0": "v1", "v1": "v0"}


class Edge:
    """A tangent edge of the fit: ``name``; ``kind`` "grid" (the grid's own boundary row
    and cross derivatives) or "surface" (a neighbour's edge: E its edge row of control
    points and D the difference row leaving it, model units, on the knots with the
    interior knots ``required`` on [0, 1])."""

    def __init__(self, name: str, kind: str, E: Optional[np.ndarray] = None, D: Optional[np.ndarray] = None,
                 required: Optional[np.ndarray] = None, feet: Optional[np.ndarray] = None):
        self.name, self.kind, self.E, self.D = name, kind, E, D
        self.required = np.zeros(0) if required is None else required
        self.feet = feet
        self.knots = None                      # the neighbour's edge knots on [0, 1]

    def on(self, U: np.ndarray, p: int) -> Tuple[np.ndarray, np.ndarray]:
        """A neighbour's (E, D) on the fit's knots U along the edge (model units): the
        edge curve and the difference row refined by the fit's extra knots (knot
        refinement, Piegl & Tiller 5.3: the same curves in the finer space)."""
        from ..curves.bspline import BSplineCurve
        assert self.E is not None and self.D is not None and self.knots is not None
        values, counts = np.unique(U, return_counts=True)
        own = np.array([np.count_nonzero(self.knots == x) for x in values])
        extra = np.repeat(values, np.maximum(counts - own, 0))
        ED = np.concatenate([self.E, self.D], axis=1)
        refined = np.asarray(BSplineCurve(ED, p, self.knots).refine(extra).control_points, float) \
            if len(extra) else ED
        d = self.E.shape[1]
        return refined[:, :d], refined[:, d:]

    def rows(self, nu: int, nv: int) -> Tuple[np.ndarray, np.ndarray]:
        """(row 0, row 1) pole indices (k, 2) along the edge."""
        k = nv if self.name[0] == "u" else nu
        r = np.arange(k)
        first, second = {"u0": (0, 1), "u1": (nu - 1, nu - 2), "v0": (0, 1), "v1": (nv - 1, nv - 2)}[self.name]
        if self.name[0] == "u":
            return np.stack([np.full(k, first), r], 1), np.stack([np.full(k, second), r], 1)
        return np.stack([r, np.full(k, first)], 1), np.stack([r, np.full(k, second)], 1)


def neighbour_edge(name: str, spec: Union["BSplineSurface", Tuple["BSplineSurface", str]], Q: np.ndarray, pu: int,
                   pv: int) -> Edge:
    """The Edge of a neighbouring surface: ``spec`` a BSplineSurface (its edge opposite to
    ``name``) or (surface, its edge name). Its edge degree raised to the fit's (degree
    elevation, Piegl & Tiller 5.5); the direction of the edge turned to the grid's
    boundary row (the ends nearer its first and last point); the feet of the boundary
    row's points on the edge curve (certified closest points) give the grid's parameters
    along the edge."""
    from ..queries.closest import closest_point
    from ..surfaces.bspline import BSplineSurface
    if isinstance(spec, (tuple, list)) and len(spec) == 2:
        surface, other = spec
    else:
        surface, other = spec, OPPOSITE[name]
    if not isinstance(surface, BSplineSurface):
        raise CagdError(f"tangent_edges: edge {name!r} expects 'grid', a BSplineSurface or (BSplineSurface, edge), "
                        f"got {type(surface).__name__}")
    if other not in EDGE_NAMES:
        raise CagdError(f"tangent_edges: the neighbour's edge must be one of {EDGE_NAMES}, got {other!r}")
    if surface.is_rational:
        raise CagdError(f"tangent_edges: the neighbour of edge {name!r} is rational; its tangent plane is not held "
                        f"by a polynomial fit (rebuild it first)")
    if surface.dim != Q.shape[2]:
        raise CagdError(f"tangent_edges: the neighbour of edge {name!r} is {surface.dim}-D, the points "
                        f"{Q.shape[2]}-D")
    S = surface.clamped() if (surface.periodic_u or surface.periodic_v) else surface
    along = "v" if other[0] == "u" else "u"          # the neighbour's direction along its edge
    p_own = pv if name[0] == "u" else pu
    p_nb = S.degree_v if along == "v" else S.degree_u
    if p_nb > p_own:
        raise CagdError(f"degree: edge {name!r} runs along a degree-{p_own} direction of the fit, its neighbour's "
                        f"edge has degree {p_nb}; fit with degree >= {p_nb} there")
    if p_own > p_nb:
        S = S.elevate(along, p_own - p_nb)
    P = np.asarray(S.control_points, float)
    if along == "u":
        P = P.transpose(1, 0, 2)                     # rows across the edge, columns along it
    knots = np.asarray(S.knots_v if along == "v" else S.knots_u, float)
    E, D = (P[0], P[0] - P[1]) if other.endswith("0") else (P[-1], P[-1] - P[-2])
    a, b = knots[0], knots[-1]
    t = (knots - a) / (b - a)
    row = Q[0] if name == "u0" else Q[-1] if name == "u1" else Q[:, 0] if name == "v0" else Q[:, -1]
    flip = (np.linalg.norm(row[0] - E[-1]) + np.linalg.norm(row[-1] - E[0])
            < np.linalg.norm(row[0] - E[0]) + np.linalg.norm(row[-1] - E[-1]))
    if flip:
        E, D, t = E[::-1], D[::-1], (1.0 - t)[::-1]
    from ..curves.bspline import BSplineCurve
    curve = BSplineCurve(E, p_own, t)
    feet = np.clip(np.asarray(closest_point(curve, row).params, float), 0.0, 1.0)
    feet[0], feet[-1] = 0.0, 1.0
    if np.any(np.diff(feet) <= 0.0):
        raise CagdError(f"tangent_edges: the grid's boundary row at {name!r} does not run along the neighbour's "
                        f"edge {other!r} (its feet on it are not increasing)")
    edge = Edge(name, "surface", E, D, t[p_own + 1:len(t) - p_own - 1], feet)
    edge.knots = t
    return edge


def _cross_derivatives(Q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """dQ/dt at row 0 of Q (m, k, d) by the one-sided 3-point formula (2-point for m = 2)
    on the non-uniform parameters t."""
    if len(t) < 3:
        return (Q[1] - Q[0]) / (t[1] - t[0])
    h1, h2 = t[1] - t[0], t[2] - t[0]
    return (-(h1 + h2) / (h1 * h2) * Q[0] + h2 / (h1 * (h2 - h1)) * Q[1] - h1 / (h2 * (h2 - h1)) * Q[2])


def _edge_rows(edge: Edge, Q: np.ndarray, u: np.ndarray, v: np.ndarray, du: Direction, dv: Direction,
               center: np.ndarray, scale: float) -> Tuple[np.ndarray, np.ndarray]:
    """(E, D) of an edge in the normalised frame on the fit's knots: a neighbour's rows,
    or the 1-D fits (ends held) of the grid's boundary row and its cross derivatives."""
    d_along, t = (dv, v) if edge.name[0] == "u" else (du, u)
    if edge.kind == "surface":
        E, D = edge.on(d_along.U, d_along.p)
        return (E - center) / scale, D / scale
    from .rebuild import _fit_rows
    G = {"u0": Q, "u1": Q[::-1], "v0": Q.transpose(1, 0, 2), "v1": Q.transpose(1, 0, 2)[::-1]}[edge.name]
    across = {"u0": u, "u1": 1.0 - u[::-1], "v0": v, "v1": 1.0 - v[::-1]}[edge.name]
    E = _fit_rows(d_along.U, d_along.p, t, G[0])
    # the derivative into the fit per unit parameter across the edge (as a neighbour's D)
    D = _fit_rows(d_along.U, d_along.p, t, _cross_derivatives(G, across))
    return E, D / max(float(np.abs(D).max()), 1e-300)


class NetFit:
    """What :func:`fit_net` returns: the net P (model units), the knots U, V (full,
    unwrapped when periodic), the rounds run and the alphas of the tangent edges."""

    def __init__(self, P: np.ndarray, U: np.ndarray, V: np.ndarray, rounds: int, alphas: np.ndarray):
        self.P, self.U, self.V, self.rounds, self.alphas = P, U, V, rounds, alphas


def _least(p: int, periodic: bool, tangents: int) -> int:
    """The fewest poles of a direction: p + 1; 2 p + 1 periodic (the cyclic band's
    offsets -p .. p distinct); 4 with both its edges' tangents held (rows 0, 1, n-2, n-1)."""
    if periodic:
        return 2 * p + 1
    return max(p + 1, 4 if tangents == 2 else 2)


def fit_net(Q: np.ndarray, u: np.ndarray, v: np.ndarray, tol: float, degrees: Tuple[int, int],
            caps: Tuple[int, int], periodic: Tuple[bool, bool], edges: Sequence[Edge], smoothing: float,
            g0: bool) -> NetFit:
    """Grow / shrink / trim (as :func:`cagd.fitting.fit_surface._shrunk` and
    :func:`cagd.fitting.fit_surface._trimmed`) the breakpoints of the full-net least squares
    of the grid Q (m, n, d) at the parameters u, v (a periodic direction's in [0, 1)) until
    every point is within tol at its parameters; the span counts driven by each row's and
    column's largest miss. ``g0``: the boundary rows the 1-D fits of the grid's boundary
    rows (as the separable fit); the corners held at the corner points."""
    from .fit import MAX_FIT_ROUNDS
    from .fit_surface import _grown, _shrunk, _trimmed
    from .interpolation import _frame
    from .rebuild import _fit_rows
    m, n, d = Q.shape
    pu, pv = degrees
    center, scale = _frame(Q.reshape(-1, d))
    Qn = (Q - center) / scale
    tol_n = tol / scale
    names = {e.name for e in edges}
    least = (_least(pu, periodic[0], len(names & {"u0", "u1"})), _least(pv, periodic[1], len(names & {"v0", "v1"})))
    # edges u0 / u1 run along v: the v knots take their neighbours' knots (and v0 / v1 the u knots)
    req_u, req_v = (np.sort(np.concatenate([np.zeros(0)] + [e.required for e in edges if e.name[0] == axis]))
                    for axis in "vu")
    for axis, (size, cap) in enumerate(zip((m, n), caps)):
        what = ("u", "rows") if axis == 0 else ("v", "columns")
        if size < least[axis]:
            raise CagdError(f"points: the fit needs at least {least[axis]} control points along {what[0]}, more than "
                            f"the grid's {size} {what[1]} allow")
        if cap < least[axis]:
            raise CagdError(f"max_control_points: at least {least[axis]} control points along {what[0]} "
                            f"({'periodic' if periodic[axis] else 'tangent edges held'}), got a cap of {cap}")
    most = tuple(c if per else c - p for c, per, p in zip(caps, periodic, degrees))
    # a periodic direction's knots kept conditioned by its sites (fit_surface._placed); the
    # clamped ones rely on the regulariser as before
    modes = ("periodic" if periodic[0] else "", "periodic" if periodic[1] else "")
    last_alphas = [np.zeros(0)]

    def directions(bu, bv):
        du = direction(bu, pu, u, periodic[0], req_u if len(req_u) else None)
        dv = direction(bv, pv, v, periodic[1], req_v if len(req_v) else None)
        return du, dv

    def solve(bu, bv):
        du, dv = directions(bu, bv)
        if du.n < least[0] or dv.n < least[1] or du.n > m + len(req_u) + pu or dv.n > n + len(req_v) + pv:
            return None, np.full((m, n), np.inf)
        held = HeldRows()
        if g0:
            for name in EDGE_NAMES:
                row = {"u0": Qn[0], "u1": Qn[-1], "v0": Qn[:, 0], "v1": Qn[:, -1]}[name]
                d_along, t = (dv, v) if name[0] == "u" else (du, u)
                try:
                    values = _fit_rows(d_along.U, d_along.p, t, row)
                except CagdError:      # a system above LSQ_DENSE_MAX with a span without a site
                    return None, np.full((m, n), np.inf)
                for ij, x in zip(Edge(name, "grid").rows(du.n, dv.n)[0], values):
                    held.fixed[tuple(ij)] = x
        if not any(periodic):
            for i, j, (a, b) in ((0, 0, (0, 0)), (du.n - 1, 0, (-1, 0)), (0, dv.n - 1, (0, -1)),
                                 (du.n - 1, dv.n - 1, (-1, -1))):
                held.fixed[(i, j)] = Qn[a, b]
        for e in edges:
            r0, r1 = e.rows(du.n, dv.n)
            for ij in np.concatenate([r0, r1]):
                held.fixed.pop(tuple(ij), None)
            try:
                E, D = _edge_rows(e, Qn, u, v, du, dv, center, scale)
            except CagdError:          # a 1-D fit above LSQ_DENSE_MAX with a span without a parameter
                return None, np.full((m, n), np.inf)
            held.tangents.append((r1, E, D))
            for ij, x in zip(r0, E):
                held.fixed[tuple(ij)] = x
        P, alphas = solve_net(Qn, du, dv, smoothing, held)
        last_alphas[0] = alphas
        return (P, du, dv, alphas), net_misses(Qn, du, dv, P)

    def sources(fit):
        return [(u, fit[4].max(axis=1))], [(v, fit[4].max(axis=0))]

    bu = np.linspace(0.0, 1.0, (least[0] if periodic[0] else least[0] - pu) + 1)
    bv = np.linspace(0.0, 1.0, (least[1] if periodic[1] else least[1] - pv) + 1)
    S, miss = solve(bu, bv)
    if S is None:
        raise CagdError(f"points: a {m} x {n} grid is too small for the asked fit (at least {least[0]} x "
                        f"{least[1]} control points)")
    rounds = 0
    while miss.max() > tol_n and rounds < MAX_FIT_ROUNDS:
        rounds += 1
        nu_ = _grown(bu, u, miss.max(axis=1), tol_n, pu, most[0], modes[0])
        nv_ = _grown(bv, v, miss.max(axis=0), tol_n, pv, most[1], modes[1])
        if len(nu_) == len(bu) and len(nv_) == len(bv):
            break
        S2, miss2 = solve(nu_, nv_)
        if S2 is None:
            break
        bu, bv, S, miss = nu_, nv_, S2, miss2
    best, shrunk = _shrunk((S, bu, bv, float(miss.max()), miss), solve, sources, tol_n, degrees,
                           MAX_FIT_ROUNDS - rounds, modes)
    best, trimmed = _trimmed(best, solve, sources, tol_n, degrees, interlace=modes)
    P, du, dv, alphas = best[0]
    P = P * scale + center
    # the held rows exactly, in model units: the boundary curves' 1-D fits, the corner
    # points, then the tangent edges' two rows (they win where they meet the others)
    if g0:
        from .fit_surface import _boundary_rows
        for name, rows in zip(EDGE_NAMES, _boundary_rows(Q, u, v, du.U, dv.U, pu, pv)):
            r0 = Edge(name, "grid").rows(du.n, dv.n)[0]
            P[r0[:, 0], r0[:, 1]] = rows
    if not any(periodic):
        P[0, 0], P[0, -1], P[-1, 0], P[-1, -1] = Q[0, 0], Q[0, -1], Q[-1, 0], Q[-1, -1]
    for e, alpha in zip(edges, alphas):
        r0, r1 = e.rows(du.n, dv.n)
        if e.kind == "surface":
            E, D = e.on(*((dv.U, pv) if e.name[0] == "u" else (du.U, pu)))
            P[r0[:, 0], r0[:, 1]] = E
            P[r1[:, 0], r1[:, 1]] = E + alpha * D
        else:
            P[r1[:, 0], r1[:, 1]] = P[r0[:, 0], r0[:, 1]] + alpha * scale * _edge_rows(
                e, Qn, u, v, du, dv, center, scale)[1]
    return NetFit(P, du.U, dv.U, rounds + shrunk + trimmed, alphas)
