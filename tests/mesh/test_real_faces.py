"""Tessellation and meshes of real trimmed faces (issue 15), skipped without
../shared/data/cad. trj1_t4m-pe (Pro/E): its trimmed faces were meshed to 1.66, 1.47 and
0.36 x their area before (a chord across a quarter circle, fans at a joint's
near-duplicate vertices, holes bridged across each other); now every one covers its trim
exactly once in (u, v) and its 3-D mesh area is within 2e-3 of area() at count 32
(measured 0.9990-1.0006), the mesh's deviation falling as the count doubles."""
import warnings

import numpy as np
import pytest

import cagd
from trim_shapes import check_triangulation, mesh_area

pytest.importorskip("OCP")
from corpus import CAD  # noqa: E402
FILE = CAD / "step" / "trj1_t4m-pe.stp"
needs_file = pytest.mark.skipif(not FILE.is_file(), reason=f"{FILE} is not there")


@pytest.fixture(scope="module")
def faces():
    from cagd.occ import read_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        items = list(read_step(FILE))
    return {i: it.object for i, it in enumerate(items) if isinstance(it.object, cagd.TrimmedSurface)}


@needs_file
def test_every_trimmed_face_is_covered_once_and_its_area_is_right(faces):
    assert sorted(faces) == [1, 3, 8, 9]
    for i, ts in faces.items():
        t = check_triangulation(ts, 32)
        assert mesh_area(ts, t) == pytest.approx(ts.area(), rel=2e-3), i


@needs_file
def test_mesh_deviation_falls_with_the_count(faces):
    from cagd.mesh.export import _deviation, _evaluate
    for i, ts in faces.items():
        errs = []
        for n in (16, 64):
            t = ts.tessellation(n)
            xyz = _evaluate(ts, t.uv)
            errs.append(_deviation(ts, t.uv, xyz, t.triangles, t.boundary, t.boundary_mid))
        assert errs[1] < 0.5 * errs[0], (i, errs)
        assert np.isfinite(errs).all()


@needs_file
def test_the_part_meshes_within_tol_checked_by_closest_points(faces):
    """Every face of trj1_t4m-pe meshed at tol = 0.1 mm (a 1.7 m part): converged, and the
    triangles' centroids lie within 2 tol of their face (certified closest points, an
    oracle apart from the mesh's edge-midpoint measure; a centroid may sag a little more
    than an edge midpoint); the trimmed faces' mesh areas within 1e-3 of area()."""
    from cagd.occ import read_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        items = [it.object for it in read_step(FILE)]
    tol = 0.1
    rng = np.random.default_rng(3)
    for i, g in enumerate(items):
        m = cagd.mesh.mesh(g, tol=tol)
        assert m.converged and m.max_error <= tol, (i, m.message)
        T = m.triangles[rng.choice(len(m.triangles), size=min(2000, len(m.triangles)), replace=False)]
        centroids = m.vertices[T].mean(axis=1)
        r = cagd.closest_point(g, centroids)
        assert r.distances.max() <= 2 * tol, (i, r.distances.max())
        if isinstance(g, cagd.TrimmedSurface):
            P = m.vertices[m.triangles]
            area = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1).sum()
            assert area == pytest.approx(g.area(), rel=1e-3), i


# faces the corpus scan found mis-tessellated (before: a crash, 3 x the area, a tube meshed
# as its seam line), with the mesh area at count 200 against area()
ODD_FACES = [
    ("wing_fuselage.step", 13, 2e-4),    # no outer polygon left in the band: concatenate raised
    ("917_fusee.stp", 148, 1e-5),        # a joint's gap closer made a sliver: 3.2 x area() at 64
    ("11752.stp", 408, 1e-5),            # area() = the mesh's to 1e-6; BRepGProp is 2.1e-4 off
]


