"""The built-in default model of `cagd demo` and the example model files load, and show
what they promise (oracles: the engine's own continuity and the geometry of each item)."""
import json
from pathlib import Path

import numpy as np
import pytest

import cagd
from cagd.model import DEFAULT_MODEL_PATH, TYPES, default_model, load_model

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples" / "models").glob("*.json"))


def test_default_model_has_the_six_items():
    m = default_model()
    assert m.units == "mm" and m.version == 1
    kinds = [(e.name, e.type, e.solid, e.export) for e in m.entries]
    assert kinds == [
        ("ellipsoid", "ellipsoid", True, True),
        ("bicubic_patch", "bezier_surface", False, True),
        ("knob_profile", "cubic_spline", False, False),
        ("knob", "revolve", True, True),
        ("corner_triangle", "bezier_triangle", False, True),
        ("coons_patch", "coons", False, True),
        ("g2_curve_1", "bezier_curve", False, True),
        ("g2_curve_2", "join", False, True),
    ]


def test_default_ellipsoid_is_the_seed_ellipsoid():
    patches = default_model()["ellipsoid"].objects
    assert len(patches) == 8
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 9))
    for s in patches:
        x, y, z = np.moveaxis(s(u, v), -1, 0)
        assert np.allclose((x / 30) ** 2 + (y / 20) ** 2 + (z / 15) ** 2, 1.0, atol=1e-13)


def test_default_patch_is_bicubic():
    s = default_model()["bicubic_patch"].objects[0]
    assert (s.degree_u, s.degree_v) == (3, 3) and s.weights is None


def test_default_profile_is_a_natural_spline_ending_on_the_axis_and_revolved_fully():
    m = default_model()
    profile = m["knob_profile"].objects[0]
    assert profile.end_condition == "natural" and len(profile.points) == 6
    assert np.all(profile.points[:, 1] == 0.0)                 # x-z plane
    assert profile.points[0, 0] == 0.0 and profile.points[-1, 0] == 0.0
    a, b = profile.domain
    assert np.allclose(profile.derivative(np.array([a, b]), 2), 0.0, atol=1e-12)   # natural ends
    t = np.linspace(a, b, 401)[1:-1]
    assert np.all(profile(t)[:, 0] > 0.0)                      # never crosses the axis
    knob = m["knob"].objects[0]
    (u0, u1), (v0, v1) = knob.domain
    uu, vv = np.meshgrid(np.linspace(u0, u1, 11), np.linspace(v0, v1, 13))
    p = knob(uu, vv)
    r = np.hypot(p[..., 0], p[..., 1])
    prof = profile(np.linspace(a, b, 11))
    assert np.allclose(r, np.abs(prof[:, 0])[None, :], atol=1e-12)
    assert np.allclose(p[..., 2], prof[:, 2][None, :], atol=1e-12)


def test_default_triangle_is_cubic_with_ten_points():
    t = default_model()["corner_triangle"].objects[0]
    assert isinstance(t, cagd.BezierTriangle) and t.degree == 3 and len(t.control_points) == 10


def test_default_coons_patch_interpolates_its_boundaries():
    doc = json.loads(DEFAULT_MODEL_PATH.read_text())
    src = next(o for o in doc["objects"] if o["name"] == "coons_patch")
    s = default_model()["coons_patch"].objects[0]
    t = np.linspace(0, 1, 17)
    c0 = cagd.BezierCurve(src["c0"]["control_points"])
    d1 = cagd.BezierCurve(src["d1"]["control_points"])
    assert np.allclose(s(t, 0 * t), c0(t), atol=1e-12)
    assert np.allclose(s(1 + 0 * t, t), d1(t), atol=1e-12)


def test_default_curve_pair_is_g2():
    m = default_model()
    a, b = m["g2_curve_1"].objects[0], m["g2_curve_2"].objects[0]
    assert a.degree == 3 and b.degree == 3
    report = cagd.continuity(a, b)
    assert report.G2 and not report.C1


def test_default_items_do_not_overlap():
    """Laid out side by side: the bounding boxes of the control nets are disjoint."""
    boxes = []
    for e in default_model().exported():
        if e.name.startswith("g2_curve"):
            continue
        pts = np.concatenate([o.to_nurbs().control_points.reshape(-1, 3) for o in e.objects])
        boxes.append((e.name, pts.min(axis=0), pts.max(axis=0)))
    for i, (na, lo_a, hi_a) in enumerate(boxes):
        for nb, lo_b, hi_b in boxes[i + 1:]:
            assert np.any(hi_a < lo_b) or np.any(hi_b < lo_a), (na, nb)


def test_default_model_is_installed_as_package_data():
    """Declared as package data (the wheel's contents: tests/test_packaging.py)."""
    setup = (ROOT / "setup.py").read_text()
    assert '"cagd.model": ["*.json"]' in setup


def test_there_are_examples():
    assert len(EXAMPLES) >= 3


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_example_model_loads(path):
    m = load_model(path)
    assert m.entries and all(e.objects for e in m.entries)


def test_default_and_examples_show_every_type():
    used = {e.type for e in default_model().entries}
    for path in EXAMPLES:
        used |= {e.type for e in load_model(path).entries}
        used |= {o["type"] for e in json.loads(path.read_text())["objects"] for v in e.values()
                 for o in (v if isinstance(v, list) else [v]) if isinstance(o, dict) and "type" in o}
    assert used == set(TYPES)


def test_the_example_in_the_docs_loads():
    text = (ROOT / "docs" / "model-format.md").read_text()
    block = text.split("```json\n", 1)[1].split("```", 1)[0]
    m = load_model(json.loads(block))
    assert [(e.name, e.solid, e.export) for e in m.entries] == [("profile", False, False), ("knob", True, True),
                                                                 ("lid", False, True)]
    profile = m["profile"].objects[0]
    t = np.linspace(*profile.domain, 401)[1:-1]
    assert np.all(profile(t)[:, 0] > 0.0)


def test_the_docs_list_every_type():
    text = (ROOT / "docs" / "model-format.md").read_text()
    for name in TYPES:
        assert f"`{name}`" in text, name
