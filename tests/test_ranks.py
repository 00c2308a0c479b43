"""cagd._ranks.ranks: each element's index within its group, against a loop."""
from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from cagd._ranks import ranks


@given(st.lists(st.integers(0, 6), max_size=12))
def test_ranks_are_the_indices_within_each_group(counts):
    want = [i for c in counts for i in range(c)]
    got = ranks(np.array(counts, dtype=np.int64))
    assert got.tolist() == want
    assert got.dtype.kind == "i"


def test_ranks_example_and_empty():
    assert ranks([2, 0, 3]).tolist() == [0, 1, 0, 1, 2]
    assert ranks(np.zeros(0, dtype=np.intp)).size == 0
    assert ranks([]).size == 0