@pytest.mark.parametrize("name, index, rel", ODD_FACES)
def test_odd_real_faces(name, index, rel):
    path = CAD / "step" / name
    if not path.is_file():
        pytest.skip(f"{path} is not there")
    from cagd.occ import read_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ts = list(read_step(path))[index].object
    t = check_triangulation(ts, 200)
    assert mesh_area(ts, t) == pytest.approx(ts.area(), rel=rel)
    m = cagd.mesh.mesh(ts, tol=1e-3 * ts.surface.size)
    assert m.converged, m.message


@pytest.mark.parametrize("name, index, occt", [("11752.stp", 407, True), ("917_fusee.stp", 93, True),
                                               ("917_fusee.stp", 45, False)])
def test_area_where_the_loop_leaves_the_domain(name, index, occt):
    """Faces whose loops leave the surface's domain within their tol: area() was 3.8e-4,
    6.6e-5 and 1.3e-4 above a fine mesh (the sliver outside counted); now within 2e-5 of
    the mesh at 3e-5 x size, and of BRepGProp where that agrees with the mesh (on face
    45 BRepGProp is 2.2e-5 below both)."""
    path = CAD / "step" / name
    if not path.is_file():
        pytest.skip(f"{path} is not there")
    from cagd.occ import area, read_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        item = list(read_step(path))[index]
    ts = item.object
    m = cagd.mesh.mesh(ts, tol=3e-5 * ts.surface.size)
    P = m.vertices[m.triangles]
    mesh = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1).sum()
    assert ts.area() == pytest.approx(mesh, rel=2e-5)
    if occt:
        assert ts.area() == pytest.approx(area(item.shape, 1e-10), rel=1e-6)


def _read(name):
    path = CAD / "step" / name
    if not path.is_file():
        pytest.skip(f"{path} is not there")
    from cagd.occ import read_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return list(read_step(path))


def test_tubes_bounded_by_their_seam_read_as_their_surface():
    """11752.stp's tubes: one wire of two seam lines at u = -pi and pi and two circles, on a
    surface of domain [0, 2 pi]. The loop is the whole surface (a turn wherever its seam
    is) and reads as the plain surface: 577 trimmed faces of 1018 instead of 949. Face 0
    (1147 x 3 mm) meshed in 37 s as a trimmed face (a band of 20,000 vertices along the
    loop ear-clipped and flipped), face 658 to area 0 at count 200 before; both now the
    surface's grid; the surface's area the face's (BRepGProp) to 1e-9."""
    from cagd.occ import area
    from cagd.surfaces.properties import area as surface_area
    items = _read("11752.stp")
    assert sum(isinstance(it.object, cagd.TrimmedSurface) for it in items) == 577
    for k in (0, 69, 658):
        s = items[k].object
        assert isinstance(s, cagd.BSplineSurface) and s.periodic_u, k
        occt = area(items[k].shape, 1e-10)
        assert surface_area(s).value == pytest.approx(occt, rel=1e-9), k
        m = cagd.mesh.mesh(s, tol=1e-3)
        assert m.converged, (k, m.message)


@pytest.mark.parametrize("index", [40, 112])
def test_a_plane_whose_loop_overshoots_its_box_meshes_in_few_triangles(index):
    """917_fusee.stp[40] and [112] (planar faces, their loops up to 6.6e-7 over the
    surface's range): the mesh at 0.1 mm took minutes (slivers of grid cells, tests/
    surfaces/test_tessellate.py); now 49 and 90 triangles, within tol, covering the trim
    once."""
    ts = _read("917_fusee.stp")[index].object
    m = cagd.mesh.mesh(ts, tol=0.1)
    assert m.converged and len(m.triangles) < 200, (m.message, len(m.triangles))
    t = check_triangulation(ts, 16)
    # a plane: only the trim chords' error (measured 2.4e-5 and 1.3e-4 at count 16)
    assert mesh_area(ts, t) == pytest.approx(ts.area(), rel=5e-4)
