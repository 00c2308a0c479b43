"""The piecewise-polynomial evaluation core (cagd/curves/ppform.py)."""
import copy
from math import factorial

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import BSpline as SciBSpline

from cagd.curves import ppform as ppform_module
from cagd.curves.ppform import PPForm, _CHUNK

from strategies import clamped_knots

SETTINGS = settings(max_examples=50, deadline=None)


def reference_spans(breaks, t):
    """b_j <= t < b_{j+1}, the last span closed at the end (searchsorted oracle)."""
    return np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, len(breaks) - 2)


def probe_parameters(breaks):
    """Every break, its neighbours one ulp away, span midpoints, the domain ends."""
    b = np.asarray(breaks, float)
    inside = np.concatenate([b, np.nextafter(b, np.inf), np.nextafter(b, -np.inf), 0.5 * (b[1:] + b[:-1])])
    return np.unique(np.clip(inside, b[0], b[-1]))


def random_pp(rng, breaks, degree, dim=2):
    return PPForm.from_unit_power(np.asarray(breaks, float), rng.normal(size=(degree + 1, len(breaks) - 1, dim)))


def as_searchsorted(pp):
    """The same pp form forced onto the searchsorted path."""
    other = copy.copy(pp)
    other._uniform = False
    other._derived = {}
    return other


UNIFORM_BREAKS = [
    np.linspace(0.0, 1.0, 11),
    np.linspace(0.1, 0.7, 7),                    # 0.1 steps: inexact in binary
    np.linspace(-3.3, 2.9, 32),
    np.linspace(1e3, 1e3 + 1.0, 65),             # offset (an inexact grid there is not detected as uniform)
    np.linspace(0.0, 1e-9, 9),
    np.arange(0.0, 7.0),                         # the seed's integer knots
    np.array([0.0, 1.0]),
]


@pytest.mark.parametrize("breaks", UNIFORM_BREAKS, ids=[f"b{i}" for i in range(len(UNIFORM_BREAKS))])
def test_uniform_fast_path_spans(breaks):
    pp = random_pp(np.random.default_rng(0), breaks, 3)
    assert pp._uniform
    t = probe_parameters(breaks)
    np.testing.assert_array_equal(pp.span_of(t), reference_spans(breaks, t))
    np.testing.assert_array_equal(as_searchsorted(pp).span_of(t), reference_spans(breaks, t))
    assert pp.span_of(np.array([breaks[-1]]))[0] == len(breaks) - 2      # right end: last span
    assert pp.span_of(np.array([breaks[0]]))[0] == 0


@settings(max_examples=50, deadline=None)
@given(a=st.floats(-1e3, 1e3), width=st.floats(1e-6, 1e3), nspan=st.integers(1, 200))
def test_uniform_fast_path_spans_random(a, width, nspan):
    breaks = np.linspace(a, a + width, nspan + 1)
    pp = random_pp(np.random.default_rng(nspan), breaks, 2, dim=1)
    t = probe_parameters(breaks)
    np.testing.assert_array_equal(pp.span_of(t), reference_spans(breaks, t))
    # and the two paths give bit-identical values
    for order in (0, 1, 2):
        np.testing.assert_array_equal(pp(t, order), as_searchsorted(pp)(t, order))


def test_nonuniform_path_detected():
    pp = random_pp(np.random.default_rng(1), [0.0, 0.1, 0.5, 1.0], 3)
    assert not pp._uniform
    t = probe_parameters(pp.breaks)
    np.testing.assert_array_equal(pp.span_of(t), reference_spans(pp.breaks, t))


@SETTINGS
@given(degree=st.integers(0, 10), nspan=st.integers(1, 8), seed=st.integers(0, 2 ** 32 - 1),
       uniform=st.booleans())
def test_from_unit_power_values_and_derivatives(degree, nspan, seed, uniform):
    """p(t) = sum_k c_k u^k, u = (t - b_j)/(b_{j+1} - b_j), and its derivatives
    (numpy.polynomial as the oracle); beyond the degree they vanish."""
    rng = np.random.default_rng(seed)
    breaks = np.linspace(0, 2, nspan + 1) if uniform else np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1, nspan))])
    coef = rng.normal(size=(degree + 1, nspan, 2))
    pp = PPForm.from_unit_power(breaks, coef)
    t = probe_parameters(breaks)
    j = reference_spans(breaks, t)
    h = breaks[j + 1] - breaks[j]
    u = (t - breaks[j]) / h
    for order in range(degree + 2):
        expected = np.zeros((t.size, 2))
        for d in range(2):
            for s in range(nspan):
                m = j == s
                c = np.polynomial.polynomial.polyder(coef[:, s, d], order) if order else coef[:, s, d]
                expected[m, d] = np.polynomial.polynomial.polyval(u[m], c) / h[m] ** order
        got = pp(t, order)
        if order > degree:
            np.testing.assert_array_equal(got, 0.0)
        else:
            ref = max(1.0, np.abs(expected).max())
            np.testing.assert_allclose(got, expected, atol=1e-12 * ref * factorial(degree))
    assert pp.derived(degree + 3).degree == 0


@SETTINGS
@given(data=st.data(), degree=st.integers(1, 10))
def test_from_bspline_vs_scipy(data, degree):
    knots = data.draw(clamped_knots(degree))
    n = len(knots) - degree - 1
    P = np.random.default_rng(data.draw(st.integers(0, 1000))).normal(size=(n, 3))
    pp = PPForm.from_bspline(knots, degree, P)
    np.testing.assert_array_equal(pp.breaks, np.unique(knots))
    t = np.linspace(knots[0], knots[-1], 77)[:-1]
    spl = SciBSpline(knots, P, degree)
    for k in range(min(degree, 3) + 1):
        ref = spl(t, nu=k)
        assert np.abs(pp(t, k) - ref).max() <= 1e-12 * max(1.0, np.abs(ref).max())


