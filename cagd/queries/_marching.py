"""Marching along one intersection branch: predictor along the kernel tangent,
corrector by Newton with a plane constraint, steps adapted to the curvature, exact
stops on domain boundaries, loop closure and singular points (bisection on the
orientation of the kernel). See :mod:`cagd.queries.intersect_surfaces`."""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ._surface_system import System, cofactors, velocity
from ._newton import newton
from ._numerics import AT_END_RTOL, RESIDUAL_FLOOR, RESIDUAL_SHARE, SIZE_ROUNDING, SLACK_RTOL, TINY, residual_tol, \
    smallest_per_group
from ._surface_system import INSIDE_SLACK

MIN_STEP_RTOL = 1e-9        # the smallest marching step, share of the model size
SINGULAR_SINE = 1e-9        # |n_A x n_B| below this: a singular point (a tangency or a crossing)
CROSSING_SINE = 1e-4        # ... and above this where the bisection ends: no simple crossing there

MAX_ANGLE = 0.35              # largest turn of the tangent per step (rad)
MAX_STEPS = 20000
COS_MAX_ANGLE = math.cos(MAX_ANGLE)
MEET_ANGLE_FLOOR = 0.05       # march_seeds: the turn assumed at least this (rad) in the meeting test

class Marcher:
    """Marches branches of the system S. Every march is a lane (a generator yielding its
    requests: frames at points, corrector solves); :meth:`drive` runs all live lanes in
    lock step, one batched evaluation (and one batched Newton corrector) per request
    kind and round for all of them, so both directions of a seed cost one march's
    Python overhead."""

    def __init__(self, S: System, tol: float):
        self.S, self.tol = S, tol
        self.ftol = residual_tol(tol, S.size)
        self.hmax = S.size / 8
        self.hmin = max(MIN_STEP_RTOL * S.size, 10 * tol * RESIDUAL_SHARE)
        self.sing = SINGULAR_SINE

    @staticmethod
    def frames(ev):
        """Per row of System.eval's arrays: point, kernel vector c (unnormalized), 3-D
        unit tangent of c, speed |dP/dc|, sine of the normals' angle."""
        F, J, P, na, nb, da = ev
        c = cofactors(J)
        v = velocity(da, c)
        speed = np.linalg.norm(v, axis=1)
        sine = np.linalg.norm(np.cross(na, nb), axis=1)
        return P, c, v / np.maximum(speed, TINY)[:, None], speed, sine

    def step_for(self, kappa):
        if kappa <= 0:
            return self.hmax
        R = 1.0 / kappa
        theta = np.clip(0.8 * (77.0 * self.tol / R) ** 0.25, 0.01, MAX_ANGLE / 1.5)
        return min(self.hmax, theta * R)

    def _correct(self, t, xp, fix=None):
        """Corrector request from the predictor xp: plane t.(x - xp) = 0, or x_fix = bound.
        The answer: (y, converged, frame at y)."""
        if fix is None:
            C, g = t, float(t @ xp)
        else:
            i, val = fix
            C = np.zeros(self.S.n)
            C[i] = 1.0
            g = val
        out = yield ("newton", xp[None], C[None], np.array([g]))
        y, ok, fr = out
        return y[0], bool(ok[0]), _row(fr, 0)

    def drive(self, lanes, stop=None):
        """Run the lanes (generators) to their ends in lock step: each round, the
        requests of all live lanes of one kind are answered by one batched call
        ("frame": System.eval at rows x; "newton": the corrector on rows (xp, C, g)).
        ``stop(results)`` -> indices of lanes to drop (their result stays None).
        Returns the lanes' return values."""
        S = self.S
        results = [None] * len(lanes)
        live = {}
        for i, g in enumerate(lanes):
            self._advance(i, g, None, live, results)
        while live:
            if stop is not None:
                for i in stop(results):
                    live.pop(i, None)
            if not live:
                break
            kinds = {}
            for i, req in live.items():
                kinds.setdefault(req[1][0], []).append(i)
            answers = {}
            for kind, ids in kinds.items():
                reqs = [live[i][1] for i in ids]
                sizes = np.cumsum([0] + [len(r[1]) for r in reqs])
                X = np.concatenate([r[1] for r in reqs])
                if kind == "frame":
                    fr = self.frames(S.eval(X))
                    for k, i in enumerate(ids):
                        answers[i] = tuple(a[sizes[k]:sizes[k + 1]] for a in fr)
                else:
                    C = np.concatenate([r[2] for r in reqs])
                    g = np.concatenate([r[3] for r in reqs])
                    y, ok, ev = newton(S, X, C, g, self.ftol, full=True)
                    fr = self.frames(ev)
                    for k, i in enumerate(ids):
                        sl = slice(sizes[k], sizes[k + 1])
                        answers[i] = (y[sl], ok[sl], tuple(a[sl] for a in fr))
            for i, ans in answers.items():
                self._advance(i, live[i][0], ans, live, results)
        return results

    @staticmethod
    def _advance(i, gen, answer, live, results):
        try:
            live[i] = (gen, gen.send(answer))
        except StopIteration as e:
            live.pop(i, None)
            results[i] = e.value

    def march_both(self, x0):
        """Both directions from x0 at once: (forward, backward) results of :meth:`march`;
        backward None when the forward march closed the loop (it is not needed)."""
        def stop(res):
            return [1] if res[0] is not None and res[0][1] == "closed" else []
        fw, bw = self.drive([self.lane(x0, 1.0), self.lane(x0, -1.0)], stop)
        return fw, (None if fw[1] == "closed" else bw)

    def lane(self, x0, sigma, meet=None):
        """The march from x0 in the direction sigma * c as a lane (see :meth:`drive`);
        returns (xs, end, other_side). ``meet`` (own index, points, params, tangents of
        the other starts, :meth:`march_seeds`): the lane also ends when another start
        lies on its new segment, end "met", other_side (its index, its orientation)."""
        S = self.S
        xs = [x0.copy()]
        fr = yield ("frame", x0[None])
        P0, c, T, speed, sine = _row(fr, 0)
        if speed <= RESIDUAL_FLOOR * S.size or sine <= self.sing:
            return xs, "singular", None
        T = sigma * T
        Ps = [P0]
        h = self.hmax / 64           # grows by at most 2x a step, capped by the measured curvature
        kappa = None
        travelled = 0.0
        x = x0.copy()
        for _ in range(MAX_STEPS):
            tpar = sigma * c / speed
            xp = x + h * tpar
            fix = None
            if not S.inside(xp, 0.0):
                out = ~S.per & ((xp < S.lo) | (xp > S.hi))
                bound = np.where(xp < S.lo, S.lo, S.hi)
                alpha = np.where(out, (bound - x) / np.where(out, xp - x, 1.0), 1.0)
                i = int(np.argmin(alpha))
                a = max(float(alpha[i]), 0.0)
                if a * h <= SLACK_RTOL * S.size:
                    return xs, "boundary", None
                xp = x + a * h * tpar
                fix = (i, bound[i])
            y, ok, fy = yield from self._correct(tpar, xp, fix)
            if ok and not S.inside(y, INSIDE_SLACK) and fix is None:
                out = ~S.per & ((y < S.lo) | (y > S.hi))
                i = int(np.argmax(out * np.abs(np.where(y < S.lo, S.lo - y, y - S.hi))))
                bnd = S.lo[i] if y[i] < S.lo[i] else S.hi[i]
                y, ok, fy = yield from self._correct(tpar, np.where(np.arange(S.n) == i, bnd, y), (i, bnd))
                fix = (i, bnd)
            if not ok or (fix is not None and not S.inside(y, AT_END_RTOL)):
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
            P1, c1, T1, speed1, sine1 = fy
            step3 = P1 - Ps[-1]
            dist = math.sqrt(float(step3 @ step3))
            if dist > 2.0 * h or (dist < 0.1 * h and fix is None):
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
            T1s = sigma * T1
            cos = float(T @ T1s)
            if cos < -COS_MAX_ANGLE and fix is None:      # the kernel flipped
                found = None
                if h <= 4 * self.hmin or (kappa is not None and kappa * h <= 0.2):
                    found = yield from self.crossing(x, y, c)
                if found is None:        # a step across a tight turn, not a crossing
                    h *= 0.25
                    if h < self.hmin:
                        return xs, "stalled", None
                    continue
                xs.append(found[0])
                return xs, "singular", y
            if cos < COS_MAX_ANGLE or sine1 <= self.sing:
                if sine1 <= self.sing and h <= 4 * self.hmin:
                    xs.append(y)
                    return xs, "singular", None
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
            if meet is not None:
                found = self._met(meet, Ps[-1], P1, y, T1s, dist, cos)
                if found is not None:
                    j, tau, s_q = found
                    if tau < 0.3 and len(xs) > 1:
                        xs.pop()
                    xs.append(xs[-1] + S.wrapdiff(meet[2][j] - xs[-1]))
                    return xs, "met", (j, s_q)
            # loop closure: the start lies on the new segment
            if len(xs) >= 3 and travelled > 2 * h and fix is None:
                seg = P1 - Ps[-1]
                w = P0 - Ps[-1]
                tau = float(w @ seg) / float(seg @ seg)
                near = np.linalg.norm(w - tau * seg)
                pd = np.abs(S.wrapdiff(x0 - y)) <= 0.25 * S.span
                if -0.05 <= tau <= 1.05 and near <= 0.1 * np.linalg.norm(seg) + 10 * self.ftol and pd.all():
                    xc = x + S.wrapdiff(x0 - x)
                    if tau < 0.3 and len(xs) > 2:
                        xs.pop()
                        xc = xs[-1] + S.wrapdiff(x0 - xs[-1])
                    xs.append(xc)
                    return xs, "closed", None
            travelled += dist
            angle = math.acos(min(max(cos, -1.0), 1.0))
            kappa = angle / max(dist, TINY)
            xs.append(y)
            Ps.append(P1)
            x, c, T, speed = y, c1, T1s, speed1
            if fix is not None:
                return xs, "boundary", None
            h = min(2 * h, self.step_for(kappa))
        return xs, "limit", None

    def _met(self, meet, Pa, Pb, y, T1, dist, cos):
        """The first other start on the segment [Pa, Pb] (step ending at y with unit
        tangent T1, turning by arccos(cos)): within the segment's sagitta bound
        (dist * angle / 8, with a factor 2 and a floor) of it in 3-D, its parameters
        within a quarter of the domain of y and its tangent parallel. Returns (index,
        tau along the segment, its orientation +-1) or None."""
        own, Q, X, T = meet
        seg = Pb - Pa
        L2 = float(seg @ seg)
        if L2 <= 0.0:
            return None
        tau = ((Q - Pa) @ seg) / L2
        cand = np.flatnonzero((tau >= -0.05) & (tau <= 1.05))
        cand = cand[cand != own]
        if not cand.size:
            return None
        w = Q[cand] - Pa
        near = np.linalg.norm(w - tau[cand, None] * seg, axis=1)
        angle = max(math.acos(min(max(cos, -1.0), 1.0)), MEET_ANGLE_FLOOR)
        along = T[cand] @ T1
        hit = (near <= 0.25 * dist * angle + 10 * self.ftol) & (np.abs(along) >= COS_MAX_ANGLE)
        hit &= np.all(np.abs(self.S.wrapdiff(X[cand] - y)) <= 0.25 * self.S.span, axis=1)
        if not hit.any():
            return None
        cand, along = cand[hit], along[hit]
        k = int(np.argmin(tau[cand]))
        return int(cand[k]), float(tau[cand[k]]), 1.0 if along[k] > 0 else -1.0

    def march_seeds(self, x):
        """March from all starts x (K, n) at once, both directions, every lane ending on
        its own (boundary, closed loop, singular point, ...) or where it meets another
        start (:meth:`_met`); then the lanes are chained through the starts they met
        (continuing with the met start's lane in the same direction of travel). Returns
        (chains, used, queue): chains [(xs, (end, end))] ("closed", "closed" for a
        loop), used (K,) the starts on an accepted chain, queue the other-side starts of
        singular ends. A chain running into a start already on another chain (a meeting
        missed in between) is dropped: its starts stay unused (the caller marches them
        one by one)."""
        K = len(x)
        fr = self.frames(self.S.eval(x))
        meet = (None, fr[0], x, fr[2])
        lanes = []
        for i in range(K):
            m = (i,) + meet[1:]
            lanes += [self.lane(x[i], 1.0, m), self.lane(x[i], -1.0, m)]
        res = self.drive(lanes)
        used = np.zeros(K, bool)
        chains, queue = [], []
        for i in range(K):
            if used[i]:
                continue
            walks, seen, ok = [], {i}, True
            for sigma in (1.0, -1.0):
                pieces, cur, s, end, beyond = [], i, sigma, None, None
                for _ in range(K + 1):
                    xs, e, other = res[2 * cur + (0 if s > 0 else 1)]
                    pieces.append(np.asarray(xs))
                    if e != "met":
                        end, beyond = e, other
                        break
                    j, s_j = other
                    if j == i:
                        end = "closed"
                        break
                    if j in seen or used[j]:
                        ok = False
                        break
                    seen.add(j)
                    cur, s = j, s_j
                walks.append((pieces, end, beyond))
                if not ok or end == "closed":
                    break
            if not ok:
                continue
            xs = _concat(walks[0][0])
            if walks[0][1] == "closed":
                ends = ("closed", "closed")
            else:
                xs = np.concatenate([_concat(walks[1][0])[::-1], xs[1:]])
                ends = (walks[1][1], walks[0][1])
            if len(xs) < 2:
                continue
            used[list(seen)] = True
            chains.append((xs, ends))
            queue += [w[2] for w in walks if w[2] is not None]
        return chains, used, queue

    def crossing(self, xa, xb, ca):
        """Bisection for the point between xa and xb where the kernel vector flips:
        (xa, xb) closing on it, or None when it is no crossing (the bisection lost the
        branch, or the surfaces are not tangent there: n_A x n_B does not vanish, the
        flip came from a step across a hairpin turn). A lane's sub-generator."""
        S = self.S
        for _ in range(60):
            Pab = (yield ("frame", np.stack([xa, xb])))[0]
            if np.linalg.norm(Pab[0] - Pab[1]) <= max(0.1 * self.tol, SIZE_ROUNDING * S.size):
                break
            d = xb - xa
            mid = 0.5 * (xa + xb)
            y, ok, fr = yield ("newton", mid[None], d[None], np.array([d @ mid]))
            if not ok[0]:
                return None
            cm = fr[1][0]
            if cm @ ca > 0:
                xa = y[0]
            else:
                xb = y[0]
        else:
            return None
        # at a simple crossing sine ~ the distance to it / size, here ~ 0.1 tol / size
        fr = yield ("frame", xa[None])
        if fr[4][0] > CROSSING_SINE:
            return None
        return xa, xb


