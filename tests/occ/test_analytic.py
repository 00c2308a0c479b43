"""OCCT's analytic surfaces for the engine's surfaces of revolution (cagd.occ.analytic,
make_face, to_occ(analytic=True)): the same point set as the engine surface both ways
(engine samples projected onto the OCCT surface by GeomAPI_ProjectPointOnSurf, OCCT
samples onto the engine surface by cagd.closest_point), the same point at the
parameters the angle relation gives, normals that agree, BRepCheck, natural bounds
(seams, degenerated edges), areas against closed forms; nurbs=True and the default
to_occ are the exact B-spline, pole for pole."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepAdaptor import BRepAdaptor_Surface  # noqa: E402
from OCP.BRepLProp import BRepLProp_SLProps  # noqa: E402
from OCP.BRepOffset import BRepOffset_MakeOffset, BRepOffset_Skin  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.Geom import Geom_BSplineSurface, Geom_RectangularTrimmedSurface  # noqa: E402
from OCP.GeomAbs import (GeomAbs_Arc, GeomAbs_BSplineSurface, GeomAbs_Cone, GeomAbs_Cylinder,  # noqa: E402
                         GeomAbs_Sphere, GeomAbs_SurfaceOfRevolution, GeomAbs_Torus)
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

import cagd  # noqa: E402
from cagd import BSplineSurface, closest_point, cone, cylinder, revolve, sphere, torus  # noqa: E402
from cagd.occ import (area, check_valid, make_face, solid_from_surfaces, subshapes, to_occ,  # noqa: E402
                      volume)
from cagd.occ.analytic import analytic_form  # noqa: E402
from cagd.surfaces import properties  # noqa: E402

from occ_strategies import revolved_surfaces  # noqa: E402

EXACT = 1e-12                     # relative to the surface's size: both are the same surface
PROJECTION_TOL = 1e-15            # a tight convergence test for GeomAPI_ProjectPointOnSurf
PROFILE = cagd.natural_cubic_spline(np.array([[2.0, 0, 0], [2.8, 0, 1.5], [2.2, 0, 4], [1.5, 0, 6], [1.8, 0, 8]]))
MOVE = 1.7 * Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
MIRROR = MOVE @ np.diag([1.0, -1.0, 1.0])
R, r, H = 3.0, 1.2, 2.5


def _revolution_area(s):
    return properties.area(s).value           # the engine's own quadrature (Gauss-Legendre per span)


CASES = {   # surface, OCCT type, closed-form area, (degenerated edges, seams)
    "sphere": (sphere(r, (1.0, -2.0, 0.5)), GeomAbs_Sphere, 4 * math.pi * r * r, (2, 1)),
    "torus": (torus(R, r, (0.0, 1.0, -1.0)), GeomAbs_Torus, 4 * math.pi ** 2 * R * r, (0, 2)),
    "cylinder": (cylinder(r, H, (2.0, 0.0, 1.0)), GeomAbs_Cylinder, 2 * math.pi * r * H, (0, 1)),
    "cone": (cone(r, H), GeomAbs_Cone, math.pi * r * math.hypot(r, H), (1, 1)),
    "moved sphere": (sphere(r).transformed(MOVE, (1.0, 2.0, 3.0)), GeomAbs_Sphere, 4 * math.pi * (1.7 * r) ** 2,
                     (2, 1)),
    "mirrored torus": (torus(R, r).transformed(MIRROR), GeomAbs_Torus, 4 * math.pi ** 2 * 1.7 ** 2 * R * r, (0, 2)),
    "mirrored cone": (cone(r, H).transformed(MIRROR, (0.0, 0.0, 1.0)), GeomAbs_Cone,
                      math.pi * 1.7 ** 2 * r * math.hypot(r, H), (1, 1)),
    "revolution": (revolve(PROFILE), GeomAbs_SurfaceOfRevolution, None, (0, 1)),
    "partial revolution": (revolve(PROFILE, (1.0, 0.0, 0.0), (0.0, 1.0, 1.0), 2.0, -1.0),
                           GeomAbs_SurfaceOfRevolution, None, (0, 0)),
    "mirrored revolution": (revolve(PROFILE, angle=4.0, start_angle=2.5).transformed(MIRROR, (1.0, 0.0, 0.0)),
                            GeomAbs_SurfaceOfRevolution, None, (0, 0)),
}


def xyz(p) -> np.ndarray:
    return np.array([p.X(), p.Y(), p.Z()])


def engine_samples(s, n=9):
    (u0, u1), (v0, v1) = s.domain
    u, v = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n + 2), indexing="ij")
    return u.ravel(), v.ravel()


def projected_distances(geom, points) -> np.ndarray:
    """Distances from points to the surface by GeomAPI_ProjectPointOnSurf with its default
    and with a tight convergence test (each stalls on some points: the default at
    ~1e-11, the tight one at the rim of a disc); each is the distance to a point of the
    surface, so the smaller one still bounds the true distance from above."""
    out = []
    for p in points:
        found = []
        for args in ((), (PROJECTION_TOL,)):
            proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, p)), geom, *args)
            if proj.NbPoints():
                found.append(proj.LowerDistance())
        assert found, f"no projection of {p}"
        out.append(min(found))
    return np.array(out)


def axis_distance(s, points) -> np.ndarray:
    r = s.revolution
    x = points - r.axis_point
    return np.linalg.norm(x - (x @ r.axis_direction)[:, None] * r.axis_direction, axis=1)


def check_same_surface(s, face, geom=None):
    """Engine points on the OCCT surface ``geom`` (when given: projection), OCCT points
    on the engine surface; the same point and normal (away from degenerate points) at
    the parameters of the angle relation."""
    size = s.size
    u, v = engine_samples(s)
    if geom is not None:
        assert projected_distances(geom, s(u, v)).max() <= EXACT * size
    adaptor = BRepAdaptor_Surface(face)
    U0, U1, V0, V1 = BRepTools.UVBounds_s(face)
    Us, Vs = np.meshgrid(np.linspace(U0, U1, 8), np.linspace(V0, V1, 7), indexing="ij")
    occt = np.array([xyz(adaptor.Value(a, b)) for a, b in zip(Us.ravel(), Vs.ravel())])
    assert closest_point(s, occt).distances.max() <= EXACT * size
    U, V = s.analytic_parameters(u, v)
    assert np.abs(np.array([xyz(adaptor.Value(a, b)) for a, b in zip(U, V)]) - s(u, v)).max() <= EXACT * size
    d = s.derivatives(u, v, 1, 1)
    regular = np.linalg.norm(np.cross(d[1, 0], d[0, 1]), axis=-1) > 1e-3 * size ** 2
    if not regular.any():
        return
    sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    normals = np.array([sign * xyz(BRepLProp_SLProps(adaptor, a, b, 1, 1e-9).Normal())
                        for a, b in zip(U[regular], V[regular])])
    assert np.abs(normals - s.normal(u[regular], v[regular])).max() <= EXACT


@pytest.mark.parametrize("name", list(CASES))
def test_analytic_face_is_the_engine_surface(name):
    s, kind, exact_area, (degenerated, seams) = CASES[name]
    face = make_face(s)
    assert check_valid(face)
    assert BRepAdaptor_Surface(face).GetType() == kind
    check_same_surface(s, face, to_occ(s, analytic=True))
    assert BRepTools.UVBounds_s(face) == pytest.approx(s.analytic_bounds, abs=1e-14)
    edges = subshapes(face, TopAbs_EDGE)
    assert sum(BRep_Tool.Degenerated_s(e) for e in edges) == degenerated
    assert sum(BRep_Tool.IsClosed_s(e, face) for e in edges) == 2 * seams       # a seam is there twice
    expected = exact_area if exact_area is not None else _revolution_area(s)
    assert area(face) == pytest.approx(expected, rel=1e-9)


@settings(max_examples=20, deadline=None)
@given(revolved_surfaces())
def test_random_revolutions(s):
    """Random profiles (crossing the axis, folding the surface): OCCT's points at the
    mapped parameters are the engine's and lie on it (GeomAPI's projection is no
    oracle on these: it returns non-global minima 4e-4 away from points on the
    surface)."""
    assume(axis_distance(s, s.revolution.profile.control_points).max() > 1e-3 * s.size)   # not a segment on the axis
    face = make_face(s)
    assert BRepAdaptor_Surface(face).GetType() == GeomAbs_SurfaceOfRevolution
    check_same_surface(s, face)


def occ_bspline_data(g):
    """Poles, weights, knots and multiplicities of a Geom_BSplineSurface, as arrays."""
    nu, nv = g.NbUPoles(), g.NbVPoles()
    poles = np.array([[xyz(g.Pole(i, j)) for j in range(1, nv + 1)] for i in range(1, nu + 1)])
    weights = np.array([[g.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)])
    knots = [np.array([f(i) for i in range(1, n + 1)]) for f, n in
             ((g.UKnot, g.NbUKnots()), (g.VKnot, g.NbVKnots()), (g.UMultiplicity, g.NbUKnots()),
              (g.VMultiplicity, g.NbVKnots()))]
    return [poles, weights, *knots, np.array([g.UDegree(), g.VDegree()])]


@pytest.mark.parametrize("name", ["sphere", "mirrored torus", "cone", "partial revolution"])
def test_nurbs_faces_and_default_to_occ_are_the_exact_bspline(name):
    s = CASES[name][0]
    geom = to_occ(s)
    assert isinstance(geom, Geom_BSplineSurface)
    face = make_face(s, nurbs=True)
    assert BRepAdaptor_Surface(face).GetType() == GeomAbs_BSplineSurface and face.Orientation() != TopAbs_REVERSED
    held = BRep_Tool.Surface_s(face)
    for a, b in zip(occ_bspline_data(held), occ_bspline_data(geom)):
        assert np.array_equal(a, b)
    f = s.occ_form()
    assert np.array_equal(occ_bspline_data(geom)[0], f.poles) and np.array_equal(occ_bspline_data(geom)[1], f.weights)


def test_to_occ_analytic_bounds_and_plain_surfaces():
    """The analytic geometry is trimmed to the engine's range where that is not the
    whole surface; a surface without a record stays a B-spline."""
    assert not isinstance(to_occ(CASES["sphere"][0], analytic=True), Geom_RectangularTrimmedSurface)
    for name in ("cylinder", "cone", "partial revolution"):
        g = to_occ(CASES[name][0], analytic=True)
        assert isinstance(g, Geom_RectangularTrimmedSurface)
        assert g.Bounds() == pytest.approx(CASES[name][0].analytic_bounds, abs=1e-14)
    plain = sphere(1.0).transformed(np.diag([1.0, 1.0, 2.0]))
    assert type(plain) is BSplineSurface and analytic_form(plain) is None
    assert isinstance(to_occ(plain, analytic=True), Geom_BSplineSurface)
    assert BRepAdaptor_Surface(make_face(plain)).GetType() == GeomAbs_BSplineSurface


@pytest.mark.parametrize("nurbs, kind", [(False, GeomAbs_Sphere), (True, GeomAbs_BSplineSurface)])
def test_solids_from_either_form(nurbs, kind):
    """A closed sphere and torus make the same solid from either face: volumes against
    the closed forms."""
    for s, exact in ((sphere(r), 4 / 3 * math.pi * r ** 3), (torus(R, r), 2 * math.pi ** 2 * R * r * r)):
        solid = solid_from_surfaces([s], nurbs=nurbs)
        faces = subshapes(solid, TopAbs_FACE)
        assert check_valid(solid) and len(faces) == 1
        assert BRepAdaptor_Surface(faces[0]).GetType() in (kind, GeomAbs_Torus if not nurbs else kind)
        assert volume(solid) == pytest.approx(exact, rel=1e-9)


def thickened(face, t: float):
    """OCCT's offset in skin mode with thickening (what cq_ext.thicken runs), or None."""
    maker = BRepOffset_MakeOffset()
    maker.Initialize(face, t, 1e-6, BRepOffset_Skin, False, False, GeomAbs_Arc, True)
    maker.MakeOffsetShape()
    return maker.Shape() if maker.IsDone() else None


@pytest.mark.parametrize("name, wall", [
    ("sphere", lambda t: 4 / 3 * math.pi * ((r + t) ** 3 - r ** 3)),
    ("mirrored torus", lambda t: 2 * math.pi ** 2 * (1.7 * R) * ((1.7 * r) ** 2 - (1.7 * r - t) ** 2)),  # normal in
    ("cylinder", lambda t: math.pi * ((r + t) ** 2 - r ** 2) * H),
    ("revolution", None)])
def test_occt_offsets_the_analytic_face_not_the_nurbs_face(name, wall):
    """BRepOffset_MakeOffset (on OCCT 7.9 and 8.0) thickens the analytic face along the
    engine's normal (outwards; inwards on the mirrored torus, whose S_u x S_v the
    reflection turned in) into a valid solid of the closed-form volume, and refuses the
    NURBS face (C0 knots)."""
    s, t = CASES[name][0], 0.2
    solid = thickened(make_face(s), t)
    assert solid is not None and check_valid(solid)
    if wall is not None:
        assert volume(solid) == pytest.approx(wall(t), rel=1e-6)
    assert thickened(make_face(s, nurbs=True), t) is None
