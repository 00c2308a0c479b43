"""Invalid documents: each gives a ModelError (a CagdError) at the exact JSON path of the
offending value, with a message starting with that path."""
import copy
import json

import pytest

from cagd import CagdError
from cagd.model import ModelError, load_model, parse_json

CURVE = {"name": "c", "type": "bspline_curve",
         "control_points": [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 5]], "degree": 3}
PROFILE = {"name": "p", "type": "bezier_curve", "control_points": [[0, 0, 10], [8, 0, 5], [0, 0, 0]]}
NET = [[[0, 0, 0], [0, 10, 1], [0, 20, 0]], [[10, 0, 1], [10, 10, 3], [10, 20, 1]]]
BASE = {"format": "cagd-model", "version": 1, "units": "mm", "objects": [CURVE, PROFILE]}


def with_(*entries, **top):
    d = copy.deepcopy(BASE)
    d["objects"].extend(copy.deepcopy(list(entries)))
    d.update(top)
    return d


def mutate(fn):
    d = copy.deepcopy(BASE)
    fn(d)
    return d


def set_in(d, path, value):
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value


def e(type_, name="x", **fields):
    return {"name": name, "type": type_, **fields}


CASES = [
    # header
    ("not an object", [1, 2], "$"),
    ("no format", mutate(lambda d: d.pop("format")), "$.format"),
    ("wrong format", mutate(lambda d: d.update(format="cagd")), "$.format"),
    ("no version", mutate(lambda d: d.pop("version")), "$.version"),
    ("version 99", mutate(lambda d: d.update(version=99)), "$.version"),
    ("version 0", mutate(lambda d: d.update(version=0)), "$.version"),
    ("version as string", mutate(lambda d: d.update(version="1")), "$.version"),
    ("version 1.0", mutate(lambda d: d.update(version=1.0)), "$.version"),
    ("version true", mutate(lambda d: d.update(version=True)), "$.version"),
    ("units inch", mutate(lambda d: d.update(units="inch")), "$.units"),
    ("name not a string", mutate(lambda d: d.update(name=3)), "$.name"),
    ("unknown top-level key", mutate(lambda d: d.update(objets=[])), "$.objets"),
    ("no objects", mutate(lambda d: d.pop("objects")), "$.objects"),
    ("objects not a list", mutate(lambda d: d.update(objects={"a": 1})), "$.objects"),
    ("empty objects", mutate(lambda d: d.update(objects=[])), "$.objects"),
    ("odd key quoted in path", mutate(lambda d: d.update({"my key": 1})), '$["my key"]'),
    # entries
    ("entry not an object", mutate(lambda d: d["objects"].append("sphere")), "$.objects[2]"),
    ("missing type", mutate(lambda d: d["objects"][0].pop("type")), "$.objects[0].type"),
    ("unknown type", mutate(lambda d: set_in(d, ["objects", 0, "type"], "bsline_curve")), "$.objects[0].type"),
    ("type not a string", mutate(lambda d: set_in(d, ["objects", 0, "type"], 7)), "$.objects[0].type"),
    ("missing name", mutate(lambda d: d["objects"][0].pop("name")), "$.objects[0].name"),
    ("empty name", mutate(lambda d: set_in(d, ["objects", 0, "name"], "")), "$.objects[0].name"),
    ("padded name", mutate(lambda d: set_in(d, ["objects", 0, "name"], " c")), "$.objects[0].name"),
    ("duplicate name", with_(e("sphere", name="c", radius=1)), "$.objects[2].name"),
    ("missing required field", mutate(lambda d: d["objects"][0].pop("degree")), "$.objects[0].degree"),
    ("unknown field (typo)", mutate(lambda d: set_in(d, ["objects", 0, "knot"], [0, 1])), "$.objects[0].knot"),
    ("field of another type", with_(e("sphere", radius=1, height=2)), "$.objects[2].height"),
    ("degree a string", mutate(lambda d: set_in(d, ["objects", 0, "degree"], "three")), "$.objects[0].degree"),
    ("degree 0", mutate(lambda d: set_in(d, ["objects", 0, "degree"], 0)), "$.objects[0].degree"),
    ("degree 2.5", mutate(lambda d: set_in(d, ["objects", 0, "degree"], 2.5)), "$.objects[0].degree"),
    ("degree too high (engine)", mutate(lambda d: set_in(d, ["objects", 0, "degree"], 4)), "$.objects[0].degree"),
    ("periodic not a bool", mutate(lambda d: set_in(d, ["objects", 0, "periodic"], 1)), "$.objects[0].periodic"),
    ("solid not a bool", mutate(lambda d: set_in(d, ["objects", 0, "solid"], "yes")), "$.objects[0].solid"),
    ("export not a bool", mutate(lambda d: set_in(d, ["objects", 0, "export"], None)), "$.objects[0].export"),
    ("description not a string", mutate(lambda d: set_in(d, ["objects", 0, "description"], [])),
     "$.objects[0].description"),
    # shapes and numbers
    ("control_points not a list", mutate(lambda d: set_in(d, ["objects", 0, "control_points"], 5)),
     "$.objects[0].control_points"),
    ("a 2-D point among 3-D points", mutate(lambda d: d["objects"][0]["control_points"][3].pop()),
     "$.objects[0].control_points[3]"),
    ("a 4-D first point", mutate(lambda d: d["objects"][0]["control_points"][0].append(1)),
     "$.objects[0].control_points[0]"),
    ("a string coordinate", mutate(lambda d: set_in(d, ["objects", 0, "control_points", 2, 1], "1")),
     "$.objects[0].control_points[2][1]"),
    ("a boolean coordinate", mutate(lambda d: set_in(d, ["objects", 0, "control_points", 1, 0], True)),
     "$.objects[0].control_points[1][0]"),
    ("a point that is a number", mutate(lambda d: set_in(d, ["objects", 0, "control_points", 1], 3)),
     "$.objects[0].control_points[1]"),
    ("one control point", mutate(lambda d: set_in(d, ["objects", 1, "control_points"], [[0, 0, 0]])),
     "$.objects[1].control_points"),
    ("huge integer", mutate(lambda d: set_in(d, ["objects", 0, "control_points", 0, 0], 10 ** 400)),
     "$.objects[0].control_points[0][0]"),
    ("NaN float in a dict", mutate(lambda d: set_in(d, ["objects", 0, "control_points", 0, 2], float("nan"))),
     "$.objects[0].control_points[0][2]"),
    ("non-positive weight", mutate(lambda d: set_in(d, ["objects", 0, "weights"], [1, 1, 0, 1])),
     "$.objects[0].weights[2]"),
    ("negative weight", mutate(lambda d: set_in(d, ["objects", 0, "weights"], [1, -2, 1, 1])),
     "$.objects[0].weights[1]"),
    ("weights miscounted", mutate(lambda d: set_in(d, ["objects", 0, "weights"], [1, 1, 1])),
     "$.objects[0].weights"),
    ("decreasing knots", mutate(lambda d: set_in(d, ["objects", 0, "knots"], [0, 0, 0, 0, 1, 0.5, 1, 1])),
     "$.objects[0].knots[5]"),
    ("knots miscounted (engine)", mutate(lambda d: set_in(d, ["objects", 0, "knots"], [0, 0, 0, 1, 1, 1])),
     "$.objects[0].knots"),
    ("surface weights: a row too short", with_(e("bezier_surface", control_points=NET, weights=[[1, 1, 1], [1, 1]])),
     "$.objects[2].weights[1]"),
    ("surface weight zero", with_(e("bezier_surface", control_points=NET, weights=[[1, 1, 1], [1, 0, 1]])),
     "$.objects[2].weights[1][1]"),
    ("net row of another length", with_(e("bezier_surface", control_points=[NET[0], NET[1][:2]])),
     "$.objects[2].control_points[1]"),
    ("net point 2-D", with_(e("bezier_surface", control_points=[NET[0], NET[1][:2] + [[1, 2]]])),
     "$.objects[2].control_points[1][2]"),
    ("surface net of 2-D points", with_(e("bezier_surface", control_points=[[[0, 0], [1, 0]], [[0, 1], [1, 1]]])),
     "$.objects[2].control_points[0][0]"),
    ("domain reversed (engine)", with_(e("polynomial_curve", coefficients=[[0, 0, 0], [1, 1, 1]], domain=[1, 0])),
     "$.objects[2].domain"),
    ("domain of three numbers", with_(e("polynomial_curve", coefficients=[[0, 0, 0], [1, 1, 1]], domain=[0, 1, 2])),
     "$.objects[2].domain"),
    ("hermite t1 of another dimension", with_(e("hermite_curve", p0=[0, 0], p1=[1, 0], t0=[1, 0], t1=[1, 0, 0])),
     "$.objects[2].t1"),
    ("unknown end condition", with_(e("cubic_spline", points=[[0, 0], [1, 1], [2, 0]], end_condition="free")),
     "$.objects[2].end_condition"),
    ("clamped spline without tangents (engine)",
     with_(e("cubic_spline", points=[[0, 0], [1, 1], [2, 0]], end_condition="clamped")), "$.objects[2].tangents"),
    ("coincident spline points (engine)", with_(e("cubic_spline", points=[[0, 0], [0, 0], [2, 0]])),
     "$.objects[2].points"),
    ("subnormal parameter step: the engine names the parameters",
     with_(e("cubic_spline", points=[[0, 0], [1, 1], [2, 0], [3, 1]], parameters=[0, 5e-324, 3, 4])),
     "$.objects[2].parameters"),
    ("rational net overflowing to inf (w P)",
     with_(e("bezier_triangle", control_points=[[-1e300, 0, 0]] + [[1, 1, 1]] * 9, weights=[1e12] + [1] * 9)),
     "$.objects[2]"),
    ("unknown interpolation parameters", with_(e("interpolate", points=[[0, 0], [1, 1], [2, 0]], parameters="arc")),
     "$.objects[2].parameters"),
    ("negative radius (engine)", with_(e("sphere", radius=-1)), "$.objects[2].radius"),
    ("zero semi-axis (engine)", with_(e("ellipsoid", a=1, b=0, c=1)), "$.objects[2].b"),
    ("zero axis direction (engine)", with_(e("revolve", profile={"ref": "p"}, axis_direction=[0, 0, 0])),
     "$.objects[2].axis_direction"),
    ("axis point with 2 coordinates", with_(e("revolve", profile={"ref": "p"}, axis_point=[0, 0])),
     "$.objects[2].axis_point"),
    ("angle above 2 pi (engine)", with_(e("revolve", profile={"ref": "p"}, angle=7)), "$.objects[2].angle"),
    ("triangle of 4 points (engine)", with_(e("bezier_triangle", control_points=[[0, 0, 0]] * 4)),
     "$.objects[2].control_points"),
    ("coons corners apart (engine, whole entry)",
     with_(e("coons", c0={"ref": "c"}, c1={"ref": "c"}, d0={"ref": "p"}, d1={"ref": "p"})), "$.objects[2]"),
    ("loft of coincident sections (engine)",
     with_(e("loft", sections=[{"ref": "c"}, {"ref": "c"}])), "$.objects[2].sections"),
    ("loft of a single section", with_(e("loft", sections=[{"ref": "c"}])), "$.objects[2].sections"),
    # references
    ("forward reference", with_(e("revolve", profile={"ref": "later"}), e("bezier_curve", name="later",
                                                                          control_points=[[0, 0, 1], [1, 0, 0]])),
     "$.objects[2].profile.ref"),
    ("self reference", with_(e("join", name="j", curve={"ref": "j"})), "$.objects[2].curve.ref"),
    ("unknown reference", with_(e("revolve", profile={"ref": "nope"})), "$.objects[2].profile.ref"),
    ("reference not a string", with_(e("revolve", profile={"ref": 3})), "$.objects[2].profile.ref"),
    ("reference with extra key", with_(e("revolve", profile={"ref": "p", "export": False})),
     "$.objects[2].profile.export"),
    ("reference to a surface", with_(e("sphere", name="s", radius=1), e("revolve", profile={"ref": "s"})),
     "$.objects[3].profile"),
    ("curve field a string", with_(e("revolve", profile="p")), "$.objects[2].profile"),
    ("join of a B-spline", with_(e("join", curve={"ref": "c"})), "$.objects[2].curve"),
    ("inline surface where a curve goes", with_(e("ruled", c0={"ref": "c"}, c1={"type": "sphere", "radius": 1})),
     "$.objects[2].c1"),
    ("inline object with a name", with_(e("ruled", c0={"ref": "c"}, c1=dict(PROFILE))), "$.objects[2].c1.name"),
    ("inline object with a bad field", with_(e("ruled", c0={"ref": "c"}, c1={"type": "bezier_curve",
                                                                           "control_points": [[0, 0, 0], [1, 2]]})),
     "$.objects[2].c1.control_points[1]"),
    ("2-D profile (engine)", with_(e("revolve", profile={"type": "bezier_curve", "control_points": [[1, 0], [2, 1]]})),
     "$.objects[2].profile"),
    ("loft section of wrong kind", with_(e("loft", sections=[{"ref": "c"}, 5])), "$.objects[2].sections[1]"),
    ("composite with a gap (engine)", with_(e("composite", curves=[{"ref": "c"}, {"ref": "p"}])),
     "$.objects[2].curves"),
    # solids
    ("solid on a curve", mutate(lambda d: set_in(d, ["objects", 0, "solid"], True)), "$.objects[0].solid"),
    ("solid on an open surface", with_(e("bezier_surface", control_points=NET, solid=True)), "$.objects[2].solid"),
    ("solid on a cylinder", with_(e("cylinder", radius=1, height=2, solid=True)), "$.objects[2].solid"),
    ("solid revolve of a partial turn", with_(e("revolve", profile={"ref": "p"}, angle=3, solid=True)),
     "$.objects[2].solid"),
    ("solid revolve of 6.28318 radians", with_(e("revolve", profile={"ref": "p"}, angle=6.28318, solid=True)),
     "$.objects[2].solid"),
    ("solid revolve with an end off the axis", with_(e("revolve", profile={"ref": "c"}, solid=True)),
     "$.objects[2].solid"),
]


