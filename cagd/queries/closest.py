"""Closest points on curves and surfaces: global, vectorized over many points, certified.

For each query point X the engine minimises g(x) = |S(x) - X|^2 over the parameter
domain (point inversion, Piegl & Tiller 6.1; seed 004, ch. 1 §4 minimum distance):

1. the object is cut into small Bezier cells (:mod:`cagd.queries.bounds`); each has a
   hull sphere (centre c_k, radius r_k), so |S - X| >= |X - c_k| - r_k on the cell;
2. a voxel grid of cell centres gives every point its nearby cells; the nearest cell
   midpoint seeds a projected Newton iteration on g (clamped to the domain, wrapped
   in periodic directions), evaluated from per-piece power-form tables by nested Horner;
3. branch and bound certifies the result: every cell whose sphere bound is below the
   distance found gets a second-order bound
   g(x) >= g(c) + grad g(c).(x - c) + m/2 |x - c|^2, with m a lower bound of the
   Hessian 2 (J^T J + (S - X).d2S) over the cell from the hodograph bounds; cells that
   may still hold a closer point are refined by box-constrained Newton and split. The
   first round bounds, per point, the parameter box spanned by its nearby cells at once
   (expanded at x* itself, no evaluation); only points it does not settle go cell by cell.

The minimum of all bounds is ``lower_bounds``: no point of the object is closer than
it, so ``distances - lower_bounds`` tells how sure the answer is.
"""
from __future__ import annotations

from typing import NamedTuple, Optional
import weakref

import numpy as np

from .. import _checks
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from .bounds import BezierPieces, bezier_pieces
from ._local import BLOCK as _BLOCK, block_max as _block_max, box_lower_bound, pair_distances as _distances, \
    PowerTable, projected_newton, split_boxes as _split

__all__ = ["ClosestPoints", "Projector", "closest_point"]


class ClosestPoints(NamedTuple):
    """Result of :func:`closest_point` for N points (or N local minima of one point).

    params: (N,) curve parameters or (N, 2) surface parameters; feet: (N, dim) closest
    points; distances: (N,); converged: (N,) the local Newton refinement met ``tol``
    within ``max_iterations``; lower_bounds: (N,) certified lower bounds on the true
    distance from the point to the whole object (``lower_bounds <= distances``)."""
    params: np.ndarray
    feet: np.ndarray
    distances: np.ndarray
    converged: np.ndarray
    lower_bounds: np.ndarray


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


