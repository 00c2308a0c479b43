"""Banded linear systems without a dense n x n matrix (issue 14): collocation matrices
of B-splines have at most p+1 non-zeros per row, within p of the diagonal when the
Schoenberg-Whitney condition holds (de Boor, A Practical Guide to Splines, XIII).

The matrix is cut into square blocks of size b >= p, which makes it block tridiagonal,
and solved by block LU without pivoting between blocks (block Thomas algorithm; Golub &
Van Loan, Matrix Computations, 4.5.1), LAPACK with partial pivoting inside each diagonal
block. Collocation matrices are totally positive, so their leading principal minors are
positive and elimination without pivoting is stable (de Boor & Pinkus 1977). Work
O(n b^2), memory O(n b), one Python iteration per block of b rows.
"""
from __future__ import annotations

import numpy as np

from ..errors import CagdError

MIN_BLOCK = 32      # rows per block at least (fewer, larger LAPACK calls for low degrees)


def solve_banded_rows(start: np.ndarray, values: np.ndarray, rhs: np.ndarray, name: str = "points") -> np.ndarray:
    """Solve A x = rhs where row j of the n x n matrix A holds ``values[j]`` (width w) in
    columns start[j] .. start[j] + w - 1, all within w - 1 of the diagonal; ``rhs`` is
    (n, k). Returns x (n, k).

    Raises:
        CagdError: naming ``name`` when a diagonal block is singular (the system is)."""
    n, w = values.shape
    k = rhs.shape[1]
    b = max(w, MIN_BLOCK)
    nb = -(-n // b)
    N = nb * b
    # block rows (nb, b, 3b): columns (I-1) b .. (I+2) b - 1 of rows I b .. I b + b - 1
    blocks = np.zeros((nb, b, 3 * b))
    rows = np.arange(n)
    I = rows // b
    col = start[:, None] + np.arange(w)
    local = col - (I[:, None] - 1) * b
    if np.any(local < 0) or np.any(local >= 3 * b):
        raise CagdError(f"{name}: the system is not banded as expected (a row reaches beyond its band)")
    blocks[I[:, None], (rows % b)[:, None], local] = values
    pad = np.arange(n, N)                          # identity rows for the padding
    blocks[pad // b, pad % b, pad % b + b] = 1.0
    r = np.zeros((nb, b, k))
    r[I, rows % b] = rhs
    Xu = np.empty((nb, b, b))
    Xr = np.empty((nb, b, k))
    prev_u = prev_r = None
    try:
        for i in range(nb):
            L, D, U = blocks[i, :, :b], blocks[i, :, b:2 * b], blocks[i, :, 2 * b:]
            ri = r[i]
            if prev_u is not None:
                D = D - L @ prev_u
                ri = ri - L @ prev_r
            sol = np.linalg.solve(D, np.concatenate([U, ri], axis=1))
            Xu[i], Xr[i] = sol[:, :b], sol[:, b:]
            prev_u, prev_r = Xu[i], Xr[i]
    except np.linalg.LinAlgError:
        raise CagdError(f"{name}: the banded system is singular (block {i} of {nb})") from None
    x = np.empty((nb, b, k))
    x[-1] = Xr[-1]
    for i in range(nb - 2, -1, -1):
        x[i] = Xr[i] - Xu[i] @ x[i + 1]
    return x.reshape(N, k)[:n]


def banded_product(start: np.ndarray, values: np.ndarray, x: np.ndarray) -> np.ndarray:
    """A @ x for the banded rows of :func:`solve_banded_rows`: (n, k)."""
    w = values.shape[1]
    return np.einsum("jw,jwk->jk", values, x[start[:, None] + np.arange(w)])
