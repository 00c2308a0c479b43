"""Pure-numpy helper shared by the bridges that build a :class:`cagd.TrimmedSurface`
from a CAD face (``cagd.occ.trim`` on OCP, the FreeCAD workbench on Part): is the
face's boundary just its parameter box (then the plain surface is the face)? And the
chaining of a loop's pcurves across a periodic seam (each moved by whole periods)."""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..curves.bspline import BSplineCurve

BOX_TOL = 1e-9          # relative (parameter box): a loop of iso-lines on the box's sides is "the box"


def is_box(loops: Sequence[Sequence[BSplineCurve]],
           domain: Tuple[Tuple[float, float], Tuple[float, float]], rel_tol: float = BOX_TOL,
           periods: Tuple[float, float] = (float("inf"), float("inf"))) -> bool:
    """One loop whose curves all have their control points on one side of the box
    ``domain`` (u = u0, u = u1, v = v0 or v = v1 within ``rel_tol`` times its size). In a
    direction of finite period (``periods``) the box's sides may lie anywhere a period
    apart: a loop of seam lines a whole turn apart bounds the whole surface wherever its
    seam is (a file's pcurves at u in [-pi, pi] on a surface of domain [0, 2 pi])."""
    if len(loops) != 1:
        return False
    (u0, u1), (v0, v1) = domain
    tol = rel_tol * max(u1 - u0, v1 - v0)
    window = turn_window(np.concatenate([c.control_points for c in loops[0]]), domain, periods, tol)
    return all(side_of(c.control_points, window, tol) is not None for c in loops[0])


def turn_window(P: np.ndarray, domain: Tuple[Tuple[float, float], Tuple[float, float]],
                periods: Tuple[float, float], tol: float) -> Tuple[Tuple[float, float], Tuple[float, float]]:
    """``domain`` with, in each direction of finite period whose points P (n, 2) span a
    whole period (within ``tol``), the box's sides moved to where P lies: a turn wherever
    its seam is."""
    box = [domain[0], domain[1]]
    for k, T in enumerate(periods):
        lo = float(P[:, k].min())
        if np.isfinite(T) and abs(float(P[:, k].max()) - lo - T) <= tol:
            box[k] = (lo, lo + T)
    return box[0], box[1]


def side_of(P: np.ndarray, domain: Tuple[Tuple[float, float], Tuple[float, float]], tol: float) -> Optional[int]:
    """Which coordinate the points P (n, 2) (a curve's control points) hold at a side
    of the box ``domain`` within ``tol``: 0 (u = u0 or u1), 1 (v = v0 or v1), or None."""
    lo, hi, first = P.min(axis=0).tolist(), P.max(axis=0).tolist(), P[0].tolist()
    for k in (0, 1):                 # all |P[:, k] - P[0, k]| <= tol, by the extremes
        if hi[k] - first[k] <= tol and first[k] - lo[k] <= tol and min(abs(first[k] - e) for e in domain[k]) <= tol:
            return k
    return None


def box_loop(domain: Tuple[Tuple[float, float], Tuple[float, float]]) -> List[BSplineCurve]:
    """The parameter box ``domain`` as a loop: its four sides, counter-clockwise, each a
    degree-1 segment on [0, 1]."""
    (u0, u1), (v0, v1) = domain
    corners = np.array([[u0, v0], [u1, v0], [u1, v1], [u0, v1], [u0, v0]])
    return [BSplineCurve(corners[i:i + 2], 1, [0.0, 0.0, 1.0, 1.0]) for i in range(4)]


def translated(c: BSplineCurve, du: float, dv: float) -> BSplineCurve:
    if du == 0 and dv == 0:
        return c
    return c.with_control_points(c.control_points + np.array([du, dv]))


def chained(loop: Sequence[BSplineCurve], periods: Tuple[float, float]) -> List[BSplineCurve]:
    """Each curve moved by whole periods to start where the previous one ends."""
    from .trimmed import _end            # a clamped curve's end is its end control point, bit for bit
    out = [loop[0]]
    for c in loop[1:]:
        end, start = _end(out[-1], 1), _end(c, 0)
        shift = [0.0, 0.0]
        for k in (0, 1):
            if np.isfinite(periods[k]):
                shift[k] = periods[k] * float(np.round((end[k] - start[k]) / periods[k]))
        out.append(translated(c, *shift))
    return out


def into_window(loop: Sequence[BSplineCurve], periods: Tuple[float, float],
                window: Tuple[Tuple[float, float], Tuple[float, float]]) -> List[BSplineCurve]:
    P = np.concatenate([c.control_points for c in loop])
    shift = [0.0, 0.0]
    for k in (0, 1):
        if np.isfinite(periods[k]):
            lo, hi = window[k]
            centre = 0.5 * (P[:, k].min() + P[:, k].max())
            shift[k] = periods[k] * float(np.round((0.5 * (lo + hi) - centre) / periods[k]))
    return [translated(c, *shift) for c in loop]
