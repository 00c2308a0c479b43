"""STL and OBJ export of engine surfaces (issue 15).

A surface is meshed on a grid of parameter lines placed per knot span by its second
derivatives: a cell h_u x h_v's edges and diagonals sag by at most
(h_u^2 |S_uu| + 2 h_u h_v |S_uv| + h_v^2 |S_vv|) / 8 from the surface (Taylor's bound
of a linear interpolant; the flatness tests of Filip, Magedson and Markot, "Surface
algorithms using bounds on derivatives", CAGD 3, 1986), so per span h^2 |S_dd| <= 2 tol
in each direction, and 2 h_u h_v |S_uv| <= 4 tol with cells square in space (the count
is the same for any split), the maxima sampled per span (2 degree points at least). An
untrimmed surface gives two triangles a cell; a :class:`TrimmedSurface` is triangulated
on those lines by :func:`cagd.surfaces._tessellate.tessellation`, its trim polylines
within tol / (2 median speed) of the curves in (u, v). The counts are doubled (bounded) until
the measured chordal deviation is at most ``tol``: the distance between the surface at
each edge's parameter midpoint and the edge's chord midpoint, and for a trim chord
between the edge's point S(c(t)) at the chord's middle parameter and the chord's
midpoint.
Formats: binary/ASCII STL (3D Systems' StereoLithography Interface Specification, 1988)
and Wavefront OBJ (``v``/``f`` records, 1-based indices). Files are written atomically.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, List, Optional, Sequence, Tuple

import numpy as np

from .. import _atomic
from .._ranks import ranks
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from ..surfaces.trimmed import TrimmedSurface, knot_lines

MAX_GRID_POINTS = 1025    # a face's grid has at most MAX_GRID_POINTS^2 points (about 1 M)
MAX_LINES = 4097          # grid lines per direction at most
MAX_REFINEMENTS = 6       # density doublings at most
TRIM_CELL_ASPECT = 2.0    # a trimmed face's grid cells: the longer side at most this times the shorter, in space
CURVATURE_SAMPLES = 2_000_000   # second-derivative samples per face at most (the grid's first guess)


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


def _grid_uv(us: np.ndarray, vs: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    U, V = np.meshgrid(us, vs, indexing="ij")
    uv = np.column_stack([U.ravel(), V.ravel()])
    n = len(vs)
    i, j = np.meshgrid(np.arange(len(us) - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + n, a + n + 1, a + 1
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return uv, tri


def _breaks(n: BSplineSurface, d: int, lo: float, hi: float) -> np.ndarray:
    """lo, the knots of direction d of the NURBS form ``n`` strictly between lo and hi
    (repeated by periods in a periodic direction: :func:`cagd.surfaces.trimmed.knot_lines`), hi."""
    return np.concatenate([[lo], knot_lines(n, d, lo, hi), [hi]])


def _span_samples(breaks: np.ndarray, per_span: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, per_span + 1)[:-1]
    inner = (breaks[:-1, None] + np.diff(breaks)[:, None] * t[None]).ravel()
    return np.append(inner, breaks[-1])


def _cell_sizes(s: Surface, n: BSplineSurface, breaks: Tuple[np.ndarray, np.ndarray], tol: float,
                aspect: Optional[float] = None) -> Tuple[List[np.ndarray], float]:
    """Per direction and knot span, the parameter step by curvature (the module docstring);
    and the median speed max(|S_u|, |S_v|) (a trim chord within tol / speed of its curve
    in (u, v) is about within tol of it in space; the refinement measures). ``n``: s's
    NURBS form (its degrees). ``aspect``: the longest cell side in space at most this many
    times the shortest (a trimmed face: the triangulation of the band along its trim has
    no points inside the cells, so a cell long across a curved direction would give
    triangles long across it). Sampled once per face; the refinement only multiplies."""
    bu, bv = breaks
    pu, pv = max(3, 2 * n.degree_u), max(3, 2 * n.degree_v)
    if (pu * len(bu)) * (pv * len(bv)) > CURVATURE_SAMPLES:     # very many spans: fewer per span
        pu = pv = max(1, int(np.sqrt(CURVATURE_SAMPLES / (len(bu) * len(bv)))))
    su, sv = _span_samples(bu, pu), _span_samples(bv, pv)
    twist = float(np.linalg.norm(s.grid(su, sv, 1, 1), axis=-1).max())
    sizes = []
    for d, (b, x) in enumerate(((bu, su), (bv, sv))):
        acc = np.linalg.norm(s.grid(su, sv, 2, 0) if d == 0 else s.grid(su, sv, 0, 2), axis=-1).max(axis=1 - d)
        span = np.clip(np.searchsorted(b, x, side="right") - 1, 0, len(b) - 2)
        peak = np.zeros(len(b) - 1)             # the largest second derivative per span (ends included)
        np.maximum.at(peak, span, acc)
        np.maximum.at(peak, np.clip(span - 1, 0, None), acc * (x == b[span]))
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            h = np.sqrt(2.0 * tol / peak)       # h^2 |S_dd| <= 2 tol: a quarter of the 8 tol budget
        sizes.append(np.minimum(np.nan_to_num(h, nan=np.inf), np.diff(b)))
    # the twist: 2 h_u h_v |S_uv| <= 4 tol. The cell count is then the same however the product
    # is split, so the cells are made square in space (h_u |S_u| = h_v |S_v|, mean speeds)
    mu = float(np.median(np.linalg.norm(s.grid(su, sv, 1, 0), axis=-1)))
    mv = float(np.median(np.linalg.norm(s.grid(su, sv, 0, 1), axis=-1)))
    hu, hv = float(sizes[0].max()), float(sizes[1].max())
    if twist > 0 and 2.0 * hu * hv * twist > 4.0 * tol:
        c = 2.0 * tol / twist
        ratio = mv / max(mu, 1e-300)                                  # h_u / h_v for square cells
        tu, tv = np.sqrt(c * ratio), np.sqrt(c / max(ratio, 1e-300))
        if hu < tu:
            tv = c / hu
        elif hv < tv:
            tu = c / hv
        sizes = [np.minimum(sizes[0], tu), np.minimum(sizes[1], tv)]
    if aspect is not None and mu > 0 and mv > 0:
        lu, lv = float(sizes[0].max()) * mu, float(sizes[1].max()) * mv      # the cells' sides in space
        sizes = [np.minimum(sizes[0], aspect * lv / mu), np.minimum(sizes[1], aspect * lu / mv)]
    return sizes, max(mu, mv)


def _lines(breaks: Tuple[np.ndarray, np.ndarray], sizes: List[np.ndarray], factor: int
           ) -> Tuple[np.ndarray, np.ndarray, bool]:
    """Grid lines (us, vs) at the steps ``sizes`` per span, ``factor`` times as many;
    capped (MAX_LINES, MAX_GRID_POINTS^2) with the flag set."""
    counts = [np.clip(np.ceil(np.diff(b) / np.maximum(h, 1e-300)), 1.0, float(MAX_LINES)) * factor
              for b, h in zip(breaks, sizes)]
    total = [float(c.sum()) for c in counts]
    capped = False
    budget = float(MAX_GRID_POINTS) ** 2
    shrink = min(1.0, np.sqrt(budget / max(total[0] * total[1], 1.0)),
                 MAX_LINES / max(total[0], 1.0), MAX_LINES / max(total[1], 1.0))
    if shrink < 1.0:
        capped = True
        counts = [np.maximum(np.floor(c * shrink), 1.0) for c in counts]
    out = []
    for b, c in zip(breaks, counts):
        k = c.astype(np.int64)
        j = ranks(k)
        out.append(np.append(np.repeat(b[:-1], k) + np.repeat(np.diff(b) / k, k) * j, b[-1]))
    return out[0], out[1], capped


def _box(g: Any) -> Tuple[Surface, np.ndarray, np.ndarray]:
    """(the surface, the parameter box to mesh): a trimmed face's outer loop's box, in
    the domain along its bounded directions."""
    if not isinstance(g, TrimmedSurface):
        (u0, u1), (v0, v1) = g.domain
        return g, np.array([u0, v0]), np.array([u1, v1])
    s = g.surface
    P = np.concatenate([c.control_points for c in g.loops[0]])
    lo, hi = P.min(axis=0), P.max(axis=0)
    for d, periodic in enumerate((s.periodic_u, s.periodic_v)):
        if not periodic:
            lo[d], hi[d] = np.clip([lo[d], hi[d]], *s.domain[d])
    return s, lo, hi


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
    from ..surfaces._tessellate import tessellation
    s, lo, hi = _box(g)
    n = s if isinstance(s, BSplineSurface) else s.to_nurbs()
    breaks = (_breaks(n, 0, lo[0], hi[0]), _breaks(n, 1, lo[1], hi[1]))
    banded = isinstance(g, TrimmedSurface) and g.region_box() is None      # a band along the trim
    sizes, speed = _cell_sizes(s, n, breaks, tol, TRIM_CELL_ASPECT if banded else None)
    factor = 1
    for _ in range(MAX_REFINEMENTS + 1):
        us, vs, capped = _lines(breaks, sizes, factor)
        bnd, bnd_mid, fallbacks = _NO_EDGES, _NO_POINTS, 0
        if isinstance(g, TrimmedSurface):
            t = tessellation(g, 0, (us, vs), 0.5 * tol / speed / factor if speed > 0 else None)
            uv, tri, bnd, bnd_mid, fallbacks = t.uv, t.triangles, t.boundary, t.boundary_mid, t.fallbacks
        else:
            uv, tri = _grid_uv(us, vs)
        xyz = _evaluate(g, uv)
        err = _deviation(g, uv, xyz, tri, bnd, bnd_mid)
        if err <= tol or capped:
            break
        factor *= 2
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
