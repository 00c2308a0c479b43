"""Parsing of triangle control points and weights given by index triple or in canonical
order; every failure is a CagdError naming the argument and the offending triple."""
from __future__ import annotations

import numbers
from collections import Counter
from collections.abc import Mapping
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .._checks import MAX_DEGREE
from ..errors import CagdError
from .basis import index_triples

Triple = Tuple[int, int, int]
#: control points or weights of a triangle: a mapping {(i, j, k): value}, a list of
#: ((i, j, k), value) pairs, or an array in index_triples order
TriangleData = Union[Mapping[Triple, ArrayLike], Sequence[Tuple[Triple, ArrayLike]], ArrayLike]


def _is_pairs(value: object) -> bool:
    """A list/tuple of ((i, j, k), value) pairs (like ``dict.items()``)."""
    if not isinstance(value, (list, tuple)) or not value:
        return False
    for e in value:
        if not (isinstance(e, (list, tuple)) and len(e) == 2 and isinstance(e[0], (list, tuple))
                and len(e[0]) == 3):
            return False
    return True


def _key(key: Any, name: str) -> Triple:
    try:
        t = tuple(key)
    except TypeError:
        t = ()
    ok = len(t) == 3 and all(isinstance(x, (numbers.Integral, np.integer)) and not isinstance(x, bool)
                             and int(x) >= 0 for x in t)
    if not ok:
        raise CagdError(f"{name}: key {key!r} is not a triple (i, j, k) of non-negative integers")
    return int(t[0]), int(t[1]), int(t[2])


def _table(value: Any, name: str) -> Tuple[int, Dict[Triple, Any]]:
    """(degree, {triple: raw value}) from a mapping or pairs, checking duplicates,
    extra and missing triples."""
    items = list(value.items()) if isinstance(value, Mapping) else list(value)
    table: Dict[Triple, Any] = {}
    for key, val in items:
        t = _key(key, name)
        if t in table:
            raise CagdError(f"{name}: triple {t} is given more than once")
        table[t] = val
    if not table:
        raise CagdError(f"{name}: no control points given")
    sums = Counter(sum(t) for t in table)
    n = max(sums, key=lambda s: (sums[s], s))
    for t in table:
        if sum(t) != n:
            raise CagdError(f"{name}: extra triple {t} with i + j + k = {sum(t)}; the other triples "
                            f"have degree {n}")
    if n < 1:
        raise CagdError(f"{name}: the degree must be at least 1, the triples give degree {n}")
    _max_degree(n, name)
    for t in index_triples(n):
        if t not in table:
            raise CagdError(f"{name}: missing triple {t} (degree {n} needs all {(n + 1) * (n + 2) // 2} "
                            f"triples with i + j + k = {n})")
    return n, table


def _max_degree(n: int, name: str) -> None:
    """Degrees above :data:`cagd.MAX_DEGREE` are refused (issue 14: the documented limit
    of every polynomial degree; the multinomials n!/(i! j! k!) leave the float range
    above 170 and the dense net holds (n+1)^2 points)."""
    if n > MAX_DEGREE:
        raise CagdError(f"{name}: the triples give degree {n}, above the maximum degree "
                        f"cagd.MAX_DEGREE = {MAX_DEGREE}")


def _degree_from_count(count: int, name: str) -> int:
    n = int(round((np.sqrt(8.0 * count + 1.0) - 3.0) / 2.0))
    if n < 1 or (n + 1) * (n + 2) // 2 != count:
        raise CagdError(f"{name}: {count} entries is not (n+1)(n+2)/2 for a degree n >= 1 "
                        f"(3, 6, 10, 15, ... entries in index_triples(n) order)")
    _max_degree(n, name)
    return n


def parse_points(value: TriangleData, name: str = "control_points") -> Tuple[np.ndarray, int]:
    """Control points as a canonical (N, dim) float array and the degree n."""
    if isinstance(value, Mapping) or _is_pairs(value):
        n, table = _table(value, name)
        triples = index_triples(n)
        rows: List[np.ndarray] = []
        for t in triples:
            try:
                p = np.atleast_1d(np.array(table[t], dtype=np.float64))
            except (TypeError, ValueError):
                raise CagdError(f"{name}: point for triple {t} is not numeric: {table[t]!r}") from None
            if p.ndim != 1:
                raise CagdError(f"{name}: point for triple {t} must be a flat coordinate vector, got shape {p.shape}")
            if rows and p.shape[0] != rows[0].shape[0]:
                raise CagdError(f"{name}: point for triple {t} has {p.shape[0]} coordinates, the point for "
                                f"{triples[0]} has {rows[0].shape[0]}")
            if not np.all(np.isfinite(p)):
                raise CagdError(f"{name}: point for triple {t} contains NaN or inf")
            rows.append(p)
        return np.array(rows), n
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise CagdError(f"{name}: not a numeric array or a mapping {{(i, j, k): point}} ({exc})") from None
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] < 1:
        raise CagdError(f"{name}: expected shape (N, dim) in index_triples(n) order, got {arr.shape}")
    n = _degree_from_count(arr.shape[0], name)
    bad = ~np.all(np.isfinite(arr), axis=1)
    if np.any(bad):
        r = int(np.argmax(bad))
        raise CagdError(f"{name}: point for triple {index_triples(n)[r]} (row {r}) contains NaN or inf")
    return arr, n


def parse_weights(value: Optional[TriangleData], n: int, name: str = "weights") -> Optional[np.ndarray]:
    """Positive weights in canonical order for a degree-n triangle, or None."""
    if value is None:
        return None
    triples = index_triples(n)
    if isinstance(value, Mapping) or _is_pairs(value):
        m, table = _table(value, name)
        if m != n:
            raise CagdError(f"{name}: the triples have degree {m}, the control points degree {n}")
        values: List[float] = []
        for t in triples:
            try:
                values.append(float(table[t]))
            except (TypeError, ValueError):
                raise CagdError(f"{name}: weight for triple {t} is not a number: {table[t]!r}") from None
        w = np.array(values)
    else:
        try:
            w = np.array(value, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise CagdError(f"{name}: not a numeric array or a mapping {{(i, j, k): weight}} ({exc})") from None
        if w.shape != (len(triples),):
            raise CagdError(f"{name}: expected {len(triples)} weights (one per control point), got shape {w.shape}")
    bad = ~np.isfinite(w) | (w <= 0)
    if np.any(bad):
        r = int(np.argmax(bad))
        raise CagdError(f"{name}: must be finite and positive (triple {triples[r]}: {float(w[r])!r})")
    return w
