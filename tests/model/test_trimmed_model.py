"""The model format's trimmed_surface (issue 15): entries build the engine's
TrimmedSurface (oracle: the direct constructor; areas against closed forms), errors name
the JSON path, dump -> load gives bit-identical loops and equal area and classification,
and `cagd export` writes a STEP whose face read back (cagd.occ.read_step) has the
engine's area to 1e-9."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from cagd import CagdError, TrimmedSurface
from cagd.model import ModelError, dumps, entry_dict, load_model, objects_to_dict, parse_json

from model_cases import CIRCLE_UV, doc, entry

EXAMPLE = Path(__file__).parents[2] / "examples" / "models" / "trimmed.json"
SHEET = {"type": "bspline_surface", "degree_u": 1, "degree_v": 1,
         "control_points": [[[0, 0, 0], [0, 20, 0]], [[20, 0, 0], [20, 20, 0]]]}     # S = (20 u, 20 v, 0)
DISK = [[{"type": "bspline_curve", **CIRCLE_UV}]]                                     # center (0.5, 0.5), r 0.3
RNG = np.random.default_rng(1515)


def line(a, b):
    return {"type": "bspline_curve", "degree": 1, "control_points": [a, b]}


def square(u0, u1, v0, v1):
    return [line([u0, v0], [u1, v0]), line([u1, v0], [u1, v1]), line([u1, v1], [u0, v1]), line([u0, v1], [u0, v0])]


def trimmed(**fields):
    return entry("T", "trimmed_surface", **{"surface": SHEET, "loops": DISK, **fields})


def test_disk_on_a_plane_has_the_closed_form_area_and_contains_the_disk():
    ts = load_model(doc(trimmed()))["T"].objects[0]
    assert isinstance(ts, TrimmedSurface)
    assert ts.area() == pytest.approx(math.pi * (20 * 0.3) ** 2, rel=1e-13)
    u, v = RNG.random(20_000), RNG.random(20_000)
    d = np.hypot(u - 0.5, v - 0.5) - 0.3
    far = np.abs(d) > 1e-9
    assert np.array_equal(ts.contains(u, v)[far], d[far] < 0)


def test_surface_by_reference_and_a_hole():
    """An annulus: the sheet by reference, a square outer loop given clockwise (the engine
    reverses it: reoriented) and the disk as a hole given counter-clockwise (reversed too)."""
    outer = square(0.1, 0.9, 0.1, 0.9)[::-1]
    outer = [line(c["control_points"][1], c["control_points"][0]) for c in outer]       # clockwise
    m = load_model(doc(dict(SHEET, name="sheet", export=False), entry("A", "trimmed_surface", surface={"ref": "sheet"},
                                                                     loops=[outer, DISK[0]])))
    ts = m["A"].objects[0]
    assert ts.reoriented == (0, 1)
    assert ts.area() == pytest.approx(400 * (0.8 ** 2 - math.pi * 0.09), rel=1e-13)
    assert ts.surface is m["sheet"].objects[0]
    assert [e.name for e in m.exported()] == ["A"]


def test_dump_then_load_gives_the_same_trimmed_surface():
    """Bit-identical surface, loops and tol; so the same area and classification."""
    for obj in [load_model(doc(trimmed()))["T"].objects[0]] + [e.objects[0] for e in load_model(EXAMPLE).entries
                                                              if e.type == "trimmed_surface"]:
        back = load_model(parse_json(dumps(objects_to_dict([("x", obj)]))))["x"].objects[0]
        assert type(back) is TrimmedSurface and back.tol == obj.tol and back.reoriented == ()
        assert np.array_equal(back.surface.to_nurbs().control_points, obj.surface.to_nurbs().control_points)
        assert [len(lp) for lp in back.loops] == [len(lp) for lp in obj.loops]
        for a, b in zip([c for lp in back.loops for c in lp], [c for lp in obj.loops for c in lp]):
            assert np.array_equal(a.control_points, b.control_points) and np.array_equal(a.knots, b.knots)
            assert (a.weights is None and b.weights is None) or np.array_equal(a.weights, b.weights)
        assert back.area() == obj.area()
        (u0, u1), (v0, v1) = obj.domain
        u, v = u0 + (u1 - u0) * RNG.random(5000), v0 + (v1 - v0) * RNG.random(5000)
        assert np.array_equal(back.classify(u, v), obj.classify(u, v))


def test_edge_curves_are_dropped_by_the_model_format():
    """The model format's trimmed_surface has no edge curves: a face with edges (read from
    a file, or given) dumps its surface, loops and tol, and loads back without edges
    (boundary() then composes S(c(t)) exactly)."""
    from cagd import BSplineCurve
    from trim_shapes import circle3d
    ts = load_model(doc(trimmed()))["T"].objects[0]
    edge = circle3d((10.0, 10.0, 0.0), 6.0)
    withe = TrimmedSurface(ts.surface, ts.loops, ts.tol, edges=[[edge]])
    assert isinstance(withe.edges[0][0], BSplineCurve)
    d = entry_dict("t", withe)
    assert "edges" not in d and d == entry_dict("t", ts)
    back = load_model(parse_json(dumps(objects_to_dict([("x", withe)]))))["x"].objects[0]
    assert back.edges is None and back.boundary().source == (("composition",),)
    assert np.abs(back.boundary().curves[0][0](np.linspace(0, 1, 9)) - edge(np.linspace(0, 1, 9))).max() <= 1e-12


def test_entry_dict_writes_the_trim_not_the_untrimmed_nurbs():
    ts = load_model(doc(trimmed()))["T"].objects[0]
    d = entry_dict("t", ts)
    assert d["type"] == "trimmed_surface" and d["surface"]["type"] == "bspline_surface"
    assert [[c["type"] for c in lp] for lp in d["loops"]] == [["bspline_curve"]]
    assert all(len(p) == 2 for p in d["loops"][0][0]["control_points"])
    json.dumps(d, allow_nan=False)


@pytest.mark.parametrize("fields, path, words", [
    (dict(loops="circle"), "$.objects[0].loops", "array of loops"),
    (dict(loops=[]), "$.objects[0].loops", "at least 1"),
    (dict(loops=[[]]), "$.objects[0].loops[0]", "at least 1"),
    (dict(loops=[DISK[0] + [3]]), "$.objects[0].loops[0][1]", "must be a curve"),
    (dict(loops=[[{"type": "bezier_curve", "control_points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]]}]]),
     "$.objects[0].loops[0][0]", "must be 2-D"),
    (dict(loops=[square(0.1, 0.9, 0.1, 0.9)[:3]]), "$.objects[0].loops[0][2]", "gap"),
    (dict(loops=[square(0.1, 1.5, 0.1, 0.9)]), "$.objects[0].loops[0][0]", "domain"),
    (dict(loops=[square(0.1, 0.9, 0.1, 0.9), square(0.5, 1.0, 0.2, 0.4)]), "$.objects[0]", "cross"),
    (dict(tol=-1), "$.objects[0].tol", "positive"),
    (dict(surface={"ref": "nothing"}), "$.objects[0].surface.ref", "no entry"),
    (dict(surface=[1, 2]), "$.objects[0].surface", "must be a surface"),
    (dict(surface={"type": "bezier_curve", "control_points": [[0, 0, 0], [1, 1, 1]]}), "$.objects[0].surface",
     "curve"),
    (dict(surface={"type": "ellipsoid", "a": 3, "b": 2, "c": 1}), "$.objects[0].surface", "8 patches"),
    (dict(surface={"type": "trimmed_surface", "surface": SHEET, "loops": DISK}), "$.objects[0].surface",
     "already trimmed"),
    (dict(surface={"type": "bezier_triangle", "control_points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}),
     "$.objects[0].surface", "triangle"),
    (dict(surface={"type": "sphere", "radius": 1, "name": "s"}), "$.objects[0].surface.name", "inline"),
    (dict(solid=True), "$.objects[0].solid", "does not bound a volume"),
])
def test_errors_name_the_json_path(fields, path, words):
    with pytest.raises(ModelError) as info:
        load_model(doc(trimmed(**fields)))
    assert info.value.path.startswith(path), str(info.value)
    assert words in str(info.value), str(info.value)
    assert isinstance(info.value, CagdError)


def test_a_reference_to_a_curve_or_to_a_trimmed_entry_is_refused():
    for ref, words in (("c", "curve"), ("T", "already trimmed")):
        d = doc(entry("c", "bspline_curve", degree=1, control_points=[[0, 0, 0], [1, 0, 0]]), trimmed(),
                entry("U", "trimmed_surface", surface={"ref": ref}, loops=DISK))
        with pytest.raises(ModelError, match=words) as info:
            load_model(d)
        assert info.value.path == "$.objects[2].surface"


# --- cagd export ---------------------------------------------------------------------------------
def test_cagd_export_writes_trimmed_faces_that_read_back_with_their_area(tmp_path):
    pytest.importorskip("OCP")
    from cagd.cli import main
    from cagd.occ import read_iges, read_step
    step, iges, report = tmp_path / "t.step", tmp_path / "t.igs", tmp_path / "r.md"
    assert main(["export", str(EXAMPLE), "-o", str(step), "--iges", str(iges), "--report", str(report),
                 "--no-progress"]) == 0
    text = report.read_text()
    assert "**all checks passed**" in text and text.count(" trim ") == 6 and "**NO**" not in text
    engine = [e.objects[0] for e in load_model(EXAMPLE).exported()]
    for read in (read_step, read_iges):
        back = [i.object for i in read(step if read is read_step else iges)]
        assert len(back) == len(engine) == 2
        for ts, b in zip(engine, back):
            assert isinstance(b, TrimmedSurface)
            assert b.area() == pytest.approx(ts.area(), rel=1e-9)
