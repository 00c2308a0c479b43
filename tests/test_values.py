"""Objects are values (issue 13): every array an engine object holds is read-only (public
attributes, properties and the private arrays its caches derive from), public attributes
cannot be rebound, constructors copy their input, and ``with_control_points`` /
``moved_pole`` / ``with_weights`` give modified copies equal to a fresh construction."""
import copy
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cagd
from cagd import CagdError
from cagd._checks import frozen
from cagd._value import Value
from cagd.curves.ppform import PPForm

from strategies import bspline_curves, coordinates, positive_weights, sample_parameters
from surface_strategies import bspline_surfaces, domain_parameters

RNG = np.random.default_rng(13)
P4 = [[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 0.0]]


def _curves():
    P = RNG.random((6, 3))
    w = RNG.uniform(0.5, 2.0, 6)
    line = cagd.BSplineCurve([[0, 0, 0], [1, 0, 0]], 1)
    ribbon = cagd.BSplineCurve([[0, 0, 1], [1, 0, 1]], 1)
    yield "BSplineCurve", cagd.BSplineCurve(P, 3)
    yield "NURBS curve", cagd.BSplineCurve(P, 3, weights=w)
    yield "periodic NURBS curve", cagd.BSplineCurve(P, 3, np.linspace(0, 1, 7), w, periodic=True)
    yield "BSplineCurve.from_occ_form", cagd.BSplineCurve.from_occ_form(*cagd.BSplineCurve(P, 3).occ_form()[:5])
    yield "BezierCurve", cagd.BezierCurve(P[:4])
    yield "rational BezierCurve", cagd.BezierCurve(P[:4], w[:4])
    yield "PolynomialCurve", cagd.PolynomialCurve(P[:4], (1.0, 2.0))
    yield "four_point_cubic", cagd.four_point_cubic(P[:4])
    yield "HermiteCurve", cagd.HermiteCurve(*P[:4])
    yield "HermiteCurve.from_directions", cagd.HermiteCurve.from_directions(P[0], P[1], P[2], P[3], 1.0, 2.0)
    yield "HermiteSpline", cagd.HermiteSpline(P[:3], P[3:], [0.0, 0.5, 2.0])
    yield "CubicSpline", cagd.CubicSpline(P[:5])
    yield "natural_cubic_spline clamped", cagd.natural_cubic_spline(P[:4], "clamped", tangents=P[4:])
    yield "natural_cubic_spline virtual", cagd.natural_cubic_spline(P[:4], "virtual")
    yield "natural_cubic_spline periodic", cagd.natural_cubic_spline(np.vstack([P[:4], P[:1]]), "periodic")
    yield "CubicSpline.transformed", cagd.natural_cubic_spline(P[:4], "clamped", tangents=P[4:]).translated([1, 2, 3])
    yield "CompositeCurve", cagd.CompositeCurve([line, cagd.BezierCurve([[1, 0, 0], [2, 1, 0], [3, 0, 0]])])
    yield "interpolate", cagd.interpolate(P, 3)
    yield "approximate", cagd.approximate(RNG.random((20, 3)), 6)
    yield "bezier_through_points", cagd.bezier_through_points(P[:4])
    yield "join", cagd.join(cagd.BezierCurve(P[:4]), P[4:], "G1")
    yield "make_compatible", cagd.make_compatible([line, ribbon.elevate(2)])[1]


