"""Measured continuity across the shared edge of two surface patches (seed 003,
2.2.3 "C0/C1 between patches"; Farin, Curves and Surfaces for CAGD, 16.5).

For Bezier patches of equal degree the seed states the conditions on the control
nets: C0, the boundary control points agree; C1, also the difference vectors
across the boundary, P_1j - P_0j of the second patch = P_mj - P_(m-1)j of the
first. G1 only asks for a common tangent plane, e.g. the second difference vector
alpha times the first, alpha > 0. Here the same properties are measured on the
surfaces themselves at ``samples`` points along the edge, so any two
:class:`cagd.Surface` objects can be compared.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .. import _checks
from .._deprecation import deprecated
from ..operations.continuity import CONTINUITY_TOL, tolerances
from ..errors import CagdError
from .base import Surface

EDGES = ("u0", "u1", "v0", "v1")


@dataclass(frozen=True)
class EdgeContinuityReport:
    """Measurements along the shared edge and the continuity they satisfy.

    gap: max |S2 - S1| at corresponding edge points (C0);
    normal_angle: max angle in radians between the tangent planes, oriented so that
    a smooth continuation is 0 and a fold back onto the first patch is pi (G1);
    cross_derivative_mismatch: max |D2 - D1| of the cross-boundary derivatives, D1
    leaving the first patch and D2 entering the second, each in its patch's own
    parameter (C1); reversed: whether the second edge runs against the first;
    rel_tol: the relative tolerance used; size: the length scale (bounding-box diagonal
    of both patches' samples); derivative_scale: max(|D1|, |D2|, size / span) that
    makes the C1 test relative; angle_tol: the G1 angle bound (radians). ``tol`` is the
    deprecated name of ``rel_tol`` (one release).
    """
    edge1: str
    edge2: str
    reversed: bool
    gap: float
    normal_angle: float
    cross_derivative_mismatch: float
    C0: bool
    G1: bool
    C1: bool
    rel_tol: float
    size: float
    derivative_scale: float
    samples: int
    angle_tol: float = CONTINUITY_TOL

    @property
    def tol(self) -> float:
        """Deprecated name of :attr:`rel_tol`."""
        deprecated("EdgeContinuityReport.tol", "use rel_tol (the same relative tolerance)")
        return self.rel_tol

    @property
    def level(self) -> str:
        """The strongest property that holds: "C1" > "G1" > "C0" > "none"."""
        for name in ("C1", "G1", "C0"):
            if getattr(self, name):
                return name
        return "none"

    def __str__(self) -> str:
        direction = "opposite" if self.reversed else "same"
        return (f"{self.level} across {self.edge1}/{self.edge2} ({direction} direction): gap {self.gap:.3g}, "
                f"normal angle {self.normal_angle:.3g} rad, cross-derivative mismatch "
                f"{self.cross_derivative_mismatch:.3g} (rel_tol {self.rel_tol:g}, size {self.size:.3g}, "
                f"angle_tol {self.angle_tol:g} rad, {self.samples} samples)")


def _edge_frame(s: Surface, edge: str, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, along-edge derivatives and inward cross-boundary derivatives of ``s`` at
    the edge parameters t in [0, 1] (mapped onto the edge's domain)."""
    (u0, u1), (v0, v1) = s.domain
    if edge[0] == "u":
        u = np.full_like(t, u0 if edge == "u0" else u1)
        v = v0 + t * (v1 - v0)
        d = s.derivatives(u, v, 1, 1)
        along, cross = d[0, 1], d[1, 0]
    else:
        u = u0 + t * (u1 - u0)
        v = np.full_like(t, v0 if edge == "v0" else v1)
        d = s.derivatives(u, v, 1, 1)
        along, cross = d[1, 0], d[0, 1]
    inward = cross if edge.endswith("0") else -cross
    return d[0, 0], along, inward


def _lift(x: np.ndarray) -> np.ndarray:
    """2-D vectors as 3-D ones (z = 0) for cross products."""
    if x.shape[-1] == 3:
        return x
    return np.concatenate([x, np.zeros(x.shape[:-1] + (1,))], axis=-1)


def _plane_angles(T: np.ndarray, D1: np.ndarray, D2: np.ndarray, t_floor: float) -> np.ndarray:
    """Angles between the oriented planes T x D1 and T x D2, 2 atan2(|a^ - b^|, |a^ + b^|),
    at the samples where both are well defined: |T| > t_floor and
    |T x D| > 1e-10 |T| max|D| (a vanishing or rounding-noise T, at a collapsed edge,
    a cross derivative collapsing at a corner, or D along the edge, says nothing
    about the tangent plane; max|D| over the edge keeps rounding noise out there)."""
    T, D1, D2 = _lift(T), _lift(D1), _lift(D2)
    a, b = np.cross(T, D1), np.cross(T, D2)
    nt = np.linalg.norm(T, axis=-1)
    na, nb = np.linalg.norm(a, axis=-1), np.linalg.norm(b, axis=-1)
    ok = (nt > t_floor) & (na > 1e-10 * nt * np.linalg.norm(D1, axis=-1).max(initial=0.0)) \
        & (nb > 1e-10 * nt * np.linalg.norm(D2, axis=-1).max(initial=0.0))
    ua, ub = a[ok] / na[ok, None], b[ok] / nb[ok, None]
    return 2.0 * np.arctan2(np.linalg.norm(ua - ub, axis=-1), np.linalg.norm(ua + ub, axis=-1))


def edge_continuity(s1: Surface, s2: Surface, edge1: str, edge2: str, samples: int = 33,
                    rel_tol: float = CONTINUITY_TOL, reverse: Optional[bool] = None, *,
                    angle_tol: Optional[float] = None, tol: Optional[float] = None) -> EdgeContinuityReport:
    """Continuity of two patches across the edge ``edge1`` of s1 = ``edge2`` of s2.

    Edges: "u0" (u = u_min, running in v), "u1" (u = u_max), "v0" (v = v_min,
    running in u), "v1" (v = v_max). Both edges are sampled at ``samples`` equally
    spaced fractions t of their domains; the second at t (``reverse`` False) or at
    1 - t (True). With ``reverse`` None the same direction is kept if it is C0
    (gap <= rel_tol size), otherwise the direction with the smaller gap is taken.
    Points are compared at corresponding fractions, so an edge curve that is
    reparametrised non-affinely between the patches shows as a gap.

    With D1 the cross-boundary derivative leaving s1 (-S_u at "u0", +S_u at "u1",
    likewise in v) and D2 the one entering s2 (+S_u at "u0", -S_u at "u1"), T the
    along-edge derivative of s1, size the bounding-box diagonal of both patches'
    samples and L the longer cross-parameter span:

    * C0: max |S2 - S1| <= rel_tol size;
    * G1: C0 and max angle(T x D1, T x D2) <= angle_tol (radians, default rel_tol),
      the angle between the tangent planes oriented across the edge (samples where T
      or T x D vanishes up to rounding, e.g. on an edge collapsed to a point, are
      skipped; none left gives nan and no G1);
    * C1: C0 and max |D2 - D1| <= rel_tol max(|D1|, |D2|, size / L): the seed's
      "difference vectors match" (seed 003, 2.2.3), e.g. for Bezier patches of
      equal degree m, P_1j - P_0j of the second = P_mj - P_(m-1)j of the first.

    ``tol`` is the deprecated name of ``rel_tol`` (one release; ``tol`` is a distance
    in cagd).

    Raises:
        CagdError: s1/s2 not rectangular Surfaces (triangles: see triangle_continuity),
            different dimensions, a surface that is not 2-D or 3-D, an unknown edge name,
            samples < 2, rel_tol not positive, angle_tol negative, reverse not True/False/None.
    """
    for name, s in (("s1", s1), ("s2", s2)):
        if not isinstance(s, Surface):
            raise CagdError(f"{name}: must be a cagd Surface, got {type(s).__name__}")
        if not s.rectangular:
            raise CagdError(f"{name}: a {type(s).__name__} has no rectangular edges u0/u1/v0/v1; "
                            f"use cagd.triangle_continuity for triangles")
    if s1.dim != s2.dim:
        raise CagdError(f"s2: dimension {s2.dim} differs from s1's {s1.dim}")
    for name, e in (("edge1", edge1), ("edge2", edge2)):
        if e not in EDGES:
            raise CagdError(f"{name}: must be one of {EDGES}, got {e!r}")
    samples = _checks.integer(samples, "samples", 2)
    rel_tol, angle_tol = tolerances("edge_continuity", rel_tol, angle_tol, tol)
    if reverse is not None and not isinstance(reverse, (bool, np.bool_)):
        raise CagdError(f"reverse: must be True, False or None, got {reverse!r}")
    if s1.dim not in (2, 3):
        raise CagdError(f"s1: edge continuity is measured for 2-D and 3-D surfaces, this one is {s1.dim}-D")

    t = np.linspace(0.0, 1.0, samples)
    p1, along, inward1 = _edge_frame(s1, edge1, t)
    forward = _edge_frame(s2, edge2, t)
    backward = _edge_frame(s2, edge2, t[::-1].copy())
    pts = np.concatenate([s1.grid(*_sample_grid(s1)).reshape(-1, s1.dim),
                          s2.grid(*_sample_grid(s2)).reshape(-1, s2.dim)])
    size = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    size = size if size > 0.0 else 1.0
    if reverse is None:
        gap_f = np.linalg.norm(forward[0] - p1, axis=-1).max()
        gap_b = np.linalg.norm(backward[0] - p1, axis=-1).max()
        reverse = bool(gap_f > rel_tol * size and gap_b < gap_f)
    p2, _, inward2 = backward if reverse else forward
    leaving1 = -inward1
    span = max(_cross_span(s1, edge1), _cross_span(s2, edge2))

    gap = float(np.linalg.norm(p2 - p1, axis=-1).max())
    mismatch = float(np.linalg.norm(inward2 - leaving1, axis=-1).max())
    dscale = max(float(np.linalg.norm(leaving1, axis=-1).max()), float(np.linalg.norm(inward2, axis=-1).max()),
                 size / span)
    along_span = _along_span(s1, edge1)
    angles = _plane_angles(along, leaving1, inward2, 1e-10 * size / along_span)
    angle = float(angles.max()) if angles.size else float("nan")

    C0 = gap <= rel_tol * size
    G1 = bool(C0 and angles.size > 0 and angle <= angle_tol)
    C1 = bool(C0 and mismatch <= rel_tol * dscale)
    return EdgeContinuityReport(edge1, edge2, bool(reverse), gap, angle, mismatch, bool(C0), G1, C1,
                                float(rel_tol), size, dscale, samples, float(angle_tol))


def _cross_span(s: Surface, edge: str) -> float:
    (u0, u1), (v0, v1) = s.domain
    return (u1 - u0) if edge[0] == "u" else (v1 - v0)


def _along_span(s: Surface, edge: str) -> float:
    (u0, u1), (v0, v1) = s.domain
    return (v1 - v0) if edge[0] == "u" else (u1 - u0)


def _sample_grid(s: Surface, count: int = 9) -> Tuple[np.ndarray, np.ndarray]:
    (u0, u1), (v0, v1) = s.domain
    return np.linspace(u0, u1, count), np.linspace(v0, v1, count)
