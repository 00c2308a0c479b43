"""The geometry of dragging a pole with the mouse, free of GUI code (numpy only):
which pole a picked ray hits, where the dragged pole goes in the plane through it
normal to the view, along an axis (a surface net's normal, or X, Y, Z) or in depth
along the view direction, its place on a snap grid, and the normals of a pole grid. The pole editor (editpoles.py) turns
mouse positions into rays (origin on the focal plane, direction into the scene) and
calls these; the headless suite and tests/workbench/test_poledrag.py test them.

A ray is ``origin + s direction``; distances are in model units. Closest points of
two lines and a ray-plane intersection are the textbook formulas (e.g. Schneider &
Eberly, Geometric Tools for Computer Graphics, 7.1.2 and 11.1.1).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import ensure_engine

ensure_engine()
from cagd import CagdError  # noqa: E402

PARALLEL = 1e-9      # |sin| of the angle below which a ray counts as parallel to a plane or an axis


def _unit(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise CagdError(f"{name}: must be 3 finite numbers, got {v!r}")
    n = float(np.linalg.norm(a))
    if n == 0.0:
        raise CagdError(f"{name}: must not be the zero vector")
    return a / n


def _point(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise CagdError(f"{name}: must be 3 finite numbers, got {v!r}")
    return a


def ray_offsets(points, origin, direction) -> tuple:
    """(distance of each point from the line of the ray, its depth s along the ray):
    s = (p - o).d, distance = |p - o - s d| for the unit direction d."""
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    o, d = _point(origin, "origin"), _unit(direction, "direction")
    rel = P - o
    depth = rel @ d
    return np.linalg.norm(rel - depth[:, None] * d, axis=1), depth


def pick_pole(points, origin, direction, tol: float) -> Optional[int]:
    """Index of the point nearest the ray's line among those within ``tol`` of it (the
    frontmost, smallest depth, of points equally near), or None when none is. ``tol``:
    the pick radius in model units (the editor's pixel radius times the size of a pixel
    on the focal plane)."""
    if not tol > 0.0:
        raise CagdError(f"tol: must be > 0, got {tol!r}")
    dist, depth = ray_offsets(points, origin, direction)
    inside = np.nonzero(dist <= tol)[0]
    if not len(inside):
        return None
    best = inside[np.lexsort((depth[inside], dist[inside]))]       # by distance, then depth
    return int(best[0])


def drag_in_plane(anchor, normal, origin, direction) -> np.ndarray:
    """Where the ray meets the plane through ``anchor`` normal to ``normal`` (the view
    plane through the picked pole): o + s d with s = (a - o).n / d.n. CagdError when
    the ray is parallel to the plane."""
    a, n = _point(anchor, "anchor"), _unit(normal, "normal")
    o, d = _point(origin, "origin"), _unit(direction, "direction")
    dn = float(d @ n)
    if abs(dn) <= PARALLEL:
        raise CagdError("direction: the ray is parallel to the drag plane")
    return o + (float((a - o) @ n) / dn) * d


def drag_along(anchor, axis, origin, direction) -> np.ndarray:
    """The point of the line ``anchor + t axis`` nearest the ray's line (the closest
    points of two lines: t = (b e - c d') / (a c - b^2) with a = u.u, b = u.d, c = d.d,
    d' = u.w, e = d.w, w = anchor - origin). CagdError when axis and ray are parallel
    (the pole's place along the axis is then undetermined)."""
    p, u = _point(anchor, "anchor"), _unit(axis, "axis")
    o, d = _point(origin, "origin"), _unit(direction, "direction")
    b = float(u @ d)
    denom = 1.0 - b * b
    if denom <= PARALLEL ** 2:
        raise CagdError("axis: parallel to the ray (move the pole in the view plane, or turn the view)")
    w = p - o
    t = (b * float(d @ w) - float(u @ w)) / denom
    return p + t * u


#: the directions a drag can be held to (the panel's "Drag along"): None is the view plane
AXES = {"View plane": None, "X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def snapped(point, step: float, axis=None) -> np.ndarray:
    """The point on a grid of spacing ``step`` (model units; 0: unchanged): every
    coordinate rounded to a multiple of step, or, for a drag held to a coordinate
    ``axis``, that coordinate only (so the point stays on the axis' line)."""
    p = _point(point, "point")
    if not (np.isfinite(step) and step >= 0.0):
        raise CagdError(f"step: must be a finite number >= 0, got {step!r}")
    if step == 0.0:
        return p
    if axis is None:
        return np.round(p / step) * step
    u = _unit(axis, "axis")
    k = int(np.argmax(np.abs(u)))
    if abs(u[k]) < 1.0 - PARALLEL:
        raise CagdError(f"axis: a snap along an axis needs a coordinate axis (X, Y or Z), got {tuple(u)}")
    q = p.copy()
    q[k] = np.round(p[k] / step) * step
    return q


def drag_in_depth(anchor, axis, start, now, up) -> np.ndarray:
    """The anchor moved along ``axis`` (the view direction) by the mouse's travel up the
    screen: anchor + ((now - start).up) axis, with ``start`` and ``now`` the pointer's
    points on the focal plane and ``up`` the view's unit up vector."""
    p, u = _point(anchor, "anchor"), _unit(axis, "axis")
    travel = float((_point(now, "now") - _point(start, "start")) @ _unit(up, "up"))
    return p + travel * u


def net_normals(grid) -> np.ndarray:
    """Unit normals of a (m, n, 3) pole grid: the cross product of its differences in u
    and v (central inside, one-sided on the border: numpy.gradient); zero where they are
    parallel (a degenerate corner)."""
    P = np.asarray(grid, dtype=float)
    if P.ndim != 3 or P.shape[2] != 3 or P.shape[0] < 2 or P.shape[1] < 2:
        raise CagdError(f"grid: must be an (m, n, 3) array with m, n >= 2, got shape {P.shape}")
    du, dv = np.gradient(P, axis=(0, 1))
    N = np.cross(du, dv)
    length = np.linalg.norm(N, axis=-1, keepdims=True)
    scale = max(float(np.abs(P).max()), 1.0) ** 2
    return np.where(length > PARALLEL * scale, N / np.where(length > 0, length, 1.0), 0.0)