def _surfaces():
    net = RNG.random((4, 5, 3))
    W = RNG.uniform(0.5, 2.0, (4, 5))
    c0 = cagd.BSplineCurve([[0, 0, 0], [1, 0, 0.3], [2, 0, 0]], 2)
    c1 = cagd.BSplineCurve([[0, 2, 0], [1, 2, -0.3], [2, 2, 0]], 2)
    d0 = cagd.BSplineCurve([[0, 0, 0], [0, 2, 0]], 1)
    d1 = cagd.BSplineCurve([[2, 0, 0], [2, 2, 0]], 1)
    flat = cagd.BSplineCurve([[0, 0, 1], [2, 0, 1]], 1)
    yield "BSplineSurface", cagd.BSplineSurface(net, 3, 2)
    yield "NURBS surface", cagd.BSplineSurface(net, 2, 3, weights=W)
    yield "periodic NURBS surface", cagd.BSplineSurface(net, 2, 3, np.linspace(0, 1, 5), None, W, periodic_u=True)
    yield "BezierSurface", cagd.BezierSurface(net)
    yield "rational BezierSurface", cagd.BezierSurface(net, W)
    yield "sphere", cagd.sphere(2.0)
    yield "torus", cagd.torus(3.0, 1.0)
    yield "cylinder", cagd.cylinder(1.0, 2.0)
    yield "cone", cagd.cone(1.0, 2.0)
    yield "revolve", cagd.revolve(cagd.BSplineCurve([[1, 0, 0], [2, 0, 1], [1, 0, 2]], 2), angle=np.pi)
    yield "ellipsoid", cagd.ellipsoid(3.0, 2.0, 1.0)[5]
    yield "ellipsoid_octant", cagd.ellipsoid_octant(3.0, 2.0, 1.0)
    yield "ruled", cagd.ruled(c0, c1)
    yield "loft", cagd.loft([c0, flat, c1], degree_v=2)
    yield "CoonsPatch", cagd.CoonsPatch(c0, c1, d0, d1)
    yield "CoonsPatch.transformed", cagd.CoonsPatch(c0, c1, d0, d1).transformed(np.eye(3), [1, 0, 0])
    yield "HermiteCoonsPatch", cagd.HermiteCoonsPatch(c0, c1, d0, d1)
    yield "interpolate_surface", cagd.interpolate_surface(RNG.random((5, 4, 3)), 3, 2)
    tri = cagd.BezierTriangle(RNG.random((10, 3)))
    yield "BezierTriangle", tri
    yield "rational BezierTriangle", cagd.BezierTriangle(RNG.random((6, 3)), RNG.uniform(0.5, 2.0, 6))
    yield "c1_neighbor", cagd.c1_neighbor(tri)


FAMILIES = list(_curves()) + list(_surfaces())


def _exercise(obj) -> None:
    """Fill the object's caches (pp forms, patch tables, NURBS forms, size)."""
    if isinstance(obj, cagd.Curve):
        a, b = obj.domain
        obj.derivatives(np.linspace(a, b, 7), 3)
        obj(np.linspace(a, b, 7))
    else:
        (u0, u1), (v0, v1) = obj.domain
        u, v = u0 + 0.3 * (u1 - u0), v0 + 0.2 * (v1 - v0)
        obj(u, v)
        obj(np.full(3, u), np.full(3, v))
        obj.derivatives(u, v, 2, 2)
        obj.grid(np.array([u]), np.array([v]), 1, 1)
        obj.size
    obj.to_nurbs()


def _properties(obj):
    cls = type(obj)
    return [n for n in dir(cls) if not n.startswith("_") and isinstance(getattr(cls, n), property)]


def _reachable(obj, path="obj", seen=None):
    """(path, value) of every array and engine object reachable from ``obj``: its
    attributes (public and private: caches), its public properties, and the items of
    the tuples, lists and dicts among them."""
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        yield path, obj
        return
    if isinstance(obj, (tuple, list)):
        for i, x in enumerate(obj):
            yield from _reachable(x, f"{path}[{i}]", seen)
        return
    if isinstance(obj, dict):
        for k, x in obj.items():
            yield from _reachable(x, f"{path}[{k!r}]", seen)
        return
    if not isinstance(obj, Value):
        return
    yield path, obj
    public = [n for n in vars(obj) if not n.startswith("_")] + _properties(obj)
    private = [n for n in vars(obj) if n.startswith("_")]
    for name in public + private:                # public first: shared arrays get their public path
        yield from _reachable(getattr(obj, name), f"{path}.{name}", seen)


