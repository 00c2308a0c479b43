"""Real STEP/IGES files written by other CAD systems (../shared/data/cad, see its
README): what OCCT reads (counts, degrees, weights) and that every engine object
evaluates as OCCT's evaluation of the face's surface; a write_step/read_step round
trip of what was read is exact. Skipped when the folder is absent."""

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface  # noqa: E402
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED  # noqa: E402

from OCP.BRepAdaptor import BRepAdaptor_Surface  # noqa: E402

from cagd import BSplineCurve, BSplineSurface, TrimmedSurface, closest_point  # noqa: E402
from cagd.occ import Imported, read_iges, read_step, write_step  # noqa: E402

from corpus import CAD  # noqa: E402
pytestmark = pytest.mark.skipif(not CAD.is_dir(), reason="../shared/data/cad is not there")

STEP_FILES = ["bug28366_fuselage.stp", "trj7_c2-al-214.stp", "xr1-tu-rod.stp", "bug29478.stp",
              "trj12_gd1-id-214.stp", "trj1_t4m-pe.stp", "xr1-db-214_7.stp"]
# faces as the README table says OCCT reads them
FACES = {"bug28366_fuselage.stp": 8, "trj7_c2-al-214.stp": 1, "xr1-tu-rod.stp": 4, "bug29478.stp": 1,
         "trj12_gd1-id-214.stp": 7, "trj1_t4m-pe.stp": 11, "xr1-db-214_7.stp": 4,
         "OCC8842_cylinder_Ideas.igs": 3}
ALL = sorted(p.name for p in (CAD / "step").glob("*") if p.is_file()) + \
    sorted(p.name for p in (CAD / "iges").glob("*") if p.is_file()) if CAD.is_dir() else []
# the nine files one bad face used to abort (issue 15): UV boxes overshooting the surface's
# range by 1e-16 to 1e-3, tori spanning 2 pi + 2e-15
ONCE_FAILED = ["11752.stp", "917_fusee.stp", "SampleCrankshaft4A.stp", "Ventilator.stp", "bug33398.step",
               "trj3_s1-al-214.stp", "trj4_k1_geo-md-203.stp", "trj4_k1_geo-tc-214.stp", "bug22566_test_Bad.igs"]
OCCT_PROJECTION_TOL = 1e-7      # GeomAPI_ProjectPointOnSurf's reach on surfaces of revolution (measured 1.8e-8)
_CACHE = {}


def path_of(name):
    return CAD / ("iges" if name.endswith((".igs", ".iges")) else "step") / name


def imported(name):
    if name not in _CACHE:
        _CACHE[name] = (read_iges if name.endswith((".igs", ".iges")) else read_step)(path_of(name))
    return _CACHE[name]


def plain(obj):
    """The surface under a trim (read_step gives TrimmedSurface for trimmed faces)."""
    return obj.untrimmed if isinstance(obj, TrimmedSurface) else obj


def surfaces(name):
    """The faces' surfaces (untrimmed), as Imported items."""
    return [Imported(i.name, plain(i.object), i.shape) for i in imported(name)
            if isinstance(plain(i.object), BSplineSurface)]


def curves(name):
    return [i for i in imported(name) if isinstance(i.object, BSplineCurve)]


@pytest.mark.parametrize("name", list(FACES))
def test_face_counts(name):
    assert len(surfaces(name)) == FACES[name]


def test_fuselage_bicubic_patches():
    ss = [i.object for i in surfaces("bug28366_fuselage.stp")]
    assert all((s.degree_u, s.degree_v) == (3, 3) and s.control_points.shape == (10, 4, 3) and s.weights is None
               and not (s.periodic_u or s.periodic_v) for s in ss)
    assert curves("bug28366_fuselage.stp") == []


def test_trj7_surface_and_free_curve():
    (c,) = curves("trj7_c2-al-214.stp")
    assert c.object.degree == 3 and len(c.object.control_points) == 7 and c.object.weights is None
    (s,) = surfaces("trj7_c2-al-214.stp")
    assert s.object.control_points.shape == (4, 4, 3) and s.object.weights is None


def test_rod_rational_half_cylinders():
    rational = [i.object for i in surfaces("xr1-tu-rod.stp") if i.object.weights is not None]
    assert len(rational) == 2
    for s in rational:
        assert {s.degree_u, s.degree_v} == {1, 3}
        # the file writes 1/3 with 11 digits (0.33333333333)
        assert np.allclose(s.weights, [[1, 1 / 3, 1 / 3, 1]] * 2, rtol=0, atol=1e-11) or \
            np.allclose(s.weights.T, [[1, 1 / 3, 1 / 3, 1]] * 2, rtol=0, atol=1e-11)


