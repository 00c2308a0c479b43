"""Issue 14, the model format: names that would break a STEP/IGES file, integers Python
cannot convert, and dump_model's atomic write."""
import copy
import errno
import os

import pytest

from cagd import CagdError
from cagd._validate import MAX_NAME_LENGTH
from cagd.model import ModelError, dump_model, dumps, entry_dict, load_model, parse_json
from cagd.model._read import MAX_INT_DIGITS

CURVE = {"name": "c", "type": "bezier_curve", "control_points": [[0, 0, 0], [1, 2, 0], [3, 1, 1]]}
DOC = {"format": "cagd-model", "version": 1, "units": "mm", "objects": [CURVE]}


def named(name):
    d = copy.deepcopy(DOC)
    d["objects"][0]["name"] = name
    return d


@pytest.mark.parametrize("name, words", [("a\nb", "control character"), ("a\x00b", "control character"),
                                         ("x\ud800", "surrogate"), ("n" * (MAX_NAME_LENGTH + 1), "at most 255"),
                                         ("line\u2028sep", "control character")])
def test_the_loader_refuses_names_that_break_files(name, words):
    """The loader accepted "a\\nb" (then cagd export wrote a broken IGES file that OCCT
    died reading) and "\\ud800" (a raw TypeError in write_step)."""
    with pytest.raises(ModelError, match=words) as info:
        load_model(named(name))
    assert info.value.path == "$.objects[0].name"
    with pytest.raises(CagdError, match=words):
        entry_dict(name, load_model(DOC)["c"].objects[0])


def test_the_longest_allowed_name_loads():
    assert load_model(named("n" * MAX_NAME_LENGTH))["n" * MAX_NAME_LENGTH].name == "n" * MAX_NAME_LENGTH


def test_an_integer_of_more_than_4300_digits_is_a_model_error_at_its_path():
    """json.loads raised a raw ValueError (Python's int conversion limit)."""
    text = dumps(DOC).replace('"version": 1', '"version": 1' + "0" * MAX_INT_DIGITS)
    with pytest.raises(ModelError, match=f"integer of {MAX_INT_DIGITS + 1} digits") as info:
        load_model(parse_json(text))
    assert info.value.path == "$.version"
    big = dumps(DOC).replace("[3, 1, 1]", "[3, 1, " + "7" * (MAX_INT_DIGITS + 5) + "]")
    with pytest.raises(ModelError) as info:
        load_model(parse_json(big))
    assert info.value.path == "$.objects[0].control_points[2][2]"
    edge = dumps(DOC).replace("[3, 1, 1]", "[3, 1, -" + "9" * MAX_INT_DIGITS + "]")   # 4,300 digits: converted
    with pytest.raises(ModelError, match="too large for float64") as info:
        load_model(parse_json(edge))
    assert info.value.path == "$.objects[0].control_points[2][2]"


def test_dump_model_is_atomic(tmp_path, monkeypatch):
    """On a full disk dump_model left a fragment with a raw OSError."""
    target = tmp_path / "m.json"
    dump_model(DOC, target)
    before = target.read_bytes()

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr("cagd._atomic.os.fsync", full)
    with pytest.raises(CagdError, match="m.json.*No space left"):
        dump_model(named("other"), target)
    monkeypatch.undo()
    assert target.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == ["m.json"]
    with pytest.raises(CagdError, match="does not exist"):
        dump_model(DOC, tmp_path / "missing" / "m.json")
    with pytest.raises(CagdError, match="doc: cannot be written as JSON"):
        dump_model({"x": float("nan")}, tmp_path / "n.json")
    assert load_model(target)["c"].name == "c"


def test_unreadable_model_paths_are_model_errors(tmp_path):
    """A NUL in the path was a raw ValueError from pathlib."""
    with pytest.raises(ModelError, match="embedded null byte"):
        load_model(str(tmp_path / "a\x00b.json"))
    with pytest.raises(ModelError, match="cannot read"):
        load_model(tmp_path)
