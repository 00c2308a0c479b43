"""Continuity of two faces along the boundary curve they share, where the faces are
trimmed (real parts meet along trimming curves, not along the sides of their
parameter boxes; :func:`cagd.edge_continuity` measures the box sides).

The shared curve is found among the faces' boundary curves (a TrimmedSurface's loop
curves, a plain surface's four box sides): the pair whose 3-D images lie closest.
Along the first face's curve, each sample's nearest point on the second surface is
found (:func:`cagd.closest_point`, certified), and there the gap (C0), the angle
between the tangent planes (G1, seed 003, 2.2.3 "a common tangent plane"; Farin,
Curves and Surfaces for CAGD, 16.5) and the normal curvatures across the curve (G2)
are measured. Two surfaces joined G1 along a curve are G2 there exactly when their
normal curvatures agree in one direction transversal to it (Pegna and Wolter, "Geometric
criteria to guarantee curvature continuity of blend surfaces", J. Mech. Des. 114, 1992:
the linkage curve theorem); the direction used is d = n1 x T, T the curve's tangent, and
kappa(d) = II(w, w) / I(w, w) with S_u w_u + S_v w_v = d (do Carmo, 3.2).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from .. import _checks
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..operations.continuity import CONTINUITY_TOL, curvature_scale, tolerances
from ._trim_box import box_loop
from .base import Surface

#: fractions of a boundary curve's domain at which the curves are matched (interior: not at the corners)
MATCH_FRACTIONS = np.linspace(0.1, 0.9, 9)
#: points per boundary curve of the second face for the matching
MATCH_POINTS = 65


@dataclass(frozen=True)
class TrimEdgeContinuityReport:
    """Measurements along the shared boundary curve of two faces.

    curve1, curve2: the shared curve's index among each face's boundary curves (loop
    curves in order, loop after loop; the box sides u=v0.., counter-clockwise from
    (u0, v0), for a plain surface); gap: max distance from the first face's curve
    samples to the second surface (C0); normal_angle: max angle in radians between
    the two tangent planes there (unoriented: 0 for a smooth joint, pi/2 for a right
    angle crease; G1); curvature_difference: max |kappa1 - kappa2| of the normal
    curvatures across the curve (the second normal turned to agree with the first);
    G2: G1 and that difference <= rel_tol max(|kappa1|, |kappa2|, 1 / size) at every
    sample; size: the length scale (the larger surface size); samples: the samples
    used (where the normal is defined on both); converged: every closest point
    certified; message: what limited the measure, if anything.

    Per station (the ``samples`` points along the first face's curve, in order; not
    compared by ==): points, (samples, 3), the stations on face 1; gaps, their distances
    to face 2; angles and curvature_differences, as above per station, NaN where a
    normal or the cross curvature is undefined. :meth:`worst` names the largest.
    """
    curve1: int
    curve2: int
    gap: float
    normal_angle: float
    C0: bool
    G1: bool
    curvature_difference: float
    G2: bool
    rel_tol: float
    angle_tol: float
    size: float
    samples: int
    converged: bool
    message: str
    points: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    gaps: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    angles: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    curvature_differences: Optional[np.ndarray] = field(default=None, compare=False, repr=False)

    @property
    def level(self) -> str:
        """The strongest property that holds: "G2" > "G1" > "C0" > "none"."""
        return "G2" if self.G2 else "G1" if self.G1 else "C0" if self.C0 else "none"

    def worst(self, measure: Optional[str] = None) -> Tuple[str, int, float, np.ndarray]:
        """(measure, station index, value, point) of the station where ``measure``
        ("gap", "angle" or "curvature", the per-station arrays) is largest (NaN stations
        skipped). ``measure`` None: the first that fails, gap unless C0, angle unless G1,
        else curvature (for a G2 joint the largest curvature difference). A measure
        undefined at every station gives index -1, value NaN, point NaN."""
        if measure is None:
            measure = "gap" if not self.C0 else "angle" if not self.G1 else "curvature"
        arrays = {"gap": self.gaps, "angle": self.angles, "curvature": self.curvature_differences}
        if measure not in arrays:
            raise CagdError(f"measure: must be one of {tuple(arrays)} or None, got {measure!r}")
        values = arrays[measure]
        if values is None or self.points is None or not np.isfinite(values).any():
            return measure, -1, float("nan"), np.full(3, np.nan)
        i = int(np.nanargmax(values))
        return measure, i, float(values[i]), self.points[i]

    def __str__(self) -> str:
        return (f"{self.level} along boundary curve {self.curve1} of face 1 = curve {self.curve2} of face 2: "
                f"gap {self.gap:.3g}, normal angle {self.normal_angle:.3g} rad, curvature difference "
                f"{self.curvature_difference:.3g} (rel_tol {self.rel_tol:g}, "
                f"size {self.size:.3g}, angle_tol {self.angle_tol:g} rad, {self.samples} samples)"
                + (f"; {self.message}" if self.message else ""))


def _boundary(s: Surface) -> Tuple[Surface, List[BSplineCurve]]:
    """(the surface the curves lie on, the face's boundary curves in its (u, v))."""
    from .trimmed import TrimmedSurface
    if isinstance(s, TrimmedSurface):
        return s.untrimmed, [c for loop in s.loops for c in loop]
    return s, box_loop(s.domain)


def _images(s: Surface, curves: List[BSplineCurve], fractions: np.ndarray) -> np.ndarray:
    """S(c(t)) at the fractions of each curve's domain: (curves, len(fractions), dim)."""
    out = []
    for c in curves:
        a, b = c.domain
        uv = np.asarray(c(a + fractions * (b - a)))
        out.append(s(uv[:, 0], uv[:, 1]))
    return np.array(out)


def trim_edge_continuity(s1: Surface, s2: Surface, samples: int = 33, rel_tol: float = CONTINUITY_TOL,
                         angle_tol: Optional[float] = None) -> TrimEdgeContinuityReport:
    """Continuity of faces ``s1`` and ``s2`` (TrimmedSurfaces or plain 3-D surfaces)
    along their shared boundary curve. The curve of s1 and the curve of s2 whose images
    are closest (max over MATCH_FRACTIONS of s1's curve of the distance to MATCH_POINTS
    points on s2's) is the shared one; along it, at ``samples`` equally spaced
    parameters, P = S1(c(t)) and its nearest point Q on s2's surface give

    * C0: max |P - Q| <= rel_tol size;
    * G1: C0 and max angle(n1(P), n2(Q)) <= angle_tol (radians, default rel_tol), the
      tangent planes' angle, at the samples where both normals are defined;
    * G2: G1 and the normal curvatures across the curve agree (the module docstring).

    Raises:
        CagdError: s1/s2 not rectangular 3-D Surfaces, samples < 2, rel_tol not
            positive, angle_tol negative.
    """
    for name, s in (("s1", s1), ("s2", s2)):
        if not isinstance(s, Surface) or not s.rectangular:
            raise CagdError(f"{name}: must be a rectangular cagd Surface (or TrimmedSurface), got {type(s).__name__}")
        if s.dim != 3:
            raise CagdError(f"{name}: continuity along a trim is measured for 3-D surfaces, this one is {s.dim}-D")
    samples = _checks.integer(samples, "samples", 2, _checks.MAX_SAMPLES)
    rel_tol, angle_tol = tolerances("trim_edge_continuity", rel_tol, angle_tol, None)
    from ..queries.closest import closest_point
    S1, curves1 = _boundary(s1)
    S2, curves2 = _boundary(s2)
    Q1 = _images(S1, curves1, MATCH_FRACTIONS)                           # (n1, 9, 3)
    R2 = _images(S2, curves2, np.linspace(0.0, 1.0, MATCH_POINTS))      # (n2, 65, 3)
    flat = R2.reshape(-1, 3)
    gaps = np.empty((len(curves1), len(curves2)))
    for i in range(len(curves1)):          # per curve of s1: (9, n2 * 65) distances, O(n2) memory
        d = np.linalg.norm(Q1[i][:, None, :] - flat[None, :, :], axis=-1)
        d = d.reshape(len(MATCH_FRACTIONS), len(curves2), -1)
        gaps[i] = d.min(axis=2).max(axis=0)
    i1, i2 = (int(k) for k in np.unravel_index(int(np.argmin(gaps)), gaps.shape))
    c = curves1[i1]
    a, b = c.domain
    uv1 = np.asarray(c(np.linspace(a, b, samples)))
    P = S1(uv1[:, 0], uv1[:, 1])
    r = closest_point(S2, P)
    uv2 = np.asarray(r.params).reshape(len(P), -1)
    size = max(float(S1.size), float(S2.size))
    gap = float(np.max(r.distances))
    n1, ok1 = S1.normals(uv1[:, 0], uv1[:, 1])
    n2, ok2 = S2.normals(uv2[:, 0], uv2[:, 1])
    ok = ok1 & ok2
    with np.errstate(invalid="ignore"):
        angles = np.where(ok, np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", n1, n2)), 0.0, 1.0)), np.nan)
    angle = float(np.nanmax(angles)) if ok.any() else float("nan")
    k1 = _cross_curvature(S1, uv1, c.derivative(np.linspace(a, b, samples), 1), n1, n1)
    k2 = _cross_curvature(S2, uv2, c.derivative(np.linspace(a, b, samples), 1), n1, n2, S1, uv1)
    both = ok & np.isfinite(k1) & np.isfinite(k2)
    differences = np.where(both, np.abs(k1 - k2), np.nan)
    diff = differences[both]
    curvature_difference = float(diff.max()) if both.any() else float("nan")
    G2_ok = both.any() and all(d <= rel_tol * curvature_scale(np.array([x]), np.array([y]), size)
                               for d, x, y in zip(diff, k1[both], k2[both]))
    converged = bool(r.converged and np.all(r.point_converged))
    notes = []
    if not converged:
        notes.append("some closest points on face 2 are not certified")
    if not ok.any():
        notes.append("no sample has a defined normal on both faces (no G1)")
    C0 = gap <= rel_tol * size
    G1 = bool(C0 and ok.any() and angle <= angle_tol)
    G2 = bool(G1 and G2_ok)
    return TrimEdgeContinuityReport(i1, i2, gap, angle, bool(C0), G1, curvature_difference, G2, float(rel_tol),
                                    float(angle_tol), size, int(np.count_nonzero(ok)), converged, "; ".join(notes),
                                    _frozen(P), _frozen(np.asarray(r.distances, dtype=float).reshape(-1)),
                                    _frozen(angles), _frozen(differences))


def _frozen(a: np.ndarray) -> np.ndarray:
    out = np.array(a, dtype=float)
    out.flags.writeable = False
    return out


def _cross_curvature(S: Surface, uv: np.ndarray, dc: np.ndarray, n1: np.ndarray, n: np.ndarray,
                     S_edge: Optional[Surface] = None, uv_edge: Optional[np.ndarray] = None) -> np.ndarray:
    """Normal curvature of S at uv in the direction d = n1 x T (T the shared curve's
    tangent S_edge_u c_u' + S_edge_v c_v', on S_edge at uv_edge, default S at uv), the
    sign taken with the normal n turned towards n1; NaN where T or S's tangent plane
    degenerates."""
    D = S.derivatives(uv[:, 0], uv[:, 1], 2, 2)
    Su, Sv = D[1, 0], D[0, 1]
    if S_edge is None or uv_edge is None:
        Eu, Ev = Su, Sv
    else:
        De = S_edge.derivatives(uv_edge[:, 0], uv_edge[:, 1], 1, 1)
        Eu, Ev = De[1, 0], De[0, 1]
    T = Eu * dc[:, :1] + Ev * dc[:, 1:2]
    d = np.cross(n1, T)
    with np.errstate(invalid="ignore", divide="ignore"):
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        sign = np.where(np.einsum("ij,ij->i", n, n1) < 0, -1.0, 1.0)
        E, F, G = (np.einsum("ij,ij->i", a, b) for a, b in ((Su, Su), (Su, Sv), (Sv, Sv)))
        det = E * G - F * F
        bu, bv = np.einsum("ij,ij->i", Su, d), np.einsum("ij,ij->i", Sv, d)
        wu, wv = (G * bu - F * bv) / det, (E * bv - F * bu) / det          # J w = d (least squares)
        L, M, N = (np.einsum("ij,ij->i", X, n) * sign for X in (D[2, 0], D[1, 1], D[0, 2]))
        k = (L * wu * wu + 2 * M * wu * wv + N * wv * wv) / (E * wu * wu + 2 * F * wu * wv + G * wv * wv)
    return np.where(np.isfinite(k), k, np.nan)
