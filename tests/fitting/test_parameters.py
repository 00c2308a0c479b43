"""One option for parametrising points: ``parameters=`` with the names of
cagd.fitting.PARAMETERS, listed once, validated in one place; the old keywords
``method=`` and ``parametrization=`` still work for one release, with a warning."""
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import cagd
from cagd.fitting import PARAMETERS, spline_parameters
from cagd.model import ModelError, load_model
from cagd.surfaces import loft_parameters, surface_parameters

ROOT = Path(__file__).resolve().parents[2]
P = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 13.0], [7.0, 14.0], [9.0, 9.0]])
GRID = np.stack(np.meshgrid(np.linspace(0, 3, 4), np.array([0.0, 1.0, 3.0]), indexing="ij"), axis=-1)
GRID = np.concatenate([GRID, np.sin(GRID[..., :1])], axis=-1)
SECTIONS = [cagd.BezierCurve([[0, 0, z], [1, 2, z], [3, 0, z]]) for z in (0.0, 1.0, 3.0, 3.5)]

# every function that parametrises points, called with a parametrisation name
CALLS = {
    "parametrize": lambda name: cagd.parametrize(P, name),
    "bezier_through_points": lambda name: cagd.bezier_through_points(P, name),
    "interpolate": lambda name: cagd.interpolate(P, 3, name),
    "approximate": lambda name: cagd.approximate(P, 4, 2, name),
    "natural_cubic_spline": lambda name: cagd.natural_cubic_spline(P, "natural", name),
    "CubicSpline": lambda name: cagd.CubicSpline(P, parameters=name),
    "HermiteSpline": lambda name: cagd.HermiteSpline(P, np.ones_like(P), name),
    "spline_parameters": lambda name: spline_parameters(P, name),
    "surface_parameters": lambda name: surface_parameters(GRID, name),
    "interpolate_surface": lambda name: cagd.interpolate_surface(GRID, 2, 2, name),
    "loft_parameters": lambda name: loft_parameters(SECTIONS, name),
    "loft": lambda name: cagd.loft(SECTIONS, 2, name),
}


@pytest.mark.parametrize("func", sorted(CALLS))
def test_every_parametrising_function_lists_exactly_the_names(func):
    with pytest.raises(cagd.CagdError) as err:
        CALLS[func]("arc_length")
    msg = str(err.value)
    assert msg.startswith("parameters:") and "'arc_length'" in msg
    assert str(PARAMETERS) in msg
    for name in PARAMETERS:                         # and each of them is accepted
        CALLS[func](name)


def test_the_names_are_listed_once_in_the_sources():
    """No second copy of the list anywhere in the engine or the workbench: a literal
    sequence of the three names (in any order) occurs in one file only."""
    names = "|".join(PARAMETERS)
    literal = re.compile(r"[\(\[]\s*(['\"](%s)['\"]\s*,\s*){2}['\"](%s)['\"]" % (names, names))
    files = [p for d in ("cagd", "workbench/cagdwb") for p in (ROOT / d).rglob("*.py")
             if literal.search(p.read_text())]
    assert [p.relative_to(ROOT).as_posix() for p in files] == ["cagd/fitting/parameters.py"]
    assert PARAMETERS == ("uniform", "chord", "centripetal")


def test_the_model_format_lists_the_same_names():
    doc = {"format": "cagd-model", "version": 1, "objects": [
        {"name": "c", "type": "interpolate", "points": P.tolist(), "parameters": "arc_length"}]}
    with pytest.raises(ModelError) as err:
        load_model(doc)
    assert err.value.path == "$.objects[0].parameters"
    assert ", ".join(f'"{n}"' for n in PARAMETERS) in str(err.value)


# --- the old keywords: same answer, with a DeprecationWarning -------------------------------------------------------
OLD = [
    ("parametrize", lambda: cagd.parametrize(P, method="centripetal"),
     lambda: cagd.parametrize(P, parameters="centripetal"), "method"),
    ("surface_parameters", lambda: np.concatenate(surface_parameters(GRID, method="centripetal")),
     lambda: np.concatenate(surface_parameters(GRID, parameters="centripetal")), "method"),
    ("spline_parameters", lambda: spline_parameters(P, parametrization="centripetal"),
     lambda: spline_parameters(P, parameters="centripetal"), "parametrization"),
    ("natural_cubic_spline", lambda: cagd.natural_cubic_spline(P, parametrization="uniform").parameters,
     lambda: cagd.natural_cubic_spline(P, parameters="uniform").parameters, "parametrization"),
    ("CubicSpline", lambda: cagd.CubicSpline(P, "clamped", tangents=[[1, 0], [0, 1]],
                                             parametrization="centripetal")(np.linspace(0, 5, 9)),
     lambda: cagd.CubicSpline(P, "clamped", "centripetal", [[1, 0], [0, 1]])(np.linspace(0, 5, 9)),
     "parametrization"),
    ("CubicSpline (sixth positional)", lambda: cagd.CubicSpline(P, "natural", "chord", None, None,
                                                                [0, 1, 2, 4, 5]).parameters,
     lambda: cagd.CubicSpline(P, parameters=[0, 1, 2, 4, 5]).parameters, "sixth positional"),
]


@pytest.mark.parametrize("name, old, new, word", OLD, ids=[o[0] for o in OLD])
def test_old_keyword_warns_and_gives_the_same_answer(name, old, new, word):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        expected = new()                            # the new form does not warn
    with pytest.warns(DeprecationWarning, match=word) as rec:
        got = old()
    assert "parameters=" in str(rec[0].message)
    assert rec[0].filename == __file__              # attributed to the caller, not to cagd
    np.testing.assert_array_equal(np.asarray(got), np.asarray(expected))


def test_old_and_new_keyword_together_is_an_error():
    with pytest.raises(cagd.CagdError, match="method.*both"):
        cagd.parametrize(P, "uniform", method="chord")
    with pytest.raises(cagd.CagdError, match="parametrization.*both"):
        cagd.natural_cubic_spline(P, parameters="uniform", parametrization="chord")


def test_hermite_spline_takes_the_names_and_values():
    T = np.ones_like(P)
    np.testing.assert_array_equal(cagd.HermiteSpline(P, T).parameters, np.arange(len(P)))
    np.testing.assert_array_equal(cagd.HermiteSpline(P, T, "chord").parameters, spline_parameters(P, "chord"))
    np.testing.assert_array_equal(cagd.HermiteSpline(P, T, [0, 1, 5, 6, 9]).parameters, [0, 1, 5, 6, 9])
    repeated = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 1.0]])       # a repeated point: uniform still works
    np.testing.assert_array_equal(cagd.HermiteSpline(repeated, np.ones_like(repeated)).parameters, [0, 1, 2])


def test_model_reads_the_old_key_with_a_warning():
    def doc(**fields):
        return {"format": "cagd-model", "version": 1, "objects": [
            {"name": "s", "type": "cubic_spline", "points": P.tolist(), **fields}]}
    new = load_model(doc(parameters="centripetal"))["s"].objects[0]
    with pytest.warns(DeprecationWarning, match="parametrization"):
        old = load_model(doc(parametrization="centripetal"))["s"].objects[0]
    np.testing.assert_array_equal(old.parameters, new.parameters)
    with pytest.raises(ModelError) as err:
        load_model(doc(parametrization="uniform", parameters="chord"))
    assert err.value.path == "$.objects[0].parametrization"
    explicit = load_model(doc(parameters=[0, 1, 2, 3, 4]))["s"].objects[0]
    np.testing.assert_array_equal(explicit.parameters, [0, 1, 2, 3, 4])
