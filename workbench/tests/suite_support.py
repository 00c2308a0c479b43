"""Shared set-up and helpers of the headless suite (see headless_suite.py): the
cagdwb import (installed addon, else the checkout), the case registry, deviation
bookkeeping and the create/edit/bad value/export cycle every object goes through."""
import os
import sys
import tempfile

import FreeCAD as App

try:
    import cagdwb
    INSTALLED = True
except ImportError:                     # not installed: load from the checkout
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import cagdwb
    INSTALLED = False


from cagdwb import analysis, conversion, curves, exchange, surfaces
from cagdwb.conversion import cagd

__all__ = ["CASES", "DEV", "INSTALLED", "OUT", "RESULTS", "TOL", "V", "WORST", "analysis", "cagd", "cagdwb", "case",
           "check", "compare", "conversion", "curves", "exchange", "expect_error", "exported", "new_doc", "note",
           "recompute_ok", "standard", "surfaces"]      # what the suite modules take from here

TOL = 1e-9
OUT = os.environ.get("CAGD_WB_OUT") or tempfile.mkdtemp(prefix="cagd-wb-")
os.makedirs(OUT, exist_ok=True)
V = App.Vector
RESULTS = {"passed": [], "failed": {}}
DEV = {"freecad": 0.0, "normals": 0.0, "step": 0.0, "iges": 0.0, "roundtrip": 0.0}
CASES = []


def case(fn):
    CASES.append(fn)
    return fn


WORST = {}


def note(kind, value, where=""):
    """Record a measured deviation; keep the largest per kind and where it was."""
    if float(value) >= DEV[kind]:
        DEV[kind], WORST[kind] = float(value), where
    return value


def check(cond, message):
    if not cond:
        raise AssertionError(message)


def new_doc(name):
    return App.newDocument(name)


def recompute_ok(obj):
    obj.Document.recompute()
    check(obj.isValid(), f"{obj.Label} invalid: {obj.getStatusString()}")
    check(not obj.Shape.isNull() and obj.Shape.isValid(), f"{obj.Label}: shape null or not valid")
    check(obj.Message == "ok", f"{obj.Label}: Message {obj.Message!r}")


def expect_error(obj, words):
    """Recompute must fail: object invalid, empty shape, message naming the problem."""
    obj.Document.recompute()
    check(not obj.isValid(), f"{obj.Label} accepted a bad value")
    check(obj.Shape.isNull(), f"{obj.Label}: stale shape kept after an error")
    msg = obj.Message.lower()
    check(msg.startswith("error:"), f"{obj.Label}: Message {obj.Message!r}")
    for w in words:
        check(w.lower() in msg, f"{obj.Label}: message {obj.Message!r} does not mention {w!r}")
    check(w.lower() in obj.getStatusString().lower(), f"status string {obj.getStatusString()!r}")


def compare(obj):
    """Shape vs engine geometry at the same parameters; returns the engine geometry."""
    geom = obj.Proxy.build(obj)
    if isinstance(geom, cagd.Curve):
        edge = obj.Shape.Edges[0]
        dev = note("freecad", exchange.compare_edge(geom, edge), obj.Label)
        check(dev <= TOL, f"{obj.Label}: edge deviates {dev:.3g}")
    else:
        d = exchange.compare_face(geom, obj.Shape.Faces[0])
        note("freecad", d["points"], obj.Label)
        note("normals", d["normals"], obj.Label)
        check(d["points"] <= TOL and d["normals"] <= TOL, f"{obj.Label}: face deviates {d}")
    return geom


def exported(obj, geom):
    """STEP and IGES round trip of one object, compared with the engine."""
    for ext, key in ((".step", "step"), (".iges", "iges")):
        path = exchange.export([obj], os.path.join(OUT, obj.Name + ext))
        shape = exchange.reimport(path)
        check(not shape.isNull(), f"{path}: nothing re-imported")
        if isinstance(geom, cagd.Curve):
            check(len(shape.Edges) >= 1, f"{path}: no edge")
            dev = exchange.compare_edge(geom, shape.Edges[0])
        else:
            check(len(shape.Faces) == 1, f"{path}: {len(shape.Faces)} faces")
            d = exchange.compare_face(geom, shape.Faces[0])
            dev = max(d["points"], d["normals"])
        note(key, dev, obj.Label)
        check(dev <= TOL, f"{obj.Label} {key}: re-import deviates {dev:.3g}")


def standard(obj, edit, bad, words, fix):
    """Create -> valid and equal to the engine -> edit changes the shape -> bad
    value is an error with an empty shape -> fix makes it valid again -> STEP/IGES."""
    recompute_ok(obj)
    geom = compare(obj)
    before = obj.Shape.copy()
    edit(obj)
    recompute_ok(obj)
    compare(obj)
    check(not obj.Shape.isPartner(before) and not _same_geometry(before, obj.Shape),
          f"{obj.Label}: editing did not change the shape")
    bad(obj)
    expect_error(obj, words)
    fix(obj)
    recompute_ok(obj)
    geom = compare(obj)
    exported(obj, geom)


def _same_geometry(a, b):
    """Same sampled points on every edge and face (at the same relative parameters)."""
    def samples(shape):
        pts = []
        for e in shape.Edges:
            t0, t1 = e.ParameterRange
            pts += [e.valueAt(t0 + (t1 - t0) * k / 6.0) for k in range(7)]
        for f in shape.Faces:
            u0, u1, v0, v1 = f.ParameterRange
            pts += [f.Surface.value(u0 + (u1 - u0) * i / 4.0, v0 + (v1 - v0) * j / 4.0)
                    for i in range(5) for j in range(5)]
        return pts
    pa, pb = samples(a), samples(b)
    return len(pa) == len(pb) and all((p - q).Length < 1e-12 for p, q in zip(pa, pb))
