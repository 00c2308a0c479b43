"""Area and enclosed volume of surfaces by Gauss-Legendre quadrature on each knot span.

area = ∫∫ |S_u × S_v| du dv;  volume = 1/3 ∑ ∫∫ S · (S_u × S_v) du dv over the closed
set of patches (divergence theorem with div x = 3; positive when the normals
S_u × S_v point outward). Integrated on the exact NURBS form (``to_nurbs()``), which
has the same image as the object, span by span, with ``nodes`` points per span and
direction; the quadrature error is estimated by comparing with ``nodes + 8`` points
and reported. That is an estimate, not a bound: where S_u x S_v vanishes along a
curve (a folded surface) |S_u x S_v| has a kink and the estimate can be low. For
polynomial patches the volume integrand is a polynomial, so nodes >= (3 (p + q) + 1) / 2
per direction makes it exact to rounding. A :class:`cagd.TrimmedSurface` counts over its
trimmed domain only (Green's theorem, :func:`cagd.surfaces.trimmed.trimmed_integral`,
AREA_TOL relative), its estimate added to the error.
"""
from __future__ import annotations

from typing import Iterable, NamedTuple, Tuple, Union

import numpy as np

from .._checks import integer
from ..errors import CagdError
from ..knots.vectors import distinct_with_multiplicities
from .base import Surface
from .trimmed import AREA_TOL, TrimmedSurface, trimmed_integral


class Integral(NamedTuple):
    """A quadrature result: the value and the estimated absolute error."""
    value: float
    error: float


def _gauss_nodes(breaks: np.ndarray, nodes: int) -> Tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(nodes)
    a, b = breaks[:-1, None], breaks[1:, None]
    return ((a + b) / 2 + (b - a) / 2 * x).ravel(), ((b - a) / 2 * w).ravel()


def _integrate(surface: Surface, nodes: int, kind: str, centre: np.ndarray) -> float:
    s = surface.to_nurbs()
    if s.dim != 3:
        raise CagdError(f"surface: area and volume need a 3-D surface, got {s.dim}-D")
    (u0, u1), (v0, v1) = s.domain
    ku = distinct_with_multiplicities(s.knots_u)[0]
    kv = distinct_with_multiplicities(s.knots_v)[0]
    ku = ku[(ku >= u0) & (ku <= u1)]
    kv = kv[(kv >= v0) & (kv <= v1)]
    us, wu = _gauss_nodes(ku, nodes)
    vs, wv = _gauss_nodes(kv, nodes)
    d = s._grid(us, vs, 1, 1)                  # all partials up to S_uv on the node grid
    n = np.cross(d[1, 0], d[0, 1])
    f = np.linalg.norm(n, axis=-1) if kind == "area" else np.einsum("...k,...k", d[0, 0] - centre, n) / 3.0
    return float(wu @ f @ wv)


def _integral(surfaces: Iterable[Surface], nodes: int, kind: str) -> Integral:
    nodes = integer(nodes, "nodes", 2, 64)
    surfaces = list(surfaces)
    if not surfaces or not all(isinstance(s, Surface) for s in surfaces):
        raise CagdError("surfaces: expected one or more cagd surfaces")
    # the volume element about the origin, as always (a set that is not quite closed,
    # e.g. a revolved surface with separate caps, depends on the centre)
    P = np.concatenate([s.to_nurbs().control_points.reshape(-1, s.dim) for s in surfaces])
    centre = np.zeros(P.shape[1])
    plain = [s for s in surfaces if not isinstance(s, TrimmedSurface)]
    value = sum(_integrate(s, nodes, kind, centre) for s in plain)
    finer = sum(_integrate(s, nodes + 8, kind, centre) for s in plain)
    error = abs(finer - value)
    for s in surfaces:
        if isinstance(s, TrimmedSurface):           # over its trimmed domain (Green's theorem)
            if s.dim != 3:
                raise CagdError(f"surface: area and volume need a 3-D surface, got {s.dim}-D")
            size = float(np.ptp(P, axis=0).max())
            r = trimmed_integral(s, AREA_TOL, None if kind == "area" else centre,
                                 0.0 if kind == "area" else AREA_TOL * size ** 3)
            finer += r.value
            error += r.error
    return Integral(finer, error)


def area(surfaces: Union[Surface, Iterable[Surface]], nodes: int = 16) -> Integral:
    """Surface area of one surface or the sum over several (see the module doc)."""
    return _integral([surfaces] if isinstance(surfaces, Surface) else surfaces, nodes, "area")


def enclosed_volume(surfaces: Union[Surface, Iterable[Surface]], nodes: int = 16) -> Integral:
    """Signed volume bounded by closed patches (positive for outward normals)."""
    return _integral([surfaces] if isinstance(surfaces, Surface) else surfaces, nodes, "volume")
