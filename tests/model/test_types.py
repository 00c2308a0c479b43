"""Every entry type of the model format builds the same object as the direct engine call
(oracle: the engine constructor with the same arguments), inline and by reference."""
import pytest

import cagd
from cagd.model import TYPES, load_model

from model_cases import CASES, CUBIC, PROFILE, REF_A, REF_B, curve_a, doc, entry, same


def test_every_type_has_a_case():
    assert {c[0] for c in CASES} == set(TYPES)


@pytest.mark.parametrize("type_, fields, direct", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_type_equals_direct_engine_call(type_, fields, direct):
    model = load_model(doc(REF_A, REF_B, entry("X", type_, **fields)))
    got = model["X"]
    assert got.type == type_ and got.path == "$.objects[2]" and got.kind == TYPES[type_].kind
    expected = direct()
    expected = expected if isinstance(expected, list) else [expected]
    assert len(got.objects) == len(expected)
    for a, b in zip(got.objects, expected):
        assert type(a) is type(b)
        same(a, b)


def test_ellipsoid_entry_has_eight_labelled_patches():
    e = load_model(doc(entry("E", "ellipsoid", a=3, b=2, c=1, solid=True)))["E"]
    assert [label for label, _ in e.labels()] == [f"E.{k}" for k in range(8)]
    assert e.solid and e.export


def test_reference_shares_the_object_and_inline_equals_reference():
    m = load_model(doc(REF_A, entry("by_ref", "ruled", c0={"ref": "A"}, c1={"ref": "A"}),
                       entry("inline", "ruled", c0={"type": "bezier_curve", "control_points": CUBIC},
                             c1={"type": "bezier_curve", "control_points": CUBIC})))
    same(m["by_ref"].objects[0], m["inline"].objects[0])


def test_references_chain_through_joins():
    m = load_model(doc(REF_A, entry("J1", "join", curve={"ref": "A"}, continuity="C2", rest_points=[[40, 0, 0]]),
                       entry("J2", "join", curve={"ref": "J1"}, continuity="G1", rest_points=[[50, 0, 0]])))
    j1, j2 = m["J1"].objects[0], m["J2"].objects[0]
    assert cagd.continuity(curve_a, j1).C2 and cagd.continuity(j1, j2).G1


def test_export_flag_and_defaults():
    m = load_model(doc(dict(REF_A, export=False), entry("S", "sphere", radius=1)))
    assert [e.name for e in m.exported()] == ["S"]
    assert m.units == "mm" and m.version == 1 and m.name is None
    assert not m["S"].solid and m["S"].description is None


def test_solid_revolve_with_ends_on_the_axis_and_closed_profile():
    load_model(doc(entry("R", "revolve", profile={"type": "bezier_curve", "control_points": PROFILE}, solid=True)))
    ring = {"type": "bspline_curve", "control_points": [[10, 0, 0], [14, 0, 0], [14, 0, 4], [10, 0, 4]],
            "degree": 3, "periodic": True}
    load_model(doc(entry("T", "revolve", profile=ring, solid=True)))


def test_file_and_dict_give_the_same_model(tmp_path):
    import json
    d = doc(REF_A, entry("S", "sphere", radius=2))
    f = tmp_path / "m.json"
    f.write_text(json.dumps(d))
    a, b = load_model(f), load_model(str(f))
    for x, y in zip(a.entries, b.entries):
        assert x.name == y.name and x.path == y.path
        same(x.objects[0], y.objects[0])


def test_relative_tolerance_key_and_its_old_name():
    """composite and coons: "rel_tol" (relative to the size); the old key "tol" is still
    read with a DeprecationWarning and gives the same object; both together is an error."""
    from cagd.model import ModelError
    a = {"type": "bezier_curve", "control_points": [[0, 0], [1, 0]]}
    b = {"type": "bezier_curve", "control_points": [[1, 2e-4], [2, 1]]}         # gap 2e-4, size ~1.4
    new = load_model(doc(entry("X", "composite", curves=[a, b], rel_tol=1e-3)))["X"].objects[0]
    assert new.rel_tol == 1e-3
    with pytest.warns(DeprecationWarning, match="rel_tol"):
        old = load_model(doc(entry("X", "composite", curves=[a, b], tol=1e-3)))["X"].objects[0]
    assert old.rel_tol == new.rel_tol
    with pytest.raises(ModelError) as err:
        load_model(doc(entry("X", "composite", curves=[a, b], tol=1e-3, rel_tol=1e-3)))
    assert err.value.path == "$.objects[0].tol"
    with pytest.raises(ModelError):                    # the default rel_tol 1e-9 rejects the gap
        load_model(doc(entry("X", "composite", curves=[a, b])))
