"""cagd._checks, the validators behind the bad-input contract: numbers are numbers (a bool
is refused, not read as 1.0), and the public functions name the argument."""
import numpy as np
import pytest

from cagd import BSplineCurve, CagdError, closest_point
from cagd import _checks


@pytest.mark.parametrize("value", [True, False, np.bool_(True), np.array(True)])
def test_a_bool_is_not_a_number(value):
    for check in (_checks.scalar, _checks.positive, _checks.nonnegative):
        with pytest.raises(CagdError, match="tol: must be a number"):
            check(value, "tol")


@pytest.mark.parametrize("value, expected", [(1, 1.0), (np.float32(0.5), 0.5), (np.int64(3), 3.0), ("2.5", 2.5)])
def test_numbers_pass(value, expected):
    assert _checks.positive(value, "tol") == expected


def test_tol_true_is_refused_by_a_query():
    c = BSplineCurve(np.array([[0.0, 0.0], [1.0, 1.0]]), 1)
    with pytest.raises(CagdError, match="tol"):
        closest_point(c, np.zeros(2), tol=True)
