"""Every public knot function answers or raises CagdError on hostile input (issue 14)."""
from __future__ import annotations

import numpy as np
import pytest

from cagd import CagdError
from cagd import knots as K

BAD = [None, "x", 3, True, 10**400, [[0.0, 1.0]], [np.nan, 1.0], [0.0, np.inf], []]


@pytest.mark.parametrize("bad", BAD, ids=repr)
def test_vector_functions_refuse_bad_vectors(bad):
    calls = [lambda: K.averaged(bad, 2), lambda: K.greville(bad, 2), lambda: K.periodic_extend(bad, 2),
             lambda: K.distinct_with_multiplicities(bad), lambda: K.is_clamped(bad, 2),
             lambda: K.occ_knots(bad, False), lambda: K.find_span(bad, 2, 0.5, 3),
             lambda: K.validate(bad, 2, 3), lambda: K.validate_period(bad, 3, 2),
             lambda: K.from_multiplicities([0.0, 1.0], bad)]
    for call in calls:
        with pytest.raises(CagdError):
            call()


@pytest.mark.parametrize("count,degree", [(3, 5), (-1, 2), (10**18, 3), (5, 10**18), ("5", 2), (5.5, 2), (4, -1)])
def test_counts_and_degrees_bounded(count, degree):
    for f in (K.clamped_uniform, K.uniform):
        with pytest.raises(CagdError):
            f(count, degree)


def test_valid_input_still_answers():
    u = K.clamped_uniform(6, 3)
    assert np.array_equal(u, [0, 0, 0, 0, 1 / 3, 2 / 3, 1, 1, 1, 1])
    assert np.allclose(K.greville(u, 3), [0, 1 / 9, 1 / 3, 2 / 3, 8 / 9, 1])
    assert K.find_span(u, 3, 1.0, 6) == 5                  # the domain end: the last non-empty span
    assert np.array_equal(K.find_span(u, 3, [0.0, 0.5], 6), [3, 4])
    assert np.array_equal(K.from_multiplicities([0.0, 1.0], [2, 3]), [0, 0, 1, 1, 1])
    with pytest.raises(CagdError, match="start, end"):
        K.clamped_uniform(5, 2, 1.0, 1.0)
    with pytest.raises(CagdError, match="param_tol"):
        K.distinct_with_multiplicities(u, -1.0)
