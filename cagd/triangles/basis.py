"""Index triples, Bernstein polynomials over a triangle and the triangular de Casteljau
step (seed 003, 3.1; Farin, Curves and Surfaces for CAGD, ch. 17).

Canonical order of the (n+1)(n+2)/2 triples (i, j, k), i + j + k = n: lexicographic
with i descending, then j descending: (n,0,0), (n-1,1,0), (n-1,0,1), (n-2,2,0), ...
The triple (i, j, k) sits at position a(a+1)/2 + (a - j), a = n - i.

Internally a net is *dense*: an array (..., n+1, n+1, D) whose entry [i, j] holds the
point of the triple (i, j, n-i-j); entries with i + j > n are padding.
"""
from __future__ import annotations

from math import factorial
from typing import Iterable, List, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..errors import CagdError

TOL = 1e-12


def index_triples(n: int) -> List[Tuple[int, int, int]]:
    """The (n+1)(n+2)/2 triples (i, j, k) with i + j + k = n in the canonical order
    (i descending, then j descending)."""
    n = _checks.integer(n, "n", 0)
    return [(i, j, n - i - j) for i in range(n, -1, -1) for j in range(n - i, -1, -1)]


def triple_position(n: int, i: int, j: int) -> int:
    """Position of (i, j, n-i-j) in :func:`index_triples` order."""
    a = n - i
    return a * (a + 1) // 2 + (a - j)


def triple_arrays(n: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Columns I, J, K of :func:`index_triples` as int arrays."""
    t = np.array(index_triples(n), dtype=np.int64).reshape(-1, 3)
    return t[:, 0], t[:, 1], t[:, 2]


def multinomials(n: int) -> np.ndarray:
    """n!/(i! j! k!) for the canonical triples."""
    return np.array([factorial(n) / (factorial(i) * factorial(j) * factorial(k))
                     for i, j, k in index_triples(n)], dtype=np.float64)


def triangle_bernstein(n: int, u: ArrayLike, v: ArrayLike) -> np.ndarray:
    """All Bernstein polynomials of degree n over the triangle,
    B_ijk(u, v, w) = n!/(i! j! k!) u^i v^j w^k, w = 1 - u - v (seed 003, 3.1, Bernstein
    form), in canonical order: shape broadcast(u, v).shape + ((n+1)(n+2)/2,).
    Defined for any real (u, v) (no domain check); they sum to 1.

    Raises:
        CagdError: n not a non-negative integer, NaN/inf parameters, shapes that do not broadcast.
    """
    n = _checks.integer(n, "n", 0)
    u, v = _checks.parameters(u, "u"), _checks.parameters(v, "v")
    try:
        u, v = np.broadcast_arrays(u, v)
    except ValueError:
        raise CagdError(f"u, v: shapes {u.shape} and {v.shape} do not broadcast") from None
    return _bernstein(n, u, v)


def _bernstein(n: int, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    I, J, K = triple_arrays(n)
    w = 1.0 - u - v
    return multinomials(n) * (u[..., None] ** I * v[..., None] ** J * w[..., None] ** K)


# --- dense nets ---------------------------------------------------------------------------
def to_dense(flat: np.ndarray, n: int) -> np.ndarray:
    """Canonical (N, D) -> dense (n+1, n+1, D), padding zero."""
    I, J, _ = triple_arrays(n)
    dense = np.zeros((n + 1, n + 1, flat.shape[-1]))
    dense[I, J] = flat
    return dense


def to_flat(dense: np.ndarray) -> np.ndarray:
    """Dense (..., m+1, m+1, D) -> canonical (..., N, D)."""
    I, J, _ = triple_arrays(dense.shape[-2] - 1)
    return dense[..., I, J, :]


def casteljau_step(net: np.ndarray, x: np.ndarray) -> np.ndarray:
    """One level of the triangular de Casteljau algorithm (seed 003, 3.1):
    b^{r}_{ijk} = x_1 b^{r-1}_{i+1,j,k} + x_2 b^{r-1}_{i,j+1,k} + x_3 b^{r-1}_{i,j,k+1}.
    ``net`` (..., m+1, m+1, D) dense, ``x`` (..., 3) (any triple: barycentric point
    or direction); returns (..., m, m, D). Leading shapes broadcast."""
    a = x[..., 0, None, None, None]
    b = x[..., 1, None, None, None]
    c = x[..., 2, None, None, None]
    return a * net[..., 1:, :-1, :] + b * net[..., :-1, 1:, :] + c * net[..., :-1, :-1, :]


def multilinear(net: np.ndarray, args: Iterable[np.ndarray]) -> np.ndarray:
    """The multilinear (homogeneous) polar form of a dense degree-n net at n triples:
    de Casteljau with argument r at level r. Returns (..., D)."""
    for x in args:
        net = casteljau_step(net, x)
    return net[..., 0, 0, :]


def barycentric(value: ArrayLike, name: str, direction: bool = False) -> np.ndarray:
    """Validated triples (..., 3): barycentric points summing to 1, or with ``direction``
    barycentric directions summing to 0 (tolerance 1e-12 relative to the entries)."""
    x = _checks.finite_array(value, name)
    if x.ndim == 0 or x.shape[-1] != 3:
        raise CagdError(f"{name}: expected barycentric triples of shape (..., 3), got shape {x.shape}")
    target = 0.0 if direction else 1.0
    s = x.sum(axis=-1)
    tol = TOL * np.maximum(1.0, np.abs(x).max(axis=-1))
    bad = np.abs(s - target) > tol
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0]) if bad.ndim else ()
        what = "a direction must sum to 0" if direction else "barycentric coordinates must sum to 1"
        raise CagdError(f"{name}: {what}, got {x[idx].tolist()} (sum {float(s[idx])!r})")
    return x
