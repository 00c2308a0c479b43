"""Closest points on curves and surfaces: global, vectorized over many points, certified.

For each query point X the engine minimises g(x) = |S(x) - X|^2 over the parameter
domain (point inversion, Piegl & Tiller 6.1; seed 004, ch. 1 §4 minimum distance):

1. the object is cut into small Bezier cells (:mod:`cagd.queries.bounds`), each Bezier
   piece into parts of about equal geometric size per row and column of pieces (a thin
   face, a sliver, along its length: issue 16, :func:`_cell_counts`); each
   cell has a hull sphere (centre c_k, radius r_k), so |S - X| >= |X - c_k| - r_k on it;
2. a voxel grid lists per voxel the cells whose spheres come near it, ordered by their
   bound over the voxel; the nearest midpoint among the voxel's first few cells seeds a
   projected Newton iteration on g (clamped to the domain, wrapped in periodic
   directions; the start is a second-order step from the midpoint with its precomputed
   S, J, H), evaluated from per-piece power-form tables by nested Horner;
3. branch and bound certifies the result: the cells whose sphere bound is below the
   distance d found (a prefix of the voxel's list) get a second-order bound
   g(x) >= g(c) + grad g(c).(x - c) + m/2 |x - c|^2, with m a lower bound of the
   Hessian 2 (J^T J + (S - X).d2S) over the cell from the hodograph bounds; cells that
   may still hold a closer point are halved round by round along the longer side of
   their image (the parameter width times the cell's first-derivative bound: a
   sliver's boxes along its length), few boxes several times a round, and refined by
   box-constrained Newton every NEWTON_EVERY rounds (Newton rarely finds a nearer foot
   there; the bounds of the halves close most boxes). The
   first round bounds, per point, the parameter box spanned by its nearby cells at once
   (expanded at x* itself, no evaluation; only cells not across a break where the object
   is less than C2, found numerically); only points it does not settle go cell by cell,
   with each cell's own bounds and partials from the cell's own piece (one-sided on a
   crease). The Hessian's bound over a whole cell comes from its Bezier coefficients
   where that can close the box (:mod:`._hessian_hull`; on rational cells those of
   w^4 times it); on a cell with a collapsed edge (a pole), where the Hessian is
   indefinite, a first-order bound from the pole's point (:mod:`._pole_bound`).

The minimum of all bounds is ``lower_bounds``: no point of the object is closer than
it, so ``distances - lower_bounds`` tells how sure the answer is.

Scale and size (issue 14): the work is done in the object's normalised frame
(:class:`cagd.queries.bounds.Frame`: translated, scaled by a power of two to O(1),
knot spans at least 1e-12 of the domain), so coordinates from 1e-300 to 1e300 give the
same answer scaled; points farther than FAR_POINT (1e50) object sizes are moved in
along their direction (their foot moves by ~1e-50 of the size). Memory is bounded:
points go in chunks (POINT_CHUNK, PAIR_BUDGET), the voxel grid holds at most
GRID_ENTRIES entries, and large objects get one cell per Bezier piece.

Bounded work (issue 14): points the voxel grid does not serve (farther than T, or
outside it) descend a binary hierarchy of the cells (boxes of their control points)
instead of meeting every cell; every point keeps at most K = max(CANDIDATES,
PAIR_BUDGET / N) candidate cells and the branch and bound at most B =
min(BRANCH_PER_POINT N + BRANCH_PER_CELL cells, BRANCH_MAX) open pairs per chunk; what a
cap leaves out enters ``lower_bounds`` with its own bound, so the certificate holds
whatever is cut (it is only less tight: on crumpled random nets and curves whose every
cell's hull meets thousands of others). When more than B boxes are open after a split,
every point keeps an equal share of B, its boxes where Newton came nearest first (the
rest into ``lower_bounds``), and the search goes on until BRANCH_WORK B (point, box) rows
have been refined in all; the boxes still open then enter ``lower_bounds`` and their
points keep the nearest foot found, reported not converged (``point_converged`` False:
the distance is an upper bound, ``lower_bounds`` the certified lower one; ``message``
says so). (The search used to stop at the first overflow: the
points still open kept their local foot, reported converged with lower bound 0; a grid
point on a folded fit got 0.68 for 2.5e-10 among 120 points.) Newton in a box starts at
the nearer, in space, of the foot found (clamped to the box) and the box's midpoint.
Points whose candidate list was cut are solved again in a group small enough to keep
every cell. Surface queries of FINE_POINTS points or more use finer cells (FINE_CELLS).

Set-up (issue 16): queries of fewer than LIGHT_POINTS points build a light projector
(about one cell per Bezier piece, no voxel grid: every point descends the hierarchy),
whose set-up is a few hundredths of the default one's; the default one makes the voxel
lists of the voxels a query meets (the whole grid only for a query of several chunks, or
once the lists made for queries have cost as much as it); the projectors of an object are
cached by identity and, for the classes naming their defining attributes
(``_content_fields``), by content, so that an equal object built again finds them.
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace
import hashlib
import itertools
from typing import Callable, List, NamedTuple, Optional, Sequence, Tuple, Union, cast
import weakref

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks, _periodic as periodic
from .._deprecation import changed
from .._ranks import ranks
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from .results import ClosestPoints
from .bounds import BLOCK as _BLOCK, FAR_POINT, BezierPieces, Frame, HullIntervals, bezier_pieces, \
    block_max as _block_max, box_lower_bound, closed_directions, robust_distance
from ._cells import PowerTable, pair_distances as _distances, split_boxes as _split
from ._hessian_hull import HessianHull, RationalHessianHull
from ._pole_bound import PoleCells
from ._newton import projected_newton
from ._numerics import AT_END_RTOL, BOUND_SHRINK_RTOL, COLLAPSED_SPEED_RTOL, LEVENBERG_RTOL, SIZE_ROUNDING, \
    SLACK_RTOL, TINY, ULP_RTOL, column_extremes, eigenvalue_2x2, row_max, smallest_per_group, squared_norms

MIN_VOXEL_RTOL = 1e-9        # the voxel size is at least this share of the size
WIN_GAP_RTOL = 1e-9          # a cell wins only by more than this share of the distance ... (the foot is proven
                             # global to it, issue 16's 1e-9 relative; at 1e-10 the nose (a pole) of a fuselage
                             # face split 11 of 500 points to 5e-10 of their distance: 419,030 Newton rows)
BETTER_RTOL = 1e-14          # a local result improves on the best by more than this share ...
BETTER_SIZE_RTOL = 1e-16     # ... plus this share of the size
STATIONARY_DIST_RTOL = 1e-9  # stationarity test: |grad g| <= 2 (|r| + this share of the size) |J| ...
GRADIENT_RTOL = 1e-6         # ... times this
SADDLE_RTOL = 1e-8           # an eigenvalue of Hess g below -this share of its trace: a saddle, not a minimum
FLAT_HESSIAN_RTOL = 1e-6     # an eigenvalue below this share of the trace: the minima form a continuum
SAME_FOOT_RTOL = 1e-6        # feet closer than this share of the size (at equal distance) are one minimum
INWARD_RTOL = 1e-4           # a foot on a domain edge is tested this share of the width inside
SECOND_ORDER_RTOL = 1e-3     # the second-order start is used where it moves under this share of a cell
C2_RTOL = 1e-10              # the derivatives at a break agree to this share: the object is C2 there
HULL_BOX_SHARE = 0.25       # a box takes its cell's half-Hessian hull from this share of the cell per direction
COUNT_SLACK = 1e-9           # rounding slack of the cell counts ceil(extent / step)
THIN_SHARE = 0.25            # a direction of less than this share of the longest one's extent is thin (cut less)

__all__ = ["ClosestPoints", "Projector", "closest_point", "CLOSEST_TOL"]

CLOSEST_TOL = 1e-12     # default tol of closest_point, relative to the object's size
GRID_VOXELS = 2e6       # voxels of a Projector's grid, at most
GRID_ENTRIES = 4e6      # (voxel, cell) entries of the grid, at most (a random 300 x 300 net made 84e6)
GRID_CHUNK = 1 << 18    # candidate entries tested at once while the grid is built
POINT_CHUNK = 16384     # query points handled at once, at most (memory O(chunk), not O(N))
MIN_CHUNK = 32          # ... at least
PAIR_BUDGET = 4e6       # (point, cell) pairs formed at once, at most
CANDIDATES = 512        # cells per point kept for branch and bound (smallest sphere bounds), at least
FINE_POINTS = 65536     # closest_point of at least this many points on a surface uses ...
FINE_CELLS = 4096       # ... at least this many cells (2e4 points around a sphere: 288 cells 4.9 s, 4232 1.3 s CPU)
LIGHT_POINTS = 1024     # closest_point of fewer points builds a light projector (no voxel grid; the default
                        # one's set-up is worth it from ~4,000 points on a bumpy 50 x 50: 1 s more, 0.25 ms
                        # less per point) ...
LIGHT_CELLS = (16, 64)  # ... of one cell per Bezier piece, at least this many (curves, surfaces)
LIGHT_BUDGET = 2        # ... and twice the default's per-cell share of the branch budget (a crumpled 16 x 16
                        # net: 1x left every near point's bound 0, 2x gives bounds within 1e-13)
CACHE_OBJECTS = 16      # projectors kept by the objects' content (the most recently used) ...
CACHE_BYTES = 256 << 20  # ... holding at most this many bytes of arrays (a default 50 x 50 one: ~30 MB)
TREE_TOP = 64           # nodes of the hierarchy's top level, at most
DIRECT_PAIRS = 16384    # points x cells up to which the hierarchy's pairs are formed directly (every cell at
                        # once: one point on a 20 x 20 net, 289 cells, found its seed cell in 0.42 ms down the
                        # hierarchy, 0.05 ms directly; its candidates in 0.22 ms, 0.15 ms)
BRANCH_PER_POINT = 256  # open (point, box) pairs per point in branch and bound, at most ...
BRANCH_PER_CELL = 16    # ... plus this many per cell (a few points on a large object)
BRANCH_MAX = 2_000_000  # ... and at most this many in all
BRANCH_WORK = 6         # (point, box) rows refined (bounded; by Newton every NEWTON_EVERY rounds) in all, at
                        # most this many times that budget
                        # (the 120 grid points on a folded fit, tests/queries/test_closest_budget.py: 4 left
                        # two at a local foot, 0.1 and 0.4 away for 1e-10; 5 none)
EVAL_CHUNK = 65536      # evaluations at once (the C2 test at the breaks, the box bounds)
NEWTON_CHUNK = 262144   # (point, box) rows refined by Newton at once
NEWTON_EVERY = 4        # branch and bound: Newton in the open boxes every this many rounds; between, they
                        # are only halved and bounded (issue 16: on the 68 real faces of benchmarks.real_faces
                        # 6 of 38,857 round Newton rows found a nearer foot at 1%; their rounds took 36% less)
FEW_ROWS = 512          # ... and halved again in the same round while that makes at most this many boxes
SPLIT_LEVELS = 6        # ... up to this many halvings a round (the rounds' fixed cost: a point on a bumpy
                        # 50 x 50 net took 20 rounds of a few dozen boxes; now 6, in half the time)
TOL_CHANGED = ("tol is a distance in model units now: Newton stops when a step moves the foot by less than tol "
               "(default CLOSEST_TOL * the object's size); it was a step relative to the parameter range, which "
               "is param_tol= now")




class GridLists(NamedTuple):
    """Voxel lists: voxel i lists cells[start[i]:start[i + 1]], with non-decreasing lower
    bounds keys[...] of their distance from the voxel."""
    cells: np.ndarray
    keys: np.ndarray
    start: np.ndarray


class GridView(NamedTuple):
    """The voxel lists of query points: point j's cells are cells[start[j]:start[j] + length[j]]."""
    cells: np.ndarray
    keys: np.ndarray
    start: np.ndarray
    length: np.ndarray

    def rows(self, i: np.ndarray) -> "GridView":
        return GridView(self.cells, self.keys, self.start[i], self.length[i])

    @staticmethod
    def empty(n: int) -> "GridView":
        """n points with no lists (no grid, or outside it)."""
        zero = np.zeros(n, dtype=np.intp)
        return GridView(np.zeros(0, dtype=np.intp), np.zeros(0), zero, zero)


