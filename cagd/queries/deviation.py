"""Deviation analysis: signed distances from a point cloud (a scan, a manufactured part)
to its model surface or curve, statistics and a colour-map picture.

The distance of a point X is the global minimum |X - S(x)| from
:func:`cagd.queries.closest.closest_point` (certified); its sign is that of
(X - S(x)).n with n = S_u x S_v / |S_u x S_v| the surface normal at the foot (seed 003,
2.1), positive on the side the normal points to. Plane curves use the left normal
(-y', x') / |C'| (positive on the left of the direction of travel); space curves have no
side and give unsigned distances.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, List, Optional, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._parallel import checked_workers, ordered_map
from .._deprecation import changed
from ..curves.base import Curve
from ..errors import CagdError
from ..surfaces.base import Surface
from ._many import nearest, objects
from .closest import TOL_CHANGED, _closest_point
from .results import Deviation
from ._numerics import TINY

__all__ = ["Deviation", "deviation", "deviation_map"]

Objects = Union[Curve, Surface, Sequence[Union[Curve, Surface]]]   # one object or the patches of a model




def _signs(obj: Union[Curve, Surface], params: np.ndarray, feet: np.ndarray, X: np.ndarray) -> Optional[np.ndarray]:
    """+1/-1 per point from the normal at the foot, None where no side exists (space
    curves). Where the normal is undefined (:meth:`cagd.Surface.normals`: a pole, a
    collapsed edge) the point counts as +1."""
    if isinstance(obj, Curve):
        if obj.dim != 2:
            return None
        d1 = obj.derivative(params, 1)
        normal = np.stack([-d1[:, 1], d1[:, 0]], axis=1)
    else:
        if obj.dim != 3:
            return None
        normal, _ = obj.normals(params[:, 0], params[:, 1])      # zero where undefined
    s = np.sign(np.einsum("nd,nd->n", X - feet, normal))
    return np.where(s == 0, 1.0, s)


#: Points measured per closest-point query by :func:`deviation` (bounds its working memory).
DEVIATION_CHUNK = 1 << 16
#: Points drawn at most by :func:`deviation_map` (every k-th, and the largest |d|).
MAP_POINTS = 200_000


def _deviation_chunk(objs: list, X: np.ndarray, signed: Optional[bool], tol: Optional[float],
                     param_tol: Optional[float]) -> tuple:
    """(d, params, feet, lower_bounds, owner, point_converged, signed) of the points X
    against the nearest of ``objs`` (:func:`cagd.queries._many.nearest`: objects far from
    every point cost a pass over their control net; on equal distances the first)."""
    def measure(o: Union[Curve, Surface], Xr: np.ndarray) -> tuple:
        r = _closest_point(o, Xr, tol=tol, param_tol=param_tol)
        sign = _signs(o, r.params, r.feet, Xr) if signed is not False else None
        if signed and sign is None:
            raise CagdError(f"signed: a {o.dim}-D curve has no side; use signed=False")
        d = r.distances if sign is None else sign * r.distances
        return [d, r.params, r.feet, r.lower_bounds, r.point_converged], sign is not None

    best, is_signed = nearest(objs, X, measure)
    return (*best, is_signed)


def _measure_chunk(shared: tuple, X: np.ndarray) -> tuple:
    """:func:`_deviation_chunk` of the points X, with ``shared`` = (objects, signed, tol,
    param_tol): the task of :func:`deviation`'s chunks, in this process or a worker's."""
    objs, signed, tol, param_tol = shared
    return _deviation_chunk(objs, X, signed, tol, param_tol)


def deviation(obj: Objects, points: ArrayLike, signed: Optional[bool] = None,
              percentiles: Sequence[float] = (1, 5, 25, 50, 75, 95, 99), tol: Optional[float] = None, *,
              param_tol: Optional[float] = None, workers: int = 1,
              progress: Optional[Callable[[int, int], None]] = None) -> Deviation:
    """Signed distances from ``points`` (N, dim) to a curve or surface (or to the nearest
    of several: the patches of one model), with max, min, mean, RMS, max |d| and
    percentiles.

    Args:
        obj: a cagd Curve or Surface, or a list of them (each point measured to the
            nearest; ``params`` are then on that object, see ``owner``).
        points: (N, dim) point cloud.
        signed: along the normal (surfaces, plane curves); default: whenever a side is
            defined; True for a space curve raises CagdError.
        percentiles: values in [0, 100].
        tol, param_tol: the closest points' stopping rule (:func:`closest_point`): ``tol`` a
            distance in model units (the foot moves by less; default 1e-12 times each
            object's size), ``param_tol`` a step relative to the parameter range. ``tol``
            was relative until cagd 0.1 (now ``param_tol``); passing it warns for one release.
        workers: processes measuring the chunks (issue 16, scan scale): 1 measures them
            here; N > 1 in a pool of N processes on this machine (:mod:`cagd._parallel`;
            started with ``spawn``, so a script calling this needs the
            ``if __name__ == "__main__":`` guard), the results the same bit for bit.
        progress: called as ``progress(done, total)`` (points measured, all points) after
            every chunk, in order.

    Raises:
        CagdError: not a curve or surface, empty/NaN points, wrong dimension, bad percentiles,
            tol or param_tol <= 0, ``workers`` not an integer >= 1; a worker's failure
            (naming the chunk and its points).

    The points are measured DEVIATION_CHUNK at a time (the closest-point queries'
    working memory is bounded by the chunk, with workers at most 2 x workers chunks are
    in flight; the results are O(N)). Every chunk is measured alone (the closest points
    are a function of the chunk's points: :func:`cagd.queries.closest.projector`), so
    the answer does not depend on ``workers``.
    """
    if tol is not None:
        changed("deviation", TOL_CHANGED)
    objs = objects(obj)
    workers = checked_workers(workers)
    pct = _checks.finite_array(percentiles, "percentiles", ndim=1)
    if np.any((pct < 0) | (pct > 100)):
        raise CagdError(f"percentiles: must lie in [0, 100], got {pct.tolist()}")
    X = np.atleast_2d(_checks.finite_array(points, "points"))
    if signed:
        for o in objs:
            if isinstance(o, Curve) and o.dim != 2:
                raise CagdError(f"signed: a {o.dim}-D curve has no side; use signed=False")
    # in chunks of DEVIATION_CHUNK points: the closest-point queries' working memory is
    # bounded by the chunk, the results are written into (N,)-sized arrays (issue 14:
    # 10^7 points through one query ran out of memory)
    out: List[np.ndarray] = []
    is_signed = True
    starts = range(0, max(len(X), 1), DEVIATION_CHUNK)

    def name(k: int) -> str:
        return f"chunk {k} (points {starts[k]} to {min(starts[k] + DEVIATION_CHUNK, len(X)) - 1})"

    parts = ordered_map(_measure_chunk, (objs, signed, tol, param_tol),
                        (X[s:s + DEVIATION_CHUNK] for s in starts), min(workers, len(starts)), name=name)
    for k, part in enumerate(parts):                  # (to the end: the pool closes there)
        s = starts[k]
        if not out:                                   # (N,)-sized results, filled chunk by chunk
            out = [np.empty((len(X),) + a.shape[1:], a.dtype) for a in part[:6]]
        for a, b in zip(out, part[:6]):
            a[s:s + len(b)] = b
        is_signed = is_signed and part[6]
        if progress is not None:
            progress(s + len(part[0]), len(X))
    d, params, feet, lower, owner, conv = out
    bad = np.flatnonzero(~conv)
    message = "" if not bad.size else (f"the closest point did not converge at {bad.size} of {len(d)} points "
                                       f"(first: index {int(bad[0])}): their distances are the nearest found, "
                                       f"the true ones lie between them and lower_bounds")
    # mean and RMS in units of max |d|: d * d overflowed for distances beyond 1e154 (RMS inf)
    max_abs = float(np.abs(d).max())
    unit = max_abs if max_abs > 0 else 1.0
    mean, rms = unit * float(np.mean(d / unit)), unit * float(np.sqrt(np.mean((d / unit) ** 2)))
    return Deviation(d, params, feet, lower, is_signed, float(d.max()), float(d.min()), mean, rms, max_abs,
                     {float(p): float(v) for p, v in zip(pct, np.percentile(d, pct))}, owner.astype(int),
                     not bad.size, message)


def deviation_map(obj: Objects, points: ArrayLike, path: Union[str, os.PathLike], result: Optional[Deviation] = None,
                  title: str = "deviation", samples: int = 40) -> Path:
    """Write a PNG colour map of the deviations: the points coloured by signed distance
    (diverging colour map, symmetric about 0) over a wireframe of the surface(s) (or the
    curves), with a colour bar; beyond MAP_POINTS points every k-th is drawn (and the
    largest |d|; the colour scale and title use all). Returns the path. matplotlib is
    imported here only."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    objs = objects(obj)
    res = deviation(objs, points) if result is None else result
    X = np.atleast_2d(_checks.finite_array(points, "points"))
    lim = max(res.max_abs, TINY)
    dist = res.distances
    if len(X) > MAP_POINTS:
        # every k-th point and the largest |d|: a scatter of 10^7 points would take
        # minutes and gigabytes in matplotlib, and the picture cannot show more
        keep = np.unique(np.append(np.arange(0, len(X), -(-len(X) // MAP_POINTS)), np.argmax(np.abs(dist))))
        X, dist = X[keep], dist[keep]
    cmap = "coolwarm" if res.signed else "viridis"
    vmin = -lim if res.signed else 0.0
    fig = plt.figure(figsize=(6.4, 4.8), dpi=110)
    if all(isinstance(o, Surface) for o in objs) and objs[0].dim == 3:
        ax = fig.add_subplot(projection="3d")
        for o in objs:
            (u0, u1), (v0, v1) = o.domain
            us, vs = np.linspace(u0, u1, samples), np.linspace(v0, v1, samples)
            if o.rectangular:
                G = o.grid(us, vs)
            else:                                   # triangle: collapsed-edge sampling
                U, V = np.meshgrid(us, vs, indexing="ij")
                G = o(U, V * (1.0 - U))
            ax.plot_wireframe(G[..., 0], G[..., 1], G[..., 2], color="0.75", lw=0.4,
                              rstride=max(1, samples // 20), cstride=max(1, samples // 20))
        sc = ax.scatter(X[:, 0], X[:, 1], X[:, 2], c=dist, cmap=cmap, vmin=vmin, vmax=lim, s=6)
    else:
        ax = fig.add_subplot()
        for o in objs:
            if isinstance(o, Curve):
                C = o(np.linspace(*o.domain, 20 * samples))
                ax.plot(C[:, 0], C[:, 1] if C.shape[1] > 1 else 0 * C[:, 0], color="0.4", lw=1.2)
        sc = ax.scatter(X[:, 0], X[:, 1] if X.shape[1] > 1 else 0 * X[:, 0], c=dist, cmap=cmap,
                        vmin=vmin, vmax=lim, s=8)
        ax.set_aspect("equal", adjustable="datalim")
    fig.colorbar(sc, ax=ax, shrink=0.8, label="signed distance" if res.signed else "distance")
    ax.set_title(f"{title}: max |d| {res.max_abs:.3g}, RMS {res.rms:.3g}", fontsize=10)
    path = Path(path)
    fig.savefig(path)
    plt.close(fig)
    return path