def _concat(pieces):
    """Lanes chained through the starts they met: each piece begins at the start the
    previous one ended on (the same point, its parameters maybe a period apart)."""
    out = [pieces[0]]
    for p in pieces[1:]:
        out.append(p[1:] + (out[-1][-1] - p[0]))
    return np.concatenate(out)


def _row(fr, j):
    """Row j of every array of a frame tuple."""
    return tuple(a[j] for a in fr)


SEGMENT_GROUP = 32            # segments_distance(within=...): consecutive segments boxed together
POINT_CHUNK = 4096            # ... and points boxed at once


def segments_distance(Q, P, chunk: int = 512, within: Optional[float] = None):
    """Distance from points Q (S, 3) to the polyline P (K, 3) and the length of the
    nearest segment. The nearest segment is found from |q - a - tau ab|^2 expanded into
    matrix products (centred coordinates; (S, K) arrays, a chunk of points at a time),
    then the distance to it and to its two neighbours is computed directly (the
    expansion's rounding, ~1e-16 of the size squared, can only confuse neighbours).
    ``within``: only distances up to this matter; points farther from every segment get
    inf (and length 0): the segments are boxed in runs of SEGMENT_GROUP, and a point is
    measured against the runs whose box grown by ``within`` holds it only."""
    if len(P) < 2:
        d = np.linalg.norm(Q - P[0], axis=1)
        return d, np.zeros(len(Q))
    if within is not None:
        return _segments_within(np.asarray(Q, float), np.asarray(P, float), float(within))
    c = P.mean(axis=0)
    Pc, Qc = P - c, Q - c
    a, ab = Pc[:-1], np.diff(Pc, axis=0)
    L2 = np.maximum(np.einsum("kd,kd->k", ab, ab), TINY)
    aa, aab = np.einsum("kd,kd->k", a, a), np.einsum("kd,kd->k", a, ab)
    K = len(a)
    near = np.empty(len(Q), np.intp)
    for s in range(0, len(Q), chunk):
        q = Qc[s:s + chunk]
        wab = q @ ab.T - aab                                            # (q - a).ab
        tau = np.clip(wab / L2, 0.0, 1.0)
        ww = np.einsum("sd,sd->s", q, q)[:, None] - 2.0 * (q @ a.T) + aa
        near[s:s + chunk] = np.argmin(ww - 2.0 * tau * wab + tau * tau * L2, axis=1)
    best = np.full(len(Q), np.inf)
    L = np.zeros(len(Q))
    for off in (-1, 0, 1):
        k = np.clip(near + off, 0, K - 1)
        w = Qc - a[k]
        t = np.clip(np.einsum("sd,sd->s", w, ab[k]) / L2[k], 0.0, 1.0)
        d = np.linalg.norm(w - t[:, None] * ab[k], axis=1)
        better = d < best
        best[better], L[better] = d[better], np.sqrt(L2[k][better])
    return best, L


