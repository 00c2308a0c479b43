"""min_distance on every family against OCCT (issue 8): curve–curve (Bezier, rational,
periodic, cubic spline; GeomAPI_ExtremaCurveCurve), curve–surface (sphere, torus,
revolution, Coons patch, loft, Bezier triangle; GeomAPI_ExtremaCurveSurface) and
surface–surface (GeomAPI_ExtremaSurfaceSurface). The engine's distance is never larger
than OCCT's by more than 1e-9 relative; where it is smaller (OCCT missed the global
minimum) the case is printed; the certified lower bound never exceeds a dense-sampling
minimum."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cagd
from cagd import BezierCurve, BSplineCurve
from cagd.queries import min_distance

from query_families import curve_of

try:                                  # the OCCT oracles need OCP
    from cagd import occ
except ImportError:
    occ = None
needs_occ = pytest.mark.skipif(occ is None, reason="OCP (cagd.occ) is not installed")

CURVES = ["bezier", "rational", "periodic", "spline"]


def surface_of(kind, rng):
    if kind == "sphere":
        return cagd.sphere(0.6, tuple(rng.uniform(-0.2, 0.2, 3)))
    if kind == "torus":
        return cagd.torus(0.8, 0.25, tuple(rng.uniform(-0.2, 0.2, 3)))
    if kind == "revolve":
        return cagd.revolve(BSplineCurve(rng.uniform(0.2, 0.8, (4, 3)) * [1, 0, 1], 3))
    if kind == "coons":
        c0 = BezierCurve([[0, 0, 0], [0.5, 0, rng.uniform(-.3, .3)], [1, 0, 0]])
        c1 = BezierCurve([[0, 1, 0], [0.5, 1, rng.uniform(-.3, .3)], [1, 1, 0]])
        d0 = BezierCurve([[0, 0, 0], [0, 0.5, rng.uniform(-.3, .3)], [0, 1, 0]])
        d1 = BezierCurve([[1, 0, 0], [1, 0.5, rng.uniform(-.3, .3)], [1, 1, 0]])
        return cagd.CoonsPatch(c0, c1, d0, d1)
    if kind == "loft":
        secs = [BSplineCurve(np.c_[np.linspace(0, 1, 4), np.full(4, y), rng.uniform(-.2, .2, 4)], 3)
                for y in (0.0, 0.5, 1.0)]
        return cagd.loft(secs, degree_v=2)
    return cagd.BezierTriangle(np.c_[[[0, 0], [.5, 0], [1, 0], [0, .5], [.5, .5], [0, 1]], rng.uniform(-.2, .2, 6)])


def dense_min(a, b, n=120):
    def pts(o):
        if isinstance(o, cagd.Curve):
            return o(np.linspace(*o.domain, n * 4))
        (u0, u1), (v0, v1) = o.domain
        U, V = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
        return o(U, V * (1 - U)) if not o.rectangular else o(U, V)
    A, B = pts(a).reshape(-1, 3), pts(b).reshape(-1, 3)
    return min(np.linalg.norm(A[i:i + 500, None] - B[None], axis=-1).min() for i in range(0, len(A), 500))


def evaluate(o, p):
    if isinstance(o, cagd.Curve):
        return o(np.array([float(p)]))[0]
    return o(float(p[0]), float(p[1]))             # triangles: their own (u, v), u + v <= 1


def compare(res, theirs, label, a=None, b=None, dense=None):
    """The engine's points are on the objects (so its distance is attained), it is no
    larger than OCCT's nor than a dense-sampling minimum, and its lower bound holds."""
    assert res.lower_bound <= res.distance + 1e-15
    if a is not None:
        pa, pb = evaluate(a, res.params[0]), evaluate(b, res.params[1])
        assert abs(np.linalg.norm(pa - pb) - res.distance) <= 1e-12 * max(1.0, res.distance), label
    if dense is not None:
        assert res.lower_bound <= dense + 1e-12 and res.distance <= dense + 1e-12, (label, res.distance, dense)
    if theirs is None:
        return
    assert res.distance <= theirs + 1e-9 * max(theirs, 1.0), (label, res.distance, theirs)
    if res.distance < theirs - 1e-9 * max(theirs, 1.0):
        print(f"{label}: OCCT {theirs:.6g} missed the global minimum {res.distance:.6g}")


