"""Surface quality maps, vectorized over arrays of (u, v): curvature maps, zebra
(reflection lines), isophotes and draft angle.

Rule at degenerate points (the normal S_u x S_v undefined, :meth:`Surface.normals`:
a pole, an apex, a collapsed patch): every map is NaN there (zebra and isophote
indices -1) and the result's ``defined`` mask says where; nothing raises for them.
Directions (light, view, pull) must be unit vectors (within UNIT_TOL).

Sources: the fundamental forms and principal curvatures, do Carmo, Differential
Geometry of Curves and Surfaces, 3.3 (via :meth:`Surface._curvatures`); reflection
lines and isophotes, Farin, Curves and Surfaces for CAGD, ch. 23 (shape interrogation);
R. Klass, Correction of local surface irregularities using reflection lines, CAD 12
(1980); T. Poeschl, Detecting surface irregularities using isophotes, CAGD 1 (1984).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._results import ReadOnlyArrays
from ..errors import CagdError
from ..surfaces.base import Surface

UNIT_TOL = 1e-9            # |1 - |d|| allowed for a direction that must be a unit vector
PARALLEL_TOL = 1e-12       # |r x a| below this: the reflected ray runs along the bars, no stripe
KINDS = ("gaussian", "mean", "max", "min")


def _surface(surface: object) -> Surface:
    if not isinstance(surface, Surface):
        raise CagdError(f"surface: expected a cagd Surface, got {type(surface).__name__}")
    return surface


def unit_direction(value: ArrayLike, name: str) -> np.ndarray:
    """A finite 3-vector of length 1 (within UNIT_TOL); CagdError naming ``name`` else."""
    d = _checks.finite_array(value, name)
    if d.shape != (3,):
        raise CagdError(f"{name}: expected a 3-vector, got shape {d.shape}")
    length = float(np.linalg.norm(d))
    if abs(length - 1.0) > UNIT_TOL:
        raise CagdError(f"{name}: must be a unit vector, its length is {length!r}")
    return d


def _normals(surface: Surface, u: ArrayLike, v: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
    return _surface(surface).normals(_checks.parameters(u, "u"), _checks.parameters(v, "v"))


def curvature_map(surface: Surface, u: ArrayLike, v: ArrayLike, kind: str = "gaussian") -> np.ndarray:
    """The curvature ``kind`` at S(u, v), element-wise with broadcasting: "gaussian"
    K = (LN - M^2) / (EG - F^2), "mean" H = (EN - 2FM + GL) / (2 (EG - F^2)), "max" and
    "min" the principal curvatures H +- sqrt(H^2 - K) (do Carmo 3.3).

    Signs follow the normal S_u x S_v (as :meth:`Surface.mean_curvature`): a normal
    pointing away from the centre of curvature gives negative normal curvature, so an
    outward sphere of radius R has H = max = min = -1/R, an outward cylinder
    max = 0, min = -1/R; K does not depend on the normal's sign. NaN where the normal
    is undefined.

    Raises:
        CagdError: not a surface, unknown kind, non-finite u or v, a curvature beyond
            the floating-point range.
    """
    if kind not in KINDS:
        raise CagdError(f"kind: must be one of {', '.join(KINDS)}, got {kind!r}")
    s = _surface(surface)
    K, H, D, defined = s._curvatures(_checks.parameters(u, "u"), _checks.parameters(v, "v"), strict=False)
    with np.errstate(over="ignore", invalid="ignore"):
        out = {"gaussian": K, "mean": H}.get(kind)
        if out is None:
            root = np.sqrt(D)
            out = H + root if kind == "max" else H - root
    if not np.all(np.isfinite(out[defined])):
        raise CagdError(f"u, v: the {kind} curvature exceeds the floating-point range there (the surface is too small)")
    return out


@dataclass(frozen=True)
class Zebra(ReadOnlyArrays):
    """Zebra stripes (reflection lines) at the sampled points, shape of broadcast(u, v).

    phase: the bar coordinate in [0, stripes) of the reflected view ray (NaN where
    undefined); index: floor(phase), the light bar (-1 where undefined); lit: the point
    shows a bar (frac(phase) < width); defined: the normal is defined and the reflected
    ray is not parallel to the bars."""
    phase: np.ndarray
    index: np.ndarray
    lit: np.ndarray
    defined: np.ndarray


def zebra(surface: Surface, u: ArrayLike, v: ArrayLike, light_dir: ArrayLike, view_dir: ArrayLike,
          stripes: int = 8, width: float = 0.5) -> Zebra:
    """Reflection lines of a family of parallel light bars (infinitely far; Klass 1980, Farin ch. 23).

    The bars run along the unit vector a = ``light_dir``; ``stripes`` bars stand evenly
    around it (one every 2 pi / stripes of angle). The view ray v = ``view_dir`` (from
    the eye to the surface, orthographic) reflects at the unit normal n into
    r = v - 2 (v.n) n; its angle about the bars phi = atan2(r.e2, r.e1), with
    e1 = the unit part of v normal to a (any unit normal to a if v is along a) and
    e2 = a x e1, gives phase = stripes (phi + pi) / (2 pi) (mod stripes). A surface
    point is lit where frac(phase) < ``width``. A plane reflects every ray alike: its
    phase is constant.

    Raises:
        CagdError: not a surface, non-finite u or v, light_dir or view_dir not a unit
            3-vector, stripes < 1, width outside (0, 1).
    """
    a = unit_direction(light_dir, "light_dir")
    view = unit_direction(view_dir, "view_dir")
    count = _checks.integer(stripes, "stripes", 1, _checks.MAX_SAMPLES)
    w = _checks.scalar(width, "width")
    if not 0.0 < w < 1.0:
        raise CagdError(f"width: must be in (0, 1) (the lit fraction of a bar period), got {w!r}")
    n, defined = _normals(surface, u, v)
    e1 = view - (view @ a) * a
    if np.linalg.norm(e1) <= PARALLEL_TOL:
        e1 = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    r = view - 2.0 * (n @ view)[..., None] * n
    x, y = r @ e1, r @ e2
    defined = defined & (np.hypot(x, y) > PARALLEL_TOL)
    phase = np.where(defined, np.mod(count * (np.arctan2(y, x) + np.pi) / (2.0 * np.pi), count), np.nan)
    index = np.where(defined, np.minimum(np.floor(np.nan_to_num(phase)), count - 1), -1).astype(np.intp)
    lit = defined & (np.nan_to_num(phase) - index < w)
    return Zebra(phase, index, lit, defined)


@dataclass(frozen=True)
class Isophotes(ReadOnlyArrays):
    """Isophotes at the sampled points: value n.L (NaN where undefined), band (the
    isophote band, -1 where undefined), defined (the normal is defined)."""
    value: np.ndarray
    band: np.ndarray
    defined: np.ndarray


def isophotes(surface: Surface, u: ArrayLike, v: ArrayLike, light_dir: ArrayLike,
              levels: Union[int, ArrayLike] = 10) -> Isophotes:
    """Isophotes (Poeschl 1984; Farin ch. 23): the brightness n.L of a light from the unit
    direction L = ``light_dir``, and its band. ``levels``: an int m >= 1, m equal bands
    of [-1, 1] (band = floor(m (n.L + 1) / 2), 1 counted in the last band), or an
    increasing array of level values c_1 < ... < c_k (band = the number of levels
    <= n.L, 0..k); the isophotes are the band boundaries n.L = c_i.

    Raises:
        CagdError: not a surface, non-finite u or v, light_dir not a unit 3-vector,
            levels < 1, or levels not a finite increasing 1-D array.
    """
    light = unit_direction(light_dir, "light_dir")
    if np.ndim(levels) == 0:
        m = _checks.integer(levels, "levels", 1, _checks.MAX_SAMPLES)
        edges = -1.0 + 2.0 * np.arange(1, m) / m
    else:
        edges = _checks.finite_array(levels, "levels", ndim=1)
        if edges.size == 0 or np.any(np.diff(edges) <= 0):
            raise CagdError("levels: must be a non-empty increasing array of values")
    n, defined = _normals(surface, u, v)
    value = np.where(defined, np.clip(n @ light, -1.0, 1.0), np.nan)
    band = np.where(defined, np.searchsorted(edges, np.nan_to_num(value), side="right"), -1).astype(np.intp)
    return Isophotes(value, band, defined)


def draft_angle(surface: Surface, u: ArrayLike, v: ArrayLike, pull_dir: ArrayLike,
                degrees: bool = False) -> np.ndarray:
    """Draft angle asin(n.d) between the unit normal n and the plane normal to the unit
    pull direction d = ``pull_dir``: in radians (degrees if ``degrees``), in
    [-pi/2, pi/2]; 0 on a wall parallel to d, positive where n leans towards d; NaN
    where the normal is undefined.

    Raises:
        CagdError: not a surface, non-finite u or v, pull_dir not a unit 3-vector.
    """
    d = unit_direction(pull_dir, "pull_dir")
    n, defined = _normals(surface, u, v)
    # asin(n.d) as atan2(n.d, |n x d|): accurate near +-pi/2 as well
    angle = np.where(defined, np.arctan2(n @ d, np.linalg.norm(np.cross(n, d), axis=-1)), np.nan)
    return np.degrees(angle) if degrees else angle
