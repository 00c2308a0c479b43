"""cq_ext for build123d users, with no CadQuery (build123d 0.13 runs on OCCT 8, which
CadQuery 2.8 cannot share a venv with; in the main venv build123d 0.12 and CadQuery
are both there and these tests pass too). ``import cq_ext`` works with CadQuery
blocked; to_b3d / from_shape round-trip exactly (points at the same parameters);
cq_ext.b3d's solid helpers return build123d shapes (the ellipsoid 4/3 pi a b c, a
thickened rectangle 6 t, the capped frustum pi h/3 (R^2 + R r + r^2)) that work in a
BuildPart; cagd.occ measures and writes build123d shapes and contexts."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

bd = pytest.importorskip("build123d")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cq_ext import b3d  # noqa: E402
from cagd import CagdError  # noqa: E402
from cagd.occ import check_valid, read_step, volume, write_step  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
A, B, C = 3.0, 2.0, 1.5
V_ELL = 4 / 3 * math.pi * A * B * C

BLOCK_CADQUERY = """
import sys
class _NoCadQuery:
    def find_spec(self, name, path=None, target=None):
        if name == "cadquery" or name.startswith("cadquery."):
            raise ModuleNotFoundError("No module named 'cadquery' (blocked)", name="cadquery")
sys.meta_path.insert(0, _NoCadQuery())
"""


def test_import_without_cadquery():
    """In a fresh interpreter with CadQuery unimportable: cq_ext imports, exports the
    library-neutral names only, and cq_ext.b3d works; the CadQuery helpers say where
    to look."""
    code = BLOCK_CADQUERY + """
import json, cagd, cq_ext
out = {"all": cq_ext.__all__, "missing": cq_ext.CADQUERY_MISSING, "cq": "cadquery" in sys.modules}
try:
    cq_ext.sew_solid
except AttributeError as exc:
    out["error"] = str(exc)
from cq_ext import b3d
solid = b3d.sew_solid(cagd.ellipsoid(3.0, 2.0, 1.5))
out["type"] = type(solid).__module__.split(".")[0] + "." + type(solid).__name__
print(json.dumps(out))
"""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout.strip().splitlines()[-1])
    assert set(out["all"]) == {"to_b3d", "from_shape", "gap_report"} and not out["cq"]
    assert "cadquery" in out["missing"]
    assert "needs CadQuery" in out["error"] and "cq_ext.b3d.sew_solid" in out["error"]
    assert out["type"] == "build123d.Solid"


CURVES = [cagd.BSplineCurve(np.array([(0, 0, 0), (1, 2, 0.5), (3, 1, -1), (4, 3, 0)], float), 3,
                            weights=[1, 2, 0.5, 1]),
          cagd.natural_cubic_spline(np.array([(0, 0), (1, 2), (3, 1), (4, 0)], float)),
          cagd.BezierCurve(np.array([(0, 0, 0), (1, 1, 1), (2, 0, 3)], float))]
SURFACES = [cagd.sphere(2.0, (1.0, 0.0, -1.0)), cagd.BezierSurface(np.array(
    [[(i, j, 0.3 * math.sin(i) * j) for j in range(4)] for i in range(3)], float))]


@pytest.mark.parametrize("curve", CURVES, ids=["nurbs", "cubic spline", "bezier"])
def test_curve_round_trip(curve):
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    edge = cq_ext.to_b3d(curve)
    assert isinstance(edge, bd.Edge) and b3d.to_b3d is cq_ext.to_b3d
    t = np.linspace(*curve.domain, 13)
    adaptor = BRepAdaptor_Curve(edge.wrapped)
    occ = np.array([[p.X(), p.Y(), p.Z()] for p in map(adaptor.Value, t.tolist())])
    expected = curve(t)
    expected = np.column_stack([expected, np.zeros((len(t), 3 - expected.shape[1]))])
    scale = np.abs(expected).max()
    assert np.abs(occ - expected).max() <= 1e-12 * scale
    assert np.abs(cq_ext.from_shape(edge, dim=curve.dim)(t) - curve(t)).max() <= 1e-12 * scale


@pytest.mark.parametrize("surface", SURFACES, ids=["sphere", "bezier"])
def test_surface_round_trip(surface):
    """The exact B-spline face (nurbs=True: the engine's parametrisation) and back; the
    default face of a sphere is OCCT's analytic one (tests/occ/test_analytic.py)."""
    face = cq_ext.to_b3d(surface, nurbs=True)
    assert isinstance(face, bd.Face) and check_valid(face)
    assert cq_ext.to_b3d(surface).geom_type.name == ("SPHERE" if surface.is_rational else "BSPLINE")
    (a, b), (c, d) = surface.domain
    s, t = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), indexing="ij")
    got = np.array([tuple(face.position_at(x, y)) for x, y in zip(s.ravel(), t.ravel())])
    U, V = a + s.ravel() * (b - a), c + t.ravel() * (d - c)
    scale = np.abs(surface(U, V)).max()
    assert np.abs(got - surface(U, V)).max() <= 1e-12 * scale
    assert np.abs(cq_ext.from_shape(face)(U, V) - surface(U, V)).max() <= 1e-12 * scale


