"""Headless test suite of the cagd workbench, run by FreeCAD's own interpreter:

    CAGD_WB_OUT=/tmp/out freecadcmd workbench/tests/headless_suite.py

Creates every object type, recomputes, checks Shape.isValid(), compares the shapes'
own evaluation (valueAt, Surface.value, Surface.normal) with the engine, edits
properties, feeds bad values (error state, empty shape, message), moves linked
inputs, exports to STEP and IGES and compares the re-imported geometry. The last
line of output is ``CAGD_WB_RESULT {json}`` with passed/failed counts, the failing
names and the largest deviations measured. Cases: conversion and analysis here,
the objects in suite_objects.py, helpers in suite_support.py.
"""
import json
import math
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402
import numpy as np  # noqa: E402

from suite_support import (CASES, DEV, WORST, INSTALLED, OUT, RESULTS, TOL, V, analysis, cagd, cagdwb, case,  # noqa: E402
                           check, conversion, curves, exchange, new_doc, note, surfaces)


# --- installation and conversion ------------------------------------------------------------
@case
def test_engine_importable():
    check(os.path.isfile(os.path.join(cagdwb.ensure_engine(), "cagd", "__init__.py")), "engine path")
    print(f"numpy {np.__version__}, python {sys.version.split()[0]}, installed addon: {INSTALLED}")


@case
def test_installed_addon_loaded():
    """When the test runner installed the addon (CAGD_WB_EXPECT_INSTALLED), FreeCAD's
    own start-up must have found it in the user Mod folder and run Init.py."""
    if os.environ.get("CAGD_WB_EXPECT_INSTALLED"):
        check(INSTALLED, "cagdwb not importable from FreeCAD's Mod path")
        mods = [os.path.realpath(d) for d in App.__ModDirs__]
        check(os.path.realpath(cagdwb.ADDON_DIR) in mods, f"addon not among FreeCAD's Mod dirs {mods}")


def _random_curves(rng):
    P = rng.normal(size=(7, 3)) * 10
    knots = np.concatenate([[0] * 4, [0.2, 0.5, 0.5], [1] * 4])
    w = rng.uniform(0.5, 2.0, 7)
    yield "polynomial", cagd.BSplineCurve(P, 3, knots)
    yield "rational", cagd.BSplineCurve(P, 3, knots, w)
    yield "periodic", cagd.BSplineCurve(P, 3, np.array([0, .1, .3, .4, .6, .7, .9, 1.0]), periodic=True)
    yield "periodic rational", cagd.BSplineCurve(P, 2, np.linspace(-1, 2, 8), w, periodic=True)
    yield "bezier rational", cagd.BezierCurve(P[:5], w[:5])
    yield "cubic spline", cagd.natural_cubic_spline(P, "periodic" if False else "natural")


@case
def test_curve_conversion_roundtrip():
    rng = np.random.default_rng(7)
    for name, c in _random_curves(rng):
        bc = conversion.curve_to_part(c)
        dev = note("freecad", exchange.compare_edge(c, bc.toShape(), 101), name)
        check(dev <= TOL, f"{name}: FreeCAD valueAt deviates {dev:.3g}")
        back = conversion.part_curve_to_engine(bc)
        t = np.linspace(*c.domain, 101)
        dev = note("roundtrip", exchange.relative_deviation(c(t), back(t)), name)
        check(dev <= TOL, f"{name}: Part -> engine deviates {dev:.3g}")
        check(back.periodic == c.to_nurbs().periodic, f"{name}: periodic flag lost")


@case
def test_part_bezier_to_engine():
    pb = Part.BezierCurve()
    pb.setPoles([V(0, 0, 0), V(1, 2, 0), V(3, 2, 1), V(4, 0, 0)])
    pb.setWeight(2, 3.0)
    c = conversion.part_curve_to_engine(pb)
    for t in np.linspace(0, 1, 11):
        check(np.abs(np.array(tuple(pb.value(t))) - c(t)).max() < 1e-12, "Part Bezier curve")
    ps = Part.BezierSurface()
    ps.increase(2, 3)
    for i in range(3):
        for j in range(4):
            ps.setPole(i + 1, j + 1, V(i, j, math.sin(i + j)))
    ps.setWeight(2, 2, 2.5)
    s = conversion.part_surface_to_engine(ps)
    for u, v in [(0, 0), (0.3, 0.7), (1, 0.5)]:
        check(np.abs(np.array(tuple(ps.value(u, v))) - s(u, v)).max() < 1e-12, "Part Bezier surface")


