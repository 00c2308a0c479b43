"""The public basis functions validate their input (issue 14): degrees and orders are
bounded, knots/parameters finite, span indices in range; no hang, no numpy errors."""
from __future__ import annotations

import numpy as np
import pytest

import cagd
from cagd import CagdError
from cagd.basis import basis_derivatives, basis_functions, basis_matrix, cox_de_boor
from cagd.fitting import approximation_knots
from cagd.operations.continuity import curve_size

U = np.array([0, 0, 0, 0, 0.5, 1, 1, 1, 1.0])


def test_bounds_and_types():
    calls = [lambda: basis_derivatives(U, 10**18, [0.5], [4], 0),
             lambda: basis_derivatives(U, 3, [0.5], [4], 10**18),
             lambda: basis_derivatives(U, 3, [np.nan], [4], 1),
             lambda: basis_derivatives(U, 3, [0.5], [7], 1),
             lambda: basis_derivatives(U, 3, [0.5], [0.5], 1),
             lambda: basis_functions("knots", 3, [0.5], [4]),
             lambda: basis_matrix(U, 3, [0.5], 5, 10**18),
             lambda: cox_de_boor(U, 10**18, [0.5]),
             lambda: cox_de_boor(U, 8, [0.5]),
             lambda: approximation_knots(np.linspace(0, 1, 10), 10**18, 3),
             lambda: approximation_knots(np.linspace(0, 1, 10), 5, cagd.MAX_DEGREE + 1),
             lambda: curve_size(cagd.BezierCurve([[0, 0], [1, 1]]), samples=10**18),
             lambda: curve_size("curve")]
    for call in calls:
        with pytest.raises(CagdError):
            call()


def test_valid_calls_unchanged():
    N = basis_functions(U, 3, [0.25, 0.75], [3, 4])
    assert np.allclose(N.sum(axis=1), 1.0)
    assert np.allclose(basis_matrix(U, 3, [0.25], 5), cox_de_boor(U, 3, [0.25]))
    d = basis_derivatives(U, 3, [0.25], [3], 2)
    assert np.allclose(d[1].sum(), 0.0, atol=1e-12) and np.allclose(d[2].sum(), 0.0, atol=1e-10)
