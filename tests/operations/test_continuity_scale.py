"""continuity() is scale-invariant (issue 14): at 1e-300 and 1e300 the same verdicts as
at unit scale (the norms squared under/overflowed: G1 False, gap inf, angle NaN)."""
from __future__ import annotations

import numpy as np
import pytest

import cagd


@pytest.mark.parametrize("s", [1e-300, 1e-200, 1e200, 1e300])
def test_same_verdicts_at_every_scale(s):
    P = cagd.BezierCurve([[0, 0], [1, 1], [2, 1], [3, 0]])
    Q = cagd.join(P, [[4, -1], [5, 0], [6, 1]], "G2")
    ref = cagd.continuity(P, Q)
    assert ref.G2 and not ref.C1                  # the oracle at unit scale (join's contract)
    r = cagd.continuity(P.transformed(np.eye(2) * s), Q.transformed(np.eye(2) * s))
    assert (r.C0, r.C1, r.C2, r.G1, r.G2) == (ref.C0, ref.C1, ref.C2, ref.G1, ref.G2)
    assert r.tangent_angle <= 1e-15
    assert np.isfinite(r.gap) and r.gap <= 1e-15 * s * 10
    assert r.curvature_difference * s == pytest.approx(ref.curvature_difference, abs=1e-12)