@case
def test_surface_conversion_roundtrip():
    rng = np.random.default_rng(3)
    P = rng.normal(size=(5, 6, 3)) * 10
    W = rng.uniform(0.5, 2.0, (5, 6))
    ku = np.concatenate([[0] * 4, [0.5], [1] * 4])
    for name, s in [("polynomial", cagd.BSplineSurface(P, 3, 2, ku)),
                    ("rational", cagd.BSplineSurface(P, 3, 2, ku, None, W)),
                    ("periodic v", cagd.BSplineSurface(P, 3, 2, ku, np.linspace(0, 3, 7), W, periodic_v=True)),
                    ("sphere", cagd.sphere(5.0, (1, 2, 3))), ("torus", cagd.torus(10.0, 3.0))]:
        bs = conversion.surface_to_part(s)
        d = exchange.compare_face(s, bs.toShape(), 13)
        note("freecad", d["points"], name), note("normals", d["normals"], name)
        check(max(d.values()) <= TOL, f"{name}: {d}")
        back = conversion.part_surface_to_engine(bs)
        U, W2 = exchange.surface_params(s, 13)
        dev = note("roundtrip", exchange.relative_deviation(s(U, W2), back(U, W2)), name)
        check(dev <= TOL, f"{name}: Part -> engine deviates {dev:.3g}")


import suite_objects  # noqa: E402,F401  (registers the object cases, in this order)


# --- analysis -------------------------------------------------------------------------------
@case
def test_continuity_faces():
    doc = new_doc("contfaces")
    rng = np.random.default_rng(5)
    P = rng.normal(size=(4, 4, 3)) + np.stack(np.meshgrid(np.arange(4) * 5.0, np.arange(4) * 5.0,
                                                          indexing="ij") + [np.zeros((4, 4))], -1)
    Q = P.copy()
    Q[:, :, 0] += 15.0
    Q[0] = P[3]
    Q[1] = 2 * P[3] - P[2]                                  # C1 across u1 / u0
    s1 = surfaces.make_bezier_surface(P, 4, doc=doc)
    s2 = surfaces.make_bezier_surface(Q, 4, doc=doc)
    doc.recompute()
    r = analysis.check_shapes(s1.Shape.Faces[0], s2.Shape.Faces[0], tol=1e-7)
    check(r.level == "C1" and "u1" in r.where and "u0" in r.where, f"C1 faces: {r.text()}")
    Q[1] = 2 * P[3] - P[2] + np.array([0, 0, 1.0])
    s2.Poles = conversion.vectors(Q.reshape(-1, 3))
    doc.recompute()
    r = analysis.check_shapes(s1.Shape.Faces[0], s2.Shape.Faces[0], tol=1e-7)
    check(r.level == "C0", f"C0 faces: {r.text()}")


@case
def test_continuity_edges_orientation():
    a = Part.makeCircle(10.0, V(0, 0, 0), V(0, 0, 1), 0, 90)
    b = Part.makeCircle(10.0, V(0, 0, 0), V(0, 0, 1), 90, 200)
    r = analysis.check_shapes(b, a, tol=1e-7)          # joint: start of b, end of a
    check(r.report.G2 and r.report.gap < 1e-9, f"circle arcs: {r.text()}")
    line = Part.makeLine(V(10, 0, 0), V(10, -10, 0))
    r = analysis.check_shapes(a, line, tol=1e-7)
    check(r.report.G1 and not r.report.G2, f"arc + tangent line: {r.text()}")


@case
def test_curvature_comb():
    R = 8.0
    arc = Part.makeCircle(R, V(0, 0, 0), V(0, 0, 1), 0, 180)
    teeth = analysis.curvature_comb(arc, 17, scale=16.0)
    for foot, tip in teeth:
        check(abs(foot.Length - R) < 1e-6, "comb foot not on the circle")
        check(abs((tip - foot).Length - 16.0 / R) < 1e-6, "tooth length != scale * curvature")
        check(tip.Length > foot.Length, "tooth points towards the centre")
    check(analysis.auto_comb_scale(arc) > 0, "auto scale")


@case
def test_save_and_reload():
    doc = new_doc("saved")
    objs = [curves.make_cubic_spline(doc=doc), surfaces.make_bezier_triangle(doc=doc)]
    doc.recompute()
    path = os.path.join(OUT, "saved.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    doc = App.openDocument(path)
    for o in doc.Objects:
        o.touch()
    doc.recompute()
    check(len(doc.Objects) == len(objs) and all(o.isValid() and o.Shape.isValid() for o in doc.Objects),
          "reloaded objects do not recompute")
    check(doc.Objects[0].Proxy.__class__.__name__ == "CubicSpline", "proxy class not restored")


def main():
    start = time.time()
    for fn in CASES:
        t0 = time.time()
        try:
            fn()
        except Exception as exc:
            RESULTS["failed"][fn.__name__] = f"{type(exc).__name__}: {exc}"
            print(f"FAIL {fn.__name__}: {exc}")
            traceback.print_exc()
        else:
            RESULTS["passed"].append(fn.__name__)
            print(f"ok   {fn.__name__} ({time.time() - t0:.2f} s)")
    summary = {"passed": len(RESULTS["passed"]), "failed": len(RESULTS["failed"]),
               "failures": RESULTS["failed"], "max_deviation": DEV, "worst": WORST, "seconds": round(time.time() - start, 2),
               "freecad": ".".join(App.Version()[:3]), "numpy": np.__version__, "out": OUT}
    print("CAGD_WB_RESULT " + json.dumps(summary), flush=True)


main()
if os.environ.get("CAGD_WB_EXIT"):
    os._exit(0)
