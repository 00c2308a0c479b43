"""The shared numerics of cagd.queries: the fast row reductions of the set-up equal
numpy's own reductions bit for bit (the certified bounds must not move)."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from cagd.queries._numerics import column_extremes, row_max, row_min, squared_norms

FLOATS = st.floats(-1e150, 1e150, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, hnp.array_shapes(min_dims=1, max_dims=4, max_side=7), elements=FLOATS))
def test_squared_norms_equal_numpy_sum_bit_for_bit(v):
    np.testing.assert_array_equal(squared_norms(v), (v ** 2).sum(-1))


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, hnp.array_shapes(min_dims=2, max_dims=4, max_side=7), elements=FLOATS))
def test_column_extremes_equal_numpy_min_max(P):
    lo, hi = column_extremes(P)
    flat = P.reshape(-1, P.shape[-1])
    np.testing.assert_array_equal(lo, flat.min(axis=0))
    np.testing.assert_array_equal(hi, flat.max(axis=0))


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, hnp.array_shapes(min_dims=2, max_dims=4, max_side=7), elements=FLOATS))
def test_row_extremes_equal_numpy_max_min(v):
    flat = v.reshape(len(v), -1)
    np.testing.assert_array_equal(row_max(v), flat.max(axis=1))
    np.testing.assert_array_equal(row_min(v), flat.min(axis=1))
