"""Validation of trimming loops without flattening them whole (issue 15, reading speed).

:class:`cagd.TrimmedSurface` checks that its loops do not cross and finds their
orientation. Both questions are decided on the loops' Bezier pieces, bisected only
where the answer needs it, with the same bisection (de Casteljau at 1/2, the chord
bound of :func:`cagd.surfaces._chords._hull_bound`) that the classification's full
flattening uses. So the chords compared in the end are the chords of that flattening,
and the verdict is the one the flattened loops would give, at a fraction of the work:
a loop is flattened to FLATTEN_TOL only where another curve comes near it.

- Crossings: a pair of pieces of different curves, or of different Bezier pieces of
  one curve (a loop that crosses itself), can only cross where their control
  boxes overlap (a piece and its chords lie in its control hull). Pairs are found by
  sweep and prune on the boxes; a pair whose boxes overlap is replaced by the pairs of
  the halves of its coarser pieces, until both are fine (chord bound at most the
  flattening tolerance); the fine pairs' chords are then tested as the flattened ones
  are (proper crossings, with the joint allowance of consecutive curves).
- Nesting: a hole's first point has the winding number of a loop's chord polygon
  with respect to the loop where it is farther from every chord than the chord's
  bound; the pieces nearer than that are bisected (down to fine: then the point
  touches the loop and gives no verdict, as with the flattened loops).
- Orientation: the signed area of a loop's chord polygon differs from the loop's by at
  most sum(2 b L + pi b^2) over its pieces (chord length L, bound b: the lens between a
  piece and its chord lies within b of the chord); the sign is decided where the
  polygon's area exceeds that, else the undecided loops' pieces are bisected.
"""
from __future__ import annotations

from typing import Callable, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from .._ranks import ranks
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ._chords import Chain, _cartesian, _crossings, _halves, _hom_pieces, _hull_bound, orient, _segment_distance

#: relative (to the loops' size): control boxes are grown by this before they are compared
#: (the halves' control points are rounded; a piece's chords stay in its box to it)
BOX_MARGIN = 1e-12
#: relative: pairs of consecutive curves are dropped within (1 - JOINT_MARGIN) of the joint
#: allowance only (a crossing computed at its edge stays for the exact test)
JOINT_MARGIN = 1e-6


class _Nodes:
    """Bezier pieces of the chain curves and the halves made of them (a binary tree per
    piece, grown on demand). Per node: its net (by degree group), chord ends A, B,
    chord bound, control box, depth, the chain curve it belongs to and the root piece
    it was cut from."""

    def __init__(self, curves: Sequence[BSplineCurve], scale: float):
        self.margin = BOX_MARGIN * scale
        self.nets: dict = {}                 # degree -> list of (k, p + 1, 3) arrays
        self._parts: List[Tuple[np.ndarray, ...]] = []
        self.count = 0
        by_degree: dict = {}
        for k, c in enumerate(curves):
            by_degree.setdefault(c.degree, []).append(k)
        for p, ks in by_degree.items():
            nets = [_hom_pieces(curves[k])[1] for k in ks]
            owner = np.concatenate([np.full(len(n), k) for k, n in zip(ks, nets)])
            self._add(p, np.concatenate(nets), owner, np.zeros(len(owner), dtype=np.int64),
                      self.count + np.arange(len(owner)))
        self._join()

    def _add(self, p: int, Q: np.ndarray, owner: np.ndarray, depth: np.ndarray, piece: np.ndarray) -> None:
        group = self.nets.setdefault(p, [])
        first = sum(len(g) for g in group)
        group.append(Q)
        P = _cartesian(Q)
        self._parts.append((np.full(len(Q), p), first + np.arange(len(Q)), owner, depth, P[:, 0], P[:, -1],
                            _hull_bound(Q), P.min(axis=1) - self.margin, P.max(axis=1) + self.margin, piece))
        self.count += len(Q)

    def _join(self) -> None:
        (self.degree, self.row, self.owner, self.depth, self.A, self.B, self.bound, self.lo,
         self.hi, self.piece) = (np.concatenate([part[i] for part in self._parts]) for i in range(10))
        self._parts = [tuple(getattr(self, a) for a in
                             ("degree", "row", "owner", "depth", "A", "B", "bound", "lo", "hi", "piece"))]

    def net(self, p: int, rows: np.ndarray) -> np.ndarray:
        group = self.nets[p]
        if len(group) > 1:
            group[:] = [np.concatenate(group)]
        return group[0][rows]

    def split(self, ids: np.ndarray) -> np.ndarray:
        """Bisect the nodes ``ids``: (len(ids), 2) ids of their halves."""
        kids = np.empty((len(ids), 2), dtype=np.int64)
        for p in np.unique(self.degree[ids]):
            sel = np.flatnonzero(self.degree[ids] == p)
            node = ids[sel]
            L, R = _halves(self.net(int(p), self.row[node]))
            start = self.count
            n = len(node)
            self._add(int(p), np.concatenate([L, R]), np.concatenate([self.owner[node]] * 2),
                      np.concatenate([self.depth[node] + 1] * 2), np.concatenate([self.piece[node]] * 2))
            kids[sel, 0] = start + np.arange(n)
            kids[sel, 1] = start + n + np.arange(n)
        self._join()
        return kids

    def meet(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        lo, hi = self.lo, self.hi
        return (lo[i, 0] <= hi[j, 0]) & (lo[j, 0] <= hi[i, 0]) & (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])