@pytest.mark.parametrize("document, path", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_invalid_document_names_the_path(document, path):
    with pytest.raises(ModelError) as info:
        load_model(document)
    err = info.value
    assert isinstance(err, CagdError) and isinstance(err, ValueError)
    assert err.path == path, str(err)
    assert str(err).startswith(path + ": ") and err.reason and str(err) == f"{err.path}: {err.reason}"


def test_the_base_document_is_valid():
    assert [x.name for x in load_model(BASE).entries] == ["c", "p"]


MESSAGES = [
    (mutate(lambda d: set_in(d, ["objects", 0, "degree"], "three")),
     '$.objects[0].degree: must be an integer >= 1, got "three"'),
    (mutate(lambda d: d.update(version=99)), "reads version 1 of the cagd-model format"),
    (mutate(lambda d: set_in(d, ["objects", 0, "knot"], [0])), "did you mean 'knots'?"),
    (mutate(lambda d: set_in(d, ["objects", 0, "type"], "bsline_curve")), "did you mean 'bspline_curve'?"),
    (with_(e("revolve", profile={"ref": "later"}), e("sphere", name="later", radius=1)),
     "'later' is defined later ($.objects[3])"),
    (mutate(lambda d: set_in(d, ["objects", 0, "knots"], [0, 0, 0, 1, 1, 1])), "expected 8 values"),
]


@pytest.mark.parametrize("document, text", MESSAGES)
def test_messages(document, text):
    with pytest.raises(ModelError, match=None) as info:
        load_model(document)
    assert text in str(info.value)


TEXTS = [
    ("NaN literal", '{"format": "cagd-model", "version": 1, "objects": [{"name": "s", "type": "sphere", '
                    '"radius": NaN}]}', "$.objects[0].radius"),
    ("Infinity literal", '{"format": "cagd-model", "version": 1, "objects": [{"name": "s", "type": "sphere", '
                         '"radius": 1, "center": [0, -Infinity, 0]}]}', "$.objects[0].center[1]"),
    ("1e400 overflows to inf", '{"format": "cagd-model", "version": 1, "objects": [{"name": "s", "type": '
                               '"sphere", "radius": 1e400}]}', "$.objects[0].radius"),
    ("duplicate key", '{"format": "cagd-model", "version": 1, "objects": [{"name": "s", "type": "sphere", '
                      '"radius": 1, "radius": 2}]}', "$.objects[0].radius"),
    ("syntax error", '{"format": "cagd-model",\n "version": 1,,}', "$"),
    ("trailing comma", '{"format": "cagd-model", "version": 1, "objects": [],}', "$"),
    ("empty text", "", "$"),
    ("deep nesting", "[" * 100000 + "]" * 100000, "$"),
    ("javascript comment", '// model\n{"format": "cagd-model"}', "$"),
]


@pytest.mark.parametrize("text, path", [t[1:] for t in TEXTS], ids=[t[0] for t in TEXTS])
def test_invalid_text(text, path, tmp_path):
    f = tmp_path / "model.json"
    f.write_text(text)
    with pytest.raises(ModelError) as info:
        load_model(f)
    assert info.value.path == path, str(info.value)


def test_syntax_error_reports_line_and_column():
    with pytest.raises(ModelError, match=r"^\$: not valid JSON: .* at line 2, column 15$"):
        parse_json('{"format": "cagd-model",\n "version": 1,,}')


def test_missing_file_and_binary_file(tmp_path):
    with pytest.raises(ModelError, match="cannot read"):
        load_model(tmp_path / "absent.json")
    f = tmp_path / "bin.json"
    f.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(ModelError, match="not UTF-8"):
        load_model(f)


def test_python_values_that_are_not_json():
    import numpy as np
    d = mutate(lambda d: set_in(d, ["objects", 0, "control_points"], np.zeros((4, 3))))
    with pytest.raises(ModelError) as info:
        load_model(d)
    assert info.value.path == "$.objects[0].control_points"
    cyclic = mutate(lambda d: None)
    cyclic["objects"][0]["weights"] = cyclic["objects"]
    with pytest.raises(ModelError, match="levels deep"):
        load_model(cyclic)


def test_data_is_never_executed(tmp_path):
    """A string that looks like code is only ever a string: it fails as a number."""
    marker = tmp_path / "executed"
    code = f"__import__('pathlib').Path({str(marker)!r}).write_text('x')"
    d = mutate(lambda d: set_in(d, ["objects", 0, "degree"], code))
    with pytest.raises(ModelError):
        load_model(json.loads(json.dumps(d)))
    assert not marker.exists()


def test_error_pickles():
    import pickle
    err = ModelError("$.objects[0]", "bad")
    back = pickle.loads(pickle.dumps(err))
    assert back.path == err.path and str(back) == str(err)