def test_periodic_imports():
    per = [i.object for i in surfaces("trj12_gd1-id-214.stp") if i.object.periodic_u]
    assert len(per) == 1 and per[0].control_points.shape[:2] == (6, 2) and per[0].weights is not None
    # the README: one V-periodic 2x16 surface of degree 1x8 shared by 2 faces; read_step gives each
    # face's own piece of it (trimmed to the face), a non-periodic 2x9 B-spline of the same degree
    deg8 = [i.object for i in surfaces("xr1-db-214_7.stp") if i.object.degree_v == 8]
    assert len(deg8) == 2 and all(s.degree_u == 1 and s.control_points.shape[:2] == (2, 9) for s in deg8)
    per = [i.object for i in surfaces("OCC8842_cylinder_Ideas.igs") if i.object.periodic_u]
    assert len(per) == 1 and per[0].control_points.shape[:2] == (8, 2)


def test_the_corpus_is_there():
    assert len(ALL) == 33 and set(ONCE_FAILED) <= set(ALL)


@pytest.mark.parametrize("name", ALL)
def test_every_face_of_every_file_is_read(name):
    """As many surfaces as OCCT's reader gives faces, nothing skipped."""
    from cagd.occ import read_shapes, subshapes
    contents = imported(name)
    assert contents.complete, contents.message
    occt = sum(len(subshapes(shape, TopAbs_FACE)) for _, shape in read_shapes(path_of(name)))
    assert len(surfaces(name)) == occt


def box_overshoots(face) -> bool:
    """The face's UV box leaves its (basis) surface's range or spans a period or more."""
    g = BRep_Tool.Surface_s(face)
    while hasattr(g, "BasisSurface"):
        g = g.BasisSurface()
    box = BRepAdaptor_Surface(face, True)
    U0, U1, V0, V1 = g.Bounds()
    out = []
    for lo, hi, a, b, periodic in ((box.FirstUParameter(), box.LastUParameter(), U0, U1, g.IsUPeriodic()),
                                   (box.FirstVParameter(), box.LastVParameter(), V0, V1, g.IsVPeriodic())):
        out.append(hi - lo >= b - a if periodic else lo < a or hi > b)
    return any(out)


def test_the_nine_files_had_overshooting_faces():
    """125 faces of the nine files have boxes past their surfaces (what used to abort them)."""
    from cagd.occ import read_shapes, subshapes
    count = sum(box_overshoots(f) for name in ONCE_FAILED for _, shape in read_shapes(path_of(name))
                for f in subshapes(shape, TopAbs_FACE))
    assert count >= 100


@pytest.mark.parametrize("name", list(FACES) + ONCE_FAILED)
def test_engine_objects_evaluate_as_occt(name):
    samples = 6 if name in FACES else 3
    items = surfaces(name)
    if name not in FACES:        # the big files: every face whose UV box needed fixing, and every 10th
        items = [i for k, i in enumerate(items) if k % 10 == 0 or box_overshoots(i.shape)]
    for item in items:
        s = item.object
        g = BRep_Tool.Surface_s(item.shape) if item.shape.ShapeType() == TopAbs_FACE else None
        assert g is not None
        (a, b), (c, d) = s.domain
        u, v = np.meshgrid(np.linspace(a, b, samples), np.linspace(c, d, samples), indexing="ij")
        # a REVERSED face comes back with u reversed (its normal is the face's)
        flip = item.shape.Orientation() == TopAbs_REVERSED
        mine = s((a + b - u.ravel()) if flip else u.ravel(), v.ravel())
        theirs = []
        for x, y in zip(u.ravel().tolist(), v.ravel().tolist()):
            p = gp_Pnt()
            g.D0(x, y, p)
            theirs.append((p.X(), p.Y(), p.Z()))
        size = np.abs(s.control_points).max()
        if isinstance(g, (Geom_BSplineSurface, Geom_BezierSurface)):
            # the same parameter: the face's piece of OCCT's surface
            assert np.abs(mine - np.array(theirs)).max() <= 1e-12 * size, (name, item.name)
        else:
            # planes, cylinders, cones, spheres, tori, revolutions: the rational form has its
            # own parameter. OCCT's points of the face (its UV box, clamped into the surface's
            # range) lie on the engine surface (certified closest points), and the engine's
            # points on OCCT's surface (OCCT's projection, whose own precision on surfaces of
            # revolution is about 1e-8 of the size: the bound is that loose)
            box = BRepAdaptor_Surface(item.shape, True)
            U0, U1, V0, V1 = g.Bounds()
            us = np.linspace(box.FirstUParameter(), box.LastUParameter(), samples)
            vs = np.linspace(box.FirstVParameter(), box.LastVParameter(), samples)
            us, vs = (us if g.IsUPeriodic() else np.clip(us, U0, U1)), (vs if g.IsVPeriodic() else np.clip(vs, V0, V1))
            occ_points = []
            for x in us.tolist():
                for y in vs.tolist():
                    p = gp_Pnt()
                    g.D0(x, y, p)
                    occ_points.append((p.X(), p.Y(), p.Z()))
            assert closest_point(s, np.array(occ_points)).distances.max() <= 1e-12 * size, (name, item.name)
            for q in mine:
                proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*q.tolist()), g)
                if proj.NbPoints():           # OCCT's projector finds nothing near some revolution axes
                    assert proj.LowerDistance() <= OCCT_PROJECTION_TOL * size, (name, item.name)