def test_sew_solid_and_shell():
    solid = b3d.sew_solid(cagd.ellipsoid(A, B, C))
    assert isinstance(solid, bd.Solid) and check_valid(solid)
    assert volume(solid) == pytest.approx(V_ELL, rel=1e-9)
    faces = [cq_ext.to_b3d(s) for s in cagd.ellipsoid(A, B, C)]
    shell = b3d.sew_shell(faces)
    assert isinstance(shell, bd.Shell) and b3d.free_edges(shell) == []
    assert volume(b3d.sew_solid(shell)) == pytest.approx(V_ELL, rel=1e-9)
    edges = b3d.free_edges(faces[:7])
    assert len(edges) == 3 and all(isinstance(e, bd.Edge) for e in edges)
    with pytest.raises(CagdError, match=r"3 free edge\(s\)") as info:
        b3d.sew_solid(faces[:7])
    lengths = sorted(float(x) for x in __import__("re").findall(r"length ([0-9.]+)", str(info.value)))
    assert lengths == pytest.approx(sorted(e.length for e in edges), rel=1e-5)


def test_thicken_a_sketch_and_use_it_in_a_part():
    with bd.BuildSketch() as sketch:
        bd.Rectangle(20, 30)
    plate = b3d.thicken(sketch, 2.0)
    assert isinstance(plate, bd.Solid) and volume(plate) == pytest.approx(20 * 30 * 2.0, rel=1e-9)
    with bd.BuildPart() as part:
        bd.insert(plate)
        bd.Cylinder(3.0, 10.0, mode=bd.Mode.SUBTRACT)
    assert check_valid(part)
    assert volume(part) == pytest.approx(20 * 30 * 2.0 - math.pi * 9 * 2.0, rel=1e-9)


def test_thicken_a_curved_face():
    patch = cagd.BezierSurface(np.array([[(i * 10 / 3, j * 10 / 3, 0.5 * math.sin(i) * math.cos(j))
                                          for j in range(4)] for i in range(4)]))
    face = cq_ext.to_b3d(patch)
    solid = b3d.thicken(face, 0.5)
    assert isinstance(solid, bd.Solid) and check_valid(solid)
    assert volume(solid) == pytest.approx(face.area * 0.5, rel=0.02)     # curvature terms: measured 4e-4


def test_close_with_caps_a_revolution():
    R, r, h = 2.0, 1.0, 3.0
    profile = cagd.BSplineCurve(np.array([[R, 0.0, 0.0], [r, h, 0.0]]), 1)
    face = cq_ext.to_b3d(cagd.revolve(profile, (0, 0, 0), (0, 1, 0)))
    solid = b3d.close_with_caps(face)
    assert isinstance(solid, bd.Solid) and check_valid(solid) and len(solid.faces()) == 3
    assert volume(solid) == pytest.approx(math.pi * h / 3 * (R * R + R * r + r * r), rel=1e-9)


def test_cagd_occ_takes_build123d_shapes(tmp_path):
    with bd.BuildPart() as part:
        bd.Box(2, 3, 4)
    write_step([("box", part), ("face", cq_ext.to_b3d(SURFACES[1]))], tmp_path / "b.step")
    names = [i.name for i in read_step(tmp_path / "b.step")]
    assert len(names) == 7 and "face" in names                # six box faces and the patch
    assert volume(part.part) == pytest.approx(24.0, rel=1e-12) and check_valid(part)


