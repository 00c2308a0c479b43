"""STL and OBJ export of engine surfaces (issue 15).

An untrimmed :class:`Surface` is meshed on an n x n grid of its domain (two triangles a
cell); a :class:`TrimmedSurface` by its ``tessellation(count)``. The density is doubled
(bounded) until the chordal deviation is at most ``tol``: the distance between the
surface at each edge's parameter midpoint and the edge's chord midpoint, and for a trim
chord between the edge's point S(c(t)) at the chord's middle parameter and the chord's
midpoint.
Formats: binary/ASCII STL (3D Systems' StereoLithography Interface Specification, 1988)
and Wavefront OBJ (``v``/``f`` records, 1-based indices). Files are written atomically.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, List, Sequence, Tuple

import numpy as np

from .. import _atomic
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.trimmed import MAX_TESSELLATION_POINTS, TrimmedSurface

START_POINTS = 8          # grid points per direction of the first try
MAX_GRID_POINTS = 257     # grid points per direction at most for an untrimmed surface
MAX_REFINEMENTS = 6       # density doublings at most
MAX_TRIMMED_POINTS = MAX_TESSELLATION_POINTS   # grid points per direction at most for a trimmed face


@dataclass(frozen=True)
class MeshResult:
    """A triangle mesh: vertices (n, 3), triangles (m, 3) int, the measured chordal
    deviation ``max_error`` and whether it met ``tol``."""
    vertices: np.ndarray
    triangles: np.ndarray
    max_error: float
    converged: bool
    message: str


_NO_EDGES = np.empty((0, 2), dtype=np.int64)
_NO_POINTS = np.empty((0, 2))


def _items(geometry: Any) -> List[Any]:
    items = list(geometry) if isinstance(geometry, (list, tuple)) else [geometry]
    if not items:
        raise CagdError("geometry: empty list, nothing to mesh")
    for i, g in enumerate(items):
        if not isinstance(g, (Surface, TrimmedSurface)):
            raise CagdError(f"geometry[{i}]: expected a Surface or TrimmedSurface, got {type(g).__name__}")
    return items


def _grid_uv(s: Surface, n: int) -> Tuple[np.ndarray, np.ndarray]:
    (u0, u1), (v0, v1) = s.domain
    U, V = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
    uv = np.column_stack([U.ravel(), V.ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + n, a + n + 1, a + 1
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return uv, tri


def _evaluate(g: Any, uv: np.ndarray) -> np.ndarray:
    base = g.surface if isinstance(g, TrimmedSurface) else g
    return np.asarray(base(uv[:, 0], uv[:, 1]), dtype=np.float64)


def _deviation(g: Any, uv: np.ndarray, xyz: np.ndarray, tri: np.ndarray, bnd: np.ndarray = _NO_EDGES,
               bnd_mid: np.ndarray = _NO_POINTS) -> float:
    """max over edges |S((p+q)/2) - (S(p)+S(q))/2|; over a trimmed face's boundary chords
    also |S(c(t_mid)) - (S(p)+S(q))/2|, the trim curve c at the chord's middle parameter."""
    if len(tri) == 0:
        return 0.0
    e = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
    mid = _evaluate(g, 0.5 * (uv[e[:, 0]] + uv[e[:, 1]]))
    err = float(np.max(np.linalg.norm(mid - 0.5 * (xyz[e[:, 0]] + xyz[e[:, 1]]), axis=1)))
    if len(bnd):
        on = _evaluate(g, bnd_mid)
        err = max(err, float(np.max(np.linalg.norm(on - 0.5 * (xyz[bnd[:, 0]] + xyz[bnd[:, 1]]), axis=1))))
    return err