TRIM_ROUND_TRIP_REL = 1e-9     # area of a trimmed face after a STEP round trip


@pytest.mark.parametrize("name", list(FACES))
def test_write_read_round_trip_is_exact(name, tmp_path):
    items = imported(name)
    write_step([(f"o{k}", i.object) for k, i in enumerate(items)], tmp_path / "again.step")
    back = {i.name: i.object for i in read_step(tmp_path / "again.step")}
    assert len(back) == len(items)
    for k, i in enumerate(items):
        if isinstance(i.object, TrimmedSurface):
            # a trimmed face is written as a face on its exact B-spline, which OCCT reads
            # back as a segment of it over the trim's box: the same surface, other poles
            again = back[f"o{k}"]
            assert isinstance(again, TrimmedSurface), (name, k)
            assert again.area() == pytest.approx(i.object.area(), rel=TRIM_ROUND_TRIP_REL), (name, k)
            continue
        a, b = plain(i.object).occ_form(), plain(back[f"o{k}"]).occ_form()
        assert np.array_equal(a.poles, b.poles), (name, k)
        assert (a.weights is None) == (b.weights is None)
        if a.weights is not None:
            assert np.array_equal(a.weights, b.weights)
        for x, y in zip(a[2:], b[2:]):
            assert np.array_equal(np.asarray(x), np.asarray(y))


# --- trimmed faces (issue 15): area and classification against OCCT ---------------------------------------
TRIM_FILES = ["trj4_k1_geo-tc-214.stp", "wing_fuselage.step", "occ22470.igs",
              "trj12_gd1-id-214.stp"]      # every trimmed face of these
SAMPLED_FILES = ["bug24595_281390.stp", "trj3_s1-id-203.stp"]
TRIM_SAMPLE = 12             # faces drawn (seeded) from SAMPLED_FILES
AREA_REL = 1e-8
CLASSIFY_POINTS = 60
TIGHT_EDGES = 1e-7           # relative: faces with larger edge tolerances are defined only that well
DOMAIN_SLACK = 1e-9          # relative: faces whose pcurves leave the surface's range by more are not compared


# issue 15, not passing yet (next session): on wing_fuselage.step, area() differs from
# BRepGProp by 1.2e-5 relative on faces where its adaptive rule stops unconverged
# (MAX_AREA_INTERVALS) after 9-13 s, with an error estimate of 1e-10

def trimmed_items():
    rng = np.random.default_rng(15)
    out = [(n, i) for n in TRIM_FILES for i in imported(n) if isinstance(i.object, TrimmedSurface)]
    rest = [(n, i) for n in SAMPLED_FILES for i in imported(n) if isinstance(i.object, TrimmedSurface)]
    picks = rng.choice(len(rest), size=min(TRIM_SAMPLE, len(rest)), replace=False)
    return out + [rest[k] for k in sorted(picks)]


