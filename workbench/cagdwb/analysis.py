"""Analysis on FreeCAD shapes through the engine: continuity of two edges or two
faces (cagd.continuity, cagd.edge_continuity) and the curvature comb of an edge.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

import FreeCAD as App

from . import conversion
from .conversion import cagd


@dataclass
class JointCheck:
    """A continuity report with the joint it was measured at, as readable text;
    ``profile`` (two faces): the engine's per-station measurements along the shared
    boundary (a cagd.TrimEdgeContinuityReport: gaps, angles, curvature differences)."""
    report: object
    where: str
    profile: Optional[object] = None

    @property
    def level(self) -> str:
        return self.report.level

    def flags(self) -> dict:
        names = ("C0", "C1", "C2", "G1", "G2") if hasattr(self.report, "G2") else ("C0", "G1", "C1")
        return {n: bool(getattr(self.report, n)) for n in names if hasattr(self.report, n)}

    def text(self) -> str:
        flags = "  ".join(f"{k} {'yes' if v else 'no'}" for k, v in self.flags().items())
        stations = f"\n{station_text(self.profile)}" if self.profile is not None else ""
        return f"{self.where}\n{flags}\n{self.report}{stations}"

    def worst(self) -> Optional[Tuple[str, int, float, np.ndarray]]:
        """The profile's worst station (TrimEdgeContinuityReport.worst: of the first
        failing measure), None for two edges."""
        return None if self.profile is None else self.profile.worst()


UNITS = {"gap": "mm", "angle": "rad", "curvature": "1/mm"}


def station_text(profile) -> str:
    """Per-station read-out: for each measure its maximum over the stations and where."""
    lines = [f"along the shared boundary, {len(profile.points)} stations:"]
    for measure in ("gap", "angle", "curvature"):
        _, i, value, point = profile.worst(measure)
        where = "undefined" if i < 0 else \
            f"{value:.6g} {UNITS[measure]} at station {i} {tuple(round(float(x), 6) for x in point)}"
        lines.append(f"  max {measure}: {where}")
    measure, i, value, _ = profile.worst()
    lines.append(f"  worst station (first failing measure, {measure}): {i}")
    return "\n".join(lines)


def _ends(curve) -> Tuple[np.ndarray, np.ndarray]:
    a, b = curve.domain
    return curve(a), curve(b)


def edges_continuity(edge1, edge2, rel_tol: float = 1e-9) -> JointCheck:
    """Continuity where two edges meet: the pair of end points closest to each other
    is the joint; the curves are reversed so that the joint is the end of the first
    and the start of the second, then measured by cagd.continuity (derivatives in each
    curve's own parameter; ``rel_tol`` relative to the edges' size)."""
    c1, c2 = conversion.edge_to_curve(edge1), conversion.edge_to_curve(edge2)
    e1, e2 = _ends(c1), _ends(c2)
    i, j = min(((i, j) for i in range(2) for j in range(2)),
               key=lambda ij: float(np.linalg.norm(e1[ij[0]] - e2[ij[1]])))
    if i == 0:
        c1 = c1.reversed()
    if j == 1:
        c2 = c2.reversed()
    report = cagd.continuity(c1, c2, rel_tol=rel_tol)
    where = (f"joint: {'start' if i == 0 else 'end'} of edge 1 -> {'start' if j == 0 else 'end'} of edge 2 "
             f"at {tuple(round(float(x), 6) for x in e1[i])}")
    return JointCheck(report, where)


def faces_continuity(face1, face2, rel_tol: float = 1e-9, samples: int = 33) -> JointCheck:
    """Continuity across the common boundary of two faces. Where either face is
    trimmed (:func:`conversion.face_to_trimmed`), along the boundary curves they share
    (cagd.trim_edge_continuity: gap, tangent-plane angle, cross-curvature); else across the pair of
    box sides ('u0', 'u1', 'v0', 'v1') with the smallest gap, by cagd.edge_continuity. Either way
    the profile is trim_edge_continuity's per-station read-out along the shared boundary (its
    ``samples`` stations: gap, angle, curvature difference at each)."""
    t1, t2 = conversion.face_to_trimmed(face1)[0], conversion.face_to_trimmed(face2)[0]
    if isinstance(t1, cagd.TrimmedSurface) or isinstance(t2, cagd.TrimmedSurface):
        r = cagd.trim_edge_continuity(t1, t2, samples=samples, rel_tol=rel_tol)
        return JointCheck(r, f"shared boundary: curve {r.curve1} of face 1 = curve {r.curve2} of face 2", r)
    s1, s2 = t1, t2                     # face_to_surface's surfaces (the boundary is the box)
    best = None
    for e1 in ("u0", "u1", "v0", "v1"):
        for e2 in ("u0", "u1", "v0", "v1"):
            r = cagd.edge_continuity(s1, s2, e1, e2, samples=9, rel_tol=rel_tol)
            if best is None or r.gap < best[0]:
                best = (r.gap, e1, e2)
    _, e1, e2 = best
    report = cagd.edge_continuity(s1, s2, e1, e2, samples=samples, rel_tol=rel_tol)
    profile = cagd.trim_edge_continuity(s1, s2, samples=samples, rel_tol=rel_tol)
    return JointCheck(report, f"shared boundary: {e1} of face 1 = {e2} of face 2", profile)


def check_shapes(shape1, shape2, rel_tol: float = 1e-9) -> JointCheck:
    """Two edges or two faces (e.g. the selected sub-elements)."""
    kinds = (shape1.ShapeType, shape2.ShapeType)
    if kinds == ("Edge", "Edge"):
        return edges_continuity(shape1, shape2, rel_tol)
    if kinds == ("Face", "Face"):
        return faces_continuity(shape1, shape2, rel_tol)
    raise cagd.CagdError(f"selection: need two edges or two faces, got {kinds[0]} and {kinds[1]}")


SHARED_EDGE_FRACTION = 1e-3   # two edges are one shared boundary: samples within this fraction of the length
SHARED_EDGE_SAMPLES = 9       # samples of the first edge tested against the second


def _coincident(edge1, edge2) -> bool:
    """Every one of SHARED_EDGE_SAMPLES points along edge1 (ends included) lies within
    SHARED_EDGE_FRACTION of its length from edge2, and the lengths agree as closely."""
    import Part
    size = max(edge1.Length, edge2.Length)
    if abs(edge1.Length - edge2.Length) > SHARED_EDGE_FRACTION * size:
        return False
    params = np.linspace(edge1.FirstParameter, edge1.LastParameter, SHARED_EDGE_SAMPLES)
    return all(Part.Vertex(edge1.valueAt(float(t))).distToShape(edge2)[0] <= SHARED_EDGE_FRACTION * size
               for t in params)


def shared_edge_faces(link1, link2):
    """The two faces meeting along two selected edges ``(obj, 'EdgeN')`` that are one
    shared boundary (:func:`_coincident`, e.g. the common edge picked on each of two
    face objects): the faces of each object's shape bounding its edge, a different face
    on each side. None when the edges are not one edge, or no such pair exists."""
    import Part
    (o1, s1), (o2, s2) = link1, link2
    e1, e2 = o1.Shape.getElement(s1), o2.Shape.getElement(s2)
    if e1.ShapeType != "Edge" or e2.ShapeType != "Edge" or not _coincident(e1, e2):
        return None
    faces1, faces2 = o1.Shape.ancestorsOfType(e1, Part.Face), o2.Shape.ancestorsOfType(e2, Part.Face)
    pairs = [(f1, f2) for f1 in faces1 for f2 in faces2 if not f1.isSame(f2)]
    return pairs[0] if pairs else None


def check_selection(link1, link2, rel_tol: float = 1e-9) -> JointCheck:
    """Two selected sub-elements ``(obj, 'EdgeN' / 'FaceN')``: two edges that are one
    shared boundary of two faces are checked as those faces along it
    (:func:`shared_edge_faces`, :func:`faces_continuity`: every station); otherwise
    :func:`check_shapes` (two edges: at the joint of their nearest ends)."""
    faces = shared_edge_faces(link1, link2)
    if faces is not None:
        r = faces_continuity(*faces, rel_tol=rel_tol)
        return JointCheck(r.report, f"the faces of the selected edges, {r.where}", r.profile)
    return check_shapes(link1[0].Shape.getElement(link1[1]), link2[0].Shape.getElement(link2[1]), rel_tol)


COMB_FRACTION = 0.2        # automatic comb scale: the longest tooth this fraction of the size
ISO_COMBS = 5              # iso-curves per direction carrying a comb on a surface


def _comb(edge, samples: int):
    """The engine's curvature comb of the edge's curve (cagd.analysis.curvature_comb:
    per knot span, at least 8 teeth on each, both limits at a knot), at least
    ``samples`` teeth, scale 1."""
    return cagd.analysis.curvature_comb(conversion.edge_to_curve(edge), samples=samples, scale=1.0)


def _teeth(comb) -> List[Tuple[App.Vector, App.Vector]]:
    return [(App.Vector(*map(float, a)), App.Vector(*map(float, b))) for a, b in zip(comb.base, comb.tips)]


def curvature_comb(edge, samples: int = 64, scale: float = 1.0) -> List[Tuple[App.Vector, App.Vector]]:
    """Teeth (foot, tip) of the curvature comb: tip = C(t) - scale * kappa(t) N(t)
    with kappa N the curvature vector (Farin 10.1), so the teeth point away from the
    centre of curvature; at least ``samples`` teeth, placed per knot span."""
    return _teeth(_comb(edge, samples).scaled(scale))


def _auto_scale(longest: float, size: float, fraction: float) -> float:
    return fraction * size / longest if longest > 0.0 else 1.0


def auto_comb_scale(edge, samples: int = 64, fraction: float = COMB_FRACTION) -> float:
    """A comb scale making the longest tooth ``fraction`` of the edge length."""
    return _auto_scale(float(_comb(edge, samples).curvature.max()), edge.Length, fraction)


def comb_arrays(edge, samples: int = 64, scale: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
    """(feet, tips), (n, 3) arrays, of the edge's comb; ``scale`` 0: automatic (longest
    tooth COMB_FRACTION of the edge length). One engine comb serves the scale and the
    teeth. The view provider draws these without making a vector per point."""
    comb = _comb(edge, samples)
    scale = scale or _auto_scale(float(comb.curvature.max()), edge.Length, COMB_FRACTION)
    scaled = comb.scaled(scale)
    return np.asarray(scaled.base, dtype=float), np.asarray(scaled.tips, dtype=float)


def comb_polylines(edge, samples: int = 64, scale: float = 0.0) -> List[List[App.Vector]]:
    """The comb of an edge as polylines (comb_arrays): each tooth, then the envelope
    through the tips."""
    feet, tips = (conversion.vectors(a) for a in comb_arrays(edge, samples, scale))
    return [[a, b] for a, b in zip(feet, tips)] + [tips]


def surface_combs(face, count: int = ISO_COMBS, samples: int = 64, scale: float = 0.0) -> List[List[App.Vector]]:
    """Curvature combs of ``count`` iso-curves in each direction of the face's surface
    (u = const and v = const, evenly over the parameter box, the boundaries included):
    the engine's comb of each iso-curve (Surface.isocurve, curvature_comb), one scale for
    all (``scale`` 0: the longest tooth COMB_FRACTION of the surface's size)."""
    surface = conversion.face_to_surface(face)
    (u0, u1), (v0, v1) = surface.domain
    isos = [surface.isocurve("u", float(v)) for v in np.linspace(v0, v1, count)] + \
           [surface.isocurve("v", float(u)) for u in np.linspace(u0, u1, count)]
    combs = [cagd.analysis.curvature_comb(c, samples=samples, scale=1.0) for c in isos]
    longest = max(float(c.curvature.max()) for c in combs)
    scale = scale or _auto_scale(longest, float(surface.size), COMB_FRACTION)
    lines: List[List[App.Vector]] = []
    for comb in combs:
        teeth = _teeth(comb.scaled(scale))
        lines += [[a, b] for a, b in teeth] + [[b for _, b in teeth]]
    return lines


def fairness_readout(edge) -> Tuple[object, str]:
    """(cagd.analysis.fairness of the edge's curve, its read-out as text): arc length,
    curvature range, curvature-variation energy, inflections, largest curvature jump at
    a knot and where (Farin 23.1-23.2, via the engine)."""
    fair = cagd.analysis.fairness(conversion.edge_to_curve(edge))
    k = np.asarray(fair.curvature)
    where = "" if not np.isfinite(fair.jump_parameter) else f" at t = {float(fair.jump_parameter):.6g}"
    text = (f"length {float(fair.length):.6g} mm, curvature {float(k.min()):.6g}..{float(k.max()):.6g} 1/mm\n"
            f"energy (integral of (dk/ds)^2 ds) {float(fair.energy):.6g}, inflections {int(fair.inflections)}, "
            f"largest curvature jump at a knot {float(fair.max_knot_jump):.6g} 1/mm{where}")
    return fair, text
