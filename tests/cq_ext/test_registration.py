"""``import cq_ext`` registers its methods on cadquery.Workplane (CadQuery's plugin
convention): every name of ``cq_ext.workplane.METHODS`` is there, documented, typed,
returns a new Workplane chained to its parent, and none of CadQuery's own methods is
replaced."""
import inspect
import json
import os
import subprocess
import sys
import typing

import numpy as np
import pytest

cq = pytest.importorskip("cadquery")

import cagd  # noqa: E402
import cq_ext  # noqa: E402
from cq_ext.workplane import METHODS  # noqa: E402

NAMES = [m.__name__ for m in METHODS]
ISSUE_NAMES = {"bezierCurve", "nurbsCurve", "interpCurve", "hermiteCurve", "joinCurves", "cagdSurface",
               "bezierSurface", "bsplineSurface", "coonsPatch", "bezierTriangle", "revolveSurface"}


def test_import_adds_methods_without_overwriting_cadquery():
    """In a fresh interpreter: the Workplane's attributes before and after ``import cq_ext``."""
    code = ("import json, cadquery as cq; before = set(dir(cq.Workplane)); "
            "own = dict(vars(cq.Workplane)); import cq_ext; "
            "after = set(dir(cq.Workplane)); "
            "changed = [n for n in own if vars(cq.Workplane).get(n) is not own[n]]; "
            "print(json.dumps({'before': sorted(before), 'added': sorted(after - before), 'changed': changed}))")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = dict(os.environ, PYTHONPATH=root + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=root,
                         env=env)
    data = json.loads(out.stdout.strip().splitlines()[-1])
    assert not set(NAMES) & set(data["before"])        # no CadQuery name reused
    assert data["changed"] == []                        # nothing of CadQuery's replaced
    assert set(data["added"]) == set(NAMES)


def test_the_issue_methods_are_all_there():
    assert ISSUE_NAMES <= set(NAMES)
    assert len(NAMES) == len(set(NAMES))


@pytest.mark.parametrize("name", NAMES)
def test_registered_function_is_the_plugin_function(name):
    fn = next(m for m in METHODS if m.__name__ == name)
    assert getattr(cq.Workplane, name) is fn
    assert name in cq_ext.__all__


def test_star_import():
    ns = {}
    exec("from cq_ext import *", ns)
    assert set(cq_ext.__all__) <= set(ns)


@pytest.mark.parametrize("name", NAMES)
def test_docstring(name):
    doc = inspect.getdoc(getattr(cq.Workplane, name))
    assert doc and len(doc.split()) >= 5, name


@pytest.mark.parametrize("name", NAMES)
def test_type_hints(name):
    fn = getattr(cq.Workplane, name)
    sig = inspect.signature(fn)
    params = list(sig.parameters.values())[1:]               # all but self
    missing = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    assert missing == [], f"{name}: no annotation on {missing}"
    assert sig.return_annotation is not inspect.Signature.empty
    hints = typing.get_type_hints(fn, globalns=vars(sys.modules[fn.__module__]))   # resolvable
    assert "return" in hints


def _box_top_edges():
    return cq.Workplane().box(2, 3, 4).faces(">Z").edges()


_P44 = [[(i, j, 0.1 * i * j) for j in range(4)] for i in range(4)]
_EL = cagd.ellipsoid(3.0, 2.0, 1.5)
_LINE = cagd.BSplineCurve(np.array([[1.0, 0.0], [1.5, 2.0]]), 1)
_BEZ44 = cagd.BSplineSurface(np.array(_P44, dtype=float), 3, 3)
_LINE3 = cagd.BSplineCurve(np.array([[1.0, 0.0, 0.0], [1.0, 3.0, 0.0]]), 1)
_AXIS = cagd.BSplineCurve(np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 3.0]]), 1)