def leaves_domain(ts):
    """How far (relative) the loops leave a bounded direction of the surface's domain:
    OCCT extrapolates the surface there, the engine does not."""
    (u0, u1), (v0, v1) = ts.domain
    flat = ts._flattened()
    over = 0.0
    if not ts.periodic_u:
        over = max(over, u0 - flat.lo[0], flat.hi[0] - u1)
    if not ts.periodic_v:
        over = max(over, v0 - flat.lo[1], flat.hi[1] - v1)
    return max(over, 0.0) / max(u1 - u0, v1 - v0)


OTHER_SPANS = 24     # the other potential costs its direction's spans per point: faces with more are left out


def other_spans(ts):
    """Knot spans over the loops in the direction area() does not integrate along."""
    from cagd.surfaces.trimmed import _knot_lines
    k = 1 - ts._inner_direction()
    flat = ts._flattened()
    return len(_knot_lines(ts, k, float(flat.lo[k]), float(flat.hi[k])))


def other_potential_area(ts):
    """The area by the potential area() does not use (G = int |S_u x S_v| du, or the one
    along v: on the face with u and v exchanged): an independent quadrature of the same
    integral."""
    from cagd.surfaces.trimmed import AREA_TOL, _area
    return _area(ts._exchanged() if ts._inner_direction() == 0 else ts, AREA_TOL).value


def edge_tolerance(face):
    from OCP.TopAbs import TopAbs_EDGE
    from cagd.occ import subshapes
    return max(BRep_Tool.Tolerance_s(e) for e in subshapes(face, TopAbs_EDGE))


def scan_area(ts, lines=40, nodes=24, samples=4001):
    """Brute force, independent of area(): int du int_{v in D(u)} |S_u x S_v| dv, the
    outer integral by Gauss-Legendre on ``lines`` pieces of each u knot span, the inner
    one between the crossings of the vertical line u with the loops (dense samples,
    then bisection), split at the v knots. Valid where no loop curve runs along a
    vertical line inside the domain."""
    s = ts.untrimmed
    x, w = np.polynomial.legendre.leggauss(nodes)
    curves = []
    for loop in ts.loops:                 # with the closing segments across the gaps (up to ts.tol)
        for c, d in zip(loop, loop[1:] + loop[:1]):
            a, b = c(c.domain[1]), d(d.domain[0])
            curves += [c] + ([BSplineCurve([a, b], 1)] if np.any(a != b) else [])
    dense = [(np.linspace(*c.domain, samples), c(np.linspace(*c.domain, samples))) for c in curves]
    lo_u = min(P[:, 0].min() for _, P in dense)
    hi_u = max(P[:, 0].max() for _, P in dense)
    ends = [P[k, 0] for _, P in dense for k in (0, -1)]
    br = np.unique(np.concatenate([[lo_u, hi_u], np.unique(s.knots_u), ends]))
    br = br[(br >= lo_u) & (br <= hi_u)]
    br = np.unique(np.concatenate([np.linspace(a, b, lines + 1) for a, b in zip(br[:-1], br[1:])]))
    U = ((br[:-1] + br[1:]) / 2)[:, None] + ((br[1:] - br[:-1]) / 2)[:, None] * x
    WU = ((br[1:] - br[:-1]) / 2)[:, None] * w
    U, WU = U.ravel(), WU.ravel()
    vs = [[] for _ in U]
    for c, (t, P) in zip(curves, dense):
        f = P[:, 0][:, None] - U[None, :]
        i, j = np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)
        a, b, flo = t[i], t[i + 1], f[i, j]
        for _ in range(60):
            m = 0.5 * (a + b)
            fm = c(m)[:, 0] - U[j]
            left = np.sign(fm) == np.sign(flo)
            a, flo, b = np.where(left, m, a), np.where(left, fm, flo), np.where(left, b, m)
        for jj, v in zip(j, c(0.5 * (a + b))[:, 1]):
            vs[jj].append(v)
    knots_v = np.unique(s.knots_v)
    total = 0.0
    for u, wu, v in zip(U, WU, vs):
        v = np.sort(v)
        assert len(v) % 2 == 0
        for a, b in zip(v[0::2], v[1::2]):
            e = np.unique(np.concatenate([[a, b], knots_v[(knots_v > a) & (knots_v < b)]]))
            V = ((e[:-1] + e[1:]) / 2)[:, None] + ((e[1:] - e[:-1]) / 2)[:, None] * x
            WV = ((e[1:] - e[:-1]) / 2)[:, None] * w
            d = s.derivatives(np.full(V.size, u), V.ravel(), 1, 1)
            total += wu * float(WV.ravel() @ np.linalg.norm(np.cross(d[1, 0], d[0, 1]), axis=-1))
    return total


