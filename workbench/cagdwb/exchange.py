"""STEP and IGES export / re-import through FreeCAD's own exchange modules, and the
comparison of a shape's geometry with engine samples."""
from __future__ import annotations

import os
from typing import Sequence

import numpy as np

import FreeCAD as App
import Part

from .conversion import cagd


def export(objects: Sequence, path: str) -> str:
    """Write the objects' shapes to ``path`` (.step/.stp through Import.export,
    .iges/.igs through Part.export) and return the path."""
    ext = os.path.splitext(path)[1].lower()
    if ext in (".step", ".stp"):
        import Import
        Import.export(list(objects), path)
    elif ext in (".iges", ".igs"):
        Part.export(list(objects), path)
    else:
        raise ValueError(f"path: expected a .step/.stp or .iges/.igs file, got {path!r}")
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        raise RuntimeError(f"export: nothing written to {path}")
    return path


def reimport(path: str) -> "Part.Shape":
    """The shape read back from a STEP or IGES file."""
    shape = Part.Shape()
    shape.read(path)
    return shape


def relative_deviation(reference: np.ndarray, values: np.ndarray) -> float:
    """max |values - reference| / max(1, bounding-box diagonal of reference)."""
    ref = np.asarray(reference, dtype=float).reshape(-1, 3)
    size = float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0)))
    return float(np.abs(np.asarray(values, dtype=float).reshape(-1, 3) - ref).max() / max(1.0, size))


def curve_samples(curve: "cagd.Curve", count: int = 41):
    t = np.linspace(*curve.domain, count)
    return t, np.atleast_2d(curve(t))


def compare_edge(curve: "cagd.Curve", edge, count: int = 41) -> float:
    """Relative deviation of edge.valueAt(t) from the engine's C(t), at the same t
    (the edge's parameter range must be the engine domain)."""
    t, ref = curve_samples(curve, count)
    got = np.array([tuple(edge.valueAt(float(x))) for x in t])
    return relative_deviation(ref, got)


def surface_params(surface: "cagd.Surface", count: int = 9):
    (u0, u1), (v0, v1) = surface.domain
    us, vs = np.linspace(u0, u1, count), np.linspace(v0, v1, count)
    U, W = np.meshgrid(us, vs, indexing="ij")
    if not getattr(surface, "rectangular", True):          # triangle: u + v <= 1
        keep = U + W <= 1.0 + 1e-12
        return U[keep], W[keep]
    return U.ravel(), W.ravel()


def face_parameters(surface: "cagd.Surface", face, U: np.ndarray, W: np.ndarray):
    """(the face's surface parameters matching the engine's (U, W), the sign taking
    its surface normal to the face's): the same parameters and +1 on a B-spline or
    Bezier face (the engine's own parametrisation); on an analytic face (Part.Sphere,
    ..., Part.SurfaceOfRevolution) the projections of the engine's points
    (Surface.parameter) and the face's orientation: the analytic parametrisation is
    the angle (:meth:`cagd.RevolvedSurface.analytic_parameters` for the workbench's
    own faces; a STEP or IGES round trip may turn it round), so the comparison is of
    point sets and face normals there."""
    if isinstance(face.Surface, (Part.BSplineSurface, Part.BezierSurface)):
        return U, W, 1.0
    geom = face.Surface
    found = np.array([geom.parameter(App.Vector(*map(float, p))) for p in np.atleast_2d(surface(U, W))])
    return found[:, 0], found[:, 1], -1.0 if face.Orientation == "Reversed" else 1.0


def compare_face(surface: "cagd.Surface", face, count: int = 9) -> dict:
    """Relative deviation of the face's surface points (and unit normals away from
    degenerate points) from the engine's S(u, v), n(u, v) at the matching parameters
    (:func:`face_parameters`); a Bezier triangle is compared through its NURBS
    (collapsed-edge) form, every other surface directly (so the engine's own
    evaluation, e.g. of a Coons patch, is the reference)."""
    nurbs = surface.to_nurbs()
    src = surface if getattr(surface, "rectangular", True) else nurbs
    U, W = surface_params(nurbs, count)
    ref = np.atleast_2d(src(U, W))
    geom = face.Surface
    FU, FW, sign = face_parameters(surface, face, U, W)
    got = np.array([tuple(geom.value(float(u), float(v))) for u, v in zip(FU, FW)])
    out = {"points": relative_deviation(ref, got)}
    normal_dev = 0.0
    normals, defined = src.normals(U, W)                  # away from degenerate points
    for u, v, n, ok in zip(FU, FW, normals, defined):
        if ok:
            m = sign * np.array(tuple(geom.normal(float(u), float(v))))
            normal_dev = max(normal_dev, float(np.abs(m - n).max()))
    out["normals"] = normal_dev
    return out