#: per object (by identity, and by content: :func:`projector`) its projectors by tier:
#: 0 light, 1 default, 2 fine
_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_BY_CONTENT: "OrderedDict[Tuple, dict]" = OrderedDict()


class Projector:
    """An object prepared for closest-point queries: its Bezier cells, their hull spheres,
    derivative bounds and a voxel grid of the cells (built once, reused by every call).

    Args:
        obj: any engine curve or surface (a Bezier triangle is handled through its
            collapsed-edge NURBS form; parameters are mapped back to the triangle's).
        cells: target number of cells (default: 16 per Bezier piece, at least 64 (curves) or
            256 (surfaces), at most 512 or 4096); pieces of larger geometric extent get more
            (see :func:`_cell_counts`).
        fine: surfaces get at least FINE_CELLS cells by default (for large queries: the set-up
            costs more, each point less; :func:`closest_point` uses it from FINE_POINTS points).
        light: for a few points (issue 16, set-up): about one cell per Bezier piece (at least
            LIGHT_CELLS) and no voxel grid; every point descends the hierarchy (set-up in
            milliseconds, each point costs more; :func:`closest_point` uses it below
            LIGHT_POINTS points).
    """

    def __init__(self, obj: Union[Curve, Surface], cells: Optional[int] = None, *, fine: bool = False,
                 light: bool = False):
        if not isinstance(obj, (Curve, Surface)):
            raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")
        self.triangle = isinstance(obj, Surface) and not obj.rectangular
        raw = bezier_pieces(obj)
        # every computation below is in the normalised frame (the object O(1), knot spans
        # of reasonable width); queries map points in and results out
        self.frame = Frame.of(raw.control_points, raw.breaks)
        self.pieces = self.frame.pieces(raw)
        k, m = self.pieces.k, len(self.pieces)
        usual = _tier_cells(k, m, 2 if fine else 1)
        default = _tier_cells(k, m, 0) if light else usual
        self.light = light
        # the branch-and-bound budget's per-cell share: a light projector's cells are
        # larger, certifying them takes the default's cells' share and their own splits
        self._budget_cells = LIGHT_BUDGET * usual if light else usual
        target = _checks.integer(cells, "cells", 1) if cells is not None else default
        self._target = None if cells is not None else target
        # a light projector of at least LIGHT_CELLS pieces: the pieces are the cells
        self.cells: BezierPieces = self.pieces if light and cells is None and m >= target else \
            self.pieces.subdivided(_cell_counts(self.pieces, target))
        # power-form table for evaluation (the Bernstein path above degree 7, where the
        # power basis loses accuracy)
        self._power = PowerTable(self.pieces) if max(self.pieces.degrees) <= 7 else None
        self.k, self.dim = k, self.pieces.dim
        self.domain = self.pieces.domain
        self.width = self.domain[:, 1] - self.domain[:, 0]
        self.wrap = np.array(self.pieces.periodic, dtype=bool)
        self.lo, self.hi = self.cells.lower, self.cells.upper
        self.centers, self.radii = self.cells.hull_spheres()
        self.T3 = self.cells.third_derivative_bounds()       # (keeps the lower orders: no second pass)
        self.L, self.M = self.cells.derivative_bounds()
        shape = self.cells.shape
        # per level l = 0..BLOCK: the bounds over the cells within l grid steps
        self.block = [np.stack([_block_max(B, shape, lv) for lv in range(_BLOCK + 1)])
                      for B in (self.L, self.M, self.T3)]
        self.mids = 0.5 * (self.lo + self.hi)
        idx = np.arange(len(self.cells))
        d = self.cells.derivatives(idx, self.mids, 2)
        self.mid_points = self._lead(d)
        if self.k == 1:
            self.mid_jacobians, self.mid_hessians = d[1][:, :, None], d[2][:, :, None, None]
        else:
            self.mid_jacobians = np.stack([d[1, 0], d[0, 1]], axis=2)
            self.mid_hessians = np.stack([np.stack([d[2, 0], d[1, 1]], axis=2),
                                          np.stack([d[1, 1], d[0, 2]], axis=2)], axis=3)
        # the piece of every cell, per direction and flat; per direction the C2-connected
        # runs of pieces (an expansion at x* holds over cells of its own run only)
        self._cell_piece_dir = [np.clip(np.searchsorted(b, 0.5 * (c[1:] + c[:-1]), side="right") - 1, 0, len(b) - 2)
                                for b, c in zip(self.pieces.breaks, self.cells.breaks)]
        if self.k == 1:
            self._cell_piece = self._cell_piece_dir[0]
        else:
            cu, cv = self._cell_piece_dir
            self._cell_piece = (cu[:, None] * self.pieces.shape[1] + cv[None, :]).ravel()
        # the half Hessian's Bernstein coefficients (tight bounds over a cell; rational: per
        # piece, restricted to its cells)
        self._hessian = HessianHull(self.cells) if self.cells.weights is None else \
            RationalHessianHull(self.cells) if self.cells is self.pieces else \
            RationalHessianHull(self.cells, self.pieces, self._cell_piece_dir)
        c2 = _c2_breaks(self.pieces, _c2_by_knots(obj, raw))
        self._run = [np.r_[0, np.cumsum(~ok)] for ok in c2]
        self._creases = [b[1:-1][~ok] for b, ok in zip(self.pieces.breaks, c2)]     # the breaks not C2
        self._cell_run = [run[cp] for run, cp in zip(self._run, self._cell_piece_dir)]
        # component rows (contiguous per coordinate and partial) for 1-D gathers
        self._mid_rows = (np.ascontiguousarray(self.mid_points.T), np.ascontiguousarray(self.mid_jacobians.T),
                          np.ascontiguousarray(self.mid_hessians.T))
        # spheres centred at the cell midpoints' images (convex hull inside): the distance
        # to the midpoint gives both the seed and the sphere bound
        Pc = self.cells.control_points.reshape(len(self.cells), -1, self.dim)
        self.mid_radii = np.sqrt(row_max(squared_norms(Pc - self.mid_points[:, None]))) * (1.0 + SLACK_RTOL)
        P = self.pieces.control_points.reshape(-1, self.dim)
        lo, hi = column_extremes(P)
        self.size = max(float((hi - lo).max()), TINY)
        self._poles = PoleCells.of(self.cells, self.size)      # cells with a collapsed edge (first-order bound)
        self.hull_radius = float(np.sqrt(squared_norms(P)).max())      # about the frame's origin
        self._grid: Optional[GridLists] = None          # every voxel's list, built for large queries
        if light:
            self.T, self._origin = 0.0, None
        else:
            self._grid_frame()
        self._build_tree()

    # --- evaluation --------------------------------------------------------------------
    def _lead(self, d: np.ndarray) -> np.ndarray:
        return d[0] if self.k == 1 else d[0, 0]

    def evaluate(self, x: np.ndarray, order: int, piece: Optional[np.ndarray] = None) -> Tuple[np.ndarray, ...]:
        """S, J (n, dim, k) and, for order 2, the second partials (n, dim, k, k) at x (n, k);
        ``piece``: the flat Bezier pieces to evaluate (one-sided partials on a boundary)."""
        if self._power is not None:
            return self._power.evaluate(x, order, piece)
        d = self.pieces.derivatives(self.pieces.locate(x) if piece is None else piece, x, order)
        if self.k == 1:
            S, J = d[0], d[1][:, :, None]
            return (S, J) if order == 1 else (S, J, d[2][:, :, None, None])
        S, J = d[0, 0], np.stack([d[1, 0], d[0, 1]], axis=2)
        if order == 1:
            return S, J
        H = np.stack([np.stack([d[2, 0], d[1, 1]], axis=2), np.stack([d[1, 1], d[0, 2]], axis=2)], axis=3)
        return S, J, H

    def evaluate_in(self, x: np.ndarray, order: int, piece: np.ndarray
                    ) -> Union[np.ndarray, Tuple[np.ndarray, ...]]:
        """:meth:`evaluate` (order >= 1) or :meth:`value` (order 0) on the given pieces."""
        if order >= 1:
            return self.evaluate(x, order, piece)
        if self._power is not None:
            return self._power.evaluate(x, 0, piece)
        return self._lead(self.pieces.derivatives(piece, x, 0))

    def value(self, x: np.ndarray) -> np.ndarray:
        if self._power is not None:
            return self._power.evaluate(x, 0)
        return self._lead(self.pieces.derivatives(self.pieces.locate(x), x, 0))

    # --- voxel grid of cell centres ----------------------------------------------------------
    def _grid_frame(self) -> None:
        """Voxels of side V = median cell radius; voxel Z lists every cell whose sphere
        comes within T = 2 V of Z, ordered by that sphere's distance from Z (the key). A
        point in Z at distance d <= T from the object therefore finds every cell that could
        hold a closer point in the prefix of keys below d: the rest are >= d away (points
        with d > T take the brute-force path). Here the grid's frame and each cell's box of
        voxels; the lists are made for the voxels a query meets (:meth:`_lists`), or for
        all of them at once for a query of several chunks (:meth:`_full_grid`)."""
        r = self.radii
        typical = float(np.median(r))
        self.T = 2.0 * typical + SLACK_RTOL * self.size
        V = max(typical, MIN_VOXEL_RTOL * self.size)
        origin = self.centers.min(axis=0) - self.T - r.max()
        extent = self.centers.max(axis=0) + self.T + r.max() - origin
        while np.prod(np.ceil(extent / V) + 1) > GRID_VOXELS:
            V *= 1.5
        reach = self.T + r
        while True:             # at most GRID_ENTRIES (voxel, cell) entries: bounded memory
            dims = (np.ceil(extent / V) + 1).astype(np.intp)
            lo = np.floor((self.centers - reach[:, None] - origin) / V).astype(np.intp).clip(0, dims - 1)
            hi = np.floor((self.centers + reach[:, None] - origin) / V).astype(np.intp).clip(0, dims - 1)
            count = np.prod(hi - lo + 1, axis=1)
            if float(count.sum()) <= GRID_ENTRIES:
                break
            V *= 1.5
        # the work of the whole grid (candidate entries), and of the lists made so far: once
        # these reach it, the whole grid is made (repeated queries pay at most twice)
        self._grid_work, self._lazy_work = float(count.sum()), 0.0
        self._origin, self._V, self._dims, self._reach, self._box = origin, V, dims, reach, (lo, hi)
        self._strides = np.array([int(np.prod(dims[a + 1:])) for a in range(self.dim)], dtype=np.intp)
        # the cells grouped by the shape of their box (the full grid's broadcasting); both
        # ways of making lists take the cells in this order, so that equal keys (a
        # symmetric object) come out in one order (a stable sort)
        span = hi - lo + 1
        code = np.zeros(len(span), dtype=np.int64)  # one integer per shape, ordered as the rows
        for a in range(self.dim):                   # (digit a below dims[a] + 1: < 2^dim GRID_VOXELS)
            code = code * (int(dims[a]) + 1) + span[:, a]
        _, first, group = np.unique(code, return_index=True, return_inverse=True)
        self._groups = (span[first], group.reshape(-1))
        self._cell_order = np.argsort(self._groups[1], kind="stable")

    def _entry_terms(self, cells: np.ndarray, coord: np.ndarray, a: int) -> Tuple[np.ndarray, np.ndarray]:
        """Along axis a, for cells and voxel coordinates (broadcast): the squared gap from
        the voxel slab to the cell's centre and the squared distance of the slab's centre
        from the cell's midpoint (summed over the axes: the exact test and the tie key)."""
        zlo = cast(np.ndarray, self._origin)[a] + coord * self._V
        c = self.centers[cells, a]
        return (np.maximum(0.0, np.maximum(zlo - c, c - zlo - self._V)) ** 2,
                (zlo + 0.5 * self._V - self.mid_points[cells, a]) ** 2)

    def _full_grid(self) -> "GridLists":
        """Every voxel's list (cached): the entries by groups of cells whose voxel boxes
        have the same shape (1 to 22 on the 68 real faces of benchmarks.real_faces); per
        axis the voxel coordinates and the two distance terms are (cells, span along the
        axis) arrays, summed into the box by broadcasting, GRID_CHUNK entries at a time
        (chunks of cells, and of the first axis's span where one cell's box is larger)."""
        if self._grid is not None:
            return self._grid
        lo, hi = self._box
        shapes, group = self._groups
        parts = []
        for g, shape in enumerate(shapes):
            members = np.flatnonzero(group == g)
            rest = int(np.prod(shape[1:]))                           # entries per step of the first axis
            width = int(min(shape[0], max(1, GRID_CHUNK // rest)))
            step = max(1, GRID_CHUNK // (width * rest))
            for c0, o0 in itertools.product(range(0, len(members), step), range(0, int(shape[0]), width)):
                cells = members[c0:c0 + step]
                vox, acc, mid = np.zeros((), dtype=np.intp), np.zeros(()), np.zeros(())
                for a in range(self.dim - 1, -1, -1):
                    offs = np.arange(o0, min(o0 + width, int(shape[0]))) if a == 0 else np.arange(shape[a])
                    coord = lo[cells, a][:, None] + offs
                    gap2, mid2 = self._entry_terms(cells[:, None], coord, a)
                    there = (len(cells),) + (1,) * a + (len(offs),) + (1,) * (self.dim - 1 - a)
                    vox = vox + (coord * self._strides[a]).reshape(there)
                    acc = acc + gap2.reshape(there)
                    mid = mid + mid2.reshape(there)
                # exact test: distance from the voxel box to the centre below T + r
                keep = (acc < (self._reach[cells] ** 2).reshape((-1,) + (1,) * self.dim)).reshape(len(cells), -1)
                full = keep.shape
                cell = np.broadcast_to(cells[:, None], full)[keep]
                parts.append((cell, self._grid_keys(np.broadcast_to(vox, acc.shape).reshape(full)[keep], cell,
                                                    acc.reshape(full)[keep],
                                                    np.broadcast_to(mid, acc.shape).reshape(full)[keep])))
        self._grid = self._sorted_lists(parts, int(np.prod(self._dims)))
        return self._grid

    def _lists(self, U: np.ndarray) -> "GridLists":
        """The lists of the voxels U (sorted voxel indices) alone, the same entries and keys
        as :meth:`_full_grid`'s (issue 16, set-up: the whole grid of a bumpy 50 x 50 net is
        2.5 M entries, a query of a few thousand points meets a few thousand voxels).
        Every cell's box of voxels is cut into rows along the last axis: a row's voxels
        are a run of indices, found in U by bisection, GRID_CHUNK rows at a time."""
        lo, hi = self._box
        last = self.dim - 1
        # the cells whose box meets the box of U's voxels (a few points meet few cells)
        zu = (U[:, None] // self._strides) % self._dims
        meets = np.all((lo <= zu.max(axis=0)) & (hi >= zu.min(axis=0)), axis=1)
        order = self._cell_order[meets[self._cell_order]]
        lo_o, span_o = lo[order], (hi - lo + 1)[order]
        rows_of = np.prod(span_o[:, :last], axis=1)                      # rows per cell
        occupied = np.zeros(int(np.prod(self._dims[:last])), dtype=bool)
        occupied[U // self._dims[last]] = True
        ends = np.cumsum(rows_of)
        parts = []
        c0, m = 0, len(rows_of)
        while c0 < m:
            base0 = ends[c0 - 1] if c0 else 0
            c1 = max(c0 + 1, int(np.searchsorted(ends, base0 + GRID_CHUNK, side="right")))
            n_rows = rows_of[c0:c1]
            k = ranks(n_rows)
            zs: List[np.ndarray] = [k] * self.dim
            base = np.zeros(len(k), dtype=np.intp)
            for a in range(last - 1, -1, -1):            # the row's coordinates (mixed radix)
                k, r = np.divmod(k, np.repeat(span_o[c0:c1, a], n_rows))
                zs[a] = np.repeat(lo_o[c0:c1, a], n_rows) + r
                base += zs[a] * self._strides[a]
            hit = np.flatnonzero(occupied[base // self._dims[last]])     # rows holding a voxel of U
            cell = order[np.repeat(np.arange(c0, c1), n_rows)[hit]]
            base = base[hit]
            first = np.searchsorted(U, base + lo[cell, last], side="left")
            n = np.searchsorted(U, base + hi[cell, last], side="right") - first
            row = np.repeat(np.arange(len(cell)), n)
            u = ranks(n) + first[row]
            cell = cell[row]
            zs = [zs[a][hit][row] for a in range(last)] + [U[u] - base[row]]
            acc, mid = np.zeros(()), np.zeros(())
            for a in range(last, -1, -1):                # the order of _full_grid's sums
                gap2, mid2 = self._entry_terms(cell, zs[a], a)
                acc, mid = acc + gap2, mid + mid2
            keep = acc < self._reach[cell] ** 2
            parts.append((cell[keep], self._grid_keys(u[keep], cell[keep], acc[keep], mid[keep])))
            self._lazy_work += len(k) + len(u)
            c0 = c1
        return self._sorted_lists(parts, len(U))

    def _sorted_lists(self, parts, voxels: int) -> "GridLists":
        """:class:`GridLists` of the (cells, keys) parts of ``voxels`` voxels."""
        cell, key = (np.concatenate([q[i] for q in parts]) if parts else np.zeros(0, dtype=np.int64)
                     for i in range(2))
        order = np.argsort(key, kind="stable")
        start = np.r_[0, np.cumsum(np.bincount(key >> 41, minlength=voxels))]
        # the keys, non-decreasing within each voxel
        keys = ((key[order] >> 25) & 65535) * (self.T / 65536.0)
        return GridLists(cell[order].astype(np.intp, copy=False), keys, start)

    def _grid_keys(self, vox: np.ndarray, cell: np.ndarray, acc: np.ndarray, mid: np.ndarray) -> np.ndarray:
        """One int64 sort key per grid entry (voxel ``vox``, cell ``cell``, squared gap
        ``acc`` from the voxel to the cell's centre, squared distance ``mid`` of the voxel's
        centre from the cell's midpoint): voxel, then the cell's sphere bound over the voxel
        rounded down to T / 2^16 (a rounded-down key is still a lower bound), then (ties:
        spheres meeting the voxel) the midpoint distance rounded."""
        with np.errstate(divide="ignore", invalid="ignore"):
            kq = np.floor(np.clip(np.sqrt(acc) - self.radii[cell], 0.0, self.T) / self.T * 65536.0)
            mq = np.sqrt(mid) / (4.0 * (self.T + self._V)) * 2.0 ** 25
        if not self.T > 0.0:             # (0 / 0)
            kq, mq = np.nan_to_num(kq), np.nan_to_num(mq)
        kq = np.clip(kq, 0, 65535).astype(np.int64)
        mq = np.clip(mq, 0, 2 ** 25 - 1).astype(np.int64)
        return (vox.astype(np.int64) << 41) | (kq << 25) | mq

    def _voxels(self, X: np.ndarray) -> "GridView":
        """The grid lists of the points' voxels: per point its first entry and number of
        entries (0 outside, and everywhere on a light projector: it has no grid), from
        the whole grid where it is built, else from lists made for these voxels alone."""
        N = len(X)
        if self._origin is None:
            return GridView.empty(N)
        with np.errstate(over="ignore", invalid="ignore"):
            zf = np.floor((X - self._origin) / self._V)
        inside = np.all(np.isfinite(zf) & (zf >= 0) & (zf < self._dims), axis=1)
        if not inside.any():
            return GridView.empty(N)
        z = np.where(inside[:, None], zf, 0).astype(np.intp)
        vid = np.zeros(N, dtype=np.intp)
        for a in range(self.dim):
            vid = vid * self._dims[a] + np.where(inside, z[:, a], 0)
        if self._grid is None and self._lazy_work >= self._grid_work:
            self._full_grid()
        if self._grid is not None:
            grid = self._grid
        else:                           # the lists of the voxels holding points
            U, inv = np.unique(vid[inside], return_inverse=True)
            grid, vid = self._lists(U), np.zeros(N, dtype=np.intp)
            vid[inside] = inv.reshape(-1)
        start = grid.start[vid]
        count = np.where(inside, grid.start[vid + 1] - start, 0)
        return GridView(grid.cells, grid.keys, start, count)

    # --- hierarchy of cells (far points) ------------------------------------------------------
    def _build_tree(self) -> None:
        """A binary hierarchy of the cells for points the voxel grid does not serve: the
        leaves are the cells in Z (Morton) order of their grid indices (neighbours in
        parameter space stay together), each node the union of two nodes of the level
        below, with the axis-aligned box of its cells' control points (the cells lie in
        their convex hulls, Farin 3.3) and the box of its cells' midpoint images, and one
        midpoint image as its representative (an upper bound on the nearest midpoint)."""
        m = len(self.radii)
        shape = self.cells.shape
        if self.k == 1:
            order = np.arange(m)
        else:
            i, j = np.divmod(np.arange(m), shape[1])
            code = np.zeros(m, dtype=np.int64)
            for b in range(31):
                code |= ((i >> b) & 1).astype(np.int64) << (2 * b + 1)
                code |= ((j >> b) & 1).astype(np.int64) << (2 * b)
            order = np.argsort(code, kind="stable")
        blo, bhi = self.cells.hull_boxes()
        self._hull_lo, self._hull_hi = blo, bhi
        levels = [(blo[order], bhi[order], self.mid_points[order], self.mid_points[order], self.mid_points[order])]
        while len(levels[-1][0]) > TREE_TOP:
            lo, hi, mlo, mhi, rep = levels[-1]
            first = np.arange(0, len(lo), 2)
            levels.append((np.minimum.reduceat(lo, first, axis=0), np.maximum.reduceat(hi, first, axis=0),
                           np.minimum.reduceat(mlo, first, axis=0), np.maximum.reduceat(mhi, first, axis=0),
                           rep[first]))
        self._tree_order = order
        self._tree = levels

    def _tree_pairs(self, X: np.ndarray, t: np.ndarray, nearest: bool
                    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Descend the hierarchy for points X with thresholds t (N,), level by level over
        (point, node) pairs, keeping the nodes whose lower bound is below t (few points
        and cells, at most DIRECT_PAIRS pairs: every pair at once, :meth:`_direct_pairs`).

        nearest=False: the bound is the distance to the node's box of control points
        (at the leaves also the hull-sphere bounds |X - c| - r, whichever is larger), t
        stays; returns the (point, cell, bound) pairs below t and per point a lower bound
        over every cell left out (t, or a smaller bound of a node dropped when a point
        holds more than K = max(CANDIDATES, PAIR_BUDGET / N) nodes: those of smallest
        bound are kept). nearest=True: the bound is the distance to the box of the
        node's midpoint images and t is lowered to the distance of each node's
        representative midpoint; returns the cell of the nearest midpoint per point
        (as ``cell``, in point order)."""
        N = len(X)
        K = max(CANDIDATES, int(PAIR_BUDGET // max(N, 1)))
        if N * len(self.radii) <= DIRECT_PAIRS and len(self.radii) <= K:
            return self._direct_pairs(X, t, nearest)
        levels = self._tree
        top = len(levels) - 1
        n0 = len(levels[top][0])
        t = np.array(t, dtype=np.float64)
        rest = t.copy()
        pid = np.repeat(np.arange(N), n0)
        node = np.tile(np.arange(n0), N)
        lb = np.zeros(0)
        for lv in range(top, -1, -1):
            lo, hi, mlo, mhi, rep = levels[lv]
            if nearest:
                lb = _box_distances(X, pid, mlo, mhi, node)
                ub = _distances(X, pid, rep, node)
                _min_into(t, pid, ub)
                keep = lb <= t[pid]
            else:
                lb = _box_distances(X, pid, lo, hi, node)
                if lv == 0:
                    lb = np.maximum(lb, self._cell_bounds(X, pid, self._tree_order[node], False))
                keep = lb < t[pid]
            pid, node, lb = pid[keep], node[keep], lb[keep]
            # at most K nodes per point (memory and work bounded): those of smallest bound
            # (a seed from the others' nearest midpoint only; candidates: rest bounds them)
            pid, node, lb = _cap(pid, node, lb, K, rest)
            if lv:                                      # the children (pid stays sorted)
                nb = len(levels[lv - 1][0])
                two = np.minimum(2, nb - 2 * node)
                pid = np.repeat(pid, two)
                node = np.repeat(2 * node, two) + ranks(two)
        if nearest:
            d = _distances(X, pid, levels[0][4], node)
            best = np.full(N, np.inf)
            _min_into(best, pid, d)
            hit = d <= best[pid]
            seed = np.zeros(N, dtype=np.intp)
            seed[pid[hit][::-1]] = self._tree_order[node[hit][::-1]]     # the first of ties
            return pid, seed, best, rest
        return pid, self._tree_order[node], lb, rest

    def _direct_pairs(self, X: np.ndarray, t: np.ndarray, nearest: bool
                      ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`_tree_pairs` over every (point, cell) pair at once (few of them, and no
        more cells than the cap K): the same pairs and bounds (in cell order); nearest=True:
        the seed cell of the nearest midpoint (the first of ties in cell order, not tree
        order; ``t`` not used: the callers pass inf), every pair as the first output."""
        N, m = len(X), len(self.radii)
        pid, cell = np.repeat(np.arange(N), m), np.tile(np.arange(m), N)
        t = np.array(t, dtype=np.float64)
        if nearest:
            d = _distances(X, pid, self.mid_points, cell).reshape(N, m)
            seed = d.argmin(axis=1)
            return pid, seed, d[np.arange(N), seed], t
        lb = self._cell_bounds(X, pid, cell)
        keep = lb < t[pid]
        return pid[keep], cell[keep], lb[keep], t

    def _cell_bounds(self, X: np.ndarray, pid: np.ndarray, cell: np.ndarray, box: bool = True) -> np.ndarray:
        """Lower bounds of |S - X[pid]| over the cells: the largest of the two hull-sphere
        bounds |X - c| - r (about the box centre and about the midpoint's image) and
        (``box``) the distance to the box of the control points (convex hull, Farin 3.3)."""
        lb = np.maximum(_distances(X, pid, self.centers, cell) - self.radii[cell],
                        _distances(X, pid, self.mid_points, cell) - self.mid_radii[cell])
        return np.maximum(lb, _box_distances(X, pid, self._hull_lo, self._hull_hi, cell)) if box else lb

    SEEDS = 4      # cells per voxel tried for the seed

    def seeds(self, X: np.ndarray, grid: "GridView") -> np.ndarray:
        """Per point the seed cell: the nearest midpoint among the first SEEDS cells of its
        voxel (those meeting the voxel, nearest its centre), or among all cells when the
        voxel is empty."""
        N, K = len(X), self.SEEDS
        k = np.minimum(grid.length, K)
        pid = np.repeat(np.arange(N), k)
        offs = ranks(k)
        cell = grid.cells[grid.start[pid] + offs]
        dist = np.full((N, K), np.inf)
        cells = np.zeros((N, K), dtype=np.intp)
        dist[pid, offs] = _distances(X, pid, self.mid_points, cell)
        cells[pid, offs] = cell
        seed = cells[np.arange(N), dist.argmin(axis=1)]
        none = np.flatnonzero(k == 0)
        chunk = max(1, int(PAIR_BUDGET // (2 * TREE_TOP)))
        for c0 in range(0, len(none), chunk):
            i = none[c0:c0 + chunk]
            seed[i] = self._tree_pairs(X[i], np.full(len(i), np.inf), True)[1]
        return seed

    def candidates(self, X: np.ndarray, d: np.ndarray, grid: "GridView"
                   ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The (point, cell) pairs whose sphere bound is below d (the distance found), with
        those bounds, and per point a lower bound over all cells left out.

        A voxel lists every cell whose sphere comes within T of it, by its bound over the
        voxel: a point with d <= T takes the prefix of cells with bound below d (the
        others are >= d away); points with d > T, or outside the grid, every cell.

        Bounded work and memory (issue 14): every point keeps at most K = max(CANDIDATES,
        PAIR_BUDGET / N) cells: the first K of its voxel's prefix (the first key left out
        bounds the rest: keys are non-decreasing); points the grid does not serve descend
        the hierarchy (:meth:`_tree_pairs`: at most K nodes per point, a node dropped
        bounds its cells), so the certificate stays ``lower_bounds <= distance to every
        cell``. Pairs are formed PAIR_BUDGET at a time."""
        N, start, count = len(X), grid.start, grid.length
        fast = (count > 0) & (d <= self.T)
        # per voxel segment, the number of keys <= d (vectorized bisection)
        q = d * (1.0 + SLACK_RTOL) + ULP_RTOL * self.size
        ends = start.copy()
        act = np.flatnonzero(fast)
        lo, hi, qa = start[act], start[act] + count[act], q[act]
        key = grid.keys
        while act.size:
            mid = (lo + hi) >> 1
            le = key[mid] <= qa
            lo, hi = np.where(le, mid + 1, lo), np.where(le, hi, mid)
            go = lo < hi
            ends[act[~go]] = lo[~go]
            act, lo, hi, qa = act[go], lo[go], hi[go], qa[go]
        n = np.where(fast, ends - start, 0)
        rest = d.copy()                        # every cell left out is >= d away
        K = max(CANDIDATES, int(PAIR_BUDGET // N))
        # a long prefix is cut after its first K cells: the keys are non-decreasing lower
        # bounds over the voxel, so the first key left out bounds every cell left out
        cut = np.flatnonzero(n > K)
        rest[cut] = np.minimum(rest[cut], key[start[cut] + K])
        n = np.minimum(n, K)
        P: List[np.ndarray] = []
        C: List[np.ndarray] = []
        B: List[np.ndarray] = []
        # groups of consecutive points with at most PAIR_BUDGET pairs (one point at least)
        cum = np.cumsum(n)
        g0 = 0
        while g0 < N:
            base = cum[g0 - 1] if g0 else 0
            g1 = max(g0 + 1, int(np.searchsorted(cum, base + PAIR_BUDGET, side="right")))
            ng = n[g0:g1]
            pid = np.repeat(np.arange(g0, g1), ng)
            offs = ranks(ng)
            cell = grid.cells[start[pid] + offs]
            lb = self._cell_bounds(X, pid, cell)
            P.append(pid)
            C.append(cell)
            B.append(lb)
            g0 = g1
        far = np.flatnonzero(~fast)
        chunk = max(1, int(PAIR_BUDGET // (2 * max(K, TREE_TOP))))
        for c0 in range(0, len(far), chunk):            # the hierarchy: O(log cells + output) per point
            i = far[c0:c0 + chunk]
            a, c, b, r = self._tree_pairs(X[i], d[i], False)
            rest[i] = np.minimum(rest[i], r)
            P.append(i[a])
            C.append(c)
            B.append(b)
        return np.concatenate(P), np.concatenate(C), np.concatenate(B), rest

    # --- queries -----------------------------------------------------------------------------
    def _stop_tolerances(self, tol: Optional[float], param_tol: Optional[float]
                         ) -> Tuple[Optional[float], Optional[float]]:
        """(tol, param_tol) validated: ``tol`` a distance (default CLOSEST_TOL * size when
        neither is given), ``param_tol`` relative to the parameter range; None: unused."""
        if tol is None and param_tol is None:
            return CLOSEST_TOL * self.size, None
        with np.errstate(over="ignore"):                # a distance in model units, in frame units
            inner = None if tol is None else float(np.float64(_checks.positive(tol, "tol")) / self.frame.scale)
        return inner, None if param_tol is None else _checks.positive(param_tol, "param_tol")

    def closest(self, points: ArrayLike, tol: Optional[float] = None, max_iterations: int = 50, max_rounds: int = 40, *,
                param_tol: Optional[float] = None) -> ClosestPoints:
        """The closest point of the object to every row of ``points`` (see :func:`closest_point`)."""
        if tol is not None:
            changed("Projector.closest", TOL_CHANGED)
        return self._closest(points, *self._stop_tolerances(tol, param_tol), max_iterations, max_rounds)

    def _closest(self, points: ArrayLike, tol: Optional[float], param_tol: Optional[float], max_iterations: int = 50,
                 max_rounds: int = 40, defer: Optional[Callable[[np.ndarray], np.ndarray]] = None) -> ClosestPoints:
        """``defer``: given the local feet's parameters (n, k) after Newton, True for the
        points whose search the caller finishes itself (cagd.queries.trimmed: feet off
        the trim); those keep their local foot, not certified (lower bound 0)."""
        model = self._points(points)
        max_iterations = _checks.integer(max_iterations, "max_iterations", 1)
        chunk = int(np.clip(PAIR_BUDGET // min(len(self.radii), CANDIDATES), MIN_CHUNK, POINT_CHUNK))
        if len(model) > chunk:          # at most CANDIDATES cells per point: pairs bounded
            if self._origin is not None:
                self._full_grid()       # (every voxel's list at once: the chunks meet most of them)
            return _concat([self._closest(model[i:i + chunk], tol, param_tol, max_iterations, max_rounds, defer)
                            for i in range(0, len(model), chunk)])
        X, far = self._inward(model)
        N = len(X)
        grid = self._voxels(X)
        seed = self.seeds(X, grid)
        dom_lo = np.broadcast_to(self.domain[:, 0], (N, self.k))
        dom_hi = np.broadcast_to(self.domain[:, 1], (N, self.k))
        x, d2, conv, (Sx, Jx, Hx, xe) = projected_newton(self, X, np.arange(N), self._start(X, seed), dom_lo, dom_hi,
                                                     self.wrap, max_iterations, tol, param_tol)
        d = np.sqrt(d2)
        # branch and bound over (point, box) pairs; first round: boxes near x* are bounded
        # by the expansion at x* itself (no evaluation), with bounds over the block of cells
        # around x*'s cell
        gap = WIN_GAP_RTOL * d + SIZE_ROUNDING * self.size
        if defer is None:
            pid, cell, lb_s, LB = self.candidates(X, d, grid)
            cut = LB < d                # the candidate list was cut (rest lowered below d)
        else:                           # only the points not deferred
            sure = np.flatnonzero(~np.asarray(defer(self.frame.params(x)), dtype=bool))
            LB = np.zeros(N)
            pid, cell, lb_s = np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp), np.zeros(0)
            if sure.size:
                pid, cell, lb_s, LB[sure] = self.candidates(X[sure], d[sure], grid.rows(sure))
                pid = sure[pid]
            cut = np.zeros(N, dtype=bool)
            cut[sure] = LB[sure] < d[sure]
        keep = lb_s < d[pid] - gap[pid]
        _min_into(LB, pid, np.where(keep, np.inf, lb_s))
        pid, cell = pid[keep], cell[keep]
        budget = min(BRANCH_PER_POINT * N + BRANCH_PER_CELL * max(len(self.radii), self._budget_cells), BRANCH_MAX)
        if len(pid) > budget:       # bounded work: per point the cells of smallest bound (the rest into LB)
            pid, cell, _ = _cap(pid, cell, lb_s[keep], max(1, budget // N), LB)
        home = self.cells.locate(xe)
        hp = home[pid]
        if self.k == 1:
            step = np.abs(cell - hp)                                           # grid steps from home
        else:
            nv = self.cells.shape[1]
            step = np.maximum(np.abs(cell // nv - hp // nv), np.abs(cell % nv - hp % nv))
        near = step <= _BLOCK
        # ... and in the C2-connected run of pieces of the piece that evaluated x*
        ep = self._power.piece_indices(xe) if self._power is not None else \
            [np.clip(np.searchsorted(b, xe[:, a], side="right") - 1, 0, len(b) - 2)
             for a, b in enumerate(self.pieces.breaks)]
        cidx = [cell] if self.k == 1 else [cell // self.cells.shape[1], cell % self.cells.shape[1]]
        for a in range(self.k):
            near &= self._cell_run[a][cidx[a]] == self._run[a][ep[a]][pid]
        # one bound per point over the parameter box spanned by its near cells; the
        # points it closes drop those pairs, the others bound them cell by cell. The
        # derivative bounds: over the cells within as many grid steps of x*'s cell as the
        # farthest of those cells (the hull of x* and the box lies in that block)
        u, ulo, uhi, ustep = _union_boxes(pid[near], self.lo[cell[near]], self.hi[cell[near]], step[near])
        if len(u):
            h = home[u]
            lu = box_lower_bound(_rows(X, u), ulo, uhi, _rows(xe, u), _rows(Sx, u), _rows(Jx, u), _rows(Hx, u),
                                 self.block[0][ustep, h], self.block[1][ustep, h], self.block[2][ustep, h])
            lu = np.sqrt(np.maximum(lu, 0.0))
            closed = lu >= d[u] - gap[u]
            LB[u[closed]] = np.minimum(LB[u[closed]], lu[closed])
            shut = np.zeros(N, dtype=bool)
            shut[u[closed]] = True
            keep = ~(near & shut[pid])
            pid, cell, near, step = pid[keep], cell[keep], near[keep], step[keep]
        lo, hi = self.lo[cell], self.hi[cell]
        # each cell's own bounds expanded at the cell's midpoint (S, J, H there are stored:
        # no evaluation); the pairs it leaves open: near ones by the expansion at x* with
        # the block bounds, then all by the cell's own bounds expanded at its point
        # nearest to x*
        lb = self._mid_bound(X, pid, cell, lo, hi)
        i = np.flatnonzero(near & (np.sqrt(np.maximum(lb, 0.0)) < d[pid] - gap[pid]))
        if len(i):
            h, lv, pi = home[pid[i]], step[i], pid[i]
            lb[i] = np.maximum(lb[i], box_lower_bound(_rows(X, pi), lo[i], hi[i], _rows(xe, pi), _rows(Sx, pi),
                                                      _rows(Jx, pi), _rows(Hx, pi), self.block[0][lv, h],
                                                      self.block[1][lv, h], self.block[2][lv, h]))
        i = np.flatnonzero(np.sqrt(np.maximum(lb, 0.0)) < d[pid] - gap[pid])
        lb[i] = np.maximum(lb[i], self._bound(X, pid[i], cell[i], lo[i], hi[i], np.clip(x[pid[i]], lo[i], hi[i]),
                                              d[pid[i]] - gap[pid[i]]))
        lb = np.sqrt(np.maximum(lb, 0.0))
        work = 0                                         # (point, box) rows refined
        near = np.zeros(len(pid))                        # how near Newton came in each box (or its parent)
        for r in range(max_rounds):
            open_ = lb < d[pid] - gap[pid]
            np.minimum.at(LB, pid[~open_], lb[~open_])
            pid, cell, lo, hi, lb, near = pid[open_], cell[open_], lo[open_], hi[open_], lb[open_], near[open_]
            if not len(pid):
                break
            work += len(pid)
            if r % NEWTON_EVERY == 0:
                y, g2, ok = self._newton_rows(X, pid, self._box_starts(X, pid, cell, lo, hi, x), lo, hi,
                                              self._cell_piece[cell], max_iterations, tol, param_tol)
                near = np.sqrt(g2)
                first = smallest_per_group(pid, near)         # best local result per point
                win = first[near[first] < d[pid[first]] * (1.0 - BETTER_RTOL) - BETTER_SIZE_RTOL * self.size]
                x[pid[win]], d[pid[win]], conv[pid[win]] = y[win], near[win], ok[win]
                gap = WIN_GAP_RTOL * d + SIZE_ROUNDING * self.size
                lb = np.sqrt(np.maximum(self._bound(X, pid, cell, lo, hi, y, d[pid] - gap[pid]), 0.0))
                open_ = lb < d[pid] - gap[pid]
                np.minimum.at(LB, pid[~open_], lb[~open_])
                pid, cell, lo, hi, lb, near = pid[open_], cell[open_], lo[open_], hi[open_], lb[open_], near[open_]
            for _ in range(SPLIT_LEVELS):             # halved, and again while the boxes are few
                pid, cell, lo, hi, lb = _split(pid, cell, lo, hi, lb, self.L[cell])
                near = np.tile(near, 2)                  # per half, how near Newton came in the box
                if 2 * len(pid) > FEW_ROWS:
                    break
            if len(pid) > budget:       # bounded work: per point an equal share of the budget, the
                if work > BRANCH_WORK * budget:          # boxes where Newton came nearest first
                    break
                order, rank = _ranks(pid, near)
                share = max(1, budget // len(np.unique(pid)))
                out = order[rank >= share]
                np.minimum.at(LB, pid[out], lb[out])     # the boxes left out bound their points
                i = order[rank < share]
                pid, cell, lo, hi, lb, near = pid[i], cell[i], lo[i], hi[i], lb[i], near[i]
            keep = lb < d[pid] - gap[pid]
            np.minimum.at(LB, pid[~keep], lb[~keep])
            pid, cell, lo, hi, near = pid[keep], cell[keep], lo[keep], hi[keep], near[keep]
            lb = np.sqrt(np.maximum(self._bound(X, pid, cell, lo, hi, np.clip(x[pid], lo, hi), d[pid] - gap[pid]), 0.0))
        lb_s = lb
        if len(pid) and len(pid) == len(lb_s):
            np.minimum.at(LB, pid, lb_s)                 # boxes left open after max_rounds
        # the work bound stopped the search with the certificate open: the foot is the
        # nearest found, not proven global (the points deferred to the caller excepted)
        open_ = LB < d - gap
        conv[self._kinked(x, ~conv & ~open_)] = True
        if defer is not None:
            open_[np.setdiff1d(np.arange(N), sure)] = False
        conv = conv & ~open_
        LB = np.minimum(LB * (1.0 - BOUND_SHRINK_RTOL), d)
        res = self._result(x, d, conv, LB, model, far)
        # the few points whose candidate list was cut and whose certificate is open (a
        # point near the centre of a sphere meets every cell) are solved again in a group
        # small enough to keep every cell (K >= cells); the better distance and the larger
        # of both lower bounds are kept
        redo = np.flatnonzero(cut & (LB < d - gap))
        if 0 < len(redo) < N and len(redo) * len(self.radii) <= PAIR_BUDGET:
            res = _merge(res, redo, self._closest(model[redo], tol, param_tol, max_iterations, max_rounds))
        return res

    def local_minima(self, point: ArrayLike, tol: Optional[float] = None, max_iterations: int = 50, *,
                     param_tol: Optional[float] = None) -> ClosestPoints:
        """Every local minimum of the distance from one point: box-constrained Newton in
        every cell, kept where the gradient vanishes (or points into the domain at its
        boundary), duplicates merged; sorted by distance."""
        if tol is not None:
            changed("Projector.local_minima", TOL_CHANGED)
        return self._local_minima(point, *self._stop_tolerances(tol, param_tol), max_iterations)

    def _local_minima(self, point: ArrayLike, tol: Optional[float], param_tol: Optional[float],
                      max_iterations: int = 50) -> ClosestPoints:
        model = self._points(point)
        if len(model) != 1:
            raise CagdError(f"points: all_minima needs exactly one point, got {len(model)}")
        X, far = self._inward(model)
        max_iterations = _checks.integer(max_iterations, "max_iterations", 1)
        m = len(self.radii)
        pid = np.zeros(m, dtype=np.intp)
        y, g2, ok, _ = projected_newton(self, X, pid, self.mids.copy(), self.lo, self.hi, np.zeros(self.k, bool),
                                     max_iterations, tol, param_tol)
        S, J, H2 = self.evaluate(y, 2)
        r = S - X[0]
        grad = 2.0 * np.einsum("nd,ndk->nk", r, J)
        JtJ = np.einsum("nda,ndb->nab", J, J)
        H = 2.0 * (JtJ + np.einsum("nd,ndab->nab", r, H2))
        scale = 2.0 * (np.sqrt(g2)[:, None] + STATIONARY_DIST_RTOL * self.size) * np.linalg.norm(J, axis=1) \
            * GRADIENT_RTOL + TINY
        open_ = ~self._closed()               # a closed direction's ends are no boundary
        at_lo = (y <= self.domain[:, 0]) & open_ & (grad > scale)
        at_hi = (y >= self.domain[:, 1]) & open_ & (grad < -scale)
        fixed = at_lo | at_hi
        good = np.all((np.abs(grad) <= scale) | fixed, axis=1)
        # second order: no descent direction along the free coordinates (not a maximum/saddle)
        floor = -SADDLE_RTOL * np.trace(2.0 * JtJ, axis1=1, axis2=2) - TINY
        for a in range(self.k):
            good &= fixed[:, a] | (H[:, a, a] >= floor)
        # a continuum of minima: a zero eigenvalue of H along the free parameters; a
        # parameter that does not move the point (a collapsed edge: a pole) counts as fixed
        flat = FLAT_HESSIAN_RTOL * np.trace(2.0 * JtJ, axis1=1, axis2=2)
        speed = np.linalg.norm(J, axis=1)
        collapsed = speed <= COLLAPSED_SPEED_RTOL * speed.sum(axis=1, keepdims=True)
        held = fixed | collapsed
        degenerate = np.zeros(len(y), bool)
        for a in range(self.k):
            alone = ~held[:, a] if self.k == 1 else ~held[:, a] & held[:, 1 - a]
            degenerate |= alone & (H[:, a, a] <= flat)
        if self.k == 2:
            both = ~fixed[:, 0] & ~fixed[:, 1]
            lmin = eigenvalue_2x2(H[:, 0, 0], H[:, 0, 1], H[:, 1, 1], -1.0)
            good &= ~both | (lmin >= floor)
            degenerate |= ~held[:, 0] & ~held[:, 1] & (lmin <= flat)
        if self.k == 2:        # a parameter bound that is a collapsed edge (a pole) is no
            good &= self._pole_minimum(X[0], y, collapsed, g2)      # boundary of the surface
        y, g2, ok, degenerate = y[good], g2[good], ok[good], degenerate[good]
        order = np.argsort(g2, kind="stable")               # merge duplicates: the closest of
        key = np.round((y[order] - self.domain[:, 0]) / self.width * 1e7).astype(np.int64)   # each 1e-7 bin
        key = np.where(self.wrap, periodic.wrap(key, 0, 10_000_000), key)
        _, first = np.unique(key, axis=0, return_index=True)
        chosen = order[np.sort(first)]
        # one row per foot point: a pole is one point for a whole edge of parameters, and
        # Newton stops within ~1e-7 of it there (the distance is flat along the edge)
        feet, dist = self.value(y[chosen]), np.sqrt(g2[chosen])
        keep: List[int] = []
        for i in range(len(chosen)):
            if not keep or not np.any((np.linalg.norm(feet[keep] - feet[i], axis=1) <= SAME_FOOT_RTOL * self.size)
                                      & (np.abs(dist[keep] - dist[i]) <= SLACK_RTOL * self.size)):
                keep.append(i)
        chosen = chosen[keep]
        d = np.sqrt(g2[chosen])
        lower = self._closest(model, tol, param_tol, max_iterations).lower_bounds[0] / self.frame.scale
        res = self._result(y[chosen], d, ok[chosen], np.minimum(np.full(len(chosen), lower), d),
                           np.repeat(model, len(chosen), axis=0), np.repeat(far, len(chosen)))
        return replace(res, isolated=~degenerate[chosen])

    def _closed(self) -> np.ndarray:
        """Directions (k,) that are periodic or close on themselves (a seam), where the
        domain's ends are no boundary of the object."""
        if getattr(self, "_closed_dirs", None) is None:
            self._closed_dirs = closed_directions(self.value, self.domain[:, 0], self.domain[:, 1],
                                                  self.wrap, self.size)
        return self._closed_dirs

    def _pole_minimum(self, X, y, collapsed, g2, count: int = 16) -> np.ndarray:
        """Rows at a collapsed edge (at a bound in one parameter, the other not moving the
        point) are minima only if the surface just off the edge is no closer: samples
        1e-4 of the domain inside, across the whole edge. (The parametrization is singular
        there: Newton stops where the meridian through the pole is orthogonal to S - X.)"""
        out = np.ones(len(y), bool)
        for a in range(2):
            edge = (np.abs(y[:, a] - self.domain[a, 0]) <= AT_END_RTOL * self.width[a]) \
                | (np.abs(y[:, a] - self.domain[a, 1]) <= AT_END_RTOL * self.width[a])
            rows = np.flatnonzero(edge & collapsed[:, 1 - a])
            if rows.size == 0:
                continue
            at_start = np.abs(y[rows, a] - self.domain[a, 0]) <= AT_END_RTOL * self.width[a]
            inward = np.where(at_start, 1.0, -1.0) * INWARD_RTOL * self.width[a]
            z = np.empty((rows.size, count, 2))
            z[:, :, a] = (y[rows, a] + inward)[:, None]
            z[:, :, 1 - a] = np.linspace(self.domain[1 - a, 0], self.domain[1 - a, 1], count)[None]
            d2 = np.sum((self.value(z.reshape(-1, 2)).reshape(rows.size, count, -1) - X) ** 2, axis=-1)
            out[rows] = d2.min(axis=1) >= g2[rows] - SLACK_RTOL * self.size ** 2
        return out

    # --- helpers -----------------------------------------------------------------------------
    def _start(self, X: np.ndarray, seed: np.ndarray) -> np.ndarray:
        """Newton's start from the seed cell's midpoint m with the precomputed S, J, H there
        (r = X - S(m)): the Gauss-Newton step d1 = (J^T J)^-1 J^T r, then the second-order
        step d = N^-1 (J^T r - J^T Q(d1)/2 - H[d1]^T J d1), N = J^T J - r.H, Q(d) = d^T H d,
        from the expansion of the stationarity condition J^T (S - X) = 0 to second order
        in d (error O(|d|^3 + |r| |d|^2)); kept in the seed cell."""
        k, dim = self.k, self.dim
        P0, J0, H0 = self._mid_rows
        r = [X[:, d] - P0[d].take(seed) for d in range(dim)]
        J = [[J0[a, d].take(seed) for d in range(dim)] for a in range(k)]
        H = {(a, b): [H0[b, a, d].take(seed) for d in range(dim)] for a in range(k) for b in range(a, k)}

        def dot(u, v):
            acc = u[0] * v[0]
            for d in range(1, dim):
                acc = acc + u[d] * v[d]
            return acc

        def sym(A):
            return np.stack([np.stack([A[min(a, b), max(a, b)] for b in range(k)], axis=1) for a in range(k)], axis=1)

        JtJ = {(a, b): dot(J[a], J[b]) for a in range(k) for b in range(a, k)}
        rhs = np.stack([dot(J[a], r) for a in range(k)], axis=1)
        d1 = _solve_sym(sym(JtJ), rhs)
        Hd = [[sum(H[min(a, b), max(a, b)][d] * d1[:, b] for b in range(k)) for d in range(dim)]
              for a in range(k)]                                                  # H[d1]
        Q = [sum(Hd[a][d] * d1[:, a] for a in range(k)) for d in range(dim)]
        Jd = [sum(J[a][d] * d1[:, a] for a in range(k)) for d in range(dim)]
        N = {key: JtJ[key] - dot(r, H[key]) for key in JtJ}
        rhs2 = rhs - np.stack([0.5 * dot(J[a], Q) + dot(Hd[a], Jd) for a in range(k)], axis=1)
        d2 = _solve_sym(sym(N), rhs2, fallback=d1)
        # the second-order step only where it is a refinement (small against d1)
        lo, hi = self.lo[seed], self.hi[seed]
        use = (np.abs(d2 - d1) <= 0.5 * np.abs(d1) + SECOND_ORDER_RTOL * (hi - lo)).all(1)
        step = np.where(use[:, None], d2, d1)
        return np.clip(self.mids[seed] + step, lo, hi)

    def _box_starts(self, X, pid, cell, lo, hi, x) -> np.ndarray:
        """Newton's start in every (point, box) row: of the foot found clamped to the box
        and the box's midpoint, the one whose image is nearer the point."""
        a, b = np.clip(x[pid], lo, hi), 0.5 * (lo + hi)
        out = np.empty_like(a)
        for c0 in range(0, len(pid), EVAL_CHUNK):
            sl = slice(c0, c0 + EVAL_CHUNK)
            piece = self._cell_piece[cell[sl]]
            Xp = X[pid[sl]]
            da = squared_norms(self.evaluate_in(a[sl], 0, piece) - Xp)
            db = squared_norms(self.evaluate_in(b[sl], 0, piece) - Xp)
            out[sl] = np.where((db < da)[:, None], b[sl], a[sl])
        return out

    def _kinked(self, x: np.ndarray, certified: np.ndarray) -> np.ndarray:
        """The points among ``certified`` (their distance proven) whose foot x lies where
        Newton's test of a smooth minimum cannot hold: on a break where the object is not
        C2 (a crease: g has a kink there), or on a cell with a pole (the parameters are not
        determined there)."""
        at = np.flatnonzero(certified)
        hit = np.zeros(len(at), dtype=bool)
        for a, cr in enumerate(self._creases):
            if len(cr) and len(at):
                j = np.clip(np.searchsorted(cr, x[at, a]), 1, len(cr)) - 1
                near = np.minimum(np.abs(x[at, a] - cr[j]), np.abs(x[at, a] - cr[np.minimum(j + 1, len(cr) - 1)]))
                hit |= near <= AT_END_RTOL * self.width[a]
        if self._poles is not None and len(at):
            hit |= self._poles.side[self.cells.locate(x[at])] >= 0
        return at[hit]

    def _newton_rows(self, X, pid, x0, lo, hi, piece, max_iterations, tol, param_tol):
        """Box-constrained Newton (no wrapping) for (point, box) rows, each box in the
        Bezier piece ``piece``, NEWTON_CHUNK rows at a time (the rows are independent;
        memory bounded): (x, g, converged)."""
        out = [projected_newton(self, X, pid[sl], x0[sl], lo[sl], hi[sl], np.zeros(self.k, bool), max_iterations,
                                tol, param_tol, piece[sl])[:3]
               for sl in (slice(c0, c0 + NEWTON_CHUNK) for c0 in range(0, len(pid), NEWTON_CHUNK))]
        if len(out) == 1:
            return out[0]
        return tuple(np.concatenate([o[i] for o in out]) for i in range(3))

    def _bound(self, X, pid, cell, lo, hi, c, target: np.ndarray) -> np.ndarray:
        """Second-order lower bound of g over boxes inside their cells, expanded at c (in
        chunks of EVAL_CHUNK boxes: the partials of millions of pairs would not fit); with
        the half Hessian's Bezier hull where it can lift the bound to ``target`` (distances:
        a box around a foot closes at once, :meth:`hull`)."""
        out = np.empty(len(pid))
        for c0 in range(0, len(pid), EVAL_CHUNK):
            sl = slice(c0, c0 + EVAL_CHUNK)
            ce, Xp = cell[sl], X[pid[sl]]
            S, J, H = self.evaluate(c[sl], 2, self._cell_piece[ce])     # the cell's own piece
            out[sl] = box_lower_bound(Xp, lo[sl], hi[sl], c[sl], S, J, H, self.L[ce], self.M[ce], self.T3[ce],
                                      hessian=self.hull(Xp, ce, lo[sl], hi[sl]),
                                      target=np.maximum(target[sl], 0.0) ** 2)
            out[sl] = self.pole_bound(Xp, ce, lo[sl], hi[sl], out[sl])
        return out

    def pole_bound(self, Xp: np.ndarray, cell: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                   g: np.ndarray) -> np.ndarray:
        """The lower bounds g of |S - X|^2 over boxes [lo, hi] of ``cell``, raised on cells
        with a collapsed edge to the first-order bound there (:mod:`._pole_bound`)."""
        if self._poles is None:
            return g
        return np.maximum(g, self._poles.squared_bound(Xp, cell, lo, hi))

    def hull(self, Xp: np.ndarray, cell: np.ndarray, lo: np.ndarray, hi: np.ndarray
             ) -> Optional[Callable[[np.ndarray], HullIntervals]]:
        """The ``hessian`` argument of :func:`box_lower_bound` for rows of points Xp in
        boxes [lo, hi] of the cells ``cell``: the half Hessian's Bezier hull over each
        cell (:class:`HessianHull`; on rational cells that of w^4 H and the range of w^4,
        :class:`RationalHessianHull`) for boxes at least HULL_BOX_SHARE of their cell per
        direction (a smaller box's own second-order bound is the tighter one)."""
        hh = self._hessian
        if hh is None:
            return None

        def intervals(i: np.ndarray) -> HullIntervals:
            ce = cell[i]
            big = np.all(hi[i] - lo[i] >= HULL_BOX_SHARE * (self.hi[ce] - self.lo[ce]), axis=1)
            out = np.full((len(i), self.k, self.k), -np.inf), np.full((len(i), self.k, self.k), np.inf)
            j = np.flatnonzero(big)
            if j.size:
                out[0][j], out[1][j] = hh.intervals(Xp[i[j]], ce[j])
            return out[0], out[1], hh.divisors(ce)
        return intervals

    def _mid_bound(self, X, pid, cell, lo, hi) -> np.ndarray:
        """:meth:`_bound` of whole cells expanded at their midpoints, from the stored S, J,
        H there (no evaluation), in chunks of EVAL_CHUNK."""
        out = np.empty(len(pid))
        for c0 in range(0, len(pid), EVAL_CHUNK):
            sl = slice(c0, c0 + EVAL_CHUNK)
            ce = cell[sl]
            out[sl] = box_lower_bound(X[pid[sl]], lo[sl], hi[sl], self.mids[ce], self.mid_points[ce],
                                      self.mid_jacobians[ce], self.mid_hessians[ce], self.L[ce], self.M[ce],
                                      self.T3[ce])
            out[sl] = self.pole_bound(X[pid[sl]], ce, lo[sl], hi[sl], out[sl])
        return out

    def _points(self, points: ArrayLike) -> np.ndarray:
        return _query_points(points, self.dim)

    def _inward(self, model: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Model points in frame units, and which of them are farther than FAR_POINT: those
        are moved in to FAR_POINT along their direction from the frame's origin (their
        closest point moves by O(1 / FAR_POINT) of the object's size, nothing at float64;
        the squared distances would overflow)."""
        X = self.frame.inward(model)
        r = robust_distance(X, np.zeros_like(X))
        far = r > FAR_POINT
        if far.any():
            X = X.copy()
            X[far] = X[far] / r[far, None] * FAR_POINT
        return X, far

    def _result(self, x, d, conv, lower, model: np.ndarray, far: np.ndarray) -> ClosestPoints:
        """The result in model units from frame-unit parameters x, distances d and lower
        bounds; rows ``far`` (see :meth:`_inward`) get their distance from the model
        point itself and the bound |X - c| - R (c the frame's origin, R the radius about
        it of the control points: the object lies in that ball)."""
        feet = self.frame.outward(self.value(x))
        s = self.frame.scale
        d, lower = d * s, lower * s
        if far.any():
            d[far] = robust_distance(model[far], feet[far])
            centre = np.broadcast_to(self.frame.centre, model[far].shape)
            lower[far] = np.minimum(np.maximum(robust_distance(model[far], centre) - s * self.hull_radius, 0.0),
                                    d[far])
        if not np.all(np.isfinite(d)):
            i = int(np.flatnonzero(~np.isfinite(d))[0])
            raise CagdError(f"points: the distance from points[{i}] to the object exceeds the float64 range")
        x = self.frame.params(x)
        if self.triangle:                                   # (s, t) -> (u, v) = (s, t (1 - s))
            x = np.stack([x[:, 0], x[:, 1] * (1.0 - x[:, 0])], axis=1)
        params = x[:, 0].copy() if self.k == 1 else x.copy()
        conv = np.array(conv, dtype=bool)
        return ClosestPoints(params, feet, d.copy(), conv, lower, None, bool(conv.all()), _unconverged(conv))


def _query_points(points: ArrayLike, dim: int) -> np.ndarray:
    """The query points as a finite (N, dim) array, N >= 1 (one point may be (dim,))."""
    X = _checks.finite_array(points, "points")
    if X.ndim == 1:
        X = X[None]
    if X.ndim != 2 or X.shape[0] == 0:
        raise CagdError(f"points: expected a non-empty (N, {dim}) array, got shape {X.shape}")
    if X.shape[1] != dim:
        raise CagdError(f"points: expected {dim}-D points (the object is {dim}-D), got {X.shape[1]}-D")
    return X


def _unconverged(conv: np.ndarray) -> str:
    """The message naming the points not converged ("" when every point converged)."""
    bad = np.flatnonzero(~conv)
    return "" if not bad.size else (
        f"not converged at {bad.size} of {len(conv)} points (first: index {int(bad[0])}): Newton did not meet "
        f"tol, or the search stopped at its work bound before proving the foot global; their distances are "
        f"the nearest found (upper bounds) and lower_bounds still hold: the true distance lies between")


def _merge(res: ClosestPoints, rows: np.ndarray, sub: ClosestPoints) -> ClosestPoints:
    """``res`` with its ``rows`` replaced by the results ``sub`` of the same points where
    those are closer (feet, parameters, convergence), the lower bound the larger of both
    (each holds), at most the distance."""
    f = {n: np.array(getattr(res, n)) for n in ("params", "feet", "distances", "point_converged", "lower_bounds")}
    better = sub.distances <= f["distances"][rows]
    r = rows[better]
    for n in ("params", "feet", "distances", "point_converged"):
        f[n][r] = getattr(sub, n)[better]
    f["lower_bounds"][rows] = np.maximum(f["lower_bounds"][rows], sub.lower_bounds)
    f["lower_bounds"] = np.minimum(f["lower_bounds"], f["distances"])
    return _concat([ClosestPoints(f["params"], f["feet"], f["distances"], f["point_converged"], f["lower_bounds"])])


def _concat(parts: List[ClosestPoints]) -> ClosestPoints:
    """The results of consecutive chunks of points as one (the message recounted)."""
    fields = {f: np.concatenate([getattr(p, f) for p in parts])
              for f in ("params", "feet", "distances", "point_converged", "lower_bounds")}
    conv = fields["point_converged"]
    return ClosestPoints(**fields, isolated=None, converged=bool(conv.all()), message=_unconverged(conv))


def _c2_by_knots(obj: Union[Curve, Surface], raw: BezierPieces) -> List[Optional[np.ndarray]]:
    """Per direction, the inner breaks where the NURBS form is C2 by its knots alone (a
    knot of multiplicity m leaves a degree-p B-spline, rational too, C^(p - m): Piegl &
    Tiller 2.2); None where the breaks are not its distinct inner knots."""
    nurbs = obj.to_nurbs()
    if isinstance(nurbs, Curve):
        forms = [(getattr(nurbs, "knots", None), getattr(nurbs, "degree", None))]
    else:
        forms = [(getattr(nurbs, "knots_u", None), getattr(nurbs, "degree_u", None)),
                 (getattr(nurbs, "knots_v", None), getattr(nurbs, "degree_v", None))]
    out: List[Optional[np.ndarray]] = []
    for (knots, p), b in zip(forms, raw.breaks):
        inner = b[1:-1]
        if knots is None or p is None or not len(inner):
            out.append(None)
            continue
        kv = np.asarray(knots, dtype=np.float64)
        mult = np.searchsorted(kv, inner, side="right") - np.searchsorted(kv, inner, side="left")
        out.append((mult >= 1) & (p - mult >= 2))
    return out


def _c2_breaks(pieces: BezierPieces, known: Optional[List[Optional[np.ndarray]]] = None) -> List[np.ndarray]:
    """Per direction, for every inner break: the object is C2 across it (``known``: True
    where the knots already say so, see :func:`_c2_by_knots`; the other breaks: all
    partials up to order 2 of the two neighbouring pieces agree, within 1e-10 of their
    size, at 4 (degree + 1) points along the break on every piece across)."""
    k, shape = pieces.k, pieces.shape
    out = []
    for a in range(k):
        n = shape[a]
        if n < 2:
            out.append(np.zeros(0, dtype=bool))
            continue
        sure = None if known is None else known[a]
        if sure is not None and len(sure) == n - 1 and sure.all():
            out.append(sure.copy())
            continue
        b = pieces.breaks[a]
        if k == 1:
            left, right = np.arange(n - 1), np.arange(1, n)
            x = b[1:-1][:, None]
            d0 = pieces.derivatives(left, x, 2)
            d1 = pieces.derivatives(right, x, 2)
            diff = np.abs(d0 - d1).max(axis=(0, 2))
            scale = np.maximum(np.abs(d0).max(axis=(0, 2)), np.abs(d1).max(axis=(0, 2)))
            out.append(diff <= C2_RTOL * scale + TINY)
            continue
        o = 1 - a                                   # the other direction
        q = pieces.degrees[o]
        t = (np.arange(4 * (q + 1)) + 0.5) / (4 * (q + 1))
        bo = pieces.breaks[o]
        gi, gj, gt = np.meshgrid(np.arange(n - 1), np.arange(shape[o]), t, indexing="ij")
        i, j, tt = gi.ravel(), gj.ravel(), gt.ravel()
        xo = bo[j] + tt * (bo[j + 1] - bo[j])
        xa = b[i + 1]
        X = np.stack([xa, xo], 1) if a == 0 else np.stack([xo, xa], 1)
        if a == 0:
            left, right = i * shape[1] + j, (i + 1) * shape[1] + j
        else:
            left, right = j * shape[1] + i, j * shape[1] + i + 1
        mask = np.add.outer(np.arange(3), np.arange(3)) <= 2
        ok = np.empty(len(left), dtype=bool)
        for c0 in range(0, len(left), EVAL_CHUNK):      # bounded memory: (3, 3, chunk, dim) at once
            sl = slice(c0, c0 + EVAL_CHUNK)
            d0 = pieces.derivatives(left[sl], X[sl], 2)
            d1 = pieces.derivatives(right[sl], X[sl], 2)
            diff = np.abs(d0 - d1)[mask].max(axis=(0, 2))
            scale = np.maximum(np.abs(d0)[mask].max(axis=(0, 2)), np.abs(d1)[mask].max(axis=(0, 2)))
            ok[sl] = diff <= C2_RTOL * scale + TINY
        out.append(np.asarray(ok.reshape(n - 1, -1).all(axis=1)))
    return out


def _box_distances(X: np.ndarray, pid: np.ndarray, lo: np.ndarray, hi: np.ndarray, node: np.ndarray) -> np.ndarray:
    """Distance from X[pid] to the axis-aligned boxes [lo, hi][node] (0 inside)."""
    acc = np.zeros(len(pid))
    for a in range(X.shape[1]):
        x = X[:, a].take(pid)
        t = np.maximum(lo[:, a].take(node) - x, 0.0) + np.maximum(x - hi[:, a].take(node), 0.0)
        acc += t * t
    return np.sqrt(acc)


def _cap(pid: np.ndarray, cell: np.ndarray, lb: np.ndarray, K: int, rest: np.ndarray
         ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per point (pid sorted), the K pairs of smallest lower bound lb; the smallest bound
    dropped enters rest[p] (rest = min(rest, dropped)): the certificate over the cells
    left out stays valid."""
    if not len(pid):
        return pid, cell, lb
    counts = np.bincount(pid, minlength=len(rest))
    if counts.max() <= K:
        return pid, cell, lb
    order, rank = _ranks(pid, lb)
    pid, cell, lb = pid[order], cell[order], lb[order]
    keep = rank < K
    np.minimum.at(rest, pid[rank == K], lb[rank == K])
    return pid[keep], cell[keep], lb[keep]


def _ranks(pid: np.ndarray, key: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The rows sorted by point pid and then key (order), and each sorted row's rank
    among its point's rows (0 for the smallest key)."""
    order = np.lexsort((key, pid))
    p = pid[order]
    return order, np.arange(len(p)) - np.searchsorted(p, p, side="left")


def _rows(A: np.ndarray, i: np.ndarray) -> np.ndarray:
    """A[i] gathered on the last axis of A.T (component-first storage), returned as the
    transposed view: per-component columns stay contiguous."""
    return np.take(A.T, i, axis=-1).T


def _min_into(out: np.ndarray, pid: np.ndarray, values: np.ndarray) -> None:
    """out[p] = min(out[p], values of the pairs of p) (like np.minimum.at; fast when pid
    is sorted)."""
    if not len(pid):
        return
    if np.any(pid[1:] < pid[:-1]):
        np.minimum.at(out, pid, values)
        return
    first = np.flatnonzero(np.r_[True, pid[1:] != pid[:-1]])
    p = pid[first]
    out[p] = np.minimum(out[p], np.minimum.reduceat(values, first))


def _solve_sym(A: np.ndarray, b: np.ndarray, fallback: Optional[np.ndarray] = None) -> np.ndarray:
    """x = A^-1 b for symmetric (n, k, k) A, k = 1 or 2, in closed form with a tiny
    Levenberg shift; rows where A is not positive definite get ``fallback`` (or 0)."""
    if A.shape[1] == 1:
        a = A[:, 0, 0]
        a = a + LEVENBERG_RTOL * np.abs(a) + TINY
        with np.errstate(divide="ignore", invalid="ignore"):
            x = b / a[:, None]
        pd = (a > 0)[:, None]
    else:
        a, bb, c = A[:, 0, 0], A[:, 0, 1], A[:, 1, 1]
        t = LEVENBERG_RTOL * (np.abs(a) + np.abs(c))
        a, c = a + t + TINY, c + t + TINY
        det = a * c - bb * bb
        with np.errstate(divide="ignore", invalid="ignore"):
            x = np.stack([(c * b[:, 0] - bb * b[:, 1]) / det, (a * b[:, 1] - bb * b[:, 0]) / det], axis=1)
        pd = ((a > 0) & (det > 0))[:, None]
    ok = pd & np.isfinite(x)
    return np.where(ok, x, 0.0 if fallback is None else fallback)


def _cell_counts(pieces: BezierPieces, target: int):
    """Parts per piece index along each direction so that the cells have about equal
    geometric extent (the first-derivative bound times the parameter width, the largest
    over the row or column of pieces): at least the uniform count per = (target / m)^(1/k)
    (>= 2, or >= 1 when there are at least ``target`` pieces: memory and time O(pieces),
    not 4 or 8 times that), at most 8 per, and at most twice the uniform total. A thin
    direction (issue 16: a sliver face), whose total extent is under THIN_SHARE of the
    longest direction's, gets at least per times that ratio (>= 1) instead of per, and
    the cells it does not take go to the long direction (up to twice the uniform total)."""
    k, shape, m = pieces.k, pieces.shape, len(pieces)
    per = max(1 if m >= target else 2, int(np.ceil((target / m) ** (1.0 / k))))
    B = pieces.partial_bounds(1)
    h = pieces.upper - pieces.lower
    ext = []
    for a in range(k):
        al = tuple(int(b == a) for b in range(k))
        e = (B[al] * h[:, a]).reshape(shape)
        ext.append(np.moveaxis(e, a, 0).reshape(shape[a], -1).max(axis=1))
    allext = np.concatenate(ext)
    ref = float(np.median(allext[np.isfinite(allext)])) if np.isfinite(allext).any() else 0.0
    if not np.isfinite(ref) or ref <= 0:
        return per
    ext = [np.where(np.isfinite(e), e, ref) for e in ext]
    # a thin direction (its total extent under THIN_SHARE of the longest's) needs no
    # more than its own extent's share of cells: a sliver is cut along its length
    total = [float(e.sum()) for e in ext]
    longest = max(total)
    low = [per if t >= THIN_SHARE * longest else max(1, int(np.ceil(per * t / longest - COUNT_SLACK))) for t in total]
    step = 1.2 * ref / per                       # cells up to 20% above the median extent / per
    if min(low) < per:                           # the cells the thin direction does not take go along
        step /= 8.0
    while True:
        counts = [np.clip(np.ceil(e / step - COUNT_SLACK), lw, 8 * per).astype(np.intp) for e, lw in zip(ext, low)]
        if np.prod([float(c.sum()) for c in counts]) <= 2.0 * m * per ** k:
            return counts
        step *= 1.25


def _union_boxes(pid: np.ndarray, lo: np.ndarray, hi: np.ndarray, step: np.ndarray):
    """Per distinct pid, the box spanning the boxes [lo, hi] of its pairs and the largest
    ``step``: (points, lower corners, upper corners, steps)."""
    if not len(pid):
        return pid, lo, hi, step
    if np.any(pid[1:] < pid[:-1]):
        order = np.argsort(pid, kind="stable")
        pid, lo, hi, step = pid[order], lo[order], hi[order], step[order]
    first = np.flatnonzero(np.r_[True, pid[1:] != pid[:-1]])
    return (pid[first], np.minimum.reduceat(lo, first, axis=0), np.maximum.reduceat(hi, first, axis=0),
            np.maximum.reduceat(step, first))


def _tier_cells(k: int, m: int, tier: int) -> int:
    """The number of cells a projector of ``tier`` (0 light, 1 default, 2 fine) aims at for
    ``m`` Bezier pieces in ``k`` parameters (see :class:`Projector`)."""
    if tier == 0:
        return max(m, LIGHT_CELLS[k - 1])
    if k == 1:
        return min(512, max(64, 16 * m))
    return min(4096, max(FINE_CELLS if tier == 2 else 256, 16 * m))


def projector(obj: Union[Curve, Surface], points: int = 0) -> Projector:
    """The cached :class:`Projector` of ``obj`` for a query of ``points`` points: light
    below LIGHT_POINTS, the default one, or for at least FINE_POINTS points on a surface
    the ``fine`` one.

    The tier is a function of ``points`` alone (issue 16, scan scale: a small query after
    a large one used the fuller projector already cached, whose answers differ in the last
    bits, so a result depended on the calls before it and a worker process or a Dask task
    could not reproduce it); the default and the fine projector are one where they aim at
    the same cells (a surface of 256 pieces or more).

    Cached by identity (while the object lives) and by content (issue 16: an equal object
    built again, e.g. by ``cq_ext.from_shape`` on every call, finds the same projector):
    the CACHE_OBJECTS most recently used contents are kept."""
    tier = 2 if points >= FINE_POINTS and isinstance(obj, Surface) else (0 if points < LIGHT_POINTS else 1)
    try:
        held = _CACHE.get(obj)
    except TypeError:
        held = None
    key = None
    if held is None:
        key = content_key(obj)
        if key is not None:
            held = _BY_CONTENT.get(key)
            if held is not None:
                _BY_CONTENT.move_to_end(key)
    if held is None:
        held = {}
    best = held.get(tier)
    other = held.get(3 - tier) if tier else None            # built with the same cells: the same projector
    if best is None and other is not None and other._target == _tier_cells(other.k, len(other.pieces), tier):
        best = other
    if best is None:
        best = Projector(obj, fine=tier == 2, light=tier == 0)
        held[tier] = best               # one dict per content: its identity and content entries share it
        try:
            _CACHE[obj] = held
        except TypeError:
            pass
        key = content_key(obj) if key is None else key
        if key is not None:
            _BY_CONTENT[key] = held
            _BY_CONTENT.move_to_end(key)
            # the most recent CACHE_OBJECTS contents, within CACHE_BYTES (the newest kept)
            while len(_BY_CONTENT) > 1 and (len(_BY_CONTENT) > CACHE_OBJECTS or sum(
                    _footprint(q) for h in _BY_CONTENT.values() for q in h.values()) > CACHE_BYTES):
                _BY_CONTENT.popitem(last=False)
    return best


def _footprint(p: Projector) -> int:
    """Bytes held by a projector's arrays (also inside its lists and tuples), computed once,
    plus those its half-Hessian hull and its whole voxel grid hold now (they are made as
    queries need them)."""
    if getattr(p, "_bytes", None) is None:
        def size(x: object, depth: int = 0) -> int:
            if isinstance(x, np.ndarray):
                return int(x.nbytes)
            if isinstance(x, (list, tuple)) and depth < 3:
                return sum(size(y, depth + 1) for y in x)
            if isinstance(x, BezierPieces) and depth < 3:
                return sum(size(y, depth + 1) for y in vars(x).values())
            return 0
        setattr(p, "_bytes", sum(size(v) for k, v in vars(p).items() if k not in ("_bytes", "_grid")))
    hull, grid = p._hessian, p._grid
    return int(getattr(p, "_bytes")) + (hull.nbytes if hull is not None else 0) + \
        (sum(int(a.nbytes) for a in grid) if grid is not None else 0)


def content_key(obj: object) -> Optional[Tuple]:
    """A key equal for objects of equal content, for the classes that name the attributes
    defining them (``_content_fields`` in the class itself, not inherited: a subclass may
    hold more): the class and those attributes (arrays by dtype, shape and a BLAKE2
    digest of their bytes); None for other objects (cached by identity only)."""
    fields = type(obj).__dict__.get("_content_fields")
    if fields is None:
        return None
    parts: List[object] = [type(obj).__module__, type(obj).__qualname__]
    for name in fields:
        x = getattr(obj, name)
        if isinstance(x, np.ndarray):
            a = np.ascontiguousarray(x)
            parts.append((a.dtype.str, a.shape, hashlib.blake2b(a.tobytes(), digest_size=16).digest()))
        elif x is None or isinstance(x, (bool, int, float)):
            parts.append(x)
        else:
            return None
    return tuple(parts)


def closest_point(obj: Union[Curve, Surface, Sequence[Union[Curve, Surface]]], points: ArrayLike,
                  all_minima: bool = False, tol: Optional[float] = None, max_iterations: int = 50, *,
                  param_tol: Optional[float] = None) -> ClosestPoints:
    """Closest points of an engine curve or surface (or of the nearest of several) to N
    points, global and certified.

    Args:
        obj: any cagd Curve or Surface (including Bezier triangles: their parameters are
            returned in the triangle's (u, v), u = s, v = t (1 - s) of the NURBS form), or
            a list of them (the patches of a model, the faces of a STEP file): each point
            gets the nearest object's closest point, ``owner`` says which (issue 16, many
            objects: objects far from every point cost a pass over their control net only,
            :mod:`cagd.queries._many`).
        points: (N, dim) points (one point may be given as (dim,)).
        all_minima: return every local minimum of the distance from one point instead.
        tol: a distance in model units: Newton stops when a step moves the foot by less
            than ``tol`` (default CLOSEST_TOL = 1e-12 times the object's size, when
            ``param_tol`` is not given either). Until cagd 0.1 ``tol`` was a step relative
            to the parameter range (now ``param_tol``); passing ``tol`` warns
            (FutureWarning) for one release.
        param_tol: relative, in parameter space: Newton also stops when every component of
            a step is below ``param_tol`` times that parameter's range (None: not used).
        max_iterations: bound on Newton steps per refinement (non-convergence is reported).

    Returns:
        :class:`ClosestPoints` (params, feet, distances, lower_bounds, point_converged,
        converged, message; with ``all_minima``, also ``isolated``: False where the
        minima form a continuum).

    Raises:
        CagdError: not a curve or surface, empty or NaN points, wrong dimension, tol or
            param_tol <= 0, a distance beyond the float64 range; ``all_minima`` with a
            list; objects of different dimensions.

    Piegl & Tiller 6.1 (point inversion by Newton); seed 004, ch. 1 §4 (minimum distance).
    """
    if tol is not None:
        changed("closest_point", TOL_CHANGED)
    if isinstance(obj, (list, tuple)):
        return _closest_of_many(obj, points, all_minima, tol, param_tol, max_iterations)
    return _closest_point(cast(Union[Curve, Surface], obj), points, all_minima, tol, param_tol, max_iterations)


def _closest_of_many(objs: Sequence[Union[Curve, Surface]], points: ArrayLike, all_minima: bool,
                     tol: Optional[float], param_tol: Optional[float], max_iterations: int) -> ClosestPoints:
    """:func:`closest_point` of a list of objects: each point against the nearest
    (:func:`cagd.queries._many.nearest`), ``owner`` its index."""
    from ._many import nearest, objects
    checked = objects(objs)
    if all_minima:
        raise CagdError("all_minima: needs one object, not a list")
    X = _query_points(points, checked[0].dim)

    def measure(o: Union[Curve, Surface], Xr: np.ndarray) -> Tuple[list, bool]:
        r = _closest_point(o, Xr, False, tol, param_tol, max_iterations)
        return [r.distances, r.params, r.feet, r.lower_bounds, r.point_converged], True

    (d, params, feet, lower, owner, conv), _ = nearest(checked, X, measure)
    return ClosestPoints(params, feet, d, conv, lower, None, bool(conv.all()), _unconverged(conv), owner)


def _closest_point(obj: Union[Curve, Surface], points: ArrayLike, all_minima: bool = False, tol: Optional[float] = None,
                   param_tol: Optional[float] = None, max_iterations: int = 50) -> ClosestPoints:
    """:func:`closest_point` without the notice on ``tol`` (for the engine's own callers)."""
    try:                            # the number of points picks the projector (validated later)
        shape = np.shape(points)
    except (TypeError, ValueError):
        shape = ()
    count = int(shape[0]) if len(shape) == 2 else 1
    from ..surfaces.trimmed import TrimmedSurface
    if isinstance(obj, TrimmedSurface):                  # the face itself (cagd.queries.trimmed)
        if all_minima:
            raise CagdError("all_minima: not available on a TrimmedSurface (use its untrimmed surface)")
        from .trimmed import closest_on_trimmed
        p = projector(obj.untrimmed, count)
        return closest_on_trimmed(obj, points, p, p._stop_tolerances(tol, param_tol), max_iterations)
    p = projector(obj, count) if isinstance(obj, (Curve, Surface)) else Projector(obj)
    stop = p._stop_tolerances(tol, param_tol)
    if all_minima:
        return p._local_minima(points, *stop, max_iterations)
    return p._closest(points, *stop, max_iterations)