def test_wing_fuselage_area_where_brepgprop_is_off():
    """A face of wing_fuselage.step (CATIA, rational 3 x 56 net, edge tolerance 2.3e-3
    mm) where BRepGProp.SurfaceProperties (precision 1e-12) gives 1158.62665: the
    brute-force scan agrees with area() to 1e-8, BRepGProp is 9.3e-6 off. area()
    converges there (it stopped at MAX_AREA_INTERVALS, unconverged, after 25 s)."""
    from cagd.occ import area
    item = [i for i in imported("wing_fuselage.step") if i.name == "Part 2[3]"][0]
    ts = item.object
    report = ts.area_report()
    assert report.converged, report.message
    oracle = scan_area(ts)
    assert abs(report.value - oracle) <= 1e-8 * oracle, (report.value, oracle)
    assert abs(area(item.shape, 1e-12) - oracle) > 5e-6 * oracle      # OCCT's own error, pinned


def test_trimmed_areas_against_brepgprop():
    """area() = the area by the other potential to 1e-9, and = BRepGProp to 1e-8 where the
    face is defined that well: its edge tolerances within TIGHT_EDGES of its size and its
    pcurves inside the surface's range (files' pcurves stray from their 3-D edges by up to
    the edge tolerance, 0.033 mm on bug24595_281390: the face is only defined to that, and
    OCCT extrapolates surfaces where pcurves leave their range, the engine does not)."""
    from cagd.occ import area
    worst_occt, worst_self, compared, both, loose = 0.0, 0.0, 0, 0, []
    for name, item in trimmed_items():
        ts = item.object
        mine = ts.area()
        if other_spans(ts) <= OTHER_SPANS:
            rel_self = abs(other_potential_area(ts) - mine) / mine
            worst_self = max(worst_self, rel_self)
            assert rel_self <= 1e-9, (name, item.name, rel_self)
            both += 1
        if leaves_domain(ts) > DOMAIN_SLACK or edge_tolerance(item.shape) > TIGHT_EDGES * ts.size:
            loose.append((name, item.name))
            continue
        occt = area(item.shape, 1e-12)
        if not occt > 0:                 # BRepGProp gives a negative area on an extrusion of trj4_k1_geo-tc-214
            loose.append((name, item.name))
            continue
        rel = abs(mine - occt) / occt
        worst_occt = max(worst_occt, rel)
        compared += 1
        assert rel <= AREA_REL, (name, item.name, rel)
    assert compared >= 19             # as measured: the tight faces of these files
    assert both >= 60
    print(f"\narea: {len(loose) + compared} trimmed faces; on {both}, the two potentials agree to {worst_self:.3g}; "
          f"{compared} against BRepGProp, worst {worst_occt:.3g}; {len(loose)} loosely defined faces not compared")


def test_trimmed_contains_against_the_face_classifier():
    """contains = BRepClass_FaceClassifier at random (u, v) of the loops' box farther than
    the chord bound plus 1e-9 (relative) from the boundary (OCCT's parameters: u mirrored on
    REVERSED faces; faces whose OCCT parameters are angles are classified at their 3-D points)."""
    from OCP.BRepClass import BRepClass_FaceClassifier
    from OCP.gp import gp_Pnt2d
    from OCP.TopAbs import TopAbs_IN, TopAbs_ON
    from cagd.occ.trim import _Identity, parameter_maps
    from cagd.occ.convert import _face_box
    rng = np.random.default_rng(16)
    checked = faces = 0
    for name, item in trimmed_items():
        ts, face = item.object, item.shape
        box = BRepAdaptor_Surface(face, True)
        geom = _face_box(BRep_Tool.Surface_s(face), box.FirstUParameter(), box.LastUParameter(),
                         box.FirstVParameter(), box.LastVParameter())
        flip = face.Orientation() == TopAbs_REVERSED
        engine = ts.untrimmed.reversed("u") if flip else ts.untrimmed
        identity = all(isinstance(m, _Identity) for m in parameter_maps(geom, engine))
        flat = ts._flattened()
        u = flat.lo[0] + (flat.hi[0] - flat.lo[0]) * rng.random(4 * CLASSIFY_POINTS)
        v = flat.lo[1] + (flat.hi[1] - flat.lo[1]) * rng.random(4 * CLASSIFY_POINTS)
        p = np.stack([u, v], axis=1)
        d = np.min([_segment_distances(p, flat.A[s:s + 4096], flat.B[s:s + 4096])
                    for s in range(0, len(flat.A), 4096)], axis=0)
        far = d > float(flat.bound.max()) + 1e-9 * flat.scale
        u, v = u[far][:CLASSIFY_POINTS], v[far][:CLASSIFY_POINTS]
        ours = ts.contains(u, v)
        (a, b), _ = ts.domain
        for k in range(len(u)):
            if identity:
                x = a + b - u[k] if flip else u[k]
                c = BRepClass_FaceClassifier(face, gp_Pnt2d(float(x), float(v[k])), 1e-9)
            else:
                c = BRepClass_FaceClassifier(face, gp_Pnt(*map(float, ts(u[k], v[k]))), 1e-7)
            state = c.State()
            if state == TopAbs_ON:
                continue
            assert (state == TopAbs_IN) == bool(ours[k]), (name, item.name, u[k], v[k])
            checked += 1
        faces += 1
    assert faces >= 40 and checked >= 30 * faces
    print(f"\ncontains: {checked} points on {faces} trimmed faces agree with BRepClass_FaceClassifier")