# one minimal valid call per method: (start workplane factory, args, kwargs, expected stack type)
CALLS = {
    "cagdCurve": (cq.Workplane, (cagd.BezierCurve(np.array([[0.0, 0], [1, 1], [2, 0]])),), {}, cq.Edge),
    "bezierCurve": (cq.Workplane, ([(0, 0), (1, 1), (2, 0)],), {}, cq.Edge),
    "nurbsCurve": (cq.Workplane, ([(0, 0), (1, 1), (2, 0), (3, 1)],), {}, cq.Edge),
    "interpCurve": (cq.Workplane, ([(0, 0), (1, 1), (2, 0), (3, 1)],), {}, cq.Edge),
    "hermiteCurve": (cq.Workplane, ((0, 0), (1, 0), (1, 1), (1, -1)), {}, cq.Edge),
    "joinCurves": (cq.Workplane, ([(0, 0), (1, 1), (2, 0), (3, 1)],), {}, cq.Edge),
    "cagdSurface": (cq.Workplane, (cagd.sphere(1.0, (0, 0, 0)),), {}, cq.Face),
    "bezierSurface": (cq.Workplane, (_P44,), {}, cq.Face),
    "bsplineSurface": (cq.Workplane, (_P44,), {"interpolate": True}, cq.Face),
    "coonsPatch": (_box_top_edges, (), {}, cq.Face),
    "loftSurface": (cq.Workplane, (_LINE, _LINE.transformed(np.eye(2), (1.0, 0.5))), {"degree_v": 1}, cq.Face),
    "ruledSurface": (cq.Workplane, (_LINE, _LINE.transformed(np.eye(2), (1.0, 0.5))), {}, cq.Face),
    "bezierTriangle": (cq.Workplane, ([(0, 0, 0), (1, 0, 0), (0, 1, 0)],), {}, cq.Face),
    "revolveSurface": (cq.Workplane, (_LINE,), {}, cq.Face),
    "sewSolid": (lambda: cq.Workplane().add([cq_ext.to_cq(s) for s in _EL]), (), {}, cq.Solid),
    "closeWithCaps": (lambda: cq.Workplane().revolveSurface(_LINE), (), {}, cq.Solid),
    "thickenSurface": (lambda: cq.Workplane().bezierSurface(_P44), (0.2,), {}, cq.Solid),
    "projectPoints": (lambda: cq.Workplane().sphere(1.0).faces(), ([(2, 0, 0), (0, 0, 3)],), {}, cq.Vertex),
    "intersectFaces": (lambda: cq.Workplane().sphere(1.0).faces(),
                       (cq.Face.makePlane(4, 4, (0, 0, 0.5), (0, 0, 1)),), {}, cq.Edge),
    "fitCurve": (cq.Workplane, ([(0, 0), (1, 1), (2, 0), (3, 1), (4, 0)],), {"tol": 0.01}, cq.Edge),
    "fitSurface": (cq.Workplane, (_P44,), {"tol": 0.01}, cq.Face),
    "rebuild": (lambda: cq.Workplane().nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1)]), (6,), {}, cq.Edge),
    "removeKnots": (lambda: cq.Workplane().nurbsCurve([(0, 0), (1, 1), (2, 0), (3, 1), (4, 0)]), (1e-6,), {},
                    cq.Edge),
    "gordonSurface": (cq.Workplane, ([_BEZ44.isocurve("u", v) for v in (0.0, 1.0)],
                                     [_BEZ44.isocurve("v", u) for u in (0.0, 1.0)]), {}, cq.Face),
    "sweepSurface": (lambda: cq.Workplane().circle(1.0), (), {"path": _AXIS}, cq.Face),
    "sweep2Surface": (cq.Workplane, (cagd.BezierCurve(np.array([[1.0, 0, 0], [0.5, 0, 1], [1, 0, 2]])), _LINE3,
                                     _LINE3.transformed(np.eye(3), (0, 0, 2.0))), {}, cq.Face),
    "blendCurve": (cq.Workplane, (_LINE, "end", _LINE.transformed(np.eye(2), (2.0, 0.5)), "start"), {}, cq.Edge),
    "blendSurface": (cq.Workplane, (_BEZ44, "u1", _BEZ44.transformed(np.eye(3), (5.0, 0, 0)), "u0"), {}, cq.Face),
    "matchSurface": (cq.Workplane, (_BEZ44.transformed(np.eye(3), (3.5, 0, 0.5)), "u0", _BEZ44, "u1"), {},
                     cq.Face),
}


def test_every_method_has_a_call_below():
    assert set(CALLS) == set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_chainable_returns_a_new_workplane(name):
    start, args, kwargs, kind = CALLS[name]
    wp = start()
    out = getattr(wp, name)(*args, **kwargs)
    assert isinstance(out, cq.Workplane) and out is not wp
    assert out.parent is wp                             # newObject: CadQuery's chaining
    assert out.plane == wp.plane
    assert out.vals() and all(isinstance(o, kind) for o in out.vals())
    assert all(o.isValid() for o in out.vals())
    # and the chain goes on with CadQuery's own methods
    assert isinstance(out.end(), cq.Workplane) and out.end() is wp