def _segments_within(Q, P, within: float):
    """segments_distance(Q, P, within=within): (S, G) box tests of the points against
    runs of SEGMENT_GROUP segments, then every segment of a run that holds the point,
    the nearest kept per point (exact: |q - a - tau ab| with tau clipped)."""
    a, ab = P[:-1], np.diff(P, axis=0)
    K = len(a)
    starts = np.arange(0, K, SEGMENT_GROUP)
    lo = np.minimum.reduceat(np.minimum(P[:-1], P[1:]), starts) - within
    hi = np.maximum.reduceat(np.maximum(P[:-1], P[1:]), starts) + within
    best, L = np.full(len(Q), np.inf), np.zeros(len(Q))
    for s0 in range(0, len(Q), POINT_CHUNK):
        q = Q[s0:s0 + POINT_CHUNK]
        pt, grp = np.nonzero(np.all((q[:, None] >= lo) & (q[:, None] <= hi), axis=2))
        if not len(pt):
            continue
        k = (starts[grp][:, None] + np.arange(SEGMENT_GROUP)).ravel()
        pt = np.repeat(pt, SEGMENT_GROUP)
        ok = k < K
        k, pt = k[ok], pt[ok]
        w = q[pt] - a[k]
        L2 = np.maximum(np.einsum("kd,kd->k", ab[k], ab[k]), TINY)
        t = np.clip(np.einsum("kd,kd->k", w, ab[k]) / L2, 0.0, 1.0)
        d = np.linalg.norm(w - t[:, None] * ab[k], axis=1)
        first = smallest_per_group(pt, d)
        best[s0 + pt[first]], L[s0 + pt[first]] = d[first], np.sqrt(L2[first])
    far = best > within
    best[far], L[far] = np.inf, 0.0
    return best, L

