"""Block-banded solver (issue 14): the same solution as a dense solve, no dense matrix."""
from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from cagd import CagdError
from cagd.basis.banded import banded_product, solve_banded_rows
from cagd.basis.bspline import basis_functions, basis_matrix
from cagd.knots import vectors as kv


@pytest.mark.parametrize("n,p", [(1, 0), (5, 2), (33, 3), (100, 7), (257, 31), (70, 12)])
def test_collocation_matches_dense_solve(n, p):
    if p >= n:
        p = n - 1
    rng = np.random.default_rng(n * 100 + p)
    u = np.sort(rng.random(n))
    u[0], u[-1] = 0.0, 1.0
    p = max(p, 0)
    U = kv.averaged(u, p) if p else np.concatenate([[0.0], 0.5 * (u[1:] + u[:-1]), [1.0]])
    span = kv.find_span(U, p, u, n)
    N = basis_functions(U, p, u, span)
    rhs = rng.random((n, 3))
    x = solve_banded_rows(span - p, N, rhs)
    dense = basis_matrix(U, p, u, n)
    # backward stable like a dense LU: residual within a few ulps of |A| |x|
    scale = np.abs(x).max() + np.abs(rhs).max()
    assert np.abs(dense @ x - rhs).max() <= 1e-13 * scale
    assert np.abs(banded_product(span - p, N, x) - rhs).max() <= 1e-13 * scale
    if n > 1:
        ref = np.linalg.solve(dense, rhs)
        cond = np.linalg.cond(dense)
        assert np.abs(x - ref).max() <= 1e-14 * cond * np.abs(ref).max()


def test_singular_system_is_a_cagd_error():
    start = np.array([0, 0, 1])
    values = np.array([[1.0, 1.0], [1.0, 1.0], [0.0, 0.0]])
    with pytest.raises(CagdError, match="singular"):
        solve_banded_rows(start, values, np.ones((3, 1)))


def test_memory_is_linear_in_n():
    """1e5 cubic rows: the dense matrix would be 80 GB; the banded solve needs O(n p)."""
    n, p = 100_000, 3
    u = np.linspace(0, 1, n)
    U = kv.averaged(u, p)
    span = kv.find_span(U, p, u, n)
    N = basis_functions(U, p, u, span)
    rhs = np.sin(7 * u)[:, None]
    tracemalloc.start()
    try:
        x = solve_banded_rows(span - p, N, rhs)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 400e6
    assert np.abs(banded_product(span - p, N, x) - rhs).max() < 1e-12