def _arrays(obj):
    return [(p, a) for p, a in _reachable(obj) if isinstance(a, np.ndarray)]


@pytest.mark.parametrize("name, obj", FAMILIES, ids=[f[0] for f in FAMILIES])
def test_every_reachable_array_is_read_only(name, obj):
    _exercise(obj)
    arrays = _arrays(obj)
    assert any(p.count(".") == 1 for p, _ in arrays), "no public array found: the walk is broken"
    for path, arr in arrays:
        assert not arr.flags.writeable, path
        with pytest.raises(ValueError, match="assignment destination is read-only"):
            arr[...] = 0.0


@pytest.mark.parametrize("name, obj", FAMILIES, ids=[f[0] for f in FAMILIES])
def test_public_attributes_cannot_be_rebound(name, obj):
    _exercise(obj)
    engine = [(p, x) for p, x in _reachable(obj) if isinstance(x, Value)]
    assert len(engine) >= 1
    for path, x in engine:
        names = [n for n in vars(x) if not n.startswith("_")] + _properties(x) + ["periodic", "new_name"]
        for n in names:
            with pytest.raises(AttributeError, match="modified copy"):
                setattr(x, n, getattr(x, n, None))
        for n in names[:1]:
            with pytest.raises(AttributeError, match="modified copy"):
                delattr(x, n)
        x._scratch = 1                       # private names (caches) stay settable
        del x._scratch


@pytest.mark.parametrize("name, obj", FAMILIES, ids=[f[0] for f in FAMILIES])
def test_copies_and_pickles_are_values_too(name, obj):
    _exercise(obj)
    assert copy.copy(obj) is obj and copy.deepcopy(obj) is obj        # immutable: its own copy
    back = pickle.loads(pickle.dumps(obj))
    np.testing.assert_array_equal(_samples(back), _samples(obj))
    for path, arr in _arrays(back):
        assert not arr.flags.writeable, path
    with pytest.raises(AttributeError, match="modified copy"):
        back.dim = 7


def test_the_issue_example_raises_and_moved_pole_gives_the_new_curve():
    c = cagd.BSplineCurve(P4, 3)
    before = c(0.5)
    with pytest.raises(ValueError, match="assignment destination is read-only"):
        c.control_points[1] = [10, 10]
    with pytest.raises(AttributeError, match="moved_pole"):
        c.control_points = [[0, 0], [10, 10], [3, 1], [4, 0]]
    with pytest.raises(AttributeError, match="with_control_points"):
        c.degree = 2
    np.testing.assert_array_equal(c(0.5), before)
    moved = c.moved_pole(1, [10, 10])
    fresh = cagd.BSplineCurve([[0, 0], [10, 10], [3, 1], [4, 0]], 3)
    np.testing.assert_array_equal(moved(0.5), fresh(0.5))
    assert np.abs(moved(0.5) - before).max() > 1.0
    np.testing.assert_array_equal(c(0.5), before)                 # the original is unchanged
    np.testing.assert_array_equal(c.control_points, P4)


def test_closest_point_after_moved_pole_uses_the_new_geometry():
    c = cagd.BSplineCurve(P4, 3)
    q = np.array([[5.0, 6.0], [2.0, -1.0]])
    first = cagd.closest_point(c, q)                               # builds and caches c's projector
    moved = c.moved_pole(1, [10, 10])
    got = cagd.closest_point(moved, q)
    want = cagd.closest_point(cagd.BSplineCurve([[0, 0], [10, 10], [3, 1], [4, 0]], 3), q)
    np.testing.assert_allclose(got.distances, want.distances, rtol=1e-14, atol=0)
    np.testing.assert_allclose(got.feet, want.feet, rtol=1e-14, atol=1e-14)
    assert np.abs(got.distances - first.distances).max() > 0.1
    with pytest.raises(ValueError):
        c.control_points[1] = [10, 10]
    again = cagd.closest_point(c, q)                                # c's cache still describes c
    np.testing.assert_array_equal(again.distances, first.distances)