@pytest.mark.parametrize("call, message", [
    (lambda: b3d.sew_solid([bd.Face.make_rect(1, 1), bd.Edge.make_line((0, 0), (1, 0))]),
     r"faces\[1\]: expected a face, got a build123d Edge holding 0 faces"),
    (lambda: b3d.thicken(bd.BuildSketch(), 1.0),
     r"faces\[0\]: expected .* got a build123d BuildSketch holding no shapes"),
    (lambda: b3d.close_with_caps(np.zeros(3)), r"faces\[0\]: expected .* got numpy ndarray"),
    (lambda: cq_ext.from_shape(bd.Solid.make_box(1, 1, 1)),
     r"shape: expected one edge or a face, got a build123d Solid$"),
    (lambda: cq_ext.from_shape(bd.Vector(1, 2, 3)),
     r"shape: expected a CadQuery or build123d shape or a TopoDS_Shape, got a build123d Vector$"),
    (lambda: volume(bd.Part()), r"shape: expected .* got a build123d Part holding no shapes$"),
    (lambda: cq_ext.to_b3d(bd.Face.make_rect(1, 1)), r"obj: expected a cagd Curve or Surface, got a build123d Face$"),
])
def test_refusals_name_library_and_type(call, message):
    with pytest.raises(CagdError, match=f"^{message}"):
        call()


# --- trimmed faces (issue 15) ------------------------------------------------------------------
def _disk(r=0.3, side=2.0):
    """A disk of radius r in (u, v) cut from S(u, v) = (side u, side v, 0): pi (side r)^2."""
    w = math.sqrt(0.5)
    unit = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    loop = cagd.BSplineCurve(unit * r + 0.5, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1],
                             [1, w, 1, w, 1, w, 1, w, 1])
    patch = cagd.BSplineSurface(np.array([[[0, 0, 0], [0, side, 0]], [[side, 0, 0], [side, side, 0]]], float), 1, 1)
    return cagd.TrimmedSurface(patch, [[loop]])


def test_to_b3d_of_a_trimmed_surface_is_a_trimmed_face():
    """pi r^2 by OCCT's BRepGProp to 1e-9, valid, extruded in a BuildPart to area x height."""
    from cagd.occ import area
    face = cq_ext.to_b3d(_disk())
    assert isinstance(face, bd.Face) and check_valid(face.wrapped)
    assert area(face.wrapped) == pytest.approx(math.pi * 0.36, rel=1e-9)
    with bd.BuildPart() as part:
        bd.extrude(face, amount=0.5)
    assert volume(part.part.wrapped) == pytest.approx(math.pi * 0.36 * 0.5, rel=1e-8)
    back = cq_ext.from_shape(face)
    assert isinstance(back, cagd.TrimmedSurface) and back.area() == pytest.approx(math.pi * 0.36, rel=1e-12)


def test_from_shape_of_a_build123d_face_with_a_hole_keeps_the_trim():
    """A 4 x 4 square minus a unit circle: 16 - pi; contains = the point set at S(u, v)."""
    with bd.BuildSketch() as sk:
        bd.Rectangle(4, 4)
        bd.Circle(1, mode=bd.Mode.SUBTRACT)
    (face,) = sk.sketch.faces()
    ts = cq_ext.from_shape(face)
    assert isinstance(ts, cagd.TrimmedSurface) and len(ts.loops) == 2
    assert ts.area() == pytest.approx(16 - math.pi, rel=1e-12)
    (u0, u1), (v0, v1) = ts.domain
    rng = np.random.default_rng(15)
    u, v = u0 + (u1 - u0) * rng.random(3000), v0 + (v1 - v0) * rng.random(3000)
    p = ts(u, v)
    x, y = p[:, 0], p[:, 1]
    far = (np.abs(np.hypot(x, y) - 1) > 1e-6) & (2 - np.maximum(np.abs(x), np.abs(y)) > 1e-6)
    want = (np.maximum(np.abs(x), np.abs(y)) < 2) & (np.hypot(x, y) > 1)
    assert np.array_equal(ts.contains(u, v)[far], want[far]) and 0 < want[far].sum() < far.sum()
