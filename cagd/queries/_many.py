"""Closest points over many objects (issue 16: the patches of a model, the faces of a
STEP file): every point measured against the nearest object, objects far from every
point at the cost of a pass over their control net.

The objects are measured nearest first (by the median over the points of the distance
to the box of their control net, :func:`cagd.queries.bounds.net_box`), each only at the
points that box, and then the top boxes of its closest-point hierarchy, do not put
beyond the distance found so far; both are certified lower bounds (the object lies in
the convex hulls of its control points, Farin 3.3), so a point's answer is that of the
nearest object. On equal distances the first object in the list owns the point.
Used by :func:`cagd.queries.closest.closest_point` and
:func:`cagd.queries.deviation.deviation` on lists of objects.
"""
from __future__ import annotations

from typing import Callable, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from .bounds import net_box, robust_distance

#: Points per block of the box bounds (memory BOX_ROWS x TREE_TOP x dim doubles).
BOX_ROWS = 4096

Measure = Callable[[Union[Curve, Surface], np.ndarray], Tuple[list, bool]]


def objects(obj: object) -> list:
    """``obj`` as a non-empty list of engine curves and surfaces of one dimension (a
    single object as a list of one)."""
    objs: list = list(obj) if isinstance(obj, (list, tuple)) else [obj]
    if not objs:
        raise CagdError("obj: no object given")
    for k, o in enumerate(objs):
        if not isinstance(o, (Curve, Surface)):
            raise CagdError(f"obj: expected a cagd Curve or Surface (or a list of them), item {k} is "
                            f"{type(o).__name__}")
    if len({o.dim for o in objs}) > 1:
        raise CagdError(f"obj: the objects have different dimensions {sorted({o.dim for o in objs})}")
    return objs


def box_bounds(o: Union[Curve, Surface], X: np.ndarray, boxes: str = "nodes") -> np.ndarray:
    """Certified lower bounds (N,) of the distance from the points X to ``o``: the
    distance to the box of its control net (``boxes="whole"``, :func:`net_box`: no set-up)
    or to the nearest box of the top level of its closest-point hierarchy ("nodes"; at
    most TREE_TOP boxes, BOX_ROWS points at a time); the object lies in the convex hulls of
    those control points (Farin 3.3), a trimmed face in its surface's. Computed in the
    frame of those boxes (:func:`robust_distance`: no overflow)."""
    from ..surfaces.trimmed import TrimmedSurface
    from .closest import projector
    whole = o.untrimmed if isinstance(o, TrimmedSurface) else o
    if boxes == "whole":
        frame, lo, hi = net_box(whole)
    else:
        p = projector(whole)
        frame, lo, hi = p.frame, p._tree[-1][0], p._tree[-1][1]         # (T, dim) each
    out = np.empty(len(X))
    with np.errstate(over="ignore", invalid="ignore"):
        for s in range(0, len(X), BOX_ROWS):
            Xf = frame.inward(X[s:s + BOX_ROWS])[:, None, :]
            gap = np.maximum(np.maximum(lo - Xf, Xf - hi), 0.0)     # (n, T, dim)
            out[s:s + BOX_ROWS] = robust_distance(gap, np.zeros_like(gap)).min(axis=1)
    return out * frame.scale


def nearest(objs: Sequence[Union[Curve, Surface]], X: np.ndarray, measure: Measure) -> Tuple[list, bool]:
    """([d, params, feet, lower_bounds, owner, point_converged], flag) of the points X
    against the nearest of ``objs`` (see the module). ``measure(o, Xr)`` gives
    ([d, params, feet, lower_bounds, point_converged], flag) of the points Xr on one
    object, |d| its distances (d may carry a sign); ``flag`` is the and of the flags of
    the objects measured."""
    N = len(X)
    bounds = [box_bounds(o, X, "whole") for o in objs] if len(objs) > 1 else [np.zeros(N)]
    order = np.argsort([float(np.median(b)) for b in bounds], kind="stable")
    best: Optional[List[np.ndarray]] = None
    flag = True
    for k in order.tolist():
        o = objs[k]
        rows = np.arange(N)
        if best is not None:                # the whole box, then the hierarchy's top boxes
            rows = np.flatnonzero(bounds[k] <= np.abs(best[0]))
            if len(rows):               # (the hierarchy costs the object's set-up)
                rows = rows[box_bounds(o, X[rows]) <= np.abs(best[0][rows])]
            if not len(rows):
                continue
        part, ok = measure(o, X[rows])
        d, params, feet, lower, conv = part
        fields = [d, params, feet, lower, np.full(len(d), k), conv]
        flag = flag and ok
        if best is None:
            best = [np.array(f) for f in fields]            # writable copies (results are read-only)
            continue
        ad, ab = np.abs(d), np.abs(best[0][rows])
        closer = (ad < ab) | ((ad == ab) & (k < best[4][rows]))
        win = rows[closer]
        for i in range(6):
            best[i] = _broadcast_rows(best[i], fields[i].shape[1:])
            val = fields[i][closer]
            best[i][win] = val.reshape(val.shape + (1,) * (best[i].ndim - val.ndim))
    assert best is not None                     # objects() gives at least one object
    return best, flag


def _broadcast_rows(a: np.ndarray, row: tuple) -> np.ndarray:
    """``a`` (N, ...) with rows broadcast against the row shape ``row`` (curve parameters
    (N,) among surface parameters (N, 2) repeat in both columns)."""
    shape = np.broadcast_shapes(a.shape[1:], row)
    if shape == a.shape[1:]:
        return a
    return np.array(np.broadcast_to(a.reshape(a.shape + (1,) * (len(shape) - a.ndim + 1)), (len(a),) + shape))