class Projector:
    """An object prepared for closest-point queries: its Bezier cells, their hull spheres,
    derivative bounds and a voxel grid of the cells (built once, reused by every call).

    Args:
        obj: any engine curve or surface (a Bezier triangle is handled through its
            collapsed-edge NURBS form; parameters are mapped back to the triangle's).
        cells: target number of cells (default: 16 per Bezier piece, at least 64 (curves) or
            256 (surfaces), at most 512 or 4096).
    """

    def __init__(self, obj, cells: Optional[int] = None):
        if not isinstance(obj, (Curve, Surface)):
            raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")
        self.triangle = isinstance(obj, Surface) and not obj.rectangular
        self.pieces = bezier_pieces(obj)
        k, m = self.pieces.k, len(self.pieces)
        default = min(512, max(64, 16 * m)) if k == 1 else min(4096, max(256, 16 * m))
        target = _checks.integer(cells, "cells", 1) if cells is not None else default
        per = max(2, int(np.ceil((target / m) ** (1.0 / k))))
        self.cells: BezierPieces = self.pieces.subdivided(per)
        # power-form table for evaluation (the Bernstein path above degree 7, where the
        # power basis loses accuracy)
        self._power = PowerTable(self.pieces) if max(self.pieces.degrees) <= 7 else None
        self.k, self.dim = k, self.pieces.dim
        self.domain = self.pieces.domain
        self.width = self.domain[:, 1] - self.domain[:, 0]
        self.wrap = np.array(self.pieces.periodic, dtype=bool)
        self.lo, self.hi = self.cells.lower, self.cells.upper
        self.centers, self.radii = self.cells.hull_spheres()
        self.L, self.M = self.cells.derivative_bounds()
        self.T3 = self.cells.third_derivative_bounds()
        shape = self.cells.shape
        self.coords = np.stack(np.unravel_index(np.arange(len(self.cells)), shape), axis=1)
        self.block = [_block_max(B, shape) for B in (self.L, self.M, self.T3)]
        self.mids = 0.5 * (self.lo + self.hi)
        idx = np.arange(len(self.cells))
        d = self.cells.derivatives(idx, self.mids, 1)
        self.mid_points = self._lead(d)
        self.mid_jacobians = d[1][:, :, None] if self.k == 1 else np.stack([d[1, 0], d[0, 1]], axis=2)
        # spheres centred at the cell midpoints' images (convex hull inside): the distance
        # to the midpoint gives both the seed and the sphere bound
        Pc = self.cells.control_points.reshape(len(self.cells), -1, self.dim)
        self.mid_radii = np.sqrt(((Pc - self.mid_points[:, None]) ** 2).sum(-1).max(axis=1)) * (1.0 + 1e-12)
        P = self.pieces.control_points.reshape(-1, self.dim)
        self.size = max(float(np.ptp(P, axis=0).max()), 1e-300)
        self._build_grid()

    # --- evaluation --------------------------------------------------------------------
    def _lead(self, d: np.ndarray) -> np.ndarray:
        return d[0] if self.k == 1 else d[0, 0]

    def evaluate(self, x: np.ndarray, order: int):
        """S, J (n, dim, k) and, for order 2, the second partials (n, dim, k, k) at x (n, k)."""
        if self._power is not None:
            return self._power.evaluate(x, order)
        d = self.pieces.derivatives(self.pieces.locate(x), x, order)
        if self.k == 1:
            S, J = d[0], d[1][:, :, None]
            return (S, J) if order == 1 else (S, J, d[2][:, :, None, None])
        S, J = d[0, 0], np.stack([d[1, 0], d[0, 1]], axis=2)
        if order == 1:
            return S, J
        H = np.stack([np.stack([d[2, 0], d[1, 1]], axis=2), np.stack([d[1, 1], d[0, 2]], axis=2)], axis=3)
        return S, J, H

    def value(self, x: np.ndarray) -> np.ndarray:
        if self._power is not None:
            return self._power.evaluate(x, 0)
        return self._lead(self.pieces.derivatives(self.pieces.locate(x), x, 0))

    # --- voxel grid of cell centres ----------------------------------------------------------
    def _build_grid(self) -> None:
        """Voxels of side V = median cell radius; voxel Z lists every cell whose sphere
        comes within T = 2 V of Z (points farther than T from every midpoint take the
        brute-force path). A point in Z with a cell midpoint closer than T therefore sees
        every cell that could hold a point closer than that: the rest are >= T away."""
        r = self.radii
        typical = float(np.median(r))
        self.T = 2.0 * typical + 1e-12 * self.size
        V = max(typical, 1e-9 * self.size)
        origin = self.centers.min(axis=0) - self.T - r.max()
        extent = self.centers.max(axis=0) + self.T + r.max() - origin
        while np.prod(np.ceil(extent / V) + 1) > 2e6:
            V *= 1.5
        dims = (np.ceil(extent / V) + 1).astype(np.intp)
        reach = self.T + r
        lo = np.floor((self.centers - reach[:, None] - origin) / V).astype(np.intp).clip(0, dims - 1)
        hi = np.floor((self.centers + reach[:, None] - origin) / V).astype(np.intp).clip(0, dims - 1)
        span = hi - lo + 1
        count = np.prod(span, axis=1)
        cell = np.repeat(np.arange(len(r)), count)
        local = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        vox = np.zeros(len(cell), dtype=np.intp)
        rem = local
        for a in range(self.dim - 1, -1, -1):          # local index -> voxel coordinates
            s = span[cell, a]
            coord = lo[cell, a] + rem % s
            rem = rem // s
            vox = vox + coord * int(np.prod(dims[a + 1:]))
            # exact test: distance from the voxel box to the centre below T + r
            zlo = origin[a] + coord * V
            gap = np.maximum(0.0, np.maximum(zlo - self.centers[cell, a], self.centers[cell, a] - zlo - V))
            if a == self.dim - 1:
                acc = gap ** 2
            else:
                acc = acc + gap ** 2
        keep = acc < reach[cell] ** 2
        vox, cell = vox[keep], cell[keep]
        order = np.argsort(vox, kind="stable")
        self._grid_cells = cell[order]
        self._grid_start = np.searchsorted(vox[order], np.arange(int(np.prod(dims)) + 1))
        self._origin, self._V, self._dims = origin, V, dims

    def candidates(self, X: np.ndarray):
        """Per point: the seed cell, the upper bound U0 (distance to that cell's midpoint),
        and the (point, cell) pairs whose sphere bound is below U0; plus the bound of all
        cells left out, per point."""
        N = len(X)
        with np.errstate(over="ignore", invalid="ignore"):
            zf = np.floor((X - self._origin) / self._V)
        inside = np.all(np.isfinite(zf) & (zf >= 0) & (zf < self._dims), axis=1)
        z = np.where(inside[:, None], zf, 0).astype(np.intp)
        vid = np.zeros(N, dtype=np.intp)
        for a in range(self.dim):
            vid = vid * self._dims[a] + np.where(inside, z[:, a], 0)
        start = self._grid_start[vid]
        count = np.where(inside, self._grid_start[vid + 1] - start, 0)
        pid = np.repeat(np.arange(N), count)
        offs = np.arange(len(pid)) - np.repeat(np.cumsum(count) - count, count)
        cell = self._grid_cells[start[pid] + offs]
        dm = _distances(X, pid, self.mid_points, cell)
        U0 = np.full(N, np.inf)
        seed = np.zeros(N, dtype=np.intp)
        has = count > 0
        if len(pid):
            first = (np.cumsum(count) - count)[has]
            U0[has] = np.minimum.reduceat(dm, first)
            hit = np.flatnonzero(dm == U0[pid])
            u, i = np.unique(pid[hit], return_index=True)
            seed[u] = cell[hit[i]]
        fast = has & (U0 <= self.T)
        keep = fast[pid]
        pid, cell = pid[keep], cell[keep]
        rest = np.where(fast, self.T, np.inf)
        far = np.flatnonzero(~fast)
        if far.size:
            fp, fc, fU, fs, frest = self._brute(X[far])
            U0[far], seed[far], rest[far] = fU, fs, frest
            pid, cell = np.concatenate([pid, far[fp]]), np.concatenate([cell, fc])
        if far.size:
            lb = _distances(X, pid, self.centers, cell) - self.radii[cell]
        else:
            lb = dm[keep] - self.mid_radii[cell]
        keep = lb < U0[pid]
        np.minimum.at(rest, pid[~keep], lb[~keep])
        return seed, U0, pid[keep], cell[keep], lb[keep], rest

    def _brute(self, X: np.ndarray):
        """Every cell against every point (chunked): the far path."""
        m = len(self.radii)
        chunk = max(1, 2_000_000 // m)
        out = [[], [], [], [], []]
        for s in range(0, len(X), chunk):
            Y = X[s:s + chunk]
            dm = np.sqrt(((Y[:, None, :] - self.mid_points[None]) ** 2).sum(-1))
            lb = np.sqrt(((Y[:, None, :] - self.centers[None]) ** 2).sum(-1)) - self.radii[None]
            U = dm.min(axis=1)
            i, c = np.nonzero(lb < U[:, None])
            out[0].append(i + s), out[1].append(c), out[2].append(U), out[3].append(dm.argmin(axis=1))
            out[4].append(np.where(lb < U[:, None], np.inf, lb).min(axis=1))
        return tuple(np.concatenate(o) for o in out)

    # --- queries -----------------------------------------------------------------------------
    def closest(self, points, tol: float = 1e-12, max_iterations: int = 50,
                max_rounds: int = 40) -> ClosestPoints:
        """The closest point of the object to every row of ``points`` (see :func:`closest_point`)."""
        X = self._points(points)
        tol = _tolerance(tol)
        max_iterations = _checks.integer(max_iterations, "max_iterations", 1)
        N = len(X)
        seed, U0, pid, cell, lb_s, LB = self.candidates(X)
        dom_lo, dom_hi = np.broadcast_to(self.domain[:, 0], (N, self.k)), np.broadcast_to(self.domain[:, 1], (N, self.k))
        x, d2, conv, (Sx, Jx, Hx, xe) = projected_newton(self, X, np.arange(N), self._start(X, seed), dom_lo, dom_hi,
                                                     self.wrap, max_iterations, tol)
        d = np.sqrt(d2)
        # branch and bound over (point, box) pairs; first round: boxes near x* are bounded
        # by the expansion at x* itself (no evaluation), with bounds over the block of cells
        # around x*'s cell
        gap = 1e-10 * d + 1e-13 * self.size
        keep = lb_s < d[pid] - gap[pid]
        np.minimum.at(LB, pid[~keep], lb_s[~keep])
        pid, cell = pid[keep], cell[keep]
        home = self.cells.locate(xe)
        near = np.all(np.abs(self.coords[cell] - self.coords[home[pid]]) <= _BLOCK, axis=1)
        # one bound per point over the parameter box spanned by its near cells; the
        # points it closes drop those pairs, the others bound them cell by cell
        u, ulo, uhi = _union_boxes(pid[near], self.lo[cell[near]], self.hi[cell[near]])
        if len(u):
            h = home[u]
            lu = box_lower_bound(X[u], ulo, uhi, xe[u], Sx[u], Jx[u], Hx[u],
                                 self.block[0][h], self.block[1][h], self.block[2][h])
            lu = np.sqrt(np.maximum(lu, 0.0))
            closed = lu >= d[u] - gap[u]
            LB[u[closed]] = np.minimum(LB[u[closed]], lu[closed])
            shut = np.zeros(N, dtype=bool)
            shut[u[closed]] = True
            keep = ~(near & shut[pid])
            pid, cell, near = pid[keep], cell[keep], near[keep]
        lo, hi = self.lo[cell], self.hi[cell]
        lb = np.empty(len(pid))
        i, h = np.flatnonzero(near), home[pid[near]]
        lb[i] = box_lower_bound(X[pid[i]], lo[i], hi[i], xe[pid[i]], Sx[pid[i]], Jx[pid[i]], Hx[pid[i]],
                                self.block[0][h], self.block[1][h], self.block[2][h])
        i = np.flatnonzero(~near)
        lb[i] = self._bound(X, pid[i], cell[i], lo[i], hi[i], np.clip(x[pid[i]], lo[i], hi[i]))
        lb = np.sqrt(np.maximum(lb, 0.0))
        for _ in range(max_rounds):
            open_ = lb < d[pid] - gap[pid]
            np.minimum.at(LB, pid[~open_], lb[~open_])
            pid, cell, lo, hi = pid[open_], cell[open_], lo[open_], hi[open_]
            if not len(pid):
                break
            y, g2, ok, _ = projected_newton(self, X, pid, np.clip(x[pid], lo, hi), lo, hi, np.zeros(self.k, bool),
                                         max_iterations, tol)
            dy = np.sqrt(g2)
            order = np.lexsort((dy, pid))                # best local result per point
            first = order[np.r_[True, pid[order][1:] != pid[order][:-1]]]
            win = first[dy[first] < d[pid[first]] * (1.0 - 1e-14) - 1e-16 * self.size]
            x[pid[win]], d[pid[win]], conv[pid[win]] = y[win], dy[win], ok[win]
            gap = 1e-10 * d + 1e-13 * self.size
            lb = np.sqrt(np.maximum(self._bound(X, pid, cell, lo, hi, y), 0.0))
            open_ = lb < d[pid] - gap[pid]
            np.minimum.at(LB, pid[~open_], lb[~open_])
            pid, cell, lo, hi, lb = _split(pid[open_], cell[open_], lo[open_], hi[open_], lb[open_])
            if len(pid) > min(256 * N + 16 * len(self.radii), 2_000_000):   # bounded work
                break
            keep = lb < d[pid] - gap[pid]
            np.minimum.at(LB, pid[~keep], lb[~keep])
            pid, cell, lo, hi = pid[keep], cell[keep], lo[keep], hi[keep]
            lb = np.sqrt(np.maximum(self._bound(X, pid, cell, lo, hi, np.clip(x[pid], lo, hi)), 0.0))
        lb_s = lb
        if len(pid) and len(pid) == len(lb_s):
            np.minimum.at(LB, pid, lb_s)                 # boxes left open after max_rounds
        LB = np.minimum(LB * (1.0 - 1e-13), d)
        return self._result(x, d, conv, LB)

    def local_minima(self, point, tol: float = 1e-12, max_iterations: int = 50) -> ClosestPoints:
        """Every local minimum of the distance from one point: box-constrained Newton in
        every cell, kept where the gradient vanishes (or points into the domain at its
        boundary), duplicates merged; sorted by distance."""
        X = self._points(point)
        if len(X) != 1:
            raise CagdError(f"points: all_minima needs exactly one point, got {len(X)}")
        tol = _tolerance(tol)
        max_iterations = _checks.integer(max_iterations, "max_iterations", 1)
        m = len(self.radii)
        pid = np.zeros(m, dtype=np.intp)
        y, g2, ok, _ = projected_newton(self, X, pid, self.mids.copy(), self.lo, self.hi, np.zeros(self.k, bool),
                                     max_iterations, tol)
        S, J, H2 = self.evaluate(y, 2)
        r = S - X[0]
        grad = 2.0 * np.einsum("nd,ndk->nk", r, J)
        JtJ = np.einsum("nda,ndb->nab", J, J)
        H = 2.0 * (JtJ + np.einsum("nd,ndab->nab", r, H2))
        scale = 2.0 * (np.sqrt(g2)[:, None] + 1e-9 * self.size) * np.linalg.norm(J, axis=1) * 1e-6 + 1e-300
        at_lo = (y <= self.domain[:, 0]) & ~self.wrap & (grad > scale)
        at_hi = (y >= self.domain[:, 1]) & ~self.wrap & (grad < -scale)
        fixed = at_lo | at_hi
        good = np.all((np.abs(grad) <= scale) | fixed, axis=1)
        # second order: no descent direction along the free coordinates (not a maximum/saddle)
        floor = -1e-8 * np.trace(2.0 * JtJ, axis1=1, axis2=2) - 1e-300
        for a in range(self.k):
            good &= fixed[:, a] | (H[:, a, a] >= floor)
        if self.k == 2:
            both = ~fixed[:, 0] & ~fixed[:, 1]
            lmin = 0.5 * (H[:, 0, 0] + H[:, 1, 1]) - np.sqrt(0.25 * (H[:, 0, 0] - H[:, 1, 1]) ** 2 + H[:, 0, 1] ** 2)
            good &= ~both | (lmin >= floor)
        y, g2, ok = y[good], g2[good], ok[good]
        order = np.argsort(g2, kind="stable")               # merge duplicates: the closest of
        key = np.round((y[order] - self.domain[:, 0]) / self.width * 1e7).astype(np.int64)   # each 1e-7 bin
        key = np.where(self.wrap, np.mod(key, 10_000_000), key)
        _, first = np.unique(key, axis=0, return_index=True)
        chosen = order[np.sort(first)]
        d = np.sqrt(g2[chosen])
        lower = self.closest(X, tol, max_iterations).lower_bounds[0]
        return self._result(y[chosen], d, ok[chosen], np.minimum(np.full(len(chosen), lower), d))

    # --- helpers -----------------------------------------------------------------------------
    def _start(self, X: np.ndarray, seed: np.ndarray) -> np.ndarray:
        """Newton's start: the seed cell's midpoint m moved by one Gauss-Newton step
        (J^T J)^-1 J^T (X - S(m)) with the precomputed J(m), kept in the seed cell."""
        J = self.mid_jacobians[seed]
        rhs = np.einsum("ndk,nd->nk", J, X - self.mid_points[seed])
        A = np.einsum("nda,ndb->nab", J, J)
        A = A + 1e-12 * np.trace(A, axis1=1, axis2=2)[:, None, None] + 1e-300 * np.eye(self.k)
        step = np.linalg.solve(A, rhs[..., None])[..., 0]
        return np.clip(self.mids[seed] + step, self.lo[seed], self.hi[seed])

    def _bound(self, X, pid, cell, lo, hi, c) -> np.ndarray:
        """Second-order lower bound of g over boxes inside their cells, expanded at c."""
        S, J, H = self.evaluate(c, 2)
        return box_lower_bound(X[pid], lo, hi, c, S, J, H, self.L[cell], self.M[cell], self.T3[cell])

    def _points(self, points) -> np.ndarray:
        X = _checks.finite_array(points, "points")
        if X.ndim == 1:
            X = X[None]
        if X.ndim != 2 or X.shape[0] == 0:
            raise CagdError(f"points: expected a non-empty (N, {self.dim}) array, got shape {X.shape}")
        if X.shape[1] != self.dim:
            raise CagdError(f"points: expected {self.dim}-D points (the object is {self.dim}-D), got {X.shape[1]}-D")
        return X

    def _result(self, x, d, conv, lower) -> ClosestPoints:
        feet = self.value(x)
        if self.triangle:                                   # (s, t) -> (u, v) = (s, t (1 - s))
            x = np.stack([x[:, 0], x[:, 1] * (1.0 - x[:, 0])], axis=1)
        params = x[:, 0].copy() if self.k == 1 else x
        return ClosestPoints(params, feet, d, conv.astype(bool), lower)


def _union_boxes(pid: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Per distinct pid, the box spanning the boxes [lo, hi] of its pairs:
    (points, lower corners, upper corners)."""
    if not len(pid):
        return pid, lo, hi
    if np.any(pid[1:] < pid[:-1]):
        order = np.argsort(pid, kind="stable")
        pid, lo, hi = pid[order], lo[order], hi[order]
    first = np.flatnonzero(np.r_[True, pid[1:] != pid[:-1]])
    return pid[first], np.minimum.reduceat(lo, first, axis=0), np.maximum.reduceat(hi, first, axis=0)


def _tolerance(tol) -> float:
    tol = _checks.scalar(tol, "tol")
    if tol <= 0:
        raise CagdError(f"tol: must be positive, got {tol}")
    return tol


def projector(obj) -> Projector:
    """The cached :class:`Projector` of ``obj`` (rebuilt when the object is new)."""
    try:
        p = _CACHE.get(obj)
    except TypeError:
        return Projector(obj)
    if p is None:
        p = Projector(obj)
        try:
            _CACHE[obj] = p
        except TypeError:
            pass
    return p


def closest_point(obj, points, all_minima: bool = False, tol: float = 1e-12,
                  max_iterations: int = 50) -> ClosestPoints:
    """Closest points of an engine curve or surface to N points, global and certified.

    Args:
        obj: any cagd Curve or Surface (including Bezier triangles: their parameters are
            returned in the triangle's (u, v), u = s, v = t (1 - s) of the NURBS form).
        points: (N, dim) points (one point may be given as (dim,)).
        all_minima: return every local minimum of the distance from one point instead.
        tol: Newton stops when a step is below ``tol`` times the parameter range.
        max_iterations: bound on Newton steps per refinement (non-convergence is reported).

    Returns:
        :class:`ClosestPoints` (params, feet, distances, converged, lower_bounds).

    Raises:
        CagdError: not a curve or surface, empty or NaN points, wrong dimension, tol <= 0.

    Piegl & Tiller 6.1 (point inversion by Newton); seed 004, ch. 1 §4 (minimum distance).
    """
    p = projector(obj) if isinstance(obj, (Curve, Surface)) else Projector(obj)
    if all_minima:
        return p.local_minima(points, tol, max_iterations)
    return p.closest(points, tol, max_iterations)
