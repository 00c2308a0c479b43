"""The curvature comb at extreme scales and counts (issue 14)."""
from __future__ import annotations

import numpy as np
import pytest

from cagd import BezierCurve, BSplineCurve, CagdError, curvature_comb
from cagd._checks import MAX_SAMPLES


@pytest.mark.parametrize("scale", [1e-300, 1e-100, 1e100, 1e300])
def test_comb_curvature_scale_invariant(scale):
    P = np.random.default_rng(0).random((6, 3))
    c = BSplineCurve(P, 3)
    ref = curvature_comb(c)
    far = curvature_comb(BSplineCurve(P * scale, 3))
    assert np.allclose(far.curvature * scale, ref.curvature, rtol=1e-12, atol=0)
    assert np.allclose(far.normals, ref.normals, atol=1e-12)
    # the oracle: the curve's own curvature at the teeth
    assert np.allclose(ref.curvature, c.curvature(ref.params), rtol=1e-12)


def test_comb_counts_bounded():
    c = BezierCurve([[0, 0], [1, 1], [2, 0]])
    for kw in ({"samples": 10**18}, {"samples_per_span": 10**18}, {"samples": MAX_SAMPLES + 1}):
        with pytest.raises(CagdError, match="samples"):
            curvature_comb(c, **kw)


def test_comb_tips_scale_with_the_curve():
    P = np.random.default_rng(1).random((5, 2))
    ref = curvature_comb(BSplineCurve(P, 3))
    for s in (1e-300, 1e300):
        far = curvature_comb(BSplineCurve(P * s, 3))
        assert np.allclose(far.tips / s, ref.tips, rtol=1e-12, atol=1e-12)
