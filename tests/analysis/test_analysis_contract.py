"""The bad-input contract (tests/contract.py) for cagd.analysis' maps and fairness:
hostile parameters, directions, counts and scales give an answer or a CagdError, and
an answer is checked (finite where the normal is defined, NaN elsewhere; a scaled
surface's maps follow K -> K/s^2, angles unchanged)."""
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cagd
from contract import call
from hostile import SCALES, counts, non_numbers

FUZZ = settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck))
values = st.one_of(st.floats(-0.5, 1.5), st.sampled_from([np.nan, np.inf, 1e308, -0.0]), non_numbers)
directions = st.one_of(st.sampled_from([(0.0, 0.0, 1.0), (0.6, 0.8, 0.0), (0.0, 0.0, 0.0), (0, 0, 2.0),
                                        (np.nan, 0, 1), (1.0, 0), "z"]), non_numbers)
KINDS = st.sampled_from(["gaussian", "mean", "max", "min", "Gauss", None, 3])


@FUZZ
@given(SCALES, values, values, KINDS)
def test_curvature_map(scale, u, v, kind):
    s = cagd.sphere(scale)
    out = call(cagd.curvature_map, s, u, v, kind)
    if out.error is None:
        k = np.asarray(out.value)
        with np.errstate(all="ignore"):
            expect = np.float64(1.0) / scale / scale if kind == "gaussian" else np.float64(-1.0) / scale
        if np.isfinite(expect) and abs(expect) > 1e-290:          # a normal double: compare
            # near a pole (u = 0 or 1) EG - F^2 ~ d^2 at a distance d: rounding grows as eps / d^2
            # (seen: 2.2e-7 at u = 0.99999)
            d = min(abs(float(u)), abs(1.0 - float(u)))
            rtol = max(1e-9, 1e-15 / d / d) if d > 0 else np.inf
            np.testing.assert_allclose(k[np.isfinite(k)], expect, rtol=rtol)


@FUZZ
@given(SCALES, values, directions, directions, counts, st.one_of(st.floats(-1, 2), non_numbers))
def test_zebra(scale, u, light, view, stripes, width):
    out = call(cagd.zebra, cagd.cylinder(scale, scale), u, 0.3, light, view, stripes, width)
    if out.error is None:
        z = out.value
        assert np.all(np.isnan(z.phase) == ~z.defined) and np.all((z.index >= 0) == z.defined)


@FUZZ
@given(SCALES, values, directions, st.one_of(counts, st.just([0.5, 0.0]), st.just([-0.5, 0.5])))
def test_isophotes_and_draft(scale, u, light, levels):
    s = cagd.torus(3 * scale, scale)
    out = call(cagd.isophotes, s, u, 0.25, light, levels)
    if out.error is None:
        assert np.all(np.abs(out.value.value[out.value.defined]) <= 1.0)
    d = call(cagd.draft_angle, s, u, 0.25, light)
    if d.error is None:
        assert np.all(np.abs(d.value) <= np.pi / 2)


@FUZZ
@given(SCALES, counts)
def test_fairness(scale, per):
    out = call(cagd.fairness, cagd.BezierCurve(np.array([[0, 0], [1, 1], [2, -1], [3, 0.0]]) * scale), per)
    if out.error is None:
        assert out.value.inflections == 1 and np.isfinite(out.value.energy)