_SAME = object()


def _surface_fresh(s, P=None, W=_SAME):
    P = s.control_points if P is None else P
    W = s.weights if W is _SAME else W
    return cagd.BSplineSurface(P, s.degree_u, s.degree_v, s.knots_u, s.knots_v, W, s.periodic_u, s.periodic_v)


def _relative(a, b):
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@settings(max_examples=40, deadline=None)
@given(bspline_curves(max_degree=5), st.data())
def test_curve_copies_equal_fresh_constructions(c, data):
    n, dim = c.control_points.shape
    i = data.draw(st.integers(-n, n - 1))
    x = np.array(data.draw(st.lists(coordinates, min_size=dim, max_size=dim)))
    Q = np.array(data.draw(st.lists(coordinates, min_size=n * dim, max_size=n * dim))).reshape(n, dim)
    t = np.concatenate([sample_parameters(c, 9), data.draw(st.lists(st.floats(*c.domain), min_size=1, max_size=5))])
    P = c.control_points.copy()
    P[i] = x
    before = c(t)
    for got, pts in ((c.moved_pole(i, x), P), (c.with_control_points(Q), Q)):
        fresh = cagd.BSplineCurve(pts, c.degree, c.knots, c.weights, c.periodic)
        assert _relative(got.derivatives(t, 2), fresh.derivatives(t, 2)) <= 1e-14
        assert got.periodic == c.periodic and got.degree == c.degree
    np.testing.assert_array_equal(c(t), before)
    w = np.array(data.draw(st.lists(positive_weights, min_size=n, max_size=n)))
    fresh = cagd.BSplineCurve(c.control_points, c.degree, c.knots, w, c.periodic)
    assert _relative(c.with_weights(w)(t), fresh(t)) <= 1e-14


@settings(max_examples=30, deadline=None)
@given(bspline_surfaces(max_degree=3), st.data())
def test_surface_copies_equal_fresh_constructions(s, data):
    nu, nv, dim = s.control_points.shape
    i, j = data.draw(st.integers(-nu, nu - 1)), data.draw(st.integers(-nv, nv - 1))
    x = np.array(data.draw(st.lists(coordinates, min_size=dim, max_size=dim)))
    P = s.control_points.copy()
    P[i, j] = x
    us, vs = domain_parameters(s, 5)
    (u0, u1), (v0, v1) = s.domain
    u = np.array(data.draw(st.lists(st.floats(u0, u1), min_size=4, max_size=4)))
    v = np.array(data.draw(st.lists(st.floats(v0, v1), min_size=4, max_size=4)))
    before = s.grid(us, vs)
    for got, fresh in ((s.moved_pole((i, j), x), _surface_fresh(s, P)),
                       (s.with_control_points(P[::-1]), _surface_fresh(s, P[::-1]))):
        assert _relative(got.grid(us, vs), fresh.grid(us, vs)) <= 1e-14
        assert _relative(got.derivatives(u, v, 1, 1), fresh.derivatives(u, v, 1, 1)) <= 1e-14
    np.testing.assert_array_equal(s.grid(us, vs), before)
    W = np.array(data.draw(st.lists(positive_weights, min_size=nu * nv, max_size=nu * nv))).reshape(nu, nv)
    assert _relative(s.with_weights(W).grid(us, vs), _surface_fresh(s, W=W).grid(us, vs)) <= 1e-14