def _segment_distances(p, a, b):
    d = b - a
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(np.einsum("pkj,kj->pk", p[:, None, :] - a[None], d) / dd, 0.0, 1.0)
    q = a[None] + t[..., None] * d[None]
    return np.linalg.norm(p[:, None, :] - q, axis=-1).min(axis=1)


@pytest.mark.parametrize("name", ["bug24595_281390.stp", "trj3_s1-id-203.stp", "wing_fuselage.step",
                                  "periodic_u_cst.step", "boxed_sphere.step"])
def test_every_trimmed_face_is_written_back(name):
    """to_occ of every trimmed face read from these files gives a face BRepCheck accepts
    (make_trimmed_face raised DifferentsPointAndParameter on 13 of 83 faces of the first
    three, with pcurve ends 7.5e-6 to 8.5e-5 mm apart in 3-D or 4.9e-6 outside the
    surface's range: vertices now carry the gap they close); read back through from_occ,
    the first three faces keep the engine's area to 1e-9."""
    from cagd.occ import from_occ, to_occ
    faces = [i.object for i in imported(name) if isinstance(i.object, TrimmedSurface)]
    assert faces
    for k, ts in enumerate(faces):
        face = to_occ(ts)
        if k < 3:
            back = from_occ(face)
            assert isinstance(back, TrimmedSurface), (name, k)
            assert abs(back.area() - ts.area()) <= 1e-9 * ts.area(), (name, k)


def test_closest_points_on_real_trimmed_faces_against_brepextrema():
    """closest_point on the trimmed faces of wing_fuselage.step and occ22470.igs (pcurves
    leaving the surface's range by up to 4.9e-6 of it: the loop samples raised before
    they were clipped into the domain) is never farther than BRepExtrema_DistShapeShape
    from the point to the face (beyond its edge tolerance; within 1e-7 of the size on 90%
    of the points), and the lower bounds hold."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    rng = np.random.default_rng(151)
    checked = tight = 0
    for name in ("wing_fuselage.step", "occ22470.igs"):
        for item in imported(name):
            ts = item.object
            if not isinstance(ts, TrimmedSurface):
                continue
            s = ts.untrimmed
            (a, b), (c, d) = s.domain
            uv = rng.random((6, 2))
            X = s(a + (b - a) * uv[:, 0], c + (d - c) * uv[:, 1]) + rng.normal(0, 0.02 * s.size, (6, 3))
            r = closest_point(ts, X)
            assert np.all(r.lower_bounds <= r.distances)
            for x, dist in zip(X, r.distances):
                ext = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, x))).Vertex(),
                                                 item.shape)
                assert ext.IsDone()
                # OCCT measures to the file's edge curves too, off S(pcurve) by up to the edge
                # tolerance (2.3e-3 mm on wing_fuselage): the face is defined to that
                slack = max(edge_tolerance(item.shape), OCCT_PROJECTION_TOL * s.size)
                assert dist <= ext.Value() * (1 + 1e-9) + slack, (name, item.name)
                tight += dist <= ext.Value() * (1 + 1e-9) + OCCT_PROJECTION_TOL * s.size
                checked += 1
    assert checked >= 100 and tight >= 0.9 * checked
