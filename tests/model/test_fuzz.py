"""Property: any JSON-ish input gives either a Model or a ModelError, never another
exception (and never a crash in the engine on input the reader let through)."""
import copy
import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cagd.model import TYPES, Model, ModelError, default_model, load_model, parse_json
from cagd.model.writer import model_to_dict

from model_cases import CASES, REF_A, REF_B, doc, entry

FIELDS = sorted({f for spec in TYPES.values() for f in spec.fields} | {"name", "type", "ref", "solid", "export",
                                                                      "format", "version", "objects", "units"})
WORDS = FIELDS + sorted(TYPES) + ["cagd-model", "A", "B", "X", "mm", "G2", "chord", "natural", "clamped"]

scalars = st.one_of(
    st.none(), st.booleans(),
    st.integers(-5, 12), st.integers(), st.sampled_from([10 ** 400, -10 ** 400]),
    st.floats(-1e3, 1e3), st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([1e308, -1e308, 5e-324]),
    st.sampled_from(WORDS), st.text(max_size=6),
)
junk = st.recursive(scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=6),
    st.dictionaries(st.one_of(st.sampled_from(WORDS), st.text(max_size=4)), inner, max_size=5)), max_leaves=30)

VALID = [doc(REF_A, REF_B, entry("X", t, **fields)) for t, fields, _ in CASES] + [model_to_dict(default_model())]


def paths(value, prefix=()):
    yield prefix
    if isinstance(value, dict):
        for k, v in value.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from paths(v, prefix + (i,))


def outcome(document):
    try:
        result = load_model(document)
    except ModelError as err:
        assert err.path.startswith("$") and str(err).startswith(err.path + ": ")
        return None
    assert isinstance(result, Model)
    return result


@settings(max_examples=300, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(junk)
def test_random_json_values(value):
    outcome(value)


@settings(max_examples=600, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(st.sampled_from(VALID), st.data())
def test_mutated_valid_documents(document, data):
    document = copy.deepcopy(document)
    for _ in range(data.draw(st.integers(1, 3))):
        where = data.draw(st.sampled_from(list(paths(document))[1:]))
        parent = document
        for k in where[:-1]:
            parent = parent[k]
        action = data.draw(st.sampled_from(["replace", "delete", "insert", "perturb"]))
        key = where[-1]
        if action == "replace":
            parent[key] = data.draw(junk)
        elif action == "delete":
            del parent[key]
        elif action == "insert" and isinstance(parent, dict):
            parent[data.draw(st.sampled_from(WORDS))] = data.draw(junk)
        elif action == "insert":
            parent.insert(key, data.draw(junk))
        elif isinstance(parent[key], float) or (type(parent[key]) is int and abs(parent[key]) < 2 ** 53):
            parent[key] = parent[key] * data.draw(st.sampled_from([-1, 0, 0.5, 2, 1e-12, 1e12]))
    outcome(document)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet='{}[]":,0123456789.-eE NaInfity\ntrue', max_size=60))
def test_random_text(text):
    try:
        value = parse_json(text)
    except ModelError as err:
        assert err.path == "$"
        return
    outcome(value)


@pytest.mark.parametrize("document", VALID[:3])
def test_the_mutated_documents_start_valid(document):
    assert outcome(document) is not None
    assert outcome(json.loads(json.dumps(document))) is not None