def _moves():
    net = RNG.random((3, 4, 3))
    tri = cagd.BezierTriangle(RNG.random((10, 3)), RNG.uniform(0.5, 2.0, 10))
    P = tri.control_points.copy()
    P[cagd.BezierTriangle.index_triples(3).index((1, 0, 2))] = [5, 5, 5]
    Pc = np.array(P4, dtype=float)
    Pc[-1] = [7, 7]
    Ps = net.copy()
    Ps[1, 2] = [5, 5, 5]
    yield (cagd.BezierCurve(P4, [1, 2, 1, 1]), (-1, [7, 7]), cagd.BezierCurve(Pc, [1, 2, 1, 1]))
    yield (cagd.BSplineCurve(P4, 2, np.linspace(0, 1, 5), periodic=True), (3, [7, 7]),
           cagd.BSplineCurve(Pc, 2, np.linspace(0, 1, 5), periodic=True))
    yield (cagd.BezierSurface(net), ((1, 2), [5, 5, 5]), cagd.BezierSurface(Ps))
    yield (cagd.BSplineSurface(net, 2, 1, None, np.linspace(0, 1, 5), periodic_v=True), ((1, -2), [5, 5, 5]),
           cagd.BSplineSurface(Ps, 2, 1, None, np.linspace(0, 1, 5), periodic_v=True))
    yield (tri, ((1, 0, 2), [5, 5, 5]), cagd.BezierTriangle(P, tri.weights))
    yield (tri, (cagd.BezierTriangle.index_triples(3).index((1, 0, 2)), [5, 5, 5]), cagd.BezierTriangle(P, tri.weights))


def _samples(obj):
    if isinstance(obj, cagd.Curve):
        a, b = obj.domain
        return obj.derivatives(np.linspace(a, b, 11), 2)
    return obj.derivatives(np.array([0.0, 0.2, 0.5, 0.1]), np.array([0.0, 0.3, 0.5, 0.9]), 1, 1)


@pytest.mark.parametrize("obj, args, want", list(_moves()))
def test_moved_pole_of_every_family_equals_a_fresh_construction(obj, args, want):
    before = _samples(obj)
    got = obj.moved_pole(*args)
    assert type(got) is type(obj)
    np.testing.assert_allclose(_samples(got), _samples(want), rtol=1e-14, atol=1e-14)
    np.testing.assert_array_equal(_samples(obj), before)
    again = obj.with_control_points(want.control_points)
    np.testing.assert_allclose(_samples(again), _samples(want), rtol=1e-14, atol=1e-14)
    with pytest.raises(CagdError, match="point"):
        obj.moved_pole(args[0], [1.0] * (obj.dim + 1))
    with pytest.raises(CagdError, match="point"):
        obj.moved_pole(args[0], [np.nan] * obj.dim)
    with pytest.raises(CagdError, match="control_points"):
        obj.with_control_points(np.vstack([want.control_points, want.control_points]))


@pytest.mark.parametrize("obj, index", [
    (cagd.BSplineCurve(P4, 3), 4), (cagd.BSplineCurve(P4, 3), -5), (cagd.BSplineCurve(P4, 3), (1, 2)),
    (cagd.BSplineCurve(P4, 3), 1.5), (cagd.BezierCurve(P4), "1"),
    (cagd.BezierSurface(np.zeros((3, 3, 3))), 1), (cagd.BezierSurface(np.zeros((3, 3, 3))), (1, 3)),
    (cagd.BSplineSurface(np.zeros((3, 3, 3)), 1, 1), (0, 1, 2)),
    (cagd.BezierTriangle(np.zeros((6, 3))), (1, 1, 1)), (cagd.BezierTriangle(np.zeros((6, 3))), (2, 1, -1)),
    (cagd.BezierTriangle(np.zeros((6, 3))), 6), (cagd.BezierTriangle(np.zeros((6, 3))), (1, 1)),
])
def test_moved_pole_with_a_bad_index_is_a_cagd_error(obj, index):
    with pytest.raises(CagdError, match="index"):
        obj.moved_pole(index, np.zeros(obj.dim))


