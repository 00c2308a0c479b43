"""Marching along one intersection branch: predictor along the kernel tangent,
corrector by Newton with a plane constraint, steps adapted to the curvature, exact
stops on domain boundaries, loop closure and singular points (bisection on the
orientation of the kernel). See :mod:`cagd.queries.intersect_surfaces`."""
from __future__ import annotations

import numpy as np

from ._surface_system import System, cofactors, velocity
from ._newton import newton
from ._numerics import AT_END_RTOL, RESIDUAL_FLOOR, RESIDUAL_SHARE, SIZE_ROUNDING, SLACK_RTOL, TINY, residual_tol
from ._surface_system import INSIDE_SLACK

MIN_STEP_RTOL = 1e-9        # the smallest marching step, share of the model size
SINGULAR_SINE = 1e-9        # |n_A x n_B| below this: a singular point (a tangency or a crossing)
CROSSING_SINE = 1e-4        # ... and above this where the bisection ends: no simple crossing there

MAX_ANGLE = 0.35              # largest turn of the tangent per step (rad)
MAX_STEPS = 20000

class Marcher:
    def __init__(self, S: System, tol: float):
        self.S, self.tol = S, tol
        self.ftol = residual_tol(tol, S.size)
        self.hmax = S.size / 8
        self.hmin = max(MIN_STEP_RTOL * S.size, 10 * tol * RESIDUAL_SHARE)
        self.sing = SINGULAR_SINE

    def frame(self, x):
        """Point, kernel vector c (unnormalized), 3-D unit tangent of c, speed |dP/dc|, sine."""
        F, J, P, na, nb, da = self.S.eval(x[None])
        c = cofactors(J)[0]
        v = velocity(da, c[None])[0]
        speed = np.linalg.norm(v)
        sine = np.linalg.norm(np.cross(na[0], nb[0]))
        return P[0], c, v / max(speed, TINY), speed, sine

    def step_for(self, kappa):
        if kappa <= 0:
            return self.hmax
        R = 1.0 / kappa
        theta = np.clip(0.8 * (77.0 * self.tol / R) ** 0.25, 0.01, MAX_ANGLE / 1.5)
        return min(self.hmax, theta * R)

    def correct(self, x, t, xp, fix=None):
        """Corrector from the predictor xp: plane t.(x - xp) = 0, or x_fix = bound."""
        if fix is None:
            C, g = t[None], np.array([t @ xp])
        else:
            i, val = fix
            C = np.zeros((1, self.S.n))
            C[0, i] = 1.0
            g = np.array([val])
        y, ok = newton(self.S, xp[None], C, g, self.ftol)
        return y[0], bool(ok[0])

    def march(self, x0, sigma):
        """March from x0 in the direction sigma * c. Returns (xs, end, other_side)."""
        S = self.S
        xs = [x0.copy()]
        P0, c, T, speed, sine = self.frame(x0)
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
            y, ok = self.correct(x, tpar, xp, fix)
            if ok and not S.inside(y, INSIDE_SLACK) and fix is None:
                out = ~S.per & ((y < S.lo) | (y > S.hi))
                i = int(np.argmax(out * np.abs(np.where(y < S.lo, S.lo - y, y - S.hi))))
                bnd = S.lo[i] if y[i] < S.lo[i] else S.hi[i]
                y, ok = self.correct(x, tpar, np.where(np.arange(S.n) == i, bnd, y), (i, bnd))
                fix = (i, bnd)
            if not ok or (fix is not None and not S.inside(y, AT_END_RTOL)):
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
            P1, c1, T1, speed1, sine1 = self.frame(y)
            dist = np.linalg.norm(P1 - Ps[-1])
            if dist > 2.0 * h or (dist < 0.1 * h and fix is None):
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
            T1s = sigma * T1
            cos = float(T @ T1s)
            if cos < -np.cos(MAX_ANGLE) and fix is None:      # the kernel flipped
                found = None
                if h <= 4 * self.hmin or (kappa is not None and kappa * h <= 0.2):
                    found = self.crossing(x, y, c)
                if found is None:        # a step across a tight turn, not a crossing
                    h *= 0.25
                    if h < self.hmin:
                        return xs, "stalled", None
                    continue
                xs.append(found[0])
                return xs, "singular", y
            if cos < np.cos(MAX_ANGLE) or sine1 <= self.sing:
                if sine1 <= self.sing and h <= 4 * self.hmin:
                    xs.append(y)
                    return xs, "singular", None
                h *= 0.5
                if h < self.hmin:
                    return xs, "stalled", None
                continue
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
            angle = np.arccos(np.clip(cos, -1.0, 1.0))
            kappa = angle / max(dist, TINY)
            xs.append(y)
            Ps.append(P1)
            x, c, T, speed = y, c1, T1s, speed1
            if fix is not None:
                return xs, "boundary", None
            h = min(2 * h, self.step_for(kappa))
        return xs, "limit", None

    def crossing(self, xa, xb, ca):
        """Bisection for the point between xa and xb where the kernel vector flips:
        (xa, xb) closing on it, or None when it is no crossing (the bisection lost the
        branch, or the surfaces are not tangent there: n_A x n_B does not vanish, the
        flip came from a step across a hairpin turn)."""
        S = self.S
        for _ in range(60):
            Pa, Pb = S.eval(np.stack([xa, xb]))[2]
            if np.linalg.norm(Pa - Pb) <= max(0.1 * self.tol, SIZE_ROUNDING * S.size):
                break
            d = xb - xa
            mid = 0.5 * (xa + xb)
            y, ok = newton(S, mid[None], d[None], np.array([d @ mid]), self.ftol)
            if not ok[0]:
                return None
            cm = self.frame(y[0])[1]
            if cm @ ca > 0:
                xa = y[0]
            else:
                xb = y[0]
        else:
            return None
        # at a simple crossing sine ~ the distance to it / size, here ~ 0.1 tol / size
        if self.frame(xa)[4] > CROSSING_SINE:
            return None
        return xa, xb


def segments_distance(Q, P):
    """Distance from points Q (S, 3) to the polyline P (K, 3) and the length of the
    nearest segment."""
    if len(P) < 2:
        d = np.linalg.norm(Q - P[0], axis=1)
        return d, np.zeros(len(Q))
    a, b = P[:-1], P[1:]
    ab = b - a
    L2 = np.maximum(np.einsum("kd,kd->k", ab, ab), TINY)
    tau = np.clip(np.einsum("skd,kd->sk", Q[:, None] - a[None], ab) / L2, 0.0, 1.0)
    near = a[None] + tau[..., None] * ab[None]
    d = np.linalg.norm(Q[:, None] - near, axis=2)
    k = np.argmin(d, axis=1)
    return d[np.arange(len(Q)), k], np.sqrt(L2[k])


