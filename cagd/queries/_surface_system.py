"""The intersection system F(x) = 0 of two surfaces (x = (u, v, s, t), F = A - B) or of a
surface and a plane (x = (u, v), F = n.(A - o)), its Jacobian, the branch tangent (the
kernel of J by cofactors) and a minimum-norm Newton corrector; used by the marching of
:mod:`cagd.queries.intersect_surfaces` (Patrikalakis & Maekawa, "Shape Interrogation
for CAD/CAM", 5.8)."""
from __future__ import annotations

from typing import Optional

import numpy as np

from .._periodic import step_across, wrap
from . import _subdivision as sd
from ._numerics import SLACK_RTOL, TINY, unit

INSIDE_SLACK = 1e-12      # a parameter this share of the width outside the domain is inside


class System:
    def __init__(self, A: sd.Geometry, B: Optional[sd.Geometry], pl=None):
        self.A, self.B, self.pl = A, B, pl
        self.n = 4 if B is not None else 2
        gs = [A] + ([B] if B is not None else [])
        self.lo = np.concatenate([g.lo for g in gs])
        self.hi = np.concatenate([g.hi for g in gs])
        self.per = np.concatenate([g.closed for g in gs])
        self.span = self.hi - self.lo
        self.size = max(g.size for g in gs)
        self.pieces = [g.bezier for g in gs]

    @property
    def collapsed(self) -> bool:
        """Some boundary edge of a surface collapses to a point (a pole, an apex, a
        triangle's corner): its control points span under SLACK_RTOL of the net."""
        if getattr(self, "_collapsed", None) is None:
            out = False
            for g in (self.A, self.B):
                P = getattr(getattr(g, "nurbs", None), "control_points", None)
                if P is None or np.ndim(P) != 3:
                    continue
                size = max(float(np.ptp(P.reshape(-1, P.shape[-1]), axis=0).max()), TINY)
                for edge in (P[0], P[-1], P[:, 0], P[:, -1]):
                    out |= bool(np.ptp(edge, axis=0).max() <= SLACK_RTOL * size)
            self._collapsed = out
        return self._collapsed

    def _partials(self, k, x):
        """Point and first partials (N, 2, 3) of surface k at parameters x (N, 2)."""
        g, bp = (self.A, self.B)[k], self.pieces[k]
        x = g.clamp(x)
        d = bp.derivatives(bp.locate(x), x, 1)
        return d[0, 0], np.stack([d[1, 0], d[0, 1]], axis=1)

    def wrap(self, x):
        if not self.per.any():
            return x
        return np.where(self.per, wrap(x, self.lo, self.span), x)

    def wrapdiff(self, d):
        return step_across(d, 0.0, self.span, self.per)

    def inside(self, x, slack=INSIDE_SLACK):
        s = slack * self.span
        return np.all(self.per | ((x >= self.lo - s) & (x <= self.hi + s)), axis=-1)

    def clip(self, x):
        out = np.minimum(np.maximum(x, self.lo), self.hi)
        return np.where(self.per, x, out) if self.per.any() else out

    def eval(self, x):
        """F (N, m), J (N, m, n), point (N, 3), unit normals of a and b (N, 3)."""
        xw = self.wrap(x)
        pa, da = self._partials(0, xw[:, :2])
        na = unit(_cross(da[:, 0], da[:, 1]))
        if self.B is None:
            o, nrm = self.pl
            F = ((pa - o) @ nrm)[:, None]
            J = (da @ nrm)[:, None, :]
            nb = np.broadcast_to(nrm, pa.shape)
        else:
            pb, db = self._partials(1, xw[:, 2:])
            F = pa - pb
            J = np.concatenate([da.transpose(0, 2, 1), -db.transpose(0, 2, 1)], axis=2)
            nb = unit(_cross(db[:, 0], db[:, 1]))
        return F, J, pa, na, nb, da



def _cross(a, b):
    """a x b of 3-vectors (N, 3) (np.cross without its axis handling)."""
    out = np.empty(a.shape)
    out[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    out[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    out[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return out


def cofactors(J):
    """Generalized cross product of the m = n - 1 rows of J (N, m, n): the kernel
    direction c_i = (-1)^i det(J without column i), |c| = product of singular values."""
    n = J.shape[2]
    cols = [np.delete(J, i, axis=2) for i in range(n)]
    return np.stack([(-1) ** i * np.linalg.det(c) for i, c in enumerate(cols)], axis=1)


def velocity(da, c):
    """3-D velocity of the parameter direction c (first two entries move on a)."""
    return da[:, 0] * c[:, :1] + da[:, 1] * c[:, 1:2]




