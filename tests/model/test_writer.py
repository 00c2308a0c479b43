"""Writing engine objects as model entries and reading them back: the data round-trips
bit for bit (floats are written with their shortest round-trip repr)."""
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd
from cagd.model import (ModelError, default_model, dump_model, dumps, entry_dict, load_model, model_to_dict,
                        objects_to_dict, parse_json)
from strategies import bspline_curves, coordinates, point_arrays, positive_weights
from surface_strategies import bezier_surfaces, bspline_surfaces

from model_cases import sample


def round_trip(obj):
    text = dumps(objects_to_dict([("x", obj)]))
    return load_model(parse_json(text))["x"].objects[0]


def assert_identical(a, b):
    assert type(a) is type(b)
    for attr in ("control_points", "weights", "knots", "knots_u", "knots_v"):
        x, y = getattr(a, attr, None), getattr(b, attr, None)
        assert (x is None) == (y is None), attr
        if x is not None:
            assert np.array_equal(x, y), attr
    for attr in ("degree", "degree_u", "degree_v", "periodic", "periodic_u", "periodic_v", "dim"):
        assert getattr(a, attr, None) == getattr(b, attr, None), attr
    assert np.array_equal(sample(a), sample(b))


@settings(max_examples=60, deadline=None)
@given(bspline_curves(dims=(2, 3)))
def test_bspline_curve_round_trip(curve):
    assert_identical(round_trip(curve), curve)


@st.composite
def bezier_curves(draw):
    n, dim = draw(st.integers(1, 8)), draw(st.integers(2, 3))
    P = draw(point_arrays(n + 1, dim))
    w = draw(st.none() | st.lists(positive_weights, min_size=n + 1, max_size=n + 1))
    return cagd.BezierCurve(P, w)


@st.composite
def triangles(draw):
    n = draw(st.integers(1, 5))
    count = (n + 1) * (n + 2) // 2
    P = draw(point_arrays(count, 3))
    w = draw(st.none() | st.lists(positive_weights, min_size=count, max_size=count))
    return cagd.BezierTriangle(P, w)


@settings(max_examples=40, deadline=None)
@given(bezier_curves())
def test_bezier_curve_round_trip(curve):
    assert_identical(round_trip(curve), curve)


@settings(max_examples=40, deadline=None)
@given(bspline_surfaces(dims=(3, 3)))
def test_bspline_surface_round_trip(surface):
    assert_identical(round_trip(surface), surface)


@settings(max_examples=30, deadline=None)
@given(bezier_surfaces(dims=(3, 3)))
def test_bezier_surface_round_trip(surface):
    assert_identical(round_trip(surface), surface)


@settings(max_examples=30, deadline=None)
@given(triangles())
def test_bezier_triangle_round_trip(tri):
    assert_identical(round_trip(tri), tri)


def test_entry_types_written():
    assert entry_dict("a", cagd.BezierCurve([[0, 0], [1, 1]]))["type"] == "bezier_curve"
    assert entry_dict("a", cagd.BSplineCurve([[0, 0], [1, 1], [2, 0]], 2))["type"] == "bspline_curve"
    assert entry_dict("a", cagd.sphere(1.0))["type"] == "bspline_surface"
    assert entry_dict("a", cagd.ellipsoid_octant(3, 2, 1))["type"] == "bezier_surface"
    d = entry_dict("a", cagd.BSplineCurve([[0, 0], [1, 1], [2, 0]], 2, weights=[1, 2, 1]), export=False,
                   description="helper")
    assert d["export"] is False and d["description"] == "helper" and d["weights"] == [1.0, 2.0, 1.0]


@pytest.mark.parametrize("obj", [
    cagd.natural_cubic_spline([[0, 0, 0], [1, 2, 0], [3, 1, 1], [4, 0, 0]]),
    cagd.HermiteCurve([0, 0], [1, 0], [0, 1], [1, 1]),
    cagd.CoonsPatch(cagd.BezierCurve([[0, 0, 0], [1, 0, 1]]), cagd.BezierCurve([[0, 1, 0], [1, 1, 0]]),
                    cagd.BezierCurve([[0, 0, 0], [0, 1, 0]]), cagd.BezierCurve([[1, 0, 1], [1, 1, 0]])),
], ids=["cubic_spline", "hermite", "coons"])
def test_other_objects_are_written_as_their_nurbs_form(obj):
    back = round_trip(obj)
    assert_identical(back, obj.to_nurbs())


def test_entry_dict_rejects_what_the_format_cannot_hold():
    with pytest.raises(cagd.CagdError, match="1-D"):
        entry_dict("a", cagd.BezierCurve([0.0, 1.0, 3.0]))
    with pytest.raises(cagd.CagdError, match="surfaces"):
        entry_dict("a", cagd.BezierSurface(np.zeros((2, 2, 2))))
    with pytest.raises(cagd.CagdError, match="obj"):
        entry_dict("a", [[0, 0, 0]])
    with pytest.raises(cagd.CagdError, match="name"):
        entry_dict("", cagd.BezierCurve([[0, 0], [1, 1]]))


def test_model_to_dict_round_trips_a_loaded_model(tmp_path):
    model = default_model()
    f = tmp_path / "copy.json"
    dump_model(model, f)
    again = load_model(f)
    assert model_to_dict(again) == model_to_dict(model)
    for a, b in zip(model.entries, again.entries):
        assert (a.name, a.type, a.solid, a.export, a.path) == (b.name, b.type, b.solid, b.export, b.path)
        for x, y in zip(a.objects, b.objects):
            assert np.array_equal(sample(x), sample(y))


def test_dumps_is_plain_json_with_points_on_one_line():
    text = dumps(objects_to_dict({"c": cagd.BezierCurve([[0, 0, 0], [1.5, 2, 0.1]])}, name="n"))
    assert "[1.5, 2.0, 0.1]" in text
    assert json.loads(text)["name"] == "n"


def test_source_keeps_references():
    doc = json.loads(dumps(model_to_dict(default_model())))
    knob = next(o for o in doc["objects"] if o["name"] == "knob")
    assert knob["profile"] == {"ref": "knob_profile"}


def test_written_entries_are_validated_on_reading():
    doc = objects_to_dict({"c": cagd.BezierCurve([[0, 0, 0], [1, 2, 0]])})
    doc["objects"][0]["weights"] = [1.0, -1.0]
    with pytest.raises(ModelError) as info:
        load_model(doc)
    assert info.value.path == "$.objects[0].weights[1]"


@settings(max_examples=20, deadline=None)
@given(st.lists(coordinates, min_size=6, max_size=6))
def test_written_floats_are_exact(xs):
    c = cagd.BezierCurve(np.array(xs).reshape(2, 3))
    assert np.array_equal(round_trip(c).control_points, c.control_points)