@pytest.mark.parametrize("uniform", [True, False])
def test_chunk_boundaries_are_seamless(uniform):
    """More than one chunk (> 32768 parameters): identical to evaluating small slices,
    and values straddling the chunk edges match the per-span oracle."""
    rng = np.random.default_rng(5)
    breaks = np.linspace(0, 1, 9) if uniform else np.sort(np.concatenate([[0.0, 1.0], rng.uniform(0, 1, 7)]))
    coef = rng.normal(size=(4, 8, 2))
    pp = PPForm.from_unit_power(breaks, coef)
    assert pp._uniform == uniform
    m = 2 * _CHUNK + 1234
    assert _CHUNK == 32768
    t = rng.uniform(0, 1, m)
    t[_CHUNK - 3:_CHUNK + 3] = breaks[3]                  # exact breaks at the chunk edge
    t[-1] = 1.0
    for order in (0, 1, 3, 4):
        whole = pp(t, order)
        assert whole.shape == (m, 2)
        pieces = np.concatenate([pp(t[s:s + 1000], order) for s in range(0, m, 1000)])
        np.testing.assert_array_equal(whole, pieces)
    # the rational projection is chunked too
    hom = PPForm.from_unit_power(breaks, np.concatenate([coef, np.abs(coef[..., :1]) + 1.0], axis=-1))
    proj = hom.projected(t)
    full = hom(t)
    np.testing.assert_allclose(proj, full[:, :2] / full[:, 2:], rtol=1e-15, atol=0)
    np.testing.assert_array_equal(proj[_CHUNK - 5:_CHUNK + 5], hom.projected(t[_CHUNK - 5:_CHUNK + 5]))


def _by_chunks(pp, t, order=0, project=False):
    """The chunked (gathering) path alone, for the comparison with the runs path."""
    pp = pp.derived(order)
    ndim = pp.dim - 1 if project else pp.dim
    out = np.empty((len(t), ndim))
    for s in range(0, len(t), _CHUNK):
        pp._horner(t[s:s + _CHUNK], out[s:s + _CHUNK], ndim, project)
    return out


@SETTINGS
@given(degree=st.integers(0, 8), nspan=st.integers(1, 9), seed=st.integers(0, 2 ** 32 - 1),
       uniform=st.booleans(), narrow=st.booleans())
def test_sorted_runs_are_bit_identical_to_the_chunks(degree, nspan, seed, uniform, narrow):
    """Sorted parameters evaluated span by span (RUN_POINTS lowered so that every case
    takes that path) give the same bits as the gathering path: every break and its ulp
    neighbours, repeated values, parameters beyond both ends (the end spans extrapolate),
    derivatives and the rational projection; an unsorted array is left to the chunks."""
    rng = np.random.default_rng(seed)
    breaks = np.linspace(-1.0, 2.0, nspan + 1) if uniform else \
        np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1, nspan))])
    if narrow and nspan > 2:                          # a span of subnormal width
        breaks = np.concatenate([breaks[:1], breaks[:1] + 5e-324, breaks[2:]])
    coef = rng.normal(size=(degree + 1, len(breaks) - 1, 3))
    pp = PPForm.from_unit_power(breaks, coef)
    assert pp._subnormal == (narrow and nspan > 2)
    t = np.sort(np.concatenate([probe_parameters(breaks), rng.uniform(breaks[0], breaks[-1], 50),
                                [breaks[0] - 0.5, breaks[-1] + 0.5], np.repeat(breaks[len(breaks) // 2], 3)]))
    with pytest.MonkeyPatch.context() as mp, np.errstate(all="ignore"):
        mp.setattr(ppform_module, "RUN_POINTS", 1)
        for order in range(degree + 2):
            np.testing.assert_array_equal(pp(t, order), _by_chunks(pp, t, order))
        np.testing.assert_array_equal(pp.projected(t), _by_chunks(pp, t, project=True))
        shuffled = rng.permutation(t)
        if not np.all(shuffled[1:] >= shuffled[:-1]):
            assert not pp._by_runs(shuffled, np.empty((len(t), 3)), 3, False)
        np.testing.assert_array_equal(pp(shuffled), _by_chunks(pp, shuffled))


def test_sorted_runs_take_over_only_where_they_pay():
    """The runs path serves sorted arrays of RUN_POINTS or more parameters per span (the
    benchmark's 10^6 sorted parameters on 97 spans) and nothing shorter."""
    pp = random_pp(np.random.default_rng(3), np.linspace(0.0, 1.0, 98), 3, dim=3)
    big = np.linspace(0.0, 1.0, 97 * ppform_module.RUN_POINTS)
    assert pp._by_runs(big, np.empty((len(big), 3)), 3, False)
    small = big[::2]
    assert not pp._by_runs(small, np.empty((len(small), 3)), 3, False)
    np.testing.assert_array_equal(pp(big), _by_chunks(pp, big))


def test_domain_and_shapes():
    pp = random_pp(np.random.default_rng(2), [0.0, 0.5, 2.0], 2, dim=3)
    assert pp.domain == (0.0, 2.0)
    assert pp.degree == 2 and pp.dim == 3
    assert pp(np.zeros((2, 5))).shape == (10, 3)
    assert pp.derived(1) is pp.derived(1)                     # cached
    assert pp.derived(0) is pp