class LoopCheck:
    """The checks of one set of closed chains (:func:`cagd.surfaces._chords.closed_chains`)
    on one tree of their pieces: ``scale`` the loops' size, ``ftol`` the flattening's
    chord bound, ``max_bisections`` its depth bound."""

    def __init__(self, chains: List[Chain], scale: float, ftol: float, max_bisections: int):
        self.chains, self.scale, self.ftol, self.max_bisections = chains, scale, ftol, max_bisections
        self.curves = [c for _, chain, _ in chains for c in chain]
        self.loop_of = np.concatenate([np.full(len(chain), i) for i, chain, _ in chains])
        self.names = np.concatenate([names for _, _, names in chains])
        self.pos = np.concatenate([[nm[q] if nm[q] >= 0 else nm[q - 1] for q in range(len(nm))]
                                   for _, _, nm in chains])
        self.loop_len = np.array([sum(1 for x in nm if x >= 0) for _, _, nm in chains])
        self.ends = np.stack([np.array([_end_point(c, side) for c in self.curves]) for side in (0, -1)])
        self.nodes = _Nodes(self.curves, scale)
        self.roots = np.arange(self.nodes.count)

    def _refinable(self, ids: np.ndarray) -> np.ndarray:
        return (self.nodes.bound[ids] > self.ftol) & (self.nodes.depth[ids] < self.max_bisections)

    # --- orientation ------------------------------------------------------------------------
    def orientations(self) -> Optional[np.ndarray]:
        """The sign (+1 counter-clockwise, -1 clockwise) of each loop's enclosed area, by
        the chord polygons of its pieces with the lens bound (module docstring); None
        where a loop stays undecided with its pieces fine (an area too small to tell:
        the caller decides on the flattened loops)."""
        nodes, leaves, count = self.nodes, self.roots, len(self.chains)
        for _ in range(self.max_bisections + 1):
            A, B, b = nodes.A[leaves], nodes.B[leaves], nodes.bound[leaves]
            lp = self.loop_of[nodes.owner[leaves]]
            area = 0.5 * np.bincount(lp, weights=A[:, 0] * B[:, 1] - B[:, 0] * A[:, 1], minlength=count)
            L = np.linalg.norm(B - A, axis=1)
            err = np.bincount(lp, weights=2.0 * b * L + np.pi * b * b, minlength=count)
            undecided = ~(np.abs(area) > err)
            if not undecided.any():
                return np.sign(area)
            split = undecided[lp] & self._refinable(leaves)
            if not split.any():
                return None
            leaves = np.concatenate([leaves[~split], nodes.split(leaves[split]).ravel()])
        return None

    # --- crossings --------------------------------------------------------------------------
    def _adjacent(self, ci: np.ndarray, cj: np.ndarray) -> np.ndarray:
        """Curves ci, cj (chain indices) consecutive in one loop (closers as their curve)."""
        li, lj = self.loop_of[ci], self.loop_of[cj]
        n = self.loop_len[li]
        step = np.mod(self.pos[cj] - self.pos[ci], n)
        return (li == lj) & ((step == 1) | (step == n - 1))

    def _joints(self, i: np.ndarray, j: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """For node pairs (i, j): whether they come from consecutive Bezier pieces of one
        curve (a curve's pieces are consecutive root ids), and the point those pieces
        share (the lower one's end)."""
        nodes = self.nodes
        pi, pj = nodes.piece[i], nodes.piece[j]
        same = (nodes.owner[i] == nodes.owner[j]) & (np.abs(pi - pj) == 1)
        return same, nodes.B[np.minimum(pi, pj)]

    def _apart_at_joint(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """For pairs (i, j) of root pieces: consecutive pieces of one curve whose control
        points, but the joint J, lie strictly on either side of the line through J normal
        to t = (unit tangent in) + (unit tangent out): their hulls, which hold the pieces,
        meet only at J, so they cannot cross (a smooth or convex joint; the pairs that
        fold back are refined)."""
        nodes = self.nodes
        pieces, _ = self._joints(i, j)
        out = np.zeros(len(i), dtype=bool)
        if not pieces.any():
            return out
        k = np.flatnonzero(pieces)
        a, b = np.minimum(i[k], j[k]), np.maximum(i[k], j[k])      # roots: node id = piece id
        for p in np.unique(nodes.degree[a]):
            sel = np.flatnonzero(nodes.degree[a] == p)
            Pa, Pb = (_cartesian(nodes.net(int(p), nodes.row[x[sel]])) for x in (a, b))
            J = Pa[:, -1:]
            t_in, t_out = J[:, 0] - Pa[:, -2], Pb[:, 1] - J[:, 0]
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (t_in / np.linalg.norm(t_in, axis=1, keepdims=True) +
                     t_out / np.linalg.norm(t_out, axis=1, keepdims=True))[:, None, :]
                below = np.all(np.sum((Pa[:, :-1] - J) * t, axis=2) < 0, axis=1)
                above = np.all(np.sum((Pb[:, 1:] - J) * t, axis=2) > 0, axis=1)
            out[k[sel]] = below & above & np.all(Pb[:, 0] == J[:, 0], axis=1)
        return out

    def _excused(self, i: np.ndarray, j: np.ndarray, reach: float) -> np.ndarray:
        """Pairs whose every crossing the joint allowance excuses: consecutive curves, and
        node j's box (which holds any crossing of a chord of j) within ``reach`` of an
        end of either curve (the crossings are not refined there, as they cannot count);
        likewise consecutive pieces of one curve within ``reach`` of the point they share."""
        nodes = self.nodes
        ci, cj = nodes.owner[i], nodes.owner[j]
        out = self._adjacent(ci, cj)
        pieces, joint = self._joints(i, j)
        if not (out.any() or pieces.any()):
            return out
        lo, hi = nodes.lo[j], nodes.hi[j]

        def within(P: np.ndarray) -> np.ndarray:
            far = np.maximum(np.abs(P - lo), np.abs(hi - P))          # the farthest corner, per axis
            return np.hypot(far[:, 0], far[:, 1]) <= reach

        close = np.zeros(len(i), dtype=bool)
        for side in (0, 1):
            for owner in (ci, cj):
                close |= within(self.ends[side][owner])
        return (out & close) | (pieces & within(joint))

    def crossing_pairs(self, cap: int, joint_reach: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
        """(i, j): the pairs of fine nodes (bound <= ftol, or bisected max_bisections
        times) of different curves (a curve and its closer count as one), or of
        different Bezier pieces of one curve, whose boxes overlap, but for pairs of
        consecutive curves or pieces within ``joint_reach`` of their joint
        (:meth:`_excused`) and consecutive pieces that meet only at their joint
        (:meth:`_apart_at_joint`). At most ``cap`` pairs are followed at each level (a
        regular sample of them beyond: bounded, as the flattened check samples its pairs)."""
        nodes = self.nodes
        key = self.loop_of * (int(self.pos.max(initial=0)) + 2) + self.pos
        i, j = _box_pairs(nodes, self.roots, key, cap)
        keep = ~self._apart_at_joint(i, j)
        i, j = i[keep], j[keep]
        for _ in range(self.max_bisections + 1):
            if joint_reach > 0 and len(i):
                keep = ~self._excused(i, j, joint_reach)
                i, j = i[keep], j[keep]
            if len(i) > cap:
                keep = np.linspace(0, len(i) - 1, cap).astype(np.int64)
                i, j = i[keep], j[keep]
            coarse = np.unique(np.concatenate([i, j]))
            coarse = coarse[self._refinable(coarse)]
            if not len(coarse):
                break
            kids = np.full((nodes.count, 2), -1, dtype=np.int64)
            kids[coarse] = nodes.split(coarse)
            ki = np.where(kids[i, :1] >= 0, kids[i], np.stack([i, np.full_like(i, -1)], axis=1))
            kj = np.where(kids[j, :1] >= 0, kids[j], np.stack([j, np.full_like(j, -1)], axis=1))
            ni = np.concatenate([ki[:, a] for a in (0, 0, 1, 1)])
            nj = np.concatenate([kj[:, b] for b in (0, 1, 0, 1)])
            ok = (ni >= 0) & (nj >= 0)
            ni, nj = ni[ok], nj[ok]
            ok = nodes.meet(ni, nj)
            i, j = ni[ok], nj[ok]
        return i, j

    def check_crossings(self, cap: int, crossing_tol: float, joint_tol: float,
                        name: Callable[[int, int], str]) -> None:
        """CagdError when fine chords of different curves, or of different pieces of one
        curve, properly cross (the test of the flattened loops: touching is allowed, and
        consecutive curves of a loop, or pieces of a curve, may cross within
        ``joint_tol`` (relative) of their joint). ``name(loop, curve)`` names a curve in
        the message (curve -1: a closer); the message gives the crossing point."""
        # a crossing of consecutive curves within joint_tol of an end is excused: pairs
        # wholly that near are dropped before they are refined (rounding kept clear)
        i, j = self.crossing_pairs(cap, joint_tol * self.scale * (1.0 - JOINT_MARGIN))
        A, B = self.nodes.A, self.nodes.B
        shared = (np.all(A[i] == B[j], axis=1) | np.all(B[i] == A[j], axis=1) |
                  np.all(A[i] == A[j], axis=1) | np.all(B[i] == B[j], axis=1))
        i, j = i[~shared], j[~shared]
        if not len(i):
            return
        a, b, c, d = A[i], B[i], A[j], B[j]
        eps = crossing_tol * self.scale * self.scale
        o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
        hit = (((o1 > eps) & (o2 < -eps)) | ((o1 < -eps) & (o2 > eps))) & \
              (((o3 > eps) & (o4 < -eps)) | ((o3 < -eps) & (o4 > eps)))
        if not hit.any():
            return
        ci, cj = self.nodes.owner[i], self.nodes.owner[j]
        li, lj = self.loop_of[ci], self.loop_of[cj]
        adjacent = self._adjacent(ci, cj)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = c + (o1 / (o1 - o2))[:, None] * (d - c)       # where chord j (c -> d) meets chord i
        near = np.zeros(len(i), dtype=bool)
        for P in self.ends:
            for owner in (ci, cj):
                near |= np.linalg.norm(x - P[owner], axis=1) <= joint_tol * self.scale
        pieces, joint = self._joints(i, j)
        hit &= ~(adjacent & near) & ~(pieces & (np.linalg.norm(x - joint, axis=1) <= joint_tol * self.scale))
        if hit.any():
            k = first_pair(li, self.names[ci], lj, self.names[cj], hit)
            where = tuple(x[k])                                    # the crossing point
            first, second = sorted([(int(li[k]), int(self.names[ci[k]])), (int(lj[k]), int(self.names[cj[k]]))])
            other = "itself" if ci[k] == cj[k] else name(*second)
            raise CagdError(f"loops: {name(*first)} crosses {other} near (u, v) = "
                            f"({where[0]:.9g}, {where[1]:.9g})")

    # --- nesting ----------------------------------------------------------------------------
    def check_nesting(self, band: float, window: Callable[[np.ndarray], np.ndarray], chunk: int) -> None:
        """CagdError when a hole (tested at its first point, moved by ``window`` into the
        loops' periodic window) lies outside the outer loop or inside another hole: the
        winding numbers of module docstring, "touching" (within ftol + band of a loop:
        no verdict from that point) as with the flattened loops."""
        n = len(self.chains)
        if n < 2:
            return
        first = [int(np.flatnonzero((self.loop_of == h) & (self.names >= 0))[0]) for h in range(1, n)]
        P = window(np.array([_end_point(self.curves[c], 0) for c in first]))
        nodes, leaves = self.nodes, self.roots
        reach = self.ftol + band
        for _ in range(self.max_bisections + 1):       # bisect the pieces some point is near
            near = np.zeros(len(leaves), dtype=bool)
            for h, q in self._point_leaf_pairs(P, leaves, reach, chunk):
                other = self.loop_of[nodes.owner[leaves[q]]] != h + 1     # a hole's own loop gives no verdict
                h, q = h[other], q[other]
                dist = _segment_distance(P[h], nodes.A[leaves[q]], nodes.B[leaves[q]])
                near[q[dist <= nodes.bound[leaves[q]] + band]] = True
            split = near & self._refinable(leaves)
            if not split.any():
                break
            leaves = np.concatenate([leaves[~split], nodes.split(leaves[split]).ravel()])
        w = np.zeros((n - 1, n), dtype=np.int64)
        d = np.full((n - 1, n), np.inf)
        for h, q in self._point_leaf_pairs(P, leaves, reach, chunk):
            seg = leaves[q]
            lp = self.loop_of[nodes.owner[seg]]
            np.add.at(w, (h, lp), _crossings(P[h, 0], P[h, 1], nodes.A[seg], nodes.B[seg]))
            np.minimum.at(d, (h, lp), _segment_distance(P[h], nodes.A[seg], nodes.B[seg]))
        i = np.arange(1, n)[:, None]
        k = np.arange(n)[None]
        bad = (k != i) & ~(d <= reach) & (((k == 0) & (w == 0)) | ((k > 0) & (w != 0)))
        if bad.any():
            r, c = np.unravel_index(int(np.argmax(bad)), bad.shape)
            hole = 1 + int(r)
            if c == 0:
                raise CagdError(f"loops[{hole}]: the hole lies outside the outer loop loops[0]")
            raise CagdError(f"loops[{hole}]: the hole lies inside the hole loops[{int(c)}]")

    def _point_leaf_pairs(self, P: np.ndarray, leaves: np.ndarray, reach: float,
                          chunk: int) -> Iterator[Tuple[np.ndarray, np.ndarray]]:
        """(point indices h, leaf positions q) in chunks: the pairs where the leaf's box,
        grown by its bound and ``reach``, holds the point's v and lies (partly) at larger
        u (only those can cross the point's ray along +u or come within reach of it)."""
        nodes = self.nodes
        grow = nodes.bound[leaves] + reach
        lo, hi = nodes.lo[leaves], nodes.hi[leaves]
        rows = max(1, chunk // max(len(leaves), 1))
        for s in range(0, len(P), rows):
            p = P[s:s + rows]
            h, q = np.nonzero((lo[None, :, 1] - grow[None] <= p[:, 1, None]) &
                              (p[:, 1, None] <= hi[None, :, 1] + grow[None]) &
                              (p[:, 0, None] <= hi[None, :, 0] + grow[None]))
            yield h + s, q


def _box_pairs(nodes: _Nodes, ids: np.ndarray, key: np.ndarray, chunk: int) -> Tuple[np.ndarray, np.ndarray]:
    """Sweep and prune over the nodes ``ids``: the pairs of different keys (of their
    curves), or of one curve's different pieces, whose boxes overlap (candidates made
    about ``chunk`` at a time)."""
    n = len(ids)
    order = ids[np.argsort(nodes.lo[ids, 0], kind="stable")]
    start = nodes.lo[order, 0]
    reach = np.searchsorted(start, nodes.hi[order, 0], side="right")
    partners = np.maximum(reach - np.arange(n) - 1, 0)
    ends = np.cumsum(partners)
    out_i, out_j = [np.empty(0, np.int64)], [np.empty(0, np.int64)]
    first = 0
    while first < n:                                   # bounded: each round takes >= 1 row
        last = max(int(np.searchsorted(ends, ends[first] - partners[first] + chunk, side="right")), first + 1)
        cnt = partners[first:last]
        total = int(cnt.sum())
        if total:
            a = np.repeat(np.arange(first, last), cnt)
            b = a + 1 + ranks(cnt)
            i, j = order[a], order[b]
            oi, oj = nodes.owner[i], nodes.owner[j]
            keep = ((key[oi] != key[oj]) | ((oi == oj) & (nodes.piece[i] != nodes.piece[j]))) & nodes.meet(i, j)
            out_i.append(i[keep])
            out_j.append(j[keep])
        first = last
    return np.concatenate(out_i), np.concatenate(out_j)


def first_pair(li: np.ndarray, ni: np.ndarray, lj: np.ndarray, nj: np.ndarray, hit: np.ndarray) -> int:
    """The index of the hit whose pair of curves (loop, name) is first in (loop, name)
    order (each pair's lower curve first): the crossing a message reports."""
    k = np.flatnonzero(hit)
    a = np.stack([li[k], ni[k]], axis=1)
    b = np.stack([lj[k], nj[k]], axis=1)
    swap = (a[:, 0] > b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] > b[:, 1]))
    lo, hi = np.where(swap[:, None], b, a), np.where(swap[:, None], a, b)
    return int(k[np.lexsort((hi[:, 1], hi[:, 0], lo[:, 1], lo[:, 0]))[0]])


def _end_point(c: BSplineCurve, side: int) -> np.ndarray:
    """The first (side 0) or last (-1) point of c's Bezier pieces (its end, as the
    flattened loops take it)."""
    Q = _hom_pieces(c)[1][side, side]
    return Q[:2] / Q[2]