@needs_occ
@settings(max_examples=8, deadline=None)
@given(st.sampled_from(CURVES), st.sampled_from(CURVES), st.integers(0, 10 ** 6))
def test_curve_curve_families(ka, kb, seed):
    from OCP.GeomAPI import GeomAPI_ExtremaCurveCurve
    rng = np.random.default_rng(seed)
    a, b = curve_of(ka, rng), curve_of(kb, rng, shift=[0.9, 0.0, 0.0])
    res = min_distance(a, b)
    ext = GeomAPI_ExtremaCurveCurve(occ.to_occ(a), occ.to_occ(b))
    compare(res, ext.LowerDistance() if ext.NbExtrema() else None, f"{ka}/{kb} seed {seed}", a, b, dense_min(a, b))


@needs_occ
@settings(max_examples=8, deadline=None)
@given(st.sampled_from(CURVES), st.sampled_from(["sphere", "torus", "revolve", "coons", "loft", "triangle"]),
       st.integers(0, 10 ** 6))
def test_curve_surface_families(kc, ks, seed):
    from OCP.GeomAPI import GeomAPI_ExtremaCurveSurface
    rng = np.random.default_rng(seed)
    c, s = curve_of(kc, rng, shift=[0.0, 0.0, 1.2]), surface_of(ks, rng)
    res = min_distance(c, s)
    ext = GeomAPI_ExtremaCurveSurface(occ.to_occ(c), occ.to_occ(s))
    compare(res, ext.LowerDistance() if ext.NbExtrema() else None, f"{kc}/{ks} seed {seed}", c, s,
            dense_min(c, s, 60))


@needs_occ
@settings(max_examples=5, deadline=None)
@given(st.sampled_from(["sphere", "torus", "coons", "triangle"]), st.sampled_from(["sphere", "loft", "revolve"]),
       st.integers(0, 10 ** 6))
def test_surface_surface_families(ka, kb, seed):
    from OCP.GeomAPI import GeomAPI_ExtremaSurfaceSurface
    rng = np.random.default_rng(seed)
    a = surface_of(ka, rng)
    b = surface_of(kb, rng).transformed(np.eye(3), [0.0, 0.0, 2.0])
    res = min_distance(a, b)
    ext = GeomAPI_ExtremaSurfaceSurface(occ.to_occ(a), occ.to_occ(b))
    compare(res, ext.LowerDistance() if ext.NbExtrema() else None, f"{ka}/{kb} seed {seed}", a, b,
            dense_min(a, b, 40))


def test_triangle_corner_against_a_sphere_converges():
    # found by the family test: the minimum is at the triangle's corner, the collapsed edge
    # of its NURBS form; halving slivers along that edge too made the pairs multiply until
    # the cap (gap 7e-6 reported); slivers are now halved across their length only
    rng = np.random.default_rng(0)
    a = surface_of("triangle", rng)
    b = surface_of("sphere", rng).transformed(np.eye(3), [0.0, 0.0, 2.0])
    res = min_distance(a, b)
    assert res.converged, res.message
    assert res.lower_bound <= res.distance <= res.lower_bound + res.tol
    assert res.distance <= dense_min(a, b, 40) + 1e-12
    assert np.allclose(res.params[0], [1.0, 0.0])                   # the corner (1, 0)
    # the same pair with a cap too small for it reports instead of crashing
    capped = min_distance(a, b, max_pairs=16)
    assert capped.lower_bound <= capped.distance
    assert capped.converged or "pair cap" in capped.message
