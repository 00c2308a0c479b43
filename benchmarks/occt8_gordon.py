"""OCCT 8.0's GeomFill_Gordon on a network given as a JSON file of curves, run in a
separate Python that has cadquery-ocp 8 (``benchmarks.gordon --occt8-python``): this
script imports OCP only, never cagd. Each curve: {"poles": [[x, y, z], ...], "knots":
[...distinct], "mults": [...], "degree": p}. Prints one JSON line: {"status", "seconds",
"poles": [nu, nv]} (or "error"). The caller runs it with a timeout and a memory limit:
on some networks it runs for minutes and gigabytes (issue 18's anchors).

Run: python benchmarks/occt8_gordon.py network.json tol
"""
import json
import sys
import time


def _curve(spec):
    from OCP.collections import Array1_double, Array1_gp_Pnt, Array1_int     # OCCT 8's templates
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt

    poles = Array1_gp_Pnt(1, len(spec["poles"]))
    for i, p in enumerate(spec["poles"], 1):
        poles.SetValue(i, gp_Pnt(*p))
    knots = Array1_double(1, len(spec["knots"]))
    mults = Array1_int(1, len(spec["mults"]))
    for i, (k, m) in enumerate(zip(spec["knots"], spec["mults"]), 1):
        knots.SetValue(i, float(k))
        mults.SetValue(i, int(m))
    return Geom_BSplineCurve(poles, knots, mults, int(spec["degree"]))


def _array(curves):
    from OCP.collections import Array1_Geom_Curve
    arr = Array1_Geom_Curve(1, len(curves))
    for i, c in enumerate(curves, 1):
        arr.SetValue(i, c)
    return arr


def main(path: str, tol: float) -> dict:
    from OCP.GeomFill import GeomFill_Gordon
    with open(path) as f:
        net = json.load(f)
    profiles, guides = [_curve(c) for c in net["profiles"]], [_curve(c) for c in net["guides"]]
    t0 = time.perf_counter()
    g = GeomFill_Gordon()
    g.Init(_array(profiles), _array(guides), tol)
    g.Perform()
    seconds = time.perf_counter() - t0
    status = str(g.Status()).split(".")[-1]
    if status != "Done":
        return {"status": status, "seconds": seconds}
    s = g.Surface()
    return {"status": status, "seconds": seconds, "poles": [s.NbUPoles(), s.NbVPoles()]}


if __name__ == "__main__":
    try:
        out = main(sys.argv[1], float(sys.argv[2]))
    except Exception as exc:          # reported to the caller, which prints it
        out = {"error": f"{type(exc).__name__}: {exc}"}
    print(json.dumps(out))
