"""``occ_knots`` / ``from_occ_knots``: OCCT's (distinct knots, multiplicities) form of
engine knot vectors and back (round trip; counting properties; errors)."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cagd import CagdError
from cagd.knots import from_occ_knots, occ_knots

from strategies import clamped_knots, floating_knots, periodic_knots


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 10).flatmap(lambda p: st.tuples(st.just(p), st.one_of(clamped_knots(p), floating_knots(p)))))
def test_nonperiodic_round_trip(pk):
    p, knots = pk
    distinct, mults, shift = occ_knots(knots, False)
    assert shift == 0
    assert np.all(np.diff(distinct) > 0) and mults.sum() == len(knots)
    assert np.array_equal(np.repeat(distinct, mults), knots)       # oracle: plain expansion
    assert np.array_equal(from_occ_knots(distinct, mults, p, False), knots)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 10).flatmap(lambda p: st.tuples(st.just(p), periodic_knots(p))))
def test_periodic_counts_and_round_trip(pk):
    p, period = pk
    distinct, mults, shift = occ_knots(period, True)
    n = len(period) - 1                                  # control points of the periodic curve
    # OCCT: poles = sum of multiplicities over one period minus the last (seam counted once)
    assert mults[0] == mults[-1] and mults[:-1].sum() == n
    left = np.count_nonzero(period == period[0])
    assert shift == left - 1
    back = from_occ_knots(distinct, mults, p, True)
    # the same period, with t_0 simple and the seam's other copies at the end
    assert back[0] == period[0] and np.count_nonzero(back == back[0]) == 1
    assert len(back) == len(period) and np.array_equal(np.unique(back), np.unique(period))
    again = occ_knots(back, True)
    assert np.array_equal(again[0], distinct) and np.array_equal(again[1], mults) and again[2] == 0


def test_periodic_example_by_hand():
    d, m, shift = occ_knots([0, 0, 1, 2, 3, 3], True)       # seam: 2 copies at the start, 2 at the end
    assert d.tolist() == [0, 1, 2, 3] and m.tolist() == [3, 1, 1, 3] and shift == 1
    assert from_occ_knots(d, m, 3, True).tolist() == [0, 1, 2, 3, 3, 3]


@pytest.mark.parametrize("args, match", [
    (([0, 1, 2], [1, 1], 2, False), "one multiplicity per distinct knot"),
    (([0, 1], [1, 5], 3, False), r"\[1, degree \+ 1"),
    (([0, 1], [0, 1], 3, False), r"\[1, degree \+ 1"),
    (([0, 1.5], [1.5, 1], 3, False), "integers"),
    (([1, 0], [2, 2], 1, False), "strictly increasing"),
    (([0, 0], [2, 2], 1, False), "strictly increasing"),
    (([0], [2], 1, False), "at least 2"),
    (([0, 1, 2], [2, 1, 3], 3, True), "equal first and last"),
    (([0, np.nan], [2, 2], 1, False), "knots"),
])
def test_errors(args, match):
    with pytest.raises(CagdError, match=match):
        from_occ_knots(*args)


def test_error_names_the_argument():
    with pytest.raises(CagdError, match="^knots_u:"):
        from_occ_knots([1, 0], [2, 2], 2, False, name="knots_u")
