"""Knot removal with an error bound (Tiller 1992; Piegl & Tiller, The NURBS Book,
5.4 and 9.4.4; the seeds do not treat it).

Removing one knot u_r (multiplicity s) from a degree-p B-spline solves the control
points P_first .. P_last (first = r - p, last = r - s) of the curve without the knot
from both ends (algorithm A5.8):

    Q_i = (P_i - (1 - a_i) Q_(i-1)) / a_i,      a_i = (u - u_i) / (u_(i+p+1) - u_i),

inwards from the left and the same from the right. The two ends meet in one control
point: where they disagree by e (the distance of the two values, or of P_i from the
combination of its two neighbours when the count is odd), the curve without the knot
differs from the original by e times one B-spline basis function, so by at most e,
and only on [u_first, u_(last+p+1)). The bound is kept per knot span and a removal is
accepted while the sum of the bounds of every span it touches stays within tol (the
triangle inequality; A9.8's bookkeeping). A rational curve is worked on in
homogeneous coordinates with the tolerance tol * w_min / (1 + max |P|) (The NURBS
Book, eq. 5.30), which bounds the change of the rational curve by tol.

The arrays here are (n, k, D): k curves that share the knots (the rows of a surface
along one direction, k = 1 for a curve), removed together; the bound is the largest
over the k.
"""
from __future__ import annotations

from dataclasses import dataclass
from bisect import bisect_left, bisect_right
from typing import List, Tuple

import numpy as np

#: passes over the interior knots at most (each pass removes at least one knot or ends)
MAX_PASSES = 64


def _remove_once(U: List[float], P: List[np.ndarray], p: int, r: int, s: int
                 ) -> Tuple[np.ndarray, float]:
    """One removal of the knot U[r] (its last index; multiplicity s): the new control
    points first .. last - 1 (first = r - p, last = r - s; one fewer than before) and
    the removal's error e (A5.8 with t = 0). Only the window is read."""
    u = U[r]
    first, last = r - p, r - s
    off = first - 1
    temp = np.empty((last - off + 2,) + P[0].shape)
    temp[0], temp[last + 1 - off] = P[off], P[last + 1]
    i, j, ii, jj = first, last, 1, last - off
    while j - i > 0:
        ai = (u - U[i]) / (U[i + p + 1] - U[i])
        aj = (u - U[j]) / (U[j + p + 1] - U[j])
        temp[ii] = (P[i] - (1.0 - ai) * temp[ii - 1]) / ai
        temp[jj] = (P[j] - aj * temp[jj + 1]) / (1.0 - aj)
        i, ii, j, jj = i + 1, ii + 1, j - 1, jj - 1
    if j - i < 0:
        gap = temp[ii - 1] - temp[jj + 1]
    else:
        ai = (u - U[i]) / (U[i + p + 1] - U[i])
        gap = P[i] - (ai * temp[ii + 1] + (1.0 - ai) * temp[ii - 1])
    err = float(np.sqrt(np.einsum("kd,kd->k", gap, gap)).max())
    # A5.8's write-back: P_i = temp_(i-off) from both ends inwards, then the control point
    # (2r - s - p) / 2 goes; the window first .. last keeps last - first points
    Q = np.stack(P[first:last + 1])
    i, j = first, last
    while j - i > 0:
        Q[i - first], Q[j - first] = temp[i - off], temp[j - off]
        i, j = i + 1, j - 1
    return np.delete(Q, (2 * r - s - p) // 2 - first, axis=0), err


def remove_knots(U: np.ndarray, P: np.ndarray, p: int, tol: float
                 ) -> Tuple[np.ndarray, np.ndarray, int, float]:
    """As many interior knots of (U, P) (degree p, P (n, k, D)) removed as the bound
    allows: passes from left to right over the distinct interior knots, each removed
    while every span it touches keeps a summed bound within ``tol``. Returns the knots,
    control points, the number of knots removed and the largest summed bound. Knots
    and rows are Python lists while removing (a removal is a local change and a list
    deletion a memmove: O(p) arithmetic per try; arrays made each time cost O(n))."""
    Ul: List[float] = [float(x) for x in U]
    Pl: List[np.ndarray] = list(np.asarray(P, float))
    a, b = Ul[p], Ul[len(Ul) - p - 1]
    spans = sorted(set(x for x in Ul if a <= x <= b))  # distinct knots: the span bounds
    bound = np.zeros(len(spans) - 1)                     # summed removal bounds per span
    removed = 0
    for _ in range(MAX_PASSES):
        changed = False
        k = p + 1
        while k < len(Ul) - p - 1:
            u = Ul[k]
            r = k
            while Ul[r + 1] == u:
                r += 1
            s = r - k + 1
            if not a < u < b:
                k = r + 1
                continue
            window, err = _remove_once(Ul, Pl, p, r, s)
            # the change lives on [U[r - p], U[r + p + 1 - s]) of the knots before it
            lo = bisect_right(spans, Ul[r - p]) - 1
            hi = bisect_left(spans, Ul[min(r + p + 1 - s, len(Ul) - 1)])
            touched = slice(max(lo, 0), max(hi, lo + 1))
            if err <= tol and float((bound[touched] + err).max()) <= tol:
                bound[touched] += err
                first, last = r - p, r - s
                Pl[first:last + 1] = list(window)
                del Ul[r]
                removed, changed = removed + 1, True
                continue                                 # the same knot again, if still there
            k = r + 1
        if not changed:
            break
    return np.array(Ul), np.stack(Pl), removed, float(bound.max(initial=0.0))


def homogeneous_tol(hom: np.ndarray, tol: float) -> float:
    """The homogeneous tolerance that bounds the rational curve's change by ``tol``:
    tol * w_min / (1 + max |P|) (The NURBS Book, eq. 5.30); hom (..., D + 1)."""
    w = hom[..., -1]
    pts = hom[..., :-1] / w[..., None]
    return tol * float(w.min()) / (1.0 + float(np.sqrt((pts * pts).sum(-1)).max()))


@dataclass(frozen=True)
class KnotRemoval:
    """The result of ``remove_knots``: the curve or surface with ``removed`` fewer
    knots, ``error_bound`` the certified bound of its distance from the original at
    equal parameters (the summed removal bounds, at most tol), ``deviation`` the largest
    distance measured at DEVIATION_SAMPLES parameters per original knot span (at equal
    parameters, so at most the bound). ``converged`` is always True (every knot the
    bound allows is removed); ``message`` says how many knots stayed."""
    result: object
    removed: int
    error_bound: float
    deviation: float
    converged: bool = True
    message: str = ""


#: parameters per knot span (and direction) at which the removal's deviation is measured
DEVIATION_SAMPLES = 9


def _span_samples(knots: np.ndarray, p: int) -> np.ndarray:
    brk = np.unique(knots[p:len(knots) - p])
    f = np.linspace(0.0, 1.0, DEVIATION_SAMPLES)
    return np.unique((brk[:-1, None] + f[None] * np.diff(brk)[:, None]).ravel())
