"""OCCT as the oracle of cagd.sweep: BRepOffsetAPI_MakePipeShell sweeps the same profile
along the same path, with the trihedron of the same kind, and the two surfaces are compared
both ways (our points' distances to OCCT's face by BRepExtrema_DistShapeShape, OCCT's points'
distances to our surface by GeomAPI_ProjectPointOnSurf). The frames agree where the kinds do:
a circle profile centred on the path gives the same pipe for every frame (rmf here against
OCCT's corrected Frenet, and Frenet against Frenet); a planar path's rotation-minimising frame
is OCCT's corrected Frenet and its fixed-binormal (plane normal) mode; "fixed" is OCCT's fixed
trihedron. Bound: our reported max_error plus OCCT's ErrorOnSurface (plus 1e-9 for the
projections). Seen (ours / OCCT's ErrorOnSurface / largest distance both ways): circle on the
helix rmf 1.7e-7 / 3.6e-9 / 2.8e-8, Frenet 1.4e-7 / 8.9e-10 / 2.7e-8; line on the planar
curve 1.75e-7 / 9.8e-9 (corrected Frenet), 8.7e-9 (binormal) / 7.8e-8; line on the helix,
fixed 1.8e-15 / 9.7e-15 / 5.9e-15; the torus (ours exact) 3.1e-15 / 2.8e-9 / 1.0e-9."""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex  # noqa: E402
from OCP.BRepExtrema import BRepExtrema_DistShapeShape  # noqa: E402
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakePipeShell  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf  # noqa: E402
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt  # noqa: E402
from OCP.TopAbs import TopAbs_FACE  # noqa: E402

from cagd import BSplineCurve, sweep  # noqa: E402
from cagd.occ import make_wire, subshapes, to_occ  # noqa: E402
sys.path.insert(0, str(Path(__file__).parent))
from test_sweep import R_MAJOR, R_MINOR, XZ, circle, helix_path  # noqa: E402

#: OCCT's approximation tolerances (3-D, boundary, angular), degree and segment caps: tight,
#: so that OCCT's own error (ErrorOnSurface) is below ours
OCCT_TOL = (1e-8, 1e-8, 1e-6)
OCCT_MAX_DEGREE, OCCT_MAX_SEGMENTS = 11, 200
SWEEP_TOL = 2e-7
PROJECTION_SLACK = 1e-9
SAMPLES = 80

HELIX = helix_path(41)
X0 = HELIX(HELIX.domain[0])


def normal_circle(radius, x, T):
    """A circle of ``radius`` about x in the plane normal to the unit T."""
    z = np.array([0.0, 0.0, 1.0])
    k = np.cross(z, T)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return circle(radius).transformed(np.eye(3) + K + K @ K / (1.0 + z @ T), x)


T0 = HELIX.derivative(HELIX.domain[0])
T0 = T0 / np.linalg.norm(T0)
PLANAR = BSplineCurve([[0, 0, 0], [2, 1, 0], [4, -1, 0], [6, 0.5, 0], [8, 0, 0]], 3)   # with an inflection
CASES = {
    "circle along a helix, rmf / corrected Frenet": (normal_circle(0.3, X0, T0), HELIX, "rmf", "corrected"),
    "circle along a helix, Frenet / Frenet": (normal_circle(0.3, X0, T0), HELIX, "frenet", "frenet"),
    "line along a planar curve, rmf / corrected Frenet": (BSplineCurve([[0, 0, 0], [-0.3, 0.6, 0.4]], 1), PLANAR,
                                                          "rmf", "corrected"),
    "line along a planar curve, rmf / fixed binormal": (BSplineCurve([[0, 0, 0], [-0.3, 0.6, 0.4]], 1), PLANAR,
                                                        "rmf", "binormal"),
    "line along a helix, fixed / fixed trihedron": (BSplineCurve(X0 + np.array([[0, 0, 0], [0.3, 0.2, 0.4]]), 1),
                                                   HELIX, "fixed", "fixed"),
    "circle around a circle (torus), rmf / corrected Frenet": (circle(R_MINOR).transformed(XZ, [R_MAJOR, 0, 0]),
                                                              circle(R_MAJOR), "rmf", "corrected"),
}


def pipe_shell(profile, path, mode):
    mk = BRepOffsetAPI_MakePipeShell(make_wire([path]))
    if mode == "frenet":
        mk.SetMode(True)
    elif mode == "corrected":
        mk.SetMode(False)
    elif mode == "binormal":
        mk.SetMode(gp_Dir(0.0, 0.0, 1.0))
    else:
        mk.SetMode(gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0), gp_Dir(1.0, 0.0, 0.0)))
    mk.SetTolerance(*OCCT_TOL)
    mk.SetMaxDegree(OCCT_MAX_DEGREE)
    mk.SetMaxSegments(OCCT_MAX_SEGMENTS)
    mk.Add(make_wire([profile]), False, False)
    mk.Build()
    assert mk.IsDone()
    return mk


def distances_to_shape(shape, X):
    out = np.empty(len(X))
    for i, x in enumerate(X):
        v = BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, x))).Vertex()
        d = BRepExtrema_DistShapeShape(v, shape)
        assert d.IsDone()
        out[i] = d.Value()
    return out


def occt_points(face, rng, count):
    surface = BRep_Tool.Surface_s(face)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    return np.array([[p.X(), p.Y(), p.Z()] for p in (surface.Value(float(u), float(v)) for u, v in
                     zip(rng.uniform(u0, u1, count), rng.uniform(v0, v1, count)))])


def distances_to_surface(surface, X):
    geom = to_occ(surface)
    out = np.empty(len(X))
    for i, x in enumerate(X):
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, x)), geom)
        out[i] = proj.LowerDistance() if proj.NbPoints() > 0 else math.inf
    return out


@pytest.mark.parametrize("name", sorted(CASES))
def test_sweep_matches_occt_pipe_shell(name):
    profile, path, ours, theirs = CASES[name]
    r = sweep(profile, path, frame=ours, tol=SWEEP_TOL)
    assert r.converged, r.message
    mk = pipe_shell(profile, path, theirs)
    occt_error = mk.ErrorOnSurface()
    assert occt_error <= SWEEP_TOL                         # OCCT's own achieved tolerance, reported
    bound = r.max_error + occt_error + PROJECTION_SLACK
    rng = np.random.default_rng(5)
    (u0, u1), (v0, v1) = r.surface.domain
    ours_on_theirs = distances_to_shape(mk.Shape(), r.surface(rng.uniform(u0, u1, SAMPLES),
                                                                 rng.uniform(v0, v1, SAMPLES)))
    faces = subshapes(mk.Shape(), TopAbs_FACE)
    theirs_on_ours = np.concatenate([distances_to_surface(r.surface, occt_points(f, rng, SAMPLES // len(faces)))
                                     for f in faces])
    worst = max(ours_on_theirs.max(), theirs_on_ours.max())
    assert worst <= bound, (name, worst, r.max_error, occt_error)