def _one(g: Any, tol: float) -> Tuple[np.ndarray, np.ndarray, float, bool, int]:
    n = START_POINTS
    cap = MAX_TRIMMED_POINTS if isinstance(g, TrimmedSurface) else MAX_GRID_POINTS
    for _ in range(MAX_REFINEMENTS + 1):
        bnd, bnd_mid, fallbacks = _NO_EDGES, _NO_POINTS, 0
        if isinstance(g, TrimmedSurface):
            t = g.tessellation(n)
            uv, tri, bnd, bnd_mid, fallbacks = t.uv, t.triangles, t.boundary, t.boundary_mid, t.fallbacks
        else:
            uv, tri = _grid_uv(g, n)
        xyz = _evaluate(g, uv)
        err = _deviation(g, uv, xyz, tri, bnd, bnd_mid)
        if err <= tol or n >= cap:
            break
        n = min(cap, 2 * n)
    return xyz, np.asarray(tri, dtype=np.int64), err, err <= tol and not fallbacks, fallbacks


def mesh(geometry: Any, tol: float = 1e-3) -> MeshResult:
    """One triangle mesh of a surface, trimmed surface or list of them with chordal
    deviation at most ``tol`` where the density cap allows."""
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not np.isfinite(tol) or tol <= 0:
        raise CagdError(f"tol: must be a positive finite distance, got {tol!r}")
    verts: List[np.ndarray] = []
    tris: List[np.ndarray] = []
    worst, ok, offset, fallbacks = 0.0, True, 0, 0
    for g in _items(geometry):
        xyz, tri, err, conv, fb = _one(g, float(tol))
        fallbacks += fb
        if xyz.shape[1] != 3:
            raise CagdError(f"geometry: surfaces must be 3-D for a mesh, got dimension {xyz.shape[1]}")
        verts.append(xyz)
        tris.append(tri + offset)
        offset += len(xyz)
        worst, ok = max(worst, err), ok and conv
    V = np.concatenate(verts)
    T = np.concatenate(tris)
    V.flags.writeable = False
    T.flags.writeable = False
    msg = (f"max deviation {worst:.3g} <= tol {tol:.3g}" if worst <= tol
           else f"max deviation {worst:.3g} > tol {tol:.3g} at the density cap")
    if fallbacks:
        msg += (f"; {fallbacks} trimmed region(s) were triangulated by the fallback of ear clipping "
                f"(triangles may overlap there)")
    return MeshResult(V, T, worst, ok, msg)


def _stl_bytes(m: MeshResult, binary: bool) -> bytes:
    p = m.vertices[m.triangles]
    nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    ln = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.divide(nrm, ln, out=np.zeros_like(nrm), where=ln > 0)
    if binary:
        rec = np.zeros(len(p), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
        rec["n"], rec["v"] = nrm, p
        return b"cagd binary STL".ljust(80, b" ") + struct.pack("<I", len(p)) + rec.tobytes()
    lines = ["solid cagd"]
    for k in range(len(p)):
        lines.append("facet normal %.9g %.9g %.9g\n outer loop" % tuple(nrm[k]))
        lines.extend(" vertex %.17g %.17g %.17g" % tuple(q) for q in p[k])
        lines.append(" endloop\nendfacet")
    lines.append("endsolid cagd\n")
    return "\n".join(lines).encode("ascii")


def write_stl(path: Any, geometry: Any, tol: float = 1e-3, binary: bool = True) -> MeshResult:
    """Write ``geometry`` meshed within chordal ``tol`` as an STL file (binary by default)."""
    m = mesh(geometry, tol)
    _atomic.write_file(path, _stl_bytes(m, bool(binary)), "path")
    return m


def write_obj(path: Any, geometry: Any, tol: float = 1e-3) -> MeshResult:
    """Write ``geometry`` meshed within chordal ``tol`` as a Wavefront OBJ file."""
    m = mesh(geometry, tol)
    out: Sequence[str] = (["# cagd OBJ"] + ["v %.17g %.17g %.17g" % tuple(v) for v in m.vertices]
                          + ["f %d %d %d" % tuple(t + 1) for t in m.triangles])
    _atomic.write_file(path, "\n".join(out) + "\n", "path")
    return m