@pytest.mark.parametrize("obj", [cagd.BSplineCurve(P4, 3), cagd.BezierCurve(P4), cagd.BezierSurface(np.ones((3, 2, 3))),
                                 cagd.BSplineSurface(np.ones((3, 2, 3)), 1, 1), cagd.BezierTriangle(np.ones((6, 2)))])
def test_with_weights_makes_rational_and_back(obj):
    count = obj.control_points.shape[:-1]
    w = np.full(count, 2.0)
    r = obj.with_weights(w)
    assert r.is_rational and not obj.is_rational
    np.testing.assert_allclose(_samples(r), _samples(obj), rtol=1e-14, atol=1e-14)   # equal weights: same shape
    assert not r.with_weights(None).is_rational
    with pytest.raises(CagdError, match="weights"):
        obj.with_weights(-w)
    with pytest.raises(CagdError, match="weights"):
        obj.with_weights(np.ones(7))


def _inputs():
    P, w, K = RNG.random((5, 3)), RNG.uniform(0.5, 2.0, 5), np.array([0, 0, 0, 0, 0.5, 1, 1, 1, 1.0])
    net, W = RNG.random((3, 4, 3)), RNG.uniform(0.5, 2.0, (3, 4))
    yield cagd.BSplineCurve, (P, 3, K, w)
    yield cagd.BezierCurve, (P, w)
    yield cagd.PolynomialCurve, (P, np.array([0.0, 2.0]))
    yield cagd.HermiteCurve, tuple(P[:4])
    yield cagd.HermiteSpline, (P, P[::-1].copy(), np.arange(5.0))
    yield cagd.CubicSpline, (P, "clamped", "chord", P[:2].copy())
    yield cagd.CubicSpline, (P, "virtual", "chord", None, P[:2] + 5.0, np.arange(5.0))
    yield cagd.BSplineSurface, (net, 2, 3, np.array([0, 0, 0, 1, 1, 1.0]), None, W)
    yield cagd.BezierSurface, (net, W)
    yield cagd.BezierTriangle, (RNG.random((6, 3)), RNG.uniform(0.5, 2.0, 6))


@pytest.mark.parametrize("cls, args", list(_inputs()), ids=lambda x: getattr(x, "__name__", ""))
def test_constructors_copy_their_input(cls, args):
    obj = cls(*args)
    before = _samples(obj)
    given = [a for a in args if isinstance(a, np.ndarray)]
    for a in given:
        assert a.flags.writeable                             # the caller's array is not frozen
        assert not any(np.shares_memory(a, b) for _, b in _arrays(obj))
    for a in given:
        a += 1.0                                             # and writing into it changes nothing
    np.testing.assert_array_equal(_samples(obj), before)


def test_frozen_copies_writable_input_and_shares_frozen_arrays():
    a = np.arange(4.0)
    f = frozen(a)
    assert a.flags.writeable and not f.flags.writeable and not np.shares_memory(a, f)
    assert frozen(f) is f                                    # a frozen array is shared, not copied
    view = f[1:]
    assert frozen(view) is not view and frozen(view).flags.owndata
    assert frozen([1, 2], np.float64).dtype == np.float64
    assert frozen(f, np.float32) is not f


def test_ppform_is_a_value():
    pp = cagd.BSplineCurve(P4, 3).ppform
    assert isinstance(pp, PPForm)
    with pytest.raises(ValueError):
        pp.coefficients[0, 0, 0] = 1.0
    with pytest.raises(AttributeError):
        pp.breaks = np.array([0.0, 1.0])


def test_constructors_show_their_own_signature():
    """The sealing metaclass does not hide the constructors' parameters from help() and IDEs."""
    import inspect
    assert list(inspect.signature(cagd.BSplineCurve).parameters)[:2] == ["control_points", "degree"]
    for cls in (cagd.BezierCurve, cagd.BSplineSurface, cagd.CoonsPatch, cagd.BezierTriangle):
        params = inspect.signature(cls).parameters
        assert "self" not in params and "args" not in params, (cls, params)
